"""The gridshell layout (lcefem.meshes.gridshell_layout) and the bar-and-hinge structure built from
it: the published 3 x 3 unchanged, the rhombic grid the orthogonal one's affine image, the loader's
one-line errors."""

import hashlib
import json
import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from lcefem.meshes.composite_beam import BeamBarHingeMesh
from lcefem.meshes.gridshell import (
    build_gridshell_bar_hinge,
    diagonal_mirror,
    select_strips,
    unmatched_mirror_rows,
)
from lcefem.meshes.gridshell_layout import NAMED_LAYOUTS, Layout, layout_from_table
from lcefem.models.errors import InputError


def digest(s) -> str:
    """sha256 of every array of a structure (nodes, panels, bar/hinge/contact groups and rests, node
    sets) and its sections."""
    h = hashlib.sha256()

    def add(name, a):
        a = np.ascontiguousarray(np.asarray(a))
        h.update(name.encode())
        h.update(str(a.dtype).encode())
        h.update(str(a.shape).encode())
        h.update(a.tobytes())

    add("nodes", s.nodes)
    add("panels", s.panels)
    add("panel_centres", s.panel_centres)
    add("panel_bars", s.panel_bars)
    for d in ("bars", "hinges", "hinge_rest", "node_sets", "contacts", "contact_rest"):
        for k in sorted(getattr(s, d)):
            add(f"{d}.{k}", getattr(s, d)[k])
    h.update(json.dumps(dict(sorted(s.sections.items())), sort_keys=True).encode())
    return h.hexdigest()[:16]


# Digests of the structures the builder gave before the layout existed (commit 029ea8c, the
# GridshellLayout(ribbons) builder): default mesh, the published configuration's glue squares
# without contact, the refined 5 x 5 and the 1 x 1.
BEFORE = {
    "default": "36c829495157ad59",
    "glue": "384d06b64e3e72ac",
    "5x5": "fe365d99ca6af350",
    "1x1": "a97515773f3b8d57",
}


def test_published_layout_reproduces_todays_structure():
    glue = BeamBarHingeMesh(top_junction="glue", contact=False)
    assert digest(build_gridshell_bar_hinge(layout=Layout.published())) == BEFORE["default"]
    assert digest(build_gridshell_bar_hinge(layout=Layout.published(), mesh=glue)) == BEFORE["glue"]
    assert digest(build_gridshell_bar_hinge(layout=NAMED_LAYOUTS["5x5"])) == BEFORE["5x5"]
    assert digest(build_gridshell_bar_hinge(layout=Layout(ribbons=1))) == BEFORE["1x1"]
    # the same through the [layout] loader: explicit published lengths change nothing
    table = {
        "pitch": 37.0,
        "ribbon_width": 7.0,
        "ribbon_thickness": 0.127,
        "strip_width": 5.0,
        "strip_thickness": 2.0,
        "wiring": "channels",
        "glued": "all",
    }
    assert digest(build_gridshell_bar_hinge(layout=layout_from_table(table))) == BEFORE["default"]


def test_rhombic_is_the_affine_image_of_the_orthogonal_grid():
    """With skewed free panels (mesh.free_panels = 'skewed'): same topology; nodes x e1 + y e2 (e2
    at 60 deg); ribbons keep their width d across themselves (builder width d/sin a along the
    other family) and the pitch along themselves."""
    lay = NAMED_LAYOUTS["rhombic60"]
    r = build_gridshell_bar_hinge(layout=lay, mesh=BeamBarHingeMesh(free_panels="skewed"))
    a = math.radians(60.0)
    width = 7.0 / math.sin(a)
    o = build_gridshell_bar_hinge(layout=Layout(ribbon_width=width, pitch=37.0))
    for name in ("bottom_strips", "top_strips", "kapton"):
        assert np.array_equal(r.bars[name], o.bars[name])
    assert np.array_equal(r.panels, o.panels)
    mapped = o.nodes[:, :2] @ np.array([[1.0, 0.0], [math.cos(a), math.sin(a)]])
    assert np.allclose(r.nodes[:, :2], mapped, atol=1e-9)
    assert np.allclose(r.nodes[:, 2], o.nodes[:, 2])
    # junction centres 37 mm apart along each family; a ribbon 7 mm wide across itself
    jc = r.nodes[r.node_sets["junction_corners"]].mean(axis=2)
    assert np.linalg.norm(jc[1, 0] - jc[0, 0]) == pytest.approx(37.0)
    assert np.linalg.norm(jc[0, 1] - jc[0, 0]) == pytest.approx(37.0)
    ends = r.nodes[r.node_sets["ribbon_ends_x"][0, 0]]  # ribbon 0's low end, sides 0 and 1
    assert abs(ends[1, 1] - ends[0, 1]) == pytest.approx(7.0)  # across e1: y difference


