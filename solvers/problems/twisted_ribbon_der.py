"""The twisted LCE ribbon on a hot plate, as a discrete elastic rod with contact, friction and heat
(seed 000): the configuration sections (:class:`RibbonConfig`) and one run (:func:`run_ribbon`, used
by ``lcefem run ribbon`` and the ribbon cases) of the rod problem
:class:`lcefem.solvers.der.ribbon.RibbonSimulation`. (The same ribbon as a static 3D FE body is
:mod:`lcefem.solvers.problems.twisted_ribbon`.)

The ribbon (director along it, stretched then twisted to the twist density, as-built at 25 C)
is laid on a plate at the ground temperature. Heat enters by contact and through the warm air
over the plate; the heated side contracts (LCE spontaneous stretch of lcefem.models.lce), which
bends and untwists the ribbon, and it may roll. Units: mm, s, N, C; the twist density is given in
turns/mm (the paper's "number of twists per unit length").

In --out DIR: centerline.pvd / centerline_steps/*.vtp (polyline: twist density, curvatures,
temperature, contact force, width direction), surface.pvd / surface_steps/*.vtp (the ribbon as
quads, temperature on each edge line), centroid.csv, history.csv, summary.json (resolved
configuration and metrics;
:func:`lcefem.solvers.analysis.rolling.rolling_metrics`), and what the ``report`` hook adds
(``lcefem run ribbon``: trajectory.png). Files keep a .part suffix until the run completes; a failed
run leaves *.partial.* files, failure.json and last_converged_state.json (node positions and edge
angles).
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.models.contact import Block
from lcefem.models.errors import InputError
from lcefem.models.lce import MeasuredContraction, NematicTransition
from lcefem.models.limits import DECOMPOSITION_TEMPERATURE, check_between
from lcefem.models.parameters import param
from lcefem.models.ribbon import SEED000_RIBBON, RibbonGeometry, RibbonLCE
from lcefem.solvers import cost
from lcefem.solvers.analysis.rolling import rolling_metrics
from lcefem.solvers.contraction_curve import LCECurve, law_summary
from lcefem.solvers.der.output import PolylineSeries, polydata
from lcefem.solvers.der.ribbon import HISTORY_COLUMNS, RibbonSections, RibbonSetup, RibbonSimulation
from lcefem.solvers.problems.protocol import StepRecord
from lcefem.solvers.runner import HistoryExport, PathProblem, StateExport, StateHistory, run
from lcefem.solvers.runtime.checks import check_config, resolved
from lcefem.solvers.runtime.files import CSVTable, write_json
from lcefem.solvers.runtime.run import Progress
from lcefem.solvers.runtime.signals import deferred_signals

CENTROID_COLUMNS = ["time [s]", "x [mm]", "y [mm]", "z [mm]"]


@dataclass(frozen=True)
class RibbonRun:
    """What the experimenter sets."""

    ground_temperature: float = param(
        100.0,
        "C",
        "chosen: seed 000 / press release: the real ribbons roll on "
        "surfaces of at least ~55 C; the model's threshold is 80-100 C (issue 32, "
        "ribbon_threshold: the seed-000 ribbon LCE does not roll at 80 C, rolls at 100 C; "
        "a registered known disagreement), so the default run uses 100 C, where the model "
        "rolls",
        minimum=-50.0,
        maximum=DECOMPOSITION_TEMPERATURE,
    )
    duration: float = param(60.0, "s", "chosen: heated time after settling", positive=True)
    output_interval: float = param(
        0.5, "s", "chosen: time between field frames (0: no fields)", minimum=0.0
    )
    record_interval: float = param(0.05, "s", "chosen: time between history rows", positive=True)


@dataclass(frozen=True)
class RibbonConfig(RibbonSections):
    """The case file's sections: the physical ones defined once in
    :class:`lcefem.solvers.der.ribbon.RibbonSections` (geometry, numerics, thermal, air,
    ground_heat, contact, friction), plus the run, the material and an obstacle."""

    run: RibbonRun = field(default_factory=RibbonRun)
    material: RibbonLCE = SEED000_RIBBON
    obstacle: Block = field(default_factory=Block)  # a block on the plate (width 0: none)

    #: The case file's sections in their documented order (summary.json's config, --help).
    SECTIONS = (
        "run",
        "geometry",
        "numerics",
        "material",
        "thermal",
        "air",
        "ground_heat",
        "contact",
        "friction",
        "obstacle",
    )

    def law(self) -> NematicTransition | MeasuredContraction:
        """The ribbon's contraction law: the material's sigmoid, or the measured curve of
        ``material.curve``."""
        return LCECurve(self.material.curve).law(self.material.transition())

    def validated(self) -> "RibbonConfig":
        check_config(self)
        self.law()  # a bad curve file is an InputError before the run
        ob = self.obstacle
        ob.block_temperature(
            self.run.ground_temperature, self.air.ambient_temperature
        )  # obstacle.heat is one of Block.HEAT
        if ob.present:
            for name in ("width", "depth", "height"):
                if getattr(ob, name) <= 2.0 * ob.edge_radius:
                    raise InputError(
                        f"obstacle.{name} = {getattr(ob, name)} mm: must exceed twice "
                        f"obstacle.edge_radius = {ob.edge_radius} mm"
                    )
        if self.numerics.method not in ("euler", "midpoint"):
            raise InputError(f"numerics.method = {self.numerics.method!r}: allowed euler, midpoint")
        if self.numerics.dt > self.run.duration:
            raise InputError(
                f"numerics.dt = {self.numerics.dt} s: must be <= run.duration = "
                f"{self.run.duration} "
                "s"
            )
        if self.numerics.contact_samples > 1 and self.numerics.contact_samples % 2:
            raise InputError(
                f"numerics.contact_samples = {self.numerics.contact_samples}: must be 1 or even"
            )
        if self.geometry.is_helical and self.geometry.twist_density not in (
            0.0,
            RibbonGeometry().twist_density,
        ):
            # initial_ribbon_state winds a helix untwisted: a twist density would be reported, not
            # used
            raise InputError(
                f"geometry.twist_density = {self.geometry.twist_density} turns/mm: a helical "
                f"ribbon (geometry.helix_radius = {self.geometry.helix_radius} mm) is untwisted; "
                "give one of the two"
            )
        edge = self.geometry.length / (self.numerics.nodes - 1)
        if (
            self.geometry.twist_density * edge > 0.5
        ):  # beyond half a turn per edge the frames alias (Nyquist)
            raise InputError(
                f"geometry.twist_density = {self.geometry.twist_density} turns/mm: more than "
                f"half a turn per rod edge ({edge:.3g} mm at numerics.nodes = "
                f"{self.numerics.nodes}); at most {0.5 / edge:.3g} turns/mm, or more nodes"
            )
        self.estimate().check()
        rows = summary_rows(self.run.duration, self.numerics.dt, self.run.record_interval)
        if rows < MIN_SUMMARY_ROWS:
            # the summary's rolling metrics fit slopes over the run's last half: refused before the
            # run rather than after it (issue 45)
            spacing = record_spacing(self.run.duration, self.numerics.dt, self.run.record_interval)
            raise InputError(
                f"run.duration = {self.run.duration:g} s: the summary's rolling metrics need "
                f"{MIN_SUMMARY_ROWS} history rows in the run's last half ({rows} at a row every "
                f"{spacing:.3g} s, run.record_interval and numerics.dt); give at least "
                f"{(2 * MIN_SUMMARY_ROWS - 1) * spacing:.3g} s or a shorter run.record_interval"
            )
        return self

    def estimate(self) -> cost.Estimate:
        """Nodes, steps and memory of this run (lcefem.solvers.cost)."""
        n = self.numerics.nodes
        est = cost.Estimate().count("nodes", n)
        est.memory(f"numerics.nodes = {n}", f"{n} rod nodes", n * cost.ROD_NODE_MEMORY)
        return cost.time_steps(
            f"numerics.dt = {self.numerics.dt} s (run.duration = {self.run.duration} s)",
            self.run.duration,
            self.numerics.dt,
            est,
        )

    def resolved(self) -> dict:
        out = resolved(self)
        out["material"].update(law_summary(self.law()))
        return {name: out[name] for name in self.SECTIONS}

    def setup(self) -> RibbonSetup:
        """The simulation's setup: the same sections, the plate temperature, the material's laws and
        the obstacle."""
        sections = {f.name: getattr(self, f.name) for f in dataclasses.fields(RibbonSections)}
        return RibbonSetup(
            **sections,
            ground_temperature=self.run.ground_temperature,
            transition=self.law(),
            elasticity=self.material.elasticity(),
            blocks=(self.obstacle,) if self.obstacle.present else (),
        )


#: History rows the rolling summary needs in the analysis window (the run's last half): the end spin
#: rates are least-squares slopes (lcefem.solvers.analysis.rolling.rolling_metrics).
MIN_SUMMARY_ROWS = 3


def _record_steps(duration: float, dt: float, record_interval: float) -> tuple[int, float, int]:
    """(steps, step [s], steps per history row) as :func:`run_ribbon` takes them."""
    n_steps = max(1, int(math.ceil(duration / dt - 1e-9)))
    h = duration / n_steps
    return n_steps, h, max(1, int(round(record_interval / h)))


def record_spacing(duration: float, dt: float, record_interval: float) -> float:
    """Time between history rows [s] of a run (a whole number of steps)."""
    _, h, every = _record_steps(duration, dt, record_interval)
    return every * h


def summary_rows(duration: float, dt: float, record_interval: float) -> int:
    """History rows of a run inside the summary's analysis window, the last half of the run
    (:func:`lcefem.solvers.analysis.rolling.window`): the row at t = 0, one every record step, the
    last step's. A run of at least (2 MIN_SUMMARY_ROWS - 1) row spacings has enough."""
    n_steps, h, every = _record_steps(duration, dt, record_interval)
    times = np.array([0.0, *(k * h for k in range(every, n_steps, every)), n_steps * h])
    # a row at the window's edge counts only when it lies clearly inside (the run's time is a sum of
    # steps: its round-off decides the edge)
    return int(np.count_nonzero(times > 0.5 * times[-1] * (1.0 + 1e-9)))


