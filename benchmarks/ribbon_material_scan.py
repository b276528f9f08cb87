"""One-parameter scans of the ribbon LCE (``RibbonLCE``) against the plate temperature (issue 32).

    nice python benchmarks/ribbon_material_scan.py --out rows.jsonl [--duration 120]
        [--nodes 61] [--dt 0.005] [--perturbation 0.01] --plates 55,65 \
        material.transition_width=25 ...
    python benchmarks/ribbon_material_scan.py --table rows.jsonl [more.jsonl ...]
        --csv validation/data/ribbon_material_scan.csv

Each ``material.field=value`` is one point of a scan: that field alone changed, every other value
the ``RibbonLCE`` default (``material`` alone, i.e. ``--set`` nothing else, is the default point).
Every run uses the converged heat and contact settings of issue 32's table (4 thickness cells,
contact sections 0.25 mm apart; docs/ribbon.md, "The converged table") with the given nodes and
fixed step, on each plate temperature [C] for ``--duration`` s after settling; one JSON row per run
is appended to ``--out`` (``ribbon_convergence.run``: speed, end spin rates and twist-density
variation over the last half, mean temperature at the end, CPU seconds). ``--perturbation`` is the
initial spin [rad/s] (``RibbonNumerics.perturbation``; 1.0 picks the rolling branch where a still
one exists too, docs/ribbon.md). The second form writes the CSV (units in the headers), one row per
run.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

#: The converged heat and contact settings of issue 32's table (docs/ribbon.md).
CONVERGED = ["numerics.cells_thickness=4"]
CONTACT_SPACING = 0.25  # mm

UNITS = {"transition_width": "K", "actuation_stretch": "-", "T_NI": "C", "youngs_modulus": "MPa"}


def scan(
    out: pathlib.Path,
    points: list[str],
    plates: list[float],
    nodes: int,
    dt: float,
    duration: float,
    perturbation: float,
) -> None:
    from ribbon_convergence import run

    for point in points:
        change = [] if point == "material" else [point]
        extra = [] if perturbation == 0.01 else [f"numerics.perturbation={perturbation}"]
        for T in plates:
            run(out, duration, [(T, nodes, dt)], CONTACT_SPACING, CONVERGED + extra + change)


HEADER = [
    "parameter [-]",
    "value [unit of the parameter]",
    "unit [-]",
    "plate temperature [C]",
    "nodes [-]",
    "dt [s]",
    "duration [s]",
    "initial spin [rad/s]",
    "average speed [mm/s]",
    "rolls [-]",
    "end spin-rate ratio [-]",
    "twist density variation [-]",
    "T mean final [C]",
    "CPU [s]",
]


def table(paths: list[pathlib.Path], csv: pathlib.Path) -> None:
    rows = []
    for p in paths:
        rows += [json.loads(line) for line in p.read_text().splitlines() if line.strip()]
    lines = [",".join(HEADER)]
    keyed = []
    for r in rows:
        name, value, spin = "default", "", 0.01
        for c in r["changes"]:
            key, _, v = c.partition("=")
            if key.startswith("material."):
                name, value = key.split(".", 1)[1], v
            elif key == "numerics.perturbation":
                spin = float(v)
        if name == "default":
            value = ""
        unit = UNITS.get(name, "")
        keyed.append(
            (
                (name, float(value) if value else 0.0, r["T"], r["nodes"], r["dt"], spin),
                [
                    name,
                    value,
                    unit,
                    r["T"],
                    r["nodes"],
                    r["dt"],
                    r["duration"],
                    spin,
                    f'{r["average_speed [mm/s]"]:.4g}',
                    int(r["rolls"]),
                    f'{r["spin_rate_ratio [-]"]:.4g}',
                    f'{r["twist_density_variation [-]"]:.3g}',
                    f'{r["T_mean_final [C]"]:.4g}',
                    f'{r["cpu"]:.1f}',
                ],
            )
        )
    for _, row in sorted(keyed, key=lambda k: k[0]):
        lines.append(",".join(str(x) for x in row))
    tmp = csv.with_suffix(".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    tmp.replace(csv)
    print(f"{len(rows)} rows -> {csv}")


def plot(csv: pathlib.Path, png: pathlib.Path) -> None:
    """PNG of the speed against the plate temperature, one line per scan point (the finest run per
    plate)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lines = csv.read_text().splitlines()[1:]
    series: dict[str, dict[float, tuple[int, float]]] = {}
    for line in lines:
        f = line.split(",")
        label = "default" if f[0] == "default" else f"{f[0]} = {f[1]} {f[2]}".rstrip()
        T, nodes, v = float(f[3]), int(f[4]), float(f[8])
        if T not in series.setdefault(label, {}) or nodes > series[label][T][0]:
            series[label][T] = (nodes, v)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for label, pts in sorted(series.items()):
        T = sorted(pts)
        ax.plot(T, [pts[t][1] for t in T], "o-", label=label)
    ax.axvspan(45.0, 65.0, color="0.9", label="reported threshold 55 +- 10 C")
    ax.set_xlabel("plate temperature [C]")
    ax.set_ylabel("speed over the last half [mm/s]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    from lcefem.validation.app.plots import save_figure

    try:  # through the one figure writer: a .part name, no planted link followed
        save_figure(fig, pathlib.Path(png), 110)
    finally:
        plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "points",
        nargs="*",
        help="material.field=value (one scan point each) or 'material' (default)",
    )
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("--plates", default="65", help="plate temperatures [C], comma-separated")
    ap.add_argument("--nodes", type=int, default=61)
    ap.add_argument("--dt", type=float, default=0.005)
    ap.add_argument("--duration", type=float, default=120.0)
    ap.add_argument("--perturbation", type=float, default=0.01, help="initial spin [rad/s]")
    ap.add_argument("--table", nargs="+", type=pathlib.Path)
    ap.add_argument("--csv", type=pathlib.Path)
    ap.add_argument(
        "--png", type=pathlib.Path, help="with --table: also plot speed against plate temperature"
    )
    a = ap.parse_args(argv)
    if a.table:
        if a.csv is None:
            print("--csv: required with --table (the CSV to write)", file=sys.stderr)
            return 2
        table(a.table, a.csv)
        if a.png:
            plot(a.csv, a.png)
        return 0
    if a.out is None or not a.points:
        print("--out and at least one point (material.field=value) are required", file=sys.stderr)
        return 2
    for p in a.points:
        if p != "material" and not (p.startswith("material.") and "=" in p):
            print(f"point {p!r}: expected material.field=value or 'material'", file=sys.stderr)
            return 2
    scan(
        a.out,
        a.points,
        [float(x) for x in a.plates.split(",")],
        a.nodes,
        a.dt,
        a.duration,
        a.perturbation,
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
