"""A twisted ribbon: the straight strip [0, L] x [-w/2, w/2] x [-t/2, t/2] mapped onto a helicoid of
twist rate tau [rad/mm] about the x axis (seed 000, 'Manufacturing the twisting ribbon robot': a
stretched strip twisted and then cross-linked, so the helicoid is the stress-free reference):

    X = (x, y cos(tau x) - z sin(tau x), y sin(tau x) + z cos(tau x)).

The mesh is a structured block (hexahedra or tetrahedra, trilinear geometry) whose nodes are mapped;
a straight strip is tau = 0. Tags (by name): cells "body"; facets "x0", "x1" (the ends), "y0", "y1"
(the long edges), "z0", "z1" (the faces at -t/2 and +t/2 before twisting).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mpi4py import MPI

import numpy as np

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.meshes.block import build_block
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param


@dataclass(frozen=True)
class TwistedRibbonMesh:
    """Resolution of the ribbon mesh; level l multiplies the level-0 divisions by l + 1."""

    along: int = param(
        120,
        "-",
        "chosen: level-0 elements along the length (0.5 mm: a 0.05 turns/mm "
        "helicoid turns by 9 degrees per trilinear element)",
        minimum=1,
    )
    across: int = param(4, "-", "chosen: level-0 elements across the width", minimum=1)
    through: int = param(
        1, "-", "chosen: level-0 quadratic elements through the thickness", minimum=1
    )
    level: int = param(0, "-", "refinement level: divisions x (level + 1)", minimum=0, maximum=6)
    cell: str = param("hex", "-", "'hex' (Q2) or 'tet' (P2)")


def helicoid(points: np.ndarray, twist_rate: float) -> np.ndarray:
    """Map straight-strip coordinates (n, 3) [mm] onto the helicoid of ``twist_rate`` [rad/mm]."""
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    c, s = np.cos(twist_rate * x), np.sin(twist_rate * x)
    return np.column_stack([x, y * c - z * s, y * s + z * c])


def build_twisted_ribbon(
    length: float,
    width: float,
    thickness: float,
    twist_rate: float,
    resolution: TwistedRibbonMesh = TwistedRibbonMesh(),
    comm: MPI.Comm | None = None,
) -> TaggedMesh:
    """Structured mesh of the twisted ribbon (lengths in mm, twist rate in rad/mm)."""
    check(resolution, "mesh")
    if not math.isfinite(twist_rate):
        raise InputError(f"twist_rate = {twist_rate}: must be finite")
    m = resolution.level + 1
    tm = build_block(
        (length, width, thickness),
        (resolution.along * m, resolution.across * m, resolution.through * m),
        resolution.cell,
        comm,
    )
    x = tm.mesh.geometry.x
    x[:, 1] -= 0.5 * width
    x[:, 2] -= 0.5 * thickness
    x[:, :] = helicoid(x, twist_rate)
    tm.info.update(
        {
            "length": length,
            "width": width,
            "thickness": thickness,
            "twist_rate": twist_rate,
            "element_size": length / (resolution.along * m),
            "level": resolution.level,
        }
    )
    return tm
