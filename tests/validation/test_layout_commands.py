"""``--layout NAME|FILE`` of ``lcefem run gridshell`` and ``lcefem design``
(docs/layouts/index.md)."""

import json

import numpy as np
import pytest

from lcefem.validation.app.cli import main
from lcefem.validation.studies.design import gridshell_design as gd

RHOMBIC_1X1 = """[layout]
ribbons = 1
angle = 60.0
[layout.wiring]
bottom = ["B"]
top = ["T"]
"""


def test_design_on_a_rhombic_layout_with_its_own_wiring(tmp_path):
    """Two drive tags (every bottom strip, every top strip) on a one-junction 60 deg cross: a round
    target is reached (both families alike) and the forward run from as built ends on it."""
    case = tmp_path / "rh.toml"
    case.write_text(RHOMBIC_1X1)
    out = tmp_path / "d"
    assert (
        main(
            [
                "design",
                "--layout",
                str(case),
                "--target-kx",
                "-0.01",
                "--target-ky",
                "-0.01",
                "--quiet",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    s = json.loads((out / "summary.json").read_text())
    assert set(s["lambdas [-]"]) == {"bottom", "top"}
    assert s["residual norm [1/mm]"] <= gd.REACHED
    # reached from flat by the run's own path with constant lambdas
    # (lcefem.validation.studies.design.gridshell_design.reach)
    assert s["reach"]["kind"] == "constant"
    rows = np.loadtxt(out / "design.csv", delimiter=",", skiprows=1)
    assert rows.shape == (2, 4)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["run", "gridshell", "--layout", "square"], "--layout = 'square': a name (published, 5x5"),
        (["run", "gridshell", "--layout", "5x5", "--ribbons", "3"], "--ribbons: not with --layout"),
        (
            [
                "run",
                "gridshell",
                "--layout",
                "hexagonal",
                "--lambda",
                "B=1.3",
                "--support",
                "table",
            ],
            "support = 'table': a hexagonal grid is held by clamp",
        ),
        (
            ["run", "gridshell", "--layout", "triangular", "--lambda", "B=1.3"],
            "support = 'rollers': a triangular grid is held by clamp, table",
        ),
        (
            ["design", "--layout", "5x5", "--ribbons", "5", "--target-kx", "0", "--target-ky", "0"],
            "--ribbons: not with --layout",
        ),
    ],
)
def test_bad_layouts_exit_2_with_one_line(tmp_path, capsys, argv, message):
    assert main([*argv, "--quiet", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "o" / "summary.json").exists()


def test_run_gridshell_with_a_layout_file(tmp_path):
    """The case file's [layout] (here a rhombic cross, clamp from the layout) reaches the run: its
    summary records the layout and the support."""
    case = tmp_path / "rh.toml"
    case.write_text(RHOMBIC_1X1.replace("angle = 60.0\n", 'angle = 60.0\nsupport = "clamp"\n'))
    out = tmp_path / "g"
    assert (
        main(
            [
                "run",
                "gridshell",
                "--layout",
                str(case),
                "--lambda",
                "bottom=1.3",
                "--quiet",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    s = json.loads((out / "summary.json").read_text())
    assert s["support"] == "clamp"
    assert s["config"]["layout"]["kind"]["value"] == "rhombic"
    assert s["results"]["z_range [mm]"] > 0.5
