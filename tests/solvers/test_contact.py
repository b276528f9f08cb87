"""Node-to-node penalty contact (solvers/contact.py): gap derivatives against finite differences,
the gap's sign, the pairs of the FE beam, and the assembled residual/Jacobian against each other."""

import dolfinx_solver  # noqa: F401
from petsc4py import PETSc

import numpy as np
import pytest

import dolfinx

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.composite_beam_fe import BeamFEMesh, build_beam_fe
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.solvers.contact import NodalDamping, NodePairContact, face_pairs, gap_and_derivatives
from lcefem.solvers.mechanics import displacement_space


def test_gap_derivatives_match_finite_differences():
    rng = np.random.default_rng(1)
    p, q, r = (rng.normal(size=(5, 3)) for _ in range(3))
    g, grad, hess = gap_and_derivatives(p, q, r)
    z = np.concatenate([p, q, r], axis=1)
    h = 1e-6
    for k in range(9):
        zp, zm = z.copy(), z.copy()
        zp[:, k] += h
        zm[:, k] -= h
        gp = gap_and_derivatives(zp[:, :3], zp[:, 3:6], zp[:, 6:])
        gm = gap_and_derivatives(zm[:, :3], zm[:, 3:6], zm[:, 6:])
        np.testing.assert_allclose((gp[0] - gm[0]) / (2 * h), grad[:, k], atol=1e-8)
        np.testing.assert_allclose((gp[1] - gm[1]) / (2 * h), hess[:, :, k], atol=1e-7)
    np.testing.assert_allclose(hess, np.transpose(hess, (0, 2, 1)), atol=1e-14)


def test_gap_sign_and_rotation_invariance():
    """Gap along the ribbon's thickness direction (r -> q): positive on q's side, invariant under a
    rigid rotation and insensitive to tangential offsets (frictionless sliding)."""
    q, r = np.array([[0.0, 0.0, 0.1]]), np.array([[0.0, 0.0, -0.1]])
    for p, expected in (([[3.0, 1.0, 0.6]], 0.5), ([[-2.0, 0.0, -0.2]], -0.3)):
        assert gap_and_derivatives(np.array(p), q, r, hessian=False)[0][0] == pytest.approx(
            expected
        )
    a = 0.7
    rot = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    p = np.array([[3.0, 1.0, 0.6]])
    assert gap_and_derivatives(p @ rot.T, q @ rot.T, r @ rot.T, hessian=False)[0][
        0
    ] == pytest.approx(0.5)


@pytest.fixture(scope="module")
def beam():
    tm = build_beam_fe(CompositeBeamGeometry(), PUBLISHED_LAMBDA_N, BeamFEMesh(level=0))
    V = displacement_space(tm.mesh, 2)
    return tm, V


def test_beam_pairs(beam):
    """Every node of a strip's free face (Q2) faces a ribbon node at the same (x, y); all gaps are
    open as built; the tributary areas add up to the face minus the share of the bond-edge nodes
    (not pairs: shared with the ribbon), which is 1/6 of the adjacent element row for Q2."""
    tm, V = beam
    X = V.tabulate_dof_coordinates()
    w = tm.info["strip_width"] / 2
    row = w * 11.5 / 4  # level 0: the 11.5 mm flanks have 4 elements
    for face, above, area in (
        ("top_strip_underside", True, 45.0 * w - 3 * row / 6),
        ("bottom_strip_topside", False, 60.0 * w - 4 * row / 6),
    ):
        pairs, areas = face_pairs(tm, V, face, "kapton", strip_above=above)
        np.testing.assert_allclose(X[pairs[:, 0], :2], X[pairs[:, 1], :2], atol=1e-9)
        np.testing.assert_allclose(X[pairs[:, 0], :2], X[pairs[:, 2], :2], atol=1e-9)
        u = dolfinx.fem.Function(V)
        gaps = NodePairContact(u, pairs, areas, 1.0).gaps()
        assert np.all(gaps > 0.0)
        assert np.all(areas > 0) and areas.sum() == pytest.approx(area, rel=1e-10)


