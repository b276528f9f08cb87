"""One ``section.field=value`` assignment of the study scripts' ``--set``
(validation.config.assign): cast to the field's type, bound-checked like a case file, one-line
errors naming the option."""

import pytest

from lcefem.models.errors import InputError
from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig
from lcefem.validation.app.config import assign, assign_or_exit


def test_an_assignment_changes_one_field_only():
    base = RibbonConfig()
    cfg = assign(base, "numerics.contact_spacing=0.25")
    assert cfg.numerics.contact_spacing == 0.25
    assert (
        cfg.numerics.cells_thickness == base.numerics.cells_thickness
        and cfg.geometry == base.geometry
    )


@pytest.mark.parametrize(
    "bad",
    [
        "numerics.cells_thickness",
        "nosection.x=1",
        "numerics.nofield=2",
        "numerics.cells_thickness=abc",
        "numerics.cells_thickness=0",
    ],
)
def test_bad_assignments_are_one_line_errors(bad):
    with pytest.raises(InputError) as e:
        assign(RibbonConfig(), bad)
    assert "\n" not in str(e.value) and (
        "--set" in str(e.value) or "cells_thickness" in str(e.value)
    )


def test_scripts_exit_2_on_bad_assignment(capsys):
    with pytest.raises(SystemExit) as e:
        assign_or_exit(RibbonConfig(), "numerics=4")
    assert e.value.code == 2 and "--set 'numerics=4'" in capsys.readouterr().err
