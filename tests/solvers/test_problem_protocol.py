"""Every body's problem in solvers/problems implements the one Problem protocol
(lcefem.solvers.problems.protocol): drives by tag, advance(dt), observables "name [unit]", fields,
save/restore state. The walk reads the sources (ast), so a new problem class is checked without
being listed here."""

from __future__ import annotations

import ast
import importlib
import inspect
import pathlib

import numpy as np
import pytest

from lcefem.models.errors import InputError
from lcefem.solvers.problems.protocol import (
    NAME_WITH_UNIT,
    Problem,
    StepRecord,
    check_quasi_static_step,
    unnamed,
)

PROBLEMS = pathlib.Path(__file__).resolve().parents[2] / "solvers" / "problems"
#: A class defining one of these is a body's problem (it drives or observes a body).
MARKS = {
    "observables",
    "observe",
    "set_lambda",
    "set_current",
    "set_shortening",
    "set_load",
    "set_drives",
}

#: Modules of solvers/problems without a problem object, each with why (left for a session that
#: can move their contents: they are written as functions over a setup, not as a problem class).
WITHOUT_PROBLEM_OBJECT = {
    "composite_beam_run": "the FE beam's run (BeamFEConfig, run_beam_fe) around composite_beam's "
    "problems",
    "tension_specimen": "one function (a closed-form check of the LCE law)",
    "body_case": "the case file of lcefem run body (schema and checks; its problem is "
    "body.BodyProblem)",
    "body_expression": "the safe expressions of a body case file (a director of x, y, z; its "
    "problem is body.BodyProblem)",
    "gridshell_bh_ball": "a ball rolling on a given surface history (no body of its own)",
    "stable_ramp": "the stability-watching load path of GridshellBH (follow_stable_path)",
    "gridshell_bh_scales": "load paths for GridshellBH",
    "gridshell_bh_sequence": "a schedule driving GridshellBH's path",
    "gridshell_bh_weights": "load paths for GridshellBH",
    "gridshell_bh_run": "one run of lcefem run gridshell (GridshellBHRunConfig, run_gridshell) "
    "around GridshellBH",
    "gridshell_fe_run": "one run of lcefem run gridshell --model fe (GridshellFERunConfig, "
    "run_gridshell_fe) "
    "around GridshellFE / HeatedGridshellFE",
}


def problem_classes() -> dict[str, list[str]]:
    found = {}
    for path in sorted(PROBLEMS.glob("*.py")):
        if path.name in ("__init__.py", "protocol.py"):
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        found[path.stem] = [
            node.name
            for node in tree.body
            if isinstance(node, ast.ClassDef)
            and MARKS & {f.name for f in node.body if isinstance(f, ast.FunctionDef)}
        ]
    return found


CLASSES = [(module, name) for module, names in problem_classes().items() for name in names]


def load(module: str, name: str):
    return getattr(importlib.import_module(f"lcefem.solvers.problems.{module}"), name)


def test_the_walk_finds_the_problems_and_only_the_listed_modules_lack_one():
    found = problem_classes()
    assert {m for m, names in found.items() if not names} == set(WITHOUT_PROBLEM_OBJECT)
    assert {
        "StripSimulation",
        "BeamFE",
        "HeatedBeamFE",
        "KaptonSpecimenFE",
        "TwistedRibbonFE",
        "GridshellFE",
        "HeatedGridshellFE",
        "GridshellBH",
        "KaptonSpecimenBH",
        "CompositeBeamBH",
        "RollingRibbonDER",
    } <= {n for _, n in CLASSES}


@pytest.mark.parametrize("module, name", CLASSES, ids=[n for _, n in CLASSES])
def test_every_problem_class_implements_the_protocol(module, name):
    cls = load(module, name)
    members = [m for m in dir(Problem) if not m.startswith("_")] + ["drive"]
    missing = [m for m in members if not hasattr(cls, m)]
    assert not missing, f"{name} lacks {missing}"
    assert NAME_WITH_UNIT.match(cls.drive), cls.drive
    # The calls the protocol makes bind to the class's own signatures.
    inspect.signature(cls.advance).bind(None, 1.0)
    inspect.signature(cls.set_drives).bind(None, {})
    inspect.signature(cls.save_state).bind(None)
    inspect.signature(cls.restore_state).bind(None, {})
    for method in ("drive_tags", "observables", "fields"):
        inspect.signature(getattr(cls, method)).bind(None)


def test_names_with_units():
    assert unnamed(["curvature [1/mm]", "stretch [-]", "T_mean bottom_strips [C]"]) == []
    assert unnamed(["curvature", "stretch[-]", "force [N] total", "[N]"]) == [
        "curvature",
        "stretch[-]",
        "force [N] total",
        "[N]",
    ]


