"""The one interface every body's problem implements (:class:`Problem`), whatever it solves: the
FE strip, beam, specimen, ribbon and gridshell, their bar-and-hinge counterparts.

A run, a study or a test can then drive any body the same way::

    problem.set_drives({"bottom_strips": 1.2})     # by tag (strip tag, group, channel, coil)
    step = problem.advance(1.0)                    # its own time: seconds, or a load parameter
    step.observables["curvature [1/mm]"]           # a StepRecord: observables, iterations, cuts
    row = problem.observables()                    # {"curvature [1/mm]": ..., ...}
    saved = problem.save_state(); ...; problem.restore_state(saved)

Every :meth:`Problem.advance` returns one :class:`StepRecord`; the one door that drives a problem
along a program and writes its exports is :func:`lcefem.solvers.runner.run`.

What a drive is (a spontaneous stretch, a coil current, an end shortening) is stated once per class
in :attr:`Problem.drive`, "name [unit]" like every observable.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

#: "name [unit]": a name, one space, the unit in brackets ("[-]" for a ratio), nothing after.
NAME_WITH_UNIT = re.compile(r"^\S.* \[[^\[\]]+\]$")


#: The two clocks a problem advances on: simulated time (heated problems) or the fraction of the way
#: to the drives set (quasi-static ones).
TIME = "time [s]"
LOAD = "load fraction [-]"


@dataclass(frozen=True)
class StepRecord:
    """What one :meth:`Problem.advance` did, the same for every body.

    ``at``: where the step ended on the problem's clock ``clock`` (:data:`TIME`: simulated time
    [s]; :data:`LOAD`: the fraction [-] of the way to the drives set, 1 at the targets);
    ``observables``: the problem's observables after the step, "name [unit]"; ``iterations``: Newton
    iterations [-] of the step (all its increments); ``cuts``: step cuts [-] of the step controller;
    ``converged``: False only for a record of a step that did not converge (advance raises
    ConvergenceError instead of returning one). ``detail``: the body's own account of the step (a
    path follower's states, kept for that body's run and studies; not compared, not exported).
    """

    at: float
    observables: Mapping[str, float]
    iterations: int = 0
    cuts: int = 0
    converged: bool = True
    clock: str = TIME
    detail: Any = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        if self.clock not in (TIME, LOAD):
            raise ValueError(f"StepRecord.clock = {self.clock!r}: allowed {TIME!r}, {LOAD!r}")
        bad = unnamed(self.observables)
        if bad:
            raise ValueError(f"observables without a unit: {bad}")


@runtime_checkable
class Problem(Protocol):
    """A body's problem, built once from a configuration and a mesh (forms compiled once), then
    driven, advanced and observed.

    ``drive``: what :meth:`set_drives` sets, "name [unit]" (e.g. ``"lambda [-]"``,
    ``"current [A]"``).
    """

    drive: str

    def drive_tags(self) -> tuple[str, ...]:
        """The tags :meth:`set_drives` accepts (strip tags, groups, channels, coils)."""
        ...

    def set_drives(self, drives: Mapping[str, float]) -> None:
        """The drive per tag (in :attr:`drive`'s unit), from now on; a tag not in
        :meth:`drive_tags` or a value out of bounds is an InputError naming it."""
        ...

    def advance(self, dt: float) -> StepRecord:
        """Move forward by ``dt`` of the problem's own time: seconds [s] for a heated problem (one
        time step), the fraction 0 < dt <= 1 of the way from the present drives to those set for a
        quasi-static one (1 reaches them); returns the :class:`StepRecord` of the step. Raises
        ConvergenceError, keeping the last converged state."""
        ...

    def observables(self) -> dict[str, float]:
        """The named observables of the present state, keys "name [unit]"."""
        ...

    def fields(self) -> dict[str, Any]:
        """The fields of the present state by "name [unit]" (dolfinx Functions for the FE problems,
        node arrays for the reduced-order ones), what ParaView shows."""
        ...

    def save_state(self) -> Any:
        """An in-memory copy of the present state (everything :meth:`advance` changes)."""
        ...

    def restore_state(self, state: Any) -> None:
        """Go back to a state returned by :meth:`save_state` of this problem."""
        ...


def steps_in_time(
    problem, duration: float, dt: float, on_row: Callable[[dict], None] | None = None
) -> list[dict]:
    """Observables of ``problem`` at its current state and after each of the equal steps of at most
    ``dt`` [s] that end at ``duration`` [s] (``problem.advance(step)``); the clock ``problem.time``
    [s] is set to k x step exactly, not a sum of steps. ``on_row`` sees each row as it comes."""
    steps = max(1, int(math.ceil(duration / dt - 1e-9)))
    step = duration / steps
    rows = [problem.observables()]
    if on_row is not None:
        on_row(rows[0])
    for k in range(1, steps + 1):
        rows.append(dict(problem.advance(step).observables))
        problem.time = k * step
        rows[-1]["time [s]"] = problem.time
        if on_row is not None:
            on_row(rows[-1])
    return rows


def path_record(fraction: float, observables: Mapping[str, float], path) -> StepRecord:
    """The :class:`StepRecord` of a bar-and-hinge advance along ``fraction`` [-] of the way:
    ``path`` a :class:`lcefem.solvers.bar_hinge.PathResult` (its Newton iterations summed, its
    failed increments as the cuts; kept as the record's ``detail``)."""
    return StepRecord(
        fraction,
        observables,
        int(sum(path.newton_iterations)),
        int(path.failed_increments),
        clock=LOAD,
        detail=path,
    )


def check_quasi_static_step(dt: float) -> float:
    """``dt`` of a quasi-static problem's :meth:`Problem.advance`: the fraction (0, 1] of the way
    to the targets; else an InputError naming it."""
    from lcefem.models.errors import InputError

    if not isinstance(dt, (int, float)) or not 0.0 < dt <= 1.0:
        raise InputError(
            f"dt = {dt}: a quasi-static problem advances by a fraction of the way to "
            "its targets, 0 < dt <= 1"
        )
    return float(dt)


def unnamed(names) -> list[str]:
    """The names not of the form "name [unit]" (:data:`NAME_WITH_UNIT`)."""
    return [n for n in names if not NAME_WITH_UNIT.match(n)]


def copy_arrays(functions) -> list:
    """Copies of the (owned and ghost) values of dolfinx Functions: the FE part of a saved state."""
    return [f.x.array.copy() for f in functions]


def put_arrays(functions, arrays) -> None:
    """Values saved by :func:`copy_arrays` back into the same Functions."""
    for f, a in zip(functions, arrays, strict=True):
        f.x.array[:] = a
        f.x.scatter_forward()
