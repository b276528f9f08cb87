"""Closed-form problems for the discrete elastic rod, each returning the DER value and reference.

Used by tests/verification/test_rod_closed_forms.py (with tolerances) and by the validation case
``rod_closed_forms`` (which records the errors and observed orders). References:

* cantilever, tip load P, small deflection: w = P L^3/(3 EI) (Timoshenko & Gere, Mechanics of
  Materials, Appendix G);
* cantilever under its own weight q: w = q L^4/(8 EI) (same table);
* cantilever, large deflection under a dead tip load (inextensible elastica,
  EI phi'' = -P cos phi, phi(0) = 0, phi'(L) = 0; Bisshopp & Drucker, Q. Appl. Math. 3, 1945),
  solved here by shooting with scipy (solve_ivp to 1e-12, brentq);
* a free rod with natural curvature kappa and twist tau relaxes to a helix of radius
  kappa/(kappa^2 + tau^2) and pitch 2 pi tau/(kappa^2 + tau^2) (Kirchhoff rod: constant
  material strains give constant curvature and torsion);
* Euler buckling of a pinned-pinned column: P_cr = pi^2 EI/L^2;
* a block sliding on an incline with Coulomb friction: sticks for tan(alpha) < mu, else slides
  with a = g (sin alpha - mu cos alpha);
* a rigid body of polar radius of gyration k rolling without slip on corners at radius R down an
  incline: a = g sin(alpha)/(1 + k^2/R^2); a straight twisted ribbon (helicoid) is such a body with
  R = sqrt(w^2 + t^2)/2 and k^2 = (w^2 + t^2)/12, so a = (3/4) g sin(alpha), provided
  mu >= tan(alpha)/4 (Meriam & Kraige, Dynamics, Sec. 6/6).

Clamped end (convention of these problems): nodes x_0 and x_1 and the angle theta_0 are fixed, with
the clamp at the middle of the first edge (x_0 at -h/2, x_1 at +h/2), so the free length is
(N - 1.5) h; the first bending node then sits h/2 from the clamp, which makes the scheme second
order (with the clamp at x_1 it is only first order).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from lcefem.models.contact import ContactLaw, FrictionLaw
from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.models.ribbon import SectionGrid, natural_strains
from lcefem.models.rod import RodSection, rectangular_section
from lcefem.models.units import STANDARD_GRAVITY
from lcefem.solvers.der.assembly import Assembly
from lcefem.solvers.der.integrator import Integrator, StepOptions
from lcefem.solvers.der.model import DiscreteRod, Ground, RestShape, RodState, lumped_masses, n_dofs
from lcefem.solvers.der.newton import NewtonOptions
from lcefem.solvers.der.static import StaticPotential, solve_static, statically_determinate_support


@dataclass
class Comparison:
    """A DER value, its closed-form reference and the rod's edge length [mm]."""

    value: float
    reference: float
    edge_length: float

    @property
    def relative_error(self) -> float:
        return abs(self.value - self.reference) / abs(self.reference)


def observed_order(edge_lengths, errors) -> float:
    """Least-squares slope of log(error) against log(edge length)."""
    return float(np.polyfit(np.log(edge_lengths), np.log(errors), 1)[0])


# A generic elastic rod for the beam problems (units mm, N, MPa): steel-like wire, 100 mm long.
LENGTH = 100.0
EI = 1000.0  # N mm^2


def _beam_section(mass_per_length: float = 0.0) -> RodSection:
    # EA large: the closed forms are for inextensible beams (axial strain ~1e-8 here).
    return RodSection(
        EA=1e8, EI1=EI, EI2=EI, GJ=EI / 1.3, mass_per_length=mass_per_length, inertia_per_length=0.0
    )


def _cantilever(n_nodes: int, section: RodSection, gravity=(0.0, 0.0, 0.0), tip_force=None):
    h = LENGTH / (n_nodes - 1.5)
    x = np.zeros((n_nodes, 3))
    x[:, 0] = np.arange(n_nodes) * h - 0.5 * h
    rest = RestShape.straight(np.full(n_nodes - 1, h))
    nm, ei = lumped_masses(section, rest.edge_length)
    fixed = np.zeros(n_dofs(n_nodes), bool)
    fixed[0:8] = True  # x_0, theta_0, x_1
    f = np.zeros(n_dofs(n_nodes))
    if tip_force is not None:
        f[4 * (n_nodes - 1) : 4 * (n_nodes - 1) + 3] = tip_force
    rod = DiscreteRod(
        section, rest, nm, ei, gravity=np.asarray(gravity, float), fixed=fixed, external_force=f
    )
    return rod, RodState.from_positions(x, first_director=np.array([0.0, 1.0, 0.0])), h


