"""solvers/problems/body.py, per region: a director written as an expression of x, y, z (the
allow-list parser of body_expression.py; equal to the constant director and to the twist option
it can spell), per-region density, specific heat and conductivity (two-layer conduction in series;
the energy balance of an adiabatic two-region block), and radiation against its closed form."""

import subprocess

import numpy as np
import pytest

from tests.solvers.test_body import BLOCK

#: two boxes of 2 x 1 x 1 mm along x sharing the face x = 2 (cell sets a, b), faces named by
#: position
LAYERS = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Box(2) = {2, 0, 0, 2, 1, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.MeshSizeMax = 0.5;
Physical Volume("a", 1) = Volume In BoundingBox{-0.1, -0.1, -0.1, 2.1, 1.1, 1.1};
Physical Volume("b", 2) = Volume In BoundingBox{1.9, -0.1, -0.1, 4.1, 1.1, 1.1};
Physical Surface("x0", 1) = Surface In BoundingBox{-0.1, -0.1, -0.1, 0.1, 1.1, 1.1};
Physical Surface("x1", 2) = Surface In BoundingBox{3.9, -0.1, -0.1, 4.1, 1.1, 1.1};
"""


def run_case(tmp_path, text, geo=BLOCK, name="block.geo"):
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case

    (tmp_path / name).write_text(geo)
    (tmp_path / "case.toml").write_text(text)
    case = load_case(tmp_path / "case.toml")
    return run_body(case, None, progress=False).history


# -- the expression parser ---------------------------------------------------------------------


def test_allowed_expressions_evaluate_as_written():
    from lcefem.solvers.problems.body_expression import check_expression, to_numpy

    pts = np.array([[0.3, -1.2, 2.5], [1.0, 2.0, 0.5]])
    cases = {
        "2": lambda x, y, z: 2.0 + 0 * x,
        "-x + 3*y - z/4": lambda x, y, z: -x + 3 * y - z / 4,
        "x**2 + +y": lambda x, y, z: x**2 + y,
        "sin(pi*z) * cos(y) + tan(x/3) - exp(-z) + sqrt(1 + x*x)": lambda x, y, z: np.sin(np.pi * z)
        * np.cos(y)
        + np.tan(x / 3)
        - np.exp(-z)
        + np.sqrt(1 + x * x),
        "atan2(y, x)": lambda x, y, z: np.arctan2(y, x),
    }
    for text, f in cases.items():
        np.testing.assert_allclose(
            to_numpy(check_expression(text), pts), f(*pts.T), rtol=1e-15, err_msg=text
        )


@pytest.mark.parametrize(
    "text, what",
    [
        ("__import__('os').system('true')", "calling the attribute .system"),
        ("__import__('os')", "calling '__import__'"),
        ("(lambda: 1)()", "calling a Lambda"),
        ("x.real", "a Attribute"),
        ("open", "the name 'open'"),
        ("e", "the name 'e'"),
        ("lambda: 1", "a Lambda"),
        ("[1, 2][0]", "a Subscript"),
        ("x if y else z", "a IfExp"),
        ("'a'", "the constant 'a'"),
        ("True", "the constant True"),
        ("x < y", "a Compare"),
        ("x // 2", "the operator FloorDiv"),
        ("x % 2", "the operator Mod"),
        ("~1", "the operator Invert"),
        ("sin(x=1)", "a keyword argument"),
        ("sin(x, y)", "sin takes 1 argument(s), got 2"),
        ("atan2(y)", "atan2 takes 2 argument(s), got 1"),
        ("x +", "not an expression (SyntaxError)"),
        ("x; y", "not an expression (SyntaxError)"),
        ("", "allowed a non-empty string"),
        ("-" * 600 + "1", "601 characters: allowed at most 500"),
    ],
)
def test_anything_else_is_refused(text, what):
    from lcefem.solvers.problems.body_expression import ExpressionError, check_expression

    with pytest.raises(ExpressionError) as info:
        check_expression(text)
    assert what in str(info.value)
    assert "\n" not in str(info.value)


def expression_case(director_line: str, extra: str = "") -> str:
    """An LCE block (4 x 1 x 1 mm) clamped at x0 with x0 held at 80 C and x1 at 25 C (the steady
    state: a linear temperature, the hot end contracting along the director), its as-built
    state at 25 C; the end x1 probed."""
    return f"""
[mesh]
file = "block.geo"
[[regions]]
name = "block"
material = "lce"
{director_line}
{extra}
[[heat]]
boundary = "x0"
type = "fixed"
temperature = 80.0
[[heat]]
boundary = "x1"
type = "fixed"
temperature = 25.0
[[supports]]
type = "clamp"
boundary = "x0"
[[probes]]
name = "end"
boundary = "x1"
[[probes]]
name = "corner"
point = [4.0, 1.0, 1.0]
[program]
steady = true
"""


def test_bad_expression_is_one_line_exit_2_nothing_written(tmp_path, lcefem_cmd):
    (tmp_path / "block.geo").write_text(BLOCK)
    (tmp_path / "case.toml").write_text(
        expression_case('director_expression = ["cos(z)", "__import__(\'os\')", "0"]')
    )
    out = tmp_path / "out"
    res = subprocess.run(
        lcefem_cmd + ["run", "body", "--config", str(tmp_path / "case.toml"), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith(
        "lcefem: error: case.toml: [[regions]][0].director_expression (y component): "
    )
    assert "calling '__import__' is not allowed; allowed numbers, x, y, z [mm], pi" in lines[0]
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize(
    "extra, message",
    [
        (
            'director = [1.0, 0.0, 0.0]',
            "exactly one of director = [x, y, z], twist = {axis, from_deg, to_deg} "
            "or director_expression",
        ),
        ('', None),
    ],
)
def test_one_director_per_region(tmp_path, extra, message):
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems.body_case import load_case

    (tmp_path / "block.geo").write_text(BLOCK)
    (tmp_path / "case.toml").write_text(
        expression_case('director_expression = ["1", "0", "x"]', extra)
    )
    if message is None:
        assert load_case(tmp_path / "case.toml").regions[0]["director_expression"] == [
            "1",
            "0",
            "x",
        ]
        (tmp_path / "case.toml").write_text(expression_case('director_expression = ["1", "0"]'))
        message = "director_expression: ['1', '0']: allowed a list of three strings"
    with pytest.raises(InputError) as info:
        load_case(tmp_path / "case.toml")
    assert message in str(info.value)


def test_zero_director_somewhere_is_refused(tmp_path):
    """x - 2 vanishes on the block's nodes at x = 2 mm: an InputError naming the place."""
    from lcefem.models.errors import InputError

    with pytest.raises(
        InputError,
        match=r"case.toml: \[\[regions\]\]\[0\].director_expression: the director is "
        r"zero or undefined at \(2, .*\) mm",
    ):
        run_case(tmp_path, expression_case('director_expression = ["x - 2", "0", "0"]'))


def compare(a: dict, b: dict, rtol: float):
    for name in a:
        np.testing.assert_allclose(b[name], a[name], rtol=rtol, atol=1e-13, err_msg=name)


def test_constant_expression_is_the_constant_director(tmp_path):
    """["1", "1", "0"] gives the body of director = [1, 1, 0] (both normalised); the body does
    deform (the hot end contracts along the director: the end moves back in x, sideways in y).
    Measured: equal to the last bit."""
    vector = run_case(tmp_path, expression_case("director = [1.0, 1.0, 0.0]"))
    expression = run_case(tmp_path, expression_case('director_expression = ["1", "1", "0"]'))
    compare(vector, expression, rtol=1e-12)
    assert vector["u_x end [mm]"][-1] < -0.05 and abs(vector["u_y end [mm]"][-1]) > 1e-3


def test_twist_written_as_an_expression_is_the_twist_option(tmp_path):
    """The twist {axis z, 0 -> 90 deg} over the block's thickness 0 <= z <= 1 mm is n = (cos(pi z
    / 2), sin(pi z / 2), 0): the same body (measured: displacements equal to 4e-14 relative,
    temperatures to 2e-16; the expression is
    normalised by |n| = 1 to rounding); a different expression (the opposite handedness) is not."""
    twist = run_case(
        tmp_path, expression_case('twist = { axis = "z", from_deg = 0.0, to_deg = 90.0 }')
    )
    expression = run_case(
        tmp_path, expression_case('director_expression = ["cos(pi/2 * z)", "sin(pi/2 * z)", "0"]')
    )
    compare(twist, expression, rtol=1e-10)
    mirrored = run_case(
        tmp_path, expression_case('director_expression = ["cos(pi/2 * z)", "-sin(pi/2 * z)", "0"]')
    )
    # the block and its mesh are symmetric about y = 0.5 mm: the mirror image moves the end sideways
    # the other way
    assert mirrored["u_y end [mm]"][-1] == pytest.approx(-twist["u_y end [mm]"][-1], rel=1e-6)
    assert abs(twist["u_y end [mm]"][-1]) > 1e-2


# -- per-region thermal properties ---------------------------------------------------------------


def test_two_layers_conduct_in_series(tmp_path):
    """Steady conduction through two 2 mm layers, k_a = 0.1 mW/(mm K) (the region's own) and k_b
    = 0.4 ([thermal]), x0 at 100 C and x1 at 20 C, the sides adiabatic: the flux is q = 80 K /
    (L_a/k_a + L_b/k_b) = 3.2 mW/mm^2 and the interface at 100 - q L_a / k_a = 36 C, so the layers'
    mean temperatures are 68 C and 28 C (linear in each layer: P1 is exact to the solver's
    rounding; one conductivity would give 80 C and 40 C)."""
    h = run_case(
        tmp_path,
        """
[mesh]
file = "layers.geo"
[thermal]
conductivity = 0.4
[[regions]]
name = "a"
material = "neo-hookean"
E = 1.0
nu = 0.3
conductivity = 0.1
[[regions]]
name = "b"
material = "neo-hookean"
E = 1.0
nu = 0.3
[[heat]]
boundary = "x0"
type = "fixed"
temperature = 100.0
[[heat]]
boundary = "x1"
type = "fixed"
temperature = 20.0
[[supports]]
type = "clamp"
boundary = "x0"
[program]
steady = true
""",
        LAYERS,
        "layers.geo",
    )
    assert h["T_mean a [C]"][-1] == pytest.approx(68.0, rel=1e-9)
    assert h["T_mean b [C]"][-1] == pytest.approx(28.0, rel=1e-9)


def test_gravity_on_each_region_density(tmp_path):
    """Gravity along x on the two layers, rho_a = 2e-9 t/mm^3 (the region's own) and rho_b = 1e-9
    ([thermal]), clamped at x0: the clamp takes -reaction_x = g (rho_a V_a + rho_b V_b) = 1e5 mm/s^2
    x 6e-9 t = 6e-4 N (one density would give 4e-4 N), to Newton's tolerance."""
    h = run_case(
        tmp_path,
        """
[mesh]
file = "layers.geo"
[thermal]
density = 1.0e-9
[[regions]]
name = "a"
material = "neo-hookean"
E = 1.0
nu = 0.3
density = 2.0e-9
[[regions]]
name = "b"
material = "neo-hookean"
E = 1.0
nu = 0.3
[[loads]]
type = "gravity"
g = [1.0e5, 0.0, 0.0]
[[supports]]
type = "clamp"
boundary = "x0"
[program]
duration = 1.0
dt = 1.0
""",
        LAYERS,
        "layers.geo",
    )
    np.testing.assert_allclose(
        -h["reaction_x x0 [N]"], 1.0e5 * (2.0e-9 * 2.0 + 1.0e-9 * 2.0), rtol=1e-6
    )


def test_adiabatic_two_region_energy_balance(tmp_path):
    """A coil of P = I^2 R = 0.01^2 A^2 x 100 ohm = 10 mW in region a (rho c its own: 2e-9 t/mm^3
    x 1e9 mJ/(t K) = 2 mJ/(mm^3 K)) next to region b ([thermal]: 1.15e-9 x 1.5e9 = 1.725), no
    exchange anywhere: backward Euler keeps the energy, sum_r rho_r c_r V_r (T_mean_r - 25 C) = P t
    at every step (to the solver's rounding), while conduction keeps a warmer than b."""
    h = run_case(
        tmp_path,
        """
[mesh]
file = "layers.geo"
[[regions]]
name = "a"
material = "lce"
director = [1.0, 0.0, 0.0]
lambda_N = 1.0001
density = 2.0e-9
specific_heat = 1.0e9
[[regions]]
name = "b"
material = "neo-hookean"
E = 1.0
nu = 0.3
[[coils]]
name = "heater"
region = "a"
resistance = 100.0
[[supports]]
type = "3-2-1"
points = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
[program]
duration = 4.0
dt = 1.0
currents = { heater = 0.01 }
""",
        LAYERS,
        "layers.geo",
    )
    power = 0.01**2 * 100.0 * 1e3  # mW
    energy = 2.0 * 2.0 * (h["T_mean a [C]"] - 25.0) + 1.725 * 2.0 * (h["T_mean b [C]"] - 25.0)
    np.testing.assert_allclose(energy, power * h["time [s]"], rtol=1e-9, atol=1e-12)
    assert h["T_mean a [C]"][-1] > h["T_mean b [C]"][-1] > 25.0


ENERGY_CASE = """
[mesh]
file = "layers.geo"
[[regions]]
name = "a"
material = "lce"
director_expression = ["1", "0.1 * z", "0"]
lambda_N = 1.0001
density = 2.0e-9
specific_heat = 1.0e9
[[regions]]
name = "b"
material = "neo-hookean"
E = 1.0
nu = 0.3
[[coils]]
name = "heater"
region = "a"
resistance = 100.0
[[supports]]
type = "3-2-1"
points = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
[[probes]]
name = "end"
boundary = "x1"
[program]
duration = 2.0
dt = 1.0
currents = { heater = 0.01 }
"""


@pytest.mark.mpi
def test_two_ranks_give_the_serial_answer(tmp_path, lcefem_cmd, serial_and_two_ranks):
    """Per-region heat capacity (DG0), a director expression and a 3-2-1 support under mpiexec -n
    2: the serial history (the 3-2-1 points' nodes live on one rank; before the look-up was
    collective the other rank stopped with 'no node there'). Measured: equal to the CSV's 10
    digits."""
    import csv

    (tmp_path / "layers.geo").write_text(LAYERS)
    (tmp_path / "case.toml").write_text(ENERGY_CASE)
    args = ["run", "body", "--config", str(tmp_path / "case.toml"), "--no-fields", "--quiet"]
    histories = []
    for run in serial_and_two_ranks(lcefem_cmd + args + ["--out", "{out}"], timeout=600):
        with open(run.out / "history.csv") as fh:
            rows = list(csv.DictReader(fh))
        histories.append({k: np.array([float(r[k]) for r in rows]) for k in rows[0]})
    serial, mpi = histories
    for name in serial:
        if name.startswith(("T", "u_")):
            np.testing.assert_allclose(mpi[name], serial[name], rtol=1e-8, atol=1e-10, err_msg=name)
    assert serial["T_mean a [C]"][-1] > serial["T_mean b [C]"][-1] > 25.0


@pytest.mark.parametrize("k", [10.0, 1000.0])
def test_radiation_balances_the_coil(tmp_path, k):
    """A coil of P = 0.002^2 A^2 x 100 ohm = 0.4 mW in a 4 x 1 x 1 mm LCE block (lambda_N =
    1.000001: its x1 face's area changes by ~1e-6 when heated) losing heat by grey-body radiation
    alone from x1 (A = 1 mm^2, emissivity 0.9, ambient 25 C), the rest adiabatic: the problem is
    one-dimensional, so at the steady state x1 is at one T with eps sigma A (T^4 - T_a^4) = P in
    kelvin (the Picard-linearised coefficient, converged, is the T^4 law): T = 81.05 C, to 1e-6
    relative in kelvin. The far end is warmer by P L / (2 k A) = 0.4 x 4 / (2 x 10) = 0.08 K
    (k = 10 mW/(mm K); P1 is nodally exact in 1D). With lambda_N = 1.0001 the area change
    (1e-4) moved T by the 1.1e-5 the T^4 law predicts: measured. k = 1000 (a stiff body): the Picard
    iteration flip-flopped by 1.6e-8 K above its 1e-10 target and never stopped until the round-off
    floor (solvers/heat.py settled) was accepted."""
    from lcefem.models import units

    h = run_case(
        tmp_path,
        """
[mesh]
file = "block.geo"
[thermal]
conductivity = K
[[regions]]
name = "block"
material = "lce"
director = [1.0, 0.0, 0.0]
lambda_N = 1.000001
[[coils]]
name = "heater"
region = "block"
resistance = 100.0
[[heat]]
boundary = "x1"
type = "radiation"
emissivity = 0.9
[[supports]]
type = "3-2-1"
points = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
[[probes]]
name = "x1"
boundary = "x1"
[program]
steady = true
currents = { heater = 0.002 }
""".replace("K", repr(k)),
    )
    power = 0.002**2 * 100.0 * 1e3  # mW
    ta = 25.0 + units.ZERO_CELSIUS_K
    t = (power / (0.9 * units.STEFAN_BOLTZMANN * 1.0) + ta**4) ** 0.25  # K
    assert h["T x1 [C]"][-1] + units.ZERO_CELSIUS_K == pytest.approx(t, rel=1e-6)
    assert h["T_max [C]"][-1] - h["T x1 [C]"][-1] == pytest.approx(power * 4.0 / (2 * k), rel=1e-3)
