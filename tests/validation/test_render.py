"""Off-screen render of a deformed dolfinx body coloured by a scalar field."""

import dolfinx_solver  # noqa: F401  (before dolfinx)
from mpi4py import MPI

import numpy as np
import pytest
from matplotlib.image import imread

import dolfinx.fem as fem
import dolfinx.mesh

from lcefem.validation.app.render import render_deformed


@pytest.fixture(scope="module")
def strip():
    """A 40 x 5 x 2 mm box, P2 displacement bending it up by 6 mm, P1 temperature 25-75 C along
    x."""
    mesh = dolfinx.mesh.create_box(MPI.COMM_SELF, [[0, 0, 0], [40, 5, 2]], [8, 2, 1])
    V = fem.functionspace(mesh, ("Lagrange", 2, (3,)))
    u = fem.Function(V)
    u.interpolate(lambda x: np.stack([-0.1 * x[0], 0 * x[0], 6.0 * np.sin(np.pi * x[0] / 40)]))
    Q = fem.functionspace(mesh, ("Lagrange", 1))
    T = fem.Function(Q)
    T.interpolate(lambda x: 25.0 + 1.25 * x[0])
    return u, T


def test_render_writes_a_coloured_png_of_the_requested_size(strip, tmp_path):
    u, T = strip
    png = render_deformed(
        tmp_path / "strip.png",
        u,
        T,
        scalar_label="temperature [C]",
        size=(400, 240),
        title="test strip",
        clim=(25.0, 75.0),
        cmap="coolwarm",
    )
    img = imread(png)[..., :3]
    assert img.shape == (240, 400, 3)
    assert img.std() > 0.05  # not blank
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    # both ends of the coolwarm scale appear: the cold (blue) and the hot (red) end of the strip
    assert np.count_nonzero((b > 0.6) & (r < 0.4)) > 50
    assert np.count_nonzero((r > 0.6) & (b < 0.35) & (g < 0.35)) > 50
    assert not list(tmp_path.glob("*.part*"))


def test_render_of_a_uniform_field_has_one_colour_on_the_body(strip, tmp_path):
    """A constant scalar at the bottom of its colour range paints the body blue only: the colour
    comes from the scalar, not from the geometry."""
    u, _ = strip
    png = render_deformed(
        tmp_path / "cold.png",
        u,
        lambda x: np.full(x.shape[1], 25.0),
        scalar_label="temperature [C]",
        size=(400, 240),
        clim=(25.0, 75.0),
        show_undeformed=False,
    )
    img = imread(png)[..., :3]
    body = img[:180, :300]  # left of the colour bar (x > 0.8 of the width), above the axes widget
    reds = np.count_nonzero((body[..., 0] > 0.6) & (body[..., 2] < 0.35))
    blues = np.count_nonzero((body[..., 2] > 0.5) & (body[..., 0] < 0.4))
    assert blues > 200 and reds == 0


def test_render_rejects_a_label_without_unit(strip, tmp_path):
    u, T = strip
    with pytest.raises(ValueError, match="unit in brackets"):
        render_deformed(tmp_path / "x.png", u, T, scalar_label="temperature")
