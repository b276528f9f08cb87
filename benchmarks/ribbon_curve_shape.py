"""Controlled change of the shape of the ribbon LCE's contraction curve a(T) (issue 32, what-if).

    nice python benchmarks/ribbon_curve_shape.py --curve HTNI --out rows.jsonl
        --plates 100,140,180 [--nodes 101] [--duration 180] [--perturbation 1.0]

The ribbon's a(T) (``models.lce.contraction_ratio`` of ``RibbonLCE``: a logistic order parameter,
T_NI 80 C, width 15 K, assumed) is replaced by the *shape* of a measured free-strain curve of
another LCE, keeping the ribbon's amplitude: a(T) = 1 - (1 - 1/lambda_N) f(T), with f(T) = (1 -
L(T)) / (1 - min L) the normalised contraction of the measured free stretch L(T) = L(T)/L(25 C)
(monotone cubic interpolation, PCHIP; f = 0 below 25 C and f(150 C) above 150 C). The two curves are
the printed LCE inks of validation/data/ribbon_lce_literature.toml (Kotikian et al., Adv. Mater.
2024; the public data of ``bertoldi-collab/morphing-lattices``): "LTNI" contracts steeply at 35-50 C
and is saturated by 60 C, "HTNI" contracts gently at 40-60 C and keeps contracting up to ~125 C.
Neither is the ribbons' material: the runs only show how the threshold and the hot plates depend on
where the curve is steep, which is the datum issue 32 misses. Every other value is the default; runs
use the converged heat and contact settings (``ribbon_material_scan.CONVERGED``). One JSON row per
run is appended to ``--out`` (``ribbon_convergence.run``) with ``changes`` naming the curve.

The curves are read from validation/data/curves/kotikian2024_<name>.csv (the same rows as the
literature file); the shaped a(T) goes to the ribbon through its case-file option ``material.curve``
(a CSV, ``<out>.<name>.curve.csv``, sampled at the nodes of the ribbon's a(T) table,
``solvers.der.ribbon.CONTRACTION_TABLE``, every 0.05 K from 25 to 150 C: the ribbon's table then
holds the same values as when this study replaced the table in code, and the runs give the same
numbers).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

CURVE_FILES = pathlib.Path(__file__).resolve().parents[1] / "validation" / "data" / "curves"
CURVES = ("LTNI", "HTNI")


def measured_curve(name: str) -> tuple[list[float], list[float]]:
    """(temperatures [C], free stretch L(T)/L(25 C) [-]) of the printed ink ``name`` (LTNI or
    HTNI)."""
    from lcefem.solvers.contraction_curve import read_contraction_csv

    curve = read_contraction_csv(CURVE_FILES / f"kotikian2024_{name}.csv")
    return list(curve.temperatures), list(curve.values)


def contraction_of_shape(name: str, lambda_N: float):
    """a(T) [-] with the ribbon's amplitude 1 - 1/lambda_N and the normalised shape of curve
    ``name``."""
    import numpy as np
    from scipy.interpolate import PchipInterpolator

    T, L = (np.asarray(v, float) for v in measured_curve(name))
    f = PchipInterpolator(T, (1.0 - L) / (1.0 - L.min()))
    amplitude = 1.0 - 1.0 / lambda_N

    def a(temperature):
        t = np.clip(np.asarray(temperature, float), T[0], T[-1])
        return 1.0 - amplitude * f(t)

    return a


def shaped_curve_file(name: str, lambda_N: float, path: pathlib.Path) -> pathlib.Path:
    """Write a(T) of :func:`contraction_of_shape` as a curve CSV at ``path``: rows at 25 and 150 C
    and at every node of the ribbon's a(T) table between them (``CONTRACTION_TABLE``: the same
    floats), so the ribbon's table of the piecewise-linear curve equals the former table of a(T)
    node for node."""
    import numpy as np

    from lcefem.models.lce import MeasuredContraction
    from lcefem.solvers.contraction_curve import write_contraction_csv
    from lcefem.solvers.der.ribbon import CONTRACTION_TABLE

    lo, hi, h = CONTRACTION_TABLE
    T_data = measured_curve(name)[0]
    nodes = lo + h * np.arange(
        -1, int(np.ceil((hi - lo) / h)) + 2
    )  # as TabulatedLaw.of places them
    T = np.concatenate(
        [[T_data[0]], nodes[(nodes > T_data[0]) & (nodes < T_data[-1])], [T_data[-1]]]
    )
    a = contraction_of_shape(name, lambda_N)(T)
    source = (
        f"shape of the printed ink {name}'s free stretch (Kotikian et al. 2024, "
        f"validation/data/curves/kotikian2024_{name}.csv, PCHIP) with the ribbon's amplitude "
        f"1 - 1/lambda_N, lambda_N = {lambda_N:g}; benchmarks/ribbon_curve_shape.py"
    )
    return write_contraction_csv(path, MeasuredContraction.from_rows(T, a, source=source))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--curve", choices=CURVES, required=True)
    ap.add_argument("--out", type=pathlib.Path, required=True)
    ap.add_argument("--plates", required=True, help="plate temperatures [C], comma separated")
    ap.add_argument("--nodes", type=int, default=101)
    ap.add_argument("--dt", type=float, default=0.005)
    ap.add_argument("--duration", type=float, default=180.0)
    ap.add_argument("--perturbation", type=float, default=0.01, help="initial spin [rad/s]")
    args = ap.parse_args(argv)
    try:
        plates = [float(p) for p in args.plates.split(",")]
    except ValueError:
        print(
            f"--plates = {args.plates!r}: allowed comma-separated temperatures in C",
            file=sys.stderr,
        )
        return 2
    if args.nodes < 3 or args.dt <= 0 or args.duration <= 0:
        print("--nodes >= 3, --dt > 0 and --duration > 0 are required", file=sys.stderr)
        return 2

    from lcefem.models.ribbon import SEED000_RIBBON
    from ribbon_convergence import run
    from ribbon_material_scan import CONTACT_SPACING, CONVERGED

    curve_file = shaped_curve_file(
        args.curve,
        SEED000_RIBBON.actuation_stretch,
        args.out.with_name(f"{args.out.name}.{args.curve}.curve.csv"),
    )
    extra = [f"material.curve={curve_file}"]
    extra += [] if args.perturbation == 0.01 else [f"numerics.perturbation={args.perturbation}"]
    scratch = args.out.with_name(args.out.name + ".part")
    for T in plates:
        scratch.unlink(missing_ok=True)
        run(scratch, args.duration, [(T, args.nodes, args.dt)], CONTACT_SPACING, CONVERGED + extra)
        row = json.loads(scratch.read_text().splitlines()[0])
        row["curve"] = args.curve
        with open(args.out, "a") as f:
            f.write(json.dumps(row) + "\n")
        print(
            f"{args.curve} {T:.0f} C: {row['average_speed [mm/s]']:.3f} mm/s, rolls "
            f"{row['rolls']:.0f}, "
            f"T mean {row.get('T_mean_final [C]', float('nan')):.1f} C, {row['cpu']:.0f} s CPU",
            flush=True,
        )
    scratch.unlink(missing_ok=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
