"""Heat sources and surface exchange of the heated LCE strip (lcefem units: mW, mm, s, C)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.models import units
from lcefem.models.errors import InputError
from lcefem.models.lce import CALIBRATED
from lcefem.models.limits import check_current
from lcefem.models.parameters import param


@dataclass(frozen=True)
class ThermalProperties:
    """Bulk thermal properties of the LCE (assumed values of shared/reference/materials.md)."""

    density: float = param(
        1.15e-9, "t/mm^3", "assumed 1.15 g/cm^3 (RM257-thiol networks 1.1-1.2)", positive=True
    )
    specific_heat: float = param(
        1.5e9,
        "mJ/(t K)",
        "1.5 J/(g K), lower end of the assumed 1.5-2.0 for elastomers; " + CALIBRATED,
        positive=True,
    )
    conductivity: float = param(
        0.25, "mW/(mm K)", "assumed 0.25 W/(m K) (polymers 0.2-0.3)", positive=True
    )

    @property
    def volumetric_heat_capacity(self) -> float:
        """rho c [mJ/(mm^3 K)]."""
        return self.density * self.specific_heat


@dataclass(frozen=True)
class SurfaceExchange:
    """Natural convection and grey-body radiation to still air (seed 001: room ~25 C, in air)."""

    film_coefficient: float = param(
        5.805e-3,
        "mW/(mm^2 K)",
        "5.8 W/(m^2 K) (still air, small bodies: 5-25 assumed); " + CALIBRATED,
        minimum=0.0,
    )
    emissivity: float = param(0.9, "-", "assumed (polymer surfaces)", minimum=0.0, maximum=1.0)
    ambient_temperature: float = param(25.0, "C", "seed 001: experiments at room temperature ~25 C")


@dataclass(frozen=True)
class Coil:
    """Embedded Ni-Cr heating coil of one free LCE strip (seed 001, Materials and Methods).

    :meth:`power` is the one current -> power step of lcefem: a "current" means the same in the
    strip, the composite beam and the gridshell, whichever coil (this one or
    :class:`GridSegmentCoil`) heats.
    """

    resistance: float = param(
        146.6,
        "ohm",
        "seed 001: mean of P/I^2 = 1.5/0.1^2, 3.26/0.15^2, 5.79/0.2^2 W/A^2",
        positive=True,
    )
    rod_diameter: float = param(
        1.0, "mm", "seed 001: wire wound on a 1 mm steel rod", positive=True
    )

    def power(self, current: float) -> float:
        """Joule power P = I^2 R [mW] of this coil at current I [A] (:func:`joule_power`)."""
        return joule_power(current, self.resistance)


@dataclass(frozen=True)
class GridSegmentCoil(Coil):
    """The coil of one 30 mm LCE segment of the robotic surface's grid (seed 001, Materials and
    Methods).

    The wire has 1.25 ohm/mm before it is stretched, so a 25 ohm segment holds 20 mm of unstretched
    coil; the text's 126-134 ohm per grid strip is about five such segments in series.
    """

    resistance: float = param(
        25.0,
        "ohm",
        "seed 001 Materials and Methods: 'the resistance within "
        "each segment of the grid is 25 ohms'",
        positive=True,
    )
    resistance_per_length: float = param(
        1.25,
        "ohm/mm",
        "seed 001 Materials and Methods: 'the "
        "resistance of the coil is 1.25 ohms/mm on average before "
        "stretch'",
        positive=True,
    )


#: Resistance range of one heater string of the robotic surface [ohm] (seed 001, Results: "the
#: coil resistances ranging from 126 to 134 ohms"); the spread the prediction bands sample.
GRID_STRING_RESISTANCE_RANGE: tuple[float, float] = (126.0, 134.0)


def joule_power(current: float, resistance: float) -> float:
    """Electric power P = I^2 R [mW] for a current I [A] through a resistance R [ohm] (scalars or
    arrays of strips).

    Raises:
        InputError: for a current outside [0, MAX_CURRENT] (the experiments' currents are
            magnitudes; lcefem.models.limits.check_current).
    """
    check_current("current", current)
    if np.any(np.asarray(resistance) <= 0):
        raise InputError(f"resistance = {resistance} ohm: must be > 0 ohm")
    return current**2 * resistance * units.W


def radiative_film_coefficient(T, T_ambient: float, emissivity: float):
    """Linearised radiation h_r = eps sigma (T^2 + Ta^2)(T + Ta) [mW/(mm^2 K)], T in C (kelvin
    inside), so that the radiative flux is h_r (T - Ta). Accepts floats, arrays or UFL
    expressions."""
    tk = T + units.ZERO_CELSIUS_K
    tak = T_ambient + units.ZERO_CELSIUS_K
    return emissivity * units.STEFAN_BOLTZMANN * (tk**2 + tak**2) * (tk + tak)
