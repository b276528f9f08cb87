"""Inverse design of bar-and-hinge structures driven by LCE strips: find strip lambdas whose stable
equilibrium has given observables (e.g. the gridshell's centre curvatures).

Design variables p_j are lambdas [-] (relative to the isotropic length) of strip selections; every
LCE bar of selection j gets the rest fraction f = p_j / lambda_N (bars in no selection keep a fixed
rest fraction). For an equilibrium x(p) (gradient g(x, f(p)) = 0 on the free DOFs) the implicit
function theorem gives the exact sensitivity

    dx_free/dp_j = -K^-1 dg_free/dp_j,   dg/dp_j = sum_{b in j} (dg/df_b) / lambda_N,

with K the Hessian of the free DOFs (factorised once per equilibrium) and dg/df_b analytic
(:meth:`BarHingeModel.rest_fraction_sensitivity`). The observables' Jacobian follows as
d obs/dp_j = (d obs/dx) dx/dp_j, the directional derivative of the (explicit, smooth) observable
function evaluated by a central difference along dx/dp_j with the largest nodal move
``OBSERVABLE_STEP`` (truncation error ~ step^2, i.e. < 1e-10 relative for the mm-scale shapes).

Forward solves are warm-started: the rest fractions are ramped from those of the previous
equilibrium to the new ones (one increment first, halved on failure), starting from the previous
equilibrium's positions; if that fails the ramp restarts from the as-built state.

The least-squares problem min_p |W (obs(p) - target)|^2 with bounds on p is solved by
scipy.optimize.least_squares (method :data:`METHOD`, the exact Jacobian above).

Units: mm, N; lambdas [-].
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.optimize as opt

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.bar_hinge.model import BarHingeModel, ReducedHessian
from lcefem.solvers.bar_hinge.newton import NewtonOptions, PathOptions, factorize, follow_path

#: Largest nodal move [mm] of the central difference of the observables along dx/dp (the shapes'
#: features are 1-100 mm: truncation ~ (1e-4/1)^2 relative, round-off ~ 1e-16 * 100 mm / 1e-4 mm).
OBSERVABLE_STEP = 1.0e-4
#: Scaled residual of a design point without an equilibrium [-]: far above any reachable one (the
#: curvature scale is 0.01 1/mm, the surface's curvatures stay below 0.1 1/mm), so the trust region
#: rejects the step.
FAILED_RESIDUAL = 1.0e3
#: Warm-started forward solves: the whole change in one increment first, halved on failure.
#: scipy.optimize.least_squares method: "dogbox" (a dogleg in a rectangular trust region; its
#: Gauss-Newton step is the minimum-norm least-squares step, exact for more design variables than
#: observables). Measured on the one-cell all-strips design (6 variables, 3 targets, random lambdas
#: seed 7): "dogbox" reaches |r| <= 1e-5 1/mm in 4 evaluations with either model set; "trf"
#: (reflective, Coleman-Li scaling) zigzags, |r| 4.0e-4 1/mm after 60 evaluations with the
#: FE-calibrated set (2.3e-5 after 200), 29 evaluations with the published one.
METHOD = "dogbox"
WARM_PATH = PathOptions(
    initial_increment=1.0, max_increment=1.0, easy_iterations=8, growth=2.0, min_increment=1.0e-3
)


@dataclass
class StripParameters:
    """Design variables: one lambda per selection (``names``), mapped onto the LCE bars.

    ``index[group]`` (m,) gives each bar's design variable (-1: fixed at ``fixed[group]``, a rest
    fraction)."""

    names: list[str]
    index: dict[str, np.ndarray]
    fixed: dict[str, np.ndarray]
    lambda_N: float

    @property
    def size(self) -> int:
        return len(self.names)

    def rest_fractions(self, p) -> dict[str, np.ndarray]:
        p = np.asarray(p, dtype=float)
        out = {}
        for g, idx in self.index.items():
            f = self.fixed[g].copy()
            on = idx >= 0
            f[on] = p[idx[on]] / self.lambda_N
            out[g] = f
        return out


def strip_parameters(
    structure: BarHingeStructure,
    selections: Sequence,
    lambda_N: float,
    fixed_lambda: float | None = None,
) -> StripParameters:
    """Design variables for selections of strips (channels "Tx", groups "XD1", strip ids, ... as
    :func:`lcefem.meshes.gridshell.select_strips`); the selections must not overlap; other strips
    keep ``fixed_lambda`` (default lambda_N: as built)."""
    from lcefem.meshes.gridshell import STRIP_GROUPS, select_strips

    sob = structure.info["strip_of_bar"]
    owner = {}
    for j, key in enumerate(selections):
        for s in select_strips(structure, key, "design.channels").tolist():
            if s in owner:
                raise InputError(
                    f"design.channels: strip {s} is in both {selections[owner[s]]!r} and {key!r}"
                )
            owner[s] = j
    index, fixed = {}, {}
    f0 = (lambda_N if fixed_lambda is None else fixed_lambda) / lambda_N
    for g in STRIP_GROUPS:
        index[g] = np.array([owner.get(int(s), -1) for s in sob[g]], dtype=np.int64)
        fixed[g] = np.full(sob[g].size, f0)
    return StripParameters([str(s) for s in selections], index, fixed, float(lambda_N))


@dataclass
class DesignState:
    """An equilibrium for design variables p: positions, observables and their Jacobian."""

    p: np.ndarray
    x: np.ndarray  # (n, 3) [mm]
    observables: np.ndarray
    jacobian: np.ndarray | None  # d obs / d p
    newton_iterations: int
    restarted: bool  # warm start failed: ramped from the as-built state


@dataclass
class ForwardStats:
    solves: int = 0
    newton_iterations: int = 0
    restarts: int = 0
    failures: int = 0  #: design points with no equilibrium reached (neither warm nor from as built)
    seconds: float = 0.0


class EquilibriumMap:
    """p -> stable equilibrium x(p) -> observables(x) and the exact Jacobian d obs/dp.

    Args:
        model: the structure's model (its rest fractions are set here).
        held: held DOF indices (positions fixed at the model's reference).
        params: the design variables.
        observable: x (n, 3) -> observables (k,).
        x0, p0: a known equilibrium and its design variables (default: the as-built state, every
            designed strip at lambda_N).
    """

    def __init__(
        self,
        model: BarHingeModel,
        held: np.ndarray,
        params: StripParameters,
        observable: Callable[[np.ndarray], np.ndarray],
        *,
        newton_options: NewtonOptions = NewtonOptions(),
        path_options: PathOptions = PathOptions(),
        x0: np.ndarray | None = None,
        p0: np.ndarray | None = None,
    ):
        self.model, self.params, self.observable = model, params, observable
        self.held = np.asarray(held, dtype=np.int64)
        self.free = np.setdiff1d(np.arange(model.ndof), self.held)
        self.reduced = ReducedHessian.of(model, self.free)
        self.newton_options, self.path_options = newton_options, path_options
        self.reference_f = {
            g: v.copy()
            for g, v in params.rest_fractions(np.full(params.size, params.lambda_N)).items()
        }
        self._x = (model.reference if x0 is None else np.asarray(x0, dtype=float)).reshape(-1, 3)
        self._f = self.reference_f if p0 is None else params.rest_fractions(p0)
        self._cache: DesignState | None = None
        self.stats = ForwardStats()

    def _ramp(self, f_from, f_to, x_start, path):
        def load(t):
            self.model.set_rest_fractions({g: f_from[g] + t * (f_to[g] - f_from[g]) for g in f_to})
            return self.model.reference.reshape(-1)[self.held]

        res = follow_path(
            self.model,
            x_start,
            self.held,
            load,
            newton_options=self.newton_options,
            path_options=path,
        )
        return res.states[-1].x, int(sum(res.newton_iterations))

    def equilibrium(self, p) -> tuple[np.ndarray, int, bool]:
        """Stable equilibrium positions (n, 3) at design variables p (warm-started)."""
        f_new = self.params.rest_fractions(p)
        t0 = time.perf_counter()
        restarted = False
        try:
            x, its = self._ramp(self._f, f_new, self._x, WARM_PATH)
        except ConvergenceError:
            restarted = True
            self.stats.restarts += 1
            try:
                x, its = self._ramp(
                    self.reference_f, f_new, self.model.reference, self.path_options
                )
            except ConvergenceError:
                # No equilibrium reached at p (e.g. the dome's ramp from as built meets a fold near
                # t = 0.96): keep the last equilibrium as the state to continue from.
                self.stats.failures += 1
                self.model.set_rest_fractions(self._f)
                raise
        self._x, self._f = x, f_new
        self.stats.solves += 1
        self.stats.newton_iterations += its
        self.stats.seconds += time.perf_counter() - t0
        return x, its, restarted

    def tangent_solve(self, x: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """dx on all DOFs (held ones zero) with K(x) dx = rhs on the free DOFs [mm per unit of rhs];
        ``rhs`` of shape (ndof,) or (ndof, m)."""
        _, _, coo = self.model.evaluate(x)
        kmat = self.reduced.matrix(coo)
        lu = factorize(kmat, self.reduced.diagonal(kmat), ldl=self.reduced.ldl_of(kmat))[0]
        rhs = np.asarray(rhs, dtype=float)
        dx = np.zeros(rhs.shape)
        dx[self.free] = lu.solve(np.ascontiguousarray(rhs[self.free]))
        return dx

    def directional_derivative(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """d obs along the displacement direction v at x, by central differences with the step
        OBSERVABLE_STEP / max|v| (zero for v = 0)."""
        big = float(np.max(np.abs(v)))
        if big == 0.0:
            return np.zeros_like(self.observable(x))
        h = OBSERVABLE_STEP / big
        xf = np.asarray(x, dtype=float).reshape(-1)
        hi = self.observable((xf + h * v).reshape(-1, 3))
        lo = self.observable((xf - h * v).reshape(-1, 3))
        return (hi - lo) / (2.0 * h)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """d obs/d p at the equilibrium x (the model's rest fractions must be those of x)."""
        model, params = self.model, self.params
        sens = model.rest_fraction_sensitivity(x)
        rhs = np.zeros((model.ndof, params.size))
        for g, (dofs, values) in sens.items():
            idx = params.index[g]
            for j in range(params.size):
                on = idx == j
                if np.any(on):
                    rhs[:, j] += (
                        np.bincount(
                            dofs[on].ravel(), weights=values[on].ravel(), minlength=model.ndof
                        )
                        / params.lambda_N
                    )
        dx = -self.tangent_solve(x, rhs)
        return np.column_stack(
            [self.directional_derivative(x, dx[:, j]) for j in range(params.size)]
        )

    def reseed(self, x: np.ndarray, p) -> None:
        """Continue from another known equilibrium x (n, 3) at design variables p (e.g. the one a
        ramp from the as-built state reaches, when the warm-started one is another branch)."""
        self._x = np.asarray(x, dtype=float).reshape(-1, 3).copy()
        self._f = self.params.rest_fractions(p)
        self._cache = None

    def state(self, p, jacobian: bool = True) -> DesignState:
        p = np.asarray(p, dtype=float).copy()
        c = self._cache
        if c is not None and np.array_equal(c.p, p) and (c.jacobian is not None or not jacobian):
            return c
        if c is not None and np.array_equal(c.p, p):
            x, its, restarted = c.x, 0, c.restarted
            self.model.set_rest_fractions(self.params.rest_fractions(p))
        else:
            x, its, restarted = self.equilibrium(p)
        state = DesignState(
            p,
            x,
            np.asarray(self.observable(x), dtype=float),
            self.jacobian(x) if jacobian else None,
            its,
            restarted,
        )
        self._cache = state
        return state


@dataclass
class DesignResult:
    p: np.ndarray
    state: DesignState
    target: np.ndarray
    residual: np.ndarray  # obs - target
    cost: float  # 0.5 |W (obs - target)|^2 [-]
    optimality: float
    iterations: int  # function evaluations of the optimiser
    message: str
    stats: ForwardStats = field(default_factory=ForwardStats)
    seconds: float = 0.0
    check: dict | None = None  # a verification by the caller (e.g. a forward run from as built)


class _Reached(Exception):
    """The residual is below the absolute tolerance: stop the optimiser."""


def solve_design(
    eq: EquilibriumMap,
    target,
    p0,
    lower: float,
    upper: float,
    *,
    scale: float | np.ndarray = 1.0,
    tolerance: float = 1e-10,
    absolute: float = 1e-4,
    max_evaluations: int = 60,
) -> DesignResult:
    """Least squares min_p 0.5 |(obs(p) - target)/scale|^2 with lower <= p <= upper.

    Args:
        scale: observable scale (units of the observables) that makes the residual dimensionless.
        tolerance: ftol/xtol/gtol of scipy.optimize.least_squares (relative: an unreachable target).
        absolute: stop as soon as |(obs - target)/scale| <= this (a reached target).
    """
    target = np.asarray(target, dtype=float)
    scale = np.broadcast_to(np.asarray(scale, dtype=float), target.shape)
    p0 = np.clip(np.asarray(p0, dtype=float), lower, upper)
    if not lower < upper:
        raise InputError(f"design bounds: lower {lower} must be < upper {upper}")
    t0 = time.perf_counter()

    evaluations = 0

    def fun(p):
        nonlocal evaluations
        evaluations += 1
        try:
            r = (eq.state(p, jacobian=False).observables - target) / scale
        except ConvergenceError:
            if evaluations == 1:
                raise  # no equilibrium at the start: nothing to step back to
            # A trial point without an equilibrium: a residual larger than any reachable one makes
            # the trust region reject the step and shrink (the optimiser never differentiates
            # there).
            return np.full(target.shape, FAILED_RESIDUAL)
        if np.linalg.norm(r) <= absolute:
            raise _Reached(np.array(p, dtype=float))
        return r

    def jac(p):
        return eq.state(p).jacobian / scale[:, None]

    try:
        sol = opt.least_squares(
            fun,
            p0,
            jac=jac,
            bounds=(lower, upper),
            method=METHOD,
            ftol=tolerance,
            xtol=tolerance,
            gtol=tolerance,
            max_nfev=max_evaluations,
            x_scale="jac",
        )
        p, optimality, message = sol.x, float(sol.optimality), str(sol.message)
    except _Reached as reached:
        p, optimality, message = reached.args[0], 0.0, f"target reached (|r| <= {absolute:g})"
    state = eq.state(p)
    resid = state.observables - target
    return DesignResult(
        p,
        state,
        target,
        resid,
        float(0.5 * np.sum((resid / scale) ** 2)),
        optimality,
        evaluations,
        message,
        dataclasses.replace(eq.stats),
        time.perf_counter() - t0,
    )


def objective_and_gradient(eq: EquilibriumMap, p, target, scale=1.0) -> tuple[float, np.ndarray]:
    """J = 0.5 |(obs - target)/scale|^2 and its exact gradient J^T r (for checks)."""
    target = np.asarray(target, dtype=float)
    scale = np.broadcast_to(np.asarray(scale, dtype=float), target.shape)
    st = eq.state(p)
    r = (st.observables - target) / scale
    return float(0.5 * r @ r), (st.jacobian / scale[:, None]).T @ r
