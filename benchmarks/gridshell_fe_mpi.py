"""The FE gridshell on 1 and N MPI ranks (issue 46, point 2): the wall time of one whole
``lcefem run gridshell --model fe --shape dome --mesh-level L`` under ``mpiexec -n N`` and its split
from PETSc's ``-log_view`` (numeric and symbolic LDL^T by MUMPS, Jacobian and residual assembly,
the linear solves, the matrix and vector assembly's communication, MPI messages and reductions).

    python benchmarks/gridshell_fe_mpi.py --level 1 --ranks 1 2 --out DIR
    python benchmarks/gridshell_fe_mpi.py --level 2 --ranks 1 2 --lambda Tx=1.1,Ty=1.1 --out DIR

``--lambda`` replaces the dome's drive by a shorter one (the first steps of a ramp: a level-2
shape's scaling within minutes instead of a 20-minute ramp per rank count).

Each run is a child process (the command line's main with PETSc's logging begun; its wall time
includes imports, mesh, JIT from the cache, output files); its summary.json gives the Newton
iterations and the curvature, which must be the serial one on every rank count. Not a test: it
prints figures. The machine is shared: the load average before and after each run is printed with
it, and wall times are upper bounds.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import time

VENV_BIN = pathlib.Path(sys.executable).parent
#: -log_view events reported (PETSc names) and what they are
EVENTS = {
    "MatCholFctrNum": "numeric LDL^T (MUMPS)",
    "MatCholFctrSym": "symbolic LDL^T (MUMPS analysis)",
    "PCSetUp": "preconditioner set-up (the factorisations)",
    "SNESJacobianEval": "Jacobian (assembly + contact terms)",
    "SNESFunctionEval": "residual (assembly + contact terms)",
    "KSPSolve": "linear solves (factorisation + triangular solves)",
    "MatSolve": "triangular solves",
    "MatAssemblyBegin": "matrix assembly begin (stash communication)",
    "MatAssemblyEnd": "matrix assembly end",
    "VecAssemblyBegin": "vector assembly begin",
    "SFBcastBegin": "ghost updates (star forest broadcast)",
    "SFReduceBegin": "ghost updates (star forest reduce)",
}


def parse_log_view(text: str) -> dict:
    """Count and max time over the ranks [s] of the events of :data:`EVENTS`, and the run's MPI
    message count and volume [B] (totals over the ranks; PETSc's own: MUMPS's messages inside the
    factorisation are not counted) and reductions."""
    out = {}
    for event in EVENTS:
        m = re.search(rf"^{event}\s+(\d+)\s+([\d.]+)\s+([\d.e+-]+)\s+([\d.]+)", text, re.M)
        if m:
            out[event] = {"count": int(m.group(1)), "max time [s]": float(m.group(3))}
    for key, pattern in (
        # max, ratio, average, total: the total over the ranks
        ("MPI messages [-]", r"^MPI Msg Count:\s+\S+\s+\S+\s+\S+\s+([\d.e+-]+)"),
        ("MPI message volume [B]", r"^MPI Msg Len \(bytes\):\s+\S+\s+\S+\s+\S+\s+([\d.e+-]+)"),
        ("MPI reductions [-]", r"^MPI Reductions:\s+([\d.e+-]+)"),
        ("log_view time [s]", r"^Time \(sec\):\s+([\d.e+-]+)"),
    ):
        m = re.search(pattern, text, re.M)
        if m:
            out[key] = float(m.group(m.lastindex))
    return out


#: The child process: the command line's main with PETSc's logging on (lcefem takes solver options
#: only from a case file, so not -log_view), then the log written as -log_view would.
CHILD = """
import sys
import dolfinx_solver  # noqa: F401
from mpi4py import MPI
from petsc4py import PETSc
PETSc.Log.begin()
from lcefem.validation.app.cli import main
rc = main(sys.argv[2:])
PETSc.Log.view(PETSc.Viewer().createASCII(sys.argv[1], comm=MPI.COMM_WORLD))
sys.exit(rc)
"""


def run(level: int, ranks: int, out: pathlib.Path, lambdas: str | None = None) -> dict:
    """One run of the dome (or of ``lambdas``, ``--lambda``'s text) at ``level`` on ``ranks``
    ranks; its figures."""
    folder = out / f"level{level}_ranks{ranks}"
    log = out / f"level{level}_ranks{ranks}_log_view.txt"
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    cmd = [sys.executable, "-c", CHILD, str(log), "run", "gridshell", "--model", "fe"]
    drive = ["--shape", "dome"] if lambdas is None else ["--lambda", lambdas]
    cmd += [*drive, "--mesh-level", str(level), "--quiet", "--overwrite"]
    cmd += ["--out", str(folder)]
    if ranks > 1:
        cmd = [str(VENV_BIN / "mpiexec"), "-n", str(ranks), *cmd]
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, check=True)
    wall = time.perf_counter() - t0
    s = json.loads((folder / "summary.json").read_text())
    return {
        "level": level,
        "ranks": ranks,
        "drive": lambdas or "dome",
        "dofs [-]": s["dofs [-]"],
        "wall time, whole command [s]": wall,
        "wall time, ramp (rank 0) [s]": s["wall time [s]"],
        "cpu time, rank 0 [s]": s["cpu time [s]"],
        "newton iterations [-]": s["newton iterations [-]"],
        "path steps [-]": s["path steps [-]"],
        "kappa_circle_x [1/mm]": s["results"]["kappa_circle_x [1/mm]"],
        "load average before, after [-]": [load0, os.getloadavg()[0]],
        "log_view": parse_log_view(log.read_text()) if log.exists() else {},
    }


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--level", type=int, default=1)
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--out", type=pathlib.Path, default=pathlib.Path("results/bench_fe_mpi"))
    p.add_argument("--lambda", dest="lambdas", help="a drive instead of the dome's, e.g. Tx=1.1")
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    results = []
    for ranks in args.ranks:
        r = run(args.level, ranks, args.out, args.lambdas)
        results.append(r)
        print(json.dumps(r, indent=1), flush=True)
        tmp = args.out / "results.json.part"
        tmp.write_text(json.dumps(results, indent=1))
        tmp.replace(args.out / "results.json")
    one = [r for r in results if r["ranks"] == 1]
    base = (one or results)[0]["wall time, whole command [s]"]
    for r in results:
        lv = r["log_view"]
        print(
            f"level {r['level']}, {r['ranks']} rank(s): {r['wall time, whole command [s]']:.1f} s "
            f"wall (speed-up {base / r['wall time, whole command [s]']:.2f}x), "
            f"{r['newton iterations [-]']} Newton iterations, circle "
            f"{r['kappa_circle_x [1/mm]']:.10f} 1/mm, load {r['load average before, after [-]']}; "
            + ", ".join(
                f"{EVENTS[e].split(' (')[0]} {lv[e]['max time [s]']:.1f} s"
                for e in EVENTS
                if e in lv and e.startswith(("MatCholFctr", "SNES"))
            )
        )


if __name__ == "__main__":
    main()
