"""A twisted LCE ribbon (seed 000) on a hot plate: an elastic rod with contact, friction and heat.

``lcefem run ribbon [--ground-temperature C] [--twist-density TURNS/MM] [--duration S] [--nodes N]
[--dt S] [--helix-radius MM] [--obstacle WIDTH HEIGHT] [--obstacle-offset MM] [--obstacle-distance
MM] [--config FILE.toml] [--no-fields] [--out DIR] [--quiet]``

The problem, its time loop and outputs: :mod:`lcefem.solvers.problems.twisted_ribbon_der`
(centerline and surface VTK series, centroid.csv, history.csv, summary.json); this module adds
trajectory.png (lcefem.validation.studies.ribbon.ribbon_analysis) and prints one line.
"""

from __future__ import annotations

import argparse

from lcefem.models.errors import InputError
from lcefem.models.ribbon import RibbonGeometry
from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, run_ribbon
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.validation.app.config import config_from_toml, override

#: Serial only (numpy/scipy); under mpiexec every rank would write the same files.
PARALLEL = False


def report(out, cfg: RibbonConfig, history: dict) -> None:
    """trajectory.png: centroid path, speed, end spin angles and temperatures."""
    from lcefem.validation.studies.ribbon.ribbon_analysis import plot_trajectory

    plot_trajectory(
        history,
        out / "trajectory.png",
        title=f"ribbon on a {cfg.run.ground_temperature:g} C plate, "
        f"{cfg.geometry.twist_density:g} turns/mm",
    )


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--ground-temperature", type=float, help="hot plate temperature [C] (default 100)"
    )
    p.add_argument("--twist-density", type=float, help="twist density [turns/mm] (default 0.05)")
    p.add_argument("--duration", type=float, help="heated time [s] (default 60)")
    p.add_argument("--nodes", type=int, help="rod nodes (default 60)")
    p.add_argument("--dt", type=float, help="time step [s] (default 0.01)")
    p.add_argument(
        "--error-tolerance",
        type=float,
        help="adaptive steps: local position error per step [mm] "
        "(default 0: fixed steps of dt; 0.01 checked in the README)",
    )
    p.add_argument(
        "--helix-radius",
        type=float,
        help="> 0: an untwisted helical ribbon of this centreline radius [mm] instead",
    )
    p.add_argument(
        "--obstacle",
        type=float,
        nargs=2,
        metavar=("WIDTH", "HEIGHT"),
        help="a block on the plate in the ribbon's path, WIDTH along the ribbon's axis and HEIGHT "
        "[mm] "
        "(the [obstacle] section of the case file has its depth, side and edge radius)",
    )
    p.add_argument(
        "--obstacle-offset",
        type=float,
        help="the block's centre along the ribbon's axis from the "
        "ribbon's middle [mm] (default 0: hit in the middle)",
    )
    p.add_argument(
        "--obstacle-distance",
        type=float,
        help="from the ribbon's centre line to the block's near face [mm] (default 5)",
    )
    p.add_argument("--config", help="TOML case file; sections: " + ", ".join(RibbonConfig.SECTIONS))
    p.add_argument("--no-fields", action="store_true", help="skip the VTK field files")
    add_out_arguments(p, "results/ribbon")


def config_from_args(args: argparse.Namespace) -> RibbonConfig:
    for name, value, unit in (("--duration", args.duration, "s"), ("--dt", args.dt, "s")):
        if value is not None and not value > 0:
            raise InputError(f"{name} = {value} {unit}: must be > 0 {unit}")
    if args.error_tolerance is not None and args.error_tolerance < 0:
        raise InputError(f"--error-tolerance = {args.error_tolerance} mm: must be >= 0 mm")
    if args.nodes is not None and args.nodes < 3:
        raise InputError(f"--nodes = {args.nodes}: must be >= 3")
    cfg = config_from_toml(args.config, RibbonConfig())
    cfg = override(cfg, "run", ground_temperature=args.ground_temperature, duration=args.duration)
    cfg = override(
        cfg, "geometry", twist_density=args.twist_density, helix_radius=args.helix_radius
    )
    if cfg.geometry.is_helical:  # wound untwisted (initial_ribbon_state): report what is simulated
        if args.twist_density not in (None, 0.0):
            raise InputError(
                f"--twist-density = {args.twist_density} turns/mm: a helical ribbon "
                f"(helix radius {cfg.geometry.helix_radius} mm) is untwisted; give one of the two"
            )
        if (
            cfg.geometry.twist_density == RibbonGeometry().twist_density
        ):  # the default, not a choice
            cfg = override(
                cfg, "geometry", twist_density=0.0
            )  # (another value: validated() refuses it)
    width, height = args.obstacle if args.obstacle is not None else (None, None)
    for name, value in (
        ("--obstacle WIDTH", width),
        ("--obstacle HEIGHT", height),
        ("--obstacle-distance", args.obstacle_distance),
    ):
        if value is not None and not value > 0:
            raise InputError(f"{name} = {value} mm: must be > 0 mm")
    cfg = override(
        cfg,
        "obstacle",
        width=width,
        height=height,
        offset=args.obstacle_offset,
        distance=args.obstacle_distance,
    )
    if (
        args.obstacle_offset is not None or args.obstacle_distance is not None
    ) and not cfg.obstacle.present:
        raise InputError(
            "--obstacle-offset/--obstacle-distance: give the block's size with --obstacle WIDTH "
            "HEIGHT "
            "(or obstacle.width in the case file)"
        )
    return override(
        cfg, "numerics", nodes=args.nodes, dt=args.dt, error_tolerance=args.error_tolerance
    )


def prepare(args: argparse.Namespace) -> RibbonConfig:
    """The validated configuration (before the output folder is touched)."""
    return config_from_args(args).validated()


def main(args: argparse.Namespace) -> int:
    cfg = args.prepared
    result = run_ribbon(
        cfg, args.out, progress=not args.quiet, fields=not args.no_fields, report=report
    )
    m = result.metrics
    print(
        f"lcefem: ribbon on {cfg.run.ground_temperature:g} C, {cfg.geometry.twist_density:g} "
        "turns/mm, "
        f"{cfg.numerics.nodes} nodes: {'rolls' if m['rolls'] else 'does not roll'}; average speed "
        f"{m['average_speed [mm/s]']:.3f} mm/s over the last half, end spin rates "
        f"{m['spin_rate_start [rad/s]']:.3f} / {m['spin_rate_end [rad/s]']:.3f} rad/s, "
        f"{m['contact_points [-]']:.1f} contact points; {result.summary['wall_time [s]']:.1f} s "
        "wall; "
        f"results in {result.out}"
    )
    return 0
