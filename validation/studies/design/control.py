"""Closed-loop shape control of the robotic surface: a simulated surface, height sensor, controller.

``lcefem control --shape dome|saddle|cylinder|table [--inputs channels|strips] [--seed S]
[--ambient-offset K] [--payload-g G] [--noise-mm N] [--max-current A] [--sustained-current A]
[--settle S] [--no-load] [--no-failure] [--full-under-load] [--relinearise] [--sensing
markers|heights|oracle] [--no-movie] --out DIR [--overwrite] [--quiet]``

From flat, the surface is driven to a Fig. 4 target (the nominal bar-and-hinge surface at the
paper's lambdas) twice with the same drawn strips (resistance, current factor and lambda_N per strip
from the measured spreads, seeded; an ambient offset): open loop (the nominal current feed-forward
and the paper's 0.2 A boost) and closed loop (the circle curvatures measured through markers at the
ends of the middle ribbons and the centre, noisy, fed back through the design Jacobian; ``--sensing
heights`` estimates them from the nine junction-centre heights instead;
:mod:`lcefem.solvers.control`). Then a payload step on the centre (default 100 g) and, with the
payload removed, one strip failing (its coil open).

Outputs (run skeleton): history.csv (time [s], phase, per loop: input currents [A], circle
curvatures [1/mm], error [1/mm], centre height and its measurement [mm]), summary.json
(``closed_loop_error``, ``open_loop_error`` [1/mm]: the full-solve error at the end of the phase
from flat; per phase errors, times to target, current peaks, the drawn plant), control_errors.png,
control_currents.png, control_curvatures.png and control.gif (the nine junction centres, both
loops).
"""

from __future__ import annotations

import argparse
import math
import pathlib
import time
from dataclasses import dataclass

import numpy as np

from lcefem.meshes.gridshell import GridshellLayout
from lcefem.models.errors import InputError
from lcefem.models.parameters import describe
from lcefem.models.shape_control import CurrentLimits, HeightSensor, PlantSpread
from lcefem.solvers import control as ctl
from lcefem.solvers.runtime.checks import check_seed
from lcefem.solvers.runtime.files import replace as rename
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.solvers.runtime.run import Progress, Run
from lcefem.validation.cases.programs import SHAPE_DRIVES

PARALLEL = False  # serial numpy/scipy bar-and-hinge model
LOOPS = ("open", "closed")


