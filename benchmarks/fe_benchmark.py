"""Cost of the 3D FE solves per Newton iteration: DOFs, seconds per iteration split into residual
assembly, Jacobian assembly, factorisation and triangular solves, Newton iterations per step, peak
memory; for the strip's 0.2 A transient and the composite beam's ramp to (lambda_T, lambda_B).

    python benchmarks/fe_benchmark.py [--strip-levels 0 1 2] [--beam-levels 0 1]
        [--csv results/fe_benchmark.csv] [--strip-steps 6] [--strip-dt 2.0] [--linear-levels 2 3]
        [--beam-variants newton lag2 cp ...]

``--beam-variants``: the beam ramp once per named variant of :data:`BEAM_VARIANTS` (line searches,
trust region, Jacobian reuse, nonlinear preconditioning, quasi-Newton, predictors, compile flags),
back to back, each row with its Newton iterations, Jacobian assemblies, numeric factorisations,
residual evaluations, refused iterates (non-finite or det F <= 0) and curvature.

``--linear-levels``: a second table, one tangent of the heated strip per level solved by MUMPS LDL^T
and by CG + algebraic multigrid (GAMG with the rigid-body near-nullspace, block size 3), and the
Jacobian's assembly time into AIJ and BAIJ (block 3) matrices: the crossover of the iterative path.

Each case runs in its own process (the peak resident memory is that case's alone). Residual and
Jacobian times are measured around the SNES callbacks (contact and damping terms included);
factor = PETSc's PCSetUp event (symbolic + numeric factorisation, or a preconditioner set-up),
solve = MatSolve (forward/backward substitution). "other" is the rest of the mechanics time (vector
updates, convergence tests, step control, the heat solves of the strip). "cpu" is the process CPU
time of the same span: on a shared machine compare CPU times, iteration counts and ratios, or run
two versions at the same time. Not a test: figures depend on the machine load.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import datetime
import json
import pathlib
import subprocess
import sys
import time

COLUMNS = [
    "case",
    "variant",
    "level",
    "dofs [-]",
    "steps [-]",
    "newton its [-]",
    "its/step [-]",
    "cuts [-]",
    "jacobians [-]",
    "factorisations [-]",
    "residuals [-]",
    "refused iterates [-]",
    "s/iteration [s]",
    "residual/it [s]",
    "jacobian/it [s]",
    "factor/it [s]",
    "solve/it [s]",
    "other/it [s]",
    "mechanics [s]",
    "wall [s]",
    "cpu [s]",
    "peak memory [MiB]",
    "observable",
    "value",
    "date",
]


class SnesTimer:
    """Wraps a SNES's residual and Jacobian callbacks with wall-clock timers."""

    def __init__(self, snes):
        self.residual = self.jacobian = 0.0
        self.residual_calls = self.jacobian_calls = 0
        self.snes = snes
        self.install()

    def install(self):
        snes = self.snes
        b, (rfun, rargs, rkw) = snes.getFunction()
        J, P, (jfun, jargs, jkw) = snes.getJacobian()
        rargs, rkw, jargs, jkw = rargs or (), rkw or {}, jargs or (), jkw or {}

        def residual(s, x, f):
            t0 = time.perf_counter()
            rfun(s, x, f, *rargs, **rkw)
            self.residual += time.perf_counter() - t0
            self.residual_calls += 1

        def jacobian(s, x, A, B):
            t0 = time.perf_counter()
            jfun(s, x, A, B, *jargs, **jkw)
            self.jacobian += time.perf_counter() - t0
            self.jacobian_calls += 1

        snes.setFunction(residual, b)
        snes.setJacobian(jacobian, J, P)


def _events() -> dict:
    from petsc4py import PETSc

    out = {}
    for name in ("PCSetUp", "MatSolve", "SNESSolve"):
        info = PETSc.Log.Event(name).getPerfInfo()
        out[name] = float(info["time"])
    # numeric factorisations (Cholesky or LU), the unit of cost of a direct-solver Newton step
    out["factorisations"] = sum(
        int(PETSc.Log.Event(name).getPerfInfo()["count"])
        for name in ("MatCholFctrNum", "MatLUFactorNum")
    )
    return out


