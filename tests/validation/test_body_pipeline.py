"""The pipeline for a user's body: `lcefem converge --config` (observed order of the bilayer
example) and `[[compare]]` entries (a closed form passes, a shifted one fails with exit 1; bad
entries exit 2 before any mesh is built)."""

import csv
import json
import math
import shutil
import subprocess

import pytest

from tests.conftest import REPO
from tests.validation.test_body_gallery import timoshenko_curvature

BILAYER = REPO / "examples" / "bodies" / "bilayer"
STRIP = REPO / "examples" / "bodies" / "strip"


def run(cmd, *args):
    return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=1200)


def bilayer_case(folder, size_factor: float, extra: str = "") -> str:
    shutil.copy(BILAYER / "bilayer.geo", folder / "bilayer.geo")
    text = (
        (BILAYER / "case.toml")
        .read_text()
        .replace("size_factor = 1.0", f"size_factor = {size_factor}")
    )
    (folder / "case.toml").write_text(text + extra)
    return str(folder / "case.toml")


def test_converge_bilayer_observed_order(tmp_path, lcefem_cmd):
    """Three levels from size factor 2 (20, 160, 1280 Q2 hexahedra). Measured (this study):
    the top tip's deflection u_z converges with observed order p = 3.98 and its axial displacement
    with p = 3.73 (Q2: between h^3, the L2 order, and h^4, nodal superconvergence); the temperature
    (uniform, adiabatic) is mesh-independent, and u_y (zero on the mirror plane y = 0, round-off)
    too. Tolerance 0.3 on p: the two tip orders' spread (0.25) plus a margin."""
    case = bilayer_case(tmp_path, 2.0)
    out = tmp_path / "study"
    res = run(
        lcefem_cmd, "converge", "--config", case, "--levels", "3", "--out", str(out), "--quiet"
    )
    assert res.returncode == 0, res.stderr
    for name in (
        "levels.csv",
        "gci.csv",
        "gci_by_time.csv",
        "convergence.json",
        "convergence.png",
        "report.md",
    ):
        assert (out / name).is_file(), name
    study = {m["metric"]: m for m in json.loads((out / "convergence.json").read_text())["metrics"]}
    assert study["u_z tip_top"]["p"] == pytest.approx(3.98, abs=0.3)
    assert study["u_x tip_top"]["p"] == pytest.approx(3.73, abs=0.3)
    assert study["u_z tip_top"]["gci_fine"] < 1e-5  # measured 8.4e-7
    assert "mesh-independent" in study["T_mean"]["flags"]
    assert "mesh-independent" in study["u_y tip_top"]["flags"]
    with open(out / "levels.csv") as fh:
        header = next(csv.reader(fh))
    assert "u_z tip_top [mm]" in header and "mesh size [-]" in header


def measured_tip_deflection() -> float:
    """The bottom tip's deflection [mm] of a Timoshenko bimorph of the bilayer (strain -0.0100 at
    47.21 C, equal layers): w = -(1 - cos(kappa L)) / |kappa| over the half length L = 20 mm."""
    from lcefem.models.lce import NematicTransition, contraction_ratio

    strain = contraction_ratio(47.21, NematicTransition()) - 1.0
    kappa = timoshenko_curvature(strain, 0.5, 0.5, 1.0, 1.0)
    return -(1.0 - math.cos(kappa * 20.0)) / abs(kappa)


COMPARE = """
[[compare]]
observable = "u_z tip_bottom [mm]"
data = "measured.csv"
tolerance = "3 %"
source = "Timoshenko's bimorph (J. Opt. Soc. Am. 11, 233, 1925), as a test's closed form"
"""


@pytest.mark.parametrize(
    "shift, code", [(1.0, 0), (1.10, 1)], ids=["closed-form-passes", "shifted-fails"]
)
def test_compare_with_a_closed_form(tmp_path, lcefem_cmd, shift, code):
    """The bilayer's tip deflection against Timoshenko's, written in um (converted to mm). Measured:
    the body gives -2.934 mm, the closed form -2.978 mm (1.5 %: the beam theory against the 3D
    finite-strain body, see test_bilayer_curvature_is_timoshenkos), so 3 % passes and the closed
    form shifted by 10 % fails with exit 1."""
    w = measured_tip_deflection() * shift * 1e3  # um
    (tmp_path / "measured.csv").write_text(f"time [s],u_z tip_bottom [um]\n0.0,{w}\n1.0,{w}\n")
    case = bilayer_case(tmp_path, 1.0, COMPARE)
    out = tmp_path / "out"
    res = run(
        lcefem_cmd, "run", "body", "--config", case, "--out", str(out), "--quiet", "--no-fields"
    )
    assert res.returncode == code, res.stdout + res.stderr
    summary = json.loads((out / "summary.json").read_text())
    (row,) = summary["comparisons"]
    assert row["passed"] is (code == 0)
    assert row["reference"] == pytest.approx(w * 1e-3)  # in mm
    assert row["value"] == pytest.approx(-2.934, abs=0.002)
    report = (out / "report.md").read_text()
    assert ("| pass |" if code == 0 else "| FAIL |") in report
    assert (out / "compare_u_z_tip_bottom_mm.png").is_file()


