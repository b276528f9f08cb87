"""Wall time of the bar-and-hinge solves: the composite beam at (lambda_T, lambda_B) = (1.33, 1.05)
and the ribbon buckling run to 50 % compression; Newton iterations per increment; DOFs.

    python benchmarks/bar_hinge_benchmark.py [--repeat 3]

Not a test: it prints figures (the best of --repeat runs) for the developers' guide and the report.
"""

from __future__ import annotations

import argparse
import platform

import numpy as np

from lcefem.meshes.composite_beam import CompositeBeamGeometry, build_beam_bar_hinge
from lcefem.meshes.kapton_ribbon import KaptonBarHingeMesh, KaptonSpecimenGeometry
from lcefem.models.bar_hinge_materials import BarHingeMaterials
from lcefem.solvers.bar_hinge import BarHingeModel
from lcefem.solvers.problems import composite_beam_bh as beam_bh
from lcefem.solvers.problems import kapton_specimen_bh as kapton_bh
from timing import best_of


def _report(name: str, seconds: float, path, dofs: int, extra: str) -> None:
    its = np.array(path.newton_iterations)
    print(
        f"{name}: {seconds:.2f} s, {dofs} DOFs, {its.size} increments "
        f"({path.failed_increments} failed), Newton iterations per increment: mean "
        f"{its.mean():.1f}, "
        f"max {its.max()}, total {its.sum()}; {extra}"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per figure (best is printed)")
    args = parser.parse_args(argv)
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"{platform.processor() or platform.machine()}"
    )

    for segments in (4, 8):
        geometry = CompositeBeamGeometry(segments=segments)
        secs, sol = best_of(lambda: beam_bh.solve_beam(1.33, 1.05, geometry), args.repeat)
        _report(
            f"beam ({segments} segments) at (1.33, 1.05)",
            secs,
            sol.path,
            sol.model.ndof,
            f"curvature {sol.curvature:.5f} 1/mm",
        )

    secs, sol = best_of(lambda: kapton_bh.solve_specimen_buckling(0.5), args.repeat)
    _report(
        "ribbon buckling to 50 % (11 panels)",
        secs,
        sol.path,
        sol.model.ndof,
        f"force at 50 % {sol.force[-1]:.4f} N",
    )
    secs, (p_cr, _) = best_of(
        lambda: kapton_bh.critical_load(KaptonSpecimenGeometry(), KaptonBarHingeMesh()), args.repeat
    )
    print(f"critical load by inertia bisection (11 panels): {secs:.3f} s, P_cr = {p_cr:.4f} N")
    model = BarHingeModel.from_materials(build_beam_bar_hinge(), BarHingeMaterials())
    x = model.reference
    secs, _ = best_of(lambda: [model.evaluate(x) for _ in range(100)], args.repeat)
    print(
        f"energy + gradient + Hessian of the 4-segment beam: {1e3 * secs / 100:.2f} ms per "
        "evaluation"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
