"""Sampling and Sobol indices (lcefem.solvers.analysis.sensitivity) against closed forms, and the
bands' sampler and surrogate of lcefem.validation.studies.gridshell.uncertainty."""

import numpy as np
import pytest
from scipy import stats

from lcefem.solvers.analysis.sensitivity import UncertainInput, sample_inputs, sobol_indices


def test_sampler_reproduces_the_input_distributions():
    inputs = [
        UncertainInput("R", "unif", (126.0, 134.0)),
        UncertainInput("lN", "norm", (1.4, 0.086)),
    ]
    X = sample_inputs(inputs, 20000, seed=1)
    assert X[:, 0].min() >= 126.0 and X[:, 0].max() <= 134.0
    assert stats.kstest(X[:, 0], stats.uniform(126.0, 8.0).cdf).pvalue > 0.01
    assert stats.kstest(X[:, 1], stats.norm(1.4, 0.086).cdf).pvalue > 0.01
    assert inputs[0].sd == pytest.approx(8.0 / np.sqrt(12.0))


def test_gridshell_inputs_sample_the_measured_spreads():
    from lcefem.validation.studies.gridshell import uncertainty as unc

    inputs = unc.gridshell_inputs("dome")
    X = sample_inputs(inputs, 20000, seed=2)
    names = [i.name for i in inputs]
    r = X[:, names.index("Bx resistance")]
    assert 126.0 <= r.min() and r.max() <= 134.0 and r.mean() == pytest.approx(130.0, abs=0.1)
    ln = X[:, names.index("Tx lambda_N")]
    assert ln.std() / ln.mean() == pytest.approx(
        8.01 / 130.22, rel=0.03
    )  # seed 001: 130.22 +- 8.01 mm
    # the nominal inputs give the current route's lambdas (Eq. 1 at the paper's dome currents)
    from lcefem.models import lumped_heat
    from lcefem.validation.studies.gridshell import gridshell_bh as gs

    f = unc.rest_fractions_of(unc.nominal_row(inputs), "dome", unc.StretchLaw("eq1"))[0]
    lam = lumped_heat.lambda_assignments_from_currents(
        gs.SHAPES["dome"]["currents"], lumped_heat.CurrentRouteConfig("eq1")
    )
    assert f * 1.4 == pytest.approx([lam[c] for c in unc.CHANNELS], rel=1e-12)


def test_sobol_indices_of_the_ishigami_function():
    # Ishigami (a = 7, b = 0.1), X_i ~ U(-pi, pi): S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424,
    # 0.2437) (Saltelli et al., Global Sensitivity Analysis: The Primer, 2008).
    inputs = [UncertainInput(f"x{i}", "unif", (-np.pi, np.pi)) for i in range(3)]

    def ishigami(X):
        return np.sin(X[:, 0]) + 7.0 * np.sin(X[:, 1]) ** 2 + 0.1 * X[:, 2] ** 4 * np.sin(X[:, 0])

    s = sobol_indices(ishigami, inputs, base_samples=8192, seed=3)["y0"]
    assert s["S1"] == pytest.approx([0.3139, 0.4424, 0.0], abs=0.03)
    assert s["ST"] == pytest.approx([0.5576, 0.4424, 0.2437], abs=0.03)


def test_grouped_sobol_indices_of_a_linear_model():
    # y = sum a_i x_i, independent inputs: S1 = ST = a_i^2 var_i / sum; a group adds its members.
    inputs = [
        UncertainInput("a1", "unif", (0.0, 1.0), "A"),
        UncertainInput("a2", "norm", (0.0, 0.5), "A"),
        UncertainInput("b", "unif", (0.0, 2.0), "B"),
    ]
    coef = np.array([1.0, 2.0, 1.0])
    var = coef**2 * np.array([1.0 / 12.0, 0.25, 4.0 / 12.0])
    exact = [(var[0] + var[1]) / var.sum(), var[2] / var.sum()]
    s = sobol_indices(lambda X: X @ coef, inputs, base_samples=4096, seed=4)["y0"]
    assert s["names"] == ["A", "B"]
    assert s["S1"] == pytest.approx(exact, abs=0.03)
    assert s["ST"] == pytest.approx(exact, abs=0.03)


def test_polynomial_surrogate_is_exact_on_a_quadratic_and_flags_a_bad_fit():
    from lcefem.validation.studies.gridshell.uncertainty import PolynomialSurrogate

    rng = np.random.default_rng(5)
    Z = rng.uniform(0.8, 1.0, (80, 3))
    y = 1.0 + 2.0 * Z[:, 0] - Z[:, 1] * Z[:, 2] + 0.5 * Z[:, 2] ** 2
    sur = PolynomialSurrogate.fit(Z, y, degree=2)
    assert sur.q2[0] == pytest.approx(1.0, abs=1e-10)
    assert sur(Z)[:, 0] == pytest.approx(y, abs=1e-10)
    noisy = PolynomialSurrogate.fit(Z, rng.normal(size=80), degree=1)
    assert noisy.q2[0] < 0.5


def test_polynomial_surrogate_through_too_few_points_is_not_validated():
    # 4 points, 6 coefficients (5 features): the fit interpolates, so leave-one-out cannot test it
    # (the hat matrix is the identity and the old formula gave Q^2 = 1, a 'valid' surrogate).
    from lcefem.validation.studies.gridshell.uncertainty import PolynomialSurrogate

    rng = np.random.default_rng(6)
    Z = rng.uniform(0.7, 1.0, (4, 5))
    sur = PolynomialSurrogate.fit(Z, rng.normal(size=4))
    assert np.isnan(sur.q2[0]) and np.isnan(sur.loo_rms[0])
    assert PolynomialSurrogate.min_points(5) == 7
    tested = PolynomialSurrogate.fit(rng.uniform(0.7, 1.0, (7, 5)), rng.normal(size=7))
    assert np.isfinite(tested.q2[0])


def test_bands_table_places_the_paper_value_inside_or_outside():
    from lcefem.validation.studies.gridshell import uncertainty as unc

    v = np.linspace(-0.030, -0.010, 201)  # 5-95 %: -0.029 .. -0.011
    rows = unc.bands_table(
        {"circle kappa_x [1/mm]": v, "circle kappa_y [1/mm]": v + 0.02, "quad kappa_x [1/mm]": v},
        {c: 0.0 for c in unc.OUTPUTS},
        "dome",
    )
    by = {r["quantity"]: r for r in rows}
    assert by["circle kappa_x [1/mm]"]["median"] == pytest.approx(-0.020)
    assert (
        by["circle kappa_x [1/mm]"]["p5"] == pytest.approx(-0.029)
        and by["circle kappa_x [1/mm]"]["inside"]
    )
    assert by["circle kappa_y [1/mm]"]["inside"] is False  # paper -0.016 below -0.009 .. 0.009
    assert by["quad kappa_x [1/mm]"]["inside"] is None  # the paper measured the circle measure only
