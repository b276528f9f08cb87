"""The bar-and-hinge solver: assembled derivatives, single panel and single hinge against closed
forms, tension-only strips, saddle escape, and path following with step halving
(solvers/bar_hinge)."""

import dataclasses
import math

import numpy as np
import pytest

from lcefem.meshes.bar_hinge_structure import BarHingeStructure, n5b8_structure
from lcefem.meshes.composite_beam import (
    BeamBarHingeMesh,
    CompositeBeamGeometry,
    build_beam_bar_hinge,
)
from lcefem.models import bar_hinge_materials as bh
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.hyperelastic import ogden_uniaxial_nominal_stress
from lcefem.solvers.bar_hinge import (
    BarHingeModel,
    NewtonOptions,
    PathOptions,
    follow_path,
    held_dofs,
    isostatic_supports,
    newton,
)

RNG = np.random.default_rng(7)


@pytest.fixture(scope="module")
def small_beam():
    structure = build_beam_bar_hinge(
        CompositeBeamGeometry(segments=2), BeamBarHingeMesh(flank_panels=2)
    )
    return structure, BarHingeModel(structure)


def test_assembled_gradient_and_hessian(small_beam):
    """Directional derivatives of the total energy and gradient against central differences, at a
    perturbed state with taut strips and active contacts."""
    structure, model = small_beam
    model.set_rest_fractions({"bottom_strips": 0.9, "top_strips": 0.97})
    x = structure.nodes + 0.05 * RNG.normal(size=structure.nodes.shape)
    forces = model.bar_forces(x)
    assert np.any(forces["bottom_strips"] > 0) and np.any(forces["top_strips"] > 0)
    energy, grad, _ = model.evaluate(x)
    hess = model.hessian(x)
    h = 1e-6
    for _ in range(4):
        v = RNG.normal(size=x.size)
        ep = model.energy(x.ravel() + h * v)
        em = model.energy(x.ravel() - h * v)
        assert (ep - em) / (2 * h) == pytest.approx(grad @ v, rel=1e-6, abs=1e-9)
        gp = model.gradient(x.ravel() + h * v)
        gm = model.gradient(x.ravel() - h * v)
        np.testing.assert_allclose(
            hess @ v, (gp - gm) / (2 * h), rtol=0, atol=1e-6 * np.max(np.abs(hess @ v))
        )
    assert abs(hess - hess.T).max() <= 1e-10 * abs(hess).max()
    model.set_rest_fractions({"bottom_strips": 1.0, "top_strips": 1.0})


def test_single_square_panel_in_plane_stretching():
    """Uniaxial stress on an N5B8 square W x W: force/extension = E t W/W, lateral strain -nu e_x
    (plane stress; Filipov et al. 2017 calibration)."""
    w, t = 5.0, 0.127
    nodes = np.array([[0, 0, 0], [w, 0, 0], [w, w, 0], [0, w, 0.0]])
    structure = n5b8_structure(nodes, np.array([[0, 1, 2, 3]]), t)
    kap = bh.KaptonBarHinge()
    model = BarHingeModel(structure, kap)
    strain = 1e-5
    held = np.concatenate(
        [
            held_dofs([0, 3], "x"),
            held_dofs([1, 2], "x"),
            held_dofs([0], "y"),
            held_dofs([0, 1, 2, 3, 4], "z"),
        ]
    )
    free = np.setdiff1d(np.arange(model.ndof), held)
    x0 = structure.nodes.copy()
    x0[[1, 2], 0] += strain * w
    res = newton(model, x0, free)
    assert res.converged
    force = model.gradient(res.x)[held_dofs([1, 2], "x")].sum()
    expected = kap.youngs_modulus * t * w * strain  # E t H e_x, H = W
    assert force == pytest.approx(expected, rel=1e-4)  # nonlinearity O(strain)
    lateral = (res.x[3, 1] - res.x[0, 1]) / w - 1.0
    assert lateral == pytest.approx(-kap.poisson_ratio * strain, rel=1e-3)


def test_single_fold_hinge_moment():
    """Two panels folded rigidly by phi about their shared edge: moment about the edge
    M = k H phi in the linear range, and the enhanced-linear law beyond it (Liu & Paulino 2017)."""
    w, h = 3.0, 7.0
    nodes = np.array([[0, 0, 0], [w, 0, 0], [w, h, 0], [0, h, 0], [2 * w, 0, 0], [2 * w, h, 0.0]])
    structure = n5b8_structure(nodes, np.array([[0, 1, 2, 3], [1, 4, 5, 2]]), 0.127)
    kap = bh.KaptonBarHinge()
    model = BarHingeModel(structure, kap)
    k = kap.hinge_stiffness(0.127)
    moving = np.array([4, 5, structure.panel_centres[1]])
    axis_point = structure.nodes[1]
    for phi in (0.1, 0.6, math.radians(160.0)):  # last one: dihedral 20 deg < 30 deg, stiffening
        rot = np.array(
            [[math.cos(phi), 0, -math.sin(phi)], [0, 1, 0], [math.sin(phi), 0, math.cos(phi)]]
        )
        x = structure.nodes.copy()
        x[moving] = (x[moving] - axis_point) @ rot.T + axis_point
        g = model.gradient(x).reshape(-1, 3)
        # moment of the forces on the moving panel about the edge (axis +y through node 1)
        arm = x[moving] - axis_point
        moment = -np.sum(np.cross(arm, g[moving])[:, 1])
        theta = math.pi - phi
        expected = h * bh.enhanced_linear_law(np.array([theta]), math.pi, k)[1][0]
        assert -moment == pytest.approx(expected, rel=1e-9)
        if phi < math.radians(150):
            assert -moment == pytest.approx(-k * h * phi, rel=1e-9)


