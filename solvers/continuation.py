"""Adaptive load stepping with step cutting: the shared mechanism for every nonlinear quasi-static solve.

A load is a fraction s in [0, 1] (of a temperature increment, a displacement, a rest-length ramp).
:func:`advance` tries the whole increment, halves it on failure (restarting from the last converged
state, never from the failed trial), grows it again after successes, and raises ConvergenceError
when the increment would fall below ``min_fraction``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from lcefem.models.errors import ConvergenceError


@dataclass
class StepReport:
    substeps: int = 0
    cuts: int = 0
    iterations: int = 0


def advance(set_load: Callable[[float], None], solve: Callable[[], tuple[bool, int, str]],
            save: Callable[[], object], restore: Callable[[object], None], *, where: str,
            first: float = 1.0, min_fraction: float = 1.0 / 256.0) -> StepReport:
    """Take the load from s = 0 (the last converged state) to s = 1.

    Args:
        set_load: sets the load at fraction s (e.g. T = T_old + s (T_new - T_old)).
        solve: one nonlinear solve from the current state; returns (converged, iterations, reason).
        save, restore: snapshot and restore of the converged state.
        where: text naming the step for messages (e.g. "t = 12.5 s").
        first: first trial increment.
        min_fraction: smallest increment before giving up.
    """
    report = StepReport()
    s, ds = 0.0, min(1.0, first)
    state = save()
    while s < 1.0 - 1e-12:
        trial = min(1.0, s + ds)
        set_load(trial)
        ok, its, reason = solve()
        report.iterations += its
        if ok:
            s = trial
            state = save()
            report.substeps += 1
            ds = min(1.0, 2.0 * ds) if report.cuts else ds
            continue
        report.cuts += 1
        restore(state)
        set_load(s)
        ds *= 0.5
        if ds < min_fraction:
            raise ConvergenceError(where, f"{reason}; load fraction {s:.4g} reached, increment "
                                   f"{ds:.3g} below the minimum {min_fraction:.3g}")
    return report
