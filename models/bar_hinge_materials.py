"""Materials of the bar-and-hinge (MERLIN-type) reduced-order model of the Kapton ribbon and the
composite beam: the parameter sections (:class:`BarHingeMaterials` and its parts, each field with
unit and source) and the material laws, each an energy density with analytic first and second
derivatives, vectorised over elements. The elements that use them (kinematics, bars, hinges,
strip bending, panel torsion, contact) are :mod:`lcefem.models.bar_hinge`.

* **Kapton and glue bars**: the stiffening Ogden-type bar law of MERLIN2 (K. Liu, G. H. Paulino,
  "Nonlinear mechanics of non-rigid origami: an efficient computational approach", Proc. R. Soc. A
  473:20170348, 2017, Sec. 3a), exponents (a1, a2) = (5, 1). With the bar stretch l = L/L0 and the
  Green strain E = (l^2 - 1)/2, the 2nd Piola stress and the energy per reference volume are

      S(l) = C0 (l^(a1-2) - l^(a2-2)) / (a1 - a2),
      W(l) = C0 [(l^a1 - 1)/(a1 (a1-a2)) + (l^a2 - 1)/(a2 (a2-a1))],

  so that dW/dE = (dW/dl)/l = S (since dE/dl = l) and the small-strain tangent is
  dS/dE|_(l=1) = C0 (a1 - 2 - a2 + 2)/(a1 - a2) = C0: C0 is Young's modulus E.
  The bar energy is A L0 W(l).
* **LCE strips**: tension-only bars with the published 3-term Ogden law
  (:func:`lcefem.models.hyperelastic.ogden_uniaxial_energy`), the stretch p = L/L_r being measured
  from a rest length L_r = f L0 that the actuation ramps from the as-built (nematic) length L0
  (f = 1) to f = lambda/lambda_N (lambda relative to the isotropic length, as the paper's lambda).
  The strip volume is conserved: a bar carries the energy V W(p) with V = A_iso L0/lambda_N, A_iso
  its share of the isotropic (cast) section, so the axial force is V W'(p)/L_r = (A_iso/lambda) P(p)
  with P the Ogden nominal stress of the isotropic-phase tension test (seed 001, Fig. 2E). The
  published model's law is A f P(p) instead (``force_law = "published"``): an energy volume
  V = A f^2 L0 that follows the rest fraction f. W = 0 for
  p < 1 (a slack strip carries nothing). The tangents are exact (the published code's cable
  tangent misses a factor 1/f^2; see shared/reference/published_reduced_model.md).
* **Rotational springs**: the enhanced-linear law of Liu & Paulino 2017 (Sec. 3b): moment per unit
  hinge length M = k (theta - theta0) for theta1 <= theta <= theta2 (30 and 330 degrees), and
  tan-type stiffening towards 0 and 2 pi so that panels cannot pass through one another:

      M = k (theta1 - theta0) + k tan(pi (theta - theta1)/(2 theta1)) / (pi/(2 theta1)),
          theta < theta1,
      M = k (theta2 - theta0)
          + k tan(pi (theta - theta2)/(2 (2 pi - theta2))) / (pi/(2 (2 pi - theta2))),
          theta > theta2;

  the hinge energy is L_h psi(theta) with psi' = M.

Units: mm, N, MPa, mJ; angles in radians inside the functions (parameters state degrees where the
published model does).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import KAPTON_DATASHEET_MODULUS, KAPTON_POISSON_RATIO, OgdenLaw
from lcefem.models.parameters import param

#: Nematic relative length lambda_N [-] of the published reduced-order model: its isotropic/nematic
#: length ratio 0.7143 = 1/1.4 (shared/reference/published_reduced_model.md). The bar-and-hinge
#: models, the FE composite beam and Eq. 2 use it; the strip model uses Eq. 1's limit
#: (models.empirical.EQ1_LAMBDA_N).
PUBLISHED_LAMBDA_N: float = 1.4

PUBLISHED = (
    "published reduced-order model (Daraio-lab/RoboticSurface_SciRob_LiuK; "
    "shared/reference/published_reduced_model.md)"
)


#: Axial force laws of the LCE strip bars (:class:`LCEStripBars`.force_law).
FORCE_LAWS = ("volume", "published")
#: Torsion models of the Kapton panels (:class:`KaptonBarHinge`.twist).
TWIST_MODELS = ("n5b8", "plate", "plate_rectangles")


# --------------------------------------------------------------------------- parameters
@dataclass(frozen=True)
class KaptonBarHinge:
    """Kapton ribbon in the bar-and-hinge model: bar law, panel calibration and hinge stiffness.

    Hinge stiffness per unit hinge length (published model; both bending and fold hinges):
    k = bending_factor E t^3 / (12 hinge_spacing).
    """

    youngs_modulus: float = param(
        KAPTON_DATASHEET_MODULUS,
        "MPa",
        "DuPont Kapton HN datasheet, 23 C "
        "(2.5 GPa, models.hyperelastic.KAPTON_DATASHEET_MODULUS); " + PUBLISHED,
        positive=True,
    )
    poisson_ratio: float = param(
        KAPTON_POISSON_RATIO,
        "-",
        "DuPont Kapton HN datasheet; " + PUBLISHED,
        minimum=0.0,
        maximum=0.49,
    )
    bar_exponent_1: float = param(
        5.0,
        "-",
        "MERLIN2 stiffening bar law, exponents [5, 1] (Liu & Paulino 2017; " + PUBLISHED + ")",
    )
    bar_exponent_2: float = param(1.0, "-", "MERLIN2 stiffening bar law, exponents [5, 1]")
    bending_factor: float = param(
        5.5,
        "-",
        PUBLISHED + ": k = 5.5 E tp^3/(12 (Lx + d)/Nx); an "
        "empirical multiplier of the plate stiffness (apparently fitted "
        "to the 0.18 N buckling test, seed 001 Fig. 2G)",
        positive=True,
    )
    hinge_spacing: float = param(
        37.0 / 11.0, "mm", PUBLISHED + ": (Lx + d)/Nx = (30 + 7)/11 mm", positive=True
    )
    linear_from: float = param(
        30.0, "deg", "enhanced-linear law, theta1 (" + PUBLISHED + ")", minimum=1.0, maximum=179.0
    )
    linear_to: float = param(
        330.0,
        "deg",
        "enhanced-linear law, theta2 (" + PUBLISHED + ")",
        minimum=181.0,
        maximum=359.0,
    )
    twist: str = param(
        "n5b8",
        "-",
        "torsion of the panels: 'n5b8' (" + PUBLISHED + ": every spoke "
        "hinge with k; a one-panel-wide ribbon then has GJ = k D^3/(2 W), 13.6 x the "
        "plate's G w t^3/3 for the gridshell's 2.3 x 7 mm panels) or 'plate' (added "
        "here: the spokes' twist mode scaled so that GJ = G w t^3/3 with G = E/(2 (1 + "
        "nu)), the bending modes unchanged; :func:`panel_twist_fraction`, "
        "docs/gridshell_calibration.md; it needs rectangular panels) or 'plate_rectangles' "
        "(added here: the plate's on the rectangular panels, the N5B8 spokes' on the others, "
        "e.g. a rhombic gridshell's junction rhombi and the trapezoids beside them, "
        "docs/layouts/rhombic.md)",
    )

    def checked(self) -> "KaptonBarHinge":
        if self.twist not in TWIST_MODELS:
            raise InputError(f"kapton.twist = {self.twist!r}: allowed {', '.join(TWIST_MODELS)}")
        return self

    @property
    def shear_modulus(self) -> float:
        """G = E/(2 (1 + nu)) [MPa] of the isotropic film (datasheet E and nu)."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    def hinge_stiffness(self, thickness: float) -> float:
        """k [N mm/(rad mm)] = bending_factor E t^3/(12 hinge_spacing) for a ribbon thickness t
        [mm]."""
        return (
            self.bending_factor * self.youngs_modulus * thickness**3 / (12.0 * self.hinge_spacing)
        )


