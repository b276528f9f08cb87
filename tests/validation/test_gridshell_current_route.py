"""The bar-and-hinge current route in both model sets (validation.gridshell_current_route): the
rule's currents give back the Fig. 4 lambdas through the lumped grid strip, the FE-calibrated set is
the configuration it was fitted in, and at the FE's own channel lambdas it meets the stored level-1
FE (the mechanics alone; docs/gridshell_thermal.md)."""

import pytest

from lcefem.validation.studies.gridshell import gridshell_bh as gs
from lcefem.validation.studies.gridshell import gridshell_current_route as route


@pytest.mark.parametrize("shape", route.SHAPES)
def test_the_rule_gives_back_the_fig4_lambdas(shape):
    # Eq. 1 inverted at the Fig. 4 lambdas, then the calibrated lumped strip: within 0.012 (the
    # strip at the grid coil's power is close to Eq. 1), the top at 1.341, the bottom at 1.053
    currents, lam = route.drive_lambdas(shape, "rule")
    fig4 = gs.SHAPES[shape]["lambdas"]
    assert set(currents) == set(fig4)
    for ch, v in fig4.items():
        assert abs(lam[ch] - v) < 0.012, (ch, lam[ch], v)  # measured 0.0110 top, 0.0027 bottom
    assert route.drive_lambdas(shape, "fig4") == (None, fig4)


def test_fe_calibrated_set_is_the_fitted_configuration():
    # validation.calibrate: strip element 'beam', plate torsion, the fitted factors, in the
    # published configuration + contact + the constant-volume bar law (AS_FE)
    from lcefem.validation.studies.gridshell import calibrate

    record = calibrate.load()
    setup = route.bh_setup("dome", gs.SHAPES["dome"]["lambdas"], "fe-calibrated")
    info, model = setup.structure.info, setup.model
    assert info["strip_element"] == "beam" and info["top_junction"] == "glue"
    assert len(setup.structure.contacts) > 0
    assert model.lce.force_law == "volume" and model.kapton.twist == "plate"
    assert model.lce.bending_factor == record["parameters"]["lce.bending_factor"]
    assert model.kapton.bending_factor == record["parameters"]["kapton.bending_factor"]
    published = route.bh_setup("dome", gs.SHAPES["dome"]["lambdas"], "published")
    assert published.structure.info.get("strip_element", "bar") == "bar"
    assert published.model.kapton.bending_factor == 5.5 and published.model.kapton.twist == "n5b8"


def test_bands_are_drawn_around_the_currents_given():
    """The rule's bands draw the spreads around the rule's currents (BandsConfig.currents), leaving
    the shape's programmed currents untouched; the rule's saddle currents are Eq. 1 inverted at the
    Fig. 4 lambdas (0.0640 A top x, 0.0786 A top y)."""
    from lcefem.models import lumped_heat
    from lcefem.models.errors import InputError
    from lcefem.validation.studies.gridshell import uncertainty as unc

    before = dict(gs.SHAPES["saddle"]["currents"])
    rule = lumped_heat.shape_currents(gs.SHAPES["saddle"]["lambdas"])
    assert rule["Ty"] == pytest.approx(0.0786, abs=1e-4) and rule["Tx"] == pytest.approx(
        0.0640, abs=1e-4
    )
    law = unc.StretchLaw("strip")
    x = unc.nominal_row(unc.gridshell_inputs("saddle"))
    f_rule = unc.rest_fractions_of(x, "saddle", law, rule)[0]
    f_prog = unc.rest_fractions_of(x, "saddle", law)[0]
    lam_n = unc.PUBLISHED_LAMBDA_N
    for k, c in enumerate(
        unc.CHANNELS
    ):  # the nominal row is the steady stretch at the given current
        power = rule[c] ** 2 * law.coil_resistance * 1.0e3
        assert f_rule[k] == pytest.approx(min(law(power), lam_n) / lam_n, rel=1e-9)
    assert (
        not abs(f_rule - f_prog).max() < 1e-6
    )  # the rule's currents differ from the programmed ones
    assert gs.SHAPES["saddle"]["currents"] == before
    with pytest.raises(InputError, match="currents"):
        unc.BandsConfig(shape="saddle", currents={"Tx": 0.05}).checked()
    with pytest.raises(InputError, match=r"currents\[Tx\]"):
        unc.BandsConfig(shape="saddle", currents={**rule, "Tx": -0.01}).checked()


def test_fe_calibrated_bh_at_the_fe_lambdas_meets_the_stored_fe_dome():
    # The stored FE current route (level 1, junctions heated): at its own channel lambdas the
    # FE-calibrated BH is within the 10 % / 0.002 1/mm (measured: -0.0191 vs -0.0190)
    held = route.fe_stored()["dome"]
    k = route.bh_curvatures("dome", route.fe_lambdas(held), "fe-calibrated")
    fe = held["kappa_circle_x [1/mm]"]
    assert abs(k["circle_x"] - fe) <= max(0.1 * abs(fe), 0.002)
    assert k["circle_x"] == pytest.approx(
        k["circle_y"], abs=1e-5
    )  # the dome's symmetry (2.4e-6 apart)
