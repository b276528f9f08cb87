"""Assembly of the bar-and-hinge energy, its gradient and its sparse Hessian.

:class:`BarHingeModel` turns a :class:`~lcefem.meshes.bar_hinge_structure.BarHingeStructure` and the
material laws of :mod:`lcefem.models.bar_hinge` into element arrays and evaluates, for node
positions x (n, 3) [mm],

    Pi(x) = sum_bars V w(L/L_r) + sum_hinges L_h psi(theta) + sum_contacts k <g0 - g>_+^2/2
            [+ sum_panels U_p]  - f_ext . (x - X)   [mJ],

(U_p: the panels' bending elements of ``kapton.twist = "plate"``,
:func:`lcefem.models.bar_hinge.panel_bending_element`), with the gradient dPi/dx [N] (the internal
minus the external forces; at a held node the reaction) and the Hessian [N/mm] as a scipy.sparse CSR
matrix whose sparsity pattern is computed once. The external forces f_ext [N] (3n,) are dead loads
(weight, a payload), zero unless set with
:meth:`BarHingeModel.set_external_forces`.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, panel_dimensions
from lcefem.models import bar_hinge as law
from lcefem.models import bar_hinge_materials as bhm
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import OgdenLaw
from lcefem.solvers.bar_hinge.kernels import (
    SPOKE_SLOT_TABLE,
    hinge_forces,
    panel_bending_forces,
    scatter_merged,
)
from lcefem.solvers.bar_hinge.ldl import SymbolicLDL, inserted_before

#: Bar groups that are LCE strips (tension-only Ogden bars with a rest length).
STRIP_GROUPS = ("bottom_strips", "top_strips")


@dataclass
class BarSet:
    """Bars of one group: nodes (m, 2), reference length L0 [mm], volume V [mm^3] and law data."""

    name: str
    nodes: np.ndarray
    length0: np.ndarray
    volume: np.ndarray
    kind: str  # "stiffening" (Kapton, glue) or "lce"
    modulus: np.ndarray | None = None  # [MPa], stiffening bars
    exponents: tuple[float, float] = (5.0, 1.0)
    rest_fraction: np.ndarray | None = None  # f = L_r/L0 [-], LCE bars
    published_area: float | None = None  # A [mm^2] of the published law A f P(p) (None: volume law)

    @property
    def rest_length(self) -> np.ndarray:
        return self.length0 if self.rest_fraction is None else self.rest_fraction * self.length0

    @property
    def energy_volume(self) -> np.ndarray:
        """V [mm^3] of the bar energy V W(p): the material volume, or, with the published law
        A f P(p), A f^2 L0 (so that V W'(p)/L_r = A f P(p))."""
        if self.published_area is None:
            return self.volume
        return self.published_area * self.rest_fraction**2 * self.length0

    def law(self, ogden: OgdenLaw):
        if self.kind == "lce":
            return lambda lam: bhm.tension_only_ogden_law(lam, ogden)
        return lambda lam: bhm.stiffening_bar_law(lam, self.modulus, self.exponents)


@dataclass
class HingeSet:
    """Rotational springs of one group: rows (h, 4) (j, k, i, l), axis length [mm], stiffness k
    [N mm/(rad mm)], rest angle and linear-range limits [rad]."""

    name: str
    nodes: np.ndarray
    length: np.ndarray
    stiffness: np.ndarray
    rest_angle: np.ndarray
    theta1: np.ndarray | float
    theta2: np.ndarray | float

    def law(self):
        return lambda th: bhm.enhanced_linear_law(
            th, self.rest_angle, self.stiffness, self.theta1, self.theta2
        )


@dataclass
class ContactSet:
    """Unilateral point-plane contacts: rows (c, 4) (p, a, b, c), rest gap g0 [mm], stiffness
    [N/mm]."""

    name: str
    nodes: np.ndarray
    rest_gap: np.ndarray
    stiffness: np.ndarray


class BarHingeModel:
    """Energy, gradient and Hessian of a bar-and-hinge structure with given materials."""

    @classmethod
    def from_materials(
        cls,
        structure: BarHingeStructure,
        materials: bhm.BarHingeMaterials = bhm.BarHingeMaterials(),
    ) -> "BarHingeModel":
        """The model of ``structure`` with every law of ``materials`` (the one definition in
        models)."""
        m = materials
        return cls(structure, m.kapton, m.lce, m.glue, m.strip_contact, m.ogden, m.contact)

    def __init__(
        self,
        structure: BarHingeStructure,
        kapton: bhm.KaptonBarHinge = bhm.KaptonBarHinge(),
        lce: bhm.LCEStripBars = bhm.LCEStripBars(),
        glue: bhm.GlueBars = bhm.GlueBars(),
        contact: bhm.StripContactSprings = bhm.StripContactSprings(),
        ogden: OgdenLaw = OgdenLaw(),
        strip_contact: bhm.StripContact = bhm.StripContact(),
    ):
        """
        Args:
            structure: geometry and topology; ``structure.sections`` gives the strips' cast section,
                the glue bar area and each contact group's area and depth.
        """
        structure.validate()
        self.structure = structure
        self.kapton, self.lce, self.glue, self.contact, self.ogden = (
            kapton,
            lce,
            glue,
            contact,
            ogden,
        )
        self.strip_contact = strip_contact
        lce.checked()

        def section(group: str, key: str) -> float:
            value = structure.sections.get(group, {}).get(key)
            if value is None or value <= 0:
                raise InputError(
                    f"structure.sections[{group!r}][{key!r}]: must be > 0 for a "
                    f"structure with {group} bars"
                )
            return float(value)

        x0 = structure.nodes
        self.reference = x0.copy()
        exps = (kapton.bar_exponent_1, kapton.bar_exponent_2)
        if exps[0] == exps[1]:
            raise InputError("kapton.bar_exponent_1 must differ from kapton.bar_exponent_2")
        self.bar_sets: list[BarSet] = []
        for name, pairs in structure.bars.items():
            if pairs.shape[0] == 0:
                continue
            length0 = structure.bar_lengths(name)
            if name == "kapton":
                area = self._kapton_areas()
                self.bar_sets.append(
                    BarSet(
                        name,
                        pairs,
                        length0,
                        area * length0,
                        "stiffening",
                        np.full(length0.size, kapton.youngs_modulus),
                        exps,
                    )
                )
            elif name == "glue":
                area = section(name, "area")
                self.bar_sets.append(
                    BarSet(
                        name,
                        pairs,
                        length0,
                        area * length0,
                        "stiffening",
                        np.full(length0.size, glue.youngs_modulus),
                        exps,
                    )
                )
            elif name in STRIP_GROUPS:
                # Volume conserved: V = (A_iso / bars per strip) * L_iso, L_iso = L0/lambda_N.
                area = section(name, "section") / lce.bars_per_strip
                volume = area * length0 / lce.lambda_N
                self.bar_sets.append(
                    BarSet(
                        name,
                        pairs,
                        length0,
                        volume,
                        "lce",
                        rest_fraction=np.ones(length0.size),
                        published_area=area if lce.force_law == "published" else None,
                    )
                )
            else:
                raise InputError(
                    f"bar group {name!r}: no material law (allowed: kapton, glue, "
                    f"{', '.join(STRIP_GROUPS)})"
                )
        k_ribbon = kapton.checked().hinge_stiffness(structure.thickness)
        t1, t2 = math.radians(kapton.linear_from), math.radians(kapton.linear_to)
        # kapton.twist = "plate": spokes beta k (their twist mode) + a panel bending element (1 -
        # beta) k
        plate = kapton.twist in ("plate", "plate_rectangles")
        self.panel_set = self._panel_bending_set(k_ribbon, kapton.twist) if plate else None
        self.hinge_sets: list[HingeSet] = []
        for name, rows in structure.hinges.items():
            if rows.shape[0] == 0:
                continue
            axis = np.linalg.norm(x0[rows[:, 1]] - x0[rows[:, 0]], axis=1)
            theta_ref = law.dihedral_angle(
                x0[rows[:, 0]], x0[rows[:, 1]], x0[rows[:, 2]], x0[rows[:, 3]], derivatives=0
            )
            if name in ("bend", "fold"):
                k = np.full(axis.size, k_ribbon)
                if name == "bend" and self.panel_set is not None:
                    k = k_ribbon * np.repeat(self.panel_set["beta"], 4)
                rest = structure.hinge_rest.get(name, theta_ref)
                lo, hi = t1, t2
            elif name == "strip_contact":
                # Force-free as built; barrier at the panel's plane on the strip's side.
                k = np.full(axis.size, contact.stiffness)
                rest = theta_ref
                lo = np.where(theta_ref < np.pi, theta_ref, 2.0 * np.pi - theta_ref)
                hi = 2.0 * np.pi - lo
            else:
                raise InputError(
                    f"hinge group {name!r}: no law (allowed: bend, fold, strip_contact)"
                )
            self.hinge_sets.append(
                HingeSet(name, rows, axis, k, np.asarray(rest, dtype=float), lo, hi)
            )
        self.contact_sets: list[ContactSet] = []
        for name, rows in structure.contacts.items():
            if rows.shape[0] == 0:
                continue
            stiffness = strip_contact.modulus * section(name, "area") / section(name, "depth")
            gap0 = structure.contact_rest.get(name)
            if gap0 is None:
                gap0 = law.point_plane_gap(*(x0[rows[:, c]] for c in range(4)), derivatives=0)
            self.contact_sets.append(
                ContactSet(
                    name, rows, np.asarray(gap0, dtype=float), np.full(rows.shape[0], stiffness)
                )
            )
        self._build_pattern()
        self.external_force = np.zeros(self.ndof)

    # ------------------------------------------------------------------ set-up
    def _panel_bending_set(self, k_ribbon: float, twist: str = "plate") -> dict:
        """Per panel: nodes (centre, corners), spoke lengths and rest angles, the twist fraction
        beta (:func:`law.panel_twist_fraction`; with ``twist = "plate_rectangles"`` 1, the N5B8
        spokes' torsion, on a panel that is not a rectangle) and the bending element's stiffness
        (1 - beta) k."""
        s = self.structure
        bend = s.hinges.get("bend", np.zeros((0, 4), dtype=np.int64))
        p = s.panels.shape[0]
        rows = bend.reshape(-1, 4, 4) if bend.shape[0] == 4 * p else None
        if rows is None or not (
            np.all(rows[:, :, 0] == s.panel_centres[:, None]) and np.all(rows[:, :, 1] == s.panels)
        ):
            raise InputError(
                "kapton.twist = 'plate': the structure's bend hinges must be the N5B8 "
                "spokes, four per panel in panel order (meshes.bar_hinge_structure)"
            )
        nodes = np.concatenate([s.panel_centres[:, None], s.panels], axis=1)
        x0 = s.nodes
        flat = rows.reshape(-1, 4)
        rest = law.dihedral_angle(*(x0[flat[:, c]] for c in range(4)), derivatives=0).reshape(p, 4)
        lengths = np.linalg.norm(x0[rows[:, :, 1]] - x0[rows[:, :, 0]], axis=2)
        width, height = panel_dimensions(s)
        # The plate's torsion is GJ = G w t^3/3 of a rectangle w x h: on a parallelogram (a rhombic
        # gridshell's panels) it breaks the grid's mirror symmetry (measured: 0.25 mm of 3.8 mm z
        # range on the rhombic60 layout at lambda_B = 1.395, clamp; 2e-7 mm with the N5B8 spokes).
        c = x0[s.panels]
        d1 = np.linalg.norm(c[:, 2] - c[:, 0], axis=1)
        d2 = np.linalg.norm(c[:, 3] - c[:, 1], axis=1)
        equal_diagonals = np.abs(d1 - d2) <= 1e-6 * np.maximum(d1, d2)
        if twist == "plate" and not np.all(equal_diagonals):
            raise InputError(
                "kapton.twist = 'plate': needs rectangular panels (a rhombic layout's are "
                "parallelograms); use kapton.twist = 'n5b8'"
            )
        beta = law.panel_twist_fraction(self.kapton, s.thickness, width, height)
        if twist == "plate_rectangles":
            # a rectangle: equal diagonals that bisect each other (a right trapezoid's differ)
            rectangle = equal_diagonals & (
                np.linalg.norm(c[:, 0] + c[:, 2] - c[:, 1] - c[:, 3], axis=1) <= 1e-6 * d1
            )
            beta = np.where(rectangle, beta, 1.0)
        return {
            "nodes": nodes,
            "lengths": lengths,
            "rest": rest,
            "beta": beta,
            "stiffness": (1.0 - beta) * k_ribbon,
        }

    def _kapton_areas(self) -> np.ndarray:
        s = self.structure
        width, height = panel_dimensions(s)
        a_w, a_h, a_s = law.n5b8_bar_areas(width, height, s.thickness, self.kapton.poisson_ratio)
        area = np.zeros(s.bars["kapton"].shape[0])
        pb = s.panel_bars
        np.add.at(area, pb[:, 0], a_w)
        np.add.at(area, pb[:, 2], a_w)
        np.add.at(area, pb[:, 1], a_h)
        np.add.at(area, pb[:, 3], a_h)
        for c in range(4, 8):
            np.add.at(area, pb[:, c], a_s)
        if np.any(area <= 0):
            raise InputError("kapton: a panel bar got no area (is every bar part of a panel?)")
        return area

    def _groups(self):
        return (*self.bar_sets, *self.hinge_sets, *self.contact_sets)

    def _build_pattern(self) -> None:
        """Merge the groups of each element kind into one block (one vectorised call per kind) and
        fix the Hessian's COO pattern."""
        self.ndof = 3 * self.structure.num_nodes
        kinds = [
            ("stiffening", [b for b in self.bar_sets if b.kind == "stiffening"]),
            ("lce", [b for b in self.bar_sets if b.kind == "lce"]),
            ("hinge", list(self.hinge_sets)),
            ("contact", list(self.contact_sets)),
        ]
        self._blocks = []
        for kind, sets in kinds:
            if not sets:
                continue
            block = {"kind": kind, "sets": sets, "nodes": np.vstack([g.nodes for g in sets])}
            cat = lambda attr: np.concatenate(
                [
                    np.broadcast_to(np.asarray(getattr(g, attr), float), (g.nodes.shape[0],))
                    for g in sets
                ]
            )
            if kind in ("stiffening", "lce"):
                block.update(length0=cat("length0"), volume=cat("volume"))
            if kind == "stiffening":
                block["modulus"] = cat("modulus")
                block["exponents"] = sets[0].exponents
            if kind == "hinge":
                block.update(
                    length=cat("length"),
                    stiffness=cat("stiffness"),
                    rest=cat("rest_angle"),
                    theta1=cat("theta1"),
                    theta2=cat("theta2"),
                )
            if kind == "contact":
                block.update(rest_gap=cat("rest_gap"), stiffness=cat("stiffness"))
            nodes = block["nodes"]
            block["dofs"] = (3 * nodes[:, :, None] + np.arange(3)).reshape(nodes.shape[0], -1)
            self._blocks.append(block)
        if getattr(self, "panel_set", None) is not None:
            nodes = self.panel_set["nodes"]
            self._blocks.append(
                {
                    "kind": "panel",
                    "nodes": nodes,
                    **self.panel_set,
                    "dofs": (3 * nodes[:, :, None] + np.arange(3)).reshape(nodes.shape[0], -1),
                }
            )
        dofs = [b["dofs"] for b in self._blocks]
        start = 0
        for b in self._blocks:  # each block's slice of the COO values
            size = b["dofs"].shape[0] * b["dofs"].shape[1] ** 2
            b["coo"] = slice(start, start + size)
            start += size
        self._coo_rows = np.concatenate([np.repeat(d, d.shape[1], axis=1).ravel() for d in dofs])
        self._coo_cols = np.concatenate([np.tile(d, (1, d.shape[1])).ravel() for d in dofs])

    # ------------------------------------------------------------------ state
    def strip_sets(self) -> list[BarSet]:
        return [b for b in self.bar_sets if b.kind == "lce"]

    def set_rest_fractions(self, fractions: dict[str, float | np.ndarray]) -> None:
        """Set f = L_r/L0 [-] of the LCE bars, by group name (scalar or one value per bar)."""
        names = {b.name: b for b in self.strip_sets()}
        for name, value in fractions.items():
            if name not in names:
                raise InputError(
                    f"rest fraction for {name!r}: no such strip group "
                    f"(have: {', '.join(names) or 'none'})"
                )
            value = np.broadcast_to(np.asarray(value, dtype=float), names[name].length0.shape)
            if np.any(value <= 0):
                raise InputError(f"rest fraction of {name}: must be > 0")
            names[name].rest_fraction = value.copy()

    def set_external_forces(self, forces) -> None:
        """Dead nodal loads [N], (n, 3) or (3n,) (e.g. weight: -m_i g along z)."""
        forces = np.asarray(forces, dtype=float).reshape(-1)
        if forces.shape != (self.ndof,) or not np.all(np.isfinite(forces)):
            raise InputError(f"external forces: need {self.ndof} finite values [N]")
        self.external_force = forces.copy()

    def rest_fractions(self) -> dict[str, np.ndarray]:
        return {b.name: b.rest_fraction.copy() for b in self.strip_sets()}

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, x: np.ndarray, derivatives: int = 2):
        """Total energy [mJ]; with derivatives >= 1 the gradient (3n,) [N]; with 2 the Hessian's COO
        values (ordered as :attr:`coo_pattern`) [N/mm].

        Args:
            x: node positions (n, 3) or (3n,) [mm].
        """
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        energy = 0.0
        grad = np.zeros(self.ndof) if derivatives >= 1 else None
        # The Hessian's COO values, each block written into its slice (no concatenation copy).
        # np.zeros: fresh pages, zero without a pass over them; the open contacts' Hessians stay
        # zero without being written (most of the contact block).
        values = np.zeros(self._coo_rows.size) if derivatives == 2 else None
        for block in self._blocks:
            nodes = block["nodes"]
            xs = [x[nodes[:, c]] for c in range(nodes.shape[1])]
            kind = block["kind"]
            if kind == "stiffening":
                exps = block["exponents"]
                out = law.bar_element(
                    xs[0],
                    xs[1],
                    block["length0"],
                    block["volume"],
                    lambda lam: bhm.stiffening_bar_law(lam, block["modulus"], exps),
                    derivatives=derivatives,
                )
            elif kind == "lce":
                rest = np.concatenate([g.rest_length for g in block["sets"]])
                volume = np.concatenate([g.energy_volume for g in block["sets"]])
                out = law.bar_element(
                    xs[0],
                    xs[1],
                    rest,
                    volume,
                    lambda lam: bhm.tension_only_ogden_law(lam, self.ogden),
                    derivatives=derivatives,
                )
            elif kind == "hinge":
                out = self._hinges(block, xs, derivatives, values)
            elif kind == "panel":
                out = self._panels(block, xs, derivatives, values)
            else:
                out = self._contacts(block, xs, derivatives, values)
                if derivatives == 2:
                    # closed_contacts(values) answers from this record, without a pass over the
                    # contact block
                    self._closed_record = (values, out[3])
                    out = out[:3]
            if derivatives == 0:
                energy += float(np.sum(out))
                continue
            energy += float(np.sum(out[0]))
            grad += np.bincount(block["dofs"].ravel(), weights=out[1].ravel(), minlength=self.ndof)
            if derivatives == 2 and kind not in ("hinge", "panel", "contact"):
                values[block["coo"]] = out[2].reshape(-1)
        if np.any(self.external_force):
            energy -= float(np.dot(self.external_force, x.reshape(-1) - self.reference.reshape(-1)))
            if derivatives >= 1:
                grad -= self.external_force
        if derivatives == 0:
            return energy
        if derivatives == 1:
            return energy, grad
        return energy, grad, values

    @staticmethod
    def _hinges(block: dict, xs: list[np.ndarray], derivatives: int, values: np.ndarray | None):
        """:func:`law.hinge_element` of the hinge block, its derivatives from the compiled kernel
        (the Hessian written straight into its slice of ``values`` when given)."""
        theta = law.dihedral_angle(*xs, derivatives=0)
        psi, moment, dmoment = bhm.enhanced_linear_law(
            theta, block["rest"], block["stiffness"], block["theta1"], block["theta2"]
        )
        energy = block["length"] * psi
        if derivatives == 0:
            return energy
        n = theta.size
        grad = np.empty((n, 12))
        hess = BarHingeModel._hessian_out(block, values, n, 12, derivatives)
        hinge_forces(
            *xs, block["length"] * moment, block["length"] * dmoment, grad, hess, derivatives == 2
        )
        if derivatives == 1:
            return energy, grad
        return energy, grad, hess

    @staticmethod
    def _hessian_out(block: dict, values, n: int, size: int, derivatives: int) -> np.ndarray:
        """Where a compiled kernel writes the block's (n, size, size) Hessians: a view of its slice
        of ``values`` when given (a slice, so no copy), a new array otherwise, and a placeholder it
        does not write when only the gradient is wanted."""
        if derivatives == 1:
            return np.empty((1, size, size))
        if values is None:
            return np.empty((n, size, size))
        return values[block["coo"]].reshape(n, size, size)

    @staticmethod
    def _panels(block: dict, xs: list[np.ndarray], derivatives: int, values: np.ndarray | None):
        """:func:`law.panel_bending_element` of the panel block, its derivatives from the compiled
        kernel (the Hessian written straight into its slice of ``values`` when given; the numpy
        version built (n, 15, 15) temporaries per spoke and was 40 % of the 5 x 5 gridshell's
        assembly)."""
        lengths = np.asarray(block["lengths"], dtype=float)
        theta = np.stack(
            [
                law.dihedral_angle(*(xs[q] for q in law.SPOKE_SLOTS[m]), derivatives=0)
                for m in range(4)
            ],
            axis=1,
        )
        d = np.mod(theta - block["rest"] + np.pi, 2.0 * np.pi) - np.pi
        c = np.asarray(block["stiffness"], dtype=float) / np.sum(lengths, axis=1)
        total = np.sum(lengths * d, axis=1)
        energy = 0.5 * c * total * total
        if derivatives == 0:
            return energy
        n = theta.shape[0]
        grad = np.empty((n, 15))
        hess = BarHingeModel._hessian_out(block, values, n, 15, derivatives)
        panel_bending_forces(
            np.stack(xs), lengths, c, c * total, SPOKE_SLOT_TABLE, grad, hess, derivatives == 2
        )
        if derivatives == 1:
            return energy, grad
        return energy, grad, hess

    @staticmethod
    def _contacts(block: dict, xs: list[np.ndarray], derivatives: int, values: np.ndarray | None):
        """:func:`law.unilateral_contact_element` of the contact block, the closed contacts'
        Hessians written into ``values`` (zero elsewhere: most contacts are open, on the 5 x 5
        gridshell at most 144 of 6920, and a zeroed (n, 12, 12) array copied into its slice cost
        as much as the bars' assembly); with derivatives == 2 also the closed contacts' indices."""
        n = block["dofs"].shape[0]
        hess_out = None
        if derivatives == 2 and values is not None:
            hess_out = values[block["coo"]].reshape(n, 12, 12)  # zero (evaluate's np.zeros)
        out = law.unilateral_contact_element(
            *xs, block["rest_gap"], block["stiffness"], derivatives=derivatives, hess_out=hess_out
        )
        if derivatives < 2:
            return out
        # closed: a positive penalty energy k <g0 - g>_+^2/2, i.e. a nonzero Hessian (the test of
        # closed_contacts); pen = g0 - g of mm-sized gaps is 0 or >= ~1e-19 mm: no underflow
        return (*out, np.flatnonzero(out[0] > 0))

    def contact_coo(self) -> tuple[slice, int] | None:
        """(slice of the COO values, entries per element) of the contact block, None without
        contacts."""
        for block in self._blocks:
            if block["kind"] == "contact":
                return block["coo"], block["dofs"].shape[1] ** 2
        return None

    def closed_contacts(self, coo_values: np.ndarray) -> np.ndarray:
        """Indices (into the contact block) of the closed contacts of Hessian values returned by
        :meth:`evaluate`: those with a nonzero diagonal. An open contact's Hessian is zero
        (:meth:`_contacts`); a closed one's point-point block is k n n^T (the gap's second
        derivative in the point is zero), whose diagonal sums to k > 0."""
        found = self.contact_coo()
        if found is None:
            return np.zeros(0, dtype=np.int64)
        record = getattr(self, "_closed_record", None)
        if record is not None and record[0] is coo_values:
            return record[1]
        block, per = found
        size = int(round(per**0.5))
        diag = coo_values[block].reshape(-1, per)[:, :: size + 1]
        return np.flatnonzero(np.any(diag != 0.0, axis=1))

    @property
    def coo_pattern(self) -> tuple[np.ndarray, np.ndarray]:
        """(rows, cols) of the Hessian's COO values returned by :meth:`evaluate`."""
        return self._coo_rows, self._coo_cols

    def energy(self, x) -> float:
        return self.evaluate(x, derivatives=0)

    def gradient(self, x) -> np.ndarray:
        return self.evaluate(x, derivatives=1)[1]

    def hessian(self, x) -> sp.csr_matrix:
        """Full Hessian [N/mm] as CSR (for tests and small problems; solvers use the reduced
        one)."""
        _, _, vals = self.evaluate(x)
        return sp.csr_matrix((vals, self.coo_pattern), shape=(self.ndof, self.ndof))

    def bar_forces(self, x) -> dict[str, np.ndarray]:
        """Axial force [N] (tension positive) of every bar, by group."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        return {
            b.name: law.axial_force(
                x[b.nodes[:, 0]],
                x[b.nodes[:, 1]],
                b.rest_length,
                b.energy_volume,
                b.law(self.ogden),
            )
            for b in self.bar_sets
        }

    def contact_forces(self, x) -> dict[str, np.ndarray]:
        """Contact pressure force k <g0 - g>_+ [N] of every contact, by group."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        out = {}
        for c in self.contact_sets:
            g = law.point_plane_gap(*(x[c.nodes[:, i]] for i in range(4)), derivatives=0)
            out[c.name] = c.stiffness * np.maximum(c.rest_gap - g, 0.0)
        return out

    def rest_fraction_sensitivity(self, x) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """d(gradient)/d f_b of every LCE bar b, by strip group: (dofs (m, 6), values (m, 6)) [N].

        With rest length L_r = f L0, stretch l = L/L_r and axial force F = V w'(l)/L_r, the bar's
        gradient is F (-u, u) (u its unit vector), and dF/df = -V (l w''(l) + w'(l))/(f L_r) with
        the material volume V (the volume law), A (w'(l) - l w''(l)) with the published law
        F = A f w'(l) (V = A f^2 L0); the other elements do not depend on f. Used for exact design
        sensitivities (implicit function theorem: dx/df = -K^-1 d(gradient)/df at an equilibrium).
        """
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        out = {}
        for b in self.strip_sets():
            d = x[b.nodes[:, 1]] - x[b.nodes[:, 0]]
            length = np.sqrt(np.einsum("ij,ij->i", d, d))
            rest = b.rest_length
            lam = length / rest
            _, dw, d2w = bhm.tension_only_ogden_law(lam, self.ogden)
            sign = -1.0 if b.published_area is None else 1.0
            dforce = b.energy_volume * (sign * dw - lam * d2w) / (b.rest_fraction * rest)
            u = d / length[:, None]
            values = np.concatenate([-dforce[:, None] * u, dforce[:, None] * u], axis=1)
            dofs = (3 * b.nodes[:, :, None] + np.arange(3)).reshape(b.nodes.shape[0], -1)
            out[b.name] = (dofs, values)
        return out

    def hinge_angles(self, x) -> dict[str, np.ndarray]:
        """Dihedral angles [rad] of every hinge, by group."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        return {
            h.name: law.dihedral_angle(
                x[h.nodes[:, 0]],
                x[h.nodes[:, 1]],
                x[h.nodes[:, 2]],
                x[h.nodes[:, 3]],
                derivatives=0,
            )
            for h in self.hinge_sets
        }


@dataclass
class _Pattern:
    """One CSC pattern of the reduced Hessian: the base pattern (every element but the contacts)
    plus some closed contacts. The base's entry p sits at ``moved[p]`` of this pattern's data; COO
    entry ``contact_source[k]`` of the closed contacts is summed into entry ``contact_target[k]``;
    the diagonal's positions (-1: not stored) and the symbolic LDL^T (built on first use)."""

    indices: np.ndarray
    indptr: np.ndarray
    moved: np.ndarray
    contact_source: np.ndarray
    contact_target: np.ndarray
    diagonal: np.ndarray
    new_entries: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # rows, cols, positions
    symbolic: SymbolicLDL | None = None


