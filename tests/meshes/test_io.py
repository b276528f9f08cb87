"""lcefem.meshes.io: every built-in mesh (strip, beam, gridshell, ribbon, specimen; 3D FE at level 0
and the bar-and-hinge structures) written as .msh, .xdmf and .vtu reads back with its names and the
built mesh's number of cells per tag: .msh through dolfinx's gmsh reader (physical names), .xdmf and
.vtu through meshio (ParaView's formats; names from the sidecar). The FE meshes read back from .msh
have the built mesh's volume per cell tag and area per facet tag, so a user can start from them."""

import json

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import meshio
import numpy as np
import pytest
import ufl

import dolfinx
import dolfinx.io.gmsh

from lcefem.meshes.io import FORMATS, TAG_DATA, to_meshio, write_mesh
from lcefem.meshes.strip import strip_volume
from lcefem.models.errors import InputError
from lcefem.validation.app.mesh import BAR_HINGE, BODIES, MeshRequest, build, build_tagged

FE = [MeshRequest(b, "fe", 0, "msh") for b in BODIES]
BH = [MeshRequest(b, "bar-hinge", None, "msh") for b in BAR_HINGE]
DIM = {"hexahedron": 3, "tetra": 3, "quad": 2, "triangle": 2, "line": 1, "vertex": 0}
_BUILT: dict = {}


def built(request: MeshRequest):
    """The body's mesh and its meshio form, built once per test session."""
    key = (request.body, request.model)
    if key not in _BUILT:
        _BUILT[key] = (build_tagged(request), build(request)[0])
    return _BUILT[key]


def fe_counts(tm) -> dict[str, int]:
    """Cells per named tag of a TaggedMesh (cell and facet tags)."""
    out = {n: int(np.count_nonzero(tm.cell_tags.values == t)) for n, t in tm.cells.items()}
    out.update({n: int(np.count_nonzero(tm.facet_tags.values == t)) for n, t in tm.facets.items()})
    return out


def bh_counts(s, distinct: bool = False) -> dict[str, int]:
    """Cells per name of a bar-and-hinge structure as io.structure_to_meshio writes it: 4 triangles
    per panel, one line per bar, one vertex per node-set entry (``distinct``: per node, as XDMF's
    point data holds a node set)."""
    out = {"panels": 4 * len(s.panels)}
    out.update({n: len(b) for n, b in s.bars.items() if len(b)})
    size = (lambda v: np.unique(v).size) if distinct else np.size
    out.update({f"nodes:{n}": int(size(v)) for n, v in s.node_sets.items() if np.size(v)})
    return out


def read_counts(path, fmt: str) -> tuple[dict[str, int], dict[str, tuple[int, int]]]:
    """({name: cells}, {name: (tag, dim)}) read back with meshio: the names from the gmsh physical
    names (.msh) or the sidecar (.xdmf, .vtu)."""
    m = meshio.read(path)
    if fmt == "msh":
        names = {n: (int(v[0]), int(v[1])) for n, v in m.field_data.items()}
        key = "gmsh:physical"
    else:
        sidecar = json.loads(path.with_name(path.stem + ".tags.json").read_text())
        assert sidecar["cell_data"] == TAG_DATA and sidecar["units"] == {"length": "mm"}
        groups = sidecar["groups"]
        names = {n: (g["tag"], g["dim"]) for n, g in groups.items() if "tag" in g}
        points = {
            n: int(np.count_nonzero(m.point_data[g["point_data"]]))
            for n, g in groups.items()
            if "point_data" in g
        }  # XDMF's node sets
        key = TAG_DATA
    found: dict[tuple[int, int], int] = {}
    for block, tags in zip(m.cells, m.cell_data[key]):
        for tag, count in zip(*np.unique(np.asarray(tags), return_counts=True)):
            found[(int(tag), DIM[block.type])] = found.get((int(tag), DIM[block.type]), 0) + int(
                count
            )
    assert set(found) == set(names.values()), (
        "a tag in the file without a name, or a name without cells"
    )
    if fmt != "msh":
        return {**{n: found[td] for n, td in names.items()}, **points}, names
    return {n: found[td] for n, td in names.items()}, names


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("request_", FE + BH, ids=lambda r: f"{r.body}-{r.model}")
def test_every_mesh_round_trips_names_and_counts(tmp_path, request_, fmt):
    tagged, m = built(request_)
    files = write_mesh(m, tmp_path, request_.stem, fmt)
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".part")] == []
    assert files[-1] == tmp_path / f"{request_.stem}{FORMATS[fmt]}"
    counts, names = read_counts(files[-1], fmt)
    expected = (
        fe_counts(tagged) if request_.model == "fe" else bh_counts(tagged, distinct=fmt == "xdmf")
    )
    assert counts == expected
    if request_.model == "fe":
        tdim = tagged.mesh.topology.dim
        assert names == {
            **{n: (t, tdim) for n, t in tagged.cells.items()},
            **{n: (t, tdim - 1) for n, t in tagged.facets.items()},
        }
    assert meshio.read(files[-1]).points.shape == m.points.shape


def measures(mesh, cell_tags, facet_tags, cells: dict, facets: dict) -> dict[str, float]:
    """Volume [mm^3] of the mesh and of each named cell tag, area [mm^2] of each named facet tag."""
    dx = ufl.Measure("dx", domain=mesh, subdomain_data=cell_tags)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
    one = dolfinx.fem.Constant(mesh, 1.0)
    value = lambda form: dolfinx.fem.assemble_scalar(dolfinx.fem.form(form))  # noqa: E731
    out = {"volume": value(one * dx)}
    out.update({n: value(one * dx(t)) for n, t in cells.items()})
    out.update({n: value(one * ds(t)) for n, t in facets.items()})
    return out


