"""The lowest eigenvalues of the FE gridshell's tangent along a ramp (issue 47, the cause
layout_5x5_fold: does the continuum lose stability where the bar-and-hinge 5 x 5 dome folds?).

Runs the ramp of ``lcefem run gridshell --model fe --layout 5x5 --shape dome --support rollers
--mesh-level 0`` (the same configuration, built by the command line's own ``prepare_fe``) in pieces
that end at the analysed load factors (default t = 0.7, 0.8, 0.9, 1.0; each piece the path
follower of the run), and at each end state:

* the tangent K = d^2 Pi/du^2 (the SNES Jacobian: volume terms, strip-ribbon contact) [N/mm],
  with the Dirichlet rows and columns removed (mirror planes, rollers);
* its lowest eigenvalues mu (K phi = mu phi, Euclidean metric on the nodal DOFs; SLEPc Krylov-Schur,
  shift-invert about ``--sigma`` with a MUMPS LDL^T) [N/mm];
* the inertia: the number of negative pivots of the LDL^T of K (MUMPS INFOG(12)), by Sylvester's law
  the number of negative eigenvalues of K (0: the state is stable against every mode the model
  can represent; the quarter model: modes symmetric about the mirror planes x = c and y = c);
* the circle curvatures [1/mm] and, per eigenvector, the share of |phi|^2 on u_z.

At every accepted step of the ramp (not with ``--no-scan``): the negative pivots and the two lowest
eigenvalues. The states
at the analysed load factors are saved (``--states DIR``: .npz, :meth:`GridshellFE.save_state`, and
the eigenvectors), and a JSON of the numbers (``--data``, written atomically after each piece).

``--classes DIR``: no ramp; at every saved state of DIR the tangent without Dirichlet conditions
restricted to each of the four parity classes of the full model about the mirror planes
(:data:`CLASSES`): the full model's tangent at a doubly symmetric state is block-diagonal in them,
so the quarter mesh gives the full model's stability of the symmetric branch (not its path past a
bifurcation).

    OMP_NUM_THREADS=1 python benchmarks/gridshell_fe_fold_eigen.py [--at 0.7,0.8,0.9,1.0]
        [--modes 6] [--sigma -1e-6] [--states DIR] [--data FILE]
    OMP_NUM_THREADS=1 python benchmarks/gridshell_fe_fold_eigen.py --classes DIR [--data FILE]

The 5 x 5 dome, 2026-12-08: 879 s CPU to t = 1 with the scan (64 steps, ~3 s per eigen solve),
about 11 s CPU per state for ``--classes`` (after the model build). Not a test: it prints figures
(docs/notes/fe_bodies_log.md, "The 5 x 5 fold").
"""

from __future__ import annotations

import argparse
import datetime
import json
import pathlib
import sys
import time

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from petsc4py import PETSc

import numpy as np


def parse_fractions(text: str) -> list[float]:
    vals = [float(x) for x in text.split(",") if x.strip()]
    if not vals or any(not 0.0 < v <= 1.0 for v in vals) or vals != sorted(set(vals)):
        raise ValueError(text)
    return vals


def reduced_tangent(model):
    """K without the Dirichlet rows and columns (AIJ, symmetric) and the kept DOFs' index set."""
    prob = model.problem
    snes = prob.snes
    x = prob._problem.x
    import dolfinx.fem.petsc

    x = x.duplicate()  # the state, not SNES's own work vector
    dolfinx.fem.petsc.assign(model.u, x)
    A, P, _ = snes.getJacobian()
    snes.computeJacobian(x, A, P)
    x.destroy()
    full = A.convert("aij")  # SBAIJ upper triangle -> whole symmetric matrix
    n = full.getSize()[0]
    held = np.unique(np.concatenate([np.asarray(d, dtype=np.int32) for d in prob._bc_dofs]))
    keep = np.setdiff1d(np.arange(n, dtype=np.int32), held)
    iset = PETSc.IS().createGeneral(keep, comm=PETSc.COMM_SELF)
    K = full.createSubMatrix(iset, iset)
    K.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    full.destroy()
    return K, keep, held


