"""Shared plumbing of the structured hexahedral meshes built directly (not with gmsh): exterior
faces of a hex8 cell list and its conversion to a distributed dolfinx mesh with named tags.

Why not gmsh for these bodies: gmsh's fragment merges every pair of coincident faces, whereas a
strip's unbonded face must keep its own nodes (only a contact term keeps it off the ribbon); a
tensor-product grid also gives the strip and ribbon nodes the same (x, y) stations, which the
node-pair contact of :func:`lcefem.solvers.contact.face_pairs` needs. The FE composite beam
(:func:`lcefem.meshes.composite_beam_fe.build_beam_fe`) and the gridshell
(:mod:`lcefem.meshes.gridshell_fe`) call these functions.

Cells are hex8 in dolfinx's (lexicographic) vertex order: vertex ``a + 2 b + 4 c`` at the corner
(a, b, c) in {0, 1}^3 along (x, y, z).
"""

from __future__ import annotations

import math

import numpy as np

#: Local vertices of each hex8 face, named by its outward normal.
LOCAL_FACES = {
    "-x": (0, 2, 4, 6),
    "+x": (1, 3, 5, 7),
    "-y": (0, 1, 4, 5),
    "+y": (2, 3, 6, 7),
    "-z": (0, 1, 2, 3),
    "+z": (4, 5, 6, 7),
}


def divisions(length: float, size: float, multiplier: int) -> int:
    """Element count on a piece of ``length`` [mm]: ``multiplier * ceil(length/size)`` (>= 1 each),
    so every level refines every piece by the same factor (nested levels)."""
    return multiplier * max(1, int(math.ceil(length / size - 1e-9)))


def exterior_faces(cells: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Faces used by one cell only.

    Returns (face vertices (m, 4), outward side per face (m,) as in :data:`LOCAL_FACES`, owning cell
    (m,)). A face whose nodes two cells share is interior (a bond); an unbonded strip face has its
    own nodes, so it and the ribbon face it touches are both exterior.
    """
    cells = np.asarray(cells, dtype=np.int64)
    nc = cells.shape[0]
    faces = np.concatenate([cells[:, loc] for loc in LOCAL_FACES.values()])
    sides = np.repeat(np.array(list(LOCAL_FACES)), nc)
    owner = np.tile(np.arange(nc), len(LOCAL_FACES))
    _, inverse, counts = np.unique(
        np.sort(faces, axis=1), axis=0, return_inverse=True, return_counts=True
    )
    once = counts[inverse.ravel()] == 1
    return faces[once], sides[once], owner[once]


def tagged_hex_mesh(
    comm,
    cells: np.ndarray,
    x: np.ndarray,
    cell_values: np.ndarray,
    facet_nodes: np.ndarray,
    facet_values: np.ndarray,
    cell_names: dict[str, int],
    facet_names: dict[str, int],
    info: dict,
):
    """dolfinx mesh of hex8 ``cells`` on points ``x`` [mm] with cell and facet tags.

    The input is used from rank 0 (the other ranks pass theirs empty) and dolfinx distributes it.
    Returns a :class:`~lcefem.meshes._gmsh.TaggedMesh` whose ``cells`` / ``facets`` keep only the
    names whose tag occurs somewhere on the mesh.
    """
    import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
    from mpi4py import MPI

    import ufl

    import basix.ufl
    import dolfinx
    import dolfinx.io

    from lcefem.meshes._gmsh import TaggedMesh

    if comm.rank != 0:  # rank 0 holds the input; dolfinx distributes it
        cells, x = np.empty((0, 8), np.int64), np.empty((0, 3))
        cell_values, facet_nodes = np.empty(0, np.int32), np.empty((0, 4), np.int64)
        facet_values = np.empty(0, np.int32)
    cells = np.asarray(cells, dtype=np.int64)
    cell_values = np.asarray(cell_values, dtype=np.int32)
    facet_nodes = np.asarray(facet_nodes, dtype=np.int64).reshape(-1, 4)
    facet_values = np.asarray(facet_values, dtype=np.int32)
    domain = ufl.Mesh(basix.ufl.element("Lagrange", "hexahedron", 1, shape=(3,)))
    msh = dolfinx.mesh.create_mesh(comm, cells, domain, np.asarray(x, dtype=np.float64))
    tags = []
    for dim, ents, vals in ((3, cells, cell_values), (2, facet_nodes, facet_values)):
        local, local_vals = dolfinx.io.distribute_entity_data(msh, dim, ents, vals)
        msh.topology.create_connectivity(dim, 0)
        msh.topology.create_connectivity(dim, 3)
        tags.append(
            dolfinx.mesh.meshtags_from_entities(
                msh,
                dim,
                dolfinx.graph.adjacencylist(local),
                local_vals.astype(np.int32, copy=False),
            )
        )

    def present(values) -> set[int]:
        mine = set(int(v) for v in np.unique(values))
        return comm.allreduce(mine, op=MPI.BOR) if comm.size > 1 else mine

    in_cells, in_facets = present(cell_values), present(facet_values)
    return TaggedMesh(
        msh,
        tags[0],
        tags[1],
        {n: t for n, t in cell_names.items() if t in in_cells},
        {n: t for n, t in facet_names.items() if t in in_facets},
        info,
    )
