"""Inverse design of the robotic surface: target centre curvatures -> strip lambdas -> currents.

``lcefem design --target-kx -0.016 --target-ky -0.016 [--target-height H] [--channels 4|all]
[--support clamp|rollers|table] [--ribbons N | --layout NAME|FILE] [--no-check] --out DIR
[--overwrite] [--quiet]``; with ``--layout`` (docs/layouts/index.md) the design variables default to
the layout's wiring (``--channels wiring``: one lambda per drive tag of ``layout.wiring``).

Finds lambdas in [1.05, lambda_N] (one per channel Tx, Ty, Bx, By, or one per strip) whose stable
equilibrium has the target centre curvatures (the paper's circle measure, dome negative) by least
squares with exact sensitivities (:mod:`lcefem.validation.studies.design.gridshell_design`), then
the currents of both current routes (segment, eq1). By default the design is one the surface reaches
from flat: the run's own path (``lcefem run gridshell``, the ramp from the as-built state) at the
lambdas printed ends within the design tolerance (1e-4 1/mm) of the target
(:func:`lcefem.validation.studies.design.gridshell_design.reach`). Where the run's ramp from flat
lands on another branch at every constant set tried, the design is a *program*: channel drives held
one after the other (an overshoot, then the release to the design's lambdas), written as
``program_schedule.toml`` and replayed here as ``lcefem run gridshell --schedule`` does (its final
curvatures in summary.json). ``--no-check`` prints the design loop's lambdas unchecked.

Outputs in --out DIR (through the run skeleton lcefem.solvers.runtime.run.Run): summary.json
(target, lambdas, currents per route, achieved curvatures in the design loop and in the forward
check, residual [1/mm], optimiser record, forward solves, Newton iterations, wall time; "reach": how
the run's path gets there, every path tried) and design.csv
(one row per design variable, numbered in the order of summary.json's "lambdas [-]": channels Tx,
Ty, Bx, By, or strip ids: lambda [-], segment-route current [A], eq1-route current [A]).
A target outside the reachable set ends normally with the smallest residual found (reported).
"""

from __future__ import annotations

import argparse
import math
import pathlib
import time
from dataclasses import dataclass

from lcefem.meshes.gridshell import GridshellLayout
from lcefem.meshes.gridshell_layout import Layout
from lcefem.models.errors import InputError
from lcefem.models.parameters import describe
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.solvers.runtime.files import write_text
from lcefem.solvers.runtime.outdir import add_out_arguments
from lcefem.solvers.runtime.run import Progress, Run
from lcefem.validation.studies.design import gridshell_design as gd
from lcefem.validation.studies.gridshell import calibrate

PARALLEL = False
COLUMNS = ["variable [-]", "lambda [-]", "current segment route [A]", "current eq1 route [A]"]


