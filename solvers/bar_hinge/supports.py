"""Supports of bar-and-hinge structures as held DOF indices (into flattened positions (3n,))."""

from __future__ import annotations

import numpy as np

from lcefem.models.errors import InputError

_AXES = {"x": 0, "y": 1, "z": 2}


def held_dofs(nodes, axes: str = "xyz") -> np.ndarray:
    """DOF indices of ``nodes`` along ``axes`` (any of "x", "y", "z"), e.g. a roller: axes="z"."""
    if not axes or any(a not in _AXES for a in axes):
        raise InputError(f"axes = {axes!r}: use a combination of 'x', 'y', 'z'")
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    return np.sort(np.concatenate([3 * nodes + _AXES[a] for a in axes]))


def isostatic_supports(a: int, b: int, c: int) -> np.ndarray:
    """Six DOFs that remove the rigid-body motions and nothing else (no reactions at equilibrium):
    node a held in x, y, z; node b (a's neighbour across the ribbon) in x and z; node c (a's
    neighbour along the beam) in z. a, b, c must not be collinear."""
    return np.sort(
        np.concatenate([held_dofs([a], "xyz"), held_dofs([b], "xz"), held_dofs([c], "z")])
    )
