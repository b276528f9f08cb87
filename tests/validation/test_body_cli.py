"""`lcefem run body`: the strip as a case file reproduces `lcefem run strip`; bad case files are one
line, exit 2, before any mesh is built, with nothing written in --out; mpiexec -n 2 gives the serial
answer."""

import csv
import shutil
import subprocess

import numpy as np
import pytest

from tests.conftest import REPO

STRIP = REPO / "examples" / "bodies" / "strip"


def run(cmd, *args, **kw):
    return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=600, **kw)


def read_history(path):
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def test_strip_instance_equals_the_strip_body():
    """The README's first run (0.2 A, 20 s) at mesh level 0 and dt = 1 s: the case file's history
    equals `lcefem run strip`'s within 1e-6 relative (measured: temperatures equal to 1e-15, the
    stretch within 5e-10 relative; the same Newton iterations)."""
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.solvers.problems.strip import StripConfig, StripMesh, StripRun, run_strip

    strip = run_strip(
        StripConfig(run=StripRun(current=0.2, duration=20.0, dt=1.0), mesh=StripMesh(level=0)),
        None,
        progress=False,
        fields=False,
    )
    case = load_case(
        STRIP / "case.toml", overrides={("mesh", "size_factor"): 1.0, ("program", "dt"): 1.0}
    )
    body = run_body(case, None, progress=False)
    s, b = strip.history, body.history
    dims = strip.summary["as_built"]
    stretch = (dims["length"] + b["u_x end [mm]"] - b["u_x clamp [mm]"]) / dims["length_isotropic"]
    np.testing.assert_allclose(b["time [s]"], s["time [s]"], rtol=0, atol=1e-12)
    for name, values in (
        ("T_mean [C]", b["T_mean [C]"]),
        ("T_max [C]", b["T_max [C]"]),
        ("T_surface [C]", b["T sides [C]"]),
        ("stretch [-]", stretch),
    ):
        np.testing.assert_allclose(values, s[name], rtol=1e-6, err_msg=name)
    assert np.array_equal(b["newton_iterations [-]"], s["newton_iterations [-]"])
    assert s["stretch [-]"][-1] < 1.1  # the strip did contract (from lambda_N = 1.426)


GOOD = """
[mesh]
file = "strip.geo"
symmetry_factor = 4
[[regions]]
name = ["lce", "coil"]
material = "lce"
director = [1.0, 0.0, 0.0]
[[coils]]
name = "coil"
region = "coil"
[[heat]]
boundary = ["sides", "end"]
type = "convection"
[[supports]]
type = "clamp"
boundary = "clamp"
[program]
duration = 2.0
dt = 1.0
currents = { coil = 0.1 }
"""


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            'name = ["lce", "coil"]',
            'name = ["lce", "core"]',
            "[[regions]][0].name: 'core' is not a cell set of strip.geo",
        ),
        (
            "director = [1.0, 0.0, 0.0]",
            "director = [0.0, 0.0, 0.0]",
            "[[regions]][0].director: [0.0, 0.0, 0.0]: zero length",
        ),
        (
            'name = ["lce", "coil"]\nmaterial = "lce"\ndirector = [1.0, 0.0, 0.0]',
            'name = "lce"\nmaterial = "lce"\ndirector = [1.0, 0.0, 0.0]\n[[regions]]\nname = '
            '"coil"\nmaterial = "kapton"',
            "[[coils]][0].region: 'coil' is a passive region (kapton)",
        ),
        (
            'boundary = "clamp"\n',
            'boundary = "clamp"\n[[supports]]\ntype = "roller"\nboundary = "clamp"\nnormal = "x"\n',
            "[[supports]][1]: boundary 'clamp': component x is constrained twice",
        ),
        ('file = "strip.geo"', 'file = "robot.geo"', "[mesh].file: 'robot.geo': file not found"),
        (
            'material = "lce"',
            'material = "lce"\ncolour = "red"',
            "[[regions]][0].colour: unknown key; allowed: name, material",
        ),
        (
            'material = "lce"',
            'material = "lce"\ncurve = "one_row.csv"',
            "[[regions]][0].curve: one_row.csv",
        ),
        (
            'material = "lce"',
            'material = "lce"\ncurve = "unitless.csv"',
            "[[regions]][0].curve: unitless.csv",
        ),
        (
            "currents = { coil = 0.1 }",
            "currents = { heater = 0.1 }",
            "[program].currents.heater: not a current tag; allowed: coil",
        ),
    ],
    ids=[
        "region-not-in-mesh",
        "zero-director",
        "coil-on-passive",
        "over-constrained",
        "missing-file",
        "unknown-key",
        "curve-one-row",
        "curve-without-units",
        "unknown-drive",
    ],
)
def test_bad_case_one_line_exit_2_nothing_written(tmp_path, lcefem_cmd, old, new, message):
    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    (tmp_path / "one_row.csv").write_text("temperature [C],stretch [-]\n25,1.4\n")
    (tmp_path / "unitless.csv").write_text("temperature,stretch\n25,1.4\n150,1.0\n")
    assert old in GOOD
    (tmp_path / "case.toml").write_text(GOOD.replace(old, new, 1))
    out = tmp_path / "out"
    res = run(lcefem_cmd, "run", "body", "--config", str(tmp_path / "case.toml"), "--out", str(out))
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith("lcefem: error: case.toml: ") and message in lines[0], lines[0]
    assert not out.exists() or not any(out.iterdir())


