"""Thermal natural strains of the LCE ribbon (lcefem.models.ribbon)."""

import numpy as np
import pytest

from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.models.ribbon import (RibbonGeometry, SectionGrid, natural_strains, natural_twist_rate)

TR = NematicTransition()
GRID = SectionGrid(4.0, 0.8, 6, 2)


def test_uniform_temperature_gives_pure_contraction():
    T = np.full((3, GRID.n_cells), 75.0)
    ns = natural_strains(T, GRID, TR)
    a = contraction_ratio(75.0, TR)
    assert np.allclose(ns.axial, a - 1.0)
    assert np.allclose(ns.curvature, 0.0, atol=1e-14)


@pytest.mark.parametrize("axis", [0, 1])
def test_small_linear_gradient_bends_towards_the_hot_side(axis):
    """kappa_bar = -(da/dT) dT/dy: the hotter side contracts more and the ribbon bends towards it."""
    T0, grad = 70.0, 0.5  # C, K/mm
    y = GRID.y1 if axis == 0 else GRID.y2
    T = T0 + grad * y
    ns = natural_strains(T[None], GRID, TR)
    slope = (contraction_ratio(T0 + 1e-4, TR) - contraction_ratio(T0 - 1e-4, TR)) / 2e-4
    assert ns.curvature[0, axis] == pytest.approx(-slope * grad, rel=2e-3)
    assert ns.curvature[0, axis] > 0  # towards +y, the hot side
    assert ns.curvature[0, 1 - axis] == pytest.approx(0.0, abs=1e-12)


def test_face_temperatures_give_a_linear_profile():
    T = GRID.from_faces(80.0, 40.0)
    assert np.allclose(T, 60.0 + 40.0 * GRID.y2 / 0.8)


def test_untwisting():
    tau0 = RibbonGeometry().twist_rate
    assert tau0 == pytest.approx(2 * np.pi * 0.05)
    assert natural_twist_rate(tau0, 1.0) == pytest.approx(tau0)
    iso = 1.0 / TR.lambda_N
    assert natural_twist_rate(tau0, iso) == pytest.approx(tau0 * (1 + 2 * (iso - iso ** -0.5)))
    assert 0 < natural_twist_rate(tau0, iso) < 0.05 * tau0  # isotropic: almost untwisted
