"""The Newton problem and the shared step controller (solvers/mechanics.py,
solvers/continuation.py): the residual without lifting equals dolfinx's lifted residual when every
Dirichlet value is zero, LDL^T and LU give the same equilibrium, inverted or non-finite iterates are
refused, the controller cuts, recovers and never grows straight into a known failure, the contact
pairs are in the Jacobian's preallocated pattern, and the direct path's upper-triangle storage is
the whole tangent."""

import dolfinx_solver  # noqa: F401
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import pytest
import ufl

import dolfinx
import dolfinx.fem.petsc

from lcefem.models.errors import ConvergenceError
from lcefem.models.hyperelastic import NeoHookeanSolid, neo_hookean_strain_energy
from lcefem.solvers.continuation import PathControl, PathFollower, advance
from lcefem.solvers.mechanics import (
    LU_OPTIONS,
    HyperelasticProblem,
    deformation_gradient,
    displacement_space,
)


def _block(traction: float, prefix: str, options=None, clamp_value=None):
    """A 4 x 1 x 1 mm neo-Hookean bar (soft: E = 1 MPa), clamped at x = 0, pulled at x = 4 by a dead
    traction [MPa]; returns (problem, traction Constant, clamp Constant)."""
    mesh = dolfinx.mesh.create_box(
        MPI.COMM_WORLD, [[0, 0, 0], [4, 1, 1]], [4, 1, 1], dolfinx.mesh.CellType.hexahedron
    )
    V = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(V)
    fdim = mesh.topology.dim - 1
    left = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[0], 0.0))
    right = dolfinx.mesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[0], 4.0))
    tags = dolfinx.mesh.meshtags(mesh, fdim, right, np.ones_like(right))
    clamp = dolfinx.fem.Constant(
        mesh, np.zeros(3) if clamp_value is None else np.asarray(clamp_value)
    )
    bcs = [dolfinx.fem.dirichletbc(clamp, dolfinx.fem.locate_dofs_topological(V, fdim, left), V)]
    t = dolfinx.fem.Constant(mesh, PETSc.ScalarType(traction))
    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 4})
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags, metadata={"quadrature_degree": 4})
    solid = NeoHookeanSolid(youngs_modulus=1.0, poisson_ratio=0.3)
    energy = neo_hookean_strain_energy(deformation_gradient(u), solid) * dx - t * u[0] * ds(1)
    return HyperelasticProblem(u, energy, bcs, prefix=prefix, petsc_options=options), t, clamp


def _stock_residual(problem) -> np.ndarray:
    """dolfinx's own residual (with the lifting) at the current u."""
    p = problem._problem
    x = p.x.duplicate()
    dolfinx.fem.petsc.assign(problem.u, x)
    b = p.b.duplicate()
    dolfinx.fem.petsc.assemble_residual(problem.snes, x, b, problem.u, p.F, p.J, problem.bcs)
    return b.array.copy()


def _residual(problem) -> np.ndarray:
    x = problem._problem.x.duplicate()
    dolfinx.fem.petsc.assign(problem.u, x)
    b = x.duplicate()
    problem.snes.computeFunction(x, b)
    return b.array.copy()


def test_zero_dirichlet_residual_skips_lifting_and_equals_the_lifted_one():
    problem, _, clamp = _block(0.05, "test_zero_bc_")
    rng = np.random.default_rng(3)
    u = problem.u
    u.x.array[:] = 0.01 * rng.standard_normal(u.x.array.size)
    for dofs in problem._bc_dofs:
        u.x.array[dofs] = 0.0
    assert problem.homogeneous_dirichlet()
    np.testing.assert_allclose(_residual(problem), _stock_residual(problem), rtol=0, atol=1e-13)
    assert problem.lifted_residuals == 0
    # a non-zero prescribed value needs the lifting, and gets it
    clamp.value = np.array([0.01, 0.0, 0.0])
    assert not problem.homogeneous_dirichlet()
    np.testing.assert_allclose(_residual(problem), _stock_residual(problem), rtol=0, atol=1e-13)
    assert problem.lifted_residuals == 1