def cantilever_tip_load(n_nodes: int, load: float = 1e-4) -> Comparison:
    """Tip deflection [mm] under a small transverse tip load P [N] (w/L ~ 3e-5)."""
    rod, st, h = _cantilever(n_nodes, _beam_section(), tip_force=(0.0, 0.0, -load))
    w = -solve_static(rod, st).state.x[-1, 2]
    return Comparison(w, load * LENGTH**3 / (3.0 * EI), h)


def cantilever_self_weight(n_nodes: int, q: float = 1e-6) -> Comparison:
    """Tip deflection [mm] under a uniform weight q [N/mm] (a mass per length q/g)."""
    rod, st, h = _cantilever(
        n_nodes, _beam_section(q / STANDARD_GRAVITY), gravity=(0.0, 0.0, -STANDARD_GRAVITY)
    )
    # The ghost half edge behind the clamp carries no load (its mass lands on fixed nodes).
    w = -solve_static(rod, st).state.x[-1, 2]
    return Comparison(w, q * LENGTH**4 / (8.0 * EI), h)


def elastica_tip_deflection(load_parameter: float) -> tuple[float, float]:
    """Tip (horizontal, vertical) displacement ratios (u/L, w/L) of the inextensible cantilever
    under a dead tip load with P L^2/EI = ``load_parameter``, by shooting on EI phi'' = -P
    cos(phi)."""
    lam = load_parameter

    def rhs(s, y):  # y = (phi, phi', x, z) in units of L
        return [y[1], -lam * math.cos(y[0]), math.cos(y[0]), math.sin(y[0])]

    def end_moment(k0):
        sol = solve_ivp(rhs, (0.0, 1.0), [0.0, k0, 0.0, 0.0], rtol=1e-12, atol=1e-14)
        return sol.y[1, -1]

    k0 = brentq(end_moment, 0.0, lam, xtol=1e-14)
    sol = solve_ivp(rhs, (0.0, 1.0), [0.0, k0, 0.0, 0.0], rtol=1e-12, atol=1e-14)
    return 1.0 - sol.y[2, -1], sol.y[3, -1]


def cantilever_large_deflection(n_nodes: int, load_parameter: float = 3.0) -> Comparison:
    """Tip deflection ratio w/L of the elastica with P L^2/EI = ``load_parameter`` (w/L = 0.603 for
    3)."""
    load = load_parameter * EI / LENGTH**2
    rod, st, h = _cantilever(n_nodes, _beam_section(), tip_force=(0.0, 0.0, -load))
    res = solve_static(rod, st, increments=6)
    w = -res.state.x[-1, 2] / LENGTH
    return Comparison(w, elastica_tip_deflection(load_parameter)[1], h)


def helix_parameters(x: np.ndarray) -> tuple[float, float]:
    """Radius and pitch [mm] of the helix through the nodes x (N, 3): axis = direction normal to
    every second difference (they point at the axis), radius from an algebraic circle fit of the
    nodes projected on the plane normal to it, pitch from the advance along it per turn."""
    d2 = x[2:] - 2.0 * x[1:-1] + x[:-2]
    axis = np.linalg.eigh(d2.T @ d2)[1][:, 0]
    basis = np.linalg.svd(np.eye(3) - np.outer(axis, axis))[0][:, :2]
    p = x @ basis
    A = np.column_stack([2 * p, np.ones(len(p))])
    b = (p**2).sum(1)
    cx, cy, c = np.linalg.lstsq(A, b, rcond=None)[0]
    radius = math.sqrt(c + cx**2 + cy**2)
    ang = np.unwrap(np.arctan2(p[:, 1] - cy, p[:, 0] - cx))
    turns = abs(ang[-1] - ang[0]) / (2.0 * math.pi)
    pitch = abs((x[-1] - x[0]) @ axis) / turns
    return radius, pitch


def helix_relaxation(n_nodes: int, kappa: float = 0.1, tau: float = 0.05, length: float = 100.0):
    """A free ribbon-like rod (EI1 != EI2) with natural curvature kappa towards m1 and twist tau
    [1/mm] relaxes from straight to a helix. Returns (radius, pitch) Comparisons."""
    sec = rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    h = length / (n_nodes - 1)
    x = np.zeros((n_nodes, 3))
    x[:, 0] = np.arange(n_nodes) * h
    straight = RestShape.straight(np.full(n_nodes - 1, h))
    rest = RestShape.from_densities(straight.edge_length, [kappa, 0.0], tau)
    nm, ei = lumped_masses(sec, straight.edge_length)
    rod = DiscreteRod(sec, rest, nm, ei, fixed=statically_determinate_support(n_nodes))
    st = RodState.from_positions(x, first_director=np.array([0.0, 1.0, 0.0]))
    res = solve_static(rod, st, increments=12, rest_from=straight)
    r, p = helix_parameters(res.state.x)
    k2 = kappa**2 + tau**2
    return Comparison(r, kappa / k2, h), Comparison(p, 2.0 * math.pi * tau / k2, h)


