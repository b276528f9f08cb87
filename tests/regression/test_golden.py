"""Golden values: today's answers of every body at its coarse level, pinned to 1e-6 relative (issue
12, step 1), so that moving code between packages is proven not to change the physics.

Produced at commit 8dfa505 (branch main) with::

    OMP_NUM_THREADS=1 .venv/bin/python -m pytest tests/regression/test_golden.py

whose calls are the ones below (each value printed with repr()). A change of physics, numerics or
default parameters fails these tests on purpose: if the change is intended, say so in the commit and
re-pin the numbers with the commit that produced them.
"""

import numpy as np
import pytest

RTOL = 1e-6


def _strip_history(bc: str) -> dict:
    """0.2 A, two backward-Euler steps of 2 s, level-0 hexahedral quarter model (the case file
    defaults otherwise)."""
    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation

    cfg = StripConfig(
        run=StripRun(current=0.2, duration=4.0, dt=2.0, bc=bc), mesh=StripMesh(level=0)
    )
    return StripSimulation(cfg).run(None, progress=False, fields=False).history


@pytest.mark.slow
def test_free_strip_transient_at_4s():
    h = _strip_history("free")
    assert h["time [s]"][-1] == 4.0
    assert h["T_mean [C]"][-1] == pytest.approx(41.7024646905809, rel=RTOL)
    assert h["T_max [C]"][-1] == pytest.approx(73.41764080373773, rel=RTOL)
    assert h["T_surface [C]"][-1] == pytest.approx(34.64940216609055, rel=RTOL)
    assert h["stretch [-]"][-1] == pytest.approx(1.406548927529679, rel=RTOL)


@pytest.mark.slow
def test_held_strip_force_at_4s():
    h = _strip_history("held")
    assert h["force [N]"][-1] == pytest.approx(0.05019849503625013, rel=RTOL)
    assert h["T_mean [C]"][-1] == pytest.approx(41.70493470984347, rel=RTOL)
    assert h["T_max [C]"][-1] == pytest.approx(73.31766744753268, rel=RTOL)
    assert h["stretch [-]"][-1] == pytest.approx(1.426, rel=RTOL)  # held at the nematic length


def test_kapton_specimen_buckling_load_bar_and_hinge():
    """Default N5B8 chain (32 panels): critical force [N] and end shortening [mm] (bisection to
    1e-4, deterministic)."""
    from lcefem.solvers.problems import kapton_specimen_bh as kapton_bh

    force, shortening = kapton_bh.critical_load()
    assert force == pytest.approx(0.18550571425277032, rel=RTOL)
    assert shortening == pytest.approx(0.0028043701171874998, rel=RTOL)


@pytest.mark.slow
def test_kapton_specimen_buckling_load_fe():
    """Level-0 Q2 specimen, linearised buckling (SLEPc): critical force [N] and end shortening
    [mm]."""
    from lcefem.meshes.kapton_ribbon import KaptonFEMesh, KaptonSpecimenGeometry
    from lcefem.solvers.problems.kapton_specimen import KaptonSpecimenFE

    crit = KaptonSpecimenFE(KaptonSpecimenGeometry(), KaptonFEMesh(level=0)).critical_load()
    assert crit.force == pytest.approx(0.09576358958571224, rel=RTOL)
    assert crit.shortening == pytest.approx(0.001538707305994088, rel=RTOL)


def test_composite_beam_bar_and_hinge_at_1p33_1p05():
    """Default 4-segment beam ramped to (lambda_T, lambda_B) = (1.33, 1.05): curvature [1/mm],
    bottom strip force [N] (two strips), and the number of path states (the step controller's
    trace)."""
    from lcefem.solvers.problems import composite_beam_bh as beam_bh

    sol = beam_bh.solve_beam(1.33, 1.05)
    forces = sol.model.bar_forces(sol.path.states[-1].x)
    assert sol.curvature == pytest.approx(0.03859300813998696, rel=RTOL)
    assert 2.0 * float(np.mean(forces["bottom_strips"])) == pytest.approx(
        0.0951843559313803, rel=RTOL
    )
    assert len(sol.path.states) == 13


@pytest.mark.slow
def test_composite_beam_fe_at_1p33_1p05():
    """Level-0 quarter model with 2 segments (the 4-segment beam takes 90 s; 2 segments run the same
    mesh builder, actuation, contact and path follower in 19 s): curvature [1/mm]."""
    from lcefem.meshes.composite_beam import CompositeBeamGeometry
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems.composite_beam import BeamFE

    beam = BeamFE(geometry=CompositeBeamGeometry(segments=2), mesh=BeamFEMesh(level=0))
    beam.ramp(1.33, 1.05)
    assert beam.curvature() == pytest.approx(0.024660446562042634, rel=RTOL)
    assert beam.contact_force() == 0.0


def test_twisted_ribbon_der_static_twist():
    """DER twisted LCE ribbon (20 mm, 0.05 turns/mm, 41 nodes), faces at 80 C and 60 C: mean twist
    density [rad/mm], curvature towards m2 [1/mm] and length [mm]."""
    from lcefem.models.ribbon import RibbonGeometry
    from lcefem.solvers.der.ribbon import ribbon_static_response

    res = ribbon_static_response(
        RibbonGeometry(length=20.0, twist_density=0.05), 41, face_temperatures=(80.0, 60.0)
    )
    assert res.mean_twist_density == pytest.approx(0.24438248174822658, rel=RTOL)
    assert res.mean_curvature[1] == pytest.approx(0.3096889942203144, rel=RTOL)
    assert res.mean_curvature[0] == pytest.approx(0.0, abs=1e-9)
    assert res.length == pytest.approx(16.811707027371263, rel=RTOL)