def test_symmetric_factorisation_gives_the_lu_solution():
    ldlt, _, _ = _block(0.1, "test_ldlt_")
    lu, _, _ = _block(0.1, "test_lu_", options=LU_OPTIONS)
    assert ldlt.snes.getKSP().getPC().getType() == "cholesky"
    assert lu.snes.getKSP().getPC().getType() == "lu"
    for p in (ldlt, lu):
        ok, its, reason = p.solve()
        assert ok, reason
    assert np.max(np.abs(ldlt.u.x.array)) > 0.1  # finite strain
    np.testing.assert_allclose(ldlt.u.x.array, lu.u.x.array, rtol=0, atol=1e-10)


def test_inverted_iterate_is_refused():
    problem, _, _ = _block(0.0, "test_inverted_")
    X = problem.u.function_space.tabulate_dof_coordinates()
    problem.u.x.array.reshape(-1, 3)[:, 0] = -2.0 * X[:, 0]  # F_xx = -1: every element inverted
    assert not problem.admissible()
    ok, _, reason = problem.solve()
    assert not ok and "NAN" in reason.upper()
    assert problem.inverted_iterates >= 1


class _ScalarProblem:
    """A stand-in problem with one scalar state, the equilibrium at load t being the state t."""

    def __init__(self):
        self.load, self.state = 0.0, 0.0

    def set_load(self, t):
        self.load = t

    def save(self):
        return self.state

    def restore(self, state):
        self.state = state


class _FailingAbove(_ScalarProblem):
    """A stand-in problem whose Newton solve fails (NaN) for any increment larger than ``limit``."""

    def __init__(self, limit: float):
        super().__init__()
        self.limit = limit
        self.trials = []

    def solve(self):
        step = self.load - self.state
        self.trials.append((self.state, self.load, step <= self.limit + 1e-12))
        if step > self.limit + 1e-12:
            self.state = float("nan")
            return False, 3, "SNES reason -4 (DIVERGED_FNORM_NAN)"
        self.state = self.load
        return True, 4, "converged"


def test_controller_cuts_recovers_and_does_not_grow_into_a_known_failure():
    p = _FailingAbove(limit=0.07)
    f = PathFollower(p, p.set_load, PathControl(first_step=0.2, max_step=0.5, predictor="none"))
    f.follow(1.0, "test")
    assert f.t == pytest.approx(1.0) and p.state == pytest.approx(1.0)
    assert f.cuts >= 1
    # while a failed load lies ahead, a trial after a success is no larger than that success
    failed_at, last_success = -1.0, None
    for a, b, ok in p.trials:
        if last_success is not None and a < failed_at - 1e-12:
            assert b - a <= last_success + 1e-12
        if ok:
            last_success = b - a
        else:
            failed_at, last_success = b, None
    assert sum(not ok for *_, ok in p.trials) == f.cuts
    # NaN states were never accepted
    assert all(np.isfinite(s) for _, s in f.history)


class _ForbiddenBand(_ScalarProblem):
    """A stand-in problem whose states in (0.55, 0.65) are inadmissible (as an inverted element):
    a solve started there fails."""

    def __init__(self):
        super().__init__()
        self.starts = []

    def admissible(self):
        return not 0.55 < self.state < 0.65

    def solve(self):
        self.starts.append(self.state)
        if not self.admissible():
            self.state = float("nan")
            return False, 0, "SNES reason -4 (DIVERGED_FUNCTION_NANORINF)"
        self.state = self.load
        return True, 4, "converged"


def test_inadmissible_secant_guess_falls_back_to_the_last_state():
    """The secant through (0, 0) and (0.3, 0.3) predicts 0.6 at t = 0.6, inside the inadmissible
    band: Newton starts from the last converged state 0.3 instead, and no step is cut."""
    p = _ForbiddenBand()
    f = PathFollower(p, p.set_load, PathControl(first_step=0.3, max_step=0.3, predictor="secant"))
    f.follow(0.6, "test")
    assert p.starts == [0.0, 0.3] and f.cuts == 0 and p.state == 0.6


def test_advance_raises_below_the_minimum_increment():
    p = _FailingAbove(limit=1e-4)
    with pytest.raises(ConvergenceError, match="below the minimum"):
        advance(p.set_load, p.solve, p.save, p.restore, where="test", min_fraction=1.0 / 16.0)
    assert p.state == 0.0  # restored to the last converged state