@dataclass(frozen=True)
class LCEStripBars:
    """LCE strips as tension-only Ogden bars with a ramped rest length (published model)."""

    lambda_N: float = param(
        PUBLISHED_LAMBDA_N,
        "-",
        PUBLISHED + ": isotropic/nematic length ratio 1/0.7143",
        minimum=1.0,
    )
    bars_per_strip: int = param(
        2,
        "-",
        "seed 001 'Numerical simulation': each strip is two identical "
        "bars along the ribbon edges, each with half the section",
        minimum=1,
    )
    force_law: str = param(
        "volume",
        "-",
        "axial force of a strip bar at stretch p from its rest "
        "length: 'volume' (ours: (A/lambda) P(p), the cast section A = 5 mm^2 per bar "
        "thinned by the rest stretch lambda at constant volume) or 'published' ("
        + PUBLISHED
        + ": A f P(p) with the rest fraction f = lambda/lambda_N; "
        "ratio volume/published = 1/(lambda_N f^2): 1.27 at f = 0.75, 0.79 at "
        "f = 0.95)",
    )

    bending_modulus: float = param(
        0.543,
        "MPa",
        "small-strain Young's modulus 3 mu_0 of the published "
        "Ogden law (models.hyperelastic.OgdenLaw; the incompressible LCE): "
        "the strips' own bending stiffness E I (only with mesh.strip_element "
        "'bending' or 'beam')",
        positive=True,
    )
    bending_factor: float = param(
        1.0,
        "-",
        "multiplier of the strips' E I (1: the as-built section's, "
        "E w_s h_s^3/12); a calibration parameter of `lcefem calibrate "
        "bar-hinge` (only with mesh.strip_element 'bending' or 'beam')",
        minimum=0.0,
    )

    def checked(self) -> "LCEStripBars":
        if self.force_law not in FORCE_LAWS:
            raise InputError(f"lce.force_law = {self.force_law!r}: allowed {', '.join(FORCE_LAWS)}")
        return self

    def rest_fraction(self, stretch):
        """Rest-length fraction f = lambda/lambda_N [-] for the paper's relative length lambda."""
        return np.asarray(stretch, dtype=float) / self.lambda_N


