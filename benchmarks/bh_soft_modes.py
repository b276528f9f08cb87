"""The bar-and-hinge tangent's softest modes along a layout's ramp: where they live and what stalls
Newton (issue 47: the 5 x 5 dome under the rollers stops short of t = 1).

Runs a layout's drive (FE-calibrated model set, GRIDSHELL_NEWTON, the defaults of the validation's
layout rows) and, at every converged load factor t >= ``--from``, prints the lowest eigenvalues of
the tangent on the free DOFs [N/mm] (shift-invert Lanczos), the share of each mode on the raised
top squares' nodes (1: a rigid motion of a square alone), the top strips without force (slack),
the active strip-ribbon contacts, and the share of the residual on the top squares' nodes. Also,
once: the smallest singular value of the six rigid-body modes restricted to the held DOFs (zero:
the support leaves a free rigid-body mode).

    OMP_NUM_THREADS=1 python benchmarks/bh_soft_modes.py [--layout 5x5] [--support rollers]
        [--from 0.55] [--modes 6] [--cpu-limit 300]

Not a test: it prints figures for docs/layouts/index.md ("Speed").
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np
import scipy.sparse.linalg as sla

from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.models.errors import ConvergenceError
from lcefem.solvers.bar_hinge.model import ReducedHessian
from lcefem.solvers.problems.gridshell_bh import SUPPORTS, GridshellBH, GridshellBHConfig
from lcefem.validation.studies.gridshell import calibrate
from lcefem.validation.studies.gridshell import gridshell_bh as gs


class CPULimit(Exception):
    pass


def rigid_modes(x: np.ndarray) -> np.ndarray:
    """The six rigid-body modes (3n, 6) of the positions x (n, 3) [mm]: three translations and
    three rotations about the centroid."""
    n = x.shape[0]
    r = np.zeros((n, 3, 6))
    for i in range(3):
        r[:, i, i] = 1.0
    c = x - x.mean(axis=0)
    for k, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):
        r[:, a, 3 + k], r[:, b, 3 + k] = -c[:, b], c[:, a]
    return r.reshape(-1, 6)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--layout", default="5x5", help="one of " + ", ".join(NAMED_LAYOUTS))
    p.add_argument("--support", default="rollers", help="one of " + ", ".join(SUPPORTS))
    p.add_argument("--shape", default="dome", help="one of " + ", ".join(gs.SHAPES))
    p.add_argument("--from", dest="start", type=float, default=0.55, help="first t analysed [-]")
    p.add_argument("--modes", type=int, default=6, help="lowest eigenpairs per state")
    p.add_argument("--cpu-limit", type=float, default=0.0, help="stop after this many CPU s")
    a = p.parse_args(argv)
    for name, value, allowed in (
        ("--layout", a.layout, NAMED_LAYOUTS),
        ("--support", a.support, SUPPORTS),
        ("--shape", a.shape, gs.SHAPES),
    ):
        if value not in allowed:
            print(f"{name} = {value!r}: allowed {', '.join(allowed)}", file=sys.stderr)
            return 2
    if a.modes < 1 or a.cpu_limit < 0 or not 0.0 <= a.start <= 1.0:
        print("--modes >= 1, --cpu-limit >= 0 s and 0 <= --from <= 1 expected", file=sys.stderr)
        return 2
    ms = calibrate.model_set("fe-calibrated")
    layout = NAMED_LAYOUTS[a.layout]
    problem = GridshellBH(
        ms.structure(layout),
        GridshellBHConfig(materials=ms.materials_for(layout), support=a.support),
    )
    problem.set_drives(gs.SHAPES[a.shape]["lambdas"])
    model, held = problem.model, problem.setup.held
    free = np.setdiff1d(np.arange(model.ndof), held)
    reduced = ReducedHessian.of(model, free)
    squares = problem.structure.node_sets["top_squares"].reshape(-1)
    sv = np.linalg.svd(rigid_modes(model.reference)[held], compute_uv=False)
    print(f"# {a.layout}, {a.support}, {a.shape}: {model.ndof} DOFs, {held.size} held")
    print(f"rigid-body modes at the held DOFs: smallest singular value {sv.min():.3g} mm")
    print(
        "t | E [mJ] | |g| [N] | lowest eigenvalues [N/mm] (share on top squares) | slack top "
        "strips | active contacts | residual share on top squares"
    )
    t0 = time.process_time()

    def on_step(s) -> None:
        if a.cpu_limit and time.process_time() - t0 > a.cpu_limit:
            raise CPULimit
        if s.t < a.start:
            return
        x = s.x.reshape(-1)
        _, g, coo = model.evaluate(x)
        vals, vecs = sla.eigsh(reduced.matrix(coo), k=a.modes, sigma=-1e-6, which="LM")
        modes = []
        for i in np.argsort(vals):
            v = np.zeros(model.ndof)
            v[free] = vecs[:, i]
            share = float((v.reshape(-1, 3)[squares] ** 2).sum())
            modes.append(f"{vals[i]:.3g} ({share:.4f})")
        gl = np.zeros(model.ndof)
        gl[free] = g[free]
        g2 = (gl.reshape(-1, 3) ** 2).sum(axis=1)
        slack = int(np.count_nonzero(model.bar_forces(x)["top_strips"] == 0.0))
        active = sum(int(np.count_nonzero(f > 0)) for f in model.contact_forces(x).values())
        print(
            f"{s.t:.5f} | {s.energy:.10g} | {s.residual:.2e} | {', '.join(modes)} | {slack} | "
            f"{active} | {g2[squares].sum() / max(g2.sum(), 1e-300):.3f}",
            flush=True,
        )

    try:
        problem.advance(on_step=on_step)
        print(f"reached t = 1 after {time.process_time() - t0:.1f} CPU s")
    except CPULimit:
        print(f"stopped at the CPU limit ({a.cpu_limit:g} s)")
    except ConvergenceError as exc:
        print(f"stopped: {exc}")
        last = getattr(exc, "last_state", None)
        if last is not None:
            on_step(last)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
