"""Wall time per simulated second of the rolling twisted ribbon (DER, contact, friction, heat) at
50, 100 and 200 nodes, on one core.

    OMP_NUM_THREADS=1 python benchmarks/ribbon_benchmark.py [--duration 10]
        [--nodes 50 100 200] [--ground-temperature 100] [--dt 0.01] [--cells-thickness 4]
        [--contact-spacing 0.25] [--warmup 0] [--profile] [--evaluations STEPS]
        [--compare NAME=VALUE[,NAME=VALUE] ...] [--rounds 3]

Each run settles the ribbon (not timed), optionally runs ``--warmup`` simulated seconds on the plate
(not timed: the ribbon heats and starts rolling), and then times ``duration`` simulated seconds on
the hot plate; it prints wall and CPU seconds (``time.process_time``, the figure to quote on a
shared machine) per simulated second, the real-time factor (simulated seconds per CPU second, > 1:
faster than real time), Newton iterations per step, step cuts and the number of dofs. ``--profile``
adds the CPU split of the timed steps into mechanics (the implicit step: assembly, factorisation,
contact) and heat (section heat step and natural shape), the finer split of a step (the compiled
Newton loop, the Python around it, the friction lag, the natural shape, the heat step with its
geometry), a cProfile listing of the hottest functions, and, with ``--evaluations STEPS``, the
potential evaluations per step (with Hessian, gradient only, energy only, and the Hessian
factorisations) counted over STEPS more steps on the Python reference Newton loop
(``StepOptions(compiled=False)``: the same iterates to round-off) and the CPU time of one evaluation
of each kind on the final state (the compiled kernels show as one call in cProfile).

``--compare NAME=VALUE[,NAME=VALUE] ...`` times solver settings from one state: after the warm-up
each setting (``RibbonSimulation.SOLVER_FIELDS`` of ``RibbonNumerics``, e.g.
``elastic_hessian_at_source=true``, ``heat_dt=0.01``, ``lag_tol=1``) runs the same timed window from
a copy of the warmed simulation, alternating with the unchanged solver for ``--rounds`` rounds (the
machine's load moves single runs by +-15 %); it prints the best and median CPU ms per step, Newton
iterations per step, the speed over the window and how far the final centroid lies from the
unchanged solver's. Not a test: figures for the report.
"""

from __future__ import annotations

import argparse
import collections
import copy
import cProfile
import dataclasses
import io
import os
import platform
import pstats
import sys
import time

import numpy as np

from lcefem.models.errors import InputError
from lcefem.solvers.der import compiled_newton, integrator, newton, ribbon
from lcefem.solvers.der.assembly import friction_lag
from lcefem.solvers.der.model import n_dofs
from lcefem.solvers.der.ribbon import ROLLING_RIBBON, RibbonNumerics, RibbonSetup, RibbonSimulation


def warmed(
    nodes: int,
    ground_temperature: float,
    dt: float,
    cells_thickness: int | None = None,
    contact_spacing: float | None = None,
    warmup: float = 0.0,
    perturbation: float | None = None,
) -> tuple[RibbonSimulation, float]:
    """The ribbon settled and ``warmup`` [s] on the plate, and the wall seconds that took."""
    changes = {"nodes": nodes, "dt": dt}
    if perturbation is not None:
        changes["perturbation"] = perturbation
    if cells_thickness is not None:
        changes["cells_thickness"] = cells_thickness
    if contact_spacing is not None:
        changes["contact_spacing"] = contact_spacing
    setup = RibbonSetup(
        geometry=ROLLING_RIBBON,
        ground_temperature=ground_temperature,
        numerics=dataclasses.replace(RibbonNumerics(), **changes),
    )
    t0 = time.perf_counter()
    sim = RibbonSimulation(setup)
    for _ in range(int(round(warmup / dt))):
        sim.step(dt)
    return sim, time.perf_counter() - t0


