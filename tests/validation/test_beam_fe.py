"""3D FE Kapton specimen and composite beam (solvers/problems/kapton_specimen.py, composite_beam.py)
against closed forms and each other, and their command lines. Coarse meshes: each test runs in
seconds."""

import json
import math
import subprocess

import pytest

from lcefem.meshes.kapton_ribbon import KaptonFEMesh, KaptonSpecimenGeometry
from lcefem.validation.app.cli import main

SPEC = KaptonSpecimenGeometry()
E, NU = 2500.0, 0.34


@pytest.fixture(scope="module")
def ribbon():
    from lcefem.solvers.problems.kapton_specimen import KaptonSpecimenFE

    return KaptonSpecimenFE(SPEC, KaptonFEMesh(level=0))


def test_ribbon_axial_stiffness_between_uniaxial_and_laterally_clamped(ribbon):
    """Small end shortening of the straight specimen: stiffer than the free uniaxial bar E A/L (the
    clamps also hold the lateral contraction), softer than the laterally constrained strip
    E A/((1 - nu^2) L)."""
    k = ribbon.axial_stiffness(1e-4 * SPEC.length)
    ea_l = E * SPEC.width * SPEC.thickness / SPEC.length
    assert ea_l < k < ea_l / (1 - NU**2)
    assert k == pytest.approx(ea_l, rel=0.02)  # the clamps' influence reaches ~W from each end


def test_ribbon_critical_load_between_beam_and_plate_euler_loads(ribbon):
    """Linearised buckling of the clamped strip: between 4 pi^2 E I/L^2 and 4 pi^2 E
    I/((1-nu^2)L^2); the first mode is the symmetric fixed-fixed mode (largest deflection at
    mid-span)."""
    crit = ribbon.critical_load()
    euler = 4 * math.pi**2 * E * SPEC.second_moment / SPEC.length**2
    assert euler < crit.force < euler / (1 - NU**2)
    assert crit.secant_change < 1e-4
    w = crit.mode.x.array.reshape(-1, 3)[:, 2]
    X = crit.mode.function_space.tabulate_dof_coordinates()
    mid = abs(X[:, 0] - 0.5 * SPEC.length) < 1e-9
    assert abs(w[mid]).max() == pytest.approx(1.0)
    assert abs(w[abs(X[:, 0] - 0.25 * SPEC.length) < 1e-9]).max() == pytest.approx(0.5, abs=0.05)


def _beam(symmetry: str):
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems.composite_beam import BeamFE, PathControl

    return BeamFE(
        mesh=BeamFEMesh(level=0, symmetry=symmetry),
        control=PathControl(first_step=0.25, max_step=0.5),
    )


def test_beam_bends_towards_the_shorter_strips_and_symmetry_is_consistent():
    """Contracting the bottom strips by 1 % bends the beam towards them (positive curvature, Eq. 2's
    sign), contracting the top ones bends it the other way; the quarter model (two symmetry planes)
    and the half model (isostatic supports) give the same curvature."""
    lam_n = 1.4
    quarter = _beam("quarter")
    quarter.ramp(lam_n, 0.99 * lam_n)
    k_bottom = quarter.curvature()
    quarter.ramp(0.99 * lam_n, lam_n)
    k_top = quarter.curvature()
    assert k_bottom > 1e-4 and k_top < -1e-4
    half = _beam("half")
    half.ramp(lam_n, 0.99 * lam_n)
    assert half.curvature() == pytest.approx(k_bottom, rel=1e-3)
    assert half.contact_force() == quarter.contact_force() == 0.0


