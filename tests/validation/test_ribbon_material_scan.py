"""The one-parameter ribbon material scan (benchmarks/ribbon_material_scan.py): its input checks
and the CSV it writes from the JSON rows."""

import json

import ribbon_material_scan as scan


def test_bad_point_exits_2(tmp_path, capsys):
    assert scan.main(["--out", str(tmp_path / "r.jsonl"), "numerics.nodes=31"]) == 2
    assert "material.field=value" in capsys.readouterr().err
    assert scan.main(["--table", str(tmp_path / "r.jsonl")]) == 2  # no --csv


def test_table_names_the_changed_parameter(tmp_path):
    row = {
        "average_speed [mm/s]": 4.818,
        "rolls": 1.0,
        "spin_rate_ratio [-]": 1.0,
        "twist_density_variation [-]": 0.0113,
        "T_mean_final [C]": 51.07,
        "T": 65.0,
        "nodes": 61,
        "dt": 0.005,
        "duration": 120.0,
        "cpu": 64.3,
        "changes": [
            "numerics.cells_thickness=4",
            "numerics.perturbation=1.0",
            "material.actuation_stretch=1.75",
        ],
    }
    rows = tmp_path / "r.jsonl"
    rows.write_text(json.dumps(row) + "\n")
    csv = tmp_path / "scan.csv"
    scan.table([rows], csv)
    header, line = csv.read_text().splitlines()
    assert "plate temperature [C]" in header and "average speed [mm/s]" in header
    f = line.split(",")
    assert f[:4] == ["actuation_stretch", "1.75", "-", "65.0"]
    assert float(f[7]) == 1.0 and float(f[8]) == 4.818
