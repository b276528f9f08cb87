"""Controlled changes of the rolling ribbon's heat model and transition (issue 32: the threshold and
the fall above 120 C).

    nice python benchmarks/ribbon_heat_study.py --out rows.jsonl [--duration 120]
        [--window 15] [--nodes 61] [--dt 0.01] [--set section.field=value ...] T [T ...]
    python benchmarks/ribbon_heat_study.py --table rows.jsonl [more.jsonl ...]
        --csv validation/data/ribbon_heat_study.csv

Runs the default ribbon (``RibbonConfig()``) on a plate at each T [C] with the changes of ``--set``
(``numerics.cells_thickness=4``, ``ground_heat.boundary_layer=2``, ``material.transition_width=30``,
...; one parameter set for every plate) and appends one JSON row per run: per window of ``--window``
seconds the centroid speed [mm/s] (displacement over the window / its length), the mean section
temperature [C], the plate-side ("hot") and far ("cold") layer temperatures [C] (per section the
thickness layer with the highest / lowest width-averaged temperature, averaged over the sections),
the fibres' contraction 1 - a(T) of those two layers and its difference, the thermal (natural)
curvature of the sections from their temperature field (mean and largest over the sections [1/mm]:
the bending drive, ``models.ribbon.natural_strains``), and the contact points; plus the speed over
the last half and the CPU seconds.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import pathlib
import sys
import time

# One BLAS thread: the section resultants (models.ribbon.natural_strains) are two small matrix
# products per step, and with 4 or 8 cells through the thickness a threaded BLAS on a loaded machine
# spent 11 ms CPU per step on them instead of 0.26 ms (measured with cProfile, 61 nodes, 6 x 4
# cells, 2026-11-28).
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def layer_temperatures(sim):
    """Per-section hottest and coldest thickness layer (width-averaged) [C], each averaged over the
    sections."""
    g = sim.grid
    T = sim.T.reshape(len(sim.T), g.n_width, g.n_thickness).mean(axis=1)  # (edges, layers)
    return float(T.max(axis=1).mean()), float(T.min(axis=1).mean())


def run_one(
    T_plate: float, duration: float, window: float, nodes: int, dt: float, changes: list[str]
) -> dict:
    import numpy as np

    from lcefem.models.lce import contraction_ratio
    from lcefem.models.ribbon import natural_strains
    from lcefem.solvers.der.ribbon import RibbonSimulation
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, RibbonRun
    from lcefem.validation.app.config import assign_or_exit

    cfg = RibbonConfig(
        run=RibbonRun(ground_temperature=T_plate, duration=duration, output_interval=0.0)
    )
    cfg = dataclasses.replace(cfg, numerics=dataclasses.replace(cfg.numerics, nodes=nodes, dt=dt))
    for c in changes:
        cfg = assign_or_exit(cfg, c)
    cfg = cfg.validated()
    t0 = time.process_time()
    sim = RibbonSimulation(cfg.setup())
    a = cfg.material.transition()
    steps_per_window = int(round(window / dt))
    n_windows = int(round(duration / window))
    c_prev = sim.state.x.mean(axis=0)
    rows = []
    for k in range(n_windows):
        for _ in range(steps_per_window):
            sim.step(dt)
        c = sim.state.x.mean(axis=0)
        hot, cold = layer_temperatures(sim)
        e_hot = 1.0 - float(contraction_ratio(np.array([hot]), a)[0])
        e_cold = 1.0 - float(contraction_ratio(np.array([cold]), a)[0])
        ns = natural_strains(sim.T, sim.grid, a, sim.contraction)
        kappa = np.linalg.norm(
            ns.curvature, axis=1
        )  # thermal (natural) curvature per section [1/mm]
        rows.append(
            {
                "t_end [s]": round((k + 1) * window, 3),
                "speed [mm/s]": round(float(np.hypot(*(c - c_prev)[:2])) / window, 3),
                "T_mean [C]": round(float(sim.T.mean()), 2),
                "T_hot_layer [C]": round(hot, 2),
                "T_cold_layer [C]": round(cold, 2),
                "T_max [C]": round(float(sim.T.max()), 2),
                "contraction_hot [-]": round(e_hot, 4),
                "contraction_cold [-]": round(e_cold, 4),
                "contraction_difference [-]": round(e_hot - e_cold, 4),
                "natural_curvature_mean [1/mm]": round(float(kappa.mean()), 5),
                "natural_curvature_max [1/mm]": round(float(kappa.max()), 5),
                "contact_points [-]": int(sim.contact_count()),
            }
        )
        c_prev = c
    half = rows[len(rows) // 2 :]
    return {
        "T": T_plate,
        "nodes": nodes,
        "dt": dt,
        "duration": duration,
        "changes": changes,
        "speed_last_half [mm/s]": round(sum(r["speed [mm/s]"] for r in half) / len(half), 3),
        "windows": rows,
        "cpu [s]": round(time.process_time() - t0, 1),
    }


def table(paths: list[pathlib.Path], csv: pathlib.Path) -> None:
    """CSV with one line per run and window (units in the headers); a run repeated is kept once."""
    runs = {}
    for p in paths:
        for line in open(p):
            if line.strip():
                r = json.loads(line)
                runs[(r["T"], r["nodes"], r["dt"], r["duration"], tuple(r["changes"]))] = r
    keys = [
        "t_end [s]",
        "speed [mm/s]",
        "T_mean [C]",
        "T_hot_layer [C]",
        "T_cold_layer [C]",
        "T_max [C]",
        "contraction_difference [-]",
        "natural_curvature_mean [1/mm]",
        "natural_curvature_max [1/mm]",
        "contact_points [-]",
    ]
    lines = [
        ",".join(
            [
                "change [-]",
                "plate temperature [C]",
                "nodes [-]",
                "dt [s]",
                "duration [s]",
                "speed over the last half [mm/s]",
                "CPU [s]",
            ]
            + ["window " + k for k in keys]
        )
    ]
    for (T, n, dt, dur, changes), r in sorted(runs.items()):
        for w in r["windows"]:
            lines.append(
                ",".join(
                    [
                        " ".join(changes) or "defaults",
                        f"{T:g}",
                        str(n),
                        f"{dt:g}",
                        f"{dur:g}",
                        f"{r['speed_last_half [mm/s]']:g}",
                        f"{r['cpu [s]']:g}",
                    ]
                    + [str(w.get(k, "")) for k in keys]
                )
            )
    tmp = csv.with_suffix(".csv.part")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, csv)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("plates", nargs="*", type=float, help="plate temperatures [C]")
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("--table", type=pathlib.Path, nargs="*")
    ap.add_argument("--csv", type=pathlib.Path)
    ap.add_argument("--duration", type=float, default=120.0)
    ap.add_argument("--window", type=float, default=15.0)
    ap.add_argument("--nodes", type=int, default=61)
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--set", action="append", default=[], dest="changes")
    a = ap.parse_args(argv)
    if a.table:
        if a.csv is None:
            print("--csv: needed with --table", file=sys.stderr)
            return 2
        table(a.table, a.csv)
        return 0
    if a.out is None or not a.plates:
        print("--out and at least one plate temperature are needed", file=sys.stderr)
        return 2
    from lcefem.models.errors import InputError

    for T in a.plates:
        try:
            row = run_one(T, a.duration, a.window, a.nodes, a.dt, a.changes)
        except InputError as e:
            print(e, file=sys.stderr)
            return 2
        with open(a.out, "a") as f:
            f.write(json.dumps(row) + "\n")
        print(json.dumps({k: v for k, v in row.items() if k != "windows"}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
