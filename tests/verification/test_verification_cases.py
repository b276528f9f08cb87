"""Manufactured-solution checks (issue 2: heat L2 order within 0.15 of theory over three meshes;
mechanics L2 order of the finite-strain LCE solver), run through their validation cases so that the
test and the report share one implementation (validation/studies/verification/manufactured.py)."""

import pytest

from lcefem.validation.cases import registry
from tests.conftest import assert_metrics_pass, assert_phenomena_shown, run_quick_case

CASES = sorted(n for n in registry() if n.startswith("verification_"))


def test_heat_and_mechanics_cases_exist():
    assert {"verification_heat_mms", "verification_mechanics_mms"} <= set(CASES)


@pytest.mark.parametrize("name", CASES)
def test_verification_case(name, tmp_path):
    metrics = run_quick_case(name, tmp_path)
    orders = [m for m in metrics if m["metric"].startswith("L2 order") and m["passed"] is not None]
    assert orders, "no checked observed order"
    assert_metrics_pass(metrics)
    assert_phenomena_shown(name, metrics)
