"""The honeycomb (hexagonal) gridshell in the bar-and-hinge model: ribbon pieces along 0, 60 and 120
deg, three of them ending at every junction at 120 deg to each other (seed 001's next step "explore
non-orthogonal meshes"; :class:`lcefem.meshes.gridshell_layout.Layout` kind "hexagonal").

The paper gives no honeycomb; what follows carries the published composite beam and the triangular
grid's junction (:mod:`lcefem.meshes.gridshell_tri`) over, and is marked "assumed" where it goes
beyond them.

* Patch: :func:`lcefem.meshes.gridshell_layout.honeycomb_patch`: the cells whose centres lie within
  n p of the centre junction (p the pitch, junction centre to junction centre; n = ``ribbons``): 3,
  6, 12, 21 cells, 13, 22, 37, 61 junctions and 15, 27, 48, 81 pieces for n = 1 .. 4. The patch
  keeps the centre junction's 3-fold symmetry (the pieces from it run at 0, 120 and 240 deg).
* Pieces: every piece is one published composite-beam segment (30 mm, the arch gap sin^2, the 5 +
  1 + 5 panels: :class:`lcefem.meshes.composite_beam.CompositeBeamGeometry`) between two junction
  plates, with its own bottom strip (a chord per ribbon edge, plate edge to plate edge, 30 mm) and
  its own top strip, and each strip is one heater coil.
* Junction (assumed): the Kapton plate is the regular hexagon of side d (d the ribbon width)
  spanned by the three piece ends: they are three alternate edges of it, at the apothem sqrt(3)
  d/2 = 6.06 mm from the centre, the other three edges are free. (The kirigami's own junction,
  the triangle where the three 7 mm bands meet, of inradius d/(2 sqrt(3)) = 2.02 mm, has no N5B8
  quad mesh that conforms to the pieces' two-node ends.) It is the triangular grid's hexagon, one
  plate of the ribbon's thickness in three N5B8 rhombi, so the default pitch is the triangular
  grid's, L + sqrt(3) d = 42.12 mm.
* Strips end at the plate; no strip turns a corner (assumed): the top strip of a piece is its two
  published halves, each from a crown edge (11.5 mm from the piece end) to the raised plate over
  the junction at the crown-edge height (0.982 mm), 2 x 11.5 mm of LCE. The raised plate is the
  hexagon, shared by the three pieces' top strips, a stiff glue block standing on the Kapton
  hexagon (15 bars in the plate, 12 to the hexagon: the strips are bonded to the junction): no
  strip crosses it, so ``mesh.top_junction`` has nothing to choose here and the plate needs no
  contact.
* Channels: one per layer and piece direction, Ta, Tb, Tc, Ba, Bb, Bc (a at 0 deg, b at 60, c at
  120; the triangular grid's convention); groups "AD1".."CUm": direction, D bottom / U top, the
  line of collinear pieces counted along the direction's normal (the ``ribbons`` wiring); the
  ``strips`` wiring gives every strip its own current.
* Support: "clamp": the centre junction's hexagon (six vertices and centre) held in x, y, z, one
  rigid support of the 6 rigid-body modes, so the reactions are statically determinate and the
  pieces' contraction is not resisted by the supports (clamping the central cell's six junctions
  would hold its six pieces' chords and end slopes: 36 reactions against 6 modes).

Node sets: "junction_corners" (J, 6) hexagon vertices at 30 + 60 m deg, "junction_centres" (J,),
"top_squares" (J, 6) (the raised plates), "junction_panels" (J, 3), "centre_junction" (4: the
inscribed rectangle, corner 0 -> 1 along +x), "centre_clamp" (7), "bottom_strip_ends".
``info["pieces"]`` (P, 2) gives each piece's junction rows (start -> end), ``info["piece_family"]``
its direction's name, ``info["circle_junctions"]`` the two junctions next to the centre on the
line through it along each direction (the circle curvatures,
:func:`lcefem.solvers.analysis.curvature.gridshell_curvatures`).

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
from lcefem.meshes.gridshell_layout import honeycomb_patch
from lcefem.meshes.gridshell_strips import add_bottom_strip, add_top_strip_half
from lcefem.meshes.gridshell_tri import (
    FAMILY_ANGLES,
    TRI_CHANNELS,
    hexagon_node_sets,
    hexagon_panels,
    hexagon_plates,
    hexagon_vertex,
    three_direction_groups,
)
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.parameters import check

#: Direction angle [deg] -> piece family name (the triangular grid's families).
FAMILY_OF_ANGLE = {int(a): f for f, a in FAMILY_ANGLES.items()}


def build_hexagonal_bar_hinge(
    geometry: CompositeBeamGeometry, layout, mesh: BeamBarHingeMesh
) -> BarHingeStructure:
    """Bar-and-hinge structure of a hexagonal layout (module docstring). ``geometry`` is the
    ``[geometry]`` section; ``layout.geometry`` gives the lengths (piece L = pitch - sqrt(3) d,
    junction_length sqrt(3) d: the hexagon's extent along a piece)."""
    from lcefem.meshes.gridshell import Strip

    if layout.glued != "all":
        raise InputError(
            f"layout.glued = {layout.glued!r}: a hexagonal layout bonds every junction; "
            "allowed 'all'"
        )
    g = layout.geometry(geometry)
    check(g, "geometry")
    m = mesh.checked()
    # A strip's contact quad split along both diagonals keeps the grid's mirrors: split along one,
    # a mirror maps it onto the other and the structure is chiral (measured on the triangular grid,
    # every top strip at 1.3: mirror-image z up to 6.46 mm apart; both: 1e-7 mm).
    both = m.contact_diagonals != "one"
    n = layout.ribbons
    d = g.ribbon_width
    apo = 0.5 * math.sqrt(3.0) * d  # hexagon apothem: where a piece leaves the junction
    lx, p = g.segment_length, g.pitch
    nf = m.flank_panels
    s_lo, s_hi = g.crown_edges
    local = np.concatenate([np.linspace(0.0, s_lo, nf + 1), np.linspace(s_hi, lx, nf + 1)])
    per_seg, last = local.size, local.size - 1
    cells, centres, ends = honeycomb_patch(n, p)
    nj = len(centres)

    coords: list[tuple[float, float, float]] = []

    def add(xy, z: float) -> int:
        coords.append((float(xy[0]), float(xy[1]), float(z)))
        return len(coords) - 1

    hex_c, hex_v, ring = hexagon_plates(centres, d, add)

    # Pieces: direction, line (collinear pieces by offset along the normal), order along it.
    pieces_info = []  # (family, theta, u, nrm, line, order)
    for a, b in ends:
        v = centres[b] - centres[a]
        theta = int(round(math.degrees(math.atan2(v[1], v[0])))) % 180
        if theta not in FAMILY_OF_ANGLE:
            raise AssertionError(f"honeycomb piece at {theta} deg")
        t = math.radians(theta)
        pieces_info.append(
            [FAMILY_OF_ANGLE[theta], theta, np.array([math.cos(t), math.sin(t)]), None, 0, 0]
        )
    for info in pieces_info:
        t = math.radians(info[1])
        info[3] = np.array([-math.sin(t), math.cos(t)])
    for fam in FAMILY_ANGLES:
        mine = [i for i, pi in enumerate(pieces_info) if pi[0] == fam]
        off = np.array([round(float(centres[ends[i, 0]] @ pieces_info[i][3]), 6) for i in mine])
        lines = np.unique(off)
        for i, o in zip(mine, off):
            pieces_info[i][4] = int(np.searchsorted(lines, o))
        for r in range(len(lines)):
            on = [i for i, o in zip(mine, off) if o == lines[r]]
            on.sort(key=lambda i: float(centres[ends[i, 0]] @ pieces_info[i][2]))
            for k, i in enumerate(on):
                pieces_info[i][5] = k

    node_of: dict[tuple[int, int, int], int] = {}
    for q, (a, b) in enumerate(ends):
        _, theta, u, nrm, _, _ = pieces_info[q]
        for st, sa in enumerate(local):
            for side in (0, 1):
                if st == 0:  # leaving junction a
                    nid = int(hex_v[a, hexagon_vertex(theta, True, side)])
                elif st == last:  # entering junction b
                    nid = int(hex_v[b, hexagon_vertex(theta, False, side)])
                else:
                    xy = centres[a] + (apo + sa) * u + (side - 0.5) * d * nrm
                    nid = add(xy, float(g.arch_height(sa)))
                node_of[(q, st, side)] = nid

    def node(q: int, st: int, side: int) -> int:
        return node_of[(q, st, side)]

    panels, kinds, panel_at = [], [], {}
    for q in range(len(ends)):
        for st in range(last):
            panel_at[(q, st)] = len(panels)
            panels.append((node(q, st, 0), node(q, st + 1, 0), node(q, st + 1, 1), node(q, st, 1)))
            kinds.append("crown" if st == nf else "flank")
    junction_panels = hexagon_panels(hex_c, hex_v, panels, kinds)
    structure = n5b8_structure(np.asarray(coords), np.asarray(panels), g.ribbon_thickness)
    pc = structure.panel_centres

    def ribbon_points(q, stations, panel_ids) -> list[int]:
        pts = [node(q, st, side) for st in stations for side in (0, 1)]
        return pts + [int(pc[panel_at[(q, st)]]) for st in panel_ids]

    strips: list[Strip] = []
    strip_of_bar = {"bottom_strips": [], "top_strips": []}
    hinge_rows: list = []
    pieces: list[StripPiece] = []

    def new_strip(layer, q) -> int:
        fam, _, _, _, line, order = pieces_info[q]
        mid = 0.5 * (centres[ends[q, 0]] + centres[ends[q, 1]])
        strips.append(Strip(len(strips), layer, fam, line, order, (float(mid[0]), float(mid[1]))))
        return strips[-1].id

    for q, (a, b) in enumerate(ends):
        theta = pieces_info[q][1]
        sid = new_strip("bottom", q)
        # bonded to the plates: the vertices across each hexagon, parallel to the piece
        add_bottom_strip(
            structure,
            lambda st, side, q=q: node(q, st, side),
            last,
            tuple(int(hex_v[a, hexagon_vertex(theta, False, s)]) for s in (0, 1)),
            tuple(int(hex_v[b, hexagon_vertex(theta, True, s)]) for s in (0, 1)),
            ribbon_points(q, range(1, last), range(last)) if m.contact else None,
            pieces,
            hinge_rows,
            both,
        )
        strip_of_bar["bottom_strips"] += [sid, sid]

    # Raised plates over the junctions (the hexagon at the crown-edge height): the glue plate.
    zc = g.top_strip_height
    raised = np.zeros((nj, 6), dtype=np.int64)
    for J in range(nj):
        raised[J] = structure.add_nodes([(*(centres[J] + ring[k]), zc) for k in range(6)])
        q6, v = raised[J], hex_v[J]
        structure.add_bars("glue", [(q6[i], q6[j]) for i in range(6) for j in range(i + 1, 6)])
        # The strips end on the junction and are bonded to it: the raised plate stands on the
        # Kapton hexagon as one glue block (a vertical and a diagonal per side face: a rigid prism).
        # Floating as the orthogonal grid's raised square does, it would hang on the six top-strip
        # bars of three pieces (four at the rim), all horizontal as built: measured 57 zero
        # tangent eigenvalues on the n = 1 patch (12 on the triangular n = 1) and a ramp to
        # lambda = 1.2 that crawled (increments of 0.002).
        structure.add_bars("glue", [(v[k], q6[k]) for k in range(6)])
        structure.add_bars("glue", [(v[k], q6[(k + 1) % 6]) for k in range(6)])

    for q, (a, b) in enumerate(ends):
        theta = pieces_info[q][1]
        sid = new_strip("top", q)
        # half at the start: raised plate over junction a -> crown edge (L - c)/2
        add_top_strip_half(
            structure,
            [node(q, nf, s) for s in (0, 1)],
            [node(q, nf + 1, s) for s in (0, 1)],
            [node(q, nf - 1, s) for s in (0, 1)],
            [int(raised[a, hexagon_vertex(theta, True, s)]) for s in (0, 1)],
            [int(raised[a, hexagon_vertex(theta, False, s)]) for s in (0, 1)],
            False,
            ribbon_points(q, range(0, nf), range(0, nf)) if m.contact else None,
            pieces,
            hinge_rows,
            both,
        )
        # half at the end: crown edge (L + c)/2 -> raised plate over junction b
        add_top_strip_half(
            structure,
            [node(q, nf + 1, s) for s in (0, 1)],
            [node(q, nf, s) for s in (0, 1)],
            [node(q, nf + 2, s) for s in (0, 1)],
            [int(raised[b, hexagon_vertex(theta, False, s)]) for s in (0, 1)],
            [int(raised[b, hexagon_vertex(theta, True, s)]) for s in (0, 1)],
            True,
            ribbon_points(q, range(nf + 2, per_seg), range(nf + 1, last)) if m.contact else None,
            pieces,
            hinge_rows,
            both,
        )
        strip_of_bar["top_strips"] += [sid] * 4

    if m.strip_contact:
        structure.add_hinges("strip_contact", np.asarray(hinge_rows, dtype=np.int64))

    centre = 0  # honeycomb_patch lists the centre junction first
    hexagon_node_sets(structure, hex_c, hex_v, raised, junction_panels, centre)
    strip_sections(
        structure,
        g,
        flank=(lx - g.crown_bond_length) / (2 * nf),
        rows_per_point=2,
        strip_rows_per_point=4 if both else 2,  # each row its share
    )
    apply_strip_element(structure, g, m.strip_element, pieces, PUBLISHED_LAMBDA_N, raised.ravel())

    # The circle measure: the junctions next to the centre on its line along each direction (one
    # piece away on one side, across a cell on the other).
    circle = {}
    for fam, theta in FAMILY_ANGLES.items():
        t = math.radians(theta)
        u, nrm = np.array([math.cos(t), math.sin(t)]), np.array([-math.sin(t), math.cos(t)])
        on = np.flatnonzero(np.abs(centres @ nrm) < 1e-6 * p)
        s = centres[on] @ u
        circle[fam] = (int(on[s < 0][np.argmax(s[s < 0])]), int(on[s > 0][np.argmin(s[s > 0])]))

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
        top_junction="glue",
        junction_xy=centres,
        cells=cells,
        pieces=ends,
        piece_family=tuple(pi[0] for pi in pieces_info),
        circle_junctions=circle,
        centre_junction_index=centre,
        panel_kind=np.asarray(kinds),
        strips=strips,
        groups=groups,
        strip_of_bar={k: np.asarray(v, dtype=np.int64) for k, v in strip_of_bar.items()},
        source=PUBLISHED
        + "; honeycomb pieces at a hexagonal plate: assumed (meshes.gridshell_hex)",
    )
    structure.validate()
    return structure
