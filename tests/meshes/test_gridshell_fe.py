"""The FE gridshell's mesh: tags by name and their counts, body volumes against closed forms,
symmetric models as fractions of the full one, the single-cell grid against the FE composite
beam, mirror symmetry of the nodes, support and contact faces, bad input."""

import json
import math
import sys

import dolfinx_solver  # noqa: F401

import numpy as np
import pytest
import ufl

import dolfinx

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.composite_beam_fe import BeamFEMesh, build_beam_fe
from lcefem.meshes.gridshell_fe import (
    CHANNELS,
    MATERIAL_CELLS,
    RECIPE_SYMMETRY,
    GridshellFEMesh,
    build_gridshell_fe,
    cell_group,
)
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError

G = CompositeBeamGeometry()
LAMBDA_N = PUBLISHED_LAMBDA_N
LEVEL0 = GridshellFEMesh(level=0)
N = 3
WS, H = G.strip_width / math.sqrt(LAMBDA_N), G.strip_thickness / math.sqrt(LAMBDA_N)
GROUPS = ("kapton", "glue", "bottom_pads", "top_pads", "bottom_strips", "top_strips")


def _mesh(symmetry, cells=N, mesh=LEVEL0):
    return build_gridshell_fe(G, LAMBDA_N, mesh, cells=cells, symmetry=symmetry)


@pytest.fixture(scope="module")
def full():
    return _mesh("full")


@pytest.fixture(scope="module")
def quarter():
    return _mesh("quarter")


def _cell_volumes(tm):
    """Volume [mm^3] of every cell and its tag (one compiled form for any grouping; serial)."""
    Q = dolfinx.fem.functionspace(tm.mesh, ("DG", 0))
    vol = dolfinx.fem.assemble_vector(dolfinx.fem.form(ufl.TestFunction(Q) * ufl.dx)).array
    tags = np.zeros(vol.size, dtype=np.int32)
    tags[tm.cell_tags.indices] = tm.cell_tags.values
    return vol, tags


def _group_volumes(tm):
    vol, tags = _cell_volumes(tm)
    return {
        name: float(vol[np.isin(tags, cell_group(tm, name))].sum())
        for name in tm.info["cell_groups"]
    }


def _area(tm, name):
    ds = ufl.Measure("ds", domain=tm.mesh, subdomain_data=tm.facet_tags)
    return dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * ds(tm.facet_tag(name))))


def _strips(tm, layer, direction=None):
    return [
        k
        for k, s in tm.info["strips"].items()
        if s["layer"] == layer and direction in (None, s["direction"])
    ]


