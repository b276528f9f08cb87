"""Built meshes out to files other tools read, through meshio (https://github.com/nschloe/meshio,
pinned 5.3.5): gmsh ``.msh``, XDMF ``.xdmf`` and VTK ``.vtu``, each with its named tags.

:func:`to_meshio` turns a dolfinx mesh with cell and facet tags and their names into a
:class:`meshio.Mesh`: one cell block per (cell type, tag), cells in VTK's vertex order, coordinates
in mm. :func:`structure_to_meshio` does the same for a bar-and-hinge structure
(:class:`~lcefem.meshes.bar_hinge_structure.BarHingeStructure`): each quad panel as the four
triangles of its N5B8 spokes, every bar group as line cells, every node set as vertex cells.
:func:`write_mesh` writes one file, without leaving a complete-looking file when it fails.

How the names travel, per format:

* ``.msh``: gmsh physical groups. Each cell carries ``gmsh:physical`` (its tag) and
  ``gmsh:geometrical``; ``field_data`` maps each name to ``[tag, dimension]`` ($PhysicalNames), so
  ``dolfinx.io.gmsh.read_from_msh`` gives the tags and ``physical_groups`` by name. Written as MSH
  2.2: meshio's MSH 4.1 writer stores physical tags on geometric entities, which it writes only
  from a node classification (``gmsh:dim_tags``) a dolfinx mesh does not have; MSH 2.2 stores them
  per element, and gmsh >= 4 reads it.
* ``.xdmf``, ``.vtu``: the cell data ``tag`` (int32, the same numbers) and the name map in the
  sidecar ``<stem>.tags.json`` (``{"groups": {name: {"tag": t, "dim": d}}, ...}``), as neither
  format has names for integer tags. In XDMF a bar-and-hinge node set is the point data of its
  name (1 on its nodes; sidecar ``{"point_data": name, "dim": 0}``): meshio cannot write vertex
  cells into a mixed XDMF topology that a reader parses. XDMF keeps its arrays in ``<stem>.h5``
  beside it (meshio's HDF5 storage, through h5py), uncompressed: once dolfinx is loaded, h5py runs
  on dolfinx's HDF5 library (the same version, 1.14.6), which has no gzip filter.

A mesh shared over several processes is gathered to rank 0, which writes it.
"""

from __future__ import annotations

import json
import os
import pathlib
import shutil

import numpy as np

from lcefem.models.errors import InputError

#: the --format choices: file suffix of each
FORMATS = {"msh": ".msh", "xdmf": ".xdmf", "vtu": ".vtu"}
#: meshio's name of each format's writer
_MESHIO_FORMAT = {"msh": "gmsh22", "xdmf": "xdmf", "vtu": "vtu"}
#: the cell data holding each cell's tag in .xdmf/.vtu
TAG_DATA = "tag"
#: VTK order of a hexahedron's vertices from dolfinx's (lexicographic: vertex a + 2 b + 4 c at the
#: corner (a, b, c)): VTK goes round the bottom face, then round the top one
_HEX_VTK = np.array([0, 1, 3, 2, 4, 5, 7, 6])
#: the same for a quadrilateral facet
_QUAD_VTK = np.array([0, 1, 3, 2])
#: dolfinx cell name -> (meshio cell type, vertex order from dolfinx's)
_CELLS = {
    "hexahedron": ("hexahedron", _HEX_VTK),
    "tetrahedron": ("tetra", np.arange(4)),
    "quadrilateral": ("quad", _QUAD_VTK),
    "triangle": ("triangle", np.arange(3)),
}
_DIM = {"hexahedron": 3, "tetra": 3, "quad": 2, "triangle": 2, "line": 1, "vertex": 0}


