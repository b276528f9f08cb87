"""Wall time of the 3 x 3 gridshell (bar-and-hinge) per shape: the paper's four Fig. 4 shapes (lambda
route, paper supports) and the eight published recipes (in the published configuration, issue 30);
the number and time of the lowest-eigenpair solves of the snap-throughs (what limits the dome); increments, Newton iterations, failed
increments, whether the target was reached exactly, centre curvatures (both measures) and z range;
with ``--set design``, the inverse design (four channels) from the paper's measured curvatures of
each Fig. 4 shape (table: flat): time per inverse solve (with the forward check from as built),
optimiser evaluations, forward solves, Newton iterations, residual; with ``--fe`` also the 3D FE
gridshell (quarter model, level 0, the shape's published support) ramped from as built to the
lambdas found: its centre curvatures against the target (issue 15: the design confirmed in FE).

    OMP_NUM_THREADS=1 python -m lcefem.validation.benchmarks.gridshell_benchmark [--only dome,saddle]
        [--set shapes|recipes|all|design] [--fe] [--json FILE]

Not a test: it prints figures for the report (the published MATLAB/Octave code: 5-27 min per shape,
300 fixed increments). The machine load matters: run it alone.
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
from lcefem.models.bar_hinge import BarHingeMaterials, LCEStripBars
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.runtime.files import write_json
from lcefem.validation import gridshell_bh as gs
from lcefem.solvers.problems import gridshell_bh as problem_bh


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
        def timed(kmat):
            t0 = time.perf_counter()
            try:
                return self._original(kmat)
            finally:
                self.calls += 1
                self.seconds += time.perf_counter() - t0
        newton_module._negative_curvature_direction = timed
        return self

    def __exit__(self, *exc):
        newton_module._negative_curvature_direction = self._original


def run_one(kind: str, name: str) -> dict:
    t0 = time.perf_counter()
    if kind == "shape":
        structure = build_gridshell_bar_hinge()
        spec = gs.SHAPES[name]
        targets, support = problem_bh.targets_from_lambdas(structure, spec["lambdas"]), spec["support"]
        materials = BarHingeMaterials()
    else:  # the published configuration (issue 30)
        recipe, support = problem_bh.RECIPES[name]
        mesh, lce, support = problem_bh.published_configuration(BeamBarHingeMesh(), LCEStripBars(), support)
        structure = build_gridshell_bar_hinge(mesh=mesh)
        targets = problem_bh.targets_from_recipe(structure, recipe)
        materials = dataclasses.replace(BarHingeMaterials(), lce=lce)
    setup = problem_bh.setup_gridshell(targets, support, structure=structure, materials=materials)
    t_setup = time.perf_counter() - t0
    row = {"kind": kind, "name": name, "support": support, "setup [s]": t_setup}
    try:
        with EigenTimer() as eig:
            sol = problem_bh.solve_gridshell(setup)
        row.update(**{"eigen solves [-]": eig.calls, "eigen solve time [s]": eig.seconds})
    except ConvergenceError as exc:
        row.update(converged=False, reason=str(exc), **{"solve [s]": time.perf_counter() - t0 - t_setup})
        return row
    x = sol.final.x
    reached = all(np.array_equal(setup.model.rest_fractions()[g], setup.targets[g])
                  for g in setup.targets)
    summ = problem_bh.shape_summary(structure, x)
    row.update(converged=True, reached=reached, **{"solve [s]": sol.path.seconds},
               increments=len(sol.path.states) - 1, newton=int(sum(sol.path.newton_iterations)),
               failed=sol.path.failed_increments,
               **{k: summ[k] for k in ("circle_x", "circle_y", "quad_kx", "quad_ky", "quad_k1",
                                        "quad_k2", "rms_residual", "z_range [mm]")})
    return row


def run_design(name: str, fe: bool = False) -> dict:
    from lcefem.validation import gridshell_design as gd
    spec = gs.SHAPES[name]
    target = spec["paper_exp"] if spec["paper_exp"][0] is not None else spec["paper_sim"]
    design = gd.setup_design("4", spec["support"])
    res = gd.inverse(design, *target)
    row = {"kind": "design", "name": name, "support": spec["support"], "target": target,
           "seconds": res.seconds, "evaluations": res.iterations, "solves": res.stats.solves,
           "newton": res.stats.newton_iterations, "residual [1/mm]": float(np.linalg.norm(res.residual)),
           "lambdas": dict(zip(design.names, res.p.tolist())),
           "achieved [1/mm]": [float(v) for v in res.state.observables[:2]]}
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
    p.add_argument("--fe", action="store_true", help="with --set design: ramp the FE gridshell to the "
                   "lambdas found (quarter model, level 0) and print its centre curvatures")
    args = p.parse_args(argv)
    jobs = []
    if args.set in ("shapes", "all"):
        jobs += [("shape", n) for n in gs.SHAPES]
    if args.set in ("recipes", "all"):
        jobs += [("recipe", n) for n in problem_bh.RECIPES]
    if args.only:
        keep = set(args.only.split(","))
        jobs = [j for j in jobs if j[1] in keep]
    print(f"# gridshell benchmark, {platform.processor() or platform.machine()}, python "
          f"{platform.python_version()}")
    if args.set == "design":
        names = args.only.split(",") if args.only else list(gs.SHAPES)
        print(f"{'name':9s} {'support':8s} {'target x/y [1/mm]':>18s} {'seconds':>8s} {'evals':>5s} "
              f"{'solves':>6s} {'newton':>6s} {'residual':>9s}", flush=True)
        rows = []
        for name in names:
            r = run_design(name, fe=args.fe)
            rows.append(r)
            print(f"{name:9s} {r['support']:8s} {r['target'][0]:8.4f}/{r['target'][1]:8.4f}  "
                  f"{r['seconds']:8.1f} {r['evaluations']:5d} {r['solves']:6d} {r['newton']:6d} "
                  f"{r['residual [1/mm]']:9.2e}", flush=True)
            if "fe circle [1/mm]" in r:
                print(f"  lambdas {r['lambdas']}; bar-and-hinge {r['achieved [1/mm]']}; FE "
                      f"{r['fe circle [1/mm]']} ({r['fe seconds']:.0f} s)", flush=True)
        if args.json:
            write_json(args.json, rows)  # .part then rename, strict JSON
        return 0
    print(f"{'kind':7s} {'name':9s} {'support':8s} {'ok':3s} {'reached':7s} {'incr':>4s} {'newton':>6s} "
          f"{'fail':>4s} {'solve s':>8s} {'circ x':>8s} {'circ y':>8s} {'quad x':>8s} {'quad y':>8s} "
          f"{'z rng':>6s} {'eig':>4s} {'eig s':>6s}", flush=True)
    rows = []
    for kind, name in jobs:
        r = run_one(kind, name)
        rows.append(r)
        if r["converged"]:
            print(f"{kind:7s} {name:9s} {r['support']:8s} yes {str(r['reached']):7s} {r['increments']:4d} "
                  f"{r['newton']:6d} {r['failed']:4d} {r['solve [s]']:8.1f} {r['circle_x']:8.4f} "
                  f"{r['circle_y']:8.4f} {r['quad_kx']:8.4f} {r['quad_ky']:8.4f} {r['z_range [mm]']:6.2f} "
                  f"{r['eigen solves [-]']:4d} {r['eigen solve time [s]']:6.1f}",
                  flush=True)
        else:
            print(f"{kind:7s} {name:9s} {r['support']:8s} NO  ({r['reason']}) {r['solve [s]']:.1f} s",
                  flush=True)
    if args.json:
        write_json(args.json, rows)  # .part then rename, strict JSON
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
