"""Heat in a ribbon's cross-sections: a grid of cell temperatures per edge, implicit Euler.

Each edge's section (w x t) is split into the cells of ``lcefem.models.ribbon.SectionGrid``; a cell
of size (w/n_w) x (t/n_t) x l stores heat rho c (w t/(n_w n_t)) l and exchanges it

* by conduction with its neighbours across the thickness and the width and with the same cell of
  the neighbouring edges (conductance k x area / centre distance);
* through its exposed patches (bottom and top faces, normals -m2, +m2; the two edges, normals
  -m1, +m1) with the air (film coefficient plus radiation to the ambient on the part not facing
  the plate, ``lcefem.models.heat.SurfaceExchange``) and with the hot ground
  (``lcefem.models.ribbon.GroundHeatExchange``: air film and radiation by facing, contact
  conduction at a touching corner).

The coefficients are evaluated on the current geometry and the previous temperatures (radiation
linearised there); the linear system is symmetric and banded (half-bandwidth n_w n_t) and is
assembled and solved by banded Cholesky; coefficients, solve and fluxes are one compiled call
(:func:`heat_kernels.heat_step`), with :meth:`SectionHeat.coefficients` in numpy as the reference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.models.contact import ContactLaw
from lcefem.models.heat import SurfaceExchange, ThermalProperties, radiative_film_coefficient
from lcefem.models.ribbon import GroundHeatExchange, SectionGrid
from lcefem.models.rod import CORNER_SIGNS
from lcefem.solvers.der import heat_kernels


def _corner_view(a, b):
    """View factor from a point to the rectangle [0, a] x [0, b] of a parallel plane, a unit
    distance away, whose corner lies at the point's foot (Howell's catalogue C-11), extended odd in
    a and in b."""
    sa, sb = np.sqrt(1.0 + a * a), np.sqrt(1.0 + b * b)
    return (a / sa * np.arctan(b / sa) + b / sb * np.arctan(a / sb)) / (2.0 * np.pi)


def block_face_view(box, points: np.ndarray, floor: float = 0.0) -> np.ndarray:
    """View factor (...,) from a point facing it squarely to the face of the axis-aligned ``box``
    nearest to each of ``points`` (..., 3) [mm]: the face's rectangle, above the plate at ``floor``
    [mm], seen from the point's distance (1 at contact over the face, falling as the block subtends
    less). Used to limit the plate's law, written for an unbounded plate, to the block's finite
    face."""
    p = np.asarray(points, float)
    lo, hi = np.array(box.lo, float), np.array(box.hi, float)
    lo[2] = max(lo[2], floor)
    n = box.normals(p)
    axis = np.argmax(np.abs(n), axis=-1)
    out = np.zeros(p.shape[:-1])
    for k in range(3):
        sel = axis == k
        if not np.any(sel):
            continue
        q = p[sel]
        plane = np.where(n[sel][:, k] > 0, hi[k], lo[k])
        d = np.maximum(np.abs(q[:, k] - plane), 1e-9)
        u, v = [j for j in range(3) if j != k]
        f = 0.0
        for cu, su in ((hi[u], 1.0), (lo[u], -1.0)):
            for cv, sv in ((hi[v], 1.0), (lo[v], -1.0)):
                f = f + su * sv * _corner_view((cu - q[:, u]) / d, (cv - q[:, v]) / d)
        out[sel] = np.clip(f, 0.0, 1.0)
    return out


@dataclass
class HeatGeometry:
    """Per edge: midpoint c (n, 3), material frame m1, m2 (n, 3), length l (n,) [mm], and optionally
    the smallest gap of each corner over the edge (n, 4) [mm] (default: the midpoint section's)."""

    centre: np.ndarray
    m1: np.ndarray
    m2: np.ndarray
    length: np.ndarray
    corner_gap: np.ndarray | None = None


@dataclass
class HeatFluxes:
    """Diagnostics of one heat step: power from the ground and to the air [mW] per edge (n,)."""

    from_ground: np.ndarray
    to_air: np.ndarray


class SectionHeat:
    """Implicit-Euler heat model of a ribbon's sections (see module docstring)."""

    def __init__(
        self,
        n_edges: int,
        grid: SectionGrid,
        reference_length: np.ndarray,
        thermal: ThermalProperties,
        air: SurfaceExchange,
        ground: GroundHeatExchange,
        contact: ContactLaw,
        ground_normal=(0.0, 0.0, 1.0),
        ground_height: float = 0.0,
    ):
        self.n = n_edges
        self.grid = grid
        self.thermal, self.air, self.ground, self.contact = thermal, air, ground, contact
        self.normal = np.asarray(ground_normal, float) / np.linalg.norm(ground_normal)
        self.height = ground_height
        w, t, nw, nt = grid.width, grid.thickness, grid.n_width, grid.n_thickness
        nc = grid.n_cells
        self.nc = nc
        dw, dt_ = w / nw, t / nt
        self.capacity = thermal.volumetric_heat_capacity * dw * dt_ * np.asarray(reference_length)
        k = thermal.conductivity
        self.k = k
        # In-section conductances per unit length: (cell a, cell b, k x contact width / distance).
        pairs = []
        for iw in range(nw):
            for it in range(nt):
                c = iw * nt + it
                if it + 1 < nt:
                    pairs.append((c, c + 1, k * dw / dt_))
                if iw + 1 < nw:
                    pairs.append((c, c + nt, k * dt_ / dw))
        self._pair_a = np.array([a for a, _, _ in pairs], int)
        self._pair_b = np.array([b for _, b, _ in pairs], int)
        self._pair_g = np.array([g for _, _, g in pairs], float)
        self.k_axial = k * dw * dt_
        # Exposed patches: cell, area per unit length, normal (frame vector index 0 = m1, 1 = m2,
        # sign), centroid offsets (a, b) along (m1, m2).
        y1, y2 = grid.y1, grid.y2
        cells, area, axis, sign, off_a, off_b = [], [], [], [], [], []
        for c in range(nc):
            iw, it = divmod(c, nt)
            if it == 0:
                cells.append(c)
                area.append(dw)
                axis.append(1)
                sign.append(-1.0)
                off_a.append(y1[c])
                off_b.append(-0.5 * t)
            if it == nt - 1:
                cells.append(c)
                area.append(dw)
                axis.append(1)
                sign.append(1.0)
                off_a.append(y1[c])
                off_b.append(0.5 * t)
            if iw == 0:
                cells.append(c)
                area.append(dt_)
                axis.append(0)
                sign.append(-1.0)
                off_a.append(-0.5 * w)
                off_b.append(y2[c])
            if iw == nw - 1:
                cells.append(c)
                area.append(dt_)
                axis.append(0)
                sign.append(1.0)
                off_a.append(0.5 * w)
                off_b.append(y2[c])
        self.p_cell = np.array(cells)
        self.p_area = np.array(area)
        self.p_axis = np.array(axis)
        self.p_sign = np.array(sign)
        self.p_off = np.stack([off_a, off_b], axis=1)
        self.corner_cells = grid.corner_cells()
        # Patch -> cell and corner -> cell sums as matrix products (one BLAS call instead of
        # np.add.at, which costs ~10x more per call at the ribbon's sizes).
        self._patch_to_cell = (self.p_cell[:, None] == np.arange(nc)[None, :]).astype(float)
        self._corner_to_cell = (self.corner_cells[:, None] == np.arange(nc)[None, :]).astype(float)

    def coefficients(self, T: np.ndarray, geo: HeatGeometry, T_ground: float, gradient=None):
        """Exchange conductances [mW/K] of each cell with the ground (n, n_cells) and the air
        (n, n_cells), the conductance-weighted air temperature [C] each cell sees (n, n_cells) and
        the conductance-weighted ground temperature [C] (n, n_cells).

        ``gradient`` (3,) [K/mm]: the plate temperature varies as T_ground + gradient . x under each
        patch and corner (x its position; None: uniform)."""
        nz = self.normal
        cz = geo.centre @ nz - self.height
        m1z, m2z = geo.m1 @ nz, geo.m2 @ nz
        heights = (
            cz[:, None]
            + self.p_off[None, :, 0] * m1z[:, None]
            + self.p_off[None, :, 1] * m2z[:, None]
        )
        nrm_z = np.where(self.p_axis == 0, m1z[:, None], m2z[:, None]) * self.p_sign[None, :]
        facing = np.maximum(0.0, -nrm_z)
        area = self.p_area[None, :] * geo.length[:, None]
        Tp = T[:, self.p_cell]
        T_uniform = T_ground
        if gradient is not None:
            gradient = np.asarray(gradient, float)
            gc, g1, g2 = geo.centre @ gradient, geo.m1 @ gradient, geo.m2 @ gradient
            T_ground = T_uniform + (
                gc[:, None]
                + self.p_off[None, :, 0] * g1[:, None]
                + self.p_off[None, :, 1] * g2[:, None]
            )
        h_ground = self.ground.patch_coefficient(heights, facing, Tp, T_ground)
        h_amb = self.air.film_coefficient + radiative_film_coefficient(
            Tp, self.air.ambient_temperature, self.air.emissivity
        ) * (1.0 - facing)
        T_air = self.ground.air_temperature(heights, self.air.ambient_temperature, T_ground)
        to_cell = self._patch_to_cell
        G_g = (h_ground * area) @ to_cell
        Q_g = (h_ground * area * T_ground) @ to_cell
        G_a = (h_amb * area) @ to_cell
        Q_a = (h_amb * area * T_air) @ to_cell
        if geo.corner_gap is not None:
            corner = geo.corner_gap
        else:
            corner = (
                cz[:, None]
                + 0.5 * self.grid.width * CORNER_SIGNS[:, 0] * m1z[:, None]
                + 0.5 * self.grid.thickness * CORNER_SIGNS[:, 1] * m2z[:, None]
            )
        weight = 0.5 * (1.0 - np.tanh(0.5 * self.contact.K1 * corner))  # 1/(1 + exp(K1 gap))
        g_contact = self.ground.contact_conductance * geo.length[:, None] * weight
        G_g += g_contact @ self._corner_to_cell
        T_corner = (
            T_uniform
            if gradient is None
            else (
                T_uniform
                + gc[:, None]
                + 0.5 * self.grid.width * CORNER_SIGNS[:, 0] * g1[:, None]
                + 0.5 * self.grid.thickness * CORNER_SIGNS[:, 1] * g2[:, None]
            )
        )
        Q_g += (g_contact * T_corner) @ self._corner_to_cell
        return G_g, G_a, Q_a / np.maximum(G_a, 1e-300), Q_g / np.maximum(G_g, 1e-300)

    def block_coefficients(self, T: np.ndarray, geo: HeatGeometry, blocks, T_ground: float = None):
        """Exchange conductances [mW/K] of each cell with blocks (n, n_cells), their
        conductance-weighted sum of block temperatures [mW] (n, n_cells), and the air exchange the
        blocks hide (conductance [mW/K] and its weighted air temperatures [mW], (n, n_cells) each: a
        patch facing a block by f sees the block instead of the air over f, so f of its air film and
        radiation to the ambient is replaced, not added; T_ground [C] for the air's boundary layer,
        None: no air hidden). ``blocks``: (box, T_block [C], corner gaps (n, 4) [mm]) per block, the
        box a ``solvers.der.model.Box`` (its ``gaps`` and outward normal). The plate's law
        (``GroundHeatExchange``) with the block's face in place of the plate: a patch whose centroid
        lies a gap z from the block and whose outward normal faces the block's outward normal n_b by
        c = max(0, -n . n_b) gets f [k_air/(z + z0) + h_rad(T, T_block)], f = c F, F the view factor
        of the block's face from the patch (:func:`block_face_view`: 1 at contact, falling with
        distance as the finite face subtends less; the plate's law is written for an unbounded
        plate, F = 1); a corner at gap g adds G_c w(g) per unit length. The air near the block is
        the air elsewhere (no boundary layer of the block)."""
        n, nc = T.shape
        G = np.zeros((n, nc))
        Q = np.zeros((n, nc))
        G_hidden = np.zeros((n, nc))
        Q_hidden = np.zeros((n, nc))
        if not blocks:
            return G, Q, G_hidden, Q_hidden
        pos = (
            geo.centre[:, None, :]
            + self.p_off[None, :, 0, None] * geo.m1[:, None, :]
            + self.p_off[None, :, 1, None] * geo.m2[:, None, :]
        )
        nrm = (
            np.where((self.p_axis == 0)[None, :, None], geo.m1[:, None, :], geo.m2[:, None, :])
            * self.p_sign[None, :, None]
        )
        area = self.p_area[None, :] * geo.length[:, None]
        Tp = T[:, self.p_cell]
        nz = self.normal
        height = pos @ nz - self.height
        ground_facing = np.maximum(0.0, -(nrm @ nz))
        h_amb = self.air.film_coefficient + radiative_film_coefficient(
            Tp, self.air.ambient_temperature, self.air.emissivity
        ) * (1.0 - ground_facing)
        T_air = (
            self.ground.air_temperature(height, self.air.ambient_temperature, T_ground)
            if T_ground is not None
            else None
        )
        seen = np.zeros_like(h_amb)  # fraction of each patch's view taken by blocks
        for box, T_block, corner in blocks:
            gap = box.gaps(pos)
            facing = np.maximum(0.0, -np.einsum("npi,npi->np", nrm, box.normals(pos)))
            facing = np.minimum(facing * block_face_view(box, pos, self.height), 1.0 - seen)
            seen += facing
            h = self.ground.patch_coefficient(gap, facing, Tp, T_block)
            G += (h * area) @ self._patch_to_cell
            Q += (h * area * T_block) @ self._patch_to_cell
            weight = 0.5 * (1.0 - np.tanh(0.5 * self.contact.K1 * corner))
            g_contact = self.ground.contact_conductance * geo.length[:, None] * weight
            G += g_contact @ self._corner_to_cell
            Q += (g_contact * T_block) @ self._corner_to_cell
        if T_air is not None:
            G_hidden = (seen * h_amb * area) @ self._patch_to_cell
            Q_hidden = (seen * h_amb * area * T_air) @ self._patch_to_cell
        return G, Q, G_hidden, Q_hidden

    def step(
        self,
        T: np.ndarray,
        dt: float,
        geo: HeatGeometry,
        T_ground: float,
        gradient=None,
        compiled: bool = True,
        blocks=(),
    ) -> tuple[np.ndarray, HeatFluxes]:
        """Cell temperatures (n, n_cells) [C] after dt [s] from T, on the geometry ``geo`` (plate at
        T_ground + gradient . x, see :meth:`coefficients`). ``compiled``: the exchange coefficients,
        the solve and the fluxes in one compiled call (:func:`heat_kernels.heat_step`; at 100 nodes
        0.51 -> 0.25 ms per call timed alone, issue 17); False: :meth:`coefficients` in numpy, kept
        as the reference (the same temperatures to round-off, ``tests/solvers/test_der_ribbon.py``).
        ``blocks``: blocks that exchange heat (:meth:`block_coefficients`); with any, the numpy
        path, the blocks' exchange added to the plate's (``HeatFluxes.from_ground`` then counts
        both)."""
        if blocks:
            G_g, G_a, T_air, T_g = self.coefficients(T, geo, T_ground, gradient)
            G_b, Q_b, G_h, Q_h = self.block_coefficients(T, geo, blocks, T_ground)
            G_gb = G_g + G_b
            T_gb = (G_g * T_g + Q_b) / np.maximum(G_gb, 1e-300)
            G_left = np.maximum(G_a - G_h, 0.0)  # the air's view left to each cell
            T_air = np.where(G_left > 0.0, (G_a * T_air - Q_h) / np.maximum(G_left, 1e-300), T_air)
            G_a = G_left
            C = self.capacity[:, None] / dt
            T_new = heat_kernels.heat_solve(
                C,
                G_gb,
                G_a,
                np.ascontiguousarray(T, float),
                T_gb,
                T_air,
                np.ascontiguousarray(geo.length, float),
                self._pair_a,
                self._pair_b,
                self._pair_g,
                float(self.k_axial),
            )
            return T_new, HeatFluxes((G_gb * (T_gb - T_new)).sum(1), (G_a * (T_new - T_air)).sum(1))
        if compiled:
            corner = (
                geo.corner_gap if geo.corner_gap is not None else self._midpoint_corner_gaps(geo)
            )
            c = np.ascontiguousarray
            g = np.zeros(3) if gradient is None else np.asarray(gradient, float)
            T_new, from_ground, to_air = heat_kernels.heat_step(
                c(T, float),
                float(dt),
                c(geo.centre, float),
                c(geo.m1, float),
                c(geo.m2, float),
                c(geo.length, float),
                c(corner, float),
                float(T_ground),
                g,
                self._kernel_data(),
            )
            return T_new, HeatFluxes(from_ground, to_air)
        G_g, G_a, T_air, T_ground = self.coefficients(T, geo, T_ground, gradient)
        C = self.capacity[:, None] / dt
        T_new = heat_kernels.heat_solve(
            C,
            G_g,
            G_a,
            np.ascontiguousarray(T, float),
            np.ascontiguousarray(T_ground, float),
            T_air,
            np.ascontiguousarray(geo.length, float),
            self._pair_a,
            self._pair_b,
            self._pair_g,
            float(self.k_axial),
        )
        fluxes = HeatFluxes((G_g * (T_ground - T_new)).sum(1), (G_a * (T_new - T_air)).sum(1))
        return T_new, fluxes

    def _kernel_data(self) -> tuple:
        """The model's constant data in the argument order of :func:`heat_kernels.heat_step` (one
        signature: int64 indices, float64 arrays and floats); built on first use (also for a pickled
        model)."""
        data = self.__dict__.get("_kernel_tuple")
        if data is None:
            w, t = self.grid.width, self.grid.thickness
            i64 = lambda a: np.ascontiguousarray(a, np.int64)  # noqa: E731
            f64 = lambda a: np.ascontiguousarray(a, float)  # noqa: E731
            corner_off = np.stack(
                [0.5 * w * CORNER_SIGNS[:, 0], 0.5 * t * CORNER_SIGNS[:, 1]], axis=1
            )
            air = (
                float(self.air.film_coefficient),
                float(self.air.ambient_temperature),
                float(self.air.emissivity),
            )
            g = self.ground
            ground = (
                float(g.air_conductivity),
                float(g.gap_floor),
                float(g.plate_emissivity),
                float(g.boundary_layer),
                float(g.contact_conductance),
            )
            data = self._kernel_tuple = (
                f64(self.capacity),
                f64(self.normal),
                float(self.height),
                i64(self.p_cell),
                f64(self.p_area),
                i64(self.p_axis),
                f64(self.p_sign),
                f64(self.p_off),
                i64(self.corner_cells),
                f64(corner_off),
                air,
                ground,
                float(self.contact.K1),
                i64(self._pair_a),
                i64(self._pair_b),
                f64(self._pair_g),
                float(self.k_axial),
            )
        return data

    def _midpoint_corner_gaps(self, geo: HeatGeometry) -> np.ndarray:
        """Gap [mm] of each corner of each edge's midpoint section (n, 4) (HeatGeometry without
        corner gaps)."""
        nz = self.normal
        cz = geo.centre @ nz - self.height
        m1z, m2z = geo.m1 @ nz, geo.m2 @ nz
        return (
            cz[:, None]
            + 0.5 * self.grid.width * CORNER_SIGNS[:, 0] * m1z[:, None]
            + 0.5 * self.grid.thickness * CORNER_SIGNS[:, 1] * m2z[:, None]
        )
