"""Programmed shape sequences of the robotic surface (seed 001, Fig. 5A and 5C): channel currents
over time -> each strip's temperature (lumped transient heat balance) -> its free stretch lambda(T)
-> the bar-and-hinge surface, solved quasi-statically at each output time from the previous
equilibrium.

``lcefem run gridshell --schedule FILE.toml [--out DIR]`` (command line and figures:
lcefem.validation.studies.gridshell.gridshell_sequence, dispatched from
lcefem.validation.app.commands.gridshell). The schedule file::

    [schedule]
    times = [0.0, 20.0, 120.0]      # s: switch times, strictly increasing, the first 0
    end = 240.0                      # s: last output time (> the last switch time, <= MAX_DURATION)
    output_interval = 5.0            # s: one quasi-static solve and one frame per interval
    support = "rollers"              # clamp | rollers | table (one support for the whole sequence)
    thermal_model = "eq1"            # strip | segment | eq1 (see THERMAL_STRIPS)
    labels = ["actuate", "dome", "..."]   # optional: a name per switch time
    heat_step = 0.05                 # s: implicit-Euler step of the heat balance (optional)
    model_set = "published"          # optional: the bar-and-hinge model set the schedule was made
                                     # with (lcefem design writes it; checked by the command line)

    [currents]                       # A per selection (channel Tx/Ty/Bx/By, layer T/B,
    Tx = [0.1, 0.04, 0.0]            # family XD.., group XD1.., half plane, strip id), one
    Bx = [0.2, 0.07, 0.0]            # value per switch time, held until the next; unnamed
                                     # strips carry no current

    [layout]                         # optional: the gridshell's layout
    preset = "5x5"                   # (lcefem.meshes.gridshell_layout, a [layout] table;
                                     # default the published 3 x 3)

Physics per selection (all its strips carry the same current and are the same lumped body): the
balance C dT/dt = I^2 R - loss(T) of :mod:`lcefem.models.lumped_heat` (implicit Euler, the current
of the interval during each step), lambda = min(lambda_s(T), lambda_N) with the transition's
spontaneous-stretch law (:func:`lcefem.models.lce.spontaneous_stretch`, the law of the current
route) and the cap at the as-built lambda_N of the strip bars (a longer strip is slack). The
bar-and-hinge surface follows with rest fractions lambda/lambda_N; the mechanics is quasi-static
(the heat time constant, ~100 s, is far above the surface's inertial times).

Outputs (through the door, lcefem.solvers.runner.run): ``history.csv`` (time [s], per-selection
current [A], temperature [C], lambda [-], centre curvatures by the circle and the quadratic-fit
measure [1/mm], z range [mm], Newton iterations), ``sequence.pvd`` + ``sequence_steps/*.vtp``
(ParaView frame series, time = simulated seconds), ``summary.json``; and what the hooks add (the
command line: ``curvature_vs_time.png``, ``snapshot_NN.png``, a render at the end of each phase NN
of the schedule).

Units: mm, s, A, C.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import time
from dataclasses import dataclass

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.meshes.gridshell_layout import Layout, layout_from_table
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N, BarHingeMaterials
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.lce import spontaneous_stretch
from lcefem.models.limits import MAX_DURATION, check_current
from lcefem.models.lumped_heat import (
    FREE_STRIP,
    GRID_EXCHANGE_FACTOR,
    GRID_STRIP,
    HeatedStrip,
    LumpedThermal,
    grid_thermal,
    implicit_euler_step,
)
from lcefem.solvers import cost
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions, follow_path
from lcefem.solvers.exports import BarHingeVTK
from lcefem.solvers.problems import gridshell_bh as gs
from lcefem.solvers.runner import HistoryExport, PathProblem, StateExport, StateHistory, run
from lcefem.solvers.runtime.run import Progress

#: The lumped body per thermal model: 'segment' is one 25 ohm, 30 mm grid segment (the current
#: route's default); 'eq1' is the free strip of Fig. 2 (146.6 ohm, 80 mm isotropic) on which Eq. 1
#: was measured: its lumped steady stretch is within 0.03 of Eq. 1
#: (tests/models/test_lumped_heat.py), so this is the transient twin of the current route's 'eq1'
#: (the paper's own current choice). 'strip' is one LCE strip of the grid (~130 ohm over 80 mm
#: isotropic, seed 001) with the grid's calibrated exchange factor (models.lumped_heat.grid_thermal;
#: docs/gridshell_thermal.md).
THERMAL_STRIPS = {"segment": HeatedStrip(), "eq1": FREE_STRIP, "strip": GRID_STRIP}
SCHEDULE_KEYS = {
    "times",
    "end",
    "output_interval",
    "support",
    "thermal_model",
    "labels",
    "heat_step",
    "model_set",
}
CURVATURE_COLUMNS = [
    "circle kappa_x [1/mm]",
    "circle kappa_y [1/mm]",
    "quad kappa_x [1/mm]",
    "quad kappa_y [1/mm]",
]


@dataclass(frozen=True)
class Schedule:
    """Piecewise-constant channel currents (module docstring)."""

    times: tuple[float, ...]  # s
    currents: dict  # selection -> tuple of currents [A], one per switch time
    end: float  # s
    output_interval: float  # s
    support: str = "rollers"
    thermal_model: str = "eq1"
    labels: tuple[str, ...] = ()
    heat_step: float = 0.05  # s
    #: the bar-and-hinge model set the schedule was made with ("": the command's default; the name
    #: is checked where the model sets live, lcefem.validation.studies.gridshell.calibrate)
    model_set: str = ""
    #: the gridshell's layout (None: the published 3 x 3)
    layout: Layout | None = None

    def current_at(self, t: float) -> dict:
        """Currents [A] per selection on the interval holding ``t`` (switch times belong to the new
        interval)."""
        k = int(np.searchsorted(self.times, t, side="right")) - 1
        return {sel: values[max(k, 0)] for sel, values in self.currents.items()}

    def output_times(self) -> np.ndarray:
        n = int(math.floor(self.end / self.output_interval + 1e-9))
        t = self.output_interval * np.arange(n + 1)
        return t if abs(t[-1] - self.end) < 1e-9 else np.append(t, self.end)


def _number(value, field: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{field} = {value!r}: must be a finite number")
    return float(value)


def schedule_from_dict(data: dict, where: str = "schedule file") -> Schedule:
    """Validated :class:`Schedule` from the TOML tables; one-line InputError naming the field."""
    for key in data:
        if key not in ("schedule", "currents", "layout"):
            raise InputError(
                f"{where}: unknown section [{key}] (allowed: [schedule], [currents], [layout])"
            )
    sched = data.get("schedule")
    if not isinstance(sched, dict):
        raise InputError(f"{where}: missing section [schedule] (times, end, output_interval)")
    for key in sched:
        if key not in SCHEDULE_KEYS:
            raise InputError(
                f"schedule.{key}: unknown key (allowed: {', '.join(sorted(SCHEDULE_KEYS))})"
            )
    for key in ("times", "end", "output_interval"):
        if key not in sched:
            raise InputError(f"schedule.{key}: missing")
    raw = sched["times"]
    if not isinstance(raw, list) or not raw:
        raise InputError(f"schedule.times = {raw!r}: must be a non-empty list of times [s]")
    times = tuple(_number(v, f"schedule.times[{i}]") for i, v in enumerate(raw))
    if times[0] != 0.0:
        raise InputError(
            f"schedule.times[0] = {times[0]}: must be 0 s (the surface starts as built)"
        )
    for i in range(1, len(times)):
        if not times[i] > times[i - 1]:
            raise InputError(
                f"schedule.times[{i}] = {times[i]}: times must be strictly increasing "
                f"(previous {times[i - 1]} s)"
            )
    end = _number(sched["end"], "schedule.end")
    if not times[-1] < end <= MAX_DURATION:
        raise InputError(
            f"schedule.end = {end}: must be after the last switch time ({times[-1]} s) and "
            f"<= {MAX_DURATION} s (lcefem.models.limits)"
        )
    interval = _number(sched["output_interval"], "schedule.output_interval")
    if not 0.0 < interval <= end:
        raise InputError(
            f"schedule.output_interval = {interval}: must be > 0 s and <= end ({end} s)"
        )
    heat_step = _number(sched.get("heat_step", 0.05), "schedule.heat_step")
    if not 0.0 < heat_step <= interval:
        raise InputError(f"schedule.heat_step = {heat_step}: must be > 0 s and <= output_interval")
    support = sched.get("support", "rollers")
    if support not in gs.SUPPORTS:
        raise InputError(f"schedule.support = {support!r}: allowed {', '.join(gs.SUPPORTS)}")
    thermal = sched.get("thermal_model", "eq1")
    if thermal not in THERMAL_STRIPS:
        raise InputError(
            f"schedule.thermal_model = {thermal!r}: allowed {', '.join(THERMAL_STRIPS)}"
        )
    labels = sched.get("labels", [])
    if (
        not isinstance(labels, list)
        or (labels and len(labels) != len(times))
        or not all(isinstance(s, str) for s in labels)
    ):
        raise InputError(
            f"schedule.labels: must be a list of {len(times)} names (one per switch time)"
        )
    currents = {}
    for sel, values in (data.get("currents") or {}).items():
        field = f"currents.{sel}"
        if not isinstance(values, list) or len(values) != len(times):
            raise InputError(
                f"{field}: must be a list of {len(times)} currents [A] (one per switch time)"
            )
        vals = tuple(_number(v, f"{field}[{i}]") for i, v in enumerate(values))
        for i, v in enumerate(vals):
            check_current(f"{field}[{i}]", v)
        # a strip number in ASCII digits; "²" or "٣" are digits to str.isdigit but not to int()
        currents[int(sel) if sel.isascii() and sel.isdigit() else sel] = vals
    if not currents:
        raise InputError(f"{where}: section [currents] is empty (give e.g. Tx = [0.1, 0.04])")
    model_set = sched.get("model_set", "")
    if "model_set" in sched and (not isinstance(model_set, str) or not model_set):
        raise InputError(
            f"schedule.model_set = {model_set!r}: a model set's name (e.g. \"fe-calibrated\")"
        )
    layout = layout_from_table(data["layout"]) if "layout" in data else None
    schedule = Schedule(
        times,
        currents,
        end,
        interval,
        support,
        thermal,
        tuple(labels),
        heat_step,
        model_set,
        layout,
    )
    schedule_estimate(schedule).check()  # before any work: exit 2 naming the field
    return schedule


#: Most implicit-Euler heat steps of a schedule: a step of 3.6 ms over the longest schedule (1 h,
#: lcefem.models.limits.MAX_DURATION), some 3000 times finer than a strip's ~10 s thermal time
#: constant (seed 001); at 0.14 ms per strip and step (measured, implicit_euler_step) about 140 s of
#: heat balance per channel.
MAX_HEAT_STEPS = 1.0e6
#: Most outputs (quasi-static bar-and-hinge solves and history rows) of a schedule: one a second
#: over the longest schedule; at about 1.5 s per output (the quick Fig. 5A sequence: 31.6 s for 21
#: outputs, docs/validation_summary_quick.md) about 1.5 h of solves.
MAX_OUTPUTS = 3600.0


def schedule_estimate(schedule: Schedule) -> cost.Estimate:
    """The schedule's work before it starts (lcefem.solvers.cost): heat steps (end / heat_step) and
    outputs (end / output_interval), each with its stated bound (:data:`MAX_HEAT_STEPS`,
    :data:`MAX_OUTPUTS`), and the history's memory."""
    heat = cost.steps(schedule.end, schedule.heat_step)
    outputs = cost.steps(schedule.end, schedule.output_interval) + 1
    est = cost.Estimate()
    est.bound(
        f"schedule.heat_step = {schedule.heat_step:g} s (end {schedule.end:g} s)",
        "heat steps",
        heat,
        MAX_HEAT_STEPS,
        "a 3.6 ms step over the longest schedule, lcefem.solvers.problems."
        "gridshell_bh_sequence.MAX_HEAT_STEPS",
    )
    est.bound(
        f"schedule.output_interval = {schedule.output_interval:g} s (end {schedule.end:g} s)",
        "outputs",
        outputs,
        MAX_OUTPUTS,
        "one quasi-static solve a second over the longest schedule, "
        "lcefem.solvers.problems.gridshell_bh_sequence.MAX_OUTPUTS",
    )
    return est.memory(
        f"schedule.output_interval = {schedule.output_interval:g} s",
        f"{outputs:.3g} outputs",
        outputs * cost.ROW_MEMORY,
    )


