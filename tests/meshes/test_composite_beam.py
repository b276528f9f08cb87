"""Composite-beam geometry (published connectivity) and the curvature measurement."""

import math

import numpy as np
import pytest

from lcefem.meshes.composite_beam import (
    BeamBarHingeMesh,
    CompositeBeamGeometry,
    beam_stations,
    build_beam_bar_hinge,
    middle_station_indices,
)
from lcefem.models import bar_hinge as bh
from lcefem.models.errors import InputError
from lcefem.solvers.analysis.curvature import beam_curvature, circle_fit, signed_circle_curvature


@pytest.fixture(scope="module")
def beam():
    return build_beam_bar_hinge(CompositeBeamGeometry(), BeamBarHingeMesh())


def test_panel_layout_follows_the_published_model(beam):
    g = CompositeBeamGeometry()
    x = beam.nodes[beam.panels[:, 0], 0]
    x_end = beam.nodes[beam.panels[:, 1], 0]
    widths = np.round(x_end - x, 9)
    # per segment: 5 x 2.3, 7 (crown), 5 x 2.3; then a 7 mm junction
    per_segment = [2.3] * 5 + [7.0] + [2.3] * 5
    expected = (per_segment + [7.0]) * (g.segments - 1) + per_segment
    np.testing.assert_allclose(widths, expected, atol=1e-9)
    assert beam.nodes[:, 0].max() == pytest.approx(g.total_length) == pytest.approx(141.0)
    assert np.allclose(beam.nodes[beam.panels, 1].min(axis=1), 0.0)
    assert np.allclose(beam.nodes[beam.panels, 1].max(axis=1), 7.0)


def test_arch_and_top_square_height(beam):
    g = CompositeBeamGeometry()
    assert g.arch_height(0.0) == 0.0 and g.arch_height(15.0) == pytest.approx(1.127)
    assert g.top_strip_height == pytest.approx(0.982, abs=5e-4)  # published: 0.982 mm
    squares = beam.node_sets["top_squares"]
    assert squares.shape == (3, 4)
    np.testing.assert_allclose(beam.nodes[squares, 2], g.top_strip_height)
    # junctions are flat, at z = 0, under the raised squares
    np.testing.assert_allclose(beam.nodes[beam.node_sets["junction_corners"], 2], 0.0, atol=1e-15)


def test_strips_have_the_ribbon_straight_length(beam):
    """As built, bottom strips (chords) and top strips (crown edge -> over the junction -> crown
    edge) both span 30 mm = L (published model)."""
    bottom = beam.bar_lengths("bottom_strips")
    np.testing.assert_allclose(bottom, 30.0)
    assert bottom.size == 2 * 4
    top = beam.bar_lengths("top_strips")
    of = beam.info["top_strip_of_bar"]
    for j in range(3):
        # two sides, each 11.5 + 7 + 11.5
        assert top[of == j].sum() == pytest.approx(2 * 30.0)
    glue = build_beam_bar_hinge(mesh=BeamBarHingeMesh(top_junction="glue"))
    np.testing.assert_allclose(glue.bar_lengths("top_strips"), 11.5)
    assert glue.bars["glue"].shape[0] == 6 * 3


def test_contacts_are_open_as_built(beam):
    for name, rows in beam.contacts.items():
        x = beam.nodes
        gap = bh.point_plane_gap(*(x[rows[:, c]] for c in range(4)), derivatives=0)
        rest = beam.contact_rest.get(name, gap)
        assert np.all(gap >= rest - 1e-12), name
    assert {"bottom_strip_contact", "top_strip_contact", "top_square_contact"} <= set(beam.contacts)


