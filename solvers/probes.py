"""Values of a dolfinx Function at points of the reference configuration, on any number of ranks."""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import numpy as np

import dolfinx
import dolfinx.geometry


class PointProbe:
    """Evaluates Functions at fixed points (n, 3) [mm]; the owning rank of each point answers and
    the result is shared with every rank. The search tree is built once."""

    def __init__(self, mesh: dolfinx.mesh.Mesh, points: np.ndarray):
        self.mesh = mesh
        self.points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
        tree = dolfinx.geometry.bb_tree(mesh, mesh.topology.dim)
        candidates = dolfinx.geometry.compute_collisions_points(tree, self.points)
        colliding = dolfinx.geometry.compute_colliding_cells(mesh, candidates, self.points)
        n_local = mesh.topology.index_map(mesh.topology.dim).size_local
        self._index, self._cells = [], []
        for i in range(len(self.points)):
            cells = [c for c in colliding.links(i) if c < n_local]  # owned cells only: one answer
            if cells:
                self._index.append(i)
                self._cells.append(cells[0])
        found = np.zeros(len(self.points), dtype=np.int32)
        found[self._index] = 1
        total = mesh.comm.allreduce(found, op=MPI.SUM)
        if np.any(total == 0):
            missing = self.points[total == 0][0]
            raise ValueError(f"probe point {missing.tolist()} lies outside the mesh")
        self._owner_count = total

    def __call__(self, f: dolfinx.fem.Function) -> np.ndarray:
        """(n, value size) array of f at the points."""
        size = int(np.prod(f.ufl_shape)) if f.ufl_shape else 1
        local = np.zeros((len(self.points), size))
        if self._index:
            local[self._index] = f.eval(
                self.points[self._index], np.array(self._cells, dtype=np.int32)
            )
        total = self.mesh.comm.allreduce(local, op=MPI.SUM)
        return total / self._owner_count[:, None]


class StationCurvature:
    """Signed curvature [1/mm] of the circle fitted through deformed stations
    (:func:`lcefem.solvers.analysis.curvature.signed_circle_curvature`): each station is the mean
    of the deformed positions of its nodes (reference points [mm] at nodes of the displacement
    space), the sign from the deformed vector between two ``up`` nodes (positive when the circle's
    centre lies opposite to it). A point that is no node of the mesh but whose image across one of
    the ``mirrors`` (planes (axis, coordinate [mm]): the mesh is a symmetric part of the body) is,
    is taken as that image's deformed position mirrored back. Serial (the node lookup is local).

    ValueError (one line) when a point is no node of the mesh nor of its mirror images."""

    def __init__(self, V: dolfinx.fem.FunctionSpace, stations, up, mirrors=(), tol: float = 1e-6):
        self.X = V.tabulate_dof_coordinates()
        self.tol = tol
        self.mirrors = list(mirrors)
        self.groups = [[self._node(p) for p in pts] for pts in stations]
        self.up_nodes = [self._node(p) for p in up]

    def _reflect(self, p: np.ndarray, planes) -> np.ndarray:
        q = np.array(p, dtype=float)
        for axis, c in planes:
            q[axis] = 2.0 * c - q[axis]
        return q

    def _node(self, point):
        """(node index, mirror planes to apply) of a reference point."""
        import itertools

        p = np.asarray(point, dtype=float)
        for k in range(len(self.mirrors) + 1):
            for planes in itertools.combinations(self.mirrors, k):
                q = self._reflect(p, planes)
                d = np.linalg.norm(self.X - q, axis=1)
                i = int(np.argmin(d))
                if d[i] <= self.tol:
                    return i, planes
        raise ValueError(
            f"station point {p.tolist()} mm is no node of the mesh (nor mirrored across "
            f"{', '.join(f'{"xyz"[a]} = {c:g}' for a, c in self.mirrors) or 'no plane'})"
        )

    def _position(self, x: np.ndarray, node) -> np.ndarray:
        i, planes = node
        return self._reflect(x[i], planes)

    def points(self, u: dolfinx.fem.Function) -> np.ndarray:
        """Deformed stations (n, 3) [mm]."""
        x = self.X + u.x.array.reshape(-1, 3)[: self.X.shape[0]]
        return np.array(
            [np.mean([self._position(x, n) for n in group], axis=0) for group in self.groups]
        )

    def __call__(self, u: dolfinx.fem.Function) -> float:
        from lcefem.solvers.analysis.curvature import signed_circle_curvature

        x = self.X + u.x.array.reshape(-1, 3)[: self.X.shape[0]]
        a, b = (self._position(x, n) for n in self.up_nodes)
        v = b - a
        return signed_circle_curvature(self.points(u), v / np.linalg.norm(v))