@dataclass(frozen=True)
class ControlRequest:
    shape: str
    inputs: str = "channels"
    seed: int = 1
    spread: PlantSpread = PlantSpread()
    sensor: HeightSensor = HeightSensor()
    limits: CurrentLimits = CurrentLimits()
    scenario: ctl.Scenario = ctl.Scenario()
    ribbons: int = 3
    movie: bool = True
    settings: ctl.ControllerSettings = ctl.ControllerSettings()

    def validated(self) -> "ControlRequest":
        if self.shape not in SHAPE_DRIVES:
            raise InputError(f"--shape = {self.shape!r}: allowed {', '.join(SHAPE_DRIVES)}")
        if self.settings.sensing not in ctl.SENSING:
            raise InputError(
                f"--sensing = {self.settings.sensing!r}: allowed {', '.join(ctl.SENSING)}"
            )
        if self.inputs not in ctl.INPUT_MODES:
            raise InputError(f"--inputs = {self.inputs!r}: allowed {', '.join(ctl.INPUT_MODES)}")
        check_seed("--seed", self.seed)
        if self.ribbons < 3 or self.ribbons % 2 == 0:
            raise InputError(
                f"--ribbons = {self.ribbons}: an odd number >= 3 (nine junction centres at least)"
            )
        for flag, v in (
            ("--max-current", self.limits.maximum),
            ("--sustained-current", self.limits.sustained),
        ):
            if not math.isfinite(v) or v <= 0.0 or v > 1.0:
                raise InputError(f"{flag} = {v}: a current in A, > 0 and <= 1")
        if self.limits.sustained > self.limits.maximum:
            raise InputError(
                f"--sustained-current = {self.limits.sustained}: must not exceed "
                f"--max-current = {self.limits.maximum}"
            )
        if not math.isfinite(self.sensor.noise) or self.sensor.noise < 0:
            raise InputError(f"--noise-mm = {self.sensor.noise}: a standard deviation in mm, >= 0")
        if not math.isfinite(self.spread.payload_mass) or self.spread.payload_mass < 0:
            raise InputError(f"--payload-g = {self.spread.payload_mass * 1e6}: a mass in g, >= 0")
        if not math.isfinite(self.spread.ambient_offset) or abs(self.spread.ambient_offset) > 30:
            raise InputError(f"--ambient-offset = {self.spread.ambient_offset}: in K, within +-30")
        sc = self.scenario
        if not math.isfinite(sc.settle) or not 10.0 <= sc.settle <= 3600.0:
            raise InputError(f"--settle = {sc.settle}: seconds, between 10 and 3600")
        return self

    def resolved(self) -> dict:
        return {
            "shape": self.shape,
            "inputs": self.inputs,
            "seed": self.seed,
            "ribbons": self.ribbons,
            "spread": describe(self.spread),
            "sensor": describe(self.sensor),
            "limits": describe(self.limits),
            "scenario": describe(self.scenario),
            "controller": describe(self.settings),
        }


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--shape", default="dome", help="target: " + ", ".join(SHAPE_DRIVES) + " (seed 001, Fig. 4)"
    )
    p.add_argument(
        "--inputs",
        default="channels",
        help="channels (Tx, Ty, Bx, By) or strips (every strip its own current)",
    )
    p.add_argument(
        "--seed", type=int, default=1, help="seed of the drawn strips and the sensor noise"
    )
    p.add_argument(
        "--ambient-offset",
        type=float,
        default=PlantSpread().ambient_offset,
        help="room temperature minus the model's 25 C [K] (default -3)",
    )
    p.add_argument(
        "--payload-g",
        type=float,
        default=PlantSpread().payload_mass * 1e6,
        help="centre payload of the load step [g] (default 100)",
    )
    p.add_argument(
        "--noise-mm",
        type=float,
        default=HeightSensor().noise,
        help="sensor noise, 1 SD [mm] (default 0.1)",
    )
    p.add_argument(
        "--max-current", type=float, default=CurrentLimits().maximum, help="[A] (default 0.2)"
    )
    p.add_argument(
        "--sustained-current",
        type=float,
        default=CurrentLimits().sustained,
        help="current allowed beyond the 30 s boost [A] (default 0.1)",
    )
    p.add_argument("--settle", type=float, default=ctl.Scenario().settle, help="time from flat [s]")
    p.add_argument("--ribbons", type=int, default=3, help="ribbons per direction (odd, >= 3)")
    p.add_argument("--no-load", action="store_true", help="skip the payload step")
    p.add_argument("--no-failure", action="store_true", help="skip the strip failure")
    p.add_argument(
        "--full-under-load",
        action="store_true",
        help="full equilibria under the payload too (slow; default: tangent map)",
    )
    p.add_argument(
        "--relinearise",
        action="store_true",
        help="recompute the sensitivities at each full solve (plant tangent map and controller)",
    )
    p.add_argument(
        "--sensing",
        default=ctl.ControllerSettings().sensing,
        help="feedback: markers (circle curvatures through the ends of the middle ribbons and "
        "the centre, noisy), heights (the nine junction-centre heights, curvature estimated), "
        "oracle (true curvature, noise-free)",
    )
    p.add_argument("--no-movie", action="store_true", help="skip control.gif")
    add_out_arguments(p, "results/control")


def prepare(args: argparse.Namespace) -> ControlRequest:
    for name in (
        "ambient_offset",
        "payload_g",
        "noise_mm",
        "max_current",
        "sustained_current",
        "settle",
    ):
        v = getattr(args, name)
        if not math.isfinite(v):
            raise InputError(f"--{name.replace('_', '-')} = {v}: must be a finite number")
    sc = ctl.Scenario(
        settle=args.settle,
        load_phase=0.0 if args.no_load else ctl.Scenario().load_phase,
        failure_phase=0.0 if args.no_failure else ctl.Scenario().failure_phase,
        full_under_load=args.full_under_load,
        relinearise=args.relinearise,
    )
    return ControlRequest(
        str(args.shape),
        str(args.inputs),
        args.seed,
        PlantSpread(ambient_offset=args.ambient_offset, payload_mass=args.payload_g * 1e-6),
        HeightSensor(noise=args.noise_mm),
        CurrentLimits(maximum=args.max_current, sustained=args.sustained_current),
        sc,
        args.ribbons,
        not args.no_movie,
        ctl.ControllerSettings(sensing=str(args.sensing)),
    ).validated()