def timed_solve(snes, run):
    """Run ``run()`` with ``snes`` instrumented; returns (result, timings)."""
    from petsc4py import PETSc

    PETSc.Log.begin()
    timer = SnesTimer(snes)
    ev0 = _events()
    t0, c0 = time.perf_counter(), time.process_time()
    result = run()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    ev = {k: v - ev0[k] for k, v in _events().items()}
    return result, {
        "wall": wall,
        "cpu": cpu,
        "residual": timer.residual,
        "jacobian": timer.jacobian,
        "its": timer.jacobian_calls,
        "residuals": timer.residual_calls,
        "factorisations": ev["factorisations"],
        "factor": ev["PCSetUp"],
        "solve": ev["MatSolve"],
        "snes": ev["SNESSolve"],
    }


def measure_strip(level: int, steps: int, dt: float) -> dict:
    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation

    sim = StripSimulation(
        StripConfig(
            run=StripRun(current=0.2, duration=steps * dt, dt=dt), mesh=StripMesh(level=level)
        )
    )
    res, t = timed_solve(
        sim.model.mechanics.snes, lambda: sim.run(None, progress=False, fields=False)
    )
    cuts = int(sum(res.history["step_cuts [-]"][1:]))
    return {
        "case": "strip 0.2 A",
        "level": level,
        "dofs [-]": sim.ndofs["displacement"],
        "steps [-]": steps,
        "cuts [-]": cuts,
        "observable": "final stretch [-]",
        "value": float(res.history["stretch [-]"][-1]),
        **_split(t),
    }


#: Newton variants of the beam ramp (overrides of the beam's Newton options): the configured full
#: Newton step and the default step controller (``O2``: the kernels compiled with dolfinx's default
#: flags instead of :data:`lcefem.solvers.mechanics.JIT_OPTIONS`; ``tangent``: the Euler predictor
#: instead of the curved one; ``before``: both, and the step control aiming at 10 iterations with
#: steps up to 0.2 and the whole tangent stored (AIJ), the state before issue 13's beam-ramp work;
#: ``aij``: the whole tangent stored instead of its upper triangle in node blocks
#: (:data:`lcefem.solvers.mechanics.PACKED_TANGENT`); ``metis``: METIS's ordering instead of
#: :data:`lcefem.solvers.problems.composite_beam.BEAM_ORDERING`'s; ``base``: both, the default of
#: 2026-11-25; ``t12``: the beam's step control
#: (:data:`lcefem.solvers.problems.composite_beam.BEAM_CONTROL`, 12 iterations, steps up to 0.25),
#: ``t10``: the shared defaults (10 iterations, steps up to 0.2);
#: ``native``: the kernels compiled for this processor, ``-march=native``); the Jacobian (and its
#: factorisation) reused for 2 or 3 iterations (modified Newton); PETSc's critical-point (one or
#: three secant steps), backtracking (on |R|^2), L2 line searches, steps damped to 0.8 and the trust
#: region. One Newton step with the beam's direct solver as a nonlinear preconditioner (``npc_``
#: prefix).
NEWTON_NPC = {
    "npc_snes_type": "newtonls",
    "npc_snes_max_it": 1,
    "npc_snes_linesearch_type": "basic",
    "npc_ksp_type": "preonly",
    "npc_pc_type": "cholesky",
    "npc_pc_factor_mat_solver_type": "mumps",
}