def _node_average(edge_values: np.ndarray) -> np.ndarray:
    out = np.empty((len(edge_values) + 1,) + edge_values.shape[1:])
    out[1:-1] = 0.5 * (edge_values[:-1] + edge_values[1:])
    out[0], out[-1] = edge_values[0], edge_values[-1]
    return out


def _interior_to_nodes(values: np.ndarray) -> np.ndarray:
    out = np.empty((len(values) + 2,) + values.shape[1:])
    out[1:-1] = values
    out[0], out[-1] = values[0], values[-1]
    return out


def centerline_fields(sim: RibbonSimulation) -> dict[str, np.ndarray]:
    """Point data of the centreline: twist density [rad/mm], curvatures towards m1, m2 and magnitude
    [1/mm], mean section temperature [C], contact force [N] (vector), width direction m1."""
    from lcefem.models.rod import material_curvatures

    st = sim.state
    geo = st.geometry()
    vor = 0.5 * (geo.length[:-1] + geo.length[1:])
    kappa = (
        material_curvatures(geo.e[:-1], geo.e[1:], geo.m1[:-1], geo.m2[:-1], geo.m1[1:], geo.m2[1:])
        / vor[:, None]
    )
    k_nodes = _interior_to_nodes(kappa)
    return {
        "twist_density [rad/mm]": _interior_to_nodes(geo.twist / vor),
        "curvature_m1 [1/mm]": k_nodes[:, 0],
        "curvature_m2 [1/mm]": k_nodes[:, 1],
        "curvature [1/mm]": np.linalg.norm(k_nodes, axis=1),
        "temperature [C]": sim.node_temperatures(),
        "contact_force [N]": sim.contact_forces(),
        "width_direction [-]": _node_average(geo.m1),
    }


