"""Newton's method on a rod potential with banded Cholesky solves and a backtracking line search.

The potential (a time step's incremental potential, or the static energy) is minimised over the
free dofs. Every iterate is reached from the solve's start by one displacement, its reference
frames transported directly from the start's tangents, so the potential is one fixed smooth
function of the dofs and its gradient and Hessian (with ``apply_source_change``) are exact:
Newton converges quadratically. Each iteration solves H d = -g with
LAPACK's banded Cholesky (dpbtrf); if H is not positive definite a Levenberg shift lambda I is added
(grown tenfold until the factorisation succeeds; it shrinks again on later iterations). The step
is scaled back by halving until the Armijo condition holds (with a round-off allowance near
convergence). If an edge turns by more than ``resource_angle`` from the start (large static
rotations), the current state becomes the new transport source.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.linalg import LinAlgError, lapack

from lcefem.solvers.der.assembly import BANDWIDTH, Derivatives
from lcefem.solvers.der.model import RodState, node_dofs, twist_dofs


@dataclass(frozen=True)
class NewtonOptions:
    """Stopping rules of the Newton loop."""

    max_iterations: int = 30
    force_tol: float = 1e-10  # [N] (and N mm on the edge angles): max |gradient| on free dofs
    step_tol: float = 1e-10  # [mm] (and rad): max |update| after a full step
    armijo: float = 1e-4
    min_step: float = 1.0 / 1024.0  # smallest line-search factor before giving up
    max_shift_tries: int = 12
    watchdog: int = 3  # full steps allowed to raise the potential before backtracking
    resource_angle: float = 1.0  # [rad] edge rotation from the start that triggers a new source
    max_rotation: float = (
        0.5  # [rad] largest edge-angle update of one iteration (longer steps are scaled)
    )
    max_displacement: float = float("inf")  # [mm] largest node update of one iteration
    unchecked_step: float = (
        0.0  # [mm, rad] updates below this are taken without the line-search energy
    )
    lag_residual: float = (
        0.0  # [N, N mm] below this residual the Hessian factor is reused (minimise); 0: never
    )
    lag_contraction: float = 0.25  # [-] a lagged step must cut the residual at least by this factor


@dataclass
class NewtonResult:
    state: RodState
    converged: bool
    iterations: int
    residual: float
    reason: str


class _FixedMask:
    """Rows and columns of prescribed dofs in the lower banded storage."""

    def __init__(self, fixed: np.ndarray):
        self.fixed = fixed
        nd = len(fixed)
        self.any = bool(fixed.any())
        if self.any:
            j = np.arange(nd)[None, :]
            r = np.arange(BANDWIDTH + 1)[:, None]
            i = r + j
            inside = i < nd
            row_fixed = np.zeros_like(inside)
            row_fixed[inside] = fixed[i[inside]]
            self.mask = (row_fixed | fixed[None, :]) & inside

    def apply(self, grad: np.ndarray, band: np.ndarray | None) -> None:
        if not self.any:
            return
        grad[self.fixed] = 0.0
        if band is not None:
            band[self.mask] = 0.0
            band[0, self.fixed] = 1.0


def banded_cholesky(band: np.ndarray) -> np.ndarray:
    """Lower banded Cholesky factor (LAPACK dpbtrf, called directly: scipy's ``cholesky_banded``
    wrapper costs as much as the factorisation at the rod's sizes)."""
    factor, info = lapack.dpbtrf(band, lower=1)
    if info != 0:
        raise LinAlgError(f"banded Cholesky: LAPACK info {info} (not positive definite)")
    return factor


def banded_cholesky_solve(factor: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solution of L L^T x = rhs with the factor of :func:`banded_cholesky` (LAPACK dpbtrs)."""
    x, info = lapack.dpbtrs(factor, rhs, lower=1)
    if info != 0:
        raise LinAlgError(f"banded Cholesky solve: LAPACK info {info}")
    return x


def factorise_banded_spd(band: np.ndarray, shift0: float, max_tries: int):
    """Cholesky factor of H + lambda I, lambda = 0 first, then growing from shift0; returns (factor,
    lambda)."""
    lam = 0.0
    scale = float(np.max(np.abs(band[0]))) or 1.0
    for _ in range(max_tries + 1):
        try:
            shifted = band
            if lam > 0.0:
                shifted = band.copy()
                shifted[0] += lam
            return banded_cholesky(shifted), lam
        except (LinAlgError, ValueError):
            lam = max(shift0, 1e-10 * scale) if lam == 0.0 else lam * 10.0
    raise LinAlgError("Hessian not positive definite even with a shift")


def minimise(
    start: RodState,
    fixed: np.ndarray,
    evaluate: Callable[[RodState, bool], Derivatives],
    options: NewtonOptions = NewtonOptions(),
) -> NewtonResult:
    """Minimise the potential ``evaluate`` from ``start`` over the free dofs.

    A full Newton step that raises the potential is still taken up to ``options.watchdog`` times
    in a row (the watchdog technique of Chamberlain et al. 1982, Nocedal & Wright Sec. 15.6): a
    linearised step of a rod moves nodes along straight lines, so a large rotation stretches the
    edges to second order and a stiff EA makes the first iterate's energy huge although Newton
    recovers in one more step. If the potential has not fallen below the checkpoint's by then,
    the solver returns to the checkpoint and backtracks along its direction.

    Lagged Hessian (``options.lag_residual`` > 0, when ``evaluate`` has a ``gradient(state)`` method
    giving energy and gradient without the Hessian): a step taken from an iterate whose residual is
    below ``lag_residual`` leads to an iterate evaluated without the Hessian; if its residual is
    below ``lag_contraction`` times the previous one, the next step reuses the last Cholesky factor
    (a chord step, Kelley, Iterative Methods for Linear and Nonlinear Equations, 1995, Sec. 5.4: it
    converges linearly at a rate that falls with the distance to the solution), else the Hessian is
    evaluated there. The converged iterate then costs a gradient only, and so do the last
    iterations of a step. Far from the solution (residual above ``lag_residual``) the chord rate is
    poor (measured on the rolling ribbon: 0.36 per iteration at 1e-5 N), so full Newton is kept
    there.

    The integrator runs the same loop compiled
    (:func:`lcefem.solvers.der.compiled_newton.minimise_step`, ``StepOptions.compiled``); this one
    is its reference and serves any other potential (statics).

    Args:
        evaluate: (state, hessian) -> Derivatives; with hessian False it may leave band None and
            must still give the energy (used by the line search).
    """
    mask = _FixedMask(fixed)
    source = start.resourced()
    total = np.zeros(len(source.q()))  # displacement of the current iterate from the source
    state = source
    n = len(start.x)
    xi, ti = node_dofs(n), twist_dofs(n)
    cos_limit = np.cos(options.resource_angle)
    shift = 0.0
    residual = np.inf
    checkpoint = None  # (total, state, energy, step, slope) before a watched full step
    watched = 0
    gradient_only = getattr(evaluate, "gradient", None) if options.lag_residual > 0 else None
    d = None  # derivatives of ``state`` (band None: gradient only)
    factor = None  # Cholesky factor of the last evaluated Hessian (and its shift)
    for it in range(1, options.max_iterations + 1):
        if (
            checkpoint is None
            and np.min(np.einsum("ki,ki->k", source.tangents, state.tangents)) < cos_limit
        ):
            source, total = state.resourced(), np.zeros_like(total)
            state, d, factor = source, None, None
        previous = residual
        if d is None:
            d = evaluate(state, True)
        g = d.grad
        mask.apply(g, d.band)
        residual = float(np.max(np.abs(g)))
        if not np.isfinite(residual):
            return NewtonResult(state, False, it, residual, "non-finite residual")
        if checkpoint is not None and d.energy <= checkpoint[2] + options.armijo * checkpoint[4]:
            checkpoint, watched = None, 0  # the watched steps paid off
        if residual <= options.force_tol and checkpoint is None:
            return NewtonResult(state, True, it - 1, residual, "residual below force_tol")
        if d.band is None and (factor is None or residual > options.lag_contraction * previous):
            d = evaluate(state, True)  # the lagged factor does not contract enough: a fresh Hessian
            g = d.grad
            mask.apply(g, d.band)
        try:
            if d.band is not None:
                factor, shift = factorise_banded_spd(
                    d.band, max(shift * 0.1, 0.0), options.max_shift_tries
                )
            step = banded_cholesky_solve(factor, -g)
        except LinAlgError:
            return NewtonResult(state, False, it, residual, "singular Hessian")
        step[fixed] = 0.0
        dx = float(np.max(np.abs(step[xi])))
        dth = float(np.max(np.abs(step[ti]))) if len(ti) else 0.0
        if max(dx, dth) <= options.step_tol and checkpoint is None:
            # The Newton update is at round-off level (e.g. a stiff EA sets a residual floor).
            return NewtonResult(
                source.moved(total + step), True, it, residual, "update below step_tol"
            )
        # Limit the update (a soft mode, e.g. rolling about the axis, can ask for huge steps).
        scale = min(
            1.0,
            options.max_rotation / dth if dth > 0 else 1.0,
            options.max_displacement / dx if dx > 0 else 1.0,
        )
        if scale < 1.0:
            step *= scale
        slope = float(g @ step)
        allowance = 1e-12 * abs(d.energy) + 1e-300
        lag = gradient_only is not None and residual <= options.lag_residual
        trial = source.moved(total + step)
        if checkpoint is None and max(dx, dth) * scale <= options.unchecked_step:
            # Quadratic convergence region: the energy check would only cost an evaluation.
            state, total = trial, total + step
            d = gradient_only(state) if lag else None
            continue
        # The trial's derivatives come with its energy: an accepted trial needs no second
        # evaluation.
        d_trial = gradient_only(trial) if lag else evaluate(trial, True)
        e_trial = d_trial.energy
        if np.isfinite(e_trial) and e_trial <= d.energy + options.armijo * slope + allowance:
            state, total, d = trial, total + step, d_trial
            continue
        if np.isfinite(e_trial) and watched < options.watchdog:
            if checkpoint is None:
                checkpoint = (total, state, d.energy, step, slope)
            watched += 1
            state, total, d = trial, total + step, d_trial
            continue
        # Back to the checkpoint (if any) and backtrack along its direction.
        if checkpoint is not None:
            total, state, energy0, step, slope = checkpoint
            checkpoint, watched = None, 0
        else:
            energy0 = d.energy
        alpha = 0.5
        while True:
            trial = source.moved(total + alpha * step)
            e_trial = evaluate(trial, False).energy
            if (
                np.isfinite(e_trial)
                and e_trial <= energy0 + options.armijo * alpha * slope + allowance
            ):
                break
            alpha *= 0.5
            if alpha < options.min_step:
                return NewtonResult(state, False, it, residual, "line search failed")
        state, total, d = trial, total + alpha * step, None
    return NewtonResult(state, False, options.max_iterations, residual, "too many iterations")