def test_a_quasi_static_step_is_a_fraction_of_the_way():
    assert check_quasi_static_step(0.25) == 0.25 and check_quasi_static_step(1) == 1.0
    for bad in (0.0, -0.5, 1.5, float("nan")):
        with pytest.raises(InputError, match="0 < dt <= 1"):
            check_quasi_static_step(bad)


def test_bar_and_hinge_gridshell_as_a_problem():
    """The cheap instance (no solve): its observables carry units, its tags are accepted, a bad tag
    is refused by name, and restore_state undoes set_drives."""
    from lcefem.meshes.gridshell import build_gridshell_bar_hinge
    from lcefem.solvers.problems.gridshell_bh import GridshellBH, GridshellBHConfig

    g = GridshellBH(build_gridshell_bar_hinge(), GridshellBHConfig(support="rollers"))
    assert isinstance(g, Problem)
    obs = g.observables()
    assert obs and unnamed(obs) == []
    assert obs["circle kappa_x [1/mm]"] == pytest.approx(0.0, abs=1e-9)  # as built: flat
    assert unnamed(g.fields()) == []
    saved = g.save_state()
    g.set_drives({tag: 1.2 for tag in g.drive_tags()})
    assert g.lambda_of("top_strips") == pytest.approx(1.2)
    with pytest.raises(InputError, match="nowhere"):
        g.set_drives({"nowhere": 1.2})
    g.restore_state(saved)
    assert g.lambda_of("top_strips") == pytest.approx(g.lambda_N)
    # per-bar rest fractions (a recipe's P0): set as given, other groups kept; a bad group or size
    # is refused by name
    bars = g.lambda_of("top_strips").size
    fractions = np.linspace(0.7, 0.95, bars)
    g.set_rest_fractions({"top_strips": fractions})
    assert np.array_equal(g.lambda_of("top_strips"), fractions * g.lambda_N)
    assert g.lambda_of("bottom_strips") == pytest.approx(g.lambda_N)
    with pytest.raises(InputError, match="nowhere"):
        g.set_rest_fractions({"nowhere": fractions})
    with pytest.raises(InputError, match="top_strips"):
        g.set_rest_fractions({"top_strips": fractions[:-1]})


def test_fe_twisted_ribbon_as_a_problem():
    """An FE instance through the protocol alone: the fraction dt of the way to the drive set,
    restore_state brings back the saved equilibrium exactly, names carry units."""
    from lcefem.solvers.problems.twisted_ribbon import TwistedRibbonFE
    from tests.solvers.test_twisted_ribbon import LENGTH, THICKNESS, TWIST, WIDTH, hot_top, mesh

    ribbon = TwistedRibbonFE(LENGTH, WIDTH, THICKNESS, TWIST, hot_top, resolution=mesh())
    assert isinstance(ribbon, Problem)
    ribbon.set_drives({"body": 0.8})
    ribbon.advance(0.5, first=0.5)  # half the way from 0 to 0.8
    half = ribbon.observables()
    assert half["load fraction [-]"] == pytest.approx(0.4, abs=1e-15)
    assert unnamed(half) == [] and unnamed(ribbon.fields()) == []
    saved = ribbon.save_state()
    ribbon.advance(1.0, first=0.5)
    assert ribbon.observables()["load fraction [-]"] == pytest.approx(0.8, abs=1e-15)
    assert ribbon.observables()["stretch [-]"] != half["stretch [-]"]
    ribbon.restore_state(saved)
    assert ribbon.observables() == half
    with pytest.raises(InputError, match="'tip'"):
        ribbon.set_drives({"tip": 0.5})


def test_bar_and_hinge_specimen_as_a_problem_is_the_one_call_path():
    """KaptonSpecimenBH driven through the protocol reaches the force of solve_specimen_buckling
    (the same path follower, same steps) at 1 % compression; in two halves it reaches the same
    elastic equilibrium; restore_state goes back to the flat specimen."""
    from lcefem.solvers.problems.kapton_specimen_bh import KaptonSpecimenBH, solve_specimen_buckling

    one_call = solve_specimen_buckling(0.01)
    k = KaptonSpecimenBH()
    assert isinstance(k, Problem)
    flat = k.save_state()
    k.set_drives({"right_clamp": 0.01 * k.specimen.length})
    k.advance(1.0)
    obs = k.observables()
    assert unnamed(obs) == [] and unnamed(k.fields()) == []
    assert obs["compression [-]"] == pytest.approx(0.01, rel=1e-12)
    assert obs["force [N]"] == pytest.approx(one_call.force[-1], rel=1e-12)
    k.restore_state(flat)
    assert k.observables()["force [N]"] == 0.0
    k.set_drives({"right_clamp": 0.01 * k.specimen.length})
    k.advance(0.5)
    k.advance(1.0)
    assert k.observables()["force [N]"] == pytest.approx(one_call.force[-1], rel=1e-6)
    with pytest.raises(InputError, match="left_clamp|'left'"):
        k.set_drives({"left": 0.1})