def benchmark(
    nodes: int,
    duration: float,
    ground_temperature: float,
    dt: float,
    cells_thickness: int | None = None,
    contact_spacing: float | None = None,
    warmup: float = 0.0,
    profile: bool = False,
    perturbation: float | None = None,
    evaluations: int = 0,
) -> dict:
    sim, build = warmed(
        nodes, ground_temperature, dt, cells_thickness, contact_spacing, warmup, perturbation
    )
    its0, cuts0 = sim.integrator.total_iterations, sim.integrator.total_cuts
    steps = int(round(duration / dt))
    x0 = sim.state.x.mean(axis=0)
    phases = collections.Counter(mechanics=0.0, heat=0.0)
    if profile:
        _split_phases(sim, phases)
    t0, c0 = time.perf_counter(), time.process_time()
    for _ in range(steps):
        sim.step(dt)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    x_end = sim.state.x.copy()
    x1 = x_end.mean(axis=0)
    its = sim.integrator.total_iterations - its0
    cuts = sim.integrator.total_cuts - cuts0
    listing = ""
    if profile:
        _unwrap(sim)
        # cProfile over a second window of the same length: inside the timed one it would inflate
        # the split
        prof = cProfile.Profile()
        prof.enable()
        for _ in range(steps):
            sim.step(dt)
        prof.disable()
        out = io.StringIO()
        pstats.Stats(prof, stream=out).sort_stats("tottime").print_stats(18)
        listing = out.getvalue()
    counts = count_evaluations(sim, evaluations) if evaluations else {}
    return {
        "evaluations": counts,
        "nodes": nodes,
        "dofs": n_dofs(nodes),
        "steps": steps,
        "wall [s]": wall,
        "cpu [s]": cpu,
        "wall per simulated second": wall / duration,
        "real-time factor": duration / cpu,
        "build+settle [s]": build,
        "newton per step": its / steps,
        "cuts": cuts,
        "speed [mm/s]": float(np.hypot(*(x1 - x0)[:2]) / duration),
        "contact samples": sim.rod.contact_samples,
        "phases": phases,
        "profile": listing,
        "x": x_end,
    }


#: (owner, attribute, phase) of the functions whose CPU seconds ``--profile`` adds up; the owner is
#: a module, a class, or "integrator" / "heat" for the simulation's own objects
_PIECES = (
    ("integrator", "trial", "mechanics"),
    (compiled_newton, "minimise_step", "compiled Newton loop"),
    (integrator, "friction_lag", "friction lag"),
    ("heat", "step", "heat step"),
    (RibbonSimulation, "heat_geometry", "heat geometry (corner gaps)"),
    (ribbon.ProgrammedShape, "rest_shape", "natural shape"),
)
_WRAPPED: list = []


def _split_phases(sim: RibbonSimulation, phases: collections.Counter) -> None:
    """Wrap the pieces of a step (``_PIECES``) to add their CPU seconds to ``phases`` ("heat": the
    heat step and the natural shape, the rest of a step besides "mechanics")."""
    for owner, name, phase in _PIECES:
        obj = (
            {"integrator": sim.integrator, "heat": sim.heat}.get(owner, owner)
            if isinstance(owner, str)
            else owner
        )
        function = getattr(obj, name)

        def timed(*a, _f=function, _phase=phase, **k):
            c = time.process_time()
            try:
                return _f(*a, **k)
            finally:
                spent = time.process_time() - c
                phases[_phase] += spent
                if _phase in ("heat step", "natural shape"):
                    phases["heat"] += spent

        _WRAPPED.append((obj, name, function, isinstance(owner, str)))
        setattr(obj, name, timed)


def _unwrap(sim: RibbonSimulation) -> None:
    """Undo :func:`_split_phases` (the instance wrappers go, the module and class functions are
    restored)."""
    while _WRAPPED:
        obj, name, function, instance = _WRAPPED.pop()
        if instance:
            delattr(obj, name)
        else:
            setattr(obj, name, function)


