"""Known disagreements: the registry is well formed and grouped by cause (every row names a
registered cause, every cause explains a row), the report's summary counts them and lists the causes
table with each row in one line, an unexplained failure stays visible, and failing metrics never
change the exit code (issue 16)."""

import dataclasses
import json

import pytest

from lcefem.models.errors import InputError
from lcefem.validation.app import report
from lcefem.validation.app.cli import main as cli_main
from lcefem.validation.cases import _CASES as CASES
from lcefem.validation.cases import NOT_JUDGED, Case, Metric, not_judged, registry
from lcefem.validation.cases import reference_data as rd

TOY_CAUSE = rd.Cause(
    "toy_modulus",
    "The toy's modulus",
    "the toy's modulus is off",
    "a stiffer toy passes",
    "the toy's measured modulus",
    99,
)
KNOWN = rd.KnownDisagreement(
    "toy_known", "force vs measured", TOY_CAUSE, "both", "0.096 N against 0.18 N"
)


def test_registry_entries_name_registered_cases_and_explain():
    entries = rd.known_disagreements()
    assert entries, "the registry is empty"
    cases = registry()
    for (case, metric), k in entries.items():
        assert case in cases, f"{case}: not a registered case"
        assert metric and len(k.explanation) > 40 and k.issue > 0


def test_every_row_names_a_cause_and_every_cause_explains_a_row():
    causes = rd.causes()
    rows = rd.known_disagreements().values()
    assert {k.cause.id for k in rows} == set(causes), (
        "a cause explains no row, or a row's cause is unlisted"
    )
    for k in rows:
        assert causes[k.cause.id] is k.cause
    for c in causes.values():
        # the datum that would decide it and the controlled changes that show it, not a placeholder
        assert (
            len(c.statement) > 40 and len(c.controlled_changes) > 20 and len(c.missing_datum) > 20
        )
    # grouped: far fewer causes than rows (64 rows, 14 causes when grouped)
    assert len(causes) < len(rows) / 2


def test_a_malformed_registry_is_an_input_error(tmp_path):
    bad = tmp_path / "kd.toml"
    cause = (
        '[[cause]]\nid = "c"\ntitle = "t"\nstatement = "s"\ncontrolled_changes = "x"\n'
        'missing_datum = "m"\nissue = 1\n'
    )
    bad.write_text(cause + '[[disagreement]]\ncase = "a"\nmetric = "b"\ncause = "c"\n')
    with pytest.raises(InputError, match="entry 1 needs case, metric, cause, level"):
        rd.known_disagreements(bad)
    bad.write_text(
        cause + '[[disagreement]]\ncase = "a"\nmetric = "b"\ncause = "d"\nlevel = "both"\n'
    )
    with pytest.raises(InputError, match="entry 1 names cause 'd', not one of c"):
        rd.known_disagreements(bad)
    bad.write_text(
        cause
        + cause.replace('"c"', '"e"')
        + '[[disagreement]]\ncase = "a"\nmetric = "b"\ncause = "c"\nlevel = "both"\n'
    )
    with pytest.raises(InputError, match="cause\\(s\\) e explain no row"):
        rd.known_disagreements(bad)


def _toy(ctx):
    return [
        Metric.within("", "force vs measured", 0.096, "N", 0.18, 0.018, "seed"),  # known
        Metric.within("", "stiffness", 2.0, "N/mm", 1.0, 0.1, "seed"),  # unexplained
        Metric.relative("", "length", 1.02, "mm", 1.0, 0.05, "seed"),  # pass
        Metric.info("", "E fitted", 4.7, "GPa", f"{NOT_JUDGED}what-if", reference=2.5),
        Metric.info("", "E guessed", 4.7, "GPa", "forgot the reason", reference=2.5),
        Metric.info("", "iterations", 12.0, "-", "solver"),
    ]


@pytest.fixture
def toy_known(monkeypatch):
    monkeypatch.setitem(CASES, "toy_known", Case("toy_known", _toy, "toy", False, False))
    monkeypatch.setattr(rd, "known_disagreements", lambda: {(KNOWN.case, KNOWN.metric): KNOWN})