def test_tag_counts_full_and_quarter(full, quarter):
    """Full n x n: 2 n (n + 1) bottom strips (one per segment), 2 n^2 top strips of 2 halves.
    Quarter (odd n): (n + 1)/2 ribbons per direction, (n + 1)/2 segments each, and per ribbon
    n top halves (the centre junction's hi half and both halves of the (n - 1)/2 outer ones)."""
    n = N
    assert len(_strips(full, "bottom")) == 2 * n * (n + 1) == 24
    assert len(_strips(full, "top")) == 4 * n**2
    whole = {k for k in full.info["cell_groups"] if k.startswith("top_") and "_j" in k}
    assert len(whole) == 2 * n**2 == 18  # the published model's top strips
    assert set(MATERIAL_CELLS) <= set(full.cells)
    assert len(full.cells) == len(MATERIAL_CELLS) + 2 * n * (n + 1) + 4 * n**2
    assert len(_strips(quarter, "bottom")) == 2 * ((n + 1) // 2) ** 2 == 8
    assert len(_strips(quarter, "top")) == 2 * ((n + 1) // 2) * n == 12
    # a tag means the same piece in every model
    for name, t in quarter.cells.items():
        assert full.cells[name] == t
    assert {"sym_x", "sym_y"} <= set(quarter.facets) and not {"sym_x", "sym_y"} & set(full.facets)


def test_channel_and_published_groups(full):
    groups = full.info["cell_groups"]
    n = N
    for channel, (layer, direction) in CHANNELS.items():
        assert set(groups[channel]) == {full.cells[k] for k in _strips(full, layer, direction)}
    assert len(groups["Bx"]) == n * (n + 1) and len(groups["Tx"]) == 2 * n**2
    assert {full.cells[f"bottom_x_r0_s{s}"] for s in range(n + 1)} == set(groups["XD1"])
    assert len(groups["YU3"]) == 2 * n  # ribbon 3: n strips of two halves
    # paper top segments: the halves over segment s; the end segments have one half
    assert groups["top_x_r0_s0"] == (full.cells["top_x_r0_j0_lo"],)
    assert set(groups["top_x_r0_s1"]) == {
        full.cells["top_x_r0_j0_hi"],
        full.cells["top_x_r0_j1_lo"],
    }
    # the wave recipe's split at x = 70.5 falls between the halves over the centre junction
    mids = {k: s["midpoint"] for k, s in full.info["strips"].items()}
    assert mids["top_x_r1_j1_lo"][0] < 70.5 < mids["top_x_r1_j1_hi"][0]
    assert mids["bottom_y_r2_s0"] == pytest.approx((107.5, 15.0))


def test_volumes_full_closed_forms(full):
    """Strips of the as-built section W_s x H = (w_a x t_a)/lambda_N; a top strip is LCE up to the
    W_s x W_s glue square where it crosses the other direction's strip; bottom pads are a cross
    under each junction plus the end tabs. The ribbon's thickness is vertical (its nodes are
    shifted in z only), so its volume is exactly the flat area x t_p: the material's true volume
    (arc length) is 1 + (pi gap/L)^2/4 = 1.0035 times that on the segments."""
    n, L, d, tab, tp = N, G.segment_length, G.ribbon_width, LEVEL0.end_tab, G.ribbon_thickness
    v = _group_volumes(full)
    length = (n + 1) * L + n * d
    assert v["kapton"] == pytest.approx(
        (2 * n * (length + 2 * tab) * d - n**2 * d**2) * tp, rel=1e-10
    )
    assert v["bottom_strips"] == pytest.approx(2 * n * (n + 1) * L * WS * H, rel=1e-10)
    top_lce = 2 * (L - G.crown_edges[1]) + d - WS
    assert v["top_strips"] == pytest.approx(2 * n**2 * top_lce * WS * H, rel=1e-10)
    assert v["glue"] == pytest.approx(n**2 * WS**2 * H, rel=1e-10)
    assert v["top_pads"] == pytest.approx(2 * n * (n + 1) * G.crown_bond_length * WS * H, rel=1e-10)
    cross = 2 * d * WS - WS**2
    assert v["bottom_pads"] == pytest.approx((n**2 * cross + 4 * n * tab * WS) * H, rel=1e-10)
    vol, tags = _cell_volumes(full)
    for name, strip in full.info["strips"].items():  # every strip tag has its piece's volume
        piece = L if strip["layer"] == "bottom" else 0.5 * top_lce
        assert vol[tags == full.cells[name]].sum() == pytest.approx(piece * WS * H, rel=1e-10), name


def test_ribbon_top_face_carries_the_arch(full):
    """The free Kapton top face: the flat area minus the crown pads plus the arch's arc-length
    excess, integral of (sqrt(1 + z'^2) - 1) over the uncovered width (~0.35 % of a segment).
    The trilinear (polyline) arch at h = 3 mm under-represents the excess by about
    (2 pi h/L)^2/12 = 3 % of it, 1e-4 of the area: the tolerance 3e-4 would not hide a missing
    arch (2.9e-3 of the area)."""
    n, L, d = N, G.segment_length, G.ribbon_width
    length = (n + 1) * L + n * d
    flat = 2 * n * (length + 2 * LEVEL0.end_tab) * d - n**2 * d**2
    s = np.linspace(0.0, L, 200001)
    slope = G.arch_gap * np.pi / L * np.sin(2 * np.pi * s / L)
    excess = np.sqrt(1 + slope**2) - 1
    lo, hi = G.crown_edges
    crown = (s >= lo) & (s <= hi)
    per_segment = d * np.trapezoid(excess, s) - WS * np.trapezoid(np.where(crown, excess, 0.0), s)
    expected = flat - 2 * n * (n + 1) * G.crown_bond_length * WS + 2 * n * (n + 1) * per_segment
    got = _area(full, "ribbon_top") + _area(full, "centre_junction")
    assert got == pytest.approx(expected, rel=3e-4)
    assert abs(got - (expected - 2 * n * (n + 1) * per_segment)) > 10 * 3e-4 * expected


@pytest.mark.parametrize(
    "cells, symmetry, factor",
    [(3, "quarter", 4), (3, "half_x", 2), (3, "half_y", 2), (2, "quarter", 4)],
)
def test_symmetric_models_are_fractions_of_the_full(cells, symmetry, factor, full):
    """Every material group of a mirror model is 1/factor of the full surface's (for n = 2 the
    planes cut segments through their crowns)."""
    whole = full if cells == N else _mesh("full", cells)
    part = _mesh(symmetry, cells)
    assert part.info["symmetry_factor"] == factor
    vw, vp = _group_volumes(whole), _group_volumes(part)
    for name in GROUPS:
        assert factor * vp[name] == pytest.approx(vw[name], rel=1e-10), name


def test_single_cell_grid_matches_the_composite_beam():
    """n = 1: one x and one y ribbon of 2 segments crossing at one junction. Per piece the same
    volumes as the FE beam of 2 segments (half model x 2 = whole beam): a bottom strip, a crown
    pad; the x top strip plus the glue square is the beam's top strip; the two ribbons share the
    junction."""
    grid = _group_volumes(_mesh("full", cells=1))
    beam = build_beam_fe(
        CompositeBeamGeometry(segments=2), LAMBDA_N, BeamFEMesh(level=0, symmetry="half")
    )
    dx = ufl.Measure("dx", domain=beam.mesh, subdomain_data=beam.cell_tags)
    f = beam.info["symmetry_factor"]
    vb = {
        k: f * dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * dx(t)))
        for k, t in beam.cells.items()
    }
    assert grid["XD1"] == pytest.approx(vb["bottom_strips"], rel=1e-10)
    assert grid["YD1"] == pytest.approx(vb["bottom_strips"], rel=1e-10)
    assert grid["top_strips"] / 2 + grid["glue"] == pytest.approx(vb["top_strips"], rel=1e-10)
    assert grid["top_pads"] == pytest.approx(2 * vb["top_pads"], rel=1e-10)
    d, tp = G.ribbon_width, G.ribbon_thickness
    assert grid["kapton"] == pytest.approx(2 * vb["kapton"] - d * d * tp, rel=1e-10)


