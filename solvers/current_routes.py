"""One interface for the routes from a coil current to a strip's lambda (:class:`CurrentRoute`),
whatever computes it: a lumped steady heat balance of one strip or segment (:class:`LumpedRoute`:
the 'strip' and 'segment' thermal models of :mod:`lcefem.models.lumped_heat`), the paper's own
estimate, Eq. 1 at the coil's Joule power (:class:`Eq1Route`), or the 3D FE heated gridshell held
at the currents to its steady state (:class:`FEHeatedRoute`, around
:class:`lcefem.solvers.problems.gridshell_heated.HeatedGridshellFE`).

These are thin adapters: each calls the route's existing code (models.lumped_heat's
``steady_stretch`` and ``eq1_stretch``, HeatedGridshellFE's ``steady_hold`` and observables), so
a change of a route's physics there reaches the adapter unchanged. The configuration section of
a run (which route, which strip, the exchange factor, a measured contraction curve) stays
:class:`lcefem.models.lumped_heat.CurrentRouteConfig`; :func:`route_from_config` turns it into a
route (``lcefem run gridshell --route current`` and ``--current`` take their lambdas through it).

A study can then compare routes through one call::

    for route in (route_from_config(cfg), Eq1Route(), FEHeatedRoute(model)):
        lambdas = route.lambdas({"Tx": 0.04, "Ty": 0.04, "Bx": 0.07, "By": 0.07})

Units: current [A], lambda [-] (isotropic = 1).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

from lcefem.models import lumped_heat as lh
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.empirical import Eq1, eq1_stretch
from lcefem.models.errors import InputError
from lcefem.models.heat import Coil
from lcefem.models.lce import MeasuredContraction
from lcefem.models.limits import check_current
from lcefem.solvers.contraction_curve import read_contraction_csv


@runtime_checkable
class CurrentRoute(Protocol):
    """Currents per selection (channel, group, strip tag) [A] -> the strips' steady lambda [-]."""

    #: Which route, as the run's configuration names it ("strip", "segment", "eq1", "fe").
    name: str

    def lambdas(self, currents: Mapping[str, float]) -> dict[str, float]:
        """{selection: current [A]} -> {selection: steady lambda [-]}; a current out of bounds is
        an InputError naming it."""
        ...


def _checked(
    currents: Mapping[str, float],
    strip: lh.HeatedStrip = lh.GRID_STRIP,
    thermal: lh.LumpedThermal | None = None,
) -> dict[str, float]:
    """The currents' bounds: each in [0, 1 A] and, held, its strip's steady temperature below
    decomposition (lcefem.models.lumped_heat.check_held_current; the grid strip's balance unless the
    route has its own)."""
    thermal = thermal if thermal is not None else lh.grid_thermal()
    for k, v in currents.items():
        check_current(f"current {k}", v)
        lh.check_held_current(f"current {k}", v, strip, thermal)
    return dict(currents)


@dataclass(frozen=True)
class LumpedRoute:
    """The steady heat balance of one lumped strip
    (:func:`lcefem.models.lumped_heat.steady_stretch`): I^2 R = loss(T) -> lambda_s(T), capped at
    the as-built ``lambda_N`` (a strip whose free length would exceed its glued length is slack)."""

    strip: lh.HeatedStrip = field(default_factory=lambda: lh.GRID_STRIP)
    thermal: lh.LumpedThermal = field(default_factory=lh.grid_thermal)
    lambda_N: float = PUBLISHED_LAMBDA_N
    name: str = "strip"

    def stretch(self, current: float) -> float:
        return min(lh.steady_stretch(current, self.strip, self.thermal), self.lambda_N)

    def lambdas(self, currents: Mapping[str, float]) -> dict[str, float]:
        return {k: self.stretch(v) for k, v in _checked(currents, self.strip, self.thermal).items()}


@dataclass(frozen=True)
class Eq1Route:
    """The paper's estimate: Eq. 1 (seed 001) at the Joule power I^2 R of ``coil``, capped at
    ``lambda_N``."""

    coil: Coil = field(default_factory=Coil)
    eq1: Eq1 = field(default_factory=Eq1)
    lambda_N: float = PUBLISHED_LAMBDA_N
    name: str = "eq1"

    def stretch(self, current: float) -> float:
        return min(float(eq1_stretch(self.coil.power(current), self.eq1)), self.lambda_N)

    def lambdas(self, currents: Mapping[str, float]) -> dict[str, float]:
        return {k: self.stretch(v) for k, v in _checked(currents).items()}


@dataclass
class FEHeatedRoute:
    """The 3D FE heated gridshell (a built ``HeatedGridshellFE``, or anything with its
    ``steady_hold(currents)`` and ``observables()``): held at the currents to the steady state,
    each channel's lambda is its spontaneous stretch at its mean temperature (the observable
    "lambda <channel> [-]"). The model keeps the held state (the shape at those currents)."""

    model: Any
    name: str = "fe"

    def lambdas(self, currents: Mapping[str, float]) -> dict[str, float]:
        currents = _checked(currents)
        self.model.steady_hold(currents)
        obs = self.model.observables()
        missing = [k for k in currents if f"lambda {k} [-]" not in obs]
        if missing:
            raise InputError(
                f"current {missing[0]}: the FE heated route reports lambda per channel "
                f"(Tx, Ty, Bx, By), not per {missing[0]!r}"
            )
        return {k: float(obs[f"lambda {k} [-]"]) for k in currents}


def route_from_config(
    config: lh.CurrentRouteConfig = lh.CurrentRouteConfig(), lambda_N: float = PUBLISHED_LAMBDA_N
) -> LumpedRoute | Eq1Route:
    """The route a run's ``current_route`` section names (thermal_model 'strip', 'segment' or
    'eq1'), the same numbers as :func:`lcefem.models.lumped_heat.stretch_from_current`."""
    config = config.checked()
    if config.thermal_model == "eq1":
        return Eq1Route(lambda_N=lambda_N)
    strip, thermal = config.lumped(curve_law(config))
    return LumpedRoute(strip, thermal, lambda_N, config.thermal_model)


def curve_law(config: lh.CurrentRouteConfig) -> MeasuredContraction | None:
    """The measured curve ``config.curve`` names (as built at 25 C, the calibrated transition's
    T_ref), or None for the sigmoid."""
    if not config.curve:
        return None
    return read_contraction_csv(config.curve, lh.LumpedThermal().transition.T_ref)


__all__ = [
    "CurrentRoute",
    "Eq1Route",
    "FEHeatedRoute",
    "LumpedRoute",
    "curve_law",
    "route_from_config",
]
