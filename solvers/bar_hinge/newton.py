"""Newton's method with an energy line search and inertia control, and load-path following with
step halving that always restarts from the last converged state.

Equilibrium is a stationary point of the total energy Pi(x) over the free DOFs. Each Newton step
solves (K + mu I) dx = -g on the free DOFs with a symmetric sparse LU (SuperLU with diagonal
pivoting and a symmetric ordering, so the signs of U's diagonal give the inertia of K by Sylvester's
law). With inertia control on, mu = 0 is kept when K is positive definite and raised otherwise, so
every step is a descent direction and the iteration settles in a stable equilibrium (a minimum);
an Armijo backtracking search on Pi then safeguards the step. Convergence: |g_free| <= force
tolerance. When Newton would fail with its residual on a few nodes (a floating block, e.g. a raised
square on slack strips), the energy is first minimised over those nodes alone (:func:`settle_block`,
a block Gauss-Seidel step with the rigid part of each step exact) and Newton goes on.

Load paths are parametrised by a load factor t in [0, 1]: ``load(t)`` sets the model's state (e.g.
the strips' rest lengths) and returns the positions of the held DOFs. A failed increment is retried
from the last converged state with half the increment (the published code kept the failed trial's
prestrain instead); when the increment falls below its minimum a ConvergenceError names where and
why, after every converged state has been handed to ``on_step``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from scipy.spatial.transform import Rotation

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.parameters import check, param
from lcefem.solvers.bar_hinge.ldl import SymbolicLDL
from lcefem.solvers.bar_hinge.model import BarHingeModel, ReducedHessian


@dataclass(frozen=True)
class NewtonOptions:
    """Newton iteration settings."""

    max_iterations: int = param(
        50,
        "-",
        "chosen: quadratic convergence takes < 10; more means a poor "
        "start, so the increment is halved instead",
        minimum=1,
    )
    force_tolerance: float = param(
        1.0e-8,
        "N",
        "chosen: 1e-7 of the 0.1 N strip and ribbon forces; "
        "displacement error < 1e-6 mm for the softest buckled mode "
        "(~0.01 N/mm)",
        positive=True,
    )
    line_search: bool = param(True, "-", "Armijo backtracking on the total energy")
    inertia_control: bool = param(
        True,
        "-",
        "shift K until positive definite, so Newton settles in "
        "minima (off: plain Newton, which may also converge to saddles)",
    )
    max_shifts: int = param(30, "-", "chosen: each shift multiplies mu by 10", minimum=1)
    max_step: float = param(
        2.0,
        "mm",
        "chosen: trust radius, the largest nodal move of one Newton "
        "step (the structures' features are 1-10 mm); guards near-singular "
        "tangents at folds of the path",
        positive=True,
    )
    stall_iterations: int = param(
        0,
        "-",
        "chosen: after this many Newton iterations without halving "
        "the residual (0: never), the steps are damped (K + mu I, mu from "
        "1e-8 of the largest stiffness, x10 after a damped step that did not "
        "lower the residual, /10 after one that did, at most 1e-2; undamped "
        "again once the residual is halved): "
        "near contact and slack-strip kinks of the tangent, undamped Newton "
        "cycles a few 1e-6 N above the tolerance",
        minimum=0,
    )
    progress_iterations: int = param(
        0,
        "-",
        "chosen: beyond max_iterations, Newton goes on (up to this many "
        "iterations in all; 0: never) while the energy still falls by more than "
        "PROGRESS of itself over the last PROGRESS_WINDOW iterations: a long "
        "descent (the 5 x 5 gridshell from flat: 110 iterations to t = 0.1, "
        "converging all along) is not a poor start, and halving its increment "
        "costs more than finishing it",
        minimum=0,
    )
    energy_slack: float = param(
        1.0e-13,
        "-",
        "chosen: the Armijo test accepts a step that raises the energy by up "
        "to this fraction of it (the round-off of the energy's sum)",
        minimum=0.0,
    )
    snap_iterations: int = param(
        1000,
        "-",
        "chosen: extra iterations allowed once a state has lost "
        "stability and Newton descends to a new stable state (snap-through)",
        minimum=0,
    )
    settle: bool = param(
        True,
        "-",
        "when Newton would fail (budget spent, or no step accepted) with the residual on a few "
        "nodes (floating_block: a floating block, e.g. a raised square on slack strips), minimise "
        "the energy over those nodes alone (settle_block) and go on with max_iterations more",
    )
    settle_stall: int = param(
        0,
        "-",
        "chosen: also settle a floating block after this many Newton iterations without halving "
        "the residual (0: only when Newton would fail)",
        minimum=0,
    )


@dataclass(frozen=True)
class PathOptions:
    """Load-factor stepping settings (t from 0 to 1)."""

    initial_increment: float = param(
        0.05,
        "-",
        "chosen: 20 increments over the ramp (the published model used 300 fixed ones)",
        positive=True,
        maximum=1.0,
    )
    max_increment: float = param(
        0.1, "-", "chosen: keeps the output history readable", positive=True, maximum=1.0
    )
    min_increment: float = param(
        1.0e-5, "-", "chosen: below this the path is declared lost", positive=True
    )
    growth: float = param(1.5, "-", "increment growth after an easy increment", minimum=1.0)
    snap_increment: float = param(
        1.0e-3,
        "-",
        "chosen: when an increment smaller than this fails "
        "(a fold of the path: the next stable state is far away), one "
        "attempt jumps this far with the snap-through iteration budget",
        positive=True,
    )
    easy_iterations: int = param(
        6,
        "-",
        "an increment that converged within this many Newton iterations lets the next one grow",
        minimum=1,
    )


@dataclass
class NewtonResult:
    x: np.ndarray
    converged: bool
    iterations: int
    residual: float
    energy: float
    reason: str
    negative_pivots: int = -1  # of the unshifted K at the last factorisation (-1 if unknown)


@dataclass
class PathState:
    """A converged state on the load path."""

    t: float
    x: np.ndarray  # positions (n, 3) [mm]
    iterations: int
    energy: float  # [mJ]
    residual: float  # [N]
    reactions: np.ndarray  # gradient at the held DOFs [N] (force the supports apply)
    negative_pivots: int
    snapped: bool = False  # reached by a snap-through from the previous state

    @classmethod
    def of(cls, model, held: np.ndarray, t: float, res, snapped: bool = False) -> "PathState":
        """The state of the converged Newton result ``res`` at load factor ``t``, with the
        reactions at the ``held`` DOFs (the model's gradient there [N])."""
        grad = model.evaluate(res.x, derivatives=1)[1]
        return cls(
            t,
            res.x.copy(),
            res.iterations,
            res.energy,
            res.residual,
            grad[held].copy(),
            res.negative_pivots,
            snapped,
        )


@dataclass
class PathResult:
    states: list[PathState] = field(default_factory=list)
    seconds: float = 0.0
    failed_increments: int = 0

    @property
    def newton_iterations(self) -> list[int]:
        return [s.iterations for s in self.states[1:]]


#: Pivots below this fraction of the largest diagonal entry count as zero (a floating part, e.g. a
#: slack strip's node): such a matrix is shifted like an indefinite one.
ZERO_PIVOT = 1e-12


def factorize(
    matrix: sp.csc_matrix,
    diagonal: np.ndarray | None = None,
    shift: float = 0.0,
    ldl: SymbolicLDL | None = None,
):
    """Factorise ``matrix`` + ``shift`` I; returns (factors with a ``solve`` method, negative
    pivots, zero pivots). ``ldl``: the symbolic LDL^T of the matrix's pattern
    (:meth:`ReducedHessian.ldl_of`): the numeric LDL^T alone, unpivoted, whose D gives the inertia;
    without it, or when a pivot is exactly zero, symmetric-mode SuperLU, whose counts are -1 when
    the inertia is not available (off-diagonal pivoting happened). ``diagonal``: the shifted
    matrix's diagonal if known (it sets the zero-pivot threshold)."""
    if diagonal is None:
        diagonal = matrix.diagonal() + shift
    tol = ZERO_PIVOT * max(float(np.max(np.abs(diagonal))) if diagonal.size else 0.0, 1e-300)
    factors = ldl.factorize(matrix.data, shift) if ldl is not None else None
    if factors is not None:
        pivots = factors.pivots
        return (
            factors,
            int(np.count_nonzero(pivots < -tol)),
            int(np.count_nonzero(np.abs(pivots) <= tol)),
        )
    if shift:
        matrix = matrix + shift * sp.identity(matrix.shape[0], format="csc")
    lu = sla.splu(
        matrix, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
    )
    if np.array_equal(lu.perm_r, lu.perm_c):
        pivots = lu.U.diagonal()
        return (
            lu,
            int(np.count_nonzero(pivots < -tol)),
            int(np.count_nonzero(np.abs(pivots) <= tol)),
        )
    return lu, -1, -1


def _descent_step(
    kmat: sp.csc_matrix,
    rhs: np.ndarray,
    options: NewtonOptions,
    damping: float = 0.0,
    diagonal: np.ndarray | None = None,
    ldl: SymbolicLDL | None = None,
):
    """Solve (K + mu I) d = rhs; mu = 0 if K is positive definite (or inertia control is off); with
    ``damping`` > 0, mu >= damping times the largest diagonal entry. ``diagonal``: K's diagonal if
    known (the shifted matrices' diagonals follow from it). ``ldl``: see :func:`factorize`."""
    n = kmat.shape[0]
    diag = kmat.diagonal() if diagonal is None else diagonal
    scale = max(float(np.max(np.abs(diag))) if n else 1.0, 1e-300)
    mu, negative = damping * scale, -1
    for attempt in range(options.max_shifts):
        try:
            lu, neg, zero = factorize(kmat, diag + mu, mu, ldl)
        except RuntimeError:  # exactly singular: regularise
            lu, neg, zero = None, n, n
        if attempt == 0:
            negative = neg if damping == 0 else -1
        if lu is not None:
            d = lu.solve(rhs)
            ok = bool(np.all(np.isfinite(d)))
            if options.inertia_control:
                # Off-diagonal pivoting (inertia unknown) means a (near-)zero pivot: shift too.
                ok = ok and neg == 0 and zero == 0
            elif zero > 0:
                ok = False  # a singular K gives no usable step: regularise
            if ok:
                return d, negative, mu
        mu = 1e-10 * scale if mu == 0 else 10.0 * mu
    raise np.linalg.LinAlgError(f"no positive definite shift up to mu = {mu:.3g} N/mm")


def _negative_curvature_direction(kmat: sp.csc_matrix) -> tuple[float, np.ndarray]:
    """Lowest eigenpair of the (free-DOF) tangent stiffness.

    Up to ``DENSE_EIGEN`` DOFs: a dense eigh (~5 s for the 2547-DOF gridshell). Faster pairs (dsyevr
    for the lowest pair only, or shift-invert Lanczos) were tried on the dome: the same final state
    to 2e-8 but a different path (its lowest eigenvalue is nearly double at the lost stabilities, so
    the escape direction within the eigenspace depends on the solver) with more cut increments
    (15-23 instead of 9). Larger: shift-invert Lanczos (ARPACK) about a shift sigma below the whole
    spectrum (the first of -1e-8, -1e-7, ... times the largest diagonal entry for which K - sigma I
    is positive definite), where the eigenvalue nearest to sigma is the lowest one.
    """
    n = kmat.shape[0]
    if n <= DENSE_EIGEN:
        vals, vecs = np.linalg.eigh(kmat.toarray())
        return float(vals[0]), vecs[:, 0]
    scale = max(float(np.max(np.abs(kmat.diagonal()))), 1e-300)
    eye = sp.identity(n, format="csc")
    shift = 1e-8 * scale
    for _ in range(12):
        try:
            lu, neg, zero = factorize(kmat + shift * eye)
        except RuntimeError:
            neg, zero = -1, -1
        if neg == 0 and zero == 0:
            op = sla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
            vals, vecs = sla.eigsh(kmat, k=1, sigma=-shift, which="LM", OPinv=op, tol=1e-12)
            return float(vals[0]), vecs[:, 0]
        shift *= 10.0
    vals, vecs = sla.eigsh(kmat, k=1, which="SA")
    return float(vals[0]), vecs[:, 0]


#: Negative curvature of the tangent above -NEGLIGIBLE_CURVATURE times its largest diagonal entry is
#: numerically zero: no escape is tried. Chosen from the dome of Fig. 4 (largest diagonal entry
#: 1485 N/mm): at its fold the lowest eigenvalues of the tangent are -1e-11 to -8e-8 N/mm
#: (7e-15 to 5e-11 of the largest entry), with several further eigenvalues within 1e-12 to 2e-8 N/mm
#: of zero (near-mechanisms of slack strips and contacts): all 10 escapes along such a direction
#: there ended in a failed increment, after a dense eigh each (2 s CPU).
NEGLIGIBLE_CURVATURE = 1.0e-10


def _negligible_negative_curvature(kmat: sp.csc_matrix, reduced: ReducedHessian) -> bool:
    """True when K + tau I is positive definite, tau = NEGLIGIBLE_CURVATURE times the largest
    diagonal entry (Sylvester's law on its LDL^T, one factorisation): the lowest eigenvalue of K is
    above -tau, no direction of K lowers the energy by more than tau/2 |v|^2."""
    diag = reduced.diagonal(kmat)
    tau = NEGLIGIBLE_CURVATURE * max(float(np.max(np.abs(diag))) if diag.size else 0.0, 1e-300)
    try:
        _, negative, zero = factorize(kmat, diag + tau, tau, reduced.ldl_of(kmat))
    except RuntimeError:
        return False
    return negative == 0 and zero == 0


#: Progress that extends Newton beyond its budget (NewtonOptions.progress_iterations): the energy
#: fell by more than PROGRESS of itself over the last PROGRESS_WINDOW iterations (chosen: the 5 x 5
#: gridshell's descent from flat lowers its 1.45 mJ by 3e-4 over 15 iterations near its end; a
#: Newton that cycles at a kink changes it by < 1e-12).
PROGRESS = 1.0e-8
PROGRESS_WINDOW = 10


#: Up to this many free DOFs the lowest eigenpair comes from a dense eigh (above, a dense matrix of
#: 8 n^2 bytes and an O(n^3) solve are too much: Lanczos).
DENSE_EIGEN = 4000


#: Settle step (a floating block, NewtonOptions.settle): when Newton stalls, the nodes that carry
#: SETTLE_SHARE of the squared residual, if there are at most SETTLE_MAX_NODES of them, are a
#: floating block (chosen: on the 5 x 5 gridshell's Fig. 4 dome under the rollers the centre
#: junction's raised top square, 4 nodes, carries 90-100 % of every stalled residual, 5.7e-4 N per
#: node against 4e-9 N elsewhere; benchmarks/bh_soft_modes.py).
SETTLE_SHARE = 0.9
SETTLE_MAX_NODES = 16
#: Couplings of at least SETTLE_STIFF times the largest diagonal entry of the tangent tie a node
#: to a block (chosen: on the published 3 x 3's Fig. 4 dome the raised square's glue bars couple
#: its nodes by 450-1300 N/mm, its contacts and strips couple it to the rest by <= 0.24 N/mm; the
#: largest diagonal entry is ~1500 N/mm).
SETTLE_STIFF = 1e-2
#: The block's own Newton iterations per settle (chosen: a 12-DOF sub-problem; each iteration one
#: energy, gradient and Hessian of the whole model) and its tolerance: a fraction of the force
#: tolerance, so that the block's residual leaves the full Newton the rest.
SETTLE_ITERATIONS = 50
SETTLE_TOLERANCE = 0.1
#: The block's Newton stops after SETTLE_PATIENCE iterations without halving its residual (chosen:
#: the published 3 x 3 dome's square sits on strip-contact kinks, where the block's Newton crawls
#: at 1e-6 N, its steps cut to 1/16).
SETTLE_PATIENCE = 10
#: Settles per Newton solve (chosen: each that halves the residual is followed by up to
#: max_iterations Newton iterations; with 10, the 5 x 5 dome's fold near t = 0.9, where settling
#: does not help, cost 180 s CPU for 0.003 of the ramp).
SETTLE_MAX = 3


def floating_block(
    grad: np.ndarray, free: np.ndarray, ndof: int, kmat: sp.csc_matrix | None = None
) -> np.ndarray | None:
    """The nodes of a floating block, or None when the residual is spread over more nodes: those
    carrying SETTLE_SHARE of |g_free|^2 (largest first), with ``kmat`` (the tangent on the free
    DOFs) closed under stiff couplings (every node coupled to the block by an entry of at least
    SETTLE_STIFF times the largest diagonal entry joins it, so a block is never a part of a stiff
    body); at most SETTLE_MAX_NODES nodes."""
    g = np.zeros(ndof)
    g[free] = grad[free]
    g2 = (g.reshape(-1, 3) ** 2).sum(axis=1)
    total = float(g2.sum())
    if total <= 0.0:
        return None
    order = np.argsort(g2, kind="stable")[::-1][:SETTLE_MAX_NODES]
    share = np.cumsum(g2[order]) / total
    k = int(np.searchsorted(share, SETTLE_SHARE)) + 1
    if k > order.size or share[k - 1] < SETTLE_SHARE:
        return None
    nodes = np.sort(order[:k])
    if kmat is None:
        return nodes
    diag = kmat.diagonal()
    stiff = SETTLE_STIFF * max(float(np.max(np.abs(diag))) if diag.size else 0.0, 1e-300)
    node_of = free // 3  # the node of each free DOF (row of kmat)
    while True:
        cols = np.flatnonzero(np.isin(node_of, nodes))
        sub = kmat[:, cols].tocoo()
        coupled = np.unique(node_of[sub.row[np.abs(sub.data) >= stiff]])
        grown = np.union1d(nodes, coupled)
        if grown.size > SETTLE_MAX_NODES:
            return None
        if grown.size == nodes.size:
            return nodes
        nodes = grown


def rigid_update(points: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Move ``points`` (m, 3) [mm] by ``step`` (m, 3) [mm] with its rigid part exact.

    The step is split into the infinitesimal rigid motion a + w x r_i (r_i = p_i - c, c the
    centroid; least squares) and the rest d_i - a - w x r_i; the new points are
    c + a + R(w) r_i + (d_i - a - w x r_i), R(w) the finite rotation of the rotation vector w
    (scipy's ``Rotation.from_rotvec``). A linear step along a block's soft rigid rotation stretches
    its stiff bars to second order (|w|^2 |r|/2), the finite rotation does not; both agree to first
    order (the same tangent, so an Armijo test with the slope g . d stays valid). Fewer than 3
    points: the linear step.
    """
    m = points.shape[0]
    if m < 3:
        return points + step
    c = points.mean(axis=0)
    r = points - c
    # d_i = a + w x r_i = a - [r_i]x w: least squares over (a, w); the translation decouples
    # (sum r_i = 0), so a is the mean step and w solves the 3 x 3 normal equations.
    a = step.mean(axis=0)
    rel = step - a
    rx = np.zeros((m, 3, 3))
    rx[:, 0, 1], rx[:, 0, 2] = r[:, 2], -r[:, 1]
    rx[:, 1, 0], rx[:, 1, 2] = -r[:, 2], r[:, 0]
    rx[:, 2, 0], rx[:, 2, 1] = r[:, 1], -r[:, 0]
    # w x r_i = rx_i @ w with rx_i = -[r_i]x
    normal = np.einsum("mji,mjk->ik", rx, rx)
    rhs = np.einsum("mji,mj->i", rx, rel)
    w = np.linalg.lstsq(normal, rhs, rcond=1e-12)[0]
    rest = rel - np.einsum("mij,j->mi", rx, w)
    return c + a + r @ Rotation.from_rotvec(w).as_matrix().T + rest


def settle_block(
    model: BarHingeModel,
    x: np.ndarray,
    free: np.ndarray,
    nodes: np.ndarray,
    reduced: ReducedHessian,
    options: NewtonOptions,
) -> tuple[np.ndarray, int]:
    """Minimise the energy over the free DOFs of the block ``nodes`` alone, every other DOF fixed
    (a block Gauss-Seidel step): Levenberg-Marquardt Newton on the block's dense tangent K_bb,
    (K_bb + mu I) d = -g_b with mu = 0 while K_bb is positive definite, each step applied with
    its rigid part exact (:func:`rigid_update`) and safeguarded by an Armijo test on the energy
    (or, where the energy cannot resolve it, on the block's residual). Stops at |g_b| <=
    SETTLE_TOLERANCE x the force tolerance, after SETTLE_PATIENCE iterations without halving
    |g_b|, or after SETTLE_ITERATIONS; returns the positions (3n,) [mm] and the iterations. A
    held DOF of the block keeps its value (the step is zero there to first order)."""
    x = np.array(x, dtype=float).reshape(-1)
    dofs = (3 * nodes[:, None] + np.arange(3)).reshape(-1)
    on_free = np.isin(dofs, free)
    index = np.searchsorted(free, dofs[on_free])  # positions in the reduced matrix
    held_in_block = ~on_free.reshape(-1, 3)
    energy, grad, coo = model.evaluate(x)
    mu = 0.0
    best, since = math.inf, 0  # the block's best residual, iterations since it was halved
    for it in range(SETTLE_ITERATIONS):
        gb = grad[dofs[on_free]]
        residual = float(np.linalg.norm(gb))
        if residual <= SETTLE_TOLERANCE * options.force_tolerance:
            return x, it
        best, since = (residual, 0) if residual <= 0.5 * best else (best, since + 1)
        if since >= SETTLE_PATIENCE:
            return x, it
        kbb = reduced.matrix(coo)[index][:, index].toarray()
        vals, vecs = np.linalg.eigh(kbb)
        scale = max(float(np.max(np.abs(np.diag(kbb)))), 1e-300)
        floor = 1e-12 * scale  # the positive definiteness resolvable in K_bb
        shift = max(mu, floor - vals[0], 0.0)
        step_b = -vecs @ ((vecs.T @ gb) / (vals + shift))
        longest = float(np.max(np.abs(step_b)))
        if longest > options.max_step:
            step_b *= options.max_step / longest
        slope = float(np.dot(gb, step_b))
        step = np.zeros(dofs.size)
        step[on_free] = step_b
        step = step.reshape(-1, 3)
        points = x.reshape(-1, 3)[nodes]
        resolvable = -slope > 1e-10 * (abs(energy) + 1e-12)
        alpha, accepted = 1.0, False
        for _ in range(30):
            trial = x.copy()
            # a held DOF keeps its value (the rotation's second-order part would move it)
            moved = rigid_update(points, alpha * step)
            trial.reshape(-1, 3)[nodes] = np.where(held_in_block, points, moved)
            if resolvable:
                e_new = model.evaluate(trial, derivatives=0)
                ok = math.isfinite(e_new) and e_new <= energy + 1e-4 * alpha * slope
            else:
                g_new = model.evaluate(trial, derivatives=1)[1]
                ok = float(np.linalg.norm(g_new[dofs[on_free]])) < residual
            if ok:
                accepted = True
                break
            alpha *= 0.5
        if not accepted:
            mu = max(10.0 * mu, 1e-8 * scale)  # a shorter, more gradient-like step
            continue
        mu = 0.0 if alpha == 1.0 else mu
        x = trial
        energy, grad, coo = model.evaluate(x)
    return x, SETTLE_ITERATIONS


def _stall(
    best: float, stalled: int, level: int, residual: float, previous: float, damping: float
) -> tuple[float, int, int]:
    """Stall bookkeeping after an accepted step: (best residual, stalled iterations, damping level).
    Halving the best residual ends the stall (no damping); a damped step lowers the damping when it
    lowered the residual, else raises it (at most 1e-2 of the largest stiffness)."""
    if residual <= 0.5 * best:
        return residual, 0, 0
    if damping:
        level = max(level - 1, 0) if residual < previous else min(level + 1, 6)
    return best, stalled + 1, level


def newton(
    model: BarHingeModel,
    x0: np.ndarray,
    free: np.ndarray,
    options: NewtonOptions = NewtonOptions(),
    reduced: ReducedHessian | None = None,
) -> NewtonResult:
    """Minimise the model's energy over the DOFs ``free`` starting from positions ``x0`` (n, 3).

    With inertia control, a point where the gradient vanishes but the tangent is indefinite (a
    saddle: the state has lost stability) is left along the eigenvector of the lowest eigenvalue,
    and the iteration continues to a stable state (a snap-through), with ``snap_iterations`` more
    iterations allowed; not when that curvature is numerically zero (above -NEGLIGIBLE_CURVATURE
    times the largest stiffness: a floating node, not a lost stability), where the step is declined.
    """
    x = np.array(x0, dtype=float).reshape(-1)
    free = np.asarray(free, dtype=np.int64)
    reduced = reduced or ReducedHessian.of(model, free)
    energy, grad, coo = model.evaluate(x)
    negative = -1
    residual = float(np.linalg.norm(grad[free]))
    budget = options.max_iterations
    escapes = 0
    it = 0
    best, stalled = residual, 0  # iterations since the residual was last halved
    history: list[float] = []  # the energy before each iteration [mJ]
    level = (
        0  # damping exponent of the stalled iterations (mu = 1e-8 * 10^level of the largest entry)
    )

    settles = 0

    def settle() -> bool:
        """Settle a floating block (settle_block); False if there is none or it does not halve the
        residual."""
        nonlocal x, energy, grad, coo, residual, budget, settles, best, stalled, level
        if not options.settle or settles >= SETTLE_MAX:
            return False
        nodes = floating_block(grad, free, model.ndof, reduced.matrix(coo))
        if nodes is None:
            return False
        trial = settle_block(model, x, free, nodes, reduced, options)[0]
        e_new, g_new, c_new = model.evaluate(trial)
        r_new = float(np.linalg.norm(g_new[free]))
        settles += 1
        if not (math.isfinite(r_new) and r_new <= 0.5 * residual):
            return False  # no floating block after all: Newton fails as it used to
        x, energy, grad, coo, residual = trial, e_new, g_new, c_new, r_new
        budget = max(budget, it + options.max_iterations)
        best, stalled, level = residual, 0, 0
        return True

    def escape() -> bool:
        """Step along negative curvature until the energy drops; False if it cannot."""
        nonlocal x, energy, grad, coo, residual, budget, escapes
        if escapes >= 20:
            return False
        kmat = reduced.matrix(coo)
        if _negligible_negative_curvature(kmat, reduced):
            return False
        lowest, vec = _negative_curvature_direction(kmat)
        if lowest >= 0:
            return False
        sign = -1.0 if float(np.dot(grad[free], vec)) > 0 else 1.0
        vec = sign * vec / np.max(np.abs(vec))
        trial = x.copy()
        for k in range(30):
            alpha = 2.0**-k  # from 1 mm (largest nodal move) down
            trial[free] = x[free] + alpha * vec
            e_new = model.evaluate(trial, derivatives=0)
            if math.isfinite(e_new) and e_new < energy - 1e-13 * abs(energy):
                x = trial
                energy, grad, coo = model.evaluate(x)
                residual = float(np.linalg.norm(grad[free]))
                if escapes == 0:
                    budget = it + options.snap_iterations
                escapes += 1
                return True
        return False

    while True:
        if not math.isfinite(energy) or not math.isfinite(residual):
            return NewtonResult(
                x.reshape(-1, 3), False, it, residual, energy, "energy or residual not finite"
            )
        if residual <= options.force_tolerance:
            try:
                kmat = reduced.matrix(coo)
                negative = factorize(kmat, reduced.diagonal(kmat), ldl=reduced.ldl_of(kmat))[1]
            except RuntimeError:
                negative = -1
            if options.inertia_control and negative > 0 and it < budget and escape():
                it += 1
                continue
            return NewtonResult(x.reshape(-1, 3), True, it, residual, energy, "converged", negative)
        if it >= budget and not (
            it < options.progress_iterations
            and len(history) > PROGRESS_WINDOW
            and history[-PROGRESS_WINDOW - 1] - energy > PROGRESS * abs(energy)
        ):
            if settle():
                continue
            break
        if options.settle_stall and stalled >= options.settle_stall and settle():
            continue
        history.append(energy)
        it += 1
        r = grad[free]
        r_old = residual
        damping = 0.0
        if options.stall_iterations and stalled >= options.stall_iterations:
            damping = 1e-8 * 10.0**level
        try:
            kmat = reduced.matrix(coo)
            step, negative, _ = _descent_step(
                kmat, -r, options, damping, reduced.diagonal(kmat), reduced.ldl_of(kmat)
            )
        except np.linalg.LinAlgError as exc:
            return NewtonResult(x.reshape(-1, 3), False, it, residual, energy, str(exc), negative)
        longest = float(np.max(np.abs(step))) if step.size else 0.0
        if longest > options.max_step:
            step *= options.max_step / longest
        slope = float(np.dot(r, step))
        alpha = 1.0
        trial = x.copy()
        accepted = False
        # When the predicted decrease is below what the energy can resolve, the residual decides.
        resolvable = -slope > 1e-10 * (abs(energy) + 1e-12)
        for _ in range(20 if options.line_search and resolvable else 0):
            trial[free] = x[free] + alpha * step
            e_new = model.evaluate(trial, derivatives=0)
            if math.isfinite(e_new) and (
                slope >= 0
                or e_new <= energy + 1e-4 * alpha * slope + options.energy_slack * abs(energy)
            ):
                accepted = True
                break
            alpha *= 0.5
        if accepted:
            x = trial
            energy, grad, coo = model.evaluate(x)
            residual = float(np.linalg.norm(grad[free]))
            best, stalled, level = _stall(best, stalled, level, residual, r_old, damping)
            continue
        # The energy cannot resolve the step: backtrack on the residual instead (near a kink of the
        # tangent, e.g. a contact switching on, the full step can overshoot while a part of it
        # helps).
        reduced_step = False
        alpha = 1.0
        for _ in range(12):
            trial[free] = x[free] + alpha * step
            # The gradient alone (an eighth of the cost with the Hessian); the Hessian only at the
            # point taken (the same energy and gradient: one evaluation code path).
            e_new, g_new = model.evaluate(trial, derivatives=1)
            r_new = float(np.linalg.norm(g_new[free]))
            if math.isfinite(r_new) and r_new < residual:
                energy, grad, coo = model.evaluate(trial)
                x, residual = trial, r_new
                reduced_step = True
                break
            alpha *= 0.5
        if reduced_step:
            best, stalled, level = _stall(best, stalled, level, residual, r_old, damping)
            continue
        if options.inertia_control and negative > 0 and escape():
            continue
        if options.stall_iterations and damping < 1e-2 and it < budget:
            # no usable step: damp the next ones (a gradient-like step near a kink still helps)
            level = min(level + 1, 6) if damping else level
            stalled = max(stalled + 1, options.stall_iterations)
            continue
        if settle():
            continue
        return NewtonResult(
            x.reshape(-1, 3), False, it, residual, energy, "line search failed", negative
        )
    return NewtonResult(
        x.reshape(-1, 3),
        False,
        it,
        residual,
        energy,
        f"no convergence in {it} iterations (|g| = {residual:.3g} N)",
        negative,
    )


def path_setup(
    model: BarHingeModel, held, newton_options: NewtonOptions, path_options: PathOptions
) -> tuple[np.ndarray, np.ndarray, ReducedHessian]:
    """The options of a load path checked, and its (held DOFs, free DOFs, reduced Hessian):
    shared by :func:`follow_path` and the stability-watching ramp
    (:mod:`lcefem.solvers.problems.stable_ramp`)."""
    check(newton_options, "solver")
    check(path_options, "path")
    if path_options.min_increment > path_options.initial_increment:
        raise InputError("path.min_increment: must be <= path.initial_increment")
    held = np.asarray(held, dtype=np.int64)
    free = np.setdiff1d(np.arange(model.ndof), held)
    return held, free, ReducedHessian.of(model, free)


def follow_path(
    model: BarHingeModel,
    x_start: np.ndarray,
    held: np.ndarray,
    load: Callable[[float], np.ndarray],
    *,
    newton_options: NewtonOptions = NewtonOptions(),
    path_options: PathOptions = PathOptions(),
    on_step: Callable[[PathState], None] | None = None,
    progress: Callable[[float], None] | None = None,
) -> PathResult:
    """Follow the equilibrium path from t = 0 to t = 1.

    Args:
        model: the bar-and-hinge model (its state is set by ``load``).
        x_start: positions (n, 3) [mm] in equilibrium at t = 0 (e.g. the reference).
        held: indices of the held (prescribed) DOFs into the flattened positions.
        load: t -> values of the held DOFs (positions [mm]) at load factor t; sets the model state.
        on_step: called with every converged state (t = 0 included), e.g. to write outputs.
        progress: called with the load factor after each converged increment.
    Returns:
        The converged states. Raises ConvergenceError (with ``last_state``) when the increment
        falls below ``path_options.min_increment``.
    """
    held, free, reduced = path_setup(model, held, newton_options, path_options)
    started = time.perf_counter()
    result = PathResult()

    snap_options = dataclasses.replace(
        newton_options,
        max_iterations=newton_options.max_iterations + newton_options.snap_iterations,
    )

    def solve(t, guess, options=newton_options):
        x = np.array(guess, dtype=float).reshape(-1)
        x[held] = load(t)
        return newton(model, x, free, options, reduced)

    def record(t, res, snapped=False):
        state = PathState.of(model, held, t, res, snapped)
        result.states.append(state)
        if on_step is not None:
            on_step(state)
        return state

    res = solve(0.0, x_start)
    if not res.converged:
        raise ConvergenceError("load factor t = 0 (the start)", res.reason)
    last = record(0.0, res)
    previous = None
    dt = path_options.initial_increment
    snap_tried_at = -1.0
    while last.t < 1.0:
        dt = min(dt, 1.0 - last.t)
        t_try = 1.0 if 1.0 - (last.t + dt) < 1e-12 else last.t + dt
        res = None
        snapped = False
        # Predictor: secant extrapolation from the last two converged states; if that fails,
        # the same increment from the last converged state itself.
        guesses = [last.x]
        if previous is not None and not last.snapped:
            ratio = (t_try - last.t) / (last.t - previous.t)
            guesses.insert(0, last.x + ratio * (last.x - previous.x))
        for guess in guesses:
            res = solve(t_try, guess)
            if res.converged:
                break
        if not res.converged and dt < path_options.snap_increment and snap_tried_at != last.t:
            # Failures at ever smaller increments: a fold of the path. Let Newton descend (with
            # inertia control) to the next stable state, a little beyond the fold.
            snap_tried_at = last.t
            t_snap = min(1.0, last.t + path_options.snap_increment)
            res_snap = solve(t_snap, last.x, snap_options)
            if res_snap.converged:
                res, t_try, snapped = res_snap, t_snap, True
                dt = path_options.snap_increment
        if res.converged:
            previous, last = last, record(t_try, res, snapped)
            if progress is not None:
                progress(t_try)
            if res.iterations <= path_options.easy_iterations:
                dt = min(dt * path_options.growth, path_options.max_increment)
            continue
        result.failed_increments += 1
        load(last.t)  # restore the model state of the last converged step
        dt *= 0.5
        if dt < path_options.min_increment:
            result.seconds = time.perf_counter() - started
            err = ConvergenceError(
                f"load factor t = {last.t:.6g} (last converged; trying t = {t_try:.6g})",
                f"{res.reason}; increment halved below {path_options.min_increment:g}",
            )
            err.last_state = last
            err.result = result
            raise err
    result.seconds = time.perf_counter() - started
    return result
