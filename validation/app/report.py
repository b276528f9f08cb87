"""Results of validation cases and the Markdown report that strings them together.

:class:`CaseResult` is what ``lcefem validate`` keeps per case (and writes, as JSON, to the case's
completion marker ``DIR/<case>/metrics.json``); :func:`write_report` writes ``DIR/report.md``: the
command, the software versions, a one-screen summary (per case judged rows passed/failed and the
worst relative error, the phenomena shown; the known disagreements of
``validation/data/known_disagreements.toml`` met in the run grouped by cause: one table of the
causes with their rows and missing data, each row in one line naming its cause, then each cause's
statement and the controlled changes that show it), the phenomena each case must show at every level
(``validation/data/phenomena.toml``), the table of all metrics with pass/fail ("FAIL (known:
<cause>)" for a known disagreement), and per case its wall time, figures (with captions naming their
sources) and errors.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import math
import pathlib
import platform
from dataclasses import asdict, dataclass, field

from lcefem.solvers.runtime.files import write_text

METRIC_KEYS = ("case", "metric", "value", "unit", "reference", "tolerance", "passed", "source")
#: done (this run), reused (--resume), failed (the solver failed or a result left its physical
#: bounds), error (any other exception), interrupted (Ctrl-C, SIGTERM), not run (selected, never
#: started).
STATUSES = ("done", "reused", "failed", "error", "interrupted", "not run")
FINISHED = ("done", "reused")


@dataclass
class CaseResult:
    """One case's outcome; ``status`` one of :data:`STATUSES`."""

    case: str
    description: str
    status: str
    wall_time: float  #: seconds of the run that produced the metrics
    metrics: list[dict] = field(default_factory=list)  #: dicts with METRIC_KEYS
    figures: list[dict] = field(default_factory=list)  #: {"path": relative to DIR, "caption": str}
    quick: bool = False
    level: int | None = None
    mesh_size: float | None = None
    mesh_size_unit: str = ""
    #: the case's declared phenomena evaluated on its metrics
    #: (:func:`lcefem.validation.app.phenomena.evaluate`)
    phenomena: list[dict] = field(default_factory=list)
    error: str = ""  #: one line; the traceback is in DIR/<case>/error.log
    finished: str = ""  #: ISO time
    rank: int | None = (
        None  #: the MPI rank that ran the case under ``mpiexec -n N lcefem validate``
    )

    def as_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> "CaseResult":
        return cls(**{k: d[k] for k in cls.__dataclass_fields__ if k in d})

    def error_row(self) -> dict:
        """A metrics.json row standing for a case that did not finish (passed = False)."""
        return {
            "case": self.case,
            "metric": f"({self.status})",
            "value": None,
            "unit": "",
            "reference": None,
            "tolerance": None,
            "passed": False,
            "source": self.error,
        }


def all_rows(results: list[CaseResult]) -> list[dict]:
    """metrics.json rows: each case's metrics, or one error row for a case that did not finish."""
    rows = []
    for r in results:
        rows.extend(r.metrics if r.status in FINISHED else [r.error_row()])
    return rows


def fmt_number(v) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{v:.4g}"


def fmt_reference(row: dict) -> str:
    ref, tol = row.get("reference"), row.get("tolerance")
    if ref is None:
        return "-"
    if tol is None:
        return f"{ref:.4g}"
    if ref != 0 and abs(ref) <= tol * (1 + 1e-12):  # a range check lo <= value <= hi
        return f"[{ref - tol:.4g}, {ref + tol:.4g}]"
    return f"{ref:.4g} ± {tol:.3g}"


def fmt_error(row: dict) -> str:
    """(value - reference)/|reference| in % against a target; against a range or a zero target,
    (value - reference)/tolerance ("tol": |.| <= 1 passes)."""
    v, ref, tol = row.get("value"), row.get("reference"), row.get("tolerance")
    if v is None or ref is None or not math.isfinite(v):
        return "-"
    if ref != 0 and (tol is None or abs(ref) > tol):
        return f"{100.0 * (v - ref) / abs(ref):+.2f} %"
    if tol:
        return f"{(v - ref) / tol:+.2f} tol"
    return f"{v - ref:+.3g}"