class _Arc:
    """A stand-in problem whose equilibrium at load t is the point (cos t, sin t) of the unit circle
    (a rotating part), with the exact tangent as its Euler predictor; records the distance of each
    Newton start from the equilibrium."""

    def __init__(self):
        self.load, self.state, self.start_errors = 0.0, np.array([1.0, 0.0]), []

    @staticmethod
    def equilibrium(t):
        return np.array([np.cos(t), np.sin(t)])

    def set_load(self, t):
        self.load = t

    def save(self):
        return self.state.copy()

    def restore(self, state):
        self.state = np.array(state, dtype=float)

    def tangent_predictor(self, set_load, t_from, t_to, converged=None):
        self.state = self.equilibrium(t_from) + (t_to - t_from) * np.array(
            [-np.sin(t_from), np.cos(t_from)]
        )
        set_load(t_to)
        return True

    def residual_norm(self):
        return float(np.linalg.norm(self.state - self.equilibrium(self.load)))

    def solve(self):
        self.start_errors.append(self.residual_norm())
        self.state = self.equilibrium(self.load)
        return True, 4, "converged"


@pytest.mark.parametrize("predictor", ["tangent", "curved"])
def test_predictor_errors_on_a_rotation_match_their_closed_forms(predictor):
    """Steps h = 0.05 along the unit circle: the Euler step leaves the arc by
    |(1 - cos h, h - sin h)| (~h^2/2); the curved predictor (parabola through the previous state,
    h1 = h) by h^2 (h + h1)/6 + O(h^4) (the third derivative of the arc has length 1)."""
    h = 0.05
    p = _Arc()
    f = PathFollower(
        p, p.set_load, PathControl(first_step=h, max_step=h, growth=1.0, predictor=predictor)
    )
    f.follow(0.5, "test")
    np.testing.assert_allclose(p.state, p.equilibrium(0.5), atol=1e-15)
    euler = np.hypot(1.0 - np.cos(h), h - np.sin(h))
    errors = np.array(p.start_errors)
    assert len(errors) == 10
    np.testing.assert_allclose(errors[0], euler, rtol=1e-9)  # no previous state yet: Euler
    expected = euler if predictor == "tangent" else h**2 * (2 * h) / 6.0
    np.testing.assert_allclose(errors[1:], expected, rtol=0.05 if predictor == "curved" else 1e-9)


def test_tangent_predictor_path_reaches_the_direct_solution():
    """The controller with the tangent predictor (and inadmissible trials cut) reaches the same
    equilibrium as one Newton solve at the full load."""
    path, t_path, _ = _block(0.0, "test_path_")
    direct, _, _ = _block(0.25, "test_direct_")
    ok, _, reason = direct.solve()
    assert ok, reason
    f = PathFollower(
        path,
        lambda s: setattr(t_path, "value", 0.25 * s),
        PathControl(first_step=0.25, max_step=1.0),
    )
    f.follow(1.0, "test")
    np.testing.assert_allclose(path.u.x.array, direct.u.x.array, rtol=0, atol=1e-8)


def test_tangent_predictor_after_a_solve_without_iterations():
    """A Newton solve that starts within tolerance (iteration 0) assembles no tangent, so the
    predictor must assemble its own: the same Euler step as from a problem never solved."""
    solved, t_solved, _ = _block(0.0, "test_zero_its_")
    ok, its, reason = solved.solve()
    assert ok and its == 0, reason
    fresh, t_fresh, _ = _block(0.0, "test_zero_its_ref_")
    assert solved.tangent_predictor(lambda s: setattr(t_solved, "value", s), 0.0, 0.1)
    assert fresh.tangent_predictor(lambda s: setattr(t_fresh, "value", s), 0.0, 0.1)
    assert np.max(np.abs(fresh.u.x.array)) > 0.1  # a real step: ~t L / E = 0.4 mm at the tip
    np.testing.assert_allclose(solved.u.x.array, fresh.u.x.array, rtol=0, atol=1e-12)


