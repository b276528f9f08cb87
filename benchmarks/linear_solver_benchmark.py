"""Linear solvers inside Newton on large meshes: direct (MUMPS), CG + GAMG and CG + p-multigrid.

    python benchmarks/linear_solver_benchmark.py --levels 2 3 4
        [--solvers ldlt gamg ...] [--csv results/linear_solver_benchmark.csv] [--max-memory 8000]

One nonlinear solve per (strip level, solver set): the heated strip (quarter, Q2 hexahedra, free)
is brought from the cast state to a prescribed hot-core temperature field (:func:`hot_core`) by the
one path follower, with the Newton options of :mod:`lcefem.solvers.mechanics` and the overrides of
:data:`SOLVER_SETS`. Each row: displacement DOFs, Newton iterations, CG iterations, time per Newton
iteration split into Jacobian assembly, PCSetUp (factorisation or multigrid set-up) and KSPSolve
(triangular solves or CG), all per linear solve (Newton's and the tangent predictor's), peak
resident memory of the process (each row runs in its own process), the final stretch (every path
must give the direct solver's answer to the Newton tolerance) and the PETSc options no object used
(an option name PETSc does not know would show there).

Not a test: times depend on the machine load; compare CPU times, iteration counts and ratios of
rows run back to back.
"""

from __future__ import annotations

import argparse
import json
import math
import pathlib
import subprocess
import sys

from fe_benchmark import print_table, timed_solve, write_table_csv

#: Temperatures of the prescribed field :func:`hot_core` [C]: the coil's core at 80 C (above
#: T_NI = 68.9 C, so the core contracts) and the surface near 40 C, roughly the strip ~10 s into
#: the 0.2 A transient; a smooth, non-uniform spontaneous strain, so Newton has real work.
CORE_TEMPERATURE, AMBIENT_TEMPERATURE = 80.0, 40.0

#: Solver sets (overrides of ``NEWTON_OPTIONS``). ``auto``: none (the path follows the size);
#: ``ldlt``: MUMPS LDL^T (the default below ``ITERATIVE_PATH_DOFS``); ``metis``:
#: the same with METIS ordering (ICNTL(7) = 5); ``blr*``: MUMPS block low-rank factorisation
#: (ICNTL(35) = 1, dropping tolerance CNTL(7)) used directly or as a CG preconditioner; ``gamg``:
#: :data:`lcefem.solvers.mechanics.GAMG_OPTIONS` (CG to 1e-4); ``gamg-*``: one change each
#: to the same with CG to 1e-8 (``gamg-rtol8``).


#: ``pmg``: :data:`lcefem.solvers.pmultigrid.PMG_OPTIONS` (Q2 -> Q1 p-multigrid, one SOR sweep on
#: Q2, the Q1 level factorised by MUMPS LDL^T); ``pmg-gamg``: one GAMG cycle on Q1 instead
#: (:data:`lcefem.solvers.mechanics.PMG_GAMG_COARSE`); ``pmg-cheb``: Chebyshev(3)/Jacobi smoothing
#: on Q2; ``pmg-chebsor``: Chebyshev(2) with the SOR sweep as its preconditioner; ``pmg-aij``:
#: the SOR sweeps on K itself instead of its BAIJ copy; ``pmg-planes``: block Jacobi over node
#: planes on Q2 (:data:`lcefem.solvers.pmultigrid.PMG_PLANE_SMOOTHER`); ``*sor2``: two SOR sweeps.
#: (Rows of 2026-11-25 before ``pmg`` took LDL^T on Q1 are named after what ran: ``pmg-gamg`` and
#: ``pmg-gamg-sor2``.)
_PMG_CHEBYSHEV = {
    "mg_levels_ksp_type": "chebyshev",
    "mg_levels_pc_type": "jacobi",
    "mg_levels_ksp_max_it": 3,
}


