"""Dead loads of the robotic surface (lcefem units: t, mm, s, N)."""

from __future__ import annotations

from dataclasses import dataclass

from lcefem.models import units
from lcefem.models.heat import ThermalProperties
from lcefem.models.parameters import param


@dataclass(frozen=True)
class SurfaceWeight:
    """The surface's weight: its measured mass spread in proportion to the Kapton and LCE
    volumes."""

    total_mass: float = param(
        33.0 * units.GRAM,
        "t",
        "seed 001: 'the robotic surface only weighs 33 g' "
        "(with coils, glue and wires; lumped on the nodes in proportion to the "
        "Kapton and LCE volumes)",
        positive=True,
    )
    kapton_density: float = param(
        1.42 * units.G_PER_CM3, "t/mm^3", "DuPont Kapton HN datasheet: 1.42 g/cm^3", positive=True
    )
    lce_density: float = param(
        ThermalProperties().density,
        "t/mm^3",
        "the LCE density of models.heat.ThermalProperties (assumed 1.15 g/cm^3)",
        positive=True,
    )
    gravity: float = param(
        units.STANDARD_GRAVITY, "mm/s^2", "standard gravity 9.80665 m/s^2", positive=True
    )
