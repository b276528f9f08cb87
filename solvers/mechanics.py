"""Quasi-static finite-strain elasticity: minimise Pi(u) = sum_r int W_r(F) dV - W_ext(u).

The residual R(u; v) = dPi/du [v] and its Jacobian are derived by UFL from the energy, so every
material law enters only through its strain energy density (mJ/mm^3). PETSc SNES (Newton with a
line search) solves each load step; the caller cuts steps on failure
(:mod:`lcefem.solvers.continuation`). The tangent is the Hessian of an energy, so it is symmetric
and MUMPS factorises it as LDL^T (indefinite Cholesky: about half the work and memory of LU);
in serial only its upper triangle is stored (:data:`PACKED_TANGENT`).

Three things every iterate gets (:class:`HyperelasticProblem`):
* the residual skips the Dirichlet lifting when every prescribed value is zero and the iterate
  already satisfies the conditions (the lifting is then exactly zero, but costs a Jacobian
  evaluation on every constrained cell);
* an iterate with a non-finite displacement or an inverted element (det F <= 0 at a quadrature
  point) gets a NaN residual, so SNES stops at once and the step controller cuts and retries
  from the last converged state instead of accepting a non-physical state;
* node couplings outside the form (contact pairs) can be added to the Jacobian's sparsity pattern
  before the first assembly (:meth:`HyperelasticProblem.add_couplings`), so no assembly reallocates.
"""

from __future__ import annotations

import atexit

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes._gmsh import TaggedMesh
from lcefem.models.errors import InputError
from lcefem.solvers import cost
from lcefem.solvers.interrupts import raise_if_interrupted
from lcefem.solvers.petsc_options import check_case_options, forget_solver_options
from lcefem.solvers.pmultigrid import PMG_OPTIONS, PMG_PLANE_SMOOTHER, PMultigrid

#: Quadrature degree for hyperelastic forms: UFL's own estimate for an energy with an inverse
#: spontaneous deformation asks for enormous tables (70 GiB seen); 4 integrates P2/Q2 stiffness
#: well. On hexahedra 4 means 27 points; the next cheaper rule (degree 2 or 3) has 8 points, a
#: reduced integration of Q2 with spurious zero-energy modes: with it the level-0 free strip (0.2 A)
#: stops converging in its first 2 s step and the beam ramp fails at its first step, so 4 stays.
QUADRATURE_DEGREE = 4

#: C compiler flags of the generated kernels (FFCx -> CFFI) of every mechanics form (residual,
#: Jacobian, energy, det F): dolfinx's default is ``-O2``. ``-O3`` with reassociation of
#: floating-point sums (``-fassociative-math`` and the flags it needs) lets the compiler vectorise
#: the quadrature-point and basis-function sums of the hyperelastic kernels: one Jacobian of the
#: composite beam, level 1 (18k DOFs), 0.358 -> 0.16 s CPU (residual 0.12 -> 0.06 s), matrix norms
#: equal to 2e-16 relative (``-O3`` alone: 0.354 s; adding ``-march=native``: 0.139 s, left out so a
#: JIT cache shared between machines stays valid). No ``-ffinite-math-only``: refused iterates
#: carry NaN by design. The -O3 compile of the beam's forms takes about a minute once (cached
#: after), so a process that finds another compiling the same form waits up to ``timeout`` seconds
#: (dolfinx's default, 10 s, failed with two benchmark processes started together).
JIT_OPTIONS = {
    "cffi_extra_compile_args": [
        "-O3",
        "-g0",
        "-fno-math-errno",
        "-fno-trapping-math",
        "-fno-signed-zeros",
        "-fassociative-math",
        "-freciprocal-math",
    ],
    "timeout": 600,
}

NEWTON_OPTIONS = {
    "snes_type": "newtonls",
    "snes_linesearch_type": "cp",  # critical-point search: R is the gradient of Pi
    "snes_rtol": 1e-10,
    "snes_atol": 1e-9,  # N: nodal force residual
    "snes_stol": 0.0,
    "snes_max_it": 25,
    "ksp_type": "preonly",
    "pc_type": "cholesky",  # LDL^T of the symmetric (possibly indefinite) tangent
    "pc_factor_mat_solver_type": "mumps",
}