@dataclass(frozen=True)
class DesignRequest:
    kx: float
    ky: float
    height: float | None
    channels: str
    support: str
    check: bool
    ribbons: int = 3
    model_set: str = calibrate.DEFAULT_MODEL_SET
    layout: Layout | None = None  # --layout (default: the published grid with ``ribbons``)

    @property
    def grid(self) -> Layout:
        return self.layout or GridshellLayout(ribbons=self.ribbons)

    def validated(self) -> "DesignRequest":
        for name, v in (("target-kx", self.kx), ("target-ky", self.ky)):
            if not math.isfinite(v) or abs(v) > 0.2:
                raise InputError(
                    f"--{name} = {v}: a curvature in 1/mm with |kappa| <= 0.2 (a radius "
                    "of at least 5 mm)"
                )
        # A centre cannot rise or sink by more than the surface's own side, 141 mm (4 x 30 mm
        # segments + 3 x 7 mm junctions, published reduced-order model; docs/sources.md).
        if self.height is not None and not (
            math.isfinite(self.height) and abs(self.height) <= 141.0
        ):
            raise InputError(
                f"--target-height = {self.height}: a finite height in mm with |H| <= 141 "
                "(the surface's side length)"
            )
        if self.channels not in gd.CHANNEL_MODES:
            raise InputError(
                f"--channels = {self.channels!r}: allowed {', '.join(gd.CHANNEL_MODES)}"
            )
        if self.grid.ribbons < 1 or self.grid.ribbons % 2 == 0:
            raise InputError(
                f"--ribbons = {self.grid.ribbons}: an odd number >= 1 (the centre junction)"
            )
        if self.support not in problem_bh.SUPPORTS:
            raise InputError(
                f"--support = {self.support!r}: allowed {', '.join(problem_bh.SUPPORTS)}"
            )
        if self.model_set not in calibrate.MODEL_SETS:
            raise InputError(
                f"--model-set = {self.model_set!r}: allowed {', '.join(calibrate.MODEL_SETS)}"
            )
        return self


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--target-kx",
        type=float,
        required=True,
        help="target centre curvature along x [1/mm] (circle measure; dome negative)",
    )
    p.add_argument(
        "--target-ky", type=float, required=True, help="target centre curvature along y [1/mm]"
    )
    p.add_argument(
        "--target-height",
        type=float,
        default=None,
        help="also match the centre junction's height [mm]",
    )
    p.add_argument(
        "--channels",
        default=None,
        help="design variables: 4 (channels Tx, Ty, Bx, By; the "
        "default), all (every strip) or wiring (the drive tags of --layout's wiring; the default "
        "with --layout)",
    )
    p.add_argument("--support", default="rollers", help="clamp, rollers or table (default rollers)")
    p.add_argument("--ribbons", type=int, default=None, help="ribbons per direction (default 3)")
    p.add_argument(
        "--layout",
        help="a gridshell layout: a name (published, 5x5, rhombic60, ...) or a TOML "
        "file with a [layout] section (docs/layouts/index.md)",
    )
    p.add_argument(
        "--no-check", action="store_true", help="skip the forward run from the as-built state"
    )
    p.add_argument(
        "--model-set",
        default=calibrate.DEFAULT_MODEL_SET,
        help="bar-and-hinge model set with its configuration: fe-calibrated (default: the strip "
        "element, the plate's torsion and the factors fitted to the 3D FE, in the glue "
        "squares and contact they were fitted in) or published (the published model's "
        "elements and factors, contracting squares; docs/gridshell_calibration.md)",
    )
    add_out_arguments(p, "results/design")


def prepare(args: argparse.Namespace) -> DesignRequest:
    layout = None
    if getattr(args, "layout", None):
        from lcefem.validation.app.layouts import load_layout

        if args.ribbons is not None:
            raise InputError("--ribbons: not with --layout (set layout.ribbons in the layout)")
        layout = load_layout(args.layout)
    channels = args.channels if args.channels is not None else ("wiring" if layout else "4")
    ribbons = 3 if args.ribbons is None else args.ribbons
    return DesignRequest(
        args.target_kx,
        args.target_ky,
        args.target_height,
        str(channels),
        args.support,
        not args.no_check,
        ribbons,
        args.model_set,
        layout,
    ).validated()


