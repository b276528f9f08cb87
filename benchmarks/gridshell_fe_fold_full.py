"""The FULL FE 5 x 5 dome followed past its mirror-breaking instability (issue 47, the cause
layout_5x5_fold: which dome does the continuum take?).

The quarter model (mirror planes x = c, y = c) ends the Fig. 4 dome under the published rollers at
circle -0.010272 1/mm (x = y); its mirror-parity classes (benchmarks/gridshell_fe_fold_eigen.py
--classes) say the full model's tangent on that branch has negative eigenvalues in the
mirror-breaking classes at t = 0.7 (AS, SA, AA) and 0.8 (AA). This script runs the same
configuration (``lcefem run gridshell --model fe --layout 5x5 --shape dome --support rollers
--mesh-level 0``, built by the command line's own ``prepare_fe``) on the FULL model
(``run.symmetry = 'full'``) in stages, each resumable from the states it saves:

* ``quarter``: the quarter model's ramp to the load factors ``--at``, each state unfolded onto
  the full model (:func:`unfold`) and solved there (``DIR/state_tT.npz``): the full model's
  doubly symmetric equilibrium, exactly when its holds are mirror-compatible (``--holds point``);
* ``ramp``: the full model's own ramp from flat to ``--to``, saving the state after every accepted
  step (``DIR/ramp_last.npz``; a rerun resumes from it); per step the z mirror defect
  (:func:`mirror_defect`) [mm];
* ``eigen``: at ``--state`` the tangent K [N/mm] without its Dirichlet rows and columns, its
  negative pivots (MUMPS LDL^T inertia) and lowest eigenpairs (SLEPc shift-invert, the helpers of
  benchmarks/gridshell_fe_fold_eigen.py), with each mode's parities about x = c, y = c
  (:func:`parities`: +1 symmetric, -1 antisymmetric); the modes go to ``DIR/modes_tT.npy``;
* ``imperfect``: from the symmetric state ``--state`` (t0, where it is still stable) the ramp to
  t = 1 under a constant imperfection force in the shape of a saved mode
  (:func:`imperfect_stage`), then the force removed and the state solved and its stability
  measured. A kick at the saddle (t = 0.7) does not do: Newton goes back to the saddle
  (K^-1 R = phi to first order), and the proximal (energy-descent) steps that would leave it move
  it by c / (c + mu) per step, with mu ~ -1e-7 N/mm and forces ~1e-7 N at Newton's tolerance.

    OMP_NUM_THREADS=1 python benchmarks/gridshell_fe_fold_full.py quarter --holds point
        --states DIR --at 0.6,0.7
    OMP_NUM_THREADS=1 python benchmarks/gridshell_fe_fold_full.py eigen --holds point
        --states DIR --state DIR/state_t0.700.npz [--modes 6]
    OMP_NUM_THREADS=1 python benchmarks/gridshell_fe_fold_full.py imperfect --holds point
        --states DIR --state DIR/state_t0.600.npz --modes-at 0.7 --mode 0 --sign 1
        --force 1e-7 [--data FILE]
    OMP_NUM_THREADS=1 python benchmarks/gridshell_fe_fold_full.py ramp --states DIR [--to 0.7]

Not a test: it prints figures (docs/notes/fe_bodies_log.md, "The 5 x 5 fold, full model").
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import json
import pathlib
import sys
import time

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

import numpy as np

from lcefem.solvers.problems.gridshell_fe_run import SHAPE_COLUMNS

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from gridshell_fe_fold_eigen import inertia, lowest_eigenpairs, reduced_tangent  # noqa: E402

#: The run's shape columns (the FE gridshell's observables), without contact force and Newton count.
OBSERVED = SHAPE_COLUMNS[:6]


def point_holds_model(model_cfg):
    """GridshellFE whose published in-plane holds (u_x, u_y at roller points A, B, C) act on the
    ribbon's mid-surface node only. The run's holds take every node through the thickness at the
    point, so u_y held at A and C (both ends at y = lo) also clamps the y ribbons' end sections
    against bending there, and u_x at A and B against twist: the full model is then not mirror
    symmetric about y = c (nor x = c), unlike the quarter model it is compared with. u_z stays
    held through the thickness (no rotation constraint: the nodes share x and y)."""
    from lcefem.solvers.problems.gridshell import GridshellFE

    class PointHolds(GridshellFE):
        def _component_dofs(self, comp, nodes):
            if comp < 2 and nodes.size:
                nodes = nodes[np.abs(self._X[nodes, 2]) == np.abs(self._X[nodes, 2]).min()]
            return super()._component_dofs(comp, nodes)

    return PointHolds(model_cfg)


def build(layout: str, support: str, level: int, symmetry: str = "full", holds: str = "published"):
    """The GridshellFE of the run's configuration on the ``symmetry`` model, drives set;
    ``holds`` 'published' (the run's) or 'point' (:func:`point_holds_model`)."""
    from lcefem.solvers.problems.gridshell_fe_run import build_model, in_model
    from lcefem.validation.app.cli import build_parser
    from lcefem.validation.app.commands.gridshell import prepare_fe

    argv = [
        "run", "gridshell", "--model", "fe", "--layout", layout, "--shape", "dome",
        "--support", support, "--mesh-level", str(level), "--out", "/tmp/unused",
    ]  # fmt: skip
    cfg = prepare_fe(build_parser(argv).parse_args(argv))
    cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, symmetry=symmetry))
    if holds == "point":
        model = point_holds_model(dataclasses.replace(cfg.model, symmetry=cfg.symmetry))
    else:
        model = build_model(cfg)
    model.set_drives(in_model(model, cfg.drive_fields()[0]))
    return model, cfg