BEAM_VARIANTS = {
    "newton": {},
    "before": {
        "jit_options": {},
        "packed_tangent": False,
        "predictor": "tangent",
        "target_iterations": 10,
        "max_step": 0.2,
    },
    "aij": {"packed_tangent": False},
    "metis": {"mat_mumps_icntl_7": 5},
    "base": {"packed_tangent": False, "mat_mumps_icntl_7": 5},
    "t10": {"target_iterations": 10, "max_step": 0.2},
    "O2": {"jit_options": {}},
    "tangent": {"predictor": "tangent"},
    "t12": {"target_iterations": 12, "max_step": 0.25},
    "native": {"jit_extra_flags": ["-march=native"]},
    "lag2": {"snes_lag_jacobian": 2, "snes_max_it": 30},
    "lag3": {"snes_lag_jacobian": 3, "snes_max_it": 40},
    "cp": {"snes_linesearch_type": "cp"},
    "cp3": {"snes_linesearch_type": "cp", "snes_linesearch_max_it": 3},
    "damped": {"snes_linesearch_damping": 0.8},
    "bt": {"snes_linesearch_type": "bt"},
    "l2": {"snes_linesearch_type": "l2"},
    "newtontr": {"snes_type": "newtontr"},
    "nleqerr": {"snes_linesearch_type": "nleqerr"},
    "ngmres-r": {"snes_type": "ngmres", "snes_npc_side": "right", **NEWTON_NPC},
    "ngmres-l": {"snes_type": "ngmres", "snes_npc_side": "left", **NEWTON_NPC},
    "anderson-r": {"snes_type": "anderson", "snes_npc_side": "right", **NEWTON_NPC},
    "qn-l": {"snes_type": "qn", "snes_npc_side": "left", **NEWTON_NPC},
    "qn-jac": {
        "snes_type": "qn",
        "snes_qn_type": "lbfgs",
        "snes_qn_scale_type": "jacobian",
        "snes_max_it": 60,
    },
}


def measure_beam(
    level: int, lambda_top: float, lambda_bottom: float, variant: str = "newton"
) -> dict:
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers import mechanics
    from lcefem.solvers.continuation import PathControl
    from lcefem.solvers.problems.composite_beam import BEAM_CONTROL, BeamFE

    options = dict(BEAM_VARIANTS[variant])
    if "jit_options" in options:  # the kernels compiled with other flags (e.g. dolfinx's -O2)
        mechanics.JIT_OPTIONS = options.pop("jit_options")
    if "packed_tangent" in options:  # AIJ instead of the upper triangle in node blocks (SBAIJ)
        mechanics.PACKED_TANGENT = options.pop("packed_tangent")
    if "jit_extra_flags" in options:  # more compile flags than JIT_OPTIONS's (e.g. -march=native)
        flags = mechanics.JIT_OPTIONS["cffi_extra_compile_args"] + options.pop("jit_extra_flags")
        mechanics.JIT_OPTIONS = {**mechanics.JIT_OPTIONS, "cffi_extra_compile_args": flags}
    # fields of the step controller (predictor, target iterations, ...) are not PETSc options
    control = dataclasses.replace(
        BEAM_CONTROL,
        **{
            f.name: options.pop(f.name)
            for f in dataclasses.fields(PathControl)
            if f.name in options
        },
    )
    model = BeamFE(mesh=BeamFEMesh(level=level), petsc_options=options, control=control)
    states, t = timed_solve(model.problem.snes, lambda: model.ramp(lambda_top, lambda_bottom))
    f = model.last_follower
    t["jacobians"], t["its"] = t["its"], f.iterations  # they differ when the Jacobian is reused
    return {
        "case": f"beam ramp ({lambda_top:g}, {lambda_bottom:g})",
        "variant": variant,
        "level": level,
        "dofs [-]": model.ndofs,
        "steps [-]": len(states),
        "cuts [-]": f.cuts,
        "jacobians [-]": t["jacobians"],
        "factorisations [-]": t["factorisations"],
        "residuals [-]": t["residuals"],
        "refused iterates [-]": model.problem.inverted_iterates,
        "observable": "curvature [1/mm]",
        "value": model.curvature(),
        **_split(t),
    }


def _split(t: dict) -> dict:
    its = max(t["its"], 1)
    other = t["wall"] - t["residual"] - t["jacobian"] - t["factor"] - t["solve"]
    return {
        "newton its [-]": t["its"],
        "s/iteration [s]": t["wall"] / its,
        "residual/it [s]": t["residual"] / its,
        "jacobian/it [s]": t["jacobian"] / its,
        "factor/it [s]": t["factor"] / its,
        "solve/it [s]": t["solve"] / its,
        "other/it [s]": other / its,
        "mechanics [s]": t["snes"] or t["wall"],
        "wall [s]": t["wall"],
        "cpu [s]": t["cpu"],
    }


LINEAR_COLUMNS = [
    "level",
    "dofs [-]",
    "assemble aij [s]",
    "assemble baij [s]",
    "ldlt factor [s]",
    "ldlt solve [s]",
    "gamg setup [s]",
    "gamg solve [s]",
    "gamg its [-]",
    "gamg/ldlt [-]",
    "relative difference [-]",
]