def _rows(x):
    return np.unique(np.round(x, 8), axis=0)


def test_nodes_are_mirror_symmetric(full, quarter):
    """The full mesh's nodes map onto themselves under x -> 2c - x, y -> 2c - y and x <-> y;
    the quarter's nodes are the full mesh's with x >= c, y >= c (n = 3 cuts only the centre
    strip band, whose two divisions put a station on c)."""
    x = full.mesh.geometry.x
    c = full.info["centre"]
    ref = _rows(x)
    for mapped in (
        np.column_stack([2 * c - x[:, 0], x[:, 1:]]),
        np.column_stack([x[:, 0], 2 * c - x[:, 1], x[:, 2]]),
        x[:, [1, 0, 2]],
    ):
        assert np.array_equal(_rows(mapped), ref)
    keep = (x[:, 0] >= c - 1e-9) & (x[:, 1] >= c - 1e-9)
    assert np.array_equal(_rows(quarter.mesh.geometry.x), _rows(x[keep]))


def test_support_and_contact_faces(full, quarter):
    """Perimeter ends: n ribbons x 2 ends x W t_p per direction; centre junction: W^2 (a quarter
    of it in the quarter model); free strip faces: the bottom strips' tops over the segments, the
    top strips' and glue squares' undersides."""
    n, L, d, tp = N, G.segment_length, G.ribbon_width, G.ribbon_thickness
    for name in ("ribbon_ends_x", "ribbon_ends_y"):
        assert _area(full, name) == pytest.approx(2 * n * d * tp, rel=1e-10)
        assert _area(quarter, name) == pytest.approx(2 * n * d * tp / 4, rel=1e-10)
    assert _area(full, "centre_junction") == pytest.approx(d * d, rel=1e-10)
    assert _area(quarter, "centre_junction") == pytest.approx(d * d / 4, rel=1e-10)
    assert full.info["centre_junction_corners"][0] == (67.0, 67.0, 0.0)
    assert _area(full, "bottom_strip_topside") == pytest.approx(2 * n * (n + 1) * L * WS, rel=1e-10)
    top_lce = 2 * (L - G.crown_edges[1]) + d - WS
    assert _area(full, "top_strip_underside") == pytest.approx(
        2 * n**2 * top_lce * WS + n**2 * WS**2, rel=1e-10
    )
    assert "centre_junction" not in _mesh("quarter", cells=2).facets  # even n: no centre junction


