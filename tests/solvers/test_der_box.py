"""Contact with a rigid block of finite size (``model.Box``: an axis-aligned box, rounded edges).

- The compiled gap (``contact_kernels.box_gap``) equals the numpy one, its normal is the gradient of
  the gap and its Hessian the gradient of the normal (central differences, on a face, an edge and a
  corner).
- The step potential with a box (contact and friction, the rod across the box's rounded edge) has
  the gradient and Hessian of its energy's central differences (tolerances of test_der_derivatives).
- A ribbon resting on the box's top carries its weight there: the box's normal forces sum to m g (to
  the Newton tolerance and the viscous damping's residual), inside the smoothing band.
- The compiled Newton step and the Python one agree with a box (same iterations, same state).
"""

import numpy as np
import pytest

from lcefem.models.contact import ContactLaw, FrictionLaw, normal_force
from lcefem.models.errors import InputError
from lcefem.models.rod import rectangular_section
from lcefem.models.units import STANDARD_GRAVITY
from lcefem.solvers.der import contact_kernels
from lcefem.solvers.der.assembly import (
    Assembly,
    ContactSampling,
    FrictionLag,
    all_gaps,
    friction_lag,
)
from lcefem.solvers.der.integrator import Integrator, StepOptions, StepPotential
from lcefem.solvers.der.model import Box, DiscreteRod, Ground, RestShape, RodState, lumped_masses
from tests.solvers.test_der_derivatives import fd_check

BOX = Box(
    (-10.0, -10.0, -5.0), (2.5, 10.0, 0.0), 0.5
)  # top face z = 0, rounded edge along y at x = 2.5


@pytest.mark.parametrize(
    "point",
    [(0.0, 1.0, 0.3), (2.9, 1.0, 0.2), (2.7, 9.8, 0.4), (3.2, -3.0, -1.0), (1.0, 0.0, -0.1)],
)
def test_box_gap_gradient_and_hessian(point):
    p = np.array(point)
    box = BOX.array()
    n, hg = np.empty(3), np.empty((3, 3))
    gap = contact_kernels.box_gap(p, box, n, hg)
    assert gap == pytest.approx(float(BOX.gaps(p)), abs=1e-14)
    h = 1e-6
    eye = np.eye(3)
    g_fd = np.array([(BOX.gaps(p + h * e) - BOX.gaps(p - h * e)) / (2 * h) for e in eye])
    assert np.allclose(n, g_fd, atol=1e-8)
    assert np.linalg.norm(n) == pytest.approx(1.0)
    nn, hh = np.empty(3), np.empty((3, 3))
    H_fd = np.empty((3, 3))
    for i, e in enumerate(eye):
        contact_kernels.box_gap(p + h * e, box, nn, hh)
        a = nn.copy()
        contact_kernels.box_gap(p - h * e, box, nn, hh)
        H_fd[:, i] = (a - nn) / (2 * h)
    assert np.allclose(hg, H_fd, atol=1e-6)


def test_box_refuses_bad_sides():
    with pytest.raises(InputError, match="radius"):
        Box((0, 0, 0), (1, 1, 1), 0.6)
    with pytest.raises(InputError, match="radius"):
        Box((0, 0, 0), (1, 1, 1), 0.0)


def box_rod(n, friction=True):
    sec = rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    rest = RestShape.from_densities(np.full(n - 1, 1.1), [0.1, -0.2], 0.3)
    nm, ei = lumped_masses(sec, rest.edge_length)
    return DiscreteRod(
        sec,
        rest,
        nm,
        ei,
        gravity=np.array([0.0, 0.0, -STANDARD_GRAVITY]),
        damping=0.5,
        ground=Ground(height=-100.0),
        contact=ContactLaw(delta=0.2, stiffness=0.3),
        friction=FrictionLaw(mu=0.4, slip_speed=2.0) if friction else None,
        boxes=(BOX,),
    )


