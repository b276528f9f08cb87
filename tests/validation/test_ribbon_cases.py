"""Helpers of the ribbon validation cases (validation/cases/ribbon.py)."""

import math

from lcefem.validation.cases.ribbon import speed_rises


def test_speed_rises_only_over_rolling_temperatures():
    """Judged over the temperatures at which the ribbon rolls, in temperature order; nan with fewer than two."""
    assert speed_rises([100, 50, 120], [1.0, 0.0, 2.0], [True, False, True]) == 1.0
    assert speed_rises([100, 120, 140], [1.0, 2.0, 1.5], [True, True, True]) == 0.0
    assert speed_rises([50, 100, 120], [5.0, 1.0, 2.0], [False, True, True]) == 1.0  # the cold row is ignored
    assert math.isnan(speed_rises([50, 100], [0.0, 1.0], [False, True]))
