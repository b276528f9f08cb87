"""Each bar-and-hinge model set carries the grid exchange factor calibrated with its own mechanics
(validation.calibrate.ModelSet.exchange_factor, read from
validation/data/grid_exchange_calibration*.json): its current route at the dome hold meets the
measured dome (docs/gridshell_thermal.md, "The exchange factor in the FE-calibrated set")."""

import pytest

from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import grid_exchange_calibration as cal
from lcefem.validation.studies.gridshell import gridshell_current_route as route

#: Tolerance on the factor [-] that today's model needs to meet the measured dome, against the
#: stored one: the factor's third decimal. Measured: the FE-calibrated set needs 0.8561 within 1e-5
#: (its calibration's brentq xtol is 1e-4); the published set 0.9508 against the stored 0.9512 (its
#: configuration moved after its calibration: dome -0.015988 vs the stored -0.015999 1/mm). The two
#: sets' factors are 0.095 apart, and the other set's factor misses the dome by 0.0025 1/mm.
FACTOR_TOL = 1e-3


def _slope(record: dict) -> float:
    """d(circle curvature)/d(factor) [1/mm] from the calibration's last two trials
    (~0.028-0.030)."""
    (f1, k1), (f2, k2) = ((t["factor [-]"], t["circle [1/mm]"]) for t in record["trials"][-2:])
    return (k2 - k1) / (f2 - f1)


@pytest.mark.parametrize("name", calibrate.MODEL_SETS)
def test_each_set_meets_the_measured_dome_with_its_own_factor(name):
    record = calibrate.exchange_calibration(name)
    ms = calibrate.model_set(name)
    assert ms.exchange_factor == record["value [-]"]  # published 0.9512, FE-calibrated 0.8561
    assert ms.configuration["current.exchange_factor"] == ms.exchange_factor
    lambdas = route.drive_lambdas("dome", "experiment", route.set_route(name))[
        1
    ]  # hold 0.04 / 0.07 A
    k = route.bh_curvatures("dome", lambdas, name)
    circle = 0.5 * (k["circle_x"] + k["circle_y"])
    # one secant step from the stored factor to the one that meets -0.016 in today's model
    assert abs((circle - cal.DOME_MEASURED) / _slope(record)) < FACTOR_TOL


def test_the_other_sets_factor_misses_the_dome():
    # controlled change: the FE-calibrated mechanics with the published set's factor holds the dome
    # at -0.0135 1/mm (docs/gridshell_thermal.md): it would need a factor ~0.095 lower
    record = calibrate.exchange_calibration("fe-calibrated")
    published = calibrate.exchange_factor("published")
    lambdas = route.drive_lambdas(
        "dome", "experiment", route.set_route("fe-calibrated", published)
    )[1]
    k = route.bh_curvatures("dome", lambdas, "fe-calibrated")
    assert (
        abs((0.5 * (k["circle_x"] + k["circle_y"]) - cal.DOME_MEASURED) / _slope(record))
        > 50 * FACTOR_TOL
    )


def test_an_explicit_factor_overrides_the_sets():
    from lcefem.models.errors import InputError
    from lcefem.validation.studies.gridshell import uncertainty as unc

    ms = calibrate.model_set("fe-calibrated")
    assert ms.current_route().exchange_factor == ms.exchange_factor
    assert ms.current_route(exchange_factor=1.0).exchange_factor == 1.0
    # the bands' strip law follows the factor: more exchange, a cooler strip, a longer lambda
    p = 0.07**2 * unc.GRID_STRIP.resistance * 1.0e3  # mW at the dome's bottom hold current
    assert unc.StretchLaw("strip", 1.0)(p) > unc.StretchLaw("strip", ms.exchange_factor)(p) + 0.01
    with pytest.raises(InputError, match="exchange-factor"):
        unc.BandsConfig(exchange_factor=-1.0).checked()
    with pytest.raises(InputError, match="model_set"):
        calibrate.exchange_factor("nope")


def test_the_models_constant_is_the_published_sets_stored_calibration():
    """models.lumped_heat.GRID_EXCHANGE_FACTOR (models/ cannot read validation data) restates the
    stored published calibration; the two must not drift apart."""
    from lcefem.models.lumped_heat import GRID_EXCHANGE_FACTOR

    assert GRID_EXCHANGE_FACTOR == calibrate.exchange_factor("published")
