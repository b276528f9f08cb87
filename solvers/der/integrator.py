"""Implicit time stepping of a discrete rod (seed 000, 'DER Differential Equation').

Implicit Euler: the state at t + h minimises the incremental potential

    Phi(q) = 1/(2h^2) |q - q_n - h qdot_n|_M^2 + c/(2h) |q - q_n|_M^2 + E_elastic(q) - f.q
             + k E_contact(q) + D_friction(q)

(M the lumped mass, c the mass-proportional damping rate, f gravity plus external forces, D the
friction potential of lagged normal forces); its stationarity is the seed's
m/dt [(q_(n+1) - q_n)/dt - qdot_n] + dE/dq - f_ext = 0 with damping, contact and friction in f_ext.
Implicit midpoint is the same minimisation over h = dt/2 for the midpoint state y, followed by
q_(n+1) = 2y - q_n and qdot_(n+1) = 2 (y - q_n)/h - qdot_n (it keeps the energy of undamped
motion; implicit Euler damps it).

A step whose Newton loop fails is retried as two half steps from the last converged state, down
to ``min_dt``; below it ``ConvergenceError`` is raised after ``on_failure(state)`` has saved the
last converged state.

Adaptive steps (:class:`StepControl`, implicit Euler): the local error of a step of length h is
estimated by the distance between the implicit Euler position q_n + h qdot_(n+1) and the
trapezoidal (second-order) one q_n + h (qdot_n + qdot_(n+1))/2 of the same step,

    err = h/2 max( |v_(n+1) - v_n|_node , r |omega_(n+1) - omega_n|_edge )   [mm]

(r: a length that turns the edge spin into a corner displacement), i.e. h^2/2 |q''|, the leading
term of Euler's local error (Hairer, Norsett & Wanner, Solving ODEs I, Sec. II.4, embedded pairs).
A step with err > tolerance is rejected and retried; the next step is
h_new = h min(max_growth, max(max_shrink, safety sqrt(tolerance/err))), within [dt_min, dt_max].
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.der import compiled_newton
from lcefem.solvers.der.assembly import (
    BANDWIDTH,
    Assembly,
    ContactSampling,
    Derivatives,
    FrictionLag,
    friction_lag,
)
from lcefem.solvers.der.model import DiscreteRod, Geometry, RodState, node_dofs, twist_dofs
from lcefem.solvers.der.newton import NewtonOptions, NewtonResult, minimise

METHODS = ("euler", "midpoint")


@dataclass(frozen=True)
class StepOptions:
    method: str = "euler"
    min_dt: float = 1e-6  # [s]
    friction_iterations: int = 1  # >1: re-solve with the normal force of the new state
    predict: bool = True  # start Newton from the inertial prediction q_n + h qdot_n
    # ... plus h^2 a_n, a_n = (qdot_n - qdot_(n-1))/dt_(n-1) the last step's mean acceleration (when
    # known): a second-order guess of q_(n+1) for smooth motion (rolling), ~0.5 Newton iterations
    # fewer. Not after an impulsive step (max |h a_n| > max |qdot_n|, e.g. landing on the ground),
    # and a step whose Newton loop fails from it is retried from the inertial guess before it is
    # halved.
    extrapolate: bool = False
    newton: NewtonOptions = field(default_factory=NewtonOptions)
    # The Newton loop in one compiled call (compiled_newton.minimise_step: the same algorithm as
    # newton.minimise, iterates equal to round-off); False: the Python loop, kept as the reference.
    compiled: bool = True
    # True: a Newton iterate moved from a transport source takes the source's elastic Hessian (its
    # gradient, the inertia, contact and friction terms stay its own): a modified Newton, because
    # within a step the shape moves by ~0.01 mm while the contact and friction Hessians change with
    # every iterate; it saves ~35 % of a Hessian evaluation (100-node ribbon: 587 -> ~370 us, issue
    # 17). Newton still stops within force_tol of a minimiser of the same step potential (converging
    # linearly near it); the 60 s ribbon's paths agree to 1e-8 mm until the rolling onset, which
    # parts them, and its 30-60 s mean speed came out 1 % lower in eight runs (README, DER, fifth
    # pass), hence off by default.
    elastic_hessian_at_source: bool = False

    def __post_init__(self):
        if self.method not in METHODS:
            raise InputError(f"method = {self.method!r}: allowed {', '.join(METHODS)}")
        if self.min_dt <= 0:
            raise InputError(f"min_dt = {self.min_dt} s: must be > 0 s")
        if self.friction_iterations < 1:
            raise InputError(f"friction_iterations = {self.friction_iterations}: must be >= 1")


@dataclass
class StepReport:
    dt: float
    iterations: int
    cuts: int


@dataclass(frozen=True)
class StepControl:
    """Step-size controller of implicit Euler from its local error estimate (module docstring)."""

    tolerance: float  # [mm] largest accepted local position error of one step
    dt_min: float  # [s]
    dt_max: float  # [s]
    length: float = 1.0  # [mm] converts edge spin rates [rad/s] to corner speeds [mm/s]
    safety: float = 0.9  # [-] the usual margin of error-per-step controllers (Hairer et al. II.4)
    max_growth: float = 2.0  # [-]
    max_shrink: float = 0.2  # [-]

    def __post_init__(self):
        for name in ("tolerance", "dt_min", "dt_max", "length"):
            if not getattr(self, name) > 0:
                raise InputError(f"{name} = {getattr(self, name)}: must be > 0")
        if self.dt_min > self.dt_max:
            raise InputError(f"dt_min = {self.dt_min} s: must be <= dt_max = {self.dt_max} s")

    def error(self, start: RodState, new: RodState) -> float:
        """Local error estimate err [mm] of the implicit Euler step start -> new (module
        docstring)."""
        h = new.time - start.time
        dv = float(np.max(np.abs(new.v - start.v)))
        dw = float(np.max(np.abs(new.omega - start.omega))) if len(new.omega) else 0.0
        return 0.5 * h * max(dv, self.length * dw)

    def next_dt(self, dt: float, error: float) -> float:
        """Step [s] after (or instead of, when error > tolerance) a step dt with the given error."""
        factor = self.max_growth if error <= 0 else self.safety * (self.tolerance / error) ** 0.5
        factor = min(self.max_growth, max(self.max_shrink, factor))
        return min(self.dt_max, max(self.dt_min, dt * factor))


def generalised_load(rod: DiscreteRod) -> np.ndarray:
    """Gravity plus external forces as a generalised force (4N-1,) [N, N mm]."""
    f = rod.external_force.copy()
    n = rod.n_nodes
    f[node_dofs(n)] += rod.node_mass[:, None] * rod.gravity[None, :]
    return f


class StepPotential:
    """The incremental potential Phi of one implicit step of length h from ``start``."""

    def __init__(
        self,
        rod: DiscreteRod,
        start: RodState,
        h: float,
        assembly: Assembly,
        sampling: ContactSampling,
        lag: FrictionLag | None,
        elastic_hessian_at_source: bool = False,
    ):
        self.rod, self.h, self.asm, self.lag, self.sampling = rod, h, assembly, lag, sampling
        self.source_elastic = elastic_hessian_at_source  # StepOptions.elastic_hessian_at_source
        self._elastic_band = None  # the elastic Hessian of the last source evaluated (own frames)
        self.mass = rod.mass_vector()
        self.q_n = start.q()
        self.q_star = self.q_n + h * start.qdot()
        self.load = generalised_load(rod)
        self.diag = self.mass * (1.0 / h**2 + rod.damping / h)

    def __call__(self, state: RodState, hessian: bool) -> Derivatives:
        return self.evaluate(state, 2 if hessian else 0)

    def gradient(self, state: RodState) -> Derivatives:
        """Energy and gradient without the Hessian (Newton's lagged-Hessian steps)."""
        return self.evaluate(state, 1)

    def evaluate(self, state: RodState, order: int) -> Derivatives:
        """Energy (order 0), with the gradient (1), with the lower-banded Hessian (2)."""
        h = self.h
        q = state.q()
        dq = q - self.q_star
        dn = q - self.q_n
        energy = (
            0.5 / h**2 * float(self.mass @ dq**2)
            + 0.5 * self.rod.damping / h * float(self.mass @ dn**2)
            - float(self.load @ q)
        )
        out = None
        if order >= 1:  # the kernels add their derivatives into the inertial ones
            grad = self.mass * (dq / h**2 + self.rod.damping * dn / h) - self.load
            band = None
            if order >= 2:
                band = np.zeros((BANDWIDTH + 1, len(q)))
                band[0] = self.diag
            out = (grad, band)
        if order >= 2 and self.source_elastic:
            if (
                state.source_tangents is None
            ):  # a source: its elastic Hessian, kept for the iterates moved from it
                self._elastic_band = np.zeros_like(band)
                energy += self.asm.elastic(self.rod, state, 2, out=(grad, self._elastic_band))[0]
            else:
                energy += self.asm.elastic(self.rod, state, 1, out=(grad, None))[0]
            band += self._elastic_band
        else:
            energy += self.asm.elastic(self.rod, state, order, out=out)[0]
        energy += self.asm.contact(
            self.rod, state, self.sampling, order, friction=self.lag, step=h, out=out
        )[0]
        if order == 0:
            return Derivatives(energy, None, None)
        return Derivatives(energy, grad, band)

    def minimise(self, start: RodState, options: NewtonOptions) -> NewtonResult:
        """``newton.minimise(start, rod.fixed, self, options)`` in one compiled call
        (:func:`compiled_newton.minimise_step`)."""
        rod, rest, sec = self.rod, self.rod.rest, self.rod.section
        inertia = (
            self.mass,
            self.q_n,
            self.q_star,
            self.load,
            self.diag,
            float(self.h),
            float(rod.damping),
        )
        rest_arrays = (
            np.ascontiguousarray(rest.edge_length, float),
            np.ascontiguousarray(rest.curvature, float),
            np.ascontiguousarray(rest.twist, float),
            np.ascontiguousarray(rest.voronoi_length, float),
            float(sec.EA),
            float(sec.EI1),
            float(sec.EI2),
            float(sec.GJ),
        )
        n_edges = rod.n_nodes - 1
        sampling = self.sampling._cached(
            ("compiled_newton", n_edges),
            lambda: self.sampling.kernel_arrays()
            + (
                self.sampling.end_edges(n_edges),
                self.sampling.end_sigma_rows(n_edges),
                self.sampling.end_offsets_array(),
            ),
        )
        c = np.ascontiguousarray  # one kernel signature whatever the caller's array layouts
        result = compiled_newton.minimise_step(
            c(start.x, float),
            c(start.theta, float),
            c(start.a1, float),
            c(start.ref_twist, float),
            c(rod.fixed, bool),
            inertia,
            rest_arrays,
            sampling,
            self._contact_arrays(),
            _options_tuple(options),
            bool(self.source_elastic),
        )
        (
            code,
            iterations,
            residual,
            (x, theta, a1, ref, e, length, t, m1, m2, twist),
            own,
            source_t,
        ) = result
        state = RodState(
            x,
            theta,
            start.v.copy(),
            start.omega.copy(),
            a1,
            ref,
            start.time,
            None if own else source_t,
        )
        state.__dict__["_geometry"] = Geometry(e, length, t, m1, m2, twist)
        return NewtonResult(
            state,
            code in compiled_newton.CONVERGED_CODES,
            iterations,
            float(residual),
            compiled_newton.REASONS[code],
        )

    def _contact_arrays(self) -> tuple:
        """The planes, the contact law and the lagged friction data of every plane, stacked for
        :func:`compiled_newton.minimise_step` (the arguments ``Assembly.contact`` passes per
        plane)."""
        rod = self.rod
        planes = rod.contact_planes()
        normals = np.array([p.unit_normal() for p in planes], float).reshape(len(planes), 3)
        heights = np.array([p.height for p in planes], float)
        law = rod.contact
        fric = self.lag is not None and rod.friction is not None and self.h > 0
        interpolated = self.sampling.interpolated
        no_n, no_p = np.zeros((1, 1)), np.zeros((1, 1, 3))
        boxes = np.array([b.array() for b in rod.boxes], float).reshape(len(rod.boxes), 8)
        lags = self.lag.all_lags() if fric else (None,) * (len(planes) + len(boxes))
        if fric and len(lags) != len(planes) + len(boxes):
            raise ValueError(
                f"friction lag has {len(lags) - 1} obstacles, the rod {len(rod.obstacles)} walls "
                "and "
                f"{len(rod.boxes)} boxes"
            )
        stacks = ([], [], [], [])
        for lag in lags:
            arrays = (
                (lag.stencil_normal, lag.stencil_points) if fric and interpolated else (no_n, no_p)
            ) + ((lag.end_normal, lag.end_points) if fric else (no_n, no_p))
            for stack, a in zip(stacks, arrays):
                stack.append(a)
        lag_ns, lag_ps, lag_ne, lag_pe = (
            _stacked(s) if s else np.zeros((0,) + z.shape)
            for s, z in zip(stacks, (no_n, no_p, no_n, no_p))
        )
        mu, K2 = (float(rod.friction.mu), float(rod.friction.K2)) if fric else (0.0, 1.0)
        if law is None:
            constants = (0.0, 1.0, 1.0, 0.0)
        else:
            constants = (
                float(law.clearance),
                float(law.delta),
                float(law.K1),
                float(law.stiffness),
            )
        return (
            (normals, heights, boxes)
            + constants
            + (bool(fric), lag_ns, lag_ps, lag_ne, lag_pe, mu, K2)
        )


def _stacked(arrays: list) -> np.ndarray:
    """np.stack(arrays) as a contiguous float array; one array (the ground alone, the ribbon's case)
    as a view with a leading axis (the same values, without np.stack's copy and ~8 us per call;
    the kernels only read it, issue 17)."""
    if len(arrays) == 1:
        return np.ascontiguousarray(arrays[0], float)[None]
    return np.ascontiguousarray(np.stack(arrays), float)


@functools.lru_cache(maxsize=16)
def _options_tuple(o: NewtonOptions) -> tuple:
    """``NewtonOptions`` in the order of :func:`compiled_newton.minimise_step`."""
    return (
        int(o.max_iterations),
        float(o.force_tol),
        float(o.step_tol),
        float(o.armijo),
        float(o.min_step),
        int(o.max_shift_tries),
        int(o.watchdog),
        float(np.cos(o.resource_angle)),
        float(o.max_rotation),
        float(o.max_displacement),
        float(o.unchecked_step),
        float(o.lag_residual),
        float(o.lag_contraction),
    )


class Integrator:
    """Steps a rod in time; ``rod.rest`` may be replaced between calls (actuation)."""

    def __init__(
        self,
        rod: DiscreteRod,
        state: RodState,
        options: StepOptions = StepOptions(),
        on_failure: Callable[[RodState], None] | None = None,
    ):
        self.rod = rod
        self.state = state
        self.options = options
        self.on_failure = on_failure
        self.assembly = Assembly(rod.n_nodes)
        self.sampling = ContactSampling.of(rod)
        self.total_iterations = 0
        self.total_cuts = 0

    def _attempt(
        self, start: RodState, dt: float, extrapolate: bool
    ) -> tuple[RodState | None, NewtonResult]:
        rod = self.rod
        midpoint = self.options.method == "midpoint"
        h = 0.5 * dt if midpoint else dt
        use_friction = rod.has_contact and rod.friction is not None
        many = self.options.friction_iterations > 1
        lag = friction_lag(rod, start, self.sampling, all_points=many) if use_friction else None
        iterations = 0
        guess = start
        qdot_n = start.qdot()
        if self.options.predict:
            qdot = qdot_n
            dq = h * qdot
            acc = start.acceleration if extrapolate else None
            if acc is not None and h * np.max(np.abs(acc)) <= np.max(np.abs(qdot)):
                dq += h * h * acc
            guess = start.moved(dq)
        result = None
        passes = self.options.friction_iterations if use_friction else 1
        for k in range(passes):
            potential = StepPotential(
                rod,
                start,
                h,
                self.assembly,
                self.sampling,
                lag,
                self.options.elastic_hessian_at_source,
            )
            if self.options.compiled:
                result = potential.minimise(guess, self.options.newton)
            else:
                result = minimise(guess, rod.fixed, potential, self.options.newton)
            iterations += result.iterations
            if not result.converged:
                result.iterations = iterations
                return None, result
            guess = result.state
            if use_friction and k + 1 < passes:  # normal forces of the new state for the next pass
                new = friction_lag(rod, guess, self.sampling)
                lag = lag.with_normals_of(new)
        result.iterations = iterations
        y = result.state
        q_n = potential.q_n  # start.q()
        if midpoint:
            new = y.moved(y.q() - q_n)
            qdot = 2.0 * (y.q() - q_n) / h - qdot_n
        else:
            new = y
            qdot = (y.q() - q_n) / h
        n = rod.n_nodes
        new.v = qdot[node_dofs(n)]
        new.omega = qdot[twist_dofs(n)]
        new.time = start.time + dt
        new.acceleration = (qdot - qdot_n) / dt  # for the next step's extrapolated guess
        return new, result

    def _advance(self, start: RodState, dt: float, depth: int) -> tuple[RodState, int, int]:
        extrapolate = self.options.extrapolate and start.acceleration is not None
        new, result = self._attempt(start, dt, extrapolate)
        if new is None and extrapolate:  # the extrapolated guess may be the cause: the inertial one
            tried = result.iterations
            new, result = self._attempt(start, dt, False)
            result.iterations += tried
        if new is not None:
            return new, result.iterations, 0
        half = 0.5 * dt
        if half < self.options.min_dt:
            if self.on_failure is not None:
                self.on_failure(start)
            raise ConvergenceError(
                f"t = {start.time:.6g} s",
                f"Newton failed ({result.reason}, residual {result.residual:.3g}) with "
                f"dt = {dt:.3g} s; smallest allowed step {self.options.min_dt:.3g} s",
            )
        mid, it1, c1 = self._advance(start, half, depth + 1)
        end, it2, c2 = self._advance(mid, half, depth + 1)
        return end, result.iterations + it1 + it2, 1 + c1 + c2

    def trial(self, dt: float) -> tuple[RodState, StepReport]:
        """The state dt [s] later (in sub-steps if Newton needs them), not yet accepted; its Newton
        iterations count in ``total_iterations`` whether or not it is accepted."""
        if not dt > 0:
            raise InputError(f"dt = {dt} s: must be > 0 s")
        new, its, cuts = self._advance(self.state, dt, 0)
        self.total_iterations += its
        self.total_cuts += cuts
        return new, StepReport(dt, its, cuts)

    def step(self, dt: float) -> StepReport:
        """Advance by dt [s] (in sub-steps if Newton needs them)."""
        self.state, report = self.trial(dt)
        return report
