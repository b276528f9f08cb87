"""``lcefem run body --config robot.toml``: a 3D FE thermo-mechanical LCE body from a mesh and a
case file (:mod:`lcefem.solvers.problems.body_case`: the schema and its checks;
:mod:`lcefem.solvers.problems.body`: the problem and its run; docs/own_robot.md).

The run writes, in --out DIR: history.csv (one row per step), temperature.bp and displacement.bp
(VTX, ParaView), summary.json (every resolved value of the case, mesh, wall time); with
``[[compare]]`` entries also report.md, one compare_<observable>.png each and the judged rows in
summary.json (:mod:`lcefem.validation.app.compare`): exit 1 when one fails. Files carry a
.part suffix until the run completes; a run that fails keeps the converged steps as *.partial.*
and writes failure.json.
"""

from __future__ import annotations

import argparse

from lcefem.meshes.communicator import default_comm
from lcefem.solvers.problems.body import run_body
from lcefem.solvers.problems.body_case import SCHEMA, load_case
from lcefem.solvers.runtime.outdir import add_out_arguments


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--config", required=True, help="the case file (TOML; docs/own_robot.md)")
    p.add_argument("--size-factor", type=float, help="override [mesh] size_factor [-]")
    p.add_argument("--duration", type=float, help="override [program] duration [s]")
    p.add_argument("--dt", type=float, help="override [program] dt [s]")
    p.add_argument("--no-fields", action="store_true", help="skip the VTX field files")
    add_out_arguments(p, "results/body")


def prepare(args: argparse.Namespace):
    """The checked case (before the output folder is touched and before any mesh is built); the
    options given override the file's keys and are checked like them."""
    overrides = {
        ("mesh", "size_factor"): args.size_factor,
        ("program", "duration"): args.duration,
        ("program", "dt"): args.dt,
        ("output", "fields"): False if args.no_fields else None,
    }
    return load_case(args.config, overrides={k: v for k, v in overrides.items() if v is not None})


def main(args: argparse.Namespace) -> int:
    case = args.prepared
    result = run_body(case, args.out, progress=not args.quiet)
    if default_comm().rank == 0:
        final = result.summary.get("final") or {}
        what = "steady state" if case.program["steady"] else f"{result.summary['steps']} steps"
        print(
            f"lcefem: body {case.path.name}, {what} in {result.summary['wall_time [s]']:.1f} s; "
            f"T_max {final.get('T_max [C]', float('nan')):.1f} C, T_mean "
            f"{final.get('T_mean [C]', float('nan')):.1f} "
            "C; "
            f"results in {result.out}"
        )
    if not case.compare:
        return 0
    if result.out is None:
        return 0
    from lcefem.solvers.runtime.exits import EXIT_CASE_ERROR
    from lcefem.validation.app.compare import write_comparisons

    rows = None
    if default_comm().rank == 0:
        rows = write_comparisons(
            case, result, result.out, command=f"lcefem run body --config {args.config}"
        )
        for r in rows:
            print(
                f"  compare {r.metric}: model {r.value:.4g} {r.unit}, measured "
                f"{r.reference if r.reference is not None else float('nan'):.4g} {r.unit} "
                f"-> {'pass' if r.passed else 'FAIL'}"
            )
        print(f"report: {result.out / 'report.md'}")
    failed = default_comm().bcast(None if rows is None else any(not r.passed for r in rows), root=0)
    if failed:
        if default_comm().rank == 0:
            print(f"lcefem run body: a [[compare]] entry failed (see {result.out / 'report.md'})")
        return EXIT_CASE_ERROR
    return 0


__all__ = ["SCHEMA", "add_arguments", "main", "prepare"]