def run_pair(req: ControlRequest, surface: ctl.Surface | None = None, progress=None) -> dict:
    """Open and closed loop on the same drawn plant: {"surface", "draw", "open", "closed",
    "names"}."""
    surface = surface or ctl.build_surface(
        req.shape, SHAPE_DRIVES[req.shape], GridshellLayout(ribbons=req.ribbons)
    )
    draw = ctl.draw_plant(surface, req.spread, req.seed)
    out = {"surface": surface, "draw": draw, "names": surface.selection(req.inputs)[1]}
    for k, loop in enumerate(LOOPS):
        out[loop] = ctl.simulate(
            surface,
            draw,
            mode=req.inputs,
            feedback=loop == "closed",
            scenario=req.scenario,
            spread=req.spread,
            sensor=req.sensor,
            limits=req.limits,
            settings=req.settings,
            seed=req.seed,
            progress=None
            if progress is None
            else (lambda t, k=k: progress(k * req_total(req) + t)),
        )
    return out


def req_total(req: ControlRequest) -> float:
    return sum(e - s for _, s, e in req.scenario.phases())


def history_columns(names: list[str]) -> list[str]:
    cols = ["time [s]", "phase [-]"]
    for loop in LOOPS:
        cols += [f"{loop} current {n} [A]" for n in names]
        cols += [
            f"{loop} circle kappa_x [1/mm]",
            f"{loop} circle kappa_y [1/mm]",
            f"{loop} error [1/mm]",
            f"{loop} centre height [mm]",
            f"{loop} measured centre height [mm]",
        ]
    return cols


def loop_summary(surface: ctl.Surface, r: ctl.RunResult) -> dict:
    return {
        "phase end error [1/mm]": r.phase_errors,
        "phase end is a full equilibrium": r.phase_full,
        "time to target [s]": r.time_to_target,
        "phase end kappa [1/mm]": {
            k: [float(v) for v in y[surface.heights : surface.heights + 2]]
            for k, y in r.phase_outputs.items()
        },
        "largest current [A]": r.max_current,
        "longest boost above the sustained current [s]": r.longest_boost,
        "peak strip temperature [C]": r.peak_temperature,
    }


