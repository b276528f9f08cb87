"""The composite beam of seed 001 (Fig. 3): a Kapton ribbon of 30 mm segments joined by 7 x 7 mm
junctions, with bottom LCE strips from junction to junction and top LCE strips from crown to crown
over each junction, following the connectivity of the published reduced-order model
(shared/reference/published_reduced_model.md).

Coordinates [mm]: x along the beam (the first segment starts at x = 0), y across the ribbon
(0 <= y <= width), z up (the top strips' side). Segment s (0-based) spans
x = s (L + d) ... s (L + d) + L; junction j joins segments j and j + 1. The flat as-built ribbon
carries the small arch z = gap sin^2(pi s/L) (s the distance from the segment's start) that makes it
buckle upwards. Every segment has a central "crown" region of length ``crown_bond_length`` where the
top strips are bonded; the top strips span from the crown's edge in one segment, over the junction,
to the crown's edge in the next (11.5 + 7 + 11.5 = 30 mm); the bottom strips span each segment as
chords between its ends (30 mm). Both have the ribbon's straight length in the as-built (nematic)
state. The strips touch the ribbon as built; in the bar-and-hinge structure frictionless contacts
keep each segment's ribbon on its side of its bottom strip, the ribbon under a top strip below it,
and the raised square of a top strip on its junction (the published model has no such contact).

:class:`CompositeBeamGeometry` holds only what a continuum (FE) builder can use too; the
bar-and-hinge discretisation choices live in :class:`BeamBarHingeMesh`.

Curvature (:func:`lcefem.solvers.analysis.curvature.beam_curvature`): the signed curvature of the
circle fitted (Pratt's algebraic fit) through the *stations* of the middle segments, the stations
being the ends' centres and the junction centres (centre of each junction square on the ribbon: the
mean of its four corners). It is positive when the circle's centre lies on the bottom side, i.e.
when the beam bends towards its bottom strips (ends lower than the middle), which happens when the
top strips are longer: the sign convention of Eq. 2 (:func:`lcefem.models.empirical.eq2_curvature`).
(The paper's surface curvatures, e.g. the dome's -0.017 1/mm, use the opposite sign: kappa = +z''
with z up.) The stations depend only on the geometry of the deformed ribbon, not on the
discretisation; note that a junction's centroid lies on the chord of its square, so a ribbon wrapped
on a circle of radius R gives 1/(R cos(d/2R)) (0.2 % more than 1/R at R = 60 mm, d = 7 mm).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, n5b8_structure
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param

PUBLISHED = (
    "published reduced-order model (Daraio-lab/RoboticSurface_SciRob_LiuK; "
    "shared/reference/published_reduced_model.md)"
)


@dataclass(frozen=True)
class CompositeBeamGeometry:
    """Dimensions of the composite beam (shared by the bar-and-hinge and the FE builders)."""

    segments: int = param(
        4,
        "-",
        "chosen: 4 segments (3 junctions) as one ribbon of the published "
        "surface; at (lambda_T, lambda_B) = (1.33, 1.05) the middle curvature is "
        "0.0337, 0.0386, 0.0383, 0.0383 1/mm for 2, 4, 6, 8 segments (bar-and-hinge; "
        "validation case beam_segment_count_bh)",
        minimum=2,
        maximum=40,
    )
    segment_length: float = param(
        30.0, "mm", PUBLISHED + ": Lx = 30 mm (l_p of Eq. 2)", positive=True
    )
    junction_length: float = param(
        7.0, "mm", PUBLISHED + ": 7 x 7 mm junction squares", positive=True
    )
    ribbon_width: float = param(
        7.0, "mm", "seed 001 Materials and Methods: ribbons 7 mm wide", positive=True
    )
    ribbon_thickness: float = param(
        0.127, "mm", "seed 001 Materials and Methods: 127 um Kapton film", positive=True
    )
    arch_gap: float = param(
        1.127,
        "mm",
        PUBLISHED + ": initial arch z = gap sin^2(pi x/Lx), gap = tp + ta/2",
        minimum=0.0,
    )
    strip_width: float = param(
        5.0, "mm", "seed 001: mould channel 5 mm wide (cast, isotropic section)", positive=True
    )
    strip_thickness: float = param(
        2.0,
        "mm",
        "seed 001: mould channel 2 mm deep (cast, isotropic section; t_a of Eq. 2)",
        positive=True,
    )
    crown_bond_length: float = param(
        7.0,
        "mm",
        PUBLISHED + ": central 7 mm panel of each segment, at whose edges the top strips attach",
        positive=True,
    )

    @property
    def pitch(self) -> float:
        """Segment + junction length [mm]."""
        return self.segment_length + self.junction_length

    @property
    def total_length(self) -> float:
        """Ribbon length [mm] = N L + (N - 1) d."""
        return self.segments * self.segment_length + (self.segments - 1) * self.junction_length

    @property
    def strip_section(self) -> float:
        """Cast (isotropic) LCE strip section [mm^2]."""
        return self.strip_width * self.strip_thickness

    def arch_height(self, s):
        """Initial arch z(s) = gap sin^2(pi s/L) [mm] at distance s [mm] from a segment's start."""
        return self.arch_gap * np.sin(np.pi * np.asarray(s, dtype=float) / self.segment_length) ** 2

    @property
    def crown_edges(self) -> tuple[float, float]:
        """Local positions s [mm] of the crown region's edges, (L - c)/2 and (L + c)/2."""
        half = 0.5 * self.crown_bond_length
        return 0.5 * self.segment_length - half, 0.5 * self.segment_length + half

    @property
    def top_strip_height(self) -> float:
        """Height [mm] of the top strips over the junctions: the arch at the crown edge (0.982
        mm)."""
        return float(self.arch_height(self.crown_edges[1]))

    def segment_start(self, s: int) -> float:
        """x [mm] of the start of segment s (0-based)."""
        return s * self.pitch

    def checked(self) -> "CompositeBeamGeometry":
        check(self, "geometry")
        if not isinstance(self.segments, int):
            raise InputError(f"geometry.segments = {self.segments!r}: must be an integer >= 2")
        if self.crown_bond_length >= self.segment_length:
            raise InputError(
                f"geometry.crown_bond_length = {self.crown_bond_length}: must be < "
                f"segment_length = {self.segment_length} mm"
            )
        return self