def test_summary_counts_and_lists_known_disagreements(toy_known, tmp_path):
    out = tmp_path / "v"
    assert (
        cli_main(["validate", "toy_known", "--out", str(out), "--quiet"]) == 0
    )  # failing rows: exit 0
    rows = json.loads((out / "metrics.json").read_text())
    assert report.count_rows(rows) == {
        "judged": 3,
        "passed": 1,
        "failed": 2,
        "known": 1,
        "info with reference": 2,
        "info with reference, no reason": 1,
        "info without reference": 1,
    }
    md = (out / "report.md").read_text()
    assert md.index("## Summary") < md.index("## Metrics")
    assert "Judged 3: 1 pass, 2 fail (1 known disagreements from 1 causes, 1 unexplained)" in md
    assert "(1 without a reason to stay unjudged)" in md
    # worst error is the unexplained stiffness (+100 %), not the known -47 %
    assert "| toy_known | done | 3 | 1 | 2 (1) | 100.0 % |" in md
    # the causes table first (rows per case, missing datum), then each row in one line naming its
    # cause
    summary = md[md.index("## Summary") : md.index("## Metrics")]
    assert "### Known disagreements: 1 rows from 1 causes" in summary
    assert (
        "| The toy's modulus (`toy_modulus`) | 99 | 1: toy_known (1) | the toy's measured modulus |"
        in summary
    )
    assert (
        "- toy_known: force vs measured = 0.096 N vs 0.18 ± 0.018; `toy_modulus`: 0.096 N against "
        "0.18 N" in summary
    )
    assert summary.index("| cause | issue | rows | missing datum |") < summary.index(
        "- toy_known: force"
    )
    assert "Controlled changes: a stiffer toy passes" in summary
    assert "| FAIL (known: toy_modulus) |" in md
    assert "| stiffness | 2 | N/mm | 1 ± 0.1 | +100.00 % | FAIL |" in md


def test_worst_error_marks_a_known_disagreement(monkeypatch):
    monkeypatch.setattr(rd, "known_disagreements", lambda: {(KNOWN.case, KNOWN.metric): KNOWN})
    rows = [Metric.within("toy_known", "force vs measured", 0.096, "N", 0.18, 0.018, "s").as_dict()]
    res = report.CaseResult("toy_known", "toy", "done", 1.0, metrics=rows)
    assert "| toy_known | done | 1 | 0 | 1 (1) | 46.7 % * | 1.0 | 0/0 |" in report.summary_lines(
        [res]
    )


def test_not_judged_prefixes_only_informative_rows_with_a_reference():
    rows = not_judged(
        [
            Metric.info("c", "a", 1.0, "-", "src", reference=2.0),
            Metric.info("c", "b", 1.0, "-", "src"),
            Metric.within("c", "d", 1.0, "-", 1.0, 0.1, "src"),
        ],
        "model vs model",
    )
    assert [m.source for m in rows] == [f"{NOT_JUDGED}model vs model; src", "src", "src"]


def test_a_registered_row_that_passes_is_reported_as_stale(monkeypatch):
    monkeypatch.setattr(rd, "known_disagreements", lambda: {(KNOWN.case, KNOWN.metric): KNOWN})
    rows = [Metric.within("toy_known", "force vs measured", 0.18, "N", 0.18, 0.018, "s").as_dict()]
    text = "\n".join(
        report.summary_lines([report.CaseResult("toy_known", "toy", "done", 1.0, metrics=rows)])
    )
    assert "### Known disagreements: 0 rows from 0 causes" in text
    assert "pass in this run (remove them from the registry): toy_known: force vs measured." in text


def test_headline_counts_keep_metrics_named_with_a_parenthesis():
    """A metric named "(a) ..." is a metric, not the status row of a case that did not finish."""
    rows = [Metric.within("toy", "(a) curvature, FE vs DER", 1.0, "1/mm", 1.0, 0.1, "s").as_dict()]
    done = report.CaseResult("toy", "toy", "done", 1.0, metrics=rows)
    failed = report.CaseResult("toy2", "toy", "error", 1.0, error="boom")
    text = report.render_report(
        [done, failed], command="lcefem validate", quick=True, total_wall=1.0
    )
    assert "Judged 1: 1 pass, 0 fail" in text
    assert report.is_status_row(failed.error_row()) and not report.is_status_row(rows[0])


def test_a_quick_only_entry_is_stale_only_at_the_quick_level(monkeypatch):
    """An entry registered for the quick level (the row fails there) may pass at the full level
    without being stale; passing at the quick level makes it stale."""
    quick_only = dataclasses.replace(KNOWN, level="quick")
    monkeypatch.setattr(rd, "known_disagreements", lambda: {(KNOWN.case, KNOWN.metric): quick_only})
    rows = [Metric.within("toy_known", "force vs measured", 0.18, "N", 0.18, 0.018, "s").as_dict()]
    for quick, stale in ((False, False), (True, True)):
        res = report.CaseResult("toy_known", "toy", "done", 1.0, metrics=rows, quick=quick)
        text = "\n".join(report.summary_lines([res]))
        assert ("pass in this run (remove them from the registry)" in text) is stale
