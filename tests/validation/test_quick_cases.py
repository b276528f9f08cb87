"""Every validation case at its quick resolution: each checked metric must pass, so a physics
regression fails CI (issue 3). Verification cases (manufactured solutions, closed forms of the FE
mechanics) run in tests/verification/test_verification_cases.py."""

import pytest

from lcefem.validation.cases import registry
from tests.conftest import assert_metrics_pass, run_quick_case

CASES = sorted(n for n in registry() if not n.startswith("verification_"))


@pytest.mark.parametrize("name", CASES)
def test_quick_case_metrics_pass(name, tmp_path):
    assert_metrics_pass(run_quick_case(name, tmp_path))
