"""``[[contact]]`` of ``lcefem run body``: penalty contact between two named facet sets.

A block pressed on another by a dead force F, both on frictionless mirror planes (x = 0, y = 0)
and the lower one on a roller (z = 0): the stress is uniaxial and uniform, so every node pair of
the contact carries the same gap and the penalty's nodal forces k A_i <-g>_+ are the consistent
nodal forces of a uniform pressure. Closed forms: contact force = F (equilibrium) and penetration
-g = F / (k A) at every pair (A the contact's reference area). The upper block starts 1 um into the
lower one, so the contact holds it from the first Newton iteration (nothing else does).

Bad input: unknown boundary, a boundary paired with itself, a bad penalty: one line naming the
entry, before any mesh is built.
"""

import numpy as np
import pytest

#: Two 1 mm cubes, the upper overlapping the lower by 0.001 mm, meshed separately (no fragment: the
#: faces in contact keep their own nodes) with the same 2 x 2 hexahedra in x and y.
BLOCKS = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {0, 0, 0.999, 1, 1, 1};
Transfinite Curve{:} = 3;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Recombine Volume{:};
Physical Volume("lower", 1) = {1};
Physical Volume("upper", 2) = {2};
Physical Surface("x0", 1) = {1, 7};
Physical Surface("y0", 2) = {3, 9};
Physical Surface("bottom", 3) = {5};
Physical Surface("lower_top", 4) = {6};
Physical Surface("upper_bottom", 5) = {11};
Physical Surface("top", 6) = {12};
Physical Surface("sides", 7) = {2, 4, 8, 10};
"""

CASE = """
[mesh]
file = "blocks.geo"
[[regions]]
name = ["lower", "upper"]
material = "neo-hookean"
E = 10.0
nu = 0.3
[[supports]]
type = "mirror"
boundary = "x0"
normal = "x"
[[supports]]
type = "mirror"
boundary = "y0"
normal = "y"
[[supports]]
type = "roller"
boundary = "bottom"
normal = "z"
[[loads]]
type = "force"
boundary = "top"
force = [0.0, 0.0, -{force}]
[[contact]]
boundary = "upper_bottom"
target = "lower_top"
axis = "z"
penalty = {penalty}
name = "blocks"
[program]
duration = 1.0
dt = 1.0
[output]
fields = false
"""


def write_case(tmp_path, **values):
    (tmp_path / "blocks.geo").write_text(BLOCKS)
    text = CASE
    for key, value in values.items():
        text = text.replace("{" + key + "}", str(value))
    (tmp_path / "case.toml").write_text(text)
    return tmp_path / "case.toml"


@pytest.mark.parametrize("penalty", [50.0, 200.0])
def test_pressed_block_contact_force_and_penetration(tmp_path, penalty):
    from lcefem.solvers.problems.body import BodyProblem, run_body
    from lcefem.solvers.problems.body_case import load_case

    force = 0.5  # [N] on the 1 mm^2 face: 0.5 MPa, 5 % strain at E = 10 MPa
    case = load_case(write_case(tmp_path, force=force, penalty=penalty))
    h = run_body(case, None, progress=False).history
    np.testing.assert_allclose(h["contact_force blocks [N]"], force, rtol=1e-8)
    np.testing.assert_allclose(h["min_gap blocks [mm]"], -force / (penalty * 1.0), rtol=1e-6)
    np.testing.assert_allclose(h["reaction_z bottom [N]"], force, rtol=1e-8)
    # uniform: every pair has the same gap (the homogeneous state is exact on this mesh)
    problem = BodyProblem(case)
    problem.set_program(0.0)
    problem.equilibrate("pressed blocks")
    gaps = problem.contacts["blocks"].gaps()
    assert gaps.size == 25  # 5 x 5 Q2 nodes of the upper block's bottom face
    np.testing.assert_allclose(gaps, -force / penalty, rtol=1e-6)


def test_default_penalty_is_the_beams():
    from lcefem.solvers.contact import PenaltyContact
    from lcefem.solvers.problems.body_case import SCHEMA

    assert SCHEMA["contact"]["penalty"][2] == PenaltyContact().stiffness


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            'target = "lower_top"',
            'target = "lid"',
            "[[contact]][0].target: 'lid' is not a facet set",
        ),
        (
            'target = "lower_top"',
            'target = "upper_bottom"',
            "[[contact]][0].target: 'upper_bottom' is the boundary itself",
        ),
        (
            'boundary = "upper_bottom"',
            'boundary = "floor"',
            "[[contact]][0].boundary: 'floor' is not a facet set",
        ),
        (
            "penalty = 50.0",
            "penalty = -1.0",
            "[[contact]][0].penalty: -1 N/mm^3: allowed > 0 N/mm^3",
        ),
        ('axis = "z"', 'axis = "w"', "[[contact]][0].axis: 'w': allowed x, y, z"),
        (
            'name = "blocks"',
            'name = "blocks"\nfriction = 0.3',
            "[[contact]][0].friction: unknown key",
        ),
    ],
)
def test_bad_contact_is_one_line_before_any_mesh(tmp_path, monkeypatch, old, new, message):
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems import body_case

    path = write_case(tmp_path, force=0.5, penalty=50.0)
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    # nothing is meshed: the checks read the physical names only
    import lcefem.meshes.reader as reader

    monkeypatch.setattr(reader, "read_tagged_mesh", lambda *a, **k: pytest.fail("a mesh was built"))
    with pytest.raises(InputError) as err:
        body_case.load_case(path)
    text = str(err.value)
    assert "\n" not in text
    assert text.startswith("case.toml: ") and message in text, text


def test_facing_pairs_are_the_beams_strip_ribbon_pairs():
    """On the FE composite beam (level 0), the general pairing of two named facet sets gives the
    beam's own strip-ribbon pairs and areas (:func:`face_pairs`), top and bottom: the body's
    [[contact]] is the beam's contact."""
    from lcefem.meshes.composite_beam import CompositeBeamGeometry
    from lcefem.meshes.composite_beam_fe import BeamFEMesh, build_beam_fe
    from lcefem.solvers.contact import face_pairs, facing_pairs
    from lcefem.solvers.mechanics import displacement_space

    tm = build_beam_fe(CompositeBeamGeometry(), 1.4, BeamFEMesh(level=0))
    V = displacement_space(tm.mesh, 2)
    for face, target, above in (
        ("top_strip_underside", "ribbon_top", True),
        ("bottom_strip_topside", "ribbon_bottom", False),
    ):
        pairs, areas = face_pairs(tm, V, face, "kapton", strip_above=above)
        general, general_areas = facing_pairs(tm, V, face, target, axis=2)
        assert pairs.shape[0] > 50
        assert np.array_equal(general, pairs), face
        np.testing.assert_array_equal(general_areas, areas)