def test_bar_and_hinge_beam_as_a_problem_is_the_one_call_path():
    """CompositeBeamBH driven through the protocol to the dome's lambdas (seed 001 Fig. 4C: 1.33
    top, 1.05 bottom) reaches the curvature of solve_beam (the same ramp, same steps); in two halves
    the same elastic equilibrium; restore_state goes back to the straight beam; a lambda out of
    [1, lambda_N] and an unknown tag are refused by name."""
    from lcefem.solvers.problems.composite_beam_bh import CompositeBeamBH, solve_beam

    one_call = solve_beam(1.33, 1.05)
    b = CompositeBeamBH()
    assert isinstance(b, Problem) and set(b.drive_tags()) == {"top_strips", "bottom_strips"}
    straight = b.save_state()
    assert b.observables()["curvature [1/mm]"] == pytest.approx(0.0, abs=1e-12)
    b.set_drives({"top_strips": 1.33, "bottom_strips": 1.05})
    b.advance(1.0)
    obs = b.observables()
    assert unnamed(obs) == [] and unnamed(b.fields()) == []
    assert obs["lambda top_strips [-]"] == 1.33 and obs["lambda bottom_strips [-]"] == 1.05
    assert obs["curvature [1/mm]"] == pytest.approx(one_call.curvature, rel=1e-12)
    b.restore_state(straight)
    b.set_drives({"top_strips": 1.33, "bottom_strips": 1.05})
    b.advance(0.5)
    assert b.observables()["lambda top_strips [-]"] == pytest.approx(0.5 * (b.lambda_N + 1.33))
    b.advance(1.0)
    assert b.observables()["curvature [1/mm]"] == pytest.approx(one_call.curvature, rel=1e-6)
    with pytest.raises(InputError, match=r"^lambda\[top_strips\] = 1.6"):
        b.set_drives({"top_strips": 1.6})
    with pytest.raises(InputError, match="'glue'"):
        b.set_drives({"glue": 1.2})


def test_der_rolling_ribbon_as_a_problem():
    """RollingRibbonDER (11 nodes): the plate's temperature is its drive, advance(dt) moves the
    clock by dt, the section heats towards the hot plate, and restore_state then the same advance
    reproduces the same state exactly (the whole simulation is saved)."""
    from lcefem.solvers.der.ribbon import RibbonNumerics
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, RollingRibbonDER

    r = RollingRibbonDER(RibbonConfig(numerics=RibbonNumerics(nodes=11, dt=0.02, settle_time=0.04)))
    assert isinstance(r, Problem)
    start = r.observables()
    assert unnamed(start) == [] and unnamed(r.fields()) == []
    r.set_drives({"plate": 120.0})
    saved = r.save_state()
    step = r.advance(0.04)
    assert isinstance(step, StepRecord) and step.at == step.observables["time [s]"]
    after = step.observables
    assert after["time [s]"] == pytest.approx(start["time [s]"] + 0.04, abs=1e-12)
    assert after["ground temperature [C]"] == 120.0
    assert after["T_max [C]"] > start["T_max [C]"]  # heat enters from the 120 C plate
    r.restore_state(saved)
    assert r.observables()["time [s]"] == start["time [s]"]
    assert r.advance(0.04) == step
    with pytest.raises(InputError, match="'air'"):
        r.set_drives({"air": 50.0})
    with pytest.raises(InputError, match=r"^ground temperature\[plate\] = 900"):
        r.set_drives({"plate": 900.0})


def test_the_ribbons_sections_are_defined_once():
    """RibbonConfig (the case file) and RibbonSetup (the simulation) take the physical sections
    from one definition (RibbonSections) and repeat none of them; the setup a config builds
    carries the config's own sections (the same objects)."""
    import dataclasses

    from lcefem.models.contact import FrictionLaw
    from lcefem.solvers.der.ribbon import RibbonSections, RibbonSetup
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, RibbonRun

    shared = {f.name for f in dataclasses.fields(RibbonSections)}
    assert len(shared) == 7
    own = {
        cls: {f.name for f in dataclasses.fields(cls)} - shared
        for cls in (RibbonConfig, RibbonSetup)
    }
    for cls in (RibbonConfig, RibbonSetup):
        assert issubclass(cls, RibbonSections)
        assert {n for n, v in vars(cls).get("__annotations__", {}).items()} == own[
            cls
        ]  # none redeclared
    assert set(RibbonConfig.SECTIONS) == {f.name for f in dataclasses.fields(RibbonConfig)}
    cfg = RibbonConfig(run=RibbonRun(ground_temperature=90.0), friction=FrictionLaw(mu=0.3))
    setup = cfg.setup()
    assert all(getattr(setup, n) is getattr(cfg, n) for n in shared)
    assert setup.ground_temperature == 90.0 and setup.blocks == ()