@dataclass(frozen=True)
class BeamBarHingeMesh:
    """Bar-and-hinge discretisation of the composite beam (choices an FE builder does not use)."""

    flank_panels: int = param(
        5,
        "-",
        PUBLISHED + ": 5 panels of 2.3 mm on each side of the crown panel (the 5 + 1 + 5 layout)",
        minimum=1,
        maximum=200,
    )
    top_junction: str = param(
        "lce",
        "-",
        "'lce': the top strip's 7 mm over a junction is LCE and "
        "contracts with the rest (its 30 mm free span is one LCE strip, as "
        "lambda_T of Eq. 2 assumes); 'glue': the published model's stiff glue "
        "square (only the 2 x 11.5 mm contract)",
    )
    strip_contact: bool = param(
        True, "-", PUBLISHED + ": weak rotational springs keep each strip on its side of its panel"
    )
    contact: bool = param(
        True,
        "-",
        "added here (absent from the published model): frictionless "
        "unilateral strip-ribbon contact: each segment's ribbon nodes stay above "
        "its bottom strip, the ribbon under a top strip stays below it, and the "
        "raised top square rests on its junction",
    )

    strip_element: str = param(
        "bar",
        "-",
        "how an LCE strip acts on the ribbon: 'bar' ("
        + PUBLISHED
        + ": two-node bars on the ribbon's nodes, no bending stiffness), "
        "'offset' (the bars act at the strip's centroid, t_p/2 + h_s/2 off the "
        "ribbon's mid-surface, on rigid links to the bonded panel), 'bending' "
        "(the strip's own bending stiffness E I, a beam element clamped to its "
        "bonded panels), 'beam' (both; added here, docs/gridshell_calibration.md)",
    )

    contact_diagonals: str = param(
        "auto",
        "-",
        "added here: a gridshell strip's contact quad split along one diagonal ('one', the "
        "published grid's structure as before) or both ('both': the same under the grid's "
        "mirrors); 'auto': both on rhombic, triangular and hexagonal grids, one on the orthogonal "
        "grid (docs/layouts/rhombic.md, triangular.md)",
    )

    free_panels: str = param(
        "auto",
        "-",
        "added here: a rhombic gridshell's free ribbon panels: 'skewed' (the orthogonal grid's "
        "affine image: parallelograms whose cross edges run along the other family, which lock "
        "in bending), 'rectangular' (cross edges across the ribbon; the trapezoid next to each "
        "junction edge takes the skew); 'auto': rectangular on a rhombic grid, the orthogonal "
        "grid unchanged (measured, docs/layouts/rhombic.md)",
    )

    def checked(self) -> "BeamBarHingeMesh":
        check(self, "mesh")
        if self.free_panels not in FREE_PANELS:
            raise InputError(
                f"mesh.free_panels = {self.free_panels!r}: allowed "
                + ", ".join(repr(e) for e in FREE_PANELS)
            )
        if self.contact_diagonals not in CONTACT_DIAGONALS:
            raise InputError(
                f"mesh.contact_diagonals = {self.contact_diagonals!r}: allowed "
                + ", ".join(repr(e) for e in CONTACT_DIAGONALS)
            )
        if self.top_junction not in ("lce", "glue"):
            raise InputError(f"mesh.top_junction = {self.top_junction!r}: allowed 'lce' or 'glue'")
        if self.strip_element not in STRIP_ELEMENTS:
            raise InputError(
                f"mesh.strip_element = {self.strip_element!r}: allowed "
                + ", ".join(repr(e) for e in STRIP_ELEMENTS)
            )
        return self