def load_schedule(path) -> Schedule:
    from lcefem.solvers.runtime.inputs import decode_error, read_toml

    path = pathlib.Path(path)
    data = read_toml(path, f"--schedule '{path}'")
    try:
        return schedule_from_dict(data, f"--schedule '{path}'")
    except InputError:
        raise
    except (
        ValueError,
        TypeError,
        RecursionError,
    ) as exc:  # only its decode error leaves the parser
        raise decode_error(f"--schedule '{path}'", exc) from None


def check_selections(schedule: Schedule, structure: BarHingeStructure) -> None:
    """Every [currents] key must select strips of the structure (InputError naming it)."""
    for sel in schedule.currents:
        gs.targets_from_lambdas(structure, {sel: 1.2}, name=f"currents.{sel}")


# -------------------------------------------------------------------------------- heat
def strip_histories(
    schedule: Schedule,
    times: np.ndarray,
    strips: dict | None = None,
    model: LumpedThermal | None = None,
    lambda_N: float = PUBLISHED_LAMBDA_N,
):
    """Temperatures [C] and stretches [-] per selection at ``times`` [s] (from ambient at t = 0).

    ``strips``: selection -> :class:`HeatedStrip` (default: the schedule's thermal model for all; a
    per-selection body lets resistances differ, e.g. in the prediction bands). Implicit Euler with
    steps of at most ``schedule.heat_step`` inside each output interval; a step carries the current
    of the interval holding its midpoint. lambda = min(lambda_s(T), lambda_N)."""
    default = THERMAL_STRIPS[schedule.thermal_model]
    if model is None:  # the grid strip's exchange carries the calibrated grid factor
        model = grid_thermal() if schedule.thermal_model == "strip" else LumpedThermal()
    strips = {sel: (strips or {}).get(sel, default) for sel in schedule.currents}
    T = {sel: model.exchange.ambient_temperature for sel in schedule.currents}
    temps = {sel: np.empty(len(times)) for sel in schedule.currents}
    for k, t in enumerate(times):
        t_prev = times[k - 1] if k else 0.0
        n = max(1, int(math.ceil((t - t_prev) / schedule.heat_step - 1e-9)))
        h = (t - t_prev) / n
        for j in range(n if t > t_prev else 0):
            currents = schedule.current_at(t_prev + (j + 0.5) * h)
            for sel in T:
                T[sel] = implicit_euler_step(T[sel], currents[sel], h, strips[sel], model)
        for sel in T:
            temps[sel][k] = T[sel]
    lambdas = {
        sel: np.minimum(np.asarray(spontaneous_stretch(v, model.transition), dtype=float), lambda_N)
        for sel, v in temps.items()
    }
    return temps, lambdas