GOOD = (
    (STRIP / "case.toml").read_text()
    + """
[[compare]]
observable = "T_max coil [C]"
data = "measured.csv"
tolerance = "2 K"
source = "a test"
"""
)


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            '"T_max coil [C]"',
            '"T_max heater [C]"',
            "[[compare]][0].observable: 'T_max heater [C]' is not an observable",
        ),
        (
            'tolerance = "2 K"',
            'tolerance = "2 mm"',
            "[[compare]][0].tolerance: '2 mm': unit 'mm'; allowed % or C, K",
        ),
        ('tolerance = "2 K"', 'tolerance = "two"', "[[compare]][0].tolerance: 'two': allowed"),
        (
            'data = "measured.csv"',
            'data = "mm.csv"',
            "[[compare]][0].data: mm.csv: column 'T [mm]': unit 'mm'",
        ),
        (
            'data = "measured.csv"',
            'data = "nounit.csv"',
            "[[compare]][0].data: nounit.csv: column 'T': unit 'missing'",
        ),
        (
            'data = "measured.csv"',
            'data = "absent.csv"',
            "[[compare]][0].data: absent.csv: file not found",
        ),
        ('source = "a test"', '', "[[compare]][0].source: missing"),
    ],
    ids=[
        "unknown-observable",
        "tolerance-unit",
        "tolerance-text",
        "data-unit",
        "data-no-unit",
        "data-missing",
        "no-source",
    ],
)
def test_bad_compare_entry_exit_2(tmp_path, lcefem_cmd, old, new, message):
    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    (tmp_path / "measured.csv").write_text("time [s],T [K]\n0,298.15\n20,330\n")
    (tmp_path / "mm.csv").write_text("time [s],T [mm]\n0,1\n")
    (tmp_path / "nounit.csv").write_text("time [s],T\n0,1\n")
    assert old in GOOD
    (tmp_path / "case.toml").write_text(GOOD.replace(old, new, 1))
    out = tmp_path / "out"
    res = run(lcefem_cmd, "run", "body", "--config", str(tmp_path / "case.toml"), "--out", str(out))
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], lines
    assert not out.exists() or not any(out.iterdir())


def test_measured_kelvin_converted(tmp_path):
    """A measured column in K is read in C, a tolerance in K is a difference of 1 C per K."""
    from lcefem.solvers.problems.body_case import load_case

    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    (tmp_path / "measured.csv").write_text("time [s],T [K]\n0,298.15\n20,330\n")
    (tmp_path / "case.toml").write_text(GOOD)
    (c,) = load_case(tmp_path / "case.toml").compare
    assert c["values"] == pytest.approx([25.0, 56.85])
    assert c["tolerance"]["absolute"] == 2.0


def test_hexahedral_read_mesh_is_not_refined(tmp_path, lcefem_cmd):
    """A hexahedral .msh cannot be refined by dolfinx: the study refuses in one line (exit 2)."""
    res = run(lcefem_cmd, "mesh", "strip", "--format", "msh", "--out", str(tmp_path / "mesh"))
    assert res.returncode == 0, res.stderr
    msh = next((tmp_path / "mesh").glob("*.msh"))
    text = (STRIP / "case.toml").read_text().replace('file = "strip.geo"', f'file = "{msh}"')
    (tmp_path / "case.toml").write_text(text)
    res = run(
        lcefem_cmd,
        "converge",
        "--config",
        str(tmp_path / "case.toml"),
        "--levels",
        "3",
        "--out",
        str(tmp_path / "study"),
    )
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "refines tetrahedra only" in lines[0], lines


def test_uniform_refinement_carries_the_named_sets(tmp_path):
    """A tetrahedral .msh (the gripper's coarse level) refined once: every named cell set has 8x
    its cells and every named facet set 4x its facets (each tetrahedron into eight, each triangle
    into four), with the same names."""
    from mpi4py import MPI

    import gmsh
    import numpy as np

    from lcefem.meshes.reader import read_tagged_mesh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(REPO / "examples" / "bodies" / "gripper" / "finger.geo"))
        gmsh.model.mesh.generate(3)
        gmsh.write(str(tmp_path / "finger.msh"))
    finally:
        gmsh.finalize()
    coarse = read_tagged_mesh(tmp_path / "finger.msh", MPI.COMM_SELF)
    fine = read_tagged_mesh(tmp_path / "finger.msh", MPI.COMM_SELF, refine=1)
    assert fine.cell_names == coarse.cell_names and fine.facet_names == coarse.facet_names
    for tag in coarse.cell_names.values():
        assert np.sum(fine.cell_tags.values == tag) == 8 * np.sum(coarse.cell_tags.values == tag)
    for tag in coarse.facet_names.values():
        assert np.sum(fine.facet_tags.values == tag) == 4 * np.sum(coarse.facet_tags.values == tag)
    assert fine.info["cells"] == 8 * coarse.info["cells"]
