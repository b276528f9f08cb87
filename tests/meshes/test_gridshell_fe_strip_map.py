"""The map from the bar-and-hinge strip ids to the FE strip tags
(:func:`lcefem.meshes.gridshell_fe.fe_lambdas_of_strips`): the strips it pairs lie at the same
as-built place, and a drive per strip that is uniform per channel gives the FE the channel drive."""

from __future__ import annotations

import dataclasses
import math

import pytest

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.meshes.gridshell_fe import fe_lambdas_of_strips, fe_strip_tags, strip_catalogue
from lcefem.meshes.gridshell_fe_gmsh import layout_fe_geometry
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.solvers.problems.gridshell_fe_run import strip_values

#: the published 3 x 3 and the reach study's refined 5 x 5 (141 mm side: pitch (141 - 5 x 7)/6 + 7)
LAYOUTS = {
    "published": NAMED_LAYOUTS["published"],
    "5x5 on 141 mm": dataclasses.replace(NAMED_LAYOUTS["5x5"], pitch=(141.0 - 35.0) / 6 + 7.0),
}
CHANNEL_DRIVE = {"Bx": 1.21, "By": 1.26, "Tx": 1.31, "Ty": 1.36}


def _both(name):
    layout = LAYOUTS[name]
    structure = build_gridshell_bar_hinge(layout=layout)
    g = layout_fe_geometry(layout, CompositeBeamGeometry())
    cat = strip_catalogue(g, layout.ribbons, g.strip_width / math.sqrt(PUBLISHED_LAMBDA_N))
    return structure, cat


@pytest.mark.parametrize("name", list(LAYOUTS))
def test_paired_strips_lie_at_the_same_place(name):
    structure, cat = _both(name)
    strips = structure.info["strips"]
    covered = [t for s in strips for t in fe_strip_tags(s)]
    assert sorted(covered) == sorted(cat)  # every FE strip tag once
    for s in strips:
        tags = fe_strip_tags(s)
        for t in tags:
            assert (cat[t]["layer"], cat[t]["direction"]) == (s.layer, s.direction)
        # a top strip's two halves lie symmetrically about its junction (the BH midpoint)
        mx = sum(cat[t]["midpoint"][0] for t in tags) / len(tags)
        my = sum(cat[t]["midpoint"][1] for t in tags) / len(tags)
        assert mx == pytest.approx(s.midpoint[0], abs=1e-9)
        assert my == pytest.approx(s.midpoint[1], abs=1e-9)


@pytest.mark.parametrize("name", list(LAYOUTS))
def test_a_uniform_drive_per_channel_is_the_channel_drive(name):
    structure, cat = _both(name)
    strips = structure.info["strips"]
    per_strip = {s.id: CHANNEL_DRIVE[s.channel] for s in strips}
    mapped = strip_values(fe_lambdas_of_strips(strips, per_strip), cat, PUBLISHED_LAMBDA_N)
    assert mapped == strip_values(CHANNEL_DRIVE, cat, PUBLISHED_LAMBDA_N)


def test_one_strip_moves_only_its_own_tags():
    structure, cat = _both("published")
    strips = structure.info["strips"]
    top = next(s for s in strips if s.layer == "top" and s.ribbon == 1 and s.index == 2)
    drive = {s.id: PUBLISHED_LAMBDA_N for s in strips} | {top.id: 1.1}
    values = strip_values(fe_lambdas_of_strips(strips, drive), cat, PUBLISHED_LAMBDA_N)
    moved = {t for t, v in values.items() if v != PUBLISHED_LAMBDA_N}
    assert moved == {f"top_{top.direction}_r1_j2_lo", f"top_{top.direction}_r1_j2_hi"}


def test_missing_or_unknown_strip_is_refused():
    structure, _ = _both("published")
    strips = structure.info["strips"]
    with pytest.raises(InputError, match="lambda of strip 0: missing"):
        fe_lambdas_of_strips(strips, {s.id: 1.2 for s in strips[1:]})
    with pytest.raises(InputError, match="no such strip"):
        fe_lambdas_of_strips(strips, {s.id: 1.2 for s in strips} | {999: 1.2})