def test_contact_couplings_are_preallocated():
    """The beam's Jacobian holds the strip-ribbon pairs before the first assembly: assembling with
    every pair in contact allocates nothing new."""
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems.composite_beam import BeamFE

    model = BeamFE(mesh=BeamFEMesh(level=0))
    A, P, _ = model.problem.snes.getJacobian()
    A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
    u = model.u
    for c in model.contacts:
        u.x.array.reshape(-1, 3)[c.pairs[:, 0], 2] += 20.0 if c is model.contacts[1] else -20.0
    assert all(np.all(c.gaps() < 0) for c in model.contacts)
    x = model.problem._problem.x
    dolfinx.fem.petsc.assign(u, x)
    model.problem.snes.computeJacobian(x, A, P)
    assert A.getInfo()["mallocs"] == 0


def test_packed_tangent_is_the_whole_tangent(monkeypatch):
    """The direct path stores the tangent's upper triangle in node blocks (SBAIJ); with strip-ribbon
    pairs closed (their Hessian inserted entry by entry, lower entries dropped) and the proximal
    term on, K v equals the whole tangent's (AIJ) to round-off, and one Newton correction
    K^-1 R agrees to the factorisations' round-off."""
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers import mechanics
    from lcefem.solvers.problems.composite_beam import BeamFE

    rng = np.random.default_rng(3)
    noise = None
    out = {}
    for packed in (True, False):
        monkeypatch.setattr(mechanics, "PACKED_TANGENT", packed)
        model = BeamFE(mesh=BeamFEMesh(level=0))
        model.set_lambdas(1.37, 1.2)
        u = model.u
        if noise is None:
            noise = 1e-3 * rng.standard_normal(u.x.array.size)
        u.x.array[:] = noise
        for c in model.contacts:  # strips pushed 0.2 mm into the ribbon
            u.x.array.reshape(-1, 3)[c.pairs[:, 0], 2] += 0.2 if c is model.contacts[1] else -0.2
        assert all(np.sum(c.gaps() < 0) > 0 for c in model.contacts)
        model.damping.weight = 0.3  # N/mm: proximal term on the diagonal
        problem = model.problem
        assert problem.packed == packed
        x = problem._problem.x
        dolfinx.fem.petsc.assign(u, x)
        A, P, _ = problem.snes.getJacobian()
        problem.snes.computeJacobian(x, A, P)
        assert A.getType() == ("seqsbaij" if packed else "seqaij")
        r = x.duplicate()
        problem.snes.computeFunction(x, r)
        v = x.duplicate()
        v.array[:] = np.sin(np.arange(v.getSize()))
        ksp = problem.snes.getKSP()
        ksp.setOperators(A, P)
        du = x.duplicate()
        ksp.solve(r, du)
        out[packed] = ((A * v).array.copy(), du.array.copy())
    Kv, Kv_whole = out[True][0], out[False][0]
    assert np.linalg.norm(Kv - Kv_whole) < 1e-13 * np.linalg.norm(Kv_whole)
    du, du_whole = out[True][1], out[False][1]
    assert np.linalg.norm(du - du_whole) < 1e-8 * np.linalg.norm(du_whole)


def test_rigid_body_modes_have_no_strain_energy():
    """The six near-nullspace vectors of the iterative path are rigid motions: the stress-free
    neo-Hookean tangent (linear elasticity) maps each to zero, and they are orthonormal."""
    from lcefem.solvers.mechanics import rigid_body_modes

    mesh = dolfinx.mesh.create_box(
        MPI.COMM_WORLD,
        [[0.0, 0.0, 0.0], [3.0, 1.0, 0.5]],
        [3, 2, 2],
        dolfinx.mesh.CellType.hexahedron,
    )
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2, (3,)))
    u = dolfinx.fem.Function(V)
    W = neo_hookean_strain_energy(deformation_gradient(u), NeoHookeanSolid())
    K = ufl.derivative(ufl.derivative(W * ufl.dx(metadata={"quadrature_degree": 4}), u), u)
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(K))
    A.assemble()
    modes = rigid_body_modes(V).getVecs()
    assert len(modes) == 6
    y = A.createVecLeft()
    for i, m in enumerate(modes):
        A.mult(m, y)
        assert y.norm() < 1e-9 * A.norm()
        for j, n in enumerate(modes):
            assert m.dot(n) == pytest.approx(float(i == j), abs=1e-12)


