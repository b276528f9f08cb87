"""The ribbon benchmark's same-state comparison (benchmarks/ribbon_benchmark.py): a solver setting
changed in a built simulation steps exactly as a simulation built with it, and bad settings are
refused with a one-line error (never its timing)."""

import dataclasses

import numpy as np
import pytest

import ribbon_benchmark as bench
from lcefem.models.errors import InputError
from lcefem.solvers.der.ribbon import ROLLING_RIBBON, RibbonNumerics, RibbonSetup, RibbonSimulation


def _sim(**numerics) -> RibbonSimulation:
    # no settling: the first step is the first with the (changed) solver options
    num = dataclasses.replace(RibbonNumerics(), nodes=11, dt=0.01, settle_time=0.0, **numerics)
    return RibbonSimulation(
        RibbonSetup(geometry=ROLLING_RIBBON, ground_temperature=140.0, numerics=num)
    )


def test_a_solver_setting_changed_after_building_steps_as_one_built_with_it():
    """lag_tol 1 and the elastic Hessian at the source change the Newton path (the iterates, not the
    equilibrium within force_tol): a changed simulation must take the same steps, bit for bit."""
    changed = _sim()
    changed.change_solver(lag_tol=1.0, elastic_hessian_at_source=True)
    built = _sim(lag_tol=1.0, elastic_hessian_at_source=True)
    plain = _sim()
    for sim in (changed, built, plain):
        for _ in range(5):
            sim.step(0.01)
    assert np.array_equal(changed.state.x, built.state.x)
    assert changed.integrator.total_iterations == built.integrator.total_iterations
    # and the change did act: the unchanged solver's path differs (the landing on the plate
    # amplifies the force_tol-sized differences of the Newton path: measured 8e-3 mm after 5 steps)
    assert not np.array_equal(changed.state.x, plain.state.x)


def test_discretisation_cannot_change_in_a_built_simulation():
    with pytest.raises(InputError, match="numerics.nodes: cannot change"):
        _sim().change_solver(nodes=21)


def test_compare_settings_are_parsed_and_checked():
    assert bench.parse_settings("heat_dt=0.01,elastic_hessian_at_source=true") == {
        "heat_dt": 0.01,
        "elastic_hessian_at_source": True,
    }
    with pytest.raises(InputError, match="NAME one of"):
        bench.parse_settings("dt=0.01")
    with pytest.raises(InputError, match="expected a float"):
        bench.parse_settings("lag_tol=fast")


def test_bad_compare_setting_exits_2_before_running(capsys):
    assert bench.main(["--nodes", "11", "--compare", "nodes=3"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--compare 'nodes=3'" in err
