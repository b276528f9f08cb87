"""The output space-mapping update (validation.studies.design.space_mapping) on linear toy models
with closed forms: no FE, no bar-and-hinge."""

from __future__ import annotations

import numpy as np
import pytest

from lcefem.models.errors import InputError
from lcefem.validation.studies.design import gridshell_reach_study as rs
from lcefem.validation.studies.design.space_mapping import output_space_map, rms

RNG = np.random.default_rng(3)
A = RNG.normal(size=(6, 3))  # a linear "surface" of 3 drives at 6 points [mm per unit drive]
T = RNG.normal(size=6)  # the target [mm]
C = RNG.normal(size=6)  # the fine model's constant offset from the coarse one [mm]


def coarse(d):
    return A @ d - T


def fine(d):
    return A @ d - T + C


def redesign(d_start, gap):
    # the coarse model's least-squares design for the corrected target T - gap (closed form)
    d, *_ = np.linalg.lstsq(A, T - gap, rcond=None)
    return d, rms(coarse(d) + gap)


def test_a_constant_model_gap_is_corrected_in_one_iteration():
    d0, *_ = np.linalg.lstsq(A, T, rcond=None)  # the coarse design
    steps, best = output_space_map(d0, fine, coarse, redesign, max_fine=3)
    # the fine model's own optimum, min_d |A d - (T - C)|: the closed form the first correction
    # must reach
    d_star, *_ = np.linalg.lstsq(A, T - C, rcond=None)
    np.testing.assert_allclose(steps[0].gap, C, atol=1e-12)
    np.testing.assert_allclose(steps[1].design, d_star, atol=1e-12)
    assert steps[1].fine_rms == pytest.approx(rms(fine(d_star)), abs=1e-12)
    assert steps[1].fine_rms < steps[0].fine_rms
    # zeroth-order consistency: the corrected coarse RMS the design was made for is the fine RMS
    assert steps[1].coarse_rms == pytest.approx(steps[1].fine_rms, abs=1e-12)
    # the second correction finds the same design: the fine RMS stops falling, the loop stops
    # after its third fine evaluation and keeps the first corrected design
    assert len(steps) == 3 and best == 1
    assert steps[0].coarse_rms is None


def test_the_loop_stops_at_max_fine_and_refuses_zero():
    d0 = np.zeros(3)
    steps, best = output_space_map(d0, fine, coarse, redesign, max_fine=1)
    assert len(steps) == 1 and best == 0
    with pytest.raises(InputError, match="max_fine"):
        output_space_map(d0, fine, coarse, redesign, max_fine=0)


def test_the_rigid_residual_offset_is_the_corrected_target():
    # a target lowered by D at the points (T - D) leaves the residual + D before the plane fit;
    # a planar D is removed by the rigid fit
    pts = np.column_stack([RNG.uniform(-50, 50, 9), RNG.uniform(-50, 50, 9), RNG.normal(size=9)])
    z = rs.TARGETS["gaussian bump"][0]
    d = RNG.normal(size=9)
    r0, r1 = rs.rigid_residual(pts, z), rs.rigid_residual(pts, z, d)
    xy = pts[:, :2] - pts[:, :2].mean(axis=0)
    basis = np.column_stack([np.ones(9), xy])
    proj = basis @ np.linalg.lstsq(basis, d, rcond=None)[0]
    np.testing.assert_allclose(r1 - r0, d - proj, atol=1e-12)
    np.testing.assert_allclose(rs.rigid_residual(pts, z, 1.0 + 0.1 * xy[:, 0]), r0, atol=1e-12)


def test_the_fe_corrected_designs_are_judged_rows_within_1_mm():
    import json

    from lcefem.validation.cases import gridshell_reach_study_bh as reach

    rows = reach.fe_corrected("gridshell_reach_study_bh")
    ref = json.loads(reach.FE_CORRECTED.read_text())
    before = json.loads(reach.FE_DESIGNS.read_text())["rows"]
    assert [r.metric.split(":")[0] for r in rows] == ["gaussian bump", "two-wave"]
    for m, row, old in zip(rows, ref["rows"], before):
        fe = [it["FE RMS to T [mm]"] for it in row["iterations"]]
        assert 1 <= len(fe) <= 3 and row["best iteration"] == int(np.argmin(fe))
        assert m.value == row["FE RMS [mm]"] == min(fe)
        # iteration 0 is the stored uncorrected design, rerun: the same FE answer (measured to
        # 3e-12 mm)
        assert (
            row["iterations"][0]["lambda per BH strip id [-]"] == old["lambda per BH strip id [-]"]
        )
        assert fe[0] == pytest.approx(old["FE RMS [mm]"], abs=1e-9)
        assert row["start FE RMS [mm]"] == fe[0]
        # judged against issue 47's 1 mm, pass or fail (measured 0.683 and 0.618 mm: both pass)
        assert m.reference == 0.0 and m.tolerance == reach.REACH_MM
        assert m.passed is (m.value <= reach.REACH_MM)
        assert m.passed
        assert all(it["FE symmetry"] == "quarter" for it in row["iterations"])
