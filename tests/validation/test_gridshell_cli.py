"""``lcefem run gridshell``: outputs and exit codes (one-cell grid, seconds)."""

import json

import numpy as np
import pytest

from lcefem.validation.app.cli import main


def test_run_writes_summary_nodes_and_vtk(tmp_path):
    out = tmp_path / "gs"
    rc = main(
        [
            "run",
            "gridshell",
            "--ribbons",
            "1",
            "--lambda",
            "T=1.33,B=1.05",
            "--quiet",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    summary = json.loads((out / "summary.json").read_text())
    r = summary["results"]
    assert summary["status"] == "completed" and r["target reached exactly"] is True
    assert r["circle_x"] < 0 and r["circle_y"] < 0  # a dome: negative (seed 001)
    assert [s["lambda [-]"] for s in summary["strips"]] == [1.05] * 4 + [1.33] * 2
    nodes = np.loadtxt(out / "nodes.csv", delimiter=",", skiprows=1)
    assert nodes.shape[1] == 7 and (out / "nodes.csv").read_text().startswith("node id [-],x0 [mm]")
    assert (out / "gridshell.pvd").is_file() and (out / "gridshell.png").is_file()
    assert not list(out.glob("*.part"))


def test_bad_input_exits_2(tmp_path, capsys):
    assert main(["run", "gridshell", "--lambda", "Tq=1.2", "--out", str(tmp_path)]) == 2
    assert "unknown strip selection 'Tq'" in capsys.readouterr().err
    assert main(["run", "gridshell", "--lambda", "T=1.6", "--out", str(tmp_path)]) == 2
    assert "lambda = 1.6: must be between 1" in capsys.readouterr().err
    assert (
        main(["run", "gridshell", "--shape", "dome", "--lambda", "T=1.2", "--out", str(tmp_path)])
        == 2
    )
    assert main(["run", "gridshell", "--current", "Tx=2", "--out", str(tmp_path)]) == 2
    assert "between 0 and 1 A" in capsys.readouterr().err


def test_current_route_from_the_command_line(tmp_path):
    out = tmp_path / "gc"
    rc = main(
        [
            "run",
            "gridshell",
            "--ribbons",
            "1",
            "--current",
            "B=0.09,T=0.0",
            "--quiet",
            "--out",
            str(out),
        ]
    )
    assert rc == 0
    summary = json.loads((out / "summary.json").read_text())
    lam = summary["drive"]["lambda (from current)"]
    assert 1.0 < lam["B"] < 1.2 and lam["T"] == 1.4  # 0.09 A contracts a grid strip; 0 A: as built


def test_non_convergence_writes_failure_json_and_exits_3(tmp_path):
    cfg = tmp_path / "case.toml"
    cfg.write_text(
        "[layout]\nribbons = 1\n[lambda]\nB = 1.05\n[solver]\nmax_iterations = 2\n"
        "[path]\ninitial_increment = 1.0\nmax_increment = 1.0\nmin_increment = 0.6\n"
    )
    out = tmp_path / "fail"
    assert main(["run", "gridshell", "--config", str(cfg), "--quiet", "--out", str(out)]) == 3
    failure = json.loads((out / "failure.json").read_text())
    assert failure["status"] == "failed" and failure["last_converged"]["load factor [-]"] == 0.0
    assert (out / "history.partial.csv").is_file() and (out / "last_converged.vtp").is_file()
    assert not (out / "summary.json").exists()


def test_recipe_departures_from_the_command_line(tmp_path, capsys):
    # --recipe runs the published model set with the strip-ribbon contact (issue 46); --departure
    # names more departures; --configuration published is the published script (no contact)
    assert (
        main(
            [
                "run",
                "gridshell",
                "--recipe",
                "cone",
                "--departure",
                "contakt",
                "--out",
                str(tmp_path / "a"),
            ]
        )
        == 2
    )
    assert "unknown departure 'contakt'" in capsys.readouterr().err
    assert (
        main(
            [
                "run",
                "gridshell",
                "--shape",
                "dome",
                "--configuration",
                "published",
                "--out",
                str(tmp_path / "b"),
            ]
        )
        == 2
    )
    assert "only with the published model set" in capsys.readouterr().err
    import argparse

    from lcefem.validation.app.commands import gridshell as cmd

    p = argparse.ArgumentParser()
    cmd.add_arguments(p)
    cfg = cmd.prepare(
        p.parse_args(
            ["--recipe", "dome", "--departure", "volume_law", "--departure", "middle_rollers"]
        )
    )
    resolved = cfg.resolved()["configuration (resolved)"]
    assert {
        k: resolved[k]
        for k in (
            "model set",
            "configuration",
            "departures",
            "mesh.contact",
            "mesh.top_junction",
            "mesh.strip_element",
            "lce.force_law",
        )
    } == {
        "model set": "published",
        "configuration": "model-set",
        "departures": ["contact", "volume_law", "middle_rollers"],
        "mesh.contact": True,
        "mesh.top_junction": "glue",
        "mesh.strip_element": "bar",
        "lce.force_law": "volume",
    }
    assert cfg.support == "middle_rollers"
    script = cmd.prepare(p.parse_args(["--recipe", "dome", "--configuration", "published"]))
    assert script.effective[0].contact is False and script.run.resolved_departures == ()


def test_model_set_of_the_run_command():
    # the command's default is the FE-calibrated set (as design, bands, sequences), its fitted
    # materials and exchange factor from the stored calibration; --model-set published the published
    # one
    import argparse

    from lcefem.validation.app.commands import gridshell as cmd
    from lcefem.validation.studies.gridshell import calibrate

    p = argparse.ArgumentParser()
    cmd.add_arguments(p)
    fe = cmd.prepare(p.parse_args(["--shape", "saddle"]))
    ms = calibrate.model_set("fe-calibrated")
    mesh, lce, support = fe.effective
    assert fe.run.model_set == "fe-calibrated" and support == "clamp"
    assert (mesh.contact, mesh.top_junction, mesh.strip_element, lce.force_law) == (
        ms.mesh.contact,
        ms.mesh.top_junction,
        ms.mesh.strip_element,
        ms.materials.lce.force_law,
    )
    assert (
        fe.kapton == ms.materials.kapton
        and fe.lce.bending_factor == ms.materials.lce.bending_factor
    )
    assert fe.current_route.exchange_factor == ms.exchange_factor
    pub = cmd.prepare(p.parse_args(["--shape", "saddle", "--model-set", "published"]))
    assert pub.run.resolved_departures == ("contact",) and pub.effective[0].strip_element == "bar"
    assert pub.current_route.exchange_factor == calibrate.exchange_factor("published")


def test_shape_from_the_papers_rule_of_currents(tmp_path, capsys):
    # --route current: Eq. 1 inverted at the Fig. 4 lambdas through the 130 ohm grid coil (0.0640 A
    # at 1.33, 0.0786 A at 1.05), back through the calibrated strip route to within 0.015 of those
    # lambdas (the strip model at the grid factor is Eq. 1's neighbour: 1.341 / 1.053)
    out = tmp_path / "rule"
    assert (
        main(
            [
                "run",
                "gridshell",
                "--ribbons",
                "1",
                "--shape",
                "dome",
                "--route",
                "current",
                "--quiet",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    drive = json.loads((out / "summary.json").read_text())["drive"]
    assert drive["current [A]"]["Tx"] == pytest.approx(0.0640, abs=1e-4)
    assert drive["current [A]"]["Bx"] == pytest.approx(0.0786, abs=1e-4)
    assert drive["lambda (from current)"]["Tx"] == pytest.approx(1.33, abs=0.015)
    assert drive["lambda (from current)"]["Bx"] == pytest.approx(1.05, abs=0.015)
    capsys.readouterr()
    # bad input: one line naming the field, exit 2 (no FE run is started)
    for argv, msg in (
        (["--route", "current"], "needs a shape"),
        (["--mesh-level", "1", "--shape", "dome"], "--mesh-level: only with --model fe"),
    ):
        assert main(["run", "gridshell", *argv, "--out", str(tmp_path / "bad")]) == 2
        assert msg in capsys.readouterr().err


def test_fe_refuses_what_it_cannot_run_in_one_line(tmp_path, capsys):
    # --model fe takes every drive of the bar-and-hinge run (issue 46); what remains refused names
    # the flag and why, exit 2, before any mesh is built
    for argv, msg in (
        (["--shape", "dome", "--route", "current", "--current", "Tx=0.1"], "give one drive"),
        ([], "give one drive of --shape, --recipe, --lambda, --current, --schedule"),
        (
            ["--shape", "dome", "--support", "middle_rollers"],
            "--support middle_rollers: not in the 3D FE",
        ),
        (["--lambda", "7=1.2"], "strip id 7: bar-and-hinge numbering"),
        (["--lambda", "Tq=1.2"], "unknown strip selection 'Tq'"),
        (["--lambda", "T=1.6"], "lambda top_x_r0_j0_lo = 1.6: must be between 1"),
        (["--current", "Tx=2"], "between 0 and 1 A"),
        (["--recipe", "cone", "--mesh-level", "4"], "--mesh-level = 4: allowed 0..3"),
        (["--shape", "dome", "--model-set", "published"], "--model-set: not with --model fe"),
        (["--shape", "dome", "--departure", "contact"], "--departure: not with --model fe"),
        (["--shape", "dome", "--thermal-model", "eq1"], "--thermal-model: not with --model fe"),
        (["--recipe", "cone", "--route", "current"], "--route: only with --shape"),
    ):
        assert (
            main(["run", "gridshell", "--model", "fe", *argv, "--out", str(tmp_path / "bad")]) == 2
        ), argv
        err = capsys.readouterr().err.strip()
        assert msg in err and len(err.splitlines()) == 1, (argv, err)
    assert not (tmp_path / "bad").exists()


def test_fe_takes_the_smallest_valid_mirror_model_of_every_drive():
    # the recipes' mirror models resolved from their drives are those of meshes.gridshell_fe
    # (RECIPE_SYMMETRY, derived there by hand); the Fig. 4 shapes by lambdas or currents: quarter
    import argparse

    from lcefem.meshes.gridshell_fe import RECIPE_SYMMETRY
    from lcefem.validation.app.commands import gridshell as cmd

    p = argparse.ArgumentParser()
    cmd.add_arguments(p)

    def prepared(*argv):
        return cmd.prepare(p.parse_args(["--model", "fe", *argv]))

    for recipe, symmetry in RECIPE_SYMMETRY.items():
        cfg = prepared("--recipe", recipe)
        assert cfg.symmetry == symmetry, recipe
        assert cfg.model.supports.kind == (
            "centre_clamp" if symmetry != "quarter" or recipe == "saddle" else "rollers"
        )
    cone = prepared("--recipe", "cone").drive_fields()[0]
    assert cone["bottom_x_r0_s1"] == pytest.approx(1.4 * 0.75) and cone[
        "top_y_r2_j1_hi"
    ] == pytest.approx(1.4 * 0.90)
    saddle = prepared("--shape", "saddle", "--route", "current")
    assert saddle.run.drive == "current" and saddle.symmetry == "quarter"
    assert saddle.currents["Tx"] == pytest.approx(
        0.0640, abs=1e-4
    )  # the paper's rule, as the BH route
    assert prepared("--lambda", "XD1=1.2").symmetry == "half_x"  # row 1 <-> row 3 under y -> 2c - y
    assert prepared("--lambda", "XD:x<70.5=1.2").symmetry == "half_y"
    assert prepared("--lambda", "XD1=1.2,YD:y>70.5=1.1").symmetry == "half_x"
    assert prepared("--lambda", "XD1=1.2,YD1=1.1").symmetry == "full"
    assert prepared("--shape", "dome", "--support", "table").model.supports.kind == "table"
    sched = prepared("--schedule", "validation/data/gridshell_fig5a_schedule.toml")
    assert (
        sched.run.drive == "schedule"
        and sched.symmetry == "quarter"
        and sched.run.duration == 495.0
    )
    assert len(sched.protocol) == 9 and sched.model.supports.kind == "rollers"


@pytest.mark.slow
def test_fe_dome_from_the_command_line_gives_the_stored_golden(tmp_path):
    # The FE dome at level 0 from the command line takes the path of the case gridshell_shapes_fe
    # (quarter model, published rollers, GridshellFE ramped from as built) and lands on its stored
    # golden (validation/data/gridshell_fe_fig4_quarter_level0.json, written to 5-6 significant
    # digits): within 1e-6 1/mm and 1e-4 mm, the stored rounding. Measured: circle -0.02217455 and
    # quadratic -0.02024031 1/mm, apex 40.566067 mm; 45 s user CPU (/usr/bin/time, shared machine).
    from lcefem.validation.cases.reference_data import DATA_DIR

    golden = json.loads((DATA_DIR / "gridshell_fe_fig4_quarter_level0.json").read_text())["shapes"][
        "dome"
    ]
    out = tmp_path / "fe_dome"
    assert (
        main(["run", "gridshell", "--model", "fe", "--shape", "dome", "--quiet", "--out", str(out)])
        == 0
    )
    s = json.loads((out / "summary.json").read_text())
    r = s["results"]
    assert s["status"] == "completed" and s["symmetry"] == "quarter" and s["support"] == "rollers"
    assert s["dofs [-]"] == golden["dofs"]
    for key in (
        "kappa_circle_x [1/mm]",
        "kappa_circle_y [1/mm]",
        "kappa_quad_x [1/mm]",
        "kappa_quad_y [1/mm]",
    ):
        assert r[key] == pytest.approx(golden[key], abs=1e-6), key
    assert np.allclose(
        r["junction_centres [mm]"], golden["junction_centres [mm]"], atol=1e-4, rtol=0.0
    )
    history = (out / "history.csv").read_text().splitlines()
    assert history[0].startswith("load factor [-],kappa_circle_x [1/mm]") and len(history) > 3
    assert (out / "displacement.bp").is_dir() and (out / "fields" / "cells.xdmf").is_file()
    assert not list(out.glob("*.part*"))


def test_every_run_reports_its_strip_ribbon_penetration(tmp_path, capsys):
    # issue 46: the published script (no contact) lets the cone's strips pass 0.97 mm through the
    # ribbon (docs/gridshell_configuration.md); the recipe's default (the published set + contact)
    # keeps them out to the penalty's 0.08 mm; the run says so in summary.json and its printed line
    for argv, deep in ((["--configuration", "published"], True), ([], False)):
        out = tmp_path / ("script" if deep else "default")
        assert (
            main(["run", "gridshell", "--recipe", "cone", *argv, "--quiet", "--out", str(out)]) == 0
        )
        s = json.loads((out / "summary.json").read_text())
        line = capsys.readouterr().out
        assert s["strips pass through the ribbon"] is deep
        if deep:
            assert s["strip-ribbon penetration [mm]"] == pytest.approx(0.97, abs=0.02)
            assert "(strips pass through the ribbon)" in line
        else:
            assert 0.0 < s["strip-ribbon penetration [mm]"] < 0.12 and "pass through" not in line
        assert f"strip-ribbon penetration {s['strip-ribbon penetration [mm]']:.2f} mm" in line


def test_fe_case_file(tmp_path, capsys):
    # --model fe --config: run keys and the FE gridshell's sections; the command line wins
    import argparse

    from lcefem.validation.app.commands import gridshell as cmd

    p = argparse.ArgumentParser()
    cmd.add_arguments(p)
    case = tmp_path / "fe.toml"
    case.write_text(
        '[run]\nrecipe = "wave"\nsymmetry = "full"\n[mesh]\nlevel = 2\n[supports]\ngravity = true\n'
    )
    cfg = cmd.prepare(p.parse_args(["--model", "fe", "--config", str(case), "--mesh-level", "1"]))
    assert (
        cfg.symmetry == "full" and cfg.model.mesh.level == 1 and cfg.model.supports.gravity is True
    )
    assert cfg.model.supports.kind == "centre_clamp" and cfg.notes == {"recipe": "wave"}
    case.write_text('[run]\nrecipe = "wave"\ncolour = "red"\n')
    assert (
        main(
            [
                "run",
                "gridshell",
                "--model",
                "fe",
                "--config",
                str(case),
                "--out",
                str(tmp_path / "o"),
            ]
        )
        == 2
    )
    assert "run.colour: not in an FE case file" in capsys.readouterr().err