def is_status_row(row: dict) -> bool:
    """The row standing for a case that did not finish (:meth:`CaseResult.error_row`: metric
    "(<status>)", no value), not a metric whose name merely starts with a parenthesis ("(a)
    ...")."""
    return row.get("value") is None and row.get("metric", "")[1:-1] in STATUSES


def fmt_pass(row: dict) -> str:
    if is_status_row(row):
        return row["metric"].strip("()").upper()
    known = known_disagreement(row) if row.get("passed") is False else None
    if known is not None:
        return f"FAIL (known: {known.cause.id})"
    return {True: "pass", False: "FAIL", None: "info"}[row.get("passed")]


NOT_JUDGED = (
    "not judged: "  # as lcefem.validation.cases.NOT_JUDGED (not imported: no case modules here)
)


def known_disagreement(row: dict):
    """The registered KnownDisagreement of a row, or None."""
    from lcefem.validation.cases.reference_data import known_disagreements

    return known_disagreements().get((row.get("case"), row.get("metric")))


def row_kind(row: dict) -> str:
    """pass | known (fails, a registered known disagreement) | FAIL (fails, unexplained) |
    info-reason (informative, has a reference, says why it is not judged) | info-no-reason (has a
    reference, no reason: to be fixed) | info (no reference)."""
    if row.get("passed") is True:
        return "pass"
    if row.get("passed") is False:
        return "known" if known_disagreement(row) is not None else "FAIL"
    if row.get("reference") is None:
        return "info"
    return "info-reason" if NOT_JUDGED in (row.get("source") or "") else "info-no-reason"


def count_rows(rows: list[dict]) -> dict[str, int]:
    """Counts for the summary: judged, passed, failed (of which known), informative with a reference
    (of which with a reason) and informative without one."""
    kinds = [row_kind(r) for r in rows]
    return {
        "judged": sum(k in ("pass", "known", "FAIL") for k in kinds),
        "passed": kinds.count("pass"),
        "failed": kinds.count("known") + kinds.count("FAIL"),
        "known": kinds.count("known"),
        "info with reference": kinds.count("info-reason") + kinds.count("info-no-reason"),
        "info with reference, no reason": kinds.count("info-no-reason"),
        "info without reference": kinds.count("info"),
    }


def relative_error(row: dict) -> float | None:
    """|value - reference|/|reference| of a judged row with a non-zero target (not a range), else
    None."""
    v, ref, tol = row.get("value"), row.get("reference"), row.get("tolerance")
    if (
        row.get("passed") is None
        or ref is None
        or ref == 0
        or (tol is not None and abs(ref) <= tol)
    ):
        return None
    if v is None or not math.isfinite(v):
        return math.inf
    return abs(v - ref) / abs(ref)


