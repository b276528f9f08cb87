"""The runner (lcefem.solvers.runner): a body's run is its problem driven through the protocol,
with export objects; the bar-and-hinge beam's run reaches the one-call path's state exactly."""

from __future__ import annotations

import csv
import json

import pytest

from lcefem.solvers.runner import HistoryExport


def test_history_columns_carry_units():
    HistoryExport(("load factor [-]", "curvature [1/mm]"), dict)
    with pytest.raises(ValueError, match="curvature"):
        HistoryExport(("load factor [-]", "curvature"), dict)


def test_beam_run_through_the_problem_is_the_one_call_path(tmp_path):
    """run_beam (CompositeBeamBH through run_quasi_static) writes the increments of solve_beam: the
    same load factors and the same final curvature to the last digit."""
    from lcefem.solvers.problems.composite_beam_bh import BeamConfig, run_beam, solve_beam

    summary = run_beam(BeamConfig(), tmp_path, progress=False)
    one_call = solve_beam(1.33, 1.05)
    with open(tmp_path / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    # every converged increment, the as-built state first (CSV: 10 significant digits)
    assert [float(r["load factor [-]"]) for r in rows] == pytest.approx(
        [s.t for s in one_call.path.states], rel=1e-9, abs=1e-12
    )
    assert float(rows[-1]["curvature [1/mm]"]) == pytest.approx(one_call.curvature, rel=1e-9)
    assert summary["results"]["curvature [1/mm]"] == one_call.curvature
    assert summary["increments"] == len(one_call.path.states) - 1
    assert json.loads((tmp_path / "summary.json").read_text())["status"] == "completed"
    assert (tmp_path / "beam.pvd").is_file()


class _Recorder:
    """An export object that keeps what it saw (and the state it got when the run failed)."""

    def __init__(self):
        self.seen, self.failed_at = [], None

    def open(self, run, out):
        return self

    def write(self, state):
        self.seen.append(state)

    def last_converged(self, folder, state):
        self.failed_at = state


def test_path_of_its_own_through_the_door_records_the_due_rows_and_shows_every_step(tmp_path):
    """A body along a path of its own (PathProblem) through the door: the history gets only the
    rows ``when`` marks due, every export sees every step, and the summary is summarize's; a failed
    step leaves failure.json, no summary.json, and each export gets the last step seen."""
    from lcefem.models.errors import ConvergenceError
    from lcefem.solvers.problems.protocol import LOAD
    from lcefem.solvers.runner import PathProblem, StateExport, StateHistory, run
    from lcefem.solvers.runtime.run import Progress

    history = HistoryExport(
        ("step [-]", "value [mm]"),
        lambda s: {"step [-]": s, "value [mm]": 0.5 * s},
        when=lambda s: s % 2 == 0,
        where=lambda s: f"step {s}",
    )
    rec = _Recorder()

    def drive(on_step):
        for k in range(5):
            on_step(k)
        return "done"

    problem = PathProblem(drive, clock=LOAD, at=lambda s: s / 4)
    summary = run(
        problem,
        problem.program(),
        [StateHistory(history), StateExport(rec)],
        tmp_path / "ok",
        config={},
        progress=Progress(0, "", "", enabled=False),
        summarize=lambda run, records: {
            "result": records[-1].detail,
            "rows": len(run.history.rows),
        },
    )
    assert rec.seen == [0, 1, 2, 3, 4]
    assert summary["result"] == "done" and summary["rows"] == 3
    with open(tmp_path / "ok" / "history.csv", newline="") as f:
        assert [float(r["step [-]"]) for r in csv.DictReader(f)] == [0, 2, 4]

    rec = _Recorder()

    def failing(on_step):
        on_step(0)
        on_step(1)
        raise ConvergenceError("step 2", "no convergence")

    problem = PathProblem(failing, end=3.0)  # on the time clock [s]
    with pytest.raises(ConvergenceError):
        run(
            problem,
            problem.program(),
            [StateHistory(history), StateExport(rec)],
            tmp_path / "bad",
            config={},
            progress=Progress(0, "", "", enabled=False),
            summarize=lambda run, records: {},
        )
    assert rec.failed_at == 1
    assert (tmp_path / "bad" / "failure.json").is_file() and not (
        tmp_path / "bad" / "summary.json"
    ).exists()