def test_path_tolerance_loosens_and_restores():
    """path_tolerance(atol) loosens Newton's absolute tolerance [N] for intermediate path states and
    path_tolerance(None) restores the configured one."""
    mesh = dolfinx.mesh.create_unit_cube(MPI.COMM_WORLD, 1, 1, 1, dolfinx.mesh.CellType.hexahedron)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
    u = dolfinx.fem.Function(V)
    W = neo_hookean_strain_energy(deformation_gradient(u), NeoHookeanSolid())
    problem = HyperelasticProblem(
        u, W * ufl.dx(metadata={"quadrature_degree": 2}), prefix="test_path_tol_"
    )
    atol = problem.snes.getTolerances()[1]
    problem.path_tolerance(1e-3)
    assert problem.snes.getTolerances()[1] == 1e-3
    problem.path_tolerance(None)
    assert problem.snes.getTolerances()[1] == atol


def test_linear_solver_follows_the_size_unless_named():
    from lcefem.solvers.mechanics import GAMG_OPTIONS, ITERATIVE_PATH_DOFS, solver_options
    from lcefem.solvers.pmultigrid import PMG_OPTIONS, PMG_PLANE_SMOOTHER

    assert solver_options(ITERATIVE_PATH_DOFS - 1)["pc_type"] == "cholesky"
    large = solver_options(ITERATIVE_PATH_DOFS)
    # the size-selected p-multigrid smooths by node planes; a named "pmg" keeps PMG_OPTIONS's SOR
    expected = {**PMG_OPTIONS, **PMG_PLANE_SMOOTHER}
    assert {k: large[k] for k in expected} == expected
    assert (
        solver_options(10, {"pc_type": "pmg"})["mg_levels_pc_type"]
        == PMG_OPTIONS["mg_levels_pc_type"]
    )
    # linear elements have no lower degree: their iterative path is GAMG on the matrix itself
    linear = solver_options(ITERATIVE_PATH_DOFS, degree=1)
    assert {k: linear[k] for k in GAMG_OPTIONS} == GAMG_OPTIONS
    assert solver_options(ITERATIVE_PATH_DOFS, {"pc_type": "cholesky"})["ksp_type"] == "preonly"
    # naming gamg brings the whole iterative set (CG, not the direct path's preonly)
    assert solver_options(10, {"pc_type": "gamg"})["ksp_type"] == "cg"
    # "pmg" is ours, not PETSc's: it brings PCMG with two levels and is not passed on as a type
    pmg = solver_options(10, {"pc_type": "pmg", "mg_levels_ksp_max_it": 2})
    assert (pmg["ksp_type"], pmg["pc_type"], pmg["pc_mg_levels"]) == ("cg", "mg", 2)
    assert pmg["mg_levels_ksp_max_it"] == 2


def test_pmultigrid_transfer_is_exact_for_linear_fields():
    """The Q1 -> Q2 interpolation P of the p-multigrid reproduces every Q1 field: the six
    rigid-body modes of Q1 (linear in x) map onto those of Q2 (to round-off), on the strip's mesh
    (any number of processes: P's ghost rows are summed once)."""
    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.mechanics import displacement_space, rigid_body_modes
    from lcefem.solvers.pmultigrid import PMultigrid
    from lcefem.solvers.problems.strip import StripConfig, StripSimulation

    sim = StripSimulation(StripConfig(mesh=StripMesh(level=0), petsc={"pc_type": "pmg"}))
    V = displacement_space(sim.model.u.function_space.mesh)
    pmg = PMultigrid(V, rigid_body_modes, sim.model.mechanics.snes.getKSP())
    assert pmg.coarse_dofs == 3 * V.mesh.geometry.index_map().size_global  # one node a vertex
    coarse, fine = (rigid_body_modes(W).getVecs() for W in (pmg.coarse_space, V))
    # the orthonormalised modes span the same space: P c lies in span(fine) with |P c| > 0
    F = np.array([f.getArray() for f in fine]).T
    for c in coarse:
        y = pmg.P.createVecLeft()
        pmg.P.mult(c, y)
        local = y.getArray()
        residual = (
            local - F @ np.linalg.lstsq(F, local, rcond=None)[0] if V.mesh.comm.size == 1 else None
        )
        assert y.norm() > 1.0
        if residual is not None:
            assert np.max(np.abs(residual)) < 1e-12 * np.max(np.abs(local))


