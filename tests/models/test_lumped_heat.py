"""Lumped heat balance of a coil-heated strip: Eq. 1 at the hold currents, inverse, transient."""

import numpy as np
import pytest

from lcefem.models.empirical import eq1_stretch
from lcefem.models.heat import Coil, joule_power
from lcefem.models.lce import NematicTransition
from lcefem.models.lumped_heat import (
    FREE_STRIP,
    HeatedStrip,
    current_for_stretch,
    heat_loss,
    steady_stretch,
    steady_temperature,
    transient_temperature,
)


@pytest.mark.parametrize("current", [0.04, 0.05, 0.06, 0.07, 0.08, 0.09])
def test_free_strip_follows_eq1_at_the_hold_currents(current):
    # Eq. 1 is a fit to the Fig. 2C steady lengths, whose sample scatter is a few 0.01 in lambda
    # (seed 001, Fig. 2C shaded bands); the lumped strip must stay within 0.03 of it.
    lam = steady_stretch(current, FREE_STRIP)
    assert lam == pytest.approx(
        float(eq1_stretch(joule_power(current, Coil().resistance))), abs=0.03
    )


def test_steady_state_balances_the_joule_power():
    for strip in (FREE_STRIP, HeatedStrip()):
        T = steady_temperature(0.07, strip)
        assert heat_loss(T, strip) == pytest.approx(0.07**2 * strip.resistance * 1e3, rel=1e-9)


@pytest.mark.parametrize("stretch", [1.05, 1.2, 1.33])
def test_current_for_stretch_inverts_the_steady_map(stretch):
    current = current_for_stretch(stretch)
    assert steady_stretch(current) == pytest.approx(stretch, abs=1e-9)


def test_grid_segment_heats_less_per_length_than_the_free_strip():
    # 25 ohm over 21.4 mm (isotropic) vs 146.6 ohm over 80 mm: 1.17 vs 1.83 ohm/mm, so a segment
    # needs a larger current than the free strip for the same lambda.
    assert current_for_stretch(1.05) > current_for_stretch(1.05, FREE_STRIP)


def test_free_strip_reaches_T_NI_within_about_10_s_at_0_2_A():
    # seed 001: 'the LCEs reach T_NI (~70 C) within 10 s' at 0.2 A; the calibration's target was
    # 10 +- 2 s (validation/data/thermal_calibration.json).
    t, T, lam = transient_temperature(lambda _: 0.2, 30.0, FREE_STRIP)
    t_ni = t[np.argmax(T >= NematicTransition().T_NI)]
    assert 8.0 <= t_ni <= 12.0
    assert lam[-1] == pytest.approx(1.0, abs=0.01)  # fully contracted within 30 s


def test_grid_strip_carries_the_coil_of_the_text_over_the_free_strips_active_length():
    # seed 001: 126-134 ohm per grid strip, 80 mm isotropic active length "preserved in the 3x3
    # grid": 1.63 ohm/mm, between the 25 ohm segment reading (1.17) and the free strip (1.83
    # ohm/mm).
    from lcefem.models.lumped_heat import GRID_STRIP, grid_segment_resistance

    per_mm = GRID_STRIP.resistance / GRID_STRIP.isotropic_length
    assert per_mm == pytest.approx(1.625, abs=1e-9)
    assert (
        HeatedStrip().resistance / HeatedStrip().isotropic_length
        < per_mm
        < FREE_STRIP.resistance / 80.0
    )
    assert grid_segment_resistance() == pytest.approx(130.0 * (30.0 / 1.4) / 80.0, rel=1e-12)


def test_eq1_current_inverts_eq1_through_the_grid_coil():
    # the paper's rule: P from Eq. 1 at lambda, I = sqrt(P/R); Eq. 1 at that power gives lambda
    # back.
    from lcefem.models.lumped_heat import eq1_current

    for lam in (1.05, 1.33):
        i = eq1_current(lam, 130.0)
        assert float(eq1_stretch(joule_power(i, 130.0))) == pytest.approx(lam, abs=1e-9)


def test_larger_grid_exchange_factor_leaves_the_strip_longer():
    # more loss at the same power: a cooler strip, closer to nematic (monotone, the calibration's
    # premise)
    from lcefem.models.lumped_heat import CurrentRouteConfig, stretch_from_current

    lams = [
        stretch_from_current(0.07, CurrentRouteConfig(exchange_factor=f), 1.426)
        for f in (0.8, 1.0, 1.5)
    ]
    assert lams[0] < lams[1] < lams[2]