def test_contact_pairs_find_the_ribbon_under_every_strip_node(quarter):
    """The node-pair contact of the FE beam works unchanged: every free strip-face node has ribbon
    nodes at its (x, y), and the tributary areas add up to the face's area."""
    from lcefem.solvers.contact import face_pairs
    from lcefem.solvers.mechanics import displacement_space

    V = displacement_space(quarter.mesh, 2)
    for face, above in (("top_strip_underside", True), ("bottom_strip_topside", False)):
        pairs, areas = face_pairs(quarter, V, face, "kapton", strip_above=above)
        assert pairs.shape[0] > 0
        X = V.tabulate_dof_coordinates()
        assert np.allclose(X[pairs[:, 0], :2], X[pairs[:, 1], :2])
        # strip above the ribbon's top face (or below its bottom face)
        gap = X[pairs[:, 0], 2] - X[pairs[:, 1], 2]
        assert np.all(gap >= -1e-9) if above else np.all(gap <= 1e-9)


def test_levels_refine_in_plane():
    c0 = _mesh("quarter").info["cells"]
    c1 = _mesh("quarter", mesh=GridshellFEMesh(level=1)).info["cells"]
    assert c1 == 4 * c0


#: Target rest-length fractions P0 of the published recipes (shared/reference/gridshell_recipes.md):
#: per family a number, a list per ribbon (1..3), or ("x", below c, above c) by the strip's
#: midpoint.
RECIPES = {
    "saddle": {"XD": 0.75, "YD": 0.95, "XU": 0.95, "YU": 0.75},
    "dome": {"XD": 0.75, "YD": 0.75, "XU": 0.95, "YU": 0.95},
    "cylinder": {"XD": 0.95, "YD": 0.95, "XU": 0.95, "YU": 0.75},
    "table": {"XD": 0.75, "YD": 0.75, "XU": 0.72, "YU": 0.72},
    "cone": {"XD": [0.75, 0.85, 0.95], "YD": 0.90, "XU": 0.95, "YU": 0.90},
    "twisted": {"XD": [0.85, 0.80, 0.95], "YD": 0.90, "XU": [0.95, 0.80, 0.85], "YU": 0.90},
    "wave": {"XD": ("x", 0.95, 0.75), "YD": 0.90, "XU": ("x", 0.75, 0.95), "YU": 0.90},
    "dustpan": {"XD": ("x", 0.95, 0.85), "YD": 0.95, "XU": ("x", 0.80, 0.95), "YU": 0.80},
}