#: How a gridshell strip's contact quad is split (BeamBarHingeMesh.contact_diagonals).
CONTACT_DIAGONALS = ("auto", "one", "both")
#: How a rhombic gridshell's free ribbon panels are cut (BeamBarHingeMesh.free_panels).
FREE_PANELS = ("auto", "skewed", "rectangular")
#: How an LCE strip acts on the ribbon (BeamBarHingeMesh.strip_element).
STRIP_ELEMENTS = ("bar", "offset", "bending", "beam")


@dataclass
class StripPiece:
    """One straight piece of an LCE strip between two bonded ends, for the strip element: the end
    nodes on each rail (a = (rail 0, rail 1), b likewise), a node of the panel each end is bonded
    to (per rail, on the far side of the end from the piece where there is one), the side of the
    ribbon the strip lies on at each end (-1 below, +1 above, 0: the end node already sits at the
    strip's centroid, e.g. a raised square), and the piece's bar on each rail (group, index)."""

    a: tuple[int, int]
    pad_a: tuple[int, int]
    side_a: int
    b: tuple[int, int]
    pad_b: tuple[int, int]
    side_b: int
    group: str
    bars: tuple[int, int]


def strip_centroid_offset(g: CompositeBeamGeometry, lambda_N: float) -> float:
    """Distance [mm] from the ribbon's mid-surface to a bonded strip's centroid: t_p/2 + h_s/2 with
    the as-built strip thickness h_s = t_a/sqrt(lambda_N) (isochoric spontaneous stretch; the FE
    beam's and gridshell's geometry, :func:`build_beam_fe`): 0.0635 + 0.845 = 0.909 mm."""
    return 0.5 * g.ribbon_thickness + 0.5 * g.strip_thickness / math.sqrt(lambda_N)


def strip_second_moment(g: CompositeBeamGeometry, lambda_N: float) -> float:
    """Second moment of area [mm^4] of the as-built strip section about its width axis,
    w_s h_s^3/12 with (w_s, h_s) = (w_a, t_a)/sqrt(lambda_N) (as the FE's strips): 1.70 mm^4."""
    f = 1.0 / math.sqrt(lambda_N)
    return g.strip_width * f * (g.strip_thickness * f) ** 3 / 12.0


