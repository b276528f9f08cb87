"""The FE gridshell problem (solvers/problems/gridshell.py), quarter model, level 0: zero actuation
keeps the as-built state, drives by channel, group and tag reach exactly their strips, the dome
curves negatively and equally in x and y, the saddle's curvatures have opposite signs."""

import numpy as np
import pytest

from lcefem.models.errors import InputError
from lcefem.solvers.problems.gridshell import (FIG4_SHAPES, GridshellConfig, GridshellFE, PathControl,
                                               fig4_shape)


#: Fraction of the Fig. 4 ramps the tests take (the whole dome ramp takes ~100 path steps, tens of
#: minutes): the signs and the x <-> y symmetry are set from the first steps on.
FRACTION = 0.04
#: Path steps of that partial ramp: the whole ramp's first steps took 0.005-0.011 of it.
PARTIAL = PathControl(first_step=0.15, max_step=0.5)


def part_of(shape: str, lambda_N: float) -> dict:
    """The first FRACTION of the linear ramp from the as-built state to a Fig. 4 shape."""
    return {k: lambda_N + FRACTION * (v - lambda_N) for k, v in FIG4_SHAPES[shape].items()}


@pytest.fixture(scope="module")
def dome():
    return fig4_shape("dome", control=PARTIAL)


def test_zero_actuation_stays_as_built(dome):
    m = dome
    m.set_lambda({"Tx": m.lambda_N, "Ty": m.lambda_N, "Bx": m.lambda_N, "By": m.lambda_N})
    m.advance()
    assert np.max(np.abs(m.u.x.array)) < 1e-10  # [mm]
    obs = m.observables()
    assert abs(obs["kappa_circle_x [1/mm]"]) < 1e-12 and abs(obs["kappa_quad_y [1/mm]"]) < 1e-12


def test_drives_select_their_strips(dome):
    m = dome
    lam_n = m.lambda_N
    m.set_lambda({"Bx": 1.05})
    strips = m.info["strips"]
    for tag, facts in strips.items():
        expected = 1.05 if facts["channel"] == "Bx" else lam_n
        assert m.lambda_of(tag, target=True).tolist() == [expected], tag
    # a group overrides its channel's value on its own strips only; a single tag on its own
    single = next(t for t, f in strips.items() if f["channel"] == "Ty")  # a top y half in the model
    m.set_lambda({"XD3": 1.2, single: 1.1})
    for tag, facts in strips.items():
        if tag == single:
            expected = 1.1
        elif facts["group"] == "XD3":
            expected = 1.2
        else:
            expected = 1.05 if facts["channel"] == "Bx" else lam_n
        assert m.lambda_of(tag, target=True).tolist() == [expected], tag
    # passive bodies keep lambda_N, the current field is untouched until advance()
    assert m.lambda_of("Bx").tolist() == [lam_n]
    for bad in ({"kapton": 1.1}, {"Tz": 1.1}, {"XD1": 1.1}, {"Tx": 0.9}, {"Tx": 1.5}):
        with pytest.raises(InputError):
            m.set_lambda(bad)  # a material, unknown, outside the quarter, below 1, above lambda_N
    m.set_lambda({"Tx": lam_n, "Ty": lam_n, "Bx": lam_n, "By": lam_n})


@pytest.mark.slow
def test_dome_is_a_symmetric_cap(dome, tmp_path):
    m = dome
    m.ramp(part_of("dome", m.lambda_N))
    obs = m.observables()
    kx, ky = obs["kappa_circle_x [1/mm]"], obs["kappa_circle_y [1/mm]"]
    qx, qy = obs["kappa_quad_x [1/mm]"], obs["kappa_quad_y [1/mm]"]
    assert kx < -5e-4 and qx < -5e-4  # [1/mm] a cap (the full ramp: the paper's -0.017 1/mm)
    assert obs["apex_z [mm]"] > 1.0  # the centre rises above the perimeter rollers
    # the recipe and the quarter mesh are symmetric under x <-> y: equal to solver tolerance
    assert abs(kx - ky) < 1e-6 * abs(kx)
    assert abs(qx - qy) < 1e-6 * abs(qx)
    jc = m.junction_centres()
    assert np.allclose(jc[:, :, 2], jc[:, :, 2].T, atol=1e-6)  # [mm]
    # fields: the strips carry stress (MPa, finite) and ParaView files are written
    files = m.write_fields(tmp_path)
    assert all(f.exists() for f in files)
    stress = m.stress.x.array
    assert np.all(np.isfinite(stress)) and 0.01 < stress.max() < 1e3


@pytest.mark.slow
def test_saddle_curvatures_have_opposite_signs():
    m = fig4_shape("saddle", control=PARTIAL)
    m.ramp(part_of("saddle", m.lambda_N))
    obs = m.observables()
    assert obs["kappa_circle_x [1/mm]"] < 0 < obs["kappa_circle_y [1/mm]"]
    assert obs["kappa_quad_x [1/mm]"] < 0 < obs["kappa_quad_y [1/mm]"]
    assert obs["gaussian_quad [1/mm^2]"] < 0


def test_config_errors():
    with pytest.raises(InputError):
        GridshellFE(GridshellConfig(supports=type(GridshellConfig().supports)(kind="table")))
