"""A body's run against measurements: the ``[[compare]]`` entries of a case file
(docs/own_robot.md; the entries are checked, and their CSVs read and converted to lcefem's units,
by :func:`lcefem.solvers.problems.body_case.load_case` before any mesh is built).

For each entry the model's history of the observable is interpolated linearly in time at the
measured times inside the run (a steady run: its one state against every measured row), and the
deviation d_k = model(t_k) - measured_k is judged against the allowed deviation a_k: the absolute
tolerance, or the relative one times |measured_k|. The entry passes when |d_k| <= a_k at every
measured time; its judged row (:class:`lcefem.validation.cases.Metric`, as the validation cases'
rows) gives the model and measured values where |d_k| / a_k is largest, and the time there.

:func:`write_comparisons` writes one comparison plot per entry (:func:`lcefem.validation.app.plots.
comparison_plot`: the model's curve, the measurements with the tolerance as error bars),
``report.md`` through the validation report (:func:`lcefem.validation.app.report.write_report`) and
adds the rows to summary.json under ``comparisons``.
"""

from __future__ import annotations

import json
import math
import pathlib
import re

import numpy as np

from lcefem.solvers.runtime.files import write_json
from lcefem.validation.app import plots
from lcefem.validation.app.report import CaseResult, write_report
from lcefem.validation.cases import Metric


def judge(case, history: dict[str, np.ndarray], name: str | None = None) -> list[Metric]:
    """One judged row per ``[[compare]]`` entry of ``case`` against the run's ``history``
    ({"name [unit]": values}, "time [s]" among them; a steady run's one row has time inf)."""
    name = name or case_label(case)
    t_model = np.asarray(history["time [s]"], float)
    rows = []
    for c in case.compare:
        obs = c["observable"]
        unit = obs[:-1].rsplit(" [", 1)[1]
        y_model = np.asarray(history[obs], float)
        t_meas, y_meas = np.asarray(c["times [s]"]), np.asarray(c["values"])
        if not np.all(np.isfinite(t_model)):  # steady state: one state, every measured row
            t, model, measured = t_meas, np.full_like(y_meas, y_model[-1]), y_meas
        else:
            inside = (t_meas >= t_model[0] - 1e-9) & (t_meas <= t_model[-1] + 1e-9)
            t, measured = t_meas[inside], y_meas[inside]
            model = np.interp(t, t_model, y_model)
        source = (
            f"{c['source']} ({pathlib.Path(c['data']).name}; tolerance {c['tolerance']['text']})"
        )
        if t.size == 0:
            rows.append(
                Metric(
                    name,
                    f"{obs}: no measured time inside the run [{t_model[0]:g}, {t_model[-1]:g}] s",
                    math.nan,
                    unit,
                    None,
                    None,
                    False,
                    source,
                )
            )
            continue
        tol = c["tolerance"]
        allowed = (
            np.full_like(measured, tol["absolute"])
            if "absolute" in tol
            else tol["relative"] * np.abs(measured)
        )
        excess = np.abs(model - measured) / np.maximum(allowed, 1e-300)
        k = int(np.argmax(excess))
        where = "steady state" if not np.all(np.isfinite(t_model)) else f"t = {t[k]:g} s"
        row = Metric.within(
            name,
            f"{obs}: largest deviation ({where}, {t.size} measured points)",
            float(model[k]),
            unit,
            float(measured[k]),
            float(allowed[k]),
            source,
        )
        rows.append(row)
    return rows


def case_label(case) -> str:
    """The case's name in the report: its folder for a case.toml, else the file's stem."""
    return case.path.parent.name if case.path.stem == "case" else case.path.stem


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_")


def plot_entry(
    path: pathlib.Path, case, history: dict[str, np.ndarray], entry: dict
) -> pathlib.Path:
    """The model's history of the entry's observable and the measurements (tolerance as error
    bars)."""
    obs = entry["observable"]
    tol = entry["tolerance"]
    y = np.asarray(entry["values"])
    err = np.full_like(y, tol["absolute"]) if "absolute" in tol else tol["relative"] * np.abs(y)
    t_model = np.asarray(history["time [s]"], float)
    y_model = np.asarray(history[obs], float)
    t_meas = np.asarray(entry["times [s]"])
    if not np.all(np.isfinite(t_model)):  # steady: the state as a line over the measured times
        t_model, y_model = np.array([t_meas[0], t_meas[-1]]), np.full(2, y_model[-1])
    series = [
        plots.Series(t_model, y_model, f"lcefem body ({case.path.name})", kind="model"),
        plots.Series(t_meas, y, f"measured ± tolerance {tol['text']}", kind="experiment", yerr=err),
    ]
    return plots.comparison_plot(
        path,
        series,
        xlabel="time [s]",
        ylabel=obs,
        sources=[entry["source"]],
        title=f"{case_label(case)}: {obs}",
    )


def write_comparisons(case, result, out: pathlib.Path, command: str) -> list[Metric]:
    """Judge every ``[[compare]]`` entry, write its plot (``compare_<observable>.png``), report.md
    (the validation report of this one run) and the rows into summary.json; returns the rows."""
    out = pathlib.Path(out)
    rows = judge(case, result.history)
    figures = []
    for entry in case.compare:
        png = plot_entry(
            out / f"compare_{_slug(entry['observable'])}.png", case, result.history, entry
        )
        figures.append(
            {
                "path": png.name,
                "caption": plots.caption(
                    f"{entry['observable']}: the body's run (line) against measurements (markers, "
                    "the "
                    "tolerance "
                    f"{entry['tolerance']['text']} as error bars).",
                    [entry["source"]],
                ),
            }
        )
    wall = float(result.summary.get("wall_time [s]", 0.0))
    res = CaseResult(
        case_label(case),
        f"`lcefem run body` of {case.path}, compared with measurements ([[compare]] entries).",
        "done",
        wall,
        metrics=[r.as_dict() for r in rows],
        figures=figures,
    )
    write_report(
        out / "report.md",
        [res],
        command=command,
        quick=False,
        total_wall=wall,
        title=f"lcefem body report: {case.path.name}",
    )
    summary_path = out / "summary.json"
    if summary_path.is_file():
        summary = json.loads(summary_path.read_text())
        summary["comparisons"] = [r.as_dict() for r in rows]
        summary["comparisons_passed"] = all(r.passed for r in rows)
        write_json(summary_path, summary)
    return rows