def test_rhombic_free_panels_are_rectangles_across_the_ribbon():
    """Issue 47 (skewed N5B8 panels lock in bending, docs/layouts/rhombic.md): by default a rhombic
    segment's interior cuts run across the ribbon. Every free panel but the first and last of a
    segment is a 7 mm wide rectangle; those two are right trapezoids between the junction's
    rhombus side (d/sin a = 8.083 mm) and a cut 7 mm long, their short side as long as a
    rectangle ((10.959 - 7 cot 60 / 2)/5 = 1.788 mm). Junction corners, topology and the crown
    (7 mm long, centred in the segment) are the skewed mesh's; the orthogonal grid is unchanged
    (its digest) whatever the option."""
    lay = NAMED_LAYOUTS["rhombic60"]
    r = build_gridshell_bar_hinge(layout=lay)
    k = build_gridshell_bar_hinge(layout=lay, mesh=BeamBarHingeMesh(free_panels="skewed"))
    assert r.info["free_panels"] == "rectangular" and k.info["free_panels"] == "skewed"
    assert np.array_equal(r.panels, k.panels)
    for name in r.bars:
        assert np.array_equal(r.bars[name], k.bars[name])
    jc = r.node_sets["junction_corners"]
    assert np.array_equal(r.nodes[jc], k.nodes[jc])
    nf = r.info["flank_panels"]
    per_seg = 2 * nf + 2
    rect_len = (
        (37.0 - 7.0 / math.sin(math.radians(60.0)) - 7.0) / 2 - 3.5 / math.tan(math.radians(60.0))
    ) / nf
    assert rect_len == pytest.approx(1.788, abs=1e-3)
    for first in (per_seg, 2 * per_seg):  # x ribbon 0, segments 1 and 2
        for i, p in enumerate(r.panels[first : first + per_seg - 1]):
            c = r.nodes[p][:, :2]
            e = [c[(m + 1) % 4] - c[m] for m in range(4)]  # 01 along, 12 across, 23, 30
            if i in (0, per_seg - 2):  # the trapezoids: one junction edge, one cut across
                junction, cut = (e[3], e[1]) if i == 0 else (e[1], e[3])
                assert np.linalg.norm(junction) == pytest.approx(7.0 / math.sin(math.radians(60)))
                assert abs(cut[0]) < 1e-9 and np.linalg.norm(cut) == pytest.approx(7.0)
                short = min(np.linalg.norm(e[0]), np.linalg.norm(e[2]))
                assert short == pytest.approx(rect_len)
                continue
            assert abs(e[0] @ e[1]) < 1e-9 and abs(e[1] @ e[2]) < 1e-9
            assert np.linalg.norm(e[1]) == pytest.approx(7.0)
            length = 7.0 if i == nf else rect_len  # the crown panel, then the flanks
            assert np.linalg.norm(e[0]) == pytest.approx(length)
    for mesh in (
        BeamBarHingeMesh(free_panels="rectangular"),
        BeamBarHingeMesh(free_panels="skewed"),
    ):
        assert (
            digest(build_gridshell_bar_hinge(layout=Layout.published(), mesh=mesh))
            == (BEFORE["default"])
        )
    with pytest.raises(InputError, match="mesh.free_panels = 'square': allowed 'auto'"):
        build_gridshell_bar_hinge(layout=lay, mesh=BeamBarHingeMesh(free_panels="square"))


def test_rhombic_grid_is_mirror_symmetric_about_its_diagonals():
    lay = NAMED_LAYOUTS["rhombic60"]
    s = build_gridshell_bar_hinge(layout=lay)
    e1, e2 = lay.directions()
    c = s.nodes[s.node_sets["centre_junction"]].mean(axis=0)
    for axis in (e1 + e2, e1 - e2):
        u = np.array([*axis, 0.0]) / np.linalg.norm(axis)
        y = s.nodes - c
        flat = y * [1, 1, 0]
        m = 2 * np.outer(flat @ u, u) - flat + y * [0, 0, 1] + c
        d, _ = cKDTree(s.nodes).query(m)
        assert d.max() < 1e-9


def test_unbonded_junctions_and_wiring():
    s = build_gridshell_bar_hinge(layout=Layout(glued=((0, 0), (1, 1), (2, 2))))
    full = build_gridshell_bar_hinge()
    # 6 unbonded junctions: each keeps a second Kapton square (4 more corners, 1 more panel)
    assert s.panels.shape[0] == full.panels.shape[0] + 6
    assert s.num_nodes == full.num_nodes + 6 * (4 + 1)
    w = build_gridshell_bar_hinge(layout=Layout(wiring=(("edge", ("XD1", "YD1")), ("top", ("T",)))))
    assert w.info["wiring"] == ("edge", "top")
    assert set(select_strips(w, "edge").tolist()) == set(select_strips(w, "XD1").tolist()) | set(
        select_strips(w, "YD1").tolist()
    )
    assert len(select_strips(w, "top")) == 18
    assert build_gridshell_bar_hinge(layout=Layout(wiring="strips")).info["wiring"] == tuple(
        range(42)
    )


