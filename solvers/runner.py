"""The one door: :func:`run` drives any problem (the Problem protocol,
:mod:`lcefem.solvers.problems.protocol`) along a program (:class:`lcefem.solvers.program.Program`:
drives against time or load fraction, transient or steady) and lets a list of exports typed on the
protocol (:mod:`lcefem.solvers.exports`: History, Fields, Probe, Reaction, each with its times)
write what they want of every StepRecord, inside the run skeleton
(:class:`lcefem.solvers.runtime.run.Run`: .part files, failure.json, summary.json with the
resolved configuration). FESTIM's ``problem.run()`` with its exports list::

    program = Program.in_time({"coil": 0.2}, duration=20.0, dt=1.0)
    run(problem, program, [History(), Fields("thermal.bp", ("temperature [C]",), times=(10.0,))],
        out, config=cfg.resolved())

Every body's run is this door. A problem whose ``advance(dt, on_step=...)`` follows its own steps
(a path follower's increments, a rod's time steps) gives a record per step through
``increment_record(state)``, on either clock; a body along a path of its own (a schedule of
drives, a transient whose drives are functions of time) is a :class:`PathProblem`. A body's own
states (each record's ``detail``) reach its export objects through :class:`StateHistory` (its
:class:`HistoryExport`, history.csv with its columns "name [unit]") and :class:`StateExport`
(e.g. :class:`~lcefem.solvers.exports.BarHingeFrames`, ``<stem>.pvd`` + ``<stem>_steps/*.vtp``
and ``last_converged.vtp`` when a run fails; :class:`~lcefem.solvers.exports.FEFields`, a VTX .bp
series); ``summarize(run, records)`` gives the body's summary (renders and the validation's
measured values come from its ``report`` hook). :func:`run_quasi_static` (the load program to
the drives in one advance) and :func:`run_in_time` (drives held in equal time steps) are the door
with a body's own columns.

Which body takes which way: the strip :func:`run` itself (``run_strip``);
:func:`run_quasi_static` ``run_beam``, ``run_specimen``, ``run_beam_fe``, ``run_gridshell``;
:func:`run_in_time` the heated FE beam; a :class:`PathProblem` ``run_specimen_fe``,
``run_ribbon``, ``run_gridshell_fe``, ``run_sequence``, ``run_body``.

Units: those of the problem (mm, N, s).
"""

from __future__ import annotations

import contextlib
import pathlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

from lcefem.solvers.problems.protocol import TIME, StepRecord, unnamed
from lcefem.solvers.program import Program
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
            run.record(
                self.row(state),
                where=self.where(state),
                at=None if self.at is None else self.at(state),
                postfix=None if self.postfix is None else self.postfix(state),
            )

    def __post_init__(self):
        bad = unnamed(self.columns)
        if bad:
            raise ValueError(f"history columns without a unit: {bad}")


