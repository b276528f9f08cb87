"""Shared gmsh plumbing: a session context and conversion to a dolfinx mesh with named tags."""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import gmsh

import dolfinx
import dolfinx.io.gmsh


@dataclass
class TaggedMesh:
    """A dolfinx mesh with cell and facet tags addressed by name.

    Attributes:
        mesh: the dolfinx mesh (coordinates in mm).
        cell_tags, facet_tags: dolfinx MeshTags.
        cells, facets: {name: integer tag} for the named physical groups.
        info: geometric facts of the body the builder derived (lengths in mm), for solvers and
            cases.
    """

    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTags
    facet_tags: dolfinx.mesh.MeshTags
    cells: dict[str, int]
    facets: dict[str, int]
    info: dict

    def cell_tag(self, name: str) -> int:
        return self.cells[name]

    def facet_tag(self, name: str) -> int:
        return self.facets[name]


@contextlib.contextmanager
def gmsh_session(name: str, verbose: bool = False):
    """Initialise gmsh for one model and finalise it afterwards (even on error)."""
    already = gmsh.isInitialized()
    if not already:
        gmsh.initialize(interruptible=False)
    gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
    gmsh.model.add(name)
    try:
        yield gmsh.model
    finally:
        gmsh.model.remove()
        if not already:
            gmsh.finalize()


def to_dolfinx(model, comm: MPI.Comm, rank: int = 0) -> tuple[dolfinx.io.gmsh.MeshData, dict, dict]:
    """Convert the gmsh model (meshed on ``rank``) to dolfinx; return (mesh data, cell names, facet
    names)."""
    data = dolfinx.io.gmsh.model_to_mesh(model, comm, rank, gdim=3)
    cells = {n: g.tag for n, g in data.physical_groups.items() if g.dim == 3}
    facets = {n: g.tag for n, g in data.physical_groups.items() if g.dim == 2}
    return data, cells, facets