def run_control(req: ControlRequest, out: pathlib.Path | None, progress: bool = True) -> dict:
    started = time.perf_counter()
    bar = Progress(2 * req_total(req), "control", "s", ".0f", progress)
    surface = ctl.build_surface(
        req.shape, SHAPE_DRIVES[req.shape], GridshellLayout(ribbons=req.ribbons)
    )
    names = surface.selection(req.inputs)[1]
    with Run(out, config=req.resolved(), columns=history_columns(names), progress=bar) as run:
        pair = run_pair(req, surface, progress=bar.to)
        o, c = pair["open"], pair["closed"]
        phases = req.scenario.phases()
        k = surface.heights
        centre = k // 2
        for i, t in enumerate(c.times):
            ph = next(j for j, (_, s, e) in enumerate(phases) if s <= t < e)
            row = {"time [s]": float(t), "phase [-]": ph}
            for loop, r in (("open", o), ("closed", c)):
                row.update(
                    {f"{loop} current {n} [A]": float(v) for n, v in zip(names, r.inputs[i])}
                )
                row.update(
                    {
                        f"{loop} circle kappa_x [1/mm]": float(r.observables[i, k]),
                        f"{loop} circle kappa_y [1/mm]": float(r.observables[i, k + 1]),
                        f"{loop} error [1/mm]": float(r.errors[i]),
                        f"{loop} centre height [mm]": float(r.observables[i, centre]),
                        f"{loop} measured centre height [mm]": float(r.measured[i, centre]),
                    }
                )
            run.record(row, where=f"t = {t} s")
        figures = []
        if out is not None:
            figures = control_figures(out, req, pair)
            if req.movie:
                figures.append(control_movie(out / "control.gif", req, pair))
        draw = pair["draw"]
        summary = {
            "model": "bar-and-hinge gridshell, closed-loop shape control (lcefem.solvers.control)",
            "shape": req.shape,
            "inputs": req.inputs,
            "closed_loop_error": c.phase_errors["target"],
            "open_loop_error": o.phase_errors["target"],
            "error unit": "1/mm: max |circle kappa - target| over x and y, full equilibrium at "
            "the end of "
            "the phase from flat",
            "tolerance [1/mm]": ctl.TOLERANCE,
            "target kappa [1/mm]": [float(v) for v in surface.y_star[k : k + 2]],
            "target lambdas [-]": {
                n: float(v)
                for n, v in zip(
                    names,
                    (surface.selection(req.inputs)[0].T @ surface.p_star)
                    / surface.selection(req.inputs)[0].sum(axis=0),
                )
            },
            "phases [s]": {n: [s, e] for n, s, e in phases},
            "open": loop_summary(surface, o),
            "closed": loop_summary(surface, c),
            "failed strip": int(surface.eq.params.names[ctl.failing_strip(surface, None)]),
            "drawn plant": {
                "segment resistance [ohm]": [
                    float(draw["resistance"].min()),
                    float(draw["resistance"].max()),
                ],
                "current factor [-]": [
                    float(draw["current_factor"].min()),
                    float(draw["current_factor"].max()),
                ],
                "lambda_N [-]": [float(draw["lambda_N"].min()), float(draw["lambda_N"].max())],
                "ambient [C]": 25.0 + req.spread.ambient_offset,
            },
            "full equilibria": surface.full_solves,
            "full equilibria time [s]": surface.seconds,
            "figures": [p.name for p in figures],
            "wall time [s]": time.perf_counter() - started,
        }
        return run.complete(summary)


# ------------------------------------------------------------------------------------ figures
def _phase_lines(ax, phases) -> None:
    for name, s, e in phases[1:]:
        ax.axvline(s, color="0.6", lw=0.8, ls=":")
        ax.text(
            s,
            1.0,
            f" {name}",
            transform=ax.get_xaxis_transform(),
            va="top",
            fontsize=8,
            color="0.4",
        )


def _save(fig, path: pathlib.Path) -> pathlib.Path:
    part = path.with_name(path.stem + ".part" + path.suffix)
    fig.savefig(part, dpi=110)
    rename(part, path)
    return path


def control_figures(out: pathlib.Path, req: ControlRequest, pair: dict) -> list[pathlib.Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    surface, o, c, names = pair["surface"], pair["open"], pair["closed"], pair["names"]
    phases = req.scenario.phases()
    k = surface.heights
    paths = []
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.semilogy(o.times, np.maximum(o.errors, 1e-6), label="open loop")
    ax.semilogy(c.times, np.maximum(c.errors, 1e-6), label="closed loop")
    for loop, r, m in (("open", o, "o"), ("closed", c, "s")):
        for name, s, e in phases:
            ax.plot(
                [e],
                [max(r.phase_errors[name], 1e-6)],
                m,
                color="C0" if loop == "open" else "C1",
                mfc="none",
            )
    ax.axhline(ctl.TOLERANCE, color="k", ls="--", lw=0.8, label="0.002 1/mm")
    _phase_lines(ax, phases)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("max |kappa - target| [1/mm]")
    ax.set_title(f"{req.shape}: curvature error (markers: full equilibria)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    paths.append(_save(fig, out / "control_errors.png"))
    plt.close(fig)

    fig, axes = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True)
    for ax, r, loop in zip(axes, (o, c), LOOPS):
        if len(names) <= 4:
            for j, n in enumerate(names):
                ax.plot(r.times, r.inputs[:, j], label=n)
            ax.legend(fontsize=8, ncol=4)
        else:
            ax.plot(r.times, r.inputs, lw=0.6)
        ax.axhline(req.limits.sustained, color="0.5", ls="--", lw=0.8)
        ax.set_ylabel(f"{loop} loop current [A]")
        _phase_lines(ax, phases)
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    paths.append(_save(fig, out / "control_currents.png"))
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 4))
    for j, axis in enumerate("xy"):
        ax.plot(
            o.times, o.observables[:, k + j], ls="--", color=f"C{j}", label=f"open kappa_{axis}"
        )
        ax.plot(c.times, c.observables[:, k + j], color=f"C{j}", label=f"closed kappa_{axis}")
        ax.axhline(surface.y_star[k + j], color=f"C{j}", lw=0.6, ls=":")
    _phase_lines(ax, phases)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("circle curvature [1/mm]")
    ax.set_title(f"{req.shape}: centre curvatures (dotted: target)")
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    paths.append(_save(fig, out / "control_curvatures.png"))
    plt.close(fig)
    return paths


