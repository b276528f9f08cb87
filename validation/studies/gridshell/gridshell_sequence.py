"""``lcefem run gridshell --schedule FILE.toml``: programmed shape sequences of the robotic surface
(seed 001, Fig. 5A and 5C). The schedule, the heat balance per selection and the quasi-static
surface are :mod:`lcefem.solvers.problems.gridshell_bh_sequence` (import them from there); this
module holds the command line (prepare, main, dispatched from
lcefem.validation.app.commands.gridshell) and the figures: curvature_vs_time.png and snapshot_NN.png
(a render at the end of each phase NN of the schedule).
"""

from __future__ import annotations

import dataclasses
import pathlib

from lcefem.models.errors import InputError
from lcefem.solvers.problems.gridshell_bh_sequence import (
    CURVATURE_COLUMNS,
    Schedule,
    check_selections,
    load_schedule,
    run_sequence,
)
from lcefem.validation.app.plots import save_figure
from lcefem.validation.studies.gridshell import calibrate


def snapshot(
    out: pathlib.Path, phase: int, label: str, t: float, structure, x, support: str
) -> None:
    """snapshot_NN.png: the surface at the end of phase NN."""
    from lcefem.validation.studies.gridshell.gridshell_plots import render_gridshell

    render_gridshell(
        out / f"snapshot_{phase:02d}.png",
        structure,
        x,
        f"t = {t:g} s: end of '{label}' ({support})",
    )


def plot_curvatures(path: pathlib.Path, history: dict, schedule: Schedule) -> pathlib.Path:
    """Centre curvatures against time (both measures), switch times marked and labelled (atomic)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4))
    t = history["time [s]"]
    for col, style in zip(CURVATURE_COLUMNS, ("-", "--", "-", "--")):
        ax.plot(
            t,
            history[col],
            style,
            label=col.replace(" [1/mm]", ""),
            color="C0" if "kappa_x" in col else "C1",
            alpha=1.0 if "circle" in col else 0.6,
        )
    for i, ts in enumerate(schedule.times):
        ax.axvline(ts, color="0.8", lw=0.8)
        if schedule.labels:
            ax.text(
                ts,
                1.0,
                " " + schedule.labels[i],
                rotation=90,
                va="top",
                fontsize=7,
                transform=ax.get_xaxis_transform(),
            )
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("centre curvature [1/mm] (dome negative)")
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    path = save_figure(fig, path, 120)
    plt.close(fig)
    return path


def surface_model(schedule: Schedule, model_set: str | None = None, layout=None):
    """(model set, structure, materials) a schedule is replayed on: the model set named on the
    command line (``model_set``), else the schedule's own (``schedule.model_set``, written by
    ``lcefem design``), else
    :data:`lcefem.validation.studies.gridshell.calibrate.DEFAULT_MODEL_SET`; the layout ``layout``
    (--layout), else the schedule's ``[layout]``, else the published 3 x 3. The one place both the
    command and :func:`lcefem.validation.studies.design.gridshell_design.replay` build it."""
    name = model_set or schedule.model_set or calibrate.DEFAULT_MODEL_SET
    if name not in calibrate.MODEL_SETS:
        raise InputError(
            f"schedule.model_set = {name!r}: allowed {', '.join(calibrate.MODEL_SETS)}"
        )
    ms = calibrate.model_set(name)
    layout = layout or schedule.layout
    return ms, ms.structure(layout), ms.materials_for(layout)


def prepare(args) -> Schedule:
    """The validated schedule (before the output folder is claimed); the other drive options of
    ``run gridshell`` do not combine with it. --model-set and --layout replace the schedule's
    own."""
    for flag, value in (
        ("--shape", args.shape),
        ("--recipe", args.recipe),
        ("--lambda", args.lambdas),
        ("--current", args.currents),
        ("--config", args.config),
    ):
        if value is not None:
            raise InputError(f"{flag}: not with --schedule (the schedule sets the currents)")
    schedule = load_schedule(args.schedule)
    if args.support is not None:
        schedule = dataclasses.replace(schedule, support=args.support)
    if args.thermal_model is not None:
        schedule = dataclasses.replace(schedule, thermal_model=args.thermal_model)
    if getattr(args, "layout", None):
        from lcefem.validation.app.layouts import load_layout

        schedule = dataclasses.replace(schedule, layout=load_layout(args.layout))
    if getattr(args, "model_set", None):
        schedule = dataclasses.replace(schedule, model_set=args.model_set)
    check_selections(schedule, surface_model(schedule)[1])
    return schedule


def main(args) -> int:
    """``lcefem run gridshell --schedule FILE`` (called from
    lcefem.validation.app.commands.gridshell)."""
    schedule = args.prepared
    # the schedule's model set (lcefem design writes it), --model-set, or the default one
    model_set, structure, materials = surface_model(schedule)
    config = {
        "schedule": dataclasses.asdict(schedule),
        "model set": model_set.name,
        "model set configuration": model_set.configuration,
    }
    summary = run_sequence(
        schedule,
        pathlib.Path(args.out),
        progress=not args.quiet,
        snapshot=snapshot,
        report=lambda out, history, sched: plot_curvatures(
            out / "curvature_vs_time.png", history, sched
        ),
        structure=structure,
        materials=materials,
        config=config,
        exchange_factor=model_set.exchange_factor,
    )
    f = summary["final"]
    print(
        f"lcefem: gridshell sequence ({summary['support']}, thermal model "
        f"{summary['thermal model']}): "
        f"{summary['outputs']} outputs to t = {schedule.end:g} s; final centre curvature x/y "
        "[1/mm]: "
        f"circle {f['circle kappa_x [1/mm]']:.4f}/{f['circle kappa_y [1/mm]']:.4f}, quadratic fit "
        f"{f['quad kappa_x [1/mm]']:.4f}/{f['quad kappa_y [1/mm]']:.4f}; deepest strip-ribbon "
        "penetration "
        f"{summary['strip-ribbon penetration [mm]']:.2f} mm"
        + (" (strips pass through the ribbon)" if summary["strips pass through the ribbon"] else "")
        + "; "
        f"{summary['wall_time [s]']:.1f} s; results in {args.out}"
    )
    return 0
