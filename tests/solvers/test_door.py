"""The one door (lcefem.solvers.runner.run): a program drives any Problem, exports typed on the
protocol write its StepRecords, export times are hit exactly, and programs and exports read from
case-file tables refuse bad input with one line naming the key."""

from __future__ import annotations

import csv
import json
import math
import subprocess

import numpy as np
import pytest

from lcefem.models.errors import InputError
from lcefem.solvers.exports import Fields, History, Probe, Reaction, exports_from_tables
from lcefem.solvers.problems.protocol import LOAD, TIME, Problem, StepRecord
from lcefem.solvers.program import Program, program_from_table
from lcefem.solvers.runner import run

K = 0.5  # [N/mm] the toy's spring


class Slider:
    """A toy problem with a closed form: a point moved along x at the drive speed v [mm/s]
    (piecewise constant), x(t) = integral of v, exact for any step; a spring of stiffness K holds it
    (reaction -K x [N] on the tag "wall"). Its fields are node arrays (two nodes)."""

    drive = "speed [mm/s]"

    def __init__(self):
        self.time, self.x, self.v = 0.0, 0.0, 0.0

    def drive_tags(self):
        return ("motor",)

    def set_drives(self, drives):
        for tag, value in drives.items():
            if tag != "motor":
                raise InputError(f"drive {tag!r}: allowed motor")
            self.v = float(value)

    def advance(self, dt):
        self.x += self.v * dt
        self.time += dt
        return StepRecord(self.time, self.observables(), iterations=1)

    def observables(self):
        return {"time [s]": self.time, "position [mm]": self.x, "speed [mm/s]": self.v}

    def fields(self):
        return {
            "node positions [mm]": np.array([[0.0, 0.0, 0.0], [1.0 + self.x, 0.0, 0.0]]),
            "temperature [C]": np.array([20.0, 20.0 + self.x]),
        }

    def reaction(self, tag, component=0):
        if tag != "wall":
            raise InputError(f"reaction tag {tag!r}: allowed wall")
        return -K * self.x if component == 0 else 0.0

    def save_state(self):
        return (self.time, self.x, self.v)

    def restore_state(self, state):
        self.time, self.x, self.v = state


def x_exact(t: float) -> float:
    """The closed form of the program below: 2 mm/s to t = 3 s, then -1 mm/s."""
    return 2.0 * min(t, 3.0) - 1.0 * max(t - 3.0, 0.0)


