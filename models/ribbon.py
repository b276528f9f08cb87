"""Twisted LCE ribbon (seed 000): geometry, programmed natural shape, thermal actuation, heat loss.

Manufacture (seed 000, 'Manufacturing the twisting ribbon robot'; Zhao et al., PNAS 2022): a flat
strip is stretched (mesogens align with the stretch, along the strip) and then twisted to the twist
density tau_0, and the second-stage crosslinking fixes that shape. The as-built (nematic, room
temperature) ribbon is the reference: a straight helicoid, natural stretch 1, natural twist tau_0,
no natural curvature, with the director along the material lines that the twist turned into
helices (helix angle alpha, tan alpha = tau_0 y at the distance y from the centreline).

Heating lowers the order; the director fibres contract by a(T) = lambda_s(T)/lambda_N
(``lcefem.models.lce.contraction_ratio``) and the transverse ones expand by a^(-1/2). As a rod:

* natural axial strain: eps* = a - 1 (director ~ axis for a small helix angle);
* natural curvatures from the eigenstrain's gradient over the section, as in beam theory with an
  eigenstrain eps*(y1, y2): kappa_bar_1 = -(1/I_1) int eps* y1 dA, kappa_bar_2 = -(1/I_2) int eps*
  y2 dA (y1 along the width m1, y2 along the thickness m2; the hotter side contracts, so the ribbon
  bends towards it);
* natural twist: contraction along helices at angle alpha and expansion across them is a shear
  gamma = 2 (a - a^(-1/2)) sin(alpha) cos(alpha) ~ 2 (a - a^(-1/2)) tau_0 y, i.e. a change of twist
  tau_bar = tau_0 [1 + 2 (a - a^(-1/2))] (small helix angle). At a = 1/lambda_N = 0.70 (isotropic)
  this gives 0.014 tau_0: the hot ribbon untwists, as twisted LCE fibres and ribbons do.

A helical ribbon (centreline a helix, director along the centreline, seed 000 Fig. 8) keeps its
programmed curvature and twist per as-built length when it contracts uniformly (all director lines
contract alike): only the thermal gradients act.

The section's temperature is held in n_width x n_thickness cells (:class:`SectionGrid`, default
6 x 2): the heat from a corner touching the plate stays near that edge, which is where it bends
and untwists the ribbon most.

Every length in mm, temperature in C, twist in rad/mm (the command line takes turns/mm).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from lcefem.models.heat import radiative_film_coefficient
from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.models.parameters import param
from lcefem.models.rod import CORNER_SIGNS, torsion_constant_rectangle

ASSUMED_SIZE = (
    "assumed: seed 000 gives no dimensions; of the order of the LCE ribbons of Zhao et al. "
    "(PNAS 2022)"
)


@dataclass(frozen=True)
class RibbonGeometry:
    """As-built (nematic, room temperature) twisted ribbon."""

    length: float = param(60.0, "mm", ASSUMED_SIZE, positive=True)
    width: float = param(4.0, "mm", ASSUMED_SIZE, positive=True)
    thickness: float = param(0.8, "mm", ASSUMED_SIZE, positive=True)
    twist_density: float = param(
        0.05,
        "turns/mm",
        "assumed: 3 turns over 60 mm; seed 000 Fig. 5 "
        "varies the twist density (number of turns per unit length)",
        minimum=0.0,
    )
    twist_lock: float = param(
        0.0,
        "-",
        "fraction of the heated helicoid's twist release that the programmed network "
        "suppresses: 0 keeps the free-ribbon helicoid coupling (HelicoidCoupling, the director "
        "field alone); 1 keeps the programmed number of turns (natural twist per as-built "
        "length tau_0 at every temperature: the twist locked by the second-stage crosslinking "
        "in the twisted state, seed 000's 'twist density remains constant'). The seed-000 "
        "ribbon material (SEED000_RIBBON) sets 1; the static 3D FE comparison keeps 0",
        minimum=0.0,
        maximum=1.0,
    )
    helix_radius: float = param(
        0.0,
        "mm",
        "0 for a twisted ribbon (straight centreline); > 0 makes "
        "an untwisted helical ribbon of that centreline radius (seed 000, "
        "Fig. 8)",
        minimum=0.0,
    )
    helix_pitch: float = param(
        20.0, "mm", "helical ribbon only: rise per turn of the centreline (assumed)", positive=True
    )

    @property
    def twist_rate(self) -> float:
        """tau_0 = 2 pi x twist density [rad/mm]."""
        return 2.0 * math.pi * self.twist_density

    @property
    def is_helical(self) -> bool:
        return self.helix_radius > 0.0

    def helix_curvature_torsion(self) -> tuple[float, float]:
        """Curvature and torsion [1/mm] of the helical centreline (radius R, pitch p):
        kappa = R/(R^2 + c^2), tau = c/(R^2 + c^2), c = p/(2 pi)."""
        c = self.helix_pitch / (2.0 * math.pi)
        d = self.helix_radius**2 + c**2
        return self.helix_radius / d, c / d


# ----------------------------------------------------------------------------------------------
# The seed-000 ribbon's LCE (issue 32)
# ----------------------------------------------------------------------------------------------
ZHAO_2022 = (
    "Zhao, Chi, Hong, Li, Yang, Yin, 'Twisting for soft intelligent autonomous robot in "
    "unstructured "
    "environments', PNAS 119 (2022) e2200265119 (abstract, PMC9295757)"
)
PRESS_RELEASE = (
    "NC State press release on Zhao et al. 2022 ('Twisted soft robots navigate mazes', 2022): 'a "
    "surface that is at least 55 degrees Celsius ... the portion of the ribbon touching the "
    "surface "
    "contracts, while the portion exposed to the air does not ... the warmer the surface, the "
    "faster "
    "it rolls'"
)
SAED_2016 = (
    "Saed, Torbati, Nair, Yakacki, 'Synthesis of programmable main-chain liquid-crystalline "
    "elastomers "
    "using a two-stage thiol-acrylate reaction', J. Vis. Exp. 107 (2016) e53546: "
    "RM257/EDDET/PETMP, "
    "programmed by stretching before the second-stage photo-crosslinking; stress-free actuation "
    "35 % "
    "at 100 % programming strain, up to 115 % at 400 %"
)


@dataclass(frozen=True)
class RibbonLCE:
    """The LCE of the twisted ribbons of seed 000 (Zhao et al., PNAS 2022), one parameter set for
    every plate temperature.

    Seed 000: the ribbons are "fabricated by mechanically stretching and twisting of a rectangular
    flat LCE strip ... synthesized in two-stage polymerization", i.e. a two-stage thiol-acrylate
    main-chain LCE (RM257/EDDET/PETMP type, Saed et al. 2016) whose second-stage crosslinking fixes
    the stretched and twisted shape. What the stored public text gives: the chemistry family and its
    actuation strain (Saed et al. 2016), the >= 55 C threshold and "warmer, faster" (press release).
    Not found (the PNAS supplementary information is not in the stored corpora; searched again in
    issue 32's second pass, docs/ribbon.md): the ribbon's modulus, its
    actuation strain against temperature, T_NI, dimensions and mass; those are assumed within the
    bounds given, and none is calibrated on a rolling case. Sources: ``ZHAO_2022``,
    ``PRESS_RELEASE``, ``SAED_2016`` (module constants, quoted in docs/ribbon.md).

    The density is ``ThermalProperties.density`` (1.15 g/cm^3 assumed, RM257-thiol networks
    1.1-1.2). The attributes map onto the solver's laws by :meth:`transition` (Warner-Terentjev
    sigmoid of ``models.lce``) and :meth:`elasticity` (the seed-001 invariant law scaled to the
    ribbon's small-strain shear modulus E/3, E = 3 mu incompressible).
    """

    youngs_modulus: float = param(
        2.6,
        "MPa",
        "assumed: small-strain modulus of the stretched, aligned ribbon "
        "along its fibres, bound 1-10 MPa (monodomain main-chain thiol-acrylate LCEs "
        "at room temperature; not found for seed 000's ribbons); 5 x the isotropic "
        "seed-001 fit (0.53 MPa), with which the ribbon sagged flat and rolled only from "
        "90-100 C (issue 32)",
        positive=True,
    )
    actuation_stretch: float = param(
        1.35,
        "-",
        "lambda_N, as-built over fully heated length along the fibres: "
        "35 % stress-free actuation at 100 % programming strain (" + SAED_2016 + "); "
        "the ribbons' own programming strain is not given",
        minimum=1.0,
    )
    T_NI: float = param(
        80.0,
        "C",
        "assumed: midpoint of the order parameter's sigmoid, bound 60-100 C for "
        "thiol-acrylate RM257 LCEs; not given for seed 000's ribbons. With the 15 K width the "
        "fibres "
        "contract 1.2 / 3.9 / 13 / 21 / 26 % at 40 / 55 / 80 / 100 / 180 C: gradually over the "
        "plates' range. Not calibrated on a rolling case: T_NI 50-80 C all leave the 55 C plate "
        "without rolling (issue 32, docs/ribbon.md)",
    )
    transition_width: float = param(
        15.0,
        "K",
        "assumed: width of the sigmoid; two-stage thiol-acrylate LCEs "
        "contract gradually over 40-140 C (broad transition of a polydisperse "
        "network), against 6.2 K calibrated for seed 001's strips",
        positive=True,
    )

    curve: str = param(
        "",
        "-",
        "CSV of a measured free stretch or strain against temperature replacing the "
        "sigmoid (T_NI, transition_width, actuation_stretch) (read by "
        "lcefem.solvers.contraction_curve; the curve's own amplitude is lambda_N); empty: the "
        "sigmoid",
    )

    def transition(self) -> NematicTransition:
        """The ribbon's nematic-isotropic transition (models.lce law, T_ref 25 C as built)."""
        return NematicTransition(
            T_NI=self.T_NI, width=self.transition_width, lambda_N=self.actuation_stretch
        )

    def elasticity(self):
        """The seed-001 invariant law (``LCEElasticity``) scaled to mu = E/3 (bulk modulus with
        it)."""
        from lcefem.models.hyperelastic import LCEElasticity

        base = LCEElasticity()
        k = self.youngs_modulus / 3.0 / base.shear_modulus
        return LCEElasticity(
            c10=base.c10 * k, c01=base.c01 * k, c30=base.c30 * k, bulk_modulus=base.bulk_modulus * k
        )


#: The seed-000 ribbon's LCE with its defaults (issue 32).
SEED000_RIBBON = RibbonLCE()


# ----------------------------------------------------------------------------------------------
# Thermal natural strains
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SectionGrid:
    """The w x t section split into n_width x n_thickness equal cells (thickness index fastest:
    cell c = i_w n_thickness + i_t; i_w = 0 at y1 = -w/2, i_t = 0 at y2 = -t/2).

    The cells carry the temperature (one value per cell, the heat model's unknowns). The eigenstrain
    resultants (:func:`natural_strains`) integrate a(T(y)) over the section with ``quadrature``
    Gauss-Legendre points per cell and direction, T(y) interpolated linearly between the cell
    centres (and extrapolated linearly to the faces): a linear temperature profile is then
    represented exactly by two cells through the thickness, and the non-linear a(T) is integrated to
    the quadrature's accuracy instead of being sampled once per cell (issue 17: the 6 x 2 grid with
    one sample per cell under-estimated one-face bending by 27 %).
    """

    width: float
    thickness: float
    n_width: int = 6
    n_thickness: int = 2
    quadrature: int = 4

    @property
    def n_cells(self) -> int:
        return self.n_width * self.n_thickness

    @property
    def y1(self) -> np.ndarray:
        """Cell centroids along m1 [mm], (n_cells,)."""
        iw = np.repeat(np.arange(self.n_width), self.n_thickness)
        return (iw + 0.5) * self.width / self.n_width - 0.5 * self.width

    @property
    def y2(self) -> np.ndarray:
        """Cell centroids along m2 [mm], (n_cells,)."""
        it = np.tile(np.arange(self.n_thickness), self.n_width)
        return (it + 0.5) * self.thickness / self.n_thickness - 0.5 * self.thickness

    def corner_cells(self) -> np.ndarray:
        """Cell of each section corner, in ``CORNER_SIGNS`` order."""
        iw = np.where(CORNER_SIGNS[:, 0] > 0, self.n_width - 1, 0)
        it = np.where(CORNER_SIGNS[:, 1] > 0, self.n_thickness - 1, 0)
        return iw * self.n_thickness + it

    def from_faces(self, T_plus, T_minus) -> np.ndarray:
        """Cell temperatures (..., n_cells) [C] of a linear through-thickness profile: T_plus on the
        face at +t/2 (towards m2), T_minus on the face at -t/2."""
        T_plus = np.asarray(T_plus, float)[..., None]
        T_minus = np.asarray(T_minus, float)[..., None]
        frac = self.y2 / self.thickness + 0.5
        return T_minus + (T_plus - T_minus) * frac

    def quadrature_rule(self):
        """Points and weights of the section quadrature: interpolation matrices P_w (n_width q,
        n_width) and P_t (n_thickness q, n_thickness) from cell values to point values, point
        coordinates y1 (n_width q,), y2 (n_thickness q,) [mm] and weights W (n_width q, n_thickness
        q) [mm^2]."""
        return _section_rule(
            self.width, self.thickness, self.n_width, self.n_thickness, self.quadrature
        )


def _interpolation_1d(size: float, n: int, q: int):
    """Gauss points of n equal cells on [-size/2, size/2], q per cell, their weights [mm] and the
    matrix of linear interpolation (extrapolation beyond the outer centres) from the n cell-centre
    values."""
    g, wg = np.polynomial.legendre.leggauss(q)
    h = size / n
    centres = (np.arange(n) + 0.5) * h - 0.5 * size
    pts = (centres[:, None] + 0.5 * h * g[None, :]).ravel()
    weights = np.tile(0.5 * h * wg, n)
    P = np.zeros((n * q, n))
    if n == 1:
        P[:, 0] = 1.0
        return pts, weights, P
    left = np.clip(np.floor((pts - centres[0]) / h).astype(int), 0, n - 2)
    frac = (pts - centres[left]) / h
    rows = np.arange(n * q)
    P[rows, left] = 1.0 - frac
    P[rows, left + 1] = frac
    return pts, weights, P


_RULES: dict = {}


def _section_rule(width, thickness, n_width, n_thickness, q):
    key = (width, thickness, n_width, n_thickness, q)
    if key not in _RULES:
        y1, w1, Pw = _interpolation_1d(width, n_width, q)
        y2, w2, Pt = _interpolation_1d(thickness, n_thickness, q)
        _RULES[key] = (Pw, Pt, y1, y2, np.outer(w1, w2))
    return _RULES[key]


@dataclass
class NaturalStrains:
    """Per section: axial eigenstrain [-], curvatures towards m1 and m2 [1/mm], mean contraction a
    [-]."""

    axial: np.ndarray
    curvature: np.ndarray  # (n, 2)
    contraction: np.ndarray


def natural_strains(
    cell_temperatures: np.ndarray,
    grid: SectionGrid,
    transition: NematicTransition,
    contraction=None,
) -> NaturalStrains:
    """Beam eigenstrain resultants of eps*(y) = a(T(y)) - 1 over the section.

    eps_bar = <eps*>, kappa_bar_i = -int eps* y_i dA / int y_i^2 dA, by the section quadrature of
    :meth:`SectionGrid.quadrature_rule` (T interpolated between the cell centres; a linear
    eigenstrain eps* = e0 - k y_i gives exactly kappa_bar_i = k). ``contraction``: a(T) on an array
    of temperatures [C] (default ``contraction_ratio`` of ``transition``; the rolling ribbon passes
    a tabulated one, ``solvers.der.tabulated``).
    """
    T = np.asarray(cell_temperatures, float)
    interpolate, moments = _resultant_matrices(
        grid.width, grid.thickness, grid.n_width, grid.n_thickness, grid.quadrature
    )
    # Two matrix products (cells -> points, points -> resultants) instead of einsums: the rolling
    # ribbon evaluates this once per time step on ~100 sections.
    points = T @ interpolate
    eps = (
        contraction_ratio(points, transition) if contraction is None else contraction(points)
    ) - 1.0
    r = eps @ moments  # (..., 3): <eps*>, kappa_bar_1, kappa_bar_2
    return NaturalStrains(r[..., 0], np.ascontiguousarray(r[..., 1:]), 1.0 + r[..., 0])


@functools.lru_cache(maxsize=16)
def _resultant_matrices(width, thickness, n_width, n_thickness, q):
    """Matrices of :func:`natural_strains`: cell values -> quadrature-point values (n_cells, points)
    and point eigenstrains -> (mean, kappa_bar_1, kappa_bar_2) (points, 3), the Gauss weights W
    [mm^2] divided by int dA, -int y1^2 dA and -int y2^2 dA."""
    Pw, Pt, y1, y2, W = _section_rule(width, thickness, n_width, n_thickness, q)
    interpolate = np.kron(Pw, Pt).T  # point (i, j) = sum Pw[i, iw] Pt[j, it] T[iw, it]
    moments = np.stack(
        [
            W / W.sum(),
            -W * y1[:, None] / float(W.sum(axis=1) @ y1**2),
            -W * y2[None, :] / float(W.sum(axis=0) @ y2**2),
        ],
        axis=-1,
    ).reshape(-1, 3)
    for m in (interpolate, moments):
        m.flags.writeable = False
    return interpolate, moments


def natural_twist_rate(tau0: float, contraction, release: float = 2.0) -> np.ndarray:
    """tau_bar = tau_0 [1 + r (a - a^(-1/2))] [rad/mm] per as-built length of a ribbon twisted after
    stretching (small helix angle). r = 2 is the eigen-shear of the inclined fibres alone (module
    docstring); :class:`HelicoidCoupling` gives r between 1 and 2 for a ribbon whose twist is
    coupled to its stretch."""
    a = np.asarray(contraction, float)
    return tau0 * (1.0 + release * (a - a**-0.5))


@dataclass(frozen=True)
class HelicoidCoupling:
    """Twist-stretch coupling of a thin twisted ribbon under a uniform contraction a (issue 17).

    Two mechanisms set the twist. The eigen-shear of the fibres (helix angle tan alpha = tau_0 y) is
    a rigid-twist pattern, released by Delta tau = 2 c tau_0, c = a - a^(-1/2)
    (:func:`natural_twist_rate` with r = 2). The fibres' length mismatch across the width, quadratic
    in y, is released by the helicoid's twist-stretch coupling (a fibre at y lengthens by tau_0
    Delta tau y^2) at Delta tau = c tau_0, the in-plane metric of the heated helicoid. With the
    energies 1/2 GJ (Delta - 2 c tau_0)^2 and 1/2 K_w (Delta - c tau_0)^2, K_w = E A tau_0^2
    Var(y^2) = E w t tau_0^2 w^4/180, the free ribbon takes

        Delta = r c tau_0,  r = (K_w + 2 GJ)/(K_w + GJ),
        stretch = a [1 - s c],  s = tau_0^2 <y^2> GJ/(K_w + GJ),  <y^2> = w^2/12,

    between the eigen-shear value (K_w << GJ: thick or little twisted) and the metric one (K_w >>
    GJ). Checked against the static 3D FE of the twisted ribbon (``ribbon_fe_vs_der`` case (b): the
    FE untwists 38 % less than r = 2 says; r = 1.31 for the default 4 x 0.8 mm, 0.05 turns/mm
    ribbon). DER has no twist-stretch coupling in its energies, so the coupling enters as the
    natural twist and stretch of the free ribbon; under external twisting moments the rod stays
    uncoupled.

    Attributes:
        release: r [-]; stretch_coefficient: s [-].
    """

    release: float = 2.0
    stretch_coefficient: float = 0.0

    @classmethod
    def of(
        cls, geometry: RibbonGeometry, youngs_modulus: float, shear_modulus: float
    ) -> "HelicoidCoupling":
        """Coupling of the twisted ribbon ``geometry`` with E, G [MPa] (E = 3 G for the LCE)."""
        w, t, tau0 = geometry.width, geometry.thickness, geometry.twist_rate
        k_w = youngs_modulus * w * t * tau0**2 * w**4 / 180.0
        gj = shear_modulus * torsion_constant_rectangle(w, t)
        return cls((k_w + 2.0 * gj) / (k_w + gj), tau0**2 * (w**2 / 12.0) * gj / (k_w + gj))

    def locked(self, fraction: float) -> "HelicoidCoupling":
        """The coupling with ``fraction`` of its twist release and stretch correction suppressed
        (``RibbonGeometry.twist_lock``): 0 returns it unchanged, 1 keeps tau_bar = tau_0 per
        as-built length and stretch = a at every contraction."""
        keep = 1.0 - fraction
        return HelicoidCoupling(self.release * keep, self.stretch_coefficient * keep)

    def twist_factor(self, contraction) -> np.ndarray:
        """tau_bar/tau_0 = 1 + r c [-] at the mean fibre contraction a."""
        return natural_twist_rate(1.0, contraction, self.release)

    def stretch_factor(self, contraction) -> np.ndarray:
        """stretch/a = 1 - s c [-]: the twisted ribbon contracts less than its fibres."""
        a = np.asarray(contraction, float)
        return 1.0 - self.stretch_coefficient * (a - a**-0.5)


# ----------------------------------------------------------------------------------------------
# Heat exchange with the hot ground and the air
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class GroundHeatExchange:
    """Heat from the hot plate into the ribbon's surface patches, and contact conduction.

    A surface patch at height z [mm] above the plate, whose outward normal n has a downward
    component f = max(0, -n_z), receives h_g = f [k_air/(z + z0) + h_rad(T, T_ground)]: conduction
    through the air film between patch and plate (film thickness z, floored by z0, which stands for
    the contact resistance) and grey-body radiation from the plate, both in proportion to how much
    the patch faces the plate. A corner touching the plate adds contact conduction G_c w(gap) per
    unit length of the edge line, w = 1/(1 + exp(K1 gap)) the contact weight (1 in contact, 1/2 at
    zero gap, ~0 beyond delta). Every patch also exchanges heat with the air by its film
    coefficient, the air being warmed by the plate in a boundary layer: T_air(z) = T_a + (T_g - T_a)
    exp(-z/d_bl).
    """

    air_conductivity: float = param(
        0.027,
        "mW/(mm K)",
        "dry air at ~40 C: 0.027 W/(m K) (Incropera, "
        "Fundamentals of Heat and Mass Transfer, Table A.4)",
        positive=True,
    )
    gap_floor: float = param(
        0.1, "mm", "assumed: z0, floor of the air-film thickness", positive=True
    )
    contact_conductance: float = param(
        1.0,
        "mW/(mm K)",
        "assumed: G_c per mm of edge line in "
        "contact, a few times the LCE conductivity (0.25 mW/(mm K)) as for "
        "the spreading conductance of a soft line contact; not measured",
        minimum=0.0,
    )
    plate_emissivity: float = param(
        0.9, "-", "assumed (oxidised or painted hot plate, polymer)", minimum=0.0, maximum=1.0
    )
    boundary_layer: float = param(
        1.0,
        "mm",
        "assumed: decay length d_bl of the air temperature over the "
        "plate; with 3 mm the whole ribbon warms and untwists instead of being "
        "heated from the contact side (ribbon_threshold case); not measured. It sets "
        "how fast the rolling falls above 120 C (issue 32, 61 nodes, speed over 60-120 s, "
        "validation/data/ribbon_heat_study.csv): 0.5 / 1 / 2 mm roll at 5.31 / 4.10 / 0.21 "
        "mm/s at 180 C and 6.95 / 6.62 / 6.28 mm/s at 100 C, and none rolls at 55 C",
        positive=True,
    )

    def air_temperature(self, height, T_ambient: float, T_ground: float):
        """T_air(z) = T_a + (T_g - T_a) exp(-z/d_bl) [C] at ``height`` [mm] above the plate."""
        return T_ambient + (T_ground - T_ambient) * np.exp(
            -np.maximum(height, 0.0) / self.boundary_layer
        )

    def patch_coefficient(self, height, facing, T, T_ground):
        """h_g [mW/(mm^2 K)] of patches at ``height`` [mm] with downward facing fraction
        ``facing``."""
        h_air = self.air_conductivity / (np.maximum(height, 0.0) + self.gap_floor)
        h_rad = radiative_film_coefficient(T, T_ground, self.plate_emissivity)
        return facing * (h_air + h_rad)
