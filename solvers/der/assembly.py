"""Assembly of the rod's energy, gradient and banded Hessian (element loops compiled in
:mod:`lcefem.solvers.der.kernels`; :meth:`Assembly.gradient` and :meth:`Assembly.band` scatter
element arrays of the numpy formulas, which the tests use as the reference).

Elements: edges (stretching; contact and friction of the end half-edges' section points; dofs
x_k, theta_k, x_(k+1): 7 contiguous entries of q) and interior-node stencils (bending, twisting,
contact and friction of the section points on the two half-edges next to the node, whose frame
angle is interpolated with the node's twist; dofs x_(k-1) ... x_(k+1): 11 contiguous entries).
The Hessian is kept in LAPACK's lower banded storage ab[i - j, j] = H[i, j] (i >= j,
half-bandwidth 10).

``order`` selects what is computed: 0 energy only (line search), 1 with gradient, 2 with Hessian.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from lcefem.models import rod as rodlaw
from lcefem.models.contact import normal_force
from lcefem.solvers.der import contact_kernels, kernels
from lcefem.solvers.der.model import Box, DiscreteRod, Ground, RodState, n_dofs

BANDWIDTH = 10

#: Edge slots (node a start, theta index, node b start) of the element layouts.
EDGE_SLOTS = ((0, 3, 4),)
STENCIL_SLOTS = ((0, 3, 4), (4, 7, 8))


@dataclass
class Derivatives:
    """Energy [mJ], gradient (4N-1,) and lower banded Hessian (11, 4N-1) of a potential."""

    energy: float
    grad: np.ndarray | None
    band: np.ndarray | None


# ----------------------------------------------------------------------------------------------
# Contact sampling
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ContactSampling:
    """Where the rod's surface meets the ground: section points (e.g. the ribbon's four corners)
    sampled ``per_edge`` times along every edge.

    per_edge even: the points of the half-edges next to an interior node take the frame angle
    interpolated with that node's twist (``lcefem.models.rod.StencilPoints``), so the ribbon's edge
    lines are continuous helices; the outer halves of the two end edges keep their edge's frame.
    per_edge 1: one section at each edge's midpoint, in the edge's frame.
    """

    offsets: np.ndarray
    per_edge: int
    stencil: rodlaw.StencilPoints | None
    end_sigma: (
        np.ndarray
    )  # (2, p_end): fractions on the first and last edge (or (1, p) for all edges)
    end_offsets: np.ndarray  # (p_end, 2)

    @classmethod
    def of(cls, rod: DiscreteRod) -> "ContactSampling":
        offsets = rod.contact_offsets
        per_edge = rod.contact_samples
        if per_edge == 1 or per_edge % 2:
            k = len(offsets)
            return cls(offsets, 1, None, np.full((1, k), 0.5), offsets)
        stencil = rodlaw.StencilPoints.sampling(offsets, per_edge)
        half = per_edge // 2
        sig = (np.arange(per_edge) + 0.5) / per_edge
        k = len(offsets)
        first = np.repeat(sig[:half], k)  # outer half of edge 0
        last = np.repeat(sig[half:], k)  # outer half of the last edge
        return cls(offsets, per_edge, stencil, np.stack([first, last]), np.tile(offsets, (half, 1)))

    @property
    def interpolated(self) -> bool:
        return self.stencil is not None

    def _cached(self, key, make):
        """``make()`` computed once per sampling (a frozen dataclass: the cache lives outside its
        fields); every Newton evaluation asks for these index arrays."""
        cache = self.__dict__.setdefault("_cache", {})
        if key not in cache:
            cache[key] = make()
        return cache[key]

    def end_edges(self, n_edges: int) -> np.ndarray:
        return self._cached(
            ("end_edges", n_edges),
            lambda: np.array([0, n_edges - 1]) if self.interpolated else np.arange(n_edges),
        )

    def end_sigma_rows(self, n_edges: int) -> np.ndarray:
        """Fractions along the edge of the end-edge points, one row per edge of
        :meth:`end_edges`."""
        if self.interpolated:
            return self.end_sigma
        return self._cached(
            ("end_sigma", n_edges),
            lambda: np.ascontiguousarray(
                np.broadcast_to(self.end_sigma, (n_edges, self.end_sigma.shape[1]))
            ),
        )

    def end_offsets_array(self) -> np.ndarray:
        """``end_offsets`` as a contiguous float array (for the kernels)."""
        return self._cached("end_offsets", lambda: np.ascontiguousarray(self.end_offsets, float))

    def kernel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(side as bool, sigma, offsets) of the stencil points (empty without interpolation)."""

        def make():
            if self.stencil is None:
                return np.zeros(0, bool), np.zeros(0), np.zeros((0, 2))
            st = self.stencil
            return (
                st.side.astype(bool),
                np.asarray(st.sigma, float),
                np.ascontiguousarray(st.offsets, float),
            )

        return self._cached("kernel_arrays", make)


