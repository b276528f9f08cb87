"""Speed of our Discrete Elastic Rods: the rolling ribbon (before/after a code change) and three
cantilever problems against PyElastica where it is installed (DisMech: ``dismech_benchmark``).

    OMP_NUM_THREADS=1 python benchmarks/der_benchmark.py [--nodes 31 100]
        [--duration 5] [--warmup 30] [--error-tolerance 0 0.01] [--baseline DIR] [--skip-ribbon]
        [--skip-peers] [--heat-dt 0.02] [--contact-spacing 0.25] [--source-elastic]
        [--same-state ROUNDS] [--csv out.csv]

Ribbon: the default twisted ribbon on a 100 C plate (``RibbonSetup``), settled and heated for
``warmup`` simulated seconds (untimed), then ``duration`` simulated seconds timed at dt = 0.01 s, or
with adaptive steps (``--error-tolerance`` > 0 [mm], ``RibbonNumerics.error_tolerance``; the run
advances record interval by record interval, 0.05 s, as ``run_ribbon`` does): CPU and wall ms per
step (and the CPU ms of the mechanics step alone; the rest is the section heat step and the natural
shape of the new temperatures; ``--heat-dt``: also with that multirate heat step,
``RibbonNumerics.heat_dt``; ``--contact-spacing``: also with contact sections that far apart [mm],
``RibbonNumerics.contact_spacing``; ``--source-elastic``: also with
``RibbonNumerics.elastic_hessian_at_source``), Newton iterations per step, and the real-time factor
(simulated seconds per CPU second, > 1: faster than real time; CPU time because the machine is
shared, wall time printed next to it). ``--baseline DIR`` runs the same loop with ``lcefem``
imported from DIR (e.g. ``git archive <commit> | tar -x -C DIR/lcefem``), in a child process, for
before/after ratios; the centroid and Newton iteration counts of both are printed to show the
answers did not change.

Peers (``pip install 'lcefem[benchmark]'``; a missing package is skipped with the reason): a clamped
round rod under its weight (L = 100 mm, r = 1 mm, E = 100 MPa, nu = 0.5, rho = 1.2e-9 t/mm^3, 51
nodes; linear tip deflection q L^4/(8 EI) = 5.9 mm, first period 0.12 s):
1. static cantilever: ours by Newton (``solve_static``), PyElastica by damped dynamics (its only
   way) until the tip is within 1e-3 of our static tip deflection;
2. damped dynamics to rest: both released straight with the same mass-proportional damping
   (30 1/s), 1 s simulated; ours implicit Euler at 5 ms steps;
3. undamped swing at matched accuracy: released straight, 0.25 s simulated; each code at the largest
   step whose tip path (sampled every 5 ms) stays within 1 % of the swing amplitude of its own run
   at a smaller step (ours: 1e-4 s; PyElastica: a 4x smaller one); ours implicit midpoint,
   PyElastica at the largest stable step of a ladder (its error there is already far below 1 %).
Not a test: figures for the README (``Discrete Elastic Rods``).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import importlib.util
import json
import math
import os
import pickle
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

# ----------------------------------------------------------------------------------------------
# The rolling ribbon (runs in this process, or in a child with another lcefem on its path)
# ----------------------------------------------------------------------------------------------


def ribbon_run(
    nodes: int,
    duration: float,
    warmup: float,
    dt: float = 0.01,
    ground_temperature: float = 100.0,
    error_tolerance: float = 0.0,
    record: float = 0.05,
    heat_dt: float = 0.0,
    elastic_hessian_at_source: bool = False,
    contact_spacing: float = 0.0,
    save_state: str | None = None,
    load_state: str | None = None,
) -> dict:
    """Settle, heat for ``warmup`` simulated seconds (untimed: the ribbon starts to roll), then time
    ``duration`` simulated seconds of the rolling ribbon (fixed steps of dt, or adaptive steps to
    every record time when ``error_tolerance`` [mm] > 0). ``save_state``: pickle the simulation
    there after the warm-up instead of timing; ``load_state``: time from that pickle instead of
    warming up (fixed steps; every code from the same state, with its own solver options)."""
    from lcefem.solvers.der.ribbon import RibbonNumerics, RibbonSetup, RibbonSimulation

    # an older package (--baseline) has fixed steps only and no such fields
    fields = {f.name for f in dataclasses.fields(RibbonNumerics)}
    control = {"error_tolerance": error_tolerance} if "error_tolerance" in fields else {}
    if heat_dt:
        control["heat_dt"] = heat_dt
    if elastic_hessian_at_source:
        control["elastic_hessian_at_source"] = True
    if contact_spacing:
        control["contact_spacing"] = contact_spacing
    # the default rolling ribbon of the package (issue 32: the seed-000 ribbon LCE, its twist
    # locked)
    setup = RibbonSetup(
        ground_temperature=ground_temperature,
        numerics=dataclasses.replace(RibbonNumerics(), nodes=nodes, dt=dt, **control),
    )
    t0 = time.perf_counter()
    adaptive = error_tolerance > 0
    if load_state:
        with open(load_state, "rb") as fh:
            sim = pickle.load(fh)
        sim.setup = dataclasses.replace(
            sim.setup, numerics=dataclasses.replace(sim.setup.numerics, **control)
        )
        # The pickle carries the solver options of the code that warmed up; every code steps with
        # its own (those a fresh simulation of this package builds; no settling needed for them).
        own = RibbonSimulation(
            dataclasses.replace(
                setup, numerics=dataclasses.replace(setup.numerics, settle_time=0.0)
            )
        )
        sim.integrator.options = own.integrator.options
        if hasattr(sim, "options"):  # (an older package keeps them on the integrator only)
            sim.options = own.integrator.options
        sim.step(dt)  # numba compilation or cache load, outside the timing
    else:
        sim = RibbonSimulation(setup)
        sim.step(dt)  # first step: numba compilation or cache load, outside the timing
        if adaptive:
            sim.advance(sim.time + warmup)
        else:
            for _ in range(int(round(warmup / dt))):
                sim.step(dt)
        if save_state:
            with open(save_state + ".part", "wb") as fh:
                pickle.dump(sim, fh)
            os.replace(save_state + ".part", save_state)
            return {"saved": save_state}
    build = time.perf_counter() - t0
    its0 = sim.integrator.total_iterations
    steps0 = getattr(sim, "steps_taken", 0)
    steps = int(round(duration / dt))
    inside = [0.0]  # CPU time in the mechanics step (the rest: heat step, natural shape)
    # The mechanics step: Integrator.trial where it exists (the ribbon's step calls it), else .step.
    hook = "trial" if hasattr(sim.integrator, "trial") else "step"
    mechanics = getattr(sim.integrator, hook)

    def timed_mechanics(h):
        c = time.process_time()
        report = mechanics(h)
        inside[0] += time.process_time() - c
        return report

    setattr(sim.integrator, hook, timed_mechanics)
    w0, c0 = time.perf_counter(), time.process_time()
    if adaptive:
        start = sim.time
        for k in range(1, int(round(duration / record)) + 1):
            sim.advance(start + k * record)
        steps = sim.steps_taken - steps0
    else:
        for _ in range(steps):
            sim.step(dt)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    st = sim.state
    return {
        "nodes": nodes,
        "steps": steps,
        "cpu_ms_per_step": 1e3 * cpu / steps,
        "mechanics_ms_per_step": 1e3 * inside[0] / steps,
        "wall_ms_per_step": 1e3 * wall / steps,
        "newton_per_step": (sim.integrator.total_iterations - its0) / steps,
        "realtime_factor_cpu": duration / cpu,
        "realtime_factor_wall": duration / wall,
        "build_s": build,
        "rejected": getattr(sim, "rejected", 0),
        "centroid": [float(v) for v in st.x.mean(axis=0)],
        "speed": float(np.hypot(*st.v.mean(axis=0)[:2])),
    }


#: Plate temperature of the timed ribbon [C] (``--ground-temperature``; issue 32: at 100 C the
#: 100-node seed-000 ribbon has not started rolling after 90 s, so the rolling cost is timed on a
#: hotter plate).
GROUND_TEMPERATURE = 100.0


def ribbon_in_child(
    nodes: int,
    duration: float,
    warmup: float,
    path: str | None,
    error_tolerance: float = 0.0,
    **options,
) -> dict:
    """:func:`ribbon_run` (keyword ``options``: heat_dt, elastic_hessian_at_source, save_state,
    load_state) in a child process,
    with ``lcefem`` from ``path`` when given (fixed steps only there: an older package may not have
    the adaptive ones)."""
    env = dict(os.environ)
    if path:
        env["PYTHONPATH"] = os.path.abspath(path) + os.pathsep + env.get("PYTHONPATH", "")
    kwargs = dict(
        nodes=nodes,
        duration=duration,
        warmup=warmup,
        error_tolerance=error_tolerance,
        ground_temperature=GROUND_TEMPERATURE,
        **options,
    )
    out = subprocess.run(
        [sys.executable, os.path.abspath(__file__), "--ribbon-worker", json.dumps(kwargs)],
        env=env,
        cwd="/",
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


# ----------------------------------------------------------------------------------------------
# The cantilever of the peer comparisons
# ----------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Cantilever:
    length: float = 100.0  # [mm]
    radius: float = 1.0  # [mm]
    youngs_modulus: float = 100.0  # [MPa]
    poisson: float = 0.5  # [-]
    density: float = 1.2e-9  # [t/mm^3] (an elastomer)
    gravity: float = 9806.65  # [mm/s^2]
    nodes: int = 51

    @property
    def shear_modulus(self) -> float:
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson))

    def linear_tip_deflection(self) -> float:
        """q L^4/(8 EI) [mm], q = rho A g."""
        q = self.density * math.pi * self.radius**2 * self.gravity
        return q * self.length**4 / (8.0 * self.youngs_modulus * math.pi * self.radius**4 / 4.0)


def our_cantilever(c: Cantilever, damping: float = 0.0):
    from lcefem.models.rod import circular_section
    from lcefem.solvers.der.model import DiscreteRod, RestShape, RodState, lumped_masses, n_dofs

    sec = circular_section(c.radius, c.youngs_modulus, c.shear_modulus, c.density)
    x = np.zeros((c.nodes, 3))
    x[:, 0] = np.linspace(0.0, c.length, c.nodes)
    state = RodState.from_positions(x, first_director=np.array([0.0, 1.0, 0.0]))
    rest = RestShape.straight(np.full(c.nodes - 1, c.length / (c.nodes - 1)))
    nm, ei = lumped_masses(sec, rest.edge_length)
    fixed = np.zeros(n_dofs(c.nodes), bool)
    fixed[:7] = True  # clamp: nodes 0 and 1 and the first edge's angle
    rod = DiscreteRod(
        sec, rest, nm, ei, gravity=np.array([0.0, 0.0, -c.gravity]), damping=damping, fixed=fixed
    )
    return rod, state


def our_static(c: Cantilever) -> tuple[float, float]:
    """(tip z [mm], wall s) of ours by Newton."""
    from lcefem.solvers.der.static import solve_static

    rod, state = our_cantilever(c)
    t0 = time.perf_counter()
    res = solve_static(rod, state)
    return float(res.state.x[-1, 2]), time.perf_counter() - t0


def our_dynamics(
    c: Cantilever, t_end: float, dt: float, damping: float, method: str, sample: float
):
    """Tip z path sampled every ``sample`` [s] and the wall time [s] of ours."""
    from lcefem.solvers.der.integrator import Integrator, StepOptions

    rod, state = our_cantilever(c, damping)
    integ = Integrator(rod, state, StepOptions(method=method))
    integ.step(dt)  # compilation / cache load outside the timing
    rod, state = our_cantilever(c, damping)
    integ = Integrator(rod, state, StepOptions(method=method))
    steps = int(round(t_end / dt))
    tip = np.empty(steps + 1)
    tip[0] = state.x[-1, 2]
    t0 = time.perf_counter()
    for i in range(1, steps + 1):
        integ.step(dt)
        tip[i] = integ.state.x[-1, 2]
    wall = time.perf_counter() - t0
    return sampled(tip, dt, t_end, sample), wall, integ.total_iterations / steps


def sampled(tip: np.ndarray, dt: float, t_end: float, sample: float) -> np.ndarray:
    """The tip path (one value per step of ``dt``) interpolated at multiples of ``sample`` up to
    t_end."""
    times = np.arange(len(tip)) * dt
    return np.interp(np.arange(0.0, t_end + 0.5 * sample, sample), times, tip)


def elastica_dynamics(c: Cantilever, t_end: float, dt: float, damping: float, sample: float):
    """Tip z path sampled every ``sample`` [s] and the wall time [s] of PyElastica (Position
    Verlet)."""
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
        pass

    sim = Sim()
    rod = ea.CosseratRod.straight_rod(
        c.nodes - 1,
        np.zeros(3),
        np.array([1.0, 0.0, 0.0]),
        np.array([0.0, 0.0, 1.0]),
        c.length,
        c.radius,
        c.density,
        youngs_modulus=c.youngs_modulus,
        shear_modulus=c.shear_modulus,
    )
    sim.append(rod)
    sim.constrain(rod).using(
        ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,)
    )
    sim.add_forcing_to(rod).using(ea.GravityForces, acc_gravity=np.array([0.0, 0.0, -c.gravity]))
    if damping > 0:
        sim.dampen(rod).using(
            ea.AnalyticalLinearDamper, uniform_damping_constant=damping, time_step=dt
        )
    sim.finalize()
    stepper = ea.PositionVerlet()
    steps = int(math.ceil(t_end / dt - 1e-9))
    tip = np.empty(steps + 1)
    tip[0] = rod.position_collection[2, -1]
    t, t0 = 0.0, time.perf_counter()
    for i in range(1, steps + 1):
        t = stepper.step(sim, t, dt)
        tip[i] = rod.position_collection[2, -1]
    wall = time.perf_counter() - t0
    return sampled(tip, dt, t_end, sample), wall


def elastica_stable_dt(c: Cantilever, z_static: float) -> float:
    """The largest step of a ladder f dl / c_E (c_E = sqrt(E/rho) the bar wave speed; f = 0.5 ...
    0.09, PyElastica's examples use ~0.3) for which 0.02 s of the undamped swing stays bounded."""
    dl = c.length / (c.nodes - 1)
    for f in (0.5, 0.35, 0.25, 0.18, 0.125, 0.09):
        dt = f * dl * math.sqrt(c.density / c.youngs_modulus)
        path, _ = elastica_dynamics(c, 0.02, dt, 0.0, 0.001)
        if np.all(np.isfinite(path)) and np.max(np.abs(path)) < 3.0 * abs(z_static):
            return dt
    raise RuntimeError("PyElastica: no stable step on the ladder")


def peers(c: Cantilever) -> list[dict]:
    rows = []
    have_elastica = importlib.util.find_spec("elastica") is not None
    if not have_elastica:
        print("  PyElastica: skipped (not installed; pip install 'lcefem[benchmark]')")
    # DisMech (the implicit DER peer) has its own benchmark on its own example problem
    print("  DisMech: see python benchmarks/dismech_benchmark.py")
    z_static, t_static = our_static(c)
    z_static, t_static = our_static(c)  # second call: without compilation / cache load
    print(
        f"  cantilever: {c.nodes} nodes, static tip deflection {-z_static:.4f} mm (linear theory "
        f"{c.linear_tip_deflection():.4f} mm)"
    )
    sample = 0.005
    # 1. static
    row = {
        "problem": "static cantilever",
        "ours": "Newton",
        "ours_s": t_static,
        "ours_error": 0.0,
        "peer": "PyElastica damped dynamics",
    }
    dt_p = elastica_stable_dt(c, z_static) if have_elastica else None
    if have_elastica:
        dt = dt_p
        for t_end in (0.5, 1.0, 2.0):
            path, wall = elastica_dynamics(c, t_end, dt, 30.0, sample)
            err = abs(path[-1] - z_static) / abs(z_static)
            if err < 1e-3:
                break
        row.update(
            peer_s=wall, peer_error=err, note=f"PyElastica dt {dt:.2e} s, {t_end:g} s simulated"
        )
    rows.append(row)
    # 2. damped dynamics to rest
    path, wall, its = our_dynamics(c, 1.0, 5e-3, 30.0, "euler", sample)
    row = {
        "problem": "damped dynamics to rest (1 s)",
        "ours": "implicit Euler dt 5 ms",
        "ours_s": wall,
        "ours_error": abs(path[-1] - z_static) / abs(z_static),
        "peer": "PyElastica Position Verlet",
    }
    if have_elastica:
        dt = dt_p
        p_path, p_wall = elastica_dynamics(c, 1.0, dt, 30.0, sample)
        row.update(
            peer_s=p_wall,
            peer_error=abs(p_path[-1] - z_static) / abs(z_static),
            note=f"ours {its:.1f} Newton/step; PyElastica dt {dt:.2e} s",
        )
    rows.append(row)
    # 3. undamped swing at matched accuracy
    t_end = 0.25
    ref, _, _ = our_dynamics(c, t_end, 1e-4, 0.0, "midpoint", sample)
    amp = float(np.max(np.abs(ref - ref[0])))
    chosen = None
    for dt in (5e-3, 2.5e-3, 1.25e-3, 6.25e-4):
        path, wall, its = our_dynamics(c, t_end, dt, 0.0, "midpoint", sample)
        err = float(np.max(np.abs(path - ref))) / amp
        chosen = (dt, wall, err, its)
        if err < 0.01:
            break
    dt, wall, err, its = chosen
    row = {
        "problem": "undamped swing, 1 % of amplitude (0.25 s)",
        "ours": f"implicit midpoint dt {dt:g} s",
        "ours_s": wall,
        "ours_error": err,
        "peer": "PyElastica Position Verlet",
    }
    if have_elastica:
        p_ref, _ = elastica_dynamics(c, t_end, dt_p / 4.0, 0.0, sample)
        p_path, p_wall = elastica_dynamics(c, t_end, dt_p, 0.0, sample)
        p_amp = float(np.max(np.abs(p_ref - p_ref[0])))
        gap = float(np.max(np.abs(p_ref - ref))) / amp
        row.update(
            peer_s=p_wall,
            peer_error=float(np.max(np.abs(p_path - p_ref))) / p_amp,
            note=f"PyElastica dt {dt_p:.2e} s (stability); ours {its:.1f} Newton/step; the two "
            "converged "
            f"paths differ by {100 * gap:.1f} % of the amplitude (Cosserat vs Kirchhoff, lumping)",
        )
    rows.append(row)
    for r in rows:
        r["speed_ratio"] = r["peer_s"] / r["ours_s"] if "peer_s" in r else float("nan")
    return rows


def same_state_rounds(nodes: int, args) -> list[dict]:
    """``--same-state``: warm up once (this code), then time the baseline, this code, each
    ``--heat-dt`` and ``--source-elastic`` from that state, alternating, ``args.same_state`` rounds;
    prints and returns the best and median CPU ms per step of each."""
    codes = (
        ([("baseline", args.baseline, {})] if args.baseline else [])
        + [("now", None, {})]
        + [(f"heat {h:g}", None, {"heat_dt": h}) for h in args.heat_dt]
        + (
            [("el. source", None, {"elastic_hessian_at_source": True})]
            if args.source_elastic
            else []
        )
    )
    with tempfile.TemporaryDirectory() as tmp:
        state = os.path.join(tmp, f"ribbon_{nodes}.pickle")
        ribbon_in_child(nodes, args.duration, args.warmup, None, save_state=state)
        runs = {label: [] for label, _, _ in codes}
        for _ in range(args.same_state):
            for label, path, options in codes:
                runs[label].append(
                    ribbon_in_child(
                        nodes, args.duration, args.warmup, path, load_state=state, **options
                    )
                )
    rows = []
    for label, rs in runs.items():
        cpu = [r["cpu_ms_per_step"] for r in rs]
        r = rs[0]
        print(
            f"  {nodes:4d} nodes {label:10s}: best {min(cpu):6.2f} / median "
            f"{statistics.median(cpu):6.2f} "
            "ms/step "
            f"of {len(cpu)}, {r['newton_per_step']:.2f} Newton/step, "
            f"{args.duration / (1e-3 * min(cpu) * r['steps']):.2f}"
            f" x real time from the best; centroid {r['centroid'][0]:.9f} {r['centroid'][1]:.9f} "
            "mm",
            flush=True,
        )
        rows.append(
            {
                "problem": f"rolling ribbon {nodes} nodes, same state",
                "code": label,
                "ms_per_step": min(cpu),
                "median_ms_per_step": statistics.median(cpu),
                "newton_per_step": r["newton_per_step"],
                "steps": r["steps"],
                "realtime_factor": args.duration / (1e-3 * min(cpu) * r["steps"]),
            }
        )
    if "baseline" in runs:
        best = {label: min(x["cpu_ms_per_step"] for x in rs) for label, rs in runs.items()}
        print(
            f"  {nodes:4d} nodes speed-up from the best: "
            + ", ".join(
                f"{label} {best['baseline'] / v:.2f} x"
                for label, v in best.items()
                if label != "baseline"
            )
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, nargs="+", default=[31, 100])
    parser.add_argument(
        "--duration", type=float, default=5.0, help="timed simulated time of the ribbon [s]"
    )
    parser.add_argument(
        "--baseline", help="directory holding an older lcefem package (before/after ratios)"
    )
    parser.add_argument("--skip-ribbon", action="store_true")
    parser.add_argument(
        "--ground-temperature",
        type=float,
        default=100.0,
        help="plate temperature of the ribbon [C]",
    )
    parser.add_argument("--skip-peers", action="store_true")
    parser.add_argument("--csv", help="write the tables to this CSV file")
    parser.add_argument(
        "--warmup",
        type=float,
        default=30.0,
        help="untimed simulated time on the plate before the timing [s] "
        "(the ribbon heats and starts rolling)",
    )
    parser.add_argument(
        "--error-tolerance",
        type=float,
        nargs="+",
        default=[0.0],
        help="ribbon step control: 0 fixed 0.01 s steps, > 0 adaptive with this local error [mm]",
    )
    parser.add_argument(
        "--source-elastic",
        action="store_true",
        help="also run the ribbon (fixed steps) with RibbonNumerics.elastic_hessian_at_source",
    )
    parser.add_argument(
        "--heat-dt",
        type=float,
        nargs="+",
        default=[],
        help="also run the ribbon (fixed steps) with these multirate heat steps [s] "
        "(RibbonNumerics.heat_dt; the default run has 0: a heat step every step)",
    )
    parser.add_argument(
        "--contact-spacing",
        type=float,
        nargs="+",
        default=[],
        help="also run the ribbon (fixed steps) with contact sections this far apart [mm] "
        "(RibbonNumerics.contact_spacing; the default run has its own)",
    )
    parser.add_argument(
        "--same-state",
        type=int,
        default=0,
        metavar="ROUNDS",
        help="time every code ROUNDS times, alternating, from one warmed-up state (pickled by "
        "this code, fixed steps); best and median CPU time (a shared machine scatters single "
        "runs by +-15 %%)",
    )
    parser.add_argument("--ribbon-worker", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    global GROUND_TEMPERATURE
    GROUND_TEMPERATURE = args.ground_temperature
    if args.ribbon_worker:
        print(json.dumps(ribbon_run(**json.loads(args.ribbon_worker))))
        return 0
    if args.duration <= 0:
        parser.error(f"--duration {args.duration}: must be > 0 s")
    if any(h <= 0 for h in args.heat_dt):
        parser.error(f"--heat-dt {args.heat_dt}: each must be > 0 s")
    if any(s <= 0 for s in args.contact_spacing):
        parser.error(f"--contact-spacing {args.contact_spacing}: each must be > 0 mm")
    print(
        f"DER benchmark: {platform.processor() or platform.machine()}, python "
        f"{platform.python_version()}, "
        f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}"
    )
    table = []
    if not args.skip_ribbon:
        print(
            f"rolling ribbon, {GROUND_TEMPERATURE:g} C plate, dt 0.01 s (fixed, or the first "
            f"adaptive step), {args.duration:g} "
            "s "
            f"timed after {args.warmup:g} s of heating (CPU time; wall in brackets):"
        )
        for n in args.nodes:
            if args.same_state > 0:
                table += same_state_rounds(n, args)
                continue
            runs = {
                ("now" if tol == 0 else f"tol {tol:g}"): ribbon_in_child(
                    n, args.duration, args.warmup, None, tol
                )
                for tol in args.error_tolerance
            }
            for heat_dt in args.heat_dt:
                runs[f"heat {heat_dt:g}"] = ribbon_in_child(
                    n, args.duration, args.warmup, None, heat_dt=heat_dt
                )
            for spacing in args.contact_spacing:
                runs[f"cs {spacing:g}"] = ribbon_in_child(
                    n, args.duration, args.warmup, None, contact_spacing=spacing
                )
            if args.source_elastic:
                runs["el. source"] = ribbon_in_child(
                    n, args.duration, args.warmup, None, elastic_hessian_at_source=True
                )
            if args.baseline:
                runs["baseline"] = ribbon_in_child(n, args.duration, args.warmup, args.baseline)
            for label, r in runs.items():
                print(
                    f"  {n:4d} nodes {label:8s}: {r['cpu_ms_per_step']:7.2f} ms/step "
                    f"({r['wall_ms_per_step']:.2f}; "
                    f"mechanics {r['mechanics_ms_per_step']:.2f}), {r['newton_per_step']:.2f} "
                    "Newton/step, "
                    f"{r['realtime_factor_cpu']:.2f} x real time {r['steps']} steps "
                    f"({r.get('rejected', 0)} "
                    "rejected) "
                    f"({r['realtime_factor_wall']:.2f}); centroid {r['centroid'][0]:.9f} "
                    f"{r['centroid'][1]:.9f} "
                    "mm, "
                    f"speed {r['speed']:.9f} mm/s",
                    flush=True,
                )
                table.append(
                    {
                        "problem": f"rolling ribbon {n} nodes",
                        "code": label,
                        "ms_per_step": r["cpu_ms_per_step"],
                        "mechanics_ms_per_step": r["mechanics_ms_per_step"],
                        "wall_ms_per_step": r["wall_ms_per_step"],
                        "newton_per_step": r["newton_per_step"],
                        "realtime_factor": r["realtime_factor_cpu"],
                        "steps": r["steps"],
                        "rejected": r.get("rejected", 0),
                    }
                )
            if "baseline" in runs and "now" in runs:
                ratio = runs["baseline"]["cpu_ms_per_step"] / runs["now"]["cpu_ms_per_step"]
                print(f"  {n:4d} nodes speed-up: {ratio:.2f} x")
    if not args.skip_peers:
        print(
            "peers (wall seconds, one core; error: relative tip error as defined in the docstring):"
        )
        rows = peers(Cantilever())
        print(
            f"  {'problem':44s} {'ours [s]':>9s} {'err':>8s} {'peer [s]':>9s} {'err':>8s} "
            f"{'peer/ours':>9s}"
        )
        for r in rows:
            nan = float("nan")
            print(
                f"  {r['problem']:44s} {r['ours_s']:9.3f} {r['ours_error']:8.1e} "
                f"{r.get('peer_s', nan):9.3f} "
                f"{r.get('peer_error', nan):8.1e} {r['speed_ratio']:9.2f}   {r['ours']}; "
                f"{r.get('note', '')}"
            )
            table.append(
                {
                    "problem": r["problem"],
                    "code": "ours vs " + r["peer"],
                    "ours_s": r["ours_s"],
                    "peer_s": r.get("peer_s"),
                    "speed_ratio": r["speed_ratio"],
                    "ours_error": r["ours_error"],
                    "peer_error": r.get("peer_error"),
                }
            )
    if args.csv and table:
        keys = sorted({k for row in table for k in row})
        tmp = args.csv + ".part"
        with open(tmp, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(table)
        os.replace(tmp, args.csv)
        print(f"written {args.csv}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