def mirror_maps(model) -> tuple[np.ndarray, np.ndarray]:
    """Node index of each node's image under the mirror x -> 2c - x and under y -> 2c - y."""
    from scipy.spatial import cKDTree

    X = model._X
    c = float(np.asarray(model.info["centre"], dtype=float).reshape(-1)[0])
    tree = cKDTree(X)
    maps = []
    for axis in (0, 1):
        Y = X.copy()
        Y[:, axis] = 2.0 * c - Y[:, axis]
        d, idx = tree.query(Y)
        if d.max() > 1e-6:
            raise RuntimeError(
                f"the full mesh is not mirror-symmetric about axis {axis}: {d.max()}"
            )
        maps.append(idx)
    return maps[0], maps[1]


def mirrored(v: np.ndarray, m: np.ndarray, axis: int) -> np.ndarray:
    """The image of a nodal vector field (n, 3) under the mirror: (Mv)(x) = S v(m(x)), S flips the
    normal component."""
    w = v.reshape(-1, 3)[m].copy()
    w[:, axis] *= -1.0
    return w


def mirror_defect(model, maps) -> tuple[float, float]:
    """max over nodes |u_z - u_z(image)| [mm] for the mirrors x = c and y = c (0: a
    mirror-symmetric state; u_z, as the in-plane holds leave a rigid in-plane translation)."""
    uz = model.u.x.array.reshape(-1, 3)[:, 2]
    return tuple(float(np.abs(uz - uz[m]).max()) for m in maps)


def parities(v: np.ndarray, maps) -> tuple[float, float]:
    """<v, M v> / <v, v> for the mirrors x = c and y = c [-]: +1 symmetric, -1 antisymmetric."""
    v = v.reshape(-1, 3)
    n = float((v * v).sum())
    return tuple(float((v * mirrored(v, m, k)).sum()) / n for k, m in enumerate(maps))


def rotation_parity(v: np.ndarray, maps) -> float:
    """<v, R v> / <v, v> for the 180 deg rotation about the vertical axis through the centre (the
    product of the two mirrors) [-]."""
    mx, my = maps
    w = mirrored(mirrored(v, my, 1), mx, 0)
    v = v.reshape(-1, 3)
    return float((v * w).sum()) / float((v * v).sum())


