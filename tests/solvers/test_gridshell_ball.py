"""The ball of Fig. 5B (solvers/problems/gridshell_bh_ball.py): its radius, and the rolling sphere's
closed forms: on an inclined plane u'' = -(5/7) g s/(1 + s^2); in a paraboloid bowl of curvature
kappa small oscillations of angular frequency sqrt((5/7) g kappa (1 + r kappa)) (the model's centre
rides at r along the normal *above the contact point*: its path has curvature kappa (1 + r kappa) at
the bottom, where the exact centre path 1/(1/kappa - r) is 3.7 % more curved at r kappa = 0.19: the
approximation stated in the module)."""

import math

import numpy as np
import pytest

from lcefem.models.ball import Ball
from lcefem.solvers.problems.gridshell_bh_ball import SurfaceHistory, roll

G = 9806.65  # mm/s^2


def _static(coeffs, half=1000.0):
    c = np.asarray(coeffs, dtype=float)
    return SurfaceHistory(np.array([0.0, 100.0]), np.vstack([c, c]), np.zeros(2), half)


def test_radius_of_10_g_aluminium():
    assert Ball().radius == pytest.approx(
        (3 * 1e-5 / (4 * math.pi * 2.70e-9)) ** (1 / 3), rel=1e-12
    )
    assert Ball().radius == pytest.approx(9.598, abs=1e-3)


def test_rolling_down_an_incline():
    s = 0.2
    ball = Ball(rolling_resistance=0.0)
    out = roll(_static([0.0, s, 0.0, 0.0, 0.0, 0.0]), ball, (0.0, 0.0), 0.0, 0.3, gravity=G)
    t = out["time [s]"]
    expected = -0.5 * (5.0 / 7.0) * G * s / (1 + s * s) * t**2
    assert np.allclose(out["u [mm]"], expected, rtol=1e-6, atol=1e-6)
    assert np.allclose(out["v [mm]"], 0.0, atol=1e-9)


def test_small_oscillation_in_a_bowl():
    kappa = 0.02
    ball = Ball(rolling_resistance=0.0)
    r = ball.radius
    omega = math.sqrt((5.0 / 7.0) * G * kappa * (1.0 + r * kappa))
    period = 2 * math.pi / omega
    out = roll(
        _static([0.0, 0.0, 0.0, 0.5 * kappa, 0.0, 0.5 * kappa]),
        ball,
        (0.5, 0.0),
        0.0,
        3 * period,
        gravity=G,
        samples=3001,
    )
    u, t = out["u [mm]"], out["time [s]"]
    # upward zero crossings give the period
    up = np.nonzero((u[:-1] < 0) & (u[1:] >= 0))[0]
    tc = t[up] - u[up] * (t[up + 1] - t[up]) / (u[up + 1] - u[up])
    # the amplitude (0.5 mm) makes the oscillation nonlinear by ~1e-4
    assert np.mean(np.diff(tc)) == pytest.approx(period, rel=2e-3)


def test_rolling_resistance_settles_the_ball_at_the_bottom():
    out = roll(
        _static([0.0, 0.0, 0.0, 0.01, 0.0, 0.01]), Ball(), (-30.0, -30.0), 0.0, 40.0, gravity=G
    )
    assert math.hypot(out["u [mm]"][-1], out["v [mm]"][-1]) < 0.5
    assert out["exit"] is None