def inertia(K) -> int:
    """Negative pivots of MUMPS's LDL^T of K (INFOG(12)): the number of negative eigenvalues."""
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setOperators(K)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("cholesky")
    pc.setFactorSolverType("mumps")
    pc.setFactorSetUpSolverType()
    F = pc.getFactorMatrix()
    F.setMumpsIcntl(7, 4)
    F.setMumpsIcntl(24, 1)  # null pivot detection: a singular K is reported, not failed
    ksp.setUp()
    neg = int(F.getMumpsInfog(12))
    null = int(F.getMumpsInfog(28))
    ksp.destroy()
    return neg, null


def lowest_eigenpairs(K, nev: int, sigma: float):
    from slepc4py import SLEPc

    eps = SLEPc.EPS().create(PETSc.COMM_SELF)
    eps.setOperators(K)
    eps.setProblemType(SLEPc.EPS.ProblemType.HEP)
    eps.setDimensions(nev, PETSc.DECIDE)
    eps.setTarget(sigma)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_REAL)
    eps.setTolerances(1e-10, 500)
    st = eps.getST()
    st.setType("sinvert")
    st.setShift(sigma)
    ksp = st.getKSP()
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("cholesky")
    pc.setFactorSolverType("mumps")
    eps.solve()
    out = []
    vr = K.createVecRight()
    for i in range(eps.getConverged()):
        mu = eps.getEigenpair(i, vr).real
        out.append((mu, vr.array.copy(), eps.computeError(i)))
    eps.destroy()
    out.sort(key=lambda p: p[0])
    return out[:nev]


#: The four parity classes of the full model's displacements about the mirror planes x = c and
#: y = c, (sign about x = c, sign about y = c, in-plane component held against the class's rigid
#: mode): "S" symmetric (the quarter model's u_n = 0 on the plane), "A" antisymmetric (u_t = u_z = 0
#: on the plane, u_n free). AS holds the x translation, SA the y translation, AA the rotation about
#: z, each by one DOF at a roller node: the full model's three published in-plane holds are
#: statically determinate, so they fix only the rigid motion.
CLASSES = {"SS": (1, 1, None), "AS": (-1, 1, 0), "SA": (1, -1, 1), "AA": (-1, -1, 0)}


def raw_tangent(model):
    """K of the current state with no Dirichlet condition (AIJ) [N/mm]: the volume forms and the
    strip-ribbon contact on every DOF."""
    import dolfinx.fem.petsc
    from dolfinx.cpp.la.petsc import create_matrix

    J = model.problem._problem.J
    pattern = dolfinx.fem.create_sparsity_pattern(J)  # the form's, plus the contact pairs'
    for c in model.contacts:
        for row in np.asarray(c.pairs, dtype=np.int32):
            pattern.insert(row, row)
    pattern.finalize()
    A = create_matrix(model.tmesh.mesh.comm, pattern, None)
    dolfinx.fem.petsc.assemble_matrix(A, J)
    A.assemble(PETSc.Mat.AssemblyType.FLUSH)
    for c in model.contacts:  # zeros on the pairs' couplings: the final assembly keeps them
        zeros = np.zeros((9, 9))
        for rows in np.asarray(c.dofs, dtype=np.int32):
            A.setValues(rows, rows, zeros, addv=PETSc.InsertMode.ADD_VALUES)
    A.assemble()
    for c in model.contacts:
        kept = c.free
        c.free = np.ones_like(kept)
        try:
            c.add_jacobian(A)
        finally:
            c.free = kept
    A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
    return A