@pytest.mark.parametrize("request_", FE, ids=lambda r: r.body)
def test_msh_loads_into_dolfinx_with_the_built_volume_and_areas(tmp_path, request_):
    """A user starting from the exported .msh gets the body's geometry: every tagged volume and
    facet area equals the built mesh's (same nodes; the sums differ only by rounding)."""
    tm, m = built(request_)
    path = write_mesh(m, tmp_path, request_.stem, "msh")[-1]
    data = dolfinx.io.gmsh.read_from_msh(path, MPI.COMM_SELF, 0, gdim=3)
    groups = data.physical_groups
    cells = {n: g.tag for n, g in groups.items() if g.dim == 3}
    facets = {n: g.tag for n, g in groups.items() if g.dim == 2}
    assert (cells, facets) == (tm.cells, tm.facets)
    ours = measures(tm.mesh, tm.cell_tags, tm.facet_tags, tm.cells, tm.facets)
    theirs = measures(data.mesh, data.cell_tags, data.facet_tags, cells, facets)
    assert theirs == pytest.approx(ours, rel=1e-12)
    assert all(v > 0 for v in ours.values())
    if request_.body == "strip":  # the quarter model: a quarter of the as-built L W H
        assert ours["volume"] == pytest.approx(strip_volume(tm.info) / 4, rel=1e-12)


def test_tetrahedra_keep_their_volume(tmp_path):
    """The strip split into tetrahedra (mesh.cell = "tet") round-trips too: same cells per tag,
    volume a quarter of L W H."""
    from lcefem.meshes.strip import StripGeometry, StripMesh, build_strip_mesh

    tm = build_strip_mesh(StripGeometry(), 1.4, StripMesh(level=0, cell="tet"), MPI.COMM_SELF)
    m = to_meshio(tm.mesh, tm.cell_tags, tm.facet_tags, {"cells": tm.cells, "facets": tm.facets})
    path = write_mesh(m, tmp_path, "strip_tet", "msh")[-1]
    data = dolfinx.io.gmsh.read_from_msh(path, MPI.COMM_SELF, 0, gdim=3)
    assert data.mesh.topology.cell_name() == "tetrahedron"
    assert read_counts(path, "msh")[0] == fe_counts(tm)
    ours = measures(tm.mesh, tm.cell_tags, tm.facet_tags, tm.cells, tm.facets)
    theirs = measures(data.mesh, data.cell_tags, data.facet_tags, tm.cells, tm.facets)
    assert theirs == pytest.approx(ours, rel=1e-12)
    assert ours["volume"] == pytest.approx(strip_volume(tm.info) / 4, rel=1e-12)


def test_a_failed_write_leaves_nothing_complete_looking(tmp_path, monkeypatch):
    _, m = built(FE[0])

    def broken(path, mesh, **kw):
        path.write_text("half a mesh")
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(meshio, "write", broken)
    with pytest.raises(OSError):
        write_mesh(m, tmp_path, "strip", "vtu")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["strip.part"]


def test_untagged_cells_and_unnamed_tags_are_refused():
    tm, _ = built(FE[0])
    with pytest.raises(InputError, match="cell tag 2 has no name"):
        to_meshio(tm.mesh, tm.cell_tags, tm.facet_tags, {"cells": {"lce": 1}, "facets": tm.facets})
    with pytest.raises(InputError, match="both a cell and a facet tag"):
        to_meshio(
            tm.mesh,
            tm.cell_tags,
            tm.facet_tags,
            {"cells": tm.cells, "facets": {**tm.facets, "lce": 9}},
        )
    n = tm.mesh.topology.index_map(3).size_local
    some = dolfinx.mesh.meshtags(
        tm.mesh, 3, np.arange(n // 2, dtype=np.int32), np.ones(n // 2, dtype=np.int32)
    )
    with pytest.raises(InputError, match=f"{n - n // 2} of {n} cells carry no cell tag"):
        to_meshio(tm.mesh, some, None, {"cells": {"lce": 1}})


@pytest.mark.parametrize("fmt", ["vtu", "xdmf"])
@pytest.mark.parametrize("request_", [FE[2], BH[1]], ids=lambda r: f"{r.body}-{r.model}")
def test_vtk_readers_open_them(tmp_path, request_, fmt):
    """ParaView's own readers (VTK's XML unstructured-grid and XDMF readers) give every point,
    every cell and each cell's tag."""
    import vtk  # with pyvista (requirements.lock)

    _, m = built(request_)
    path = write_mesh(m, tmp_path, request_.stem, fmt)[-1]
    reader = vtk.vtkXMLUnstructuredGridReader() if fmt == "vtu" else vtk.vtkXdmfReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutputDataObject(0)
    vertices = sum(len(c.data) for c in m.cells if c.type == "vertex")
    cells = sum(len(c.data) for c in m.cells) - (vertices if fmt == "xdmf" else 0)
    assert (grid.GetNumberOfPoints(), grid.GetNumberOfCells()) == (len(m.points), cells)
    tags = np.array([grid.GetCellData().GetArray(TAG_DATA).GetValue(i) for i in range(cells)])
    kept = [t for c, t in zip(m.cells, m.cell_data[TAG_DATA]) if fmt == "vtu" or c.type != "vertex"]
    assert np.array_equal(np.sort(tags), np.sort(np.concatenate(kept)))
