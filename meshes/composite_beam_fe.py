"""The continuum (FE) mesh of the composite beam of seed 001 (Fig. 3): a structured hexahedral (Q2)
mesh of the Kapton ribbon, the LCE strips and their bond pads, with cell and facet tags, on the
geometry :class:`lcefem.meshes.composite_beam.CompositeBeamGeometry` shares with the bar-and-hinge
structure (:func:`lcefem.meshes.composite_beam.build_beam_bar_hinge`).

Coordinates [mm] as in :mod:`lcefem.meshes.composite_beam`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lcefem.meshes._hexgrid import divisions as hex_divisions
from lcefem.meshes._hexgrid import exterior_faces, tagged_hex_mesh
from lcefem.meshes.communicator import resolve_comm
from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param

#: Cell tags of the FE beam (by name).
FE_CELLS = ("kapton", "bottom_strips", "bottom_pads", "top_strips", "top_pads")
#: Facet tags of the FE beam (by name): free faces of the ribbon and of the strips where they are
#: not bonded, the symmetry planes and every other exterior face ("surface").
FE_FACETS = (
    "ribbon_top",
    "ribbon_bottom",
    "top_strip_underside",
    "bottom_strip_topside",
    "surface",
    "sym_x",
    "sym_y",
)


@dataclass(frozen=True)
class BeamFEMesh:
    """Structured hexahedral (Q2) mesh of the composite beam and the FE-only representation choices.

    Level l multiplies the level-0 in-plane element counts (``ceil(length/size)`` on every piece:
    flank, crown, junction, tab, and across the width) by l + 1; the through-thickness counts are
    fixed (``ribbon_layers``, ``strip_layers``): one Q2 element through a layer already represents
    a linear strain through it (membrane plus bending), and refining them too would make the finest
    level of a 4-level study unaffordable. At (lambda_T, lambda_B) = (1.33, 1.05), level 0, two
    ribbon layers change the curvature by less than 1e-6 relative and two strip layers by +0.07 %.
    """

    size: float = param(
        3.0,
        "mm",
        "chosen: level-0 in-plane element size (levels 0-3: 3, 1.5, 1, 0.75 mm)",
        positive=True,
    )
    level: int = param(
        1, "-", "refinement level: in-plane element size = size / (level + 1)", minimum=0, maximum=8
    )
    ribbon_layers: int = param(
        1, "-", "chosen: Q2 elements through the 0.127 mm ribbon", minimum=1, maximum=8
    )
    strip_layers: int = param(
        1, "-", "chosen: Q2 elements through each LCE strip", minimum=1, maximum=8
    )
    symmetry: str = param(
        "quarter",
        "-",
        "'quarter' (mid-planes x = total_length/2 and y = width/2 "
        "as symmetry planes) or 'half' (y = width/2 only)",
    )
    end_tab: float = param(
        3.5,
        "mm",
        "chosen: a flat ribbon tab of half a junction at each beam "
        "end, under which the first and last bottom strips are bonded (as the "
        "others are under the junctions); the bar-and-hinge chords attach at the "
        "end edges instead",
        positive=True,
    )

    def element_size(self) -> float:
        return self.size / (self.level + 1)

    def checked(self) -> "BeamFEMesh":
        check(self, "mesh")
        if self.symmetry not in ("quarter", "half"):
            raise InputError(f"mesh.symmetry = {self.symmetry!r}: allowed 'quarter' or 'half'")
        for name in ("level", "ribbon_layers", "strip_layers"):
            if not isinstance(getattr(self, name), int):
                raise InputError(f"mesh.{name} = {getattr(self, name)!r}: must be an integer")
        return self


def beam_pieces(g: CompositeBeamGeometry, tab: float) -> list[tuple[float, float, str, int]]:
    """(x0, x1, kind, segment or junction index) along the beam: tab, flank, crown, flank, junction,
    ..."""
    s_lo, s_hi = g.crown_edges
    pieces = [(-tab, 0.0, "tab", -1)]
    for s in range(g.segments):
        x0 = g.segment_start(s)
        pieces += [
            (x0, x0 + s_lo, "flank", s),
            (x0 + s_lo, x0 + s_hi, "crown", s),
            (x0 + s_hi, x0 + g.segment_length, "flank", s),
        ]
        if s + 1 < g.segments:
            pieces.append((x0 + g.segment_length, g.segment_start(s + 1), "junction", s))
    pieces.append((g.total_length, g.total_length + tab, "tab", g.segments))
    return pieces


def fe_stations(geometry: CompositeBeamGeometry) -> list[list[tuple[float, float, float]]]:
    """Reference points [mm] whose deformed mean is each curvature station, in the order of
    :func:`beam_stations`: the centre of the left end (x = 0), each junction's centre (its two
    edges on the ribbon's mid-surface), the centre of the right end. Points lie on the ribbon's
    mid-surface at y = 0; by symmetry about y = width/2 the mean over the ribbon's two edges has
    the same x and z, so these give the same stations as the bar-and-hinge corners."""
    g = geometry
    pts = [[(0.0, 0.0, 0.0)]]
    for j in range(g.segments - 1):
        x0 = g.segment_start(j) + g.segment_length
        pts.append([(x0, 0.0, 0.0), (x0 + g.junction_length, 0.0, 0.0)])
    pts.append([(g.total_length, 0.0, 0.0)])
    return pts


def build_beam_fe(
    geometry: CompositeBeamGeometry, lambda_N: float, mesh: BeamFEMesh = BeamFEMesh(), comm=None
):
    """Hexahedral mesh of the as-built (nematic) composite beam with bonds where the published model
    connects strips and ribbon, and separate (unbonded) faces elsewhere.

    Bodies (x along the beam, y across, z up; the ribbon's mid-surface on the arch
    z = gap sin^2(pi s/L) of each segment, flat at junctions and tabs):

    * ribbon (cells "kapton"), thickness t_p;
    * bottom LCE layer under the ribbon, flat, z in [-t_p/2 - H, -t_p/2]: the strips
      ("bottom_strips", the 30 mm chords under the segments) and their bond pads ("bottom_pads",
      under the junctions and end tabs, sharing their faces with the ribbon: the glue);
    * top LCE layer: pads on the crowns ("top_pads", following the arch, bonded) and strips
      ("top_strips", flat at the crown-edge height, from crown edge to crown edge over a junction:
      11.5 + 7 + 11.5 = 30 mm, the published top-strip span).

    The strips are centred on the ribbon, with the as-built section of the cast one, W_s x H =
    (w_a x t_a)/sqrt(lambda_N) (isochoric spontaneous stretch). A strip's free face and the ribbon
    face over it have their own nodes (they touch only along the bond edges), so nothing but a
    contact term keeps them apart (:mod:`lcefem.solvers.contact`).

    A tensor-product grid (shared x and y stations for all bodies) is built here directly rather
    than with gmsh: gmsh's fragment merges every pair of coincident faces, whereas the unbonded
    strip faces must keep their own nodes; the shared stations also give the contact pairs.
    Geometry is trilinear (hex8): the arch is a polyline at the element size.

    Tags by name: cells :data:`FE_CELLS`; facets :data:`FE_FACETS` (only the symmetry planes the
    model has). ``info`` holds the as-built dimensions, the station points (:func:`fe_stations`),
    the mid-plane ``x_mid`` and ``symmetry_factor`` (forces and volumes of the whole beam are this
    times the mesh's).
    """
    import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

    comm = resolve_comm(comm)
    g = geometry.checked()
    m = mesh.checked()
    if not (isinstance(lambda_N, (int, float)) and lambda_N >= 1.0):
        raise InputError(f"lambda_N = {lambda_N}: must be >= 1")
    quarter = m.symmetry == "quarter"
    mult = m.level + 1
    tp, W = g.ribbon_thickness, g.ribbon_width
    ws, H = g.strip_width / math.sqrt(lambda_N), g.strip_thickness / math.sqrt(lambda_N)
    if not ws < W:
        raise InputError(
            f"geometry.strip_width = {g.strip_width} mm: the as-built strip must be "
            f"narrower than the ribbon ({W} mm)"
        )
    x_mid = 0.5 * g.total_length
    pieces = beam_pieces(g, m.end_tab)
    if quarter:
        kept = []
        for x0, x1, kind, idx in pieces:
            if x1 > x_mid + 1e-9:
                kept.append((max(x0, x_mid), x1, kind, idx))
        pieces = kept

    def divisions(length: float) -> int:
        return hex_divisions(length, m.size, mult)

    # x stations and, per x cell, the piece kind
    xs, cell_kind = [pieces[0][0]], []
    for x0, x1, kind, _ in pieces:
        n = divisions(x1 - x0)
        xs.extend(np.linspace(x0, x1, n + 1)[1:])
        cell_kind += [kind] * n
    xs = np.asarray(xs)
    cell_kind = np.asarray(cell_kind)
    nxc = cell_kind.size
    # per station: arch height, bonded below (touches a tab/junction), bonded above (touches a
    # crown)
    arch = np.zeros(xs.size)
    for s in range(g.segments):
        x0 = g.segment_start(s)
        inside = (xs >= x0 - 1e-9) & (xs <= x0 + g.segment_length + 1e-9)
        arch[inside] = g.arch_height(np.clip(xs[inside] - x0, 0.0, g.segment_length))
    touches = lambda kinds: np.array(
        [any(cell_kind[c] in kinds for c in (i - 1, i) if 0 <= c < nxc) for i in range(xs.size)]
    )
    bonded_bottom = touches(("tab", "junction"))
    bonded_top = touches(("crown",))
    # the top layer spans from the first crown's start to the last crown's end
    s_lo, s_hi = g.crown_edges
    top_lo, top_hi = s_lo, g.segment_start(g.segments - 1) + s_hi
    xc = 0.5 * (xs[:-1] + xs[1:])
    top_cell = (xc > top_lo) & (xc < top_hi)
    z_c = g.top_strip_height

    # y stations: ribbon edge part | strip part (| strip part | edge part)
    y_a = 0.5 * (W - ws)
    y_parts = [(0.0, y_a), (y_a, 0.5 * W)]  # both models keep y <= W/2 (symmetry plane y = W/2)
    ys = [0.0]
    strip_y_cell = []
    for k, (y0, y1) in enumerate(y_parts):
        n = divisions(y1 - y0)
        ys.extend(np.linspace(y0, y1, n + 1)[1:])
        strip_y_cell += [k >= 1] * n
    ys = np.asarray(ys)
    strip_y_cell = np.asarray(strip_y_cell)
    nyc = strip_y_cell.size
    nb, nr, nt = m.strip_layers, m.ribbon_layers, m.strip_layers
    k_rb, k_rt = nb, nb + nr  # node layers of the ribbon's bottom and top faces

    ids: dict[tuple[int, int, int, str], int] = {}
    coords: list[tuple[float, float, float]] = []

    def node(i: int, j: int, k: int, body: str) -> int:
        if body == "b" and k == k_rb and bonded_bottom[i]:
            body = "r"
        elif body == "t" and k == k_rt and bonded_top[i]:
            body = "r"
        key = (i, j, k, body)
        found = ids.get(key)
        if found is not None:
            return found
        if body == "r":
            z = arch[i] + tp * (-0.5 + (k - k_rb) / nr)
        elif body == "b":
            z = -0.5 * tp - H * (k_rb - k) / nb
        else:
            base = arch[i] + 0.5 * tp if bonded_top[i] else z_c + 0.5 * tp
            z = base + H * (k - k_rt) / nt
        ids[key] = len(coords)
        coords.append((xs[i], ys[j], z))
        return ids[key]

    cells, cell_values, cell_body = [], [], []
    tag = {name: n for n, name in enumerate(FE_CELLS, start=1)}

    def add_cell(i: int, j: int, k: int, body: str, name: str) -> None:
        cells.append(
            [node(i + a, j + b, k + c, body) for c in (0, 1) for b in (0, 1) for a in (0, 1)]
        )
        cell_values.append(tag[name])
        cell_body.append(body)

    for i in range(nxc):
        kind = cell_kind[i]
        for j in range(nyc):
            for k in range(k_rb, k_rt):
                add_cell(i, j, k, "r", "kapton")
            if not strip_y_cell[j]:
                continue
            for k in range(0, k_rb):
                add_cell(
                    i, j, k, "b", "bottom_pads" if kind in ("tab", "junction") else "bottom_strips"
                )
            if top_cell[i]:
                for k in range(k_rt, k_rt + nt):
                    add_cell(i, j, k, "t", "top_pads" if kind == "crown" else "top_strips")
    cells = np.asarray(cells, dtype=np.int64)
    x = np.asarray(coords, dtype=np.float64)

    # Exterior faces (used by one cell) and their names, from the owning cell's body and side.
    faces, sides, owner = exterior_faces(cells)
    ftag = {name: n for n, name in enumerate(FE_FACETS, start=1)}
    facet_values = []
    tol = 1e-9 * g.total_length
    for f in range(faces.shape[0]):
        side, body = sides[f], cell_body[owner[f]]
        pts = x[faces[f]]
        if quarter and np.all(np.abs(pts[:, 0] - x_mid) < tol):
            name = "sym_x"
        elif np.all(np.abs(pts[:, 1] - 0.5 * W) < tol):
            name = "sym_y"
        elif body == "r" and side in ("+z", "-z"):
            name = "ribbon_top" if side == "+z" else "ribbon_bottom"
        elif body == "t" and side == "-z":
            name = "top_strip_underside"
        elif body == "b" and side == "+z":
            name = "bottom_strip_topside"
        else:
            name = "surface"
        facet_values.append(ftag[name])
    info = {
        "segments": g.segments,
        "total_length": g.total_length,
        "x_mid": x_mid,
        "symmetry": m.symmetry,
        "symmetry_factor": 4 if quarter else 2,
        "ribbon_thickness": tp,
        "ribbon_width": W,
        "strip_width": ws,
        "strip_thickness": H,
        "strip_y_range": (y_a, W - y_a),
        "top_strip_height": z_c,
        "lambda_N": float(lambda_N),
        "element_size": m.element_size(),
        "level": m.level,
        "end_tab": m.end_tab,
        "stations": fe_stations(g),
        "cells": int(cells.shape[0]),
        "nodes": int(x.shape[0]),
    }
    return tagged_hex_mesh(
        comm, cells, x, np.asarray(cell_values), faces, np.asarray(facet_values), tag, ftag, info
    )
