"""The robotic surface's Fig. 5 tasks (seed 001) as studies that write their results into a folder:
the programmed sequence with the cover scales (Fig. 5A), the ball (Fig. 5B) and the weights (Fig. 5C).
Used by the validation cases (lcefem.validation.cases.gridshell_fig5_bh) and by
``lcefem run gridshell --task sequence|ball|weights`` (lcefem.validation.commands.gridshell);
docs/fig5_tasks.md."""

from __future__ import annotations

import dataclasses
import json
import pathlib

import numpy as np

from lcefem.models.cover_scales import CoverScales
from lcefem.solvers.problems.gridshell_bh_sequence import load_schedule, phase_ends, run_sequence
from lcefem.solvers.run import write_text
from lcefem.validation import fig5_plots

DATA = pathlib.Path(__file__).resolve().parent / "data"
FIG5A_SCHEDULE = DATA / "gridshell_fig5a_schedule.toml"
TASKS = ("sequence", "ball", "weights")


def write_json(path: pathlib.Path, data: dict) -> pathlib.Path:
    return write_text(pathlib.Path(path), json.dumps(data, indent=2, default=float) + "\n")


# ------------------------------------------------------------------------------ Fig. 5A sequence
def scale_sequence(out: pathlib.Path, *, schedule_path=FIG5A_SCHEDULE, output_interval: float | None = None,
                   scales: CoverScales | None = CoverScales(), movie: bool = True, progress: bool = False,
                   schedule=None) -> dict:
    """The schedule on the covered surface: history.csv (curvatures by the quadratic fit through the
    nine scale centres and by the circle), sequence.pvd + sequence_steps/ (ParaView), sequence.gif (a
    frame per output), curvature_vs_time.png and snapshot_NN.png; returns the run summary with
    ``phase_end``: {label: {time, quad kx, quad ky}} at the end of each phase."""
    from lcefem.validation.gridshell_sequence import plot_curvatures, snapshot

    schedule = schedule or load_schedule(schedule_path)
    if output_interval is not None:
        schedule = dataclasses.replace(schedule, output_interval=float(output_interval))
    out = pathlib.Path(out)
    frames = []

    def frame(k, t, structure, x):
        if movie:
            frames.append(fig5_plots.surface_frame(structure, x, scales, f"t = {t:.0f} s"
                                                   + (" (cover scales)" if scales else "")))

    summary = run_sequence(schedule, out, progress=progress, scales=scales, frame=frame, snapshot=snapshot,
                           report=lambda o, history, sched: plot_curvatures(o / "curvature_vs_time.png",
                                                                            history, sched))
    if movie and frames:
        fig5_plots.write_gif(out / "sequence.gif", frames, 0.25)
    h = summary["history"]
    times = np.asarray(h["time [s]"])
    ends = phase_ends(schedule, times)
    labels = schedule.labels or tuple(f"phase {i}" for i in range(len(schedule.times)))
    summary["phase_end"] = {labels[p]: {"time [s]": float(times[k]),
                                        "quad kappa_x [1/mm]": float(h["quad kappa_x [1/mm]"][k]),
                                        "quad kappa_y [1/mm]": float(h["quad kappa_y [1/mm]"][k]),
                                        "circle kappa_x [1/mm]": float(h["circle kappa_x [1/mm]"][k]),
                                        "circle kappa_y [1/mm]": float(h["circle kappa_y [1/mm]"][k])}
                            for k, p in ends.items()}
    return summary
