"""Benchmark of the 0.2 A free-strip transient (30 s) at three mesh levels: Newton iterations per
step, seconds per step, degrees of freedom and peak memory. Each level runs in its own process so
that the peak resident memory (getrusage ru_maxrss) belongs to that level alone.

Run:  .venv/bin/python benchmarks/strip_benchmark.py [--levels 0 1 2] [--dt 0.5]
      (add --cell tet or --symmetry full to compare discretisations)
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys


def measure(level: int, dt: float, cell: str, symmetry: str) -> dict:
    """One run in this process (called in a child process by :func:`main`)."""
    import resource
    import time

    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation

    t0 = time.perf_counter()
    sim = StripSimulation(
        StripConfig(
            run=StripRun(current=0.2, duration=30.0, dt=dt),
            mesh=StripMesh(level=level, cell=cell, symmetry=symmetry),
        )
    )
    build = time.perf_counter() - t0
    res = sim.run(None, progress=False, fields=False)
    its = res.history["newton_iterations [-]"][1:]
    steps = len(its)
    return {
        "level": level,
        "cell": cell,
        "symmetry": symmetry,
        "element size [mm]": sim.dims["element_size"],
        "cells": res.summary["mesh"]["cells"],
        "dofs u": sim.ndofs["displacement"],
        "dofs T": sim.ndofs["temperature"],
        "steps": steps,
        "newton its/step": float(its.mean()),
        "s/step": res.summary["wall_time [s]"] / steps,
        "build [s]": build,
        "peak memory [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "final stretch [-]": res.summary["metrics"]["final_stretch [-]"],
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--dt", type=float, default=0.5, help="time step [s]")
    parser.add_argument("--cell", choices=("hex", "tet"), default="hex")
    parser.add_argument("--symmetry", choices=("quarter", "full"), default="quarter")
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child is not None:
        print(json.dumps(measure(args.child, args.dt, args.cell, args.symmetry)))
        return
    rows = []
    for level in args.levels:
        out = subprocess.run(
            [
                sys.executable,
                __file__,
                "--child",
                str(level),
                "--dt",
                str(args.dt),
                "--cell",
                args.cell,
                "--symmetry",
                args.symmetry,
            ],
            capture_output=True,
            text=True,
            check=True,
        )
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
        r = rows[-1]
        print(
            f"level {level}: {r['dofs u']} displacement dofs, {r['s/step']:.2f} s/step",
            file=sys.stderr,
        )
    keys = list(rows[0])
    print("\t".join(keys))
    for r in rows:
        print("\t".join(f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k]) for k in keys))


if __name__ == "__main__":
    main()
