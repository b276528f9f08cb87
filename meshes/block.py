"""A rectangular block [0, Lx] x [0, Ly] x [0, Lz] (mm): the specimen of verification problems
(manufactured solutions, homogeneous uniaxial tests).

Tags (by name): cells "body"; facets "x0", "x1", "y0", "y1", "z0", "z1" (the faces at the lower and
upper bound of each coordinate).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import numpy as np

import dolfinx

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.meshes.communicator import resolve_comm
from lcefem.models.errors import InputError

FACETS = ("x0", "x1", "y0", "y1", "z0", "z1")


def build_block(
    lengths=(1.0, 1.0, 1.0), divisions=(2, 2, 2), cell: str = "hex", comm: MPI.Comm | None = None
) -> TaggedMesh:
    """Structured block mesh of hexahedra (``cell="hex"``) or tetrahedra (``"tet"``)."""
    if any(L <= 0 for L in lengths):
        raise InputError(f"block lengths = {tuple(lengths)} mm: must be > 0")
    if any(int(n) < 1 for n in divisions):
        raise InputError(f"block divisions = {tuple(divisions)}: must be >= 1")
    cell_type = {"hex": dolfinx.mesh.CellType.hexahedron, "tet": dolfinx.mesh.CellType.tetrahedron}
    if cell not in cell_type:
        raise InputError(f"cell = {cell!r}: allowed hex, tet")
    mesh = dolfinx.mesh.create_box(
        resolve_comm(comm),
        [np.zeros(3), np.asarray(lengths, dtype=float)],
        [int(n) for n in divisions],
        cell_type[cell],
    )
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    facets, values = [], []
    for tag, name in enumerate(FACETS, start=1):
        axis, upper = divmod(tag - 1, 2)
        where = lengths[axis] if upper else 0.0
        found = dolfinx.mesh.locate_entities_boundary(
            mesh, tdim - 1, lambda x, a=axis, w=where: np.isclose(x[a], w)
        )
        facets.append(found)
        values.append(np.full(len(found), tag, dtype=np.int32))
    order = np.argsort(np.concatenate(facets))
    facet_tags = dolfinx.mesh.meshtags(
        mesh, tdim - 1, np.concatenate(facets)[order], np.concatenate(values)[order]
    )
    n_cells = mesh.topology.index_map(tdim).size_local
    cell_tags = dolfinx.mesh.meshtags(
        mesh, tdim, np.arange(n_cells, dtype=np.int32), np.ones(n_cells, dtype=np.int32)
    )
    info = {
        "lengths": tuple(float(L) for L in lengths),
        "divisions": tuple(int(n) for n in divisions),
        "cell": cell,
        "element_size": float(max(L / n for L, n in zip(lengths, divisions))),
    }
    return TaggedMesh(
        mesh,
        cell_tags,
        facet_tags,
        {"body": 1},
        {name: i for i, name in enumerate(FACETS, start=1)},
        info,
    )
