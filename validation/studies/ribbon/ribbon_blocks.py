"""The rolling twisted ribbon meeting a block of finite size on the hot plate (seed 000, Fig. 1: the
robot meets an obstacle; "hit near an end, it turns slightly and passes; hit in the middle, it
pushes, snaps and reverses").

    OMP_NUM_THREADS=1 nice python -m lcefem.validation.studies.ribbon.ribbon_blocks \
        [--placements none middle end]
        [--width 20] [--end-width 10] [--overlap MM] [--height 10] [--distance 5] [--side 0]
        [--friction 0.5] [--block-heat none|plate|ambient|given] [--block-temperature C]
        [--nodes 60] [--dt 0.01] [--length MM]
        [--duration 120] [--ground-temperature 100] [--every 1] [--out results/ribbon_blocks]

Each placement is one run of ``lcefem run ribbon`` (the default ribbon and material) with the block
of the ``[obstacle]`` section: ``middle`` a block of --width centred on the ribbon's middle, ``end``
a block of --end-width whose far edge lines up with one end of the ribbon (it meets the last
--end-width mm of the ribbon), ``none`` no block. Printed every --every simulated seconds and
written to blocks.csv: centroid [mm], velocity [mm/s], heading [deg from +x], axis angle [deg from
+x], end spins [rad], smallest gap to the block [mm], mean and hottest section temperature [C],
twist density [turns/mm] and elastic energy [mJ]; block_<placement>.gif: the ribbon's two edge lines
and the block seen from above. The phenomena (validation/data/phenomena.toml, ribbon_block_*) are
judged on these rows.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import os
import pathlib

import numpy as np

from lcefem.models.contact import Block
from lcefem.solvers.der.ribbon import RibbonSimulation
from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig
from lcefem.validation.app.config import override

COLUMNS = [
    "placement",
    "block_heat",
    "time [s]",
    "centroid_x [mm]",
    "centroid_y [mm]",
    "velocity_x [mm/s]",
    "velocity_y [mm/s]",
    "heading [deg]",
    "axis_angle [deg]",
    "spin_start [rad]",
    "spin_end [rad]",
    "block_gap [mm]",
    "T_mean [C]",
    "T_max [C]",
    "twist_density [turns/mm]",
    "elastic_energy [mJ]",
]


def block_for(
    placement: str,
    width: float,
    end_width: float,
    height: float,
    distance: float,
    side: float,
    length: float,
    friction: float = Block().friction,
    heat: str = Block().heat,
    temperature: float = Block().temperature,
) -> Block:
    if placement == "none":
        return Block()
    if placement == "middle":
        return Block(
            width=width,
            height=height,
            distance=distance,
            offset=0.0,
            direction=side,
            friction=friction,
            heat=heat,
            temperature=temperature,
        )
    if placement == "end":
        return Block(
            width=end_width,
            height=height,
            distance=distance,
            offset=0.5 * (length - end_width),
            direction=side,
            friction=friction,
            heat=heat,
            temperature=temperature,
        )
    raise ValueError(f"placement {placement!r}: allowed none, middle, end")


def axis_angle(x: np.ndarray) -> float:
    """Angle [deg] of the ribbon's end-to-end chord (in the plate's plane) from +x."""
    d = x[-1] - x[0]
    return math.degrees(math.atan2(d[1], d[0]))


def edge_lines(sim: RibbonSimulation) -> np.ndarray:
    """The ribbon's two long edges (2, N, 3) [mm] (centre line +- half the width along m1)."""
    geo = sim.state.geometry()
    m1 = np.empty_like(sim.state.x)
    m1[1:-1] = 0.5 * (geo.m1[:-1] + geo.m1[1:])
    m1[0], m1[-1] = geo.m1[0], geo.m1[-1]
    m1 /= np.linalg.norm(m1, axis=1, keepdims=True)
    hw = 0.5 * sim.setup.geometry.width
    return np.stack([sim.state.x - hw * m1, sim.state.x + hw * m1])


def elastic_energy(sim: RibbonSimulation) -> float:
    """Elastic energy [mJ] of the ribbon (stretching, bending, twisting against its current natural
    shape)."""
    from lcefem.solvers.der.assembly import Assembly

    asm = sim.__dict__.setdefault("_energy_assembly", Assembly(sim.rod.n_nodes))
    return float(asm.elastic(sim.rod, sim.state, 0)[0])