def test_completed_run_outputs(tmp_path, lcefem_cmd):
    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    (tmp_path / "case.toml").write_text(GOOD)
    out = tmp_path / "out"
    res = run(
        lcefem_cmd,
        "run",
        "body",
        "--config",
        str(tmp_path / "case.toml"),
        "--out",
        str(out),
        "--quiet",
    )
    assert res.returncode == 0, res.stderr
    names = {p.name for p in out.iterdir()}
    assert {"history.csv", "summary.json", "temperature.bp", "displacement.bp"} <= names
    assert not any(n.endswith(".part") for n in names)
    h = read_history(out / "history.csv")
    assert list(h["time [s]"]) == [0.0, 1.0, 2.0]
    # the coil's power is that of the whole coil: I^2 R = 0.1^2 x 146.6 ohm = 1466 mW
    assert h["power coil [mW]"][-1] == pytest.approx(0.1**2 * 146.6 * 1e3)
    assert h["T_max coil [C]"][-1] > h["T_max lce [C]"][0] == 25.0


@pytest.mark.mpi
def test_two_ranks_give_the_serial_answer(lcefem_cmd, serial_and_two_ranks):
    args = [
        "run",
        "body",
        "--config",
        str(STRIP / "case.toml"),
        "--size-factor",
        "1",
        "--dt",
        "1",
        "--duration",
        "4",
        "--no-fields",
        "--quiet",
    ]
    runs = serial_and_two_ranks(lcefem_cmd + args + ["--out", "{out}"], timeout=600)
    s, p = (read_history(r.out / "history.csv") for r in runs)
    for name in s:
        if name.startswith(("T", "u_x")):
            np.testing.assert_allclose(p[name], s[name], rtol=1e-8, atol=1e-10, err_msg=name)