class ReducedHessian:
    """Maps the COO Hessian values of a model onto the CSC matrix of the free DOFs.

    Build it with :meth:`of`, which keeps one per (model, free DOFs): the pattern depends on nothing
    else, and building it (a sort of the ~0.7 M COO entries, 0.06-0.25 s on the gridshell) was
    repeated for every warm-started forward solve of a design (55 times in the quick design case).

    The unilateral contacts (:meth:`BarHingeModel.closed_contacts`) enter the pattern only while
    closed: on the 5 x 5 gridshell the 6920 strip-ribbon contacts held 996,480 of the 2.05 M COO
    entries and doubled the tangent's stored entries (458,973 against 242,397 without them), the
    LDL^T's fill (335,589 against 248,478) and its flops (2.0e7 against 1.2e7) with structural
    zeros, while at most 144 of them close at once (the Fig. 4 dome under the clamp: 123 sets of
    closed contacts over its 415 tangents). One pattern per set of closed contacts, built on first
    use by merging the set's entries into the base pattern and its symbolic LDL^T
    (:meth:`SymbolicLDL.with_entries`: the base's fill-reducing ordering). The values summed into
    each entry are the same, in the same order, as with every contact in the pattern (an open
    contact's entries are zeros); only the factorisation's order of operations changes.
    """

    #: Patterns kept per ReducedHessian, the least recently used dropped first (chosen: ~10 MB each
    #: with its symbolic LDL^T on the 5 x 5 gridshell; a path's tangents revisit the sets of the
    #: last few iterations, and a dropped set costs ~20 ms to merge again).
    MAX_PATTERNS = 32

    @classmethod
    def of(cls, model: BarHingeModel, free: np.ndarray) -> "ReducedHessian":
        """The reduced Hessian of ``model`` on ``free``, built once per model and set of free
        DOFs."""
        free = np.asarray(free, dtype=np.int64)
        cache = model.__dict__.setdefault("_reduced_hessians", {})
        key = free.tobytes()
        if key not in cache:
            cache[key] = cls(model, free)
        return cache[key]

    def __init__(self, model: BarHingeModel, free: np.ndarray):
        ndof = model.ndof
        self.model = model
        self.free = np.asarray(free, dtype=np.int64)
        index = np.full(ndof, -1, dtype=np.int64)
        index[self.free] = np.arange(self.free.size)
        rows, cols = model.coo_pattern
        r, c = index[rows], index[cols]
        keep = (r >= 0) & (c >= 0)
        n = self.free.size
        self.n = n
        # CSC order: by column, then row
        self._keys = c * n + r
        self._kept = keep
        self._contacts = model.contact_coo()
        base = keep.copy()
        if self._contacts is not None:
            base[self._contacts[0]] = False
        source = np.flatnonzero(base)
        self._base_keys, inverse = np.unique(self._keys[source], return_inverse=True)
        target = inverse.astype(np.int64)
        # COO order: the base entries before the contact block, its closed contacts, the rest
        split = (
            0 if self._contacts is None else int(np.searchsorted(source, self._contacts[0].start))
        )
        self._before = (source[:split], target[:split])
        self._after = (source[split:], target[split:])
        self._patterns: OrderedDict[bytes, _Pattern] = OrderedDict()
        self._by_indices: dict[int, _Pattern] = {}
        self._base: _Pattern | None = None

    def _csc(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """indices, indptr and diagonal positions of the sorted CSC keys (column * n + row)."""
        n = self.n
        indices = (keys % n).astype(np.int32)
        indptr = np.concatenate([[0], np.cumsum(np.bincount(keys // n, minlength=n))])
        diagonal = np.full(n, -1, dtype=np.int64)
        on = indices == keys // n
        diagonal[indices[on]] = np.flatnonzero(on)
        return indices, indptr.astype(np.int32), diagonal

    def _pattern(self, closed: np.ndarray) -> _Pattern:
        """The pattern with the contacts ``closed`` (indices into the contact block)."""
        key = closed.tobytes()
        pattern = self._patterns.get(key)
        if pattern is not None:
            self._patterns.move_to_end(key)
            return pattern
        while len(self._patterns) >= self.MAX_PATTERNS:
            _, dropped = self._patterns.popitem(last=False)
            self._by_indices.pop(id(dropped.indices), None)
        base_keys, none = self._base_keys, np.zeros(0, dtype=np.int64)
        if not closed.size and self._base is not None:
            pattern = self._base  # kept apart from the cache: every merge starts from it
        elif not closed.size:
            indices, indptr, diagonal = self._csc(base_keys)
            moved = np.arange(base_keys.size)
            pattern = self._base = _Pattern(indices, indptr, moved, none, none, diagonal)
        else:
            # Merged into the base pattern by insertion (O(base) copies and searches of the few
            # new keys, no sort of the whole pattern).
            base = self._pattern(none)
            block, per = self._contacts
            source = (block.start + closed[:, None] * per + np.arange(per)).reshape(-1)
            source = source[self._kept[source]]
            source_keys = self._keys[source]
            new = np.unique(source_keys)
            at = np.searchsorted(base_keys, new)
            stored = at < base_keys.size
            stored[stored] = base_keys[at[stored]] == new[stored]
            new, at = new[~stored], at[~stored]
            keys = np.insert(base_keys, at, new)
            shift = inserted_before(at, base_keys.size)  # new keys before each base entry
            moved = np.arange(base_keys.size) + shift
            n = self.n
            rows, cols = new % n, new // n
            indices = np.insert(base.indices, at, rows.astype(np.int32))
            indptr = (base.indptr + np.searchsorted(cols, np.arange(n + 1))).astype(np.int32)
            diagonal = np.where(base.diagonal >= 0, moved[base.diagonal], -1)
            pattern = _Pattern(
                indices,
                indptr,
                moved,
                source,
                np.searchsorted(keys, source_keys),
                diagonal,
                (rows, cols, np.searchsorted(keys, new)),
            )
        self._patterns[key] = pattern
        self._by_indices[id(pattern.indices)] = pattern
        return pattern

    def _symbolic(self, pattern: _Pattern) -> SymbolicLDL:
        if pattern.symbolic is None:
            if pattern.new_entries is None:  # the base pattern
                pattern.symbolic = SymbolicLDL(pattern.indices, pattern.indptr, self.n)
            else:
                base = self._symbolic(self._pattern(np.zeros(0, dtype=np.int64)))
                pattern.symbolic = base.with_entries(pattern.moved, *pattern.new_entries)
        return pattern.symbolic

    def _pattern_of(self, matrix: sp.csc_matrix) -> _Pattern:
        """The pattern of a matrix returned by :meth:`matrix`; one dropped from the cache since
        (or a matrix of another origin) gets a stand-alone pattern of its own (own ordering)."""
        pattern = self._by_indices.get(id(matrix.indices))
        if pattern is not None and pattern.indices is matrix.indices:
            return pattern
        if self._base is not None and self._base.indices is matrix.indices:
            return self._base
        diagonal = np.full(self.n, -1, dtype=np.int64)
        cols = np.repeat(np.arange(self.n), np.diff(matrix.indptr))
        on = matrix.indices == cols
        diagonal[matrix.indices[on]] = np.flatnonzero(on)
        none = np.zeros(0, dtype=np.int64)
        return _Pattern(matrix.indices, matrix.indptr, none, none, none, diagonal)

    def matrix(self, coo_values: np.ndarray) -> sp.csc_matrix:
        """The reduced Hessian [N/mm] (CSC) of the model's COO values: the open contacts' entries
        (zeros) are left out of its pattern."""
        closed = (
            np.zeros(0, dtype=np.int64)
            if self._contacts is None
            else self.model.closed_contacts(coo_values)
        )
        p = self._pattern(closed)
        data = scatter_merged(
            coo_values,
            *self._before,
            p.contact_source,
            p.contact_target,
            *self._after,
            p.moved,
            p.indices.size,
        )
        out = sp.csc_matrix((data, p.indices, p.indptr), shape=(self.n, self.n))
        if out.indices is not p.indices:  # scipy copied them: the lookups need ours
            out.indices, out.indptr = p.indices, p.indptr
        return out

    def ldl_of(self, matrix: sp.csc_matrix) -> SymbolicLDL:
        """The symbolic LDL^T (ordering, elimination tree) of a matrix returned by :meth:`matrix`,
        built once per pattern."""
        return self._symbolic(self._pattern_of(matrix))

    def diagonal(self, matrix: sp.csc_matrix) -> np.ndarray:
        """The diagonal of a matrix returned by :meth:`matrix` (as ``matrix.diagonal()``, by the
        stored positions instead of a search of every column)."""
        positions = self._pattern_of(matrix).diagonal
        out = np.zeros(self.n)
        on = positions >= 0
        out[on] = matrix.data[positions[on]]
        return out
