"""`lcefem calibrate bar-hinge`: input checks, the parameter file, and the stored calibration."""

import json

import pytest

from lcefem.models.bar_hinge_materials import BarHingeMaterials
from lcefem.validation.app.cli import main as cli_main
from lcefem.validation.studies.gridshell import calibrate as cal


@pytest.mark.parametrize(
    "args, field",
    [
        (["--shapes", "dome,bowl"], "--shapes"),
        (["--parameters", "eta"], "--parameters"),
        (["--max-evaluations", "0"], "--max-evaluations"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, args, field):
    assert cli_main(["calibrate", "bar-hinge", *args, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and field in err[0]
    assert not (tmp_path / "o").exists()


def test_one_shape_fit_writes_the_parameter_file_with_residuals(tmp_path):
    # The table alone, the strip E I factor alone, one evaluation: the file holds the fitted value,
    # the residual per shape in units of the tolerance (the BH table with the strip element is
    # -0.0039 against the FE's -0.0045 1/mm: within 0.002) and the command.
    out = tmp_path / "cal"
    assert (
        cli_main(
            [
                "calibrate",
                "bar-hinge",
                "--shapes",
                "table",
                "--parameters",
                "strip_bending_factor",
                "--beam-points",
                "none",
                "--max-evaluations",
                "1",
                "--out",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    rec = json.loads((out / "bar_hinge_calibration.json").read_text())
    assert set(rec["parameters"]) == {"lce.bending_factor"}
    row = rec["fitted"]["shapes"]["table"]["circle_x"]
    assert row["FE [1/mm]"] == pytest.approx(-0.0045, abs=5e-5)
    assert row["residual [-]"] == pytest.approx((row["BH [1/mm]"] - row["FE [1/mm]"]) / 0.002)
    assert abs(row["residual [-]"]) <= 1.0
    assert rec["command"].startswith("lcefem calibrate bar-hinge") and rec["command"].endswith(
        "--twist plate"
    )
    assert rec["fixed"] == {"kapton.twist": "plate"}


def test_stored_calibration_applies_to_the_materials():
    rec = cal.load()
    assert rec is not None, (
        "validation/data/bar_hinge_calibration.json: run lcefem calibrate bar-hinge"
    )
    m = cal.calibrated_materials(rec, BarHingeMaterials())
    assert m.lce.bending_factor == rec["parameters"]["lce.bending_factor"]
    assert m.kapton.bending_factor == rec["parameters"]["kapton.bending_factor"]
    # the FE-equivalent BH: the plate's torsion of the Kapton panels (fixed, not fitted)
    assert rec["fixed"] == {"kapton.twist": "plate"} and m.kapton.twist == "plate"
    old = {k: v for k, v in rec.items() if k != "fixed"}  # a record from before kapton.twist
    assert cal.calibrated_materials(old).kapton.twist == "n5b8"
    for name, (section, fld, _, lo, hi) in cal.PARAMETERS.items():
        assert lo <= rec["parameters"][f"{section}.{fld}"] <= hi


def test_model_set_carries_the_configuration_it_was_fitted_in():
    # 'fe-calibrated' was fitted in calibrate.shape_setup's configuration (published glue squares +
    # contact + the constant-volume law, strip element 'beam'): the model set holds exactly that
    # structure and those materials, so design, bands and sequences run where it was fitted.
    import numpy as np

    from lcefem.meshes.composite_beam import BeamBarHingeMesh

    ms = cal.model_set("fe-calibrated")
    assert (ms.mesh.top_junction, ms.mesh.contact, ms.mesh.strip_element) == ("glue", True, "beam")
    assert ms.materials.lce.force_law == "volume"
    fitted = cal.shape_setup("saddle", cal.calibrated_materials(cal.load()))
    s = ms.structure()
    assert s.nodes.shape == fitted.structure.nodes.shape and np.array_equal(
        s.nodes, fitted.structure.nodes
    )
    for field in ("bars", "hinges", "contacts"):
        ours, theirs = getattr(s, field), getattr(fitted.structure, field)
        assert set(ours) == set(theirs) and all(np.array_equal(ours[k], theirs[k]) for k in ours)
    assert (
        "glue" in s.bars
        and len(s.info["strip_beams"]) == len(fitted.structure.info["strip_beams"]) > 0
    )
    m = fitted.model
    assert (m.kapton, m.lce, m.glue, m.ogden) == (
        ms.materials.kapton,
        ms.materials.lce,
        ms.materials.glue,
        ms.materials.ogden,
    )
    # 'published': the published elements and factors in the mesh's defaults (contracting squares)
    pub = cal.model_set("published")
    assert pub.mesh == BeamBarHingeMesh() and pub.materials == BarHingeMaterials()
    assert cal.model_set("fe-calibrated").configuration["mesh.top_junction"] == "glue"
    with pytest.raises(cal.InputError, match="model_set"):
        cal.model_set("bogus")