def summary_lines(results: list["CaseResult"]) -> list[str]:
    """The one-screen summary: per case judged rows passed/failed and the worst relative error of
    its judged rows against a target, then the known disagreements met in this run, grouped by cause
    (:func:`causes_lines`)."""
    lines = [
        "## Summary",
        "",
        "Worst error: largest |value - reference|/|reference| over the case's judged rows with a "
        "target (not a range), against experiment, a published fit or a closed form as the row's "
        "source says; * marks a known disagreement. Wall time: the case's own run (for a reused "
        "case, the run that produced it). Phenomena: the qualitative physics the case must show at "
        "every level (validation/data/phenomena.toml), shown / declared.",
        "",
        "| case | state | judged | passed | failed (known) | worst error | wall time [s] | "
        "phenomena |",
        "|---|---|---|---|---|---|---|---|",
    ]
    met = []
    for res in results:
        rows = res.metrics if res.status in FINISHED else [res.error_row()]
        c = count_rows(rows)
        worst, worst_known = None, False
        for r in rows:
            e = relative_error(r)
            if e is not None and (worst is None or e > worst):
                worst, worst_known = e, known_disagreement(r) is not None
        met += [(r, known_disagreement(r)) for r in rows if row_kind(r) == "known"]
        w = "-" if worst is None else ("no value" if math.isinf(worst) else f"{100 * worst:.1f} %")
        shown = sum(p["holds"] for p in res.phenomena)
        ph = f"{shown}/{len(res.phenomena)}" if res.status in FINISHED else "-"
        if res.status in FINISHED and shown < len(res.phenomena):
            ph += " NOT SHOWN"
        lines.append(
            f"| {res.case} | {res.status} | {c['judged']} | {c['passed']} | "
            f"{c['failed']} ({c['known']}) | {w}{' *' if worst_known else ''} | "
            f"{res.wall_time:.1f} | {ph} |"
        )
    lines += causes_lines(met)
    # A registered disagreement whose row now passes is stale (the model was fixed, or the row
    # renamed): say so, so the registry does not keep excusing a row that no longer needs it.
    # An entry is stale only at the level it is registered for: a row expected to fail at the quick
    # level alone may pass at the full level.
    passed = {
        (r["case"], r["metric"], "quick" if res.quick else "full")
        for res in results
        if res.status in FINISHED
        for r in res.metrics
        if r.get("passed") is True
    }
    stale = [
        k
        for key, k in known_disagreements_registry().items()
        if any(
            (*key, lv) in passed for lv in (("quick", "full") if k.level == "both" else (k.level,))
        )
    ]
    if stale:
        lines += [
            "",
            "Registered disagreements that pass in this run (remove them from the registry): "
            + "; ".join(f"{k.case}: {k.metric}" for k in stale)
            + ".",
        ]
    return lines + [""]


def causes_lines(met: list[tuple[dict, object]]) -> list[str]:
    """The known disagreements met in a run, grouped by cause: one table of the causes (title,
    issue, rows per case, missing datum), then each row in one line naming its cause, then each
    cause's statement and the controlled changes that show it. ``met``: (row, KnownDisagreement)
    pairs."""
    by_cause: dict[str, list[tuple[dict, object]]] = {}
    for r, k in met:
        by_cause.setdefault(k.cause.id, []).append((r, k))
    lines = [
        "",
        f"### Known disagreements: {len(met)} rows from {len(by_cause)} causes",
        "",
        "Each cause is one physical gap between the model and its reference, with the datum that "
        "would decide it (registry: validation/data/known_disagreements.toml).",
        "",
    ]
    if not met:
        return lines + ["- none"]
    lines += ["| cause | issue | rows | missing datum |", "|---|---|---|---|"]
    for cid, pairs in by_cause.items():
        cause = pairs[0][1].cause
        per_case: dict[str, int] = {}
        for r, _ in pairs:
            per_case[r["case"]] = per_case.get(r["case"], 0) + 1
        rows = f"{len(pairs)}: " + ", ".join(f"{c} ({n})" for c, n in per_case.items())
        lines.append(
            "| "
            + " | ".join(
                _md_cell(c)
                for c in (f"{cause.title} (`{cid}`)", cause.issue, rows, cause.missing_datum)
            )
            + " |"
        )
    lines += ["", "Rows (value vs reference, cause: the row's own numbers):", ""]
    lines += [
        f"- {r['case']}: {r['metric']} = {fmt_number(r['value'])} {r['unit']} vs "
        f"{fmt_reference(r)}; "
        f"`{k.cause.id}`" + (f": {k.note}" if k.note else "")
        for cid in by_cause
        for r, k in by_cause[cid]
    ]
    lines += ["", "Causes:", ""]
    for cid, pairs in by_cause.items():
        cause = pairs[0][1].cause
        lines += [
            f"- **{cause.title}** (`{cid}`, issue {cause.issue}): {cause.statement} "
            f"Controlled changes: {cause.controlled_changes} Missing datum: {cause.missing_datum}"
        ]
    return lines


