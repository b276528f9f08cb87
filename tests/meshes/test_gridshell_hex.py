"""The honeycomb gridshell in the bar-and-hinge model (lcefem.meshes.gridshell_hex): its counts from
the layout's plan and the closed-form geometry of its pieces and junction plates."""

import math

import numpy as np
import pytest

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS, Layout
from lcefem.models.errors import InputError
from lcefem.solvers.problems import gridshell_bh as problem

G = CompositeBeamGeometry()  # L = 30 mm, d = 7 mm (seed 001; the published model)


@pytest.mark.parametrize(
    "n, cells, junctions, pieces", [(1, 3, 13, 15), (2, 6, 22, 27), (3, 12, 37, 48)]
)
def test_counts_follow_the_plan(n, cells, junctions, pieces):
    """From the plan (Layout.plan: J junctions, P pieces): J hexagons, a bottom strip (2 bars) and a
    top strip (2 halves of 2 bars) per piece, 11 panels per piece + 3 rhombi per hexagon, 4 spoke
    hinges per panel, fold hinges 10 + 2 per piece (its own and its two plate edges) + 3 per
    hexagon, 4 + 4 strip-ribbon springs per piece; the patch's cells within n pitches."""
    layout = Layout(kind="hexagonal", ribbons=n)
    plan = layout.plan()
    assert (len(plan["cells"]), len(plan["junctions"]), len(plan["lines"])) == (
        cells,
        junctions,
        pieces,
    )
    s = build_gridshell_bar_hinge(layout=layout)
    J, P = junctions, pieces
    assert s.node_sets["junction_corners"].shape == (J, 6)
    np.testing.assert_allclose(s.info["junction_xy"], plan["junctions"], atol=1e-12)
    assert s.info["pieces"].shape == (P, 2)
    assert s.panels.shape[0] == 11 * P + 3 * J
    assert s.bars["bottom_strips"].shape[0] == 2 * P
    assert s.bars["top_strips"].shape[0] == 4 * P
    assert len(s.info["strips"]) == 2 * P
    assert s.hinges["bend"].shape[0] == 4 * s.panels.shape[0]
    assert s.hinges["fold"].shape[0] == 12 * P + 3 * J
    assert s.hinges["strip_contact"].shape[0] == 8 * P
    assert s.bars["glue"].shape[0] == 27 * J
    assert s.info["wiring"] == ("Ta", "Tb", "Tc", "Ba", "Bb", "Bc")
    # three piece directions, each a third of the pieces
    fam = np.array(s.info["piece_family"])
    assert [int((fam == f).sum()) for f in "abc"] == [P // 3] * 3


def test_piece_and_plate_closed_form():
    """Every piece is the published 30 mm segment between two plates (bottom chords 30 mm); the
    pitch is L + sqrt(3) d = 42.12 mm (the plate's apothem sqrt(3) d/2 at each end); hexagon
    vertices at d from the centre; a top-strip half spans crown edge to plate edge, 11.5 mm; three
    pieces meet at 120 deg at an inner junction (the centre junction's at 0, 120, 240 deg). The
    plan rounds junction centres to 1e-12 mm, hence rtol 1e-10."""
    layout = Layout(kind="hexagonal", ribbons=2)
    s = build_gridshell_bar_hinge(layout=layout)
    x = s.nodes
    d = G.ribbon_width
    assert layout.geometry(G).pitch == pytest.approx(G.segment_length + math.sqrt(3.0) * d)
    r = np.linalg.norm(
        x[s.node_sets["junction_corners"]] - x[s.node_sets["junction_centres"]][:, None], axis=2
    )
    np.testing.assert_allclose(r, d, rtol=1e-12)
    b = s.bars["bottom_strips"]
    np.testing.assert_allclose(np.linalg.norm(x[b[:, 0]] - x[b[:, 1]], axis=1), 30.0, rtol=1e-10)
    t = s.bars["top_strips"]
    np.testing.assert_allclose(np.linalg.norm(x[t[:, 0]] - x[t[:, 1]], axis=1), 11.5, rtol=1e-10)
    c = s.info["junction_xy"]
    ends = s.info["pieces"]
    at_centre = [c[b_] - c[a_] if a_ == 0 else c[a_] - c[b_] for a_, b_ in ends if 0 in (a_, b_)]
    angles = sorted(math.degrees(math.atan2(v[1], v[0])) % 360.0 for v in at_centre)
    np.testing.assert_allclose(angles, [0.0, 120.0, 240.0], atol=1e-8)


def test_named_layout_is_held_by_the_clamp():
    assert NAMED_LAYOUTS["hexagonal"].support == "clamp"


@pytest.mark.parametrize(
    "layout, support, message",
    [
        (Layout(kind="hexagonal", glued=((0, 0),)), "clamp", "layout.glued = ((0, 0),)"),
        (Layout(kind="hexagonal", ribbons=1), "rollers", "support = 'rollers': a hexagonal grid"),
        (Layout(kind="hexagonal", ribbons=1), "table", "support = 'table': a hexagonal grid"),
    ],
)
def test_refusals_are_one_line(layout, support, message):
    with pytest.raises(InputError) as err:
        problem.setup_gridshell(None, support, layout=layout)
    assert message in str(err.value) and "\n" not in str(err.value)