def apply_strip_element(
    structure: BarHingeStructure,
    g: CompositeBeamGeometry,
    element: str,
    pieces: list[StripPiece],
    lambda_N: float,
    raised: np.ndarray,
) -> None:
    """Give the strips their centroid offset and/or bending element (``element``, see
    :attr:`BeamBarHingeMesh.strip_element`); 'bar' leaves the structure as it is.

    * offset: each strip end on the ribbon gets a node at the strip's centroid, e =
      :func:`strip_centroid_offset` along the ribbon's normal (on the strip's side), tied to the
      end node, its neighbour across the width and its bonded-panel node by three bars of the glue
      group (a rigid tripod: E A = 8.9 kN against strip forces below 1 N), and the strip's bar moves
      to it; the ``raised`` nodes (the raised squares the top strips run over) rise by e so that a
      top strip stays straight as built.
    * bending: one :func:`lcefem.models.bar_hinge.strip_beam_element` per piece and rail (half the
      section's second moment each), ``info["strip_beams"]`` (m, 6) rows (a, a2, pa, b, b2, pb)
      and ``sections["strip_beams"] = {"second_moment": I/2}``.
    """
    if element == "bar":
        return
    offset = element in ("offset", "beam")
    e = strip_centroid_offset(g, lambda_N)
    x = structure.nodes
    if offset and len(raised):
        structure.nodes[np.asarray(raised, dtype=np.int64)] += (0.0, 0.0, e)
    ends: dict[tuple, int] = {}  # (end node, across, pad, side) -> its centroid node

    def centroid(node: int, across: int, pad: int, side: int) -> int:
        key = (node, across, pad, side)
        if key not in ends:
            n = np.cross(x[across] - x[node], x[pad] - x[node])
            n = n / np.linalg.norm(n)
            if n[2] * side < 0:
                n = -n
            p = int(structure.add_nodes([x[node] + e * n])[0])
            structure.add_bars("glue", [(p, node), (p, across), (p, pad)])
            ends[key] = p
        return ends[key]

    rows = []
    top_ends: dict[int, int] = {}  # crown-edge ribbon node -> its top strip's centroid node
    for pc in pieces:
        a, b = list(pc.a), list(pc.b)
        if offset:
            if pc.side_a:
                a = [centroid(pc.a[r], pc.a[1 - r], pc.pad_a[r], pc.side_a) for r in (0, 1)]
            if pc.side_b:
                b = [centroid(pc.b[r], pc.b[1 - r], pc.pad_b[r], pc.side_b) for r in (0, 1)]
            for ends_, new_, side in ((pc.a, a, pc.side_a), (pc.b, b, pc.side_b)):
                if side > 0:
                    top_ends.update({int(ends_[r]): int(new_[r]) for r in (0, 1)})
            bars = structure.bars[pc.group]
            for r in (0, 1):
                old = {int(pc.a[r]): a[r], int(pc.b[r]): b[r]}
                i = pc.bars[r]
                bars[i] = [old.get(int(v), int(v)) for v in bars[i]]
        for r in (0, 1):
            rows.append((a[r], a[1 - r], pc.pad_a[r], b[r], b[1 - r], pc.pad_b[r]))
    if offset and "top_strip_contact" in structure.contacts:
        # The ribbon under a top strip stays e below the strip's centroid line (its underside, as
        # built at the crown edge), the plane through the centroid nodes and the raised square.
        rows_c = structure.contacts["top_strip_contact"]
        moved = np.isin(rows_c[:, 1:], list(top_ends)).any(axis=1)
        for col in (1, 2, 3):
            rows_c[:, col] = [top_ends.get(int(v), int(v)) for v in rows_c[:, col]]
        rest = structure.contact_rest.get("top_strip_contact")
        if rest is not None:
            structure.contact_rest["top_strip_contact"] = np.where(moved, rest + e, rest)
    if element in ("bending", "beam"):
        structure.info["strip_beams"] = np.asarray(rows, dtype=np.int64)
        structure.sections["strip_beams"] = {
            "second_moment": 0.5 * strip_second_moment(g, lambda_N)
        }
    structure.info["strip_element"] = element


def strip_contact_rows(end_a, end_b, panel_a, panel_b, far_a, far_b):
    """Two contact hinges at a strip's end: axis across the width, wings panel node and far end."""
    return [(end_a, end_b, panel_a, far_a), (end_b, end_a, panel_b, far_b)]