def phenomena_lines(results: list["CaseResult"]) -> list[str]:
    """The section listing every declared phenomenon of the finished cases: shown or NOT SHOWN, the
    values it was read from, and why it must hold."""
    lines = [
        "## Phenomena",
        "",
        "What each case must show at every resolution, quick and full alike "
        "(`validation/data/phenomena.toml`); a phenomenon NOT SHOWN means this level does not show "
        "the physics the case is about.",
        "",
        "| case | phenomenon | condition | values | shown | why |",
        "|---|---|---|---|---|---|",
    ]
    for res in results:
        if res.status not in FINISHED:
            continue
        for p in res.phenomena:
            values = (
                "; ".join(f"{k} = {fmt_number(v)}" for k, v in p["values"].items())
                or f"no metric matches {p['selector']}"
            )
            # the condition as a code span: its regular expression ([^)] ...) is not Markdown
            condition = "`" + _md_cell(f"{p['selector']} {p['condition']}") + "`"
            lines.append(
                "| "
                + " | ".join(
                    (
                        _md_cell(res.case),
                        _md_cell(p["phenomenon"]),
                        condition,
                        _md_cell(values),
                        "yes" if p["holds"] else "NOT SHOWN",
                        _md_cell(p["why"]),
                    )
                )
                + " |"
            )
    return lines + [""]


MODEL_VS_MODEL = "model vs model"  #: marks a row that compares two of our models (in its source)


def model_vs_model_lines(results: list["CaseResult"]) -> list[str]:
    """Rows comparing two of our own models (FE, bar-and-hinge, DER, closed forms of them), grouped:
    they say how far the reduced models can be trusted, not whether one agrees with experiment. A
    row with an agreed band is judged there; one without says in its source what is expected and
    why."""
    rows = [
        r
        for res in results
        if res.status in FINISHED
        for r in res.metrics
        if MODEL_VS_MODEL in (r.get("source") or "").lower()
    ]
    if not rows:
        return []
    lines = [
        "## Model vs model",
        "",
        "Our models against each other (3D FE, bar-and-hinge, Discrete Elastic Rods): judged "
        "where a "
        "band is agreed, else informative with the reason in the source.",
        "",
        "| case | metric | value | other model | error | pass | expected, and why |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            "| "
            + " | ".join(
                _md_cell(c)
                for c in (
                    r["case"],
                    r["metric"],
                    f"{fmt_number(r['value'])} {r['unit']}",
                    fmt_reference(r),
                    fmt_error(r),
                    fmt_pass(r),
                    r["source"],
                )
            )
            + " |"
        )
    return lines + [""]


def phenomena_count(results: list["CaseResult"]) -> tuple[int, int]:
    """(shown, declared) over the finished cases."""
    ph = [p for r in results if r.status in FINISHED for p in r.phenomena]
    return sum(p["holds"] for p in ph), len(ph)


def known_disagreements_registry() -> dict:
    from lcefem.validation.cases.reference_data import known_disagreements

    return known_disagreements()


