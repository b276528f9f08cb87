"""Reading a user's mesh with named cell and facet sets (``lcefem run body``'s ``[mesh] file``).

Three kinds of file, coordinates in mm, regions and boundaries by physical name:

* a gmsh ``.geo`` script: parsed and meshed in 3D through the gmsh Python API, with the option
  ``Mesh.MeshSizeFactor`` set to ``size_factor`` before the script is read (a script can read it
  back, e.g. ``sf = Mesh.MeshSizeFactor;``, to scale transfinite divisions; free meshes follow it
  by themselves);
* a gmsh ``.msh`` file: read by :func:`dolfinx.io.gmsh.read_from_msh` (physical groups of dimension
  3 are the cell sets, of dimension 2 the facet sets);
* any other file meshio reads (``.vtu``, ``.xdmf``, ...) whose cell blocks carry an integer tag
  array (cell data ``gmsh:physical``, ``cell_tags``, ``tags`` or ``tag``; 3D blocks are cells, 2D
  blocks facets) and a name map: meshio's ``field_data`` ``{name: [id, dim]}``, or a sidecar TOML
  ``<file>.tags.toml`` with tables ``[cells]`` and ``[facets]`` of ``name = id``, or the sidecar
  ``<stem>.tags.json`` that ``lcefem mesh`` writes beside its .vtu and .xdmf. It goes to dolfinx
  through a gmsh 2.2 ``.msh`` written by meshio in a temporary folder (one conversion path: the
  node orderings are meshio's and gmsh's business, not ours).

:func:`physical_names` reads only the names (no mesh is built): the case file's checks use it.
:func:`read_tagged_mesh` builds the dolfinx mesh (serial read on rank 0, distributed over ``comm``).
"""

from __future__ import annotations

import pathlib
import tempfile
import tomllib
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.meshes.communicator import resolve_comm
from lcefem.models.errors import InputError

#: Cell-data names searched, in order, for the integer tags of a meshio-read file.
TAG_ARRAYS = ("gmsh:physical", "cell_tags", "tags", "tag")
#: meshio cell types by topological dimension (those a 3D body and its facets use).
VOLUME_TYPES = ("tetra", "hexahedron", "tetra10", "hexahedron27", "wedge", "pyramid")
SURFACE_TYPES = ("triangle", "quad", "triangle6", "quad9")


@dataclass
class ReadMesh:
    """A mesh read from a user's file.

    Attributes:
        mesh: the dolfinx mesh (mm).
        cell_tags, facet_tags: dolfinx MeshTags.
        cell_names, facet_names: {physical name: integer tag}.
        info: what was read (file, size factor, cells).
    """

    mesh: object
    cell_tags: object
    facet_tags: object
    cell_names: dict[str, int]
    facet_names: dict[str, int]
    info: dict = field(default_factory=dict)

    def tagged(self) -> TaggedMesh:
        """The same mesh as a :class:`TaggedMesh` (what the solvers take)."""
        return TaggedMesh(
            self.mesh,
            self.cell_tags,
            self.facet_tags,
            dict(self.cell_names),
            dict(self.facet_names),
            dict(self.info),
        )


def mesh_kind(path: pathlib.Path) -> str:
    """'geo', 'msh' or 'meshio' by the file's suffix."""
    suffix = path.suffix.lower()
    return {".geo": "geo", ".msh": "msh"}.get(suffix, "meshio")


def _gmsh_names(path: pathlib.Path, size_factor: float) -> tuple[dict, dict]:
    import gmsh

    from lcefem.meshes._gmsh import gmsh_session

    with gmsh_session("names") as model:
        gmsh.option.setNumber("Mesh.MeshSizeFactor", size_factor)
        try:
            gmsh.merge(str(path))
        except Exception as exc:  # gmsh raises a bare Exception with its own text
            raise InputError(f"mesh.file = {str(path)!r}: gmsh cannot read it ({exc})") from None
        cells, facets = {}, {}
        for dim, tag in model.getPhysicalGroups():
            name = model.getPhysicalName(dim, tag) or str(tag)
            if dim in (2, 3) and len(model.getEntitiesForPhysicalGroup(dim, tag)) == 0:
                raise InputError(
                    f"mesh.file = {str(path)!r}: physical group {name!r} (dimension {dim}) "
                    "is empty: no entity carries its tag"
                )
            if dim == 3:
                cells[name] = tag
            elif dim == 2:
                facets[name] = tag
    return cells, facets


def _meshio_read(path: pathlib.Path):
    import meshio

    try:
        return meshio.read(str(path))
    except Exception as exc:  # meshio raises ReadError, KeyError, ... by format
        raise InputError(
            f"mesh.file = {str(path)!r}: meshio cannot read it ({type(exc).__name__}: {exc})"
        ) from None


