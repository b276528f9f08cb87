"""Smooth contact energy and smooth Coulomb friction of seed 000 (lcefem.models.contact)."""

import math

import numpy as np
import pytest

from lcefem.models.contact import (
    ContactLaw,
    FrictionLaw,
    contact_energy,
    friction_force,
    friction_gamma,
    friction_potential,
    normal_force,
)

LAW = ContactLaw(delta=0.05, stiffness=2.0, clearance=0.1)


def test_constants_of_seed_000():
    assert LAW.K1 == pytest.approx(15.0 / 0.05)
    assert FrictionLaw(mu=0.3, slip_speed=0.2).K2 == pytest.approx(75.0)


def test_pieces_of_the_contact_energy():
    """(2h - D)^2 below 2h - delta, the squared softplus inside, 0 above 2h + delta (seed 000)."""
    two_h, d = LAW.clearance, LAW.delta
    gaps = np.array([-0.3, two_h - 2 * d, two_h - 0.5 * d, two_h, two_h + 0.5 * d, two_h + 2 * d])
    E = contact_energy(gaps, LAW)[0]
    assert E[0] == pytest.approx((two_h + 0.3) ** 2)
    assert E[1] == pytest.approx(d**2 * 4)
    K1 = LAW.K1
    assert E[2] == pytest.approx((math.log1p(math.exp(K1 * 0.5 * d)) / K1) ** 2)
    assert E[3] == pytest.approx((math.log(2.0) / K1) ** 2)
    assert E[5] == 0.0


@pytest.mark.parametrize("gap", [-0.2, 0.06, 0.08, 0.1, 0.12, 0.14])
def test_contact_energy_derivatives(gap):
    E, d1, d2 = contact_energy(np.array([gap]), LAW)
    h = 1e-7
    ep, em = contact_energy(np.array([gap + h]), LAW), contact_energy(np.array([gap - h]), LAW)
    assert d1[0] == pytest.approx((ep[0][0] - em[0][0]) / (2 * h), rel=1e-6, abs=1e-12)
    assert d2[0] == pytest.approx((ep[1][0] - em[1][0]) / (2 * h), rel=1e-5, abs=1e-9)


def test_pieces_join_to_within_exp_minus_15():
    two_h, d = LAW.clearance, LAW.delta
    for edge in (two_h - d, two_h + d):
        lo, hi = contact_energy(np.array([edge - 1e-12, edge + 1e-12]), LAW)[0]
        assert abs(hi - lo) <= 2 * math.exp(-15) * d * d


def test_normal_force_is_the_stiffness_times_the_slope():
    assert normal_force(np.array([-0.1]), LAW)[0] == pytest.approx(2.0 * 2 * (LAW.clearance + 0.1))
    assert normal_force(np.array([1.0]), LAW)[0] == 0.0


def test_gamma_is_the_seed_formula():
    law = FrictionLaw(mu=0.4, slip_speed=0.1)
    v = np.linspace(0, 1, 11)
    assert np.allclose(friction_gamma(v, law), 2.0 / (1.0 + np.exp(-law.K2 * v)) - 1.0)


def test_friction_potential_gives_the_coulomb_force_and_its_jacobian():
    """-dD/du is the seed's F_fr = -mu gamma v_T/|v_T| F_n with v = u/h; the Hessian by
    differences."""
    rng = np.random.default_rng(0)
    law = FrictionLaw(mu=0.4, slip_speed=0.3)
    nrm = np.array([0.1, 0.2, 1.0]) / np.linalg.norm([0.1, 0.2, 1.0])
    h = 0.01
    u = np.concatenate(
        [1e-2 * rng.standard_normal((5, 3)), 1e-6 * rng.standard_normal((2, 3))]
    )  # slip and stick
    fn = 0.1 + rng.random(len(u))
    D, g, H = friction_potential(u, nrm, fn, h, law)
    v_t = (u - (u @ nrm)[:, None] * nrm) / h
    assert np.allclose(-g, friction_force(v_t, fn, law), rtol=1e-12, atol=1e-15)
    assert np.allclose((g * nrm).sum(1), 0.0, atol=1e-14)
    for i in range(len(u)):
        for d in np.eye(3):
            hh = 1e-8
            gp = friction_potential((u[i] + hh * d)[None], nrm, fn[i : i + 1], h, law)[1][0]
            gm = friction_potential((u[i] - hh * d)[None], nrm, fn[i : i + 1], h, law)[1][0]
            assert np.allclose(
                H[i] @ d, (gp - gm) / (2 * hh), rtol=1e-5, atol=1e-6 * np.abs(H[i]).max()
            )
        Dp = friction_potential((u[i] * (1 + 1e-6))[None], nrm, fn[i : i + 1], h, law)[0][0]
        Dm = friction_potential((u[i] * (1 - 1e-6))[None], nrm, fn[i : i + 1], h, law)[0][0]
        assert (Dp - Dm) / (2e-6) == pytest.approx(g[i] @ u[i], rel=1e-5, abs=1e-18)


def test_sliding_friction_saturates_at_mu_fn():
    law = FrictionLaw(mu=0.5, slip_speed=0.01)
    f = friction_force(np.array([[10.0, 0.0, 0.0]]), np.array([2.0]), law)
    assert f[0] == pytest.approx([-1.0, 0.0, 0.0])
