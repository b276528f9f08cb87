"""The buckling specimen's bar-and-hinge geometry (seed 001: 36 x 7 x 0.127 mm, fixed-fixed)."""

import numpy as np
import pytest

from lcefem.meshes.kapton_ribbon import (
    KaptonBarHingeMesh,
    KaptonSpecimenGeometry,
    build_ribbon_bar_hinge,
)
from lcefem.models.errors import InputError


def test_specimen_structure():
    spec, mesh = KaptonSpecimenGeometry(), KaptonBarHingeMesh(panels=12, imperfection=1e-3)
    s = build_ribbon_bar_hinge(spec, mesh)
    assert s.panels.shape == (12 + 2, 4)  # free panels plus one clamp panel at each end
    np.testing.assert_allclose(s.nodes[s.node_sets["left_end"], 0], 0.0)
    np.testing.assert_allclose(s.nodes[s.node_sets["right_end"], 0], spec.length)
    assert s.node_sets["left_clamp"].size == 5 and s.node_sets["right_clamp"].size == 5
    # clamps are flat and outside the free length
    np.testing.assert_allclose(s.nodes[s.node_sets["left_clamp"], 2], 0.0)
    assert s.nodes[s.node_sets["left_clamp"], 0].max() == 0.0
    # first fixed-fixed mode, amplitude a L at mid-span, zero slope at the clamps
    assert s.nodes[s.node_sets["mid_span"], 2] == pytest.approx(1e-3 * spec.length)
    assert spec.second_moment == pytest.approx(7 * 0.127**3 / 12)
    # every shared edge carries a fold hinge: 12 + 2 panels -> 13 folds
    assert s.hinges["fold"].shape[0] == 13


@pytest.mark.parametrize(
    "spec,mesh",
    [
        (KaptonSpecimenGeometry(supports="pinned"), KaptonBarHingeMesh()),
        (KaptonSpecimenGeometry(length=-1.0), KaptonBarHingeMesh()),
        (KaptonSpecimenGeometry(), KaptonBarHingeMesh(panels=1)),
    ],
)
def test_bad_input(spec, mesh):
    with pytest.raises(InputError):
        build_ribbon_bar_hinge(spec, mesh)