def euler_buckling(n_nodes: int) -> Comparison:
    """Critical axial load [N] of a pinned-pinned column: the load at which the smallest eigenvalue
    of the constrained Hessian at the (straight, compressed) equilibrium crosses zero."""
    sec = _beam_section()
    h = LENGTH / (n_nodes - 1)
    x = np.zeros((n_nodes, 3))
    x[:, 0] = np.arange(n_nodes) * h
    rest = RestShape.straight(np.full(n_nodes - 1, h))
    nm, ei = lumped_masses(sec, rest.edge_length)
    fixed = np.zeros(n_dofs(n_nodes), bool)
    fixed[0:4] = True  # pin at node 0 and the twist angle of the first edge
    last = 4 * (n_nodes - 1)
    fixed[last + 1 : last + 3] = True  # the other pin slides along x only
    asm = Assembly(n_nodes)
    free = ~fixed
    st0 = RodState.from_positions(x, first_director=np.array([0.0, 1.0, 0.0]))

    def smallest_eigenvalue(load):
        f = np.zeros(n_dofs(n_nodes))
        f[last] = -load
        rod = DiscreteRod(sec, rest, nm, ei, fixed=fixed, external_force=f)
        st = solve_static(rod, st0).state
        d = StaticPotential(rod, asm, f)(st, True)
        nd = n_dofs(n_nodes)
        H = np.zeros((nd, nd))
        for r in range(d.band.shape[0]):
            idx = np.arange(nd - r)
            H[idx + r, idx] = d.band[r, : nd - r]
            H[idx, idx + r] = d.band[r, : nd - r]
        return np.linalg.eigvalsh(H[np.ix_(free, free)])[0]

    p_euler = math.pi**2 * EI / LENGTH**2
    p_cr = brentq(smallest_eigenvalue, 0.5 * p_euler, 1.5 * p_euler, xtol=1e-12 * p_euler)
    return Comparison(p_cr, p_euler, h)


def _flat_ribbon_on_ground(
    n_nodes: int,
    length: float,
    youngs: float,
    twist: float = 0.0,
    width: float = 4.0,
    thickness: float = 0.8,
    axis: int = 0,
    mu: float = 0.5,
    slip_speed: float = 0.2,
):
    """A stiff ribbon (E = ``youngs``) lying on the plane z = 0 along ``axis`` (0: x, 1: y), face
    down when untwisted; returns (rod, state)."""
    sec = rectangular_section(width, thickness, youngs, youngs / 3.0, 1.15e-9)
    h = length / (n_nodes - 1)
    s = np.arange(n_nodes) * h
    x = np.zeros((n_nodes, 3))
    x[:, axis] = s
    tangent = np.eye(3)[axis]
    # m1 (width) horizontal and normal to the axis: the ribbon lies on its face (twist 0).
    first = np.cross(np.array([0.0, 0.0, 1.0]), tangent)
    theta = twist * (s[:-1] + 0.5 * h)
    st = RodState.from_positions(x, theta, first_director=first)
    geo = st.geometry()
    lowest = (
        0.5 * (x[:-1, 2] + x[1:, 2])
        - 0.5 * width * np.abs(geo.m1[:, 2])
        - 0.5 * thickness * np.abs(geo.m2[:, 2])
    )
    x[:, 2] -= lowest.min()
    st = RodState.from_positions(x, theta, first_director=first)
    rest = RestShape.from_densities(np.full(n_nodes - 1, h), [0.0, 0.0], twist)
    nm, ei = lumped_masses(sec, rest.edge_length)
    rod = DiscreteRod(
        sec,
        rest,
        nm,
        ei,
        gravity=np.array([0.0, 0.0, -STANDARD_GRAVITY]),
        ground=Ground(),
        contact=ContactLaw(delta=0.02, stiffness=5.0),
        friction=FrictionLaw(mu=mu, slip_speed=slip_speed),
    )
    return rod, st


def _settle(rod: DiscreteRod, st: RodState, dt: float, duration: float) -> RodState:
    integ = Integrator(
        rod.replace(damping=50.0), st, StepOptions(newton=NewtonOptions(max_iterations=60))
    )
    for _ in range(int(round(duration / dt))):
        integ.step(dt)
    out = integ.state
    out.v[:] = 0.0
    out.omega[:] = 0.0
    return out