def test_node_sets(beam):
    sets = beam.node_sets
    assert sets["left_end"].shape == (2,) and sets["right_end"].shape == (2,)
    np.testing.assert_allclose(beam.nodes[sets["left_end"], 0], 0.0)
    np.testing.assert_allclose(beam.nodes[sets["right_end"], 0], 141.0)
    assert sets["junction_centres"].shape == (3,) and sets["crown_centres"].shape == (4,)
    np.testing.assert_allclose(beam.nodes[sets["junction_centres"], 0], [33.5, 70.5, 107.5])
    # even N: the middle panel is the middle junction; odd N: the middle crown
    assert beam.nodes[sets["middle_panel"], 0].mean() == pytest.approx(70.5)
    odd = build_beam_bar_hinge(CompositeBeamGeometry(segments=3))
    assert odd.nodes[odd.node_sets["middle_panel"], 0].mean() == pytest.approx(37.0 + 15.0)


@pytest.mark.parametrize(
    "bad",
    [
        dict(segments=1),
        dict(segment_length=-1.0),
        dict(crown_bond_length=30.0),
        dict(ribbon_thickness=0.0),
    ],
)
def test_bad_geometry_is_an_input_error(bad):
    with pytest.raises(InputError):
        build_beam_bar_hinge(CompositeBeamGeometry(**bad))


def test_bad_mesh_option_is_an_input_error():
    with pytest.raises(InputError, match="top_junction"):
        build_beam_bar_hinge(mesh=BeamBarHingeMesh(top_junction="rigid"))


# ---------------------------------------------------------------------------- curvature
def _rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


@pytest.mark.parametrize("n", [3, 7])
def test_circle_fit_is_exact_for_points_on_a_circle(n):
    radius, centre = 23.0, np.array([4.0, -2.0, 7.0])
    rot = _rotation([0.3, 1.0, -0.4], 0.8)
    phi = np.linspace(-0.9, 1.1, n)
    pts = centre + (np.stack([radius * np.cos(phi), radius * np.sin(phi), 0 * phi], axis=1)) @ rot.T
    kappa, c, _ = circle_fit(pts)
    assert kappa == pytest.approx(1 / radius, rel=1e-10)
    np.testing.assert_allclose(c, centre, atol=1e-8)


def test_circle_fit_of_collinear_points_is_zero():
    pts = np.outer(np.linspace(0, 10, 5), [1.0, 2.0, 0.5])
    assert circle_fit(pts)[0] == 0.0
    assert signed_circle_curvature(pts, [0, 0, 1]) == 0.0


def test_beam_curvature_sign_convention_and_invariance(beam):
    """A beam wrapped on a circle of radius R with its ends down (towards the bottom strips) has
    positive curvature (the sign of Eq. 2 when the top strips are longer); ends up, negative; a
    rigid motion changes nothing; the as-built beam is straight. The stations are the junction
    squares' centroids, which lie on chords of the arc: radius R cos(d/(2R)) for junctions of length
    d."""
    assert beam_curvature(beam, beam.nodes) == pytest.approx(0.0, abs=1e-12)
    radius, xc, d = 60.0, 70.5, 7.0
    expected = 1.0 / (radius * math.cos(d / (2 * radius)))
    for sign in (1.0, -1.0):
        x0 = beam.nodes
        s = x0[:, 0] - xc
        r = radius + sign * x0[:, 2]  # centre at z = -sign R: the top side is outside for sign +1
        bent = np.stack(
            [xc + r * np.sin(s / radius), x0[:, 1], -sign * radius + sign * r * np.cos(s / radius)],
            axis=1,
        )
        assert beam_curvature(beam, bent) == pytest.approx(sign * expected, rel=1e-9)
        moved = bent @ _rotation([1.0, -0.5, 2.0], 2.4).T + np.array([3.0, -8.0, 1.0])
        assert beam_curvature(beam, moved) == pytest.approx(sign * expected, rel=1e-9)
    assert beam_stations(beam).shape == (5, 3)


def test_middle_stations():
    np.testing.assert_array_equal(middle_station_indices(4), [1, 2, 3])
    np.testing.assert_array_equal(middle_station_indices(2), [0, 1, 2])
    np.testing.assert_array_equal(middle_station_indices(5), [1, 2, 3, 4])
    np.testing.assert_array_equal(middle_station_indices(8), [3, 4, 5])