def to_meshio(mesh, cell_tags, facet_tags, names: dict[str, dict[str, int]]):
    """A :class:`meshio.Mesh` of a linear (degree-1 geometry) dolfinx ``mesh`` with its tags.

    Args:
        mesh: dolfinx mesh, coordinates in mm; shared over several processes, it is gathered to
            rank 0 of its communicator (nodes in their global order), which gets the result: the
            other ranks get None.
        cell_tags, facet_tags: dolfinx MeshTags of the cells and facets (``facet_tags`` may be
            None).
        names: ``{"cells": {name: tag}, "facets": {name: tag}}``; a name must be unique across both.

    Returns a mesh whose cell blocks are the tagged cells (one block per tag, in tag order), then
    the tagged facets (likewise); each block carries ``gmsh:physical`` = ``gmsh:geometrical`` =
    ``tag`` = its tag, ``field_data`` = ``{name: [tag, dim]}``, ``cell_sets`` = ``{name: [indices
    per block]}``. Untagged cells are refused (a reader that builds a mesh from the tagged cells
    would drop them); untagged facets are simply not written.
    """
    import dolfinx

    comm = mesh.comm
    if mesh.geometry.cmaps[0].degree != 1:
        raise InputError(
            f"mesh export: geometry of degree {mesh.geometry.cmaps[0].degree}; only linear "
            "(degree-1) meshes are written"
        )
    tdim = mesh.topology.dim
    cell_name = mesh.topology.cell_name()
    if cell_name not in _CELLS:
        raise InputError(f"mesh export: cell type {cell_name!r}; allowed {', '.join(_CELLS)}")
    cells_by_name = dict(names.get("cells", {}))
    facets_by_name = dict(names.get("facets", {}))
    both = set(cells_by_name) & set(facets_by_name)
    if both:
        raise InputError(
            f"mesh export: names {sorted(both)} are both a cell and a facet tag; a gmsh "
            "physical name must be unique"
        )
    # this process's owned cells and facets (a facet on a process boundary is owned by one process)
    n_cells = mesh.topology.index_map(tdim).size_local
    cell_values = np.zeros(n_cells, dtype=np.int32)
    owned = cell_tags.indices < n_cells
    cell_values[cell_tags.indices[owned]] = cell_tags.values[owned]
    mtype, order = _CELLS[cell_name]
    cell_nodes = np.asarray(mesh.geometry.dofmaps[0][:n_cells])[:, order]
    fname = dolfinx.cpp.mesh.cell_entity_type(mesh.topology.cell_type, tdim - 1, 0).name
    ftype, forder = _CELLS[fname]
    facet_nodes, facet_values = (
        np.empty((0, len(forder)), dtype=np.int64),
        np.empty(0, dtype=np.int32),
    )
    if facet_tags is not None:
        mesh.topology.create_entities(tdim - 1)
        mine = facet_tags.indices < mesh.topology.index_map(tdim - 1).size_local
        if np.any(mine):
            nodes = dolfinx.mesh.entities_to_geometry(
                mesh, tdim - 1, facet_tags.indices[mine], False
            )
            facet_nodes, facet_values = (
                np.asarray(nodes)[:, forder],
                np.asarray(facet_tags.values[mine]),
            )
    untagged = comm.allreduce(int(np.count_nonzero(cell_values == 0)))
    if untagged:
        raise InputError(
            f"mesh export: {untagged} of {comm.allreduce(n_cells)} cells carry no cell tag"
        )
    for what, values, by_name in (
        ("cell", cell_values, cells_by_name),
        ("facet", facet_values, facets_by_name),
    ):
        present = sorted(set().union(*comm.allgather(set(np.unique(values).tolist()))))
        unnamed = [t for t in present if t not in by_name.values()]
        if unnamed:  # every process refuses alike
            raise InputError(
                f"mesh export: {what} tag {unnamed[0]} has no name (named: "
                f"{', '.join(f'{n}={t}' for n, t in by_name.items())})"
            )
    x = np.asarray(mesh.geometry.x, dtype=np.float64)
    if comm.size > 1:  # gather to rank 0, nodes by their global index
        imap = mesh.geometry.index_map()
        n_own = imap.size_local
        to_global = imap.local_to_global(np.arange(n_own + imap.num_ghosts, dtype=np.int32))
        parts = comm.gather(
            (
                x[:n_own],
                to_global[:n_own],
                to_global[cell_nodes],
                cell_values,
                to_global[facet_nodes],
                facet_values,
            ),
            root=0,
        )
        if comm.rank != 0:
            return None
        x = np.empty((imap.size_global, 3))
        for xs, ids, *_ in parts:
            x[ids] = xs
        cell_nodes, cell_values, facet_nodes, facet_values = (
            np.concatenate([p[k] for p in parts]) for k in (2, 3, 4, 5)
        )
    blocks = _blocks(mtype, cell_nodes, cell_values, cells_by_name, "cell")
    blocks += _blocks(ftype, facet_nodes, facet_values, facets_by_name, "facet")
    return _assemble(x, blocks)