def read(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def test_the_door_drives_a_problem_along_a_program_and_hits_the_export_times(tmp_path):
    """Steps of at most 2 s to 5 s (h = 5/3 s), the switch at 3 s and the export times 1.25 and
    2.5 s are the stops; every row equals the closed form x(t); each export writes at its times."""
    p = Slider()
    assert isinstance(p, Problem)
    program = program_from_table(
        {
            "clock": "time",
            "duration": 5.0,
            "dt": 2.0,
            "drives": [{"at": 0.0, "motor": 2.0}, {"at": 3.0, "motor": -1.0}],
        }
    )
    exports = [
        History(),
        Probe("tip.csv", "temperature [C]", (1.0, 0.0, 0.0), times=(2.5,)),
        Reaction("wall.csv", "wall"),
        Fields("slider", times=(1.25,)),
    ]
    summary = run(p, program, exports, tmp_path / "out", config={"toy": True})
    h = 5.0 / 3.0
    head, rows = read(tmp_path / "out" / "history.csv")
    assert head == ["time [s]", "position [mm]", "speed [mm/s]"]
    assert rows[:, 0].tolist() == [
        0.0,
        1.25,
        float(f"{h:.10g}"),
        2.5,
        3.0,
        float(f"{2 * h:.10g}"),
        5.0,
    ]
    np.testing.assert_allclose(rows[:, 1], [x_exact(t) for t in rows[:, 0]], rtol=1e-9, atol=1e-12)
    assert rows[-1, 1] == pytest.approx(4.0, abs=1e-12)  # 6 mm out, 2 mm back
    head, probe = read(tmp_path / "out" / "tip.csv")
    assert head == ["time [s]", "temperature [C]"] and probe.tolist() == [[2.5, 25.0]]
    head, wall = read(tmp_path / "out" / "wall.csv")
    assert head == ["time [s]", "reaction wall x [N]"]
    np.testing.assert_allclose(wall[:, 1], -K * rows[:, 1], atol=1e-12)
    pvd = (tmp_path / "out" / "slider.pvd").read_text()
    assert pvd.count("<DataSet") == 1 and 'timestep="1.25"' in pvd
    assert summary["steps"] == 6 and summary["final"]["position [mm]"] == pytest.approx(4.0)
    saved = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert saved["status"] == "completed" and saved["config"] == {"toy": True}
    assert not list((tmp_path / "out").glob("*.part"))


def test_a_failed_step_keeps_the_rows_as_partial_and_writes_failure_json(tmp_path):
    """A ConvergenceError in advance: history.partial.csv up to the last converged step and
    failure.json naming it; no summary.json."""
    from lcefem.models.errors import ConvergenceError

    class Breaks(Slider):
        def advance(self, dt):
            if self.time + dt > 2.5:
                raise ConvergenceError(f"t = {self.time + dt:g} s", "no convergence (the test's)")
            return super().advance(dt)

    with pytest.raises(ConvergenceError):
        run(Breaks(), Program.in_time({"motor": 1.0}, 4.0, 1.0), [History()], tmp_path, config={})
    _, rows = read(tmp_path / "history.partial.csv")
    assert rows[:, 0].tolist() == [0.0, 1.0, 2.0]
    failure = json.loads((tmp_path / "failure.json").read_text())
    assert failure["where"] == "t = 3 s" and failure["last_converged"]["position [mm]"] == 2.0
    assert not (tmp_path / "summary.json").exists()


def test_a_load_program_advances_by_the_fraction_of_the_way_left():
    """Stops 0.5 and 1 of a load program: the first advance goes half the way, the second the
    whole rest (1.0, the targets exactly)."""
    seen = []

    class Ramp(Slider):
        def advance(self, dt):
            seen.append(dt)
            return StepRecord(dt, self.observables(), clock=LOAD)

    summary = run(
        Ramp(),
        Program.quasi_static({"motor": 1.0}, dt=0.5),
        [History()],
        None,
        config={},
        summarize=lambda skeleton, records: {"at": [r.at for r in records]},
    )
    assert seen == [0.5, 1.0] and summary["at"] == [0.0, 0.5, 1.0]


def test_step_records_and_exports_carry_units():
    with pytest.raises(ValueError, match="position"):
        StepRecord(1.0, {"position": 1.0})
    with pytest.raises(ValueError, match="clock"):
        StepRecord(1.0, {}, clock="days")
    with pytest.raises(ValueError, match="curvature"):
        History(columns=("time [s]", "curvature"))
    assert StepRecord(1.0, {"x [mm]": 1.0}, detail="a") == StepRecord(
        1.0, {"x [mm]": 1.0}, detail="b"
    )
    assert TIME == "time [s]" and LOAD == "load fraction [-]"


@pytest.mark.parametrize(
    "table, message",
    [
        (
            {"clock": "days", "duration": 1.0, "drives": [{"at": 0.0, "coil": 0.1}]},
            r"^program\.clock = 'days': allowed 'time', 'load'$",
        ),
        ({"dt": 1.0, "drives": [{"at": 0.0, "coil": 0.1}]}, r"^program: missing key 'duration'"),
        (
            {"duration": 10.0, "dt": 20.0, "drives": [{"at": 0.0, "coil": 0.1}]},
            r"^program\.dt = 20.0 s: must be > 0 and <= 10 s$",
        ),
        (
            {"duration": 10.0, "drives": [{"at": 1.0, "coil": 0.1}]},
            r"^program\.drives: the first entry must be at = 0$",
        ),
        (
            {"duration": 10.0, "drives": [{"at": 0.0, "coil": "hot"}]},
            r"^program\.drives\[0\]\.coil = 'hot': must be a number$",
        ),
        (
            {"duration": 10.0, "drives": [{"at": 0.0, "coil": 0.1}, {"at": 0.0, "coil": 0.2}]},
            r"'at' must increase",
        ),
        ({"duration": 10.0, "drives": [{"coil": 0.1}]}, r"^program\.drives\[0\]: missing key 'at'"),
        (
            {"duration": 10.0, "current": 0.2, "drives": []},
            r"^program: unknown key 'current' \(allowed: ",
        ),
        (
            {"clock": "load", "duration": 2.0, "drives": [{"at": 0.0, "top_strips": 1.2}]},
            r"^program\.duration: not for clock = 'load'",
        ),
        (
            {"clock": "load", "steady": True, "drives": [{"at": 0.0, "top_strips": 1.2}]},
            r"^program\.steady: only with clock = 'time'$",
        ),
    ],
)
def test_a_bad_program_is_one_line_naming_the_key(table, message):
    with pytest.raises(InputError, match=message) as info:
        program_from_table(table)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "tables, message",
    [
        (
            [{"kind": "movie", "name": "a"}],
            r"^exports\[0\]\.kind = 'movie': allowed history, fields, probe, reaction$",
        ),
        (
            [{"kind": "probe", "name": "p.csv", "field": "temperature [C]", "point": [1, 2]}],
            r"^exports\[0\]\.point = \[1, 2\]: three coordinates \[mm\]$",
        ),
        ([{"kind": "history", "columns": ["time"]}], r"^exports\[0\]\.columns: 'time' has no unit"),
        (
            [{"kind": "fields", "name": "a.bp", "every": 0}],
            r"^exports\[0\]\.every = 0: an integer >= 1$",
        ),
        ([{"kind": "reaction", "name": "r.csv"}], r"^exports\[0\]: missing key 'tag'$"),
        (
            [{"kind": "fields", "name": "a.bp"}, {"kind": "history", "name": "a.bp"}],
            r"^exports\[1\]\.name = 'a.bp': a file name, unique",
        ),
        ([{"kind": "history", "times": [-1.0]}], r"^exports\[0\]\.times = \[-1.0\]"),
        ([{"kind": "history", "step": 2}], r"^exports\[0\]: unknown key 'step' for kind 'history'"),
    ],
)
def test_bad_exports_are_one_line_naming_the_entry(tables, message):
    with pytest.raises(InputError, match=message) as info:
        exports_from_tables(tables)
    assert "\n" not in str(info.value)