# -------------------------------------------------------------------------------- mechanics
class QuasiStaticSurface:
    """The bar-and-hinge surface followed through a sequence of rest-fraction targets: each new
    target is reached by path following from the previous equilibrium (warm start), the rest
    fractions interpolated linearly; if that fails (e.g. a snap), the ramp from the as-built state
    (:func:`lcefem.solvers.problems.gridshell_bh.solve_gridshell`) is tried."""

    def __init__(
        self,
        structure: BarHingeStructure,
        support: str = "rollers",
        materials: BarHingeMaterials = BarHingeMaterials(),
        newton: NewtonOptions = gs.GRIDSHELL_NEWTON,
        path: PathOptions = gs.GRIDSHELL_PATH,
        start: tuple[dict, np.ndarray] | None = None,
        scales=None,
    ):
        self.structure = structure
        self.setup = gs.setup_gridshell(None, support, structure=structure, materials=materials)
        if scales is not None:  # the cover-scale layer (lcefem.models.cover_scales.CoverScales)
            from lcefem.solvers.problems.gridshell_bh_scales import cover_setup

            self.setup = cover_setup(self.setup, scales, materials)
        self.newton, self.path = newton, path
        if start is None:
            self.fractions = {g: v.copy() for g, v in self.setup.targets.items()}
            self.x = structure.nodes.copy()
        else:  # another equilibrium (e.g. the nominal one of the same structure) as the start
            self.fractions = {g: np.asarray(v, dtype=float).copy() for g, v in start[0].items()}
            self.x = np.asarray(start[1], dtype=float).reshape(-1, 3).copy()
        self.iterations = 0  # Newton iterations of the last advance
        self.cold_restarts = 0
        self._solved = False

    def advance(self, targets: dict[str, np.ndarray], tolerance: float = 1e-10) -> np.ndarray:
        """Equilibrium positions (n, 3) [mm] at rest fractions ``targets`` (by bar group)."""
        f0 = self.fractions
        if self._solved and all(
            np.max(np.abs(targets[g] - f0[g]), initial=0.0) <= tolerance for g in f0
        ):
            self.iterations = 0
            return self.x
        model, held = self.setup.model, self.setup.held

        def load(t: float) -> np.ndarray:
            model.set_rest_fractions({g: f0[g] + t * (targets[g] - f0[g]) for g in f0})
            return model.reference.reshape(-1)[held]

        try:
            result = follow_path(
                model, self.x, held, load, newton_options=self.newton, path_options=self.path
            )
        except ConvergenceError:
            self.cold_restarts += 1
            self.setup.targets = {g: np.asarray(v, dtype=float) for g, v in targets.items()}
            result = gs.solve_gridshell(self.setup, newton_options=self.newton, path=self.path).path
        self.x = result.states[-1].x.reshape(-1, 3).copy()
        self.fractions = {g: np.asarray(v, dtype=float).copy() for g, v in targets.items()}
        self.iterations = int(sum(s.iterations for s in result.states))
        self._solved = True
        return self.x

    def curvatures(self) -> dict:
        return gs.shape_summary(self.structure, self.x)


