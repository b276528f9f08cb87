"""Every validation case at its quick resolution: each failing row must be a registered known
disagreement (validation/data/known_disagreements.toml), so a physics regression (an unexplained
failure) fails CI while an explained disagreement with experiment does not (issues 3, 16), and each
must show the phenomena declared for it in validation/data/phenomena.toml, the physics its full
level shows (issue 16).
Verification cases (manufactured solutions, closed forms of the FE mechanics) run in
tests/verification/test_verification_cases.py."""

import pytest

from lcefem.validation.cases import registry
from tests.conftest import assert_failures_known, assert_phenomena_shown, run_quick_case

CASES = sorted(n for n in registry() if not n.startswith("verification_"))


@pytest.mark.parametrize("name", CASES)
def test_quick_case_failures_are_known_disagreements(name, tmp_path):
    metrics = run_quick_case(name, tmp_path)
    assert_failures_known(metrics)
    assert_phenomena_shown(name, metrics)
