"""Transfer of a finite-element field between two meshes of the same tagged body (mesh
refinement, ``lcefem converge --prolong``).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

import numpy as np

from lcefem.models.errors import InputError


def prolong_by_tag(u_from, tags_from, V_to, tags_to) -> np.ndarray:
    """Nodal values (n, bs) of the vector field ``u_from`` at the DOF nodes of ``V_to`` (another
    mesh of the same body), cell tag by cell tag: a node of a tag-k cell takes the value of the
    tag-k cell of the other mesh that contains it (or, where the meshes' discretised geometry
    differs, e.g. the arch's chords, the nearest tag-k cell, its polynomial extended). By tag, so
    that bodies that touch without being bonded (strips over ribbons) each keep their own
    displacement at the shared surface. Serial."""
    from dolfinx import geometry

    mesh0 = u_from.function_space.mesh
    dim = mesh0.topology.dim
    X = V_to.tabulate_dof_coordinates()
    dofs = V_to.dofmap.list
    cell_tag = np.full(dofs.shape[0], -1, dtype=np.int32)
    cell_tag[tags_to.indices] = tags_to.values
    out = np.full((X.shape[0], u_from.function_space.dofmap.index_map_bs), np.nan)
    for tag in np.unique(tags_to.values):
        cells0 = tags_from.find(int(tag))
        if cells0.size == 0:
            raise InputError(f"prolong: cell tag {tag} has no cells on the source mesh")
        nodes = np.unique(dofs[cell_tag == tag].ravel())
        nodes = nodes[np.isnan(out[nodes, 0])]  # shared (bonded) nodes: the first tag's value
        if nodes.size == 0:
            continue
        pts = np.ascontiguousarray(X[nodes])
        tree = geometry.bb_tree(mesh0, dim, entities=cells0)
        hits = geometry.compute_colliding_cells(
            mesh0, geometry.compute_collisions_points(tree, pts), pts
        )
        counts = np.diff(hits.offsets)
        owner = np.full(nodes.size, -1, dtype=np.int32)
        owner[counts > 0] = hits.array[hits.offsets[:-1][counts > 0]]
        lost = np.flatnonzero(owner < 0)
        if lost.size:
            mid = geometry.create_midpoint_tree(mesh0, dim, cells0)
            owner[lost] = geometry.compute_closest_entity(tree, mid, mesh0, pts[lost])
        out[nodes] = u_from.eval(pts, owner)
    if np.isnan(out).any():
        raise RuntimeError("prolong: nodes outside every tagged cell")
    return out
