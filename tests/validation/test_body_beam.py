"""`lcefem run body` on examples/bodies/composite_beam/ (the composite beam as a case file:
prescribed stretches per LCE cell set reached by the path follower, strip-ribbon [[contact]], the
[[curvature]] of the middle stations) reproduces `lcefem run beam --model fe` (the default ramp to
lambda_T = 1.33, lambda_B = 1.05) at mesh level 0, on the mesh `lcefem mesh beam --format msh
--mesh-level 0` writes."""

import csv
import shutil

import numpy as np
import pytest

from tests.conftest import REPO

BEAM = REPO / "examples" / "bodies" / "composite_beam"


def read_history(path):
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def level0_case(folder):
    """The example's case file beside the level-0 beam mesh (as `lcefem mesh beam --mesh-level
    0`)."""
    from lcefem.meshes.io import write_mesh
    from lcefem.validation.app.mesh import MeshRequest, build

    m, _ = build(MeshRequest("beam", "fe", 0, "msh"))
    write_mesh(m, folder, "beam", "msh", {"body": "beam", "model": "fe"})
    shutil.copy(BEAM / "case.toml", folder / "case.toml")
    return folder / "case.toml"


@pytest.mark.slow
def test_beam_instance_equals_the_fe_beam(tmp_path):
    """Every accepted increment of the ramp: the same load factors and Newton iterations, the
    curvature and the smallest strip-ribbon gap within 1e-6 relative, the contact force within 1e-9
    N (measured 2026-12-07 against history.csv, which keeps 10 significant digits: load factors,
    stretches, curvature and gap within 4e-10 relative, the CSV's rounding; in memory, against
    solve_beam_fe with the run's PathControl(), the load factors are equal, the curvature within
    9e-11 relative and the gap within 1e-12; the contact stays open
    on this ramp at level 0, min gap 0.049 mm, so tests/solvers/test_body_contact.py checks that
    the case's contact pairs are the beam's)."""
    from lcefem.meshes.composite_beam_fe import BeamFEMesh
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.solvers.problems.composite_beam_run import BeamFEConfig, run_beam_fe

    b = run_body(load_case(level0_case(tmp_path)), None, progress=False).history
    run_beam_fe(BeamFEConfig(mesh=BeamFEMesh(level=0)), tmp_path / "beam", progress=False)
    s = read_history(tmp_path / "beam" / "history.csv")
    assert b["load factor [-]"][0] == 0.0 and b["curvature beam [1/mm]"][0] == 0.0  # as built
    b = {k: v[1:] for k, v in b.items()}  # the beam records the increments only
    np.testing.assert_allclose(b["load factor [-]"], s["load factor [-]"], rtol=1e-6)
    np.testing.assert_allclose(b["stretch top_strips [-]"], s["lambda_top [-]"], rtol=1e-6)
    np.testing.assert_allclose(b["stretch bottom_strips [-]"], s["lambda_bottom [-]"], rtol=1e-6)
    np.testing.assert_allclose(b["curvature beam [1/mm]"], s["curvature [1/mm]"], rtol=1e-6)
    np.testing.assert_allclose(
        b["contact_force top [N]"] + b["contact_force bottom [N]"],
        s["contact force [N]"],
        rtol=1e-6,
        atol=1e-9,
    )
    np.testing.assert_allclose(
        np.minimum(b["min_gap top [mm]"], b["min_gap bottom [mm]"]), s["min gap [mm]"], rtol=1e-6
    )
    assert np.array_equal(b["newton_iterations [-]"], s["newton iterations [-]"])
    assert s["curvature [1/mm]"][-1] > 0.02  # the beam did bend (towards its bottom strips)


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            "top_strips = 1.33",
            "kapton = 1.33",
            "[program].stretches.kapton: not an LCE cell set; allowed: top_strips",
        ),
        (
            "top_strips = 1.33",
            "top_strips = 1.45",
            "[program].stretches.top_strips: 1.45: allowed >= 1 (isotropic) "
            "and <= the region's lambda_N = 1.4",
        ),
        (
            "[program]\n",
            '[[coils]]\nname = "c"\nregion = "top_pads"\n[program]\ncurrents = { c = 0.1 }\n',
            "[program].stretches: a stretch ramp is quasi-static: no [program] currents (given: c)",
        ),
        (
            "[program]\n",
            "[program]\nsteady = true\n",
            "[program].stretches: a stretch ramp is quasi-static; allowed steady = false",
        ),
        (
            "stretches = { top_strips = 1.33, bottom_strips = 1.05 }",
            "duration = 2.0\n[path]\nmax_step = 0.25",
            "[path]: only with a stretch ramp ([program] stretches)",
        ),
        (
            "[program]\n",
            "[path]\nmax_step = 0.001\n[program]\n",
            "[path]: allowed min_step (0.0001) and first_step (0.01) <= max_step (0.001)",
        ),
        (
            "[program]\n",
            "[path]\ngrowth = 0.5\n[program]\n",
            "[path].growth: 0.5: allowed >= 1 and <= 100",
        ),
        (
            "            [[104.0, 0.0, 0.0], [111.0, 0.0, 0.0]]]",
            "]",
            "[[curvature]][0].stations: allowed a list of three or more stations",
        ),
        (
            "up = [[70.5, 3.5, -0.0635], [70.5, 3.5, 0.0635]]",
            "up = [[70.5, 3.5, 0.0], [70.5, 3.5, 0.0]]",
            "[[curvature]][0].up: the two points coincide",
        ),
        (
            'target = "ribbon_top"',
            'target = "ribbon_middle"',
            "[[contact]][0].target: 'ribbon_middle' is not a facet set",
        ),
        (
            'target = "ribbon_top"',
            'target = "top_strip_underside"',
            "[[contact]][0].target: 'top_strip_underside' is the boundary itself",
        ),
    ],
    ids=[
        "stretch-on-passive",
        "stretch-above-lambda_N",
        "stretch-and-current",
        "stretch-and-steady",
        "path-without-ramp",
        "path-steps",
        "path-growth",
        "two-stations",
        "up-coincident",
        "contact-unknown",
        "contact-itself",
    ],
)
def test_bad_beam_case_one_line_before_any_mesh(tmp_path, old, new, message):
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems.body_case import load_case

    shutil.copy(BEAM / "beam.msh", tmp_path / "beam.msh")
    text = (BEAM / "case.toml").read_text()
    assert old in text
    (tmp_path / "case.toml").write_text(text.replace(old, new, 1))
    with pytest.raises(InputError) as err:
        load_case(tmp_path / "case.toml")
    line = str(err.value)
    assert "\n" not in line and line.startswith("case.toml: ") and message in line, line


