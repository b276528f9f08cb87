"""The gridshell builder: published layout and counts, 4-fold symmetry, strip selections."""

import numpy as np
import pytest

from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry
from lcefem.meshes.gridshell import (
    GridshellLayout,
    build_gridshell_bar_hinge,
    resolve_bar_values,
    select_strips,
)
from lcefem.meshes.gridshell_fe import junction_centres
from lcefem.models.errors import InputError


@pytest.fixture(scope="module")
def grid():
    return build_gridshell_bar_hinge()


def test_counts_follow_the_published_layout(grid):
    info = grid.info
    # 6 ribbons x 4 segments x 11 panels + 9 junction squares
    assert grid.panels.shape[0] == 6 * 4 * 11 + 9
    strips = info["strips"]
    assert sum(s.layer == "bottom" for s in strips) == 24
    assert sum(s.layer == "top" for s in strips) == 18
    assert grid.bars["bottom_strips"].shape[0] == 48  # two bars per strip
    for name, count in {"Bx": 12, "By": 12, "Tx": 9, "Ty": 9, "XD1": 4, "YU3": 3}.items():
        assert len(info["groups"][name]) == count
    np.testing.assert_allclose(junction_centres(CompositeBeamGeometry(), 3), [33.5, 70.5, 107.5])
    assert grid.nodes[:, :2].min() == 0.0 and grid.nodes[:, :2].max() == pytest.approx(141.0)
    # every bottom strip is a 30 mm chord, every top strip 11.5 + 7 + 11.5 mm
    np.testing.assert_allclose(grid.bar_lengths("bottom_strips"), 30.0, atol=1e-12)
    top = grid.bar_lengths("top_strips")
    sob = info["strip_of_bar"]["top_strips"]
    per_strip = np.bincount(sob, weights=top)[np.unique(sob)] / 2.0  # two edges per strip
    np.testing.assert_allclose(per_strip, 30.0, atol=1e-9)
    # the raised squares sit at the crown-edge height 0.982 mm
    np.testing.assert_allclose(
        grid.nodes[grid.node_sets["top_squares"].ravel(), 2],
        CompositeBeamGeometry().top_strip_height,
    )
    assert CompositeBeamGeometry().top_strip_height == pytest.approx(0.982, abs=5e-4)


def _rotated_index(nodes, centre):
    """For each node, the index of the node at its position rotated by +90 deg about the z axis
    through ``centre`` (-1 if none)."""
    rel = nodes - [centre, centre, 0.0]
    rot = np.column_stack([-rel[:, 1], rel[:, 0], rel[:, 2]]) + [centre, centre, 0.0]
    keys = {tuple(np.round(p, 7)): i for i, p in enumerate(nodes)}
    return np.array([keys.get(tuple(np.round(p, 7)), -1) for p in rot])


def test_structure_is_four_fold_symmetric(grid):
    perm = _rotated_index(grid.nodes, 70.5)
    assert np.all(perm >= 0)
    for group in ("kapton", "bottom_strips", "top_strips"):
        bars = {tuple(sorted(b)) for b in grid.bars[group].tolist()}
        mapped = {tuple(sorted(perm[b])) for b in grid.bars[group]}
        assert mapped == bars, group


def test_top_junction_modes():
    lce = build_gridshell_bar_hinge(mesh=BeamBarHingeMesh(top_junction="lce"))
    glue = build_gridshell_bar_hinge(mesh=BeamBarHingeMesh(top_junction="glue"))
    assert "glue" not in lce.bars and glue.bars["glue"].shape[0] == 9 * 6
    assert lce.bars["top_strips"].shape[0] == 18 * 6 and glue.bars["top_strips"].shape[0] == 18 * 4


def test_selections_and_half_planes(grid):
    vals = resolve_bar_values(grid, {"XU:x<70.5": 0.75, "XU:x>70.5": 0.95}, 1.0)
    mid = 0.5 * (
        grid.nodes[grid.bars["top_strips"][:, 0]] + grid.nodes[grid.bars["top_strips"][:, 1]]
    )
    xs = np.isin(grid.info["strip_of_bar"]["top_strips"], grid.info["groups"]["Tx"])
    assert np.all(vals["top_strips"][xs & (mid[:, 0] < 70.4)] == 0.75)
    assert np.all(vals["top_strips"][xs & (mid[:, 0] > 70.6)] == 0.95)
    # the middle square's bars lie on the line: the mean of both sides
    on_line = xs & (np.abs(mid[:, 0] - 70.5) < 1e-9)
    assert on_line.sum() == 2 * 3 and np.allclose(vals["top_strips"][on_line], 0.85)
    assert np.all(vals["top_strips"][~xs] == 1.0) and np.all(vals["bottom_strips"] == 1.0)
    assert set(select_strips(grid, "XD").tolist()) == set(grid.info["groups"]["Bx"].tolist())
    with pytest.raises(InputError, match="unknown strip selection 'Tz'"):
        select_strips(grid, "Tz")


def test_one_cell_and_bad_input():
    one = build_gridshell_bar_hinge(layout=GridshellLayout(ribbons=1))
    assert len(one.info["strips"]) == 4 + 2 and one.nodes[:, 0].max() == pytest.approx(67.0)
    with pytest.raises(InputError, match="layout.ribbons"):
        build_gridshell_bar_hinge(layout=GridshellLayout(ribbons=0))
    with pytest.raises(InputError, match="junction_length"):
        build_gridshell_bar_hinge(CompositeBeamGeometry(junction_length=8.0))
