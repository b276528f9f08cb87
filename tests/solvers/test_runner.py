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
        [s.t for s in one_call.path.states], rel=1e-9, abs=1e-12)
    assert float(rows[-1]["curvature [1/mm]"]) == pytest.approx(one_call.curvature, rel=1e-9)
    assert summary["results"]["curvature [1/mm]"] == one_call.curvature
    assert summary["increments"] == len(one_call.path.states) - 1
    assert json.loads((tmp_path / "summary.json").read_text())["status"] == "completed"
    assert (tmp_path / "beam.pvd").is_file()