def class_held(model, sx: int, sy: int, rigid) -> np.ndarray:
    """Held DOFs (unrolled) of a parity class: on the plane x = c u_x (S) or u_y, u_z (A), likewise
    on y = c; the rollers' u_z; one in-plane DOF against the class's rigid mode."""
    import dolfinx.fem

    tm, V = model.tmesh, model.V
    fdim = tm.mesh.topology.dim - 1
    held = [3 * model.support_nodes[2] + 2]
    for name, axis, sign in (("sym_x", 0, sx), ("sym_y", 1, sy)):
        facets = tm.facet_tags.find(tm.facet_tag(name))
        for k in [axis] if sign > 0 else [j for j in range(3) if j != axis]:
            held.append(np.asarray(dolfinx.fem.locate_dofs_topological(V.sub(k), fdim, facets)))
    if rigid is not None:
        nodes = model.support_nodes[2]
        c = np.asarray(model.info["centre"], dtype=float).reshape(-1)[:2]
        far = model._X[nodes, :2] - c
        # x translation (AS): any roller node; rotation about z (AA): u_x = -w (y - c), the
        # roller node farthest from y = c; y translation (SA): u_y
        pick = nodes[int(np.argmax(np.abs(far[:, 1])))] if sx < 0 and sy < 0 else nodes[0]
        held.append(np.array([3 * pick + rigid]))
    return np.unique(np.concatenate(held).astype(np.int32))


