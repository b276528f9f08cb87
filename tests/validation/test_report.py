"""Report formatting: reference ranges, errors, strict JSON, error rows."""

import json
import math

from lcefem.solvers.runtime.files import json_safe
from lcefem.validation.app import report
from lcefem.validation.app.report import CaseResult
from lcefem.validation.cases import Metric


def _row(metric: Metric) -> dict:
    return metric.as_dict()


def test_target_reference_shows_relative_error():
    row = _row(Metric.relative("c", "force", 1.43, "N", 1.36, 0.1, "seed"))
    assert report.fmt_reference(row) == "1.36 ± 0.136"
    assert report.fmt_error(row) == "+5.15 %"
    assert report.fmt_pass(row) == "pass"


def test_range_reference_shows_interval_and_error_in_tolerances():
    row = _row(Metric.between("c", "strain", 0.06, "-", 0.0, 0.05, "seed"))
    assert report.fmt_reference(row) == "[0, 0.05]"
    assert report.fmt_error(row) == "+1.40 tol"  # (0.06 - 0.025)/0.025
    assert report.fmt_pass(row) == "FAIL"


def test_nan_values_are_written_as_null_and_fail():
    m = Metric.within("c", "time to 70 C", math.nan, "s", 10.0, 1.0, "seed")
    assert m.passed is False
    text = json.dumps(json_safe([m.as_dict()]), allow_nan=False)
    assert '"value": null' in text


def test_report_lists_errors_and_figures_with_captions():
    ok = CaseResult(
        "a",
        "case a",
        "done",
        1.25,
        metrics=[_row(Metric.info("a", "x", 1.0, "N", "src"))],
        figures=[{"path": "a/fig.png", "caption": "A figure. Sources: seed 001."}],
    )
    bad = CaseResult(
        "b", "case b", "error", 0.5, error="ConvergenceError: no convergence at t = 3 s"
    )
    md = report.render_report([ok, bad], command="lcefem validate a b", quick=True, total_wall=1.75)
    assert "`lcefem validate a b`" in md and "quick (coarse, CI)" in md
    assert "| a | x | 1 | N | - | - | info | src |" in md
    assert (
        "| b | (error) | - |  | - | - | ERROR | ConvergenceError: no convergence at t = 3 s |" in md
    )
    assert "![Figure 1](a/fig.png)" in md and "*Figure 1. A figure. Sources: seed 001.*" in md
    assert "wall time: 1.25 s" in md and "1 metrics pass" not in md  # informative only
    assert "0 metrics pass, 0 fail, 1 informative; 1 cases did not finish" in md


def test_numpy_scalars_from_cases_are_written_as_plain_json():
    import numpy as np

    m = Metric.within("c", "x", np.float64(1.0), "-", np.float64(1.0), np.float64(0.1), "s")
    text = json.dumps(
        json_safe(m.as_dict() | {"n": np.int64(3), "ok": np.bool_(True)}), allow_nan=False
    )
    assert '"passed": true' in text and '"n": 3' in text and '"ok": true' in text
