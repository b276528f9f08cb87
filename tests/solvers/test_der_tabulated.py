"""The tabulated law of the rolling ribbon's natural shape (solvers.der.tabulated): cubics exactly,
the contraction ratio within the interpolation error bound, the law itself outside the table."""

import numpy as np

from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.models.ribbon import SectionGrid, natural_strains
from lcefem.solvers.der.ribbon import CONTRACTION_TABLE, tabulated_contraction
from lcefem.solvers.der.tabulated import TabulatedLaw

TR = NematicTransition()


def test_a_cubic_is_reproduced_to_round_off():
    """Four-point Lagrange interpolation is exact for cubics."""
    cubic = lambda x: 1.5 - 0.3 * x + 0.02 * x**2 - 0.004 * x**3  # noqa: E731
    table = TabulatedLaw.of(cubic, -3.0, 7.0, 0.37)
    x = np.linspace(-3.0, table.hi, 10_001, endpoint=False)
    assert np.max(np.abs(table(x) - cubic(x))) < 1e-12 * np.max(np.abs(cubic(x)))


def test_contraction_ratio_within_the_interpolation_bound():
    """|error| <= (9/16) h^4 max|a''''| / 4!, a'''' by finite differences on the table's range."""
    lo, hi, h = CONTRACTION_TABLE
    table = tabulated_contraction(TR)
    d = 0.02
    x = np.arange(lo, hi, d)
    fourth = np.diff(contraction_ratio(x, TR), 4) / d**4
    bound = 9.0 / 16.0 * h**4 * np.max(np.abs(fourth)) / 24.0
    error = table.max_error()
    assert 0.0 < error <= bound
    assert bound < 1e-9  # a stretch error far below the Newton tolerances (1e-5 of a node's weight)


def test_outside_the_table_the_law_itself():
    table = tabulated_contraction(TR)
    x = np.array([table.lo - 1.0, table.hi, table.hi + 500.0, -273.0])
    assert np.array_equal(table(x), contraction_ratio(x, TR))
    assert np.isnan(table(np.array([np.nan]))[0])


def test_natural_strains_with_the_table_match_the_exact_law():
    """The section resultants (curvatures of a through-thickness and across-width gradient) agree to
    the table's error."""
    grid = SectionGrid(4.0, 0.8)
    T = 50.0 + 60.0 * np.random.default_rng(1).random((40, grid.n_cells))
    exact = natural_strains(T, grid, TR)
    tab = natural_strains(T, grid, TR, tabulated_contraction(TR))
    error = tabulated_contraction(TR).max_error()
    assert np.max(np.abs(tab.axial - exact.axial)) <= error
    # kappa = -int eps y dA / int y^2 dA: at most error * int |y| dA / int y^2 dA = error * 3/(2
    # half-size)
    assert np.max(np.abs(tab.curvature[:, 0] - exact.curvature[:, 0])) <= error * 3.0 / (
        2.0 * 2.0
    ) * (1 + 1e-6)
    assert np.max(np.abs(tab.curvature[:, 1] - exact.curvature[:, 1])) <= error * 3.0 / (
        2.0 * 0.4
    ) * (1 + 1e-6)
    assert (
        np.max(np.abs(exact.curvature[:, 1])) > 1e3 * error * 3.0 / 0.8
    )  # the comparison is not vacuous
