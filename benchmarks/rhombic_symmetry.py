"""Why the bar-and-hinge rhombic dome leaves the diagonal symmetry the 3D FE keeps (issue 47, known
disagreement layout_rhombic_transfer): three measurements of the FE-calibrated model set.

1. The structure under both diagonal mirrors: rows of each element group whose image is not in the
   group (:func:`lcefem.meshes.gridshell.unmatched_mirror_rows`), the strips' contact quads split
   along one diagonal and along both (``mesh.contact_diagonals``).
2. The Fig. 4 dome's ramp under the centre clamp, in ``--steps`` increments: circle kappa x / y
   [1/mm], the largest |z - z(mirror image)| [mm], the slack top-strip bars, and the lowest
   eigenvalues of the tangent [N/mm] on the free DOFs restricted to the mirror-symmetric and to the
   antisymmetric displacements (a negative antisymmetric one: the symmetric state is unstable).
   ``--symmetric-from T``: from T on, Newton restricted to the symmetric displacements continues
   the symmetric branch to t = 1.
3. ``--chain``: the bending and torsional stiffness [k mm^2] of a straight chain of N5B8 panels
   (2.2 mm along a 7 mm wide ribbon, cross edges at 90 and 60 deg, every hinge k = 1, corners on
   the isometric cylinder / helicoid, centre nodes free), and the same of one free ribbon segment
   as the builder makes it (:func:`segment_stiffness`): the published grid's, and the rhombic
   grid's with skewed and with rectangular free panels (``mesh.free_panels``).

    OMP_NUM_THREADS=1 python benchmarks/rhombic_symmetry.py [--layout rhombic60]
        [--diagonals auto|one|both] [--steps 10] [--at 0.668,0.672] [--symmetric-from 0.66]
        [--kapton-factor 1] [--flank-panels 5] [--free-panels auto] [--chain]

Not a test: it prints the figures of docs/layouts/rhombic.md.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from scipy.optimize import minimize

from lcefem.meshes.bar_hinge_structure import n5b8_structure
from lcefem.meshes.gridshell import (
    build_gridshell_bar_hinge,
    diagonal_mirror,
    unmatched_mirror_rows,
)
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.models.bar_hinge import dihedral_angle
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.solvers.analysis.curvature import gridshell_curvatures
from lcefem.solvers.bar_hinge.model import ReducedHessian
from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import gridshell_bh as gs


def mirror_operator(structure, perm) -> tuple[sp.csr_matrix, np.ndarray]:
    """The mirror as a DOF map Q (3n x 3n: (Q v) at node perm[i] = R v_i) and R (3 x 3: the plane
    reflection that swaps e1 and e2)."""
    a = math.radians(structure.info["layout"].angle)
    r = np.array([[math.cos(a), math.sin(a), 0.0], [math.sin(a), -math.cos(a), 0.0], [0, 0, 1.0]])
    n = structure.num_nodes
    rows, cols, vals = [], [], []
    for i in range(n):
        for p in range(3):
            for q in range(3):
                if r[p, q] != 0.0:
                    rows.append(3 * perm[i] + p)
                    cols.append(3 * i + q)
                    vals.append(r[p, q])
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * n, 3 * n)), r


def parity_basis(perm, r, free, sign: int) -> sp.csc_matrix:
    """Orthonormal basis (free DOFs x m) of the displacements with Q v = sign v."""
    n = perm.size
    pos = -np.ones(3 * n, dtype=np.int64)
    pos[free] = np.arange(free.size)
    w, vec = np.linalg.eigh(r)
    rows, cols, vals, col = [], [], [], 0
    for i in range(n):
        j = perm[i]
        if j < i:
            continue
        if j == i:  # a node on the mirror line: R's eigenvectors of eigenvalue sign
            for e in np.flatnonzero(np.abs(w - sign) < 1e-9):
                v = vec[:, e]
                if all(pos[3 * i + q] >= 0 or abs(v[q]) < 1e-14 for q in range(3)):
                    for q in np.flatnonzero(np.abs(v) > 1e-14):
                        rows.append(pos[3 * i + q])
                        cols.append(col)
                        vals.append(v[q])
                    col += 1
            continue
        for c in range(3):
            if pos[3 * i + c] < 0:
                continue
            rows.append(pos[3 * i + c])
            cols.append(col)
            vals.append(1.0 / math.sqrt(2.0))
            for q in np.flatnonzero(r[:, c] != 0.0):
                rows.append(pos[3 * j + q])
                cols.append(col)
                vals.append(sign * r[q, c] / math.sqrt(2.0))
            col += 1
    return sp.csc_matrix((vals, (rows, cols)), shape=(free.size, col))


def lowest(h, basis, k=2) -> np.ndarray:
    w = sla.eigsh((basis.T @ h @ basis).tocsc(), k=k, sigma=-1e-6, which="LM")[0]
    return np.sort(w)


def chain_stiffness(
    width: float, along: float, angle: float, mode: str, fold: float = 1.0, panels: int = 12
) -> float:
    """EI or GJ [k mm^2] of a chain of N5B8 parallelograms (hinges only: spokes k = 1 N mm/(rad
    mm), folds ``fold`` k)."""
    a = math.radians(angle)
    f = np.array([math.cos(a), math.sin(a)]) * width / math.sin(a)
    pts = [(*(np.array([i * along, 0.0]) + s * f), 0.0) for i in range(panels + 1) for s in (0, 1)]
    quads = [(2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1) for i in range(panels)]
    s = n5b8_structure(np.array(pts), np.array(quads), 0.127)
    nc = s.nodes.shape[0] - panels
    centre = s.nodes[:nc, 0].mean()
    return imposed_hinge_energy(s, nc, s.nodes[:nc, 0] - centre, centre, mode, fold) / (
        panels * along
    )


def imposed_hinge_energy(
    s, nc: int, u: np.ndarray, centre: float, mode: str, fold: float, kappa: float = 1e-3
) -> float:
    """2 U / kappa^2 [k mm^3] of an N5B8 structure ``s`` whose first ``nc`` (corner) nodes are put
    on the isometric cylinder (``mode`` "bend", about the axis across the ribbon) or helicoid
    (about its centre line) of curvature ``kappa`` [1/mm], ``u`` [mm] their coordinate along the
    ribbon from ``centre`` (x [mm]); the centre nodes free; U the hinges' energy (spokes k = 1 N
    mm/(rad mm), folds ``fold`` k) at its minimum over the centre nodes."""
    x0 = s.nodes
    x = x0.copy()
    if mode == "bend":
        x[:nc, 0] = centre + np.sin(kappa * u) / kappa
        x[:nc, 2] = (1.0 - np.cos(kappa * u)) / kappa
    else:
        v = x0[:nc, 1] - x0[:nc, 1].mean()
        x[:nc, 1] = x0[:nc, 1].mean() + v * np.cos(kappa * u)
        x[:nc, 2] = v * np.sin(kappa * u)
    rows = np.vstack([s.hinges["bend"], s.hinges["fold"]])
    k = np.r_[np.ones(len(s.hinges["bend"])), np.full(len(s.hinges["fold"]), fold)]
    length = k * np.linalg.norm(x0[rows[:, 1]] - x0[rows[:, 0]], axis=1)
    rest = dihedral_angle(*(x0[rows[:, c]] for c in range(4)), derivatives=0)

    def energy(z):
        y = x.copy()
        y[nc:] = z.reshape(-1, 3)
        th = dihedral_angle(*(y[rows[:, c]] for c in range(4)), derivatives=0)
        return 0.5 * np.sum(length * (th - rest) ** 2)

    res = minimize(energy, x[s.panels].mean(axis=1).ravel(), method="BFGS", options={"gtol": 1e-14})
    return 2.0 * res.fun / kappa**2


def segment_stiffness(structure, mode: str, fold: float = 1.0) -> float:
    """EI or GJ [k mm^2] of one free ribbon segment of a gridshell structure (x ribbon 0, segment
    1: junction edge to junction edge, its panels as built, laid flat), as
    :func:`chain_stiffness`: hinges only (spokes k = 1 N mm/(rad mm), folds ``fold`` k), corners on
    the isometric cylinder / helicoid about the ribbon's centre line, centre nodes free; the
    energy per unit length of the segment's centre line."""
    per_seg = 2 * structure.info["flank_panels"] + 2
    first = per_seg  # x ribbon 0: segment 0's panels and junction, then segment 1's
    ids = np.arange(first, first + per_seg - 1)
    assert not np.any(structure.info["panel_kind"][ids] == "junction")
    quads0 = structure.panels[ids]
    used, quads = np.unique(quads0, return_inverse=True)
    pts = structure.nodes[used].copy()
    pts[:, 2] = 0.0
    e1 = np.array([1.0, 0.0])
    along = pts[:, :2] @ e1
    # the centre line's length: the junction edges' midpoints
    start = pts[quads.reshape(-1, 4)[0, [0, 3]], :2].mean(axis=0) @ e1
    end = pts[quads.reshape(-1, 4)[-1, [1, 2]], :2].mean(axis=0) @ e1
    length = end - start
    s = n5b8_structure(pts, quads.reshape(-1, 4), 0.127)
    centre = 0.5 * (start + end)
    return imposed_hinge_energy(s, pts.shape[0], along - centre, centre, mode, fold) / length


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--layout", default="rhombic60")
    p.add_argument("--diagonals", default="auto", help="mesh.contact_diagonals: auto, one, both")
    p.add_argument("--steps", type=int, default=10, help="increments of the ramp (>= 1)")
    p.add_argument("--at", default="", help="extra load factors t to analyse, comma separated")
    p.add_argument(
        "--symmetric-from", type=float, default=0.0, help="continue the symmetric branch"
    )
    p.add_argument("--kapton-factor", type=float, default=1.0, help="x kapton.bending_factor")
    p.add_argument("--flank-panels", type=int, default=0, help="mesh.flank_panels (0: the set's)")
    p.add_argument(
        "--free-panels", default="auto", help="mesh.free_panels: auto, skewed, rectangular"
    )
    p.add_argument("--chain", action="store_true", help="also the N5B8 chain's EI and GJ")
    a = p.parse_args(argv)
    try:
        at = sorted(
            {round(k / a.steps, 6) for k in range(1, a.steps + 1)}
            | {float(v) for v in a.at.split(",") if v}
        )
    except ValueError:
        print(f"--at = {a.at!r}: comma-separated load factors in (0, 1]", file=sys.stderr)
        return 2
    layout = NAMED_LAYOUTS.get(a.layout)
    if (
        layout is None
        or layout.kind not in ("orthogonal", "rhombic")
        or a.diagonals not in ("auto", "one", "both")
        or a.steps < 1
        or not all(0.0 < t <= 1.0 for t in at)
        or not 0.0 <= a.symmetric_from < 1.0
        or a.kapton_factor <= 0.0
        or not 0 <= a.flank_panels <= 200
        or a.free_panels not in ("auto", "skewed", "rectangular")
    ):
        print(
            "--layout: a two-family named layout; --diagonals auto|one|both; --steps >= 1; "
            "0 < --at <= 1; 0 <= --symmetric-from < 1; --kapton-factor > 0; "
            "0 <= --flank-panels <= 200; --free-panels auto|skewed|rectangular",
            file=sys.stderr,
        )
        return 2
    ms = calibrate.model_set("fe-calibrated")
    ms = dataclasses.replace(ms, mesh=dataclasses.replace(ms.mesh, free_panels=a.free_panels))
    mats = ms.materials_for(layout)
    kapton = dataclasses.replace(
        mats.kapton, bending_factor=mats.kapton.bending_factor * a.kapton_factor
    )
    mats = dataclasses.replace(mats, kapton=kapton)
    mesh = dataclasses.replace(ms.mesh, contact_diagonals=a.diagonals)
    if a.flank_panels:
        mesh = dataclasses.replace(mesh, flank_panels=a.flank_panels)
    s = build_gridshell_bar_hinge(layout=layout, mesh=mesh)
    print(f"# {a.layout}, clamp, Fig. 4 dome, FE-calibrated set, contact_diagonals {a.diagonals}")
    for d in ("one", "both"):
        other = build_gridshell_bar_hinge(
            layout=layout, mesh=dataclasses.replace(mesh, contact_diagonals=d)
        )
        for which in ("diag", "anti"):
            bad = unmatched_mirror_rows(other, diagonal_mirror(other, which))
            print(
                f"split {d}, mirror {which}: unmatched rows",
                {k: v for k, v in bad.items() if v},
            )
    perm = diagonal_mirror(s, "diag")
    q, r = mirror_operator(s, perm)
    problem = GridshellBH(s, GridshellBHConfig(materials=mats, support="clamp"))
    model, held = problem.model, problem.setup.held
    free = np.setdiff1d(np.arange(model.ndof), held)
    reduced = ReducedHessian.of(model, free)
    sym, anti = parity_basis(perm, r, free, +1), parity_basis(perm, r, free, -1)
    lam = gs.SHAPES["dome"]["lambdas"]

    def report(t, x, label=""):
        xs = x.reshape(-1, 3)
        c = gridshell_curvatures(s, xs)
        h = reduced.matrix(model.evaluate(xs.reshape(-1))[2])
        slack = int(np.count_nonzero(model.bar_forces(xs.reshape(-1))["top_strips"] == 0.0))
        ws, wa = lowest(h, sym), lowest(h, anti)
        print(
            f"{t:.3f} | {c['circle_x']:.5f} / {c['circle_y']:.5f} | "
            f"{np.abs(xs[perm, 2] - xs[:, 2]).max():.1e} | {slack}/{s.bars['top_strips'].shape[0]} "
            f"| {ws[0]:.3g}, {ws[1]:.3g} | {wa[0]:.3g}, {wa[1]:.3g} {label}",
            flush=True,
        )

    print(
        "t | circle kappa x / y [1/mm] | max |z - z(mirror)| [mm] | slack top bars | lowest "
        "symmetric eigenvalues [N/mm] | lowest antisymmetric [N/mm]"
    )
    t0 = time.process_time()
    for t in at:
        if a.symmetric_from and t > a.symmetric_from:
            break
        problem.set_drives(
            {k: PUBLISHED_LAMBDA_N + t * (v - PUBLISHED_LAMBDA_N) for k, v in lam.items()}
        )
        problem.advance()
        report(t, problem.x)
    if a.symmetric_from:
        problem.set_drives(lam)
        target = problem._target
        x = problem.x.reshape(-1).copy()
        for t in [u for u in at if u > a.symmetric_from]:
            model.set_rest_fractions({g: 1.0 + t * (v - 1.0) for g, v in target.items()})
            for _ in range(400):
                e, g, coo = model.evaluate(x)
                gy = sym.T @ g[free]
                if np.abs(gy).max() < 1e-7:
                    break
                dy = sla.spsolve((sym.T @ reduced.matrix(coo) @ sym).tocsc(), -gy)
                step = 1.0
                while step > 1e-8:
                    xn = x.copy()
                    xn[free] += step * (sym @ dy)
                    if model.evaluate(xn, derivatives=0) <= e + 1e-4 * step * (gy @ dy):
                        break
                    step *= 0.5
                x = xn
            else:
                print(
                    f"{t:.3f}: the symmetric Newton did not converge (|g| {np.abs(gy).max():.1e})"
                )
                break
            report(t, x, "(symmetric branch)")
    print(f"CPU {time.process_time() - t0:.1f} s")
    if a.chain:
        for angle in (90.0, 60.0):
            ei = chain_stiffness(7.0, 2.2, angle, "bend")
            gj = chain_stiffness(7.0, 2.2, angle, "twist")
            # folds free: the spokes alone set the least EI/GJ any fold stiffness can give
            ratio = chain_stiffness(7.0, 2.2, angle, "bend", 0.0) / chain_stiffness(
                7.0, 2.2, angle, "twist", 0.0
            )
            print(
                f"N5B8 chain, 2.2 mm panels at {angle:g} deg: EI {ei:.2f} k mm^2,",
                f"GJ {gj:.2f} k mm^2; folds free (k_f = 0): EI/GJ",
                f"{ratio:.3f}",
            )
        # one free segment as built, junction edge to junction edge (mesh.free_panels)
        for name, panels in (
            ("published", "auto"),
            ("rhombic60", "skewed"),
            ("rhombic60", "rectangular"),
        ):
            seg = build_gridshell_bar_hinge(
                layout=NAMED_LAYOUTS[name], mesh=dataclasses.replace(mesh, free_panels=panels)
            )
            print(
                f"segment of {name}, {seg.info['free_panels']} free panels: EI",
                f"{segment_stiffness(seg, 'bend'):.2f} k mm^2, GJ",
                f"{segment_stiffness(seg, 'twist'):.2f} k mm^2",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
