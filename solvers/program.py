"""A program: what a run does to a problem, as data (FESTIM's settings + milestones).

A :class:`Program` drives a problem (:class:`lcefem.solvers.problems.protocol.Problem`) along one
clock: simulated time [s] (heated problems: coil currents switched at given times, equal steps of at
most ``dt``) or the load fraction [-] of the way to the drives set (quasi-static problems: the
lambdas, an end shortening; ``dt`` the fraction per advance, 1 the whole way with the problem's own
path follower). ``steady`` asks for the steady state instead of a transient. The run
(:func:`lcefem.solvers.runner.run`) adds the export times to the steps as milestones, so an export
at t = 7.5 s is written at 7.5 s exactly.

A program comes from a table (a case file's ``[program]``, or an entry of
``validation/data/programs.toml`` ``[run_programs.NAME]``), read by :func:`program_from_table`::

    [program]
    clock = "time"        # "time" [s] or "load" [-]
    duration = 20.0       # [s] (time); a load program ends at 1, the drives set
    dt = 1.0              # [s] largest time step, or the fraction of the way per advance
    steady = false        # the steady state at the drives instead (time only)
    [[program.drives]]    # the drives switched at ``at`` [s] (time) or set at 0 (load)
    at = 0.0
    coil = 0.2            # tag = value, in the problem's drive unit ("current [A]", "lambda [-]")

A bad table is one InputError naming the key and what is allowed, before anything is built.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from lcefem.models.errors import InputError
from lcefem.solvers.problems.protocol import LOAD, TIME

#: The clocks of a program by their case-file names.
CLOCKS = {"time": TIME, "load": LOAD}
#: Two stops closer than this fraction of the program's end are one (round-off of k x dt).
SAME_STOP = 1e-9


@dataclass(frozen=True)
class Program:
    """Drives against a clock (module docstring). ``drives``: ((at, {tag: value}), ...), sorted,
    the first at 0; ``end``: duration [s] of a time program, 1 for a load program; ``dt``: the
    largest step [s] or fraction [-] of one advance; ``steady``: the steady state instead (time
    clock); ``record_start``: the state before the first step is a record (a row at 0)."""

    clock: str
    drives: tuple[tuple[float, Mapping[str, float]], ...]
    end: float
    dt: float
    steady: bool = False
    record_start: bool = True

    def __post_init__(self):
        if self.clock not in (TIME, LOAD):
            raise InputError(f"program.clock = {self.clock!r}: allowed {', '.join(CLOCKS)}")
        unit = "s" if self.clock == TIME else "-"
        if not (math.isfinite(self.end) and self.end > 0):
            raise InputError(f"program.duration = {self.end} {unit}: must be > 0")
        if not (math.isfinite(self.dt) and 0 < self.dt <= self.end):
            raise InputError(
                f"program.dt = {self.dt} {unit}: must be > 0 and <= {self.end:g} {unit}"
            )
        if self.clock == LOAD and self.end != 1.0:
            raise InputError(
                f"program.duration = {self.end}: a load program ends at 1 (the drives set)"
            )
        if self.steady and self.clock != TIME:
            raise InputError("program.steady: only with clock = 'time'")
        times = [at for at, _ in self.drives]
        if not times or times[0] != 0.0:
            raise InputError("program.drives: the first entry must be at = 0")
        if any(b <= a for a, b in zip(times, times[1:])) or times[-1] >= self.end:
            raise InputError(
                f"program.drives: 'at' must increase and stay below the end ({self.end:g} {unit})"
            )
        if self.clock == LOAD and len(times) > 1:
            raise InputError(
                "program.drives: a load program has one entry (at = 0), the drives it ramps to"
            )

    @classmethod
    def in_time(cls, drives: Mapping[str, float], duration: float, dt: float, **kw) -> "Program":
        """Constant drives for ``duration`` [s] in equal steps of at most ``dt`` [s]."""
        return cls(TIME, ((0.0, dict(drives)),), float(duration), float(dt), **kw)

    @classmethod
    def quasi_static(cls, drives: Mapping[str, float], dt: float = 1.0, **kw) -> "Program":
        """The drives reached along the load fraction 0 -> 1, ``dt`` of the way per advance."""
        return cls(LOAD, ((0.0, dict(drives)),), 1.0, float(dt), **kw)

    def stops(self, milestones: Iterable[float] = ()) -> list[float]:
        """The ends of the steps on the clock: k x h (h = end / ceil(end / dt), equal steps, each k
        x h exactly, not a sum), the drive switches and the ``milestones`` (export times) inside
        (0, end]; stops closer than :data:`SAME_STOP` x end to a grid stop are that stop."""
        n = max(1, int(math.ceil(self.end / self.dt - 1e-9)))
        h = self.end / n
        grid = [k * h for k in range(1, n + 1)]
        extra = [
            t for t in (*[at for at, _ in self.drives[1:]], *milestones) if 0.0 < t <= self.end
        ]
        tol = SAME_STOP * self.end
        stops = list(grid)
        for t in extra:
            if all(abs(t - s) > tol for s in stops):
                stops.append(float(t))
        return sorted(stops)

    def drives_at(self, t: float) -> Mapping[str, float] | None:
        """The drives switched on at ``t`` (None if none switch there)."""
        for at, drives in self.drives:
            if abs(at - t) <= SAME_STOP * self.end:
                return drives
        return None

    def describe(self) -> dict:
        """The program for summary.json."""
        return {
            "clock": self.clock,
            "end": self.end,
            "dt": self.dt,
            "steady": self.steady,
            "drives": [{"at": at, **dict(d)} for at, d in self.drives],
        }


PROGRAM_KEYS = ("clock", "duration", "dt", "steady", "drives")


def _number(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where} = {value!r}: must be a number")
    return float(value)


def program_from_table(table, where: str = "program") -> Program:
    """The :class:`Program` of a TOML table (module docstring); one InputError naming
    ``where``.key and what is allowed for a bad one."""
    if not isinstance(table, Mapping):
        raise InputError(f"{where}: must be a table with keys {', '.join(PROGRAM_KEYS)}")
    unknown = [k for k in table if k not in PROGRAM_KEYS]
    if unknown:
        raise InputError(
            f"{where}: unknown key {unknown[0]!r} (allowed: {', '.join(PROGRAM_KEYS)})"
        )
    clock = table.get("clock", "time")
    if clock not in CLOCKS:
        raise InputError(f"{where}.clock = {clock!r}: allowed {', '.join(repr(c) for c in CLOCKS)}")
    steady = table.get("steady", False)
    if not isinstance(steady, bool):
        raise InputError(f"{where}.steady = {steady!r}: must be true or false")
    if clock == "load":
        if "duration" in table:
            raise InputError(f"{where}.duration: not for clock = 'load' (a load program ends at 1)")
        end = 1.0
    elif steady:
        end = _number(table.get("duration", 1.0), f"{where}.duration")
    elif "duration" not in table:
        raise InputError(f"{where}: missing key 'duration' (simulated time [s])")
    else:
        end = _number(table["duration"], f"{where}.duration")
    dt = _number(table.get("dt", end), f"{where}.dt")
    entries = table.get("drives")
    if not isinstance(entries, list) or not entries:
        raise InputError(
            f"{where}.drives: must be a list of tables [[{where}.drives]] with 'at' and tag = value"
        )
    drives = []
    for i, entry in enumerate(entries):
        here = f"{where}.drives[{i}]"
        if not isinstance(entry, Mapping):
            raise InputError(f"{here}: must be a table with 'at' and tag = value")
        if "at" not in entry:
            raise InputError(
                f"{here}: missing key 'at' ({'[s]' if clock == 'time' else '0 for a load program'})"
            )
        values = {k: _number(v, f"{here}.{k}") for k, v in entry.items() if k != "at"}
        if not values:
            raise InputError(f"{here}: no drive (tag = value)")
        drives.append((_number(entry["at"], f"{here}.at"), values))
    try:
        return Program(CLOCKS[clock], tuple(drives), end, dt, steady=steady)
    except InputError as exc:  # the Program's own checks name "program.<key>": name the table
        raise InputError(where + str(exc).removeprefix("program")) from None


__all__ = ["CLOCKS", "Program", "program_from_table"]
