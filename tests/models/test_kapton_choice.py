"""The Kapton stiffness decision (issue 16): one modulus, used by every Kapton body, and the
effective free length that reconciles it with the measured buckling load."""

import math

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.models.bar_hinge_materials import KaptonBarHinge
from lcefem.models.hyperelastic import (
    KAPTON_DATASHEET_MODULUS,
    KAPTON_MODULI,
    KAPTON_SPECIMEN_EFFECTIVE_LENGTH,
    NeoHookeanSolid,
)
from lcefem.validation.cases.reference_data import reference


def test_every_kapton_body_uses_the_chosen_modulus():
    assert (
        KAPTON_MODULI["datasheet"] == KAPTON_DATASHEET_MODULUS == 2500.0
    )  # [MPa] DuPont datasheet
    assert NeoHookeanSolid().youngs_modulus == KAPTON_DATASHEET_MODULUS
    assert KaptonBarHinge().youngs_modulus == KAPTON_DATASHEET_MODULUS


def test_effective_free_length_gives_the_measured_buckling_load():
    # fixed-fixed Euler load 4 pi^2 E I / L^2 of the datasheet film at the effective free length
    g = CompositeBeamGeometry()
    inertia = g.ribbon_width * g.ribbon_thickness**3 / 12.0  # [mm^4]
    euler = (
        4.0 * math.pi**2 * KAPTON_DATASHEET_MODULUS * inertia / KAPTON_SPECIMEN_EFFECTIVE_LENGTH**2
    )
    measured = float(reference("ribbon.buckling_load"))  # 0.18 N, seed 001 Fig. 2G
    # 5 %: the FE specimen buckles 4 % above Euler's load (README, Kapton ribbon)
    assert abs(euler - measured) <= 0.05 * measured
    # and the full 36 mm specimen length gives half of it: the disagreement the choice explains
    euler_36 = euler * (KAPTON_SPECIMEN_EFFECTIVE_LENGTH / 36.0) ** 2
    assert euler_36 < 0.55 * measured
