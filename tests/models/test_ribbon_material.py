"""The seed-000 ribbon LCE (issue 32): its laws map onto the solver's transition and elasticity."""

import pytest

from lcefem.models.lce import contraction_ratio
from lcefem.models.ribbon import SEED000_RIBBON, RibbonLCE


def test_transition_reaches_the_published_actuation_strain():
    """Fully heated, the fibres contract to 1/lambda_N: 35 % actuation strain (Saed et al. 2016) is
    L_cold/L_hot = 1.35, i.e. a = 0.741; as built (25 C) a = 1."""
    tr = SEED000_RIBBON.transition()
    assert contraction_ratio(25.0, tr) == pytest.approx(1.0, abs=1e-12)
    assert contraction_ratio(400.0, tr) == pytest.approx(1.0 / 1.35, rel=1e-3)
    # contraction grows monotonically through the transition, half of it near T_NI
    a = [float(contraction_ratio(T, tr)) for T in (40.0, 55.0, 80.0, 120.0, 180.0)]
    assert all(x > y for x, y in zip(a, a[1:]))


def test_elasticity_has_the_ribbon_modulus():
    """E = 3 mu of the scaled invariant law equals the ribbon's Young's modulus."""
    m = RibbonLCE(youngs_modulus=4.0)
    assert 3.0 * m.elasticity().shear_modulus == pytest.approx(4.0, rel=1e-12)
    assert m.elasticity().bulk_modulus / m.elasticity().shear_modulus == pytest.approx(
        SEED000_RIBBON.elasticity().bulk_modulus / SEED000_RIBBON.elasticity().shear_modulus
    )


def test_thermal_curvature_fades_once_the_section_passes_the_transition():
    """The bending drive of a section heated from one face: a small linear temperature gradient g
    across the thickness gives the beam closed form kappa_2 = -a'(T0) g (eps* = a(T) - 1 linear in
    y2). It is largest near T_NI and fades once the whole section is past the transition (the fall
    of the rolling speed above 120 C, issue 32: docs/ribbon.md)."""

    from lcefem.models.ribbon import SectionGrid, natural_strains

    tr = SEED000_RIBBON.transition()
    grid = SectionGrid(4.0, 0.8, 6, 2, 4)
    g = 1.0  # K/mm: 0.8 K across the 0.8 mm thickness

    def kappa(T0):
        T = (
            T0 + g * grid.y2
        )  # linear through the thickness: exact on 2 cells (SectionGrid docstring)
        return float(natural_strains(T[None, :], grid, tr).curvature[0, 1])

    def slope(T0, h=1e-3):
        return float(contraction_ratio(T0 + h, tr) - contraction_ratio(T0 - h, tr)) / (2 * h)

    for T0 in (55.0, 80.0, 120.0, 180.0):
        assert kappa(T0) == pytest.approx(-slope(T0) * g, rel=2e-3)
    assert abs(kappa(180.0)) < 0.02 * abs(
        kappa(80.0)
    )  # saturated section: < 2 % of the drive at T_NI
