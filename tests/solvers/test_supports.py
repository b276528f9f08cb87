"""Named supports (solvers/supports.py): the 3-2-1 rule removes exactly the six rigid-body motions;
face helpers hold what they say and refuse unknown faces."""

import numpy as np
import pytest

from lcefem.meshes.block import build_block
from lcefem.models.errors import InputError
from lcefem.solvers.mechanics import displacement_space
from lcefem.solvers.supports import clamp_face, mirror_planes, plane_clamp, rigid_body_321


@pytest.fixture(scope="module")
def block():
    tm = build_block((2.0, 1.0, 0.5), (2, 2, 1), "hex")
    return tm, displacement_space(tm.mesh, 2)


def _held(V, bcs) -> list[tuple[int, int]]:
    """(node, component) pairs held by ``bcs`` (serial; DirichletBC dofs are unrolled, 3 per
    node)."""
    return [(int(d) // 3, int(d) % 3) for bc in bcs for d in bc.dof_indices()[0]]


def test_rigid_body_321_removes_six_rigid_motions_and_nothing_else(block):
    tm, V = block
    bcs = rigid_body_321(V, (0, 0, 0), (2.0, 0, 0), (0, 1.0, 0))
    held = _held(V, bcs)
    assert len(held) == 6  # statically determinate: no constraint beyond the rigid motions
    X = V.tabulate_dof_coordinates()
    # the six rigid modes (3 translations, 3 small rotations) at the held (node, component)s
    modes = []
    for k in range(3):
        modes.append([1.0 if c == k else 0.0 for _, c in held])
    for axis in range(3):
        w = np.zeros(3)
        w[axis] = 1.0
        modes.append([np.cross(w, X[n])[c] for n, c in held])
    assert np.linalg.matrix_rank(np.array(modes)) == 6  # no rigid motion survives


def test_face_helpers_hold_the_named_components(block):
    tm, V = block
    X = V.tabulate_dof_coordinates()
    clamp = _held(V, clamp_face(tm, V, "x0"))
    assert clamp and all(np.isclose(X[n, 0], 0.0) for n, _ in clamp)
    assert {c for _, c in clamp} == {0, 1, 2}
    plane = _held(V, plane_clamp(tm, V, "y0", 1))
    assert (
        plane and {c for _, c in plane} == {1} and all(np.isclose(X[n, 1], 0.0) for n, _ in plane)
    )
    assert (
        len(mirror_planes(tm, V, [("y0", 1), ("sym_q", 0)])) == 1
    )  # planes the mesh lacks: skipped
    with pytest.raises(InputError, match="support face 'nope'"):
        clamp_face(tm, V, "nope")
