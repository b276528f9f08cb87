"""``lcefem run ribbon``: bad input exits 2 with one line; a short run writes complete outputs."""

import dataclasses
import json
import subprocess

import pytest

from lcefem.models.errors import InputError
from lcefem.validation.app.cli import main


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--duration", "-1"], "--duration = -1.0 s: must be > 0 s"),
        (["--nodes", "0"], "--nodes = 0: must be >= 3"),
        (["--config", "/nonexistent/case.toml"], "file not found"),
        (["--obstacle", "0", "10"], "--obstacle WIDTH = 0.0 mm: must be > 0 mm"),
        (
            ["--obstacle-offset", "5"],
            "--obstacle-offset/--obstacle-distance: give the block's size",
        ),
        (
            ["--obstacle", "0.8", "10"],
            "obstacle.width = 0.8 mm: must exceed twice obstacle.edge_radius",
        ),
    ],
)
def test_bad_input_exits_2(argv, message, capsys, tmp_path):
    code = main(["run", "ribbon", "--quiet", "--out", str(tmp_path / "out"), *argv])
    err = capsys.readouterr().err
    assert code == 2
    assert message in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_unknown_config_key(tmp_path, capsys):
    cfg = tmp_path / "case.toml"
    cfg.write_text("[geometry]\nwidht = 4.0\n")
    assert (
        main(["run", "ribbon", "--quiet", "--config", str(cfg), "--out", str(tmp_path / "o")]) == 2
    )
    assert "unknown key 'geometry.widht'" in capsys.readouterr().err


def test_config_bounds(tmp_path, capsys):
    cfg = tmp_path / "case.toml"
    cfg.write_text("[numerics]\nnodes = 2\n")
    assert (
        main(["run", "ribbon", "--quiet", "--config", str(cfg), "--out", str(tmp_path / "o")]) == 2
    )
    assert "numerics.nodes = 2" in capsys.readouterr().err


def test_short_run_end_to_end(tmp_path, lcefem_cmd):
    out = tmp_path / "run"
    proc = subprocess.run(
        [
            *lcefem_cmd,
            "run",
            "ribbon",
            "--ground-temperature",
            "90",
            "--duration",
            "0.4",
            "--nodes",
            "12",
            "--dt",
            "0.02",
            "--out",
            str(out),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    names = {p.name for p in out.iterdir()}
    assert {
        "centerline.pvd",
        "surface.pvd",
        "centroid.csv",
        "history.csv",
        "trajectory.png",
        "summary.json",
    } <= names
    assert not any(n.endswith(".part") for n in names)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["config"]["run"]["ground_temperature"]["value"] == 90.0
    assert summary["config"]["numerics"]["nodes"]["value"] == 12
    assert (out / "centroid.csv").read_text().splitlines()[0] == "time [s],x [mm],y [mm],z [mm]"
    import pyvista as pv

    reader = pv.get_reader(str(out / "centerline.pvd"))
    assert len(reader.time_values) >= 2
    mesh = reader.read()[0]
    assert mesh.n_points == 12
    for name in (
        "twist_density [rad/mm]",
        "curvature [1/mm]",
        "temperature [C]",
        "contact_force [N]",
    ):
        assert name in mesh.point_data


def test_config_from_args_rejects_bad_dt(tmp_path):
    from argparse import Namespace

    from lcefem.validation.app.commands.ribbon import config_from_args

    args = Namespace(
        config=None,
        ground_temperature=None,
        duration=None,
        twist_density=None,
        helix_radius=None,
        nodes=None,
        dt=0.0,
    )
    with pytest.raises(InputError, match="--dt"):
        config_from_args(args)


def test_obstacle_reaches_the_rod(tmp_path):
    """--obstacle places a box of that width and height in the ribbon's path, centred on its
    middle."""
    import argparse

    from lcefem.solvers.der.ribbon import RibbonSimulation
    from lcefem.validation.app.commands import ribbon

    parser = argparse.ArgumentParser()
    ribbon.add_arguments(parser)
    args = parser.parse_args(["--obstacle", "20", "8", "--obstacle-distance", "6", "--nodes", "12"])
    cfg = ribbon.config_from_args(args).validated()
    setup = cfg.setup()
    assert len(setup.blocks) == 1
    sim = RibbonSimulation(
        dataclasses.replace(setup, numerics=dataclasses.replace(setup.numerics, settle_time=0.0))
    )
    (box,) = sim.rod.boxes
    x = sim.state.x
    mid = 0.5 * (x[:, 0].min() + x[:, 0].max())
    assert box.hi[0] - box.lo[0] == pytest.approx(20.0)
    assert 0.5 * (box.hi[0] + box.lo[0]) == pytest.approx(mid)
    assert box.hi[2] == pytest.approx(8.0)
    assert box.lo[1] - x[:, 1].max() == pytest.approx(6.0)  # the near face on the +y side
    assert sim.block_gaps()[0] == pytest.approx(6.0 - 0.5 * cfg.geometry.width, abs=0.2)
