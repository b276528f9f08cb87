"""Curvature measures against closed forms (paraboloids, saddles, spheres), and their signs."""

import math

import numpy as np
import pytest

from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.solvers.analysis.curvature import gridshell_curvatures, quadratic_surface_curvatures

GRID = np.array([-37.0, 0.0, 37.0])


def _grid_points(f):
    u, v = np.meshgrid(GRID, GRID, indexing="ij")
    return u.ravel(), v.ravel(), f(u.ravel(), v.ravel())


@pytest.mark.parametrize(
    "ka, kb, angle",
    [(-0.017, -0.017, 0.0), (-0.010, 0.014, 0.0), (0.018, 0.0, 0.0), (-0.010, 0.014, 0.4)],
)
def test_quadratic_fit_is_exact_on_quadratics(ka, kb, angle):
    c, s = math.cos(angle), math.sin(angle)

    def f(u, v):
        a, b = c * u + s * v, -s * u + c * v
        return 0.5 * (ka * a**2 + kb * b**2) + 3.0

    q = quadratic_surface_curvatures(*_grid_points(f))
    assert q["k1"] == pytest.approx(min(ka, kb), abs=1e-12)
    assert q["k2"] == pytest.approx(max(ka, kb), abs=1e-12)
    if ka != kb:
        d = q["dir1"] if ka < kb else q["dir2"]
        assert abs(abs(np.dot(d[:2], [c, s])) - 1.0) < 1e-10
    assert q["gaussian"] == pytest.approx(ka * kb, abs=1e-14)


def test_quadratic_fit_of_a_sphere_cap():
    # A sphere is not a quadratic: z = R - r^2/(2R) - r^4/(8R^3) - ... On the 3 x 3 grid of pitch h
    # the least-squares fit absorbs the quartic term into the curvature, a relative error of order
    # (h/R)^2 (about 0.69 (h/R)^2 here); it must vanish like (h/R)^2.
    errors = []
    for radius in (200.0, 400.0, 1000.0):
        q = quadratic_surface_curvatures(
            *_grid_points(lambda u, v: np.sqrt(radius**2 - u**2 - v**2))
        )
        assert q["k1"] == pytest.approx(q["k2"], abs=1e-14)
        err = q["k1"] * radius + 1.0  # relative error of -1/R (the fit overestimates |k|)
        assert 0.0 < -err < (37.0 / radius) ** 2
        errors.append(-err)
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1)


@pytest.fixture(scope="module")
def grid():
    return build_gridshell_bar_hinge()


@pytest.mark.parametrize(
    "ka, kb",
    [(-1 / 60.0, -1 / 60.0), (1 / 60.0, 1 / 60.0), (-1 / 100.0, 1 / 70.0), (1 / 55.0, 0.0)],
)
def test_gridshell_measures_and_signs(grid, ka, kb):
    # Map every node onto z + (ka (x - c)^2 + kb (y - c)^2)/2: junction centres (means of four
    # corners) lie on a shifted copy of the same paraboloid, so the quadratic fit is exact; the
    # circle through the middle ribbon's end centres (x = 0, 141; y = 70.5 +- 3.5) and the apex has
    # the closed form 2 h/(a^2 + h^2), a = 70.5 mm, h the apex-to-ends height.
    x = grid.nodes.copy()
    c = 70.5
    x[:, 2] += 0.5 * (ka * (x[:, 0] - c) ** 2 + kb * (x[:, 1] - c) ** 2)
    k = gridshell_curvatures(grid, x)
    assert k["quad_kx"] == pytest.approx(ka, abs=1e-10)
    assert k["quad_ky"] == pytest.approx(kb, abs=1e-10)
    a = 70.5
    for name, kk in (("circle_x", ka), ("circle_y", kb)):
        h = 0.5 * kk * (a**2 - 3.5**2)  # ends' height over the apex (corners at +-3.5 average out)
        expected = 2.0 * h / (a**2 + h**2)
        assert k[name] == pytest.approx(expected, abs=1e-10)
        assert np.sign(k[name]) == np.sign(kk)  # dome negative, bowl positive (seed 001)