def sample_points(state: RodState, sampling: ContactSampling):
    """Positions and frame offsets [mm] of all sample points: (pos_s, r_s) (N-2, p_s, 3) of the
    stencil points (empty without interpolation) and (pos_e, r_e) (n_end, p_e, 3) of the end-edge
    points; computed once per state (states are not modified in place once built)."""
    cache = state.__dict__.setdefault("_samples", {})
    out = cache.get(id(sampling))
    if out is None:
        geo = state.geometry()
        n_edges = len(geo.t)
        side, sigma, offsets = sampling.kernel_arrays()
        out = contact_kernels.sample_points(
            state.x,
            state.a1,
            geo.t,
            state.theta,
            geo.twist,
            geo.m1,
            geo.m2,
            side,
            sigma,
            offsets,
            sampling.end_edges(n_edges),
            sampling.end_sigma_rows(n_edges),
            sampling.end_offsets_array(),
        )
        cache[id(sampling)] = out
    return out


def all_gaps(
    rod: DiscreteRod, state: RodState, sampling: ContactSampling, plane: Ground | Box | None = None
):
    """Gaps [mm] of every sample point to the ground (or to ``plane``, a plane or a box): (stencil
    (N-2, p_s) or None, ends (n_end, p_e))."""
    plane = rod.ground if plane is None else plane
    if isinstance(plane, Box):
        pos_s, _, pos_e, _ = sample_points(state, sampling)
        return (plane.gaps(pos_s) if sampling.interpolated else None), plane.gaps(pos_e)
    nrm = plane.unit_normal()
    h = plane.height
    pos_s, _, pos_e, _ = sample_points(state, sampling)
    gs = pos_s @ nrm - h if sampling.interpolated else None
    return gs, pos_e @ nrm - h


def point_positions(
    state: RodState, sampling: ContactSampling, kind: str, elem: np.ndarray, col: np.ndarray
):
    """Positions (k, 3) of selected sample points, with their frame offsets r and edge tangents t
    (k, 3); ``elem`` is the stencil index or the row of the end-edge set."""
    pos_s, r_s, pos_e, r_e = sample_points(state, sampling)
    t = state.geometry().t
    if kind == "stencil":
        edge = elem + sampling.stencil.side[col]
        return pos_s[elem, col], r_s[elem, col], t[edge]
    return pos_e[elem, col], r_e[elem, col], t[sampling.end_edges(len(t))[elem]]


@dataclass
class FrictionLag:
    """Start-of-step data of the friction potential for the stencil and end-edge point sets: the
    normal forces of all points (lagged) [N] and the positions [mm] of those with a force (NaN
    elsewhere)."""

    stencil_normal: np.ndarray | None
    stencil_points: np.ndarray | None
    end_normal: np.ndarray
    end_points: np.ndarray
    obstacles: tuple["FrictionLag", ...] = ()  # the same for each of ``rod.obstacles``
    boxes: tuple["FrictionLag", ...] = ()  # the same for each of ``rod.boxes``

    def with_normals_of(self, new: "FrictionLag") -> "FrictionLag":
        """These start-of-step points with the normal forces of ``new`` (re-solves with updated
        forces)."""
        return FrictionLag(
            new.stencil_normal,
            self.stencil_points,
            new.end_normal,
            self.end_points,
            tuple(a.with_normals_of(b) for a, b in zip(self.obstacles, new.obstacles)),
            tuple(a.with_normals_of(b) for a, b in zip(self.boxes, new.boxes)),
        )

    def all_lags(self) -> tuple["FrictionLag", ...]:
        """The ground's, the walls' and the boxes' lags, in the order of
        ``DiscreteRod.contact_shapes``."""
        return (self,) + self.obstacles + self.boxes


