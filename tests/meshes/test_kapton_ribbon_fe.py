"""The FE buckling specimen's gmsh mesh: named tags, volume and faces, element counts per level."""

import dolfinx_solver  # noqa: F401

import pytest
import ufl

import dolfinx

from lcefem.meshes.kapton_ribbon import KaptonFEMesh, KaptonSpecimenGeometry, build_ribbon_fe
from lcefem.models.errors import InputError


def _integral(tm, measure_kind, tag=None):
    m = ufl.Measure(
        measure_kind,
        domain=tm.mesh,
        subdomain_data=tm.cell_tags if measure_kind == "dx" else tm.facet_tags,
    )
    return dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * (m(tag) if tag else m)))


@pytest.mark.parametrize("symmetry, factor", [("half", 0.5), ("full", 1.0)])
def test_volume_and_faces(symmetry, factor):
    spec = KaptonSpecimenGeometry()
    tm = build_ribbon_fe(spec, KaptonFEMesh(level=0, symmetry=symmetry))
    assert tm.cells == {"kapton": 1}
    assert _integral(tm, "dx") == pytest.approx(factor * 36.0 * 7.0 * 0.127, rel=1e-12)
    for name in ("clamp_left", "clamp_right"):
        assert _integral(tm, "ds", tm.facet_tag(name)) == pytest.approx(
            factor * 7.0 * 0.127, rel=1e-12
        )
    if symmetry == "half":
        assert _integral(tm, "ds", tm.facet_tag("sym_y")) == pytest.approx(36.0 * 0.127, rel=1e-12)
        assert tm.info["symmetry_factor"] == 2
    else:
        assert "sym_y" not in tm.facets


def test_level_refines_in_plane_only():
    coarse = build_ribbon_fe(mesh=KaptonFEMesh(level=0)).info["divisions"]
    fine = build_ribbon_fe(mesh=KaptonFEMesh(level=1)).info["divisions"]
    assert fine[0] == 2 * coarse[0] and fine[1] == 2 * coarse[1]
    assert fine[2] == coarse[2] == 1  # one Q2 element through the thickness


@pytest.mark.parametrize(
    "mesh", [KaptonFEMesh(symmetry="quarter"), KaptonFEMesh(size=0.0), KaptonFEMesh(level=-1)]
)
def test_bad_mesh_input(mesh):
    with pytest.raises(InputError):
        build_ribbon_fe(mesh=mesh)
