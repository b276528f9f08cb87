"""Wall time of the shape controller's model steps (issue 37: within 1 s on one core).

    OMP_NUM_THREADS=1 python benchmarks/control_benchmark.py [--shape cylinder] [--repeat 3]

Prints, for one Fig. 4 target on the 3 x 3 surface:
* the controller's per-sample step (disturbance estimate from the nine heights, reference correction
  through the design Jacobian, current law and limits, the nominal thermal observer);
* a re-linearisation: the exact sensitivities of the observables to every strip's lambda at the
  target's equilibrium (one factorisation and 42 solves, EquilibriumMap.jacobian), the model step a
  controller that re-linearises would run;
* one simulated second of the plant (42 strips' heat and the tangent map).
Not a test: it prints numbers (the best of --repeat runs).
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from lcefem.meshes.gridshell import GridshellLayout
from lcefem.models.shape_control import PlantSpread, StripHeat
from lcefem.solvers import control as ctl
from lcefem.validation.cases.programs import SHAPE_DRIVES


def best(fn, repeat: int, inner: int = 1) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        out.append((time.perf_counter() - t0) / inner)
    return min(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", default="cylinder", choices=list(SHAPE_DRIVES))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"{platform.processor() or platform.machine()}"
    )
    t0 = time.perf_counter()
    surface = ctl.build_surface(args.shape, SHAPE_DRIVES[args.shape], GridshellLayout())
    print(
        f"{args.shape}: target equilibrium and sensitivities built in "
        f"{time.perf_counter() - t0:.2f} "
        "s "
        f"({surface.eq.model.ndof} DOFs, {surface.p_star.size} strips)"
    )
    S, _ = surface.selection("channels")
    ctrl = ctl.ShapeController(surface, S)
    h = surface.y_star[: surface.heights] + 0.1
    kappa = (
        surface.y_star[surface.heights : surface.heights + 2] + 1e-4
    )  # the markers' circle curvatures
    t_ctrl = best(lambda: ctrl.step(h, 1.0, kappa), args.repeat, inner=100)
    print(f"controller step (channels, sensing {ctrl.settings.sensing}): {t_ctrl * 1e3:.3f} ms")
    S2, _ = surface.selection("strips")
    ctrl2 = ctl.ShapeController(surface, S2)
    t_ctrl2 = best(lambda: ctrl2.step(h, 1.0, kappa), args.repeat, inner=100)
    print(f"controller step (strips): {t_ctrl2 * 1e3:.3f} ms")
    t_jac = best(lambda: surface.eq.jacobian(surface.x_star), args.repeat)
    print(
        f"re-linearisation (d obs / d lambda, 42 strips): {t_jac:.3f} s "
        f"({'within' if t_jac <= 1.0 else 'above'} 1 s)"
    )
    draw = ctl.draw_plant(surface, PlantSpread(), 1)
    plant = ctl.SurfacePlant(surface, draw, StripHeat())
    u = np.full(4, 0.08)

    def plant_second():
        plant.step(S, u, 1.0)
        plant.output()

    t_plant = best(plant_second, args.repeat, inner=20)
    print(f"plant, one simulated second: {t_plant * 1e3:.3f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
