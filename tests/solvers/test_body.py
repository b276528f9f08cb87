"""solvers/problems/body.py on a small block: dead loads and reactions (equilibrium: the supports
take the applied loads), the heat balance of a coil against convection on boundaries with
different film coefficients (the steady state), a 3-2-1 support that constrains nothing."""

import numpy as np
import pytest

BLOCK = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 4, 1, 1};
Mesh.MeshSizeMax = 1 * Mesh.MeshSizeFactor;
Transfinite Curve{:} = 3;
Transfinite Curve{ Curve In BoundingBox{-0.1, -0.1, -0.1, 4.1, 0.1, 0.1} } = 5;
Transfinite Curve{ Curve In BoundingBox{-0.1, 0.9, -0.1, 4.1, 1.1, 0.1} } = 5;
Transfinite Curve{ Curve In BoundingBox{-0.1, -0.1, 0.9, 4.1, 0.1, 1.1} } = 5;
Transfinite Curve{ Curve In BoundingBox{-0.1, 0.9, 0.9, 4.1, 1.1, 1.1} } = 5;
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};
Recombine Volume{:};
Physical Volume("block", 1) = {1};
Physical Surface("x0", 1) = Surface In BoundingBox{-0.1, -0.1, -0.1, 0.1, 1.1, 1.1};
Physical Surface("x1", 2) = Surface In BoundingBox{3.9, -0.1, -0.1, 4.1, 1.1, 1.1};
Physical Surface("y0", 3) = Surface In BoundingBox{-0.1, -0.1, -0.1, 4.1, 0.1, 1.1};
Physical Surface("y1", 4) = Surface In BoundingBox{-0.1, 0.9, -0.1, 4.1, 1.1, 1.1};
Physical Surface("z0", 5) = Surface In BoundingBox{-0.1, -0.1, -0.1, 4.1, 1.1, 0.1};
Physical Surface("z1", 6) = Surface In BoundingBox{-0.1, -0.1, 0.9, 4.1, 1.1, 1.1};
"""


def run_case(tmp_path, text):
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case

    (tmp_path / "block.geo").write_text(BLOCK)
    (tmp_path / "case.toml").write_text(text)
    case = load_case(tmp_path / "case.toml")
    return case, run_body(case, None, progress=False)


def test_loads_are_taken_by_the_supports(tmp_path):
    """A passive block (E = 1 MPa) on three mirror/roller planes, pulled along x by a force, a
    (negative, dead) pressure and gravity, the force and pressure ramped by the program: the
    roller's reaction is their sum (equilibrium, to Newton's tolerance), and the end's mean
    displacement is F L / (E A) to first order in the strain (0.5 %)."""
    case, result = run_case(
        tmp_path,
        """
[mesh]
file = "block.geo"
[thermal]
density = 1.2e-9
[[regions]]
name = "block"
material = "neo-hookean"
E = 1.0
nu = 0.3
[[supports]]
type = "roller"
boundary = "x0"
normal = "x"
[[supports]]
type = "mirror"
boundary = "y0"
normal = "y"
[[supports]]
type = "mirror"
boundary = "z0"
normal = "z"
[[loads]]
type = "force"
boundary = "x1"
force = [0.004, 0.0, 0.0]
name = "pull"
[[loads]]
type = "pressure"
boundary = "x1"
pressure = -0.001
name = "suction"
[[loads]]
type = "gravity"
g = [1.0e5, 0.0, 0.0]
[[probes]]
name = "end"
boundary = "x1"
[program]
duration = 2.0
dt = 1.0
loads = { pull = [[0.0, 0.0], [2.0, 1.0]], suction = [[0.0, 0.0], [2.0, 1.0]] }
""",
    )
    h = result.history
    weight = 1.2e-9 * 1.0e5 * 4.0  # rho g V [N]
    applied = np.array([weight + f * 0.005 for f in (0.0, 0.5, 1.0)])
    np.testing.assert_allclose(-h["reaction_x x0 [N]"], applied, rtol=1e-6, atol=1e-10)
    # first order: the end moves by F L / (E A) plus the weight's share (rho g L^2 / (2 E))
    expected = 0.005 * 4.0 / 1.0 + 1.2e-9 * 1.0e5 * 16.0 / 2.0
    assert h["u_x end [mm]"][-1] == pytest.approx(expected, rel=0.01)


def test_steady_coil_heat_leaves_through_the_convecting_boundaries(tmp_path):
    """A coil of 2.5 mW in an LCE block with no spontaneous deformation to speak of (lambda_N =
    1.0001), convection h = 0.01 mW/(mm^2 K) on x1 and 0.005 on y1 and z1, the rest adiabatic,
    held by a 3-2-1 support: at the steady state sum_b h_b A_b (mean T_b - T_inf) = P, to the
    reference-area share of the deformation (1e-4)."""
    case, result = run_case(
        tmp_path,
        """