def structure_to_meshio(structure):
    """A :class:`meshio.Mesh` of a bar-and-hinge structure [mm]: the Kapton panels as triangles
    (each quad panel the four triangles centre-corner-next corner of its N5B8 spokes) named
    ``panels``, every bar group as line cells under its own name (``kapton``: the panels' edges and
    spokes, ``bottom_strips``, ``top_strips``, ``glue``, ...), every node set as vertex cells under
    ``nodes:<name>`` (the supports' and measures' nodes). Tags count from 1 in that order; tags and
    names are carried as in :func:`to_meshio`."""
    p = np.asarray(structure.panels, dtype=np.int64)
    centres = np.asarray(structure.panel_centres, dtype=np.int64)
    triangles = np.stack(
        [np.repeat(centres, 4), p.reshape(-1), np.roll(p, -1, axis=1).reshape(-1)], axis=1
    )
    groups = [("panels", "triangle", triangles)]
    groups += [
        (name, "line", np.asarray(bars, dtype=np.int64).reshape(-1, 2))
        for name, bars in structure.bars.items()
        if len(bars)
    ]
    groups += [
        (f"nodes:{name}", "vertex", np.asarray(nodes, dtype=np.int64).reshape(-1, 1))
        for name, nodes in structure.node_sets.items()
        if np.size(nodes)
    ]
    blocks = [(mtype, conn, tag, name) for tag, (name, mtype, conn) in enumerate(groups, start=1)]
    return _assemble(np.asarray(structure.nodes, dtype=np.float64), blocks)


def _blocks(
    mtype: str, conn: np.ndarray, values: np.ndarray, by_name: dict[str, int], what: str
) -> list[tuple]:
    """(meshio type, connectivity, tag, name) per tag present, in tag order; a tag without a name
    is refused (tags by name)."""
    name_of = {t: n for n, t in by_name.items()}
    out = []
    for tag in np.unique(values):
        if int(tag) not in name_of:
            raise InputError(
                f"mesh export: {what} tag {int(tag)} has no name (named: "
                f"{', '.join(f'{n}={t}' for n, t in by_name.items())})"
            )
        out.append((mtype, np.ascontiguousarray(conn[values == tag]), int(tag), name_of[int(tag)]))
    return out


def _assemble(x: np.ndarray, blocks: list[tuple]):
    import meshio

    cells = [meshio.CellBlock(mtype, conn) for mtype, conn, _, _ in blocks]
    tags = [np.full(len(conn), tag, dtype=np.int32) for _, conn, tag, _ in blocks]
    field_data, cell_sets = {}, {}
    for k, (mtype, conn, tag, name) in enumerate(blocks):
        field_data[name] = np.array([tag, _DIM[mtype]])
        cell_sets[name] = [
            np.arange(len(c)) if j == k else np.empty(0, dtype=np.int64)
            for j, c in enumerate(cells)
        ]
    return meshio.Mesh(
        x,
        cells,
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags, TAG_DATA: tags},
        field_data=field_data,
        cell_sets=cell_sets,
    )