def run(cfg: RibbonConfig, placement: str, duration: float, every: float, verbose: bool = True):
    """One run with ``cfg``'s block: (rows every ``every`` s, frames (time, edge lines (2, N, 2)),
    boxes (lo, hi))."""
    sim = RibbonSimulation(cfg.setup())
    dt = cfg.numerics.dt
    per = max(1, int(round(every / dt)))
    rows, frames = [], []
    x_prev, t_prev = sim.state.x.mean(0), sim.state.time
    for i in range(1, int(round(duration / dt)) + 1):
        sim.step(dt)
        if i % per:
            continue
        obs = sim.observe()
        c = sim.state.x.mean(0)
        v = (c - x_prev) / (sim.state.time - t_prev)
        x_prev, t_prev = c, sim.state.time
        gaps = sim.block_gaps()
        blk = sim.setup.blocks[0] if sim.setup.blocks else None
        rows.append(
            {
                "placement": placement,
                "block_heat": blk.heat if blk else "",
                "time [s]": obs["time [s]"],
                "centroid_x [mm]": c[0],
                "centroid_y [mm]": c[1],
                "velocity_x [mm/s]": v[0],
                "velocity_y [mm/s]": v[1],
                "heading [deg]": math.degrees(math.atan2(v[1], v[0])),
                "axis_angle [deg]": axis_angle(sim.state.x),
                "spin_start [rad]": obs["spin_start [rad]"],
                "spin_end [rad]": obs["spin_end [rad]"],
                "block_gap [mm]": float(gaps.min()) if len(gaps) else float("nan"),
                "T_mean [C]": obs["T_mean [C]"],
                "T_max [C]": obs["T_max [C]"],
                "twist_density [turns/mm]": obs["twist_density [turns/mm]"],
                "elastic_energy [mJ]": elastic_energy(sim),
            }
        )
        frames.append((sim.state.time, edge_lines(sim)[..., :2].copy()))
        r = rows[-1]
        if verbose:
            print(
                f"  {placement:6s} t {r['time [s]']:6.1f} s  centroid "
                f"({r['centroid_x [mm]']:7.2f}, "
                f"{r['centroid_y [mm]']:7.2f}) "
                f"mm  v ({r['velocity_x [mm/s]']:6.2f}, {r['velocity_y [mm/s]']:6.2f}) mm/s  axis "
                f"{r['axis_angle [deg]']:6.1f} "
                f"deg  spins {r['spin_start [rad]']:7.2f} {r['spin_end [rad]']:7.2f} rad  gap "
                f"{r['block_gap [mm]']:7.3f} "
                "mm",
                flush=True,
            )
    boxes = [(b.lo, b.hi) for b in sim.rod.boxes]
    return rows, frames, boxes