[mesh]
file = "block.geo"
[[regions]]
name = "block"
material = "lce"
twist = { axis = "z", from_deg = 0.0, to_deg = 90.0 }
lambda_N = 1.0001
[[coils]]
name = "heater"
region = "block"
resistance = 100.0
[[heat]]
boundary = "x1"
type = "convection"
h = 0.01
[[heat]]
boundary = ["y1", "z1"]
type = "convection"
h = 0.005
[[supports]]
type = "3-2-1"
points = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
[[probes]]
name = "x1"
boundary = "x1"
[[probes]]
name = "y1"
boundary = "y1"
[[probes]]
name = "z1"
boundary = "z1"
[program]
steady = true
currents = { heater = 0.005 }
""",
    )
    row = {k: v[-1] for k, v in result.history.items()}
    power = 0.005**2 * 100.0 * 1e3  # [mW]
    assert row["power heater [mW]"] == pytest.approx(power)
    out = sum(
        hb * area * (row[f"T {b} [C]"] - 25.0)
        for b, hb, area in (("x1", 0.01, 1.0), ("y1", 0.005, 4.0), ("z1", 0.005, 4.0))
    )
    assert out == pytest.approx(power, rel=1e-4)
    assert row["T_max [C]"] > row["T x1 [C]"] > 25.0


COIL_CASE = """
[mesh]
file = "block.geo"
[[regions]]
name = "block"
material = "lce"
director = [0.0, 0.0, 2.0]
[[coils]]
name = "heater"
region = "block"
[[supports]]
type = "clamp"
boundary = "x0"
[program]
duration = 4.0
dt = 1.0
"""


def test_schedule_file_drives_and_bounds(tmp_path):
    """A program from a CSV schedule (linear between its rows, constant after), the director
    normalised; a current above lcefem's bound and an unknown column are one-line errors."""
    from lcefem.models.errors import InputError
    from lcefem.solvers.problems.body_case import load_case

    (tmp_path / "block.geo").write_text(BLOCK)
    (tmp_path / "program.csv").write_text("time [s],heater [A]\n0,0.0\n2,0.2\n")
    (tmp_path / "case.toml").write_text(COIL_CASE + 'schedule = "program.csv"\n')
    case = load_case(tmp_path / "case.toml")
    current = case.drives["currents"]["heater"]
    assert [current(t) for t in (0.0, 1.0, 2.0, 3.0)] == pytest.approx([0.0, 0.1, 0.2, 0.2])
    assert case.regions[0]["director"] == [0.0, 0.0, 1.0]
    (tmp_path / "program.csv").write_text("time [s],heater [A]\n0,0.0\n2,2.0\n")
    with pytest.raises(
        InputError, match=r"case.toml: \[program\].schedule heater = .*between 0 and 1 A"
    ):
        load_case(tmp_path / "case.toml")
    (tmp_path / "program.csv").write_text("time [s],cooler [A]\n0,0.0\n")
    with pytest.raises(InputError, match="column 'cooler \\[A\\]': not a coil"):
        load_case(tmp_path / "case.toml")
