"""The FE gridshell cases' bookkeeping (validation/cases/gridshell_fe.py): registered (the shapes
case under lcefem converge), the model-vs-model band, the partial ramp of the quick level. The
cases' quick runs are exercised by tests/validation/test_quick_cases.py."""

import pytest

from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.validation.cases import registry
from lcefem.validation.cases.gridshell_fe import MODEL_BAND, SWEEP_LAMBDA_B, _partial, agreement


def test_cases_are_registered_and_the_shapes_case_converges():
    cases = registry()
    assert cases["gridshell_shapes_fe"].convergence and cases["gridshell_shapes_fe"].fe
    assert cases["gridshell_sweep_fe"].fe


def test_model_band_is_relative_to_the_larger_magnitude():
    assert MODEL_BAND == 0.10  # issue 14: "agree within 10 %"
    assert agreement(-0.0200, -0.0190) and not agreement(-0.0200, -0.0170)
    assert not agreement(0.001, -0.001)  # opposite signs never agree


def test_partial_ramp_and_sweep_range():
    lam = _partial({"Tx": 1.33, "Bx": 1.05}, PUBLISHED_LAMBDA_N, 0.1)
    assert lam["Tx"] == pytest.approx(PUBLISHED_LAMBDA_N - 0.1 * (PUBLISHED_LAMBDA_N - 1.33))
    assert _partial({"Bx": 1.05}, PUBLISHED_LAMBDA_N, 1.0)["Bx"] == pytest.approx(1.05)
    assert SWEEP_LAMBDA_B[0] == 1.33 and SWEEP_LAMBDA_B[-1] == 1.05  # issue 14's range
