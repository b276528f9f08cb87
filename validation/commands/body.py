"""``lcefem run body --config robot.toml``: a 3D FE thermo-mechanical LCE body from a mesh and a
case file (:mod:`lcefem.solvers.problems.body_case`: the schema and its checks;
:mod:`lcefem.solvers.problems.body`: the problem and its run; docs/own_robot.md).

The run writes, in --out DIR: history.csv (one row per step), temperature.bp and displacement.bp
(VTX, ParaView), summary.json (every resolved value of the case, mesh, wall time). Files carry a
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
    overrides = {("mesh", "size_factor"): args.size_factor, ("program", "duration"): args.duration,
                 ("program", "dt"): args.dt, ("output", "fields"): False if args.no_fields else None}
    return load_case(args.config, overrides={k: v for k, v in overrides.items() if v is not None})


def main(args: argparse.Namespace) -> int:
    case = args.prepared
    result = run_body(case, args.out, progress=not args.quiet)
    if default_comm().rank == 0:
        final = result.summary.get("final") or {}
        what = "steady state" if case.program["steady"] else f"{result.summary['steps']} steps"
        print(f"lcefem: body {case.path.name}, {what} in {result.summary['wall_time [s]']:.1f} s; "
              f"T_max {final.get('T_max [C]', float('nan')):.1f} C, T_mean {final.get('T_mean [C]', float('nan')):.1f} C; "
              f"results in {result.out}")
    return 0


__all__ = ["SCHEMA", "add_arguments", "main", "prepare"]
