"""The triangular gridshell in the bar-and-hinge model (lcefem.meshes.gridshell_tri): counts of the
lattice, the hexagonal junction's closed-form geometry, and the grid's symmetry in the model."""

import math

import numpy as np
import pytest

from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import build_gridshell_bar_hinge, line_mirror, unmatched_mirror_rows
from lcefem.meshes.gridshell_layout import Layout
from lcefem.models.errors import InputError
from lcefem.solvers.analysis.curvature import normal_curvature_y
from lcefem.solvers.problems import gridshell_bh as problem

G = CompositeBeamGeometry()  # L = 30 mm, d = 7 mm (seed 001; the published model)


@pytest.mark.parametrize("n", [1, 3, 5])
def test_element_counts_follow_the_lattice(n):
    """J = 3 k (k + 1) + 1 junctions (k = (n - 1)/2); each family crosses every junction once and
    has n ribbons of (junctions + 1) segments: 3 (J + n) bottom strips (2 bars each), 3 J top
    strips (6 bars each with contracting squares), 3 (J + n) (2 f + 1) ribbon panels + 3 rhombi
    per hexagon (f = 5 flank panels)."""
    s = build_gridshell_bar_hinge(layout=Layout(kind="triangular", ribbons=n))
    k = n // 2
    J = 3 * k * (k + 1) + 1
    segments = 3 * (J + n)
    assert s.node_sets["junction_corners"].shape == (J, 6)
    assert s.bars["bottom_strips"].shape[0] == 2 * segments
    assert s.bars["top_strips"].shape[0] == 6 * 3 * J
    assert len(s.info["strips"]) == segments + 3 * J
    assert s.panels.shape[0] == segments * 11 + 3 * J
    assert s.info["wiring"] == ("Ta", "Tb", "Tc", "Ba", "Bb", "Bc")
    assert all(s.node_sets[f"ribbon_ends_{f}"].shape == (n, 2, 2) for f in "abc")


def test_hexagonal_junction_and_segments_closed_form():
    """The hexagon of side d: vertices at distance d from its centre, the ribbon ends on its edges
    (every bottom strip's chord is the published segment, L = 30 mm); the default pitch is
    L + sqrt(3) d = 42.12 mm; a top strip runs crown edge to crown edge, (L - c) + sqrt(3) d =
    23 + 12.12 mm (c = 7 mm crown bond)."""
    layout = Layout(kind="triangular", ribbons=3)
    s = build_gridshell_bar_hinge(layout=layout)
    x = s.nodes
    d = G.ribbon_width
    assert layout.geometry(G).pitch == pytest.approx(G.segment_length + math.sqrt(3.0) * d)
    r = np.linalg.norm(
        x[s.node_sets["junction_corners"]] - x[s.node_sets["junction_centres"]][:, None], axis=2
    )
    np.testing.assert_allclose(r, d, rtol=1e-12)
    b = s.bars["bottom_strips"]
    np.testing.assert_allclose(np.linalg.norm(x[b[:, 0]] - x[b[:, 1]], axis=1), 30.0, rtol=1e-12)
    t = s.bars["top_strips"].reshape(-1, 6, 2)  # left, left, exit, exit, square, square
    span = np.linalg.norm(x[t[:, 0, 0]] - x[t[:, 2, 1]], axis=1)
    np.testing.assert_allclose(span, 23.0 + math.sqrt(3.0) * d, rtol=1e-12)


