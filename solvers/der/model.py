"""The discrete rod (what does not change in a step) and its state (what does).

Degrees of freedom, interleaved so that every element touches a contiguous block and the
Hessian is banded (half-bandwidth 10): q = (x_0, theta_0, x_1, theta_1, ..., theta_(N-2), x_(N-1)),
4N - 1 values, nodes x_i [mm] at q[4i:4i+3] and edge angles theta_k [rad] at q[4k+3].
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass, field

import numpy as np

from lcefem.models.contact import ContactLaw, FrictionLaw
from lcefem.models.errors import InputError
from lcefem.models.rod import CORNER_SIGNS, RodSection
from lcefem.solvers.der import frame_kernels
from lcefem.solvers.der import frames as fr


def n_dofs(n_nodes: int) -> int:
    return 4 * n_nodes - 1


@functools.lru_cache(maxsize=64)
def node_dofs(n_nodes: int) -> np.ndarray:
    """Indices (N, 3) of the node coordinates in q (read-only)."""
    idx = 4 * np.arange(n_nodes)[:, None] + np.arange(3)[None, :]
    idx.flags.writeable = False
    return idx


@functools.lru_cache(maxsize=64)
def twist_dofs(n_nodes: int) -> np.ndarray:
    """Indices (N-1,) of the edge angles in q (read-only)."""
    idx = 4 * np.arange(n_nodes - 1) + 3
    idx.flags.writeable = False
    return idx


@dataclass(frozen=True)
class Geometry:
    """Derived quantities of a state: edges e (N-1, 3) [mm], lengths (N-1,), unit tangents t,
    material frames m1, m2 (N-1, 3) and integrated twists m (N-2,) [rad]."""

    e: np.ndarray
    length: np.ndarray
    t: np.ndarray
    m1: np.ndarray
    m2: np.ndarray
    twist: np.ndarray


@dataclass
class RestShape:
    """Natural (stress-free) geometry; may change between steps (heat actuation).

    Attributes:
        edge_length: rest edge lengths |e_bar| [mm], (N-1,).
        curvature: natural integrated curvatures (kappa_bar_1, kappa_bar_2) [-] of interior nodes,
            (N-2, 2).
        twist: natural integrated twist m_bar [rad] of interior nodes, (N-2,).
    """

    edge_length: np.ndarray
    curvature: np.ndarray
    twist: np.ndarray

    @property
    def voronoi_length(self) -> np.ndarray:
        """l_bar_k = (|e_bar^(k-1)| + |e_bar^k|)/2 [mm], (N-2,)."""
        return 0.5 * (self.edge_length[:-1] + self.edge_length[1:])

    @classmethod
    def straight(cls, edge_length: np.ndarray) -> "RestShape":
        n = len(edge_length) - 1
        return cls(np.asarray(edge_length, float).copy(), np.zeros((n, 2)), np.zeros(n))

    @classmethod
    def from_densities(
        cls, edge_length: np.ndarray, curvature: np.ndarray, twist: np.ndarray
    ) -> "RestShape":
        """From curvature densities (kappa_1, kappa_2) [1/mm] and twist density [rad/mm] at interior
        nodes (scalars, (N-2,) or (N-2, 2)), integrated over the rest Voronoi lengths."""
        edge_length = np.asarray(edge_length, float)
        vor = 0.5 * (edge_length[:-1] + edge_length[1:])
        k = np.broadcast_to(np.asarray(curvature, float), (len(vor), 2)) * vor[:, None]
        tw = np.broadcast_to(np.asarray(twist, float), (len(vor),)) * vor
        return cls(edge_length.copy(), np.array(k), np.array(tw))

    def copy(self) -> "RestShape":
        return RestShape(self.edge_length.copy(), self.curvature.copy(), self.twist.copy())


@dataclass(frozen=True)
class Ground:
    """A rigid plane {p : n.p = height}; points have gap n.p - height [mm]."""

    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)
    height: float = 0.0

    def unit_normal(self) -> np.ndarray:
        """The plane's unit normal (computed once; read-only)."""
        n = self.__dict__.get("_unit_normal")
        if n is None:
            n = np.asarray(self.normal, float)
            n = n / np.linalg.norm(n)
            n.flags.writeable = False
            self.__dict__["_unit_normal"] = n  # frozen dataclass: cache outside its fields
        return n


