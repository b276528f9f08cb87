"""``mpiexec -n 2 lcefem converge``: the levels farmed over the ranks give the serial study, both
ranks take levels, and a level that fails ends the study with its error on every rank."""

import csv
import subprocess
import sys

import pytest

#: A convergence case registered before the CLI loads the real ones: the trapezoid rule for the
#: integral of exp on [0, 1] (error ~ h^2 (e - 1)/12), 0.5 s per level so that both ranks get work;
#: with FAIL_LEVEL set, that level raises a ConvergenceError.
SCRIPT = """
import math, sys, time
import numpy as np
from lcefem.models.errors import ConvergenceError
from lcefem.validation import cases
from lcefem.validation.cases import Case, Metric
from lcefem.validation.app.cli import main

FAIL_LEVEL = int(sys.argv[2])

def trapezoid(ctx):
    time.sleep(0.5)
    if ctx.level == FAIL_LEVEL:
        raise ConvergenceError("trapezoid", f"made to fail at level {ctx.level}")
    n = 4 * 2 ** ctx.level
    x = np.linspace(0.0, 1.0, n + 1)
    ctx.mesh_size, ctx.mesh_size_unit = 1.0 / n, "-"
    y = np.exp(x)
    integral = float(np.sum(0.5 * (y[1:] + y[:-1])) / n)
    return [Metric.info("", "integral of exp", integral, "-", "trapezoid")]

cases._CASES["test_trapezoid"] = Case("test_trapezoid", trapezoid, "trapezoid rule", False, True)
sys.exit(main(["converge", "test_trapezoid", "--levels", "4", "--out", sys.argv[1], "--quiet"]))
"""


def _converge(prefix, script, out, fail_level=-1):
    return subprocess.run(
        prefix + [sys.executable, str(script), str(out), str(fail_level)],
        capture_output=True,
        text=True,
        timeout=300,
    )


def _rows(path):
    with path.open() as fh:
        return list(csv.reader(fh))


@pytest.mark.mpi
def test_farmed_levels_give_the_serial_study(serial_and_two_ranks, tmp_path):
    import json

    script = tmp_path / "trapezoid.py"
    script.write_text(SCRIPT)
    runs = serial_and_two_ranks([sys.executable, script, "{out}", "-1"], timeout=300)
    serial, farmed = (r.out for r in runs)
    for name in ("levels.csv", "gci.csv"):
        assert _rows(farmed / name) == _rows(serial / name)
    p = float(
        _rows(farmed / "gci.csv")[1][_rows(farmed / "gci.csv")[0].index("observed order p [-]")]
    )
    assert p == pytest.approx(2.0, abs=1e-3)  # the trapezoid rule's order
    ranks = {
        json.loads((farmed / f"level{i}" / "metrics.json").read_text())["rank"] for i in range(4)
    }
    assert ranks == {0, 1}


@pytest.mark.mpi
def test_a_failed_level_ends_the_farmed_study_with_its_error(mpiexec, tmp_path):
    script = tmp_path / "trapezoid.py"
    script.write_text(SCRIPT)
    res = _converge([mpiexec, "-n", "2"], script, tmp_path / "out", fail_level=2)
    assert res.returncode == 3, res.stderr[-3000:]  # EXIT_SOLVER, as the serial study
    assert "level 2" in res.stderr and "made to fail" in res.stderr
    assert not (tmp_path / "out" / "gci.csv").exists()
    assert (tmp_path / "out" / "level2" / "error.log").is_file()
