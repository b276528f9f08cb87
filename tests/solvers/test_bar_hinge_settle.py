"""The settle step of the bar-and-hinge Newton (solvers/bar_hinge/newton.py: floating_block,
rigid_update, settle_block): a stiff block hanging on soft strips, turned far by a couple, stalls
plain Newton (each linear step along the block's rotation stretches its stiff glue bars to second
order); settling the block reaches the same stable equilibrium as plain Newton given many more
iterations (issue 47: the 5 x 5 dome's floating raised square)."""

import importlib
import math

import numpy as np
import pytest

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.solvers.bar_hinge import BarHingeModel, NewtonOptions, ReducedHessian, held_dofs

nw = importlib.import_module("lcefem.solvers.bar_hinge.newton")


def floating_triangle(torque: float):
    """A rigid glue triangle (side 8.7 mm, 3 free nodes) held by three radial LCE strips (rest
    fraction 0.999: barely taut, so its rotation about z is soft) to three free anchors, each
    fixed by a stiff glue tripod to three held nodes; a couple ``torque`` [N mm] about z and a
    small out-of-plane load act on the triangle. Returns (model, free DOFs, block, anchors)."""
    a = 5.0  # triangle's circumradius [mm]
    ang = np.radians([90.0, 210.0, 330.0])
    radial = np.c_[np.cos(ang), np.sin(ang), np.zeros(3)]
    block, anchors = a * radial, 6 * a * radial
    feet = [
        anchors[i] + d
        for i in range(3)
        for d in (3 * radial[i] + [0, 0, 3], 3 * radial[i] - [0, 0, 3], [0, 0, 0])
    ]
    for i in range(3):  # the third foot of each tripod: sideways
        feet[3 * i + 2] = anchors[i] + 3.0 * np.array([-radial[i, 1], radial[i, 0], 0.0])
    s = BarHingeStructure(
        nodes=np.vstack([block, anchors, feet]),
        thickness=0.127,
        panels=np.zeros((0, 4), dtype=np.int64),
        panel_centres=np.zeros(0, dtype=np.int64),
        panel_bars=np.zeros((0, 8), dtype=np.int64),
    )
    glue = [(0, 1), (1, 2), (2, 0)] + [(3 + i, 6 + 3 * i + k) for i in range(3) for k in range(3)]
    s.add_bars("glue", glue)
    s.sections["glue"] = {"area": 0.889}
    s.add_bars("top_strips", [(0, 3), (1, 4), (2, 5)])
    s.sections["top_strips"] = {"section": 1.0}
    model = BarHingeModel(s)
    model.set_rest_fractions({"top_strips": 0.999})
    forces = np.zeros((s.num_nodes, 3))
    tangent = np.c_[-radial[:, 1], radial[:, 0], np.zeros(3)]
    forces[:3] = torque / (3.0 * a) * tangent
    forces[:3, 2] += 1e-4 * np.array([1.0, -0.5, -0.5])
    model.set_external_forces(forces)
    free = np.setdiff1d(np.arange(model.ndof), held_dofs(np.arange(6, 15)))
    return model, free, np.arange(3), np.arange(3, 6)


def lowest_eigenvalue(model, x, free) -> float:
    kmat = ReducedHessian.of(model, free).matrix(model.evaluate(x)[2]).toarray()
    return float(np.linalg.eigvalsh(kmat)[0])


def test_rigid_update_turns_a_block_without_stretching_it():
    """A step that is an infinitesimal rotation w x r: the update turns the points by the finite
    rotation (distances kept to round-off; the linear step stretches them by |w|^2 |r|^2 / 2)."""
    p = np.array([[5.0, 0, 0], [-2.5, 4.33, 0], [-2.5, -4.33, 0], [0, 0, 1.0]])
    w = np.array([0.1, -0.2, 0.4])  # [rad]
    step = np.cross(w, p - p.mean(axis=0))
    moved = nw.rigid_update(p, step)
    d0 = np.linalg.norm(p[:, None] - p[None], axis=2)
    assert np.abs(np.linalg.norm(moved[:, None] - moved[None], axis=2) - d0).max() < 1e-12
    linear = p + step
    assert np.abs(np.linalg.norm(linear[:, None] - linear[None], axis=2) - d0).max() > 0.1


