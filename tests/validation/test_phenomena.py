"""The phenomena each case must show at every level (validation/data/phenomena.toml, issue 16):
declarations complete and well formed, their evaluation, and their place in the report. That the
quick level shows them is asserted by tests/validation/test_quick_cases.py on the real runs."""

import pytest

from lcefem.models.errors import InputError
from lcefem.validation.app import phenomena, report
from lcefem.validation.cases import registry


def test_every_case_declares_a_phenomenon_and_none_is_stale():
    cases = set(registry())
    declared = {p.case for p in phenomena.declared()}
    assert cases - declared == set(), "cases without a declared phenomenon"
    assert declared - cases == set(), "phenomena of cases that do not exist"


def test_declared_phenomena_are_qualitative_conditions_with_a_reason():
    for p in phenomena.declared():
        assert p.why and p.phenomenon
        assert p.above is not None or p.below is not None
        if p.above is not None and p.below is not None:
            assert p.above < p.below, p


ROWS = [
    {"metric": "dome (lambda): kappa_x circle vs paper simulation", "value": -0.02},
    {"metric": "dome (lambda): kappa_y circle vs paper simulation", "value": -0.02},
]


def test_a_pattern_needs_every_match_to_hold():
    ev = {p["phenomenon"]: p for p in phenomena.evaluate("gridshell_shapes_bh", ROWS)}
    dome = ev["the dome lambdas make a dome: negative curvature in x and y"]
    assert dome["holds"] and len(dome["values"]) == 2
    flipped = [ROWS[0], {**ROWS[1], "value": 0.001}]
    dome = {p["phenomenon"]: p for p in phenomena.evaluate("gridshell_shapes_bh", flipped)}[
        dome["phenomenon"]
    ]
    assert not dome["holds"]


def test_a_missing_metric_or_a_nan_is_not_shown():
    ev = phenomena.evaluate("gridshell_shapes_bh", [])
    assert ev and not any(p["holds"] for p in ev)
    nan = [{**r, "value": float("nan")} for r in ROWS] + [{**ROWS[0], "metric": "x", "value": None}]
    assert not any(p["holds"] for p in phenomena.evaluate("gridshell_shapes_bh", nan))


@pytest.mark.parametrize(
    "entry, field",
    [
        ({"case": "c", "phenomenon": "p", "why": "w", "metric": "m"}, "above and/or below"),
        (
            {"case": "c", "phenomenon": "p", "why": "w", "metric": "m", "pattern": "x", "above": 0},
            "exactly one",
        ),
        ({"case": "c", "phenomenon": "p", "why": "w", "pattern": "(", "above": 0}, "pattern"),
        ({"case": "c", "phenomenon": "p", "why": "", "metric": "m", "above": 0}, ".why"),
        ({"case": "c", "phenomenon": "p", "why": "w", "metric": "m", "above": "0"}, ".above"),
        (
            {"case": "c", "phenomenon": "p", "why": "w", "metric": "m", "above": 0, "tol": 1},
            "unknown key",
        ),
    ],
)
def test_bad_declarations_name_the_field(tmp_path, entry, field):
    path = tmp_path / "phenomena.toml"
    path.write_text(
        "[[phenomenon]]\n" + "".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in entry.items())
    )
    with pytest.raises(InputError, match=field.replace("(", r"\(")):
        phenomena.declared(path)


def test_report_flags_a_phenomenon_not_shown():
    shown = report.CaseResult(
        "gridshell_shapes_bh",
        "",
        "done",
        1.0,
        metrics=[],
        phenomena=phenomena.evaluate("gridshell_shapes_bh", ROWS),
    )
    text = report.render_report([shown], command="lcefem validate", quick=True, total_wall=1.0)
    assert "NOT SHOWN" in text  # the saddle and cylinder rows are absent from ROWS
    assert "| the dome lambdas make a dome: negative curvature in x and y |" in text.replace(
        "| gridshell_shapes_bh | the dome", "| the dome"
    )
    assert "Phenomena shown: 1/4." in text


def test_model_vs_model_rows_are_grouped_in_their_own_section():
    row = {
        "case": "ribbon_fe_vs_der",
        "metric": "(b) twist rate, FE vs DER",
        "value": 0.29,
        "unit": "rad/mm",
        "reference": 0.27,
        "tolerance": None,
        "passed": None,
        "source": "not judged: model vs model (FE vs DER) with no agreed band",
    }
    other = {**row, "metric": "closed form", "source": "Euler"}
    res = report.CaseResult("ribbon_fe_vs_der", "", "done", 1.0, metrics=[row, other])
    section = "\n".join(report.model_vs_model_lines([res]))
    assert (
        "## Model vs model" in section and row["metric"] in section and "closed form" not in section
    )
    assert (
        report.model_vs_model_lines([report.CaseResult("x", "", "done", 1.0, metrics=[other])])
        == []
    )