def test_measured_curve_sampled_from_the_law_gives_the_law(tmp_path):
    """A region's measured curve (CSV) sampled every 1 K from the present law it replaces gives the
    same body within the piecewise-linear interpolation error (h^2 max|lambda''|/8 ~ 1e-4 in stretch
    at 1 K, measured on the strip: 2.8e-5); a curve whose contraction ends 30 K earlier contracts
    the heated strip further (the direction of the change, at the same current and time)."""
    from lcefem.models.lce import MeasuredContraction, NematicTransition, spontaneous_stretch
    from lcefem.solvers.contraction_curve import write_contraction_csv
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case

    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    good = GOOD.replace("[program]", '[[probes]]\nname = "end"\nboundary = "end"\n[program]')
    (tmp_path / "case.toml").write_text(good)
    plain = load_case(tmp_path / "case.toml")
    r = plain.regions[0]
    law = NematicTransition(
        T_NI=r["T_NI"], width=r["width"], lambda_N=r["lambda_N"], T_ref=r["T_ref"]
    )
    T = np.arange(20.0, 301.0, 1.0)
    for name, shift in (("sampled.csv", 0.0), ("earlier.csv", 30.0)):
        rows = spontaneous_stretch(np.minimum(T + shift, 300.0), law)
        write_contraction_csv(tmp_path / name, MeasuredContraction.from_rows(T, rows, source=name))
    results = {}
    for name in ("sampled.csv", "earlier.csv", None):
        text = (
            good
            if name is None
            else good.replace('material = "lce"', f'material = "lce"\ncurve = "{name}"')
        )
        (tmp_path / "case.toml").write_text(text)
        results[name] = run_body(load_case(tmp_path / "case.toml"), None, progress=False).history
    base, sampled, earlier = results[None], results["sampled.csv"], results["earlier.csv"]
    # the heat sees the deformation only through the staggered coupling: equal within 1e-6
    np.testing.assert_allclose(sampled["T_mean lce [C]"], base["T_mean lce [C]"], rtol=1e-6)
    np.testing.assert_allclose(
        sampled["u_x end [mm]"], base["u_x end [mm]"], rtol=0, atol=2e-3 * 80
    )
    assert earlier["u_x end [mm]"][-1] < base["u_x end [mm]"][-1] - 5 * abs(
        sampled["u_x end [mm]"][-1] - base["u_x end [mm]"][-1]
    )


@pytest.mark.parametrize("fmt", ["msh", "vtu", "xdmf"])
def test_exported_builtin_mesh_reads_back_into_the_body(tmp_path, fmt):
    """`lcefem mesh strip --format FMT` written, then `lcefem run body` on it: the same body as the
    strip's own .geo at the same level (level 0 = size factor 1), its history equal within the
    solvers' tolerance (the cells may come back in another order)."""
    from lcefem.meshes.io import write_mesh
    from lcefem.solvers.problems.body import run_body
    from lcefem.solvers.problems.body_case import load_case
    from lcefem.validation.app.mesh import MeshRequest, build

    m, _ = build(MeshRequest("strip", "fe", 0, fmt))
    write_mesh(m, tmp_path, "strip", fmt)
    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    case = (STRIP / "case.toml").read_text()
    assert 'file = "strip.geo"' in case
    (tmp_path / "geo.toml").write_text(case)
    (tmp_path / "export.toml").write_text(
        case.replace('file = "strip.geo"', f'file = "strip.{fmt}"')
    )
    over = {("mesh", "size_factor"): 1.0, ("program", "dt"): 1.0, ("program", "duration"): 2.0}
    geo = run_body(load_case(tmp_path / "geo.toml", overrides=over), None, progress=False).history
    exp = run_body(
        load_case(tmp_path / "export.toml", overrides=over), None, progress=False
    ).history
    assert set(exp) == set(geo)
    for name in geo:
        np.testing.assert_allclose(exp[name], geo[name], rtol=1e-8, atol=1e-9, err_msg=name)


def test_a_case_files_petsc_goes_through_the_allow_list(tmp_path, lcefem_cmd):
    """A [petsc] option that would run code (pc_type python) or write a file (a monitor's viewer) is
    refused like in every other case file: exit 2, one line, nothing written."""
    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    for option in ('pc_type = "python"', 'snes_monitor = "ascii:' + str(tmp_path / "x.txt") + '"'):
        (tmp_path / "case.toml").write_text(GOOD + "[petsc]\n" + option + "\n")
        out = tmp_path / "out"
        res = run(
            lcefem_cmd, "run", "body", "--config", str(tmp_path / "case.toml"), "--out", str(out)
        )
        assert res.returncode == 2, res.stderr
        assert len(res.stderr.strip().splitlines()) == 1 and "[petsc]" in res.stderr, res.stderr
        assert not (tmp_path / "x.txt").exists() and (not out.exists() or not any(out.iterdir()))
