"""The robotic surface of seed 001 (Fig. 4, 5): an n x n gridshell of Kapton ribbons with bottom and
top LCE strips, in the bar-and-hinge model, with the layout and connectivity of the published
reduced-order model (shared/reference/gridshell_recipes.md). The layout (grid kind: orthogonal,
rhombic, triangular (three families at hexagonal junctions: :mod:`lcefem.meshes.gridshell_tri`) or
hexagonal (the honeycomb: :mod:`lcefem.meshes.gridshell_hex`);
ribbon count, lengths, bonded junctions, wiring) is one
:class:`lcefem.meshes.gridshell_layout.Layout`; what follows describes the orthogonal grid, of which
a rhombic one is the affine image, its free ribbon panels then cut across the ribbon
(``mesh.free_panels``; docs/layouts/rhombic.md).

Coordinates [mm], z up (the top strips' side), z = 0 the flat Kapton grid. n ribbons run along x and
n along y; each is n + 1 segments of length L joined by n junction squares of d x d (d = the ribbon
width); ribbon r (0-based) occupies the band [c_r - d/2, c_r + d/2] with junction centres
c_r = L + d/2 + r (L + d). For the paper's 3 x 3 grid (L = 30, d = 7): ribbons 141 mm long, bands
[30, 37], [67, 74], [104, 111], junction centres 33.5, 70.5, 107.5. Every segment has the arch
z = gap sin^2(pi s/L) and the 5 + 1 + 5 panels of the composite beam
(:class:`~lcefem.meshes.composite_beam.BeamBarHingeMesh`), all discretised N5B8; the junction
squares are shared by the crossing x and y ribbons.

Strips (one id per strip; ``info["strips"]`` lists them):

* bottom: one per segment, junction edge to junction edge (or ribbon end to junction edge), two bars
  along the ribbon's edges: (n + 1) per ribbon, 2 n (n + 1) in all (24 for n = 3);
* top: one per junction and direction, from the crown edge of one segment over the raised square to
  the crown edge of the next (11.5 + 7 + 11.5 = 30 mm): n per ribbon, 2 n^2 in all (18 for n = 3),
  as the published model. The raised square (one per junction, at the crown-edge height 0.982 mm)
  is shared by the x and y top strips: with ``top_junction = "lce"`` its edges along x belong to the
  x strip and its edges along y to the y strip (each strip's full 30 mm contracts); with "glue" it
  is the published model's stiff glue square.

How the top strips relate to the paper's count: the paper counts 24 top segments (48 LCE segments in
all, Fig. 4A), i.e. one top segment per 30 mm ribbon segment, each with its own 25 ohm coil section.
Our (and the published model's) top strip over junction j covers the inner halves (11.5 mm) of the
two segments beside it plus the junction; so paper top segment k of a ribbon is the union of the
halves of our top strips k - 1 and k over it, and the outer halves of the two end segments of each
ribbon (0-18.5 and 122.5-141 mm) carry no top strip. Driving a whole channel (Tx, Ty) is the same
in both counts; per-segment recipes map each of our top strips to the two paper segments it
touches (``info["top_strip_paper_segments"]``).

Groups (``info["groups"]``, strip ids): "XD1".."XDn", "YD1".."YDn" (bottom strips per ribbon),
"XU1".."XUn", "YU1".."YUn" (top strips per ribbon), ribbon 1 at the lowest y (x ribbons) or lowest x
(y ribbons); the paper's channels (Fig. 4A) "Bx", "By", "Tx", "Ty" are the unions.

Node sets: "junction_corners" (n, n, 4) indexed [i_x, i_y] (junction at x = c_ix, y = c_iy),
"junction_centres" (n, n) (N5B8 centre nodes), "top_squares" (n, n, 4), "ribbon_ends_x" /
"ribbon_ends_y" (n, 2, 2: ribbon, end (low, high), side), "bottom_strip_ends" (all nodes bottom
strips attach to), "centre_junction" (4 corners of the middle junction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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
from lcefem.meshes.gridshell_fe import junction_centres
from lcefem.meshes.gridshell_layout import BAR_HINGE_KINDS, Layout
from lcefem.meshes.gridshell_strips import add_bottom_strip, add_top_strip
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.parameters import check

DIRECTIONS = ("x", "y")
#: The paper's four control channels (seed 001, Fig. 4A): (layer, direction).
CHANNELS = {"Tx": ("top", "x"), "Ty": ("top", "y"), "Bx": ("bottom", "x"), "By": ("bottom", "y")}


#: The layout (the published 3 x 3 by default): :class:`lcefem.meshes.gridshell_layout.Layout`; the
#: former name of the ribbon count's section, kept for its callers.
GridshellLayout = Layout


@dataclass(frozen=True)
class Strip:
    """One LCE strip: id, layer ("bottom"/"top"), direction ("x"/"y"), ribbon (0-based), index along
    the ribbon (segment for bottom strips, junction for top strips), midpoint (x, y) [mm]."""

    id: int
    layer: str
    direction: str
    ribbon: int
    index: int
    midpoint: tuple[float, float]

    @property
    def group(self) -> str:
        """Published group name, e.g. "XD1" (bottom, x ribbon 1) or "YU3"."""
        return f"{self.direction.upper()}{'D' if self.layer == 'bottom' else 'U'}{self.ribbon + 1}"

    @property
    def channel(self) -> str:
        return f"{'T' if self.layer == 'top' else 'B'}{self.direction}"


def build_gridshell_bar_hinge(
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    layout: Layout = Layout(),
    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
) -> BarHingeStructure:
    """Bar-and-hinge structure of the gridshell (see the module docstring) from its layout
    (:class:`~lcefem.meshes.gridshell_layout.Layout`: orthogonal or rhombic, ribbon count, lengths,
    bonded junctions, wiring; the published 3 x 3 by default).

    A rhombic layout is built in the oblique coordinates of its two families and mapped to the plane
    (x, y) -> x e1 + y e2 as the nodes are placed (``layout.to_plane``), so that every length the
    builder derives (panels, strips, squares) is the plane's; at 90 deg the map is the identity and
    the published structure is unchanged. On a rhombic grid a segment's interior cuts then run
    across the ribbon (``mesh.free_panels`` "auto" / "rectangular": rectangles, and a right
    trapezoid beside each junction edge; the arch along the centre line), so that the panels do
    not lock in bending; "skewed" keeps the affine image's parallelograms. An unbonded junction
    (``layout.glued``) keeps a Kapton square per ribbon (two coincident, unconnected squares; the
    raised top square is shared as before). Wiring tags (``layout.wiring``) are added to
    ``info["groups"]`` and listed in ``info["wiring"]``.

    ``geometry.segments`` is ignored (a ribbon has ``layout.ribbons + 1`` segments); the junction
    squares are ribbon_width x ribbon_width, so ``geometry.junction_length`` must equal
    ``geometry.ribbon_width``. Bar groups, hinge groups, contacts and sections as
    :func:`~lcefem.meshes.composite_beam.build_beam_bar_hinge`; ``info["strip_of_bar"]`` gives, per
    group ("bottom_strips", "top_strips"), the strip id of every bar.
    """
    layout = layout.checked()
    if layout.kind not in BAR_HINGE_KINDS:
        raise InputError(
            f"layout.kind = {layout.kind!r}: the bar-and-hinge builder builds "
            f"{', '.join(BAR_HINGE_KINDS)}"
        )
    if layout.kind == "triangular":
        from lcefem.meshes.gridshell_tri import build_triangular_bar_hinge

        return build_triangular_bar_hinge(geometry, layout, mesh)
    if layout.kind == "hexagonal":
        from lcefem.meshes.gridshell_hex import build_hexagonal_bar_hinge

        return build_hexagonal_bar_hinge(geometry, layout, mesh)
    g = layout.geometry(geometry)
    if g.crown_bond_length >= g.segment_length:
        raise InputError(
            f"geometry.crown_bond_length = {g.crown_bond_length}: must be < "
            f"segment_length = {g.segment_length} mm"
        )
    check(g, "geometry")
    n = layout.ribbons
    m = mesh.checked()
    bonded = layout.glued_junctions()  # None: all
    plane = layout.to_plane if layout.oblique else None
    # a strip's contact quad split along both diagonals keeps the grid's mirror symmetries; one
    # diagonal (the published structure, its digest) maps onto the other under a mirror
    both = m.contact_diagonals == "both" or (m.contact_diagonals == "auto" and layout.oblique)
    if abs(g.junction_length - g.ribbon_width) > 1e-12:
        raise InputError(
            f"geometry.junction_length = {g.junction_length}: must equal ribbon_width = "
            f"{g.ribbon_width} mm in a gridshell (the junctions are where ribbons cross)"
        )
    nseg = n + 1
    nf = m.flank_panels
    lx, d = g.segment_length, g.ribbon_width
    s_lo, s_hi = g.crown_edges
    local = np.concatenate([np.linspace(0.0, s_lo, nf + 1), np.linspace(s_hi, lx, nf + 1)])
    per_seg = local.size
    last = per_seg - 1
    # Rectangular free panels (mesh.free_panels) on a rhombic grid: the interior cuts of a segment
    # run across the ribbon instead of along the other family. A side of the ribbon at o [mm]
    # (builder coordinates, across along the other family) from its centre line lies o cos a
    # further along than the centre line, so its node of a cut at p along the centre line goes to
    # p - o cos a. The junction edges stay (the rhombus's sides); the first and last panel of a
    # segment become trapezoids that take the skew. The flank's cuts after the first are equally
    # spaced from the trapezoid's short side (half the skew d cot a / 2 past the junction edge's
    # centre) to the crown edge, so the trapezoid's short side is as long as each rectangle.
    rect = layout.oblique and m.free_panels in ("auto", "rectangular")
    cos_a = float(layout.directions()[1, 0])
    cuts = local
    if rect:
        half_skew = 0.5 * g.ribbon_width * abs(cos_a)
        if s_lo <= half_skew:
            raise InputError(
                f"mesh.free_panels = {m.free_panels!r}: the crown edge {s_lo:.3f} mm from the "
                f"junction must lie beyond half the skew {half_skew:.3f} mm; use 'skewed'"
            )
        flank = half_skew + (s_lo - half_skew) * np.arange(1, nf + 1) / nf
        flank[-1] = s_lo
        cuts = np.concatenate([[0.0], flank, lx - flank[::-1], [lx]])
    centres = junction_centres(g, n)
    length = nseg * lx + n * d

    # Corner nodes, shared where ribbons cross (junction corners only, all at z = 0).
    coords: list[tuple[float, float, float]] = []
    index: dict[tuple[int, int], int] = {}

    def add(x: float, y: float, z: float, own: str | None = None) -> int:
        # ``own``: the ribbon direction at an unbonded junction's corner (not shared across ribbons)
        key = (round(x * 1e6), round(y * 1e6), own)
        if key in index:
            return index[key]
        index[key] = len(coords)
        if plane is not None:
            x, y = (float(v) for v in plane(np.array([x, y])))
        coords.append((x, y, z))
        return index[key]

    def unbonded(direction: str, r: int, s: int, a: int) -> str | None:
        """The direction when station a of segment s of ribbon r is a corner of an unbonded
        junction."""
        if bonded is None:
            return None
        j = s if (a == last and s < n) else s - 1 if (a == 0 and s > 0) else None
        if j is None:
            return None
        junction = (j, r) if direction == "x" else (r, j)
        return None if junction in bonded else direction

    # ribbon frame: x ribbons along +x, side 0 at the lower y; y ribbons along +y, side 0 at the
    # higher x, so that along x across = +z for both (the beam builder's orientation).
    node_of = {}
    for direction in DIRECTIONS:
        for r in range(n):
            for s in range(nseg):
                for a, sa in enumerate(local):
                    along = g.segment_start(s) + sa
                    z = float(g.arch_height(sa))
                    own = unbonded(direction, r, s, a)
                    for side in (0, 1):
                        if rect and 0 < a < last:
                            # the cut across the ribbon; the arch follows the ribbon's centre line
                            offset = (side - 0.5) * d if direction == "x" else (0.5 - side) * d
                            along = g.segment_start(s) + cuts[a] - offset * cos_a
                            z = float(g.arch_height(cuts[a]))
                        if direction == "x":
                            nid = add(along, centres[r] - 0.5 * d + side * d, z, own)
                        else:
                            nid = add(centres[r] + 0.5 * d - side * d, along, z, own)
                        node_of[(direction, r, s, a, side)] = nid

    def node(direction: str, r: int, s: int, a: int, side: int) -> int:
        return node_of[(direction, r, s, a, side)]

    panels, kinds, panel_at = [], [], {}
    junction_panel = {}
    for direction in DIRECTIONS:
        for r in range(n):
            for s in range(nseg):
                for a in range(per_seg - 1):
                    panel_at[(direction, r, s, a)] = len(panels)
                    panels.append(
                        (
                            node(direction, r, s, a, 0),
                            node(direction, r, s, a + 1, 0),
                            node(direction, r, s, a + 1, 1),
                            node(direction, r, s, a, 1),
                        )
                    )
                    kinds.append("crown" if a == nf else "flank")
                if s + 1 < nseg and (
                    direction == "x" or (bonded is not None and (r, s) not in bonded)
                ):
                    # each bonded junction square once (with the x ribbon); an unbonded one per
                    # ribbon
                    if direction == "x":
                        junction_panel[(s, r)] = len(panels)
                    panels.append(
                        (
                            node(direction, r, s, last, 0),
                            node(direction, r, s + 1, 0, 0),
                            node(direction, r, s + 1, 0, 1),
                            node(direction, r, s, last, 1),
                        )
                    )
                    kinds.append("junction")
    structure = n5b8_structure(np.asarray(coords), np.asarray(panels), g.ribbon_thickness)
    pc = structure.panel_centres

    def ribbon_points(direction, r, s, stations, panel_ids) -> list[int]:
        pts = [node(direction, r, s, a, side) for a in stations for side in (0, 1)]
        return pts + [int(pc[panel_at[(direction, r, s, a)]]) for a in panel_ids]

    strips: list[Strip] = []
    strip_of_bar = {"bottom_strips": [], "top_strips": []}
    hinge_rows = []

    def new_strip(layer, direction, r, k, mid_along) -> int:
        mid = (mid_along, centres[r]) if direction == "x" else (centres[r], mid_along)
        if plane is not None:
            mid = plane(np.asarray(mid))
        strips.append(Strip(len(strips), layer, direction, r, k, (float(mid[0]), float(mid[1]))))
        return strips[-1].id

    pieces: list[StripPiece] = []  # for mesh.strip_element (apply_strip_element)
    # Bottom strips: chords of every segment along both ribbon edges.
    for direction in DIRECTIONS:
        for r in range(n):
            for s in range(nseg):
                sid = new_strip("bottom", direction, r, s, g.segment_start(s) + 0.5 * lx)
                nd = lambda a, side: node(direction, r, s, a, side)  # noqa: E731
                pts = None
                if m.contact:
                    pts = ribbon_points(direction, r, s, range(1, last), range(per_seg - 1))
                add_bottom_strip(
                    structure,
                    nd,
                    last,
                    tuple(
                        node(direction, r, s - 1, last, k) if s > 0 else nd(1, k) for k in (0, 1)
                    ),
                    tuple(
                        node(direction, r, s + 1, 0, k) if s + 1 < nseg else nd(last - 1, k)
                        for k in (0, 1)
                    ),
                    pts,
                    pieces,
                    hinge_rows,
                    both,
                )
                strip_of_bar["bottom_strips"] += [sid, sid]

    # Raised squares over the junctions, corners (x0,y0), (x1,y0), (x1,y1), (x0,y1).
    zc = g.top_strip_height
    squares = np.zeros((n, n, 4), dtype=np.int64)
    for ix in range(n):
        for iy in range(n):
            x0, y0 = centres[ix] - 0.5 * d, centres[iy] - 0.5 * d
            corners = [(x0, y0), (x0 + d, y0), (x0 + d, y0 + d), (x0, y0 + d)]
            if plane is not None:
                corners = [tuple(float(v) for v in plane(np.asarray(c))) for c in corners]
            squares[ix, iy] = structure.add_nodes([(cx, cy, zc) for cx, cy in corners])
            q = squares[ix, iy]
            if m.top_junction == "glue":
                structure.add_bars(
                    "glue",
                    [
                        (q[0], q[1]),
                        (q[1], q[2]),
                        (q[2], q[3]),
                        (q[3], q[0]),
                        (q[0], q[2]),
                        (q[1], q[3]),
                    ],
                )
            if m.contact:
                jp = structure.panels[junction_panel[(ix, iy)]]
                structure.add_contacts(
                    "top_square_contact",
                    [
                        (int(p), *t)
                        for p in q
                        for t in ((jp[0], jp[3], jp[1]), (jp[2], jp[1], jp[3]))
                    ],
                )

    # Top strips: crown edge of segment j -> square over junction j -> crown edge of segment j + 1.
    for direction in DIRECTIONS:
        for r in range(n):
            for j in range(n):
                sid = new_strip("top", direction, r, j, centres[j])
                q = squares[j, r] if direction == "x" else squares[r, j]
                # square corners in the ribbon frame: (entry side 0, entry side 1, exit side 1,
                # exit side 0), entry at the lower along-coordinate.
                if direction == "x":
                    e0, e1, x1, x0 = q[0], q[3], q[2], q[1]
                else:  # side 0 at the higher x
                    e0, e1, x1, x0 = q[1], q[0], q[3], q[2]
                left = [node(direction, r, j, nf + 1, side) for side in (0, 1)]
                right = [node(direction, r, j + 1, nf, side) for side in (0, 1)]
                nbars = add_top_strip(
                    structure,
                    (
                        left,
                        [node(direction, r, j, nf, s) for s in (0, 1)],
                        [node(direction, r, j, nf + 2, s) for s in (0, 1)],
                    ),
                    (
                        right,
                        [node(direction, r, j + 1, nf + 1, s) for s in (0, 1)],
                        [node(direction, r, j + 1, nf - 1, s) for s in (0, 1)],
                    ),
                    (e0, e1),
                    (x0, x1),
                    m.top_junction == "lce",
                    (
                        ribbon_points(
                            direction, r, j, range(nf + 2, per_seg), range(nf + 1, per_seg - 1)
                        ),
                        ribbon_points(direction, r, j + 1, range(0, nf), range(0, nf)),
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

    jc = np.zeros((n, n, 4), dtype=np.int64)
    jcent = np.zeros((n, n), dtype=np.int64)
    for (ix, iy), p in junction_panel.items():
        jc[ix, iy] = structure.panels[p]
        jcent[ix, iy] = pc[p]
    ends = {}
    for direction in DIRECTIONS:
        ends[direction] = np.array(
            [
                [
                    [node(direction, r, 0, 0, side) for side in (0, 1)],
                    [node(direction, r, n, last, side) for side in (0, 1)],
                ]
                for r in range(n)
            ],
            dtype=np.int64,
        )
    sets = structure.node_sets
    sets["junction_corners"] = jc
    sets["junction_centres"] = jcent
    sets["top_squares"] = squares
    sets["ribbon_ends_x"] = ends["x"]
    sets["ribbon_ends_y"] = ends["y"]
    sets["bottom_strip_ends"] = np.unique(structure.bars["bottom_strips"])
    sets["centre_junction"] = jc[n // 2, n // 2]
    # As the composite beam's, with a contact row per point and triangle of a strip quad (two; four
    # with both diagonals) and two per raised-square corner.
    strip_sections(
        structure,
        g,
        flank=(lx - g.crown_bond_length) / (2 * nf),
        rows_per_point=2,
        strip_rows_per_point=4 if both else 2,
    )
    apply_strip_element(
        structure, g, m.strip_element, pieces, PUBLISHED_LAMBDA_N, squares.reshape(-1)
    )

    groups: dict[str, list[int]] = {}
    for st in strips:
        groups.setdefault(st.group, []).append(st.id)
    for name, (layer, direction) in CHANNELS.items():
        groups[name] = [st.id for st in strips if st.layer == layer and st.direction == direction]
    wiring = add_wiring(layout, strips, groups)
    paper_segments = {st.id: (st.index, st.index + 1) for st in strips if st.layer == "top"}
    structure.info.update(
        kind=layout.kind,
        angle=layout.angle,
        wiring=wiring,
        layout=layout,
        ribbons=n,
        segments_per_ribbon=nseg,
        flank_panels=nf,
        free_panels="skewed" if layout.oblique and not rect else "rectangular",
        top_junction=m.top_junction,
        ribbon_length=length,
        junction_centres_1d=centres,
        panel_kind=np.asarray(kinds),
        strips=strips,
        groups={k: np.asarray(v, dtype=np.int64) for k, v in groups.items()},
        strip_of_bar={k: np.asarray(v, dtype=np.int64) for k, v in strip_of_bar.items()},
        top_strip_paper_segments=paper_segments,
        source=PUBLISHED,
    )
    structure.validate()
    return structure


def add_wiring(
    layout: Layout, strips: list[Strip], groups: dict[str, list[int]], channels=CHANNELS
) -> tuple:
    """Add the layout's wiring tags to ``groups`` (strip ids by tag); return the tags in order (a
    named wiring: the ``channels``, Tx, Ty, Bx, By on a two-family grid; the groups XD1..YUn; or
    the strip ids)."""
    table = layout.wiring_table()
    if table == "channels":
        return tuple(channels)
    if table == "ribbons":
        return tuple(sorted(k for k in groups if k not in channels))
    if table == "strips":
        return tuple(st.id for st in strips)
    tags = []
    for tag, selections in table:
        ids: list[int] = []
        for key in selections:
            key = FAMILIES.get(key, key)
            if isinstance(key, int):
                if not 0 <= key < len(strips):
                    raise InputError(
                        f"layout.wiring.{tag}: strip id {key} out of range 0..{len(strips) - 1}"
                    )
                ids.append(key)
            elif key in ("T", "B"):
                ids += [st.id for st in strips if st.layer == ("top" if key == "T" else "bottom")]
            elif key in groups:
                ids += list(groups[key])
            else:
                raise InputError(
                    f"layout.wiring.{tag}: unknown selection {key!r} (allowed: T, B, "
                    f"{', '.join(sorted(groups))}, a strip id)"
                )
        ids = sorted(set(ids))
        if tag in groups and sorted(groups[tag]) != ids:
            raise InputError(
                f"layout.wiring: tag {tag!r} is a built-in group with other strips; "
                "choose another name"
            )
        groups[tag] = ids
        tags.append(tag)
    return tuple(tags)


def bar_midpoints(structure: BarHingeStructure, group: str) -> np.ndarray:
    """As-built midpoints (m, 3) [mm] of the bars of a strip group."""
    pairs = structure.bars[group]
    return 0.5 * (structure.nodes[pairs[:, 0]] + structure.nodes[pairs[:, 1]])


#: Families of the published recipes (all ribbons of one layer and direction) -> channel.
FAMILIES = {"XD": "Bx", "YD": "By", "XU": "Tx", "YU": "Ty"}
STRIP_GROUPS = ("bottom_strips", "top_strips")


def resolve_bar_values(
    structure: BarHingeStructure, assignments: dict, default: float, name: str = "strips"
) -> dict[str, np.ndarray]:
    """Per-bar values by strip group ("bottom_strips", "top_strips") from ``{key: value}`` applied
    in order (later keys override earlier ones; bars not named get ``default``). Keys:

    * a channel "Tx", "Ty", "Bx", "By" (seed 001, Fig. 4A), or "T" / "B" (a whole layer);
    * a published family "XD", "YD", "XU", "YU" (= the channels) or group "XD1" .. "YU3";
    * a half-plane selection "XD:x<70.5" (the bars of a family whose as-built midpoint lies below /
      above the coordinate, as the published wave and dustpan recipes; a bar whose midpoint lies on
      the line, e.g. the raised square of the middle top strip, gets the mean of the values of the
      two sides);
    * a strip id (int, :class:`Strip`.id).
    """
    info = structure.info
    sob = info["strip_of_bar"]
    out = {g: np.full(sob[g].size, float(default)) for g in STRIP_GROUPS}
    on_line_set: dict[str, np.ndarray] = {
        g: np.zeros(sob[g].size, dtype=bool) for g in STRIP_GROUPS
    }
    for key, value in assignments.items():
        value = float(value)
        if isinstance(key, str) and ":" in key:
            family, cond = key.split(":", 1)
            op = "<" if "<" in cond else ">" if ">" in cond else None
            parts = cond.split(op) if op else []
            ok = family in FAMILIES and len(parts) == 2 and parts[0] in ("x", "y")
            try:
                bound = float(parts[1]) if ok else 0.0
            except ValueError:
                ok = False
            if not ok:
                raise InputError(
                    f"{name}: bad selection {key!r} (form 'XD:x<70.5': family XD, YD, "
                    f"XU or YU, axis x or y, < or >, a coordinate in mm)"
                )
            ids = set(select_strips(structure, FAMILIES[family], name).tolist())
            k = 0 if parts[0] == "x" else 1
            for g in STRIP_GROUPS:
                mid = bar_midpoints(structure, g)[:, k]
                mine = np.isin(sob[g], list(ids))
                side = (mid < bound - 1e-9) if op == "<" else (mid > bound + 1e-9)
                out[g][mine & side] = value
                line = mine & (np.abs(mid - bound) <= 1e-9)
                seen = line & on_line_set[g]
                out[g][seen] = 0.5 * (out[g][seen] + value)
                fresh = line & ~on_line_set[g]
                out[g][fresh] = value
                on_line_set[g] |= line
            continue
        ids = select_strips(structure, key, name)
        for g in STRIP_GROUPS:
            out[g][np.isin(sob[g], ids)] = value
    return out


def select_strips(structure: BarHingeStructure, key, name: str = "strips") -> np.ndarray:
    """Strip ids selected by a channel, layer, family, group or strip id (see
    :func:`resolve_bar_values`)."""
    info = structure.info
    strips = info["strips"]
    groups = info["groups"]
    if isinstance(key, (int, np.integer)) and not isinstance(key, bool):
        if not 0 <= key < len(strips):
            raise InputError(f"{name}: strip id {key} out of range 0..{len(strips) - 1}")
        return np.array([key], dtype=np.int64)
    key = FAMILIES.get(key, key)
    if key in ("T", "B"):
        layer = "top" if key == "T" else "bottom"
        return np.asarray([s.id for s in strips if s.layer == layer], dtype=np.int64)
    if key in groups:
        return groups[key]
    allowed = ", ".join(["T", "B", *sorted(groups), *FAMILIES, "XD:x<70.5", "a strip id"])
    raise InputError(f"{name}: unknown strip selection {key!r} (allowed: {allowed})")


def diagonal_mirror(structure: BarHingeStructure, which: str = "diag") -> np.ndarray:
    """Node i -> the node at its mirror image about a diagonal of a two-family grid (orthogonal or
    rhombic, n x n): "diag" swaps the families ((u, v) -> (v, u) in the oblique coordinates of
    e1, e2), "anti" the other diagonal ((u, v) -> (L - v, L - u), L the ribbon length [mm]).
    Coincident nodes (a strip end's centroid nodes, one per strip) are told apart by the positions
    of the nodes they are barred to. Raises InputError when a node has no image (the structure is
    not mirror-symmetric in its nodes)."""
    layout = structure.info["layout"]
    if layout.kind not in ("orthogonal", "rhombic") or which not in ("diag", "anti"):
        raise InputError(
            f"diagonal_mirror: kind {layout.kind!r}, which {which!r}: a two-family grid and "
            "'diag' or 'anti'"
        )
    x = structure.nodes
    e = layout.directions()
    uv = np.linalg.solve(e.T, x[:, :2].T).T
    m = uv[:, ::-1] if which == "diag" else structure.info["ribbon_length"] - uv[:, ::-1]
    return node_image_map(structure, np.column_stack([m @ e, x[:, 2]]), "diagonal_mirror")


def line_mirror(structure: BarHingeStructure, angle: float) -> np.ndarray:
    """Node i -> the node at its mirror image about the vertical plane through the centre
    junction's centroid at ``angle`` [deg] from x (any layout with the node set
    "centre_junction"; coincident nodes told apart as in :func:`diagonal_mirror`). Raises
    InputError when a node has no image (that line is not a mirror of the structure)."""
    x = structure.nodes
    c = np.r_[x[np.ravel(structure.node_sets["centre_junction"])][:, :2].mean(axis=0), 0.0]
    a = math.radians(2.0 * angle)
    m = np.array([[math.cos(a), math.sin(a), 0.0], [math.sin(a), -math.cos(a), 0.0], [0, 0, 1]])
    return node_image_map(structure, (x - c) @ m.T + c, f"line_mirror({angle:g} deg)")


def node_image_map(structure: BarHingeStructure, image: np.ndarray, what: str) -> np.ndarray:
    """Node i -> the node at ``image[i]`` [mm] (the nodes under a mirror), coincident nodes told
    apart by the images of the nodes they are barred to (to 0.1 um). Raises InputError naming
    ``what`` when a node has no image."""
    x = structure.nodes

    def key(p) -> tuple:
        return tuple(int(round(v * 1e4)) for v in p)  # 0.1 um

    near: list[set] = [set() for _ in range(structure.num_nodes)]
    for a, b in np.vstack([np.zeros((0, 2), dtype=np.int64), *structure.bars.values()]):
        near[a].add(b)
        near[b].add(a)
    index: dict = {}
    for i in range(structure.num_nodes):
        index.setdefault((key(x[i]), frozenset(key(x[j]) for j in near[i])), []).append(i)
    out = np.full(structure.num_nodes, -1, dtype=np.int64)
    for i in range(structure.num_nodes):
        hit = index.get((key(image[i]), frozenset(key(image[j]) for j in near[i])), [])
        if len(hit) == 1:
            out[i] = hit[0]
    if np.any(out < 0):
        raise InputError(f"{what}: {int(np.sum(out < 0))} nodes have no mirror image")
    return out


def unmatched_mirror_rows(structure: BarHingeStructure, perm: np.ndarray) -> dict[str, int]:
    """Per element group ("bars.<g>", "hinges.<g>", "contacts.<g>", "panels"): the rows whose image
    under the node map ``perm`` (:func:`diagonal_mirror`) is not a row of the group (bars: node
    pairs; hinges: axis and wings as pairs; contacts: point and triangle; panels: corner sets).
    All zero: the structure maps onto itself."""

    def canon(kind: str, r: tuple):
        if kind in ("bars", "panels"):
            return frozenset(r)
        if kind == "hinges":
            return frozenset(r[:2]), frozenset(r[2:])
        return r[0], frozenset(r[1:])

    out = {}
    groups = [("panels", "panels", structure.panels)]
    for kind in ("bars", "hinges", "contacts"):
        groups += [(kind, f"{kind}.{k}", v) for k, v in getattr(structure, kind).items()]
    for kind, name, rows in groups:
        have = {canon(kind, tuple(r)) for r in rows.tolist()}
        out[name] = len({canon(kind, tuple(r)) for r in perm[rows].tolist()} - have)
    return out