def unfold(model, path) -> None:
    """The full model's state from a quarter model's saved state (same mesh level): every node
    takes the displacement of its image in the quarter x >= c, y >= c, with the normal component
    flipped across each mirror (u_x for x < c, u_y for y < c), then the in-plane translation that
    zeroes the held in-plane DOFs (the published holds fix the rigid motion only)."""
    from scipy.spatial import cKDTree

    with np.load(path) as st:
        if str(st["symmetry"]) != "quarter":
            raise SystemExit(f"{path}: not a quarter model's state")
        Xq, uq = st["dof_coordinates"], st["u"].reshape(-1, 3)
        # every strip (the quarter holds a quarter of them) at the ramp's lambda of t
        t = float(st["t"])
        model.lam.x.array[:] = model.lambda_N + t * (model.target - model.lambda_N)
        model._set_weight(float(st["gravity_on"]))
    X = model._X
    c = float(np.asarray(model.info["centre"], dtype=float).reshape(-1)[0])
    folded = X.copy()
    folded[:, :2] = c + np.abs(X[:, :2] - c)
    d, q = cKDTree(Xq).query(folded)
    if d.max() > 1e-6:
        raise SystemExit(f"{path}: a full-model node has no quarter image ({d.max():.2e} mm)")
    u = uq[q].copy()
    u[X[:, 0] < c, 0] *= -1.0
    u[X[:, 1] < c, 1] *= -1.0
    for comp in (0, 1):  # the translation that zeroes the held in-plane DOFs' mid-surface nodes
        nodes = model.support_nodes[comp]
        if nodes.size:
            mid = nodes[np.abs(X[nodes, 2]) == np.abs(X[nodes, 2]).min()]
            u[:, comp] -= u[mid, comp].mean()
    model.u.x.array[:] = u.ravel()
    model.u.x.scatter_forward()


def load_state(model, path) -> None:
    """Displacement and per-strip lambda of a state saved by GridshellFE.save_state (same mesh)."""
    with np.load(path) as st:
        if st["u"].shape != model.u.x.array.shape or str(st["symmetry"]) != "full":
            raise SystemExit(f"{path}: not a state of this full model")
        model.u.x.array[:] = st["u"]
        for tag, value in zip(st["strip_tags"], st["strip_lambda"]):
            model.lam.x.array[model._dof_tag == tag] = value
        model._set_weight(float(st["gravity_on"]))
    model.u.x.scatter_forward()


def state_t(path) -> float:
    with np.load(path) as st:
        return float(st["t"]) if "t" in st.files else float("nan")


def save(model, path, t: float) -> None:
    """save_state plus the load factor t [-] (atomic)."""
    path = pathlib.Path(path)
    model.save_state(path)
    with np.load(path) as st:
        data = {k: st[k] for k in st.files}
    tmp = path.with_name(path.name + ".part.npz")
    np.savez(tmp, t=t, **data)
    tmp.replace(path)


def summary(model, maps) -> dict:
    obs = model.observables()
    out = {k: obs[k] for k in OBSERVED}
    dx, dy = mirror_defect(model, maps)
    out["mirror defect x = c [mm]"] = dx
    out["mirror defect y = c [mm]"] = dy
    out["energy [mJ]"] = model.problem.total_energy()
    return out


def ramp(model, maps, t_from: float, t_to: float, last: pathlib.Path, log: list) -> None:
    """The run's path follower from t_from (the model's state) to t_to, saving every step."""
    dt = (t_to - t_from) / (1.0 - t_from)

    def on_step(st) -> None:
        t = t_from + st.load_factor * (t_to - t_from)
        o = st.observables
        dx, dy = mirror_defect(model, maps)
        log.append(
            (t, st.iterations, o["kappa_circle_x [1/mm]"], o["kappa_circle_y [1/mm]"], dx, dy)
        )
        print(
            f"  t = {t:.4f} ({st.iterations} its, CPU {time.process_time():.0f} s): circle "
            f"{o['kappa_circle_x [1/mm]']:.6f} / {o['kappa_circle_y [1/mm]']:.6f} 1/mm, "
            f"mirror defect {dx:.2e} / {dy:.2e} mm",
            flush=True,
        )
        save(model, last, t)

    model.advance(dt, on_step=on_step)


def eigen(model, maps, nev: int, sigma: float):
    """Negative pivots and lowest eigenpairs of the held-DOF-free tangent, with parities."""
    K, keep, held = reduced_tangent(model)
    neg, null = inertia(K)
    pairs = lowest_eigenpairs(K, nev, sigma)
    K.destroy()
    modes, vecs = [], []
    for mu, v, err in pairs:
        full = np.zeros(model.u.x.array.size)
        full[keep] = v
        px, py = parities(full, maps)
        modes.append(
            {
                "eigenvalue [N/mm]": mu,
                "residual norm [N/mm]": err,
                "parity x = c [-]": px,
                "parity y = c [-]": py,
                "parity 180 deg rotation [-]": rotation_parity(full, maps),
            }
        )
        vecs.append(full)
    return neg, null, modes, np.array(vecs)


