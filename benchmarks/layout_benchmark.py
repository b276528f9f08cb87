"""CPU time of bar-and-hinge shapes on the new gridshell layouts (lcefem.meshes.gridshell_layout;
issue 47's target: a shape of the 5 x 5 layout within 10 s on one core).

Each run builds the layout's structure in a model set (FE-calibrated by default, its plate torsion
only on rectangular panels: ModelSet.materials_for), ramps the strips from as built to the drive and
prints CPU seconds (time.process_time of this process, one BLAS thread), increments, Newton
iterations, the lowest-eigenpair solves of the snap-throughs (count and CPU s), the centre
curvatures (circle and quadratic measures, dome negative) and the z range.

    OMP_NUM_THREADS=1 python benchmarks/layout_benchmark.py
        [--only NAME,...] [--model-set fe-calibrated|published] [--json FILE]

Runs (NAME: layout, support, drive): ``5x5-bottom`` (5x5, rollers, every bottom strip at lambda
1.37: the test's round dome), ``5x5-dome`` (5x5, rollers, the Fig. 4 dome's Tx = Ty = 1.33, Bx = By
= 1.05), ``5x5-dome-SUPPORT`` (the same drive on the other supports: clamp, middle_rollers,
table), ``rhombic60-bottom`` (rhombic60, clamp, lambda_B = 1.395), ``published-dome`` (the 3 x 3
for scale).
``--design``: also a design on the 5 x 5 (issue 47's second target: within 2 minutes on one core):
``lcefem design --layout 5x5 --channels 4`` to the elongated dome (-0.010, -0.006) 1/mm on rollers
(case gridshell_reach_bh's off-grid target), the design loop and the reach search from flat; prints
its CPU seconds, forward solves, the design kind and the distance from flat.
``--run-newton``: the shapes with the run's own Newton settings (RAMP_NEWTON: stall damping, as
``lcefem run gridshell``) instead of the problem's default. ``--former-newton``: without the
progress budget and the energy slack of GRIDSHELL_NEWTON (the settings before 2026-12-07, to
compare). ``--cpu-limit S``: stop a shape after S CPU seconds and print the load factor reached.
Not a test: it prints figures for the report (timings depend on the machine's load).
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import time

from gridshell_benchmark import EigenTimer
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.solvers.problems.gridshell_bh import (
    GRIDSHELL_NEWTON,
    RAMP_NEWTON,
    GridshellBH,
    GridshellBHConfig,
)
from lcefem.solvers.runtime.files import write_json
from lcefem.validation.studies.gridshell import calibrate

DOME = {
    "Tx": 1.33,
    "Ty": 1.33,
    "Bx": 1.05,
    "By": 1.05,
}  # seed 001 Fig. 4B (validation/data/programs.toml)
RUNS = {
    "5x5-bottom": ("5x5", "rollers", {"B": 1.37}),
    "5x5-dome": ("5x5", "rollers", DOME),
    "5x5-dome-clamp": ("5x5", "clamp", DOME),
    "5x5-dome-middle_rollers": ("5x5", "middle_rollers", DOME),
    "5x5-dome-table": ("5x5", "table", DOME),
    "rhombic60-bottom": ("rhombic60", "clamp", {"B": 1.395}),
    "published-dome": ("published", "rollers", DOME),
}


#: The design run of ``--design``: target (kappa_x, kappa_y) [1/mm], support.
DESIGN = ((-0.010, -0.006), "rollers")


def run_design(model_set: str) -> dict:
    """``lcefem design --layout 5x5`` (4 channels) to :data:`DESIGN`: CPU s, solves, reach kind."""
    from lcefem.validation.studies.design import gridshell_design as gd

    (kx, ky), support = DESIGN
    t0 = time.process_time()
    design = gd.setup_design("4", support, layout=NAMED_LAYOUTS["5x5"], model_set=model_set)
    res = gd.inverse(design, kx, ky)
    found = res.check["reach"]
    return {
        "run": "5x5-design",
        "cpu [s]": time.process_time() - t0,
        "forward solves": res.stats.solves,
        "kind": found.kind,
        "distance from flat [1/mm]": found.distance,
        "runs from flat": len(found.attempts),
        "lambdas": [float(v) for v in found.p],
    }


#: GRIDSHELL_NEWTON's fields before the progress budget and the energy slack (``--former-newton``).
FORMER = {"progress_iterations": 0, "energy_slack": 1.0e-13}


class CPULimit(Exception):
    """A shape stopped at ``--cpu-limit``; ``t``: the last converged load factor."""

    def __init__(self, t: float):
        self.t = t


def run_one(
    name: str,
    model_set: str,
    run_newton: bool = False,
    former: bool = False,
    cpu_limit: float = 0.0,
) -> dict:
    layout_name, support, drive = RUNS[name]
    ms = calibrate.model_set(model_set)
    layout = NAMED_LAYOUTS[layout_name]
    t0 = time.process_time()
    structure = ms.structure(layout)
    solver = RAMP_NEWTON if run_newton else GRIDSHELL_NEWTON
    if former:
        solver = dataclasses.replace(solver, **FORMER)
    problem = GridshellBH(
        structure,
        GridshellBHConfig(materials=ms.materials_for(layout), support=support, solver=solver),
    )
    problem.set_drives(drive)

    def progress(t: float) -> None:
        if cpu_limit and time.process_time() - t0 > cpu_limit:
            raise CPULimit(t)

    with EigenTimer() as eig:
        try:
            path = problem.advance(progress=progress).detail  # the PathResult
        except CPULimit as stop:
            return {
                "run": name,
                "layout": layout_name,
                "support": support,
                "dofs": int(problem.model.ndof),
                "cpu [s]": time.process_time() - t0,
                "stopped at t": stop.t,
            }
    cpu = time.process_time() - t0
    o = problem.observables()
    return {
        "run": name,
        "layout": layout_name,
        "model set": model_set,
        "support": support,
        "drive": drive,
        "dofs": int(problem.model.ndof),
        "cpu [s]": cpu,
        "increments": len(path.states) - 1,
        "newton iterations": int(sum(path.newton_iterations)),
        "failed increments": path.failed_increments,
        "eigen solves": eig.calls,
        "eigen cpu [s]": eig.seconds,
        **{k: float(v) for k, v in o.items()},
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument(
        "--only", default=",".join(RUNS), help="comma-separated runs: " + ", ".join(RUNS)
    )
    p.add_argument("--model-set", default=calibrate.DEFAULT_MODEL_SET, choices=calibrate.MODEL_SETS)
    p.add_argument("--json", help="write the rows to this JSON file")
    p.add_argument("--design", action="store_true", help="also a design on the 5 x 5 (DESIGN)")
    p.add_argument(
        "--run-newton", action="store_true", help="the shapes with RAMP_NEWTON (the run's)"
    )
    p.add_argument(
        "--former-newton",
        action="store_true",
        help="without the progress budget and energy slack (FORMER)",
    )
    p.add_argument(
        "--cpu-limit",
        type=float,
        default=0.0,
        help="stop a shape after this many CPU seconds (0: never)",
    )
    args = p.parse_args(argv)
    if args.cpu_limit < 0:
        p.error(f"--cpu-limit = {args.cpu_limit}: must be >= 0 s")
    names = [n.strip() for n in args.only.split(",") if n.strip()]
    for n in names:
        if n not in RUNS:
            p.error(f"--only: unknown run {n!r} (allowed: {', '.join(RUNS)})")
    print(
        f"# {platform.processor() or platform.machine()}, python {platform.python_version()}, "
        f"model set {args.model_set}"
    )
    print(
        "run | dofs | CPU [s] | increments | Newton | eigen solves (CPU s) | circle kx/ky [1/mm] | "
        "quad kx/ky [1/mm] | z range [mm]"
    )
    rows = []
    for n in names:
        r = run_one(n, args.model_set, args.run_newton, args.former_newton, args.cpu_limit)
        rows.append(r)
        if "stopped at t" in r:
            print(
                f"{n} | {r['dofs']} | > {r['cpu [s]']:.2f} | "
                f"stopped at t = {r['stopped at t']:.4g}",
                flush=True,
            )
            continue
        print(
            f"{n} | {r['dofs']} | {r['cpu [s]']:.2f} | {r['increments']} | "
            f"{r['newton iterations']} "
            "| "
            f"{r['eigen solves']} ({r['eigen cpu [s]']:.2f}) | {r['circle kappa_x [1/mm]']:.5f}/"
            f"{r['circle kappa_y [1/mm]']:.5f} | {r['quad kappa_x [1/mm]']:.5f}/"
            f"{r['quad kappa_y [1/mm]']:.5f} | {r['z range [mm]']:.2f}",
            flush=True,
        )
    if args.design:
        r = run_design(args.model_set)
        rows.append(r)
        print(
            f"5x5-design | CPU {r['cpu [s]']:.1f} s | {r['forward solves']} forward solves | "
            f"{r['kind']} "
            f"({r['runs from flat']} runs from flat, {r['distance from flat [1/mm]']:.1e} 1/mm "
            "off) "
            "| "
            "lambdas " + "/".join(f"{v:.4f}" for v in r["lambdas"]),
            flush=True,
        )
    if args.json:
        write_json(args.json, {"rows": rows})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
