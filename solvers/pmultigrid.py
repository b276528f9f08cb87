"""p-multigrid for the quadratic (Q2/P2) displacement tangent: two levels on the same mesh.

The fine level is the Q2 tangent K (the Jacobian SNES assembles), smoothed by one SSOR sweep;
the coarse level is the Galerkin operator K_1 = P^T K P of the linear (Q1/P1) vector space on the
same mesh, P the interpolation Q1 -> Q2 (exact: every Q1 function is a Q2 function), factorised
(MUMPS LDL^T) or cycled by smoothed-aggregation AMG (GAMG) with the six rigid-body modes of the Q1
space as its near-nullspace. The Q1 operator has 1/8 of the DOFs and a 27-point node stencil (the
Q2 one couples edge, face and cell nodes across 125 points), so its factorisation is cheap; the
smoother only has to remove what Q1 cannot represent within a cell. Aggregation multigrid on the
Q2 matrix itself needs 2-3x the CG iterations (near-incompressible LCE, stretched cells).

PETSc's PCMG drives the cycle (options under the problem's prefix: ``mg_levels_*`` for the Q2
smoother, ``mg_coarse_*`` for the Q1 solve, e.g. ``mg_coarse_pc_gamg_threshold``).
:class:`PMultigrid` builds P once and recomputes K_1 whenever SNES assembles a new K
(:meth:`update`, called from the Jacobian callback), so the coarse AMG hierarchy is rebuilt with
the tangent, as GAMG on K would be.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np

import dolfinx
import dolfinx.fem.petsc

from lcefem.models.errors import InputError

#: The PETSc options of the p-multigrid path (overrides of the Newton options; the problem's
#: ``pc_type = "pmg"`` brings them): CG to a relative 1e-4 (inexact Newton, as for GAMG), PCMG with
#: two levels and a multiplicative V-cycle; on Q2 one symmetric SOR sweep (PETSc's local SSOR, so
#: block Jacobi across processes) before and after the coarse correction; the Q1 level factorised by
#: MUMPS LDL^T (1/8 of the DOFs with a 27-point node stencil; its PCSetUp, wall: 0.4 s at 105k fine
#: DOFs, 9.8 s at 532k, 34 s at 1.11M). Measured on the hot-core strip (``linear_solver_benchmark``,
#: README "Linear solvers on large meshes"): CG iterations per solve 43-60 from 46k to 1.11M DOFs;
#: one GAMG cycle on Q1 instead (:data:`lcefem.solvers.mechanics.PMG_GAMG_COARSE`, memory-scalable)
#: needs 86-113 and 1.6-2.0x the CPU time; two SOR sweeps cut the iterations by
#: 15-25 % for 1.2x the CPU, Chebyshev(3)/Jacobi was 1.5x the CPU of one sweep at 46k, and threshold
#: 0.05, no aggressive coarsening, SOR or two cycles on the Q1 GAMG changed less than 5 %.
#: ``pmg_smoother_mat_type`` (ours, not PETSc's): the SOR sweeps and the level residual run on a
#: copy of K in 3x3 node blocks (BAIJ, refreshed with every tangent; the Galerkin product needs
#: AIJ): a third of AIJ's index traffic, and SOR then inverts each node's 3x3 block. On the
#: hot-state tangent of the 46k strip one CG solve took 6.7-6.8 s CPU with 102 iterations against
#: 8.3-9.0 s with 108 on AIJ (1.27x), one product K x 1.21x faster, the copy 0.105 s CPU per tangent
#: (the Jacobian 0.9 s); over the path-followed solve 188.6 against 203.8 s CPU at 200k DOFs
#: (1.08x, back to back), 1.0-1.07x at 46k. The copy costs memory: 3.2 GiB peak at 532k against
#: 2.4. Chebyshev(2) with the SOR sweep as its preconditioner halves the CG iterations of the
#: hot-state solves (172 against 371 at 46k) for the same or 1.12x the CPU, so it is not kept.
PMG_OPTIONS = {
    "ksp_type": "cg",
    "ksp_rtol": 1e-4,
    "ksp_max_it": 2000,
    "pc_type": "mg",
    "pc_mg_levels": 2,
    "pc_mg_type": "multiplicative",
    "pc_mg_cycle_type": "v",
    "mg_levels_ksp_type": "richardson",
    "mg_levels_pc_type": "sor",
    "mg_levels_ksp_max_it": 1,
    "mg_coarse_ksp_type": "preonly",
    "mg_coarse_pc_type": "cholesky",
    "mg_coarse_pc_factor_mat_solver_type": "mumps",
    "pmg_smoother_mat_type": "baij",
}


#: The Q2 smoother by node planes (``pc_type = "pmg"`` with these overrides; ``pmg_smoother_blocks``
#: is ours, not PETSc's): one damped block-Jacobi sweep (additive Schwarz without overlap, weight
#: 0.7) before and after the coarse correction, a block being the DOFs of
#: :data:`PLANES_PER_BLOCK` consecutive node planes normal to the mesh's longest axis (slices of the
#: strip's cross-section), factorised by PETSc's sparse Cholesky. Why: the slow modes of the
#: hot-state tangent are not smooth (their Q1 interpolant misses 87-100 % of the ten slowest, 46k
#: DOFs, so no coarse operator on Q1 can fix them: selective reduced integration of the volumetric
#: energy on Q1 took 4-5x the CG iterations) but element-scale modes strongly coupled within the
#: section of stretched cells (axial aspect 4), which a point SOR sweep relaxes node by node. On the
#: hot tangent of the 46k path (the three Newton right-hand sides) CG took 15/15/15 iterations and
#: 6.1 s CPU against 83/102/109 and 26 s with one SOR sweep; weight 0.5: 16-18 its, 7.5 s; one plane
#: per block 23-27 its (0.5), two 15-20 (0.7); Chebyshev(2) instead of Richardson 10-11 its, 5.6-7.3
#: s. Over the path-followed solve of the hot-core strip (``linear_solver_benchmark --levels 2 3 4
#: --solvers pmg-planes pmg``, back to back, 2026-11-26) 51-55 CG iterations for the whole path
#: against 371-485, 1.93x / 2.25x / 2.53x less CPU at 46k / 105k / 200k DOFs, and 344 s CPU at 532k
#: (SOR: 602 s; MUMPS LDL^T 1138 s: 3.3x), the stretch LDL^T's to 1.3e-14; peak memory 4.3 GiB at
#: 532k against 3.2 (the block factors). README "Linear solvers on large meshes".
#: Weight 0.7: a block couples to one block on either side (Q2 spans three node planes), so the
#: blocks' inverse times K has eigenvalues below ~2 and 0.7 keeps the sweep contracting (SPD cycle,
#: as CG needs). Needs planes of nodes (structured, transfinite meshes such as the strip's); on an
#: unstructured mesh the blocks are a few nodes and the sweep is close to point-block Jacobi.
PMG_PLANE_SMOOTHER = {
    "pmg_smoother_blocks": "planes",
    "pmg_smoother_mat_type": "aij",
    "mg_levels_pc_type": "asm",
    "mg_levels_pc_asm_type": "basic",
    "mg_levels_pc_asm_overlap": 0,
    "mg_levels_sub_pc_type": "cholesky",
    "mg_levels_ksp_richardson_scale": 0.7,
}

#: Node planes per block of :data:`PMG_PLANE_SMOOTHER` [-]: 3 (15 CG its per solve at 46k) against
#: 2 (15-20) and 1 (23-27 with weight 0.5), the same CPU for 2 and 3.
PLANES_PER_BLOCK = 3


def node_planes(V: dolfinx.fem.FunctionSpace, per_block: int = PLANES_PER_BLOCK) -> list[PETSc.IS]:
    """The owned DOFs of ``V`` grouped by node planes normal to the mesh's longest axis,
    ``per_block`` consecutive planes a block (global PETSc numbering, one IS per block on this
    process): a plane is the nodes whose coordinate along that axis agrees to 1e-6 of the extent."""
    mesh = V.mesh
    comm = mesh.comm
    x = mesh.geometry.x
    lo = np.array([comm.allreduce(float(v), op=MPI.MIN) for v in x.min(axis=0)])
    hi = np.array([comm.allreduce(float(v), op=MPI.MAX) for v in x.max(axis=0)])
    axis = int(np.argmax(hi - lo))
    index_map, bs = V.dofmap.index_map, V.dofmap.index_map_bs
    n = index_map.size_local
    coord = V.tabulate_dof_coordinates()[:n, axis]
    key = np.round((coord - lo[axis]) / (1e-6 * (hi[axis] - lo[axis])))
    order = np.argsort(key, kind="stable")
    starts = np.flatnonzero(np.r_[True, np.diff(key[order]) != 0])
    first = index_map.local_range[0] * bs
    planes = []
    for nodes in np.split(order, starts[per_block::per_block]):
        dofs = first + (bs * np.sort(nodes)[:, None] + np.arange(bs)).ravel()
        planes.append(PETSc.IS().createGeneral(dofs.astype(PETSc.IntType), comm=PETSc.COMM_SELF))
    return planes


class PMultigrid:
    """Two-level p-multigrid (degree ``V``'s -> 1) for the tangent of the vector space ``V``.

    Args:
        V: the displacement space (vector Lagrange of degree >= 2) [mm].
        near_nullspace: a function of a space returning its rigid-body modes (PETSc.NullSpace).
        ksp: the Newton KSP, whose PC (set from the options) must be a two-level PCMG.
    """

    def __init__(self, V: dolfinx.fem.FunctionSpace, near_nullspace, ksp: PETSc.KSP):
        pc = ksp.getPC()
        if pc.getType() != PETSc.PC.Type.MG or pc.getMGLevels() != 2:
            raise InputError(
                '[petsc] pc_type = "pmg": pc_mg_levels must stay 2 (the fine and the '
                f'linear level), got {pc.getMGLevels()}'
            )
        degree = V.ufl_element().embedded_superdegree
        if degree < 2:
            raise InputError(
                f'[petsc] pc_type = "pmg": needs displacements of degree >= 2, these have '
                f'degree {degree} (use pc_type = "gamg")'
            )
        mesh = V.mesh
        self.coarse_space = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (mesh.geometry.dim,)))
        # rows: fine (Q2) DOFs, columns: coarse (Q1) DOFs; ghost contributions summed by assemble
        self.P = dolfinx.fem.petsc.interpolation_matrix(self.coarse_space, V)
        self.P.assemble()
        self.coarse_nullspace = near_nullspace(self.coarse_space)
        self.coarse_matrix = None
        self._fine = None  # the tangent matrix K_1 was computed from (its sparsity is K_1's)
        self.smoothed_matrix = None  # K copied into node blocks (BAIJ) for the Q2 smoother
        # "aij": the smoother sweeps K itself (no copy); "baij": see PMG_OPTIONS
        kind = PETSc.Options(ksp.getOptionsPrefix()).getString("pmg_smoother_mat_type", "baij")
        if kind not in ("aij", "baij"):
            raise InputError(f'[petsc] pmg_smoother_mat_type: "aij" or "baij", got {kind!r}')
        parallel = V.mesh.comm.size > 1
        self.smoother_mat_type = ("mpi" if parallel else "seq") + kind
        # "planes": the Q2 smoother is block Jacobi over node planes (PMG_PLANE_SMOOTHER)
        blocks = PETSc.Options(ksp.getOptionsPrefix()).getString("pmg_smoother_blocks", "none")
        if blocks not in ("none", "planes"):
            raise InputError(f'[petsc] pmg_smoother_blocks: "none" or "planes", got {blocks!r}')
        self.smoother_blocks = node_planes(V) if blocks == "planes" else None
        self.updates = 0  # Galerkin products computed (tests, benchmarks)

    @property
    def coarse_dofs(self) -> int:
        return self.P.getSize()[1]

    def update(self, K: PETSc.Mat) -> bool:
        """K_1 <- P^T K P, in place while K is the same matrix (same sparsity), with the rigid-body
        near-nullspace and symmetry flag GAMG needs. Returns True when K_1 is a new matrix (first
        call, or K replaced, e.g. by a contact pattern): the PCMG must then be given it."""
        self.updates += 1
        if self._fine is not None and self._fine.handle == K.handle:
            K.ptap(self.P, result=self.coarse_matrix)
            if self.smoothed_matrix is not K:
                K.convert(self.smoother_mat_type, self.smoothed_matrix)
            return False
        for m in (self.coarse_matrix, self.smoothed_matrix):
            if m is not None and m is not self._fine:
                m.destroy()
        self._fine = K
        self.coarse_matrix = K.ptap(self.P)
        self.smoothed_matrix = (
            K
            if self.smoother_mat_type == K.getType()
            else K.convert(self.smoother_mat_type, PETSc.Mat())
        )
        self.coarse_matrix.setNearNullSpace(self.coarse_nullspace)
        self.coarse_matrix.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        return True

    def configure(self, ksp: PETSc.KSP) -> None:
        """Give the KSP's PCMG (two levels, from the options) its interpolation and the coarse
        operator (call after :meth:`update` has run once)."""
        pc = ksp.getPC()
        pc.setMGInterpolation(1, self.P)
        pc.getMGCoarseSolve().setOperators(self.coarse_matrix, self.coarse_matrix)
        # PCMG keeps a fine-level operator that is not the KSP's (it re-reads the KSP's only when
        # the smoother's is the same matrix), so the SOR sweeps and the level residual run on BAIJ
        smoother = pc.getMGSmoother(1)
        smoother.setOperators(self.smoothed_matrix, self.smoothed_matrix)
        if self.smoother_blocks is not None:
            # before PCSetUp, which would otherwise split the process's DOFs into one block
            smoother.getPC().setType(PETSc.PC.Type.ASM)
            smoother.getPC().setASMLocalSubdomains(len(self.smoother_blocks), self.smoother_blocks)