def _p0(recipe, strip, centre):
    rule = RECIPES[recipe][strip["group"][:2]]
    if isinstance(rule, list):
        return rule[strip["ribbon"]]
    if isinstance(rule, tuple):
        return rule[1] if strip["midpoint"][0] < centre else rule[2]
    return rule


@pytest.mark.parametrize("recipe", sorted(RECIPES))
def test_recipe_symmetry_table_holds(recipe, full):
    """Each mirror plane of RECIPE_SYMMETRY maps every strip onto one of its family with the same
    P0; a plane it leaves out maps some strip onto one with another P0."""
    strips, c = full.info["strips"], full.info["centre"]
    key = lambda s, mid: (s["layer"], s["direction"], tuple(np.round(mid, 6)))  # noqa: E731
    where = {key(s, s["midpoint"]): k for k, s in strips.items()}
    valid = {"quarter": (0, 1), "half_x": (0,), "half_y": (1,)}[RECIPE_SYMMETRY[recipe]]
    for axis in (0, 1):
        same = []
        for s in strips.values():
            mid = list(s["midpoint"])
            mid[axis] = 2 * c - mid[axis]
            image = strips[where[key(s, mid)]]
            same.append(_p0(recipe, s, c) == _p0(recipe, image, c))
        assert all(same) if axis in valid else not all(same), (recipe, axis)


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(cells=0), "cells"),
        (dict(cells=2.0), "cells"),
        (dict(mesh=GridshellFEMesh(level=-1)), "mesh.level"),
        (dict(mesh=GridshellFEMesh(size=0.0)), "mesh.size"),
        (dict(symmetry="eighth"), "symmetry"),
        (dict(lambda_N=0.5), "lambda_N"),
        (dict(geometry=CompositeBeamGeometry(junction_length=8.0)), "geometry.junction_length"),
        (dict(geometry=CompositeBeamGeometry(strip_width=9.0)), "geometry.strip_width"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    args = dict(geometry=G, lambda_N=LAMBDA_N, mesh=LEVEL0, cells=1, symmetry="full")
    args.update(kwargs)
    with pytest.raises(InputError) as err:
        build_gridshell_fe(**args)
    message = str(err.value)
    assert message.startswith(field) and "\n" not in message


_TWO_RANKS = """
import json, sys
import dolfinx_solver  # noqa: F401
import dolfinx, ufl
from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.gridshell_fe import GridshellFEMesh, build_gridshell_fe, cell_group
tm = build_gridshell_fe(CompositeBeamGeometry(), 1.4, GridshellFEMesh(level=0), symmetry="quarter")
dx = ufl.Measure("dx", domain=tm.mesh, subdomain_data=tm.cell_tags)
ds = ufl.Measure("ds", domain=tm.mesh, subdomain_data=tm.facet_tags)
out = {g: dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * dx(cell_group(tm, g))))
       for g in ("kapton", "glue", "bottom_strips", "top_strips", "XD2", "Ty")}
out.update({f: dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * ds(t)))
            for f, t in tm.facets.items()})
out = {k: tm.mesh.comm.allreduce(v) for k, v in out.items()}
if tm.mesh.comm.rank == 0:
    json.dump({"values": out, "ranks": tm.mesh.comm.size}, open(sys.argv[1], "w"))
"""


@pytest.mark.mpi
def test_two_ranks_give_the_serial_mesh(tmp_path, serial_and_two_ranks):
    """Made on rank 0 and distributed: the same tags (by name) and volumes/areas on 2 ranks."""
    script = tmp_path / "two_ranks.py"
    script.write_text(_TWO_RANKS)
    runs = serial_and_two_ranks([sys.executable, script, "{out}"], timeout=300)
    results = {r.ranks: json.loads(r.out.read_text()) for r in runs}
    assert results[2]["ranks"] == 2
    serial, parallel = results[1]["values"], results[2]["values"]
    assert set(serial) == set(parallel) and {"sym_x", "centre_junction"} <= set(serial)
    for key, value in serial.items():
        assert parallel[key] == pytest.approx(value, rel=1e-12), key