def test_curvature_map_sweep_equals_ramps_from_the_as_built_state():
    """curvature_map_fe continues each grid point from its neighbour with a larger first increment
    (NEIGHBOUR_FIRST_STEP): the swept curvatures are those of ramps from the as-built state
    (2-segment level-0 beam, grid {0.98, 1} lambda_N)."""
    from lcefem.meshes.composite_beam import CompositeBeamGeometry
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems.composite_beam import BeamFE, curvature_map_fe

    lam_n = 1.4
    geometry = CompositeBeamGeometry(segments=2)
    grid = [0.98 * lam_n, lam_n]
    kappa, stats, _ = curvature_map_fe(grid, geometry=geometry, mesh=BeamFEMesh(level=0))
    assert stats["points"] == 4
    for i, j in ((1, 0), (0, 1)):
        direct = BeamFE(geometry=geometry, mesh=BeamFEMesh(level=0))
        direct.ramp(grid[i], grid[j])
        assert kappa[i, j] == pytest.approx(direct.curvature(), rel=1e-6)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["beam", "--model", "fe", "--lambda-top", "0.5"], "run.lambda_top = 0.5"),
        (["beam", "--mesh-level", "1"], "--mesh-level: only with --model fe"),
        (["beam", "--model", "fe", "--mesh-level", "-1"], "mesh.level = -1"),
        (["ribbon-buckling", "--model", "fe", "--compression", "2"], "run.compression = 2.0"),
    ],
)
def test_bad_input_exits_2(argv, message, capsys, tmp_path):
    code = main(["run", *argv, "--quiet", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert message in err
    assert len(err.strip().splitlines()) == 1


def test_beam_fe_run_end_to_end(tmp_path, lcefem_cmd):
    cfg = tmp_path / "case.toml"
    cfg.write_text("[mesh]\nlevel = 0\n[path]\nfirst_step = 0.5\nmax_step = 0.5\n")
    out = tmp_path / "beam"
    proc = subprocess.run(
        [
            *lcefem_cmd,
            "run",
            "beam",
            "--model",
            "fe",
            "--lambda-top",
            "1.4",
            "--lambda-bottom",
            "1.39",
            "--config",
            str(cfg),
            "--out",
            str(out),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    names = {p.name for p in out.iterdir()}
    assert {
        "history.csv",
        "displacement.bp",
        "beam_fe.png",
        "beam_fe_3d.png",
        "summary.json",
    } <= names
    assert not any(".part" in n for n in names)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["model"] == "fe" and summary["results"]["curvature [1/mm]"] > 0
    assert summary["config"]["mesh"]["level"]["value"] == 0


def test_ribbon_fe_run_end_to_end(tmp_path, lcefem_cmd):
    out = tmp_path / "ribbon"
    proc = subprocess.run(
        [
            *lcefem_cmd,
            "run",
            "ribbon-buckling",
            "--model",
            "fe",
            "--compression",
            "0.02",
            "--mesh-level",
            "0",
            "--out",
            str(out),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    names = {p.name for p in out.iterdir()}
    assert {"history.csv", "displacement.bp", "ribbon_buckling.png", "summary.json"} <= names
    r = json.loads((out / "summary.json").read_text())["results"]
    assert (
        r["Euler, E I (datasheet E) [N]"]
        < r["critical load [N]"]
        < r["Euler, plate strip E I/(1 - nu^2) [N]"]
    )
    # just past buckling the force stays within a few per cent of the critical load
    assert r["force at final compression [N]"] == pytest.approx(r["critical load [N]"], rel=0.1)


def test_heated_beam_early_heating_is_adiabatic_and_bends_towards_the_heated_strips():
    """Coil current through the top strips (heat model driving the FE beam): in the first second the
    strips' mean temperature rises by q/(rho c) (adiabatic: convection and conduction into the pads
    remove a few per cent; 5 % tolerance), the unheated bottom strips stay at 25 C, and the
    contracting top strips bend the beam towards them (negative curvature)."""
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.models.heat import ThermalProperties
    from lcefem.solvers.problems.composite_beam import HeatedBeamRun
    from lcefem.solvers.problems.composite_beam_run import beam_fe_heated

    model, rows, _ = beam_fe_heated(
        HeatedBeamRun(current=0.2, heated="top", duration=2.0, dt=1.0), mesh=BeamFEMesh(level=0)
    )
    thermal = ThermalProperties()
    rate = model.heat.power_density.value / (thermal.density * thermal.specific_heat)  # [K/s]
    assert rows[1]["T_mean top_strips [C]"] - 25.0 == pytest.approx(rate * 1.0, rel=0.05)
    assert rows[2]["T_mean bottom_strips [C]"] == pytest.approx(25.0, abs=1e-3)
    assert rows[2]["curvature [1/mm]"] < -1e-5


def test_beam_drives_are_addressed_by_strip_tag():
    """The FE beams take drives per strip tag (as the gridshell): lambda per tag for BeamFE, current
    per heated tag for HeatedBeamFE; unknown tags and lambdas outside [1, lambda_N] are refused by
    name."""
    from lcefem.meshes.composite_beam import CompositeBeamGeometry
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems.composite_beam import BeamFE, HeatedBeamFE

    geometry, mesh = CompositeBeamGeometry(segments=2), BeamFEMesh(level=0)
    beam = BeamFE(geometry, mesh)
    beam.set_drives({"bottom_strips": 1.05})
    assert beam.target == {"top_strips": beam.actuation.lambda_N, "bottom_strips": 1.05}
    with pytest.raises(InputError, match="drive 'kapton'"):
        beam.set_drives({"kapton": 1.2})
    with pytest.raises(InputError, match=r"lambda\[top_strips\] = 1.6"):
        beam.set_drives({"top_strips": 1.6})
    assert set(beam.observables()) >= {"curvature [1/mm]", "contact force [N]"}
    heated = HeatedBeamFE(("top_strips", "bottom_strips"), geometry, mesh)
    with pytest.raises(InputError, match="one power density"):
        heated.set_drives({"top_strips": 0.2, "bottom_strips": 0.1})
    heated.set_drives({"top_strips": 0.2, "bottom_strips": 0.2})
    assert heated.current == 0.2


def test_critical_load_from_a_coarser_mesh_needs_one_secant_step(ribbon):
    """ribbon_buckling_fe starts the finer mesh's buckling analysis at the coarser mesh's critical
    shortening: one secant step gives the load that two from the Euler estimate give."""
    from lcefem.solvers.problems.kapton_specimen import KaptonSpecimenFE

    coarse = ribbon.critical_load()
    again = KaptonSpecimenFE(SPEC, KaptonFEMesh(level=0)).critical_load(
        secant_steps=1, start=coarse.shortening
    )
    assert again.force == pytest.approx(coarse.force, rel=1e-6)
