"""Programmed shape sequences of the gridshell
(lcefem.validation.studies.gridshell.gridshell_sequence): schedule parsing, the heat history against
the closed-form steady state, and the unheated surface."""

import dataclasses
import pathlib
import subprocess

import numpy as np
import pytest

from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.models.errors import InputError
from lcefem.models.lce import spontaneous_stretch
from lcefem.models.lumped_heat import (
    FREE_STRIP,
    GRID_STRIP,
    HeatedStrip,
    LumpedThermal,
    grid_thermal,
    steady_temperature,
)
from lcefem.solvers.problems import gridshell_bh_sequence as seq

REPO = pathlib.Path(__file__).resolve().parents[2]
GOOD = {
    "schedule": {"times": [0.0, 20.0], "end": 60.0, "output_interval": 10.0},
    "currents": {"Tx": [0.1, 0.04], "Bx": [0.2, 0.07]},
}


def _with(section, key, value):
    data = {k: dict(v) for k, v in GOOD.items()}
    if value is None:
        data[section].pop(key)
    else:
        data[section][key] = value
    return data


@pytest.mark.parametrize(
    "data, field",
    [
        ({**GOOD, "extra": {}}, "[extra]"),
        (_with("schedule", "durations", [1.0]), "schedule.durations"),
        (_with("schedule", "times", [0.0, 20.0, 20.0]), "schedule.times[2]"),
        (_with("schedule", "times", [5.0, 20.0]), "schedule.times[0]"),
        (_with("schedule", "end", 10.0), "schedule.end"),
        (_with("schedule", "end", 1.0e5), "schedule.end"),
        (_with("schedule", "output_interval", 0.0), "schedule.output_interval"),
        (_with("schedule", "support", "glue"), "schedule.support"),
        (_with("schedule", "thermal_model", "fe"), "schedule.thermal_model"),
        (_with("currents", "Tx", [0.1, -0.04]), "currents.Tx[1]"),
        (_with("currents", "Tx", [0.1, 1.5]), "currents.Tx[1]"),
        (_with("currents", "Tx", [0.1]), "currents.Tx"),
        (_with("currents", "Tx", [0.1, "a"]), "currents.Tx[1]"),
        (_with("schedule", "times", None), "schedule.times"),
    ],
)
def test_bad_schedules_are_refused_naming_the_field(data, field):
    with pytest.raises(InputError) as err:
        seq.schedule_from_dict(data)
    assert field in str(err.value) and "\n" not in str(err.value)


def test_unknown_selection_is_refused():
    sched = seq.schedule_from_dict(_with("currents", "Tz", [0.1, 0.1]))
    with pytest.raises(InputError, match="currents.Tz"):
        seq.check_selections(sched, build_gridshell_bar_hinge())


def test_command_line_refuses_a_bad_schedule_in_one_line(tmp_path, lcefem_cmd):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        '[schedule]\ntimes = [0, 10, 5]\nend = 20\noutput_interval = 5\n[currents]\nTx = [0.1, '
        '0.1, 0.1]\n'
    )
    p = subprocess.run(
        [*lcefem_cmd, "run", "gridshell", "--schedule", str(bad), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 2
    assert p.stderr.strip().count("\n") == 0 and "schedule.times[2]" in p.stderr
    assert not (tmp_path / "o").exists()


def test_shipped_schedules_parse():
    for name in ("gridshell_fig5a_schedule.toml", "gridshell_weight_lifting_schedule.toml"):
        sched = seq.load_schedule(REPO / "validation" / "data" / name)
        assert len(sched.labels) == len(sched.times)
        seq.check_selections(sched, build_gridshell_bar_hinge())


@pytest.mark.parametrize(
    "thermal_model, strip", [("segment", HeatedStrip()), ("eq1", FREE_STRIP), ("strip", GRID_STRIP)]
)
def test_constant_current_reaches_the_closed_form_steady_state(thermal_model, strip):
    # tau = C / (dLoss/dT) ~ 100 s: after 2000 s the transient is e^-20 below the steady state,
    # which implicit Euler shares exactly (its fixed point is the root of I^2 R = loss(T)).
    current = 0.08
    sched = seq.Schedule(
        (0.0,),
        {"Tx": (current,)},
        end=2000.0,
        output_interval=500.0,
        thermal_model=thermal_model,
        heat_step=0.5,
    )
    temps, lambdas = seq.strip_histories(sched, sched.output_times())
    # the grid strip carries the calibrated grid exchange (models.lumped_heat.grid_thermal)
    T_ss = steady_temperature(
        current, strip, grid_thermal() if thermal_model == "strip" else LumpedThermal()
    )
    assert temps["Tx"][0] == pytest.approx(LumpedThermal().exchange.ambient_temperature)
    assert temps["Tx"][-1] == pytest.approx(T_ss, abs=1e-6)
    assert np.all(np.diff(temps["Tx"]) > -1e-9)  # heating from ambient is monotonic
    lam = min(float(spontaneous_stretch(T_ss, LumpedThermal().transition)), 1.4)
    assert lambdas["Tx"][-1] == pytest.approx(lam, abs=1e-8)


def test_switch_time_belongs_to_the_new_interval():
    sched = seq.schedule_from_dict(GOOD)
    assert sched.current_at(19.999) == {"Tx": 0.1, "Bx": 0.2}
    assert sched.current_at(20.0) == {"Tx": 0.04, "Bx": 0.07}
    assert list(sched.output_times()) == [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0]


def test_zero_current_leaves_the_surface_as_built():
    sched = dataclasses.replace(
        seq.schedule_from_dict(GOOD), currents={"T": (0.0, 0.0), "B": (0.0, 0.0)}, end=20.0
    )
    summary = seq.run_sequence(sched, None, progress=False)
    h = summary["history"]
    assert np.allclose(h["T lambda [-]"], 1.4) and np.allclose(h["B lambda [-]"], 1.4)
    for col in seq.CURVATURE_COLUMNS:
        assert np.max(np.abs(h[col])) < 1e-9, col
    assert np.ptp(h["z range [mm]"]) < 1e-9


def test_phase_ends_are_the_last_outputs_before_each_switch():
    sched = seq.schedule_from_dict(GOOD)  # switches at 0 and 20 s, outputs every 10 s to 60 s
    assert seq.phase_ends(sched, sched.output_times()) == {1: 0, 6: 1}