@dataclass(frozen=True)
class GlueBars:
    """Stiff bars that hold the two bars of a top strip together over a junction (published
    model)."""

    youngs_modulus: float = param(
        1.0e4, "MPa", PUBLISHED + ": Ogden bar law with C0 = 5e3*2", positive=True
    )


@dataclass(frozen=True)
class StripContactSprings:
    """Very weak rotational springs between a strip's end and its panel that keep the strip on its
    side of the ribbon: enhanced-linear law whose rest angle and stiffening limit are both the
    as-built angle theta_b (so the spring is force-free as built and its barrier sits at the
    panel's plane, theta = 0 or 2 pi). The published model used a rest angle of pi/6 with the
    barrier from pi/6, which pushes slack strips away from their panels."""

    stiffness: float = param(1.0e-5, "N mm/(rad mm)", PUBLISHED + ": Kc = 1e-5", minimum=0.0)


@dataclass(frozen=True)
class StripContact:
    """Frictionless unilateral contact between the LCE strips and the ribbon (added here; the
    published model has none, so strips can pass through the ribbon). A point is held on its side of
    a plane by the penalty energy k <g0 - g>_+^2/2 (g its signed distance to the plane, g0 the
    smallest allowed), with k = E_c A_c/t_a: the strip's through-thickness stiffness over the
    contact area A_c, t_a the strip thickness (areas and depths come with the geometry)."""

    modulus: float = param(
        0.543,
        "MPa",
        "small-strain modulus 3 mu_0 of the published Ogden law "
        "(models.hyperelastic.OgdenLaw): the LCE strip compressed through its "
        "thickness",
        positive=True,
    )


@dataclass(frozen=True)
class BarHingeMaterials:
    """Every material law of the bar-and-hinge model, one place (defaults: the published model's
    values; units and sources on each field of each part): the Kapton ribbon (bars and hinges), the
    LCE strip bars, the glue bars, the strip-panel springs, the strip-ribbon contact and the LCE's
    Ogden law (:class:`lcefem.models.hyperelastic.OgdenLaw`, the published fit). Used by the
    bar-and-hinge beam, Kapton specimen and gridshell; the solver builds its model with
    ``BarHingeModel(structure, m.kapton, m.lce, m.glue, m.strip_contact, m.ogden, m.contact)``."""

    kapton: KaptonBarHinge = KaptonBarHinge()
    lce: LCEStripBars = LCEStripBars()
    glue: GlueBars = GlueBars()
    strip_contact: StripContactSprings = StripContactSprings()
    contact: StripContact = StripContact()
    ogden: OgdenLaw = OgdenLaw()

    @property
    def materials(self) -> "BarHingeMaterials":
        """The material laws alone (a run configuration that extends this class keeps its other
        sections to itself)."""
        return BarHingeMaterials(
            **{f.name: getattr(self, f.name) for f in dataclasses.fields(BarHingeMaterials)}
        )


# --------------------------------------------------------------------------- material laws
def stiffening_bar_law(stretch, modulus, exponents=(5.0, 1.0)):
    """MERLIN2 Ogden-type bar law (Liu & Paulino 2017): (W, dW/dl, d2W/dl2) per reference volume.

    W(l) = C0 [(l^a1 - 1)/(a1 (a1-a2)) + (l^a2 - 1)/(a2 (a2-a1))] [MPa = mJ/mm^3] with C0 =
    ``modulus`` [MPa]; dW/dl = C0 (l^(a1-1) - l^(a2-1))/(a1-a2) = l S [MPa]; d2W/dl2(1) = C0.
    """
    a1, a2 = (float(a) for a in exponents)
    lam = np.asarray(stretch, dtype=float)
    c = np.asarray(modulus, dtype=float) / (a1 - a2)
    # ((1 + d)^a - 1 - a d)/a without cancellation for small d = l - 1 (the d terms cancel in W).
    d = lam - 1.0
    log_l = np.log1p(d)
    w = c * ((np.expm1(a1 * log_l) - a1 * d) / a1 - (np.expm1(a2 * log_l) - a2 * d) / a2)
    dw = c * (lam ** (a1 - 1.0) - lam ** (a2 - 1.0))
    d2w = c * ((a1 - 1.0) * lam ** (a1 - 2.0) - (a2 - 1.0) * lam ** (a2 - 2.0))
    return w, dw, d2w