def control_movie(
    path: pathlib.Path, req: ControlRequest, pair: dict, frames: int = 40
) -> pathlib.Path:
    """The nine junction centres (heights by the tangent map; in-plane positions of the target)
    of both loops against the target, as a GIF (matplotlib's Pillow writer)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    from lcefem.solvers.analysis.curvature import junction_centre_points

    surface, o, c = pair["surface"], pair["open"], pair["closed"]
    n = surface.structure.info["ribbons"]
    xy = junction_centre_points(surface.structure, surface.x_star)[..., :2]
    k = surface.heights
    target = surface.y_star[:k].reshape(n, n)
    idx = np.linspace(0, len(c.times) - 1, frames).astype(int)
    fig = plt.figure(figsize=(8, 4))
    axes = [fig.add_subplot(1, 2, j + 1, projection="3d") for j in range(2)]
    zlo = min(o.observables[:, :k].min(), c.observables[:, :k].min(), target.min()) - 2
    zhi = max(o.observables[:, :k].max(), c.observables[:, :k].max(), target.max()) + 2

    def draw(f):
        i = idx[f]
        for ax, r, loop in zip(axes, (o, c), LOOPS):
            ax.cla()
            ax.plot_wireframe(xy[..., 0], xy[..., 1], target, color="0.6", lw=0.6)
            ax.plot_wireframe(
                xy[..., 0],
                xy[..., 1],
                r.observables[i, :k].reshape(n, n),
                color="C1" if loop == "closed" else "C0",
            )
            ax.set_zlim(zlo, zhi)
            ax.set_title(
                f"{loop} loop, t = {r.times[i]:.0f} s\nerror {r.errors[i]:.4f} 1/mm", fontsize=9
            )
            ax.set_xlabel("x [mm]", fontsize=7)
            ax.set_ylabel("y [mm]", fontsize=7)
            ax.set_zlabel("z [mm]", fontsize=7)
        return axes

    anim = FuncAnimation(fig, draw, frames=frames)
    part = path.with_name(path.stem + ".part" + path.suffix)
    anim.save(part, writer=PillowWriter(fps=6), dpi=60)
    plt.close(fig)
    rename(part, path)
    return path


def main(args: argparse.Namespace) -> int:
    req = args.prepared
    s = run_control(req, pathlib.Path(args.out), progress=not args.quiet)
    o, c = s["open"], s["closed"]
    ttt = c["time to target [s]"]["target"]
    extra = "; ".join(
        f"{ph}: open {o['phase end error [1/mm]'][ph]:.4f}, closed "
        f"{c['phase end error [1/mm]'][ph]:.4f}"
        for ph in c["phase end error [1/mm]"]
        if ph != "target"
    )
    print(
        f"lcefem: control {req.shape}: error from flat open loop {s['open_loop_error']:.5f}, "
        "closed "
        "loop "
        f"{s['closed_loop_error']:.5f} 1/mm (tolerance {ctl.TOLERANCE}); closed loop within it "
        "after "
        f"{ttt:.0f} s; {extra} 1/mm; {s['wall time [s]']:.1f} s; results in {args.out}"
    )
    return 0
