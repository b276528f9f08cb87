"""Parameters of closed-loop shape control of the robotic surface (seed 001, beyond the paper: its
Discussion names "external sensors that provide feedback for closed-loop control" as the next step):
the current limits of the paper's operating rule, the measured spreads the simulated surface draws
its strips from, the sensor, and the vectorised lumped heat balance of the grid's strips.

* Current limits (:class:`CurrentLimits`): 0-0.2 A; a current above the sustained limit 0.1 A (the
  paper's "0.1-A current for slower contraction", Fig. 5C "reduced to half (0.1 A)") may be kept for
  at most 30 s at a time ("We did not keep a 0.2-A current for more than 30 s to avoid overheating
  the LCEs"), after which the channel stays at or below 0.1 A for a rest time (assumed 30 s).
* Spreads (:class:`PlantSpread`): per strip, the coil-string resistance uniform 126-134 ohm (a
  grid segment's 25 ohm scaled by R/130 ohm), the current reaching the strip within +-5 %, and
  lambda_N normal with the measured relative SD 8.01/130.22; an ambient offset; a payload.
* Sensor (:class:`HeightSensor`): the nine junction-centre heights with Gaussian noise.
* Heat (:func:`strip_temperature_step`): the lumped balance of :mod:`lcefem.models.lumped_heat`,
  C dT/dt = I^2 R - loss(T), one implicit-Euler step for many strips at once. Its transient is the
  model's own (no lag is added): at 0.2 A a 25 ohm segment reaches lambda = 1.06 in 23 s, the
  paper's "about 20 s until full contraction" at 0.2 A (seed 001, Fig. 2B).

Units: mm, s, A, ohm, C, mW, t (tonne).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from lcefem.models import units
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.heat import GRID_STRING_RESISTANCE_RANGE, GridSegmentCoil
from lcefem.models.lce import spontaneous_stretch
from lcefem.models.lumped_heat import HeatedStrip, LumpedThermal, heat_loss, implicit_euler_step
from lcefem.models.parameters import param

#: Nominal string resistance [ohm]: mid-range of the measured 126-134 ohm (seed 001, Results).
NOMINAL_STRING = 0.5 * sum(GRID_STRING_RESISTANCE_RANGE)


@dataclass(frozen=True)
class CurrentLimits:
    """The paper's operating rule for the strip currents (module docstring)."""

    maximum: float = param(
        0.2,
        "A",
        "seed 001, Results: 'we chose to operate the system with a 0.2-A "
        "current for more rapid contraction'",
        positive=True,
    )
    sustained: float = param(
        0.1,
        "A",
        "seed 001: 'a 0.1-A current for slower contraction'; Fig. 5C: "
        "'After 25 s, to avoid overheating, currents were reduced to half (0.1 A)'",
        positive=True,
    )
    boost_time: float = param(
        30.0,
        "s",
        "seed 001: 'We did not keep a 0.2-A current for more than 30 s "
        "to avoid overheating the LCEs'",
        positive=True,
    )
    rest_time: float = param(
        30.0,
        "s",
        "assumed: after a 30 s boost the channel stays at or below the "
        "sustained current as long before boosting again",
        minimum=0.0,
    )

    def checked(self) -> "CurrentLimits":
        for name in ("maximum", "sustained", "boost_time"):
            v = getattr(self, name)
            if not np.isfinite(v) or v <= 0.0:
                raise InputError(f"limits.{name} = {v}: must be a positive number")
        if not np.isfinite(self.rest_time) or self.rest_time < 0.0:
            raise InputError(f"limits.rest_time = {self.rest_time}: must be >= 0 s")
        if self.sustained > self.maximum:
            raise InputError(
                f"limits.sustained = {self.sustained} A: must not exceed limits.maximum = "
                f"{self.maximum} A"
            )
        if self.maximum > 1.0:
            raise InputError(f"limits.maximum = {self.maximum} A: must be at most 1 A")
        return self


class BoostGuard:
    """Enforces :class:`CurrentLimits` per channel: ``limit(dt)`` gives each channel's allowed
    maximum for the next step, ``account(currents, dt)`` books the step."""

    def __init__(self, limits: CurrentLimits, channels: int):
        self.limits = limits.checked()
        self.boosting = np.zeros(
            channels
        )  # time spent above the sustained current in this boost [s]
        self.resting = np.full(channels, np.inf)  # time since the last boost ended [s]

    def limit(self) -> np.ndarray:
        lim = self.limits
        ok = (self.boosting < lim.boost_time) & (
            (self.boosting > 0.0) | (self.resting >= lim.rest_time)
        )
        return np.where(ok, lim.maximum, lim.sustained)

    def account(self, currents: np.ndarray, dt: float) -> None:
        above = np.asarray(currents) > self.limits.sustained * (1.0 + 1e-9)
        ended = (~above) & (self.boosting > 0.0)
        self.resting = np.where(ended, dt, np.where(above, self.resting, self.resting + dt))
        self.boosting = np.where(above, self.boosting + dt, 0.0)


