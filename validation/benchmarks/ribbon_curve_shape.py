"""Controlled change of the shape of the ribbon LCE's contraction curve a(T) (issue 32, what-if only).

    nice python -m lcefem.validation.benchmarks.ribbon_curve_shape --curve HTNI --out rows.jsonl
        --plates 100,140,180 [--nodes 101] [--duration 180] [--perturbation 1.0]

The ribbon's a(T) (``models.lce.contraction_ratio`` of ``RibbonLCE``: a logistic order parameter, T_NI
80 C, width 15 K, assumed) is replaced by the *shape* of a measured free-strain curve of another LCE,
keeping the ribbon's amplitude: a(T) = 1 - (1 - 1/lambda_N) f(T), with f(T) = (1 - L(T)) / (1 - min L)
the normalised contraction of the measured free stretch L(T) = L(T)/L(25 C) (monotone cubic
interpolation, PCHIP; f = 0 below 25 C and f(150 C) above 150 C). The two curves are the printed LCE
inks of validation/data/ribbon_lce_literature.toml (Kotikian et al., Adv. Mater. 2024; the public data of
``bertoldi-collab/morphing-lattices``): "LTNI" contracts steeply at 35-50 C and is saturated by 60 C,
"HTNI" contracts gently at 40-60 C and keeps contracting up to ~125 C. Neither is the ribbons' material:
the runs only show how the threshold and the hot plates depend on where the curve is steep, which is
the datum issue 32 misses. Every other value is the default; runs use the converged heat and contact
settings (``ribbon_material_scan.CONVERGED``). One JSON row per run is appended to ``--out``
(``ribbon_convergence.run``) with ``changes`` naming the curve.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys
import tomllib

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

LITERATURE = pathlib.Path(__file__).resolve().parents[1] / "data" / "ribbon_lce_literature.toml"
CURVES = ("LTNI", "HTNI")


def measured_curve(name: str) -> tuple[list[float], list[float]]:
    """(temperatures [C], free stretch L(T)/L(25 C) [-]) of the printed ink ``name`` (LTNI or HTNI)."""
    data = tomllib.loads(LITERATURE.read_text())
    for entry in data.get("entry", []):
        if f"value_{name}" in entry:
            return list(entry["temperature"]), list(entry[f"value_{name}"])
    raise SystemExit(f"{LITERATURE}: no entry with value_{name}")


def contraction_of_shape(name: str, lambda_N: float):
    """a(T) [-] with the ribbon's amplitude 1 - 1/lambda_N and the normalised shape of curve ``name``."""
    import numpy as np
    from scipy.interpolate import PchipInterpolator

    T, L = (np.asarray(v, float) for v in measured_curve(name))
    f = PchipInterpolator(T, (1.0 - L) / (1.0 - L.min()))
    amplitude = 1.0 - 1.0 / lambda_N

    def a(temperature):
        t = np.clip(np.asarray(temperature, float), T[0], T[-1])
        return 1.0 - amplitude * f(t)

    return a


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
        print(f"--plates = {args.plates!r}: allowed comma-separated temperatures in C", file=sys.stderr)
        return 2
    if args.nodes < 3 or args.dt <= 0 or args.duration <= 0:
        print("--nodes >= 3, --dt > 0 and --duration > 0 are required", file=sys.stderr)
        return 2

    from lcefem.models.ribbon import SEED000_RIBBON
    from lcefem.solvers.der import ribbon as der_ribbon
    from lcefem.solvers.der.tabulated import TabulatedLaw
    from lcefem.validation.benchmarks.ribbon_convergence import run
    from lcefem.validation.benchmarks.ribbon_material_scan import CONTACT_SPACING, CONVERGED

    law = TabulatedLaw.of(contraction_of_shape(args.curve, SEED000_RIBBON.actuation_stretch),
                          *der_ribbon.CONTRACTION_TABLE)
    # The what-if: the simulation takes a(T) only through this table (RibbonSimulation.contraction).
    der_ribbon.tabulated_contraction = lambda transition: law
    extra = [] if args.perturbation == 0.01 else [f"numerics.perturbation={args.perturbation}"]
    scratch = args.out.with_name(args.out.name + ".part")
    for T in plates:
        scratch.unlink(missing_ok=True)
        run(scratch, args.duration, [(T, args.nodes, args.dt)], CONTACT_SPACING, CONVERGED + extra)
        row = json.loads(scratch.read_text().splitlines()[0])
        row["curve"] = args.curve
        with open(args.out, "a") as f:
            f.write(json.dumps(row) + "\n")
        print(f"{args.curve} {T:.0f} C: {row['average_speed [mm/s]']:.3f} mm/s, rolls {row['rolls']:.0f}, "
              f"T mean {row.get('T_mean_final [C]', float('nan')):.1f} C, {row['cpu']:.0f} s CPU", flush=True)
    scratch.unlink(missing_ok=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
