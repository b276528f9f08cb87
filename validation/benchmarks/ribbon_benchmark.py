"""Wall time per simulated second of the rolling twisted ribbon (DER with contact, friction and heat)
at 50, 100 and 200 nodes, on one core.

    OMP_NUM_THREADS=1 python -m lcefem.validation.benchmarks.ribbon_benchmark [--duration 10]
        [--nodes 50 100 200] [--ground-temperature 100] [--dt 0.01]

Each run settles the ribbon (not timed) and then times ``duration`` simulated seconds on the hot
plate; it prints wall seconds per simulated second (< 1: faster than real time), Newton iterations
per step, step cuts and the number of dofs. Not a test: figures for the report.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import time

from lcefem.models.ribbon import RibbonGeometry
from lcefem.solvers.der.model import n_dofs
from lcefem.solvers.der.ribbon import RibbonNumerics, RibbonSetup, RibbonSimulation


def benchmark(nodes: int, duration: float, ground_temperature: float, dt: float) -> dict:
    setup = RibbonSetup(geometry=RibbonGeometry(), ground_temperature=ground_temperature,
                        numerics=dataclasses.replace(RibbonNumerics(), nodes=nodes, dt=dt))
    t0 = time.perf_counter()
    sim = RibbonSimulation(setup)
    build = time.perf_counter() - t0
    its0, cuts0 = sim.integrator.total_iterations, sim.integrator.total_cuts
    steps = int(round(duration / dt))
    t0 = time.perf_counter()
    for _ in range(steps):
        sim.step(dt)
    wall = time.perf_counter() - t0
    return {"nodes": nodes, "dofs": n_dofs(nodes), "steps": steps, "wall [s]": wall,
            "wall per simulated second": wall / duration, "build+settle [s]": build,
            "newton per step": (sim.integrator.total_iterations - its0) / steps,
            "cuts": sim.integrator.total_cuts - cuts0}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, nargs="+", default=[50, 100, 200])
    parser.add_argument("--duration", type=float, default=10.0, help="timed simulated time [s]")
    parser.add_argument("--ground-temperature", type=float, default=100.0, help="plate temperature [C]")
    parser.add_argument("--dt", type=float, default=0.01, help="time step [s]")
    args = parser.parse_args(argv)
    print(f"ribbon benchmark: {platform.processor() or platform.machine()}, python {platform.python_version()}, "
          f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}, plate {args.ground_temperature:g} C, "
          f"dt {args.dt:g} s, {args.duration:g} s timed per size")
    for n in args.nodes:
        r = benchmark(n, args.duration, args.ground_temperature, args.dt)
        print(f"  {r['nodes']:4d} nodes ({r['dofs']} dofs): {r['wall per simulated second']:.2f} s wall per simulated "
              f"second ({r['wall [s]']:.1f} s for {r['steps']} steps), {r['newton per step']:.2f} Newton iterations "
              f"per step, {r['cuts']} step cuts; build + settle {r['build+settle [s]']:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
