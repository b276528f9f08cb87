"""A plain container for bar-and-hinge structures, and the N5B8 discretisation of quad panels.

A structure is geometry and topology only (no material constants): node coordinates [mm], the
quadrilateral Kapton panels, bar groups and hinge groups by name, and node sets by name. The
solvers turn it into element arrays with the material laws of :mod:`lcefem.models.bar_hinge`.

N5B8 (Filipov et al., Int. J. Solids Struct. 124:26-45, 2017; Liu & Paulino, Proc. R. Soc. A
473:20170348, 2017): each quad panel gets a centre node, 4 edge bars and 4 spokes (centre to
corners), and a bending hinge along every spoke (wings: the two neighbouring corners); each edge
shared by two panels carries a fold hinge whose wings are the two panel centres.

Hinge rows are (j, k, i, l): axis j -> k, wings i and l (see
:func:`lcefem.models.bar_hinge.dihedral_angle`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from lcefem.models.errors import InputError


@dataclass
class BarHingeStructure:
    """Nodes, panels, bar and hinge groups, and node sets of a bar-and-hinge model.

    Attributes:
        nodes: reference (as-built) coordinates [mm], shape (n, 3).
        thickness: Kapton ribbon thickness [mm] (geometry; the panels' bar areas and hinge
            stiffness follow from it and the material).
        panels: corner node indices of the Kapton quad panels, (p, 4), in cyclic order.
        panel_centres: N5B8 centre node of each panel, (p,).
        panel_bars: indices into ``bars["kapton"]`` of each panel's (edge01, edge12, edge23, edge30,
            spoke0, spoke1, spoke2, spoke3), (p, 8).
        bars: bar groups by name, each (m, 2) node indices (e.g. "kapton", "bottom_strips",
            "top_strips", "glue").
        hinges: hinge groups by name, each (h, 4) rows (j, k, i, l) (e.g. "bend", "fold",
            "strip_contact").
        hinge_rest: optional rest angles [rad] by hinge group (default: the as-built angle).
        node_sets: node index arrays by name (any shape), e.g. "left_end", "junction_corners".
        contacts: unilateral point-plane contacts by name, each (c, 4) rows (p, a, b, c): point p
            stays above the plane of a, b, c (normal (c - a) x (b - a)).
        contact_rest: smallest allowed distance [mm] of each contact's point to its plane, by
            contact group (default: the as-built distance).
        sections: geometric section data [mm, mm^2] of non-Kapton bar groups, e.g.
            {"bottom_strips": {"section": 10.0}} (a strip's cast cross-section),
            {"glue": {"area": 0.889}}, {"top_square_contact": {"area": 8.75, "depth": 2.0}}.
        info: free-form description (dimensions used, counts).
    """

    nodes: np.ndarray
    thickness: float
    panels: np.ndarray
    panel_centres: np.ndarray
    panel_bars: np.ndarray
    bars: dict[str, np.ndarray] = field(default_factory=dict)
    hinges: dict[str, np.ndarray] = field(default_factory=dict)
    hinge_rest: dict[str, np.ndarray] = field(default_factory=dict)
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)
    contacts: dict[str, np.ndarray] = field(default_factory=dict)
    contact_rest: dict[str, np.ndarray] = field(default_factory=dict)
    sections: dict[str, dict[str, float]] = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    @property
    def num_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def num_dofs(self) -> int:
        return 3 * self.num_nodes

    def add_nodes(self, coords) -> np.ndarray:
        """Append nodes (k, 3) [mm]; return their indices."""
        coords = np.atleast_2d(np.asarray(coords, dtype=float))
        start = self.num_nodes
        self.nodes = np.vstack([self.nodes, coords])
        return np.arange(start, start + coords.shape[0])

    def add_bars(self, group: str, pairs) -> np.ndarray:
        """Append bars (k, 2) to ``group``; return their indices within the group."""
        pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        old = self.bars.get(group, np.zeros((0, 2), dtype=np.int64))
        self.bars[group] = np.vstack([old, pairs])
        return np.arange(old.shape[0], old.shape[0] + pairs.shape[0])

    def add_hinges(self, group: str, rows, rest=None) -> None:
        """Append hinges (k, 4) rows (j, k, i, l) to ``group``, with optional rest angles [rad]."""
        rows = np.asarray(rows, dtype=np.int64).reshape(-1, 4)
        old = self.hinges.get(group, np.zeros((0, 4), dtype=np.int64))
        self.hinges[group] = np.vstack([old, rows])
        if rest is not None:
            rest = np.broadcast_to(np.asarray(rest, dtype=float), (rows.shape[0],))
            prev = self.hinge_rest.get(group, np.zeros(0))
            if prev.shape[0] != old.shape[0]:
                raise InputError(f"hinge group {group!r}: rest angles given for only some hinges")
            self.hinge_rest[group] = np.concatenate([prev, rest])

    def add_contacts(self, group: str, rows, rest=None) -> None:
        """Append point-plane contacts (k, 4) rows (p, a, b, c) to ``group``, with optional smallest
        allowed distances [mm] (all-or-none per group)."""
        rows = np.asarray(rows, dtype=np.int64).reshape(-1, 4)
        old = self.contacts.get(group, np.zeros((0, 4), dtype=np.int64))
        self.contacts[group] = np.vstack([old, rows])
        if rest is not None:
            rest = np.broadcast_to(np.asarray(rest, dtype=float), (rows.shape[0],))
            prev = self.contact_rest.get(group, np.zeros(0))
            if prev.shape[0] != old.shape[0]:
                raise InputError(f"contact group {group!r}: rest distances given for only some")
            self.contact_rest[group] = np.concatenate([prev, rest])

    def bar_lengths(self, group: str, positions=None) -> np.ndarray:
        """Lengths [mm] of the bars of ``group`` at ``positions`` (default: reference)."""
        x = self.nodes if positions is None else positions
        pairs = self.bars[group]
        return np.linalg.norm(x[pairs[:, 1]] - x[pairs[:, 0]], axis=1)

    def validate(self) -> None:
        """Raise InputError for out-of-range indices, degenerate bars or non-finite coordinates."""
        if not np.all(np.isfinite(self.nodes)):
            raise InputError("structure.nodes: coordinates must be finite")
        n = self.num_nodes
        for name, arr in [
            *(("bars." + k, v) for k, v in self.bars.items()),
            *(("hinges." + k, v) for k, v in self.hinges.items()),
            *(("contacts." + k, v) for k, v in self.contacts.items()),
            ("panels", self.panels),
        ]:
            if arr.size and (arr.min() < 0 or arr.max() >= n):
                raise InputError(f"structure.{name}: node index out of range 0..{n - 1}")
        for name in self.bars:
            if self.bars[name].size and np.min(self.bar_lengths(name)) <= 0.0:
                raise InputError(f"structure.bars.{name}: zero-length bar")


def n5b8_structure(nodes, panels, thickness: float) -> BarHingeStructure:
    """N5B8 discretisation of planar quad panels (Filipov et al. 2017).

    Args:
        nodes: corner coordinates [mm], (n, 3).
        panels: (p, 4) corner indices in cyclic order; each panel must be planar (its centre node is
            the mean of its corners, the diagonals' intersection for a parallelogram).
        thickness: ribbon thickness [mm].
    Returns:
        A :class:`BarHingeStructure` with the group "kapton" (edges then spokes), hinge groups
        "bend" (spokes) and "fold" (edges shared by two panels), centre nodes appended after the
        corner nodes, and node set "panel_centres".
    """
    nodes = np.asarray(nodes, dtype=float)
    panels = np.asarray(panels, dtype=np.int64)
    if panels.ndim != 2 or panels.shape[1] != 4:
        raise InputError("panels: expected an array of shape (p, 4)")
    if thickness <= 0:
        raise InputError(f"thickness = {thickness}: must be > 0 mm")
    num_corner = nodes.shape[0]
    num_panels = panels.shape[0]
    centres = nodes[panels].mean(axis=1)
    centre_ids = num_corner + np.arange(num_panels)
    all_nodes = np.vstack([nodes, centres])

    # Edges: unique sorted pairs; record which panels use each edge.
    edges = np.stack([panels, np.roll(panels, -1, axis=1)], axis=2).reshape(-1, 2)
    keys = np.sort(edges, axis=1)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    inverse = inverse.reshape(num_panels, 4)
    spokes = np.stack([np.repeat(centre_ids, 4), panels.reshape(-1)], axis=1)
    kapton = np.vstack([unique, spokes])
    panel_bars = np.hstack(
        [inverse, unique.shape[0] + np.arange(4 * num_panels).reshape(num_panels, 4)]
    )

    # Bending hinges along the spokes: axis centre -> corner c, wings the neighbouring corners.
    prev_corner = np.roll(panels, 1, axis=1)
    next_corner = np.roll(panels, -1, axis=1)
    bend = np.stack(
        [
            np.repeat(centre_ids, 4),
            panels.reshape(-1),
            prev_corner.reshape(-1),
            next_corner.reshape(-1),
        ],
        axis=1,
    )

    # Fold hinges on shared edges: wings are the two panel centres.
    owner = [[] for _ in range(unique.shape[0])]
    for p in range(num_panels):
        for c in range(4):
            owner[inverse[p, c]].append(p)
    fold = []
    for edge_id, users in enumerate(owner):
        if len(users) == 2:
            a, b = unique[edge_id]
            fold.append((a, b, centre_ids[users[0]], centre_ids[users[1]]))
        elif len(users) > 2:
            raise InputError(f"panels: edge {tuple(unique[edge_id])} shared by {len(users)} panels")
    fold = np.asarray(fold, dtype=np.int64).reshape(-1, 4)

    structure = BarHingeStructure(
        nodes=all_nodes,
        thickness=float(thickness),
        panels=panels,
        panel_centres=centre_ids,
        panel_bars=panel_bars,
    )
    structure.bars["kapton"] = kapton
    structure.hinges["bend"] = bend
    structure.hinges["fold"] = fold
    structure.node_sets["panel_centres"] = centre_ids
    return structure


def panel_dimensions(structure: BarHingeStructure, positions=None) -> tuple[np.ndarray, np.ndarray]:
    """(W, H) [mm] of each panel: W the mean length of edges 01 and 23, H of edges 12 and 30."""
    x = structure.nodes if positions is None else positions
    p = structure.panels
    side = [np.linalg.norm(x[np.roll(p, -1, axis=1)[:, c]] - x[p[:, c]], axis=1) for c in range(4)]
    return 0.5 * (side[0] + side[2]), 0.5 * (side[1] + side[3])