def versions() -> dict[str, str]:
    """Versions of lcefem, dolfinx (the dolfinx-solver-real wheel), numpy, scipy and Python."""
    out = {"python": platform.python_version()}
    for name, dist in (
        ("lcefem", "lcefem"),
        ("dolfinx", "dolfinx-solver-real"),
        ("numpy", "numpy"),
        ("scipy", "scipy"),
        ("matplotlib", "matplotlib"),
        ("pyvista", "pyvista"),
    ):
        try:
            out[name] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def render_report(
    results: list[CaseResult],
    *,
    command: str,
    quick: bool,
    total_wall: float,
    title: str | None = None,
    ranks: int = 1,
) -> str:
    """The Markdown text of the report (figure paths relative to the report's folder); ``ranks``:
    the MPI ranks the cases were farmed over (1: one after the other). The default title names the
    level, so that the quick and full summaries copied into the documentation are two pages with two
    titles."""
    if title is None:
        title = f"lcefem validation report, {'quick' if quick else 'full'} level"
    rows = all_rows(results)
    n_pass = sum(r["passed"] is True for r in rows)
    n_fail = sum(r["passed"] is False and r["value"] is not None for r in rows)
    n_info = sum(r["passed"] is None for r in rows)
    counts = count_rows([r for r in rows if not is_status_row(r)])
    n_causes = len({known_disagreement(r).cause.id for r in rows if row_kind(r) == "known"})
    unfinished = [r for r in results if r.status not in FINISHED]
    ver = versions()
    now = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
    lines = [
        f"# {title}",
        "",
        f"- command: `{command}`",
        f"- resolution: {'quick (coarse, CI)' if quick else 'default'}",
        f"- written: {now}; total wall time {total_wall:.1f} s"
        + (f" on {ranks} MPI ranks (cases farmed, each case on one rank)" if ranks > 1 else ""),
        "- versions: " + ", ".join(f"{k} {v}" for k, v in ver.items()),
        "",
        f"**{len(results)} cases: {n_pass} metrics pass, {n_fail} fail, {n_info} informative; "
        f"{len(unfinished)} cases did not finish"
        + (
            ": this report is INCOMPLETE "
            f"({', '.join(f'{r.case}: {r.status}' for r in unfinished)}).**"
            if unfinished
            else ".**"
        ),
        "",
        f"Judged {counts['judged']}: {counts['passed']} pass, {counts['failed']} fail "
        f"({counts['known']} known disagreements from {n_causes} causes, "
        f"{counts['failed'] - counts['known']} unexplained); "
        f"informative {counts['info with reference']} with a reference "
        f"({counts['info with reference, no reason']} without a reason to stay unjudged), "
        f"{counts['info without reference']} without. "
        "Phenomena shown: {}/{}.".format(*phenomena_count(results)),
        "",
        *summary_lines(results),
        *phenomena_lines(results),
        *model_vs_model_lines(results),
        "## Metrics",
        "",
        "Pass means |value - reference| <= tolerance (a range [lo, hi] is lo <= value <= hi). "
        "Error is "
        "(value - reference)/|reference| against a target, or (value - reference)/tolerance "
        "(\"tol\") against a range or a zero target; informative rows have no pass/fail.",
        "",
        "| case | metric | value | unit | reference ± tolerance | error | pass | source |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            "| "
            + " | ".join(
                _md_cell(c)
                for c in (
                    r["case"],
                    r["metric"],
                    fmt_number(r["value"]),
                    r["unit"],
                    fmt_reference(r),
                    fmt_error(r),
                    fmt_pass(r),
                    r["source"],
                )
            )
            + " |"
        )
    lines += ["", "## Cases", ""]
    fig_no = 0
    for res in results:
        lines.append(f"### {res.case}")
        lines.append("")
        if res.description:
            lines.append(res.description)
            lines.append("")
        status = {
            "done": "completed in this run",
            "reused": "reused from an earlier run (--resume)",
            "failed": "FAILED: the solver failed or a result left its physical bounds",
            "error": "FAILED with an error",
            "interrupted": "interrupted",
            "not run": "not run (the run stopped before this case)",
        }[res.status]
        facts = [f"status: {status}", f"wall time: {res.wall_time:.2f} s"]
        if res.mesh_size is not None:
            facts.append(f"mesh size: {res.mesh_size:.4g} {res.mesh_size_unit}")
        lines.append("- " + "; ".join(facts))
        if res.error:
            lines.append(f"- error: `{_md_cell(res.error)}` (traceback in `{res.case}/error.log`)")
        lines.append("")
        for fig in res.figures:
            fig_no += 1
            lines.append(f"![Figure {fig_no}]({fig['path']})")
            lines.append("")
            lines.append(f"*Figure {fig_no}. {fig['caption']}*")
            lines.append("")
    return "\n".join(lines) + "\n"


def write_report(path: pathlib.Path, results: list[CaseResult], **kwargs) -> pathlib.Path:
    """Write :func:`render_report` to ``path`` atomically."""
    return write_text(path, render_report(results, **kwargs))