def surface_polydata(sim: RibbonSimulation):
    """The ribbon as a strip of quads between its two edge lines (x +- w/2 m1 at the nodes), with
    the temperature of the cells along each edge line."""
    st = sim.state
    geo = st.geometry()
    m1 = _node_average(geo.m1)
    m1 /= np.linalg.norm(m1, axis=1, keepdims=True)
    hw = 0.5 * sim.setup.geometry.width
    n = len(st.x)
    pts = np.concatenate([st.x - hw * m1, st.x + hw * m1])
    nt = sim.grid.n_thickness
    T_left = sim.T[:, :nt].mean(1)
    T_right = sim.T[:, -nt:].mean(1)
    temp = np.concatenate([_node_average(T_left), _node_average(T_right)])
    quads = np.stack(
        [np.arange(n - 1), np.arange(1, n), n + np.arange(1, n), n + np.arange(n - 1)], 1
    )
    return polydata(pts, quads=quads, point_data={"temperature [C]": temp})


# -- the run ----------------------------------------------------------------------------------
@dataclass
class RibbonResult:
    history: dict[str, np.ndarray]
    metrics: dict
    summary: dict
    out: pathlib.Path | None
    simulation: RibbonSimulation


@dataclass(frozen=True)
class RibbonStep:
    """What the ribbon's run shows its exports after a step: the step (of dt), the step of the
    previous call, and the observed row when one is due (else None)."""

    step: int
    previous: int
    row: dict | None


