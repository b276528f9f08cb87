"""The triangular gridshell in the bar-and-hinge model: three families of Kapton ribbons at 0, 60
and 120 deg crossing at every junction of a triangular lattice (seed 001's next step "explore
non-orthogonal meshes"; :class:`lcefem.meshes.gridshell_layout.Layout` kind "triangular").

The paper is silent on three ribbons at one junction; the choices below carry the published
orthogonal junction over (meshes/gridshell.py) and are marked "assumed" where they go beyond it.

* Lattice: junction centres P = i a1 + j a2 (a1 = p (1, 0), a2 = p (1/2, sqrt(3)/2), p the pitch)
  with |i|, |j|, |i + j| <= k, k = (n - 1)/2: a hexagonal patch of 3 k (k + 1) + 1 junctions (7
  for n = 3, 19 for n = 5), n ribbons per family (n odd: the centre junction is the lattice's
  origin). Families "a" (0 deg, along x), "b" (60 deg), "c" (120 deg); ribbon r (0-based) of a
  family is its r-th line by its offset along the family's normal (-sin t, cos t), so ribbon
  (n - 1)/2 passes through the centre.
* Junction (assumed): the three films are stacked and glued over the regular hexagon of side d (d
  the ribbon width) whose six edges are the six ribbon ends: each ribbon enters through one edge
  and leaves through the opposite one, so the hexagon's apothem sqrt(3) d/2 is where a ribbon
  leaves the other two (the outer edge of the overlap of its band with theirs). The hexagon is one
  Kapton plate of the ribbon's thickness, split into three rhombi of side d from its centre (N5B8
  each): as the published model treats its two glued films as one 7 x 7 mm square, the three
  films are one plate. The three ribbons' bands cover the hexagon exactly (each of its points lies
  on at least one ribbon), so the plate is the junction's Kapton and nothing more. All three films
  lie at z = 0 (the stack's 0.25 mm is neglected, as the published model neglects its two films'
  0.127 mm).
* Segments: every ribbon segment is the published composite beam (30 mm, arch gap sin^2, the 5 + 1
  + 5 panels; :class:`lcefem.meshes.composite_beam.CompositeBeamGeometry`), between the hexagons'
  edges, and every ribbon ends one free segment beyond its last junction (as the orthogonal
  grid's). So the default pitch is L + sqrt(3) d = 42.12 mm (:meth:`Layout.geometry`).
* Strips, per family as per direction of the orthogonal grid: a bottom strip per segment (two
  chord bars along the ribbon's edges) and a top strip per junction from the crown edge of one
  segment over a raised plate to the crown edge of the next. The raised plate (assumed: the
  orthogonal grid's raised square carried to three families) is the hexagon at the crown-edge
  height, shared by the three top strips: each top strip runs from its entry edge to its exit edge
  (with ``top_junction = "lce"`` along the two chords between them, each vertex belongs to two
  families); with "glue" it is a stiff glue plate (all 15 vertex pairs).
* Channels: one per layer and family, Ta, Tb, Tc, Ba, Bb, Bc (the natural extension of the
  paper's four, Tx, Ty, Bx, By: one current per layer and direction, seed 001 Fig. 4A); groups
  "AD1".."CUn" (family, D bottom / U top, ribbon number).
* Supports: "clamp" (the centre hexagon's six vertices and centre held in x, y, z: the published
  clamp of the centre junction's corners, on a hexagon; 21 DOFs) and "table" (the
  surface's weight on a rigid table; lcefem.solvers.problems.gridshell_bh). The published rollers
  sit at the ends of an orthogonal grid's outer ribbons and have no counterpart here.

Node sets: "junction_corners" (J, 6) hexagon vertices at 30 + 60 m deg, "junction_centres" (J,),
"top_squares" (J, 6) (the raised plates), "centre_junction" (4: the inscribed rectangle, corner 0
-> 1 along +x, for the centre frame), "centre_clamp" (7), "ribbon_ends_a", "ribbon_ends_b",
"ribbon_ends_c" (n, 2, 2: ribbon, end low/high along the family, side), "ribbon_ends_x" (=
"ribbon_ends_a"), "bottom_strip_ends". ``info["junction_lattice"]`` (J, 2) gives (i, j) of each
junction, ``info["centre_junction_index"]`` the centre's row.

Units: mm.
"""

