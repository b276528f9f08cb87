"""Values of a dolfinx Function at given points of the reference configuration, on any number of ranks."""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
import numpy as np
from mpi4py import MPI

import dolfinx
import dolfinx.geometry


class PointProbe:
    """Evaluates Functions at fixed points (n, 3) [mm]; the owning rank of each point answers and the
    result is shared with every rank. The search tree is built once."""

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
            local[self._index] = f.eval(self.points[self._index], np.array(self._cells, dtype=np.int32))
        total = self.mesh.comm.allreduce(local, op=MPI.SUM)
        return total / self._owner_count[:, None]