def run(
    problem,
    program: Program,
    exports,
    out: pathlib.Path | None,
    *,
    config: dict,
    progress: Progress | None = None,
    summarize: Callable[[Run, list], dict] | None = None,
    comm=None,
) -> dict:
    """Drive ``problem`` along ``program`` inside the run skeleton (progress bar, .part files,
    failure.json, summary.json last) and let every export (``exports``: objects of
    :mod:`lcefem.solvers.exports`, the first History the run's history) write each record.

    Steps: the program's drives at 0 (``set_drives``; none: those set before), the start record
    (``problem.start()`` if the problem has it and the program records its start: a dead load
    applied first; else its observables at 0), then for a time program
    ``advance(stop - previous)`` to each stop (equal steps of at most dt, the drive switches and the
    exports' times as milestones; the clock ``problem.time`` set to the stop exactly; a problem
    with ``increment_record(state)`` gives a record per step of its own, ``advance(dt, on_step=)``:
    a :class:`PathProblem`'s one step is its whole path), for a load
    program ``advance`` by the fraction of the way left to each stop (a problem with
    ``increment_record(state)`` gives a record per converged increment of its path follower), for
    a steady one ``problem.steady()``. ``summarize(run, records)`` (the start and every advance's
    record) gives the summary's entries (default: the program, the number of steps, the final
    observables). Returns the summary."""
    from lcefem.solvers.exports import History

    if comm is None:  # a problem shared over MPI ranks claims and writes its folder collectively
        comm = getattr(problem, "comm", None)
    out = None if out is None else pathlib.Path(out)
    milestones = sorted({t for e in exports for t in (getattr(e, "times", None) or ())})
    late = [t for t in milestones if t > program.end * (1.0 + 1e-12)]
    if late and not program.steady:
        from lcefem.models.errors import InputError

        raise InputError(
            f"exports times: {late[0]:g} beyond the program's end ({program.end:g} "
            f"{'s' if program.clock == TIME else 'of the way'})"
        )
    stops = [] if program.steady else program.stops(milestones)
    with Run(out, config=config, progress=progress, comm=comm) as skeleton:
        main = next((e for e in exports if isinstance(e, History)), None)
        writers = [e.open(skeleton, out, problem, main=e is main) for e in exports]
        records: list[StepRecord] = []
        last: list[StepRecord] = []
        count = [0]

        def emit(record: StepRecord) -> None:
            for writer in writers:
                writer.write(record, count[0])
            count[0] += 1
            last[:] = [record]

        skeleton.on_failure(
            lambda folder: last and [w.last_converged(folder, last[0]) for w in writers]
        )
        if program.drives[0][
            1
        ]:  # none: the drives set beforehand (a gridshell's rest fraction per bar)
            problem.set_drives(program.drives[0][1])
        start = (
            problem.start()
            if program.record_start and hasattr(problem, "start")
            else StepRecord(0.0, problem.observables(), clock=program.clock)
        )
        records.append(start)
        if program.record_start:
            emit(start)
        if program.steady:
            records.append(problem.steady())
            emit(records[-1])
        previous = 0.0
        increments = getattr(problem, "increment_record", None)
        for stop in stops:
            switch = program.drives_at(previous) if previous > 0.0 else None
            if switch is not None:
                problem.set_drives(switch)
            if (
                program.clock == TIME and increments is not None
            ):  # the problem's own steps to the stop
                record = replace(
                    problem.advance(stop - previous, on_step=lambda s: emit(increments(s))), at=stop
                )
            elif program.clock == TIME:
                record = problem.advance(stop - previous)
                if hasattr(problem, "time"):
                    with contextlib.suppress(AttributeError):  # a clock the problem keeps read-only
                        problem.time = stop  # k x dt exactly, not a sum of steps
                obs = record.observables
                record = replace(
                    record, at=stop, observables={**obs, TIME: stop} if TIME in obs else obs
                )
                emit(record)
            else:
                base, left = previous, 1.0 - previous
                if increments is None:
                    record = problem.advance((stop - previous) / left if stop < 1.0 else 1.0)
                    emit(replace(record, at=stop))
                else:
                    record = problem.advance(
                        (stop - previous) / left if stop < 1.0 else 1.0,
                        on_step=lambda s: emit(
                            (lambda r: replace(r, at=base + left * r.at))(increments(s))
                        ),
                    )
                    record = replace(record, at=stop)
            records.append(record)
            previous = stop
        summary = (
            summarize(skeleton, records)
            if summarize is not None
            else {
                "program": program.describe(),
                "steps": len(records) - 1,
                "final": dict(records[-1].observables),
            }
        )
        return skeleton.complete(summary)


@dataclass(frozen=True)
class StateHistory:
    """The door's export of a body's history from its own states (each record's ``detail``:
    ``history.row(state)`` where ``history.when(state)``), the run's history.csv opened with its
    columns before the first step (a run that fails at once leaves its header)."""

    history: HistoryExport
    times = None

    def open(self, run, out, problem=None, main: bool = False):
        run.open_history(list(self.history.columns))
        return _StateHistoryWriter(self.history, run)


class _StateHistoryWriter:
    def __init__(self, history: HistoryExport, run):
        self.history, self.run = history, run

    def write(self, record, index: int) -> None:
        import math

        h, state = self.history, record.detail
        if h.when is None or h.when(state):  # the bar at the state's own place, else the record's
            at = (
                h.at(state) if h.at is not None else record.at if math.isfinite(record.at) else None
            )
            self.run.record(
                h.row(state),
                where=h.where(state),
                at=at,
                postfix=None if h.postfix is None else h.postfix(state),
            )

    def last_converged(self, folder, record) -> None:
        pass  # the rows so far are kept as history.partial.csv


@dataclass(frozen=True)
class StateExport:
    """An export object of a body's own states (open(run, out) -> write(state)) fed by the door:
    each record's ``detail`` (the state its path follower gave)."""

    export: Any
    times = None

    def open(self, run, out, problem=None, main: bool = False):
        return _StateExportWriter(self.export.open(run, out))


class _StateExportWriter:
    def __init__(self, writer):
        self.writer = writer

    def write(self, record, index: int) -> None:
        self.writer.write(record.detail)

    def last_converged(self, folder, record) -> None:
        self.writer.last_converged(folder, record.detail)