def _solver_sets() -> dict[str, dict]:
    from lcefem.solvers.mechanics import GAMG_OPTIONS, PMG_GAMG_COARSE
    from lcefem.solvers.pmultigrid import PMG_PLANE_SMOOTHER

    g = dict(GAMG_OPTIONS)
    g8 = {**g, "ksp_rtol": 1e-8}  # the variants were measured with exact (1e-8) CG solves
    # every MUMPS set names its pc_type: above ITERATIVE_PATH_DOFS the default is CG + p-multigrid
    ldlt = {"pc_type": "cholesky"}
    # the factorisation of the step's first tangent preconditions CG for the rest of the Newton
    # solve
    lag_pc = {
        **ldlt,
        "ksp_type": "cg",
        "ksp_rtol": 1e-8,
        "ksp_max_it": 200,
        "snes_lag_preconditioner": 100,
    }
    blr_pc = {
        **ldlt,
        "ksp_type": "cg",
        "ksp_rtol": 1e-8,
        "ksp_max_it": 200,
        "mat_mumps_icntl_35": 1,
    }
    return {
        "auto": {},  # the size decides (solvers.mechanics.solver_options)
        "ldlt": ldlt,
        "metis": {**ldlt, "mat_mumps_icntl_7": 5},
        "lu": {"pc_type": "lu"},
        "blr-8": {**ldlt, "mat_mumps_icntl_35": 1, "mat_mumps_cntl_7": 1e-8},
        "blr-6-cg": {**blr_pc, "mat_mumps_cntl_7": 1e-6},
        "blr-4-cg": {**blr_pc, "mat_mumps_cntl_7": 1e-4},
        "ldlt-lag-cg": {**lag_pc},
        "blr-4-lag-cg": {**lag_pc, "mat_mumps_icntl_35": 1, "mat_mumps_cntl_7": 1e-4},
        "gamg": g,
        "gamg-rtol8": g8,
        "gamg-t0": {**g8, "pc_gamg_threshold": 0.0},
        "gamg-t-1": {**g8, "pc_gamg_threshold": -1.0},
        "gamg-t05": {**g8, "pc_gamg_threshold": 0.05},
        "gamg-agg0": {**g8, "pc_gamg_aggressive_coarsening": 0},
        "gamg-agg2": {**g8, "pc_gamg_aggressive_coarsening": 2},
        "gamg-sor": {**g8, "mg_levels_pc_type": "sor"},
        "gamg-cheb2": {**g8, "mg_levels_ksp_max_it": 2},
        "gamg-cheb5": {**g8, "mg_levels_ksp_max_it": 5},
        "gamg-esteig": {**g8, "mg_levels_ksp_chebyshev_esteig": "0,0.05,0,1.1"},
        "gamg-reuse": {**g8, "pc_gamg_reuse_interpolation": True},
        "gamg-lag": {**g8, "snes_lag_preconditioner": 100},
        "gamg-rtol6": {**g8, "ksp_rtol": 1e-6},
        "gamg-rtol4": {**g8, "ksp_rtol": 1e-4},
        "gamg-ew": {**g8, "snes_ksp_ew": True},
        "gamg-sor-rtol4": {**g8, "mg_levels_pc_type": "sor", "ksp_rtol": 1e-4},
        "ldlt-lag-cg4": {**lag_pc, "ksp_rtol": 1e-4},
        "pmg": {"pc_type": "pmg"},
        "pmg-aij": {"pc_type": "pmg", "pmg_smoother_mat_type": "aij"},
        "pmg-planes": {"pc_type": "pmg", **PMG_PLANE_SMOOTHER},
        "pmg-sor2": {"pc_type": "pmg", "mg_levels_ksp_max_it": 2},
        "pmg-cheb": {"pc_type": "pmg", **_PMG_CHEBYSHEV},
        "pmg-chebsor": {
            "pc_type": "pmg",
            "mg_levels_ksp_type": "chebyshev",
            "mg_levels_ksp_max_it": 2,
        },
        "pmg-gamg": {"pc_type": "pmg", **PMG_GAMG_COARSE},
        "pmg-gamg-sor2": {"pc_type": "pmg", **PMG_GAMG_COARSE, "mg_levels_ksp_max_it": 2},
    }


def hot_core(geometry: dict):
    """T(x) [C]: AMBIENT + (CORE - AMBIENT) exp(-r^2 / (2 s^2)) (1 + x / L) / 2, r the distance to
    the coil axis (y = W/2, z = H/2), s the coil's half side; hotter towards the free end."""
    W, H, L = geometry["width"], geometry["thickness"], geometry["length"]
    s = 0.5 * math.sqrt(geometry["coil_area"])

    def T(x):
        import numpy as np

        r2 = (x[1] - 0.5 * W) ** 2 + (x[2] - 0.5 * H) ** 2
        return AMBIENT_TEMPERATURE + (CORE_TEMPERATURE - AMBIENT_TEMPERATURE) * np.exp(
            -r2 / (2 * s * s)
        ) * 0.5 * (1.0 + x[0] / L)

    return T


