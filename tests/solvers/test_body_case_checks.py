"""solvers/problems/body_case.py's checks of regions, coils, heat exchange, supports, loads and
probes: each bad entry is one InputError line naming the file, the entry and what is allowed (the
command line turns it into exit 2 before any mesh is built: tests/validation/test_body_cli.py).
Only the mesh file's names are read here (gmsh parses the .geo, no mesh is built)."""

import pytest

from tests.solvers.test_body import BLOCK

GOOD = """
[mesh]
file = "block.geo"
[[regions]]
name = "block"
material = "lce"
director = [1.0, 0.0, 0.0]
[[coils]]
name = "heater"
region = "block"
[[heat]]
boundary = "x1"
type = "convection"
[[heat]]
boundary = "x1"
type = "radiation"
[[heat]]
boundary = "x0"
type = "fixed"
temperature = 30.0
[[supports]]
type = "roller"
boundary = "x0"
normal = "x"
[[supports]]
type = "point"
point = [0.0, 0.0, 0.0]
components = ["y", "z"]
[[supports]]
type = "point"
point = [0.0, 1.0, 0.0]
components = ["z"]
[[loads]]
type = "force"
boundary = "x1"
force = [0.001, 0.0, 0.0]
[[probes]]
name = "end"
boundary = "x1"
"""


def check(tmp_path, text):
    from lcefem.solvers.problems.body_case import load_case

    (tmp_path / "block.geo").write_text(BLOCK)
    (tmp_path / "case.toml").write_text(text)
    return load_case(tmp_path / "case.toml")


def test_the_good_case_passes(tmp_path):
    case = check(tmp_path, GOOD)
    assert [s["type"] for s in case.supports] == ["roller", "point", "point"]
    assert case.heat[2]["name"] == "x0"  # a fixed temperature's drive tag: its boundaries' names
    assert case.loads[0]["name"] == "force0"


