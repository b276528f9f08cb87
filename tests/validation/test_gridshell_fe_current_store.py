"""The FE current route's stored runs (validation.gridshell_fe_current_store) and the rows the case
gridshell_heated_fe makes of them: a required shape (dome, saddle) that is not stored, or was run
with a junction heating other than the default, is a failing row, never silence."""

import json
import math

from lcefem.solvers.problems.gridshell_heated import JUNCTION_HEATING_DEFAULT
from lcefem.validation.cases import gridshell_heated_fe
from lcefem.validation.cases.gridshell_heated_fe import _stored_current_route_rows
from lcefem.validation.studies.gridshell import gridshell_fe_current_store as store


def _summary(shape: str, level: int, heating: str) -> dict:
    return {
        "shape": shape,
        "mesh level": level,
        "support": "rollers",
        "current [A]": {},
        "current rule": "r",
        "held": {"kappa_circle_x [1/mm]": -0.01, "kappa_circle_y [1/mm]": -0.01},
        "cpu [s]": 1.0,
        "junction_heating": heating,
    }


def test_store_refuses_a_level_below_one_by_name(tmp_path, capsys):
    run = tmp_path / "run"
    run.mkdir()
    (run / "summary.json").write_text(json.dumps(_summary("dome", 0, JUNCTION_HEATING_DEFAULT)))
    assert store.main([str(run), "--out", str(tmp_path / "s.json")]) == 2
    assert "mesh level = 0" in capsys.readouterr().err
    assert not (tmp_path / "s.json").exists()


def test_missing_or_off_default_runs_are_failing_rows(tmp_path, monkeypatch):
    stored = tmp_path / store.STORE.name  # absolute: DATA_DIR / stored is stored
    monkeypatch.setattr(gridshell_heated_fe, "CURRENT_ROUTE_LEVEL1", str(stored))
    monkeypatch.setattr(gridshell_heated_fe, "JUNCTION_HEATING_DOME", str(tmp_path / "none.json"))
    rows = _stored_current_route_rows("c")  # no stored file at all
    missing = [r for r in rows if "not stored" in r.metric]
    assert {r.metric.split(" ")[0] for r in missing} == set(store.REQUIRED)
    assert all(r.passed is False and math.isnan(r.value) for r in missing)
    # a dome run with the junctions unheated ('off', not the default) is refused the same way
    stored.write_text(json.dumps({"runs": {"dome": _summary("dome", 1, "off")}}))
    rows = _stored_current_route_rows("c")
    dome = [r for r in rows if r.metric.startswith("dome")]
    assert len(dome) == 1 and dome[0].passed is False and "'off'" in dome[0].metric
