"""The one step controller of every nonlinear quasi-static path: a load parameter t (a fraction of a
temperature increment, a strip-length ramp, an end shortening) followed from the last converged
state to a target.

:class:`PathFollower`:
* predictor: the tangent (Euler) step u <- u - K^-1 R(u; t_new) with the factorised tangent of the
  last converged state (:meth:`lcefem.solvers.mechanics.HyperelasticProblem.tangent_predictor`)
  plus, by default, the quadratic term of the parabola through the previous converged state
  (:meth:`PathFollower._curve`: a rotating thin part moves on an arc, which the straight Euler
  step leaves by h^2/2 times the squared rotation rate, a membrane strain: on the beam's second
  step the residual after the Euler step is 120 N, after the curved one 2.7 N); else the secant
  through the last two converged states, else (also when the secant's state is non-finite or inverts
  an element) the last state;
* corrector: one Newton solve (SNES); the problem refuses non-finite iterates and inverted elements
  (det F <= 0 at a quadrature point), so a step is never accepted in such a state;
* step size from the Newton iteration count: h <- h clip(sqrt(n_target/n), 1/2, growth);
* on failure: restore the last converged state, halve the step, and grow no further than the
  last successful step until the point of the failure is passed (no growth straight into a known
  failure);
* below ``min_step`` the path has a fold (a snap-through): the follower relaxes at the next load
  with damped Newton steps (proximal point, :class:`lcefem.solvers.contact.NodalDamping`), or raises
  :class:`ConvergenceError` when the problem has no damping.

:func:`advance` is the same controller for callers that supply callables instead of a problem.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from lcefem.models.errors import ConvergenceError
from lcefem.models.parameters import param


@dataclass
class StepReport:
    substeps: int = 0
    cuts: int = 0
    iterations: int = 0


@dataclass(frozen=True)
class PathControl:
    """Adaptive stepping of a load path t: 0 -> 1."""

    first_step: float = param(
        0.01,
        "-",
        "chosen: first increment of t (the as-built beam is almost a "
        "mechanism: its first increments rotate thin Kapton a lot)",
        positive=True,
        maximum=1.0,
    )
    max_step: float = param(0.2, "-", "chosen: largest increment of t", positive=True, maximum=1.0)
    min_step: float = param(
        1.0e-4,
        "-",
        "chosen: an increment below this that still fails marks a "
        "fold of the path (a snap-through), crossed by relaxation",
        positive=True,
    )
    growth: float = param(2.0, "-", "chosen: largest increment growth after one step", minimum=1.0)
    target_iterations: int = param(
        10,
        "-",
        "chosen: Newton iterations per step the step size aims "
        "at (h <- h sqrt(target/n)); beam ramp (1.33, 1.05), level 0, "
        "tangent predictor: 5 -> 242, 7 -> 234, 10 -> 152 (max_step "
        "0.2), 12 -> 162 (max_step 0.25, 3 cuts) Newton iterations",
        minimum=1,
    )
    predictor: str = param(
        "curved",
        "-",
        "'curved' (the Euler step plus the quadratic term "
        "through the previous converged state, kept when admissible and of "
        "smaller residual), 'tangent' (Euler step with the converged tangent; "
        "the secant when the problem has none or the Euler step is "
        "inadmissible), 'secant' or 'none'. Beam ramp (1.33, 1.05), level 0: "
        "98 Newton iterations in 15 steps with 'curved', 146 in 20 with "
        "'tangent' (234 before the step control's target of 10), 301 with "
        "the secant",
    )
    snap_step: float = param(0.01, "-", "chosen: increment of t across a fold", positive=True)
    relaxation_steps: int = param(
        60, "-", "chosen: most damped (proximal) Newton steps across a fold", minimum=1
    )
    damping: float = param(
        1.0e-3,
        "N/mm",
        "chosen: first proximal weight c of the relaxation "
        "(energy + c/2 sum |u - u_k|^2 over the nodes), divided by 4 after each "
        "success down to damping_floor",
        positive=True,
    )
    damping_floor: float = param(
        1.0e-9,
        "N/mm",
        "chosen: proximal weight below which the relaxation ends with an undamped solve",
        positive=True,
    )
    path_atol: float | None = param(
        None,
        "N",
        "chosen: absolute residual tolerance of Newton on "
        "the intermediate states of a path (None: the problem's own "
        "tolerance everywhere). The state reached at each follow() "
        "target is always solved to the problem's own tolerance, so "
        "the answer does not change; only the path in between is "
        "looser (it only seeds the next predictor)",
    )


#: Predictors of :class:`PathControl` (see its ``predictor``).
PREDICTORS = ("tangent", "curved", "secant", "none")


class PathFollower:
    """Follows an equilibrium path in a load parameter t (see the module docstring).

    Args:
        problem: has ``solve() -> (converged, iterations, reason)``, ``save()``, ``restore(state)``
            (e.g. :class:`lcefem.solvers.mechanics.HyperelasticProblem`); a ``tangent_predictor``
            method enables the tangent predictor.
        set_load: sets the model's load at path parameter t.
        control: :class:`PathControl`.
        damping: a :class:`lcefem.solvers.contact.NodalDamping` attached to the problem (None: folds
            raise ConvergenceError).
        t0: the path parameter of the current (converged) state.
    """

    def __init__(
        self,
        problem,
        set_load: Callable[[float], None],
        control: PathControl = PathControl(),
        damping=None,
        t0: float = 0.0,
    ):
        if control.predictor not in PREDICTORS:
            raise ValueError(f"predictor {control.predictor!r}: one of {', '.join(PREDICTORS)}")
        self.problem, self.set_load, self.control = problem, set_load, control
        self.damping = damping
        self.t = t0
        self.history = [(t0, problem.save())]
        self.step = control.first_step
        self.iterations = 0
        self.cuts = 0
        self.snaps = 0
        self.substeps = 0
        self.failed_at = -math.inf  # load of the last failed trial (no growth until passed)

    def _predict(self, t: float) -> None:
        c = self.control
        if (
            c.predictor in ("tangent", "curved")
            and hasattr(self.problem, "tangent_predictor")
            and self.problem.tangent_predictor(self.set_load, self.t, t, self.history[-1][1])
        ):
            if c.predictor == "curved" and len(self.history) == 2:
                self._curve(t)
            return
        if c.predictor == "none" or len(self.history) < 2:
            return
        (t1, u1), (t2, u2) = self.history[-2], self.history[-1]
        if t2 != t1:
            self.problem.restore(u2 + (t - t2) / (t2 - t1) * (u2 - u1))
            admissible = getattr(self.problem, "admissible", None)
            if admissible is not None and not admissible():
                self.problem.restore(u2)  # an inverted secant guess: Newton from the last state

    def _curve(self, t: float) -> None:
        """Add the quadratic term to the Euler step u_E = u2 + h v (h = t - t2): the parabola with
        value u2 and slope v at t2 through the previous converged state (t1, u1),
        u = u_E + (h/h1)^2 (u1 - u2 + h1 v), h1 = t2 - t1. A rotating thin part moves on an arc,
        which the straight Euler step leaves (membrane strain); the parabola follows its curvature.
        Kept only when admissible and of smaller residual than u_E."""
        (t1, u1), (t2, u2) = self.history
        h, h1 = t - t2, t2 - t1
        norm = getattr(self.problem, "residual_norm", None)
        if h1 <= 0.0 or h <= 0.0 or norm is None:
            return
        euler = self.problem.save()
        r_euler = norm()
        v = (euler - u2) / h
        self.problem.restore(euler + (h / h1) ** 2 * (u1 - u2 + h1 * v))
        admissible = getattr(self.problem, "admissible", lambda: True)
        if not (admissible() and norm() < r_euler):
            self.problem.restore(euler)

    def _accept(self, t: float) -> None:
        self.t = t
        self.substeps += 1
        self.history = [self.history[-1], (t, self.problem.save())]

    def _solve(self, final: bool = True) -> tuple[bool, int, str]:
        loosen = getattr(self.problem, "path_tolerance", None)
        if loosen is not None:
            loosen(None if final else self.control.path_atol)
        ok, its, reason = self.problem.solve()
        self.iterations += its
        return ok, its, reason

    def _next_step(self, its: int) -> float:
        c = self.control
        factor = min(c.growth, max(0.5, math.sqrt(c.target_iterations / max(its, 1))))
        step = self.step * factor
        if self.t < self.failed_at - 1e-12:
            step = min(step, self.step)  # the last failure lies ahead: no growth into it
        return min(c.max_step, step)

    def follow(
        self, t_to: float, where: str, on_step: Callable[[float, int], None] | None = None
    ) -> None:
        """From the current t to ``t_to``; ``on_step(t, iterations)`` after each accepted step."""
        c = self.control
        while self.t < t_to - 1e-12:
            t_new = min(t_to, self.t + self.step)
            self.set_load(t_new)
            self._predict(t_new)
            ok, its, reason = self._solve(final=t_new >= t_to - 1e-12)
            if ok:
                self._accept(t_new)
                self.step = self._next_step(its)
                if on_step is not None:
                    on_step(self.t, its)
                continue
            self.cuts += 1
            self.failed_at = t_new
            self.problem.restore(self.history[-1][1])
            self.set_load(self.t)
            self.step = 0.5 * (t_new - self.t)
            if self.step >= c.min_step:
                continue
            t_new = min(t_to, self.t + c.snap_step)
            its = self._relax(t_new, where, f"fold at t = {self.t:.5g} ({reason})")
            self._accept(t_new)
            self.history = self.history[-1:]  # no secant across the jump
            self.step = c.first_step
            self.snaps += 1
            if on_step is not None:
                on_step(self.t, its)

    def _relax(self, t_new: float, where: str, why: str) -> int:
        if self.damping is None:
            raise ConvergenceError(
                where,
                f"{why}; load fraction {self.t:.4g} reached, increment "
                f"below the minimum {self.control.min_step:.3g}",
            )
        c = self.control
        start = self.problem.save()
        self.set_load(t_new)
        weight, its_total = c.damping, 0
        try:
            for _ in range(c.relaxation_steps):
                self.damping.anchor[:] = self.problem.save()
                self.damping.weight = weight
                ok, its, reason = self._solve()
                its_total += its
                if not ok:
                    self.problem.restore(self.damping.anchor.copy())
                    weight *= 10.0
                    continue
                if weight < c.damping_floor:
                    break
                weight *= 0.25
            self.damping.weight = 0.0
            ok, its, reason = self._solve()
            its_total += its
        finally:
            self.damping.weight = 0.0
        if not ok:
            self.problem.restore(start)
            self.set_load(self.t)
            raise ConvergenceError(
                f"{where}: {why}", f"relaxation at t = {t_new:.5g} failed: {reason}"
            )
        return its_total

    def report(self) -> StepReport:
        return StepReport(self.substeps, self.cuts, self.iterations)


class _Callables:
    def __init__(self, solve, save, restore):
        self.solve, self.save, self.restore = solve, save, restore


def advance(
    set_load: Callable[[float], None],
    solve: Callable[[], tuple[bool, int, str]],
    save: Callable[[], object],
    restore: Callable[[object], None],
    *,
    where: str,
    first: float = 1.0,
    min_fraction: float = 1.0 / 256.0,
) -> StepReport:
    """Take the load from s = 0 (the last converged state) to s = 1 with :class:`PathFollower`
    (no predictor: the callables give none), trying the whole increment first.

    Args:
        set_load: sets the load at fraction s (e.g. T = T_old + s (T_new - T_old)).
        solve: one nonlinear solve from the current state; returns (converged, iterations, reason).
        save, restore: snapshot and restore of the converged state.
        where: text naming the step for messages (e.g. "t = 12.5 s").
        first: first trial increment.
        min_fraction: smallest increment before giving up (ConvergenceError).
    """
    first = min(1.0, first)
    control = PathControl(first_step=first, max_step=1.0, min_step=min_fraction, predictor="none")
    follower = PathFollower(_Callables(solve, save, restore), set_load, control)
    follower.follow(1.0, where)
    return follower.report()