def run_design(req: DesignRequest, out: pathlib.Path | None, progress: bool = True) -> dict:
    started = time.perf_counter()
    design = gd.setup_design(
        req.channels,
        req.support,
        height=req.height is not None,
        layout=req.grid,
        model_set=req.model_set,
    )
    config = {
        "target": {
            "kappa_x [1/mm]": req.kx,
            "kappa_y [1/mm]": req.ky,
            "centre height [mm]": req.height,
        },
        "channels": req.channels,
        "support": req.support,
        "ribbons": req.grid.ribbons,
        "layout": describe(req.grid),
        "model set": req.model_set,
        "model set configuration": calibrate.model_set(req.model_set).configuration,
        "bounds [-]": [gd.LAMBDA_MIN, design.lambda_N],
        "observable": "circle curvature through the centre junction and the middle ribbon's ends "
        "(seed 001, gridshell without cover scales)",
    }
    with Run(
        out,
        config=config,
        columns=COLUMNS,
        history="design.csv",
        progress=Progress(1.0, "design", "", ".0f", progress),
    ) as run:
        result = gd.inverse(design, req.kx, req.ky, height=req.height, check=req.check)
        summary = gd.design_summary(design, result)
        found = (result.check or {}).get("reach")
        if found is not None and found.kind == "program" and out is not None:
            schedule = gd.program_schedule(
                design,
                found.stages,
                [f"overshoot {k + 1}" for k in range(len(found.stages) - 1)]
                + ["release to the design"],
            )
            # replayed before the file is written: a failed replay leaves no complete-looking
            # schedule
            replayed = gd.replay(design, schedule)
            comment = (
                f"lcefem design --target-kx {req.kx} --target-ky {req.ky} (support {req.support}, "
                f"model set {req.model_set}): no constant set of lambdas tried reaches the target "
                "from flat;\nthis program does (replay: lcefem run gridshell --schedule THIS_FILE; "
                f"replayed here: {replayed['circle_x']:.6f} / {replayed['circle_y']:.6f} 1/mm).\n"
                "Drives per stage (lambdas [-]):\n"
                + "\n".join(
                    ", ".join(f"{k}={v:.5f}" for k, v in d.items())
                    for d in summary["reach"]["stages"]
                )
            )
            write_text(out / "program_schedule.toml", gd.schedule_toml(schedule, comment))
            summary["program schedule"] = {
                "file": "program_schedule.toml",
                "replay [1/mm]": replayed,
            }
        currents = summary["currents [A]"]
        for j, (name, lam) in enumerate(summary["lambdas [-]"].items()):
            run.record(
                {
                    "variable [-]": j,
                    "lambda [-]": lam,
                    "current segment route [A]": currents["segment"][name],
                    "current eq1 route [A]": currents["eq1"][name],
                },
                where=f"variable {name}",
            )
        summary["wall time [s]"] = time.perf_counter() - started
        summary.update({"ribbons": req.ribbons, "model set": req.model_set})
        return run.complete({"model": "bar-hinge gridshell, inverse design", **summary})


def protocol(s: dict, out) -> str:
    """How the printed design is reached from flat: the command that replays it."""
    found = s.get("reach")
    if found is None:
        return "unchecked (--no-check): the design loop's lambdas"
    lam = ",".join(f"{k}={v:.5f}" for k, v in s["lambdas [-]"].items())
    reached = s["distance from the target along the run's path [1/mm]"]
    if found["kind"] == "constant":
        extra = f" --ribbons {s['ribbons']}" if s.get("ribbons", 3) != 3 else ""
        # the run's --model-set (branch grid) defaults to the FE-calibrated set, design's default
        # too
        if s.get("model set", calibrate.DEFAULT_MODEL_SET) != calibrate.DEFAULT_MODEL_SET:
            extra += f" --model-set {s['model set']}"
        return (
            f"reached from flat by `lcefem run gridshell --lambda {lam} --support "
            f"{s['support']}{extra}` "
            f"({reached:.1e} 1/mm off)"
        )
    if found["kind"] == "program":
        r = s.get("program schedule", {}).get("replay [1/mm]")
        replayed = f", replay {r['circle_x']:.5f}/{r['circle_y']:.5f}" if r else ""
        return (
            f"no constant lambdas reach it from flat; a program of {len(found['stages'])} drives "
            "does "
            f"({reached:.1e} 1/mm off{replayed}): `lcefem run gridshell --schedule "
            f"{pathlib.Path(out) / 'program_schedule.toml'}`"
        )
    a = s["achieved (forward run from as built) [1/mm]"]
    return (
        f"NOT reached from flat: the closest run ends {a['kappa_x']:.5f}/{a['kappa_y']:.5f} "
        f"({reached:.1e} 1/mm off; no program found)"
    )


def main(args: argparse.Namespace) -> int:
    s = run_design(args.prepared, pathlib.Path(args.out), progress=not args.quiet)
    lams = ", ".join(f"{k}={v:.4f}" for k, v in list(s["lambdas [-]"].items())[:8])
    t = s["target"]
    print(
        f"lcefem: design: target {t['kappa_x [1/mm]']:.4f}/{t['kappa_y [1/mm]']:.4f} 1/mm; lambdas "
        f"{lams}; "
        f"{protocol(s, args.out)}; {s['time [s]']:.1f} s inverse (with checks), "
        f"{s['wall time [s]']:.1f} s in all; results in {args.out}"
    )
    return 0
