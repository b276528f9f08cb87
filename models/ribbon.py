"""Twisted LCE ribbon (seed 000): geometry, programmed natural shape, thermal actuation, heat exchange.

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
  eigenstrain eps*(y1, y2): kappa_bar_1 = -(1/I_1) int eps* y1 dA, kappa_bar_2 = -(1/I_2) int eps* y2 dA
  (y1 along the width m1, y2 along the thickness m2; the hotter side contracts, so the ribbon bends
  towards it);
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

import math
from dataclasses import dataclass

import numpy as np

from lcefem.models.heat import radiative_film_coefficient
from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.models.parameters import param
from lcefem.models.rod import CORNER_SIGNS

ASSUMED_SIZE = ("assumed: seed 000 gives no dimensions; of the order of the LCE ribbons of Zhao et al. "
                "(PNAS 2022)")


@dataclass(frozen=True)
class RibbonGeometry:
    """As-built (nematic, room temperature) twisted ribbon."""

    length: float = param(60.0, "mm", ASSUMED_SIZE, positive=True)
    width: float = param(4.0, "mm", ASSUMED_SIZE, positive=True)
    thickness: float = param(0.8, "mm", ASSUMED_SIZE, positive=True)
    twist_density: float = param(0.05, "turns/mm", "assumed: 3 turns over 60 mm; seed 000 Fig. 5 "
                                 "varies the twist density (number of turns per unit length)",
                                 minimum=0.0)
    helix_radius: float = param(0.0, "mm", "0 for a twisted ribbon (straight centreline); > 0 makes "
                                "an untwisted helical ribbon of that centreline radius (seed 000, "
                                "Fig. 8)", minimum=0.0)
    helix_pitch: float = param(20.0, "mm", "helical ribbon only: rise per turn of the centreline "
                               "(assumed)", positive=True)

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
        d = self.helix_radius ** 2 + c ** 2
        return self.helix_radius / d, c / d


# ----------------------------------------------------------------------------------------------
# Thermal natural strains
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SectionGrid:
    """The w x t section split into n_width x n_thickness equal cells (thickness index fastest:
    cell c = i_w n_thickness + i_t; i_w = 0 at y1 = -w/2, i_t = 0 at y2 = -t/2)."""

    width: float
    thickness: float
    n_width: int = 6
    n_thickness: int = 2

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
        """Cell temperatures (..., n_cells) [C] of a linear through-thickness profile: T_plus on the face
        at +t/2 (towards m2), T_minus on the face at -t/2."""
        T_plus = np.asarray(T_plus, float)[..., None]
        T_minus = np.asarray(T_minus, float)[..., None]
        frac = self.y2 / self.thickness + 0.5
        return T_minus + (T_plus - T_minus) * frac


@dataclass
class NaturalStrains:
    """Per section: axial eigenstrain [-], curvatures towards m1 and m2 [1/mm], mean contraction a [-]."""

    axial: np.ndarray
    curvature: np.ndarray  # (n, 2)
    contraction: np.ndarray


def natural_strains(cell_temperatures: np.ndarray, grid: SectionGrid,
                    transition: NematicTransition) -> NaturalStrains:
    """Beam eigenstrain resultants of eps*(y) = a(T(y)) - 1 over the cells of the section.

    eps_bar = mean of eps*, kappa_bar_i = -sum(eps* y_i) / sum(y_i^2) (the cells' own second moments,
    so a linear eigenstrain eps* = e0 - k y_i gives exactly kappa_bar_i = k).
    """
    a = contraction_ratio(np.asarray(cell_temperatures, float), transition)
    eps = a - 1.0
    y1, y2 = grid.y1, grid.y2
    k1 = -(eps @ y1) / float(y1 @ y1)
    k2 = -(eps @ y2) / float(y2 @ y2)
    return NaturalStrains(eps.mean(axis=-1), np.stack([k1, k2], axis=-1), a.mean(axis=-1))


def natural_twist_rate(tau0: float, contraction) -> np.ndarray:
    """tau_bar = tau_0 [1 + 2 (a - a^(-1/2))] [rad/mm] of a ribbon twisted after stretching (see the
    module docstring; small helix angle)."""
    a = np.asarray(contraction, float)
    return tau0 * (1.0 + 2.0 * (a - a ** -0.5))


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
    zero gap, ~0 beyond delta). Every patch also exchanges heat with the air by its film coefficient,
    the air being warmed by the plate in a boundary layer: T_air(z) = T_a + (T_g - T_a) exp(-z/d_bl).
    """

    air_conductivity: float = param(0.027, "mW/(mm K)", "dry air at ~40 C: 0.027 W/(m K) (Incropera, "
                                    "Fundamentals of Heat and Mass Transfer, Table A.4)", positive=True)
    gap_floor: float = param(0.1, "mm", "assumed: z0, floor of the air-film thickness", positive=True)
    contact_conductance: float = param(1.0, "mW/(mm K)", "assumed: G_c per mm of edge line in "
                                       "contact, a few times the LCE conductivity (0.25 mW/(mm K)) as for "
                                       "the spreading conductance of a soft line contact; not measured",
                                       minimum=0.0)
    plate_emissivity: float = param(0.9, "-", "assumed (oxidised or painted hot plate, polymer)",
                                    minimum=0.0, maximum=1.0)
    boundary_layer: float = param(1.0, "mm", "assumed: decay length d_bl of the air temperature over the "
                                  "plate; with 3 mm the whole ribbon warms and untwists instead of being "
                                  "heated from the contact side (ribbon_threshold case); not measured",
                                  positive=True)

    def air_temperature(self, height, T_ambient: float, T_ground: float):
        """T_air(z) = T_a + (T_g - T_a) exp(-z/d_bl) [C] at ``height`` [mm] above the plate."""
        return T_ambient + (T_ground - T_ambient) * np.exp(-np.maximum(height, 0.0) / self.boundary_layer)

    def patch_coefficient(self, height, facing, T, T_ground):
        """h_g [mW/(mm^2 K)] of patches at ``height`` [mm] with downward facing fraction ``facing``."""
        h_air = self.air_conductivity / (np.maximum(height, 0.0) + self.gap_floor)
        h_rad = radiative_film_coefficient(T, T_ground, self.plate_emissivity)
        return facing * (h_air + h_rad)