@pytest.mark.parametrize("angle", [30.0, 90.0, 150.0])
def test_structure_maps_onto_itself_under_the_mirrors(angle):
    """The lines through the centre junction at 30, 90 and 150 deg (between two families) are
    mirrors of the n = 3 lattice: every panel, bar, hinge and contact row has its image with the
    strips' contact quads split along both diagonals (mesh.contact_diagonals = "auto"). Split
    along one, the mirror maps each split onto the other: 3120 contact rows without image (7884 in
    the FE-calibrated set's mesh), and every top strip at 1.3 (clamp, FE-calibrated set) gives
    mirror-image nodes 6.46 mm apart (1e-6 mm with both; docs/layouts/triangular.md)."""
    both = build_gridshell_bar_hinge(layout=Layout(kind="triangular", ribbons=3))
    assert sum(unmatched_mirror_rows(both, line_mirror(both, angle)).values()) == 0
    one = build_gridshell_bar_hinge(
        layout=Layout(kind="triangular", ribbons=3),
        mesh=BeamBarHingeMesh(contact_diagonals="one"),
    )
    left = unmatched_mirror_rows(one, line_mirror(one, angle))
    assert left["contacts.bottom_strip_contact"] + left["contacts.top_strip_contact"] == 3120


def test_a_line_along_a_family_is_not_a_mirror():
    """The families cross in layers at a junction, so the line along family a (0 deg) maps
    nodes onto none: refused with one line."""
    s = build_gridshell_bar_hinge(layout=Layout(kind="triangular", ribbons=3))
    with pytest.raises(InputError, match="no mirror image"):
        line_mirror(s, 0.0)


def _grid(drives, support="clamp", mesh=BeamBarHingeMesh()):
    s = build_gridshell_bar_hinge(layout=Layout(kind="triangular", ribbons=3), mesh=mesh)
    g = problem.GridshellBH(s, problem.GridshellBHConfig(support=support))
    g.set_drives(drives)
    g.advance()
    return g


def test_zero_drive_leaves_the_grid_as_built():
    g = _grid({"T": 1.4, "B": 1.4})  # lambda_N = 1.4: as built
    assert np.max(np.abs(g.x - g.structure.nodes)) < 1e-9


def test_uniform_lambda_keeps_the_threefold_symmetry():
    """Every strip at one lambda on a grid with 3-fold symmetry (lattice, junctions, clamp of the
    whole centre hexagon): the three middle ribbons' circle curvatures agree and the centre
    quadratic is isotropic (kappa_x = kappa_y) to the Newton tolerance (|g| <= 1e-6 N, ~1e-7 1/mm:
    solvers.problems.gridshell_bh.GRIDSHELL_NEWTON); measured 0.0037954 1/mm (a bowl), equal to
    1e-16."""
    g = _grid({"T": 1.2, "B": 1.2})
    k = problem.gridshell_curvatures(g.structure, g.x)
    assert abs(k["circle_a"]) > 1e-3  # the surface did curve
    assert k["circle_b"] == pytest.approx(k["circle_a"], abs=1e-7)
    assert k["circle_c"] == pytest.approx(k["circle_a"], abs=1e-7)
    assert k["quad_ky"] == pytest.approx(k["quad_kx"], abs=1e-7)
    assert k["circle_y"] == pytest.approx(k["circle_x"], abs=1e-7)


def test_normal_curvature_y_closed_form():
    """Euler's k(t) of the form kxx = 0.01, kxy = 0.003, kyy = -0.02 [1/mm] at 0, 60, 120 deg
    gives back kyy."""
    kxx, kxy, kyy = 0.01, 0.003, -0.02

    def k(t):
        c, s = math.cos(math.radians(t)), math.sin(math.radians(t))
        return kxx * c * c + 2 * kxy * c * s + kyy * s * s

    assert normal_curvature_y(k(0), k(60), k(120)) == pytest.approx(kyy, abs=1e-15)


@pytest.mark.parametrize(
    "layout, support, message",
    [
        (Layout(kind="triangular", ribbons=4), "clamp", "layout.ribbons = 4: a triangular layout"),
        (Layout(kind="triangular", glued=((0, 0),)), "clamp", "layout.glued = ((0, 0),)"),
        (Layout(kind="triangular", ribbons=3), "rollers", "support = 'rollers': a triangular"),
    ],
)
def test_refusals_are_one_line(layout, support, message):
    with pytest.raises(InputError) as err:
        problem.setup_gridshell(None, support, layout=layout)
    assert message in str(err.value) and "\n" not in str(err.value)