@pytest.mark.parametrize(
    "table, message",
    [
        (
            {"kind": "hex"},
            "layout.kind = 'hex': allowed orthogonal, rhombic, triangular, hexagonal",
        ),
        ({"ribbons": 0}, "layout.ribbons = 0: must be >= 1"),
        ({"angle": 20.0}, "layout.angle = 20.0: must be >= 30.0 deg"),
        ({"colour": 1}, "unknown key 'layout.colour'"),
        ({"preset": "square"}, "layout.preset = 'square': allowed published"),
        ({"glued": [[0, 5]]}, "layout.glued: (0, 5): a junction [i_x, i_y], each 0..2"),
        ({"wiring": "pairs"}, "layout.wiring = 'pairs': allowed channels, ribbons, strips"),
        ({"wiring": {"A": []}}, "layout.wiring: ('A', ()): a tag and a non-empty list"),
        ({"support": "glue"}, "layout.support = 'glue': allowed"),
        ({"pitch": 12.0}, None),
    ],
)
def test_layout_loader_errors_are_one_line(table, message):
    if message is None:  # pitch too short for the junction and crown: the builder's geometry check
        with pytest.raises(InputError, match="layout.pitch = 12.0 mm: must exceed"):
            build_gridshell_bar_hinge(layout=layout_from_table(table))
        return
    with pytest.raises(InputError) as err:
        layout_from_table(table)
    assert message in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("name", sorted(NAMED_LAYOUTS))
def test_every_named_layout_has_a_plan(name):
    """Junction centres and ribbon centre lines of every kind (the docs' pictures): triangular has
    three families (three line directions), hexagonal junctions of three pieces."""
    plan = NAMED_LAYOUTS[name].plan()
    lines = plan["lines"]
    dirs = lines[:, 1] - lines[:, 0]
    angles = {round(math.degrees(math.atan2(d[1], d[0])) % 180.0, 6) for d in dirs}
    kind = NAMED_LAYOUTS[name].kind
    expected = {"orthogonal": 2, "rhombic": 2, "triangular": 3, "hexagonal": 3}[kind]
    assert len(angles) == expected
    assert plan["junctions"].shape[1] == 2


@pytest.mark.parametrize("strip_element", ["bar", "beam"])
def test_rhombic_element_sets_map_onto_themselves_under_both_diagonal_mirrors(strip_element):
    """Issue 47: every bar, hinge, panel and contact row of the rhombic structure has its mirror
    image about both diagonals in its group, the strips' contact quads split along both diagonals
    (mesh.contact_diagonals 'auto'). Split along one (the published structure's), every strip
    contact row misses its image: a mirror maps an x ribbon's diagonal onto the other diagonal of
    a y ribbon's strip (measured: the BH lost the grid's x = y from t ~ 0.2 of the dome's ramp)."""
    lay = NAMED_LAYOUTS["rhombic60"]
    s = build_gridshell_bar_hinge(layout=lay, mesh=BeamBarHingeMesh(strip_element=strip_element))
    one = build_gridshell_bar_hinge(
        layout=lay, mesh=BeamBarHingeMesh(strip_element=strip_element, contact_diagonals="one")
    )
    assert (
        s.contacts["bottom_strip_contact"].shape[0]
        == 2 * one.contacts["bottom_strip_contact"].shape[0]
    )
    for which in ("diag", "anti"):
        perm = diagonal_mirror(s, which)
        bad = unmatched_mirror_rows(s, perm)
        assert not any(bad.values()), bad
        # the clamp (centre junction) and the drive (Bx <-> By, Tx <-> Ty) map too
        centre = s.node_sets["centre_junction"]
        assert set(perm[centre].tolist()) == set(centre.tolist())
        for group, (a, b) in (("bottom_strips", ("Bx", "By")), ("top_strips", ("Tx", "Ty"))):
            bars = s.bars[group]
            row = {frozenset(r): i for i, r in enumerate(bars.tolist())}
            image = np.array([row[frozenset(r)] for r in perm[bars].tolist()])
            sob, groups = s.info["strip_of_bar"][group], s.info["groups"]
            assert np.all(np.isin(sob[image[np.isin(sob, groups[a])]], groups[b]))
        bad = unmatched_mirror_rows(one, diagonal_mirror(one, which))
        for name in ("contacts.bottom_strip_contact", "contacts.top_strip_contact"):
            assert bad[name] == one.contacts[name.split(".")[1]].shape[0]