from __future__ import annotations

import math

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, n5b8_structure
from lcefem.meshes.composite_beam import (
    PUBLISHED,
    BeamBarHingeMesh,
    CompositeBeamGeometry,
    StripPiece,
    apply_strip_element,
    strip_sections,
)
from lcefem.meshes.gridshell_strips import add_bottom_strip, add_top_strip
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.parameters import check

#: The three ribbon families: name -> direction angle [deg].
FAMILY_ANGLES = {"a": 0.0, "b": 60.0, "c": 120.0}
#: One channel per layer and family (the paper's four, seed 001 Fig. 4A, for three families).
TRI_CHANNELS = {
    f"{'T' if layer == 'top' else 'B'}{f}": (layer, f)
    for layer in ("top", "bottom")
    for f in FAMILY_ANGLES
}


def lattice(n: int) -> np.ndarray:
    """Junction indices (J, 2) (i, j) of the hexagonal patch |i|, |j|, |i + j| <= (n - 1)/2."""
    k = n // 2
    return np.array(
        [(i, j) for i in range(-k, k + 1) for j in range(-k, k + 1) if abs(i + j) <= k],
        dtype=np.int64,
    )


def hexagon_vertex(family_angle: float, exit_: bool, side: int) -> int:
    """Index m (vertex at 30 + 60 m deg) of the hexagon vertex where a ribbon of direction
    ``family_angle`` [deg] leaves (``exit_``) or enters the junction, on side 0 (right of the
    ribbon, lateral -d/2) or 1."""
    if exit_:
        phi = family_angle + (30.0 if side else -30.0)
    else:
        phi = family_angle + (150.0 if side else 210.0)
    return int(round((phi - 30.0) / 60.0)) % 6


