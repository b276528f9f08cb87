"""CPU time of a reachable design of a Fig. 4 target (issue 50: within 2 minutes on one core).

    OMP_NUM_THREADS=1 python benchmarks/reach_benchmark.py [--shape cylinder] [--support S]

Runs ``lcefem design``'s default for the paper's measured curvatures of one Fig. 4 shape (seed 001;
table: the flat) on its published support (or ``--support``), FE-calibrated set: the design loop,
then the search along the run's own path from flat
(lcefem.validation.studies.design.gridshell_design.reach), and prints the CPU seconds of each part,
the kind of design (constant lambdas or a program), how far the run from flat ends from the target
and the lambdas. Not a test: it prints numbers.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from lcefem.validation.studies.design import gridshell_design as gd
from lcefem.validation.studies.gridshell import gridshell_bh as gs

BUDGET = 120.0  # s CPU on one core (issue 50)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shape", default="cylinder", choices=list(gs.SHAPES))
    parser.add_argument("--support", default=None, help="default: the shape's published support")
    args = parser.parse_args(argv)
    spec = gs.SHAPES[args.shape]
    target = spec["paper_exp"] if spec["paper_exp"][0] is not None else spec["paper_sim"]
    support = args.support or spec["support"]
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"{platform.processor() or platform.machine()}"
    )
    t0 = time.process_time()
    design = gd.setup_design("4", support)
    t1 = time.process_time()
    res = gd.inverse(design, *target)
    t2 = time.process_time()
    found = res.check["reach"]
    lams = ", ".join(f"{k}={v:.4f}" for k, v in gd.lambdas_by_name(design, found.p).items())
    print(
        f"{args.shape} target {target[0]:g}/{target[1]:g} 1/mm on {support}: set-up {t1 - t0:.1f} "
        "s "
        "CPU, "
        f"design loop {t2 - t1 - found.seconds:.1f} s CPU, search along the run's path "
        f"{found.seconds:.1f} "
        "s "
        f"CPU ({len(found.attempts)} runs from flat); total {t2 - t0:.1f} s CPU "
        f"({'within' if t2 - t0 <= BUDGET else 'over'} the {BUDGET:.0f} s budget)"
    )
    print(
        f"design: {found.kind}, {len(found.stages)} drive(s); the run from flat ends "
        f"{found.achieved[0]:.5f}/{found.achieved[1]:.5f} 1/mm, {found.distance:.1e} 1/mm from the "
        f"target (tolerance {gd.DESIGN_TOLERANCE:g}); lambdas {lams}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