def test_floating_block_is_the_few_nodes_carrying_the_residual():
    g = np.zeros(30)
    g[[6, 7, 8, 12]] = [1.0, 1.0, 1.0, 1.0]  # nodes 2 and 4
    g[20] = 0.01
    assert list(nw.floating_block(g, np.arange(30), 30)) == [2, 4]
    assert nw.floating_block(np.ones(300), np.arange(300), 300) is None  # spread: no block


def test_floating_block_is_closed_under_stiff_couplings():
    """A residual on two corners of the glue triangle: the block is the whole triangle (its glue
    bars couple the third corner stiffly), not the strips' anchors (soft couplings)."""
    model, free, block, _ = floating_triangle(0.05)
    _, _, coo = model.evaluate(model.reference)
    kmat = ReducedHessian.of(model, free).matrix(coo)
    g = np.zeros(model.ndof)
    g[[0, 4]] = 1.0  # nodes 0 and 1
    assert list(nw.floating_block(g, free, model.ndof)) == [0, 1]
    assert list(nw.floating_block(g, free, model.ndof, kmat)) == list(block)


def test_settle_reaches_the_stable_equilibrium_plain_newton_reaches_slowly():
    """Couple 0.05 N mm: plain Newton stalls within its 50 iterations (|g| = 0.24 N, measured);
    with the settle step it converges to |g| <= 1e-8 N at a stable state (lowest tangent
    eigenvalue > 0, measured 2.1e-4 N/mm) that plain Newton reaches after 92 iterations, the same
    to 1e-9 mm (measured 7e-13 mm); the block has turned by 0.44 rad."""
    model, free, block, _ = floating_triangle(0.05)
    x0 = model.reference
    plain = nw.newton(model, x0, free, NewtonOptions(settle=False))
    assert not plain.converged
    settled = nw.newton(model, x0, free, NewtonOptions())
    assert settled.converged and settled.residual <= 1e-8
    assert settled.negative_pivots == 0 and lowest_eigenvalue(model, settled.x, free) > 1e-5
    long = nw.newton(model, x0, free, NewtonOptions(settle=False, max_iterations=5000))
    assert long.converged and long.iterations > 50
    assert np.abs(settled.x - long.x).max() < 1e-9
    # the block has turned far: a linear step of that size would stretch its glue bars
    turn = math.atan2(settled.x[0, 0] - x0[0, 0], x0[0, 1])
    assert abs(turn) > 0.1


@pytest.mark.parametrize("torque", [0.002, 0.05])
def test_settle_block_alone_minimises_over_the_block(torque):
    """settle_block moves only the block's nodes and leaves their residual below a tenth of the
    force tolerance (the others fixed: the anchors keep theirs)."""
    model, free, block, anchors = floating_triangle(torque)
    x0 = model.reference.reshape(-1)
    opts = NewtonOptions()
    x, iterations = nw.settle_block(
        model, x0, free, block, ReducedHessian.of(model, free), opts
    )
    moved = np.flatnonzero(np.abs(x - x0).reshape(-1, 3).max(axis=1) > 0)
    assert set(moved) <= set(block) and iterations < nw.SETTLE_ITERATIONS
    g = model.evaluate(x, derivatives=1)[1].reshape(-1, 3)
    assert np.linalg.norm(g[block]) <= 0.1 * opts.force_tolerance
    assert model.evaluate(x, derivatives=0) < model.evaluate(x0, derivatives=0)


def test_settle_block_keeps_a_held_dof_of_the_block():
    """A block node held along z (a roller): the held DOF stays where it is, and the settle still
    brings the block's free residual below a tenth of the tolerance."""
    model, free, block, _ = floating_triangle(0.002)
    free = free[free != 2]  # node 0, z
    x0 = model.reference.reshape(-1)
    opts = NewtonOptions()
    x, _ = nw.settle_block(model, x0, free, block, ReducedHessian.of(model, free), opts)
    assert x[2] == x0[2]
    g = model.evaluate(x, derivatives=1)[1]
    dofs = np.intersect1d((3 * block[:, None] + np.arange(3)).ravel(), free)
    assert np.linalg.norm(g[dofs]) <= 0.1 * opts.force_tolerance