def hexagon_plates(centres: np.ndarray, d: float, add) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Kapton hexagons of side ``d`` [mm] at the junction ``centres`` (J, 2) [mm], at z = 0: per
    junction its centre node, then the six vertices at 30 + 60 m deg (``add(xy, z)`` -> node id).
    Returns (centre ids (J,), vertex ids (J, 6), the vertices' offsets (6, 2) [mm])."""
    nj = len(centres)
    hex_v = np.zeros((nj, 6), dtype=np.int64)
    hex_c = np.zeros(nj, dtype=np.int64)
    ang = np.radians(30.0 + 60.0 * np.arange(6))
    ring = d * np.column_stack([np.cos(ang), np.sin(ang)])
    for J in range(nj):
        hex_c[J] = add(centres[J], 0.0)
        hex_v[J] = [add(centres[J] + ring[k], 0.0) for k in range(6)]
    return hex_c, hex_v, ring


def hexagon_panels(hex_c: np.ndarray, hex_v: np.ndarray, panels: list, kinds: list) -> np.ndarray:
    """Append each hexagon's three rhombi (centre, vertices 2k, 2k + 1, 2k + 2) to ``panels`` (kind
    "junction"); returns their panel rows (J, 3)."""
    junction_panels = np.zeros((len(hex_c), 3), dtype=np.int64)
    for J in range(len(hex_c)):
        v = hex_v[J]
        for k in range(3):
            junction_panels[J, k] = len(panels)
            panels.append((hex_c[J], v[2 * k], v[2 * k + 1], v[(2 * k + 2) % 6]))
            kinds.append("junction")
    return junction_panels


def hexagon_node_sets(structure, hex_c, hex_v, raised, junction_panels, centre: int) -> None:
    """The node sets of a grid of hexagonal junctions (module docstring); ``centre`` is the centre
    junction's row."""
    sets = structure.node_sets
    sets["junction_corners"] = hex_v
    sets["junction_centres"] = hex_c
    sets["top_squares"] = raised
    sets["junction_panels"] = junction_panels
    # The centre hexagon's inscribed rectangle (210, 330, 30, 150 deg): corner 0 -> 1 along +x.
    sets["centre_junction"] = hex_v[centre, [3, 5, 0, 2]]
    # The clamp holds the whole centre hexagon (its six vertices and centre): held on four of them,
    # the inscribed rectangle, the plate bends under the three families unequally.
    sets["centre_clamp"] = np.append(hex_v[centre], hex_c[centre])
    sets["bottom_strip_ends"] = np.unique(structure.bars["bottom_strips"])


def three_direction_groups(layout, strips: list) -> tuple[dict, tuple]:
    """Groups (per line and layer, and the six channels Ta .. Bc) and the layout's wiring tags of
    a grid with three ribbon directions (:func:`lcefem.meshes.gridshell.add_wiring`)."""
    from lcefem.meshes.gridshell import add_wiring

    groups: dict[str, list[int]] = {}
    for st in strips:
        groups.setdefault(st.group, []).append(st.id)
    for name, (layer, fam) in TRI_CHANNELS.items():
        groups[name] = [st.id for st in strips if st.layer == layer and st.direction == fam]
    wiring = add_wiring(layout, strips, groups, TRI_CHANNELS)
    return {k: np.asarray(v, dtype=np.int64) for k, v in groups.items()}, wiring


def build_triangular_bar_hinge(
    geometry: CompositeBeamGeometry, layout, mesh: BeamBarHingeMesh
) -> BarHingeStructure:
    """Bar-and-hinge structure of a triangular layout (module docstring). ``geometry`` is the
    ``[geometry]`` section; ``layout.geometry`` gives the lengths (segment L = pitch - sqrt(3) d,
    junction_length sqrt(3) d, the hexagon's extent along a ribbon)."""
    from lcefem.meshes.gridshell import Strip

    n = layout.ribbons
    if n % 2 == 0:
        raise InputError(
            f"layout.ribbons = {n}: a triangular layout needs an odd count (a centre junction)"
        )
    if layout.glued != "all":
        raise InputError(
            f"layout.glued = {layout.glued!r}: a triangular layout bonds every junction; "
            "allowed 'all'"
        )
    g = layout.geometry(geometry)
    check(g, "geometry")
    m = mesh.checked()
    # A strip's contact quad split along both diagonals keeps the grid's mirrors: split along one,
    # a mirror maps it onto the other and the structure is chiral (measured on the triangular grid,
    # every top strip at 1.3: mirror-image z up to 6.46 mm apart; both: 1e-7 mm).
    both = m.contact_diagonals != "one"
    d = g.ribbon_width
    apo = 0.5 * math.sqrt(3.0) * d  # hexagon apothem: where a ribbon leaves the junction
    lx, p = g.segment_length, g.pitch
    nf = m.flank_panels
    s_lo, s_hi = g.crown_edges
    local = np.concatenate([np.linspace(0.0, s_lo, nf + 1), np.linspace(s_hi, lx, nf + 1)])
    per_seg, last = local.size, local.size - 1
    ij = lattice(n)
    a1, a2 = np.array([p, 0.0]), np.array([0.5 * p, 0.5 * math.sqrt(3.0) * p])
    centres = ij[:, 0:1] * a1 + ij[:, 1:2] * a2
    nj = len(ij)

    coords: list[tuple[float, float, float]] = []

    def add(xy, z: float) -> int:
        coords.append((float(xy[0]), float(xy[1]), float(z)))
        return len(coords) - 1

    hex_c, hex_v, ring = hexagon_plates(centres, d, add)

    # Ribbons: per family, the lattice lines by offset; each with its junctions sorted along it.
    ribbons = []  # (family, r, u, normal, offset, [junction rows along u])
    for fam, theta in FAMILY_ANGLES.items():
        t = math.radians(theta)
        u, nrm = np.array([math.cos(t), math.sin(t)]), np.array([-math.sin(t), math.cos(t)])
        off = np.round(centres @ nrm, 6)
        for r, o in enumerate(np.unique(off)):
            rows = np.flatnonzero(off == o)
            rows = rows[np.argsort(centres[rows] @ u)]
            ribbons.append((fam, r, u, nrm, float(centres[rows[0]] @ nrm), rows))
    if any(len(rb[5]) < 1 for rb in ribbons) or len(ribbons) != 3 * n:
        raise AssertionError("triangular lattice: every family has n ribbons")

    node_of: dict[tuple, int] = {}
    for fam, r, u, nrm, off, rows in ribbons:
        theta = FAMILY_ANGLES[fam]
        s0 = float(centres[rows[0]] @ u) - apo - lx  # start of segment 0 along u
        starts = [s0] + [float(centres[J] @ u) + apo for J in rows]
        for q, start in enumerate(starts):
            for a, sa in enumerate(local):
                for side in (0, 1):
                    if a == 0 and q > 0:  # leaving junction q - 1
                        nid = int(hex_v[rows[q - 1], hexagon_vertex(theta, True, side)])
                    elif a == last and q < len(rows):  # entering junction q
                        nid = int(hex_v[rows[q], hexagon_vertex(theta, False, side)])
                    else:
                        xy = (start + sa) * u + off * nrm + (side - 0.5) * d * nrm
                        nid = add(xy, float(g.arch_height(sa)))
                    node_of[(fam, r, q, a, side)] = nid

    def node(fam, r, q, a, side) -> int:
        return node_of[(fam, r, q, a, side)]

    panels, kinds, panel_at = [], [], {}
    for fam, r, u, nrm, off, rows in ribbons:
        for q in range(len(rows) + 1):
            for a in range(last):
                panel_at[(fam, r, q, a)] = len(panels)
                panels.append(
                    (
                        node(fam, r, q, a, 0),
                        node(fam, r, q, a + 1, 0),
                        node(fam, r, q, a + 1, 1),
                        node(fam, r, q, a, 1),
                    )
                )
                kinds.append("crown" if a == nf else "flank")
    junction_panels = hexagon_panels(hex_c, hex_v, panels, kinds)
    structure = n5b8_structure(np.asarray(coords), np.asarray(panels), g.ribbon_thickness)
    pc = structure.panel_centres

    def ribbon_points(fam, r, q, stations, panel_ids) -> list[int]:
        pts = [node(fam, r, q, a, side) for a in stations for side in (0, 1)]
        return pts + [int(pc[panel_at[(fam, r, q, a)]]) for a in panel_ids]

    strips: list[Strip] = []
    strip_of_bar = {"bottom_strips": [], "top_strips": []}
    hinge_rows: list = []
    pieces: list[StripPiece] = []

    def new_strip(layer, fam, r, k, u, nrm, off, along) -> int:
        mid = along * u + off * nrm
        strips.append(Strip(len(strips), layer, fam, r, k, (float(mid[0]), float(mid[1]))))
        return strips[-1].id

    for fam, r, u, nrm, off, rows in ribbons:
        s0 = float(centres[rows[0]] @ u) - apo - lx
        starts = [s0] + [float(centres[J] @ u) + apo for J in rows]
        nseg = len(rows) + 1
        for q in range(nseg):
            sid = new_strip("bottom", fam, r, q, u, nrm, off, starts[q] + 0.5 * lx)
            nd = lambda a, side, q=q: node(fam, r, q, a, side)  # noqa: E731
            add_bottom_strip(
                structure,
                nd,
                last,
                tuple(node(fam, r, q - 1, last, k) if q > 0 else nd(1, k) for k in (0, 1)),
                tuple(
                    node(fam, r, q + 1, 0, k) if q + 1 < nseg else nd(last - 1, k) for k in (0, 1)
                ),
                ribbon_points(fam, r, q, range(1, last), range(last)) if m.contact else None,
                pieces,
                hinge_rows,
                both,
            )
            strip_of_bar["bottom_strips"] += [sid, sid]

    # Raised plates over the junctions (the hexagon at the crown-edge height).
    zc = g.top_strip_height
    raised = np.zeros((nj, 6), dtype=np.int64)
    for J in range(nj):
        raised[J] = structure.add_nodes([(*(centres[J] + ring[k]), zc) for k in range(6)])
        q6 = raised[J]
        if m.top_junction == "glue":
            structure.add_bars("glue", [(q6[i], q6[j]) for i in range(6) for j in range(i + 1, 6)])
        if m.contact:
            v = hex_v[J]
            # point above the hexagon's plane: rows (p, a, b, c) with (c - a) x (b - a) = +z
            tris = ((v[0], v[4], v[2]), (v[1], v[5], v[3]))
            structure.add_contacts("top_square_contact", [(int(pt), *t) for pt in q6 for t in tris])

    for fam, r, u, nrm, off, rows in ribbons:
        theta = FAMILY_ANGLES[fam]
        for k, J in enumerate(rows):
            sid = new_strip("top", fam, r, k, u, nrm, off, float(centres[J] @ u))
            e0, e1 = (int(raised[J, hexagon_vertex(theta, False, s)]) for s in (0, 1))
            x0, x1 = (int(raised[J, hexagon_vertex(theta, True, s)]) for s in (0, 1))
            left = [node(fam, r, k, nf + 1, side) for side in (0, 1)]
            right = [node(fam, r, k + 1, nf, side) for side in (0, 1)]
            nbars = add_top_strip(
                structure,
                (
                    left,
                    [node(fam, r, k, nf, s) for s in (0, 1)],
                    [node(fam, r, k, nf + 2, s) for s in (0, 1)],
                ),
                (
                    right,
                    [node(fam, r, k + 1, nf + 1, s) for s in (0, 1)],
                    [node(fam, r, k + 1, nf - 1, s) for s in (0, 1)],
                ),
                (e0, e1),
                (x0, x1),
                m.top_junction == "lce",
                (
                    ribbon_points(fam, r, k, range(nf + 2, per_seg), range(nf + 1, last)),
                    ribbon_points(fam, r, k + 1, range(0, nf), range(0, nf)),
                )
                if m.contact
                else None,
                pieces,
                hinge_rows,
                both,
            )
            strip_of_bar["top_strips"] += [sid] * nbars

    if m.strip_contact:
        structure.add_hinges("strip_contact", np.asarray(hinge_rows, dtype=np.int64))

    ends = {}
    for fam in FAMILY_ANGLES:
        mine = [rb for rb in ribbons if rb[0] == fam]
        ends[fam] = np.array(
            [
                [
                    [node(fam, r, 0, 0, s) for s in (0, 1)],
                    [node(fam, r, len(rows), last, s) for s in (0, 1)],
                ]
                for fam_, r, u, nrm, off, rows in mine
            ],
            dtype=np.int64,
        )
    centre = int(np.flatnonzero((ij[:, 0] == 0) & (ij[:, 1] == 0))[0])
    hexagon_node_sets(structure, hex_c, hex_v, raised, junction_panels, centre)
    sets = structure.node_sets
    for fam in FAMILY_ANGLES:
        sets[f"ribbon_ends_{fam}"] = ends[fam]
    sets["ribbon_ends_x"] = ends["a"]
    strip_sections(
        structure,
        g,
        flank=(lx - g.crown_bond_length) / (2 * nf),
        rows_per_point=2,
        strip_rows_per_point=4 if both else 2,  # each row its share
    )
    # As the square's corners (strip_sections): the plate's six vertices share one strip's footprint
    # on the junction (w x sqrt(3) d), two contact rows per vertex.
    structure.sections["top_square_contact"] = {
        "area": g.strip_width * g.junction_length / 6.0 / 2.0,
        "depth": g.strip_thickness,
    }
    apply_strip_element(structure, g, m.strip_element, pieces, PUBLISHED_LAMBDA_N, raised.ravel())

    groups, wiring = three_direction_groups(layout, strips)
    structure.info.update(
        kind=layout.kind,
        angle=layout.angle,
        wiring=wiring,
        layout=layout,
        ribbons=n,
        families=tuple(FAMILY_ANGLES),
        family_angles=tuple(FAMILY_ANGLES.values()),
        channels=tuple(TRI_CHANNELS),
        flank_panels=nf,
        top_junction=m.top_junction,
        junction_lattice=ij,
        junction_xy=centres,
        centre_junction_index=centre,
        panel_kind=np.asarray(kinds),
        strips=strips,
        groups=groups,
        strip_of_bar={k: np.asarray(v, dtype=np.int64) for k, v in strip_of_bar.items()},
        source=PUBLISHED
        + "; three families at a hexagonal junction: assumed (meshes.gridshell_tri)",
    )
    structure.validate()
    return structure