def friction_lag(
    rod: DiscreteRod,
    state: RodState,
    sampling: ContactSampling,
    all_points: bool = False,
    plane: Ground | Box | None = None,
) -> FrictionLag:
    """Sample points and contact normal forces of ``state`` (the start of a step) on the ground
    (and, in ``obstacles`` and ``boxes``, on each wall and box), or on ``plane`` alone; positions of
    all points with ``all_points``, else only of those with a normal force."""
    if plane is None and (rod.obstacles or rod.boxes):
        ground = friction_lag(rod, state, sampling, all_points, rod.ground)
        walls = tuple(friction_lag(rod, state, sampling, all_points, w) for w in rod.obstacles)
        boxes = tuple(friction_lag(rod, state, sampling, all_points, b) for b in rod.boxes)
        return dataclasses.replace(ground, obstacles=walls, boxes=boxes)
    gs, ge = all_gaps(rod, state, sampling, plane)
    out = []
    for kind, gap in (("stencil", gs), ("edge", ge)):
        if gap is None:
            out += [None, None]
            continue
        law = rod.contact
        normal = contact_kernels.normal_force(
            np.ascontiguousarray(gap),
            float(law.clearance),
            float(law.delta),
            float(law.K1),
            float(law.stiffness),
        )
        # the sample positions where a point has a force (all with all_points), NaN elsewhere: one
        # np.where instead of full + nonzero + fancy indexing (the same values, ~2x less time, issue
        # 17)
        points = sample_points(state, sampling)[0 if kind == "stencil" else 2]
        pos = points.copy() if all_points else np.where((normal > 0.0)[..., None], points, np.nan)
        out += [normal, pos]
    return FrictionLag(*out)