def _strip_structure(length=30.0):
    nodes = np.array([[0.0, 0, 0], [length, 0, 0]])
    s = BarHingeStructure(
        nodes=nodes,
        thickness=0.127,
        panels=np.zeros((0, 4), dtype=np.int64),
        panel_centres=np.zeros(0, dtype=np.int64),
        panel_bars=np.zeros((0, 8), dtype=np.int64),
    )
    s.add_bars("bottom_strips", [(0, 1)])
    s.sections["bottom_strips"] = {"section": 10.0}
    return s


def test_lce_bars_are_tension_only_with_volume_conserving_force():
    """Force of one bar (half of a 10 mm^2 strip) at rest fraction f = lambda/lambda_N and stretch
    p: (5 mm^2/lambda) P_Ogden(p) in tension, zero force and stiffness when slack."""
    structure = _strip_structure()
    lce = bh.LCEStripBars()
    model = BarHingeModel(structure, lce=lce)
    lam = 1.05
    model.set_rest_fractions({"bottom_strips": lce.rest_fraction(lam)})
    rest = 30.0 * lam / lce.lambda_N
    for p in (1.02, 1.2):
        x = np.array([[0.0, 0, 0], [p * rest, 0, 0]])
        force = model.bar_forces(x)["bottom_strips"][0]
        assert force == pytest.approx(5.0 / lam * ogden_uniaxial_nominal_stress(p), rel=1e-12)
    slack = np.array([[0.0, 0, 0], [0.9 * rest, 0.5, 0]])
    assert model.bar_forces(slack)["bottom_strips"][0] == 0.0
    assert abs(model.hessian(slack)).max() == 0.0
    with pytest.raises(InputError):
        model.set_rest_fractions({"top_strips": 0.9})


def test_newton_leaves_a_saddle_for_a_stable_state():
    """The perfect flat ribbon compressed beyond its critical load is an equilibrium but a saddle;
    with inertia control Newton leaves it along the negative curvature and settles in a buckled,
    stable state of lower energy."""
    from lcefem.meshes.kapton_ribbon import (
        KaptonBarHingeMesh,
        KaptonSpecimenGeometry,
        build_ribbon_bar_hinge,
    )

    spec = KaptonSpecimenGeometry()
    s = build_ribbon_bar_hinge(spec, KaptonBarHingeMesh(panels=8, imperfection=0.0))
    model = BarHingeModel(s)
    held = np.concatenate(
        [held_dofs(s.node_sets["left_clamp"]), held_dofs(s.node_sets["right_clamp"])]
    )
    free = np.setdiff1d(np.arange(model.ndof), held)
    x = s.nodes.copy()
    shortening = 0.5  # mm, well beyond the critical 0.003 mm
    x[s.node_sets["right_clamp"], 0] -= shortening
    inner = np.setdiff1d(
        np.arange(s.num_nodes),
        np.concatenate([s.node_sets["left_clamp"], s.node_sets["right_clamp"]]),
    )
    x[inner, 0] *= 1.0 - shortening / spec.length
    flat = newton(model, x, free, NewtonOptions(inertia_control=False))
    assert flat.converged and flat.negative_pivots >= 1
    assert np.abs(flat.x[:, 2]).max() < 1e-12
    stable = newton(model, flat.x, free)
    assert stable.converged and stable.negative_pivots == 0
    assert np.abs(stable.x[:, 2]).max() > 1.0 and stable.energy < flat.energy


def test_path_restarts_from_the_last_converged_state(small_beam):
    """A crude Newton budget forces failed increments; every recorded state must carry exactly the
    rest fractions of its own load factor (no accumulation from failed trials, unlike the published
    code), and the path must still reach t = 1."""
    structure, model = small_beam
    held = isostatic_supports(*structure.node_sets["centre_support"])
    target = 0.8
    fixed = structure.nodes.reshape(-1)[held].copy()

    def load(t):
        model.set_rest_fractions({"bottom_strips": 1 + t * (target - 1), "top_strips": 1.0})
        return fixed

    seen = []
    result = follow_path(
        model,
        structure.nodes,
        held,
        load,
        newton_options=NewtonOptions(max_iterations=6),
        path_options=PathOptions(initial_increment=0.5, max_increment=0.5),
        on_step=lambda st: seen.append((st.t, model.rest_fractions()["bottom_strips"][0])),
    )
    assert result.failed_increments > 0
    assert seen[-1][0] == 1.0
    for t, f in seen:
        assert f == pytest.approx(1 + t * (target - 1), abs=1e-15)


def test_path_failure_raises_with_the_last_converged_state(small_beam):
    structure, model = small_beam
    held = isostatic_supports(*structure.node_sets["centre_support"])
    fixed = structure.nodes.reshape(-1)[held].copy()

    def load(t):
        model.set_rest_fractions({"bottom_strips": 1 - 0.3 * t, "top_strips": 1.0})
        return fixed

    options = NewtonOptions(max_iterations=1, snap_iterations=0)
    with pytest.raises(ConvergenceError) as info:
        follow_path(
            model,
            structure.nodes,
            held,
            load,
            newton_options=options,
            path_options=PathOptions(initial_increment=0.1, min_increment=0.02),
        )
    err = info.value
    assert "load factor t = " in err.where and err.last_state.t < 1.0
    assert "increment halved below" in err.reason


def test_invalid_options_are_input_errors(small_beam):
    structure, model = small_beam
    held = isostatic_supports(*structure.node_sets["centre_support"])
    with pytest.raises(InputError):
        follow_path(
            model,
            structure.nodes,
            held,
            lambda t: structure.nodes.reshape(-1)[held],
            path_options=dataclasses.replace(PathOptions(), initial_increment=-0.1),
        )
    with pytest.raises(InputError):
        held_dofs([0], "w")