def _exported_names(sidecar: pathlib.Path) -> tuple[dict, dict]:
    """{name: id} of cells and facets from the sidecar ``<stem>.tags.json`` that ``lcefem mesh``
    writes beside an .xdmf or .vtu (:func:`lcefem.meshes.io.write_mesh`: ``{"groups": {name:
    {"tag": t, "dim": d}}}``); node sets (dim 0, point data) are not regions or boundaries."""
    import json

    try:
        groups = json.loads(sidecar.read_text(encoding="utf-8"))["groups"]
        pairs = [(str(n), int(g["tag"]), int(g["dim"])) for n, g in groups.items()]
    except (ValueError, KeyError, TypeError, AttributeError, RecursionError) as exc:
        raise InputError(
            f"{sidecar.name}: not a tag map of lcefem mesh ({type(exc).__name__}); "
            "allowed: {\"groups\": {name: {\"tag\": int, \"dim\": 2|3}}}"
        ) from None
    return ({n: t for n, t, d in pairs if d == 3}, {n: t for n, t, d in pairs if d == 2})


def _meshio_names(path: pathlib.Path, data) -> tuple[dict, dict]:
    """{name: id} of cells and facets from the sidecar ``<file>.tags.toml``, the sidecar
    ``<stem>.tags.json`` of an ``lcefem mesh`` export, or meshio's field_data."""
    sidecar = path.with_name(path.name + ".tags.toml")
    exported = path.with_suffix(".tags.json")
    if not sidecar.is_file() and exported.is_file():
        return _exported_names(exported)
    if sidecar.is_file():
        try:
            table = tomllib.loads(sidecar.read_text(encoding="utf-8"))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise InputError(f"{sidecar.name}: invalid TOML ({exc})") from None
        unknown = set(table) - {"cells", "facets"}
        if unknown:
            raise InputError(
                f"{sidecar.name}: unknown table(s) {sorted(unknown)}; allowed: cells, facets"
            )
        out = []
        for key in ("cells", "facets"):
            names = table.get(key, {})
            bad = [n for n, v in names.items() if not isinstance(v, int) or isinstance(v, bool)]
            if bad:
                raise InputError(f"{sidecar.name}: [{key}] {bad[0]}: the tag must be an integer")
            out.append(dict(names))
        return out[0], out[1]
    cells, facets = {}, {}
    for name, value in (data.field_data or {}).items():
        vals = list(value)
        if len(vals) >= 2:
            (cells if int(vals[1]) == 3 else facets if int(vals[1]) == 2 else {})[name] = int(
                vals[0]
            )
    if not cells:
        raise InputError(
            f"mesh.file = {str(path)!r}: no named cell sets (meshio field_data "
            f"{{name: [id, 3]}} or a sidecar {sidecar.name} with [cells] name = id)"
        )
    return cells, facets


def _check_tags_present(path: pathlib.Path, data, cells: dict, facets: dict) -> None:
    """Every named tag of a meshio file occurs in its tag array (cells in 3D blocks, facets in
    2D)."""
    import numpy as np

    key = next((k for k in TAG_ARRAYS if k in data.cell_data), None)
    if key is None:
        raise InputError(
            f"mesh.file = {str(path)!r}: no tag array among its cell data "
            f"({', '.join(data.cell_data) or 'none'}); allowed names: {', '.join(TAG_ARRAYS)}"
        )
    found = {3: set(), 2: set()}
    for block, tags in zip(data.cells, data.cell_data[key]):
        dim = 3 if block.type in VOLUME_TYPES else 2 if block.type in SURFACE_TYPES else None
        if dim is not None:
            found[dim] |= set(np.unique(np.asarray(tags, dtype=int)).tolist())
    for names, dim, what in ((cells, 3, "cell"), (facets, 2, "facet")):
        for name, tag in names.items():
            if tag not in found[dim]:
                raise InputError(
                    f"mesh.file = {str(path)!r}: {what} set {name!r} (tag {tag}) is missing: "
                    f"no {what} carries tag {tag} in {key!r}"
                )


def physical_names(
    path: str | pathlib.Path, size_factor: float = 1.0, comm=None
) -> tuple[dict, dict]:
    """({cell set name: id}, {facet set name: id}) of a mesh file, without building a mesh (rank 0
    reads, the others receive). InputError when the file cannot be read."""
    comm = resolve_comm(comm)
    path = pathlib.Path(path)
    result, error = None, None
    if comm.rank == 0:
        try:
            if not path.is_file():
                raise InputError(f"mesh.file = {str(path)!r}: file not found")
            if mesh_kind(path) == "meshio":
                data = _meshio_read(path)
                result = _meshio_names(path, data)
                _check_tags_present(path, data, *result)
            else:
                result = _gmsh_names(path, size_factor)
        except InputError as exc:
            error = str(exc)
    result, error = comm.bcast((result, error), root=0)
    if error:
        raise InputError(error)
    return result