def rest_fractions(
    structure: BarHingeStructure, lambdas: dict, lambda_N: float = PUBLISHED_LAMBDA_N
) -> dict[str, np.ndarray]:
    """Rest fractions per bar from lambdas per selection (strips not named stay as built)."""
    return gs.targets_from_lambdas(structure, lambdas, lambda_N, "sequence lambda")


# -------------------------------------------------------------------------------- run
def phase_ends(schedule: Schedule, times: np.ndarray) -> dict[int, int]:
    """{output index: phase index}: the last output time of each phase (before the next switch)"""
    ends = list(schedule.times[1:]) + [schedule.end + 1.0]
    out = {}
    for phase, stop in enumerate(ends):
        inside = np.nonzero((times >= schedule.times[phase]) & (times < stop))[0]
        if inside.size:
            out[int(inside[-1])] = phase
    return out


def columns_for(schedule: Schedule) -> list[str]:
    cols = ["time [s]"]
    for sel in schedule.currents:
        cols += [f"{sel} current [A]", f"{sel} temperature [C]", f"{sel} lambda [-]"]
    return cols + CURVATURE_COLUMNS + ["z range [mm]", "newton iterations [-]"]


@dataclass(frozen=True)
class SequenceStep:
    """One output of a sequence: its index ``k``, time ``t`` [s], positions ``x`` (n, 3) [mm] and
    history ``row``."""

    k: int
    t: float
    x: np.ndarray
    row: dict


