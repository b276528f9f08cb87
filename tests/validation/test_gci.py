"""Grid Convergence Index against the published worked example and synthetic sequences of known
order.
"""

import math

import pytest

from lcefem.validation.studies.verification.gci import gci, observed_order


def test_celik_2008_table1_reattachment_length():
    """Celik et al. 2008, J. Fluids Eng. 130, 078001, Table 1, first column (phi = dimensionless
    reattachment length, monotonic convergence): 2D grids of N1, N2, N3 = 18000, 8000, 4500 cells,
    so h ~ N^(-1/2), r21 = 1.5, r32 = 1.333; phi = 6.063, 5.972, 5.863. Published: p = 1.53,
    phi_ext21 = 6.1685, e_a21 = 1.5 %, e_ext21 = 1.7 %, GCI_fine21 = 2.2 %."""
    h = tuple(n**-0.5 for n in (18000, 8000, 4500))
    res = gci(h, (6.063, 5.972, 5.863))
    assert round(res.r21, 3) == 1.5 and round(res.r32, 3) == 1.333
    assert round(res.p, 2) == 1.53
    assert round(res.extrapolated, 4) == 6.1685
    assert round(100 * res.e_a, 1) == 1.5
    assert round(100 * res.e_ext, 1) == 1.7
    assert round(100 * res.gci_fine, 1) == 2.2
    assert not res.oscillatory
    assert res.iterations > 1  # unequal ratios: the fixed-point iteration was needed


@pytest.mark.parametrize("ratios", [(2.0, 2.0), (1.5, 1.3333333333333333), (1.3, 1.7)])
def test_observed_order_of_a_second_order_sequence(ratios):
    """f(h) = 1 + 0.3 h^2 exactly: p = 2, extrapolated value 1, GCI = Fs |f1 - 1|/f1 exactly."""
    h1 = 0.1
    h = (h1, h1 * ratios[0], h1 * ratios[0] * ratios[1])
    f = tuple(1.0 + 0.3 * x**2 for x in h)
    res = gci(h, f)
    assert res.p == pytest.approx(2.0, abs=1e-6)
    assert res.extrapolated == pytest.approx(1.0, abs=1e-10)
    # with the exact order the GCI is the safety factor times the true relative error of phi1
    assert res.gci_fine == pytest.approx(1.25 * 0.3 * h1**2 / f[0], rel=1e-6)


def test_alternating_differences_are_flagged_oscillatory():
    """f(h) = 1 + (-1)^k 0.2 h_k: differences alternate in sign, Celik's s = -1 branch."""
    h = (0.1, 0.15, 0.225)
    f = (1.0 + 0.2 * 0.1, 1.0 - 0.2 * 0.15, 1.0 + 0.2 * 0.225)
    res = gci(h, f)
    assert res.oscillatory
    assert math.isfinite(res.p) and res.p > 0


def test_mesh_independent_value_has_no_order_and_zero_gci():
    res = gci((1.0, 2.0, 4.0), (3.0, 3.0, 3.0))
    assert math.isnan(res.p)
    assert res.extrapolated == 3.0 and res.gci_fine == 0.0


def test_bad_mesh_sizes_are_rejected():
    with pytest.raises(ValueError, match="h1 < h2 < h3"):
        gci((1.0, 0.5, 2.0), (1.0, 2.0, 3.0))
    assert math.isnan(observed_order((1.0, 2.0, 4.0), (1.0, 1.0, 2.0))[0])