def measure_linear(level: int, steps: int, dt: float) -> dict:
    """One tangent of the heated strip (after ``steps`` steps of ``dt`` at 0.2 A) solved by MUMPS
    LDL^T and by CG + GAMG (rigid-body near-nullspace, block size 3, :data:`GAMG_OPTIONS`); the
    Jacobian assembled into AIJ and into BAIJ (block 3)."""
    from petsc4py import PETSc

    import dolfinx.fem.petsc

    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.mechanics import GAMG_OPTIONS, rigid_body_modes  # first: orders MPI
    from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation

    sim = StripSimulation(
        StripConfig(
            run=StripRun(current=0.2, duration=steps * dt, dt=dt), mesh=StripMesh(level=level)
        )
    )
    sim.run(None, progress=False, fields=False)
    mech = sim.model.mechanics
    J_form, bcs = mech._problem.J, mech.bcs
    row = {"level": level, "dofs [-]": sim.ndofs["displacement"]}
    mats = {}
    for kind in ("aij", "baij"):
        A = dolfinx.fem.petsc.create_matrix(J_form, kind=kind)
        A.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(A, J_form, bcs=bcs)  # first pass: allocation, warm-up
        A.assemble()
        A.zeroEntries()
        t0 = time.perf_counter()
        dolfinx.fem.petsc.assemble_matrix(A, J_form, bcs=bcs)
        A.assemble()
        row[f"assemble {kind} [s]"] = time.perf_counter() - t0
        A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        mats[kind] = A
    A = mats["aij"]
    A.setBlockSize(3)
    A.setNearNullSpace(rigid_body_modes(mech.u.function_space))
    b = A.createVecLeft()
    b.set(1.0)
    dolfinx.fem.petsc.set_bc(b, bcs, alpha=0.0)
    solutions = {}
    for name, options in (
        (
            "ldlt",
            {"ksp_type": "preonly", "pc_type": "cholesky", "pc_factor_mat_solver_type": "mumps"},
        ),
        ("gamg", GAMG_OPTIONS),
    ):
        prefix = f"linbench_{name}_"
        opts = PETSc.Options()
        for k, v in options.items():
            opts[prefix + k] = v
        ksp = PETSc.KSP().create(A.comm)
        ksp.setOptionsPrefix(prefix)
        ksp.setOperators(A)
        ksp.setFromOptions()
        x = b.duplicate()
        t0 = time.perf_counter()
        ksp.setUp()
        t1 = time.perf_counter()
        ksp.solve(b, x)
        t2 = time.perf_counter()
        label = "factor" if name == "ldlt" else "setup"
        row[f"{name} {label} [s]"], row[f"{name} solve [s]"] = t1 - t0, t2 - t1
        if name == "gamg":
            row["gamg its [-]"] = ksp.getIterationNumber() if ksp.getConvergedReason() > 0 else -1
        solutions[name] = x
    row["gamg/ldlt [-]"] = (row["gamg setup [s]"] + row["gamg solve [s]"]) / (
        row["ldlt factor [s]"] + row["ldlt solve [s]"]
    )
    d = solutions["gamg"] - solutions["ldlt"]
    row["relative difference [-]"] = d.norm() / solutions["ldlt"].norm()
    return row