def test_iterative_path_gives_the_direct_newton_solution():
    """The heated strip (level 0) brought to the benchmark's hot-core temperature by CG + GAMG
    (forced, with a coarse grid of <= 100 equations so that level 0's 2325 DOFs get a three-level
    hierarchy) and by MUMPS LDL^T: the same equilibrium to the Newton tolerance (snes_rtol times the
    displacement; measured difference 4e-15 mm of 1.69 mm)."""
    sims = _hot_core_strips((("cholesky", {}), ("gamg", {"pc_gamg_coarse_eq_limit": 100})))
    ksp = sims["gamg"].model.mechanics.snes.getKSP()
    assert (ksp.getType(), ksp.getPC().getType()) == ("cg", "gamg")
    assert (
        ksp.getPC().getMGLevels() >= 3 and min(sims["gamg"].cg_its) > 10
    )  # multigrid, not a coarse solve
    A = ksp.getOperators()[0]
    assert A.getBlockSize() == 3 and A.getNearNullSpace().getVecs()
    _assert_same_displacement(sims["cholesky"], sims["gamg"])


@pytest.mark.parametrize("coarse", ["cholesky", "gamg"])
def test_pmultigrid_gives_the_direct_newton_solution(coarse):
    """The same hot-core strip (level 0) by CG + Q2 -> Q1 p-multigrid (``pc_type = "pmg"``, the Q1
    level factorised or cycled by GAMG) and by MUMPS LDL^T: the same equilibrium to the Newton
    tolerance; the coarse operator is the Galerkin P^T K P of the Q1 space (one block of 3 per mesh
    vertex, about 1/8 of the Q2 DOFs), recomputed with every tangent."""
    from lcefem.solvers.mechanics import PMG_GAMG_COARSE

    extra = (
        {**PMG_GAMG_COARSE, "mg_coarse_pc_gamg_coarse_eq_limit": 100} if coarse == "gamg" else {}
    )
    sims = _hot_core_strips((("cholesky", {}), ("pmg", extra)))
    mech = sims["pmg"].model.mechanics
    pc = mech.snes.getKSP().getPC()
    assert (mech.snes.getKSP().getType(), pc.getType(), pc.getMGLevels()) == ("cg", "mg", 2)
    assert pc.getMGCoarseSolve().getPC().getType() == coarse
    K1 = pc.getMGCoarseSolve().getOperators()[0]
    assert K1.handle == mech.pmultigrid.coarse_matrix.handle and K1.getNearNullSpace().getVecs()
    fine_dofs = mech.u.function_space.dofmap.index_map.size_global * 3
    assert K1.getSize()[0] == mech.pmultigrid.coarse_dofs < fine_dofs / 4
    # one Galerkin product per tangent (Newton's and the predictor's), every CG solve iterated
    assert mech.pmultigrid.updates == len(sims["pmg"].cg_its) and min(sims["pmg"].cg_its) > 5
    # the Q2 smoother sweeps a node-block (BAIJ) copy of the last tangent: the same operator
    K, S = mech.snes.getKSP().getOperators()[0], pc.getMGSmoother(1).getOperators()[0]
    assert S.getType() == "seqbaij" and S.getBlockSize() == 3 and S.handle != K.handle
    v, Kv, Sv = K.createVecRight(), K.createVecLeft(), K.createVecLeft()
    v.setRandom()
    K.mult(v, Kv)
    S.mult(v, Sv)
    Sv.axpy(-1.0, Kv)
    assert Sv.norm() < 1e-12 * Kv.norm()
    _assert_same_displacement(sims["cholesky"], sims["pmg"])