class RibbonFrames:
    """Export object: the centreline and surface VTK series (``centerline.pvd``, ``surface.pvd``), a
    frame when a multiple of ``every`` steps (of dt) lies in (previous, step], and at the last step
    ``last``."""

    def __init__(self, sim: "RibbonSimulation", every: int, last: int):
        self.sim, self.every, self.last = sim, every, last

    def open(self, run, out: pathlib.Path) -> "RibbonFrames":
        self.series = [
            run.output(PolylineSeries(out, "centerline")),
            run.output(PolylineSeries(out, "surface")),
        ]
        return self

    def write(self, state: RibbonStep) -> None:
        if state.step // self.every > state.previous // self.every or state.step == self.last:
            sim = self.sim
            n = len(sim.state.x)
            t = sim.state.time
            self.series[0].write(
                t, polydata(sim.state.x, lines=[np.arange(n)], point_data=centerline_fields(sim))
            )
            self.series[1].write(t, surface_polydata(sim))

    def last_converged(self, folder, state) -> None:
        pass  # the series are kept as *.partial.* up to the last frame


class CentroidTable:
    """Export object: centroid.csv, the centroid [mm] of every history row."""

    def open(self, run, out) -> "CentroidTable":
        self.table = run.output(
            CSVTable(None if out is None else out / "centroid.csv", CENTROID_COLUMNS)
        )
        return self

    def write(self, state: RibbonStep) -> None:
        row = state.row
        if row is not None:
            self.table.append(
                {
                    "time [s]": row["time [s]"],
                    "x [mm]": row["centroid_x [mm]"],
                    "y [mm]": row["centroid_y [mm]"],
                    "z [mm]": row["centroid_z [mm]"],
                }
            )

    def last_converged(self, folder, state) -> None:
        pass


@dataclass(frozen=True)
class LastConvergedState:
    """Export object: when a step fails, ``last_converged_state.json`` of the integrator's last
    converged state (the last of ``saved``, filled by the simulation's on_failure)."""

    saved: list

    def open(self, run, out) -> "LastConvergedState":
        return self

    def write(self, state) -> None:
        pass

    def last_converged(self, folder, state) -> None:
        s = self.saved[-1]
        write_json(
            folder / "last_converged_state.json",
            {"time [s]": float(s.time), "x [mm]": s.x, "theta [rad]": s.theta},
        )


def run_ribbon(
    config: RibbonConfig,
    out: pathlib.Path | None = None,
    progress: bool = True,
    fields: bool = True,
    label: str = "ribbon",
    report=None,
) -> RibbonResult:
    """Build and run one rolling-ribbon simulation (see module docstring); ``out`` None writes
    nothing. ``report(out, config, history)`` (optional: the validation's figures) runs, when
    ``out`` is given, before the summary is written."""
    config = config.validated()
    out = None if out is None else pathlib.Path(out)
    started = time.perf_counter()
    saved = []  # the integrator's last converged state when a step fails
    sim = RibbonSimulation(config.setup(), on_failure=lambda state: saved.append(state.copy()))
    run_cfg = config.run
    dt = config.numerics.dt
    n_steps = max(1, int(math.ceil(run_cfg.duration / dt - 1e-9)))
    dt = run_cfg.duration / n_steps
    rec_every = max(1, int(round(run_cfg.record_interval / dt)))
    out_every = (
        max(1, int(round(run_cfg.output_interval / dt))) if run_cfg.output_interval > 0 else 0
    )
    bar = Progress(
        run_cfg.duration, f"{label} {run_cfg.ground_temperature:g} C", "s", enabled=progress
    )

    def drive(on_step):
        """Fixed steps of dt (every step seen: frames every ``out_every`` steps, rows every
        ``rec_every``) or adaptive ones landing on the record times of fixed steps of dt (frames at
        the record that reaches or passes each frame time)."""
        on_step(RibbonStep(0, -1, sim.observe()))
        # A signal is honoured at the next record (a few ms of compiled steps), never inside numba.
        with deferred_signals():
            if sim.control is None:
                for step in range(1, n_steps + 1):
                    sim.step(dt)
                    due = step % rec_every == 0 or step == n_steps
                    on_step(RibbonStep(step, step - 1, sim.observe() if due else None))
            else:
                previous = 0
                for step in [*range(rec_every, n_steps, rec_every), n_steps]:
                    sim.advance(step * dt)
                    on_step(RibbonStep(step, previous, sim.observe()))
                    previous = step

    found = {}

    def summarize(run, _) -> dict:
        wall = time.perf_counter() - started
        found["hist"] = hist = run.history.as_arrays()
        found["metrics"] = metrics = rolling_metrics(hist)
        if out is not None and report is not None:
            report(out, config, hist)
        return {
            "metrics": metrics,
            "steps": sim.steps_taken,
            "dt [s]": dt,
            "nodes": config.numerics.nodes,
            "edge_length [mm]": config.geometry.length / (config.numerics.nodes - 1),
            "newton_iterations": sim.integrator.total_iterations,
            "step_cuts": sim.integrator.total_cuts,
            "rejected_steps": sim.rejected,
            "wall_time [s]": wall,
            "wall_time_per_simulated_second": wall / run_cfg.duration,
        }

    history = HistoryExport(
        tuple(HISTORY_COLUMNS),
        lambda s: s.row,
        when=lambda s: s.row is not None,
        where=lambda s: f"t = {s.row['time [s]']:.4g} s",
        at=lambda s: s.row["time [s]"],
        postfix=lambda s: f"y={s.row['centroid_y [mm]']:.2f}mm T={s.row['T_mean [C]']:.1f}C",
    )
    frames = (
        RibbonFrames(sim, out_every, n_steps) if out is not None and fields and out_every else None
    )
    problem = PathProblem(drive, end=run_cfg.duration, at=lambda s: s.step * dt)
    exports = [
        StateHistory(history),
        *(
            StateExport(e)
            for e in (frames, CentroidTable(), LastConvergedState(saved))
            if e is not None
        ),
    ]
    summary = run(
        problem,
        problem.program(),
        exports,
        out,
        config=config.resolved(),
        progress=bar,
        summarize=lambda skeleton, records: summarize(skeleton, records[-1].detail),
    )
    return RibbonResult(found["hist"], found["metrics"], summary, out, sim)


