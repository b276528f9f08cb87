"""Eq. 1 and Eq. 2 of seed 001 (models/empirical.py)."""

import numpy as np
import pytest

from lcefem.models.empirical import Eq2, eq1_power, eq1_stretch, eq2_curvature
from lcefem.models.heat import joule_power


def test_eq1_limits_and_midpoint():
    assert eq1_stretch(0.0) == pytest.approx(1.0 + 0.426 / (1 + np.exp(-11.97 * 0.635)), rel=1e-12)
    assert eq1_stretch(635.0) == pytest.approx(1.0 + 0.426 / 2.0)  # gamma_3 = 0.635 W
    assert eq1_stretch(5000.0) == pytest.approx(1.0, abs=1e-12)


def test_eq1_inverse():
    lam = np.array([1.05, 1.2, 1.33, 1.4])
    np.testing.assert_allclose(eq1_stretch(eq1_power(lam)), lam, rtol=1e-12)


def test_eq1_at_hold_current_uses_joule_power():
    """0.06 A through 146.6 ohm is 0.528 W: Eq. 1 gives 1.334."""
    assert joule_power(0.06, 146.6) == pytest.approx(527.76)
    assert eq1_stretch(joule_power(0.06, 146.6)) == pytest.approx(1.3335, abs=1e-3)


def test_eq2_sign_and_flat_beam():
    assert eq2_curvature(1.2, 1.2) == 0.0
    assert eq2_curvature(1.33, 1.05) > 0 > eq2_curvature(1.05, 1.33)
    # hand evaluation at (1.33, 1.05), l_p = 30, t_a = 2, lambda_N = 1.4, eta = 0.57
    s = 2.38
    expected = 16 * 0.57 * 0.28 / (s * (2.0 + 30.0 * np.sqrt(4 - s**2 / 1.96)))
    assert eq2_curvature(1.33, 1.05, Eq2()) == pytest.approx(expected, rel=1e-12)
