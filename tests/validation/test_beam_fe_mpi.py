"""The FE composite beam from the command line under ``mpiexec -n 2`` gives the serial answer
(issues 46, 48): the lambda ramp and the coil-current route, level 0, 2 segments. The curvature
stations (composite_beam.BeamStations) take each point from the rank owning its node and combine
them with one allreduce; the strip-ribbon contact runs on N ranks (solvers/contact.py)."""

import csv
import json
import subprocess

import pytest

#: 2 segments, level 0 (the golden beam of tests/regression/test_golden.py): the ramp to (1.33,
#: 1.05) and 2 s of 0.2 A in the bottom strips (ex02's run, shortened)
ROUTES = {
    "lambda": ["--lambda-top", "1.33", "--lambda-bottom", "1.05"],
    "current": ["--current", "0.2", "--heated", "bottom", "--duration", "2"],
}

#: 2 ranks against serial: the same Newton iterates up to the factorisations' round-off (measured
#: 2026-12-07, level 0: the ramp, 4 segments, 1.5e-13 relative; 0.2 A for 3 s, 2 segments, 3.5e-11:
#: each time step's Newton stops after 2 iterations at the 1e-7 N residual, which keeps more of
#: the round-off)
RTOL = 1e-10
#: history.csv keeps 10 significant digits: round-off can flip the last one (measured: one row's
#: curvature 0.0004267525734 serial, ...735 on 2 ranks)
ROW_RTOL = 2e-9


def _run(cmd, out, route, ranks, mpiexec):
    argv = ["run", "beam", "--model", "fe", "--mesh-level", "0", "--segments", "2", "--quiet"]
    launcher = [mpiexec, "-n", str(ranks)] if ranks > 1 else []
    done = subprocess.run(
        [*launcher, *cmd, *argv, *ROUTES[route], "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("lcefem: beam (fe)"), done.stdout  # rank 0's
    with open(out / "history.csv") as fh:
        rows = list(csv.DictReader(fh))
    return json.loads((out / "summary.json").read_text()), rows


@pytest.mark.mpi
@pytest.mark.slow
@pytest.mark.parametrize("route", sorted(ROUTES))
def test_fe_beam_on_two_ranks_gives_the_serial_curvature(route, tmp_path, lcefem_cmd, mpiexec):
    serial, s_rows = _run(lcefem_cmd, tmp_path / "serial", route, 1, mpiexec)
    two, p_rows = _run(lcefem_cmd, tmp_path / "two", route, 2, mpiexec)
    assert serial["ranks"] == 1 and two["ranks"] == 2 and two["status"] == "completed"
    kappa = serial["results"]["curvature [1/mm]"]
    # bent towards the shorter (bottom) strips, Eq. 2's sign (measured: 0.0247 and 8.6e-5 1/mm)
    assert kappa > 1e-5
    assert two["results"]["curvature [1/mm]"] == pytest.approx(kappa, rel=RTOL)
    # the same accepted path: load factors or times, curvatures, temperatures, contact row by row
    assert len(p_rows) == len(s_rows) > 2
    for s, p in zip(s_rows, p_rows):
        for key, value in s.items():
            assert float(p[key]) == pytest.approx(float(value), rel=ROW_RTOL, abs=1e-15), key
    # rank 0 draws the side view from the gathered nodes; the pyvista render is serial only
    assert (tmp_path / "two" / "beam_fe.png").is_file()
    if route == "lambda":
        assert (tmp_path / "serial" / "beam_fe_3d.png").is_file()
        assert not (tmp_path / "two" / "beam_fe_3d.png").exists()
    assert not list((tmp_path / "two").glob("*.part*"))
