"""One description of a gridshell's layout (seed 001's robotic surface and its next steps): which
grid, how large, which junctions are bonded, how the strips are wired to channels, and how it is
held.

Seed 001 ends with its own next steps: "To achieve higher geometric complexity, it is necessary to
add control channels (fig. S6), refine the grid mesh (fig. S7), and explore non-orthogonal meshes."
A
:class:`Layout` is that choice, as a frozen dataclass (every field with its unit and source) and a
case-file section ``[layout]`` (:func:`layout_from_table`, one-line errors;
:func:`lcefem.validation.app.layouts.load_layout` reads ``--layout NAME|FILE``). The published
3 x 3 surface is :meth:`Layout.published` (all defaults).

Generators (``kind``):

* "orthogonal": ``ribbons`` ribbons along x and as many along y, junction centres
  c_r = L + d/2 + r p (p = ``pitch``, d the ribbon width, L = p - d the free segment);
* "rhombic": the same two families, the second at ``angle`` [deg] to the first (e1 = (1, 0),
  e2 = (cos a, sin a)): the orthogonal grid's affine image (x, y) -> x e1 + y e2 built in the
  oblique coordinates (the junctions are rhombi of side d/sin a; a ribbon's width across itself
  stays d). The bar-and-hinge builder then moves a free segment's interior cuts across the ribbon
  (rectangular panels, ``mesh.free_panels``; the affine image's parallelograms lock in bending);
* "triangular": three families at 0, 60 and 120 deg through the points of a triangular lattice of
  spacing p (three ribbons cross at every junction, a hexagon of side d; p defaults to L + sqrt(3) d
  = 42.12 mm, so that every segment keeps the published 30 mm; an odd count of ribbons per family);
* "hexagonal": the honeycomb of edge p (three ribbon pieces meet at every junction, a hexagon of
  side d; p defaults to the triangular grid's 42.12 mm), the cells within ``ribbons`` p of the
  centre junction (:func:`honeycomb_patch`).

The bar-and-hinge builder (:func:`lcefem.meshes.gridshell.build_gridshell_bar_hinge`) builds the
two two-family kinds with an equal count of ribbons per family, the triangular one (an odd count
per family; hexagonal junctions, :mod:`lcefem.meshes.gridshell_tri`) and the honeycomb
(:mod:`lcefem.meshes.gridshell_hex`): :data:`BAR_HINGE_KINDS`; the 3D FE mesh the two-family kinds
(:data:`FE_KINDS`). :meth:`Layout.plan` gives every kind's junctions and ribbon (piece) centre
lines, for pictures and meshers.

Lengths in mm, angles in degrees (converted to radians only inside).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from lcefem.models.errors import InputError
from lcefem.models.parameters import check, param

KINDS = ("orthogonal", "rhombic", "triangular", "hexagonal")
#: Kinds the bar-and-hinge builder builds: two families of straight ribbons (two per junction), the
#: triangular grid (three per junction, lcefem.meshes.gridshell_tri) and the honeycomb (three
#: pieces end at every junction, lcefem.meshes.gridshell_hex).
BAR_HINGE_KINDS = ("orthogonal", "rhombic", "triangular", "hexagonal")
#: Kinds the 3D FE mesh builds (two families of ribbons, two strips a junction).
FE_KINDS = ("orthogonal", "rhombic")
#: Named wirings: "channels" (seed 001 Fig. 4A: Tx, Ty, Bx, By, one current per layer and
#: direction), "ribbons" (one per layer and ribbon: XD1 .. YUn), "strips" (one per strip id).
WIRINGS = ("channels", "ribbons", "strips")
#: Support names a layout may choose (checked here, their held DOFs are the problem's:
#: lcefem.solvers.problems.gridshell_bh.SUPPORTS; "" = the support the shape or recipe names).
SUPPORT_NAMES = ("", "clamp", "rollers", "middle_rollers", "table")


@dataclass(frozen=True)
class Layout:
    """A gridshell's layout (module docstring). A length of 0 takes the ``[geometry]`` section's
    value (:class:`lcefem.meshes.composite_beam.CompositeBeamGeometry`, the published model's
    numbers), so that every number keeps one definition."""

    kind: str = param(
        "orthogonal",
        "-",
        "seed 001 Fig. 4: an orthogonal grid; rhombic, triangular, "
        "hexagonal: the paper's 'explore non-orthogonal meshes'",
    )
    ribbons: int = param(
        3,
        "-",
        "seed 001 Fig. 4: the 3 x 3 grid (3 ribbons per direction, 9 "
        "junctions); fig. S7 refines it",
        minimum=1,
        maximum=15,
    )
    angle: float = param(
        90.0,
        "deg",
        "angle between the two ribbon families (rhombic; 90 for the "
        "orthogonal grid, seed 001 Fig. 4)",
        minimum=30.0,
        maximum=150.0,
    )
    pitch: float = param(
        0.0,
        "mm",
        "junction centre to junction centre along a ribbon; 0: the "
        "geometry section's segment_length + junction_length (published: 30 + 7 mm; "
        "triangular: 30 + sqrt(3) 7 mm, its hexagonal junction)",
        minimum=0.0,
    )
    ribbon_width: float = param(
        0.0,
        "mm",
        "Kapton ribbon width across the ribbon; 0: the geometry section's (seed 001: 7 mm)",
        minimum=0.0,
    )
    ribbon_thickness: float = param(
        0.0,
        "mm",
        "Kapton film thickness; 0: the geometry section's (seed 001: 127 um)",
        minimum=0.0,
    )
    strip_width: float = param(
        0.0,
        "mm",
        "LCE strip width; 0: the geometry section's (seed 001: 5 mm mould channel)",
        minimum=0.0,
    )
    strip_thickness: float = param(
        0.0,
        "mm",
        "LCE strip thickness; 0: the geometry section's (seed 001: 2 mm mould channel)",
        minimum=0.0,
    )
    glued: str | tuple = param(
        "all",
        "-",
        "bonded junctions: 'all' (seed 001: every crossing glued) "
        "or a list of [i_x, i_y] junction indices; an unbonded junction keeps "
        "each ribbon's own Kapton square (the raised top square stays shared)",
    )
    wiring: str | tuple = param(
        "channels",
        "-",
        "which strips share a current (a drive tag): "
        "'channels' (seed 001 Fig. 4A: Tx, Ty, Bx, By), 'ribbons' (XD1..YUn), "
        "'strips' (one per strip), or a table tag = [selections]",
    )
    support: str = param(
        "",
        "-",
        "the support ('' = the shape's or recipe's published one; clamp, "
        "rollers, middle_rollers, table: lcefem.solvers.problems.gridshell_bh)",
    )

    @classmethod
    def published(cls) -> "Layout":
        """The published 3 x 3 orthogonal surface (seed 001 Fig. 4; published reduced-order
        model)."""
        return cls()

    def checked(self) -> "Layout":
        check(self, "layout")
        if self.kind not in KINDS:
            raise InputError(f"layout.kind = {self.kind!r}: allowed {', '.join(KINDS)}")
        if not isinstance(self.ribbons, int) or isinstance(self.ribbons, bool):
            raise InputError(f"layout.ribbons = {self.ribbons!r}: must be an integer >= 1")
        if self.kind == "orthogonal" and self.angle != 90.0:
            raise InputError(
                f"layout.angle = {self.angle}: must be 90 for kind 'orthogonal' (use kind "
                "'rhombic' for another angle)"
            )
        if self.support not in SUPPORT_NAMES:
            raise InputError(
                f"layout.support = {self.support!r}: allowed "
                f"{', '.join(repr(s) for s in SUPPORT_NAMES)}"
            )
        self.glued_junctions()
        self.wiring_table()
        return self

    # ---------------------------------------------------------------- derived quantities
    @property
    def oblique(self) -> bool:
        """True when the two families are not at 90 deg (the builder maps the orthogonal grid)."""
        return self.angle != 90.0

    def directions(self) -> np.ndarray:
        """Unit vectors (2, 2) of the two families: e1 = (1, 0), e2 = (cos a, sin a); exactly
        (0, 1) at 90 deg (no rounding in the published grid)."""
        if not self.oblique:
            return np.array([[1.0, 0.0], [0.0, 1.0]])
        a = math.radians(self.angle)
        return np.array([[1.0, 0.0], [math.cos(a), math.sin(a)]])

    def geometry(self, base):
        """The ``[geometry]`` section ``base`` (CompositeBeamGeometry) with this layout's lengths,
        in the builder's coordinates: along the ribbons, and across them along the other family, so
        the width there is d/sin a and a junction is d/sin a long."""
        w = self.ribbon_width or base.ribbon_width
        if self.kind in ("triangular", "hexagonal"):
            return self._triangular_geometry(base, w)
        stretch = 1.0 if not self.oblique else 1.0 / math.sin(math.radians(self.angle))
        along = w * stretch if (self.oblique or self.ribbon_width) else base.junction_length
        pitch = self.pitch or base.pitch
        changes = {}
        if self.pitch or self.oblique or self.ribbon_width:
            if pitch - along <= base.crown_bond_length:
                raise InputError(
                    f"layout.pitch = {pitch} mm: must exceed the junction length {along:.3f} "
                    f"mm + the crown bond {base.crown_bond_length} mm"
                )
            changes.update(
                segment_length=pitch - along, junction_length=along, ribbon_width=w * stretch
            )
        for name in ("ribbon_thickness", "strip_width", "strip_thickness"):
            if getattr(self, name):
                changes[name] = getattr(self, name)
        return dataclasses.replace(base, **changes) if changes else base

    def _triangular_geometry(self, base, w: float):
        """The triangular grid's lengths: the junction is the hexagon of side w (apothem sqrt(3)
        w/2, lcefem.meshes.gridshell_tri), so junction_length = sqrt(3) w along a ribbon; the
        default pitch keeps the published free segment (pitch = segment_length + sqrt(3) w =
        42.12 mm for 30 and 7 mm)."""
        along = math.sqrt(3.0) * w
        pitch = self.pitch or base.segment_length + along
        if pitch - along <= base.crown_bond_length:
            raise InputError(
                f"layout.pitch = {pitch} mm: must exceed the hexagonal junction's length "
                f"{along:.3f} mm + the crown bond {base.crown_bond_length} mm"
            )
        changes = dict(segment_length=pitch - along, junction_length=along, ribbon_width=w)
        for name in ("ribbon_thickness", "strip_width", "strip_thickness"):
            if getattr(self, name):
                changes[name] = getattr(self, name)
        return dataclasses.replace(base, **changes)

    def to_plane(self, xy: np.ndarray) -> np.ndarray:
        """Builder coordinates (.., 2) -> plane [mm]: x e1 + y e2 (the identity at 90 deg)."""
        if not self.oblique:
            return np.asarray(xy, dtype=float)
        return np.asarray(xy, dtype=float) @ self.directions()

    def glued_junctions(self) -> set[tuple[int, int]] | None:
        """None for 'all', else the set of bonded (i_x, i_y) junctions (checked against the
        grid)."""
        if self.glued == "all":
            return None
        if isinstance(self.glued, str):
            raise InputError(
                f"layout.glued = {self.glued!r}: 'all' or a list of [i_x, i_y] junctions"
            )
        out = set()
        for item in self.glued:
            ok = (
                isinstance(item, (list, tuple))
                and len(item) == 2
                and all(
                    isinstance(v, int) and not isinstance(v, bool) and 0 <= v < self.ribbons
                    for v in item
                )
            )
            if not ok:
                raise InputError(
                    f"layout.glued: {item!r}: a junction [i_x, i_y], each 0..{self.ribbons - 1}"
                )
            out.add((int(item[0]), int(item[1])))
        return out

    def wiring_table(self) -> tuple[tuple[str, tuple], ...] | str:
        """A named wiring (a string of :data:`WIRINGS`) or the checked ((tag, (selection, ...)),
        ...)."""
        if isinstance(self.wiring, str):
            if self.wiring not in WIRINGS:
                raise InputError(
                    f"layout.wiring = {self.wiring!r}: allowed {', '.join(WIRINGS)} or a "
                    "table tag = [selections]"
                )
            return self.wiring
        out = []
        for item in self.wiring:
            ok = (
                isinstance(item, (list, tuple))
                and len(item) == 2
                and isinstance(item[0], str)
                and item[0]
                and isinstance(item[1], (list, tuple))
                and len(item[1]) > 0
                and all(isinstance(s, (str, int)) and not isinstance(s, bool) for s in item[1])
            )
            if not ok:
                raise InputError(
                    f"layout.wiring: {item!r}: a tag and a non-empty list of selections "
                    "(channels, groups XD1.., strip ids)"
                )
            out.append((item[0], tuple(item[1])))
        tags = [t for t, _ in out]
        if len(set(tags)) != len(tags):
            raise InputError(f"layout.wiring: tags repeat ({', '.join(tags)})")
        return tuple(out)

    # ---------------------------------------------------------------- plan (every kind)
    def plan(self, base=None) -> dict:
        """Junction centres (k, 2) [mm] and ribbon centre lines (m, 2, 2) [mm] in the plane, for any
        kind (pictures; a mesher's input). ``base``: the geometry section (default: published)."""
        from lcefem.meshes.composite_beam import CompositeBeamGeometry

        g = self.checked().geometry(base or CompositeBeamGeometry())
        n, p = self.ribbons, g.pitch
        if self.kind in FE_KINDS:
            c = g.segment_length + 0.5 * g.junction_length + p * np.arange(n)
            length = (n + 1) * g.segment_length + n * g.junction_length
            ij = np.array([(a, b) for a in c for b in c])
            lines = [((0.0, r), (length, r)) for r in c] + [((r, 0.0), (r, length)) for r in c]
            return {
                "junctions": self.to_plane(ij),
                "lines": self.to_plane(np.asarray(lines)),
                "width": self.ribbon_width or g.ribbon_width,
            }
        if self.kind == "triangular":
            k = n // 2
            a1, a2 = np.array([p, 0.0]), np.array([0.5 * p, 0.5 * math.sqrt(3.0) * p])
            pts = np.array(
                [
                    i * a1 + j * a2
                    for i in range(-k, k + 1)
                    for j in range(-k, k + 1)
                    if abs(i + j) <= k
                ]
            )
            lines = []
            for u in (a1, a2, a2 - a1):
                u = u / np.linalg.norm(u)
                normal = np.array([-u[1], u[0]])
                for off in np.unique(np.round(pts @ normal, 6)):
                    on = pts[np.abs(pts @ normal - off) < 1e-6]
                    s = on @ u
                    # a free segment beyond the last junction's hexagon (meshes.gridshell_tri)
                    ext = g.segment_length + 0.5 * g.junction_length
                    lines.append(
                        (off * normal + (s.min() - ext) * u, off * normal + (s.max() + ext) * u)
                    )
            return {
                "junctions": pts,
                "lines": np.asarray(lines),
                "width": self.ribbon_width or g.ribbon_width,
            }
        cells, pts, pieces = honeycomb_patch(n, p)
        return {
            "junctions": pts,
            "lines": pts[pieces],
            "cells": cells,
            "width": self.ribbon_width or g.ribbon_width,
        }


def honeycomb_patch(n: int, pitch: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The honeycomb of edge ``pitch`` [mm] (pieces along 0, 60 and 120 deg) around its centre
    junction at the origin (pieces from it at 0, 120 and 240 deg): the cells whose centres lie
    within n pitch of it (3, 6, 12, 21 cells for n = 1 .. 4), so that the patch keeps the
    junction's 3-fold symmetry. Returns cell centres (c, 2), junction centres (J, 2) [mm] (the
    centre junction first) and pieces (P, 2) (junction rows start -> end, the piece's direction
    at 0, 60 or 120 deg)."""
    p = pitch
    first = np.array([0.5 * p, 0.5 * math.sqrt(3.0) * p])  # the cell at 60 deg
    b1, b2 = np.array([1.5 * p, 0.5 * math.sqrt(3.0) * p]), np.array([0.0, math.sqrt(3.0) * p])
    m = 2 * n + 2
    cells = [first + i * b1 + j * b2 for i in range(-m, m + 1) for j in range(-m, m + 1)]
    cells = [c for c in cells if np.hypot(*c) <= (n + 1e-9) * p]
    cells.sort(key=lambda c: (round(math.atan2(c[1], c[0]), 9), round(float(np.hypot(*c)), 9)))
    rows: dict[tuple[int, int], int] = {(0, 0): 0}
    pts = [np.zeros(2)]
    pieces = set()
    ring = p * np.array([[math.cos(math.pi / 3 * k), math.sin(math.pi / 3 * k)] for k in range(6)])
    for c in cells:
        ids = []
        for q in c + ring:
            key = (round(q[0] / p * 1e6), round(q[1] / p * 1e6))
            if key not in rows:
                rows[key] = len(pts)
                pts.append(np.round(q, 12))  # a piece along 0 deg: its ends' y exactly equal
            ids.append(rows[key])
        for k in range(6):
            a, b = ids[k], ids[(k + 1) % 6]
            u = pts[b] - pts[a]
            # orient along 0, 60 or 120 deg
            ang = (math.degrees(math.atan2(u[1], u[0])) + 1.0) % 360.0
            pieces.add((a, b) if ang < 180.0 else (b, a))
    return np.asarray(cells), np.asarray(pts), np.asarray(sorted(pieces), dtype=np.int64)


#: Layouts by name (``--layout NAME``): the published surface, a refined and two non-orthogonal
#: ones.
NAMED_LAYOUTS: dict[str, Layout] = {
    "published": Layout.published(),
    "5x5": Layout(ribbons=5),
    "7x7": Layout(ribbons=7),
    "rhombic60": Layout(kind="rhombic", angle=60.0),
    "rhombic60_5x5": Layout(kind="rhombic", ribbons=5, angle=60.0),
    "triangular": Layout(kind="triangular", ribbons=5),
    "hexagonal": Layout(kind="hexagonal", ribbons=1, support="clamp"),
}


def layout_from_table(
    table: dict | None, base: Layout | None = None, name: str = "layout"
) -> Layout:
    """A ``[layout]`` case-file table applied to ``base`` (default: the published layout); the key
    ``preset`` starts from a named layout. Lists become tuples (glued: [[i, j], ...]; wiring: a
    table tag = [selections]); an unknown key, a wrong type or a bad value is one InputError
    line."""
    table = dict(table or {})
    layout = base or Layout.published()
    if "preset" in table:
        preset = table.pop("preset")
        if preset not in NAMED_LAYOUTS:
            raise InputError(f"{name}.preset = {preset!r}: allowed {', '.join(NAMED_LAYOUTS)}")
        layout = NAMED_LAYOUTS[preset]
    fields = {f.name: f for f in dataclasses.fields(Layout)}
    changes = {}
    for key, value in table.items():
        if key not in fields:
            raise InputError(
                f"unknown key '{name}.{key}'; allowed: preset, {', '.join(sorted(fields))}"
            )
        if key == "glued":
            if isinstance(value, list):
                value = tuple(tuple(v) if isinstance(v, list) else v for v in value)
            elif not isinstance(value, str):
                raise InputError(
                    f"{name}.glued = {value!r}: 'all' or a list of [i_x, i_y] junctions"
                )
        elif key == "wiring":
            if isinstance(value, dict):
                value = tuple(
                    (str(k), tuple(v) if isinstance(v, list) else v) for k, v in value.items()
                )
            elif not isinstance(value, str):
                raise InputError(
                    f"{name}.wiring = {value!r}: a name ({', '.join(WIRINGS)}) or a table "
                    "tag = [selections]"
                )
        else:
            current = getattr(layout, key)
            if (
                isinstance(current, float)
                and isinstance(value, int)
                and not isinstance(value, bool)
            ):
                value = float(value)
            if type(value) is not type(current):
                raise InputError(f"{name}.{key} = {value!r}: expected {type(current).__name__}")
        changes[key] = value
    if (
        "angle" in changes
        and "kind" not in changes
        and layout.kind == "orthogonal"
        and changes["angle"] != 90.0
    ):
        changes["kind"] = "rhombic"  # an angle other than 90 deg is a rhombic grid
    return dataclasses.replace(layout, **changes).checked()
