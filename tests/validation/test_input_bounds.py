"""Issue 45, causes 10-13, as a user meets them: the real entry point in a subprocess, exit 2 and
one line naming the field and what is allowed, nothing written; the bound's words agree with the
check."""

import json
import subprocess

import pytest

from lcefem.models.errors import InputError
from lcefem.models.limits import check_between, range_text


def _refused(lcefem_cmd, args, out, *needles):
    proc = subprocess.run(
        [*lcefem_cmd, *args, "--out", str(out)], capture_output=True, text=True, timeout=300
    )
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1 and lines[0].startswith("lcefem: error: "), proc.stderr
    for needle in needles:
        assert needle in lines[0], lines[0]
    assert not out.exists()  # refused before the folder was touched
    return lines[0]


def test_held_currents_are_bounded_like_a_schedule(lcefem_cmd, tmp_path):
    """1 A held on every channel: the grid strip's steady temperature (lumped balance) is far above
    decomposition (the schedule route stops there with exit 3); refused before the run."""
    line = _refused(
        lcefem_cmd,
        ["run", "gridshell", "--current", "Tx=1,Ty=1,Bx=1,By=1"],
        tmp_path / "g",
        "current Tx = 1 A",
        "not below 300 C (decomposition",
    )
    # the largest current it names holds the strip just below decomposition
    from lcefem.models import lumped_heat as lh
    from lcefem.validation.studies.gridshell import calibrate

    # the run's default model set carries its own grid exchange factor (the FE-calibrated set's)
    thermal = lh.grid_thermal(calibrate.exchange_factor(calibrate.DEFAULT_MODEL_SET))
    i_max = float(line.rsplit("hold at most ", 1)[1].split(" A")[0])
    assert lh.steady_temperature(i_max, lh.GRID_STRIP, thermal) < 300.0
    assert lh.steady_temperature(i_max + 0.002, lh.GRID_STRIP, thermal) > 300.0


def test_a_temperature_at_the_excluded_bound_says_so(lcefem_cmd, tmp_path):
    """300 C is decomposition: refused, and the message says 'below 300', not 'between ... and
    300'."""
    line = _refused(
        lcefem_cmd,
        ["run", "ribbon", "--ground-temperature", "300"],
        tmp_path / "r",
        "run.ground_temperature = 300 C",
        "< 300 C (decomposition",
    )
    assert "between" not in line


def test_control_seed_is_checked_like_uncertainty(lcefem_cmd, tmp_path):
    a = _refused(lcefem_cmd, ["control", "--seed", "-1"], tmp_path / "c", "--seed = -1")
    b = _refused(
        lcefem_cmd, ["uncertainty", "gridshell", "--seed", "-1"], tmp_path / "u", "--seed = -1"
    )
    assert a == b


def test_a_ribbon_too_short_for_its_summary_is_refused_up_front(lcefem_cmd, tmp_path):
    """0.1 s with a row every 0.05 s leaves one row in the last half: refused with the shortest
    duration that has three; that duration runs and writes its summary."""
    line = _refused(
        lcefem_cmd,
        ["run", "ribbon", "--duration", "0.1", "--nodes", "20"],
        tmp_path / "r",
        "run.duration = 0.1 s",
        "give at least 0.25 s",
    )
    assert "3 history rows" in line
    out = tmp_path / "ok"
    proc = subprocess.run(
        [
            *lcefem_cmd,
            "run",
            "ribbon",
            "--duration",
            "0.25",
            "--nodes",
            "20",
            "--quiet",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


@pytest.mark.parametrize(
    "schedule, needle",
    [
        (
            "end = 60.0\noutput_interval = 5.0\nheat_step = 1e-12",
            "6e+13 heat steps, more than the bound 1e+06",
        ),
        (
            "end = 3600.0\noutput_interval = 0.01\nheat_step = 0.005",
            "3.6e+05 outputs, more than the bound 3.6e+03",
        ),
    ],
)
def test_a_schedule_that_would_not_end_is_refused_with_its_cost(
    lcefem_cmd, tmp_path, schedule, needle
):
    path = tmp_path / "s.toml"
    path.write_text(f"[schedule]\ntimes = [0.0]\n{schedule}\n[currents]\nTx = [0.1]\n")
    line = _refused(
        lcefem_cmd, ["run", "gridshell", "--schedule", str(path)], tmp_path / "g", needle
    )
    assert needle in line  # the one line names the cost and its bound


@pytest.mark.parametrize(
    "low_open, high_open", [(False, False), (True, False), (False, True), (True, True)]
)
def test_a_bound_message_never_contradicts_its_check(low_open, high_open):
    """At each end the value is refused exactly when the words exclude it ('>'/'<'), accepted when
    they include it ('between ..., both included', '>='/'<=')."""
    text = range_text(0.0, 300.0, "C", low_open=low_open, high_open=high_open)
    for value, is_open, word in ((0.0, low_open, "> 0 C"), (300.0, high_open, "< 300 C")):
        if is_open:
            with pytest.raises(
                InputError, match="must be " + text.replace("(", r"\(").replace(")", r"\)")
            ):
                check_between("T", value, 0.0, 300.0, "C", low_open=low_open, high_open=high_open)
            assert word in text
        else:
            assert (
                check_between("T", value, 0.0, 300.0, "C", low_open=low_open, high_open=high_open)
                == value
            )
            assert word not in text
    with pytest.raises(InputError, match="must be a number"):
        check_between("T", float("nan"), 0.0, 300.0, "C")
