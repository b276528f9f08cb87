"""Displacement supports as named helpers: each returns a list of dolfinx DirichletBCs on a
displacement space V (a blocked vector space, components 0, 1, 2 = x, y, z; values in mm).

* :func:`clamp_face` — every component held on a tagged face (u = value, default 0).
* :func:`plane_clamp` — one component held on a tagged face (u_comp = 0: a mirror plane or a
  frictionless wall).
* :func:`mirror_planes` — several :func:`plane_clamp` at once, skipping planes the mesh lacks
  (a reduced model has only some of them).
* :func:`point_support` — given components held at the node located at a point.
* :func:`rigid_body_321` — the 3-2-1 rule: three points that remove the six rigid-body motions
  and nothing else (statically determinate).
* :func:`point_dofs`, :func:`nodes_on_line` — the DOF look-ups behind them, for custom supports.

Faces are named by the mesh's facet tags (:class:`lcefem.meshes._gmsh.TaggedMesh`), never numbers.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from petsc4py import PETSc

import numpy as np

import dolfinx

from lcefem.models.errors import InputError


def _facets(tmesh, face: str) -> np.ndarray:
    if face not in tmesh.facets:
        raise InputError(
            f"support face {face!r}: not a facet tag of the mesh (has "
            f"{', '.join(sorted(tmesh.facets))})"
        )
    tdim = tmesh.mesh.topology.dim
    tmesh.mesh.topology.create_connectivity(tdim - 1, tdim)
    return tmesh.facet_tags.find(tmesh.facet_tag(face))


def clamp_face(tmesh, V, face: str, value=None) -> list:
    """u = ``value`` [mm] (a 3-vector, a dolfinx Constant for a moving clamp, default 0) on the
    facets tagged ``face``."""
    dofs = dolfinx.fem.locate_dofs_topological(V, tmesh.mesh.topology.dim - 1, _facets(tmesh, face))
    if value is None:
        value = np.zeros(3, dtype=PETSc.ScalarType)
    return [dolfinx.fem.dirichletbc(value, dofs, V)]


def plane_clamp(tmesh, V, face: str, component: int) -> list:
    """u_component = 0 on the facets tagged ``face`` (a mirror plane normal to that axis, or a
    frictionless wall)."""
    dofs = dolfinx.fem.locate_dofs_topological(
        V.sub(component), tmesh.mesh.topology.dim - 1, _facets(tmesh, face)
    )
    return [dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0), dofs, V.sub(component))]


def mirror_planes(tmesh, V, planes: Iterable[tuple[str, int]]) -> list:
    """:func:`plane_clamp` for each (face, normal component) whose face the mesh has (a quarter
    model has two mirror planes, a half model one, the full model none)."""
    return [
        bc
        for face, comp in planes
        if face in tmesh.facets
        for bc in plane_clamp(tmesh, V, face, comp)
    ]


def point_dofs(V, component: int, point, tol: float = 1e-6) -> np.ndarray:
    """DOFs (of V.sub(component)) of the node at ``point`` [mm] (within ``tol``) on this process;
    raises if no process has one (collective over the mesh's communicator)."""
    Vc, _ = V.sub(component).collapse()
    p = np.asarray(point, dtype=float)
    dofs = dolfinx.fem.locate_dofs_geometrical(
        (V.sub(component), Vc), lambda x: np.linalg.norm(x.T - p, axis=1) < tol
    )[0]
    # the node lives on one or a few processes: the others find none, which is no error
    if V.mesh.comm.allreduce(int(dofs.size)) == 0:
        raise InputError(
            f"support point {tuple(float(v) for v in p)}: no node there (tolerance {tol:g} mm)"
        )
    return dofs


def nodes_on_line(V, component: int, marker: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """DOFs (of V.sub(component)) of the nodes where ``marker(x)`` is true (x: (3, n) [mm])."""
    Vc, _ = V.sub(component).collapse()
    return dolfinx.fem.locate_dofs_geometrical((V.sub(component), Vc), marker)[0]


def component_bc(V, component: int, dofs) -> dolfinx.fem.DirichletBC:
    """u_component = 0 on ``dofs`` (indices of V.sub(component))."""
    return dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0), dofs, V.sub(component))


def point_support(V, point, components: Sequence[int], tol: float = 1e-6) -> list:
    """u_c = 0 for each c in ``components`` at the node at ``point`` [mm]."""
    return [component_bc(V, c, point_dofs(V, c, point, tol)) for c in components]


def rigid_body_321(V, a, b, c, tol: float = 1e-6) -> list:
    """The 3-2-1 rule: point ``a`` held in x, y, z; point ``b`` (along x from a) in y and z;
    point ``c`` (off the line ab, in the x-y plane) in z. Removes the six rigid-body motions and
    adds no constraint (no reaction when the body is free of load)."""
    return (
        point_support(V, a, (0, 1, 2), tol)
        + point_support(V, b, (1, 2), tol)
        + point_support(V, c, (2,), tol)
    )


__all__ = [
    "clamp_face",
    "component_bc",
    "mirror_planes",
    "nodes_on_line",
    "plane_clamp",
    "point_dofs",
    "point_support",
    "rigid_body_321",
]