def _meshio_to_msh(path: pathlib.Path, folder: pathlib.Path) -> pathlib.Path:
    """The meshio-read file as a gmsh 2.2 .msh with physical tags and names (in ``folder``)."""
    import meshio
    import numpy as np

    data = _meshio_read(path)
    cells, facets = _meshio_names(path, data)
    _check_tags_present(path, data, cells, facets)
    key = next(k for k in TAG_ARRAYS if k in data.cell_data)
    blocks, physical = [], []
    for block, tags in zip(data.cells, data.cell_data[key]):
        if block.type in VOLUME_TYPES or block.type in SURFACE_TYPES:
            blocks.append((block.type, block.data))
            physical.append(np.asarray(tags, dtype=int).reshape(-1))
    out = folder / "mesh.msh"
    field_data = {n: np.array([i, 3]) for n, i in cells.items()}
    field_data.update({n: np.array([i, 2]) for n, i in facets.items()})
    converted = meshio.Mesh(
        np.asarray(data.points, dtype=float)[:, :3],
        blocks,
        cell_data={"gmsh:physical": physical, "gmsh:geometrical": physical},
        field_data=field_data,
    )
    meshio.write(str(out), converted, file_format="gmsh22", binary=False)
    return out


def volume_cell_types(path: str | pathlib.Path) -> set[str]:
    """meshio's names of the 3D cell types of a .msh or meshio-read file (no mesh is built)."""
    data = _meshio_read(pathlib.Path(path))
    return {b.type for b in data.cells if b.type in VOLUME_TYPES}


def refine_uniformly(read: ReadMesh, times: int) -> ReadMesh:
    """``read`` with every edge halved ``times`` times (:func:`dolfinx.mesh.refine`, Plaza's
    algorithm: each tetrahedron into eight) and its cell and facet tags carried to the children
    (:func:`dolfinx.mesh.transfer_meshtag`). Tetrahedra only: dolfinx does not refine hexahedra
    (InputError)."""
    import dolfinx

    if times <= 0:
        return read
    if read.mesh.topology.cell_type != dolfinx.mesh.CellType.tetrahedron:
        raise InputError(
            f"mesh.refine = {times}: dolfinx refines tetrahedra only and "
            f"{pathlib.Path(read.info.get('file', 'the mesh')).name} has "
            f"{read.mesh.topology.cell_type.name} cells; refine its .geo by size_factor"
        )
    mesh, cell_tags, facet_tags = read.mesh, read.cell_tags, read.facet_tags
    for _ in range(times):
        mesh.topology.create_entities(1)
        mesh.topology.create_connectivity(2, 3)
        fine, parent_cell, parent_facet = dolfinx.mesh.refine(
            mesh, option=dolfinx.mesh.RefinementOption.parent_cell_and_facet
        )
        fine.topology.create_connectivity(2, 3)
        cell_tags = dolfinx.mesh.transfer_meshtag(cell_tags, fine, parent_cell, parent_facet)
        facet_tags = dolfinx.mesh.transfer_meshtag(facet_tags, fine, parent_cell, parent_facet)
        mesh = fine
    info = {**read.info, "refine": times, "cells": mesh.topology.index_map(3).size_global}
    return ReadMesh(
        mesh, cell_tags, facet_tags, dict(read.cell_names), dict(read.facet_names), info
    )


def read_tagged_mesh(
    path: str | pathlib.Path, comm=None, size_factor: float = 1.0, refine: int = 0
) -> ReadMesh:
    """The dolfinx mesh of ``path`` (.geo meshed with ``size_factor``, .msh, or a meshio-read file;
    see the module docstring) with its named cell and facet tags, distributed over ``comm``; then
    ``refine`` uniform refinements (:func:`refine_uniformly`)."""
    import gmsh

    import dolfinx.io.gmsh

    from lcefem.meshes._gmsh import gmsh_session, to_dolfinx

    comm = resolve_comm(comm)
    path = pathlib.Path(path)
    kind = mesh_kind(path)
    if kind == "geo":
        with gmsh_session("body") as model:
            if comm.rank == 0:
                gmsh.option.setNumber("Mesh.MeshSizeFactor", size_factor)
                gmsh.merge(str(path))
                model.mesh.generate(3)
            data, cells, facets = to_dolfinx(model, comm)
    else:
        with tempfile.TemporaryDirectory() as folder:
            msh = path
            if kind == "meshio":
                converted, error = None, None
                if comm.rank == 0:
                    try:
                        converted = _meshio_to_msh(path, pathlib.Path(folder))
                    except InputError as exc:
                        error = str(exc)
                error = comm.bcast(error, root=0)
                if error:
                    raise InputError(error)
                msh = converted
            data = dolfinx.io.gmsh.read_from_msh(msh if comm.rank == 0 else path, comm, 0, gdim=3)
        cells = {n: g.tag for n, g in data.physical_groups.items() if g.dim == 3}
        facets = {n: g.tag for n, g in data.physical_groups.items() if g.dim == 2}
    info = {
        "file": str(path),
        "kind": kind,
        "size_factor": size_factor,
        "cells": data.mesh.topology.index_map(3).size_global,
    }
    return refine_uniformly(
        ReadMesh(data.mesh, data.cell_tags, data.facet_tags, cells, facets, info), refine
    )