def _incline_acceleration(
    rod, st, dt: float, duration: float, angle: float, axis: int
) -> tuple[float, float]:
    """Tilt gravity by ``angle`` [rad] along ``axis`` (0: x, 1: y), integrate for ``duration`` [s]
    and return (mean acceleration along ``axis`` over the second half [mm/s^2], final mean velocity
    [mm/s])."""
    tilt = np.zeros(3)
    tilt[axis] = math.sin(angle)
    tilt[2] = -math.cos(angle)
    rod = rod.replace(gravity=STANDARD_GRAVITY * tilt)
    integ = Integrator(rod, st, StepOptions(newton=NewtonOptions(max_iterations=60)))
    steps = int(round(duration / dt))
    vel = []
    for _ in range(steps):
        integ.step(dt)
        vel.append(float(integ.state.v[:, axis].mean()))
    vel = np.array(vel)
    half = steps // 2
    return (vel[-1] - vel[half - 1]) / (dt * (steps - half)), float(vel[-1])


def incline_sliding(
    angle_deg: float, mu: float, duration: float = 0.2, dt: float = 0.004, n_nodes: int = 6
):
    """A stiff flat ribbon on a plane inclined by ``angle_deg`` (gravity tilted) with friction mu.

    Returns (mean acceleration along the slope over the second half [mm/s^2], reference
    g (sin - mu cos) or 0 when it sticks, final speed [mm/s])."""
    rod, st = _flat_ribbon_on_ground(n_nodes, 20.0, 50.0, mu=mu)
    st = _settle(rod, st, dt, 0.05)
    a = math.radians(angle_deg)
    acc, v_end = _incline_acceleration(rod, st, dt, duration, a, axis=0)
    ref = STANDARD_GRAVITY * (math.sin(a) - mu * math.cos(a)) if math.tan(a) > mu else 0.0
    return acc, ref, v_end


def incline_rolling(
    n_nodes: int, angle_deg: float = 5.0, mu: float = 1.0, duration: float = 0.1, dt: float = 0.002
) -> Comparison:
    """A stiff twisted ribbon (helicoid, 3 turns over 30 mm) rolling down an incline across its
    axis.

    Value: acceleration of the centroid across the axis over the second half [mm/s^2]; reference
    (3/4) g sin(alpha) (rolling without slip on the corner helices, k^2/R^2 = 1/3)."""
    turns_per_mm = 0.1
    rod, st = _flat_ribbon_on_ground(
        n_nodes, 30.0, 100.0, twist=2.0 * math.pi * turns_per_mm, mu=mu
    )
    rod = rod.replace(contact_samples=4)
    st = _settle(rod, st, dt, 0.02)
    a = math.radians(angle_deg)
    acc, _ = _incline_acceleration(rod, st, dt, duration, a, axis=1)
    return Comparison(acc, 0.75 * STANDARD_GRAVITY * math.sin(a), 30.0 / (n_nodes - 1))


def one_face_bending(
    cells_thickness: int,
    quadrature: int,
    faces=(60.0, 25.0),
    width: float = 4.0,
    thickness: float = 0.8,
    cells_width: int = 6,
) -> Comparison:
    """Natural curvature kappa_bar_2 [1/mm] of a strip with a linear temperature profile through the
    thickness (faces at T_plus, T_minus [C]) from the section grid of :mod:`lcefem.models.ribbon`,
    against the beam closed form kappa_2 = -(12/t^3) int_{-t/2}^{t/2} (a(T(y)) - 1) y dy (scipy quad
    to 1e-14). ``edge_length`` holds the cell height t/n_t [mm]. A free straight strip takes exactly
    this curvature in DER, and the 3D FE strip agrees with the closed form to 0.2 % (case
    ribbon_fe_vs_der, (a)); quadrature 1 is the one-sample-per-cell rule used before issue 17.
    """
    tr = NematicTransition()
    T_plus, T_minus = faces

    def profile(y):
        return T_minus + (T_plus - T_minus) * (y / thickness + 0.5)

    moment = quad(
        lambda y: (float(contraction_ratio(profile(y), tr)) - 1.0) * y,
        -0.5 * thickness,
        0.5 * thickness,
        epsabs=1e-14,
        epsrel=1e-12,
    )[0]
    reference = -12.0 * moment / thickness**3
    grid = SectionGrid(width, thickness, cells_width, cells_thickness, quadrature)
    value = float(natural_strains(grid.from_faces(T_plus, T_minus), grid, tr).curvature[1])
    return Comparison(value, reference, thickness / cells_thickness)