#: The unsymmetric factorisation (the default before LDL^T): ``petsc_options=LU_OPTIONS``.
LU_OPTIONS = {"pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}

#: The iterative path: conjugate gradients with smoothed-aggregation algebraic multigrid (hypre is
#: not in this PETSc build), the six rigid-body modes as its near-nullspace and the matrix blocked
#: by 3 (``HyperelasticProblem`` sets both when ``pc_type`` is ``gamg``). ``pc_type = "gamg"`` in
#: the overrides brings the whole set (CG, not the direct path's ``preonly``). CG stops at a
#: relative residual of 1e-4 (an inexact Newton): on the strip's hot-core solve Newton still takes 3
#: iterations (as with 1e-8 at 15k DOFs, as LDL^T at 46k) and CG 0.46x the iterations of 1e-8 at
#: 15k; Eisenstat-Walker tolerances (snes_ksp_ew) failed to converge there. Chebyshev/Jacobi stays:
#: SOR halves the CG iterations but costs more per iteration (1.3x CPU at 46k); thresholds -1, 0,
#: 0.05, no aggressive coarsening and Chebyshev degree 2 or 5 were no faster at 15k
#: (``benchmarks/linear_solver_benchmark.py``, README "Linear solvers on large meshes").
GAMG_OPTIONS = {
    "ksp_type": "cg",
    "ksp_rtol": 1e-4,
    "ksp_max_it": 2000,
    "pc_type": "gamg",
    "pc_gamg_threshold": 0.02,
    "pc_gamg_square_graph": 1,
    "mg_levels_ksp_type": "chebyshev",
    "mg_levels_pc_type": "jacobi",
    "mg_levels_ksp_max_it": 3,
}

#: One GAMG V-cycle on the linear level of the p-multigrid instead of its factorisation (with
#: ``pc_type = "pmg"``): the AMG settings of :data:`GAMG_OPTIONS` under the coarse solver's prefix.
PMG_GAMG_COARSE = {
    "mg_coarse_pc_type": "gamg",
    **{
        f"mg_coarse_{k}": v
        for k, v in GAMG_OPTIONS.items()
        if k.startswith(("pc_gamg_", "mg_levels_"))
    },
}

#: Forcing of the last Newton step on the iterative paths [-]: from the third Newton step on, when
#: the quadratic model of the iteration, |R_k+1| ~ |R_k|^3 / |R_k-1|^2, expects Newton's tolerance
#: t (``snes_atol``, or ``snes_rtol`` |R_0| if larger) to be met by this step, CG solves it to the
#: relative tolerance min(ksp_rtol, FINAL_STEP_FORCING t / |R_k|) instead of ksp_rtol alone. Why:
#: CG stops on the preconditioned residual, and on the strip's tangents the true one then is
#: 8.5-10x larger (relative 1.0e-3 after 1e-4 at 46k DOFs); over the path-followed solve at 200k
#: Newton went 2.0e-2, 1.3e-4, 2.1e-6, 1.8e-9 N (atol 1e-9 N) and took a 4th iteration (136 CG
#: iterations) for a residual the exact solve leaves at 1.8e-11 N (LDL^T: 3 iterations). 0.02
#: leaves a margin of ~5 for that ratio. Not from the second step: the first step from the
#: predicted state is not yet quadratic (the model said 1.8e-9 N at 46k, 1.5e-11 N at 2.3k DOFs,
#: where LDL^T left 1.1e-6 and 5.7e-9 N). Eisenstat-Walker forcing (``snes_ksp_ew``, versions 1-3,
#: rtol0 = rtol_max = 1e-2) was tried on the 46k path: the loose first solves cost 4-5 Newton
#: iterations and 295-383 CG iterations against 3 and 331 (the defaults 0.3 / 0.9 did not converge
#: in 25 iterations).
FINAL_STEP_FORCING = 0.02

#: Displacement DOFs (global) [-] from which :func:`solver_options` takes the iterative path when
#: the caller names no ``pc_type``: CG + p-multigrid (:data:`lcefem.solvers.pmultigrid.PMG_OPTIONS`)
#: for quadratic elements. CPU time per Newton iteration (Jacobian + linear solve) on the heated
#: strip, quarter, Q2, one process, p-MG / MUMPS LDL^T: 1.12 at 46k DOFs (3.33 / 2.97 s, back to
#: back), 0.70, 0.49 (back to back), 0.28, 0.20 at 105k, 200k, 339k, 532k (``linear_solver_benchmark
#: --levels 2 3 4 5 6 --solvers ldlt pmg --newton-its 2``, 2026-11-25, load 3-6 on 2 cores; the
#: LDL^T rows above 200k from 2026-11-24); ratio 1 at 5.6e4 DOFs by log-log interpolation. That
#: protocol (two Newton iterations from the cast state) flatters CG: over the whole path-followed
#: solve (``--levels 2 4 --solvers ldlt pmg``) the later tangents need 83 (46k) and 126 (200k) CG
#: iterations per solve against 43 and 52, Newton 4 iterations against LDL^T's 3 at 200k, and p-MG
#: took 181 s CPU against 136 s for LDL^T at 200k. So the switch stays at 3e5, where the
#: two-iteration ratio is 3.6x (339k) and the GAMG crossover was; CG also needs a positive
#: definite tangent, and the bodies that can buckle or touch were measured on the direct path only.
#: With :data:`FINAL_STEP_FORCING` and the BAIJ smoother (2026-11-26, same-day pairs) p-MG takes
#: LDL^T's 3 Newton iterations on the path, and LDL^T / p-MG for the whole solve is 0.43 (46k),
#: 1.01 (105k), 1.49 (200k), and 1.89 at 532k (602 s against the 1138 s of 2026-11-25): the switch
#: stays here. With the smoother by node planes (:data:`AUTOMATIC_PMG_SMOOTHER`, 2026-11-26) LDL^T /
#: p-MG over the path is 0.66 (46k), 1.65 (105k), 3.1-3.6 (200k), 3.3 (532k): crossover ~7e4 DOFs by
#: log-log interpolation. The switch still stays at 3e5: only the strip was measured there, LDL^T
#: fits in memory below it (2.8 GiB at 200k), and moving it would move the strip's finer
#: convergence levels onto CG (same equilibria to the Newton tolerance, other round-off).
ITERATIVE_PATH_DOFS = 300_000

#: The Q2 smoother of the p-multigrid that :func:`solver_options` selects by size: block Jacobi over
#: node planes (:data:`lcefem.solvers.pmultigrid.PMG_PLANE_SMOOTHER`, whose comment gives the
#: measurements) instead of PMG_OPTIONS's one SOR sweep, which stays for ``pc_type = "pmg"`` named
#: by the caller. The blocks need node planes across the longest axis (transfinite hexahedral
#: meshes: the strip, the twisted ribbon); on unstructured meshes the sweep is close to point-block
#: Jacobi.
AUTOMATIC_PMG_SMOOTHER = PMG_PLANE_SMOOTHER


#: The direct path (``pc_type = "cholesky"``) in serial stores the tangent's upper triangle in node
#: blocks (SBAIJ, :func:`_upper_block_matrix`) instead of the whole matrix (AIJ); False keeps AIJ
#: (the benchmarks' reference). Parallel runs keep AIJ: the packed matrix was measured in serial
#: only.
PACKED_TANGENT = True


def solver_options(ndofs: int, overrides: dict | None = None, degree: int = 2) -> dict:
    """PETSc options of a mechanics problem with ``ndofs`` displacement DOFs [-] of polynomial
    ``degree``: :data:`NEWTON_OPTIONS`, then the iterative path's set when the overrides name it
    (``pc_type = "pmg"``: :data:`PMG_OPTIONS`; ``pc_type = "gamg"``: :data:`GAMG_OPTIONS`) or name
    no ``pc_type`` and ``ndofs >= ITERATIVE_PATH_DOFS`` (p-multigrid for degree >= 2, GAMG for
    linear elements, which have no lower degree to go to), then the overrides."""
    overrides = dict(overrides or {})
    options = dict(NEWTON_OPTIONS)
    pc = overrides.get("pc_type")
    automatic = pc is None and ndofs >= ITERATIVE_PATH_DOFS
    if automatic:
        pc = "pmg" if degree >= 2 else "gamg"
    if pc == "pmg":  # not a PETSc name: PCMG with the Q1 level built by HyperelasticProblem
        overrides.pop("pc_type", None)
        options.update(PMG_OPTIONS)
        if automatic:  # the size-selected path smooths by node planes (AUTOMATIC_PMG_SMOOTHER)
            options.update(AUTOMATIC_PMG_SMOOTHER)
    elif pc == "gamg":
        options.update(GAMG_OPTIONS)
    options.update(overrides)
    return options


def rigid_body_modes(V: dolfinx.fem.FunctionSpace) -> PETSc.NullSpace:
    """The six rigid-body displacements of a 3D vector space (three translations, three rotations
    x -> e_i x x about the origin) as an orthonormalised PETSc near-nullspace for algebraic
    multigrid."""
    index_map, bs = V.dofmap.index_map, V.dofmap.index_map_bs
    n = index_map.size_local
    x = V.tabulate_dof_coordinates()[:n]
    basis = [dolfinx.la.vector(index_map, bs=bs, dtype=PETSc.ScalarType) for _ in range(6)]
    arrays = [b.array[: n * bs].reshape(n, bs) for b in basis]
    for i in range(3):
        arrays[i][:, i] = 1.0
    arrays[3][:, 0], arrays[3][:, 1] = -x[:, 1], x[:, 0]
    arrays[4][:, 0], arrays[4][:, 2] = x[:, 2], -x[:, 0]
    arrays[5][:, 2], arrays[5][:, 1] = x[:, 1], -x[:, 2]
    dolfinx.la.orthonormalize(basis)
    vecs = [
        PETSc.Vec().createWithArray(b.array[: n * bs], bsize=bs, comm=V.mesh.comm) for b in basis
    ]
    return PETSc.NullSpace().create(vectors=vecs, comm=V.mesh.comm)


def displacement_space(mesh: dolfinx.mesh.Mesh, degree: int = 2) -> dolfinx.fem.FunctionSpace:
    """Vector Lagrange space (P2 on tetrahedra, Q2 on hexahedra by default) for u [mm]."""
    return dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (mesh.geometry.dim,)))