class Assembly:
    """Index maps of one rod size; evaluates the elastic, contact and friction terms."""

    def __init__(self, n_nodes: int):
        self.n_nodes = n = n_nodes
        self.ndof = nd = n_dofs(n)
        self.edge_base = 4 * np.arange(n - 1)
        self.node_base = 4 * np.arange(n - 2)
        self.edge_idx = self.edge_base[:, None] + np.arange(7)[None, :]
        self.stencil_idx = self.node_base[:, None] + np.arange(11)[None, :]
        self._e_pairs = np.tril_indices(7)
        self._s_pairs = np.tril_indices(11)
        a, c = self._e_pairs
        self.edge_band = (a - c)[None, :] * nd + self.edge_base[:, None] + c[None, :]
        a, c = self._s_pairs
        self.stencil_band = (a - c)[None, :] * nd + self.node_base[:, None] + c[None, :]
        self.band_size = (BANDWIDTH + 1) * nd
        self._no_db, self._no_ddb = (
            np.zeros((1, 3)),
            np.zeros((1, 3, 3)),
        )  # placeholders (same source)
        self._no_band = np.zeros((1, 1))  # placeholder (no Hessian)
        self._no_lag_n, self._no_lag_p = (
            np.zeros((1, 1)),
            np.zeros((1, 1, 3)),
        )  # placeholders (no friction)
        self._no_box = np.zeros(8)  # placeholder (a plane)

    # -- scatter ---------------------------------------------------------------------------
    def gradient(self, g_edges, g_stencils, edge_rows=None, stencil_rows=None) -> np.ndarray:
        g = np.zeros(self.ndof)
        if g_edges is not None:
            idx = self.edge_idx if edge_rows is None else self.edge_idx[edge_rows]
            g += np.bincount(idx.ravel(), g_edges.ravel(), minlength=self.ndof)
        if g_stencils is not None:
            idx = self.stencil_idx if stencil_rows is None else self.stencil_idx[stencil_rows]
            g += np.bincount(idx.ravel(), g_stencils.ravel(), minlength=self.ndof)
        return g

    def band(self, terms, diagonal: np.ndarray | None) -> np.ndarray:
        """Lower band of sum of element Hessians; ``terms`` = [(kind, H, rows)], kind 'edge' or
        'stencil', rows the element indices (None: all)."""
        ab = np.zeros(self.band_size)
        for kind, h, rows in terms:
            if h is None:
                continue
            if kind == "band":  # already in banded storage
                ab += h.ravel()
                continue
            if kind == "edge":
                a, c = self._e_pairs
                idx = self.edge_band if rows is None else self.edge_band[rows]
            else:
                a, c = self._s_pairs
                idx = self.stencil_band if rows is None else self.stencil_band[rows]
            ab += np.bincount(idx.ravel(), h[:, a, c].ravel(), minlength=self.band_size)
        ab = ab.reshape(BANDWIDTH + 1, self.ndof)
        if diagonal is not None:
            ab[0] += diagonal
        return ab

    # -- elastic energy ----------------------------------------------------------------------
    def _outputs(self, order: int, out):
        """The gradient and band arrays a kernel adds into: ``out`` = (grad, band) when given (band
        may be None below order 2), else new zero arrays."""
        if out is not None:
            grad, band = out
            return grad, (band if order >= 2 else self._no_band), True
        grad = np.zeros(self.ndof)
        band = np.zeros((BANDWIDTH + 1, self.ndof)) if order >= 2 else self._no_band
        return grad, band, False

    def elastic(self, rod: DiscreteRod, state: RodState, order: int = 2, out=None):
        """Stretching, bending and twisting (compiled element loops, :func:`kernels.elastic`).

        Args:
            out: optional (grad (4N-1,), band (11, 4N-1) or None) to add the derivatives into.

        Returns:
            (energy, gradient (4N-1,) or None, Hessian terms for :meth:`band`); with ``out`` the
            derivatives are in ``out`` and (energy, None, []) is returned.
        """
        sec = rod.section
        rest = rod.rest
        geo = state.geometry()
        change = source_change(state) if order >= 1 else None
        db, ddb = change if change is not None else (self._no_db, self._no_ddb)
        grad, band, given = self._outputs(order, out)
        energy = kernels.elastic(
            state.x,
            geo.m1,
            geo.m2,
            geo.twist,
            rest.edge_length,
            rest.curvature,
            rest.twist,
            rest.voronoi_length,
            float(sec.EA),
            float(sec.EI1),
            float(sec.EI2),
            float(sec.GJ),
            db,
            ddb,
            change is not None,
            order >= 2,
            grad,
            band,
        )
        if given:
            return energy, None, []
        return (
            energy,
            (grad if order >= 1 else None),
            ([("band", band, None)] if order >= 2 else []),
        )

    # -- contact and friction ----------------------------------------------------------------
    def contact(
        self,
        rod: DiscreteRod,
        state: RodState,
        sampling: ContactSampling,
        order: int = 2,
        friction: FrictionLag | None = None,
        step: float = 0.0,
        out=None,
    ):
        """Contact potential k E(gap) of the sample points with the ground, the walls and the boxes,
        plus (when ``friction`` is given) the friction potential over a step of length ``step`` [s]
        (compiled: :func:`contact_kernels.contact`). Only the points within reach of a plane (or
        carrying a lagged friction force on it) are differentiated.

        Args:
            out: as in :meth:`elastic`.

        Returns:
            (energy, gradient (4N-1,) or None, Hessian terms for :meth:`band`); with ``out``
            (energy, None, []).
        """
        if not rod.has_contact:
            return 0.0, None, []
        law = rod.contact
        fric = friction is not None and rod.friction is not None and step > 0
        change = source_change(state) if order >= 1 else None
        db, ddb = change if change is not None else (self._no_db, self._no_ddb)
        geo = state.geometry()
        n_edges = len(geo.t)
        pos_s, r_s, pos_e, r_e = sample_points(state, sampling)
        side, sigma, _ = sampling.kernel_arrays()
        grad, band, given = self._outputs(order, out)
        energy = 0.0
        if fric and (
            len(friction.obstacles) != len(rod.obstacles) or len(friction.boxes) != len(rod.boxes)
        ):
            raise ValueError(
                f"friction lag has {len(friction.obstacles)} obstacles and {len(friction.boxes)} "
                "boxes, "
                f"the rod {len(rod.obstacles)} and {len(rod.boxes)}"
            )
        shapes = rod.contact_shapes()
        lags = friction.all_lags() if fric else (None,) * len(shapes)
        for plane, lag in zip(shapes, lags):
            # (the normal passed as a writeable copy: a read-only array would be a second kernel
            # signature next to the compiled Newton loop's, compiled again for nothing)
            if fric:
                lag_ns = lag.stencil_normal if sampling.interpolated else self._no_lag_n
                lag_ps = lag.stencil_points if sampling.interpolated else self._no_lag_p
                lag_ne, lag_pe = lag.end_normal, lag.end_points
                mu, K2 = rod.friction.mu, rod.friction.K2
            else:
                lag_ns, lag_ps, lag_ne, lag_pe = (
                    self._no_lag_n,
                    self._no_lag_p,
                    self._no_lag_n,
                    self._no_lag_p,
                )
                mu, K2 = 0.0, 1.0
            is_box = isinstance(plane, Box)
            normal = np.array(rod.ground.unit_normal() if is_box else plane.unit_normal())
            height = 0.0 if is_box else float(plane.height)
            energy += contact_kernels.contact(
                pos_s,
                r_s,
                pos_e,
                r_e,
                state.x,
                geo.t,
                geo.length,
                side,
                sigma,
                sampling.end_edges(n_edges),
                sampling.end_sigma_rows(n_edges),
                normal,
                height,
                float(law.clearance),
                float(law.delta),
                float(law.K1),
                float(law.stiffness),
                fric,
                lag_ns,
                lag_ps,
                lag_ne,
                lag_pe,
                float(mu),
                float(K2),
                float(step),
                db,
                ddb,
                change is not None,
                order,
                grad,
                band,
                plane.array() if is_box else self._no_box,
                is_box,
            )
        if given:
            return energy, None, []
        return (
            energy,
            (grad if order >= 1 else None),
            ([("band", band, None)] if order >= 2 else []),
        )


