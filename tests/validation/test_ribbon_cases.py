"""Helpers of the ribbon validation cases (validation/cases/ribbon.py)."""

import math

import pytest

from lcefem.validation.cases.ribbon import speed_rises


def test_speed_rises_only_over_rolling_temperatures():
    """Judged over the temperatures at which the ribbon rolls, in temperature order; nan with fewer
    than two."""
    assert speed_rises([100, 50, 120], [1.0, 0.0, 2.0], [True, False, True]) == 1.0
    assert speed_rises([100, 120, 140], [1.0, 2.0, 1.5], [True, True, True]) == 0.0
    assert (
        speed_rises([50, 100, 120], [5.0, 1.0, 2.0], [False, True, True]) == 1.0
    )  # the cold row is ignored
    assert math.isnan(speed_rises([50, 100], [0.0, 1.0], [False, True]))


def test_rolls_from_threshold_flags_a_stall_when_hotter():
    from lcefem.validation.cases.ribbon import rolls_from_threshold

    assert rolls_from_threshold([50, 100, 140, 180], [False, True, True, True]) == 1.0
    assert (
        rolls_from_threshold([180, 50, 100, 140], [False, False, True, True]) == 0.0
    )  # stalls at 180 C
    assert math.isnan(rolls_from_threshold([50, 60], [False, False]))


def test_steady_mismatch_takes_the_worst_rolling_run():
    from lcefem.validation.cases.ribbon import steady_mismatch

    runs = [
        {"rolls": True, "spin_rate_ratio [-]": 0.95, "twist_density_variation [-]": 0.02},
        {"rolls": True, "spin_rate_ratio [-]": 1.08, "twist_density_variation [-]": 0.07},
        {"rolls": False, "spin_rate_ratio [-]": 7.0, "twist_density_variation [-]": 0.5},
    ]  # ignored
    spin, twist = steady_mismatch(runs)
    assert spin == pytest.approx(0.08) and twist == pytest.approx(0.07)
    assert all(math.isnan(v) for v in steady_mismatch(runs[2:]))
