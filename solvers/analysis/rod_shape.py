"""Rod-like measures of a ribbon or strip solved as a 3D body (units: mm, 1/mm, rad/mm): the
centreline curvatures in the material frame, the twist rate and the stretch, measured the way
Discrete Elastic Rods measure a rod, so a 3D FE shape and a DER shape compare number for number.

Measured on stations x_k along the reference centreline from the deformed centre and edge points,
with the discrete formulas of Discrete Elastic Rods (Bergou et al. 2008; :mod:`lcefem.models.rod`):

- edges e_k between stations, tangents t_k; material frame m1 = width direction (edge points'
  difference at the edge midpoint, made normal to t_k), m2 = t_k x m1 (thickness direction, towards
  the face z = +t/2 of the straight strip);
- stretch: deformed centreline length / reference length between the first and last station;
- material curvatures (kappa_1 towards m1, kappa_2 towards m2) [1/mm]: (kappa b)_k projected on the
  mean frame of the two edges, over the Voronoi length, averaged over the interior stations;
- twist rate: sum of the signed angles between m1 of an edge parallel-transported to the next edge
  and that edge's m1 (DER's discrete twist), over the summed Voronoi length;
- circle curvature: Pratt's circle through the centre stations (:func:`.curvature.circle_fit`).

These are second-order accurate in the station spacing s (on a helix of curvature kappa and torsion
tau the curvature's relative error is about -tau^2 s^2/4: -0.6 % for the twisted ribbons at s = 0.5
mm), so shapes are Richardson-extrapolated from the spacings s and 2 s
(:func:`measure_extrapolated`; tests/validation/test_ribbon_fe.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.models.errors import InputError
from lcefem.models.rod import cross, material_curvatures, parallel_transport, signed_angle
from lcefem.solvers.analysis.curvature import circle_fit

__all__ = ["RodLikeShape", "measure_extrapolated", "measure_shape", "parallel_transport"]


@dataclass
class RodLikeShape:
    """Rod-like description of a ribbon, measured as Discrete Elastic Rods measure a rod."""

    stretch: float  #: centreline length / reference length [-]
    curvature: float  #: mean |kappa| of the centreline [1/mm]
    material_curvature: (
        np.ndarray
    )  #: mean (kappa_1, kappa_2): towards width m1, thickness m2 [1/mm]
    twist_rate: float  #: [rad/mm]
    circle_curvature: (
        float  #: of the least-squares circle through the stations (planar shapes) [1/mm]
    )
    centreline: np.ndarray  #: (n, 3) stations [mm]


def measure_shape(centre: np.ndarray, edge_plus: np.ndarray, edge_minus: np.ndarray) -> dict:
    """DER measures of a ribbon from its centre and edge points (n, 3) [mm] at n >= 3 stations
    (``edge_plus`` at +w/2 along the width, i.e. m1 points from ``edge_minus`` to ``edge_plus``).

    Returns arc_length [mm], material_curvature (kappa_1, kappa_2) [1/mm] and curvature (mean
    |kappa|) [1/mm] averaged over the interior stations, twist_rate [rad/mm], circle_curvature
    [1/mm].
    """
    centre = np.asarray(centre, float)
    if len(centre) < 3:
        raise InputError(f"{len(centre)} stations: need at least 3")
    e = np.diff(centre, axis=0)
    length = np.linalg.norm(e, axis=1)
    t = e / length[:, None]
    widths = np.asarray(edge_plus, float) - np.asarray(edge_minus, float)
    mids = 0.5 * (widths[1:] + widths[:-1])
    m1 = mids - np.einsum("ki,ki->k", mids, t)[:, None] * t
    m1 /= np.linalg.norm(m1, axis=1)[:, None]
    m2 = cross(t, m1)
    voronoi = 0.5 * (length[1:] + length[:-1])
    kappa = material_curvatures(e[:-1], e[1:], m1[:-1], m2[:-1], m1[1:], m2[1:]) / voronoi[:, None]
    twist = signed_angle(parallel_transport(m1[:-1], t[:-1], t[1:]), m1[1:], t[1:])
    return {
        "arc_length": float(length.sum()),
        "material_curvature": kappa.mean(axis=0),
        "curvature": float(np.linalg.norm(kappa, axis=1).mean()),
        "twist_rate": float(twist.sum() / voronoi.sum()),
        "circle_curvature": circle_fit(centre)[0],
    }


def measure_extrapolated(centre: np.ndarray, edge_plus: np.ndarray, edge_minus: np.ndarray) -> dict:
    """:func:`measure_shape` at the stations' spacing s and at 2 s (every other station; give an odd
    number of equally spaced stations), Richardson-extrapolated to s -> 0: (4 m(s) - m(2 s))/3 for
    the arc length, the curvatures and the twist rate, whose error is O(s^2) (O(s^4) after)."""
    if len(centre) % 2 == 0 or len(centre) < 5:
        raise InputError(f"{len(centre)} stations: need an odd number >= 5")
    fine = measure_shape(centre, edge_plus, edge_minus)
    coarse = measure_shape(centre[::2], edge_plus[::2], edge_minus[::2])
    out = dict(fine)
    for key in ("arc_length", "material_curvature", "curvature", "twist_rate"):
        out[key] = (4.0 * np.asarray(fine[key]) - np.asarray(coarse[key])) / 3.0
        out[key] = float(out[key]) if np.ndim(out[key]) == 0 else out[key]
    return out