def print_modes(neg, null, modes) -> None:
    print(f"negative pivots {neg}, null {null}", flush=True)
    for m in modes:
        print(
            f"  {m['eigenvalue [N/mm]']:.4g} N/mm (res {m['residual norm [N/mm]']:.1e}): parity "
            f"x {m['parity x = c [-]']:+.3f}, y {m['parity y = c [-]']:+.3f}, rotation "
            f"{m['parity 180 deg rotation [-]']:+.3f}",
            flush=True,
        )


def quarter_stage(a, states: pathlib.Path) -> int:
    """The quarter model's ramp to the load factors ``--at``, each state unfolded onto the full
    model (:func:`unfold`) and solved there (Newton; a doubly symmetric equilibrium of the full
    model, 0-2 iterations), saved as ``state_tT.npz`` (full) and ``quarter_tT.npz``."""
    cpu0 = time.process_time()
    fractions = sorted(float(x) for x in a.at.split(","))
    saved = [(f, states / f"quarter_t{f:.3f}.npz") for f in fractions]
    if not all(p.exists() for _, p in saved):  # else: unfold the saved quarter states only
        quarter, _ = build(a.layout, a.support, a.level, "quarter")
        print(f"# quarter: {quarter.ndofs} DOFs", flush=True)
        t_prev = 0.0
        for f, path in saved:
            quarter.advance((f - t_prev) / (1.0 - t_prev))
            t_prev = f
            save(quarter, path, f)
            o = quarter.observables()
            print(f"quarter t = {f:.3f}: circle {o['kappa_circle_x [1/mm]']:.6f} / "
                  f"{o['kappa_circle_y [1/mm]']:.6f} 1/mm; CPU {time.process_time() - cpu0:.0f} s",
                  flush=True)  # fmt: skip
        del quarter
    full, _ = build(a.layout, a.support, a.level, "full", a.holds)
    maps = mirror_maps(full)
    for f, path in saved:
        unfold(full, path)
        for bc in full.bcs:
            bc.set(full.u.x.array)
        full.u.x.scatter_forward()
        r0 = float(np.abs(full.residual()).max())
        ok, its, reason = full.problem.solve()
        r1 = float(np.abs(full.residual()).max())
        print(f"full t = {f:.3f}: unfolded residual {r0:.2e} N, Newton {ok} in {its} its "
              f"({reason}), residual {r1:.2e} N: {summary(full, maps)}", flush=True)  # fmt: skip
        if ok:
            save(full, states / f"state_t{f:.3f}.npz", f)
    print(f"CPU {time.process_time() - cpu0:.0f} s")
    return 0


def imperfect_stage(model, maps, a, states: pathlib.Path, t0: float) -> int:
    """From the doubly symmetric state at t0 the ramp to t = 1 under a constant imperfection: nodal
    forces f = s F phi / max_node |phi| [N] (phi a saved mode at ``--modes-at``, F ``--force``, s
    ``--sign``; a NodalLoad, the potential -f.u), so the path takes the branch the mode leads to
    past the bifurcation continuously, as an imperfect structure would; at t = 1 the force is
    removed and the state solved again (and its stability measured)."""
    vecs = np.load(states / f"modes_t{a.modes_at:.3f}.npy")
    phi = vecs[a.mode]
    f = a.sign * a.force * phi / np.linalg.norm(phi.reshape(-1, 3), axis=1).max()
    n = model.offset.force.size
    model.offset.force[:] = f[:n]
    model.offset.factor = 1.0
    c0 = time.process_time()
    start = summary(model, maps)
    tag = f"imp_m{a.mode}{'p' if a.sign > 0 else 'm'}{a.force:g}"
    log: list = []
    try:
        ramp(model, maps, t0, 1.0, states / f"{tag}_last.npz", log)
    finally:
        with_force = summary(model, maps)
        model.offset.factor = 0.0
    ok, its, reason = model.problem.solve()
    end = summary(model, maps)
    neg, null, modes, _ = eigen(model, maps, 4, a.sigma)
    cpu = time.process_time() - c0
    save(model, states / f"{tag}_t1.000.npz", 1.0)
    print(f"t = 1 with the force: {with_force}")
    print(f"t = 1 without it (Newton {ok}, {its} its): {end}; CPU {cpu:.0f} s")
    print_modes(neg, null, modes)
    if a.data:
        write_json(a.data, {
            "source": "benchmarks/gridshell_fe_fold_full.py " + " ".join(sys.argv[1:]),
            "date": str(datetime.date.today()),
            "dofs [-]": int(model.ndofs),
            "t0 [-]": t0, "mode": a.mode, "mode at t [-]": a.modes_at, "sign": a.sign,
            "largest nodal force [N]": a.force, "at t0": start,
            "path (t, its, circle_x, circle_y [1/mm], z mirror defect x, y [mm])": log,
            "end with the force": with_force, "end": end, "end newton iterations": its,
            "end negative pivots [-]": neg, "end modes": modes, "cpu [s]": cpu,
        })  # fmt: skip
    return 0