def measure(level: int, solver: str, newton_its: int | None = None) -> dict:
    """One path-followed solve of the strip at ``level`` with the solver set ``solver``; with
    ``newton_its``, instead, that many Newton iterations from the cast state straight at the
    hot-core temperature (no predictor, no step control: the cost per iteration of large meshes)."""
    import resource

    from petsc4py import PETSc

    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.continuation import StepReport
    from lcefem.solvers.mechanics import GAMG_OPTIONS  # noqa: F401  (first: MPI before petsc4py)
    from lcefem.solvers.problems.strip import StripConfig, StripSimulation

    options = dict(_solver_sets()[solver])
    if newton_its:
        options["snes_max_it"] = newton_its
    sim = StripSimulation(StripConfig(mesh=StripMesh(level=level), petsc=options))
    snes = sim.model.mechanics.snes
    A = snes.getJacobian()[0]
    PETSc.Log.begin()
    ksp0 = PETSc.Log.Event("KSPSolve").getPerfInfo()["time"]
    ksp_its = [0]
    snes.getKSP().setPostSolve(
        lambda ksp, b, x: ksp_its.__setitem__(0, ksp_its[0] + ksp.getIterationNumber())
    )
    if newton_its:
        model = sim.model
        T = sim._nodal_field(hot_core(sim.dims), "temperature", model.heat.T.x.array)
        model.heat.T.x.array[:] = model.T_mech.x.array[:] = T
        (_, n_its, _), t = timed_solve(snes, model.mechanics.solve)
        report = StepReport(substeps=0, cuts=0, iterations=n_its)
    else:
        report, t = timed_solve(snes, lambda: sim.set_temperature(hot_core(sim.dims)))
    ksp_time = PETSc.Log.Event("KSPSolve").getPerfInfo()["time"] - ksp0
    its = max(t["its"], 1)  # Jacobians = linear solves (Newton's and the tangent predictor's)
    prefix = snes.getOptionsPrefix()
    unused = sorted(k for k in options if not PETSc.Options().used(prefix + k))
    return {
        "level": level,
        "solver": solver,
        "protocol": f"{newton_its} Newton its" if newton_its else "path-followed solve",
        "dofs [-]": sim.ndofs["displacement"],
        "block size [-]": A.getBlockSize(),
        "newton its [-]": report.iterations,
        "linear solves [-]": t["its"],
        "cg its [-]": ksp_its[0],
        "steps [-]": report.substeps,
        "cuts [-]": report.cuts,
        "s/iteration [s]": t["wall"] / its,
        "jacobian/it [s]": t["jacobian"] / its,
        "pcsetup/it [s]": t["factor"] / its,
        "kspsolve/it [s]": ksp_time / its,
        "cpu/it [s]": t["cpu"] / its,
        "wall [s]": t["wall"],
        "cpu [s]": t["cpu"],
        "residual norm [N]": snes.getFunctionNorm(),
        "peak memory [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "stretch [-]": sim.stretch(),
        "unused options": " ".join(unused),
    }


COLUMNS = [
    "level",
    "solver",
    "protocol",
    "dofs [-]",
    "block size [-]",
    "steps [-]",
    "cuts [-]",
    "newton its [-]",
    "linear solves [-]",
    "cg its [-]",
    "s/iteration [s]",
    "jacobian/it [s]",
    "pcsetup/it [s]",
    "kspsolve/it [s]",
    "cpu/it [s]",
    "wall [s]",
    "cpu [s]",
    "peak memory [MiB]",
    "residual norm [N]",
    "stretch [-]",
    "unused options",
]


def growth_exponents(rows: list[dict], min_dofs: int = 40_000) -> dict[str, tuple[float, int, int]]:
    """Per solver set: the exponent p of a least-squares fit cpu/it ~ DOFs^p over the rows with at
    least ``min_dofs`` DOFs (the issue's target: p <= 1.15 from 50k DOFs), with the DOF range."""
    import numpy as np

    out = {}
    for solver in dict.fromkeys(r["solver"] for r in rows):
        pts = sorted(
            (float(r["dofs [-]"]), float(r["cpu/it [s]"]))
            for r in rows
            if r["solver"] == solver and float(r["dofs [-]"]) >= min_dofs
        )
        if len(pts) >= 2:
            n, t = np.log(np.array(pts)).T
            out[solver] = (float(np.polyfit(n, t, 1)[0]), int(pts[0][0]), int(pts[-1][0]))
    return out