def count_evaluations(sim: RibbonSimulation, steps: int) -> dict:
    """Potential evaluations per step over ``steps`` more steps on the Python reference Newton loop
    (the compiled loop's iterates to round-off, ``tests/solvers/test_der_compiled_newton.py``): with
    Hessian, gradient only, energy only, and Hessian factorisations; then the CPU microseconds of
    one evaluation of each kind on the final state (the compiled kernels of
    ``compiled_newton._evaluate``)."""
    counts = collections.Counter()
    evaluate, factorise = integrator.StepPotential.evaluate, newton.factorise_banded_spd
    kinds = {2: "Hessian", 1: "gradient", 0: "energy"}

    def counted(self, state, order):
        counts[kinds[order]] += 1
        return evaluate(self, state, order)

    def counted_factorise(*a, **k):
        counts["factorisations"] += 1
        return factorise(*a, **k)

    options = sim.integrator.options
    sim.integrator.options = dataclasses.replace(options, compiled=False)
    integrator.StepPotential.evaluate, newton.factorise_banded_spd = counted, counted_factorise
    try:
        for _ in range(steps):
            sim.step(sim.setup.numerics.dt)
    finally:
        integrator.StepPotential.evaluate, newton.factorise_banded_spd = evaluate, factorise
        sim.integrator.options = options
    out = {k: counts[k] / steps for k in ("Hessian", "gradient", "energy", "factorisations")}
    out.update({f"{v} evaluation [us]": t for v, t in zip(kinds.values(), _evaluation_times(sim))})
    return out


def _evaluation_times(sim: RibbonSimulation, repeats: int = 200) -> list[float]:
    """CPU microseconds of one compiled evaluation with Hessian, gradient and energy of the step
    potential at an iterate moved 1e-4 mm (rad) from the state (with the source change, as Newton's
    iterates)."""
    rod, st, h = sim.rod, sim.state, sim.setup.numerics.dt
    sampling = sim.integrator.sampling
    potential = integrator.StepPotential(
        rod, st, h, sim.integrator.assembly, sampling, friction_lag(rod, st, sampling)
    )
    rest, sec = rod.rest, rod.section
    c = np.ascontiguousarray
    inertia = (
        potential.mass,
        potential.q_n,
        potential.q_star,
        potential.load,
        potential.diag,
        float(h),
        float(rod.damping),
    )
    rest_arrays = (
        c(rest.edge_length, float),
        c(rest.curvature, float),
        c(rest.twist, float),
        c(rest.voronoi_length, float),
        float(sec.EA),
        float(sec.EI1),
        float(sec.EI2),
        float(sec.GJ),
    )
    n_edges = rod.n_nodes - 1
    arrays = sampling.kernel_arrays() + (
        sampling.end_edges(n_edges),
        sampling.end_sigma_rows(n_edges),
        sampling.end_offsets_array(),
    )
    contact = potential._contact_arrays()
    source = compiled_newton._own_geometry(
        c(st.x, float), c(st.theta, float), c(st.a1, float), c(st.ref_twist, float)
    )
    nd = n_dofs(rod.n_nodes)
    moved = compiled_newton._moved(source, 1e-4 * np.sin(np.arange(nd)))
    empty = (np.zeros((1, 3)), np.zeros((1, 3, 3)), np.zeros((1, 1)))
    out = []
    for order in (2, 1, 0):

        def once():
            compiled_newton._evaluate(
                moved,
                False,
                source[6],
                inertia,
                rest_arrays,
                arrays,
                contact,
                np.int64(order),
                *empty,
                False,
                np.zeros((11, nd)),
            )

        once()
        c0 = time.process_time()
        for _ in range(repeats):
            once()
        out.append((time.process_time() - c0) / repeats * 1e6)
    return out