def volume_measure(tmesh: TaggedMesh, degree: int = QUADRATURE_DEGREE) -> ufl.Measure:
    """dx with the cell tags and a fixed quadrature degree."""
    return ufl.Measure(
        "dx",
        domain=tmesh.mesh,
        subdomain_data=tmesh.cell_tags,
        metadata={"quadrature_degree": degree},
    )


def surface_measure(tmesh: TaggedMesh, degree: int = QUADRATURE_DEGREE) -> ufl.Measure:
    return ufl.Measure(
        "ds",
        domain=tmesh.mesh,
        subdomain_data=tmesh.facet_tags,
        metadata={"quadrature_degree": degree},
    )


def deformation_gradient(u) -> ufl.core.expr.Expr:
    """F = I + Grad u (reference configuration = mesh)."""
    return ufl.Identity(len(u)) + ufl.grad(u)


class HyperelasticProblem:
    """Newton solver for the stationary points of an energy functional ``energy`` (UFL rank-0 form).

    Args:
        u: displacement Function [mm] (its values are the initial guess and receive the solution).
        energy: Pi(u) as a UFL form [mJ], e.g. ``W(F) * dx - dot(t, u) * ds``.
        bcs: Dirichlet conditions (their values may change between solves).
        prefix: PETSc options prefix, unique per problem.
        petsc_options: overrides of :data:`NEWTON_OPTIONS`; the linear solver follows the problem
            size unless they name a ``pc_type`` (:func:`solver_options`).
    """

    def __init__(
        self,
        u: dolfinx.fem.Function,
        energy: ufl.Form,
        bcs=(),
        *,
        prefix: str = "lcefem_mech_",
        petsc_options: dict | None = None,
        check_inversion: bool = True,
        user_options=(),
    ):
        self.u = u
        V = u.function_space
        self.bcs = list(bcs)
        #: the options a user gave (a case file's [petsc]): each one a case file may set (also for a
        #: library caller, who passes them here without the command line), and each read by the
        #: solver
        given = dict(petsc_options or {})
        check_case_options({k: given[k] for k in user_options if k in given})
        self._unchecked_options = [prefix + str(k) for k in user_options]
        self.test = ufl.TestFunction(V)
        self.residual = ufl.derivative(energy, u, self.test)
        jacobian = ufl.derivative(self.residual, u, ufl.TrialFunction(V))
        options = solver_options(
            V.dofmap.index_map.size_global * V.dofmap.index_map_bs,
            petsc_options,
            V.ufl_element().embedded_superdegree,
        )
        self.iterative = options.get("pc_type") in ("gamg", "mg")
        if not self.iterative:  # a direct factorisation that cannot fit: refuse before assembling
            ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
            cost.Estimate().memory(
                "mesh (its level or size)",
                f"{ndofs} displacement DOFs factorised directly",
                cost.fe_memory(ndofs),
            ).check()
        _drop_stale_options(prefix, options)
        self._problem = dolfinx.fem.petsc.NonlinearProblem(
            self.residual,
            u,
            bcs=self.bcs,
            J=jacobian,
            petsc_options=options,
            petsc_options_prefix=prefix,
            jit_options=JIT_OPTIONS,
        )
        self.symmetric = options.get("pc_type") in ("cholesky", "gamg", "mg")
        self.packed = (
            PACKED_TANGENT and options.get("pc_type") == "cholesky" and V.mesh.comm.size == 1
        )
        if self.packed:
            pattern = dolfinx.fem.create_sparsity_pattern(self._problem.J)
            pattern.finalize()
            self._use_matrix(pattern, np.empty((0, 1), dtype=np.int32))
        elif self.symmetric:
            self._problem.A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        self._near_nullspace = rigid_body_modes(V) if self.iterative else None
        if self.iterative:
            self._problem.A.setNearNullSpace(self._near_nullspace)
        self.energy_form = dolfinx.fem.form(energy, jit_options=JIT_OPTIONS)
        self.last_iterations = 0
        self._bc_dofs = [bc.dof_indices()[0] for bc in self.bcs]
        self._det_F = _det_F_expression(u) if check_inversion else None
        self.lifted_residuals = 0  # residuals that needed the lifting (tests, benchmarks)
        self.inverted_iterates = 0  # iterates refused (non-finite or det F <= 0)
        self.tangent_current = False  # the KSP holds a factorised tangent at the saved state
        self._tolerances = None  # SNES (rtol, atol, stol, max_it) as configured
        snes = self.snes
        self._b = snes.getFunction()[0]
        snes.setFunction(self._assemble_residual, self._b)
        # p-multigrid (pc_type = "pmg"): the Q1 Galerkin operator follows every assembled tangent
        self.pmultigrid = None
        A, P, (jac, jargs, jkw) = snes.getJacobian()
        if options.get("pc_type") == "mg":
            self.pmultigrid = PMultigrid(V, rigid_body_modes, snes.getKSP())
            snes.setJacobian(
                self._assemble_jacobian_pmg, A, P, kargs={"assemble": (jac, jargs, jkw)}
            )
        else:
            snes.setJacobian(self._assemble_jacobian, A, P, kargs={"assemble": (jac, jargs, jkw)})
        self._ksp_rtol = options.get("ksp_rtol")
        self._newton_norms = []  # |R_k| [N] of the Newton solve under way (the forcing's model)
        self._predicting = False
        if self.iterative:
            snes.getKSP().setPreSolve(self._final_step_forcing)

    def _final_step_forcing(self, ksp, b, x) -> None:
        """KSP pre-solve hook of the iterative paths: the relative tolerance of this linear solve,
        tightened on the Newton step expected to converge (:data:`FINAL_STEP_FORCING`); the tangent
        predictor's solve keeps the configured one."""
        rtol = self._ksp_rtol
        if not self._predicting:
            k = self.snes.getIterationNumber()
            if k == 0:
                self._newton_norms = []
            norm = b.norm()
            self._newton_norms.append(norm)
            if k >= 2 and len(self._newton_norms) >= 3 and norm > 0.0:
                snes_rtol, atol, _, _ = self.snes.getTolerances()
                target = max(atol, snes_rtol * self._newton_norms[0])
                previous = self._newton_norms[-2]
                if norm**3 / previous**2 < target:
                    rtol = min(rtol, FINAL_STEP_FORCING * target / norm)
        ksp.setTolerances(rtol=rtol)

    def _assemble_jacobian(self, snes, x, A, P, assemble) -> None:
        """SNES Jacobian callback: dolfinx's, after honouring an interrupt an earlier callback
        swallowed (PETSc turns an exception raised inside a callback into an error code; a
        Ctrl-C that landed in an assembly left the matrix unassembled, and every later solve failed
        with "Object is in wrong state" instead of stopping)."""
        raise_if_interrupted()
        jac, jargs, jkw = assemble
        jac(snes, x, A, P, *jargs, **jkw)

    def _assemble_jacobian_pmg(self, snes, x, A, P, assemble) -> None:
        """SNES Jacobian callback of the p-multigrid path: the tangent, then its Q1 Galerkin
        operator (when that operator is new, the PCMG gets its transfer and coarse operators)."""
        raise_if_interrupted()
        jac, jargs, jkw = assemble
        jac(snes, x, A, P, *jargs, **jkw)
        if self.pmultigrid.update(A if P is None else P):
            self.pmultigrid.configure(snes.getKSP())

    def _assemble_residual(self, snes, x, b) -> None:
        """SNES residual callback: R(x), lifted only when the lifting is not identically zero; NaN
        when x is non-finite or inverts an element."""
        from dolfinx.fem.petsc import apply_lifting, assemble_vector, assign, set_bc

        raise_if_interrupted()  # one swallowed inside an earlier callback (see _assemble_jacobian)
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        assign(x, self.u)
        with b.localForm() as local:
            local.set(0.0)
        if not self.admissible():
            self.inverted_iterates += 1
            with b.localForm() as local:
                local.set(np.nan)
            return
        assemble_vector(b, self._problem.F)
        if not self.homogeneous_dirichlet():
            self.lifted_residuals += 1
            apply_lifting(b, [self._problem.J], bcs=[self.bcs], x0=[x], alpha=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        set_bc(b, self.bcs, x0=x, alpha=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)

    def homogeneous_dirichlet(self) -> bool:
        """True when every Dirichlet value is zero and u vanishes on every constrained DOF: the
        lifting -J (g - u) is then zero (collective)."""
        local = True
        values = self.u.x.array
        for bc, dofs in zip(self.bcs, self._bc_dofs):
            g = bc.g
            gval = g.value if hasattr(g, "value") else g.x.array[dofs]
            if np.any(np.asarray(gval) != 0.0) or np.any(values[dofs] != 0.0):
                local = False
                break
        return bool(self.u.function_space.mesh.comm.allreduce(local, op=MPI.LAND))

    def admissible(self) -> bool:
        """u finite and det F > 0 at every quadrature point of the volume forms (collective)."""
        ok = bool(np.all(np.isfinite(self.u.x.array)))
        if ok and self._det_F is not None:
            expr, cells = self._det_F
            det = expr.eval(self.u.function_space.mesh, cells)
            ok = bool(np.all(det > 0.0))
        return bool(self.u.function_space.mesh.comm.allreduce(ok, op=MPI.LAND))

    def add_couplings(self, blocks: np.ndarray) -> None:
        """Add node couplings outside the form to the Jacobian's sparsity pattern: each row of
        ``blocks`` (global node = block indices, the displacement index map's numbering; in serial
        the local ones) couples all its nodes with one another. Rebuilds the matrix (call before
        the first solve). On several ranks each rank passes its own rows (a row's nodes may be
        owned by other ranks): the pattern is built on the index map with the rows' nodes this rank
        neither owns nor ghosts added as ghosts (:func:`with_ghosts`), so the couplings are in it
        before the first assembly and every row of the matrix holds its entries."""
        blocks = np.asarray(blocks, dtype=np.int64).reshape(len(blocks), -1)
        V = self.u.function_space
        if V.mesh.comm.size == 1:
            blocks = blocks.astype(np.int32)
            pattern = dolfinx.fem.create_sparsity_pattern(self._problem.J)
        else:
            from dolfinx.cpp.fem import build_sparsity_pattern
            from dolfinx.cpp.la import SparsityPattern

            bs = V.dofmap.index_map_bs
            imap, local = with_ghosts(V.dofmap.index_map, blocks.ravel())
            blocks = local.reshape(blocks.shape)
            pattern = SparsityPattern(V.mesh.comm, [imap, imap], [bs, bs])
            build_sparsity_pattern(pattern, self._problem.J._cpp_object)
        for row in blocks:
            pattern.insert(row, row)
        pattern.finalize()
        self._use_matrix(pattern, blocks)

    def _use_matrix(self, pattern, blocks: np.ndarray) -> None:
        """Give SNES a new Jacobian matrix with every entry of the finalised node ``pattern``
        allocated and set (to zero), so that no assembly reallocates: SBAIJ of its upper triangle
        on the packed direct path (:func:`_upper_block_matrix`), else AIJ, filled by one assembly
        of the form and zeros on the couplings of ``blocks`` (a final assembly squeezes out
        entries never set, and the couplings would then need a reallocation at their first
        nonzero value)."""
        from dolfinx.cpp.la.petsc import create_matrix

        old = self._problem.A
        bs = self.u.function_space.dofmap.index_map_bs
        if self.packed:
            A = _upper_block_matrix(pattern, bs, old.comm)
            A.setLGMap(*old.getLGMap())
        else:
            A = create_matrix(self.u.function_space.mesh.comm, pattern, None)
            dolfinx.fem.petsc.assemble_matrix(A, self._problem.J, bcs=self.bcs)
            A.assemble(PETSc.Mat.AssemblyType.FLUSH)
            dofs = (bs * blocks[:, :, None] + np.arange(bs, dtype=np.int32)).reshape(
                len(blocks), -1
            )
            zeros = np.zeros((dofs.shape[1], dofs.shape[1]))
            for row in dofs:  # local indices of the pattern's index map (serial: global)
                A.setValuesLocal(row, row, zeros, addv=PETSc.InsertMode.ADD_VALUES)
            A.assemble()
        A.setOptionsPrefix(old.getOptionsPrefix())
        if self.symmetric:
            A.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        if self.iterative:
            A.setNearNullSpace(self._near_nullspace)
        _, _, (jac, jargs, jkw) = self.snes.getJacobian()
        self.snes.setJacobian(jac, A, None, args=jargs, kargs=jkw)
        self._problem._A.destroy()
        self._problem._A = A

    def tangent_predictor(self, set_load, t_from: float, t_to: float, converged=None) -> bool:
        """Euler (tangent) predictor for the load ``t_to`` from the converged state at ``t_from``
        (the current u): u <- u - K^-1 R(u; t_to), K the tangent at that state: the factorisation
        left by its last Newton solve when :attr:`tangent_current`, else assembled and factorised
        here (at ``converged``, an array, if given). The load is left at ``t_to``. Returns False
        (u unchanged) if the predicted state is non-finite or inverts an element.

        (Further chord corrections with the same factorisation were tried on the beam ramp: none
        reduced the residual by half, so Newton starts from the Euler step.)"""
        snes, ksp = self.snes, self.snes.getKSP()
        x = self._problem.x
        guess = self.u.x.array.copy()
        ok = False
        vecs = []
        try:
            if not self.tangent_current:
                if converged is not None:
                    self.restore(converged)
                set_load(t_from)
                dolfinx.fem.petsc.assign(self.u, x)
                A, P, _ = snes.getJacobian()
                snes.computeJacobian(x, A, P)
                ksp.setOperators(A, P)
                self.tangent_current = True
                self.restore(guess)
            set_load(t_to)
            dolfinx.fem.petsc.assign(self.u, x)
            r, du = x.duplicate(), x.duplicate()
            vecs = [r, du]
            snes.computeFunction(x, r)
            if np.isfinite(r.norm()):
                self._predicting = True
                try:
                    ksp.solve(r, du)
                finally:
                    self._predicting = False
                x.axpy(-1.0, du)
                dolfinx.fem.petsc.assign(x, self.u)
                self.u.x.scatter_forward()
                ok = ksp.getConvergedReason() > 0 and self.admissible()
        except PETSc.Error as exc:
            raise_if_interrupted(exc)  # an interrupt in a callback is not a failed prediction
            ok = False
        for v in vecs:
            v.destroy()
        if not ok:
            self.u.x.array[:] = guess
            self.u.x.scatter_forward()
        set_load(t_to)
        return ok

    def residual_norm(self) -> float:
        """|R(u)| [N] at the current u and load (Dirichlet rows included; NaN when u is refused)."""
        x = self._problem.x
        dolfinx.fem.petsc.assign(self.u, x)
        r = x.duplicate()
        try:
            self.snes.computeFunction(x, r)
            return float(r.norm())
        finally:
            r.destroy()

    def path_tolerance(self, atol: float | None) -> None:
        """Newton's absolute residual tolerance [N] for the next solves: ``atol`` if it is looser
        than the configured one (an intermediate state of a path), else the configured one."""
        if self._tolerances is None:
            self._tolerances = self.snes.getTolerances()
        rtol, atol0, stol, max_it = self._tolerances
        self.snes.setTolerances(
            rtol=rtol, atol=atol0 if atol is None else max(atol0, atol), stol=stol, max_it=max_it
        )

    @property
    def snes(self):
        return self._problem.solver

    def solve(self) -> tuple[bool, int, str]:
        """One Newton solve from the current u. Returns (converged, iterations, reason text)."""
        self.tangent_current = False
        try:
            self._problem.solve()
        except PETSc.Error as exc:  # e.g. a factorisation failure
            raise_if_interrupted(exc)  # Ctrl-C inside a PETSc callback is not a failed solve
            return False, self.snes.getIterationNumber(), f"PETSc error {exc}"
        raise_if_interrupted()  # a callback's interrupt PETSc reported as a diverged reason
        reason = self.snes.getConvergedReason()
        its = self.snes.getIterationNumber()
        if its > 0 and self._unchecked_options:
            self._check_options_used()
        self.last_iterations = its
        self.u.x.scatter_forward()
        ok = reason > 0 and bool(np.all(np.isfinite(self.u.x.array)))
        # only Newton's own KSP ends holding the tangent of the converged state (a quasi-Newton or
        # nonlinearly preconditioned SNES factorises elsewhere or at an earlier iterate), and only
        # after an iteration: a start already within tolerance converges at iteration 0 without a
        # Jacobian, and the KSP holds an older tangent or none (the tangent predictor then failed
        # on an unassembled matrix and the path went on without a prediction)
        self.tangent_current = ok and its > 0 and self.snes.getType() == PETSc.SNES.Type.NEWTONLS
        return ok, its, f"SNES reason {reason} ({_snes_reason_name(reason)}) after {its} iterations"

    def _check_options_used(self) -> None:
        """After the first solve that assembled and factorised a tangent, every option the user gave
        has been read by the SNES, KSP, PC or factorisation that it configures; one that was not is
        unknown or misspelt (PETSc only warns at exit, after a run that ignored it): InputError."""
        db = PETSc.Options()
        unused = [name for name in self._unchecked_options if not db.used(name)]
        self._unchecked_options = []
        if unused:
            prefix = self._problem.solver.getOptionsPrefix() or ""
            names = ", ".join(n[len(prefix) :] if n.startswith(prefix) else n for n in unused)
            raise InputError(
                f"[petsc] {names}: not read by this problem's solver (SNES, KSP, PC, "
                "factorisation): an unknown or misspelt option, or one this solver "
                "does not use; see the PETSc manual pages"
            )

    def save(self) -> np.ndarray:
        return self.u.x.array.copy()

    def restore(self, state: np.ndarray) -> None:
        self.u.x.array[:] = state
        self.u.x.scatter_forward()

    def total_energy(self) -> float:
        """Pi(u) [mJ]."""
        comm = self.u.function_space.mesh.comm
        return comm.allreduce(dolfinx.fem.assemble_scalar(self.energy_form), op=MPI.SUM)

    def reaction_form(self, weight: dolfinx.fem.Function) -> dolfinx.fem.Form:
        """Compiled R(u; weight): with ``weight`` equal to a unit vector on the dofs of a
        constrained face and 0 elsewhere, this is the force [N] the body exerts on that face's
        support."""
        return dolfinx.fem.form(
            ufl.replace(self.residual, {self.test: weight}), jit_options=JIT_OPTIONS
        )


# lcefem's problems leave their options in PETSc's database (their solvers read some only when they
# need them); at exit, before PETSc finalises (petsc4py registered its finalisation at import,
# earlier, and atexit runs the latest first), they are removed, so that an option a problem never
# needed (a beam confirmed in 0 Newton iterations never factorises: mat_mumps_icntl_7) is not
# reported as "options you set that were not used"
# (lcefem.solvers.petsc_options.forget_solver_options; the command line also calls it when a command
# ends).
atexit.register(forget_solver_options)


def with_ghosts(imap, blocks: np.ndarray):
    """(index map, local indices): ``imap`` (a dolfinx IndexMap) with the global indices of
    ``blocks`` that this rank neither owns nor ghosts appended to its ghosts, so every local index
    of ``imap`` keeps its meaning, and the local indices of ``blocks`` in the new map (collective:
    each ghost's owner is found from the ranks' owned ranges)."""
    from dolfinx.cpp.common import IndexMap

    comm = imap.comm
    blocks = np.asarray(blocks, dtype=np.int64)
    start, end = imap.local_range
    ghosts = np.asarray(imap.ghosts, dtype=np.int64)
    wanted = np.unique(blocks)
    extra = np.setdiff1d(wanted[(wanted < start) | (wanted >= end)], ghosts)
    starts = np.asarray(comm.allgather(int(start)), dtype=np.int64)
    owners = (np.searchsorted(starts, extra, side="right") - 1).astype(np.int32)
    new = IndexMap(
        comm,
        imap.size_local,
        np.concatenate([ghosts, extra]),
        np.concatenate([np.asarray(imap.owners, dtype=np.int32), owners]),
        GHOST_TAG,
    )
    return new, new.global_to_local(blocks).astype(np.int32)


#: MPI tag of the index map's ghost-owner exchange (dolfinx's default, MPI::tag::consensus_nbx).
GHOST_TAG = 1201


def _drop_stale_options(prefix: str, options: dict) -> None:
    """Remove from PETSc's options database every option under ``prefix`` that ``options`` does not
    set. The options a problem sets stay in the database after it is built (multigrid reads its
    level smoothers' options only at set-up), so without this a later problem of the same prefix
    would inherit them (``pc_mg_levels`` of a p-multigrid is an error for GAMG)."""
    db = PETSc.Options()
    for name in db.getAll():
        if name.startswith(prefix) and name[len(prefix) :] not in options:
            db.delValue(name)


def _upper_block_matrix(pattern, bs: int, comm) -> PETSc.Mat:
    """A serial SBAIJ matrix (block size ``bs``: one node's displacement) holding the blocks of the
    finalised node sparsity ``pattern`` on and above the diagonal, all set to zero; insertions
    below the diagonal are ignored, a new nonzero is an error.

    Why: the tangent is the Hessian of an energy, so its lower triangle repeats the upper one and
    the LDL^T factorisation reads only the upper one. Storing the upper triangle in node blocks
    halves the entries the assembly inserts, and MUMPS takes it without extracting the triangle:
    composite beam, level 1 (18,072 DOFs), one Jacobian 0.215 -> 0.145 s CPU; its ramp to
    (1.33, 1.05) 44.1 -> 39.2 s CPU (mean of two, back to back on a loaded machine, 2026-11-26),
    the same iterations and curvature bit for bit. (dolfinx's own ``kind="sbaij"`` matrix gave a
    wrong matrix-vector product on the level-0 beam: relative error ~1.)"""
    edges, offsets = pattern.graph
    n = len(offsets) - 1
    rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(offsets))
    upper = edges >= rows
    keys = np.unique(rows[upper] * n + edges[upper])  # row-major, columns sorted in each row
    starts = np.zeros(n + 1, dtype=PETSc.IntType)
    np.cumsum(np.bincount(keys // n, minlength=n), out=starts[1:])
    A = PETSc.Mat().createSBAIJ(
        n * bs, bs, csr=(starts, (keys % n).astype(PETSc.IntType)), comm=comm
    )
    A.setOption(PETSc.Mat.Option.IGNORE_LOWER_TRIANGULAR, True)
    A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
    return A


def _det_F_expression(u):
    """(Expression of det F at the quadrature points of degree QUADRATURE_DEGREE, local cells)."""
    import basix

    mesh = u.function_space.mesh
    points, _ = basix.make_quadrature(mesh.basix_cell(), QUADRATURE_DEGREE)
    expr = dolfinx.fem.Expression(ufl.det(deformation_gradient(u)), points, jit_options=JIT_OPTIONS)
    n = mesh.topology.index_map(mesh.topology.dim).size_local
    return expr, np.arange(n, dtype=np.int32)


def assemble_global(form: dolfinx.fem.Form, comm: MPI.Comm) -> float:
    return comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)


def _snes_reason_name(reason: int) -> str:
    for name in dir(PETSc.SNES.ConvergedReason):
        if not name.startswith("_") and getattr(PETSc.SNES.ConvergedReason, name) == reason:
            return name
    return "unknown"