@dataclass(frozen=True)
class PlantSpread:
    """The measured spreads a simulated surface draws its strips from (per strip, seeded RNG)."""

    string_resistance: tuple = param(
        GRID_STRING_RESISTANCE_RANGE,
        "ohm",
        "seed 001, Results: coil resistances 'ranging from 126 to 134 ohms': uniform per strip",
    )
    current_factor: float = param(
        0.05,
        "-",
        "seed 001: 'the magnitude of current flowing through each "
        "LCE strip varies around the assigned values' (no number): assumed "
        "uniform +-5 % (as lcefem uncertainty gridshell)",
        minimum=0.0,
    )
    lambda_N_relative_sd: float = param(
        8.01 / 130.22,
        "-",
        "seed 001, Results: nematic length 130.22 +- 8.01 mm (1 SD, 9 strips): normal per strip",
        minimum=0.0,
    )
    ambient_offset: float = param(
        -3.0,
        "K",
        "assumed: the room 3 K cooler than the 25 C the model "
        "assumes (seed 001: 'room temperature ~25 C')",
    )
    payload_mass: float = param(
        1.0e-4,
        "t",
        "issue 37: a 100 g weight on the centre (seed 001, Fig. 5C lifts weights)",
        minimum=0.0,
    )


def draw_strips(
    spread: PlantSpread, strips: int, rng: np.random.Generator, lambda_N: float = PUBLISHED_LAMBDA_N
) -> dict[str, np.ndarray]:
    """Per-strip segment resistance [ohm], current factor [-] and lambda_N [-] (``strips`` each)."""
    lo, hi = spread.string_resistance
    r = rng.uniform(lo, hi, strips) / NOMINAL_STRING * GridSegmentCoil().resistance
    c = 1.0 + rng.uniform(-spread.current_factor, spread.current_factor, strips)
    ln = rng.normal(lambda_N, spread.lambda_N_relative_sd * lambda_N, strips)
    ln = np.clip(ln, 1.0 + 1e-3, None)  # a normal tail below 1 would be no LCE strip at all
    return {"resistance": r, "current_factor": c, "lambda_N": ln}


@dataclass(frozen=True)
class HeightSensor:
    """The nine junction-centre heights, as a laser scanner or tracked markers give them."""

    noise: float = param(
        0.1,
        "mm",
        "assumed: 1 SD of a structured-light/laser scanner on reflective "
        "markers (seed 001 used a NextEngine 3D laser scanner with reflective tape at "
        "the nine cover-scale centres; ~0.1 mm class)",
        minimum=0.0,
    )
    period: float = param(
        1.0, "s", "assumed: one scan per second (seed 001's thermal images: 1 Hz)", positive=True
    )


@dataclass(frozen=True)
class StripHeat:
    """The lumped strip of a grid segment and its exchange (defaults: models.lumped_heat)."""

    segment: HeatedStrip = field(default_factory=HeatedStrip)
    model: LumpedThermal = field(default_factory=LumpedThermal)

    def at_ambient(self, offset: float) -> "StripHeat":
        ex = self.model.exchange
        return replace(
            self,
            model=replace(
                self.model,
                exchange=replace(ex, ambient_temperature=ex.ambient_temperature + offset),
            ),
        )

    @property
    def ambient(self) -> float:
        return float(self.model.exchange.ambient_temperature)


def strip_temperature_step(
    T: np.ndarray,
    currents: np.ndarray,
    resistances: np.ndarray,
    dt: float,
    heat: StripHeat = StripHeat(),
) -> np.ndarray:
    """Temperatures [C] after one implicit-Euler step dt [s] of C (T - T_k)/dt = I^2 R - loss(T)
    for every strip at once (:func:`lcefem.models.lumped_heat.implicit_euler_step` on arrays)."""
    return implicit_euler_step(
        np.asarray(T, dtype=float),
        np.asarray(currents, dtype=float),
        dt,
        heat.segment,
        heat.model,
        resistance=np.asarray(resistances, dtype=float),
    )


def free_stretch(T, heat: StripHeat = StripHeat()) -> np.ndarray:
    """Free relative length lambda_s(T) [-] of the strips (calibrated transition)."""
    return np.asarray(
        spontaneous_stretch(np.asarray(T, dtype=float), heat.model.transition), dtype=float
    )


class SteadyMaps:
    """Tabulated steady maps of the nominal segment (for the controller): lambda -> temperature ->
    holding current (monotonic; linear interpolation on a 0.05 K grid)."""

    def __init__(self, heat: StripHeat = StripHeat(), resistance: float | None = None):
        T = np.arange(heat.ambient, heat.ambient + 250.0, 0.05)
        lam = free_stretch(T, heat)
        keep = np.concatenate([[True], np.diff(lam) < -1e-12])  # strictly decreasing part
        self.T, self.lam = T[keep], lam[keep]
        r = heat.segment.resistance if resistance is None else resistance
        self.current = np.sqrt(
            np.maximum(heat_loss(self.T, heat.segment, heat.model), 0.0) / (r * 1.0e3)
        )

    def temperature(self, lam) -> np.ndarray:
        """Steady temperature [C] holding the free stretch ``lam`` (clipped to the table)."""
        return np.interp(-np.asarray(lam, dtype=float), -self.lam, self.T)

    def hold_current(self, T) -> np.ndarray:
        """Current [A] holding the strip at temperature T [C]."""
        return np.interp(np.asarray(T, dtype=float), self.T, self.current)

    def stretch_at_current(self, current: float) -> float:
        """Steady free stretch [-] at ``current`` [A]."""
        return float(np.interp(current, self.current, self.lam))


def payload_weight(mass: float) -> float:
    """Weight [N] of a payload of ``mass`` [t]."""
    return float(mass * units.STANDARD_GRAVITY)