def strip_sections(
    structure: BarHingeStructure,
    g: CompositeBeamGeometry,
    flank: float,
    rows_per_point: int = 1,
    strip_rows_per_point: int | None = None,
) -> None:
    """Section data of the strip, glue and contact groups [mm, mm^2], shared by the beam and the
    gridshell.

    Contact areas: a raised-square corner carries a quarter of the strip's footprint on the
    junction; a ribbon node half the strip's width over one flank panel of length ``flank`` [mm].
    With ``rows_per_point`` contact rows per point (the gridshell has one per triangle of a strip
    quad) each row carries its share, so the total contact stiffness is the same;
    ``strip_rows_per_point`` (default ``rows_per_point``) for the strips' contacts alone (4 with
    both diagonals of a strip quad, :func:`lcefem.meshes.gridshell_strips.quad_triangles`).
    """
    strip_rows = strip_rows_per_point or rows_per_point
    structure.sections["bottom_strips"] = {"section": g.strip_section}
    structure.sections["top_strips"] = {"section": g.strip_section}
    structure.sections["glue"] = {"area": g.ribbon_width * g.ribbon_thickness}
    structure.sections["top_square_contact"] = {
        "area": 0.25 * g.strip_width * g.junction_length / rows_per_point,
        "depth": g.strip_thickness,
    }
    for name in ("bottom_strip_contact", "top_strip_contact"):
        structure.sections[name] = {
            "area": 0.5 * g.strip_width * flank / strip_rows,
            "depth": g.strip_thickness,
        }


