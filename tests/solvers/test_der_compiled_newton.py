"""The compiled Newton loop of a time step (``compiled_newton.minimise_step``) against the Python
loop it replaces (``newton.minimise``, kept as the reference): the same iterates to round-off, step
for step, on a ribbon on the hot plate (contact, friction, moving transport source), a rod thrown at
a wall (an obstacle plane) and a clamped rod whose steps need cutting (fixed dofs); and the banded
Cholesky against LAPACK's."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.linalg import lapack

from lcefem.models.contact import ContactLaw, FrictionLaw
from lcefem.models.rod import RodSection, rectangular_section
from lcefem.models.units import STANDARD_GRAVITY
from lcefem.solvers.der.banded import (
    band_cholesky,
    band_cholesky_rows,
    band_cholesky_solve,
    band_cholesky_solve_rows,
)
from lcefem.solvers.der.integrator import Integrator, StepOptions
from lcefem.solvers.der.model import DiscreteRod, Ground, RestShape, RodState, lumped_masses, n_dofs
from lcefem.solvers.der.newton import NewtonOptions
from lcefem.solvers.der.ribbon import RibbonNumerics, RibbonSetup, RibbonSimulation

# Round-off of the two paths: the same operations, but BLAS dot products and LAPACK's rank-one
# updates may group (fuse) multiply-adds differently; a Newton solve converged to force_tol
# carries such differences on without amplifying them over a few dozen steps.
ROUND_OFF = 1e-9  # [mm, rad]


def test_band_cholesky_matches_lapack():
    rng = np.random.default_rng(3)
    n, kd = 40, 10
    dense = rng.standard_normal((n, n))
    dense = np.tril(np.triu(dense @ dense.T, -kd), kd) + 2 * kd * np.eye(
        n
    )  # banded, diagonally dominant
    ab = np.zeros((kd + 1, n))
    for r in range(kd + 1):
        ab[r, : n - r] = np.diagonal(dense, -r)
    ref, info = lapack.dpbtrf(ab, lower=1)
    assert info == 0
    mine = ab.copy()
    assert band_cholesky(mine) == 0
    np.testing.assert_allclose(mine, ref, rtol=1e-13, atol=1e-13)
    rhs = rng.standard_normal(n)
    x = rhs.copy()
    band_cholesky_solve(mine, x)
    np.testing.assert_allclose(dense @ x, rhs, rtol=1e-11, atol=1e-11)
    bad = ab.copy()
    bad[0, 7] = -1.0  # the leading minor of order 8 is not positive definite (LAPACK's info)
    assert band_cholesky(bad.copy()) == lapack.dpbtrf(bad, lower=1)[1] == 8
    # the transposed storage (the compiled Newton loop and the heat step): the same factor and solve
    # bit for bit
    rows = np.ascontiguousarray(ab.T)
    assert band_cholesky_rows(rows) == 0
    np.testing.assert_array_equal(rows.T, mine)
    y = rhs.copy()
    band_cholesky_solve_rows(rows, y)
    np.testing.assert_array_equal(y, x)
    assert band_cholesky_rows(np.ascontiguousarray(bad.T)) == 8


def _run_both(make, steps, dt):
    """(python integrator, compiled integrator) after ``steps`` steps of dt from ``make()``, with
    the Newton iterations and step cuts of every step (must agree exactly)."""
    out = []
    for compiled in (False, True):
        integ = make()
        integ.options = dataclasses.replace(integ.options, compiled=compiled)
        reports = [integ.step(dt) for _ in range(steps)]
        out.append((integ, [(r.iterations, r.cuts) for r in reports]))
    (py, rep_py), (cc, rep_cc) = out
    assert rep_cc == rep_py
    np.testing.assert_allclose(cc.state.x, py.state.x, rtol=0, atol=ROUND_OFF)
    np.testing.assert_allclose(cc.state.theta, py.state.theta, rtol=0, atol=ROUND_OFF)
    np.testing.assert_allclose(cc.state.v, py.state.v, rtol=0, atol=ROUND_OFF / dt)
    return py, cc, rep_py


@pytest.mark.parametrize("at_source", [False, True])
def test_ribbon_on_the_hot_plate_same_iterates(at_source):
    """16-node ribbon settled on the 100 C plate, 25 steps of 0.02 s heating (contact, friction,
    lagged Hessians and a moving source every step), with exact Hessians and with the elastic
    Hessian of the transport source (``StepOptions.elastic_hessian_at_source``)."""
    sim = RibbonSimulation(
        RibbonSetup(
            ground_temperature=100.0,
            numerics=RibbonNumerics(
                nodes=16, dt=0.02, settle_time=0.1, elastic_hessian_at_source=at_source
            ),
        )
    )
    state = sim.state.copy()
    state.acceleration = sim.state.acceleration

    def make():
        integ = Integrator(sim.rod, state.copy(), sim.options)
        integ.state.acceleration = state.acceleration
        return integ

    _, _, reports = _run_both(make, 25, 0.02)
    assert sum(it for it, _ in reports) > 25  # Newton did work in these steps


@pytest.mark.parametrize("angle_deg", [0.0, 30.0])
def test_rod_thrown_at_a_wall_same_iterates(angle_deg):
    """The obstacle case of test_der_obstacle: ground plus a wall plane, friction on both."""
    n, speed = 11, 100.0
    sec = rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    rest = RestShape.straight(np.full(n - 1, 1.0))
    nm, ei = lumped_masses(sec, rest.edge_length)
    a = math.radians(angle_deg)
    normal = np.array([math.sin(a), math.cos(a), 0.0])
    x = np.zeros((n, 3))
    x[:, 0] = np.arange(n) - 0.5 * (n - 1)
    x[:, 2] = 2.1  # just above the ground: its corners touch it
    state = RodState.from_positions(x, first_director=np.array([0.0, 0.0, 1.0]))
    wall = Ground(tuple(normal), float(np.min(x @ normal)) - 4.0)
    rod = DiscreteRod(
        sec,
        rest,
        nm,
        ei,
        gravity=np.array([0.0, 0.0, -STANDARD_GRAVITY]),
        ground=Ground(),
        contact=ContactLaw(),
        friction=FrictionLaw(),
        obstacles=(wall,),
    )
    state.v = np.tile(-speed * normal, (n, 1))
    _, cc, _ = _run_both(lambda: Integrator(rod, state.copy()), 60, 1e-3)
    # the paths were compared through the impact: 6 mm of free flight against a wall 4 mm away, and
    # the wall has taken the approach speed (in free flight it stays, gravity is along z)
    assert np.mean(cc.state.v @ normal) > -0.1 * speed


def test_clamped_rod_with_step_cuts_same_iterates():
    """A clamped, falling, bending rod whose 0.1 s step needs cutting (fixed dofs, failed Newton
    loops, halved steps: test_der_integrator.test_step_cutting_recovers)."""
    n = 8
    sec = RodSection(
        EA=1e4, EI1=1.0, EI2=1.0, GJ=1.0, mass_per_length=1e-6, inertia_per_length=1e-8
    )
    rest = RestShape.straight(np.full(n - 1, 10.0 / (n - 1)))
    nm, ei = lumped_masses(sec, rest.edge_length)
    x = np.zeros((n, 3))
    x[:, 0] = np.linspace(0.0, 10.0, n)
    rod = DiscreteRod(
        sec,
        rest,
        nm,
        ei,
        gravity=np.array([0.0, 0.0, -STANDARD_GRAVITY]),
        fixed=np.r_[np.ones(8, bool), np.zeros(n_dofs(n) - 8, bool)],
    )
    state = RodState.from_positions(x)
    options = StepOptions(min_dt=1e-3, newton=NewtonOptions(max_iterations=6))
    _, _, reports = _run_both(lambda: Integrator(rod, state.copy(), options), 2, 0.1)
    assert reports[0][1] >= 1
