"""docs/examples/strip_library.py, the library-use example of docs/library.md, runs at level 0 and
gives the physics it claims (it is the documentation's promise that the public API works)."""

import runpy

import pytest

from tests.conftest import REPO


def test_library_example_runs_at_level_0(tmp_path, capsys):
    example = runpy.run_path(str(REPO / "docs" / "examples" / "strip_library.py"))
    r = example["main"](level=0, out=tmp_path)
    # a free strip at a uniform spontaneous stretch takes exactly that length (homogeneous state)
    assert r["free strip stretch at lambda_s = 1.2 [-]"] == pytest.approx(1.2, rel=1e-8)
    # a linear stretch field 1.35 -> 1.25 along the strip: length = its mean (to the Q2
    # interpolation)
    assert r["free strip stretch, graded 1.35 -> 1.25 [-]"] == pytest.approx(1.30, rel=1e-3)
    # only the coil cells hot: the strip contracts, but far less than fully (bulk stays nematic)
    assert 1.3 < r["free strip stretch, coil at 90 C [-]"] < 1.426
    # held at the as-built length while the stretch drops: tension
    assert r["held strip force at lambda_s = 1.2 [N]"] > 0.0
    # the Kapton specimen's linearised buckling load: the golden value (tests/regression)
    assert r["Kapton specimen critical load [N]"] == pytest.approx(0.09576358958571224, rel=1e-6)
    assert (tmp_path / "kapton" / "displacement.bp").is_dir()
    assert "Kapton specimen critical load [N]" in capsys.readouterr().out


def test_prescribed_fields_refuse_bad_input():
    from lcefem.meshes.strip import StripMesh
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation

    sim = StripSimulation(StripConfig(run=StripRun(current=0.0), mesh=StripMesh(level=0)))
    with pytest.raises(InputError, match="spontaneous_stretch"):
        sim.set_spontaneous_stretch(2.0)
    with pytest.raises(InputError, match=r"temperature\['nope'\]"):
        sim.set_temperature({"nope": 50.0})
    with pytest.raises(InputError, match="drive 'lce'"):
        sim.set_drives({"lce": 0.1})