def movie(path: pathlib.Path, frames, boxes, title: str, frame_step: int = 1) -> pathlib.Path:
    """GIF of the ribbon's edge lines and the block (top view, plate coordinates [mm])."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.patches import Rectangle

    from lcefem.validation.studies.gridshell.fig5_plots import frame_image, write_gif

    # a fixed window: the ribbon's start and, with a block, 45 mm in front of it (a ribbon rolling
    # away leaves it)
    start = frames[0][1].reshape(-1, 2)
    lo = start.min(0) - np.array([10.0, 15.0])
    hi = start.max(0) + np.array([10.0, 45.0])
    for b_lo, b_hi in boxes:
        if start[:, 1].mean() > b_hi[1]:  # the ribbon starts on the +y side of the block
            lo = np.array([min(lo[0], b_lo[0] - 5.0), b_lo[1] - 5.0])
            hi = np.array([max(hi[0], b_hi[0] + 5.0), b_hi[1] + 45.0])
        else:
            lo = np.array([min(lo[0], b_lo[0] - 5.0), b_lo[1] - 45.0])
            hi = np.array([max(hi[0], b_hi[0] + 5.0), b_hi[1] + 5.0])
    images = []
    for t, lines in frames[::frame_step]:

        def draw(fig, t=t, lines=lines):
            ax = fig.add_subplot()
            for b_lo, b_hi in boxes:
                ax.add_patch(Rectangle(b_lo[:2], b_hi[0] - b_lo[0], b_hi[1] - b_lo[1], color="0.5"))
            ax.plot(lines[0, :, 0], lines[0, :, 1], "C0", lw=1.2)
            ax.plot(lines[1, :, 0], lines[1, :, 1], "C3", lw=1.2)
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_aspect("equal")
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_title(f"{title}, t = {t:.0f} s (top view; edge lines)", fontsize=9)

        images.append(frame_image(draw, size=(6.4, 4.0), dpi=70))
    return write_gif(path, images, 0.15)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--placements",
        nargs="+",
        default=["none", "middle", "end"],
        choices=["none", "middle", "end"],
    )
    parser.add_argument(
        "--width", type=float, default=20.0, help="width of the middle block along the ribbon [mm]"
    )
    parser.add_argument("--end-width", type=float, default=10.0, help="width of the end block [mm]")
    parser.add_argument("--height", type=float, default=10.0, help="block height [mm]")
    parser.add_argument(
        "--distance", type=float, default=5.0, help="centre line to the block's face [mm]"
    )
    parser.add_argument(
        "--friction", type=float, default=Block().friction, help="friction coefficient on the block"
    )
    parser.add_argument(
        "--block-heat",
        default=Block().heat,
        choices=list(Block.HEAT),
        help="the block's heat exchange with the ribbon (models.contact.Block.heat)",
    )
    parser.add_argument(
        "--block-temperature",
        type=float,
        default=Block().temperature,
        help="the block's temperature [C] with --block-heat given",
    )
    parser.add_argument(
        "--overlap",
        type=float,
        help="end block: how much of the ribbon's end it meets [mm] (default: all of --end-width)",
    )
    parser.add_argument(
        "--side",
        type=float,
        default=0.0,
        help="+1: block towards +y, -1: towards -y, 0: on the "
        "side the ribbon rolls to without a block (a run without one decides)",
    )
    parser.add_argument("--nodes", type=int)
    parser.add_argument(
        "--length",
        type=float,
        help="ribbon length [mm] (default: the rolling ribbon's 60 mm; the "
        "seed-000 robots' length is not given, issue 32 quotes ~12 cm)",
    )
    parser.add_argument("--dt", type=float)
    parser.add_argument("--duration", type=float, default=120.0, help="heated time [s]")
    parser.add_argument(
        "--ground-temperature", type=float, default=100.0, help="plate temperature [C]"
    )
    parser.add_argument("--every", type=float, default=1.0, help="row and frame interval [s]")
    parser.add_argument("--out", default="results/ribbon_blocks")
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        dest="changes",
        help="section.field=value: a change of RibbonConfig (e.g. material.youngs_modulus=1.0)",
    )
    args = parser.parse_args(argv)
    if args.length is not None and not args.length > 0:
        parser.error(f"--length = {args.length}: must be > 0")
    for name in ("width", "end_width", "height", "distance", "duration", "every"):
        if not getattr(args, name) > 0:
            parser.error(f"--{name.replace('_', '-')} = {getattr(args, name)}: must be > 0")
    if args.side not in (1.0, -1.0, 0.0):
        parser.error(f"--side = {args.side}: allowed 1, -1, 0")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    base = override(
        RibbonConfig(), "run", ground_temperature=args.ground_temperature, duration=args.duration
    )
    base = override(base, "numerics", nodes=args.nodes, dt=args.dt)
    base = override(base, "geometry", length=args.length)
    from lcefem.validation.app.config import assign_or_exit

    for change in args.changes:
        base = assign_or_exit(base, change)
    rows = []
    placements = list(args.placements)
    if args.side == 0.0:  # the reference run first: the block goes where the ribbon rolls
        if "none" in placements:
            placements.remove("none")
        free, frames, _ = run(base.validated(), "none", args.duration, args.every)
        rows += free
        args.side = 1.0 if free[-1]["centroid_y [mm]"] >= free[0]["centroid_y [mm]"] else -1.0
        if "none" in args.placements:
            movie(
                out / "block_none.gif", frames, [], f"{args.ground_temperature:g} C plate, no block"
            )
    for placement in placements:
        block = block_for(
            placement,
            args.width,
            args.end_width,
            args.height,
            args.distance,
            args.side,
            base.geometry.length,
            args.friction,
            args.block_heat,
            args.block_temperature,
        )
        if placement == "end" and args.overlap is not None:
            block = dataclasses.replace(
                block, offset=0.5 * (base.geometry.length + args.end_width) - args.overlap
            )
        cfg = RibbonConfig(
            **{**{f: getattr(base, f) for f in base.__dataclass_fields__}, "obstacle": block}
        ).validated()
        r, frames, boxes = run(cfg, placement, args.duration, args.every)
        rows += r
        movie(
            out / f"block_{placement}.gif",
            frames,
            boxes,
            f"{args.ground_temperature:g} C plate, block: {placement}"
            + (f" (block heat: {args.block_heat})" if args.block_heat != "none" else ""),
        )
    tmp = out / "blocks.csv.part"
    with open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, out / "blocks.csv")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
