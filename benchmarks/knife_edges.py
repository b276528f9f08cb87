"""Knife edges: does a phenomenon's verdict rest on round-off? (issue 45, cause 15)

A validated phenomenon (validation/data/phenomena.toml) must not flip when nothing physical changes.
This reruns each case at the quick level as a user would (``lcefem validate CASE --quick`` in a
subprocess) under changes that move only round-off, and compares the phenomena's verdicts and
values:

* ``as is``: the environment unchanged;
* ``other BLAS``: OpenBLAS's SSE3 kernels (``OPENBLAS_CORETYPE=Prescott``) on one thread: another
  summation order in every dot product, matrix product and factorisation, as on another machine.

A phenomenon is a knife edge when its verdict differs between the variants, or when its values move
across the variants by more than a hundredth of their margin to the condition's bound (then the
margin is not far beyond round-off and the next machine may flip it). Values that are indicators
(0/1) hide their margin: only the rerun speaks for them.

For the Fig. 5B ball (the case that had one) it also moves the ball by +-1e-9 and +-1e-6 mm in y
where it is placed and where the saddle takes it over, on the nominal (symmetric) surface and on the
drawn one (:data:`lcefem.validation.studies.gridshell.fig5_tasks.BALL_SURFACE_SEED`), and runs the
ball on other draws of the measured lambda_N spread (seeds 2-6): the released side must not depend
on round-off, and with the measured spread the saddle releases the ball across a y edge on every
draw.

    python benchmarks/knife_edges.py [CASE ...] [--budget S] [--out DIR] [--no-ball]

Not a test (minutes per case): it prints a table for docs/validation.md. Default cases: every case
whose quick run took at most ``--budget`` seconds in the stored quick summary
(docs/validation_summary_quick.md); the others are named as not checked.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pathlib
import re
import subprocess
import sys
import time

VARIANTS = {
    "as is": {},
    "other BLAS": {
        "OPENBLAS_CORETYPE": "Prescott",
        "OPENBLAS_NUM_THREADS": "1",
        "OMP_NUM_THREADS": "1",
    },
}
ROOT = pathlib.Path(__file__).resolve().parents[1]
QUICK_SUMMARY = ROOT / "docs" / "validation_summary_quick.md"
#: A phenomenon is a knife edge when round-off (the change of its values between the variants) is
#: more than this fraction of its margin to the bound: a margin less than a hundred times what
#: round-off moves may flip on the next machine (dynamics with contact amplify round-off to 1e-4 of
#: a value; a verdict a hundred times further away does not rest on it).
MARGIN_FRACTION = 1e-2


def quick_wall_times(path: pathlib.Path = QUICK_SUMMARY) -> dict[str, float]:
    """{case: wall time [s]} from the summary table of the stored quick report."""
    times = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[1] in ("done", "reused"):
            try:
                times[cells[0]] = float(cells[6])
            except ValueError:
                pass
    return times


def run_case(case: str, out: pathlib.Path, env: dict) -> tuple[list[dict] | None, float, str]:
    """(metric rows or None, wall time [s], the last error line) of ``lcefem validate CASE
    --quick``."""
    exe = pathlib.Path(sys.executable).with_name("lcefem")
    t0 = time.perf_counter()
    p = subprocess.run(
        [str(exe), "validate", case, "--quick", "--overwrite", "--quiet", "--out", str(out)],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - t0
    path = out / "metrics.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None, wall, (p.stderr.strip().splitlines() or ["no metrics.json"])[-1]
    rows = data if isinstance(data, list) else data.get("metrics", data.get(case, []))
    rows = [r for r in rows if isinstance(r, dict) and r.get("case", case) == case]
    return rows, wall, ""


def margin(p, value) -> float:
    """Distance [value's unit] from ``value`` to the nearest bound of phenomenon ``p``'s condition
    (negative when it does not hold)."""
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        return -math.inf
    d = [value - p.above] if p.above is not None else []
    d += [p.below - value] if p.below is not None else []
    return min(d)


def check_case(case: str, out: pathlib.Path) -> list[dict]:
    """One row per phenomenon of ``case``: verdict per variant, smallest margin, largest spread of
    its values across the variants, and the finding."""
    from lcefem.validation.app import phenomena

    runs = {}
    for name, env in VARIANTS.items():
        rows, wall, err = run_case(case, out / re.sub(r"\W+", "_", name), env)
        runs[name] = (rows, wall, err)
    results = []
    for p in phenomena.for_case(case):
        verdicts, values = {}, {}
        for name, (rows, _, err) in runs.items():
            if rows is None:
                verdicts[name] = f"no result ({err})"
                continue
            ev = [e for e in phenomena.evaluate(case, rows) if e["phenomenon"] == p.phenomenon][0]
            verdicts[name] = "yes" if ev["holds"] else "NO"
            values[name] = ev["values"]
        names = sorted(set().union(*(v.keys() for v in values.values()))) if values else []
        spread, smallest, indicator = 0.0, math.inf, False
        for m in names:
            vs = [v.get(m) for v in values.values()]
            vs = [v for v in vs if isinstance(v, (int, float)) and math.isfinite(v)]
            if not vs:
                continue
            spread = max(spread, max(vs) - min(vs))
            smallest = min(smallest, min(margin(p, v) for v in vs))
            indicator |= "(1 = yes)" in m
        flips = len(set(verdicts.values())) > 1
        if flips:
            finding = "KNIFE EDGE: the verdict flips"
        elif smallest != math.inf and smallest > 0 and spread > MARGIN_FRACTION * smallest:
            finding = "KNIFE EDGE: round-off moves the values by more than 1/100 of the margin"
        elif spread > 0.0:
            finding = (
                f"same verdict (round-off moves the values, margin {smallest / spread:.2g} x that)"
            )
        elif indicator:
            finding = "same verdict (an indicator: its margin is hidden)"
        else:
            finding = "same verdict"
        results.append(
            {
                "case": case,
                "phenomenon": p.phenomenon,
                "verdicts": verdicts,
                "margin": smallest,
                "spread": spread,
                "finding": finding,
                "wall [s]": {k: round(v[1], 1) for k, v in runs.items()},
            }
        )
    return results


def ball_check(out: pathlib.Path) -> list[str]:
    """The ball on the nominal and the drawn surfaces, moved by +-1e-9 mm; other draws (lines)."""
    from lcefem.validation.cases.gridshell_fig5_bh import QUICK_NEWTON
    from lcefem.validation.studies.gridshell import fig5_tasks

    lines = []
    for seed in (None, fig5_tasks.BALL_SURFACE_SEED, 2, 3, 4, 5, 6):
        frames = fig5_tasks.morph_frames(newton=QUICK_NEWTON, surface_seed=seed)
        shifts = (
            (0.0, 1e-9, -1e-9, 1e-6, -1e-6)
            if seed in (None, fig5_tasks.BALL_SURFACE_SEED)
            else (0.0,)
        )
        outcomes = []
        for dy in shifts:
            s = fig5_tasks.ball_task(
                out / "ball", frames=frames, movie=False, surface_seed=seed, shift=(0.0, dy)
            )
            outcomes.append(
                (
                    dy,
                    s["distance from centre at end of bowl hold [mm]"],
                    s["exit side"] or "not released",
                    s["release time [s]"],
                )
            )
        label = "nominal (symmetric)" if seed is None else f"drawn lambda_N, seed {seed}"
        for dy, dist, side, t in outcomes:
            lines.append(
                f"ball, {label}, shift dy = {dy:+.0e} mm: {dist:.3g} mm from the centre after the "
                f"bowl; saddle: {side}" + (f" at {t:.1f} s" if t else "")
            )
    return lines


def main(argv: list[str] | None = None) -> int:
    from lcefem.validation.app import phenomena

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help="cases (default: every case within --budget)")
    parser.add_argument(
        "--budget",
        type=float,
        default=25.0,
        help="largest stored quick wall time [s] of a default case (default 25)",
    )
    parser.add_argument("--out", default="results/knife_edges", help="scratch folder of the reruns")
    parser.add_argument("--no-ball", action="store_true", help="skip the ball's own check")
    args = parser.parse_args(argv)
    out = pathlib.Path(args.out)
    declared = sorted({p.case for p in phenomena.declared()})
    times = quick_wall_times()
    # cheapest first: as many as the time allows
    cases = args.cases or sorted(
        (c for c in declared if times.get(c, math.inf) <= args.budget), key=lambda c: times[c]
    )
    skipped = [c for c in declared if c not in cases]
    print(f"variants: {', '.join(f'{k} {v or {}}' for k, v in VARIANTS.items())}")
    if not args.no_ball:
        for line in ball_check(out):
            print(line, flush=True)
    for case in cases:
        for r in check_case(case, out / case):
            print(
                f"{r['case']} | {r['phenomenon']} | "
                f"{', '.join(f'{k}: {v}' for k, v in r['verdicts'].items())}"
                f" | margin {r['margin']:.3g}, spread {r['spread']:.3g} | {r['finding']} | wall "
                f"{r['wall [s]']}",
                flush=True,
            )
    if skipped:
        why = (
            "not named"
            if args.cases
            else (f"stored quick wall time above {args.budget:g} s or not in the quick summary")
        )
        print(f"not checked in this run ({why}): " + ", ".join(skipped))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
