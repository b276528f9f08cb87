#!/usr/bin/env bash
# lcefem validate farmed over MPI ranks: one rank per core (NPROC, default `nproc`), at most one per
# case, each case whole on one rank (validation/app/farm.py); the answers do not depend on the number of
# ranks. Serial, with the reason printed, when the venv has no mpiexec or one rank is all there is.
# Usage: scripts/validate.sh [lcefem validate arguments]   (make validate / make validate-quick)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=.venv/bin
# nproc counts OMP_NUM_THREADS as the cores it may use: ask it without, for the cores themselves.
cores=${NPROC:-$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc 2>/dev/null || echo 1)}
cases=$("$BIN/lcefem" validate --list | wc -l)
ranks=$(( cores < cases ? cores : cases ))
if [ ! -x "$BIN/mpiexec" ]; then
    reason="no $BIN/mpiexec (it comes with the mpich wheel of requirements.lock: run make env)"
elif [ "$ranks" -lt 2 ]; then
    reason="$cores core(s) for $cases case(s): one rank"
else
    echo "lcefem validate: $ranks MPI ranks ($cores cores, $cases cases), each case on one rank"
    # One BLAS/OpenMP thread per rank: the ranks already fill the cores.
    OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} exec "$BIN/mpiexec" -n "$ranks" "$BIN/lcefem" validate "$@"
fi
echo "lcefem validate: serial ($reason)"
exec "$BIN/lcefem" validate "$@"
