"""Does the bar-and-hinge 5 x 5 dome keep the mirror symmetries the quarter FE imposes? (issue 47,
the cause layout_5x5_fold).

Runs a layout's Fig. 4 drive under a support (FE-calibrated model set, GRIDSHELL_NEWTON, as
benchmarks/bh_soft_modes.py and the validation's layout rows), and at every converged load factor
t >= ``--from`` prints:

* the circle curvatures kappa_x / kappa_y [1/mm];
* the largest |z_i - z_m(i)| [mm] over the nodes i, m the node at the mirror image of i about the
  planes x = c and y = c (c the grid's centre, the quarter FE's mirror planes) and about the
  diagonal x <-> y (the symmetry the BH leaves near the fold). z is compared because the
  published in-plane holds (three DOFs at three corners) fix the in-plane rigid motion at
  unsymmetric points: z is blind to it;
* the lowest eigenvalues of the tangent on the free DOFs [N/mm] (shift-invert Lanczos), each with
  the parity of its z part under the three mirrors: (|P+ v_z|^2 - |P- v_z|^2)/|v_z|^2, +1 a mode
  symmetric about the plane, -1 antisymmetric (the quarter FE represents only modes symmetric about
  both x = c and y = c).

``--diagonals both``: the strips' contact quads split along both diagonals (``auto``, the model
set's, splits the orthogonal grid's along one: no row of the strip contacts has its image under
the x = c or y = c mirror, so the structure itself is not mirror-symmetric).
``--settle-stall N``: the Newton's settle after N stalled iterations (0: only where Newton used to
fail, the default; 5: the path that snaps at t = 0.876, docs/notes/performance_log.md, "The settle
step"). ``--save FILE``: the positions of every analysed state (.npz, written atomically).

    OMP_NUM_THREADS=1 python benchmarks/bh_fold_symmetry.py [--layout 5x5] [--support rollers]
        [--from 0.65] [--modes 4] [--settle-stall 0] [--diagonals auto]
        [--save FILE]

Not a test: it prints the figures of docs/notes/fe_bodies_log.md ("The 5 x 5 fold").
"""

from __future__ import annotations

import argparse
import dataclasses
import pathlib
import sys
import time

import numpy as np
import scipy.sparse.linalg as sla

from lcefem.meshes.gridshell import (
    build_gridshell_bar_hinge,
    diagonal_mirror,
    node_image_map,
    unmatched_mirror_rows,
)
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.analysis.curvature import gridshell_curvatures
from lcefem.solvers.bar_hinge.model import ReducedHessian
from lcefem.solvers.problems.gridshell_bh import (
    GRIDSHELL_NEWTON,
    SUPPORTS,
    GridshellBH,
    GridshellBHConfig,
)
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import gridshell_bh as gs


def plane_mirror(structure, axis: int, centre: float) -> np.ndarray:
    """Node i -> the node at the mirror image of node i about the plane x_axis = centre [mm]
    (:func:`lcefem.meshes.gridshell.node_image_map`). Raises InputError when a node has none."""
    image = structure.nodes.copy()
    image[:, axis] = 2.0 * centre - image[:, axis]
    return node_image_map(structure, image, "plane_mirror")


