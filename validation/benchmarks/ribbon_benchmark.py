"""Wall time per simulated second of the rolling twisted ribbon (DER with contact, friction and heat)
at 50, 100 and 200 nodes, on one core.

    OMP_NUM_THREADS=1 python -m lcefem.validation.benchmarks.ribbon_benchmark [--duration 10]
        [--nodes 50 100 200] [--ground-temperature 100] [--dt 0.01] [--cells-thickness 4]
        [--contact-spacing 0.25] [--warmup 0] [--profile]

Each run settles the ribbon (not timed), optionally runs ``--warmup`` simulated seconds on the plate
(not timed: the ribbon heats and starts rolling), and then times ``duration`` simulated seconds on the
hot plate; it prints wall and CPU seconds (``time.process_time``, the figure to quote on a shared
machine) per simulated second, the real-time factor (simulated seconds per CPU second, > 1: faster
than real time), Newton iterations per step, step cuts and the number of dofs. ``--profile`` adds the
CPU split of the timed steps into mechanics (the implicit step: assembly, factorisation, contact) and
heat (section heat step and natural shape), and a cProfile listing of the hottest functions.
Not a test: figures for the report.
"""

from __future__ import annotations

import argparse
import cProfile
import dataclasses
import io
import os
import platform
import pstats
import time

import numpy as np

from lcefem.solvers.der.model import n_dofs
from lcefem.solvers.der.ribbon import ROLLING_RIBBON, RibbonNumerics, RibbonSetup, RibbonSimulation


def benchmark(nodes: int, duration: float, ground_temperature: float, dt: float, cells_thickness: int | None = None,
              contact_spacing: float | None = None, warmup: float = 0.0, profile: bool = False,
              perturbation: float | None = None) -> dict:
    changes = {"nodes": nodes, "dt": dt}
    if perturbation is not None:
        changes["perturbation"] = perturbation
    if cells_thickness is not None:
        changes["cells_thickness"] = cells_thickness
    if contact_spacing is not None:
        changes["contact_spacing"] = contact_spacing
    setup = RibbonSetup(geometry=ROLLING_RIBBON, ground_temperature=ground_temperature,
                        numerics=dataclasses.replace(RibbonNumerics(), **changes))
    t0 = time.perf_counter()
    sim = RibbonSimulation(setup)
    for _ in range(int(round(warmup / dt))):
        sim.step(dt)
    build = time.perf_counter() - t0
    its0, cuts0 = sim.integrator.total_iterations, sim.integrator.total_cuts
    steps = int(round(duration / dt))
    x0 = sim.state.x.mean(axis=0)
    phases = {"mechanics": 0.0, "heat": 0.0}
    if profile:
        _split_phases(sim, phases)
        prof = cProfile.Profile()
        prof.enable()
    t0, c0 = time.perf_counter(), time.process_time()
    for _ in range(steps):
        sim.step(dt)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    listing = ""
    if profile:
        prof.disable()
        out = io.StringIO()
        pstats.Stats(prof, stream=out).sort_stats("tottime").print_stats(18)
        listing = out.getvalue()
    x1 = sim.state.x.mean(axis=0)
    return {"nodes": nodes, "dofs": n_dofs(nodes), "steps": steps, "wall [s]": wall, "cpu [s]": cpu,
            "wall per simulated second": wall / duration, "real-time factor": duration / cpu,
            "build+settle [s]": build, "newton per step": (sim.integrator.total_iterations - its0) / steps,
            "cuts": sim.integrator.total_cuts - cuts0, "speed [mm/s]": float(np.hypot(*(x1 - x0)[:2]) / duration),
            "contact samples": sim.rod.contact_samples, "phases": phases, "profile": listing,
            "x": sim.state.x.copy()}


def _split_phases(sim: RibbonSimulation, phases: dict) -> None:
    """Wrap the simulation's mechanics trial step and heat step to add their CPU seconds to ``phases``."""
    trial, heat_step = sim.integrator.trial, sim.heat.step

    def timed_trial(*a, **k):
        c = time.process_time()
        try:
            return trial(*a, **k)
        finally:
            phases["mechanics"] += time.process_time() - c

    def timed_heat(*a, **k):
        c = time.process_time()
        try:
            return heat_step(*a, **k)
        finally:
            phases["heat"] += time.process_time() - c

    sim.integrator.trial, sim.heat.step = timed_trial, timed_heat


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, nargs="+", default=[50, 100, 200])
    parser.add_argument("--duration", type=float, default=10.0, help="timed simulated time [s]")
    parser.add_argument("--ground-temperature", type=float, default=100.0, help="plate temperature [C]")
    parser.add_argument("--dt", type=float, default=0.01, help="time step [s]")
    parser.add_argument("--cells-thickness", type=int, default=None,
                        help="RibbonNumerics.cells_thickness (default: RibbonNumerics' own)")
    parser.add_argument("--contact-spacing", type=float, default=None,
                        help="[mm] RibbonNumerics.contact_spacing (default: RibbonNumerics' own)")
    parser.add_argument("--perturbation", type=float, default=None,
                        help="[rad/s] RibbonNumerics.perturbation, the initial spin (1.0 starts the 100 C, 95-107-node "
                             "ribbon on its rolling branch, docs/ribbon.md)")
    parser.add_argument("--warmup", type=float, default=0.0, help="untimed simulated time on the plate first [s]")
    parser.add_argument("--profile", action="store_true", help="CPU split mechanics / heat and a cProfile listing")
    parser.add_argument("--positions", help="write the final node positions of each size to <this>_<nodes>.npy")
    args = parser.parse_args(argv)
    print(f"ribbon benchmark: {platform.processor() or platform.machine()}, python {platform.python_version()}, "
          f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}, plate {args.ground_temperature:g} C, "
          f"dt {args.dt:g} s, cells_thickness {args.cells_thickness or RibbonNumerics().cells_thickness}, "
          f"contact_spacing {args.contact_spacing if args.contact_spacing is not None else RibbonNumerics().contact_spacing:g} mm, "
          f"initial spin {args.perturbation if args.perturbation is not None else RibbonNumerics().perturbation:g} rad/s, "
          f"warm-up {args.warmup:g} s, {args.duration:g} s timed per size")
    for n in args.nodes:
        r = benchmark(n, args.duration, args.ground_temperature, args.dt, args.cells_thickness, args.contact_spacing,
                      args.warmup, args.profile, args.perturbation)
        print(f"  {r['nodes']:4d} nodes ({r['dofs']} dofs, {r['contact samples']} contact sections per edge): "
              f"real-time factor {r['real-time factor']:.2f} (simulated s per CPU s; {r['cpu [s]']:.1f} s CPU, "
              f"{r['wall [s]']:.1f} s wall for {r['steps']} steps), {r['newton per step']:.2f} Newton iterations "
              f"per step, {r['cuts']} step cuts, speed {r['speed [mm/s]']:.6f} mm/s; build + settle + warm-up "
              f"{r['build+settle [s]']:.1f} s", flush=True)
        if args.profile:
            ph = r["phases"]
            print(f"    CPU split: mechanics {ph['mechanics']:.2f} s, heat {ph['heat']:.2f} s, other "
                  f"{r['cpu [s]'] - ph['mechanics'] - ph['heat']:.2f} s (profiled run: slower than unprofiled)")
            print(r["profile"])
        if args.positions:
            np.save(f"{args.positions}_{n}.npy", r["x"])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
