"""The runner of a quasi-static body through the Problem protocol
(:mod:`lcefem.solvers.problems.protocol`): set the drives, advance the whole way, and let export
objects write what a FEniCSx/ParaView user expects, through the run skeleton
(:class:`lcefem.solvers.runtime.run.Run`: .part files, failure.json, summary.json with the resolved
configuration).

Export objects (one per output, each built by the body's run from its problem):

* :class:`HistoryExport` — history.csv, one row per converged increment, columns "name [unit]";
* :class:`BarHingeFrames` — ParaView: ``<stem>.pvd`` + ``<stem>_steps/*.vtp`` (ribbon triangles,
  bars, displacement, axial force), and ``last_converged.vtp`` when a run fails;
* the summary: ``summarize(run, result) -> dict`` (the body's results; renders and the validation's
  measured values come from its ``report`` hook), written last as summary.json.

Units: those of the problem (mm, N, s).
"""

from __future__ import annotations

import pathlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from lcefem.solvers.exports import bar_hinge_run
from lcefem.solvers.problems.protocol import unnamed
from lcefem.solvers.runtime.run import Progress


@dataclass(frozen=True)
class HistoryExport:
    """history.csv: ``columns`` ("name [unit]") filled by ``row(state)`` at every converged
    increment of the path follower."""

    columns: tuple[str, ...]
    row: Callable[[Any], dict]

    def __post_init__(self):
        bad = unnamed(self.columns)
        if bad:
            raise ValueError(f"history columns without a unit: {bad}")


@dataclass(frozen=True)
class BarHingeFrames:
    """ParaView frames of a bar-and-hinge problem: ``<stem>.pvd`` + ``<stem>_steps/*.vtp``."""

    stem: str
    structure: Any
    model: Any


def run_quasi_static(problem, drives: Mapping[str, float], out: pathlib.Path, *, config: dict,
                     history: HistoryExport, frames: BarHingeFrames, progress: Progress,
                     summarize: Callable[[Any, Any], dict], progress_scale: float = 1.0) -> dict:
    """One run of a quasi-static bar-and-hinge problem: ``problem.set_drives(drives)``, then
    ``problem.advance(1.0)`` (the whole way), each converged increment recorded by the exports;
    ``summarize(run, path_result)`` gives the summary's entries (after the history is complete,
    before summary.json is written); the bar shows ``progress_scale`` x the fraction of the way.
    Returns the summary."""
    with bar_hinge_run(pathlib.Path(out), frames.stem, frames.structure, frames.model, config=config,
                       columns=list(history.columns), row=history.row, progress=progress) as (run, on_step):
        problem.set_drives(drives)
        result = problem.advance(1.0, on_step=on_step, progress=lambda t: progress.to(progress_scale * t))
        return run.complete(summarize(run, result))


__all__ = ["BarHingeFrames", "HistoryExport", "run_quasi_static"]
