"""Issue 45, cause 14: the library checks the inputs the command line checks (docs/failure_modes.md,
'The library's contract'): a time step, a stretch, a folder holding another run's results."""

import dataclasses

import dolfinx_solver  # noqa: F401  (before dolfinx/petsc4py)

import numpy as np
import pytest

from lcefem.models.errors import InputError
from lcefem.models.lce import NematicTransition, spontaneous_stretch, temperature_for_stretch
from lcefem.solvers.problems.strip import StripConfig, StripSimulation, run_strip
from lcefem.solvers.runtime.outdir import claim_out


def _small_strip() -> StripConfig:
    cfg = StripConfig()
    return dataclasses.replace(
        cfg,
        run=dataclasses.replace(cfg.run, duration=1.0, dt=0.5),
        mesh=dataclasses.replace(cfg.mesh, level=0),
    )


def test_temperature_for_stretch_is_the_inverse_inside_its_range_and_refuses_outside():
    tr = NematicTransition()
    for lam in (1.05, 1.2, tr.lambda_N):
        assert float(spontaneous_stretch(temperature_for_stretch(lam, tr), tr)) == pytest.approx(
            lam, rel=1e-12
        )
    for lam in (0.5, 1.0, 1.5, float("nan")):  # no temperature gives these (NaN or inf before)
        with pytest.raises(
            InputError, match=r"^stretch = .*: must be > 1 \(isotropic\) and < 1\.426"
        ):
            temperature_for_stretch(lam, tr)
    with pytest.raises(InputError):
        temperature_for_stretch(np.array([1.1, 0.9]), tr)


def test_strip_advance_refuses_a_step_that_is_not_forward_in_time():
    sim = StripSimulation(_small_strip())
    for dt in (-1.0, 0.0, float("nan"), 1e9):
        with pytest.raises(InputError, match=r"^dt = .*: must be"):
            sim.advance(dt)
    assert sim.time == 0.0  # time never moved


def test_run_strip_claims_its_folder_like_the_command_line(tmp_path):
    """A library run refuses a folder holding another run's results (or the user's files) and leaves
    it untouched; inside a folder its caller claimed (the command line, validate) it writes."""
    cfg = _small_strip()
    first = tmp_path / "first"
    run_strip(cfg, first, progress=False)
    before = {p.name: p.stat().st_mtime_ns for p in first.iterdir()}
    with pytest.raises(InputError, match="holds the results of another run"):
        run_strip(cfg, first, progress=False)
    assert {p.name: p.stat().st_mtime_ns for p in first.iterdir()} == before
    assert not (first / ".lcefem.lock").exists()
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine")
    with pytest.raises(InputError):
        run_strip(cfg, mine, progress=False)
    assert [p.name for p in mine.iterdir()] == ["notes.txt"]
    with claim_out(
        first, overwrite=True, command="library run"
    ):  # the caller's claim replaces them
        result = run_strip(cfg, first / "again", progress=False)
    assert (first / "again" / "summary.json").is_file() and result.summary["status"] == "completed"
