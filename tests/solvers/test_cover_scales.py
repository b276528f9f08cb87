"""The cover-scale layer (models/cover_scales.py, solvers/bar_hinge/cover_scales.py): closed forms
of the lens area and of the plate energy on a paraboloid, invariance under a rigid rotation, and the
covered model's gradient and Hessian against finite differences."""

import math

import numpy as np
import pytest

from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.models.cover_scales import CoverScales
from lcefem.models.errors import InputError
from lcefem.solvers.bar_hinge.cover_scales import CoveredModel, junction_pitch, scale_layer_matrix


@pytest.fixture(scope="module")
def structure():
    return build_gridshell_bar_hinge()


def test_lens_area_closed_forms():
    s = CoverScales()
    r = 25.0
    assert s.lens_area(0.0) == pytest.approx(math.pi * r * r, rel=1e-12)
    assert s.lens_area(50.0) == 0.0
    # d = r: 2 r^2 acos(1/2) - (r/2) sqrt(3) r = r^2 (2 pi/3 - sqrt(3)/2)
    assert s.lens_area(r) == pytest.approx(
        r * r * (2.0 * math.pi / 3.0 - math.sqrt(3.0) / 2.0), rel=1e-12
    )
    # 3 x 3 disks on a 37 mm pitch: 12 neighbour lenses, diagonals (52.3 mm) apart, both layers
    # counted
    assert s.bent_area(37.0, 3) == pytest.approx(24.0 * s.lens_area(37.0), rel=1e-12)
    assert CoverScales(bent="disks").bent_area(37.0, 3) == pytest.approx(9 * math.pi * r * r)
    with pytest.raises(InputError, match="scales.bent"):
        CoverScales(bent="glued").checked()


def _paraboloid(structure, kx, ky):
    x = structure.nodes.copy()
    c = x[:, :2] - np.array([70.5, 70.5])
    x[:, 2] = 0.5 * (kx * c[:, 0] ** 2 + ky * c[:, 1] ** 2)
    return x


@pytest.mark.parametrize("kx, ky", [(-0.02, -0.02), (-0.01, 0.015), (0.018, 0.0)])
def test_layer_energy_is_plate_energy_on_paraboloid(structure, kx, ky):
    """U = D A_b (kx^2 + ky^2 + 2 nu kx ky)/2 exactly: the second differences of z = (kx X^2 + ky
    Y^2)/2 on the junction grid are (0, 0, k p^2) and the mixed ones vanish."""
    s = CoverScales()
    h = scale_layer_matrix(structure, s)
    x = _paraboloid(structure, kx, ky).reshape(-1)
    area = s.bent_area(junction_pitch(structure), 3)
    nu = s.poisson_ratio
    expected = 0.5 * s.bending_stiffness * area * (kx * kx + ky * ky + 2.0 * nu * kx * ky)
    assert 0.5 * x @ (h @ x) == pytest.approx(expected, rel=1e-9)


def test_layer_energy_invariant_under_rotation_and_zero_flat(structure):
    h = scale_layer_matrix(structure, CoverScales())
    flat = structure.nodes.reshape(-1)
    assert abs(0.5 * flat @ (h @ flat)) < 1e-12
    x = _paraboloid(structure, -0.01, 0.015)
    a = 0.4
    rot = np.array(
        [[1.0, 0.0, 0.0], [0.0, math.cos(a), -math.sin(a)], [0.0, math.sin(a), math.cos(a)]]
    )
    y = (x @ rot.T + np.array([3.0, -2.0, 5.0])).reshape(-1)
    x = x.reshape(-1)
    assert 0.5 * y @ (h @ y) == pytest.approx(0.5 * x @ (h @ x), rel=1e-10)


def test_covered_model_adds_the_layer(structure):
    """Energy, gradient and Hessian of the covered model minus those of the bare one are the layer's
    factor x^T H x / 2, factor H x and factor H (the layer's COO block placed in the pattern)."""
    model = CoveredModel.from_materials(structure).attach_scales(CoverScales(), factor=0.7)
    bare = CoveredModel.from_materials(structure).attach_scales(CoverScales(), factor=0.0)
    h = scale_layer_matrix(structure, CoverScales())
    x = _paraboloid(structure, -0.01, 0.012).reshape(-1)
    e1, g1, _ = model.evaluate(x)
    e0, g0, _ = bare.evaluate(x)
    assert e1 - e0 == pytest.approx(0.35 * x @ (h @ x), rel=1e-10)
    assert np.allclose(g1 - g0, 0.7 * (h @ x), rtol=1e-10, atol=1e-12)
    diff = (model.hessian(x) - bare.hessian(x) - 0.7 * h).tocoo()
    # round-off of the bare Hessian (entries up to ~1e4 N/mm) cancels to ~1e-12
    assert np.max(np.abs(diff.data), initial=0.0) <= 1e-7 * np.max(np.abs(h.data))
    # and the layer alone against finite differences of its energy
    d = np.random.default_rng(3).standard_normal(x.size)
    eps = 1e-3
    fd = (model.layer_energy(x + eps * d) - model.layer_energy(x - eps * d)) / (2 * eps)
    assert fd == pytest.approx(0.7 * (h @ x) @ d, rel=1e-8)


def test_covered_model_keeps_the_strip_bending_elements():
    """With the FE-calibrated model set (strip element 'beam') the covered model is the strip-beam
    model plus the layer: energy, gradient and Hessian minus the strip-beam model's are the layer's
    (a covered model without the strip elements would differ by their bending energy, > 0 here)."""
    from lcefem.solvers.bar_hinge.strip_beams import StripBeamModel, bar_hinge_model
    from lcefem.solvers.problems.gridshell_bh_scales import CoveredStripBeamModel, covered_model
    from lcefem.validation.studies.gridshell import calibrate

    ms = calibrate.model_set("fe-calibrated")
    s, materials = ms.structure(), ms.materials
    model = covered_model(s, materials, CoverScales(), factor=0.7)
    strip = bar_hinge_model(s, materials)
    assert isinstance(model, CoveredStripBeamModel) and isinstance(strip, StripBeamModel)
    h = scale_layer_matrix(s, CoverScales())
    x = (s.nodes + np.random.default_rng(5).normal(scale=0.05, size=s.nodes.shape)).reshape(-1)
    e1, g1, _ = model.evaluate(x)
    e0, g0, _ = strip.evaluate(x)
    assert e1 - e0 == pytest.approx(0.35 * x @ (h @ x), rel=1e-10)
    assert np.allclose(g1 - g0, 0.7 * (h @ x), rtol=1e-10, atol=1e-12)
    diff = (model.hessian(x) - strip.hessian(x) - 0.7 * h).tocoo()
    assert np.max(np.abs(diff.data), initial=0.0) <= 1e-7 * np.max(np.abs(h.data))
    assert float(np.sum(strip.strip_beam_energy(x))) > 0
    # the published set's structure keeps the plain covered model
    assert type(covered_model(build_gridshell_bar_hinge())) is CoveredModel
