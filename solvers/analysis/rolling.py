"""Rolling metrics of a rolling-ribbon history (time [s], centroid [mm], end spin angles [rad],
contact points, twist density, temperatures [C]): rolling speed, end spin rates, contact points.

The metrics mirror what the experiments report (seed 000, 'LCE Twisting Robots Dynamics'): the
average rolling speed (distance over time), the number of contact points, and whether both ends
spin at the same rate once rolling is steady.
"""

from __future__ import annotations

import math

import numpy as np

#: A ribbon "rolls" when, over the analysis window, its centroid moved at least this far [mm] and
#: both ends turned at least this much [rad] the same way (a quarter turn: more than the rocking and
#: untwisting seen below the threshold).
ROLL_DISTANCE = 2.0
ROLL_ANGLE = 0.5 * math.pi


def window(history: dict[str, np.ndarray], start_fraction: float = 0.5) -> np.ndarray:
    """Boolean mask of the analysis window: the last (1 - start_fraction) of the run."""
    t = np.asarray(history["time [s]"])
    return t >= t[0] + start_fraction * (t[-1] - t[0])


def rolling_metrics(
    history: dict[str, np.ndarray], start_fraction: float = 0.5
) -> dict[str, float]:
    """Average speed [mm/s] (net centroid distance over the window's time), end spin rates [rad/s]
    (least-squares slopes), their ratio, mean contact points, final and mean twist density and its
    relative variation (max - min)/mean over the window, and ``rolls``."""
    h = {k: np.asarray(v, float) for k, v in history.items()}
    w = window(h, start_fraction)
    t = h["time [s]"][w]
    if len(t) < 3:
        raise ValueError("history too short for rolling metrics")
    dx = h["centroid_x [mm]"][w][-1] - h["centroid_x [mm]"][w][0]
    dy = h["centroid_y [mm]"][w][-1] - h["centroid_y [mm]"][w][0]
    span = t[-1] - t[0]
    distance = math.hypot(dx, dy)
    s0 = np.polyfit(t, h["spin_start [rad]"][w], 1)[0]
    s1 = np.polyfit(t, h["spin_end [rad]"][w], 1)[0]
    turn0 = h["spin_start [rad]"][w][-1] - h["spin_start [rad]"][w][0]
    turn1 = h["spin_end [rad]"][w][-1] - h["spin_end [rad]"][w][0]
    rolls = bool(
        distance >= ROLL_DISTANCE
        and abs(turn0) >= ROLL_ANGLE
        and abs(turn1) >= ROLL_ANGLE
        and turn0 * turn1 > 0
    )
    twist = h["twist_density [turns/mm]"][w]
    mean_twist = float(np.mean(twist))
    total = math.hypot(
        h["centroid_x [mm]"][-1] - h["centroid_x [mm]"][0],
        h["centroid_y [mm]"][-1] - h["centroid_y [mm]"][0],
    )
    return {
        "average_speed [mm/s]": distance / span,
        "distance [mm]": distance,
        "total_distance [mm]": total,
        "spin_rate_start [rad/s]": float(s0),
        "spin_rate_end [rad/s]": float(s1),
        "spin_rate_ratio [-]": float(s1 / s0) if abs(s0) > 1e-12 else float("nan"),
        "contact_points [-]": float(np.mean(h["contact_points [-]"][w])),
        "twist_density_final [turns/mm]": float(h["twist_density [turns/mm]"][-1]),
        "twist_density_mean [turns/mm]": mean_twist,
        # (max - min)/mean of the interior twist density over the window: 0 for a constant twist
        # density
        "twist_density_variation [-]": float((twist.max() - twist.min()) / abs(mean_twist))
        if abs(mean_twist) > 1e-12
        else float("nan"),
        "T_mean_final [C]": float(h["T_mean [C]"][-1]),
        "T_max_final [C]": float(h["T_max [C]"][-1]),
        "rolls": rolls,
    }
