"""Smooth implicit contact and smooth Coulomb friction (seed 000, 'Contact Model'; Choi, Tong, Jawed
& Joo, J. Appl. Mech. 2021; Tong, Choi, Joo & Jawed, 2022).

Contact energy of a point at distance Delta [mm] from a surface, with the minimum engagement
distance 2h [mm] and the smoothing width delta [mm], K1 = 15/delta [1/mm]:

    E(Delta) = (2h - Delta)^2                                  Delta <= 2h - delta
             = ((1/K1) log(1 + exp(K1 (2h - Delta))))^2         2h - delta < Delta < 2h + delta
             = 0                                                Delta >= 2h + delta

and the contact potential is k E [mJ] with the stiffness k [N/mm]; the contact force is
F^c = -k dE/dDelta along the surface normal. (The three pieces join to within exp(-15) ~ 3e-7 of
delta, as in the seed.)

Friction (seed 000, 'Static Friction'): F^fr = -mu gamma(|v_T|) v_T/|v_T| F^n with
gamma(v) = 2/(1 + exp(-K2 v)) - 1 = tanh(K2 v/2), K2 = 15/nu, nu the slipping tolerance [mm/s].
Over a time step h with the normal force F^n and the normal held at their start-of-step values
(lagged, as in incremental-potential contact), this force is minus the gradient of the friction
potential

    D(u) = mu F^n h Gamma(|u_T|/h),   Gamma(v) = (2/K2) ln cosh(K2 v/2),   u_T = (I - n n^T) u,

where u is the point's displacement over the step; D is smooth and convex, so friction joins the
implicit step's minimisation with an exact, symmetric Hessian.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.models.errors import InputError
from lcefem.models.parameters import param


@dataclass(frozen=True)
class ContactLaw:
    """Smooth penalty contact of seed 000."""

    delta: float = param(
        0.05,
        "mm",
        "chosen: smoothing width, 6 % of the ribbon thickness (seed 000: "
        "'allowing small penetrations'); wide enough that a rolling ribbon's edge "
        "stays in the smooth band for several 0.01 s steps",
        positive=True,
    )
    stiffness: float = param(
        1.0,
        "N/mm",
        "assumed: k; with the ribbon's weight (~2e-3 N) the static penetration stays below delta",
        positive=True,
    )
    clearance: float = param(
        0.0,
        "mm",
        "2h of seed 000: minimum engagement distance (0 for points "
        "on the true surface, e.g. ribbon corners; the radius for a round rod's "
        "centreline)",
        minimum=0.0,
    )

    @property
    def K1(self) -> float:
        """K1 = 15/delta [1/mm] (seed 000)."""
        return 15.0 / self.delta


@dataclass(frozen=True)
class FrictionLaw:
    """Smooth Coulomb friction of seed 000."""

    mu: float = param(
        0.5, "-", "assumed friction coefficient of an elastomer on a metal plate", minimum=0.0
    )
    slip_speed: float = param(
        0.2,
        "mm/s",
        "chosen: nu of seed 000, the slipping tolerance; a "
        "tangential load of half the Coulomb limit creeps at 0.07 nu = 0.015 mm/s, "
        "well below the rolling speeds (~1 mm/s); smaller nu makes the friction "
        "potential sharper than Newton's steps",
        positive=True,
    )

    @property
    def K2(self) -> float:
        """K2 = 15/nu [s/mm] (seed 000)."""
        return 15.0 / self.slip_speed


def contact_energy(gap: np.ndarray, law: ContactLaw):
    """E(Delta) of seed 000 and its first two derivatives [mm^2, mm, -] (without the stiffness k).

    Args:
        gap: distances Delta [mm] (any shape).
    """
    gap = np.asarray(gap, dtype=float)
    d = law.clearance - gap  # 2h - Delta
    K1 = law.K1
    x = K1 * d
    s = np.logaddexp(0.0, x) / K1  # softplus / K1
    sig = 0.5 * (1.0 + np.tanh(0.5 * x))  # logistic, overflow-free
    energy = s * s
    d1 = -2.0 * s * sig
    d2 = 2.0 * sig * sig + 2.0 * s * sig * (1.0 - sig) * K1
    inner = d >= law.delta  # Delta <= 2h - delta: the quadratic piece
    energy = np.where(inner, d * d, energy)
    d1 = np.where(inner, -2.0 * d, d1)
    d2 = np.where(inner, 2.0, d2)
    outer = d <= -law.delta  # Delta >= 2h + delta: no contact
    energy = np.where(outer, 0.0, energy)
    d1 = np.where(outer, 0.0, d1)
    d2 = np.where(outer, 0.0, d2)
    return energy, d1, d2


def normal_force(gap: np.ndarray, law: ContactLaw) -> np.ndarray:
    """Magnitude of the contact force F^n = k |dE/dDelta| [N] at each point."""
    return -law.stiffness * contact_energy(gap, law)[1]


def friction_gamma(speed: np.ndarray, law: FrictionLaw) -> np.ndarray:
    """gamma(|v_T|) = 2/(1 + exp(-K2 |v_T|)) - 1 [-] (seed 000)."""
    return np.tanh(0.5 * law.K2 * np.abs(speed))


def friction_force(v_t: np.ndarray, normal: np.ndarray, law: FrictionLaw) -> np.ndarray:
    """F^fr = -mu gamma(|v_T|) v_T/|v_T| F^n [N] for tangential velocities v_t (n, 3) [mm/s]."""
    speed = np.linalg.norm(v_t, axis=-1)
    a = 0.5 * law.K2
    phi = np.where(a * speed > 1e-4, np.tanh(a * speed) / np.maximum(speed, 1e-300), a)
    return -law.mu * (normal * phi)[..., None] * v_t


def friction_potential(
    u: np.ndarray, normal_dir: np.ndarray, normal: np.ndarray, h: float, law: FrictionLaw
):
    """Friction potential D of the points, its gradient and Hessian in the displacement u.

    Args:
        u: displacement of each contact point over the step [mm], shape (n, 3).
        normal_dir: unit surface normal n (3,) or (n, 3).
        normal: normal force F^n [N] of each point (lagged), shape (n,).
        h: time step [s].

    Returns:
        D (n,) [mJ], dD/du (n, 3) [N] (= minus the friction force), d2D/du2 (n, 3, 3) [N/mm].
    """
    n_dir = np.broadcast_to(normal_dir, u.shape)
    w = u - np.einsum("ni,ni->n", u, n_dir)[:, None] * n_dir  # tangential displacement
    v = np.linalg.norm(w, axis=1) / h  # slip speed [mm/s]
    a = 0.5 * law.K2
    z = a * v
    small = z < 1e-3
    zs = np.where(small, 1.0, z)
    # Gamma(v) = ln cosh(z)/a; phi = tanh(z)/v; psi = phi'(v)/v (finite limits at v -> 0).
    logcosh = np.where(
        small, 0.5 * z * z - z**4 / 12.0, zs + np.log1p(np.exp(-2.0 * zs)) - np.log(2.0)
    )
    th = np.tanh(zs)
    vs = np.where(small, 1.0, v)
    phi = np.where(small, a * (1.0 - z * z / 3.0), th / vs)
    psi = np.where(
        small,
        -2.0 * a**3 / 3.0 + 8.0 * a**5 * v * v / 15.0,
        (a * (1.0 - th * th) * vs - th) / vs**3,
    )
    coef = law.mu * normal
    energy = coef * h * logcosh / a
    grad = (coef * phi / h)[:, None] * w
    proj = np.eye(3) - n_dir[:, :, None] * n_dir[:, None, :]
    hess = (coef / h)[:, None, None] * (
        phi[:, None, None] * proj + (psi / h**2)[:, None, None] * w[:, :, None] * w[:, None, :]
    )
    return energy, grad, hess


@dataclass(frozen=True)
class Wall:
    """A rigid vertical wall standing on the plate across the rolling ribbon's path (seed 000, Fig.
    1: the robot meets an obstacle), with the plate's contact and friction laws, placed relative to
    the as-built ribbon's centre line."""

    distance: float = param(
        10.0,
        "mm",
        "chosen: from the nearest point of the ribbon's centre line to the wall "
        "(the ribbon is ~4 mm wide: a few mm of rolling before contact)",
        positive=True,
    )
    angle: float = param(
        0.0,
        "deg",
        "angle between the wall and the ribbon's axis: 0 head-on (the whole "
        "length meets it at once), > 0 turned about the vertical so one end meets it first",
        minimum=-89.0,
        maximum=89.0,
    )
    direction: float = param(
        1.0,
        "-",
        "side of the ribbon the wall stands on: +1 towards +y (where the default "
        "ribbon rolls at 31 nodes and 100 C, measured with "
        "validation/studies/ribbon/ribbon_obstacle.py), "
        "-1 towards -y",
        minimum=-1.0,
        maximum=1.0,
    )

    def plane(self, centreline: np.ndarray) -> tuple[tuple[float, float, float], float]:
        """(unit normal pointing back to the ribbon, height) of the wall's face for the ribbon's
        as-built centre line ``centreline`` (N, 3) [mm]: the rod stays where normal . p > height,
        and the nearest centre-line node is ``distance`` from the face."""
        a = np.radians(self.angle)
        side = 1.0 if self.direction > 0 else -1.0
        normal = -side * np.array([-np.sin(a), np.cos(a), 0.0])
        return tuple(float(v) for v in normal), float(
            np.min(np.asarray(centreline) @ normal) - self.distance
        )