def build_beam_bar_hinge(
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
) -> BarHingeStructure:
    """Bar-and-hinge structure of the composite beam (N5B8 ribbon, strips, glue; published
    connectivity).

    Groups: bars "kapton", "bottom_strips" (2 bars per strip, along y = 0 and y = width),
    "top_strips" (per side: crown edge -> raised junction square [-> across it] -> crown edge),
    "glue"; hinges "bend", "fold", "strip_contact"; point-plane contacts "bottom_strip_contact"
    (ribbon nodes of a segment above its bottom strip's plane), "top_strip_contact" (ribbon nodes
    between a crown edge and the junction below the top strip piece over them) and
    "top_square_contact" (raised-square corners above their junction). ``sections`` holds the
    strips' cast section, the glue bar area and each contact group's area and depth.
    Node sets: "left_end", "right_end" (2 nodes each), "junction_corners" (nj, 4),
    "junction_centres" (nj,), "top_squares" (nj, 4: raised square over each junction),
    "crown_centres" (N,), "middle_panel" (corners of the middle junction panel, or of the middle
    crown panel for odd N), "centre_support" (3 of them: a corner, its neighbour across the
    width, its neighbour along x). ``info["bottom_strip_of_bar"]`` / ``info["top_strip_of_bar"]``
    give each strip bar's strip number.
    """
    g = geometry.checked()
    m = mesh.checked()
    nf = m.flank_panels
    lx, width = g.segment_length, g.ribbon_width
    s_lo, s_hi = g.crown_edges
    local = np.concatenate([np.linspace(0.0, s_lo, nf + 1), np.linspace(s_hi, lx, nf + 1)])
    per_seg = local.size  # stations per segment
    last = per_seg - 1
    # Corner nodes: segment s, station a, side y = 0 (even) / y = width (odd)
    coords = []
    for s in range(g.segments):
        x = g.segment_start(s) + local
        z = g.arch_height(local)
        for xi, zi in zip(x, z):
            coords.append((xi, 0.0, zi))
            coords.append((xi, width, zi))
    coords = np.asarray(coords)

    def node(s: int, a: int, side: int) -> int:
        return 2 * (s * per_seg + a) + side

    panels, kinds, panel_at = [], [], {}
    for s in range(g.segments):
        for a in range(per_seg - 1):
            panel_at[(s, a)] = len(panels)
            panels.append((node(s, a, 0), node(s, a + 1, 0), node(s, a + 1, 1), node(s, a, 1)))
            kinds.append("crown" if a == nf else "flank")
        if s + 1 < g.segments:
            panels.append(
                (node(s, last, 0), node(s + 1, 0, 0), node(s + 1, 0, 1), node(s, last, 1))
            )
            kinds.append("junction")
    structure = n5b8_structure(coords, np.asarray(panels), g.ribbon_thickness)
    kinds = np.asarray(kinds)
    centres = structure.panel_centres

    def ribbon_points(s: int, stations, panel_ids) -> list[int]:
        """Corner nodes at the given stations of segment s and the centres of its given panels."""
        pts = [node(s, a, side) for a in stations for side in (0, 1)]
        return pts + [int(centres[panel_at[(s, a)]]) for a in panel_ids]

    hinge_rows = []
    # Bottom strips: chords between the segment's end stations, one bar per ribbon edge.
    bottom_of_bar = []
    pieces: list[StripPiece] = []
    for s in range(g.segments):
        idx = []
        for side in (0, 1):
            idx += list(
                structure.add_bars("bottom_strips", [(node(s, 0, side), node(s, last, side))])
            )
            bottom_of_bar.append(s)
        # Bonded panels: the junctions on either side (the flank panel at a free end).
        pieces.append(
            StripPiece(
                (node(s, 0, 0), node(s, 0, 1)),
                tuple(node(s - 1, last, k) if s > 0 else node(s, 1, k) for k in (0, 1)),
                -1,
                (node(s, last, 0), node(s, last, 1)),
                tuple(
                    node(s + 1, 0, k) if s + 1 < g.segments else node(s, last - 1, k)
                    for k in (0, 1)
                ),
                -1,
                "bottom_strips",
                (int(idx[0]), int(idx[1])),
            )
        )
        hinge_rows += strip_contact_rows(
            node(s, 0, 0),
            node(s, 0, 1),
            node(s, 1, 0),
            node(s, 1, 1),
            node(s, last, 0),
            node(s, last, 1),
        )
        hinge_rows += strip_contact_rows(
            node(s, last, 0),
            node(s, last, 1),
            node(s, last - 1, 0),
            node(s, last - 1, 1),
            node(s, 0, 0),
            node(s, 0, 1),
        )
        if m.contact:
            # Plane (a, b across, c along): normal (c - a) x (b - a) = +z, the ribbon's side.
            a, b, c = node(s, 0, 0), node(s, 0, 1), node(s, last, 0)
            pts = ribbon_points(s, range(1, last), range(per_seg - 1))
            structure.add_contacts("bottom_strip_contact", [(p, a, b, c) for p in pts], rest=0.0)

    # Top strips over each junction, at the crown-edge height.
    zc = g.top_strip_height
    top_of_bar = []
    squares = []
    for j in range(g.segments - 1):
        x0 = g.segment_start(j) + lx
        x1 = g.segment_start(j + 1)
        sq = structure.add_nodes([(x0, 0.0, zc), (x0, width, zc), (x1, width, zc), (x1, 0.0, zc)])
        squares.append(sq)
        j1, j2, j3, j4 = (int(v) for v in sq)
        left = [node(j, nf + 1, side) for side in (0, 1)]  # crown edge s = (L + c)/2 of segment j
        right = [
            node(j + 1, nf, side) for side in (0, 1)
        ]  # crown edge s = (L - c)/2 of segment j+1
        lce = [(left[0], j1), (left[1], j2), (j4, right[0]), (j3, right[1])]
        if m.top_junction == "lce":
            lce += [(j1, j4), (j2, j3)]
            glue = [(j1, j2), (j4, j3)]
        else:
            glue = [(j1, j3), (j2, j4), (j1, j2), (j2, j3), (j3, j4), (j4, j1)]
        idx = structure.add_bars("top_strips", lce)
        top_of_bar += [j] * len(lce)
        # Crown-edge pieces bonded to the crown panel, square pieces to the raised square.
        pieces.append(
            StripPiece(
                (left[0], left[1]),
                (node(j, nf, 0), node(j, nf, 1)),
                1,
                (j1, j2),
                (j4, j3),
                0,
                "top_strips",
                (int(idx[0]), int(idx[1])),
            )
        )
        pieces.append(
            StripPiece(
                (j4, j3),
                (j1, j2),
                0,
                (right[0], right[1]),
                (node(j + 1, nf + 1, 0), node(j + 1, nf + 1, 1)),
                1,
                "top_strips",
                (int(idx[2]), int(idx[3])),
            )
        )
        structure.add_bars("glue", glue)
        hinge_rows += strip_contact_rows(
            left[0], left[1], node(j, nf + 2, 0), node(j, nf + 2, 1), j1, j2
        )
        hinge_rows += strip_contact_rows(
            right[0], right[1], node(j + 1, nf - 1, 0), node(j + 1, nf - 1, 1), j4, j3
        )
        if m.contact:
            # Square corners above the junction (normal +z), at least their as-built height.
            a, b, c = node(j, last, 0), node(j, last, 1), node(j + 1, 0, 0)
            structure.add_contacts("top_square_contact", [(p, a, b, c) for p in (j1, j2, j3, j4)])
            # Ribbon under each top strip piece (normal -z: below the strip).
            pts = ribbon_points(j, range(nf + 2, per_seg), range(nf + 1, per_seg - 1))
            structure.add_contacts(
                "top_strip_contact", [(p, left[0], j1, left[1]) for p in pts], rest=0.0
            )
            pts = ribbon_points(j + 1, range(0, nf), range(0, nf))
            structure.add_contacts(
                "top_strip_contact", [(p, j4, right[0], j3) for p in pts], rest=0.0
            )

    if m.strip_contact:
        structure.add_hinges("strip_contact", np.asarray(hinge_rows, dtype=np.int64))

    junction_panels = np.flatnonzero(kinds == "junction")
    crown_panels = np.flatnonzero(kinds == "crown")
    structure.node_sets["left_end"] = np.array([node(0, 0, 0), node(0, 0, 1)])
    structure.node_sets["right_end"] = np.array(
        [node(g.segments - 1, last, 0), node(g.segments - 1, last, 1)]
    )
    structure.node_sets["junction_corners"] = structure.panels[junction_panels]
    structure.node_sets["junction_centres"] = centres[junction_panels]
    structure.node_sets["top_squares"] = np.asarray(squares, dtype=np.int64).reshape(-1, 4)
    structure.node_sets["crown_centres"] = centres[crown_panels]
    if g.segments % 2 == 0:
        mid_panel = structure.panels[junction_panels[g.segments // 2 - 1]]
    else:
        mid_panel = structure.panels[crown_panels[g.segments // 2]]
    structure.node_sets["middle_panel"] = mid_panel
    structure.node_sets["centre_support"] = np.array([mid_panel[0], mid_panel[3], mid_panel[1]])
    strip_sections(structure, g, flank=(lx - g.crown_bond_length) / (2 * nf))
    apply_strip_element(
        structure,
        g,
        m.strip_element,
        pieces,
        PUBLISHED_LAMBDA_N,
        np.asarray(squares, dtype=np.int64).reshape(-1),
    )
    structure.info.update(
        segments=g.segments,
        flank_panels=nf,
        top_junction=m.top_junction,
        panel_kind=kinds,
        bottom_strip_of_bar=np.asarray(bottom_of_bar),
        top_strip_of_bar=np.asarray(top_of_bar),
        total_length=g.total_length,
    )
    structure.validate()
    return structure


# --------------------------------------------------------------------------- curvature
def beam_stations(structure: BarHingeStructure, positions=None) -> np.ndarray:
    """Stations (N + 1, 3) [mm]: the centre of the left end, the junction centres (mean of each
    junction square's four corners on the ribbon), the centre of the right end."""
    x = structure.nodes if positions is None else np.asarray(positions)
    sets = structure.node_sets
    rows = [x[sets["left_end"]].mean(axis=0)]
    rows += list(x[sets["junction_corners"]].mean(axis=1))
    rows.append(x[sets["right_end"]].mean(axis=0))
    return np.asarray(rows)


def middle_station_indices(segments: int) -> np.ndarray:
    """Stations bounding the middle segments: the middle two for even N, the middle three for odd
    N >= 3 (the middle segment and its neighbours), all stations for N = 1."""
    if segments < 1:
        raise InputError(f"segments = {segments}: must be >= 1")
    span = 2 if segments % 2 == 0 else min(3, segments)
    first = (segments - span) // 2
    return np.arange(first, first + span + 1)


def beam_up_vector(structure: BarHingeStructure, positions=None) -> np.ndarray:
    """Unit normal of the middle panel (junction, or crown for odd N) on the top strips' side
    (+z in the as-built state), following the panel's rotation."""
    x = structure.nodes if positions is None else np.asarray(positions)
    c = structure.node_sets["middle_panel"]
    v = np.cross(x[c[1]] - x[c[0]], x[c[3]] - x[c[0]])
    return v / np.linalg.norm(v)