@dataclass(frozen=True)
class Box:
    """A rigid axis-aligned block with rounded edges: the outer box [lo, hi] [mm] with its edges and
    corners rounded to ``radius`` [mm], i.e. the points within ``radius`` of the inner box
    [lo + radius, hi - radius]. A point's gap is its distance to the inner box minus the radius, the
    signed distance to the rounded surface outside the inner box: continuous with a continuous
    gradient (the outward unit normal), so the smooth contact law of the planes applies unchanged;
    its Hessian (P - n n^T)/D (P the axes along which the point lies beyond the inner box, D the
    distance) is bounded by 1/radius on the rounded edges and zero on the flat faces."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    radius: float
    friction: float | None = (
        None  # friction coefficient on the box [-]; None: the rod's friction law's
    )

    def __post_init__(self):
        lo, hi = np.asarray(self.lo, float), np.asarray(self.hi, float)
        if lo.shape != (3,) or hi.shape != (3,):
            raise InputError(
                f"box lo = {self.lo}, hi = {self.hi}: must be three coordinates each [mm]"
            )
        if not self.radius > 0:
            raise InputError(f"box radius = {self.radius} mm: must be > 0 mm")
        if self.friction is not None and not self.friction >= 0:
            raise InputError(f"box friction = {self.friction}: must be >= 0")
        if np.any(hi - lo <= 2.0 * self.radius):
            raise InputError(
                f"box lo = {self.lo}, hi = {self.hi} mm: each side must exceed twice the edge "
                f"radius {self.radius} mm"
            )

    def array(self) -> np.ndarray:
        """(lo, hi, radius, friction coefficient or -1 for the rod's) as an (8,) float array (for
        the kernels)."""
        mu = -1.0 if self.friction is None else float(self.friction)
        return np.array(tuple(self.lo) + tuple(self.hi) + (self.radius, mu), float)

    def gaps(self, points: np.ndarray) -> np.ndarray:
        """Gaps [mm] of points (..., 3) to the rounded box (negative inside)."""
        p = np.asarray(points, float)
        r = self.radius
        lo = np.asarray(self.lo, float) + r
        hi = np.asarray(self.hi, float) - r
        d = np.maximum(lo - p, 0.0) + np.maximum(p - hi, 0.0)
        outside = np.sqrt(np.einsum("...i,...i->...", d, d))
        inside = -np.minimum(p - lo, hi - p).min(axis=-1)
        return np.where(outside > 0.0, outside, np.minimum(inside, 0.0)) - r

    def normals(self, points: np.ndarray) -> np.ndarray:
        """Outward unit normals (..., 3) of the rounded box at the points nearest to ``points``
        (..., 3) (the gradient of :meth:`gaps`; inside the inner box, that of its nearest face)."""
        p = np.asarray(points, float)
        r = self.radius
        lo = np.asarray(self.lo, float) + r
        hi = np.asarray(self.hi, float) - r
        d = np.maximum(p - hi, 0.0) - np.maximum(lo - p, 0.0)
        dist = np.sqrt(np.einsum("...i,...i->...", d, d))
        out = d / np.maximum(dist, 1e-300)[..., None]
        inside = dist <= 0.0
        if np.any(inside):
            depth = np.concatenate([p - lo, hi - p], axis=-1)  # distances to the faces -x.., +x..
            face = np.argmin(depth, axis=-1)
            face_normal = np.concatenate([-np.eye(3), np.eye(3)])[face]
            out = np.where(inside[..., None], face_normal, out)
        return out


@dataclass
class DiscreteRod:
    """Everything a step needs besides the state.

    Attributes:
        section: stiffnesses, mass and inertia per length, width/thickness (for the contact
            corners).
        rest: natural geometry (may be replaced between steps).
        node_mass: lumped node masses [t], (N,); edge_inertia: polar mass moments of the edges
            [t mm^2].
        gravity: acceleration vector [mm/s^2].
        damping: mass-proportional viscous damping rate [1/s] (air drag of the slow motions).
        ground, contact, friction: optional rigid plane with the smooth laws of seed 000.
        obstacles: further rigid planes (walls standing on the ground) with the same contact and
            friction laws; each is a half-space {p : n.p < height} the rod stays out of.
        boxes: rigid blocks of finite size (:class:`Box`) with the same contact and friction laws.
        contact_offsets: (p, 2) cross-section points (a, b) [mm] (offset a m1 + b m2 from the
            centreline) that touch the ground: the ribbon's four corners by default, so that a flat
            ribbon touches with its face (two corners per section) or with an edge; the centreline
            (with ContactLaw.clearance = radius) for a round rod.
        contact_samples: sections sampled per edge (even: frame angle interpolated with the nodes'
            twist, so the ribbon's edges are continuous helices; 1: edge midpoints only).
        fixed: boolean mask of prescribed dofs (4N-1,); they keep their current values.
        external_force: constant generalised force [N for nodes, N mm for edge angles], (4N-1,).
    """

    section: RodSection
    rest: RestShape
    node_mass: np.ndarray
    edge_inertia: np.ndarray
    gravity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    damping: float = 0.0
    ground: Ground | None = None
    contact: ContactLaw | None = None
    friction: FrictionLaw | None = None
    obstacles: tuple[Ground, ...] = ()
    boxes: tuple[Box, ...] = ()
    contact_offsets: np.ndarray | None = None
    contact_samples: int = 2
    fixed: np.ndarray | None = None
    external_force: np.ndarray | None = None

    def __post_init__(self):
        n = len(self.node_mass)
        if n < 3:
            raise InputError(f"nodes = {n}: a discrete rod needs >= 3 nodes")
        if self.contact_samples < 1:
            raise InputError(f"contact_samples = {self.contact_samples}: must be >= 1")
        self.obstacles = tuple(self.obstacles)
        self.boxes = tuple(self.boxes)
        if (self.obstacles or self.boxes) and (self.ground is None or self.contact is None):
            raise InputError("obstacles: walls and boxes need a ground and a contact law")
        if self.fixed is None:
            self.fixed = np.zeros(n_dofs(n), bool)
        if self.external_force is None:
            self.external_force = np.zeros(n_dofs(n))
        if self.contact_offsets is None:
            s = self.section
            if s.width > 0 or s.thickness > 0:
                self.contact_offsets = CORNER_SIGNS * np.array([0.5 * s.width, 0.5 * s.thickness])
            else:
                self.contact_offsets = np.zeros((1, 2))
        self.gravity = np.asarray(self.gravity, float)

    @property
    def n_nodes(self) -> int:
        return len(self.node_mass)

    @property
    def has_contact(self) -> bool:
        return self.ground is not None and self.contact is not None

    def contact_planes(self) -> tuple[Ground, ...]:
        """The ground and the obstacles (empty without contact)."""
        return (self.ground,) + self.obstacles if self.has_contact else ()

    def contact_shapes(self) -> tuple:
        """The ground, the walls and the boxes (empty without contact)."""
        return self.contact_planes() + self.boxes if self.has_contact else ()

    def mass_vector(self) -> np.ndarray:
        """Diagonal of the lumped mass matrix (4N-1,) [t for nodes, t mm^2 for edge angles]."""
        n = self.n_nodes
        m = np.empty(n_dofs(n))
        m[node_dofs(n)] = self.node_mass[:, None]
        m[twist_dofs(n)] = self.edge_inertia
        return m

    def replace(self, **changes) -> "DiscreteRod":
        return dataclasses.replace(self, **changes)


def lumped_masses(section: RodSection, edge_length: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Node masses (half of each adjacent edge) [t] and edge polar inertia [t mm^2]."""
    me = section.mass_per_length * edge_length
    node_mass = np.zeros(len(edge_length) + 1)
    node_mass[:-1] += 0.5 * me
    node_mass[1:] += 0.5 * me
    return node_mass, section.inertia_per_length * edge_length


@dataclass
class RodState:
    """Configuration and velocities of a rod, with its reference frames.

    Attributes:
        x: node positions [mm], (N, 3); theta: edge angles [rad], (N-1,).
        v: node velocities [mm/s]; omega: edge spin rates d(theta)/dt [rad/s].
        a1: reference directors [-], (N-1, 3), normal to the tangents.
        ref_twist: reference twist of the interior nodes [rad], (N-2,).
        time: [s].
        source_tangents: tangents (N-1, 3) the reference directors were transported from by
            :meth:`moved` (None: the state's own tangents); the energies' derivatives are taken
            with that source held fixed.
        acceleration: mean generalised acceleration (4N-1,) [mm/s^2, rad/s^2] of the time step that
            produced this state (None: not produced by a step); the integrator's extrapolated guess.
    """

    x: np.ndarray
    theta: np.ndarray
    v: np.ndarray
    omega: np.ndarray
    a1: np.ndarray
    ref_twist: np.ndarray
    time: float = 0.0
    source_tangents: np.ndarray | None = None
    acceleration: np.ndarray | None = None

    @classmethod
    def from_positions(
        cls,
        x: np.ndarray,
        theta: np.ndarray | None = None,
        first_director: np.ndarray | None = None,
        time: float = 0.0,
    ) -> "RodState":
        """A rod at rest with reference directors space-parallel transported from ``first_director``
        (so the reference twist starts at zero)."""
        x = np.asarray(x, float).copy()
        t = fr.unit(fr.edges_of(x))
        if first_director is None:
            first_director = fr.perpendicular_director(t[:1])[0]
        a1 = fr.space_parallel_directors(t, np.asarray(first_director, float))
        n = len(x)
        theta = np.zeros(n - 1) if theta is None else np.asarray(theta, float).copy()
        return cls(x, theta, np.zeros_like(x), np.zeros(n - 1), a1, np.zeros(n - 2), time)

    def copy(self) -> "RodState":
        src = None if self.source_tangents is None else self.source_tangents.copy()
        return RodState(
            self.x.copy(),
            self.theta.copy(),
            self.v.copy(),
            self.omega.copy(),
            self.a1.copy(),
            self.ref_twist.copy(),
            self.time,
            src,
        )

    def resourced(self) -> "RodState":
        """The same configuration with its own tangents as the transport source."""
        return RodState(
            self.x, self.theta, self.v, self.omega, self.a1, self.ref_twist, self.time, None
        )

    def geometry(self) -> Geometry:
        """Edges, tangents, material frames and twists (computed once per state; states are not
        modified in place once built)."""
        geo = self.__dict__.get("_geometry")
        if geo is None:
            e = self.x[1:] - self.x[:-1]
            length = np.sqrt(np.einsum("ki,ki->k", e, e))
            t = e / length[:, None]
            m1, m2 = fr.material_frames(self.a1, t, self.theta)
            twist = self.theta[1:] - self.theta[:-1] + self.ref_twist
            geo = Geometry(e, length, t, m1, m2, twist)
            self.__dict__["_geometry"] = geo
        return geo

    @property
    def tangents(self) -> np.ndarray:
        return self.geometry().t

    def q(self) -> np.ndarray:
        n = len(self.x)
        q = np.empty(n_dofs(n))
        q[node_dofs(n)] = self.x
        q[twist_dofs(n)] = self.theta
        return q

    def qdot(self) -> np.ndarray:
        n = len(self.x)
        q = np.empty(n_dofs(n))
        q[node_dofs(n)] = self.v
        q[twist_dofs(n)] = self.omega
        return q

    def material_frames(self) -> tuple[np.ndarray, np.ndarray]:
        geo = self.geometry()
        return geo.m1, geo.m2

    def moved(self, dq: np.ndarray) -> "RodState":
        """The state displaced by dq, with reference frames transported in time from this state's
        tangents (which become the new state's ``source_tangents``) and the reference twist
        continued (velocities are copied unchanged)."""
        n = len(self.x)
        x = self.x + dq[node_dofs(n)]
        theta = self.theta + dq[twist_dofs(n)]
        t_old = self.tangents
        # frames, tangents and twists in one compiled pass (a Newton iterate is a moved state)
        e, length, t_new, a1, ref, m1, m2, twist = frame_kernels.moved_geometry(
            x, theta, self.a1, t_old, self.ref_twist
        )
        out = RodState(x, theta, self.v.copy(), self.omega.copy(), a1, ref, self.time, t_old)
        out.__dict__["_geometry"] = Geometry(e, length, t_new, m1, m2, twist)
        return out
