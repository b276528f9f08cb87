"""Convergence of the rolling ribbon's speed in nodes and time step (issue 32).

    nice python benchmarks/ribbon_convergence.py --out rows.jsonl [--duration 40]
        [--contact-spacing 0.25] [--set numerics.cells_thickness=4 ...] T,nodes,dt [T,nodes,dt ...]
    python benchmarks/ribbon_convergence.py --table rows.jsonl [more.jsonl ...]
        --csv validation/data/ribbon_convergence.csv
    nice python benchmarks/ribbon_convergence.py --issue-table --out rows.jsonl
        --csv table.csv [--processes 2]

The third form is issue 32's table in one command: every plate of ``ISSUE_PLATES`` x nodes of
``ISSUE_NODES`` x step of ``ISSUE_STEPS`` at the converged settings (``ISSUE_SETTINGS``: 180 s, 0.25
mm contact sections, 4 thickness cells; ``--duration``, ``--contact-spacing`` and ``--set`` override
them), the runs not yet in ``--out`` only (a stopped sweep resumes), ``--processes`` at once, then
the CSV of the second form from ``--out``.

The first form runs the default ribbon (``RibbonConfig()``: the seed-000 ribbon LCE with its twist
locked, 60 x 4 x 0.8 mm, 0.05 turns/mm) on a plate at T [C] with the given rod nodes and fixed step
dt [s] for ``--duration`` seconds after settling, and appends one JSON row per run (rolling metrics
of the last half: average speed, end spin rates, twist-density variation; CPU seconds) to ``--out``;
several processes may share the work. ``--set section.field=value`` changes one field of
``RibbonConfig`` for every run (as in ``ribbon_heat_study``); the rows record the changes. The
second form writes the CSV table (units in the headers) with the relative change of each speed
against the run at half its step and against the next node count.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import pathlib
import sys
import time

# One BLAS thread (see ribbon_heat_study: a threaded BLAS on a loaded machine cost 40x in
# natural_strains).
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

COLUMNS = [
    "average_speed [mm/s]",
    "rolls",
    "spin_rate_start [rad/s]",
    "spin_rate_end [rad/s]",
    "spin_rate_ratio [-]",
    "twist_density_mean [turns/mm]",
    "twist_density_variation [-]",
    "T_mean_final [C]",
]


def run(
    out: pathlib.Path,
    duration: float,
    jobs: list[tuple[float, int, float]],
    contact_spacing: float = 0.0,
    changes: list[str] | None = None,
) -> None:
    from lcefem.solvers.der.ribbon import RibbonNumerics
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, RibbonRun, run_ribbon
    from lcefem.validation.app.config import assign_or_exit

    changes = list(changes or [])
    for T, nodes, dt in jobs:
        cfg = RibbonConfig(
            run=RibbonRun(ground_temperature=T, duration=duration, output_interval=0.0),
            numerics=dataclasses.replace(
                RibbonNumerics(), nodes=nodes, dt=dt, contact_spacing=contact_spacing
            ),
        )
        for c in changes:
            cfg = assign_or_exit(cfg, c)
        t0 = time.process_time()
        m = run_ribbon(cfg, None, progress=False, fields=False).metrics
        row = {k: float(m[k]) for k in COLUMNS}
        row.update(
            {
                "T": T,
                "nodes": nodes,
                "dt": dt,
                "duration": duration,
                "contact_spacing": contact_spacing,
                "changes": changes,
                "cpu": time.process_time() - t0,
            }
        )
        with open(out, "a") as f:
            f.write(json.dumps(row) + "\n")


#: Issue 32 point 3: speed against node count and step at four plates [C], nodes, steps [s]. The
#: steps halve from 0.01 s; with 0.25 mm contact sections 0.01 s shows the sampling lock
#: (docs/ribbon.md).
ISSUE_PLATES = (60.0, 100.0, 140.0, 180.0)
ISSUE_NODES = (31, 61, 101)
ISSUE_STEPS = (0.01, 0.005, 0.0025)
#: The converged table's settings (validation/data/ribbon_convergence_cells4.csv): 180 s on the
#: plate, contact sections 0.25 mm apart, 4 heat cells through the thickness.
ISSUE_SETTINGS = {
    "duration": 180.0,
    "contact_spacing": 0.25,
    "changes": ["numerics.cells_thickness=4"],
}


def issue_table(
    out: pathlib.Path,
    csv: pathlib.Path,
    duration: float,
    contact_spacing: float,
    changes: list[str],
    processes: int = 1,
) -> None:
    """Runs the grid ``ISSUE_PLATES`` x ``ISSUE_NODES`` x ``ISSUE_STEPS`` (those not yet in ``out``
    with the same duration, spacing and changes), ``processes`` at a time, then ``table(out,
    csv)``."""
    done = set()
    if out.exists():
        for line in open(out):
            if line.strip():
                r = json.loads(line)
                if (r["duration"], r.get("contact_spacing", 0.0), r.get("changes", [])) == (
                    duration,
                    contact_spacing,
                    changes,
                ):
                    done.add((r["T"], int(r["nodes"]), r["dt"]))
    jobs = [
        (T, n, dt)
        for T in ISSUE_PLATES
        for n in ISSUE_NODES
        for dt in ISSUE_STEPS
        if (T, n, dt) not in done
    ]
    # the costliest first (most nodes, smallest step), so the processes finish together
    jobs.sort(key=lambda j: -j[1] / j[2])
    print(f"{len(jobs)} runs to do ({len(done)} already in {out})", flush=True)
    if processes > 1 and len(jobs) > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(processes) as pool:
            for f in [pool.submit(run, out, duration, [j], contact_spacing, changes) for j in jobs]:
                f.result()
    else:
        run(out, duration, jobs, contact_spacing, changes)
    table([out], csv)


def _change(value: float, reference: dict | None) -> float:
    """(value - reference speed)/reference speed; nan without a reference or when it does not
    roll."""
    if reference is None or not reference["rolls"] or abs(reference["average_speed [mm/s]"]) < 1e-3:
        return float("nan")
    return (value - reference["average_speed [mm/s]"]) / reference["average_speed [mm/s]"]


def lock_rate(nodes: int, dt: float, contact_spacing: float) -> float:
    """Spin rate [rad/s] at which the plate contact passes one contact section per step: the twisted
    edge turns 2 pi tau_0 s per section of as-built spacing s (tau_0 the built twist density
    [turns/mm]; the locked twist keeps it per as-built length), so 2 pi tau_0 s / dt. A run whose
    end spin rate equals it (or a whole multiple) rolls in step with the contact sampling, a
    numerical lock (docs/ribbon.md)."""
    from lcefem.solvers.der.ribbon import RibbonNumerics, contact_samples_per_edge
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig

    g = RibbonConfig().geometry
    num = dataclasses.replace(RibbonNumerics(), nodes=nodes, contact_spacing=contact_spacing)
    s = g.length / (nodes - 1) / contact_samples_per_edge(num, g.length)
    return 2.0 * math.pi * g.twist_density * s / dt


def table(paths: list[pathlib.Path], csv: pathlib.Path) -> None:
    """CSV of every run with the relative change of its speed against the run at half its step (same
    nodes) and against the run with the next larger node count (same step), both of the same
    duration, and its end spin rate over the contact-sampling lock rate (``lock_rate``)."""
    rows = [json.loads(line) for p in paths for line in open(p) if line.strip()]
    # one row per (T, nodes, dt, duration, contact spacing): a run repeated by two processes is
    # deterministic
    for r in rows:
        r.setdefault("contact_spacing", 0.0)
        r["cs"] = (
            r["contact_spacing"],
            " ".join(r.get("changes", [])),
        )  # the run's settings besides T, nodes, dt
    rows = list(
        {(r["T"], int(r["nodes"]), r["dt"], r["duration"], r["cs"]): r for r in rows}.values()
    )
    rows.sort(key=lambda r: (r["cs"], r["duration"], r["T"], r["nodes"], -r["dt"]))
    by = {(r["T"], int(r["nodes"]), r["dt"], r["duration"], r["cs"]): r for r in rows}
    header = [
        "changes [-]",
        "plate temperature [C]",
        "nodes [-]",
        "dt [s]",
        "duration [s]",
        "contact spacing [mm]",
        "average speed [mm/s]",
        "rolls [-]",
        "change against half the step [-]",
        "change against the next node count [-]",
        "end spin-rate ratio [-]",
        "twist density variation [-]",
        "T mean final [C]",
        "CPU [s]",
        "spin rate over the sampling lock rate [-]",
    ]
    lines = [",".join(header)]
    for r in rows:
        T, n, dt, dur, cs = r["T"], int(r["nodes"]), r["dt"], r["duration"], r["cs"]
        finer_nodes = sorted(
            m
            for (T2, m, d2, u2, c2) in by
            if T2 == T and d2 == dt and u2 == dur and c2 == cs and m > n
        )
        v = r["average_speed [mm/s]"]
        lines.append(
            ",".join(
                f"{x:.6g}" if isinstance(x, float) else str(x)
                for x in (
                    cs[1] or "defaults",
                    T,
                    n,
                    dt,
                    dur,
                    cs[0],
                    v,
                    r["rolls"],
                    _change(v, by.get((T, n, dt / 2, dur, cs))),
                    _change(v, by.get((T, finer_nodes[0], dt, dur, cs)) if finer_nodes else None),
                    r["spin_rate_ratio [-]"],
                    r["twist_density_variation [-]"],
                    r["T_mean_final [C]"],
                    r["cpu"],
                    abs(r["spin_rate_start [rad/s]"]) / lock_rate(n, dt, cs[0]),
                )
            )
        )
    tmp = csv.with_suffix(".csv.part")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, csv)


def plot(paths: list[pathlib.Path], png: pathlib.Path) -> None:
    """PNG of the average speed against plate temperature, one curve per (nodes, dt, duration), with
    the ~55 C threshold reported for the real ribbons (press release on Zhao et al. 2022)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lcefem.validation.app.plots import save_figure

    rows = [json.loads(line) for p in paths for line in open(p) if line.strip()]
    groups: dict[tuple, list] = {}
    for r in rows:
        groups.setdefault((int(r["nodes"]), r["dt"], r["duration"]), []).append(r)
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for (n, dt, dur), rs in sorted(groups.items()):
        rs.sort(key=lambda r: r["T"])
        ax.plot(
            [r["T"] for r in rs],
            [r["average_speed [mm/s]"] for r in rs],
            "o-",
            label=f"{n} nodes, {dt:g} s, {dur:g} s run (last half)",
        )
    ax.axvline(55.0, color="k", ls="--", lw=1, label="reported threshold, 'at least 55 C'")
    ax.set_xlabel("plate temperature [C]")
    ax.set_ylabel("average rolling speed [mm/s]")
    ax.set_title("DER ribbon, seed-000 ribbon LCE (seed: 'warmer surface, faster')", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, png, 120)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("jobs", nargs="*", help="T,nodes,dt")
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("--duration", type=float, default=40.0)
    ap.add_argument(
        "--contact-spacing",
        type=float,
        default=0.0,
        help="[mm] RibbonNumerics.contact_spacing of the runs (0: contact_samples per edge)",
    )
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        dest="changes",
        help="section.field=value: a change of RibbonConfig for every run (e.g. "
        "numerics.cells_thickness=4)",
    )
    ap.add_argument("--table", type=pathlib.Path, nargs="*")
    ap.add_argument("--csv", type=pathlib.Path)
    ap.add_argument(
        "--plot", type=pathlib.Path, help="with --table: also a PNG of speed against temperature"
    )
    ap.add_argument(
        "--issue-table",
        action="store_true",
        help="run issue 32's grid (ISSUE_PLATES x ISSUE_NODES x ISSUE_STEPS, ISSUE_SETTINGS) into "
        "--out "
        "and write --csv",
    )
    ap.add_argument("--processes", type=int, default=1, help="with --issue-table: runs at once")
    a = ap.parse_args(argv)
    if a.issue_table:
        if a.out is None or a.csv is None:
            print("--issue-table: needs --out and --csv", file=sys.stderr)
            return 2
        if a.processes < 1:
            print(f"--processes = {a.processes}: must be >= 1", file=sys.stderr)
            return 2
        given = argv if argv is not None else sys.argv[1:]
        duration = a.duration if "--duration" in given else ISSUE_SETTINGS["duration"]
        spacing = (
            a.contact_spacing if "--contact-spacing" in given else ISSUE_SETTINGS["contact_spacing"]
        )
        changes = a.changes or list(ISSUE_SETTINGS["changes"])
        issue_table(a.out, a.csv, duration, spacing, changes, a.processes)
        return 0
    if a.table:
        if a.csv is None:
            print("--csv: needed with --table", file=sys.stderr)
            return 2
        table(a.table, a.csv)
        if a.plot is not None:
            plot(a.table, a.plot)
        return 0
    if a.out is None or not a.jobs:
        print("--out and at least one T,nodes,dt job are needed", file=sys.stderr)
        return 2
    try:
        jobs = [(float(t), int(n), float(d)) for t, n, d in (j.split(",") for j in a.jobs)]
    except ValueError:
        print("jobs: each must be T,nodes,dt (e.g. 100,60,0.01)", file=sys.stderr)
        return 2
    run(a.out, a.duration, jobs, a.contact_spacing, a.changes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