class SequenceFrames:
    """Export object: ``sequence.pvd`` + ``sequence_steps/*.vtp``, a frame per output (time =
    simulated seconds); ``model`` the BarHingeModel (its bar forces)."""

    def __init__(self, structure: BarHingeStructure, model):
        self.structure, self.model = structure, model

    def open(self, run, out) -> "SequenceFrames":
        self.vtk = run.output(BarHingeVTK(out, "sequence", self.structure))
        return self

    def write(self, s: SequenceStep) -> None:
        self.vtk.write(s.t, s.x, self.model.bar_forces(s.x))

    def last_converged(self, folder, s) -> None:
        pass  # the series is kept as *.partial.* up to the last frame


@dataclass(frozen=True)
class SequenceHooks:
    """Export object: the caller's ``frame(k, t, structure, x)`` at every output and ``snapshot(out,
    phase, label, t, structure, x, support)`` at the last output of each phase (``snapshots``:
    :func:`phase_ends`; only with ``out``)."""

    schedule: "Schedule"
    structure: BarHingeStructure
    snapshots: dict
    out: pathlib.Path | None
    frame: object = None
    snapshot: object = None

    def open(self, run, out) -> "SequenceHooks":
        return self

    def write(self, s: SequenceStep) -> None:
        if self.frame is not None:
            self.frame(s.k, s.t, self.structure, s.x)
        if self.out is not None and self.snapshot is not None and s.k in self.snapshots:
            phase = self.snapshots[s.k]
            label = self.schedule.labels[phase] if self.schedule.labels else f"phase {phase}"
            self.snapshot(
                pathlib.Path(self.out),
                phase,
                label,
                s.t,
                self.structure,
                s.x,
                self.schedule.support,
            )

    def last_converged(self, folder, s) -> None:
        pass


