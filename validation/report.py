"""Results of validation cases and the Markdown report that strings them together.

:class:`CaseResult` is what ``lcefem validate`` keeps per case (and writes, as JSON, to the case's
completion marker ``DIR/<case>/metrics.json``); :func:`write_report` writes ``DIR/report.md``: the
command, the software versions, a summary, the table of all metrics with pass/fail, and per case its
wall time, figures (with captions naming their sources) and errors.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import json
import math
import pathlib
import platform
from dataclasses import asdict, dataclass, field

import numpy as np

from lcefem.solvers.run import write_text

METRIC_KEYS = ("case", "metric", "value", "unit", "reference", "tolerance", "passed", "source")
#: done (this run), reused (--resume), failed (the solver failed or a result left its physical bounds),
#: error (any other exception), interrupted (Ctrl-C, SIGTERM), not run (selected, never started).
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
    error: str = ""  #: one line; the traceback is in DIR/<case>/error.log
    finished: str = ""  #: ISO time

    def as_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> "CaseResult":
        return cls(**{k: d[k] for k in cls.__dataclass_fields__ if k in d})

    def error_row(self) -> dict:
        """A metrics.json row standing for a case that did not finish (passed = False)."""
        return {"case": self.case, "metric": f"({self.status})", "value": None, "unit": "",
                "reference": None, "tolerance": None, "passed": False, "source": self.error}


def json_safe(obj):
    """Plain Python types (numpy scalars unwrapped), non-finite floats as None: strict JSON."""
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    return obj


def write_text_atomic(path: pathlib.Path, text: str) -> pathlib.Path:
    """Write to ``path.part`` and rename, so a reader never sees a half-written file."""
    return write_text(path, text)


def write_json_atomic(path: pathlib.Path, obj) -> pathlib.Path:
    return write_text_atomic(path, json.dumps(json_safe(obj), indent=1, allow_nan=False) + "\n")


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


def fmt_pass(row: dict) -> str:
    if row.get("metric", "").startswith("(") and row.get("value") is None:
        return row["metric"].strip("()").upper()
    return {True: "pass", False: "FAIL", None: "info"}[row.get("passed")]


def versions() -> dict[str, str]:
    """Versions of lcefem, dolfinx (the dolfinx-solver-real wheel), numpy, scipy and Python."""
    out = {"python": platform.python_version()}
    for name, dist in (("lcefem", "lcefem"), ("dolfinx", "dolfinx-solver-real"),
                       ("numpy", "numpy"), ("scipy", "scipy"), ("matplotlib", "matplotlib"),
                       ("pyvista", "pyvista")):
        try:
            out[name] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def _md_cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def render_report(results: list[CaseResult], *, command: str, quick: bool, total_wall: float,
                  title: str = "lcefem validation report") -> str:
    """The Markdown text of the report (figure paths relative to the report's folder)."""
    rows = all_rows(results)
    n_pass = sum(r["passed"] is True for r in rows)
    n_fail = sum(r["passed"] is False and r["value"] is not None for r in rows)
    n_info = sum(r["passed"] is None for r in rows)
    unfinished = [r for r in results if r.status not in FINISHED]
    ver = versions()
    now = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
    lines = [f"# {title}", "",
             f"- command: `{command}`",
             f"- resolution: {'quick (coarse, CI)' if quick else 'default'}",
             f"- written: {now}; total wall time {total_wall:.1f} s",
             "- versions: " + ", ".join(f"{k} {v}" for k, v in ver.items()),
             "",
             f"**{len(results)} cases: {n_pass} metrics pass, {n_fail} fail, {n_info} informative; "
             f"{len(unfinished)} cases did not finish"
             + (f": this report is INCOMPLETE ({', '.join(f'{r.case}: {r.status}' for r in unfinished)}).**"
                if unfinished else ".**"), "",
             "| case | state |", "|---|---|",
             *(f"| {r.case} | {r.status} |" for r in results), "",
             "## Metrics", "",
             "Pass means |value - reference| <= tolerance (a range [lo, hi] is lo <= value <= hi). Error is "
             "(value - reference)/|reference| against a target, or (value - reference)/tolerance "
             "(\"tol\") against a range or a zero target; informative rows have no pass/fail.",
             "",
             "| case | metric | value | unit | reference ± tolerance | error | pass | source |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| " + " | ".join(_md_cell(c) for c in (
            r["case"], r["metric"], fmt_number(r["value"]), r["unit"], fmt_reference(r), fmt_error(r),
            fmt_pass(r), r["source"])) + " |")
    lines += ["", "## Cases", ""]
    fig_no = 0
    for res in results:
        lines.append(f"### {res.case}")
        lines.append("")
        if res.description:
            lines.append(res.description)
            lines.append("")
        status = {"done": "completed in this run", "reused": "reused from an earlier run (--resume)",
                  "failed": "FAILED: the solver failed or a result left its physical bounds",
                  "error": "FAILED with an error", "interrupted": "interrupted",
                  "not run": "not run (the run stopped before this case)"}[res.status]
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
    return write_text_atomic(path, render_report(results, **kwargs))
