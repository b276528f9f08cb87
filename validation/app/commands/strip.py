"""``lcefem run strip``: command-line glue of the thermo-mechanical strip problem
(:mod:`lcefem.solvers.problems.strip`: configuration, model, time loop, outputs).

The run writes, in --out DIR: history.csv (one row per step), thermal.bp and displacement.bp
(VTX, ParaView), summary.json (resolved configuration, metrics, timings). Files carry a .part
suffix until the run completes; a run that fails keeps the converged steps as *.partial.* and
writes failure.json.
"""

from __future__ import annotations

import argparse
import dataclasses

from lcefem.meshes.communicator import default_comm
from lcefem.models.heat import Coil
from lcefem.solvers.problems.strip import BOUNDARY_CONDITIONS, StripConfig, run_strip, strip_program
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.validation.app.config import config_from_toml, door_from_toml, override
from lcefem.validation.cases.programs import SEED_T_NI


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--current", type=float, help="coil current [A] (default 0.2)")
    p.add_argument("--duration", type=float, help="simulated time [s] (default 30)")
    p.add_argument("--dt", type=float, help="time step [s] (default 0.5)")
    p.add_argument("--bc", choices=BOUNDARY_CONDITIONS, help="free strip or held at nematic length")
    p.add_argument("--tip-load", type=float, help="dead load on the free end [N]")
    p.add_argument(
        "--steady",
        action="store_true",
        default=None,
        help="solve the thermal steady state instead of a transient",
    )
    p.add_argument(
        "--mesh-level",
        type=int,
        help="refinement level l: element size = mesh-size / (l + 1) (default 1)",
    )
    p.add_argument("--mesh-size", type=float, help="level-0 element size [mm] (default 2)")
    p.add_argument("--cell", choices=("hex", "tet"), help="hexahedra (Q2) or tetrahedra (P2)")
    p.add_argument(
        "--symmetry", choices=("quarter", "full"), help="mesh a quarter (default) or all"
    )
    p.add_argument(
        "--resistance", type=float, help=f"coil resistance [ohm] (default {Coil().resistance:g})"
    )
    p.add_argument(
        "--config",
        help="TOML case file; sections: "
        + ", ".join(f.name for f in dataclasses.fields(StripConfig))
        + "; [program] and [[exports]] (the run's "
        "drives against time and what it writes: docs/library.md)",
    )
    p.add_argument("--no-fields", action="store_true", help="skip the VTX field files")
    add_out_arguments(p, "results/strip")


def config_from_args(args: argparse.Namespace) -> StripConfig:
    cfg = config_from_toml(args.config, StripConfig(), door=True)
    cfg = override(
        cfg,
        "run",
        current=args.current,
        duration=args.duration,
        dt=args.dt,
        bc=args.bc,
        tip_load=args.tip_load,
        steady=args.steady,
    )
    cfg = override(
        cfg,
        "mesh",
        level=args.mesh_level,
        size=args.mesh_size,
        cell=args.cell,
        symmetry=args.symmetry,
    )
    return override(cfg, "coil", resistance=args.resistance)


def prepare(args: argparse.Namespace) -> StripConfig:
    """The validated configuration (before the output folder is touched); the case file's
    ``[program]`` and ``[[exports]]`` (if any) checked too, kept in ``args.door``."""
    cfg = config_from_args(args).validated()
    args.door = door_from_toml(args.config)
    return cfg


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    program, exports = getattr(args, "door", (None, None))
    result = run_strip(
        cfg,
        args.out,
        progress=not args.quiet,
        fields=not args.no_fields,
        crossing_temperature=SEED_T_NI,
        program=program,
        exports=exports,
    )
    first = default_comm().rank == 0  # one rank prints
    if first and (program or strip_program(cfg)).steady:
        obs = result.summary["steady_state"]
        print(
            f"lcefem: strip {cfg.run.current:g} A ({cfg.run.bc}) steady state: stretch "
            f"{obs['stretch [-]']:.4f}, T_mean {obs['T_mean [C]']:.1f} C, force "
            f"{obs['force [N]']:.4f} "
            "N; "
            f"results in {result.out}"
        )
    elif first:
        m = result.summary["metrics"]
        print(
            f"lcefem: strip {cfg.run.current:g} A ({cfg.run.bc}), {result.summary['steps']} steps "
            "in "
            f"{result.summary['wall_time [s]']:.1f} s; final stretch {m['final_stretch [-]']:.4f}, "
            f"T_mean {m['final_T_mean [C]']:.1f} C, force {result.history['force [N]'][-1]:.4f} N; "
            f"results in {result.out}"
        )
    return 0
