"""The runner of a quasi-static body through the Problem protocol
(:mod:`lcefem.solvers.problems.protocol`): set the drives, advance the whole way, and let export
objects write what a FEniCSx/ParaView user expects, through the run skeleton
(:class:`lcefem.solvers.runtime.run.Run`: .part files, failure.json, summary.json with the resolved
configuration).

Export objects (one per output, each built by the body's run from its problem):

* :class:`HistoryExport` — history.csv, one row per converged step, columns "name [unit]";
* fields for ParaView (:mod:`lcefem.solvers.exports`): :class:`~lcefem.solvers.exports.BarHingeFrames`
  (``<stem>.pvd`` + ``<stem>_steps/*.vtp``, ``last_converged.vtp`` when a run fails) or
  :class:`~lcefem.solvers.exports.FEFields` (a VTX .bp series of the problem's Functions);
* the summary: ``summarize(run, result) -> dict`` (the body's results; renders and the validation's
  measured values come from its ``report`` hook), written last as summary.json.

A body's run is then its problem, its columns and its summary: quasi-static bodies through
:func:`run_quasi_static` (``run_beam``, ``run_specimen``, ``run_beam_fe``), heated ones in time
through :func:`run_in_time` (the heated FE beam), and those along a path of their own through
:func:`run_path` (``run_strip``, ``run_specimen_fe``, ``run_ribbon``, ``run_gridshell``).

Units: those of the problem (mm, N, s).
"""

from __future__ import annotations

import pathlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from lcefem.solvers.problems.protocol import steps_in_time, unnamed
from lcefem.solvers.runtime.run import Progress, Run


def _load_factor_where(state) -> str:
    return f"load factor {state.t:.4g}"


@dataclass(frozen=True)
class HistoryExport:
    """history.csv: ``columns`` ("name [unit]") filled by ``row(state)`` at every converged step
    (those where ``when(state)`` is true, if given: a run whose steps are finer than its rows);
    ``where(state)`` names the step (failure.json), ``at(state)`` (optional) moves the progress bar,
    ``postfix(state)`` (optional) is the bar's note."""

    columns: tuple[str, ...]
    row: Callable[[Any], dict]
    where: Callable[[Any], str] = _load_factor_where
    at: Callable[[Any], float] | None = None
    when: Callable[[Any], bool] | None = None
    postfix: Callable[[Any], str] | None = None

    def record(self, run, state) -> None:
        """The row of ``state`` into the run's history (when due)."""
        if self.when is None or self.when(state):
            run.record(self.row(state), where=self.where(state),
                       at=None if self.at is None else self.at(state),
                       postfix=None if self.postfix is None else self.postfix(state))

    def __post_init__(self):
        bad = unnamed(self.columns)
        if bad:
            raise ValueError(f"history columns without a unit: {bad}")


def run_path(drive: Callable[[Callable[[Any], None]], Any], out: pathlib.Path, *, config: dict,
             history: HistoryExport, fields, progress: Progress,
             summarize: Callable[[Any, Any], dict], exports: tuple = (), comm=None) -> dict:
    """One run of a body along a path of its own (a schedule of drives, a path follower's own
    targets, a rod's time steps), inside the run skeleton: ``drive(on_step)`` moves the problem and
    calls ``on_step(state)`` at every converged step it wants seen; the history records it (when
    due) and each export object (``fields``, or None, then ``exports``: each with
    ``open(run, out)`` giving a writer with ``write(state)`` and ``last_converged(folder, state)``)
    writes what it wants of it (a frame every n steps, a table row); when the run fails, each
    writer gets the last state seen. ``summarize(run, result)`` gives the summary's entries
    (``result``: what ``drive`` returned); ``comm``: the MPI communicator of a parallel run (rank
    0 writes the history and summary). Returns the summary."""
    out = None if out is None else pathlib.Path(out)
    with Run(out, config=config, columns=list(history.columns), progress=progress, comm=comm) as run:
        writers = [export.open(run, out) for export in (fields, *exports) if export is not None]
        last = []

        def on_step(state) -> None:
            history.record(run, state)
            for writer in writers:
                writer.write(state)
            last[:] = [state]

        run.on_failure(lambda folder: last and [w.last_converged(folder, last[0]) for w in writers])
        return run.complete(summarize(run, drive(on_step)))


def run_quasi_static(problem, drives: Mapping[str, float], out: pathlib.Path, *, config: dict,
                     history: HistoryExport, fields, progress: Progress,
                     summarize: Callable[[Any, Any], dict], progress_scale: float | None = 1.0) -> dict:
    """One run of a quasi-static problem (:func:`run_path`): ``problem.set_drives(drives)``, then
    ``problem.advance(1.0, on_step=..., progress=...)`` (the whole way), each converged step
    recorded by the exports (``fields``: an export object with ``open(run, out)``);
    ``summarize(run, result)`` gives the summary's entries (after the history is complete, before
    summary.json is written); the bar shows ``progress_scale`` x the fraction of the way (None: only
    ``history.at``). Returns the summary."""

    def drive(on_step):
        problem.set_drives(drives)
        return problem.advance(1.0, on_step=on_step, progress=None if progress_scale is None else
                               (lambda t: progress.to(progress_scale * t)))

    return run_path(drive, out, config=config, history=history, fields=fields, progress=progress,
                    summarize=summarize)


def _time_where(row) -> str:
    return f"t = {row['time [s]']:.4g} s"


def _time_at(row) -> float:
    return row["time [s]"]


def run_in_time(problem, drives: Mapping[str, float], out: pathlib.Path, *, duration: float, dt: float,
                config: dict, columns, progress: Progress, summarize: Callable[[Any, list], dict],
                fields=None) -> dict:
    """One run of a heated problem in time: ``problem.set_drives(drives)``, then equal steps of
    at most ``dt`` [s] to ``duration`` [s] (``problem.advance(step)`` each, the problem's clock
    ``time`` [s] set to k x step exactly, not a sum of steps); history.csv gets ``columns`` of
    ``problem.observables()`` at 0 and after every step ("t = ... s" names a failed step);
    ``fields`` (optional export object) one frame per step; ``summarize(run, rows)`` the summary's
    entries. Returns the summary."""
    out = None if out is None else pathlib.Path(out)
    history = HistoryExport(tuple(columns), dict, where=_time_where, at=_time_at)
    with Run(out, config=config, columns=list(history.columns), progress=progress) as run:
        writer = None if fields is None else fields.open(run, out)

        def record(row: dict) -> None:
            run.record(row, where=history.where(row), at=history.at(row))
            if writer is not None:
                writer.write(row)

        problem.set_drives(drives)
        rows = steps_in_time(problem, duration, dt, record)
        return run.complete(summarize(run, rows))


__all__ = ["HistoryExport", "run_in_time", "run_path", "run_quasi_static"]
