"""The rolling ribbon's convergence table (benchmarks/ribbon_convergence.py): the contact-sampling
lock rate and the table's relative changes."""

import csv
import json
import math

import pytest

from ribbon_convergence import lock_rate, table


def test_lock_rate_is_one_contact_section_per_step():
    # 60 mm, 0.05 turns/mm: 61 nodes with 0.25 mm sections (4 per 1 mm edge) and 31 nodes (8 per 2
    # mm edge) share the spacing, so the lock rate 2 pi 0.05 0.25 / 0.01 = 5 pi / 2 rad/s, the spin
    # of the locked runs
    assert lock_rate(61, 0.01, 0.25) == pytest.approx(2.5 * math.pi, rel=1e-12)
    assert lock_rate(31, 0.01, 0.25) == pytest.approx(2.5 * math.pi, rel=1e-12)
    assert lock_rate(61, 0.005, 0.25) == pytest.approx(5.0 * math.pi, rel=1e-12)
    # 2 sections per edge (contact_spacing 0): 0.5 mm at 61 nodes
    assert lock_rate(61, 0.01, 0.0) == pytest.approx(5.0 * math.pi, rel=1e-12)


def test_table_changes_against_half_step_and_finer_nodes(tmp_path):
    base = {
        "rolls": 1.0,
        "spin_rate_ratio [-]": 1.0,
        "twist_density_variation [-]": 0.01,
        "T_mean_final [C]": 100.0,
        "T": 140.0,
        "duration": 180.0,
        "contact_spacing": 0.25,
        "changes": ["numerics.cells_thickness=4"],
        "cpu": 1.0,
        "spin_rate_start [rad/s]": 2.5 * math.pi,
    }
    rows = [
        dict(base, nodes=61, dt=0.01, **{"average_speed [mm/s]": 11.0}),
        dict(base, nodes=61, dt=0.005, **{"average_speed [mm/s]": 10.0}),
        dict(base, nodes=101, dt=0.01, **{"average_speed [mm/s]": 12.1}),
    ]
    src = tmp_path / "rows.jsonl"
    src.write_text("".join(json.dumps(r) + "\n" for r in rows))
    out = tmp_path / "table.csv"
    table([src], out)
    got = {(int(r["nodes [-]"]), float(r["dt [s]"])): r for r in csv.DictReader(open(out))}
    r = got[(61, 0.01)]
    assert float(r["change against half the step [-]"]) == pytest.approx(0.1)
    assert float(r["change against the next node count [-]"]) == pytest.approx(
        11.0 / 12.1 - 1.0, rel=1e-5
    )
    assert float(r["spin rate over the sampling lock rate [-]"]) == pytest.approx(1.0, rel=1e-5)
    assert r["changes [-]"] == "numerics.cells_thickness=4"
