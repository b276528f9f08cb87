"""One CurrentRoute interface (lcefem.solvers.current_routes) over the three current -> lambda
routes: the lumped ones give exactly what models.lumped_heat.stretch_from_current gives for the same
configuration, Eq. 1 inverted and applied again returns the stretch it was inverted at, and the FE
heated route reads each channel's lambda from the held model."""

from __future__ import annotations

import pytest

from lcefem.models import lumped_heat as lh
from lcefem.models.errors import InputError
from lcefem.models.heat import Coil
from lcefem.solvers.current_routes import (
    CurrentRoute,
    Eq1Route,
    FEHeatedRoute,
    LumpedRoute,
    route_from_config,
)

DOME_HOLD = {"Tx": 0.04, "Ty": 0.04, "Bx": 0.07, "By": 0.07}


@pytest.mark.parametrize("thermal_model", lh.THERMAL_MODELS)
def test_a_configured_route_is_the_existing_route(thermal_model):
    config = lh.CurrentRouteConfig(thermal_model=thermal_model)
    route = route_from_config(config)
    assert isinstance(route, CurrentRoute) and route.name == thermal_model
    assert route.lambdas(DOME_HOLD) == lh.lambda_assignments_from_currents(DOME_HOLD, config)


def test_lumped_route_caps_at_lambda_n_and_contracts_with_current():
    route = LumpedRoute()
    assert route.stretch(0.0) == route.lambda_N  # ambient: nematic, capped at the as-built length
    lams = [route.stretch(i) for i in (0.04, 0.07, 0.1, 0.2)]
    assert all(b < a for a, b in zip(lams, lams[1:]))
    assert lams[-1] == pytest.approx(1.0, abs=0.02)  # 0.2 A: isotropic (seed 001, Fig. 2C)


def test_eq1_route_inverts_the_papers_rule():
    """eq1_current(lambda, R) is Eq. 1 inverted through a coil of R: the Eq. 1 route through the
    same coil gives lambda back."""
    resistance = lh.GRID_STRIP_RESISTANCE
    route = Eq1Route(coil=Coil(resistance=resistance))
    for lam in (1.05, 1.2, 1.33):
        assert route.stretch(lh.eq1_current(lam, resistance)) == pytest.approx(lam, rel=1e-12)


class HeldModel:
    """What FEHeatedRoute needs of HeatedGridshellFE: steady_hold(currents), observables()."""

    def __init__(self):
        self.held = None

    def steady_hold(self, currents):
        self.held = dict(currents)
        return []

    def observables(self):
        return {
            f"lambda {ch} [-]": 1.4 - I
            for ch, I in self.held.items()
            if ch in ("Tx", "Ty", "Bx", "By")
        }


def test_fe_heated_route_holds_the_model_and_reads_the_channels():
    model = HeldModel()
    route = FEHeatedRoute(model)
    assert isinstance(route, CurrentRoute) and route.name == "fe"
    assert route.lambdas(DOME_HOLD) == {k: 1.4 - v for k, v in DOME_HOLD.items()}
    assert model.held == DOME_HOLD
    with pytest.raises(
        InputError, match="^current XD1: the FE heated route reports lambda per channel"
    ):
        route.lambdas({"XD1": 0.05})


@pytest.mark.parametrize(
    "route", [LumpedRoute(), Eq1Route(), FEHeatedRoute(HeldModel())], ids=["lumped", "eq1", "fe"]
)
def test_a_bad_current_is_refused_by_name(route):
    with pytest.raises(InputError, match="^current Tx"):
        route.lambdas({"Tx": -0.1})