def run_sequence(
    schedule: Schedule,
    out: pathlib.Path | None,
    *,
    progress: bool = True,
    structure: BarHingeStructure | None = None,
    frames: bool = True,
    config: dict | None = None,
    snapshot=None,
    report=None,
    scales=None,
    frame=None,
    materials: BarHingeMaterials = BarHingeMaterials(),
    exchange_factor: float = GRID_EXCHANGE_FACTOR,
) -> dict:
    """Run a schedule through the run skeleton (outputs in the module docstring); returns the
    summary (with ``history``: the columns as lists). With ``out``: ``snapshot(out, phase, label, t,
    structure, x, support)`` at the last output of each phase and ``report(out, history, schedule)``
    before the summary is written (optional: the validation's figures). ``scales``: a
    :class:`lcefem.models.cover_scales.CoverScales` puts the cover scales on the surface;
    ``frame(k, t, structure, x)`` is called at every output (e.g. a movie's frames). ``materials``
    and ``structure`` choose the model (e.g. the FE-calibrated set of
    :func:`lcefem.validation.studies.gridshell.calibrate.model_set`: a structure with
    ``strip_element = "beam"``); ``exchange_factor`` [-] is the grid strip's (thermal model
    'strip'), the one calibrated with the model set (default: the published set's,
    :data:`lcefem.models.lumped_heat.GRID_EXCHANGE_FACTOR`)."""
    structure = structure or build_gridshell_bar_hinge()
    check_selections(schedule, structure)
    times = schedule.output_times()
    thermal = (
        grid_thermal(exchange_factor) if schedule.thermal_model == "strip" else LumpedThermal()
    )
    temps, lambdas = strip_histories(schedule, times, model=thermal)
    surface = QuasiStaticSurface(structure, schedule.support, materials, scales=scales)
    snapshots = phase_ends(schedule, times)
    bar = Progress(float(times[-1]), "sequence", "s", ".0f", progress)
    started = time.perf_counter()
    resolved = config or {"schedule": dataclasses.asdict(schedule)}
    # [mm] deepest strip-ribbon penetration over the outputs (NaN: a structure without contact rows)
    found = {"depth": 0.0 if structure.contacts else math.nan}

    def follow(on_step) -> None:
        """The surface's equilibrium at each output time (from the previous one), one state each."""
        for k, t in enumerate(times):
            lam_k = {sel: float(lambdas[sel][k]) for sel in schedule.currents}
            x = surface.advance(rest_fractions(structure, lam_k))
            summ = surface.curvatures()
            if structure.contacts:
                found["depth"] = max(found["depth"], gs.structure_penetration(structure, x))
            row = {"time [s]": float(t)}
            current = schedule.current_at(t - 1e-12) if t > 0 else schedule.current_at(0.0)
            for sel in schedule.currents:
                row.update(
                    {
                        f"{sel} current [A]": current[sel],
                        f"{sel} temperature [C]": temps[sel][k],
                        f"{sel} lambda [-]": lam_k[sel],
                    }
                )
            row.update(
                {
                    "circle kappa_x [1/mm]": summ["circle_x"],
                    "circle kappa_y [1/mm]": summ["circle_y"],
                    "quad kappa_x [1/mm]": summ["quad_kx"],
                    "quad kappa_y [1/mm]": summ["quad_ky"],
                    "z range [mm]": summ["z_range [mm]"],
                    "newton iterations [-]": surface.iterations,
                }
            )
            on_step(SequenceStep(k, float(t), x, row))

    def summarize(skeleton, _) -> dict:
        history = skeleton.history.as_arrays()
        depth = found["depth"]
        if out is not None and report is not None:
            report(pathlib.Path(out), history, schedule)
        return {
            "model": "bar-hinge gridshell, quasi-static sequence",
            "support": schedule.support,
            "cover scales": dataclasses.asdict(scales) if scales is not None else None,
            "thermal model": schedule.thermal_model,
            "outputs": len(times),
            "cold restarts": surface.cold_restarts,
            "wall_time [s]": time.perf_counter() - started,
            "final": {c: float(history[c][-1]) for c in CURVATURE_COLUMNS},
            "strip-ribbon penetration [mm]": depth,
            "strips pass through the ribbon": bool(depth > gs.PENETRATION_LIMIT),
            "history": {c: v.tolist() for c, v in history.items()},
        }

    history = HistoryExport(
        tuple(columns_for(schedule)),
        lambda s: s.row,
        where=lambda s: f"t = {s.t:.4g} s",
        at=lambda s: s.t,
    )
    exports = [StateHistory(history)]
    if frames and out is not None:
        exports.append(StateExport(SequenceFrames(structure, surface.setup.model)))
    if frame is not None or (out is not None and snapshot is not None):
        exports.append(
            StateExport(SequenceHooks(schedule, structure, snapshots, out, frame, snapshot))
        )
    problem = PathProblem(follow, end=float(times[-1]), at=lambda s: s.t)
    return run(
        problem, problem.program(), exports, out, config=resolved, progress=bar, summarize=summarize
    )
