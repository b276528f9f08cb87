"""Node-wise terms added to a dolfinx Newton problem outside UFL: frictionless unilateral
node-to-node penalty contact between a strip's free face and a thin ribbon, a nodal proximal
(damping) term and a fixed nodal load (:class:`NodalLoad`, the residual homotopy's offset).

Used by the FE composite beam (:func:`lcefem.meshes.composite_beam_fe.build_beam_fe`), whose strips
and ribbon share their x and y stations: every node p of a strip's unbonded face has, at the same
reference (x, y), a node q on the ribbon face towards the strip and a node r on the ribbon's other
face. With the ribbon's current thickness direction m = (q - r)/|q - r| (pointing to the strip's
side), the gap is

    g = (p - q) . m,

and the penalty energy of the pair is ``E = k A <-g>_+^2 / 2`` with A the tributary area of p (the
integral of its Q2 basis function over the strip face) and k a pressure per penetration [N/mm^3].
Only the normal gap is penalised: sliding is free (frictionless). Pairs are fixed in the reference
configuration, so the gap is exact where the ribbon under a sliding strip is flat (the junctions)
and approximate to second order in the sliding distance where it is curved; this is the "simple
frictionless penalty" of issue 4, not a surface-to-surface contact algorithm.

The energy, its gradient and its exact Hessian (checked against finite differences in
tests/solvers/test_contact.py) are added to the residual and Jacobian a dolfinx NonlinearProblem's
SNES assembles (:func:`attach`).

:class:`NodalDamping` adds ``c/2 sum_i |u_i - a_i|^2`` over the free DOFs (a: an anchor state), a
proximal term that makes a Newton step well posed across a fold of the equilibrium path (a
snap-through); with c -> 0 the solution is an equilibrium of the undamped problem. Unlike a volume
integral it weighs the thin ribbon's nodes as much as the strips'. The pairs couple nodes of
different cells, which UFL forms cannot express; :func:`attach` adds them to the Jacobian's sparsity
pattern before the first assembly.

Under MPI (issue 46) each pair lives on the rank owning its strip node p (:func:`face_pairs` matches
the nodes gathered from every rank and returns the pairs in global node indices); the positions of
its ribbon nodes, which another rank may own, come through an index map with them as ghosts
(:func:`lcefem.solvers.mechanics.with_ghosts`, one forward scatter per residual and Jacobian); the
pairs' couplings enter the Jacobian's pattern by global index, and their residual and Jacobian
entries on rows other ranks own travel in PETSc's assembly. The table's nodes, the damping and the
nodal load act on owned DOFs (diagonal Hessians). Observables (forces, energy, gaps, active sets)
are those of the whole model on every rank (collective).
"""

from __future__ import annotations

from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.models.parameters import param


@dataclass(frozen=True)
class PenaltyContact:
    """Parameters of the strip-ribbon penalty contact."""

    enabled: bool = param(
        True,
        "-",
        "chosen: strips and ribbon may not pass through one another "
        "(the bar-and-hinge model of issue 4 found such contact decisive)",
    )
    stiffness: float = param(
        50.0,
        "N/mm^3",
        "chosen: about 100 x E_LCE/H_strip (0.52 MPa / 1.69 mm), "
        "so the penetration is ~1 % of the strip's own compression under the "
        "same pressure; the case beam_contact_fe shows the curvature does not "
        "depend on it",
        positive=True,
    )


def gap_and_derivatives(p: np.ndarray, q: np.ndarray, r: np.ndarray, hessian: bool = True):
    """Gap g = (p - q) . (q - r)/|q - r| of n pairs (arrays (n, 3) [mm]), its gradient (n, 9) with
    respect to (p, q, r) and, if asked, its Hessian (n, 9, 9)."""
    d = q - r
    ell = np.linalg.norm(d, axis=1)
    m = d / ell[:, None]
    w = p - q
    mw = np.einsum("ij,ij->i", m, w)
    g = mw
    h = (w - m * mw[:, None]) / ell[:, None]  # dg/dd = (I - m m^T) w / |d|
    grad = np.concatenate([m, -m + h, -h], axis=1)
    if not hessian:
        return g, grad, None
    n = p.shape[0]
    eye = np.broadcast_to(np.eye(3), (n, 3, 3))
    mm = np.einsum("ni,nj->nij", m, m)
    proj = (eye - mm) / ell[:, None, None]  # d2g/dw dd
    wm = np.einsum("ni,nj->nij", w, m)
    gdd = (
        -wm - np.transpose(wm, (0, 2, 1)) - mw[:, None, None] * eye + 3.0 * mw[:, None, None] * mm
    ) / (ell**2)[:, None, None]
    # z = (p, q, r): w = p - q, d = q - r
    jw = np.array([1.0, -1.0, 0.0])
    jd = np.array([0.0, 1.0, -1.0])
    H = (
        np.einsum("a,b,nij->naibj", jw, jd, proj)
        + np.einsum("a,b,nij->naibj", jd, jw, proj)
        + np.einsum("a,b,nij->naibj", jd, jd, gdd)
    )
    return g, grad, H.reshape(n, 9, 9)