def test_exports_from_a_case_file_table():
    history, fields, probe, reaction = exports_from_tables(
        [
            {"kind": "history"},
            {"kind": "fields", "name": "thermal.bp", "fields": ["temperature [C]"], "times": [10]},
            {"kind": "probe", "name": "tip.csv", "field": "temperature [C]", "point": [1, 0, 0]},
            {"kind": "reaction", "name": "clamp.csv", "tag": "clamp", "component": 2},
        ]
    )
    assert history == History()
    assert fields == Fields("thermal.bp", ("temperature [C]",), times=(10.0,))
    assert probe == Probe("tip.csv", "temperature [C]", (1.0, 0.0, 0.0))
    assert reaction == Reaction("clamp.csv", "clamp", 2)


def test_an_export_of_a_field_or_reaction_the_problem_lacks_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"field 'stress \[MPa\]' not among the problem's fields"):
        run(
            Slider(),
            Program.in_time({"motor": 1.0}, 1.0, 1.0),
            [Probe("p.csv", "stress [MPa]", (0, 0, 0))],
            tmp_path,
            config={},
        )
    with pytest.raises(InputError, match=r"reaction tag 'floor': allowed wall"):
        run(
            Slider(),
            Program.in_time({"motor": 1.0}, 1.0, 1.0),
            [Reaction("r.csv", "floor")],
            tmp_path,
            config={},
        )