def test_assembled_jacobian_is_the_derivative_of_the_residual(beam):
    tm, V = beam
    pairs, areas = face_pairs(tm, V, "bottom_strip_topside", "kapton", strip_above=False)
    u = dolfinx.fem.Function(V)
    # push the strip nodes up through the ribbon: every pair penetrates
    u.x.array.reshape(-1, 3)[pairs[:, 0], 2] = 2.0
    contact = NodePairContact(u, pairs, areas, 10.0)
    damping = NodalDamping(u)
    damping.weight, damping.anchor[:] = 0.3, 0.01
    assert np.all(contact.gaps() < 0)
    n = u.x.array.size
    A = PETSc.Mat().createAIJ([n, n], nnz=200)
    A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
    A.setUp()
    contact.add_jacobian(A)
    damping.add_jacobian(A)

    def residual() -> np.ndarray:
        b = PETSc.Vec().createSeq(n)
        contact.add_residual(b)
        damping.add_residual(b)
        return b.array.copy()

    dofs = [3 * int(pairs[7, 0]) + 2, 3 * int(pairs[7, 1]) + 2, 3 * int(pairs[20, 2]) + 0]
    h = 1e-6
    for j in dofs:
        u.x.array[j] += h
        rp = residual()
        u.x.array[j] -= 2 * h
        rm = residual()
        u.x.array[j] += h
        column = A.getColumnVector(j).array
        np.testing.assert_allclose((rp - rm) / (2 * h), column, atol=1e-5 * np.abs(column).max())
    # the energy's gradient is the residual
    r0 = residual() - damping.weight * (u.x.array - damping.anchor)
    e0 = contact.energy()
    for j in dofs:
        u.x.array[j] += h
        ep = contact.energy()
        u.x.array[j] -= 2 * h
        em = contact.energy()
        u.x.array[j] += h
        assert (ep - em) / (2 * h) == pytest.approx(r0[j], rel=1e-6, abs=1e-9)
    assert e0 > 0


def test_rigid_plane_contact_pushes_back_by_the_penetrated_area():
    """A unit cube (hexahedra, Q2) lowered by delta into the plane z = 0: the plane's face nodes'
    tributary areas sum to the face's 1 mm^2, the reaction is k x 1 mm^2 x delta, the residual is
    k A g on each node's z DOF (summing to the reaction) and the Jacobian's diagonal k A; lifted
    above the plane, nothing (g > 0), and at g = 0 the Jacobian keeps k A (closed)."""
    from mpi4py import MPI

    from lcefem.solvers.contact import RigidPlaneContact, plane_face_nodes

    mesh = dolfinx.mesh.create_unit_cube(MPI.COMM_SELF, 2, 2, 2, dolfinx.mesh.CellType.hexahedron)
    V = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(V)
    nodes, areas = plane_face_nodes(V, 0.0)
    assert areas.sum() == pytest.approx(1.0, rel=1e-12)
    k, delta = 50.0, 1e-3  # [N/mm^3], [mm]
    plane = RigidPlaneContact(u, nodes, areas, 0.0, k)
    n = V.dofmap.index_map.size_local * 3
    A = PETSc.Mat().createAIJ([n, n], nnz=1, comm=MPI.COMM_SELF)
    A.setUp()
    plane.add_jacobian(A)  # g = 0: closed
    assert A.getDiagonal().array[3 * nodes + 2] == pytest.approx(k * areas)
    u.x.array[2::3] = -delta
    assert plane.normal_force() == pytest.approx(k * delta, rel=1e-12)
    b = PETSc.Vec().createSeq(n)
    plane.add_residual(b)
    assert b.array[3 * nodes + 2] == pytest.approx(-k * areas * delta)
    assert b.array.sum() == pytest.approx(-k * delta, rel=1e-12)
    u.x.array[2::3] = delta
    b.zeroEntries()
    plane.add_residual(b)
    assert plane.normal_force() == 0.0 and not np.any(b.array)
