"""The twisted-ribbon FE problem (solvers/problems/twisted_ribbon.py) driven step by step: an
elastic equilibrium does not depend on the path, so advancing to half the load and then to the whole
gives the one-ramp answer; the observables carry their units and read the same shape."""

import math

import pytest

from lcefem.meshes.twisted_ribbon import TwistedRibbonMesh
from lcefem.solvers.problems.twisted_ribbon import TwistedRibbonFE, solve_twisted_ribbon

LENGTH, WIDTH, THICKNESS = 6.0, 4.0, 0.8
TWIST = 2 * math.pi * 0.05  # [rad/mm], the rolling ribbon's 0.05 turns/mm


def hot_top(y, z):
    """One face hotter [C]: 60 C on z = +t/2, 40 C on z = -t/2, linear between (UFL)."""
    return 50.0 + 20.0 * z / THICKNESS + 0.0 * y


def mesh():
    return TwistedRibbonMesh(along=12, across=4, through=1, level=0)


def test_advancing_in_two_parts_gives_the_one_ramp_equilibrium():
    once = solve_twisted_ribbon(
        LENGTH, WIDTH, THICKNESS, TWIST, hot_top, resolution=mesh(), first=0.5
    )
    ribbon = TwistedRibbonFE(LENGTH, WIDTH, THICKNESS, TWIST, hot_top, resolution=mesh())
    ribbon.advance(0.5, first=0.5)
    half = ribbon.observables()
    ribbon.advance(1.0, first=0.5)
    obs = ribbon.observables()
    assert half["load fraction [-]"] == 0.5 and obs["load fraction [-]"] == 1.0
    d = once.deformed
    assert obs["stretch [-]"] == pytest.approx(d.stretch, rel=1e-8)
    assert obs["twist rate [rad/mm]"] == pytest.approx(d.twist_rate, rel=1e-6)
    assert obs["kappa_2 [1/mm]"] == pytest.approx(d.material_curvature[1], rel=1e-6)
    # the hotter face contracts more: the ribbon bends towards it (kappa_2 > 0 is towards z = +t/2),
    # and half the spontaneous-stretch change bends it less than the whole
    assert 0.0 < half["kappa_2 [1/mm]"] < obs["kappa_2 [1/mm]"]
