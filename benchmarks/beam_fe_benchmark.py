"""Wall time of the 3D FE composite beam at (lambda_T, lambda_B) = (1.33, 1.05) against the
bar-and-hinge beam; DOFs, steps, Newton iterations, time per iteration; the FE ribbon's critical
load.

    python benchmarks/beam_fe_benchmark.py [--levels 0 1] [--repeat 1]

Not a test: it prints figures (the best of --repeat runs) for the developers' guide and the report.
The machine load matters: run it alone.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from lcefem.solvers.problems import composite_beam_bh as beam_bh
from timing import best_of


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[0, 1], help="FE mesh levels")
    parser.add_argument("--repeat", type=int, default=1, help="runs per figure (best is printed)")
    parser.add_argument("--lambda-top", type=float, default=1.33)
    parser.add_argument("--lambda-bottom", type=float, default=1.05)
    args = parser.parse_args(argv)
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.meshes.kapton_ribbon import KaptonFEMesh
    from lcefem.solvers.problems import composite_beam as beam_fe
    from lcefem.solvers.problems import kapton_specimen

    lt, lb = args.lambda_top, args.lambda_bottom
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"{platform.processor() or platform.machine()}; composite beam at ({lt:g}, {lb:g})"
    )
    secs, sol = best_of(lambda: beam_bh.solve_beam(lt, lb), args.repeat)
    its = np.array(sol.path.newton_iterations)
    print(
        f"bar-and-hinge (4 segments): {secs:.2f} s, {sol.model.ndof} DOFs, {its.size} increments, "
        f"{its.sum()} Newton iterations ({1e3 * secs / its.sum():.1f} ms each); "
        f"curvature {sol.curvature:.5f} 1/mm"
    )
    for level in args.levels:
        mesh = BeamFEMesh(level=level)

        def solve():
            model = beam_fe.BeamFE(mesh=mesh)
            t0 = time.perf_counter()
            model.ramp(lt, lb)
            return model, time.perf_counter() - t0

        secs, (model, ramp) = best_of(solve, args.repeat)
        f = model.last_follower
        print(
            f"3D FE level {level} ({model.tmesh.info['symmetry']} model, "
            f"{model.tmesh.info['cells']} "
            f"Q2 hexahedra, {model.ndofs} DOFs): {secs:.1f} s in all, ramp {ramp:.1f} s, "
            f"{len(f.history) and f.iterations} Newton iterations ({ramp / f.iterations:.2f} s "
            "each), "
            f"{f.cuts} cut steps, {f.snaps} folds; curvature {model.curvature():.5f} 1/mm"
        )
    for level in (0, 1):

        def ribbon():
            r = kapton_specimen.KaptonSpecimenFE(mesh=KaptonFEMesh(level=level))
            return r, r.critical_load()

        secs, (r, crit) = best_of(ribbon, args.repeat)
        print(
            f"FE ribbon critical load, level {level} ({r.ndofs} DOFs): {secs:.1f} s, "
            f"P_cr = {crit.force:.5f} N"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
