"""The measured contraction curve (models.lce.MeasuredContraction, issue 44): its normalisation to
the sigmoid law's quantities, its piecewise-linear error against a smooth law (quadratic in the row
spacing), and the UFL form equal to numpy at the rows, between them and outside the table."""

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import numpy as np
import pytest
import ufl

import dolfinx

from lcefem.models.errors import InputError
from lcefem.models.lce import (
    MeasuredContraction,
    NematicTransition,
    contraction_ratio,
    order_parameter,
    spontaneous_stretch,
    temperature_for_stretch,
)

SIGMOID = NematicTransition()


def sampled(spacing: float, transition: NematicTransition = SIGMOID) -> MeasuredContraction:
    """The present law's lambda_s(T) sampled every ``spacing`` K over 0-200 C (hot end:
    isotropic)."""
    T = np.arange(0.0, 200.0 + 0.5 * spacing, spacing)
    return MeasuredContraction.from_rows(T, spontaneous_stretch(T, transition), source="sigmoid")


def test_normalisation_matches_the_sigmoid_law():
    """a(T_ref) = 1, lambda_N = L(T_ref)/L_min (the sigmoid's lambda_N within its value at 200 C,
    lambda_s(200 C) - 1 ~ 1e-9), and the laws' functions dispatch on the curve."""
    m = sampled(1.0)
    assert float(contraction_ratio(SIGMOID.T_ref, m)) == 1.0
    assert m.lambda_N == pytest.approx(SIGMOID.lambda_N, rel=1e-8)
    assert float(spontaneous_stretch(200.0, m)) == 1.0
    T = np.array([30.0, 60.0, 69.0, 80.0])
    np.testing.assert_allclose(order_parameter(T, m), order_parameter(T, SIGMOID), atol=2e-4)
    # the inverse: the temperature of a stretch, back through the curve
    assert float(spontaneous_stretch(temperature_for_stretch(1.2, m), m)) == pytest.approx(
        1.2, rel=1e-12
    )


def test_strain_rows_and_cooling_order_give_the_same_curve():
    """Strain e = L - 1 and rows measured on cooling (decreasing T) give the stretch curve."""
    T, L = [25.0, 50.0, 80.0, 120.0], [1.0, 0.9, 0.7, 0.68]
    a = MeasuredContraction.from_rows(T, L)
    b = MeasuredContraction.from_rows(T[::-1], [v - 1.0 for v in L[::-1]], kind="strain")
    assert a.temperatures == b.temperatures
    np.testing.assert_allclose(a.values, b.values, rtol=0, atol=1e-15)
    assert a.lambda_N == pytest.approx(1.0 / 0.68)


def test_constant_outside_the_table():
    """Below the first row the first value, above the last the last: no extrapolation."""
    m = MeasuredContraction.from_rows([40.0, 60.0, 90.0], [1.0, 0.8, 0.75])
    np.testing.assert_array_equal(
        m.measured(np.array([-10.0, 40.0, 90.0, 300.0])), [1.0, 1.0, 0.75, 0.75]
    )
    assert float(m.measured(50.0)) == pytest.approx(0.9, rel=1e-15)  # linear between the rows


def test_interpolation_error_of_a_sampled_sigmoid_falls_quadratically():
    """max |lambda_table - lambda_sigmoid| over 20-120 C for rows every 4, 2, 1, 0.5 K: each halving
    divides it by 4 (piecewise-linear error h^2 max|lambda''| / 8); measured ratios 3.9-4.0."""
    T = np.linspace(20.0, 120.0, 20001)
    errors = [
        np.max(np.abs(spontaneous_stretch(T, sampled(h)) - spontaneous_stretch(T, SIGMOID)))
        for h in (4.0, 2.0, 1.0, 0.5)
    ]
    ratios = [a / b for a, b in zip(errors, errors[1:])]
    assert all(3.6 < r < 4.4 for r in ratios), (errors, ratios)
    # h^2/8 max|lambda''|: the bound the error must stay under at every spacing
    d2 = np.max(np.abs(np.gradient(np.gradient(spontaneous_stretch(T, SIGMOID), T), T)))
    assert all(e <= 1.02 * h * h / 8.0 * d2 for e, h in zip(errors, (4.0, 2.0, 1.0, 0.5)))


@pytest.mark.parametrize(
    "rows",
    [
        ([25.0], [1.0]),  # one row
        ([25.0, 25.0, 60.0], [1.0, 0.9, 0.8]),  # repeated temperature
        ([25.0, 60.0, 40.0], [1.0, 0.9, 0.8]),  # not monotonic
        ([25.0, 60.0], [1.0, 0.0]),  # stretch 0
        ([25.0, float("nan")], [1.0, 0.8]),  # NaN
    ],
)
def test_bad_rows_are_one_line_input_errors(rows):
    with pytest.raises(InputError) as err:
        MeasuredContraction.from_rows(*rows)
    assert "\n" not in str(err.value) and "allowed" in str(err.value)


def test_ufl_form_equals_numpy_at_rows_between_and_outside():
    """The UFL conditionals interpolated at points placed on every row, between rows and outside the
    table give the numpy values to rounding (1e-15), for a measured curve with uneven rows."""
    m = MeasuredContraction.from_rows(
        [25.0, 35.0, 40.0, 45.0, 50.0, 60.0, 90.0, 150.0],
        [1.0, 0.921, 0.877, 0.779, 0.635, 0.587, 0.593, 0.617],
    )
    probes = np.concatenate(
        [m.temperatures, [10.0, 25.0 - 1e-9, 37.5, 44.999, 51.0, 100.0, 150.0 + 1e-9, 400.0]]
    )
    mesh = dolfinx.mesh.create_interval(MPI.COMM_SELF, len(probes) - 1, [0.0, 1.0])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    T = dolfinx.fem.Function(V)
    x = V.tabulate_dof_coordinates()[:, 0]
    T.x.array[:] = probes[np.rint(x * (len(probes) - 1)).astype(int)]
    for law in (m.stretch, m.contraction, m.measured):
        out = dolfinx.fem.Function(V)
        out.interpolate(dolfinx.fem.Expression(law(T), V.element.interpolation_points))
        np.testing.assert_allclose(out.x.array, law(T.x.array), rtol=1e-15, atol=1e-15)
    assert isinstance(m.stretch(T), ufl.core.expr.Expr)