def second_piola_stress(stretch, modulus, exponents=(5.0, 1.0)):
    """S = C0 (l^(a1-2) - l^(a2-2))/(a1 - a2) [MPa] of the MERLIN2 bar law (Liu & Paulino 2017)."""
    a1, a2 = (float(a) for a in exponents)
    lam = np.asarray(stretch, dtype=float)
    return modulus * (lam ** (a1 - 2.0) - lam ** (a2 - 2.0)) / (a1 - a2)


def tension_only_ogden_law(stretch, law: OgdenLaw = OgdenLaw()):
    """(W, dW/dp, d2W/dp2) of the incompressible Ogden law in uniaxial stretch p, zero for p < 1.

    W = sum_k mu_k/a_k (p^a_k + 2 p^(-a_k/2) - 3) [MPa], dW/dp = P (nominal stress, Ogden 1997),
    d2W/dp2 = sum_k mu_k ((a_k - 1) p^(a_k - 2) + (a_k/2 + 1) p^(-a_k/2 - 2)). W and dW/dp are
    continuous at p = 1 (both vanish); d2W/dp2 jumps from 0 to the small-strain modulus 3 mu_0.
    """
    p = np.asarray(stretch, dtype=float)
    taut = p > 1.0
    q = np.where(taut, p, 1.0)
    w = np.zeros_like(q)
    dw = np.zeros_like(q)
    d2w = np.zeros_like(q)
    log_q = np.log1p(q - 1.0)
    for m, a in zip(law.mu, law.alpha):
        # q^a + 2 q^(-a/2) - 3 without cancellation near q = 1
        w += m / a * (np.expm1(a * log_q) + 2.0 * np.expm1(-0.5 * a * log_q))
        dw += m * (q ** (a - 1.0) - q ** (-0.5 * a - 1.0))
        d2w += m * ((a - 1.0) * q ** (a - 2.0) + (0.5 * a + 1.0) * q ** (-0.5 * a - 2.0))
    return np.where(taut, w, 0.0), np.where(taut, dw, 0.0), np.where(taut, d2w, 0.0)


def enhanced_linear_law(theta, theta0, k, theta1=math.radians(30.0), theta2=math.radians(330.0)):
    """Enhanced-linear rotational spring (Liu & Paulino 2017, Sec. 3b): (psi, M, dM/dtheta) per unit
    length.

    Args:
        theta: dihedral angle [rad] in (0, 2 pi); theta0: rest angle [rad]; k: stiffness
            [N mm/(rad mm)]; theta1 < theta2: limits [rad] of the linear range.
    Returns:
        psi [N mm/mm], M = dpsi/dtheta [N mm/mm], dM/dtheta [N mm/(rad mm)]; all zero where k = 0.
    """
    th = np.asarray(theta, dtype=float)
    th0 = np.broadcast_to(np.asarray(theta0, dtype=float), th.shape)
    kk = np.broadcast_to(np.asarray(k, dtype=float), th.shape)
    t1 = np.broadcast_to(np.asarray(theta1, dtype=float), th.shape)
    t2 = np.broadcast_to(np.asarray(theta2, dtype=float), th.shape)
    left, right = th < t1, th > t2
    # Linear range
    psi = 0.5 * kk * (th - th0) ** 2
    m = kk * (th - th0)
    dm = kk.copy()
    # Towards 0: M = k (t1 - t0) + k tan(c (th - t1))/c, c = pi/(2 t1); psi continuous at t1.
    c = np.pi / (2.0 * t1)
    arg = np.where(left, c * (th - t1), 0.0)
    psi_l = (
        0.5 * kk * (t1 - th0) ** 2 + kk * (t1 - th0) * (th - t1) - kk / c**2 * np.log(np.cos(arg))
    )
    psi = np.where(left, psi_l, psi)
    m = np.where(left, kk * (t1 - th0) + kk * np.tan(arg) / c, m)
    dm = np.where(left, kk / np.cos(arg) ** 2, dm)
    # Towards 2 pi: the mirror image with c = pi/(2 (2 pi - t2)).
    c = np.pi / (2.0 * (2.0 * np.pi - t2))
    arg = np.where(right, c * (th - t2), 0.0)
    psi_r = (
        0.5 * kk * (t2 - th0) ** 2 + kk * (t2 - th0) * (th - t2) - kk / c**2 * np.log(np.cos(arg))
    )
    psi = np.where(right, psi_r, psi)
    m = np.where(right, kk * (t2 - th0) + kk * np.tan(arg) / c, m)
    dm = np.where(right, kk / np.cos(arg) ** 2, dm)
    return psi, m, dm
