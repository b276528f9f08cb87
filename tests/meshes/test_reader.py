"""meshes/reader.py: a user's mesh read from a .geo (meshed with a size factor), a .msh and a
meshio file (.vtu with a tag array and a name map) gives the same named sets as the built-in
strip."""

from mpi4py import MPI

import gmsh
import meshio
import numpy as np
import pytest

from lcefem.meshes.reader import physical_names, read_tagged_mesh
from lcefem.meshes.strip import StripGeometry, StripMesh, build_strip_mesh
from lcefem.models.errors import InputError
from tests.conftest import REPO

GEO = REPO / "examples" / "bodies" / "strip" / "strip.geo"


def counts(m):
    return (
        {n: len(m.cell_tags.find(t)) for n, t in m.cell_names.items()},
        {n: len(m.facet_tags.find(t)) for n, t in m.facet_names.items()},
    )


@pytest.fixture(scope="module")
def strip0():
    s = build_strip_mesh(StripGeometry(), 1.426, StripMesh(level=0), MPI.COMM_SELF)
    return (
        {n: len(s.cell_tags.find(t)) for n, t in s.cells.items()},
        {n: len(s.facet_tags.find(t)) for n, t in s.facets.items()},
        s.mesh.geometry.x,
    )


@pytest.mark.parametrize("factor, level", [(1.0, 0), (0.5, 1)])
def test_geo_with_size_factor_is_the_builtin_strip(factor, level):
    read = read_tagged_mesh(GEO, MPI.COMM_SELF, factor)
    built = build_strip_mesh(StripGeometry(), 1.426, StripMesh(level=level), MPI.COMM_SELF)
    assert counts(read) == (
        {n: len(built.cell_tags.find(t)) for n, t in built.cells.items()},
        {n: len(built.facet_tags.find(t)) for n, t in built.facets.items()},
    )
    np.testing.assert_allclose(
        np.sort(read.mesh.geometry.x, axis=0), np.sort(built.mesh.geometry.x, axis=0), atol=1e-12
    )


def test_msh_and_vtu_read_back(tmp_path, strip0):
    msh = tmp_path / "strip.msh"
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.merge(str(GEO))
        gmsh.model.mesh.generate(3)
        gmsh.write(str(msh))
    finally:
        gmsh.finalize()
    assert physical_names(msh, comm=MPI.COMM_SELF) == (
        {"lce": 1, "coil": 2},
        {"clamp": 1, "end": 2, "sides": 3, "sym_y": 4, "sym_z": 5},
    )
    assert counts(read_tagged_mesh(msh, MPI.COMM_SELF)) == strip0[:2]
    # the same mesh as .vtu: the tags in cell data, the names in a sidecar TOML
    m = meshio.read(msh)
    blocks = [(b.type, b.data) for b in m.cells if b.type in ("hexahedron", "quad")]
    tags = [
        t for b, t in zip(m.cells, m.cell_data["gmsh:physical"]) if b.type in ("hexahedron", "quad")
    ]
    vtu = tmp_path / "strip.vtu"
    meshio.write(vtu, meshio.Mesh(m.points, blocks, cell_data={"cell_tags": tags}))
    (tmp_path / "strip.vtu.tags.toml").write_text(
        "[cells]\nlce = 1\ncoil = 2\n[facets]\nclamp = 1\nend = 2\nsides = 3\nsym_y = 4\nsym_z = "
        "5\n"
    )
    read = read_tagged_mesh(vtu, MPI.COMM_SELF)
    assert counts(read) == strip0[:2]
    # a name whose tag no cell carries: a missing tag, refused before any mesh is built
    (tmp_path / "strip.vtu.tags.toml").write_text(
        "[cells]\nlce = 1\ncoil = 7\n[facets]\nclamp = 1\n"
    )
    with pytest.raises(InputError, match="cell set 'coil' \\(tag 7\\) is missing"):
        physical_names(vtu, comm=MPI.COMM_SELF)
    np.testing.assert_allclose(
        np.sort(read.mesh.geometry.x, axis=0), np.sort(strip0[2], axis=0), atol=1e-12
    )


def test_unreadable_and_unnamed_files(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        physical_names(tmp_path / "none.msh", comm=MPI.COMM_SELF)
    bad = tmp_path / "bad.geo"
    bad.write_text("Point(1) = {0, 0, 0\n")
    with pytest.raises(InputError, match="gmsh cannot read it"):
        physical_names(bad, comm=MPI.COMM_SELF)
    empty = tmp_path / "empty.geo"
    empty.write_text(
        'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\nPhysical Volume("body", 1) = '
        '{1};\n'
        'Physical Surface("lid", 1) = Surface In BoundingBox{5, 5, 5, 6, 6, 6};\n'
    )
    # gmsh drops a physical group that selects nothing: the case file's check then names it
    assert physical_names(empty, comm=MPI.COMM_SELF) == ({"body": 1}, {})
    vtu = tmp_path / "plain.vtu"
    meshio.write(vtu, meshio.Mesh(np.eye(4, 3), [("tetra", np.array([[0, 1, 2, 3]]))]))
    with pytest.raises(InputError, match="no named cell sets"):
        physical_names(vtu, comm=MPI.COMM_SELF)
