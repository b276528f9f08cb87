"""The bar-and-hinge 5 x 5 Fig. 4 dome's path through its fold (issue 47, known disagreement
layout_5x5_fold): where the x <-> y symmetric path loses stability and of what kind.

Runs the layout's dome ramp (FE-calibrated set, rollers, the problem's Newton; ``--diagonals both``:
the strips' contact quads split along both diagonals, so that the structure maps onto itself under
the diagonal mirrors) and, at every converged load factor t >= ``--from``, prints the circle
curvatures [1/mm], the lowest eigenvalues of the tangent on the free DOFs [N/mm] and, per mode, its
parity under the two diagonal mirrors (x <-> y: "diag"; (x, y) -> (L - y, L - x): "anti"; +1
symmetric, -1 antisymmetric, after the six rigid-body modes are removed: the rollers' in-plane
holds are not mirror images of each other), its share on the raised top squares, and
|v . dg/dt| / (|v| |dg/dt|) (the mode against the load's rate: ~0 at a symmetry-breaking
bifurcation, O(1) at a limit point). ``--save DIR``: each analysed state as DIR/state_<t>.npz.

    OMP_NUM_THREADS=1 python benchmarks/bh_fold_path.py [--from 0.6] [--to 0.92] [--modes 4]
        [--diagonals auto|both] [--settle-stall 0] [--save DIR]

Not a test: it prints the figures of docs/layouts/index.md ("The fold").
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np
import scipy.sparse.linalg as sla

from lcefem.meshes.gridshell import build_gridshell_bar_hinge, diagonal_mirror
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.solvers.analysis.curvature import gridshell_curvatures
from lcefem.solvers.bar_hinge.model import ReducedHessian
from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
from lcefem.solvers.problems.stable_ramp import StabilityOptions
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import gridshell_bh as gs

sys.path.insert(0, str(Path(__file__).parent))
from bh_soft_modes import rigid_modes  # noqa: E402


class Done(Exception):
    pass


def mirror_parity(v: np.ndarray, perm: np.ndarray, r: np.ndarray, x: np.ndarray) -> float:
    """<Q v', v'> / |v'|^2 of a full-DOF mode v (3n,), v' = v without its rigid-body part at the
    positions x (n, 3); Q the mirror: (Q v) at node perm[i] = R v_i. +1 symmetric, -1 anti."""
    rb = np.linalg.qr(rigid_modes(x))[0]
    w = v - rb @ (rb.T @ v)
    q = np.zeros_like(w).reshape(-1, 3)
    q[perm] = w.reshape(-1, 3) @ r.T
    return float(q.reshape(-1) @ w / max(w @ w, 1e-300))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--from", dest="start", type=float, default=0.6)
    p.add_argument("--to", dest="stop", type=float, default=1.0)
    p.add_argument("--modes", type=int, default=4)
    p.add_argument("--diagonals", default="auto", choices=("auto", "both"))
    p.add_argument("--settle-stall", type=int, default=0)
    p.add_argument("--save", default="")
    p.add_argument(
        "--stable", action="store_true", help="the ramp of follow_stable_path (StabilityOptions())"
    )
    p.add_argument(
        "--start-state",
        default="",
        help="an npz of --save (x, t): ramp from that state at its t instead of from flat",
    )
    p.add_argument("--initial-increment", type=float, default=0.0, help="PathOptions' (0: default)")
    a = p.parse_args(argv)
    if a.modes < 1 or a.settle_stall < 0 or not 0.0 <= a.start <= a.stop <= 1.0:
        print("--modes >= 1, --settle-stall >= 0, 0 <= --from <= --to <= 1", file=sys.stderr)
        return 2
    ms = calibrate.model_set("fe-calibrated")
    layout = NAMED_LAYOUTS["5x5"]
    s = build_gridshell_bar_hinge(
        layout=layout, mesh=dataclasses.replace(ms.mesh, contact_diagonals=a.diagonals)
    )
    cfg = GridshellBHConfig(materials=ms.materials_for(layout), support="rollers")
    cfg = dataclasses.replace(
        cfg, solver=dataclasses.replace(cfg.solver, settle_stall=a.settle_stall)
    )
    if a.stable:
        cfg = dataclasses.replace(cfg, stability=StabilityOptions())
    if a.initial_increment:
        cfg = dataclasses.replace(
            cfg, path=dataclasses.replace(cfg.path, initial_increment=a.initial_increment)
        )
    problem = GridshellBH(s, cfg)
    problem.set_drives(gs.SHAPES["dome"]["lambdas"])
    model, held = problem.model, problem.setup.held
    free = np.setdiff1d(np.arange(model.ndof), held)
    reduced = ReducedHessian.of(model, free)
    squares = s.node_sets["top_squares"].reshape(-1)
    swap = np.array([[0.0, 1, 0], [1, 0, 0], [0, 0, 1]])
    mirrors = {
        "diag": (diagonal_mirror(s, "diag"), swap),
        "anti": (diagonal_mirror(s, "anti"), -swap + np.diag([0, 0, 2.0])),
    }
    start = {g: v.copy() for g, v in model.rest_fractions().items()}
    target = problem._target
    t_begin = 0.0
    if a.start_state:
        saved = np.load(a.start_state)
        t_begin = float(saved["t"])
        problem.x = saved["x"].reshape(-1, 3).copy()
        problem._current = {g: start[g] + t_begin * (target[g] - start[g]) for g in target}
        model.set_rest_fractions(problem._current)
    print(
        f"# 5x5 Fig. 4 dome, rollers, contact_diagonals {a.diagonals}, "
        f"settle_stall {a.settle_stall}"
    )
    print(
        "t | E [mJ] | circle kappa x / y [1/mm] | per mode: eigenvalue [N/mm] (diag, anti parity; "
        "top-square share; load alignment)"
    )
    t0 = time.process_time()

    def set_t(t):
        model.set_rest_fractions({g: start[g] + t * (target[g] - start[g]) for g in target})

    def on_step(st) -> None:
        st = dataclasses.replace(st, t=t_begin + st.t * (1.0 - t_begin))
        if st.t < a.start:
            return
        x = st.x.reshape(-1)
        _, g, coo = model.evaluate(x)
        vals, vecs = sla.eigsh(reduced.matrix(coo), k=a.modes, sigma=-1e-6, which="LM")
        dt = 1e-6
        set_t(st.t + dt)
        gp = model.evaluate(x, derivatives=1)[1]
        set_t(st.t)
        rate = (gp - g)[free] / dt
        c = gridshell_curvatures(s, st.x)
        modes = []
        for i in np.argsort(vals):
            v = np.zeros(model.ndof)
            v[free] = vecs[:, i]
            par = [mirror_parity(v, pm, r, st.x.reshape(-1, 3)) for pm, r in mirrors.values()]
            share = float((v.reshape(-1, 3)[squares] ** 2).sum())
            align = abs(vecs[:, i] @ rate) / np.linalg.norm(rate)
            modes.append(f"{vals[i]:.3g} ({par[0]:+.2f}, {par[1]:+.2f}; {share:.2f}; {align:.1e})")
        print(
            f"{st.t:.5f} | {st.energy:.9g} | {c['circle_x']:.6f} / {c['circle_y']:.6f} | "
            f"{' | '.join(modes)} | {time.process_time() - t0:.0f} s"
            f"{' snap' if st.snapped else ''}",
            flush=True,
        )
        if a.save:
            np.savez(Path(a.save) / f"state_{st.t:.6f}.npz", x=st.x, t=st.t)
        if a.stop < 1.0 and st.t >= a.stop:
            raise Done

    try:
        rec = problem.advance(on_step=on_step)
        res = rec.detail
        out = problem.observables()
        x = problem.x.reshape(-1)
        vals = sla.eigsh(reduced.matrix(model.evaluate(x)[2]), k=a.modes, sigma=-1e-6)[0]
        print(
            f"t = 1: {len(res.states) - 1} increments ({res.failed_increments} failed), "
            f"{sum(res.newton_iterations)} Newton iterations, snapped at "
            f"{[round(st.t, 6) for st in res.states if st.snapped]}"
        )
        print(" | ".join(f"{k} {v:.7g}" for k, v in out.items()))
        print(f"energy {res.states[-1].energy:.10g} mJ, |g| {res.states[-1].residual:.2e} N")
        print(f"lowest tangent eigenvalues [N/mm] {np.sort(vals)}")
        if a.save:
            np.savez(Path(a.save) / "end.npz", x=problem.x)
    except Done:
        pass
    print(f"CPU {time.process_time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