def test_a_bad_program_in_a_case_file_exits_2_with_one_line_and_writes_nothing(
    tmp_path, lcefem_cmd
):
    case = tmp_path / "case.toml"
    case.write_text('[program]\nduration = 5.0\n[[program.drives]]\nat = 0.0\ncoil = "hot"\n')
    out = tmp_path / "out"
    proc = subprocess.run(
        [*lcefem_cmd, "run", "strip", "--config", str(case), "--out", str(out), "--quiet"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.strip()]
    assert (
        len(lines) == 1
        and "case.toml: program.drives[0].coil = 'hot': must be a number" in lines[0]
    )
    assert not out.exists()


def test_run_targets_come_from_the_body_registry():
    """``lcefem run`` targets are the registrations' targets; adding a body is one registration."""
    from lcefem.solvers import registry
    from lcefem.validation.app.commands import RUN_TARGETS

    assert list(RUN_TARGETS) == list(registry.targets())
    assert RUN_TARGETS["strip"] == "lcefem.validation.app.commands.strip"
    for entry in registry.BODIES.values():
        assert entry.config_class() is not None and registry._load(entry.problem) is not None
    extra = registry.register(
        registry.Body("toy", "a slider", "toy", "toy", "math:pi", "math:pi", None)
    )
    try:
        assert registry.targets()["toy"] == "toy"
    finally:
        del registry.BODIES[extra.name]
    with pytest.raises(ValueError, match="twice"):
        registry.register(registry.BODIES["strip"])


def test_the_strip_and_the_beams_register_their_default_program():
    from lcefem.solvers.registry import body

    strip = body("strip")
    cfg = strip.config_class()()
    program = strip.default_program(cfg)
    assert (
        program.clock == TIME
        and program.end == cfg.run.duration
        and program.drives == ((0.0, {"coil": cfg.run.current}),)
    )
    beam = body("beam")
    lam = beam.default_program(beam.config_class()())
    assert lam.clock == LOAD and lam.drives[0][1] == {"top_strips": 1.33, "bottom_strips": 1.05}
    assert math.isclose(lam.stops()[-1], 1.0)
    with pytest.raises(InputError, match="body 'robot'"):
        body("robot")


def test_programs_toml_holds_run_programs_behind_the_checked_loader(tmp_path):
    """validation/data/programs.toml's [run_programs]: each a Program with its source; a bad entry
    is one InputError naming the file and the key."""
    from lcefem.validation.cases.programs import PATH, load_programs, run_program

    pulse, source = run_program("strip_pulse_0p2A_20s_then_off")
    assert pulse.drives == ((0.0, {"coil": 0.2}), (20.0, {"coil": 0.0})) and "seed 001" in source
    assert pulse.stops()[39:41] == [20.0, 20.5] and pulse.drives_at(20.0) == {"coil": 0.0}
    bad = tmp_path / "programs.toml"
    bad.write_text(
        PATH.read_text().replace(
            "duration = 30.0\ndt = 0.5\ndrives = [{ at = 0.0, coil = 0.2 }]\n",
            "duration = 30.0\ndt = 50.0\ndrives = [{ at = 0.0, coil = 0.2 }]\n",
        )
    )
    with pytest.raises(
        InputError,
        match=r"^programs\.toml: run_programs\.strip_0p2A_30s\.dt = 50\.0 s: must be > 0 "
        r"and <= 30 s$",
    ):
        load_programs(bad)
    with pytest.raises(InputError, match="allowed strip_0p2A_30s"):
        run_program("robot")


def test_the_bar_and_hinge_beam_through_the_door_from_its_registration(tmp_path):
    """The registered beam (bar-and-hinge) built and run from its registration alone: one row per
    converged increment of its path follower (its first the as-built state), the last at the targets
    with the curvature its run reports (run_beam, the same problem and path); its fields as ParaView
    frames of the structure."""
    from lcefem.solvers.problems.composite_beam_bh import run_beam
    from lcefem.solvers.registry import body

    beam = body("beam")
    cfg = beam.config_class()()
    problem = beam.build(cfg)
    exports = [History(), Fields("beam"), Probe("tip.csv", "node positions [mm]", (0.0, 0.0, 0.0))]
    summary = run(
        problem, beam.default_program(cfg), exports, tmp_path / "door", config=cfg.resolved()
    )
    head, rows = read(tmp_path / "door" / "history.csv")
    assert head == [
        "load fraction [-]",
        "lambda top_strips [-]",
        "lambda bottom_strips [-]",
        "curvature [1/mm]",
    ]
    assert (
        rows[-1, 0] == 1.0
        and rows[-1, 1] == pytest.approx(1.33)
        and rows[-1, 2] == pytest.approx(1.05)
    )
    assert (
        rows[0, 0] == 0.0 and rows[0, 1] == pytest.approx(1.4) and np.all(np.diff(rows[:, 0]) > 0)
    )
    reference = run_beam(cfg, tmp_path / "run_beam", progress=False)
    assert rows[-1, 3] == pytest.approx(reference["results"]["curvature [1/mm]"], rel=1e-12)
    assert summary["final"]["curvature [1/mm]"] == pytest.approx(rows[-1, 3], rel=1e-12)
    pvd = (tmp_path / "door" / "beam.pvd").read_text()
    assert pvd.count("<DataSet") == len(
        rows
    )  # a frame per record: the as-built start, every increment
    head, tip = read(tmp_path / "door" / "tip.csv")
    assert head == [
        "load fraction [-]",
        "node positions_x [mm]",
        "node positions_y [mm]",
        "node positions_z [mm]",
    ]


def test_a_case_file_names_a_program_of_programs_toml(tmp_path):
    from lcefem.validation.app.config import door_from_toml
    from lcefem.validation.cases.programs import run_program

    case = tmp_path / "case.toml"
    case.write_text('[program]\nname = "strip_pulse_0p2A_20s_then_off"\n')
    program, exports = door_from_toml(case)
    assert program == run_program("strip_pulse_0p2A_20s_then_off")[0] and exports is None
    case.write_text('[program]\nname = "robot"\n')
    with pytest.raises(InputError, match=r"^case\.toml: program 'robot': allowed "):
        door_from_toml(case)


def test_an_export_time_beyond_the_program_is_refused_and_a_run_in_memory_writes_nothing(tmp_path):
    with pytest.raises(InputError, match=r"^exports times: 7 beyond the program's end \(5 s\)$"):
        run(
            Slider(),
            Program.in_time({"motor": 1.0}, 5.0, 1.0),
            [History(times=(7.0,))],
            tmp_path / "a",
            config={},
        )
    assert not (tmp_path / "a").exists()
    summary = run(
        Slider(),
        Program.in_time({"motor": 1.0}, 2.0, 1.0),
        [History(), Fields("slider")],
        None,
        config={},
    )
    assert summary["final"]["position [mm]"] == 2.0


def test_validation_cases_come_from_the_registrations_in_their_order():
    """``lcefem validate``'s case modules are those registered with the bodies (and the empirical
    laws, no body's), in registration order; each body knows its own; a module registered twice or
    for a body not registered is refused."""
    from lcefem.solvers import registry
    from lcefem.validation.cases import CASE_MODULES

    assert CASE_MODULES == [f"lcefem.validation.cases.{m}" for m in registry.CASES]
    assert CASE_MODULES[:3] == [
        "lcefem.validation.cases.ribbon",
        "lcefem.validation.cases.empirical",
        "lcefem.validation.cases.beam_bar_hinge",
    ]
    assert registry.body("gridshell-fe").cases == ("gridshell_fe", "gridshell_heated_fe")
    assert registry.CASES["empirical"] is None
    with pytest.raises(ValueError, match="twice"):
        registry.register_cases("strip", "strip")
    with pytest.raises(ValueError, match="robot"):
        registry.register_cases("robot", "robot_case")
    assert "robot_case" not in registry.CASES