def source_change(state: RodState):
    """Holonomy derivatives (per edge) for a state whose frames came from ``state.source_tangents``,
    or None when the source is the state itself."""
    src = state.source_tangents
    if src is None:
        return None
    if (
        "_source_change" in state.__dict__
    ):  # computed once per state (elastic and contact both need it)
        return state.__dict__["_source_change"]
    geo = state.geometry()
    out = (
        None
        if np.max(np.abs(src - geo.t)) == 0.0
        else kernels.source_change(src, geo.t, geo.length)
    )
    state.__dict__["_source_change"] = out
    return out


def node_contact_forces(rod: DiscreteRod, state: RodState, sampling: ContactSampling) -> np.ndarray:
    """Contact force vector per node (N, 3) [N]: each sample point's force shared by the nodes of
    its edge in proportion to its position along the edge."""
    out = np.zeros((rod.n_nodes, 3))
    if not rod.has_contact:
        return out
    gs, ge = all_gaps(rod, state, sampling)
    nrm = rod.ground.unit_normal()
    n_edges = rod.n_nodes - 1
    f_end = normal_force(ge, rod.contact)
    sig = (
        sampling.end_sigma
        if sampling.interpolated
        else np.broadcast_to(sampling.end_sigma, f_end.shape)
    )
    ids = sampling.end_edges(n_edges)
    np.add.at(out, ids, ((1.0 - sig) * f_end).sum(1)[:, None] * nrm)
    np.add.at(out, ids + 1, (sig * f_end).sum(1)[:, None] * nrm)
    if gs is not None:
        fs = normal_force(gs, rod.contact)
        st = sampling.stencil
        side = st.side.astype(bool)
        # points of edge e (nodes k-1, k) and f (nodes k, k+1) of stencil s (node k = s + 1)
        w_prev = np.where(side, 0.0, 1.0 - st.sigma)
        w_node = np.where(side, 1.0 - st.sigma, st.sigma)
        w_next = np.where(side, st.sigma, 0.0)
        k = np.arange(n_edges - 1)
        out[k] += (fs @ w_prev)[:, None] * nrm
        out[k + 1] += (fs @ w_node)[:, None] * nrm
        out[k + 2] += (fs @ w_next)[:, None] * nrm
    return out


def edge_corner_gaps(rod: DiscreteRod, state: RodState, sampling: ContactSampling) -> np.ndarray:
    """Smallest gap [mm] of each section point kind (e.g. each corner) over the samples of each
    edge, shape (N-1, len(offsets)); +inf without a ground. One compiled pass over the sample points
    (:func:`contact_kernels.edge_min_gaps`; the gaps as :func:`all_gaps` computes them)."""
    n_edges = rod.n_nodes - 1
    k = len(sampling.offsets)
    if rod.ground is None:
        return np.full((n_edges, k), np.inf)
    pos_s, _, pos_e, _ = sample_points(state, sampling)
    side, slot_s, slot_e = gap_slots(sampling)
    return contact_kernels.edge_min_gaps(
        pos_s,
        pos_e,
        side,
        slot_s,
        sampling.end_edges(n_edges),
        slot_e,
        n_edges,
        k,
        rod.ground.unit_normal(),
        float(rod.ground.height),
        sampling.interpolated,
    )


def gap_slots(sampling: ContactSampling) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For :func:`contact_kernels.edge_min_gaps` and the block's corner gaps: the edge (0: the
    stencil's first, 1: its second) and section point kind of every stencil point, and the kind of
    every end-edge point (points of one edge are stored kind-fastest: ``ContactSampling.of``);
    computed once per sampling."""
    return sampling._cached("edge_min_gaps", lambda: _make_gap_slots(sampling))


def _make_gap_slots(sampling: ContactSampling) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    k = len(sampling.offsets)
    side, _, _ = sampling.kernel_arrays()
    side = np.ascontiguousarray(side, np.int64)
    slot_s = np.zeros(len(side), np.int64)
    for flag in (0, 1):
        cols = np.nonzero(side == flag)[0]
        slot_s[cols] = np.arange(len(cols)) % k
    slot_e = np.arange(sampling.end_sigma.shape[1]) % k
    return side, slot_s, np.ascontiguousarray(slot_e, np.int64)