def write_json(path, record) -> None:
    path = pathlib.Path(path)
    tmp = path.with_name(path.name + ".part")
    tmp.write_text(json.dumps(record, indent=1) + "\n")
    tmp.replace(path)
    print(f"wrote {path}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("stage", choices=("quarter", "ramp", "eigen", "imperfect"))
    ap.add_argument("--layout", default="5x5")
    ap.add_argument("--support", default="rollers")
    ap.add_argument("--level", type=int, default=0)
    ap.add_argument("--states", required=True, help="folder of the states (.npz) and modes")
    ap.add_argument("--to", type=float, default=0.7, help="ramp: end load factor [-]")
    ap.add_argument(
        "--holds",
        default="published",
        choices=("published", "point"),
        help="in-plane holds through the thickness (the run's) or at the mid-surface node",
    )
    ap.add_argument("--at", default="0.7", help="quarter: load factors of the states [-]")
    ap.add_argument("--state", default="", help="eigen, imperfect: the state (.npz)")
    ap.add_argument("--modes", type=int, default=6)
    ap.add_argument("--sigma", type=float, default=-1e-6, help="shift [N/mm]")
    ap.add_argument("--mode", type=int, default=0, help="imperfect: index of the saved mode")
    ap.add_argument("--sign", type=float, default=1.0, choices=(1.0, -1.0))
    ap.add_argument("--data", default="", help="imperfect: JSON to write")
    ap.add_argument("--modes-at", type=float, default=0.7, help="imperfect: t of the saved mode")
    ap.add_argument(
        "--force", type=float, default=2e-7, help="imperfect: largest nodal imperfection force [N]"
    )
    a = ap.parse_args(argv)
    if not 0.0 < a.to <= 1.0 or a.force <= 0.0 or a.level < 0 or a.modes < 1:
        print("--to in (0, 1], --force > 0, --level >= 0, --modes >= 1 expected", file=sys.stderr)
        return 2
    states = pathlib.Path(a.states)
    states.mkdir(parents=True, exist_ok=True)
    cpu0 = time.process_time()
    if a.stage == "quarter":
        return quarter_stage(a, states)
    model, cfg = build(a.layout, a.support, a.level, "full", a.holds)
    maps = mirror_maps(model)
    print(f"# {a.layout}, {a.support}, {cfg.symmetry}, level {a.level}: {model.ndofs} DOFs, "
          f"build CPU {time.process_time() - cpu0:.0f} s", flush=True)  # fmt: skip

    if a.stage == "ramp":
        t0 = 0.0
        last = states / "ramp_last.npz"
        if last.exists() and state_t(last) < a.to:
            load_state(model, last)
            t0 = state_t(last)
            print(f"resumed at t = {t0:.4f}", flush=True)
        log: list = []
        ramp(model, maps, t0, a.to, last, log)
        save(model, states / f"state_t{a.to:.3f}.npz", a.to)
        print(f"t = {a.to}: {summary(model, maps)}; CPU {time.process_time() - cpu0:.0f} s")
        return 0

    if not a.state:
        print("--state: the .npz state to start from is required", file=sys.stderr)
        return 2
    load_state(model, a.state)
    t0 = state_t(a.state)
    if a.stage == "eigen":
        c0 = time.process_time()
        neg, null, modes, vecs = eigen(model, maps, a.modes, a.sigma)
        print(f"t = {t0:.4f}: {summary(model, maps)}; eigen CPU {time.process_time() - c0:.0f} s")
        print_modes(neg, null, modes)
        np.save(states / f"modes_t{t0:.3f}.npy", vecs)
        write_json(states / f"eigen_t{t0:.3f}.json",
                   {"t [-]": t0, "negative pivots [-]": neg, "modes": modes})  # fmt: skip
        return 0

    return imperfect_stage(model, maps, a, states, t0)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
