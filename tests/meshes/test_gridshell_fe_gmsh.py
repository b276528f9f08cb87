"""The FE gridshell mesh made by gmsh (issue 47) against the structured builder it replaces: the
same vertices bit for bit, the same cells under every tag, the same tagged faces; a layout's mesh
(refined, rhombic) against closed-form volumes; bad input."""

import math

import dolfinx_solver  # noqa: F401
from mpi4py import MPI

import numpy as np
import pytest
import ufl

import dolfinx

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell_fe import GridshellFEMesh, build_gridshell_fe, cell_group
from lcefem.meshes.gridshell_fe_gmsh import build_layout_fe
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS, Layout
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError

G = CompositeBeamGeometry()


def _pair(cells, symmetry, level=0):
    return [
        build_gridshell_fe(
            G,
            PUBLISHED_LAMBDA_N,
            GridshellFEMesh(level=level, mesher=m),
            MPI.COMM_SELF,
            cells=cells,
            symmetry=symmetry,
        )
        for m in ("hexgrid", "gmsh")
    ]


def _cells_by_tag(tm):
    """Per cell tag name: its cells, each by its 8 corners' coordinates (independent of the
    numbering; exact: the vertices are bit for bit the same)."""
    x, dofmap = tm.mesh.geometry.x, tm.mesh.geometry.dofmaps[0]
    return {
        name: sorted(tuple(sorted(map(tuple, x[dofmap[c]]))) for c in tm.cell_tags.find(t))
        for name, t in tm.cells.items()
    }


def _facets_by_tag(tm):
    """Per facet tag name: the set of its faces, each by its sorted vertex coordinates."""
    x = tm.mesh.geometry.x
    tm.mesh.topology.create_connectivity(2, 3)
    out = {}
    for name, t in tm.facets.items():
        nodes = dolfinx.mesh.entities_to_geometry(tm.mesh, 2, tm.facet_tags.find(t))
        out[name] = {tuple(sorted(map(tuple, x[f]))) for f in nodes}
    return out


@pytest.mark.parametrize("cells, symmetry", [(3, "quarter"), (4, "half_y")])
def test_gmsh_mesh_is_the_structured_mesh(cells, symmetry):
    """Both builders give the same vertex set bit for bit (so the same results), the same cells
    under every cell tag, the same faces under every facet tag (bonded faces interior, unbonded
    strip faces doubled: both sides tagged) and the same facts; 3 x 3 quarter (the Fig. 4 runs) and
    an even grid's half (mirror plane through the crowns)."""
    old, new = _pair(cells, symmetry)
    assert new.info.pop("mesher") == "gmsh" and old.info.pop("mesher") == "hexgrid"
    assert new.info == old.info
    xa, xb = (np.unique(t.mesh.geometry.x, axis=0) for t in (old, new))
    assert xa.shape == xb.shape and np.array_equal(xa, xb)
    assert old.cells == new.cells and old.facets == new.facets
    assert _cells_by_tag(old) == _cells_by_tag(new)
    fa, fb = _facets_by_tag(old), _facets_by_tag(new)
    assert {k: len(v) for k, v in fa.items()} == {k: len(v) for k, v in fb.items()}
    assert fa == fb


def test_gmsh_is_the_default_mesher():
    assert GridshellFEMesh().mesher == "gmsh"
    with pytest.raises(InputError, match="mesh.mesher = 'occ': allowed gmsh, hexgrid"):
        GridshellFEMesh(mesher="occ").checked()


def _kapton_volume(tm):
    Q = dolfinx.fem.functionspace(tm.mesh, ("DG", 0))
    vol = dolfinx.fem.assemble_vector(dolfinx.fem.form(ufl.TestFunction(Q) * ufl.dx)).array
    tags = np.zeros(vol.size, dtype=np.int32)
    tags[tm.cell_tags.indices] = tm.cell_tags.values
    return float(vol[np.isin(tags, cell_group(tm, "kapton"))].sum())


@pytest.mark.parametrize("name", ["5x5", "rhombic60"])
def test_layout_mesh_kapton_volume_closed_form(name):
    """Kapton volume of a layout's mesh = t_p (2 n l w - n^2 w^2 / sin a): 2 n ribbons of width w
    (7 mm, across the ribbon) and length l = (n + 1) L + n d + 2 tab along it, less the n^2 junction
    rhombi counted twice (side d = w / sin a, area w^2 / sin a); the arch shears the film
    vertically, which keeps its volume. 5 x 5 as a quarter (the default on an orthogonal grid), the
    rhombic 60 deg grid whole."""
    layout = NAMED_LAYOUTS[name]
    mesh = GridshellFEMesh(level=0)
    tm = build_layout_fe(layout, G, PUBLISHED_LAMBDA_N, mesh, MPI.COMM_SELF)
    n, s = layout.ribbons, math.sin(math.radians(layout.angle))
    w, d = G.ribbon_width, G.ribbon_width / s
    length = (n + 1) * (G.pitch - d) + n * d + 2 * mesh.end_tab
    expected = G.ribbon_thickness * (2 * n * length * w - n**2 * w**2 / s)
    assert tm.info["symmetry"] == ("full" if layout.oblique else "quarter")
    assert tm.info["symmetry_factor"] * _kapton_volume(tm) == pytest.approx(expected, rel=1e-12)


def test_layout_mesh_refuses_what_it_does_not_build():
    with pytest.raises(InputError, match="layout.kind = 'triangular'"):
        build_layout_fe(NAMED_LAYOUTS["triangular"], G, PUBLISHED_LAMBDA_N)
    with pytest.raises(InputError, match="layout.glued"):
        build_layout_fe(Layout(glued=((0, 0),)), G, PUBLISHED_LAMBDA_N)
    with pytest.raises(InputError, match="no mirror plane"):
        build_layout_fe(NAMED_LAYOUTS["rhombic60"], G, PUBLISHED_LAMBDA_N, symmetry="quarter")
