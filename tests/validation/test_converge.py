"""Convergence studies: observed order, flags, refinement-ratio check, ``lcefem converge``."""

import csv
import json
import math

import numpy as np
import pytest

from lcefem.validation import cases as case_registry
from lcefem.validation.app.cli import main as cli_main
from lcefem.validation.app.converge import analyse, ratio_warnings
from lcefem.validation.cases import Case, Metric

H = [0.4, 0.25, 0.16, 0.1, 0.0625]  # ratios 1.6


def test_second_order_sequence_gives_p_2():
    res = analyse(H, [1.0 + 0.3 * h**2 for h in H], "f", "-")
    assert res.p == pytest.approx(2.0, abs=1e-6)
    assert res.extrapolated == pytest.approx(1.0, abs=1e-9)
    assert all(p == pytest.approx(2.0, abs=1e-6) for p in res.triple_orders)
    assert res.flags == []


def test_oscillatory_sequence_is_flagged():
    # a second-order error whose sign alternates with the level
    vals = [1.0 + (-1) ** k * 0.3 * h**2 for k, h in enumerate(H)]
    res = analyse(H, vals)
    assert "oscillatory" in res.flags


def test_drifting_and_diverging_sequences_are_flagged():
    # pre-asymptotic: error = 0.05 h + h^3 changes its apparent order from about 2.6 towards 1
    for levels in (H, H[1:]):
        drift = analyse(levels, [1.0 + 0.05 * h + h**3 for h in levels])
        assert "drifting" in drift.flags and "oscillatory" not in drift.flags
    grow = analyse(H, [1.0 + 1.0 / h for h in H])  # moves away as the mesh is refined
    assert "diverging" in grow.flags


def test_mesh_independent_metric():
    res = analyse(H, [2.5] * len(H))
    assert res.flags == ["mesh-independent"] and res.gci_fine == 0.0


def test_refinement_ratio_below_1p3_is_reported():
    assert ratio_warnings(H) == []
    msgs = ratio_warnings([1.0, 0.5, 0.42, 0.2])
    assert len(msgs) == 1 and "levels 1 and 2" in msgs[0] and "1.190" in msgs[0]


def _quadrature_case(ctx):
    """Trapezoid rule for the integral of exp on [0, 1] (error ~ h^2/12 (e - 1))."""
    n = 4 * 2**ctx.level
    x = np.linspace(0.0, 1.0, n + 1)
    ctx.mesh_size = 1.0 / n
    ctx.mesh_size_unit = "-"
    y = np.exp(x)
    integral = float(np.sum(0.5 * (y[1:] + y[:-1])) / n)
    return [
        Metric.within("", "integral of exp", integral, "-", math.e - 1.0, 1e-2, "closed form e - 1")
    ]


@pytest.fixture
def quadrature_case(monkeypatch):
    monkeypatch.setitem(
        case_registry._CASES,
        "test_quadrature",
        Case("test_quadrature", _quadrature_case, "trapezoid rule", False, True),
    )
    monkeypatch.setitem(
        case_registry._CASES,
        "test_no_levels",
        Case("test_no_levels", _quadrature_case, "no levels", False, False),
    )


def test_converge_command_end_to_end(quadrature_case, tmp_path, capsys):
    out = tmp_path / "conv"
    assert (
        cli_main(["converge", "test_quadrature", "--levels", "4", "--out", str(out), "--quiet"])
        == 0
    )
    with (out / "gci.csv").open() as fh:
        row = next(csv.DictReader(fh))
    assert float(row["observed order p [-]"]) == pytest.approx(2.0, abs=1e-3)
    assert float(row["extrapolated value [unit]"]) == pytest.approx(math.e - 1.0, rel=1e-7)
    with (out / "levels.csv").open() as fh:
        header = next(csv.reader(fh))
    assert header == ["level [-]", "mesh size [-]", "integral of exp [-]"]
    data = json.loads((out / "convergence.json").read_text())
    assert data["mesh_sizes"] == [0.25, 0.125, 0.0625, 0.03125] and data["warnings"] == []
    assert (out / "convergence.png").stat().st_size > 10_000
    assert all((out / f"level{i}" / "metrics.json").is_file() for i in range(4))
    assert "GCI" in capsys.readouterr().out


def test_converge_bad_input_exits_2(quadrature_case, tmp_path, capsys):
    assert cli_main(["converge", "test_quadrature", "--levels", "3", "--out", str(tmp_path)]) == 2
    assert "--levels = 3: must be between 4 and 9" in capsys.readouterr().err
    assert cli_main(["converge", "test_no_levels", "--out", str(tmp_path)]) == 2
    assert "cases with levels: " in capsys.readouterr().err
    assert cli_main(["converge", "no_such_case", "--out", str(tmp_path)]) == 2


def test_converge_resume_reuses_complete_levels_only(quadrature_case, tmp_path, monkeypatch):
    out = tmp_path / "conv"
    assert (
        cli_main(["converge", "test_quadrature", "--levels", "4", "--out", str(out), "--quiet"])
        == 0
    )
    first = (out / "gci.csv").read_text()
    (out / "level3" / "metrics.json").unlink()  # level 3 interrupted: must run again
    calls = []

    def counting(ctx):
        calls.append(ctx.level)
        return _quadrature_case(ctx)

    monkeypatch.setitem(
        case_registry._CASES,
        "test_quadrature",
        Case("test_quadrature", counting, "trapezoid rule", False, True),
    )
    assert (
        cli_main(
            [
                "converge",
                "test_quadrature",
                "--levels",
                "4",
                "--out",
                str(out),
                "--quiet",
                "--resume",
            ]
        )
        == 0
    )
    assert calls == [3]
    assert (out / "gci.csv").read_text() == first


def test_converge_prolong_hands_each_level_the_previous_folder(
    quadrature_case, tmp_path, monkeypatch, capsys
):
    """--prolong: level 0 starts from scratch, level i > 0 gets level i - 1's folder (where that
    level wrote its state), and a case that cannot start from a coarser state is refused by name."""
    seen = []

    def recording(ctx):
        seen.append((ctx.level, ctx.prolong_from))
        if ctx.prolong_from is not None:  # the previous level has finished writing there
            assert (ctx.prolong_from / "state.txt").read_text() == str(ctx.level - 1)
        ctx.path("state.txt").write_text(str(ctx.level))
        return _quadrature_case(ctx)

    monkeypatch.setitem(
        case_registry._CASES,
        "test_prolong",
        Case("test_prolong", recording, "trapezoid rule", False, True, True),
    )
    out = tmp_path / "conv"
    assert (
        cli_main(
            ["converge", "test_prolong", "--levels", "4", "--prolong", "--out", str(out), "--quiet"]
        )
        == 0
    )
    assert seen == [(0, None)] + [(i, out.absolute() / f"level{i - 1}") for i in (1, 2, 3)]
    seen.clear()
    assert (
        cli_main(
            [
                "converge",
                "test_prolong",
                "--levels",
                "4",
                "--out",
                str(tmp_path / "plain"),
                "--quiet",
            ]
        )
        == 0
    )
    assert [p for _, p in seen] == [None] * 4  # without --prolong every level starts from scratch
    assert (
        cli_main(
            [
                "converge",
                "test_quadrature",
                "--levels",
                "4",
                "--prolong",
                "--out",
                str(tmp_path / "refused"),
            ]
        )
        == 2
    )
    assert "--prolong: case 'test_quadrature' cannot start" in capsys.readouterr().err