def parity(vz: np.ndarray, perm: np.ndarray) -> float:
    """(|v+|^2 - |v-|^2)/|v|^2 of a nodal scalar field under the node map ``perm`` [-]."""
    plus, minus = 0.5 * (vz + vz[perm]), 0.5 * (vz - vz[perm])
    return float(((plus**2).sum() - (minus**2).sum()) / max((vz**2).sum(), 1e-300))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--layout", default="5x5", help="one of " + ", ".join(NAMED_LAYOUTS))
    p.add_argument("--support", default="rollers", help="one of " + ", ".join(SUPPORTS))
    p.add_argument("--from", dest="start", type=float, default=0.65, help="first t analysed [-]")
    p.add_argument("--modes", type=int, default=4, help="lowest eigenpairs per state")
    p.add_argument("--settle-stall", type=int, default=0, help="Newton's settle_stall [-]")
    p.add_argument("--diagonals", default="auto", help="mesh.contact_diagonals: auto, one, both")
    p.add_argument("--save", default="", help="npz of the analysed states' positions [mm]")
    a = p.parse_args(argv)
    for name, value, allowed in (
        ("--layout", a.layout, NAMED_LAYOUTS),
        ("--support", a.support, SUPPORTS),
    ):
        if value not in allowed:
            print(f"{name} = {value!r}: allowed {', '.join(allowed)}", file=sys.stderr)
            return 2
    if (
        a.modes < 1
        or a.settle_stall < 0
        or not 0.0 <= a.start <= 1.0
        or a.diagonals not in ("auto", "one", "both")
    ):
        print(
            "--modes >= 1, --settle-stall >= 0, 0 <= --from <= 1 and --diagonals auto|one|both "
            "expected",
            file=sys.stderr,
        )
        return 2
    ms = calibrate.model_set("fe-calibrated")
    layout = NAMED_LAYOUTS[a.layout]
    solver = dataclasses.replace(GRIDSHELL_NEWTON, settle_stall=a.settle_stall)
    structure = build_gridshell_bar_hinge(
        layout=layout, mesh=dataclasses.replace(ms.mesh, contact_diagonals=a.diagonals)
    )
    problem = GridshellBH(
        structure,
        GridshellBHConfig(materials=ms.materials_for(layout), support=a.support, solver=solver),
    )
    problem.set_drives(gs.SHAPES["dome"]["lambdas"])
    model, held = problem.model, problem.setup.held
    free = np.setdiff1d(np.arange(model.ndof), held)
    reduced = ReducedHessian.of(model, free)
    c = 0.5 * structure.info["ribbon_length"]
    mirrors = {
        "x": plane_mirror(structure, 0, c),
        "y": plane_mirror(structure, 1, c),
        "diag": diagonal_mirror(structure, "diag"),
    }
    for name, perm in mirrors.items():
        bad = {k: v for k, v in unmatched_mirror_rows(structure, perm).items() if v}
        print(f"# structure rows without their image under the {name} mirror: {bad or 'none'}")
    print(
        f"# {a.layout}, {a.support}, dome, contact_diagonals {a.diagonals}, "
        f"settle_stall {a.settle_stall}: {model.ndof} DOFs, "
        f"{held.size} held, mirror planes at {c:g} mm"
    )
    print(
        "t | circle kappa x / y [1/mm] | max |dz| at the x, y, diagonal mirror images [mm] | "
        "lowest eigenvalues [N/mm] (z parity x, y, diag)"
    )
    saved: dict[str, np.ndarray] = {}
    t0 = time.process_time()

    def on_step(s) -> None:
        if s.t < a.start:
            return
        xs = s.x.reshape(-1, 3)
        cv = gridshell_curvatures(structure, xs)
        dz = [float(np.abs(xs[m, 2] - xs[:, 2]).max()) for m in mirrors.values()]
        _, _, coo = model.evaluate(xs.reshape(-1))
        vals, vecs = sla.eigsh(reduced.matrix(coo), k=a.modes, sigma=-1e-6, which="LM")
        modes = []
        for i in np.argsort(vals):
            v = np.zeros(model.ndof)
            v[free] = vecs[:, i]
            vz = v.reshape(-1, 3)[:, 2]
            par = ", ".join(f"{parity(vz, m):+.2f}" for m in mirrors.values())
            modes.append(f"{vals[i]:.3g} ({par})")
        saved[f"t{s.t:.6f}"] = xs.copy()
        print(
            f"{s.t:.5f} | {cv['circle_x']:.6f} / {cv['circle_y']:.6f} | "
            + ", ".join(f"{d:.2e}" for d in dz)
            + f" | {'; '.join(modes)} | {time.process_time() - t0:.0f} s",
            flush=True,
        )

    try:
        problem.advance(on_step=on_step)
        print(f"reached t = 1 after {time.process_time() - t0:.1f} CPU s")
    except ConvergenceError as exc:
        print(f"stopped: {exc}")
    if a.save:
        out = pathlib.Path(a.save)
        tmp = out.with_name(out.name + ".part.npz")
        np.savez(tmp, **saved)
        tmp.replace(out)
        print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
