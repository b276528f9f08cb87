"""The LCE strip with its embedded heater coil, in the as-built nematic state (seed 001).

Dimensions follow from the cast section and the isotropic active length by the isochoric
spontaneous stretch lambda_N along the strip axis (x):

    length L = L_iso lambda_N,  width W = W_cast / sqrt(lambda_N),
    thickness H = H_cast / sqrt(lambda_N).

The coil (Ni-Cr wire wound on a 1 mm rod, seed 001) runs along the axis; it is represented by a
central square prism of the same cross-sectional area as the rod's disc (pi/4 mm^2 as cast),
stretched with the strip. The cross-section is split at y = W/2 and z = H/2 (4 x 4 blocks) so that
its centre lines are mesh lines: the free strip's clamp uses them for symmetry constraints.

Both the body and the coil are symmetric about the planes y = W/2 and z = H/2; with
``symmetry="quarter"`` only the quarter y <= W/2, z <= H/2 is meshed (4x fewer unknowns, ~10x faster
factorisation), and those planes are tagged for symmetry conditions.

Tags (by name): cells "lce", "coil"; facets "clamp" (x = 0), "end" (x = L), "sides" (outer faces
parallel to the axis), and with quarter symmetry "sym_y" (y = W/2) and "sym_z" (z = H/2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mpi4py import MPI

from lcefem.meshes._gmsh import TaggedMesh, gmsh_session, to_dolfinx
from lcefem.meshes.communicator import resolve_comm
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param


@dataclass(frozen=True)
class StripGeometry:
    """Cast dimensions of the free LCE strip (seed 001) and its coil."""

    length_isotropic: float = param(
        80.0, "mm", "seed 001: active length 80 mm in the isotropic phase", positive=True
    )
    width_cast: float = param(5.0, "mm", "seed 001: mould channel 5 mm wide", positive=True)
    thickness_cast: float = param(2.0, "mm", "seed 001: mould channel 2 mm deep", positive=True)
    coil_diameter: float = param(1.0, "mm", "seed 001: coil wound on a 1 mm rod", positive=True)

    def as_built(self, lambda_N: float) -> dict:
        """As-built (nematic) dimensions [mm] for the nematic spontaneous stretch ``lambda_N``."""
        s = 1.0 / math.sqrt(lambda_N)
        coil_side = math.sqrt(math.pi) / 2.0 * self.coil_diameter * s  # same area as the disc
        return {
            "length": self.length_isotropic * lambda_N,
            "width": self.width_cast * s,
            "thickness": self.thickness_cast * s,
            "coil_side": coil_side,
            "length_isotropic": self.length_isotropic,
            "lambda_N": lambda_N,
        }


@dataclass(frozen=True)
class StripMesh:
    """Resolution of the strip mesh.

    Level 0 divides every block edge into ceil(length / size) elements (axially with size x
    axial_aspect); level l multiplies all those counts by l + 1, so the element size is
    size / (l + 1) and successive levels refine uniformly by 2, 1.5, 1.33, ... (>= 1.3 for the first
    four levels, as a grid-convergence study wants: Celik et al. 2008).
    """

    size: float = param(
        2.0, "mm", "chosen: level-0 element size of the convergence family", positive=True
    )
    axial_aspect: float = param(
        4.0, "-", "chosen: fields vary slowly along the uniform strip", positive=True
    )
    level: int = param(
        1, "-", "refinement level: element size = size / (level + 1)", minimum=0, maximum=8
    )
    cell: str = param("hex", "-", "'hex' (Q2) or 'tet' (P2)")
    symmetry: str = param(
        "quarter", "-", "'quarter' (mid-planes y = W/2, z = H/2 as symmetry planes) or 'full'"
    )

    def element_size(self) -> float:
        return self.size / (self.level + 1)


def _divisions(length: float, size: float, multiplier: int) -> int:
    """Elements on an edge of ``length``: ceil(length / size) at level 0, times the level
    multiplier."""
    return multiplier * max(1, int(math.ceil(length / size - 1e-9)))


def strip_mesh_counts(geometry: StripGeometry, lambda_N: float, resolution: StripMesh) -> dict:
    """Cells and quadratic (Q2/P2) nodes of :func:`build_strip_mesh`'s mesh, counted without
    building it (floats: a nonsense size gives a huge or infinite count rather than an overflow).
    Hexahedra exactly; tetrahedra: 6 per hexahedron (gmsh's split of a transfinite hexahedron),
    nodes as the hexahedra's (a lower bound: the diagonals add edge nodes)."""
    dims = geometry.as_built(lambda_N)
    L, W, H, c = dims["length"], dims["width"], dims["thickness"], dims["coil_side"]
    quarter = resolution.symmetry == "quarter"
    ys = [0.0, 0.5 * (W - c), 0.5 * W, 0.5 * (W + c), W][: 3 if quarter else 5]
    zs = [0.0, 0.5 * (H - c), 0.5 * H, 0.5 * (H + c), H][: 3 if quarter else 5]
    m = float(resolution.level + 1)

    def div(length: float, size: float) -> float:
        ratio = length / size if size > 0 else math.inf
        return m * max(1.0, math.ceil(ratio - 1e-9) if math.isfinite(ratio) else math.inf)

    nx = div(L, resolution.size * resolution.axial_aspect)
    ny = sum(div(b - a, resolution.size) for a, b in zip(ys[:-1], ys[1:]))
    nz = sum(div(b - a, resolution.size) for a, b in zip(zs[:-1], zs[1:]))
    return {
        "cells": nx * ny * nz * (6.0 if resolution.cell == "tet" else 1.0),
        "nodes": (2 * nx + 1) * (2 * ny + 1) * (2 * nz + 1),
    }


def build_strip_mesh(
    geometry: StripGeometry,
    lambda_N: float,
    resolution: StripMesh = StripMesh(),
    comm: MPI.Comm | None = None,
) -> TaggedMesh:
    """Structured gmsh mesh of the as-built strip (hexahedra, or each hexahedron split into
    tetrahedra).

    Returns a :class:`TaggedMesh` whose ``info`` holds the as-built dimensions and the element size.
    """
    comm = resolve_comm(comm)
    check(geometry, "geometry")
    check(resolution, "mesh")
    if resolution.cell not in ("hex", "tet"):
        raise InputError(f"mesh.cell = {resolution.cell!r}: allowed 'hex' or 'tet'")
    if resolution.symmetry not in ("quarter", "full"):
        raise InputError(f"mesh.symmetry = {resolution.symmetry!r}: allowed 'quarter' or 'full'")
    quarter = resolution.symmetry == "quarter"
    dims = geometry.as_built(lambda_N)
    L, W, H, c = dims["length"], dims["width"], dims["thickness"], dims["coil_side"]
    if not c < min(W, H):
        raise InputError(
            f"geometry.coil_diameter = {geometry.coil_diameter} mm: coil must fit in the section"
        )
    h = resolution.element_size()
    size, multiplier = resolution.size, resolution.level + 1
    ys = [0.0, 0.5 * (W - c), 0.5 * W, 0.5 * (W + c), W]
    zs = [0.0, 0.5 * (H - c), 0.5 * H, 0.5 * (H + c), H]
    if quarter:
        ys, zs = ys[:3], zs[:3]
    nx = _divisions(L, size * resolution.axial_aspect, multiplier)

    with gmsh_session("strip") as model:
        if comm.rank == 0:
            occ = model.occ
            boxes = []
            for j in range(len(ys) - 1):
                for k in range(len(zs) - 1):
                    tag = occ.addBox(0.0, ys[j], zs[k], L, ys[j + 1] - ys[j], zs[k + 1] - zs[k])
                    boxes.append((3, tag))
            occ.fragment(boxes, [])
            occ.synchronize()
            vols = [t for _, t in model.getEntities(3)]
            coil_vols, lce_vols = [], []
            for v in vols:
                _, y, z = occ.getCenterOfMass(3, v)
                (
                    coil_vols
                    if abs(y - 0.5 * W) < 0.5 * c and abs(z - 0.5 * H) < 0.5 * c
                    else lce_vols
                ).append(v)
            # Transfinite (structured) divisions: every curve gets the count its length asks for.
            tol = 1e-4 * min(W, H)  # OCC bounding boxes are padded by its tolerance
            for _, curve in model.getEntities(1):
                xmin, ymin, zmin, xmax, ymax, zmax = model.getBoundingBox(1, curve)
                if xmax - xmin > tol:
                    n = nx
                else:
                    n = _divisions(max(ymax - ymin, zmax - zmin), size, multiplier)
                model.mesh.setTransfiniteCurve(curve, n + 1)
            for _, surf in model.getEntities(2):
                model.mesh.setTransfiniteSurface(surf)
                if resolution.cell == "hex":
                    model.mesh.setRecombine(2, surf)
            for v in vols:
                model.mesh.setTransfiniteVolume(v)
                if resolution.cell == "hex":
                    model.mesh.setRecombine(3, v)
            names = ["clamp", "end", "sides"] + (["sym_y", "sym_z"] if quarter else [])
            faces = {n: [] for n in names}
            y_out, z_out = ((0.0,), (0.0,)) if quarter else ((0.0, W), (0.0, H))
            for _, surf in model.getEntities(2):
                xmin, ymin, zmin, xmax, ymax, zmax = model.getBoundingBox(2, surf)
                y0, z0 = 0.5 * (ymin + ymax), 0.5 * (zmin + zmax)
                if xmax - xmin < tol:
                    faces["clamp" if xmax < 0.5 * L else "end"].append(surf)
                elif ymax - ymin < tol and any(abs(y0 - v) < tol for v in y_out):
                    faces["sides"].append(surf)
                elif zmax - zmin < tol and any(abs(z0 - v) < tol for v in z_out):
                    faces["sides"].append(surf)
                elif quarter and ymax - ymin < tol and abs(y0 - 0.5 * W) < tol:
                    faces["sym_y"].append(surf)
                elif quarter and zmax - zmin < tol and abs(z0 - 0.5 * H) < tol:
                    faces["sym_z"].append(surf)
            model.addPhysicalGroup(3, lce_vols, 1, "lce")
            model.addPhysicalGroup(3, coil_vols, 2, "coil")
            for tag, name in enumerate(names, start=1):
                model.addPhysicalGroup(2, faces[name], tag, name)
            model.mesh.generate(3)
        data, cells, facets = to_dolfinx(model, comm)

    info = dict(dims)
    info.update(
        {
            "element_size": h,
            "axial_element_size": L / nx,
            "cell": resolution.cell,
            "level": resolution.level,
            "coil_area": c * c,
            "symmetry": resolution.symmetry,
            "symmetry_factor": 4 if quarter else 1,
        }
    )
    return TaggedMesh(data.mesh, data.cell_tags, data.facet_tags, cells, facets, info)


def strip_volume(dims: dict) -> float:
    """Volume [mm^3] of the whole as-built strip: L W H (equal to the cast volume, by isochory)."""
    return dims["length"] * dims["width"] * dims["thickness"]
