"""The robotic surface of seed 001 (Fig. 4) as a 3D continuum: a hexahedral (Q2-ready) mesh of the
n x n gridshell of Kapton ribbons with bottom and top LCE strips, with the dimensions of the FE
composite beam (:func:`lcefem.meshes.composite_beam_fe.build_beam_fe`,
:class:`CompositeBeamGeometry`) and the layout and connectivity of the published reduced-order model
(shared/reference/gridshell_recipes.md, published_reduced_model.md).

Made by gmsh (``GridshellFEMesh.mesher = "gmsh"``, the default since issue 47;
:mod:`lcefem.meshes.gridshell_fe_gmsh`: one transfinite, recombined block of gmsh's built-in kernel
per piece and layer of the plan below) or built directly as a tensor-product hex grid
(``"hexgrid"``, :mod:`lcefem.meshes._hexgrid`). Both give the same vertices, cells and tags:
unbonded strip faces keep their own nodes, and strips and ribbons share (x, y) stations for the
node-pair contact.

Coordinates [mm], z up (the top strips' side), z = 0 the flat Kapton grid's mid-surface. n ribbons
run along x and n along y; each has n + 1 segments of length L joined by n junction squares d x d
(d = ribbon width = junction length), plus a flat end tab (``GridshellFEMesh.end_tab``, as the FE
beam) under which the end bottom strips are bonded. Ribbon r (0-based) occupies the band
[c_r - d/2, c_r + d/2], c_r = L + d/2 + r (L + d): for n = 3, L = 30, d = 7 the bands [30, 37],
[67, 74], [104, 111], ribbons 141 mm (plus the tabs), centre c = 70.5. Every segment carries the
arch z = gap sin^2(pi s/L) of the ribbon along it; junctions and tabs are flat.

Bodies (as the FE beam, per ribbon; the strips have the as-built section
W_s x H = (w_a x t_a)/sqrt(lambda_N), centred on their ribbon):

* "kapton": every ribbon and junction, one body; the crossing ribbons share the junction squares.
* bottom layer (flat, z in [-t_p/2 - H, -t_p/2]): bottom strips, one per segment, junction edge to
  junction edge (or tab to junction), free on top (contact); "bottom_pads" bonded under the tabs and
  under each junction, where they form a cross (the x and y strips' pads meet under the junction).
* top layer: "top_pads" bonded on each segment's crown (central ``crown_bond_length``, following the
  arch); top strips flat at the crown-edge height z_c = 0.982 mm from a crown edge over a junction
  to the next crown edge (11.5 + 7 + 11.5 = 30 mm, the published span), free underneath (contact).

**Where the x and y top strips cross** (over every junction) they cannot share volume: the
W_s x W_s square where their bands overlap is a "glue" block at the strips' height (z_c), bonded to
both strips and not to the junction below (the published model's raised square, 0.982 mm above the
junction, not attached to the ribbon). Each top strip is LCE up to that square: 2 (L - s_c) + d -
W_s = 25.8 mm of its 30 mm at lambda_N = 1.4 (the published model: 23 mm LCE + 7 mm glue; the FE
beam: 30 mm LCE). The corners of the d x d junction outside both strip bands carry no top material.

**Tags by name.** One cell tag per LCE piece that can be driven on its own (0-based r, s, j):

* ``bottom_{x|y}_r{r}_s{s}``: bottom strip under segment s of the x (or y) ribbon r; 2 n (n + 1).
* ``top_{x|y}_r{r}_j{j}_{lo|hi}``: the half of the top strip over junction j of ribbon r on the
  lower (``lo``: segment j, 11.5 mm + the 1.4 mm arm to the glue square) or higher (``hi``: segment
  j + 1) side; 4 n^2 halves of 2 n^2 strips. Halves, because the published recipes drive the
  11.5 mm pieces on either side of a junction separately (wave and dustpan split at x = 70.5, which
  is a junction centre).
* "kapton", "glue", "bottom_pads", "top_pads": one tag each (passive bodies).

``info["cell_groups"]`` maps group names to tuples of cell tags (``dx(tags)`` integrates over the
union; :func:`cell_group`): materials "kapton", "glue", "bottom_pads", "top_pads", "bottom_strips",
"top_strips"; the paper's channels (Fig. 4A) "Bx" = all ``bottom_x_*``, "By" = ``bottom_y_*``,
"Tx" = ``top_x_*``, "Ty" = ``top_y_*``; the published groups "XD{r+1}" = ``bottom_x_r{r}_*``,
"YD{r+1}" = ``bottom_y_r{r}_*``, "XU{r+1}" = ``top_x_r{r}_*``, "YU{r+1}" = ``top_y_r{r}_*`` (ribbon
1 at the lowest y for x ribbons, lowest x for y ribbons); whole top strips ``top_{d}_r{r}_j{j}``
(both halves: the published model's 2 n^2 = 18 top strips); the paper's top segments
``top_{d}_r{r}_s{s}`` = the halves lying over segment s (``j{s-1}_hi`` and ``j{s}_lo``): the paper
counts one top segment per ribbon segment (24 top, 48 LCE segments for n = 3); the outer halves of
the end segments carry no top strip, so its end top segments are the single halves ``j0_lo`` /
``j{n-1}_hi``. ``info["strips"]`` gives each strip tag's layer, direction, ribbon, index, side,
group, channel and as-built midpoint (x, y) of the whole (uncut) piece, for half-plane selections.

Facets: "ribbon_top", "ribbon_bottom" (free Kapton faces), "top_strip_underside" (top strips and
glue squares, free), "bottom_strip_topside" (free), "ribbon_ends_x" / "ribbon_ends_y" (the
perimeter end faces of the x / y ribbons: roller supports), "centre_junction" (top face of the
centre junction, odd n only: the saddle's clamp; its corners' mid-surface points are
``info["centre_junction_corners"]``), "sym_x" / "sym_y" (mirror planes x = c, y = c), "surface".

**Symmetry.** ``symmetry``: "quarter" (mirror planes x = c and y = c, keeps x >= c, y >= c),
"half_x" (mirror plane x = c), "half_y" (y = c), "full". A mirror model is valid only when the
actuation is mirror-symmetric too (and a symmetric solution is sought: a symmetry-breaking
bifurcation needs the full model). The recipes of gridshell_recipes.md, with per-ribbon groups
(ribbon 1 <-> n under y -> 2c - y) and half-plane selections (x < 70.5 <-> x > 70.5 under
x -> 2c - x); the supports (8 perimeter rollers, the saddle's centre-junction clamp, a table) are
symmetric under both mirrors:

    ======== ============== ============== ==========================================
    recipe   x -> 2c - x    y -> 2c - y    smallest valid model (RECIPE_SYMMETRY)
    ======== ============== ============== ==========================================
    saddle   yes            yes            quarter
    dome     yes            yes            quarter (x <-> y too: an eighth, not built)
    cylinder yes            yes            quarter
    table    yes            yes            quarter (x <-> y too: an eighth, not built)
    cone     yes            no (XD1, XD3)  half_x
    twisted  yes            no (XD, XU)    half_x (y -> 2c - y with top <-> bottom is a
                                           symmetry of the loads, not of the body)
    wave     no (x < c)     yes            half_y
    dustpan  no (x < c)     yes            half_y
    ======== ============== ============== ==========================================

For even n the mirror planes cut the segments through their crowns (no centre junction).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from lcefem.meshes._hexgrid import divisions, exterior_faces, tagged_hex_mesh
from lcefem.meshes.communicator import resolve_comm
from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.composite_beam_fe import BeamFEMesh, beam_pieces
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param

DIRECTIONS = ("x", "y")
#: symmetry -> (mirror plane x = c, mirror plane y = c)
SYMMETRIES = {
    "quarter": (True, True),
    "half_x": (True, False),
    "half_y": (False, True),
    "full": (False, False),
}
#: The smallest valid model of each published recipe (module docstring).
RECIPE_SYMMETRY = {
    "saddle": "quarter",
    "dome": "quarter",
    "cylinder": "quarter",
    "table": "quarter",
    "cone": "half_x",
    "twisted": "half_x",
    "wave": "half_y",
    "dustpan": "half_y",
}
#: The paper's four control channels (seed 001, Fig. 4A): (layer, direction).
CHANNELS = {"Tx": ("top", "x"), "Ty": ("top", "y"), "Bx": ("bottom", "x"), "By": ("bottom", "y")}
#: Passive bodies, one cell tag each.
MATERIAL_CELLS = ("kapton", "glue", "bottom_pads", "top_pads")
#: Facet tags (by name).
FE_FACETS = (
    "ribbon_top",
    "ribbon_bottom",
    "top_strip_underside",
    "bottom_strip_topside",
    "ribbon_ends_x",
    "ribbon_ends_y",
    "centre_junction",
    "sym_x",
    "sym_y",
    "surface",
)

#: The two builders of the same mesh (GridshellFEMesh.mesher).
MESHERS = ("gmsh", "hexgrid")

_BEAM = BeamFEMesh()


@dataclass(frozen=True)
class GridshellFEMesh:
    """Structured hexahedral discretisation of the gridshell: the FE beam's choices
    (:class:`~lcefem.meshes.composite_beam_fe.BeamFEMesh`; its symmetry is the builder's argument
    here). Level l multiplies every piece's level-0 in-plane element count (``ceil(length/size)``)
    by l + 1 (nested levels); the through-thickness counts are fixed, as in the beam."""

    size: float = param(
        _BEAM.size,
        "mm",
        "as the FE composite beam (BeamFEMesh.size): level-0 in-plane element size",
        positive=True,
    )
    level: int = param(
        _BEAM.level,
        "-",
        "as the FE beam (BeamFEMesh.level): refinement level, "
        "in-plane element size = size / (level + 1); the 3 x 3 quarter has ~5x the "
        "beam quarter's DOFs at the same level (97k Q2 DOFs at level 1)",
        minimum=0,
        maximum=8,
    )
    ribbon_layers: int = param(
        _BEAM.ribbon_layers,
        "-",
        "as the FE beam (BeamFEMesh.ribbon_layers): Q2 elements through the ribbon",
        minimum=1,
        maximum=8,
    )
    strip_layers: int = param(
        _BEAM.strip_layers,
        "-",
        "as the FE beam (BeamFEMesh.strip_layers): Q2 elements through each LCE strip",
        minimum=1,
        maximum=8,
    )
    end_tab: float = param(
        _BEAM.end_tab,
        "mm",
        "as the FE beam (BeamFEMesh.end_tab): flat ribbon "
        "tab at each ribbon end, under which the end bottom strips are bonded",
        positive=True,
    )
    mesher: str = param(
        "gmsh",
        "-",
        "'gmsh' (meshes.gridshell_fe_gmsh: blocks of gmsh's built-in "
        "kernel, transfinite and recombined) or 'hexgrid' (the structured grid built "
        "directly, before issue 47); both give the same vertices, cells and tags",
    )
    shear_angle: float = param(
        90.0,
        "deg",
        "angle between the two ribbon families (gmsh mesher; 90: "
        "seed 001's orthogonal grid; another angle: the rhombic layout, "
        "meshes.gridshell_layout, a full model only)",
        minimum=30.0,
        maximum=150.0,
    )

    def element_size(self) -> float:
        """In-plane element size [mm] at this level."""
        return self.size / (self.level + 1)

    def checked(self) -> "GridshellFEMesh":
        check(self, "mesh")
        if self.mesher not in MESHERS:
            raise InputError(f"mesh.mesher = {self.mesher!r}: allowed {', '.join(MESHERS)}")
        if self.shear_angle != 90.0 and self.mesher != "gmsh":
            raise InputError(
                f"mesh.shear_angle = {self.shear_angle}: only with mesh.mesher = 'gmsh'"
            )
        for name in ("level", "ribbon_layers", "strip_layers"):
            if not isinstance(getattr(self, name), int):
                raise InputError(f"mesh.{name} = {getattr(self, name)!r}: must be an integer")
        return self


# --------------------------------------------------------------------------- names
def bottom_strip_name(direction: str, ribbon: int, segment: int) -> str:
    """Cell tag name of the bottom strip under ``segment`` of ribbon ``ribbon`` (0-based)."""
    return f"bottom_{direction}_r{ribbon}_s{segment}"


def top_strip_name(direction: str, ribbon: int, junction: int, side: str) -> str:
    """Cell tag name of the ``side`` ("lo"/"hi") half of the top strip over ``junction``."""
    return f"top_{direction}_r{ribbon}_j{junction}_{side}"


def fe_strip_tags(strip) -> tuple[str, ...]:
    """The FE cell tags of one bar-and-hinge strip (:class:`lcefem.meshes.gridshell.Strip`: layer,
    direction, 0-based ribbon and index): a bottom strip under segment s is
    ``bottom_{d}_r{r}_s{s}``; a top strip over junction j is the two halves
    ``top_{d}_r{r}_j{j}_lo`` and ``_hi`` (both meshes count ribbons from the lowest y for x ribbons,
    the lowest x for y ribbons, and segments and junctions from the lowest coordinate)."""
    if strip.layer == "bottom":
        return (bottom_strip_name(strip.direction, strip.ribbon, strip.index),)
    if strip.layer == "top":
        d, r, j = strip.direction, strip.ribbon, strip.index
        return tuple(top_strip_name(d, r, j, side) for side in ("lo", "hi"))
    raise InputError(f"strip {strip.id}: layer {strip.layer!r}: allowed bottom, top")


def fe_lambdas_of_strips(strips, lambdas: dict) -> dict[str, float]:
    """``{FE strip tag: lambda [-]}`` of lambdas per bar-and-hinge strip id (``lambdas``: {id:
    lambda}; ``strips``: the structure's ``info["strips"]``), for the FE run's ``--lambda`` (which
    refuses the bar-and-hinge strip ids). Every strip of ``strips`` must have a lambda."""
    out = {}
    for s in strips:
        if s.id not in lambdas:
            raise InputError(f"lambda of strip {s.id}: missing (every strip needs one)")
        for tag in fe_strip_tags(s):
            out[tag] = float(lambdas[s.id])
    extra = set(lambdas) - {s.id for s in strips}
    if extra:
        raise InputError(f"lambda of strip {min(extra)}: no such strip (ids 0..{len(strips) - 1})")
    return out


def strip_catalogue(geometry: CompositeBeamGeometry, cells: int, strip_width: float) -> dict:
    """Every LCE strip tag of the full n x n model, in tag order, with its facts:
    layer, direction, ribbon, index (segment or junction), side (top halves), group ("XD1"),
    channel ("Bx"), paper segment (the ribbon segment it lies on), as-built midpoint (x, y) [mm]."""
    g, n = geometry, cells
    centres = junction_centres(g, n)
    s_lo, s_hi = g.crown_edges
    out = {}

    def xy(direction, along, across):
        return (float(along), float(across)) if direction == "x" else (float(across), float(along))

    for d in DIRECTIONS:
        for r in range(n):
            for s in range(n + 1):
                out[bottom_strip_name(d, r, s)] = dict(
                    layer="bottom",
                    direction=d,
                    ribbon=r,
                    index=s,
                    side="",
                    paper_segment=s,
                    group=f"{d.upper()}D{r + 1}",
                    channel=f"B{d}",
                    midpoint=xy(d, g.segment_start(s) + 0.5 * g.segment_length, centres[r]),
                )
    for d in DIRECTIONS:
        for r in range(n):
            for j in range(n):
                lo = 0.5 * (g.segment_start(j) + s_hi + centres[j] - 0.5 * strip_width)
                hi = 0.5 * (centres[j] + 0.5 * strip_width + g.segment_start(j + 1) + s_lo)
                for side, along, seg in (("lo", lo, j), ("hi", hi, j + 1)):
                    out[top_strip_name(d, r, j, side)] = dict(
                        layer="top",
                        direction=d,
                        ribbon=r,
                        index=j,
                        side=side,
                        paper_segment=seg,
                        group=f"{d.upper()}U{r + 1}",
                        channel=f"T{d}",
                        midpoint=xy(d, along, centres[r]),
                    )
    return out


def junction_centres(geometry: CompositeBeamGeometry, cells: int) -> np.ndarray:
    """Junction centres c_r = L + d/2 + r (L + d) [mm] along either axis."""
    g = geometry
    return g.segment_start(np.arange(cells)) + g.segment_length + 0.5 * g.junction_length


def cell_group(tmesh, name: str) -> tuple[int, ...]:
    """Cell tags of a group (``info["cell_groups"]``) or of a single tag name, for ``dx(tags)``."""
    groups = tmesh.info["cell_groups"]
    if name in groups:
        return groups[name]
    if name in tmesh.cells:
        return (tmesh.cells[name],)
    raise InputError(f"cell group {name!r}: not on this mesh; groups: {', '.join(sorted(groups))}")


# --------------------------------------------------------------------------- axis pieces
def axis_pieces(g: CompositeBeamGeometry, n: int, tab: float, ws: float, cut: bool) -> list[tuple]:
    """Pieces (t0, t1, kind, index, top, in_band) along either axis [mm]: the FE beam's pieces of a
    ribbon of n + 1 segments, each junction split at the strip band c +- W_s/2 (the crossing
    ribbon's strips); ``top`` = (junction, side) of the top-strip half over the piece or None;
    ``in_band`` for the junction's middle part. With ``cut`` only t >= centre is kept."""
    beam = dataclasses.replace(g, segments=n + 1)
    out = []
    for t0, t1, kind, idx in beam_pieces(beam, tab):
        if kind == "junction":
            c = 0.5 * (t0 + t1)
            out += [
                (t0, c - 0.5 * ws, kind, idx, (idx, "lo"), False),
                (c - 0.5 * ws, c + 0.5 * ws, kind, idx, None, True),
                (c + 0.5 * ws, t1, kind, idx, (idx, "hi"), False),
            ]
        elif kind == "flank":
            first = (
                t0 <= g.segment_start(idx) + 1e-9
            )  # before the crown: the strip over junction s-1
            j, side = (idx - 1, "hi") if first else (idx, "lo")
            out.append((t0, t1, kind, idx, (j, side) if 0 <= j < n else None, False))
        else:
            out.append((t0, t1, kind, idx, None, False))
    if cut:
        centre = 0.5 * beam.total_length
        out = [(max(p[0], centre),) + p[1:] for p in out if p[1] > centre + 1e-9]
    return out


def axis_stations(pieces: list[tuple], size: float, mult: int) -> tuple[np.ndarray, list[tuple]]:
    """Stations [mm] along the axis and, per 1D cell, its piece."""
    ts, cell_piece = [pieces[0][0]], []
    for p in pieces:
        k = divisions(p[1] - p[0], size, mult)
        ts.extend(np.linspace(p[0], p[1], k + 1)[1:])
        cell_piece += [p] * k
    return np.asarray(ts), cell_piece


def arch_at(g: CompositeBeamGeometry, n: int, ts: np.ndarray) -> np.ndarray:
    """Arch height [mm] of a ribbon along the axis at stations ts (zero on junctions and tabs)."""
    z = np.zeros(ts.size)
    for s in range(n + 1):
        x0 = g.segment_start(s)
        inside = (ts >= x0 - 1e-9) & (ts <= x0 + g.segment_length + 1e-9)
        z[inside] = g.arch_height(np.clip(ts[inside] - x0, 0.0, g.segment_length))
    return z


def plan_regions(px: tuple, py: tuple, n: int) -> tuple[bool, str | None, str | None]:
    """(ribbon?, bottom-layer name, top-layer name) of the in-plane cell with axis pieces px, py."""
    jx, jy = px[2] == "junction", py[2] == "junction"
    if jx and jy:  # junction square (px index, py index)
        band_x, band_y = px[5], py[5]
        bottom = "bottom_pads" if band_x or band_y else None
        if band_x and band_y:
            top = "glue"
        elif band_y:  # arm of the x strip over junction px[3] of x ribbon py[3]
            top = top_strip_name("x", py[3], px[3], px[4][1])
        elif band_x:
            top = top_strip_name("y", px[3], py[3], py[4][1])
        else:
            top = None
        return True, bottom, top
    if not (jx or jy):
        return False, None, None  # a hole of the grid
    d, along, across = ("x", px, py) if jy else ("y", py, px)
    if not across[5]:
        return True, None, None  # ribbon beside its strips
    r = across[3]
    bottom = "bottom_pads" if along[2] == "tab" else bottom_strip_name(d, r, along[3])
    if along[2] == "crown":
        top = "top_pads"
    elif along[2] == "flank" and along[4] is not None:
        top = top_strip_name(d, r, *along[4])
    else:
        top = None
    return True, bottom, top


# --------------------------------------------------------------------------- builder
def checked_inputs(
    geometry: CompositeBeamGeometry,
    lambda_N: float,
    mesh: "GridshellFEMesh",
    cells: int,
    symmetry: str,
) -> tuple:
    """The builders' checked inputs: (geometry, n, mesh, t_p, W, W_s, H) [mm]; one-line
    InputError."""
    g = geometry
    if not isinstance(cells, int) or isinstance(cells, bool) or not 1 <= cells <= 39:
        raise InputError(
            f"cells = {cells!r}: must be an integer from 1 to 39 (ribbons per direction)"
        )
    if symmetry not in SYMMETRIES:
        raise InputError(f"symmetry = {symmetry!r}: allowed {', '.join(SYMMETRIES)}")
    n = cells
    dataclasses.replace(g, segments=n + 1).checked()
    m = mesh.checked()
    if not (isinstance(lambda_N, (int, float)) and lambda_N >= 1.0):
        raise InputError(f"lambda_N = {lambda_N}: must be >= 1")
    if abs(g.junction_length - g.ribbon_width) > 1e-12:
        raise InputError(
            f"geometry.junction_length = {g.junction_length}: must equal ribbon_width = "
            f"{g.ribbon_width} mm in a gridshell (the junctions are where ribbons cross)"
        )
    tp, W = g.ribbon_thickness, g.ribbon_width
    ws, H = g.strip_width / math.sqrt(lambda_N), g.strip_thickness / math.sqrt(lambda_N)
    if not ws < W:
        raise InputError(
            f"geometry.strip_width = {g.strip_width} mm: the as-built strip must be "
            f"narrower than the ribbon ({W} mm)"
        )
    return g, n, m, tp, W, ws, H


def build_gridshell_fe(
    geometry: CompositeBeamGeometry,
    lambda_N: float,
    mesh: GridshellFEMesh = GridshellFEMesh(),
    comm=None,
    cells: int = 3,
    symmetry: str = "quarter",
):
    """Hexahedral mesh of the as-built (nematic) n x n gridshell (see the module docstring).

    Args:
        geometry: ribbon, junction, strip and arch dimensions [mm] (``segments`` is ignored: a
            ribbon has ``cells + 1`` segments; ``junction_length`` must equal ``ribbon_width``).
        lambda_N: as-built (nematic) spontaneous stretch [-]: the strips' as-built section is the
            cast one / sqrt(lambda_N) per side.
        mesh: :class:`GridshellFEMesh`.
        comm: MPI communicator (default: :func:`lcefem.meshes.communicator.default_comm`); the mesh
            is made on rank 0 and distributed.
        cells: n, ribbons per direction (the paper's 3 x 3 grid: 3).
        symmetry: "quarter", "half_x", "half_y" or "full" (:data:`RECIPE_SYMMETRY`).

    Returns a :class:`~lcefem.meshes._gmsh.TaggedMesh`; cell names as in the module docstring with
    the tag numbers of the full model (a tag means the same piece in every symmetry), only those
    present kept; ``info``: ``cell_groups``, ``strips`` (:func:`strip_catalogue`, present tags),
    ``centre`` c, ``symmetry_factor`` (volumes and forces of the whole surface are this times the
    mesh's), as-built dimensions, ``junction_centres``, ``centre_junction_corners``, counts.
    """
    comm = resolve_comm(comm)
    g, n, m, tp, W, ws, H = checked_inputs(geometry, lambda_N, mesh, cells, symmetry)
    if m.mesher == "gmsh":
        from lcefem.meshes.gridshell_fe_gmsh import build_gridshell_fe_gmsh

        return build_gridshell_fe_gmsh(geometry, lambda_N, mesh, comm, cells, symmetry)
    cut_x, cut_y = SYMMETRIES[symmetry]
    mult = m.level + 1
    length = (n + 1) * g.segment_length + n * g.junction_length
    centre = 0.5 * length
    xs, px = axis_stations(axis_pieces(g, n, m.end_tab, ws, cut_x), m.size, mult)
    ys, py = axis_stations(axis_pieces(g, n, m.end_tab, ws, cut_y), m.size, mult)
    arch_x, arch_y = arch_at(g, n, xs), arch_at(g, n, ys)
    z_c = g.top_strip_height

    # in-plane regions, and the in-plane nodes bonded below (pads) and above (crown pads)
    catalogue = strip_catalogue(g, n, ws)
    names = list(MATERIAL_CELLS) + list(catalogue)
    tag = {name: k for k, name in enumerate(names, start=1)}
    plan = []
    bonded_bottom = np.zeros((xs.size, ys.size), dtype=bool)
    bonded_top = np.zeros((xs.size, ys.size), dtype=bool)
    for i, pxi in enumerate(px):
        for j, pyj in enumerate(py):
            ribbon, bottom, top = plan_regions(pxi, pyj, n)
            if not ribbon:
                continue
            plan.append((i, j, bottom, top))
            if bottom == "bottom_pads":
                bonded_bottom[i : i + 2, j : j + 2] = True
            if top == "top_pads":
                bonded_top[i : i + 2, j : j + 2] = True

    nb, nr, nt = m.strip_layers, m.ribbon_layers, m.strip_layers
    k_rb, k_rt = nb, nb + nr  # node layers of the ribbon's bottom and top faces
    ids: dict[tuple[int, int, int, str], int] = {}
    coords: list[tuple[float, float, float]] = []

    def node(i: int, j: int, k: int, body: str) -> int:
        # bonded faces share the ribbon's nodes; unbonded ones keep their own (contact only)
        if (body == "b" and k == k_rb and bonded_bottom[i, j]) or (
            body == "t" and k == k_rt and bonded_top[i, j]
        ):
            body = "r"
        key = (i, j, k, body)
        found = ids.get(key)
        if found is not None:
            return found
        mid = arch_x[i] + arch_y[j]  # at most one is non-zero: a ribbon node is on a band
        if body == "r":
            z = mid + tp * (-0.5 + (k - k_rb) / nr)
        elif body == "b":
            z = -0.5 * tp - H * (k_rb - k) / nb
        else:
            z = (mid if bonded_top[i, j] else z_c) + 0.5 * tp + H * (k - k_rt) / nt
        ids[key] = len(coords)
        coords.append((xs[i], ys[j], z))
        return ids[key]

    cell_nodes, cell_values, cell_body = [], [], []

    def add_cell(i: int, j: int, k: int, body: str, name: str) -> None:
        cell_nodes.append(
            [node(i + a, j + b, k + c, body) for c in (0, 1) for b in (0, 1) for a in (0, 1)]
        )
        cell_values.append(tag[name])
        cell_body.append(body)

    for i, j, bottom, top in plan:
        for k in range(k_rb, k_rt):
            add_cell(i, j, k, "r", "kapton")
        if bottom is not None:
            for k in range(0, k_rb):
                add_cell(i, j, k, "b", bottom)
        if top is not None:
            for k in range(k_rt, k_rt + nt):
                add_cell(i, j, k, "t", top)
    cell_nodes = np.asarray(cell_nodes, dtype=np.int64)
    x = np.asarray(coords, dtype=np.float64)
    cell_body = np.asarray(cell_body)

    faces, sides, owner = exterior_faces(cell_nodes)
    facet_values = facet_names_of(
        x[faces],
        sides,
        cell_body[owner],
        cut_x,
        cut_y,
        centre,
        (-m.end_tab, length + m.end_tab),
        0.5 * g.junction_length,
        n % 2 == 1,
        1e-9 * length,
    )
    ftag = {name: k for k, name in enumerate(FE_FACETS, start=1)}
    facet_values = np.asarray([ftag[v] for v in facet_values], dtype=np.int32)

    present = sorted(set(cell_values))
    tag_of = {v: k for k, v in tag.items()}
    present_names = [tag_of[v] for v in present]
    strips = {k: v for k, v in catalogue.items() if k in tag and tag[k] in present}
    info = mesh_info(
        g,
        n,
        m,
        symmetry,
        float(lambda_N),
        ws,
        H,
        strips,
        cell_groups_of(present_names, tag, strips),
    )
    info["mesher"] = "hexgrid"
    info.update(cells=int(cell_nodes.shape[0]), nodes=int(x.shape[0]))
    return tagged_hex_mesh(
        comm, cell_nodes, x, np.asarray(cell_values, np.int32), faces, facet_values, tag, ftag, info
    )


def mesh_info(
    g: CompositeBeamGeometry,
    n: int,
    m: "GridshellFEMesh",
    symmetry: str,
    lambda_N: float,
    ws: float,
    H: float,
    strips: dict,
    cell_groups: dict,
) -> dict:
    """The builders' ``info`` (lengths [mm]; :func:`build_gridshell_fe`)."""
    tp, W = g.ribbon_thickness, g.ribbon_width
    length = (n + 1) * g.segment_length + n * g.junction_length
    centre = 0.5 * length
    return {
        "cells_per_direction": n,
        "ribbon_length": length,
        "centre": centre,
        "symmetry": symmetry,
        "symmetry_factor": {"quarter": 4, "half_x": 2, "half_y": 2, "full": 1}[symmetry],
        "ribbon_thickness": tp,
        "ribbon_width": W,
        "strip_width": ws,
        "strip_thickness": H,
        "top_strip_height": g.top_strip_height,
        "lambda_N": float(lambda_N),
        "element_size": m.element_size(),
        "level": m.level,
        "end_tab": m.end_tab,
        "junction_centres": tuple(float(c) for c in junction_centres(g, n)),
        "centre_junction_corners": (
            tuple(
                (centre + a, centre + b, 0.0)
                for a in (-0.5 * W, 0.5 * W)
                for b in (-0.5 * W, 0.5 * W)
            )
            if n % 2 == 1
            else ()
        ),
        "strips": strips,
        "cell_groups": cell_groups,
    }


def facet_names_of(
    pts: np.ndarray,
    sides: np.ndarray,
    body: np.ndarray,
    cut_x: bool,
    cut_y: bool,
    centre: float,
    ends: tuple[float, float],
    half_junction: float,
    odd: bool,
    tol: float,
) -> np.ndarray:
    """Name of each exterior face (points (m, 4, 3) [mm]); the first matching rule wins."""
    on = lambda axis, value: np.all(np.abs(pts[:, :, axis] - value) < tol, axis=1)  # noqa: E731
    r, t, b = body == "r", body == "t", body == "b"
    at_end = lambda axis: on(axis, ends[0]) | on(axis, ends[1])  # noqa: E731
    in_centre = np.all(np.abs(pts[:, :, :2] - centre) < half_junction + tol, axis=(1, 2))
    rules = [
        (cut_x & on(0, centre), "sym_x"),
        (cut_y & on(1, centre), "sym_y"),
        (r & np.isin(sides, ("-x", "+x")) & at_end(0), "ribbon_ends_x"),
        (r & np.isin(sides, ("-y", "+y")) & at_end(1), "ribbon_ends_y"),
        (odd & r & (sides == "+z") & in_centre, "centre_junction"),
        (r & (sides == "+z"), "ribbon_top"),
        (r & (sides == "-z"), "ribbon_bottom"),
        (t & (sides == "-z"), "top_strip_underside"),
        (b & (sides == "+z"), "bottom_strip_topside"),
    ]
    return np.select([c for c, _ in rules], [name for _, name in rules], default="surface")


def cell_groups_of(present: list[str], tag: dict[str, int], strips: dict) -> dict[str, tuple]:
    """Group name -> cell tags present (module docstring)."""
    groups: dict[str, list[int]] = {}

    def add(group: str, name: str) -> None:
        groups.setdefault(group, []).append(tag[name])

    for name in present:
        if name in MATERIAL_CELLS:
            add(name, name)
            continue
        s = strips[name]
        d, r = s["direction"], s["ribbon"]
        add(f"{s['layer']}_strips", name)
        add(s["channel"], name)
        add(s["group"], name)
        if s["layer"] == "top":
            add(f"top_{d}_r{r}_j{s['index']}", name)
            add(f"top_{d}_r{r}_s{s['paper_segment']}", name)
    return {k: tuple(sorted(v)) for k, v in groups.items()}