def test_step_potential_derivatives_with_a_box():
    rng = np.random.default_rng(4)
    n = 6
    rod = box_rod(n)
    x = np.zeros((n, 3))
    x[:, 0] = np.arange(n) * 1.0  # across the rounded edge at x = 2 ... 2.5
    x += 0.05 * rng.standard_normal((n, 3))
    x[:, 2] += 1.9
    start = RodState.from_positions(
        x,
        theta=0.3 * np.arange(n - 1) + 0.2 * rng.standard_normal(n - 1),
        first_director=np.array([0.0, 0.0, 1.0]),
    )
    start.v = rng.standard_normal((n, 3))
    start.omega = rng.standard_normal(n - 1)
    sampling = ContactSampling.of(rod)
    asm = Assembly(n)
    # the box's contact is active in the check, with points on the top face and on the rounded edge
    assert asm.contact(rod, start, sampling, 0)[0] > 0
    gs, ge = all_gaps(rod, start, sampling, BOX)
    pos = np.concatenate([p.reshape(-1, 3) for p in Assembly_points(start, sampling)])
    near = np.concatenate([gs.ravel(), ge.ravel()]) < rod.contact.delta
    assert np.any(near & (pos[:, 0] > 2.0)) and np.any(near & (pos[:, 0] < 2.0))
    lag = friction_lag(rod, start, sampling, all_points=True)
    # non-zero lagged normal forces everywhere on the box (friction on every point; none on the far
    # ground)
    b = lag.boxes[0]
    box_lag = FrictionLag(
        1e-3 * (1 + rng.random(b.stencil_normal.shape)),
        b.stencil_points,
        1e-3 * (1 + rng.random(b.end_normal.shape)),
        b.end_points,
    )
    lag = FrictionLag(
        lag.stencil_normal, lag.stencil_points, lag.end_normal, lag.end_points, (), (box_lag,)
    )
    pot = StepPotential(rod, start, 0.01, asm, sampling, lag)
    offset = 0.05 * rng.standard_normal(4 * n - 1)
    g, g_fd, H, H_fd = fd_check(pot, start, offset)
    assert np.max(np.abs(g - g_fd)) < 1e-7 * np.max(np.abs(g))
    assert np.max(np.abs(H - H_fd)) < 1e-5 * np.max(np.abs(H))


def Assembly_points(state, sampling):
    from lcefem.solvers.der.assembly import sample_points

    pos_s, _, pos_e, _ = sample_points(state, sampling)
    return pos_s, pos_e


def resting_ribbon(compiled: bool):
    """A straight flat ribbon laid on the box's top (its lower face 0.01 mm above it), ground far
    below."""
    n = 5
    sec = rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    rest = RestShape.straight(np.full(n - 1, 2.0))
    nm, ei = lumped_masses(sec, rest.edge_length)
    law = ContactLaw()
    rod = DiscreteRod(
        sec,
        rest,
        nm,
        ei,
        gravity=np.array([0.0, 0.0, -STANDARD_GRAVITY]),
        damping=20.0,
        ground=Ground(height=-100.0),
        contact=law,
        friction=FrictionLaw(),
        boxes=(BOX,),
    )
    x = np.zeros((n, 3))
    x[:, 0] = -8.0 + 2.0 * np.arange(n)
    x[:, 2] = 0.4 + 0.01
    state = RodState.from_positions(
        x, first_director=np.array([0.0, 1.0, 0.0])
    )  # width along y: flat
    return rod, Integrator(rod, state, StepOptions(compiled=compiled))


def test_ribbon_resting_on_the_box_top_carries_its_weight():
    rod, integ = resting_ribbon(compiled=True)
    for _ in range(100):  # 1 s, damping 20/s: the settling transient decays by exp(-20)
        integ.step(0.01)
    gs, ge = all_gaps(rod, integ.state, integ.sampling, BOX)
    forces = np.concatenate(
        [normal_force(gs, rod.contact).ravel(), normal_force(ge, rod.contact).ravel()]
    )
    weight = rod.node_mass.sum() * STANDARD_GRAVITY
    assert forces.sum() == pytest.approx(weight, rel=1e-3)
    assert -min(gs.min(), ge.min()) < rod.contact.delta  # resting within the smoothing band
    assert (
        np.abs(integ.state.x[:, :2] - resting_ribbon(True)[1].state.x[:, :2]).max() < 1e-3
    )  # did not slide


def test_compiled_and_python_steps_agree_with_a_box():
    states = []
    for compiled in (True, False):
        rod, integ = resting_ribbon(compiled)
        integ.state.v[:, 0] = 5.0  # sliding along the top towards the rounded edge
        for _ in range(20):
            integ.step(0.01)
        states.append(integ.state.x.copy())
    assert np.abs(states[0] - states[1]).max() < 1e-8