def test_bad_contact_exits_2_with_one_line_and_writes_nothing(tmp_path, lcefem_cmd):
    import subprocess

    shutil.copy(BEAM / "beam.msh", tmp_path / "beam.msh")
    text = (
        (BEAM / "case.toml")
        .read_text()
        .replace('target = "ribbon_bottom"', 'target = "bottom_strip_topside"')
    )
    (tmp_path / "case.toml").write_text(text)
    out = tmp_path / "out"
    res = subprocess.run(
        lcefem_cmd + ["run", "body", "--config", str(tmp_path / "case.toml"), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert (
        len(lines) == 1
        and "[[contact]][1].target: 'bottom_strip_topside' is the boundary itself" in lines[0]
    )
    assert not out.exists() or not any(out.iterdir())


def test_a_stretch_ramp_is_not_compared_against_time_nor_converged(tmp_path):
    """[[compare]] (measurements against time) and `lcefem converge --config` (the same recorded
    times at every level) do not apply to a ramp in a load factor: one line each."""
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.validation.app.converge_body import check_refinable

    shutil.copy(BEAM / "beam.msh", tmp_path / "beam.msh")
    text = (BEAM / "case.toml").read_text()
    (tmp_path / "case.toml").write_text(text)
    with pytest.raises(
        InputError, match="a stretch ramp .* records the path follower's own increments"
    ):
        check_refinable(load_case(tmp_path / "case.toml"), 3)
    (tmp_path / "k.csv").write_text("time [s],stretch top_strips [-]\n0,1.4\n1,1.33\n")
    (tmp_path / "case.toml").write_text(
        text.replace(
            "[program]\n",
            '[[compare]]\nobservable = "stretch '
            'top_strips [-]"\ndata = "k.csv"\ntolerance = "5 %"\nsource = "x"\n'
            "[program]\n",
        )
    )
    with pytest.raises(
        InputError, match=r"\[\[compare\]\]: measurements are compared against time"
    ):
        load_case(tmp_path / "case.toml")
