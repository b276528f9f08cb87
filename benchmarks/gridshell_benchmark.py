"""CPU and wall time of the 3 x 3 gridshell (bar-and-hinge) per shape: the paper's four Fig. 4
shapes (lambda route, paper supports) and the eight published recipes (in the published
configuration, issue 30); the number and CPU time of the lowest-eigenpair solves of the
snap-throughs; increments, Newton iterations, failed increments, whether the target was reached
exactly, centre curvatures (both measures) and z range; with ``--set design``, the inverse design
(four channels) from the paper's measured curvatures of each Fig. 4 shape (table: flat): CPU and
wall time per inverse solve (with the forward check from as built), optimiser evaluations, forward
solves, Newton iterations, eigen solves, residual and the lambdas found; with ``--fe`` also the 3D
FE gridshell (quarter model, level 0, the shape's published support) ramped from as built to the
lambdas found: its centre curvatures against the target (issue 15: the design confirmed in FE).

``--save FILE.npz`` keeps the final states (positions; design: lambdas), ``--compare FILE.npz``
prints each run's distance from them (ribbon nodes / all nodes [mm]; design: largest lambda
change): with ``--baseline`` (the solver before issue 30's speed-up: escapes along any negative
curvature, no stall damping) this is the side-by-side check that a speed-up keeps the answers.

    OMP_NUM_THREADS=1 python benchmarks/gridshell_benchmark.py [--only dome,saddle]
        [--set shapes|recipes|all|design] [--baseline] [--stall N] [--save F] [--compare F] [--fe]
        [--json FILE]

Not a test: it prints figures for the report (the published MATLAB/Octave code: 5-27 min per shape,
300 fixed increments). CPU time is of this process (time.process_time): wall time depends on the
machine's load.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import platform
import time

import numpy as np

from lcefem.meshes.composite_beam import BeamBarHingeMesh
from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.models.bar_hinge_materials import BarHingeMaterials, LCEStripBars
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.problems import gridshell_bh as problem_bh
from lcefem.solvers.problems import gridshell_bh_run as problem_bh_run
from lcefem.solvers.problems.gridshell_bh import RAMP_NEWTON
from lcefem.solvers.runtime.files import write_json
from lcefem.validation.cases.programs import RECIPES
from lcefem.validation.studies.gridshell import gridshell_bh as gs

#: The Newton module (the package re-exports its function ``newton`` under the same name).
newton_module = importlib.import_module("lcefem.solvers.bar_hinge.newton")


class EigenTimer:
    """Counts the lowest-eigenpair solves of the Newton escapes (snap-throughs) and their time: the
    dense eigh of the ~2500 free DOFs is what makes the dome slow (issue 30: 5-10 s per call on one
    idle core, ~100 s under BLAS thread contention on the shared machine)."""

    def __init__(self):
        self.calls, self.seconds = 0, 0.0
        self._original = newton_module._negative_curvature_direction

    def __enter__(self):
        def timed(*args, **kwargs):
            t0 = time.process_time()
            try:
                return self._original(*args, **kwargs)
            finally:
                self.calls += 1
                self.seconds += time.process_time() - t0

        newton_module._negative_curvature_direction = timed
        return self

    def __exit__(self, *exc):
        newton_module._negative_curvature_direction = self._original


#: Newton settings of the shape and recipe runs (--baseline: as before issue 30's speed-up).
NEWTON = RAMP_NEWTON


def run_one(kind: str, name: str) -> dict:
    t0, c0 = time.perf_counter(), time.process_time()
    if kind == "shape":
        structure = build_gridshell_bar_hinge()
        spec = gs.SHAPES[name]
        targets, support = (
            problem_bh.targets_from_lambdas(structure, spec["lambdas"]),
            spec["support"],
        )
        materials = BarHingeMaterials()
    else:  # the published configuration (issue 30)
        recipe, support = RECIPES[name]
        mesh, lce, support = problem_bh_run.published_configuration(
            BeamBarHingeMesh(), LCEStripBars(), support
        )
        structure = build_gridshell_bar_hinge(mesh=mesh)
        targets = problem_bh.targets_from_recipe(structure, recipe)
        materials = dataclasses.replace(BarHingeMaterials(), lce=lce)
    setup = problem_bh.setup_gridshell(targets, support, structure=structure, materials=materials)
    t_setup = time.perf_counter() - t0
    row = {"kind": kind, "name": name, "support": support, "setup [s]": t_setup}
    c1 = time.process_time()
    try:
        with EigenTimer() as eig:
            sol = problem_bh.solve_gridshell(setup, newton_options=NEWTON)
        row.update(
            **{
                "eigen solves [-]": eig.calls,
                "eigen solve CPU [s]": eig.seconds,
                "CPU [s]": time.process_time() - c1,
                "setup CPU [s]": c1 - c0,
            }
        )
    except ConvergenceError as exc:
        row.update(
            converged=False,
            reason=str(exc),
            **{
                "solve [s]": time.perf_counter() - t0 - t_setup,
                "CPU [s]": time.process_time() - c1,
            },
        )
        return row
    x = sol.final.x
    reached = all(
        np.array_equal(setup.model.rest_fractions()[g], setup.targets[g]) for g in setup.targets
    )
    summ = problem_bh.shape_summary(structure, x)
    row.update(
        converged=True,
        reached=reached,
        **{"solve [s]": sol.path.seconds},
        increments=len(sol.path.states) - 1,
        newton=int(sum(sol.path.newton_iterations)),
        failed=sol.path.failed_increments,
        **{
            k: summ[k]
            for k in (
                "circle_x",
                "circle_y",
                "quad_kx",
                "quad_ky",
                "quad_k1",
                "quad_k2",
                "rms_residual",
                "z_range [mm]",
            )
        },
    )
    row["x"], row["ribbon"] = x, problem_bh.ribbon_nodes(structure)
    return row


def run_design(name: str, fe: bool = False) -> dict:
    from lcefem.validation.studies.design import gridshell_design as gd

    spec = gs.SHAPES[name]
    target = spec["paper_exp"] if spec["paper_exp"][0] is not None else spec["paper_sim"]
    design = gd.setup_design("4", spec["support"])
    c0 = time.process_time()
    with EigenTimer() as eig:
        res = gd.inverse(design, *target)
    row = {
        "kind": "design",
        "name": name,
        "support": spec["support"],
        "target": target,
        "seconds": res.seconds,
        "CPU [s]": time.process_time() - c0,
        "eigen solves [-]": eig.calls,
        "eigen solve CPU [s]": eig.seconds,
        "evaluations": res.iterations,
        "solves": res.stats.solves,
        "newton": res.stats.newton_iterations,
        "residual [1/mm]": float(np.linalg.norm(res.residual)),
        "lambdas": dict(zip(design.names, res.p.tolist())),
        "achieved [1/mm]": [float(v) for v in res.state.observables[:2]],
    }
    if fe:
        from lcefem.validation.cases.gridshell_fe import run_fe_shape

        _, obs = run_fe_shape(name, row["lambdas"])
        row["fe circle [1/mm]"] = [obs["kappa_circle_x [1/mm]"], obs["kappa_circle_y [1/mm]"]]
        row["fe seconds"] = obs["wall time [s]"]
    return row


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--set", choices=("shapes", "recipes", "all", "design"), default="all")
    p.add_argument("--only", help="comma-separated names")
    p.add_argument("--json", help="also write the rows to this JSON file")
    p.add_argument(
        "--baseline",
        action="store_true",
        help="the solver as before issue 30's speed-up "
        "(an escape along any negative curvature, however small; no stall damping), for a "
        "side-by-side "
        "run",
    )
    p.add_argument(
        "--stall",
        type=int,
        help="Newton's stall_iterations for the shape and recipe runs "
        "(default: the ramp's, RAMP_NEWTON)",
    )
    p.add_argument("--save", help="write the final positions of every converged run to this .npz")
    p.add_argument(
        "--compare",
        help="print the largest nodal distance [mm] of each final state from "
        "the one saved in this .npz, over the ribbon nodes and over all nodes (a floating "
        "node, e.g. of a slack strip's raised square, is not fixed by the force tolerance)",
    )
    p.add_argument(
        "--fe",
        action="store_true",
        help="with --set design: ramp the FE gridshell to the "
        "lambdas found (quarter model, level 0) and print its centre curvatures",
    )
    args = p.parse_args(argv)
    if args.baseline:
        global NEWTON
        newton_module.NEGLIGIBLE_CURVATURE = 0.0
        NEWTON = dataclasses.replace(NEWTON, stall_iterations=0)
    if args.stall is not None:
        NEWTON = dataclasses.replace(NEWTON, stall_iterations=args.stall)
    jobs = []
    if args.set in ("shapes", "all"):
        jobs += [("shape", n) for n in gs.SHAPES]
    if args.set in ("recipes", "all"):
        jobs += [("recipe", n) for n in RECIPES]
    if args.only:
        keep = set(args.only.split(","))
        jobs = [j for j in jobs if j[1] in keep]
    print(
        f"# gridshell benchmark, {platform.processor() or platform.machine()}, python "
        f"{platform.python_version()}; CPU: time.process_time of this process (wall depends on the "
        f"machine's load)"
    )
    saved = dict(np.load(args.compare)) if args.compare else None
    if args.set == "design":
        names = args.only.split(",") if args.only else list(gs.SHAPES)
        print(
            f"{'name':9s} {'support':8s} {'target x/y [1/mm]':>18s} {'wall s':>8s} {'CPU s':>8s} "
            f"{'evals':>5s} {'solves':>6s} {'newton':>6s} {'eig':>4s} {'eig CPU':>7s} "
            f"{'residual':>9s} "
            f"lambdas{'  max |lambda - saved|' if saved else ''}",
            flush=True,
        )
        rows, states = [], {}
        for name in names:
            r = run_design(name, fe=args.fe)
            rows.append(r)
            key = f"design:{name}"
            states[key] = np.array(list(r["lambdas"].values()))
            moved = ""
            if saved is not None and key in saved:
                r["max |lambda - saved| [-]"] = float(np.max(np.abs(states[key] - saved[key])))
                moved = f"  {r['max |lambda - saved| [-]']:.2e}"
            print(
                f"{name:9s} {r['support']:8s} {r['target'][0]:8.4f}/{r['target'][1]:8.4f}  "
                f"{r['seconds']:8.1f} {r['CPU [s]']:8.1f} {r['evaluations']:5d} {r['solves']:6d} "
                f"{r['newton']:6d} {r['eigen solves [-]']:4d} {r['eigen solve CPU [s]']:7.1f} "
                f"{r['residual [1/mm]']:9.2e} {np.array2string(states[key], precision=6)}{moved}",
                flush=True,
            )
            if "fe circle [1/mm]" in r:
                print(
                    f"  lambdas {r['lambdas']}; bar-and-hinge {r['achieved [1/mm]']}; FE "
                    f"{r['fe circle [1/mm]']} ({r['fe seconds']:.0f} s)",
                    flush=True,
                )
        if args.save:
            np.savez(args.save, **states)
        if args.json:
            write_json(args.json, rows)  # .part then rename, strict JSON
        return 0
    print(
        f"{'kind':7s} {'name':9s} {'support':8s} {'ok':3s} {'reached':7s} {'incr':>4s} "
        f"{'newton':>6s} "
        f"{'fail':>4s} {'wall s':>7s} {'CPU s':>7s} {'circ x':>8s} {'circ y':>8s} {'quad x':>8s} "
        f"{'quad y':>8s} {'z rng':>6s} {'eig':>4s} {'eig CPU':>7s}{
            '  max |x - saved| ribbon / all nodes [mm]' if saved else ''
        }",
        flush=True,
    )
    rows, states = [], {}
    for kind, name in jobs:
        r = run_one(kind, name)
        rows.append(r)
        if r["converged"]:
            key = f"{kind}:{name}"
            states[key], ribbon = r.pop("x"), r.pop("ribbon")
            moved = ""
            if saved is not None and key in saved:
                distance = np.linalg.norm(states[key] - saved[key], axis=1)
                r["max |x - saved| [mm]"] = float(np.max(distance))
                r["max |x - saved| ribbon [mm]"] = float(np.max(distance[ribbon]))
                moved = (
                    f"  {r['max |x - saved| ribbon [mm]']:.2e} / {r['max |x - saved| [mm]']:.2e}"
                )
            print(
                f"{kind:7s} {name:9s} {r['support']:8s} yes {str(r['reached']):7s} "
                f"{r['increments']:4d} "
                f"{r['newton']:6d} {r['failed']:4d} {r['solve [s]']:7.1f} {r['CPU [s]']:7.1f} "
                f"{r['circle_x']:8.4f} {r['circle_y']:8.4f} {r['quad_kx']:8.4f} "
                f"{r['quad_ky']:8.4f} "
                f"{r['z_range [mm]']:6.2f} {r['eigen solves [-]']:4d} "
                f"{r['eigen solve CPU [s]']:7.1f}{moved}",
                flush=True,
            )
        else:
            print(
                f"{kind:7s} {name:9s} {r['support']:8s} NO  ({r['reason']}) {r['solve [s]']:.1f} s "
                "wall, "
                f"{r['CPU [s]']:.1f} s CPU",
                flush=True,
            )
    if args.save:
        np.savez(args.save, **states)
    if args.json:
        write_json(args.json, rows)  # .part then rename, strict JSON
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