def child(args) -> dict:
    import resource

    kind, level = args.child
    if kind == "linear":
        row = measure_linear(int(level), 2, args.strip_dt)
        row["peak memory [MiB]"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        return row
    if kind == "strip":
        row = measure_strip(int(level), args.strip_steps, args.strip_dt)
    else:
        row = measure_beam(int(level), args.lambda_top, args.lambda_bottom, args.beam_variant)
    row["its/step [-]"] = row["newton its [-]"] / max(row["steps [-]"], 1)
    row["peak memory [MiB]"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    row["date"] = datetime.date.today().isoformat()  # rows of different days share one CSV
    return row


def print_table(rows: list[dict], file=sys.stdout, columns: list[str] | None = None) -> None:
    short = columns or [
        "case",
        "variant",
        "level",
        "dofs [-]",
        "newton its [-]",
        "its/step [-]",
        "cuts [-]",
        "jacobians [-]",
        "factorisations [-]",
        "residuals [-]",
        "refused iterates [-]",
        "s/iteration [s]",
        "residual/it [s]",
        "jacobian/it [s]",
        "factor/it [s]",
        "solve/it [s]",
        "wall [s]",
        "cpu [s]",
        "peak memory [MiB]",
        "value",
    ]
    cells = [[_fmt(r.get(k, "")) for k in short] for r in rows]
    widths = [max(len(k), *(len(c[i]) for c in cells)) for i, k in enumerate(short)]
    print("  ".join(k.rjust(w) for k, w in zip(short, widths)), file=file)
    for c in cells:
        print("  ".join(v.rjust(w) for v, w in zip(c, widths)), file=file)


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.7g}" if abs(v) < 1e-2 else f"{v:.4g}"
    return str(v)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strip-levels", type=int, nargs="*", default=[0, 1, 2])
    parser.add_argument("--beam-levels", type=int, nargs="*", default=[0, 1])
    parser.add_argument("--strip-steps", type=int, default=6, help="time steps of the transient")
    parser.add_argument("--strip-dt", type=float, default=2.0, help="time step [s]")
    parser.add_argument("--lambda-top", type=float, default=1.33)
    parser.add_argument("--lambda-bottom", type=float, default=1.05)
    parser.add_argument(
        "--linear-levels",
        type=int,
        nargs="*",
        default=[],
        help="strip levels at which one tangent is solved by MUMPS LDL^T and by "
        "CG + GAMG, and assembled as AIJ and BAIJ (a separate table)",
    )
    parser.add_argument(
        "--beam-variants",
        nargs="+",
        default=["newton"],
        help=f"Newton variants of the beam ramp, from {', '.join(BEAM_VARIANTS)}",
    )
    parser.add_argument("--csv", type=pathlib.Path, default=None, help="CSV file of the table")
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    parser.add_argument("--beam-variant", default="newton", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    for name in args.beam_variants + [args.beam_variant]:
        if name not in BEAM_VARIANTS:
            parser.error(f"--beam-variants: {name!r} is not one of {', '.join(BEAM_VARIANTS)}")
    if args.child:
        print(json.dumps(child(args)))
        return 0
    rows = []
    jobs = [("strip", lv, "newton") for lv in args.strip_levels]
    jobs += [("beam", lv, v) for lv in args.beam_levels for v in args.beam_variants]
    jobs += [("linear", lv, "newton") for lv in args.linear_levels]
    for kind, level, variant in jobs:
        cmd = [
            sys.executable,
            __file__,
            "--child",
            kind,
            str(level),
            "--strip-steps",
            str(args.strip_steps),
            "--strip-dt",
            str(args.strip_dt),
            "--lambda-top",
            str(args.lambda_top),
            "--lambda-bottom",
            str(args.lambda_bottom),
            "--beam-variant",
            variant,
        ]
        out = subprocess.run(cmd, capture_output=True, text=True)
        if out.returncode != 0:
            print(f"{kind} level {level} failed:\n{out.stderr[-2000:]}", file=sys.stderr)
            continue
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"{kind} level {level} done", file=sys.stderr, flush=True)
    linear = [r for r in rows if "gamg its [-]" in r]
    rows = [r for r in rows if "gamg its [-]" not in r]
    if rows:
        print_table(rows)
    if linear:
        print_table(linear, columns=LINEAR_COLUMNS + ["peak memory [MiB]"])
    if args.csv is not None:
        write_table_csv(args.csv, COLUMNS, rows)
        if linear:
            write_table_csv(
                args.csv.with_name(args.csv.stem + "_linear.csv"),
                LINEAR_COLUMNS + ["peak memory [MiB]"],
                linear,
            )
    return 0


def write_table_csv(path: pathlib.Path, columns: list[str], rows: list[dict]) -> None:
    """The table under a temporary name, renamed when complete."""
    from lcefem.solvers.runtime.files import part_name, replace

    path.parent.mkdir(parents=True, exist_ok=True)
    with open(part_name(path), "w", newline="") as fh:
        w = csv.DictWriter(fh, columns, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    replace(part_name(path), path)


if __name__ == "__main__":
    raise SystemExit(main())