def crossover(rows: list[dict], direct: str = "ldlt", iterative: str = "gamg") -> float | None:
    """DOFs at which ``iterative`` becomes as cheap per iteration (CPU) as ``direct``: the ratio's
    log interpolated linearly in log DOFs between the two measured sizes around its sign change;
    None when it does not change sign in the rows."""
    import numpy as np

    def cost(name):
        return {float(r["dofs [-]"]): float(r["cpu/it [s]"]) for r in rows if r["solver"] == name}

    d, i = cost(direct), cost(iterative)
    pts = sorted((n, np.log(i[n] / d[n])) for n in d.keys() & i.keys())
    for (n0, r0), (n1, r1) in zip(pts, pts[1:]):
        if r0 > 0.0 >= r1:
            return float(np.exp(np.log(n0) + r0 / (r0 - r1) * (np.log(n1) - np.log(n0))))
    return None


def _read_csv(paths: list[pathlib.Path]) -> list[dict]:
    import csv

    def value(text: str):
        for kind in (int, float):
            try:
                return kind(text)
            except ValueError:
                pass
        return text

    rows = []
    for path in paths:
        with open(path, newline="") as fh:
            rows += [{k: value(v) for k, v in r.items()} for r in csv.DictReader(fh)]
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sets = _solver_sets()
    parser.add_argument("--levels", type=int, nargs="+", default=[2, 3])
    parser.add_argument(
        "--solvers",
        nargs="+",
        default=["ldlt", "gamg"],
        help=f"solver sets, from {', '.join(sets)}",
    )
    parser.add_argument(
        "--newton-its",
        type=int,
        default=None,
        help="only this many Newton iterations straight at the hot core (large meshes)",
    )
    parser.add_argument("--csv", type=pathlib.Path, default=None, help="CSV file of the table")
    parser.add_argument(
        "--merge",
        type=pathlib.Path,
        nargs="+",
        default=None,
        help="no runs: the table and growth exponents of these CSV files (one --csv)",
    )
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    for name in args.solvers:
        if name not in sets:
            parser.error(f"--solvers: {name!r} is not one of {', '.join(sets)}")
    if args.child:
        print(json.dumps(measure(int(args.child[0]), args.child[1], args.newton_its)))
        return 0
    rows = _read_csv(args.merge) if args.merge else []
    for level in [] if args.merge else args.levels:
        for solver in args.solvers:
            cmd = [sys.executable, __file__, "--child", str(level), solver]
            if args.newton_its:
                cmd += ["--newton-its", str(args.newton_its)]
            out = subprocess.run(cmd, capture_output=True, text=True)
            if out.returncode != 0:
                print(f"level {level} {solver} failed:\n{out.stderr[-2000:]}", file=sys.stderr)
                continue
            # PETSc may print its unused-option warning after the row
            rows.append(
                json.loads([ln for ln in out.stdout.splitlines() if ln.startswith("{")][-1])
            )
            print_table(rows[-1:], columns=COLUMNS, file=sys.stderr)
    print_table(rows, columns=COLUMNS)
    for protocol in dict.fromkeys(r.get("protocol", "") for r in rows):
        same = [r for r in rows if r.get("protocol", "") == protocol]
        for solver, (p, lo, hi) in growth_exponents(same).items():
            print(f"{solver}, {protocol}: cpu per iteration ~ DOFs^{p:.2f} from {lo} to {hi} DOFs")
        sizes = {}
        for r in same:
            sizes.setdefault(r["solver"], set()).add(r["dofs [-]"])
        for it in sorted(
            n
            for n in sizes
            if n.startswith(("gamg", "pmg", "auto"))
            and len(sizes[n] & sizes.get("ldlt", set())) >= 2
        ):
            n = crossover(same, "ldlt", it)
            print(
                f"{it} vs ldlt, {protocol}: crossover "
                + (f"at {n:.0f} DOFs" if n else "not in the measured range")
            )
    if args.csv is not None:
        write_table_csv(args.csv, COLUMNS, rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
