"""The reach study's distance (lcefem.validation.studies.design.gridshell_reach_study): the rigid
fit removes exactly a vertical translation and two tilts, and leaves closed-form distances of the
flat surface."""

import numpy as np
import pytest

from lcefem.validation.studies.design import gridshell_reach_study as rs


def _grid(n=9, side=141.0):
    u = np.linspace(-side / 2, side / 2, n)
    x, y = np.meshgrid(u, u)
    return np.column_stack(
        [x.ravel() + 30.0, y.ravel() - 12.0, np.zeros(x.size)]
    )  # off-centre on purpose


def test_rigid_fit_removes_translation_and_tilts_only():
    pts = _grid()
    target = rs.TARGETS["gaussian bump"][0]
    xy = pts[:, :2] - pts[:, :2].mean(axis=0)
    # the target itself, lifted and tilted: distance 0
    pts[:, 2] = target(xy[:, 0], xy[:, 1]) + 3.0 + 0.01 * xy[:, 0] - 0.02 * xy[:, 1]
    np.testing.assert_allclose(rs.rigid_residual(pts, target), 0.0, atol=1e-12)
    # a curvature is not a rigid motion: z = x^2 / 200 against the flat target keeps its variance
    pts[:, 2] = xy[:, 0] ** 2 / 200.0
    r = rs.rigid_residual(pts, lambda x, y: 0.0 * x)
    q = xy[:, 0] ** 2 / 200.0
    assert np.sqrt(np.mean(r**2)) == pytest.approx(np.std(q), rel=1e-12)


def test_flat_surface_against_the_twist_is_its_rms():
    # On a centred symmetric grid x y is orthogonal to 1, x and y: nothing of the twist is rigid, so
    # the flat surface's distance is the RMS of tau x y over the points.
    pts = _grid()
    xy = pts[:, :2] - pts[:, :2].mean(axis=0)
    r = rs.rigid_residual(pts, rs.TARGETS["twisted"][0])
    expected = rs.TWIST * np.sqrt(np.mean((xy[:, 0] * xy[:, 1]) ** 2))
    assert np.sqrt(np.mean(r**2)) == pytest.approx(expected, rel=1e-12)
    assert expected > 1.0  # the flat surface misses the twist by more than the study's 1 mm


def test_study_grids_keep_the_published_side():
    from lcefem.meshes.composite_beam import CompositeBeamGeometry

    for name in ("3x3", "5x5"):
        g = rs.GRIDS[name].geometry(CompositeBeamGeometry())
        n = rs.GRIDS[name].ribbons
        assert (n + 1) * g.segment_length + n * g.junction_length == pytest.approx(
            rs.SIDE, abs=1e-9
        )


def test_triangular_grid_has_its_own_channels_and_support():
    """The triangular grid runs with the paper's channels extended to three families (one per layer
    and family: 6), 6 per ribbon (3 families x 3 ribbons x 2 layers = 18), one per strip (30 bottom
    + 21 top), under the clamp; the paper's 4 channels do not apply there (one line)."""
    import dataclasses

    from lcefem.meshes.gridshell import build_gridshell_bar_hinge
    from lcefem.models.errors import InputError
    from lcefem.validation.studies.design import gridshell_design as gd

    assert rs.grid_wirings("triangular") == ("6 channels", "per ribbon and layer", "per strip")
    assert rs.grid_support("triangular") == "clamp" and rs.grid_support("3x3") == "rollers"
    counts = []
    for wiring in rs.grid_wirings("triangular"):
        mode, wires = rs.WIRINGS[wiring]
        s = build_gridshell_bar_hinge(
            layout=dataclasses.replace(rs.GRIDS["triangular"], wiring=wires)
        )
        counts.append(len(gd.channel_selections(s, mode)))
    assert counts == [6, 18, 51]
    with pytest.raises(InputError, match="wiring = '4 channels' on grid 'triangular': allowed 6"):
        rs.best_surface("dome", "triangular", "4 channels")


def test_honeycomb_has_six_channels_and_the_clamp():
    """The honeycomb (3 cells, 15 pieces) runs with the triangular grid's 6 channels, 30 per ribbon
    and layer (every piece on its own line: as per strip) and 30 per strip, under the clamp."""
    import dataclasses

    from lcefem.meshes.gridshell import build_gridshell_bar_hinge
    from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
    from lcefem.validation.studies.design import gridshell_design as gd

    honeycomb = NAMED_LAYOUTS["hexagonal"]
    assert "hexagonal" not in rs.GRIDS  # its patch is smaller than the others (module docstring)
    assert rs.grid_wirings(honeycomb) == ("6 channels", "per ribbon and layer", "per strip")
    assert rs.grid_support(honeycomb) == "clamp"
    counts = []
    for wiring in rs.grid_wirings(honeycomb):
        mode, wires = rs.WIRINGS[wiring]
        s = build_gridshell_bar_hinge(layout=dataclasses.replace(honeycomb, wiring=wires))
        counts.append(len(gd.channel_selections(s, mode)))
    assert counts == [6, 30, 30]
