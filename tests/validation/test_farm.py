"""``mpiexec -n 2 lcefem validate``: the cases farmed over the ranks give the serial run's answers,
files and exit status (issue 13); the hand-out order and the affinity groups."""

import json
import shutil
import signal
import subprocess
import sys
import time

import pytest

from lcefem.validation.app import farm
from lcefem.validation.cases import AFFINITY, registry

#: Cheap quick cases: a rod closed form (numba), the tension law, two FE cases (a strip in tension,
#: the heat solver's manufactured solution) and an affinity group (both share the 100 C ribbon run).
CASES = [
    "rod_closed_forms",
    "tension_law",
    "strip_isotropic_tension",
    "verification_heat_mms",
    "ribbon_end_spin",
    "ribbon_helical",
]


def _validate(prefix, lcefem_cmd, out, *cases):
    return subprocess.run(
        prefix + lcefem_cmd + ["validate", *cases, "--quick", "--quiet", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=900,
    )


def _markers(out) -> dict:
    return {c: json.loads((out / c / "metrics.json").read_text()) for c in CASES}


@pytest.fixture(scope="module")
def serial_and_farmed(tmp_path_factory):
    """The same quick cases run serially and farmed over 2 ranks: the two out folders."""
    from tests.conftest import VENV_BIN, run_serial_and_two_ranks

    argv = [str(VENV_BIN / "lcefem"), "validate", *CASES, "--quick", "--quiet", "--out", "{out}"]
    runs = run_serial_and_two_ranks(argv, tmp_path_factory.mktemp("farm"))
    return tuple(r.out for r in runs)


@pytest.mark.mpi
@pytest.mark.slow
def test_farmed_run_gives_the_serial_metrics(serial_and_farmed):
    """Each case runs whole on one rank's MPI.COMM_SELF, so its arithmetic is the serial one: every
    metrics.json row equal (values bit for bit), every case done, and both ranks did work."""
    serial, farmed = serial_and_farmed
    assert json.loads((farmed / "metrics.json").read_text()) == json.loads(
        (serial / "metrics.json").read_text()
    )
    s, f = _markers(serial), _markers(farmed)
    assert (
        {c: m["status"] for c, m in f.items()}
        == {c: m["status"] for c, m in s.items()}
        == dict.fromkeys(CASES, "done")
    )
    assert {m["rank"] for m in f.values()} == {0, 1}
    assert {m["rank"] for m in s.values()} == {None}
    report = (farmed / "report.md").read_text()
    assert "on 2 MPI ranks" in report and "INCOMPLETE" not in report


@pytest.mark.mpi
@pytest.mark.slow
def test_an_affinity_group_stays_on_one_rank(serial_and_farmed):
    """ribbon_end_spin and ribbon_helical share the 100 C ribbon run (validation/cases/ribbon.py
    _RUNS): one rank runs both, in the serial order, so the run is made once (the second case runs
    only its own helical ribbon: less time than the first, which also made the shared run)."""
    _, farmed = serial_and_farmed
    f = _markers(farmed)
    assert f["ribbon_end_spin"]["rank"] == f["ribbon_helical"]["rank"]
    assert f["ribbon_helical"]["wall_time"] < f["ribbon_end_spin"]["wall_time"]


@pytest.mark.mpi
@pytest.mark.slow
def test_resume_of_a_farmed_run_runs_only_what_is_missing(
    serial_and_farmed, tmp_path, lcefem_cmd, mpiexec
):
    """--resume under mpiexec reuses the complete cases of a farmed run (their markers) and reruns
    the one whose marker is gone: the serial answers again."""
    serial, farmed = serial_and_farmed
    out = tmp_path / "v"
    shutil.copytree(farmed, out)
    (out / "tension_law" / "metrics.json").unlink()
    res = _validate([mpiexec, "-n", "2"], lcefem_cmd, out, *CASES, "--resume")
    assert res.returncode == 0, res.stderr[-3000:]
    assert {m["status"] for m in _markers(out).values()} == {
        "done"
    }  # a marker records the run that made it
    report = (out / "report.md").read_text()
    assert "| tension_law | done |" in report and "| rod_closed_forms | reused |" in report
    assert json.loads((out / "metrics.json").read_text()) == json.loads(
        (serial / "metrics.json").read_text()
    )


ONE_RANK_PETSC = """
import sys
from lcefem.validation.app import farm
farm.petsc_world_per_rank()
from mpi4py import MPI
from petsc4py import PETSc
if MPI.COMM_WORLD.rank == 0:  # a case on rank 0 makes a PETSc object without naming a communicator
    ksp = PETSc.KSP().create()
    A = PETSc.Mat().createAIJ([4, 4])
    A.setUp()
    A.assemble()
    sys.stdout.write(f"{ksp.getComm().getSize()} {A.getComm().getSize()}")
"""


@pytest.mark.mpi
def test_petsc_objects_of_one_rank_never_wait_for_the_other(mpiexec, tmp_path):
    """Farmed ranks run different cases: a PETSc object made on one rank only, without a
    communicator (PETSc's world by default), and PETSc's exit clean-up must not wait for the other
    rank. With COMM_WORLD as PETSc's world this script hangs at exit (seen in a farmed make
    validate-quick: rank 0 in petsc4py's garbage_cleanup, rank 1 in MPI_Finalize); with each rank's
    own world it ends, and the objects live on one rank."""
    script = tmp_path / "one_rank_petsc.py"
    script.write_text(ONE_RANK_PETSC)
    res = subprocess.run(
        [mpiexec, "-n", "2", sys.executable, str(script)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 0, res.stderr[-3000:]
    assert res.stdout == "1 1"


@pytest.mark.mpi
def test_an_interrupted_farm_stops_every_rank_and_leaves_nothing_complete(
    lcefem_cmd, mpiexec, tmp_path
):
    """SIGTERM to mpiexec while both ranks run a strip: exit 143, both cases reported interrupted,
    the rest not run, the report says INCOMPLETE; no completion marker, no *.part, no
    failure.json."""
    out = tmp_path / "v"
    cases = ["strip_transient_0p2A", "strip_transient_0p1A", "tension_law", "rod_closed_forms"]
    proc = subprocess.Popen(
        [mpiexec, "-n", "2"]
        + lcefem_cmd
        + ["validate", *cases, "--quick", "--quiet", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    end = time.monotonic() + 300
    while (
        len(list(out.glob("strip_transient_*/**/history.csv.part"))) < 2
    ):  # both ranks inside a case
        assert time.monotonic() < end and proc.poll() is None, (
            "the two strips never ran side by side"
        )
        time.sleep(0.2)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    # the dispatcher thread ended before its communicator was freed (issue 45)
    assert "Null communicator" not in err and "lcefem-farm" not in err and "Traceback" not in err, (
        err
    )
    report = (out / "report.md").read_text()
    assert (
        "| strip_transient_0p2A | interrupted |" in report
        and "| strip_transient_0p1A | interrupted |" in report
    )
    assert "| tension_law | not run |" in report and "INCOMPLETE" in report
    assert not list(out.glob("*/metrics.json"))
    assert not list(out.rglob("*.part")) and not list(out.rglob("failure.json"))


def test_groups_are_handed_out_largest_first_and_stay_whole():
    """schedule: the affinity groups' members together, in the given order; groups sorted by summed
    cost, a case without a cost (a new case) first; makespan: list scheduling over the ranks."""
    cases = list(registry().values())
    costs = farm.case_costs(False)
    groups = farm.schedule(
        cases, lambda c: 1e9 if c.name == "tension_law" else costs.get(c.name, 0.0)
    )
    names = [[cases[i].name for i in g] for g in groups]
    assert names[0] == ["tension_law"]
    for members in AFFINITY.values():
        assert [cases[i].name for g in groups for i in g if cases[i].name in members] == list(
            members
        )
        assert list(members) in names
    total = [sum(costs.get(n, 0.0) for n in g) for g in names[1:]]
    assert total == sorted(total, reverse=True)
    assert farm.makespan([5.0, 4.0, 3.0, 3.0, 1.0], 2) == (8.0, [8.0, 8.0])


def test_cost_table_and_affinity_groups_name_registered_cases():
    """A renamed case must not leave its cost or its group behind (it would lose its place in the
    queue or its shared run)."""
    known = set(registry())
    for quick in (False, True):
        assert set(farm.case_costs(quick)) <= known
    assert {n for members in AFFINITY.values() for n in members} <= known
