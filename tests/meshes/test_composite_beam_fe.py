"""The FE composite beam's mesh: body volumes (closed forms), bonded and free faces, stations."""

import math

import dolfinx_solver  # noqa: F401

import pytest
import ufl

import dolfinx

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.composite_beam_fe import FE_CELLS, BeamFEMesh, build_beam_fe, fe_stations
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError

G = CompositeBeamGeometry()
LAMBDA_N = PUBLISHED_LAMBDA_N


@pytest.fixture(scope="module")
def quarter():
    return build_beam_fe(G, LAMBDA_N, BeamFEMesh(level=0))


def _volumes(tm):
    dx = ufl.Measure("dx", domain=tm.mesh, subdomain_data=tm.cell_tags)
    return {
        n: dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * dx(t))) for n, t in tm.cells.items()
    }


def _area(tm, name):
    ds = ufl.Measure("ds", domain=tm.mesh, subdomain_data=tm.facet_tags)
    return dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * ds(tm.facet_tag(name))))


def test_body_volumes_quarter(quarter):
    """Quarter x >= 141/2, y <= 3.5: ribbon 74 mm long (half junction, 2 segments, junction, tab);
    strips of the as-built section (5 x 2 mm cast)/sqrt(lambda_N), half width."""
    v = _volumes(quarter)
    assert set(v) == set(FE_CELLS)
    half_section = 0.5 * 5.0 * 2.0 / LAMBDA_N
    assert v["kapton"] == pytest.approx((3.5 + 30 + 7 + 30 + 3.5) * 3.5 * 0.127, rel=1e-10)
    assert v["bottom_strips"] == pytest.approx(2 * 30.0 * half_section, rel=1e-10)
    assert v["bottom_pads"] == pytest.approx((3.5 + 7.0 + 3.5) * half_section, rel=1e-10)
    assert v["top_strips"] == pytest.approx((15.0 + 30.0) * half_section, rel=1e-10)
    assert v["top_pads"] == pytest.approx(2 * 7.0 * half_section, rel=1e-10)


def test_half_model_is_twice_the_quarter(quarter):
    half = build_beam_fe(G, LAMBDA_N, BeamFEMesh(level=0, symmetry="half"))
    vq, vh = _volumes(quarter), _volumes(half)
    for name in FE_CELLS:
        assert vh[name] == pytest.approx(2 * vq[name], rel=1e-10)
    assert "sym_x" not in half.facets and "sym_x" in quarter.facets


def test_bonds_only_on_the_pads(quarter):
    """The strips' free faces cover exactly their unbonded length: the bottom strips' tops over the
    segments, the top strips' undersides between crown edges; the ribbon's free top face is its
    whole top minus the crown pads (the arch adds (pi gap/L)^2/4 ~ 0.35 % of length)."""
    w = quarter.info["strip_width"] / 2
    assert _area(quarter, "bottom_strip_topside") == pytest.approx(2 * 30.0 * w, rel=1e-10)
    assert _area(quarter, "top_strip_underside") == pytest.approx(45.0 * w, rel=1e-10)
    arch = 1.0 + (math.pi * G.arch_gap / G.segment_length) ** 2 / 4
    top = 74.0 * 3.5 + 60.0 * 3.5 * (arch - 1.0) - 2 * 7.0 * w
    assert _area(quarter, "ribbon_top") == pytest.approx(top, rel=2e-3)


def test_free_faces_do_not_share_nodes_with_the_ribbon_away_from_bond_edges(quarter):
    """A strip's free face touches the ribbon only along the bond edges (segment ends for the
    bottom strips, crown edges for the top strips)."""
    tm = quarter
    mesh = tm.mesh
    mesh.topology.create_connectivity(2, 0)
    mesh.topology.create_connectivity(3, 0)
    ribbon_vertices = set(
        dolfinx.mesh.compute_incident_entities(
            mesh.topology, tm.cell_tags.find(tm.cell_tag("kapton")), 3, 0
        )
    )
    x = mesh.geometry.x
    g = G
    seg_ends = [g.segment_start(s) + e for s in range(g.segments) for e in (0.0, g.segment_length)]
    crown_edges = [g.segment_start(s) + e for s in range(g.segments) for e in g.crown_edges]
    for face, edges in (("bottom_strip_topside", seg_ends), ("top_strip_underside", crown_edges)):
        verts = dolfinx.mesh.compute_incident_entities(
            mesh.topology, tm.facet_tags.find(tm.facet_tag(face)), 2, 0
        )
        shared = [v for v in verts if v in ribbon_vertices]
        assert shared, face
        # vertex indices equal geometry indices for this linear mesh built in serial
        assert all(min(abs(x[v, 0] - e) for e in edges) < 1e-9 for v in shared), face


def test_stations_and_levels():
    pts = fe_stations(G)
    assert len(pts) == G.segments + 1
    assert pts[1] == [(30.0, 0.0, 0.0), (37.0, 0.0, 0.0)]
    c0 = build_beam_fe(G, LAMBDA_N, BeamFEMesh(level=0)).info["cells"]
    c1 = build_beam_fe(G, LAMBDA_N, BeamFEMesh(level=1)).info["cells"]
    assert c1 == 4 * c0  # in-plane refinement only


@pytest.mark.parametrize(
    "geometry, mesh",
    [
        (G, BeamFEMesh(symmetry="full")),
        (G, BeamFEMesh(size=-1.0)),
        (CompositeBeamGeometry(strip_width=9.0), BeamFEMesh()),
    ],
)
def test_bad_input(geometry, mesh):
    with pytest.raises(InputError):
        build_beam_fe(geometry, LAMBDA_N, mesh)
