"""The cover-scale layer in the bar-and-hinge energy (an equivalent elastic layer,
:mod:`lcefem.models.cover_scales`).

The disks are pinned at the junction centres c_ij (the mean of each junction square's four corners,
the same stations as the paper's nine scale centres). The surface's curvatures at the scales are the
vector finite differences of these centres on the grid pitch p [mm]:

    Dx_ij = c_(i-1)j - 2 c_ij + c_(i+1)j,   Dy_ij = c_i(j-1) - 2 c_ij + c_i(j+1),
    Dxy_ij = c_(i+1)(j+1) - c_(i+1)j - c_i(j+1) + c_ij,

each ~ p^2 kappa n (n the surface normal) for a smooth surface; as vectors they are unchanged by
rigid motions (rotations included), so the layer needs no frame. The plate energy
D A_b (kx^2 + ky^2 + 2 nu kx ky + 2 (1 - nu) kxy^2)/2 is written as the positive semi-definite sum

    U = D/(2 p^4) [ (1 - nu) (sum_x a_x |Dx|^2 + sum_y a_y |Dy|^2) + nu A_b |mean Dx + mean Dy|^2
                    + 2 (1 - nu) sum_cells a_c |Dxy|^2 ],

with a_x = A_b / (number of x stencils) etc.: for a uniform curvature it is exactly the plate energy
over A_b. U = x^T H x / 2 with a constant Hessian H (3N x 3N, N nodes): the layer adds one fixed
block to the model's Hessian. Approximations (stated in docs/fig5_tasks.md): the in-plane part of
the differences (non-uniform in-plane strain) is penalised too; the layer carries no membrane force
(the disks slide); the disks' own weight is in the surface's measured 33 g.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.models.cover_scales import CoverScales
from lcefem.models.errors import InputError
from lcefem.solvers.bar_hinge.model import BarHingeModel


def junction_pitch(structure: BarHingeStructure) -> float:
    """Distance [mm] between neighbouring junction centres as built (square grid)."""
    c = structure.nodes[structure.node_sets["junction_corners"]].mean(axis=2)
    if c.shape[0] < 3 or c.shape[1] < 3:
        raise InputError("cover scales: need at least 3 x 3 junctions (curvature stencils)")
    return float(np.linalg.norm(c[1, 0] - c[0, 0]))


def centre_operator(structure: BarHingeStructure) -> sp.csr_matrix:
    """P (n*n, N): junction centres = P @ node positions (mean of each junction's four corners)."""
    corners = structure.node_sets["junction_corners"].reshape(-1, 4)
    rows = np.repeat(np.arange(corners.shape[0]), 4)
    return sp.csr_matrix(
        (np.full(rows.size, 0.25), (rows, corners.ravel())),
        shape=(corners.shape[0], structure.num_nodes),
    )


def scale_layer_matrix(
    structure: BarHingeStructure, scales: CoverScales = CoverScales()
) -> sp.csr_matrix:
    """The layer's constant Hessian H [N/mm] on the 3N position DOFs (module docstring)."""
    scales = scales.checked()
    n = structure.node_sets["junction_corners"].shape[0]
    p = junction_pitch(structure)
    area = scales.bent_area(p, n)
    nu = scales.poisson_ratio
    idx = np.arange(n * n).reshape(n, n)

    def stencil_rows(entries):  # list of [(junction, coefficient), ...] -> sparse (m, n*n)
        data, r, c = [], [], []
        for k, row in enumerate(entries):
            for j, v in row:
                r.append(k)
                c.append(j)
                data.append(v)
        return sp.csr_matrix((data, (r, c)), shape=(len(entries), n * n))

    dx = stencil_rows(
        [
            [(idx[i - 1, j], 1.0), (idx[i, j], -2.0), (idx[i + 1, j], 1.0)]
            for i in range(1, n - 1)
            for j in range(n)
        ]
    )
    dy = stencil_rows(
        [
            [(idx[i, j - 1], 1.0), (idx[i, j], -2.0), (idx[i, j + 1], 1.0)]
            for i in range(n)
            for j in range(1, n - 1)
        ]
    )
    dxy = stencil_rows(
        [
            [
                (idx[i + 1, j + 1], 1.0),
                (idx[i + 1, j], -1.0),
                (idx[i, j + 1], -1.0),
                (idx[i, j], 1.0),
            ]
            for i in range(n - 1)
            for j in range(n - 1)
        ]
    )
    mean = sp.csr_matrix(dx.mean(axis=0) + dy.mean(axis=0))
    s = (
        (1.0 - nu) * (area / dx.shape[0] * (dx.T @ dx) + area / dy.shape[0] * (dy.T @ dy))
        + nu * area * (mean.T @ mean)
        + 2.0 * (1.0 - nu) * area / dxy.shape[0] * (dxy.T @ dxy)
    )
    s = s * (scales.bending_stiffness / p**4)
    pc = centre_operator(structure)
    scalar = (pc.T @ s @ pc).tocsr()
    return sp.kron(scalar, sp.identity(3), format="csr")


class CoveredModel(BarHingeModel):
    """A :class:`BarHingeModel` with the cover-scale layer: Pi + factor * x^T H x / 2. Build with
    :meth:`from_materials` and call :meth:`attach_scales` before the first solve (it extends the
    Hessian's pattern). ``factor`` (0..1) ramps the layer in (continuation from a bare
    equilibrium)."""

    def attach_scales(
        self, scales: CoverScales = CoverScales(), factor: float = 1.0
    ) -> "CoveredModel":
        if "_reduced_hessians" in self.__dict__:
            raise InputError("cover scales: attach them before the first solve")
        self.scales = scales.checked()
        h = scale_layer_matrix(self.structure, scales).tocoo()
        self._layer = h.tocsr()
        self._layer_values = h.data.copy()
        start = self._coo_rows.size
        self._coo_rows = np.concatenate([self._coo_rows, h.row.astype(self._coo_rows.dtype)])
        self._coo_cols = np.concatenate([self._coo_cols, h.col.astype(self._coo_cols.dtype)])
        self._layer_slice = slice(start, self._coo_rows.size)
        self.factor = float(factor)
        return self

    def layer_energy(self, x) -> float:
        """The layer's energy [mJ] at positions x (with the current factor)."""
        xf = np.asarray(x, dtype=float).reshape(-1)
        return 0.5 * self.factor * float(xf @ (self._layer @ xf))

    def evaluate(self, x: np.ndarray, derivatives: int = 2):
        out = super().evaluate(x, derivatives)
        xf = np.asarray(x, dtype=float).reshape(-1)
        hx = self.factor * (self._layer @ xf)
        e = 0.5 * float(xf @ hx)
        if derivatives == 0:
            return out + e
        if derivatives == 1:
            return out[0] + e, out[1] + hx
        energy, grad, values = out
        values[self._layer_slice] = self.factor * self._layer_values
        return energy + e, grad + hx, values
