"""CPU cost of the 3D FE gridshell's Fig. 4 shapes ramped from flat (issue 46, point 2), with the
speed-up of the ramp (:data:`lcefem.solvers.problems.gridshell.GRIDSHELL_ORDERING`, MUMPS's PORD
ordering of the LDL^T) or without it (``--baseline``).

    python benchmarks/gridshell_fe_speed.py [--shapes dome table saddle cylinder]
        [--level 0] [--baseline] [--json out.json]

Per shape (quarter model, the shape's published supports, the path of ``lcefem run gridshell
--model fe --shape NAME``): CPU seconds of the build and of the ramp (``time.process_time``, this
process only), path steps, Newton iterations, cut steps, LDL^T factorisations, the share of the
ramp's wall time in the factorisations and in the Jacobian assemblies (PETSc's event log), and the
circle and quadratic centre curvatures [1/mm]. ``--baseline`` runs the ramp as before the speed-up:
MUMPS's automatic ordering (ICNTL(7) = 7, METIS here). Path control: the shared
:class:`lcefem.solvers.continuation.PathControl` in both.

Not a test: it prints figures for docs/performance.md. The machine load matters: give it with the
numbers (CPU seconds compare across loads better than wall, not exactly).
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import time

#: What --baseline passes instead of the speed-up: MUMPS's automatic ordering choice.
BASELINE_ORDERING = {"mat_mumps_icntl_7": 7}


def run_shape(shape: str, level: int, baseline: bool) -> dict:
    """Build and ramp one Fig. 4 shape; the figures (units in the keys)."""
    from petsc4py import PETSc

    from lcefem.validation.cases.programs import FIG4_SHAPES, fig4_shape

    PETSc.Log.begin()
    events = {name: PETSc.Log.Event(name) for name in ("MatCholFctrNum", "SNESJacobianEval")}
    before = {name: e.getPerfInfo() for name, e in events.items()}
    cpu0 = time.process_time()
    if baseline:
        from lcefem.meshes.gridshell_fe import GridshellFEMesh
        from lcefem.solvers.problems.gridshell import (
            GridshellConfig,
            GridshellFE,
            GridshellSupports,
        )
        from lcefem.validation.cases.programs import PUBLISHED_SUPPORTS

        cfg = GridshellConfig(
            mesh=GridshellFEMesh(level=level),
            symmetry="quarter",
            supports=GridshellSupports(kind=PUBLISHED_SUPPORTS[shape]),
        )
        model = GridshellFE(cfg, petsc_options=dict(BASELINE_ORDERING))
    else:
        model = fig4_shape(shape, mesh_level=level)
    cpu1, wall1 = time.process_time(), time.perf_counter()
    states = model.ramp(FIG4_SHAPES[shape])
    cpu2, wall2 = time.process_time(), time.perf_counter()
    after = {name: e.getPerfInfo() for name, e in events.items()}
    f = model.last_follower
    obs = model.observables()
    ramp_wall = max(wall2 - wall1, 1e-9)

    def share(name: str) -> float:
        return (after[name]["time"] - before[name]["time"]) / ramp_wall

    return {
        "shape": shape,
        "level": level,
        "variant": "baseline" if baseline else "default",
        "dofs": model.ndofs,
        "build cpu [s]": cpu1 - cpu0,
        "ramp cpu [s]": cpu2 - cpu1,
        "cpu [s]": cpu2 - cpu0,
        "ramp wall [s]": ramp_wall,
        "steps": len(states),
        "newton iterations": f.iterations,
        "cut steps": f.cuts,
        "folds": f.snaps,
        "factorisations": after["MatCholFctrNum"]["count"] - before["MatCholFctrNum"]["count"],
        "factorisation share of wall [-]": share("MatCholFctrNum"),
        "jacobian share of wall [-]": share("SNESJacobianEval"),
        "peak memory [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        **{k: v for k, v in obs.items() if k.startswith("kappa_") or k == "apex_z [mm]"},
    }


def main(argv: list[str] | None = None) -> int:
    import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

    from lcefem.validation.cases.programs import FIG4_SHAPES

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--shapes",
        nargs="+",
        default=["dome", "table", "saddle", "cylinder"],
        choices=list(FIG4_SHAPES),
    )
    parser.add_argument("--level", type=int, default=0, choices=range(4), help="FE mesh level")
    parser.add_argument(
        "--baseline", action="store_true", help="switch the speed-up off (MUMPS's own ordering)"
    )
    parser.add_argument("--json", default=None, help="also write the figures to this file")
    args = parser.parse_args(argv)
    print(
        f"python {platform.python_version()}, {platform.machine()}; FE gridshell, quarter, level "
        f"{args.level}, {'baseline' if args.baseline else 'default'}; load average "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores",
        flush=True,
    )
    rows = []
    for shape in args.shapes:
        r = run_shape(shape, args.level, args.baseline)
        rows.append(r)
        print(
            f"{shape}: {r['cpu [s]']:.1f} s CPU (ramp {r['ramp cpu [s]']:.1f}), {r['steps']} "
            "steps, "
            f"{r['newton iterations']} Newton its ({r['cut steps']} cuts), {r['factorisations']} "
            f"LDL^T (share of wall: factorisation {r['factorisation share of wall [-]']:.2f}, "
            f"Jacobian {r['jacobian share of wall [-]']:.2f}); circle "
            f"{r['kappa_circle_x [1/mm]']:+.8f} {r['kappa_circle_y [1/mm]']:+.8f}, quadratic "
            f"{r['kappa_quad_x [1/mm]']:+.8f} {r['kappa_quad_y [1/mm]']:+.8f} 1/mm",
            flush=True,
        )
    if args.json:
        from lcefem.solvers.runtime.files import write_json

        write_json(args.json, rows)  # .part then rename, strict JSON
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