def tag_counts(m) -> dict[str, int]:
    """{name: number of cells} of a mesh made by :func:`to_meshio` / :func:`structure_to_meshio`."""
    return {name: int(sum(len(s) for s in sets)) for name, sets in m.cell_sets.items()}


def name_map(m) -> dict[str, dict[str, int]]:
    """{name: {"tag": t, "dim": d}} of a mesh made by :func:`to_meshio` (the sidecar's groups)."""
    return {name: {"tag": int(v[0]), "dim": int(v[1])} for name, v in m.field_data.items()}


def write_mesh(m, out, stem: str, fmt: str, meta: dict | None = None) -> list[pathlib.Path]:
    """Write ``m`` as ``out/<stem>.<fmt>`` (and ``out/<stem>.tags.json`` for xdmf/vtu, with
    ``out/<stem>.h5`` for xdmf); return the paths written.

    The files are written in the folder ``out/<stem>.part/`` and moved into ``out`` when all are
    complete, the mesh file last: a failed write leaves only the ``.part`` folder. ``meta`` (plain
    JSON values) goes into the sidecar beside the name map.
    """
    import meshio

    if fmt not in FORMATS:
        raise InputError(f"format = {fmt!r}: allowed {', '.join(FORMATS)}")
    out = pathlib.Path(out)
    stage = out / f"{stem}.part"
    if stage.exists():
        shutil.rmtree(stage)
    stage.mkdir(parents=True)
    target = stage / f"{stem}{FORMATS[fmt]}"
    written = []
    if fmt == "msh":
        # MSH 2.2 (module docstring); only the tags: the tag data must not be written twice
        plain = meshio.Mesh(
            m.points,
            m.cells,
            field_data=m.field_data,
            cell_data={k: m.cell_data[k] for k in ("gmsh:physical", "gmsh:geometrical")},
        )
        meshio.write(target, plain, file_format=_MESHIO_FORMAT[fmt], binary=False)
    else:
        cells, tags, groups, point_data = (
            list(m.cells),
            list(m.cell_data[TAG_DATA]),
            name_map(m),
            {},
        )
        if fmt == "xdmf":
            # meshio writes vertex cells into a mixed XDMF topology without their node count, which
            # no reader (meshio's own included) parses: node sets go as point data instead
            keep = [k for k, c in enumerate(cells) if c.type != "vertex"]
            name_of = {(g["tag"], g["dim"]): n for n, g in groups.items()}
            for k in sorted(set(range(len(cells))) - set(keep)):
                name = name_of[(int(tags[k][0]), 0)]
                point_data[name] = np.zeros(len(m.points), dtype=np.int32)
                point_data[name][cells[k].data.ravel()] = 1
                groups[name] = {"point_data": name, "dim": 0}
            cells, tags = [cells[k] for k in keep], [tags[k] for k in keep]
        plain = meshio.Mesh(m.points, cells, cell_data={TAG_DATA: tags}, point_data=point_data)
        # XDMF uncompressed (module docstring)
        meshio.write(
            target,
            plain,
            file_format=_MESHIO_FORMAT[fmt],
            **({"compression": None} if fmt == "xdmf" else {}),
        )
        if fmt == "xdmf":  # its arrays, named after it (the .xdmf refers to it by that name)
            written.append(target.with_suffix(".h5"))
        sidecar = stage / f"{stem}.tags.json"
        sidecar.write_text(
            json.dumps(
                {
                    "units": {"length": "mm"},
                    "cell_data": TAG_DATA,
                    "groups": groups,
                    **(meta or {}),
                },
                indent=2,
            )
            + "\n"
        )
        written.append(sidecar)
    written.append(target)  # the mesh file last
    final = []
    for path in written:
        dst = out / path.name
        os.replace(path, dst)
        final.append(dst)
    stage.rmdir()
    return final