def test_plane_smoother_gives_the_direct_newton_solution():
    """p-multigrid with the Q2 smoother by node planes (``PMG_PLANE_SMOOTHER``: block Jacobi, each
    block the DOFs of three consecutive node planes normal to the strip's axis) on the level-0
    hot-core strip: the blocks partition the DOFs, each spans at most three axial positions, and
    the equilibrium is LDL^T's to the Newton tolerance."""
    from lcefem.solvers.pmultigrid import PLANES_PER_BLOCK, PMG_PLANE_SMOOTHER, node_planes

    sims = _hot_core_strips((("cholesky", {}), ("pmg", dict(PMG_PLANE_SMOOTHER))))
    mech = sims["pmg"].model.mechanics
    V = mech.u.function_space
    smoother = mech.snes.getKSP().getPC().getMGSmoother(1).getPC()
    assert smoother.getType() == "asm"
    blocks = node_planes(V)
    assert len(smoother.getASMSubKSP()) == len(blocks) > 1
    dofs = np.concatenate([b.getIndices() for b in blocks])
    assert np.array_equal(np.sort(dofs), np.arange(3 * V.dofmap.index_map.size_local))
    x = V.tabulate_dof_coordinates()[:, 0]
    for b in blocks:
        assert len(np.unique(np.round(x[b.getIndices()[::3] // 3], 9))) <= PLANES_PER_BLOCK
    assert max(sims["pmg"].cg_its) < 60  # the smoother is applied (measured 4-15 per solve)
    _assert_same_displacement(sims["cholesky"], sims["pmg"])


def _assert_same_displacement(direct, other) -> None:
    """u equal to the Newton tolerance: snes_rtol times the largest displacement [mm]."""
    from lcefem.solvers.mechanics import NEWTON_OPTIONS

    u_direct, u_other = direct.model.u.x.array, other.model.u.x.array
    assert np.max(np.abs(u_direct)) > 1.0  # mm: the hot core contracts the strip
    np.testing.assert_allclose(
        u_other, u_direct, rtol=0, atol=NEWTON_OPTIONS["snes_rtol"] * np.max(np.abs(u_direct))
    )


def test_final_newton_step_is_solved_to_the_newton_tolerance(monkeypatch):
    """CG stops on the preconditioned residual, which on the strip's tangents is ~10x smaller than
    the true one: with Newton's tolerance at 1e-12 N (level-0 hot-core strip), CG to a relative 1e-4
    leaves 3.4e-12 N after the third Newton step and costs a fourth linear solve, while LDL^T meets
    it in three. The final-step forcing (:data:`FINAL_STEP_FORCING`) solves that step to
    0.02 t / |R_k| (1.8e-13 N left) and Newton takes LDL^T's three steps (four linear solves with
    the predictor's); the earlier steps keep ksp_rtol."""
    import lcefem.solvers.mechanics as mechanics

    tight = {"snes_atol": 1e-12, "snes_rtol": 1e-12}
    its = {}
    for name, forcing in (("forced", mechanics.FINAL_STEP_FORCING), ("unforced", 1e30)):
        monkeypatch.setattr(mechanics, "FINAL_STEP_FORCING", forcing)
        sims = _hot_core_strips((("pmg", tight),))
        its[name] = len(sims["pmg"].cg_its)
        if name == "forced":
            rtols, rhs = sims["pmg"].cg_rtols, sims["pmg"].rhs_norms
            assert rtols[:-1] == [1e-4] * (len(rtols) - 1)  # predictor and Newton steps 1-2
            assert rtols[-1] == pytest.approx(0.02 * 1e-12 / rhs[-1])
    direct = len(_hot_core_strips((("cholesky", tight),))["cholesky"].cg_its)
    assert its["forced"] == direct == 4 and its["unforced"] == 5


def _hot_core_strips(solvers) -> dict:
    """The level-0 strip brought to the benchmark's hot-core temperature with each (pc_type,
    extra options) of ``solvers``; each simulation carries ``cg_its``, ``cg_rtols`` and
    ``rhs_norms``: per linear solve its Krylov iterations, relative tolerance and |b| [N]."""
    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.problems.strip import StripConfig, StripSimulation
    from linear_solver_benchmark import hot_core

    sims = {}
    for pc, extra in solvers:
        sim = StripSimulation(StripConfig(mesh=StripMesh(level=0), petsc={"pc_type": pc, **extra}))
        sim.cg_its, sim.cg_rtols, sim.rhs_norms = [], [], []

        def record(ksp, b, x, sim=sim):
            sim.cg_its.append(ksp.getIterationNumber())
            sim.cg_rtols.append(ksp.getTolerances()[0])
            sim.rhs_norms.append(b.norm())

        sim.model.mechanics.snes.getKSP().setPostSolve(record)
        sim.set_temperature(hot_core(sim.dims))
        sims[pc] = sim
    return sims
