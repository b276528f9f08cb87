"""Finite-difference checks of the assembled DER potentials (elastic, contact, friction, inertia).

The step potential is one fixed function of the dofs within a Newton solve (reference frames
transported from the solve's start), so its assembled gradient and banded Hessian must equal the
central differences of its energy, also away from the transport source. Tolerances: gradient to
1e-7 of its largest entry (central differences with h = 1e-6, round-off ~1e-10); Hessian to 1e-5 of
its largest entry (second differences with h = 1e-4, truncation O(h^2) times fourth derivatives).
"""

import numpy as np
import pytest

from lcefem.models.contact import ContactLaw, FrictionLaw
from lcefem.models.rod import rectangular_section
from lcefem.solvers.der.assembly import Assembly, ContactSampling, FrictionLag, friction_lag
from lcefem.solvers.der.integrator import StepPotential
from lcefem.solvers.der.model import DiscreteRod, Ground, RestShape, RodState, lumped_masses
from lcefem.solvers.der.static import StaticPotential


def dense(band):
    n = band.shape[1]
    H = np.zeros((n, n))
    for r in range(band.shape[0]):
        idx = np.arange(n - r)
        H[idx + r, idx] = band[r, : n - r]
        H[idx, idx + r] = band[r, : n - r]
    return H


def fd_check(potential, source, offset):
    """Compare analytic derivatives at source.moved(offset) with differences of the energy."""
    state = source.moved(offset)
    d = potential(state, True)
    H = dense(d.band)
    nd = len(offset)
    eye = np.eye(nd)

    def energy(dq):
        return potential(source.moved(offset + dq), False).energy

    h = 1e-6
    g_fd = np.array([(energy(h * eye[i]) - energy(-h * eye[i])) / (2 * h) for i in range(nd)])
    h = 1e-4
    H_fd = np.empty((nd, nd))
    for i in range(nd):
        for j in range(i, nd):
            H_fd[i, j] = H_fd[j, i] = (
                energy(h * (eye[i] + eye[j]))
                - energy(h * (eye[i] - eye[j]))
                - energy(h * (eye[j] - eye[i]))
                + energy(-h * (eye[i] + eye[j]))
            ) / (4 * h * h)
    return d.grad, g_fd, H, H_fd


def ribbon_rod(n, samples, friction=True, rng=None):
    sec = rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    rest = RestShape.from_densities(np.full(n - 1, 1.1), [0.1, -0.2], 0.3)
    nm, ei = lumped_masses(sec, rest.edge_length)
    return DiscreteRod(
        sec,
        rest,
        nm,
        ei,
        gravity=np.array([0.0, 0.0, -9806.65]),
        damping=0.5,
        ground=Ground(),
        contact=ContactLaw(delta=0.2, stiffness=0.3),
        friction=FrictionLaw(mu=0.4, slip_speed=2.0) if friction else None,
        contact_samples=samples,
    )


def ribbon_state(n, rng):
    x = np.zeros((n, 3))
    x[:, 0] = np.arange(n) * 1.0
    x += 0.05 * rng.standard_normal((n, 3))
    x[:, 2] += 1.9
    st = RodState.from_positions(
        x,
        theta=0.3 * np.arange(n - 1) + 0.2 * rng.standard_normal(n - 1),
        first_director=np.array([0.0, 0.0, 1.0]),
    )
    st.v = rng.standard_normal((n, 3))
    st.omega = rng.standard_normal(n - 1)
    return st


@pytest.mark.parametrize("samples", [1, 2, 4])
def test_step_potential_derivatives_with_contact_and_friction(samples):
    rng = np.random.default_rng(3)
    n = 6
    rod = ribbon_rod(n, samples)
    start = ribbon_state(n, rng)
    sampling = ContactSampling.of(rod)
    lag = friction_lag(rod, start, sampling, all_points=True)
    # Non-zero lagged normal forces everywhere, so friction acts on every sample point.
    lag = FrictionLag(
        None if lag.stencil_normal is None else 1e-3 * (1 + rng.random(lag.stencil_normal.shape)),
        lag.stencil_points,
        1e-3 * (1 + rng.random(lag.end_normal.shape)),
        lag.end_points,
    )
    pot = StepPotential(rod, start, 0.01, Assembly(n), sampling, lag)
    offset = 0.05 * rng.standard_normal(4 * n - 1)  # away from the transport source
    g, g_fd, H, H_fd = fd_check(pot, start, offset)
    assert np.max(np.abs(g - g_fd)) < 1e-7 * np.max(np.abs(g))
    assert np.max(np.abs(H - H_fd)) < 1e-5 * np.max(np.abs(H))


def test_contact_is_active_in_the_check():
    """The configuration of the check above really has points inside the contact band."""
    rng = np.random.default_rng(3)
    n = 6
    rod = ribbon_rod(n, 4)
    start = ribbon_state(n, rng)
    e_contact = Assembly(n).contact(rod, start, ContactSampling.of(rod), 0)[0]
    assert e_contact > 0


def test_static_potential_derivatives_without_ground():
    rng = np.random.default_rng(5)
    n = 5
    rod = ribbon_rod(n, 4).replace(ground=None, contact=None, friction=None)
    start = ribbon_state(n, rng)
    pot = StaticPotential(rod, Assembly(n), rng.standard_normal(4 * n - 1) * 1e-3)
    g, g_fd, H, H_fd = fd_check(pot, start, 0.1 * rng.standard_normal(4 * n - 1))
    assert np.max(np.abs(g - g_fd)) < 1e-7 * np.max(np.abs(g))
    assert np.max(np.abs(H - H_fd)) < 1e-5 * np.max(np.abs(H))
