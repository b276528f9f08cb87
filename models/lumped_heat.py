"""Lumped (cross-section averaged) heat balance of a coil-heated LCE strip, and the current ->
temperature -> lambda map of one grid segment of the robotic surface (seed 001); the gridshell's
current route (:class:`CurrentRouteConfig`, :func:`stretch_from_current`: a channel current to a
strip's steady lambda, by this lumped segment or by the paper's Eq. 1 at the coil power).

Per unit of current strip length, with T uniform over the section (Biot number h t/k ~ 0.006 mm/K
* 2 mm / 0.25 ~ 0.05 << 1, so the lumped model is adequate for the steady state):

    rho c A(lambda) dT/dt = I^2 R / l(lambda) - (h + h_r(T)) p(lambda) (T - T_a),

where R is the coil resistance over the strip's length l(lambda) = l_iso lambda, A = A_iso/lambda
and p = p_iso/sqrt(lambda) the section and its perimeter at relative length lambda (the strip
deforms isochorically and uniformly across its section), h the calibrated film coefficient and h_r
the linearised radiation (:mod:`lcefem.models.heat`), and lambda = lambda_s(T) the free spontaneous
stretch of :mod:`lcefem.models.lce` (calibrated transition). The whole-strip balance is then
I^2 R = (h + h_r(T)) (T - T_a) p_iso l_iso sqrt(lambda_s(T)).

Checked against Eq. 1 (seed 001) for the free strip of Fig. 2 (R = 146.6 ohm, 80 mm isotropic,
5 x 2 mm): the lumped steady lambda is within 0.03 of Eq. 1 at the hold currents 0.04-0.09 A
(tests/models/test_lumped_heat.py). A grid segment (seed 001, Materials and Methods): 25 ohm over
the 30 mm nematic segment (l_iso = 30/1.4 mm). One coil of the surface ("126 to 134 ohms") is then
about five such segments in series (or one ribbon's four segments and three 7 mm junction pieces at
the same 0.83 ohm/mm, 117.5 ohm, plus leads); the channel current I_Tx etc. flows through each
segment of a coil, so each segment dissipates I^2 x 25 ohm.

The grid strip (issue 31, docs/gridshell_thermal.md): seed 001 says the free strips' "active lengths
of 80 mm in their isotropic phase and 130.22 mm in nematic phase ... are also preserved in the 3x3
grid design", and that the grid's coils range "from 126 to 134 ohms" per LCE strip (Discussion of
Fig. 4), while the channel currents are "the average applied current to each LCE strip" (Fig. 4A
text) and were chosen "according to Fig. 2C" (the free strip's Eq. 1). A grid strip (one layer's
line across the surface: 4 segments of 30 mm and 3 junction pieces, 141 mm nematic, 12 strips = 48
segments) thus carries a ~130 ohm coil over ~80 mm isotropic: 1.63 ohm/mm against the segment
reading's 25 ohm over 21.4 mm (1.17 ohm/mm) and the free strip's 1.83 ohm/mm. The "25 ohm per
segment" then holds for the 4 x 30 mm segments only if the 3 junction pieces and leads take the
other ~30 ohm; the strip reading (:data:`GRID_STRIP`, thermal model 'strip', the default) spreads
the coil uniformly, as the fabrication (one coil stretched to the designated length, fig. S8) does.
Its exchange is the free strip's calibrated one with the convective film coefficient scaled by one
grid factor (:attr:`CurrentRouteConfig.exchange_factor`, calibrated on the dome protocol only).

Units: mm, s, mW, C, ohm, A.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.empirical import Eq1, eq1_power, eq1_stretch
from lcefem.models.errors import InputError
from lcefem.models.heat import (
    GRID_STRING_RESISTANCE_RANGE,
    Coil,
    GridSegmentCoil,
    SurfaceExchange,
    ThermalProperties,
    joule_power,
    radiative_film_coefficient,
)
from lcefem.models.lce import MeasuredContraction, NematicTransition, spontaneous_stretch
from lcefem.models.limits import DECOMPOSITION_TEMPERATURE, check_current
from lcefem.models.parameters import param


@dataclass(frozen=True)
class HeatedStrip:
    """A coil-heated LCE strip as a lumped body: coil resistance, isotropic length and section."""

    resistance: float = param(
        GridSegmentCoil().resistance,
        "ohm",
        "models.heat.GridSegmentCoil: "
        "seed 001, 'the resistance within each segment of the grid is 25 ohms'",
        positive=True,
    )
    isotropic_length: float = param(
        30.0 / PUBLISHED_LAMBDA_N,
        "mm",
        "published reduced-order model: 30 mm nematic "
        "segment at lambda_N = 1.4 (isotropic 21.4 mm)",
        positive=True,
    )
    width: float = param(
        5.0, "mm", "seed 001: mould channel 5 mm wide (cast, isotropic)", positive=True
    )
    thickness: float = param(
        2.0, "mm", "seed 001: mould channel 2 mm deep (cast, isotropic)", positive=True
    )

    @property
    def perimeter(self) -> float:
        """Isotropic section perimeter p_iso [mm]."""
        return 2.0 * (self.width + self.thickness)

    @property
    def section(self) -> float:
        """Isotropic section A_iso [mm^2]."""
        return self.width * self.thickness


#: The free strip of seed 001, Fig. 2 (Eq. 1 was measured on it): 146.6 ohm over 80 mm isotropic.
FREE_STRIP = HeatedStrip(resistance=Coil().resistance, isotropic_length=80.0)

#: Coil resistance of one LCE strip of the grid [ohm]: midpoint of seed 001's "ranging from 126 to
#: 134 ohms" (Results, discussion of Fig. 4); the range is GRID_STRING_RESISTANCE_RANGE
#: (models.heat).
GRID_STRIP_RESISTANCE = 0.5 * (GRID_STRING_RESISTANCE_RANGE[0] + GRID_STRING_RESISTANCE_RANGE[1])
#: Active isotropic length of one LCE strip of the grid [mm]: seed 001, "active lengths of 80 mm in
#: their isotropic phase ... are also preserved in the 3x3 grid design for consistency".
GRID_STRIP_ISOTROPIC_LENGTH = 80.0
#: One LCE strip of the grid as a lumped body (the 'strip' reading, module docstring).
GRID_STRIP = HeatedStrip(
    resistance=GRID_STRIP_RESISTANCE, isotropic_length=GRID_STRIP_ISOTROPIC_LENGTH
)


def grid_segment_resistance(
    segment_isotropic_length: float = 30.0 / PUBLISHED_LAMBDA_N, strip: HeatedStrip = GRID_STRIP
) -> float:
    """Resistance [ohm] of the part of a grid strip's coil inside one segment of isotropic length
    ``segment_isotropic_length`` [mm] when the coil is spread uniformly over the strip's active
    length (the 'strip' reading): R_strip l_seg / l_strip (34.8 ohm for a 30 mm nematic segment, vs
    the text's 25 ohm)."""
    return strip.resistance * segment_isotropic_length / strip.isotropic_length


@dataclass(frozen=True)
class LumpedThermal:
    """Material and exchange parameters of the lumped balance (all calibrated or assumed
    elsewhere)."""

    transition: NematicTransition | MeasuredContraction = NematicTransition()
    exchange: SurfaceExchange = SurfaceExchange()
    thermal: ThermalProperties = ThermalProperties()


def heat_loss(T, strip: HeatedStrip, model: LumpedThermal = LumpedThermal()):
    """Steady loss of the whole strip [mW] at uniform temperature T [C]:
    (h + h_r(T)) (T - T_a) p_iso l_iso sqrt(lambda_s(T))."""
    ex = model.exchange
    h = ex.film_coefficient + radiative_film_coefficient(T, ex.ambient_temperature, ex.emissivity)
    lam = spontaneous_stretch(T, model.transition)
    return (
        h * (T - ex.ambient_temperature) * strip.perimeter * strip.isotropic_length * np.sqrt(lam)
    )


def steady_temperature(
    current: float, strip: HeatedStrip = HeatedStrip(), model: LumpedThermal = LumpedThermal()
) -> float:
    """Steady temperature [C] of the strip carrying ``current`` [A]: root of I^2 R = loss(T)
    (the loss increases monotonically with T, so the root is unique; Brent's method)."""
    check_current("current", current)
    power = joule_power(current, strip.resistance)
    lo = model.exchange.ambient_temperature
    if power == 0.0:
        return lo
    hi = lo + 50.0
    while heat_loss(hi, strip, model) < power:  # bracket: the loss grows without bound with T
        hi = lo + 2.0 * (hi - lo)
    return float(brentq(lambda T: heat_loss(T, strip, model) - power, lo, hi, xtol=1e-10))


def steady_stretch(
    current: float, strip: HeatedStrip = HeatedStrip(), model: LumpedThermal = LumpedThermal()
) -> float:
    """Steady relative length lambda_s(T) [-] (isotropic = 1) of the free strip at ``current``
    [A]."""
    return float(spontaneous_stretch(steady_temperature(current, strip, model), model.transition))


def current_for_stretch(
    stretch: float, strip: HeatedStrip = HeatedStrip(), model: LumpedThermal = LumpedThermal()
) -> float:
    """Inverse of :func:`steady_stretch`: the current [A] that holds the strip at ``stretch`` [-]
    (strictly between 1 and the as-built lambda_N of the transition)."""
    lam_n = model.transition.lambda_N
    if not 1.0 < stretch < lam_n:
        raise InputError(f"stretch = {stretch}: must lie strictly between 1 and {lam_n}")
    # lambda_s falls monotonically with the current, from lambda_N at 0 A to ~1 well below 1 A.
    return float(brentq(lambda i: steady_stretch(i, strip, model) - stretch, 0.0, 1.0, xtol=1e-13))


def check_held_current(
    name: str,
    current: float,
    strip: HeatedStrip = HeatedStrip(),
    model: LumpedThermal = LumpedThermal(),
) -> float:
    """A current [A] held on a strip (a steady drive, ``lcefem run gridshell --current``): in the
    current bounds (:func:`lcefem.models.limits.check_current`) and its steady temperature
    (:func:`steady_temperature`) below the decomposition temperature, the bound a schedule meets as
    a result (exit 3) checked before the run (an InputError naming ``name``, with the largest
    current held below it). Returns the steady temperature [C]."""
    check_current(name, current)
    T = steady_temperature(current, strip, model)
    if not T < DECOMPOSITION_TEMPERATURE:
        i_max = brentq(
            lambda i: steady_temperature(i, strip, model) - DECOMPOSITION_TEMPERATURE,
            0.0,
            float(current),
            xtol=1e-6,
        )
        raise InputError(
            f"{name} = {current:g} A: held, the strip's steady temperature would be {T:.0f} C "
            f"(lumped heat balance, models.lumped_heat), not below {DECOMPOSITION_TEMPERATURE:g} C "
            "(decomposition, lcefem.models.limits); hold at most "
            f"{math.floor(i_max * 1e3) / 1e3:g} "
            "A"
        )
    return T


def heat_capacity(strip: HeatedStrip, model: LumpedThermal = LumpedThermal()) -> float:
    """Heat capacity rho c A_iso l_iso [mJ/K] of the whole strip (it does not change with lambda:
    the strip deforms isochorically)."""
    return model.thermal.volumetric_heat_capacity * strip.section * strip.isotropic_length


def implicit_euler_step(
    T_previous: float,
    current: float,
    dt: float,
    strip: HeatedStrip = HeatedStrip(),
    model: LumpedThermal = LumpedThermal(),
    resistance=None,
) -> float:
    """Temperature [C] after one implicit-Euler step dt [s] of the lumped balance
    C (T - T_k)/dt = I^2 R - loss(T) (:func:`heat_loss`, C = :func:`heat_capacity`), at ``current``
    [A] during the step (Newton on T; the loss is smooth and increasing, so it converges from T_k).
    ``T_previous`` and ``current`` may be arrays of strips (then the result is one), with per-strip
    coil resistances [ohm] in ``resistance`` (default: ``strip.resistance``)."""
    cap = heat_capacity(strip, model)
    power = joule_power(current, strip.resistance if resistance is None else resistance)
    T = T_previous if np.ndim(T_previous) == 0 else np.asarray(T_previous, dtype=float)
    for _ in range(30):
        eps = 1e-4
        r = cap * (T - T_previous) / dt - power + heat_loss(T, strip, model)
        dr = cap / dt + (heat_loss(T + eps, strip, model) - heat_loss(T - eps, strip, model)) / (
            2 * eps
        )
        step = r / dr
        T = T - step
        if np.max(np.abs(step)) < 1e-9:
            break
    return float(T) if np.ndim(T) == 0 else T


def transient_temperature(
    schedule,
    duration: float,
    strip: HeatedStrip = HeatedStrip(),
    model: LumpedThermal = LumpedThermal(),
    dt: float = 0.05,
):
    """Temperature history of the lumped strip from ambient under a current schedule.

    Args:
        schedule: t [s] -> current [A].
        duration: [s]; dt: time step [s] (:func:`implicit_euler_step`, the current taken at the end
            of each step).
    Returns:
        (times (k,) [s], temperatures (k,) [C], stretches (k,) [-]).
    """
    n = int(math.ceil(duration / dt))
    times = np.linspace(0.0, n * dt, n + 1)
    temps = np.empty(n + 1)
    temps[0] = model.exchange.ambient_temperature
    for k in range(n):
        temps[k + 1] = implicit_euler_step(temps[k], schedule(times[k + 1]), dt, strip, model)
    return times, temps, np.asarray(spontaneous_stretch(temps, model.transition), dtype=float)


# -- the gridshell's current route ----------------------------------------------------------------
THERMAL_MODELS = ("strip", "segment", "eq1")

#: The grid's one calibrated heat-exchange parameter [-]: the convective film coefficient of a strip
#: in the sandwich over the free strip's calibrated one (models.heat.SurfaceExchange, 5.8 W/(m^2 K),
#: fitted on the free strip hanging vertically in still air). Calibrated on the dome protocol only
#: (seed 001: hold 0.04 A top / 0.07 A bottom after the 20 s actuation pulse, measured centre
#: curvature -0.016 1/mm, circle measure) with the bar-and-hinge current route:
#: ``python -m lcefem.validation.studies.gridshell.grid_exchange_calibration`` -> validation/data/
#: grid_exchange_calibration.json (0.9512; the uncalibrated 1.0 gives -0.0146 1/mm). Published bound
#: (docs/gridshell_thermal.md): 0.5-2.3, from the natural-convection correlations (Incropera; Nu =
#: 0.54 Ra^1/4 upper / 0.27 lower face with L = A/P, 0.59 Ra^1/4 vertical faces) for a horizontal
#: 5 x 2 mm strip with all faces exposed (upper end) or its upper face covered by the 7 mm Kapton
#: ribbon (lower end), over the vertical 80 mm strip's 6.9 W/(m^2 K) scaled to the calibrated 5.8.
GRID_EXCHANGE_FACTOR = 0.9512


@dataclass(frozen=True)
class CurrentRouteConfig:
    """The configuration of the gridshell's current route: how a channel current becomes a strip's
    lambda (the thermal model and its lumped bodies); the route itself is
    lcefem.solvers.current_routes (``route_from_config``)."""

    thermal_model: str = param(
        "strip",
        "-",
        "'strip': our lumped steady heat balance of one grid LCE "
        "strip (~130 ohm coil over 80 mm isotropic, seed 001) with the free "
        "strip's calibrated transition and the grid's calibrated exchange "
        "factor (models.lumped_heat, docs/gridshell_thermal.md); 'segment': the "
        "same balance for one 25 ohm, 30 mm segment (the earlier reading, "
        "under-powered); 'eq1': the paper's own estimate, Eq. 1 at the "
        "power I^2 R of a 146.6 ohm strip coil (seed 001: 'We can estimate the "
        "required current for each LCE strip by the imposed stretch, using Eq. 1')",
    )
    segment: HeatedStrip = field(default_factory=HeatedStrip)
    strip: HeatedStrip = field(default_factory=lambda: GRID_STRIP)
    exchange_factor: float = param(
        GRID_EXCHANGE_FACTOR,
        "-",
        "grid strip's convective film coefficient "
        "over the free strip's (thermal model 'strip'); calibrated on the "
        "dome protocol (validation/data/grid_exchange_calibration.json)",
        positive=True,
    )
    curve: str = param(
        "",
        "-",
        "CSV of the LCE's measured free stretch or strain against temperature: the "
        "lumped strip's lambda_s(T) (thermal models 'strip' and 'segment'; read by "
        "lcefem.solvers.current_routes.route_from_config); empty: the calibrated sigmoid",
    )

    def checked(self) -> "CurrentRouteConfig":
        if self.thermal_model not in THERMAL_MODELS:
            raise InputError(
                f"current.thermal_model = {self.thermal_model!r}: allowed "
                f"{', '.join(THERMAL_MODELS)}"
            )
        if self.curve and self.thermal_model == "eq1":
            raise InputError(
                f"current_route.curve = {self.curve!r}: allowed only with thermal_model 'strip' "
                "or 'segment' (Eq. 1 is a fit of its own)"
            )
        return self

    def temperature_model(
        self, law: MeasuredContraction | None = None
    ) -> tuple[HeatedStrip, "LumpedThermal"]:
        """The lumped body whose steady temperature bounds a held current: the route's own (with
        ``law``, its measured curve), and the grid strip's for 'eq1' (Eq. 1 has no temperature)."""
        self.checked()
        return (
            (GRID_STRIP, grid_thermal(self.exchange_factor))
            if self.thermal_model == "eq1"
            else self.lumped(law)
        )

    def lumped(self, law: MeasuredContraction | None = None) -> tuple[HeatedStrip, "LumpedThermal"]:
        """The lumped body and its thermal model for the 'strip' and 'segment' thermal models (the
        exchange factor applies to the grid strip only); ``law``: a measured curve replacing the
        transition's sigmoid in lambda_s(T) (the heat balance's sqrt(lambda) and the strip's
        lambda)."""
        if self.curve and law is None:
            raise InputError(
                f"current_route.curve = {self.curve!r}: the curve is read by "
                "lcefem.solvers.current_routes.route_from_config; pass its law"
            )
        if self.thermal_model == "segment":
            thermal = LumpedThermal()
        else:
            thermal = grid_thermal(self.exchange_factor)
        if law is not None:
            thermal = dataclasses.replace(thermal, transition=law)
        return (self.segment if self.thermal_model == "segment" else self.strip), thermal


def grid_thermal(exchange_factor: float = GRID_EXCHANGE_FACTOR) -> LumpedThermal:
    """The lumped thermal model of a grid strip: the free strip's calibrated transition, capacity
    and radiation, its convective film coefficient times ``exchange_factor`` [-]."""
    if not (math.isfinite(exchange_factor) and exchange_factor > 0):
        raise InputError(f"exchange_factor = {exchange_factor}: must be > 0")
    ex = SurfaceExchange()
    return LumpedThermal(
        exchange=SurfaceExchange(
            film_coefficient=ex.film_coefficient * exchange_factor,
            emissivity=ex.emissivity,
            ambient_temperature=ex.ambient_temperature,
        )
    )


def stretch_from_current(
    current: float,
    route: CurrentRouteConfig = CurrentRouteConfig(),
    lambda_N: float = PUBLISHED_LAMBDA_N,
    law: MeasuredContraction | None = None,
) -> float:
    """Steady lambda [-] of a grid strip at ``current`` [A], capped at the as-built lambda_N (a
    strip whose free length would exceed its glued length is slack: rest fraction 1); ``law``: the
    measured curve ``route.curve`` names (:meth:`CurrentRouteConfig.lumped`)."""
    if route.checked().thermal_model == "eq1":
        lam = float(eq1_stretch(Coil().power(current), Eq1()))
    else:
        strip, model = route.lumped(law)
        lam = steady_stretch(current, strip, model)
    return min(lam, lambda_N)


def lambda_assignments_from_currents(
    currents: dict,
    route: CurrentRouteConfig = CurrentRouteConfig(),
    lambda_N: float = PUBLISHED_LAMBDA_N,
    law: MeasuredContraction | None = None,
) -> dict:
    """{selection: current [A]} -> {selection: lambda [-]} through :func:`stretch_from_current`."""
    return {k: stretch_from_current(float(v), route, lambda_N, law) for k, v in currents.items()}


def eq1_current(stretch: float, resistance: float = GRID_STRIP_RESISTANCE) -> float:
    """The paper's rule for a hold current [A]: Eq. 1 inverted at ``stretch`` [-] (the power P that
    holds a free strip there, seed 001: 'We can estimate the required current for each LCE strip by
    the imposed stretch, using Eq. 1'), through a coil of ``resistance`` [ohm]: I = sqrt(P / R)
    (0.064 A at lambda 1.33 and 0.079 A at 1.05 for the grid's 130 ohm coils; the dome's protocol
    used 0.04 / 0.07 A, 'according to Fig. 2C')."""
    if not 1.0 < stretch < 1.0 + Eq1().gamma_1:
        raise InputError(
            f"stretch = {stretch}: must lie strictly between 1 and {1.0 + Eq1().gamma_1}"
        )
    return math.sqrt(eq1_power(stretch, Eq1()) / (resistance * 1e3))


def shape_currents(lambdas: dict, resistance: float = GRID_STRIP_RESISTANCE) -> dict:
    """{channel: lambda [-]} -> {channel: hold current [A]} by the paper's rule
    (:func:`eq1_current`)."""
    return {k: eq1_current(float(v), resistance) for k, v in lambdas.items()}