@dataclass(frozen=True)
class Block:
    """A rigid block of finite size standing on the plate in the rolling ribbon's path (seed 000,
    Fig. 1: the robot meets an obstacle and turns or reverses), with the plate's contact and
    friction laws. Axis-aligned: its width runs along the as-built ribbon's axis (x), its depth
    along the rolling direction (y); placed relative to the as-built ribbon's centre line. Heat
    exchange with the ribbon (``heat``): none (the default, as before: the block's temperature
    unknown), or at a temperature, by the law the plate uses (``models.ribbon.GroundHeatExchange``:
    air film and radiation through the patches facing the block, contact conduction G_c along a
    corner line touching it)."""

    width: float = param(
        0.0, "mm", "chosen: extent along the ribbon's axis; 0: no block", minimum=0.0
    )
    height: float = param(
        10.0,
        "mm",
        "chosen: above the plate; taller than the ribbon's 4 mm width, so the "
        "rolling ribbon (its section spins about the axis, reaching ~2 mm above it) cannot "
        "climb it",
        positive=True,
    )
    depth: float = param(10.0, "mm", "chosen: extent along the rolling direction", positive=True)
    distance: float = param(
        5.0,
        "mm",
        "chosen: from the ribbon's centre line to the block's near face (the "
        "ribbon's half width is 2 mm: ~3 mm of rolling before contact)",
        positive=True,
    )
    offset: float = param(
        0.0,
        "mm",
        "chosen: the block's centre along the ribbon's axis from the ribbon's "
        "middle: 0 hits the middle, +-(length - width)/2 lines its edge up with an end",
    )
    direction: float = param(
        1.0,
        "-",
        "side of the ribbon the block stands on: +1 towards +y, -1 towards -y "
        "(the side the ribbon rolls to: validation/studies/ribbon/ribbon_obstacle.py prints it)",
        minimum=-1.0,
        maximum=1.0,
    )
    friction: float = param(
        0.5,
        "-",
        "assumed: friction coefficient of the ribbon on the block's faces, as on "
        "the plate (FrictionLaw.mu: an elastomer on a hard surface)",
        minimum=0.0,
    )
    edge_radius: float = param(
        0.5,
        "mm",
        "assumed: rounding of the block's edges (a machined or printed "
        "block's edges are rounded to ~0.1-1 mm); the contact's normal turns "
        "smoothly around an edge over this radius",
        positive=True,
    )
    heat: str = param(
        "none",
        "-",
        "the block's heat exchange with the ribbon: 'none' (no exchange; seed 000 gives "
        "neither the obstacle's material nor its temperature), 'plate' (at the plate's "
        "temperature: a "
        "block standing on the hot plate conducts from it; a metal block reaches it, a polymer one "
        "stays between air and plate), 'ambient' (at the air's: a block just put down), or 'given' "
        "(at ``temperature``)",
    )
    temperature: float = param(
        25.0, "C", "the block's temperature with heat = 'given' (otherwise unused)"
    )

    HEAT = ("none", "plate", "ambient", "given")

    def block_temperature(self, plate: float, ambient: float) -> float | None:
        """The block's temperature [C] on a plate at ``plate`` in air at ``ambient`` (None: no
        exchange)."""
        if self.heat not in self.HEAT:
            raise InputError(f"obstacle.heat = {self.heat!r}: allowed {', '.join(self.HEAT)}")
        return {"none": None, "plate": plate, "ambient": ambient, "given": self.temperature}[
            self.heat
        ]

    @property
    def present(self) -> bool:
        return self.width > 0

    def box(
        self, centreline: np.ndarray
    ) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """(lo, hi) corners [mm] of the block for the as-built centre line (N, 3) [mm] along x; the
        bottom lies an edge radius (plus 1 mm) below the plate, so that its lower edges' rounding is
        buried and the plate meets the block's faces at a right angle."""
        c = np.asarray(centreline, float)
        xmid = 0.5 * (c[:, 0].min() + c[:, 0].max())
        side = 1.0 if self.direction > 0 else -1.0
        near = (c[:, 1].max() + self.distance) if side > 0 else (c[:, 1].min() - self.distance)
        far = near + side * self.depth
        x0, x1 = xmid + self.offset - 0.5 * self.width, xmid + self.offset + 0.5 * self.width
        bottom = -(self.edge_radius + 1.0)
        return ((x0, min(near, far), bottom), (x1, max(near, far), self.height))
