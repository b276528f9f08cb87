"""The published configuration of the bar-and-hinge gridshell (issue 30): supports per recipe, the
glue squares, the bar force law A f P(p), rest fractions, and the departures as options
(shared/reference/gridshell_recipes.md, Examples2D.m of the published model)."""

import dataclasses

import numpy as np
import pytest

from lcefem.meshes.composite_beam import BeamBarHingeMesh
from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.models import bar_hinge_materials as law
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import OgdenLaw
from lcefem.solvers.bar_hinge import BarHingeModel
from lcefem.solvers.problems import gridshell_bh as g
from lcefem.solvers.problems import gridshell_bh_run as grun
from lcefem.validation.cases.programs import RECIPES, SHAPE_DRIVES

PUBLISHED_MESH, PUBLISHED_LCE, _ = grun.published_configuration(
    BeamBarHingeMesh(), law.LCEStripBars(), "clamp"
)


def _held_points(structure, dofs):
    """{(x, y): axes} of held DOFs at as-built coordinates [mm] (rounded to 0.1 mm)."""
    out = {}
    for d in dofs:
        xy = tuple(np.round(structure.nodes[d // 3, :2], 1))
        out[xy] = out.get(xy, "") + "xyz"[d % 3]
    return out


def test_published_supports_per_recipe():
    s = build_gridshell_bar_hinge(mesh=PUBLISHED_MESH)
    rollers = _held_points(s, g.support_dofs(s, "rollers"))
    # Examples2D.m: z at the outer ribbons' outer-edge end nodes; (30,0) x y, (30,141) x, (111,0) y.
    assert rollers == {
        (30.0, 0.0): "xyz",
        (30.0, 141.0): "xz",
        (111.0, 0.0): "yz",
        (111.0, 141.0): "z",
        (141.0, 30.0): "z",
        (141.0, 111.0): "z",
        (0.0, 30.0): "z",
        (0.0, 111.0): "z",
    }
    clamp = _held_points(s, g.support_dofs(s, "clamp"))
    assert clamp == {
        (67.0, 67.0): "xyz",
        (74.0, 67.0): "xyz",
        (74.0, 74.0): "xyz",
        (67.0, 74.0): "xyz",
    }
    supports = {name: support for name, (_, support) in RECIPES.items()}
    assert supports == {
        "saddle": "clamp",
        "cone": "clamp",
        "twisted": "clamp",
        "wave": "clamp",
        "dustpan": "clamp",
        "dome": "rollers",
        "cylinder": "rollers",
        "table": "rollers",
    }


def test_published_structure_has_120_lce_and_54_glue_bars():
    s = build_gridshell_bar_hinge(mesh=PUBLISHED_MESH)
    assert s.bars["bottom_strips"].shape[0] + s.bars["top_strips"].shape[0] == 120  # 24*2 + 18*4
    assert s.bars["glue"].shape[0] == 54  # 9 squares x 6
    assert not s.contacts  # no strip-ribbon contact in the published model
    assert "strip_contact" in s.hinges  # only the weak strip-panel springs (Kc = 1e-5)
    # contracting squares: the square edges are LCE (2 per top strip), no glue
    ours = build_gridshell_bar_hinge(mesh=dataclasses.replace(PUBLISHED_MESH, top_junction="lce"))
    assert ours.bars["top_strips"].shape[0] == 18 * 6 and "glue" not in ours.bars


def test_recipe_rest_fractions():
    s = build_gridshell_bar_hinge(mesh=PUBLISHED_MESH)
    t = g.targets_from_recipe(s, RECIPES["wave"][0])
    mid = {grp: 0.5 * (s.nodes[s.bars[grp][:, 0]] + s.nodes[s.bars[grp][:, 1]]) for grp in t}
    sob = s.info["strip_of_bar"]
    strips = s.info["strips"]
    for grp, values in t.items():
        for f, sid, m in zip(values, sob[grp], mid[grp]):
            st = strips[sid]
            if st.direction == "y":
                assert f == pytest.approx(0.90)
            elif st.layer == "bottom":
                assert f == pytest.approx(0.95 if m[0] < 70.5 else 0.75)
            else:  # XU: 0.75 below x = 70.5, 0.95 above (glue squares carry no LCE)
                assert f == pytest.approx(0.75 if m[0] < 70.5 else 0.95)


def test_published_force_law_is_A_f_P_and_its_sensitivity_is_exact():
    s = build_gridshell_bar_hinge(mesh=PUBLISHED_MESH)
    mats = dataclasses.replace(law.BarHingeMaterials(), lce=PUBLISHED_LCE)
    model = BarHingeModel.from_materials(s, mats)
    ours = BarHingeModel.from_materials(s, law.BarHingeMaterials())
    f = 0.75
    for m in (model, ours):
        m.set_rest_fractions({"bottom_strips": f, "top_strips": f})
    x = s.nodes.copy()
    p = 1.0 / f  # as built, every strip is stretched by 1/f from its rest length
    _, dw, _ = law.tension_only_ogden_law(np.array([p]), OgdenLaw())
    area = 5.0  # mm^2 per bar: half the 5 x 2 mm section (published: A = wa ta / 2)
    assert model.bar_forces(x)["bottom_strips"][0] == pytest.approx(area * f * dw[0], rel=1e-12)
    # ours: (A/lambda) P(p), lambda = 1.4 f: ratio 1/(1.4 f^2) = 1.27 at f = 0.75
    ratio = ours.bar_forces(x)["bottom_strips"][0] / model.bar_forces(x)["bottom_strips"][0]
    assert ratio == pytest.approx(1.0 / (1.4 * f * f), rel=1e-12)
    # d(gradient)/df against a central difference of the gradient
    rng = np.random.default_rng(1)
    xp = x + 0.05 * rng.standard_normal(x.shape)
    sens = model.rest_fraction_sensitivity(xp)["bottom_strips"]
    h = 1e-6
    base = model.rest_fractions()
    for b in (0, 7):
        grads = []
        for sign in (1, -1):
            fr = base["bottom_strips"].copy()
            fr[b] += sign * h
            model.set_rest_fractions({"bottom_strips": fr})
            grads.append(model.gradient(xp))
        model.set_rest_fractions(base)
        fd = (grads[0] - grads[1]) / (2 * h)
        dofs, vals = sens[0][b], sens[1][b]
        assert vals == pytest.approx(fd[dofs], rel=1e-6, abs=1e-6 * np.abs(vals).max())


def test_departures_and_configurations():
    mesh, lce, support = grun.published_configuration(
        BeamBarHingeMesh(), law.LCEStripBars(), "rollers", "contact,volume_law,middle_rollers"
    )
    assert (mesh.contact, mesh.top_junction, lce.force_law, support) == (
        True,
        "glue",
        "volume",
        "middle_rollers",
    )
    with pytest.raises(InputError, match="unknown departure"):
        grun.parse_departures("contakt")
    programs = {"shapes": SHAPE_DRIVES, "recipes": RECIPES}
    # the published script: no contact; the published model set (the default) adds the contact
    cfg = grun.GridshellBHRunConfig(
        run=grun.GridshellRun(recipe="cone", configuration="published"), **programs
    )
    assert cfg.support == "clamp" and cfg.run.resolved_departures == ()
    assert (
        cfg.effective[0].contact is False and cfg.effective_materials.lce.force_law == "published"
    )
    shape = grun.GridshellBHRunConfig(run=grun.GridshellRun(shape="dome"), **programs)
    assert shape.effective[0].contact is True and shape.effective[0].top_junction == "glue"
    fe = grun.GridshellBHRunConfig(
        run=grun.GridshellRun(shape="dome", model_set="fe-calibrated"), **programs
    )
    assert fe.effective[0].strip_element == "beam" and fe.effective[1].force_law == "volume"
    with pytest.raises(InputError, match="published model set"):
        grun.GridshellBHRunConfig(
            run=grun.GridshellRun(
                shape="dome", model_set="fe-calibrated", configuration="published"
            ),
            **programs,
        ).validated()
    with pytest.raises(InputError, match=r"run.shape = 'dome': allowed $"):
        grun.GridshellBHRunConfig(
            run=grun.GridshellRun(shape="dome")
        ).validated()  # no programs given


#: Golden values of the published recipes (published configuration; circle and quadratic-fit centre
#: curvatures [1/mm]), measured on 2026-11-28
#: (lcefem.validation.studies.gridshell.gridshell_configuration; the Newton tolerance 1e-6 N gives
#: ~1e-7 1/mm).
GOLDEN = {
    "cone": (-0.02045, -0.001569, -0.0205, -0.001772),
    "twisted": (-0.004112, 6.07e-05, -0.00423, 0.001851),
}


@pytest.mark.parametrize("recipe", sorted(GOLDEN))
def test_published_recipe_golden_values(recipe):
    p0, support = RECIPES[recipe]
    s = build_gridshell_bar_hinge(mesh=PUBLISHED_MESH)
    mats = dataclasses.replace(law.BarHingeMaterials(), lce=PUBLISHED_LCE)
    setup = g.setup_gridshell(g.targets_from_recipe(s, p0), support, structure=s, materials=mats)
    k = g.solve_gridshell(setup).curvatures
    got = (k["circle_x"], k["circle_y"], k["quad_kx"], k["quad_ky"])
    assert got == pytest.approx(GOLDEN[recipe], abs=1e-4)