class PathProblem:
    """A body whose run follows a path of its own (a rod's time steps with their heat, a path
    follower's own targets, a schedule of drives, a transient whose drives are functions of time)
    as a problem of the door (:func:`run`): ``follow(on_step)`` moves the body the whole way,
    calling ``on_step(state)`` at every state it wants seen (the start first) and returning its
    account; the door's one ``advance`` (a program of one step: :meth:`program`) runs it and turns
    each state into a record (:meth:`increment_record`: at ``at(state)`` on ``clock``, the state
    its ``detail``, written by :class:`StateHistory` and :class:`StateExport`). ``comm``: the MPI
    communicator of a problem shared over ranks (the run claims and writes its folder on it)."""

    drive = "none [-]"

    def __init__(
        self,
        follow: Callable[[Callable[[Any], None]], Any],
        *,
        clock: str = TIME,
        end: float = 1.0,
        at: Callable[[Any], float] | None = None,
        comm=None,
    ):
        self.follow, self.clock, self.end, self.at, self.comm = follow, clock, float(end), at, comm

    def program(self) -> Program:
        """The program of one step to the path's end (its drives its own: none set by the door)."""
        return (
            Program.in_time({}, self.end, self.end, record_start=False)
            if self.clock == TIME
            else Program.quasi_static({}, record_start=False)
        )

    def drive_tags(self) -> tuple[str, ...]:
        return ()

    def set_drives(self, drives: Mapping[str, float]) -> None:
        if drives:
            from lcefem.models.errors import InputError

            raise InputError(f"drives {', '.join(drives)}: a path of its own takes none")

    def advance(self, dt: float, on_step: Callable[[Any], None] | None = None) -> StepRecord:
        result = self.follow(on_step or (lambda state: None))
        return StepRecord(self.end, {}, clock=self.clock, detail=result)

    def increment_record(self, state) -> StepRecord:
        return StepRecord(
            self.end if self.at is None else float(self.at(state)),
            {},
            clock=self.clock,
            detail=state,
        )

    def observables(self) -> dict[str, float]:
        return {}


def run_quasi_static(
    problem,
    drives: Mapping[str, float],
    out: pathlib.Path,
    *,
    config: dict,
    history: HistoryExport,
    fields,
    progress: Progress,
    summarize: Callable[[Any, Any], dict],
    progress_scale: float | None = 1.0,
) -> dict:
    """One run of a quasi-static problem through the door (:func:`run`): the load program to
    ``drives`` in one advance (the whole way), each converged increment of the problem's path
    follower a record (``problem.increment_record``), written by ``history`` (a HistoryExport of the
    body's own states) and ``fields`` (an export object of them with ``open(run, out)``, or None);
    ``summarize(run, result)`` gives the summary's entries (``result``: the advance's ``detail``,
    after the history is complete, before summary.json is written). The bar shows the fraction of
    the way (``progress_scale``: kept for the callers; the door's bar follows the records).
    Returns the summary."""
    exports = [StateHistory(history), *(() if fields is None else (StateExport(fields),))]
    return run(
        problem,
        Program.quasi_static(drives, record_start=False),
        exports,
        out,
        config=config,
        progress=progress,
        summarize=lambda skeleton, records: summarize(skeleton, records[-1].detail),
    )


def run_in_time(
    problem,
    drives: Mapping[str, float],
    out: pathlib.Path,
    *,
    duration: float,
    dt: float,
    config: dict,
    columns,
    progress: Progress,
    summarize: Callable[[Any, list], dict],
    fields=None,
) -> dict:
    """One run of a heated problem in time through the door (:func:`run`): ``drives`` held for
    ``duration`` [s] in equal steps of at most ``dt`` [s] (the clock ``time`` [s] set to k x step
    exactly, not a sum of steps); history.csv gets ``columns`` of the observables at 0 and after
    every step ("t = ... s" names a failed step); ``fields`` (optional, an export of
    :mod:`lcefem.solvers.exports`) its frames; ``summarize(run, rows)`` (rows: the observables of
    every record) the summary's entries. Returns the summary."""
    from lcefem.solvers.exports import History

    exports = [History(columns=tuple(columns)), *(() if fields is None else (fields,))]
    return run(
        problem,
        Program.in_time(drives, duration, dt),
        exports,
        out,
        config=config,
        progress=progress,
        summarize=lambda skeleton, records: summarize(
            skeleton, [dict(r.observables) for r in records]
        ),
    )


__all__ = [
    "HistoryExport",
    "PathProblem",
    "StateExport",
    "StateHistory",
    "run",
    "run_in_time",
    "run_quasi_static",
]