def parse_settings(text: str) -> dict:
    """``NAME=VALUE[,NAME=VALUE]`` of ``RibbonSimulation.SOLVER_FIELDS`` -> {name: value} (typed as
    the field's default); an unknown name or a bad value raises InputError naming it."""
    defaults = RibbonNumerics()
    out = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or name not in RibbonSimulation.SOLVER_FIELDS:
            raise InputError(
                f"--compare {item!r}: expected NAME=VALUE with NAME one of "
                f"{', '.join(RibbonSimulation.SOLVER_FIELDS)}"
            )
        kind = type(getattr(defaults, name))
        try:
            if kind is bool:
                if value.strip().lower() not in ("true", "false"):
                    raise ValueError(value)
                out[name] = value.strip().lower() == "true"
            else:
                out[name] = kind(value)
        except ValueError:
            raise InputError(f"--compare {name}={value!r}: expected a {kind.__name__}") from None
    return out


def compare(
    sim: RibbonSimulation, settings: list[dict], duration: float, rounds: int
) -> list[dict]:
    """Each of ``settings`` (and the unchanged solver first) timed over ``duration`` [s] from a copy
    of ``sim``, alternately for ``rounds`` rounds: CPU ms per step (best, median), Newton iterations
    per step, speed [mm/s] over the window, final centroid [mm] and its distance from the unchanged
    solver's [mm]."""
    dt = sim.setup.numerics.dt
    steps = int(round(duration / dt))
    runs = [{"setting": "unchanged", "changes": {}}] + [
        {"setting": ",".join(f"{k}={v}" for k, v in s.items()), "changes": s} for s in settings
    ]
    for run in runs:
        run["ms"] = []
    for _ in range(rounds):
        for run in runs:
            copy_ = copy.deepcopy(sim)
            copy_.change_solver(**run["changes"])
            its0 = copy_.integrator.total_iterations
            x0 = copy_.state.x.mean(axis=0)
            c0 = time.process_time()
            for _ in range(steps):
                copy_.step(dt)
            run["ms"].append((time.process_time() - c0) / steps * 1e3)
            run["newton per step"] = (copy_.integrator.total_iterations - its0) / steps
            run["centroid"] = copy_.state.x.mean(axis=0)
            run["speed [mm/s]"] = float(np.hypot(*(run["centroid"] - x0)[:2]) / duration)
    for run in runs:
        run["apart [mm]"] = float(np.linalg.norm(run["centroid"] - runs[0]["centroid"]))
    return runs


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, nargs="+", default=[50, 100, 200])
    parser.add_argument("--duration", type=float, default=10.0, help="timed simulated time [s]")
    parser.add_argument(
        "--ground-temperature", type=float, default=100.0, help="plate temperature [C]"
    )
    parser.add_argument("--dt", type=float, default=0.01, help="time step [s]")
    parser.add_argument(
        "--cells-thickness",
        type=int,
        default=None,
        help="RibbonNumerics.cells_thickness (default: RibbonNumerics' own)",
    )
    parser.add_argument(
        "--contact-spacing",
        type=float,
        default=None,
        help="[mm] RibbonNumerics.contact_spacing (default: RibbonNumerics' own)",
    )
    parser.add_argument(
        "--perturbation",
        type=float,
        default=None,
        help="[rad/s] RibbonNumerics.perturbation, the initial spin (1.0 starts the 100 C, "
        "95-107-node "
        "ribbon on its rolling branch, docs/ribbon.md)",
    )
    parser.add_argument(
        "--warmup", type=float, default=0.0, help="untimed simulated time on the plate first [s]"
    )
    parser.add_argument(
        "--profile", action="store_true", help="CPU split mechanics / heat and a cProfile listing"
    )
    parser.add_argument(
        "--positions", help="write the final node positions of each size to <this>_<nodes>.npy"
    )
    parser.add_argument(
        "--evaluations",
        type=int,
        default=0,
        metavar="STEPS",
        help="count potential evaluations per step over STEPS more steps (Python reference loop)",
    )
    parser.add_argument(
        "--compare",
        nargs="+",
        default=[],
        metavar="NAME=VALUE[,NAME=VALUE]",
        help="solver settings timed from one warmed state against the unchanged solver "
        f"(names: {', '.join(RibbonSimulation.SOLVER_FIELDS)})",
    )
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds of --compare")
    args = parser.parse_args(argv)
    try:
        settings = [parse_settings(text) for text in args.compare]
        if args.rounds < 1:
            raise InputError(f"--rounds {args.rounds}: must be >= 1")
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    numerics = RibbonNumerics()  # the defaults, printed for the options not given
    print(
        f"ribbon benchmark: {platform.processor() or platform.machine()}, python "
        f"{platform.python_version()}, "
        f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}, plate "
        f"{args.ground_temperature:g} "
        "C, "
        f"dt {args.dt:g} s, cells_thickness "
        f"{args.cells_thickness or RibbonNumerics().cells_thickness}, "
        "contact_spacing "
        f"{numerics.contact_spacing if args.contact_spacing is None else args.contact_spacing:g}"
        " mm, "
        "initial spin "
        f"{args.perturbation if args.perturbation is not None else numerics.perturbation:g}"
        " rad/s, "
        f"warm-up {args.warmup:g} s, {args.duration:g} s timed per size"
    )
    for n in args.nodes:
        if settings:
            sim, _ = warmed(
                n,
                args.ground_temperature,
                args.dt,
                args.cells_thickness,
                args.contact_spacing,
                args.warmup,
                args.perturbation,
            )
            print(
                f"  {n} nodes, {args.rounds} rounds from one state: CPU ms/step best / median, "
                "real-time "
                "factor "
                "from the best, Newton/step, speed over the window, final centroid apart from the "
                "unchanged solver's"
            )
            for run in compare(sim, settings, args.duration, args.rounds):
                print(
                    f"    {run['setting']:40s} {min(run['ms']):.3f} / "
                    f"{float(np.median(run['ms'])):.3f} "
                    "ms, "
                    f"{args.dt * 1e3 / min(run['ms']):.2f} x, {run['newton per step']:.3f} "
                    "Newton/step, "
                    f"{run['speed [mm/s]']:.4f} mm/s, {run['apart [mm]']:.2e} mm",
                    flush=True,
                )
            continue
        r = benchmark(
            n,
            args.duration,
            args.ground_temperature,
            args.dt,
            args.cells_thickness,
            args.contact_spacing,
            args.warmup,
            args.profile,
            args.perturbation,
            args.evaluations,
        )
        print(
            f"  {r['nodes']:4d} nodes ({r['dofs']} dofs, {r['contact samples']} contact sections "
            "per "
            "edge): "
            f"real-time factor {r['real-time factor']:.2f} (simulated s per CPU s; "
            f"{r['cpu [s]']:.1f} s "
            "CPU, "
            f"{r['wall [s]']:.1f} s wall for {r['steps']} steps), {r['newton per step']:.2f} "
            "Newton "
            "iterations "
            f"per step, {r['cuts']} step cuts, speed {r['speed [mm/s]']:.6f} mm/s; build + settle "
            "+ "
            "warm-up "
            f"{r['build+settle [s]']:.1f} s",
            flush=True,
        )
        if args.profile:
            ph = r["phases"]
            print(
                f"    CPU split: mechanics {ph['mechanics']:.2f} s, heat {ph['heat']:.2f} s, other "
                f"{r['cpu [s]'] - ph['mechanics'] - ph['heat']:.2f} s (the timed window; then "
                "cProfile over the next "
                "one)"
            )
            print(
                "    per step [ms]: "
                + ", ".join(
                    f"{k} {v / r['steps'] * 1e3:.3f}" for k, v in ph.items() if k not in ("heat",)
                )
            )
            print(r["profile"])
        if r["evaluations"]:
            print("    per step: " + ", ".join(f"{k} {v:.2f}" for k, v in r["evaluations"].items()))
        if args.positions:
            np.save(f"{args.positions}_{n}.npy", r["x"])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