@pytest.mark.parametrize(
    "old, new, message",
    [
        # regions
        (
            'name = "block"\nmaterial = "lce"\ndirector = [1.0, 0.0, 0.0]',
            'name = "block"\nmaterial = "lce"\ndirector = [1.0, 0.0, 0.0]\n[[regions]]\nname = '
            '"block"\nmaterial = "glue"',
            "[[regions]][1].name: 'block' already has a material (one region per cell set)",
        ),
        (
            'director = [1.0, 0.0, 0.0]',
            'director = [1.0, 0.0, 0.0]\nE = 5.0',
            "[[regions]][0].E: only for a passive material",
        ),
        (
            'director = [1.0, 0.0, 0.0]',
            '',
            "[[regions]][0]: an LCE region needs exactly one of director",
        ),
        (
            'material = "lce"\ndirector = [1.0, 0.0, 0.0]',
            'material = "neo-hookean"\nE = 1.0',
            "[[regions]][0]: a neo-hookean region needs E [MPa] and nu [-]",
        ),
        (
            'material = "lce"\ndirector = [1.0, 0.0, 0.0]',
            'material = "kapton"\ntwist = { axis = "z", from_deg = 0, to_deg = 9 }',
            "[[regions]][0].twist: only for material = 'lce' (this region is 'kapton')",
        ),
        (
            'material = "lce"\ndirector = [1.0, 0.0, 0.0]',
            'material = "glue"\ndirector_expression = ["1", "0", "0"]',
            "[[regions]][0].director_expression: only for material = 'lce' (this region is 'glue')",
        ),
        (
            'director = [1.0, 0.0, 0.0]',
            'twist = { axis = "w", from_deg = 0, to_deg = 9 }',
            "[[regions]][0].twist: allowed {axis = 'x'|'y'|'z', from_deg = number, to_deg = "
            "number}",
        ),
        (
            'director = [1.0, 0.0, 0.0]',
            'director = [1.0, 0.0, 0.0]\nconductivity = -1.0',
            "[[regions]][0].conductivity: -1 mW/(mm K): allowed > 0 mW/(mm K)",
        ),
        # coils
        (
            'region = "block"',
            'region = "block"\n[[coils]]\nname = "heater"\nregion = "block"',
            "[[coils]][1].name: 'heater' is used twice",
        ),
        # heat exchange
        (
            'type = "radiation"',
            'type = "convection"',
            "[[heat]][1].boundary: 'x1' has a convection entry already",
        ),
        (
            'boundary = "x0"\ntype = "fixed"',
            'boundary = "x1"\ntype = "fixed"',
            "[[heat]][2].boundary: 'x1': a fixed temperature excludes convection and radiation",
        ),
        (
            'type = "radiation"',
            'type = "radiation"\nT_inf = 30.0',
            "[[heat]][1].T_inf: 'x1': convection and radiation need one T_inf",
        ),
        (
            'type = "fixed"\ntemperature = 30.0',
            'type = "fixed"',
            "[[heat]][2].temperature: missing: a fixed temperature [C]",
        ),
        (
            'type = "radiation"',
            'type = "radiation"\ntemperature = 30.0',
            "[[heat]][1]: name and temperature are keys of a fixed temperature only",
        ),
        (
            'boundary = "x1"\ntype = "convection"',
            'boundary = "top"\ntype = "convection"',
            "[[heat]][0].boundary: 'top' is not a facet set of block.geo",
        ),
        # supports
        (
            'type = "roller"\nboundary = "x0"\nnormal = "x"',
            'type = "clamp"',
            "[[supports]][0].boundary: missing: a clamp acts on a facet set",
        ),
        (
            'type = "roller"\nboundary = "x0"\nnormal = "x"',
            'type = "mirror"\nboundary = "x0"',
            "[[supports]][0].normal: missing: the component a mirror fixes ('x', 'y' or 'z')",
        ),
        (
            'normal = "x"',
            'normal = "x"\n[[supports]]\ntype = "mirror"\nboundary = "x0"\nnormal = "x"',
            "[[supports]][1]: boundary 'x0': component x is constrained twice; allowed one "
            "support per component",
        ),
        (
            'components = ["y", "z"]',
            'components = ["y", "y"]',
            "[[supports]][1].components: ['y', 'y']: allowed a list of distinct 'x', 'y', 'z'",
        ),
        (
            'type = "point"\npoint = [0.0, 0.0, 0.0]\ncomponents = ["y", "z"]',
            'type = "3-2-1"\npoints = [[0.0, 0.0, 0.0]]',
            "[[supports]][1].points: allowed three points [[x, y, z], [x, y, z], [x, y, z]]",
        ),
        (
            'type = "point"\npoint = [0.0, 0.0, 0.0]',
            'type = "point"',
            "[[supports]][1].point: missing: [x, y, z] mm",
        ),
        # loads
        ('force = [0.001, 0.0, 0.0]', 'pressure = 0.1', "[[loads]][0].force: missing"),
        (
            'type = "force"\nboundary = "x1"',
            'type = "pressure"',
            "[[loads]][0].boundary: missing: a pressure acts on a facet set",
        ),
        (
            'force = [0.001, 0.0, 0.0]',
            'force = [0.001, 0.0]',
            "[[loads]][0].force: [0.001, 0.0]: allowed a list of three numbers",
        ),
        (
            'type = "force"',
            'type = "torque"',
            "[[loads]][0].type: 'torque': allowed force, pressure, gravity",
        ),
        # probes
        (
            'name = "end"\nboundary = "x1"',
            'name = "end"\nboundary = "x1"\npoint = [4.0, 0.5, 0.5]',
            "[[probes]][0]: a probe needs exactly one of boundary or point",
        ),
    ],
    ids=[
        "region-twice",
        "E-on-lce",
        "no-director",
        "neo-hookean-without-nu",
        "twist-on-passive",
        "expression-on-passive",
        "twist-axis",
        "negative-conductivity",
        "coil-twice",
        "convection-twice",
        "fixed-with-convection",
        "two-ambients",
        "fixed-without-temperature",
        "temperature-on-radiation",
        "heat-boundary-not-in-mesh",
        "clamp-without-boundary",
        "mirror-without-normal",
        "mirror-on-roller",
        "point-components",
        "321-two-points-short",
        "point-without-point",
        "force-missing",
        "pressure-without-boundary",
        "force-two-components",
        "unknown-load",
        "probe-both",
    ],
)
def test_bad_entries_are_one_line(tmp_path, old, new, message):
    from lcefem.models.errors import InputError

    assert old in GOOD
    with pytest.raises(InputError) as info:
        check(tmp_path, GOOD.replace(old, new, 1))
    text = str(info.value)
    assert text.startswith("case.toml: ") and message in text, text
    assert "\n" not in text