def classes_main(model, cfg, a) -> int:
    """Eigenvalues of the four parity classes at every saved state of ``a.classes``."""
    folder = pathlib.Path(a.classes)
    files = sorted(folder.glob("state_t*.npz"))
    if not files:
        print(f"--classes {folder}: no state_t*.npz there", file=sys.stderr)
        return 2
    lam_n = model.lambda_N
    rows = []
    for path in files:
        st = np.load(path)
        model.u.x.array[:] = st["u"]
        model.u.x.scatter_forward()
        model.lam.x.array[:] = lam_n
        for tag, value in zip(st["strip_tags"], st["strip_lambda"]):
            model.lam.x.array[model._dof_tag == tag] = value
        obs = model.observables()
        c0 = time.process_time()
        A = raw_tangent(model)
        n = A.getSize()[0]
        row = {
            "state": path.name,
            "circle_x [1/mm]": obs["kappa_circle_x [1/mm]"],
            "circle_y [1/mm]": obs["kappa_circle_y [1/mm]"],
        }
        for name, (sx, sy, rigid) in CLASSES.items():
            held = class_held(model, sx, sy, rigid)
            keep = np.setdiff1d(np.arange(n, dtype=np.int32), held)
            iset = PETSc.IS().createGeneral(keep, comm=PETSc.COMM_SELF)
            K = A.createSubMatrix(iset, iset)
            K.setOption(PETSc.Mat.Option.SYMMETRIC, True)
            neg, null = inertia(K)
            mus = [p[0] for p in lowest_eigenpairs(K, a.modes, a.sigma)]
            K.destroy()
            row[name] = {
                "held DOFs [-]": int(held.size),
                "negative pivots [-]": neg,
                "null pivots [-]": null,
                "lowest eigenvalues [N/mm]": mus,
            }
            print(
                f"{path.name} {name}: held {held.size}, negative pivots {neg}, null {null}, "
                "lowest " + ", ".join(f"{m:.4g}" for m in mus) + " N/mm",
                flush=True,
            )
        A.destroy()
        row["cpu [s]"] = time.process_time() - c0
        rows.append(row)
    if a.data:
        record = {
            "source": (
                "lcefem.solvers.problems.gridshell.GridshellFE (lcefem run gridshell --model fe "
                f"--layout {a.layout} --shape dome --support {a.support} --mesh-level {a.level}, "
                f"{cfg.symmetry} model) at the saved states of "
                "benchmarks/gridshell_fe_fold_eigen.py; the tangent (volume forms and contact, "
                "no Dirichlet condition) restricted to each parity class about the mirror planes "
                "x = c, y = c (S: u_n = 0 on the plane, A: u_t = u_z = 0), the rollers' u_z and "
                "one in-plane DOF against the class's rigid mode held; SLEPc shift-invert about "
                f"{a.sigma:g} N/mm (MUMPS), negative pivots = MUMPS INFOG(12); "
                f"{datetime.date.today()} (issue 47)"
            ),
            "classes": {k: {"x = c": v[0], "y = c": v[1]} for k, v in CLASSES.items()},
            "rows": rows,
        }
        out = pathlib.Path(a.data)
        tmp = out.with_name(out.name + ".part")
        tmp.write_text(json.dumps(record, indent=1) + "\n")
        tmp.replace(out)
        print(f"wrote {out}")
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--layout", default="5x5")
    ap.add_argument("--support", default="rollers")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--at", default="0.7,0.8,0.9,1.0", help="analysed load factors [-]")
    ap.add_argument("--modes", type=int, default=6)
    ap.add_argument("--sigma", type=float, default=-1e-6, help="shift [N/mm]")
    ap.add_argument("--states", default="", help="folder for the states (.npz)")
    ap.add_argument("--data", default="", help="JSON to write")
    ap.add_argument(
        "--no-scan", action="store_true", help="no eigen solve at the steps between load factors"
    )
    ap.add_argument(
        "--classes",
        default="",
        help="folder of saved states: no ramp; the four mirror-parity classes' eigenvalues",
    )
    a = ap.parse_args(argv)
    try:
        fractions = parse_fractions(a.at)
    except ValueError:
        print(
            f"--at = {a.at!r}: increasing load factors in (0, 1], comma-separated", file=sys.stderr
        )
        return 2
    if a.modes < 1 or a.level < 0:
        print("--modes >= 1 and --level >= 0 expected", file=sys.stderr)
        return 2
    from lcefem.solvers.problems.gridshell_fe_run import build_model, in_model
    from lcefem.validation.app.cli import build_parser
    from lcefem.validation.app.commands.gridshell import prepare_fe

    argv_run = [
        "run",
        "gridshell",
        "--model",
        "fe",
        "--layout",
        a.layout,
        "--shape",
        "dome",
        "--support",
        a.support,
        "--mesh-level",
        str(a.level),
        "--out",
        "/tmp/unused",
    ]
    args = build_parser(argv_run).parse_args(argv_run)
    cfg = prepare_fe(args)
    model = build_model(cfg)
    model.set_drives(in_model(model, cfg.drive_fields()[0]))
    if a.classes:
        return classes_main(model, cfg, a)
    states_dir = pathlib.Path(a.states) if a.states else None
    if states_dir:
        states_dir.mkdir(parents=True, exist_ok=True)
    print(
        f"# {a.layout}, {a.support}, {cfg.symmetry}, level {a.level}: {model.ndofs} DOFs",
        flush=True,
    )
    rows = []
    t_prev, cpu0 = 0.0, time.process_time()
    steps = newton = 0
    path = []  # every accepted step: t, circle curvatures, negative pivots, lowest eigenvalues

    def scan(t0: float, t1: float):
        def on_step(st) -> None:
            t = t0 + st.load_factor * (t1 - t0)
            try:
                K, _, _ = reduced_tangent(model)
                neg, _ = inertia(K)
                mus = [p[0] for p in lowest_eigenpairs(K, 2, a.sigma)]
                K.destroy()
            except Exception as exc:  # noqa: BLE001  (a scan point lost, the ramp goes on)
                print(f"  t = {t:.4f}: eigen analysis failed: {exc!r}", flush=True)
                return
            o = st.observables
            path.append(
                {
                    "t [-]": t,
                    "circle_x [1/mm]": o["kappa_circle_x [1/mm]"],
                    "circle_y [1/mm]": o["kappa_circle_y [1/mm]"],
                    "negative pivots [-]": neg,
                    "lowest eigenvalues [N/mm]": mus,
                }
            )
            print(
                f"  t = {t:.4f}: circle {path[-1]['circle_x [1/mm]']:.6f} / "
                f"{path[-1]['circle_y [1/mm]']:.6f}, negative pivots {neg}, lowest "
                + ", ".join(f"{m:.4g}" for m in mus)
                + " N/mm",
                flush=True,
            )

        return on_step

    def write_data() -> None:
        if a.data:
            record = {
                "source": (
                    "lcefem.solvers.problems.gridshell.GridshellFE (the configuration of lcefem "
                    f"run gridshell --model fe --layout {a.layout} --shape dome "
                    f"--support {a.support} "
                    f"--mesh-level {a.level}, {cfg.symmetry} model), ramped in pieces ending at "
                    f"t = {a.at}; tangent = the SNES Jacobian without the Dirichlet rows and "
                    "columns;"
                    f" eigenvalues by SLEPc Krylov-Schur shift-invert about {a.sigma:g} N/mm "
                    "(MUMPS LDL^T), negative pivots = MUMPS INFOG(12); python "
                    "benchmarks/gridshell_fe_fold_eigen.py "
                    + " ".join(argv or sys.argv[1:])
                    + f", "
                    f"{datetime.date.today()} (issue 47); serial, the shared 2-core machine"
                ),
                "layout": a.layout,
                "support": a.support,
                "symmetry": cfg.symmetry,
                "mesh level": a.level,
                "dofs [-]": int(model.ndofs),
                "path steps [-]": steps,
                "newton iterations [-]": newton,
                "rows": rows,
                "path": path,
            }
            out = pathlib.Path(a.data)
            tmp = out.with_name(out.name + ".part")
            tmp.write_text(json.dumps(record, indent=1) + "\n")
            tmp.replace(out)
            print(f"wrote {out}")

    for f in fractions:
        dt = (f - t_prev) / (1.0 - t_prev)
        rec = model.advance(dt, on_step=None if a.no_scan else scan(t_prev, f))
        steps += len(rec.detail)
        newton += sum(s.iterations for s in rec.detail)
        t_prev = f
        cpu_ramp = time.process_time() - cpu0
        obs = model.observables()
        c0 = time.process_time()
        try:
            K, keep, held = reduced_tangent(model)
            neg, null = inertia(K)
            pairs = lowest_eigenpairs(K, a.modes, a.sigma)
        except Exception as exc:  # keep the ramp (and its states) going: report and go on
            import traceback

            traceback.print_exc()
            print(f"t = {f:.3f}: eigen analysis failed: {exc!r}", flush=True)
            if states_dir:
                model.save_state(states_dir / f"state_t{f:.3f}.npz")
            continue
        cpu_eig = time.process_time() - c0
        modes = []
        for mu, v, err in pairs:
            full = np.zeros(model.u.x.array.size)
            full[keep] = v
            vz = full.reshape(-1, 3)
            modes.append(
                {
                    "eigenvalue [N/mm]": mu,
                    "residual norm [N/mm]": err,
                    "uz share [-]": float((vz[:, 2] ** 2).sum() / (vz**2).sum()),
                }
            )
        row = {
            "t [-]": f,
            "circle_x [1/mm]": obs["kappa_circle_x [1/mm]"],
            "circle_y [1/mm]": obs["kappa_circle_y [1/mm]"],
            "z_range [mm]": obs["z_range [mm]"],
            "negative pivots [-]": neg,
            "null pivots [-]": null,
            "free DOFs [-]": int(keep.size),
            "held DOFs [-]": int(held.size),
            "modes": modes,
            "ramp cpu [s]": cpu_ramp,
            "eigen cpu [s]": cpu_eig,
        }
        rows.append(row)
        print(
            f"t = {f:.3f}: circle {row['circle_x [1/mm]']:.6f} / {row['circle_y [1/mm]']:.6f} 1/mm;"
            f" negative pivots {neg}, null {null}; lowest eigenvalues [N/mm] "
            + ", ".join(f"{m['eigenvalue [N/mm]']:.4g} (uz {m['uz share [-]']:.2f})" for m in modes)
            + f"; ramp CPU {cpu_ramp:.0f} s, eigen CPU {cpu_eig:.1f} s",
            flush=True,
        )
        if states_dir:
            model.save_state(states_dir / f"state_t{f:.3f}.npz")
            vecs = np.zeros((len(pairs), model.u.x.array.size))
            for i, (_, v, _) in enumerate(pairs):
                vecs[i, keep] = v
            np.save(states_dir / f"modes_t{f:.3f}.npy", vecs)
        K.destroy()
        write_data()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
