"""`lcefem run strip`: outputs of a completed run, one-line errors for bad input, and a failed run
that leaves nothing that looks complete."""

import csv
import json
import subprocess

import pytest


def run(cmd, *args, **kw):
    return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=600, **kw)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--current", "-0.1"], "run.current = -0.1: must be >= 0.0 A"),
        (["--mesh-size", "0"], "mesh.size = 0.0: must be > 0 mm"),
        (["--duration", "0"], "run.duration = 0.0: must be > 0 s"),
        (["--config", "/nonexistent/case.toml"], "file not found"),
        (["--bc", "sideways"], "invalid choice: 'sideways'"),
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, lcefem_cmd, args, message):
    out = tmp_path / "out"
    res = run(lcefem_cmd, "run", "strip", "--out", str(out), *args)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], res.stderr
    assert not (out / "summary.json").exists()


def test_unknown_config_key(tmp_path, lcefem_cmd):
    case = tmp_path / "case.toml"
    case.write_text("[run]\ncurrent = 0.1\nvoltage = 3\n")
    res = run(lcefem_cmd, "run", "strip", "--config", str(case), "--out", str(tmp_path / "o"))
    assert res.returncode == 2
    assert "unknown key 'run.voltage'; allowed: bc, current" in res.stderr


def test_completed_run_outputs(tmp_path, lcefem_cmd):
    case = tmp_path / "case.toml"
    case.write_text(
        "[run]\ncurrent = 0.15\nduration = 4.0\ndt = 2.0\n[exchange]\nemissivity = 0.8\n"
    )
    out = tmp_path / "run"
    res = run(lcefem_cmd, "run", "strip", "--config", str(case), "--out", str(out), "--quiet")
    assert res.returncode == 0, res.stderr
    names = {p.name for p in out.iterdir()}
    assert {"history.csv", "summary.json", "thermal.bp", "displacement.bp"} <= names
    assert not any(n.endswith(".part") for n in names)
    with open(out / "history.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["time [s]"]) for r in rows] == [0.0, 2.0, 4.0]
    assert float(rows[-1]["T_mean [C]"]) > 25.0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed"
    assert summary["config"]["run"]["current"] == {
        "value": 0.15,
        "unit": "A",
        "source": summary["config"]["run"]["current"]["source"],
    }
    assert summary["config"]["exchange"]["emissivity"]["value"] == 0.8
    assert summary["power [mW]"] == pytest.approx(0.15**2 * 146.6 * 1e3)


def test_failed_run_keeps_converged_steps_as_partial(tmp_path, lcefem_cmd):
    """Newton allowed no iteration: the first heated step cannot converge even after step
    cutting."""
    case = tmp_path / "case.toml"
    case.write_text("[run]\nduration = 2.0\ndt = 1.0\n[petsc]\nsnes_max_it = 0\n")
    out = tmp_path / "run"
    # level 0: the level-1 default takes ~170 tangent predictions (55 s CPU) to the same failure
    res = run(
        lcefem_cmd,
        "run",
        "strip",
        "--config",
        str(case),
        "--mesh-level",
        "0",
        "--out",
        str(out),
        "--quiet",
    )
    assert res.returncode == 3
    assert "no convergence at t = 1 s" in res.stderr
    names = {p.name for p in out.iterdir()}
    assert "summary.json" not in names and "history.csv" not in names
    assert {"failure.json", "history.partial.csv"} <= names
    failure = json.loads((out / "failure.json").read_text())
    assert failure["last_converged"]["time [s]"] == 0.0 and failure["where"] == "t = 1 s"