# -- the rolling ribbon as a problem (the Problem protocol) -------------------------------------
class RollingRibbonDER:
    """The rolling ribbon as a problem (lcefem.solvers.problems.protocol.Problem) around the rod
    simulation :class:`lcefem.solvers.der.ribbon.RibbonSimulation`: the drive is the plate's
    temperature [C] (tag ``plate``, read by every heat step from then on), :meth:`advance` moves
    the simulated time by ``dt`` [s] (fixed or adaptive steps, as :func:`run_ribbon`), the
    observables are the rod's history row, the fields its centreline's point data."""

    drive = "ground temperature [C]"

    def __init__(self, config: RibbonConfig = RibbonConfig()):
        self.config = config.validated()
        self.sim = RibbonSimulation(self.config.setup())

    def drive_tags(self) -> tuple[str, ...]:
        return ("plate",)

    def set_drives(self, drives) -> None:
        import dataclasses

        for tag, value in drives.items():
            if tag not in self.drive_tags():
                raise InputError(
                    f"drive {tag!r}: the ribbon's only drive is the plate (allowed plate)"
                )
            # the bounds of the case file's and the command line's run.ground_temperature (its
            # field's minimum; below decomposition, lcefem.models.limits.check_temperature)
            check_between(
                f"ground temperature[{tag}]",
                value,
                RibbonRun.__dataclass_fields__["ground_temperature"].metadata["minimum"],
                DECOMPOSITION_TEMPERATURE,
                "C",
                high_open=True,
                high_note="decomposition, lcefem.models.limits",
            )
            self.sim.setup = dataclasses.replace(self.sim.setup, ground_temperature=float(value))

    def advance(self, dt: float) -> StepRecord:
        """``dt`` [s] more of simulated time; returns its :class:`StepRecord`."""
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise InputError(f"dt = {dt} s: must be > 0")
        self.sim.advance(self.sim.time + float(dt))
        return StepRecord(float(self.sim.time), self.observables())

    def observables(self) -> dict[str, float]:
        return {
            **self.sim.observe(),
            "ground temperature [C]": float(self.sim.setup.ground_temperature),
        }

    def fields(self) -> dict:
        return {"node positions [mm]": self.sim.state.x, **centerline_fields(self.sim)}

    def save_state(self) -> bytes:
        """The whole simulation pickled (rod state, section temperatures, step control, clocks)."""
        import pickle

        return pickle.dumps(self.sim)

    def restore_state(self, state: bytes) -> None:
        import pickle

        self.sim = pickle.loads(state)
