"""Reference and material frames of a discrete rod, moved by time-parallel transport.

Each edge k carries a reference director a1^k (unit, normal to the tangent t^k); a2^k = t^k x a1^k.
The material frame is the reference frame turned by the edge angle theta^k:
m1 = cos(theta) a1 + sin(theta) a2, m2 = t x m1 (seed 000, 'DER - Parallel Transport').
When the tangents change, a1 is parallel transported in time from the old tangent to the new one
(no spin about the tangent), and the reference twist of node k, the signed angle from the space
transport of a1^(k-1) onto t^k to a1^k, is updated continuously (no 2 pi jumps).
"""

from __future__ import annotations

import numpy as np

from lcefem.models.rod import cross, parallel_transport, signed_angle


def edges_of(x: np.ndarray) -> np.ndarray:
    """Edge vectors e^k = x_(k+1) - x_k [mm], shape (N-1, 3)."""
    return x[1:] - x[:-1]


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def transport_directors(a1: np.ndarray, t_old: np.ndarray, t_new: np.ndarray) -> np.ndarray:
    """Time-parallel transport of the reference directors from the old to the new tangents, then
    re-orthonormalised against t_new (removes round-off drift over many steps)."""
    a = parallel_transport(a1, t_old, t_new)
    a -= np.einsum("ki,ki->k", a, t_new)[:, None] * t_new
    return unit(a)


def reference_twist(
    a1: np.ndarray, t: np.ndarray, previous: np.ndarray | None = None
) -> np.ndarray:
    """Reference twist [rad] of the interior nodes, continued from ``previous`` (no 2 pi jumps)."""
    u = parallel_transport(a1[:-1], t[:-1], t[1:])
    angle = signed_angle(u, a1[1:], t[1:])
    if previous is None:
        return angle
    return previous + np.angle(np.exp(1j * (angle - previous)))


def material_frames(
    a1: np.ndarray, t: np.ndarray, theta: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(m1, m2) of each edge from its reference director, tangent and angle."""
    a2 = cross(t, a1)
    c = np.cos(theta)[:, None]
    s = np.sin(theta)[:, None]
    m1 = c * a1 + s * a2
    m2 = -s * a1 + c * a2
    return m1, m2


def perpendicular_director(t: np.ndarray, hint: np.ndarray | None = None) -> np.ndarray:
    """A unit vector normal to each tangent: the projection of ``hint`` (default: the axis least
    aligned with t)."""
    if hint is None:
        idx = np.argmin(np.abs(t), axis=1)
        hint = np.eye(3)[idx]
    hint = np.broadcast_to(hint, t.shape)
    a = hint - np.einsum("ki,ki->k", hint, t)[:, None] * t
    return unit(a)


def space_parallel_directors(t: np.ndarray, first: np.ndarray) -> np.ndarray:
    """Reference directors by space-parallel transport of ``first`` along the tangents (zero
    reference twist); used to initialise a rod."""
    a1 = np.empty_like(t)
    a1[0] = unit(first - np.dot(first, t[0]) * t[0])
    for k in range(1, len(t)):  # initialisation only, once per rod
        a1[k] = parallel_transport(a1[k - 1], t[k - 1], t[k])
    return a1