class NodePairContact:
    """Penalty contact of node pairs (p, q, r) of a vector Q2/P2 space (block indices).

    Args:
        u: displacement Function [mm].
        pairs: (n, 3) global block (node) indices p (strip face), q (ribbon face towards the
            strip), r (ribbon's other face); in serial the local ones. On several ranks each rank
            holds the pairs whose p it owns (:func:`face_pairs`).
        areas: (n,) tributary areas of p [mm^2].
        stiffness: penalty k [N/mm^3].
    """

    def __init__(
        self, u: dolfinx.fem.Function, pairs: np.ndarray, areas: np.ndarray, stiffness: float
    ):
        V = u.function_space
        self.u = u
        self.comm = V.mesh.comm
        self.pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 3)
        self.areas = np.asarray(areas, dtype=float)
        self.stiffness = float(stiffness)
        # global DOFs of each pair (rows and columns of its residual and Jacobian entries)
        self.dofs = (3 * self.pairs[:, :, None] + np.arange(3)).reshape(-1, 9).astype(np.int32)
        if self.comm.size == 1:
            self.rows = self.pairs  # rows of the node arrays: local = global
            self.reference = V.tabulate_dof_coordinates()
            self._nodes = None
        else:  # the pairs' nodes owned elsewhere become ghosts of a map of their own
            from lcefem.solvers.mechanics import with_ghosts

            imap, local = with_ghosts(V.dofmap.index_map, self.pairs.ravel())
            self.rows = local.reshape(-1, 3).astype(np.int64)
            self._nodes = dolfinx.la.vector(imap, 3)
            self._owned = 3 * V.dofmap.index_map.size_local
            X = V.tabulate_dof_coordinates()
            self.reference = self._gathered(X.ravel()).reshape(-1, 3).copy()
        self.fixed = np.zeros(self._local_size(), dtype=bool)
        self.free = np.ones(self.dofs.shape, dtype=bool)

    def _local_size(self) -> int:
        if self._nodes is None:
            return self.u.function_space.dofmap.index_map.size_local * 3
        return self._nodes.array.size

    def _gathered(self, values: np.ndarray) -> np.ndarray:
        """Per-DOF ``values`` of this rank's owned DOFs (the first entries) on the pairs' nodes,
        ghosts included (collective)."""
        v = self._nodes
        v.array[:] = 0.0
        v.array[: self._owned] = values[: self._owned]
        v.scatter_forward()
        return v.array

    def set_constrained(self, bcs) -> None:
        """Rows and columns of Dirichlet DOFs get no contact terms (they are identity rows)."""
        fixed = np.zeros(self.u.x.array.size, dtype=bool)
        for bc in bcs:
            idx, _ = bc.dof_indices()
            fixed[idx] = True
        self.fixed = fixed if self._nodes is None else self._gathered(fixed) > 0.5
        self.free = ~self.fixed[3 * self.rows[:, :, None] + np.arange(3)].reshape(-1, 9)

    def positions(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Current positions [mm] of this rank's p, q, r (collective on several ranks)."""
        u = self.u.x.array if self._nodes is None else self._gathered(self.u.x.array)
        x = self.reference + u.reshape(-1, 3)
        return x[self.rows[:, 0]], x[self.rows[:, 1]], x[self.rows[:, 2]]

    def _sum(self, value: float) -> float:
        return value if self.comm.size == 1 else float(self.comm.allreduce(value))

    def _local_gaps(self) -> np.ndarray:
        return gap_and_derivatives(*self.positions(), hessian=False)[0]

    def gaps(self) -> np.ndarray:
        """Current gaps [mm] (negative: penetration) of every pair (on several ranks gathered from
        all, collective)."""
        g = self._local_gaps()
        return g if self.comm.size == 1 else np.concatenate(self.comm.allgather(g))

    def energy(self) -> float:
        """Penalty energy [mJ]."""
        g = np.minimum(self._local_gaps(), 0.0)
        return self._sum(0.5 * self.stiffness * float(np.sum(self.areas * g * g)))

    def normal_force(self) -> float:
        """Sum of the pair forces k A <-g>_+ [N] (contact force on the mesh)."""
        g = self._local_gaps()
        return self._sum(self.stiffness * float(np.sum(self.areas * np.maximum(-g, 0.0))))

    def active(self) -> np.ndarray:
        return self.gaps() < 0.0

    def add_residual(self, b: PETSc.Vec) -> None:
        g, grad, _ = gap_and_derivatives(*self.positions(), hessian=False)
        on = g < 0.0
        if not np.any(on) and self.comm.size == 1:
            return
        f = (self.stiffness * self.areas[on] * g[on])[:, None] * grad[on]
        idx = self.dofs[on].ravel()
        vals = f.ravel()
        keep = self.free[on].ravel()
        # global rows; those another rank owns reach it in the assembly
        b.setValues(idx[keep].astype(np.int32), vals[keep], addv=PETSc.InsertMode.ADD_VALUES)
        b.assemble()

    def add_jacobian(self, A: PETSc.Mat) -> None:
        g, grad, H = gap_and_derivatives(*self.positions())
        k = self.stiffness * self.areas
        on = g < 0.0
        blocks = np.zeros_like(H)
        blocks[on] = k[on, None, None] * (
            np.einsum("ni,nj->nij", grad[on], grad[on]) + g[on, None, None] * H[on]
        )
        # Same nonzero pattern every time (zeros for open pairs); no terms on Dirichlet
        # rows/columns.
        free = self.free
        blocks *= free[:, :, None] & free[:, None, :]
        for rows, vals in zip(self.dofs, blocks):
            A.setValues(rows, rows, vals, addv=PETSc.InsertMode.ADD_VALUES)
        A.assemble()


class RigidPlaneContact:
    """Frictionless unilateral penalty contact of body nodes with a rigid horizontal plane z = z0
    (a table under the gridshell): gap g = Z + u_z - z0 per node, energy ``k A <-g>_+^2 / 2`` with
    A the node's tributary area [mm^2] on the contacting face and k [N/mm^3] the pressure per
    penetration, as :class:`NodePairContact`. Only u_z enters, so the Jacobian is diagonal.

    A node at the plane (g <= ``touch`` = 1e-9 mm, round-off of the tabulated reference
    coordinates: the as-built state resting on the table) counts as closed in the Jacobian: the
    one-sided Hessian k A that keeps the first Newton step well posed when the plane is the only
    vertical support.

    Args:
        u: displacement Function [mm].
        nodes: local block (node) indices of the contacting face (on several ranks the nodes this
            rank owns: :func:`plane_face_nodes`).
        areas: (n,) tributary areas [mm^2].
        height: z0 [mm] of the plane (reference coordinates).
        stiffness: penalty k [N/mm^3].
    """

    def __init__(
        self,
        u: dolfinx.fem.Function,
        nodes: np.ndarray,
        areas: np.ndarray,
        height: float,
        stiffness: float,
    ):
        V = u.function_space
        self.u = u
        self.comm = V.mesh.comm
        self.nodes = np.asarray(nodes, dtype=np.int64)
        self.areas = np.asarray(areas, dtype=float)
        self.height = float(height)
        self.stiffness = float(stiffness)
        self.z_ref = V.tabulate_dof_coordinates()[self.nodes, 2]
        self.dofs = (3 * self.nodes + 2).astype(np.int32)
        # their global rows (owned nodes: offset by the rank's first DOF; serial: the same)
        self.rows = (self.dofs + 3 * V.dofmap.index_map.local_range[0]).astype(np.int32)
        self.free = np.ones(self.dofs.size, dtype=bool)

    #: Gap [mm] up to which a node counts as touching in the Jacobian (class docstring).
    touch = 1e-9

    def set_constrained(self, bcs) -> None:
        """Dirichlet rows get no contact terms (they are identity rows)."""
        fixed = np.concatenate([bc.dof_indices()[0] for bc in bcs]) if bcs else np.zeros(0)
        self.free = ~np.isin(self.dofs, fixed)

    def _local_gaps(self) -> np.ndarray:
        return self.z_ref + self.u.x.array[self.dofs] - self.height

    def gaps(self) -> np.ndarray:
        """Current gaps [mm] (negative: penetration) of every node (on several ranks gathered
        from all, collective)."""
        g = self._local_gaps()
        return g if self.comm.size == 1 else np.concatenate(self.comm.allgather(g))

    def normal_force(self) -> float:
        """Sum of the nodal reactions k A <-g>_+ [N] (the plane's push on the body)."""
        f = self.stiffness * float(np.sum(self.areas * np.maximum(-self._local_gaps(), 0.0)))
        return f if self.comm.size == 1 else float(self.comm.allreduce(f))

    def active(self) -> np.ndarray:
        return self.gaps() < 0.0

    def add_residual(self, b: PETSc.Vec) -> None:
        g = self._local_gaps()
        on = (g < 0.0) & self.free
        if np.any(on):
            b.setValues(
                self.rows[on],
                self.stiffness * self.areas[on] * g[on],
                addv=PETSc.InsertMode.ADD_VALUES,
            )
        b.assemble()

    def add_jacobian(self, A: PETSc.Mat) -> None:
        on = (self._local_gaps() <= self.touch) & self.free
        k = np.where(on, self.stiffness * self.areas, 0.0)  # same pattern every time (diagonal)
        for dof, value in zip(self.rows[self.free], k[self.free]):
            A.setValue(dof, dof, value, addv=PETSc.InsertMode.ADD_VALUES)
        A.assemble()


def plane_face_nodes(
    V: dolfinx.fem.FunctionSpace, height: float, tol: float = 1e-9
) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (local block indices) of the exterior faces lying in the plane z = height [mm] and
    their tributary areas [mm^2] (integral of each node's basis function over those faces). On
    several ranks: the nodes this rank owns, found on any rank, with their areas summed over the
    ranks (collective)."""
    mesh = V.mesh
    fdim = mesh.topology.dim - 1
    facets = dolfinx.mesh.locate_entities_boundary(
        mesh, fdim, lambda x: np.abs(x[2] - height) < tol
    )
    if mesh.comm.allreduce(facets.size) == 0:
        raise ValueError(f"no exterior face in the plane z = {height} mm")
    tags = dolfinx.mesh.meshtags(mesh, fdim, facets, np.ones(facets.size, dtype=np.int32))
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags, metadata={"quadrature_degree": 4})
    weights = dolfinx.fem.assemble_vector(dolfinx.fem.form(ufl.TestFunction(V)[2] * ds(1)))
    nodes = dolfinx.fem.locate_dofs_topological(V, fdim, facets)
    if mesh.comm.size > 1:  # a node may lie on faces of another rank only: mark, then sum
        weights.scatter_reverse(dolfinx.la.InsertMode.add)
        imap = V.dofmap.index_map
        mark = dolfinx.la.vector(imap, 1)
        mark.array[nodes] = 1.0
        mark.scatter_reverse(dolfinx.la.InsertMode.add)
        nodes = np.flatnonzero(mark.array[: imap.size_local] > 0.0).astype(np.int32)
    areas = weights.array.reshape(-1, 3)[:, 2]
    return nodes, areas[nodes]


class _NodalTerm:
    """A term on the free DOFs of ``u`` that this rank owns (its Hessian is diagonal, so no DOF of
    another rank enters): :func:`attach` marks the constrained ones."""

    def __init__(self, u: dolfinx.fem.Function):
        self.u = u
        self.fixed = np.zeros(u.x.array.size, dtype=bool)

    def set_constrained(self, bcs) -> None:
        self.fixed[:] = False
        for bc in bcs:
            idx, _ = bc.dof_indices()
            self.fixed[idx] = True

    def _add_on_free(self, b: PETSc.Vec, values: np.ndarray) -> None:
        """b += values (one per local DOF of ``u``) on the free DOFs."""
        n = b.getLocalSize()
        r = values[:n].copy()
        r[self.fixed[:n]] = 0.0
        with b.localForm() as local:
            local.array[:n] += r


class NodalDamping(_NodalTerm):
    """Proximal term c/2 sum |u - anchor|^2 over the free DOFs [mJ]; ``weight`` c [N/mm] is 0 (off)
    except while a path follower relaxes across a fold."""

    def __init__(self, u: dolfinx.fem.Function):
        super().__init__(u)
        self.weight = 0.0
        self.anchor = np.zeros(u.x.array.size)

    def add_residual(self, b: PETSc.Vec) -> None:
        if self.weight != 0.0:
            self._add_on_free(b, self.weight * (self.u.x.array - self.anchor))

    def add_jacobian(self, A: PETSc.Mat) -> None:
        if self.weight == 0.0:
            return
        d = A.createVecLeft()
        n = d.getLocalSize()
        d.setArray(np.where(self.fixed[:n], 0.0, self.weight))
        A.setDiagonal(d, addv=PETSc.InsertMode.ADD_VALUES)
        A.assemble()
        d.destroy()


class NodalLoad(_NodalTerm):
    """A fixed nodal force vector f [N] (one entry per owned DOF) scaled by ``factor`` [-]: the
    residual gains -factor f on the free DOFs (the potential -factor f . u [mJ]; no Jacobian). 0
    (off) except while :meth:`lcefem.solvers.problems.gridshell.GridshellFE.settle` follows the
    residual homotopy R(u) - (1 - s) R(u_0) = 0 from a state u_0 that is no equilibrium
    (f = R(u_0), factor = 1 - s): u_0 solves it at s = 0, an equilibrium at s = 1."""

    def __init__(self, u: dolfinx.fem.Function):
        super().__init__(u)
        self.factor = 0.0
        # one entry per owned DOF (the residual vector's local part; serial: every DOF)
        V = u.function_space
        self.force = np.zeros(V.dofmap.index_map.size_local * V.dofmap.index_map_bs)

    def add_residual(self, b: PETSc.Vec) -> None:
        if self.factor != 0.0:
            self._add_on_free(b, -self.factor * self.force)

    def add_jacobian(self, A: PETSc.Mat) -> None:
        """Constant in u: nothing."""


def face_pairs(
    tmesh: TaggedMesh,
    V: dolfinx.fem.FunctionSpace,
    strip_face: str,
    ribbon_cells: str,
    strip_above: bool,
    decimals: int = 6,
) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (p, q, r) and tributary areas [mm^2] for the nodes of facet group ``strip_face``.

    q and r are the ribbon (cells ``ribbon_cells``) nodes with the same reference (x, y) as p on the
    ribbon face towards the strip (``strip_above``: its top face) and on its other face. Nodes of
    the strip face that belong to the ribbon too (the bonded edges) are skipped. On several ranks
    (collective): the nodes of every rank are matched, and each rank gets the pairs whose p it owns,
    in global node indices.
    """
    mesh = tmesh.mesh
    fdim = mesh.topology.dim - 1
    mesh.topology.create_connectivity(fdim, mesh.topology.dim)
    facets = tmesh.facet_tags.find(tmesh.facet_tag(strip_face))
    p_nodes = dolfinx.fem.locate_dofs_topological(V, fdim, facets)
    ribbon = dolfinx.fem.locate_dofs_topological(
        V, mesh.topology.dim, tmesh.cell_tags.find(tmesh.cell_tag(ribbon_cells))
    )
    X = V.tabulate_dof_coordinates()
    # tributary areas: integral of each node's basis function over the strip face
    v = ufl.TestFunction(V)
    ds = ufl.Measure(
        "ds", domain=mesh, subdomain_data=tmesh.facet_tags, metadata={"quadrature_degree": 4}
    )
    weights = dolfinx.fem.assemble_vector(dolfinx.fem.form(v[2] * ds(tmesh.facet_tag(strip_face))))
    if mesh.comm.size == 1:
        p_nodes = np.setdiff1d(p_nodes, ribbon)
        q, r = _ribbon_partners(strip_face, X[p_nodes], ribbon, X[ribbon], strip_above, decimals)
        areas = weights.array.reshape(-1, 3)[p_nodes, 2]
        return np.column_stack([p_nodes, q, r]), areas
    weights.scatter_reverse(dolfinx.la.InsertMode.add)  # the owners' areas, whole
    imap = V.dofmap.index_map
    p_ids, p_x = _gather_nodes(imap, p_nodes, X)
    r_ids, r_x = _gather_nodes(imap, ribbon, X)
    keep = ~np.isin(p_ids, r_ids)
    p_ids, p_x = p_ids[keep], p_x[keep]
    start, end = imap.local_range
    # every rank matches every node (the same data: the same answer, or the same error)
    q, r = _ribbon_partners(strip_face, p_x, r_ids, r_x, strip_above, decimals)
    mine = (p_ids >= start) & (p_ids < end)
    areas = weights.array.reshape(-1, 3)[p_ids[mine] - start, 2]
    return np.column_stack([p_ids[mine], q[mine], r[mine]]), areas


def _gather_nodes(imap, nodes: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Global indices (sorted, each once) and reference coordinates [mm] of the local ``nodes`` of
    every rank (collective)."""
    comm = imap.comm
    ids = np.concatenate(comm.allgather(imap.local_to_global(np.asarray(nodes, dtype=np.int32))))
    xs = np.concatenate(comm.allgather(X[nodes]))
    ids, first = np.unique(ids, return_index=True)
    return ids, xs[first]


def _ribbon_partners(
    strip_face: str,
    p_x: np.ndarray,
    ribbon: np.ndarray,
    r_x: np.ndarray,
    strip_above: bool,
    decimals: int,
) -> tuple[np.ndarray, np.ndarray]:
    """q and r of :func:`face_pairs` for strip nodes at ``p_x`` (n, 3) [mm] among the ribbon nodes
    ``ribbon`` at ``r_x``."""
    # ribbon columns: nodes grouped by (x, y), extremes in z are its bottom and top faces
    keys = np.round(r_x[:, :2], decimals)
    order = np.lexsort((r_x[:, 2], keys[:, 1], keys[:, 0]))
    keys, nodes = keys[order], ribbon[order]
    uniq, first, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    bottom = nodes[first]
    top = nodes[first + counts - 1]
    lookup = {tuple(k): i for i, k in enumerate(uniq)}
    pk = np.round(p_x[:, :2], decimals)
    col = np.array([lookup.get(tuple(k), -1) for k in pk], dtype=np.int64)
    if np.any(col < 0):
        raise ValueError(
            f"{strip_face}: {int(np.sum(col < 0))} strip nodes have no ribbon node at "
            "the same (x, y); the bodies must share their x and y stations"
        )
    q = top[col] if strip_above else bottom[col]
    r = bottom[col] if strip_above else top[col]
    return q, r


def attach(problem, contacts: list) -> None:
    """Add the node-wise terms' residual and Jacobian (``contacts``: :class:`NodePairContact`,
    :class:`NodalDamping`) to the SNES callbacks of ``problem`` (a
    :class:`lcefem.solvers.mechanics.HyperelasticProblem`; its own assembly runs first and copies
    the iterate into ``u``). The contact pairs' couplings join the Jacobian's sparsity pattern
    before the first assembly, so no assembly reallocates."""
    snes = problem.snes
    for c in contacts:
        c.set_constrained(problem.bcs)
    pairs = [c.pairs for c in contacts if isinstance(c, NodePairContact)]
    if pairs:
        problem.add_couplings(np.concatenate(pairs))
    b, (residual, r_args, r_kargs) = snes.getFunction()
    J, P, (jacobian, j_args, j_kargs) = snes.getJacobian()
    r_args, r_kargs, j_args, j_kargs = r_args or (), r_kargs or {}, j_args or (), j_kargs or {}

    def with_contact_residual(snes_, x, f):
        residual(snes_, x, f, *r_args, **r_kargs)
        if not np.isfinite(f.norm()):  # refused iterate (NaN residual): keep it NaN
            return
        for c in contacts:
            c.add_residual(f)

    def with_contact_jacobian(snes_, x, A, B):
        jacobian(snes_, x, A, B, *j_args, **j_kargs)
        for c in contacts:
            c.add_jacobian(A)

    snes.setFunction(with_contact_residual, b)
    snes.setJacobian(with_contact_jacobian, J, P)


def facing_pairs(
    tmesh: TaggedMesh,
    V: dolfinx.fem.FunctionSpace,
    boundary: str,
    target: str,
    axis: int,
    decimals: int = 6,
) -> tuple[np.ndarray, np.ndarray]:
    """Pairs (p, q, r) of :class:`NodePairContact` and tributary areas [mm^2] between two named
    facet sets that face each other across the reference direction ``axis`` (0, 1, 2: x, y, z).

    p runs over the nodes of ``boundary``; q is the node of ``target`` with the same two other
    reference coordinates (rounded to ``decimals`` mm: the two faces must share their stations, as
    the composite beam's strips and ribbon do); r is the node of the cells that own ``target``'s
    facets, at those coordinates, farthest from q along ``axis`` (the cell's other side: the current
    m = (q - r)/|q - r| is the target's normal through its cell layer). Nodes of ``boundary`` that
    lie on ``target`` too (bonded edges) are skipped. With ``boundary`` a strip's free face and
    ``target`` the face of a one-element-thick ribbon towards it this gives the pairs of
    :func:`face_pairs`. The areas are the integrals of each p's basis function over ``boundary``.

    ValueError (one line) when a node of ``boundary`` has no partner or two nodes of ``target``
    share the coordinates of one."""
    mesh = V.mesh
    tdim = mesh.topology.dim
    fdim = tdim - 1
    mesh.topology.create_connectivity(fdim, tdim)
    b_facets = tmesh.facet_tags.find(tmesh.facet_tag(boundary))
    t_facets = tmesh.facet_tags.find(tmesh.facet_tag(target))
    p_nodes = dolfinx.fem.locate_dofs_topological(V, fdim, b_facets)
    q_nodes = dolfinx.fem.locate_dofs_topological(V, fdim, t_facets)
    p_nodes = np.setdiff1d(p_nodes, q_nodes)
    f2c = mesh.topology.connectivity(fdim, tdim)
    owners = (
        np.unique(np.concatenate([f2c.links(f) for f in t_facets]))
        if t_facets.size
        else np.zeros(0, dtype=np.int32)
    )
    column = dolfinx.fem.locate_dofs_topological(V, tdim, owners.astype(np.int32))
    X = V.tabulate_dof_coordinates()
    others = [i for i in range(3) if i != axis]

    def keys(nodes):
        return [tuple(k) for k in np.round(X[nodes][:, others], decimals)]

    q_of = {}
    for k, q in zip(keys(q_nodes), q_nodes):
        if k in q_of:
            raise ValueError(
                f"{target}: two nodes at the same {'xyz'[others[0]]}, {'xyz'[others[1]]} "
                f"= {k} [mm]; the target face must be single-valued across {'xyz'[axis]}"
            )
        q_of[k] = int(q)
    r_of: dict[tuple, int] = {}
    for k, n in zip(keys(column), column):
        q = q_of.get(k)
        if q is None:
            continue
        best = r_of.get(k)
        if best is None or abs(X[n, axis] - X[q, axis]) > abs(X[best, axis] - X[q, axis]):
            r_of[k] = int(n)
    pk = keys(p_nodes)
    missing = [k for k in pk if k not in q_of]
    if missing:
        raise ValueError(
            f"{boundary}: {len(missing)} nodes have no node of {target} at the same "
            f"{'xyz'[others[0]]}, {'xyz'[others[1]]} (first at {missing[0]} mm); the two "
            "faces must share their stations"
        )
    q = np.array([q_of[k] for k in pk], dtype=np.int64)
    r = np.array([r_of[k] for k in pk], dtype=np.int64)
    if np.any(q == r):
        raise ValueError(f"{target}: its cells have no thickness along {'xyz'[axis]}")
    v = ufl.TestFunction(V)
    ds = ufl.Measure(
        "ds", domain=mesh, subdomain_data=tmesh.facet_tags, metadata={"quadrature_degree": 4}
    )
    weights = dolfinx.fem.assemble_vector(dolfinx.fem.form(v[2] * ds(tmesh.facet_tag(boundary))))
    areas = weights.array.reshape(-1, 3)[p_nodes, 2]
    return np.column_stack([p_nodes, q, r]), areas
