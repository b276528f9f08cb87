"""The stored FE of the layouts at the full ramp (validation/data/
gridshell_fe_layouts_full_ramp_level0.json, benchmarks/gridshell_fe_layouts_full_ramp.py) and the
rows of the case gridshell_bh_vs_fe it feeds: the tenth-ramp rows at both levels, the full-ramp
5 x 5 (its bar-and-hinge run takes minutes) at the full level only (issue 47)."""

from __future__ import annotations

import json

import pytest

from lcefem.validation.cases import CaseContext
from lcefem.validation.cases import gridshell_bh_vs_fe as case


def test_the_full_ramp_data_file_is_complete():
    ref = json.loads(case.FE_LAYOUTS_FULL.read_text())
    assert ref["fraction"] == 1.0
    assert {r["layout"]: r["support"] for r in ref["rows"]} == {
        "5x5": "rollers",
        "rhombic60": "clamp",
    }
    assert {r["layout"]: r["symmetry"] for r in ref["rows"]} == {
        "5x5": "quarter",
        "rhombic60": "full",
    }
    for key in ("circle_x", "circle_y", "quad_x", "quad_y", "z_range", "dofs", "cpu"):
        assert key in ref["units"]
    for r in ref["rows"]:
        # a dome: both circle curvatures negative, equal on the 5 x 5 by its symmetry
        assert r["circle_x"] < 0 and r["circle_y"] < 0
        assert r["cpu"] > 0 and r["dofs"] > 0
    five = next(r for r in ref["rows"] if r["layout"] == "5x5")
    assert five["circle_x"] == pytest.approx(five["circle_y"], rel=1e-6)
    assert "benchmarks/gridshell_fe_layouts_full_ramp.py" in ref["source"]


@pytest.mark.parametrize("quick", [True, False])
def test_full_level_only_rows_are_left_to_the_full_level(monkeypatch, tmp_path, quick):
    seen = []
    monkeypatch.setattr(
        case,
        "_layout_rows",
        lambda name, ref, rows: seen.extend((ref["fraction"], r["layout"]) for r in rows) or [],
    )
    case._layouts(CaseContext(tmp_path, quick=quick), "gridshell_bh_vs_fe")
    tenth = {lay for f, lay in seen if f != 1.0}
    full = {lay for f, lay in seen if f == 1.0}
    assert tenth == {"published", "5x5", "rhombic60"}  # kept as they are at both levels
    assert full == ({"rhombic60"} if quick else {"5x5", "rhombic60"})


def test_the_reach_designs_fe_rows_are_informative_with_the_bh_as_reference():
    from lcefem.validation.cases import gridshell_reach_study_bh as reach

    rows = reach.fe_confirmation("gridshell_reach_study_bh")
    ref = json.loads(reach.FE_DESIGNS.read_text())
    assert [r.metric.split(":")[0] for r in rows] == ["gaussian bump", "two-wave"]
    for m, row in zip(rows, ref["rows"]):
        assert m.passed is None and m.reference == row["BH RMS [mm]"] and m.unit == "mm"
        assert m.value == row["FE RMS [mm]"] > 0
        # the FE ran the mirror means on the quarter: the BH of those drives is within 0.02 mm of
        # the design's (measured 0.016 and 0.001 mm)
        assert row["FE symmetry"] == "quarter" and row["symmetrized"]
        drift = abs(
            row["BH RMS from as built, symmetrized drives [mm]"]
            - row["BH RMS from as built, design drives [mm]"]
        )
        assert drift < 0.02


def test_a_symmetric_fe_row_judges_the_bh_families_by_their_bending_not_by_x_and_y(monkeypatch):
    # The rhombic BH dome bifurcates at t = 0.670 and which family bends more is set by round-off
    # (docs/layouts/rhombic.md): the same BH state with x and y exchanged gives the same rows.
    import lcefem.solvers.problems.gridshell_bh as gbh

    ref = json.loads(case.FE_LAYOUTS_FULL.read_text())
    row = next(r for r in ref["rows"] if r["layout"] == "rhombic60")
    assert case._mirror_symmetric(row)
    assert not case._mirror_symmetric({"circle_x": -0.012, "circle_y": -0.019})

    def rows_for(kx, ky):
        class Fake:
            def __init__(self, *args, **kwargs):
                pass

            def set_drives(self, lambdas):
                pass

            def advance(self):
                pass

            def observables(self):
                return {"circle kappa_x [1/mm]": kx, "circle kappa_y [1/mm]": ky}

        monkeypatch.setattr(gbh, "GridshellBH", Fake)
        out = case._layout_rows("gridshell_bh_vs_fe", ref, [row])
        return {m.metric: (m.value, m.passed) for m in out if "circle" in m.metric}

    a, b = rows_for(-0.01945, -0.01211), rows_for(-0.01211, -0.01945)
    assert a == b
    label = "rhombic60 dome (clamp, full ramp): circle kappa, {} bent family, BH vs FE"
    assert a[label.format("more")][0] == -0.01945 and a[label.format("less")][0] == -0.01211
