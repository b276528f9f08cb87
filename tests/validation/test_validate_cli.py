"""``lcefem validate``: outputs, exit codes, error rows, --resume and interrupted runs."""

import json
import subprocess

import pytest

from lcefem.solvers.runtime.outdir import STAMP_TEXT
from lcefem.validation import cases as case_registry
from lcefem.validation.app import plots
from lcefem.validation.app.cli import main as cli_main
from lcefem.validation.app.report import METRIC_KEYS
from lcefem.validation.cases import Case, Metric

EMPIRICAL = ["tension_law", "ribbon_load_strain"]


def test_validate_quick_on_the_closed_form_cases(lcefem_cmd, tmp_path):
    """The console command end to end; every quick metric of these cases meets its tolerance."""
    out = tmp_path / "v"
    proc = subprocess.run(
        [*lcefem_cmd, "validate", *EMPIRICAL, "--quick", "--quiet", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    rows = json.loads((out / "metrics.json").read_text())
    assert rows and all(tuple(r) == METRIC_KEYS for r in rows)
    assert {r["case"] for r in rows} == set(EMPIRICAL)
    assert all(r["passed"] is not False for r in rows), [r for r in rows if r["passed"] is False]
    assert all(r["source"] for r in rows)
    for name in EMPIRICAL:
        assert (out / name / "metrics.json").is_file()
        assert (out / name / f"{name}.csv").read_text().splitlines()[0].count(
            "["
        ) >= 3  # units in headers
    md = (out / "report.md").read_text()
    assert "| case | metric | value | unit | reference ± tolerance | error | pass | source |" in md
    assert "lcefem validate tension_law ribbon_load_strain --quick --quiet --out" in md
    assert "wall time" in md and "dolfinx" in md and "python" in md
    assert "![Figure 1](tension_law/tension_law.png)" in md and "Sources: " in md
    assert "tension_law" in proc.stdout and "pass" in proc.stdout


def _ok_case(ctx):
    (ctx.out / "data.csv").write_text("x [-]\n1\n")
    png = plots.comparison_plot(
        ctx.path("ok.png"),
        [plots.Series([0, 1], [0, 1], "model")],
        xlabel="x [-]",
        ylabel="y [-]",
        sources=["test"],
    )
    ctx.add_figure(png, "a line. Sources: test.")
    return [Metric.within("", "one", 1.0, "-", 1.0, 0.1, "test")]


def _failing_metric_case(ctx):
    return [Metric.within("", "two", 2.0, "N", 1.0, 0.1, "test")]


def _raising_case(ctx):
    (ctx.out / "partial.csv").write_text("t [s]\n")
    raise RuntimeError("solver blew up")


def _interrupted_case(ctx):
    raise KeyboardInterrupt


def test_validate_with_a_relative_out_from_another_directory(lcefem_cmd, tmp_path):
    """As ``make validate`` runs it: a relative --out, resolved once against the working directory.
    (A figure path joined to the out folder twice failed every case that writes a figure.)"""
    cwd = tmp_path / "elsewhere"
    cwd.mkdir()
    proc = subprocess.run(
        [*lcefem_cmd, "validate", "tension_law", "--quick", "--quiet", "--out", "rel/v"],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=cwd,
    )
    assert proc.returncode == 0, proc.stderr
    out = cwd / "rel" / "v"
    assert (out / "tension_law" / "tension_law.png").is_file()
    assert (out / "tension_law" / "metrics.json").is_file()
    assert not (out / "tension_law" / "rel").exists()  # nothing written under a doubled path
    assert "![Figure 1](tension_law/tension_law.png)" in (out / "report.md").read_text()


@pytest.fixture
def toy_cases(monkeypatch):
    calls = {}

    def counted(func):
        def run(ctx):
            calls[ctx.case] = calls.get(ctx.case, 0) + 1
            return func(ctx)

        return run

    for name, func in (
        ("toy_ok", _ok_case),
        ("toy_fail", _failing_metric_case),
        ("toy_raise", _raising_case),
        ("toy_interrupt", _interrupted_case),
    ):
        monkeypatch.setitem(
            case_registry._CASES, name, Case(name, counted(func), f"{name} case", False, False)
        )
    return calls


def test_failing_metric_exits_0_and_unknown_case_exits_2(toy_cases, tmp_path, capsys):
    out = tmp_path / "v"
    assert cli_main(["validate", "toy_ok", "toy_fail", "--out", str(out), "--quiet"]) == 0
    rows = json.loads((out / "metrics.json").read_text())
    assert [(r["case"], r["passed"]) for r in rows] == [("toy_ok", True), ("toy_fail", False)]
    assert "FAIL" in capsys.readouterr().out
    assert cli_main(["validate", "toy_ok", "no_such_case", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "unknown case(s) no_such_case; known cases:" in err and "toy_ok" in err


def test_a_raising_case_is_an_error_row_and_the_run_goes_on(toy_cases, tmp_path):
    out = tmp_path / "v"
    assert cli_main(["validate", "toy_raise", "toy_ok", "--out", str(out), "--quiet"]) == 1
    rows = json.loads((out / "metrics.json").read_text())
    assert rows[0]["case"] == "toy_raise" and rows[0]["passed"] is False
    assert "RuntimeError: solver blew up" in rows[0]["source"]
    assert rows[1]["case"] == "toy_ok" and rows[1]["passed"] is True
    assert not (out / "toy_raise" / "metrics.json").exists()  # no completion marker
    assert "solver blew up" in (out / "toy_raise" / "error.log").read_text()
    md = (out / "report.md").read_text()
    assert "FAILED with an error" in md and "| toy_raise | (error) |" in md


def test_resume_skips_completed_cases_only(toy_cases, tmp_path):
    out = tmp_path / "v"
    cli_main(["validate", "toy_ok", "toy_raise", "--out", str(out), "--quiet"])
    assert toy_cases == {"toy_ok": 1, "toy_raise": 1}
    cli_main(["validate", "toy_ok", "toy_raise", "--out", str(out), "--quiet", "--resume"])
    assert toy_cases == {"toy_ok": 1, "toy_raise": 2}  # the completed case was not run again
    rows = json.loads((out / "metrics.json").read_text())
    assert rows[0]["case"] == "toy_ok" and rows[0]["passed"] is True  # its results are kept
    assert "reused from an earlier run" in (out / "report.md").read_text()
    # a marker of a --quick run does not stand for the default resolution
    cli_main(["validate", "toy_ok", "--out", str(out), "--quiet", "--resume", "--quick"])
    assert toy_cases["toy_ok"] == 2
    # a missing figure makes the outputs incomplete
    (out / "toy_ok" / "ok.png").unlink()
    cli_main(["validate", "toy_ok", "--out", str(out), "--quiet", "--resume", "--quick"])
    assert toy_cases["toy_ok"] == 3


def test_interrupted_run_keeps_completed_cases_and_leaves_no_marker(toy_cases, tmp_path, capsys):
    out = tmp_path / "v"
    # a stale marker of an earlier complete run must not survive a resumed run that is interrupted
    (out / "toy_interrupt").mkdir(parents=True)
    (out / ".lcefem-out").write_text(
        STAMP_TEXT.format(command="validate")
    )  # --resume: lcefem's folder
    (
        out / "toy_interrupt" / "metrics.json"
    ).write_text(  # of another resolution (quick): not reused
        '{"case": "toy_interrupt", "description": "", "status": "done", "wall_time": 0.0, '
        '"quick": true, '
        '"metrics": [], "figures": []}'
    )
    rc = cli_main(
        [
            "validate",
            "toy_ok",
            "toy_interrupt",
            "toy_fail",
            "--out",
            str(out),
            "--quiet",
            "--resume",
        ]
    )
    assert rc == 130 and "interrupted" in capsys.readouterr().err
    assert (out / "toy_ok" / "metrics.json").is_file()
    assert not (out / "toy_interrupt" / "metrics.json").exists()
    assert "toy_fail" not in toy_cases  # the run stopped
    rows = json.loads((out / "metrics.json").read_text())
    assert [r["case"] for r in rows] == ["toy_ok", "toy_interrupt", "toy_fail"]
    assert [r["metric"] for r in rows[1:]] == ["(interrupted)", "(not run)"]
    report = (out / "report.md").read_text()
    assert "| toy_fail | not run |" in report and "INCOMPLETE" in report
    assert not list(out.rglob("*.part")) and not (out / ".lcefem.lock").exists()


def test_list_names_the_cases(toy_cases, capsys):
    assert cli_main(["validate", "--list"]) == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in [*EMPIRICAL, "toy_ok"])
