"""The LCE strips of a gridshell segment in the bar-and-hinge model, shared by the builders of every
grid kind (:mod:`lcefem.meshes.gridshell`, :mod:`lcefem.meshes.gridshell_tri`,
:mod:`lcefem.meshes.gridshell_hex`): the published model's strips (a bottom chord per segment; a top
strip from a segment's crown edge to a raised plate over a junction), its weak strip-ribbon
rotational springs (``strip_contact`` rows) and our frictionless strip-ribbon contact rows (point
under/over the plane of a strip quad, both of its triangles so that the contact is the same for a
ribbon traversed either way).

Each function appends to the caller's ``pieces`` (:class:`~lcefem.meshes.composite_beam.StripPiece`,
for the strip element) and ``hinge_rows`` and adds bars and contacts to the structure, in the order
the orthogonal builder always used (the published structure's digest depends on it). Units: mm.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import StripPiece, strip_contact_rows


def quad_triangles(a: int, b: int, c: int, d: int, both_diagonals: bool = False) -> list:
    """Contact triangles (p, q, r) of a strip's quad a -> b -> c -> d (cyclic; each triangle keeps
    the quad's sense, so its plane's normal (r - p) x (q - p) points to the same side): split along
    the diagonal b-d, (a, b, d) and (c, d, b) (the order the published-grid digest depends on), and
    with ``both_diagonals`` also along a-c, (a, b, c) and (c, d, a). A warped quad's two splits
    differ; a mirror of the grid maps an x ribbon's strip onto a y ribbon's with the other
    diagonal, so only both together are mirror-symmetric (measured on the rhombic grid,
    docs/layouts/rhombic.md)."""
    tris = [(a, b, d), (c, d, b)]
    if both_diagonals:
        tris += [(a, b, c), (c, d, a)]
    return tris


def add_bottom_strip(
    structure: BarHingeStructure,
    nd: Callable[[int, int], int],
    last: int,
    pad_a: tuple[int, int],
    pad_b: tuple[int, int],
    contact_points: Sequence[int] | None,
    pieces: list[StripPiece],
    hinge_rows: list,
    both_diagonals: bool = False,
) -> list[int]:
    """A segment's bottom strip: one chord bar per ribbon edge (group "bottom_strips") from station
    0 to station ``last`` (``nd(station, side)`` -> node), bonded at both ends (``pad_a``,
    ``pad_b``: a node per side of the panel beyond each end). With ``contact_points`` (ribbon
    nodes of the segment) they stay on the ribbon's side of the strip's quad, split into two
    triangles along one diagonal, or with ``both_diagonals`` along both (four triangles: the split
    is then the same under every mirror of the grid, :func:`quad_triangles`). Returns the two bars'
    indices."""
    idx: list[int] = []
    for side in (0, 1):
        idx += list(structure.add_bars("bottom_strips", [(nd(0, side), nd(last, side))]))
    pieces.append(
        StripPiece(
            (nd(0, 0), nd(0, 1)),
            tuple(pad_a),
            -1,
            (nd(last, 0), nd(last, 1)),
            tuple(pad_b),
            -1,
            "bottom_strips",
            (int(idx[0]), int(idx[1])),
        )
    )
    hinge_rows += strip_contact_rows(
        nd(0, 0), nd(0, 1), nd(1, 0), nd(1, 1), nd(last, 0), nd(last, 1)
    )
    hinge_rows += strip_contact_rows(
        nd(last, 0), nd(last, 1), nd(last - 1, 0), nd(last - 1, 1), nd(0, 0), nd(0, 1)
    )
    if contact_points is not None:
        # Both triangles of the strip's (possibly warped) quad, so that the contact is the same
        # for the ribbon traversed either way (a half turn of the grid); one diagonal is not the
        # same under the grid's mirrors, which map it onto the other (both_diagonals).
        tris = quad_triangles(nd(0, 0), nd(0, 1), nd(last, 1), nd(last, 0), both_diagonals)
        structure.add_contacts(
            "bottom_strip_contact", [(p, *t) for p in contact_points for t in tris], rest=0.0
        )
    return idx


def add_top_strip_half(
    structure: BarHingeStructure,
    crown: Sequence[int],
    crown_pad: Sequence[int],
    crown_inner: Sequence[int],
    raised: Sequence[int],
    raised_pad: Sequence[int],
    crown_first: bool,
    contact_points: Sequence[int] | None,
    pieces: list[StripPiece],
    hinge_rows: list,
    both_diagonals: bool = False,
) -> list[int]:
    """One straight piece of a top strip between a segment's crown edge (``crown``: a node per
    side; ``crown_pad`` the crown panel's nodes beyond it, ``crown_inner`` the next station towards
    the junction) and a raised plate over the junction (``raised``: the two plate nodes it is bonded
    to, ``raised_pad`` the plate's nodes across from them): one bar per side (group "top_strips"),
    crown -> raised when ``crown_first`` (the piece runs from the crown edge to the junction along
    the ribbon), else raised -> crown. With ``contact_points`` (the ribbon nodes under the piece)
    they stay below the strip (its quad split along one diagonal, or both with ``both_diagonals``,
    :func:`quad_triangles`). Returns the two bars' indices."""
    c0, c1 = (int(v) for v in crown)
    r0, r1 = (int(v) for v in raised)
    if crown_first:
        idx = structure.add_bars("top_strips", [(c0, r0), (c1, r1)])
        ends = ((c0, c1), tuple(crown_pad), 1), ((r0, r1), tuple(raised_pad), 0)
        tris = quad_triangles(c0, r0, r1, c1, both_diagonals)
    else:
        idx = structure.add_bars("top_strips", [(r0, c0), (r1, c1)])
        ends = ((r0, r1), tuple(raised_pad), 0), ((c0, c1), tuple(crown_pad), 1)
        tris = quad_triangles(r0, c0, c1, r1, both_diagonals)
    pieces.append(StripPiece(*ends[0], *ends[1], "top_strips", (int(idx[0]), int(idx[1]))))
    hinge_rows += strip_contact_rows(c0, c1, int(crown_inner[0]), int(crown_inner[1]), r0, r1)
    if contact_points is not None:
        structure.add_contacts(
            "top_strip_contact", [(p, *t) for p in contact_points for t in tris], rest=0.0
        )
    return [int(i) for i in idx]


def add_top_strip(
    structure: BarHingeStructure,
    left: tuple[Sequence[int], Sequence[int], Sequence[int]],
    right: tuple[Sequence[int], Sequence[int], Sequence[int]],
    entry: Sequence[int],
    exit_: Sequence[int],
    lce: bool,
    contact_points: tuple[Sequence[int], Sequence[int]] | None,
    pieces: list[StripPiece],
    hinge_rows: list,
    both_diagonals: bool = False,
) -> int:
    """A top strip over a junction (the published model's: crown edge of one segment -> raised
    plate -> crown edge of the next): ``left`` and ``right`` are (crown, crown_pad, crown_inner)
    of the two segments (:func:`add_top_strip_half`), ``entry`` / ``exit_`` the plate nodes where
    it enters and leaves the plate; with ``lce`` the strip contracts over the plate too (two more
    bars, entry -> exit). ``contact_points``: the ribbon nodes under each half. Returns the number
    of bars the strip got; ``both_diagonals``: :func:`add_top_strip_half`."""
    pts = contact_points or (None, None)
    both = both_diagonals
    add_top_strip_half(structure, *left, entry, exit_, True, pts[0], pieces, hinge_rows, both)
    add_top_strip_half(structure, *right, exit_, entry, False, pts[1], pieces, hinge_rows, both)
    if not lce:
        return 4
    structure.add_bars("top_strips", [(entry[0], exit_[0]), (entry[1], exit_[1])])
    return 6
