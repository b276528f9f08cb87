"""The catalogue of issue 10: every way a run can go wrong ends in one line, a documented exit
status and an output folder that says what happened (lcefem.solvers.runtime, through the command
line).

Exit statuses: 2 bad input or unusable --out, 3 solver failure or a result out of physical bounds,
130 Ctrl-C, 143 SIGTERM. Fast targets only: the bar-and-hinge beam (2 segments), the rod ribbon, and
the strip at mesh level 0.
"""

import json
import os
import signal
import socket
import subprocess
import sys
import time

import pytest

from lcefem.validation.app.cli import main as cli_main

BEAM = [
    "run",
    "beam",
    "--segments",
    "2",
    "--lambda-top",
    "1.38",
    "--quiet",
]  # 2 s bar-and-hinge run
STRIP = ["run", "strip", "--mesh-level", "0", "--quiet", "--no-fields"]
LOCK = ".lcefem.lock"


def lcefem(cmd, *args, cwd=None, mpi=None):
    prefix = [mpi, "-n", "2"] if mpi else []
    return subprocess.run(
        prefix + cmd + [str(a) for a in args], capture_output=True, text=True, timeout=300, cwd=cwd
    )


def one_line(res) -> str:
    err = res if isinstance(res, str) else res.stderr
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


def cli(capsys, *args) -> tuple[int, str]:
    """``lcefem ARGS`` in this process (no interpreter start-up): (exit status, stderr)."""
    capsys.readouterr()
    try:
        code = cli_main([str(a) for a in args])
    except SystemExit as exc:  # argparse
        code = exc.code
    return code, capsys.readouterr().err


def results(out) -> set[str]:
    return {p.name for p in out.iterdir() if not p.name.startswith(".")} if out.exists() else set()


@pytest.fixture(scope="module")
def finished_beam(tmp_path_factory):
    """A completed bar-and-hinge beam run (its summary.json) to reuse the out folder of."""
    out = tmp_path_factory.mktemp("beam") / "done"
    assert cli_main([*BEAM, "--out", str(out)]) == 0
    return out


# -- 1. ownership of the out folder -------------------------------------------------------------
def test_second_run_into_a_used_folder_is_refused_and_changes_nothing(finished_beam, capsys):
    before = (finished_beam / "summary.json").read_text()
    code, err = cli(capsys, *BEAM, "--lambda-top", "1.35", "--out", finished_beam)
    assert code == 2
    assert f"--out = '{finished_beam}': holds the results of another run" in one_line(err)
    assert "--overwrite" in one_line(err)
    assert (finished_beam / "summary.json").read_text() == before
    assert not (finished_beam / LOCK).exists()


def test_overwrite_replaces_the_earlier_run_and_its_stale_files(finished_beam, capsys, tmp_path):
    out = tmp_path / "again"
    subprocess.run(["cp", "-r", str(finished_beam), str(out)], check=True)
    (out / "failure.json").write_text('{"status": "failed"}')  # an earlier run's state
    code, err = cli(capsys, *BEAM, "--lambda-top", "1.35", "--out", out, "--overwrite")
    assert code == 0, err
    assert not (out / "failure.json").exists()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["config"]["run"]["lambda_top"]["value"] == 1.35


def test_overwrite_never_empties_a_folder_lcefem_did_not_write(capsys, tmp_path):
    (tmp_path / "thesis.tex").write_text("precious")
    code, err = cli(capsys, *BEAM, "--out", tmp_path, "--overwrite")
    assert code == 2 and "holds files not written by lcefem" in one_line(err)
    assert (tmp_path / "thesis.tex").read_text() == "precious"


def test_a_folder_locked_by_a_live_run_is_refused(capsys, tmp_path):
    out = tmp_path / "busy"
    out.mkdir()
    (out / LOCK).write_text(f"{os.getppid()} {socket.gethostname()}\n")  # pytest's parent is alive
    code, err = cli(capsys, *BEAM, "--out", out)
    assert code == 2
    assert f"--out = '{out}': in use by another lcefem run (pid {os.getppid()}" in one_line(err)
    assert results(out) == set()


def test_the_lock_of_a_killed_run_is_taken_over(capsys, tmp_path):
    out = tmp_path / "stale"
    out.mkdir()
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    ).stdout.strip()
    (out / LOCK).write_text(f"{dead} {socket.gethostname()}\n")
    code, err = cli(capsys, *BEAM, "--out", out)
    assert code == 0, err
    assert "summary.json" in results(out) and not (out / LOCK).exists()


def test_two_concurrent_runs_one_is_refused(lcefem_cmd, capsys, tmp_path):
    out = tmp_path / "race"
    first = subprocess.Popen(
        lcefem_cmd
        + ["run", "ribbon", "--duration", "1", "--nodes", "20", "--quiet", "--out", str(out)],
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        _wait_for(lambda: (out / LOCK).exists())
        code, err = cli(capsys, *BEAM, "--out", out)
        assert code == 2
        assert f"--out = '{out}': in use by another lcefem run (pid {first.pid}" in one_line(err)
    finally:
        assert first.wait(timeout=120) == 0, first.stderr.read()
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


# -- 2. physical bounds of inputs ---------------------------------------------------------------
BAD_INPUTS = [
    (STRIP + ["--current", "1e200"], "run.current = 1e+200: must be <= 1.0 A"),
    (STRIP + ["--current", "-0.1"], "run.current = -0.1: must be >= 0.0 A"),
    (STRIP + ["--duration", "1e6"], "run.duration = 1000000.0 s: must be <= 3600.0 s"),
    (STRIP + ["--mesh-level", "1.5"], "argument --mesh-level: invalid int value: '1.5'"),
    (["run", "strip", "--quiet", "--config", "{case}"], "mesh.level = 1.5: must be an integer"),
    (
        ["run", "ribbon", "--quiet", "--config", "{case}"],
        "air.ambient_temperature = -400 C: must be > -273.15 C (absolute zero) and < 300 C "
        "(decomposition",
    ),
    (
        ["run", "ribbon", "--quiet", "--config", "{case}"],
        "material.T_NI = 500 C: must be > -273.15 C (absolute zero) and < 300 C (decomposition",
    ),
    (BEAM + ["--config", "{case}"], "kapton.youngs_modulus = 0.0"),
    (["run", "ribbon", "--quiet", "--ground-temperature", "450"], "run.ground_temperature = 450.0"),
]
CASE_FILES = {
    4: "[mesh]\nlevel = 1.5\n",
    5: "[air]\nambient_temperature = -400.0\n",
    6: "[material]\nT_NI = 500.0\n",
    7: "[kapton]\nyoungs_modulus = 0.0\n",
}


@pytest.mark.parametrize("i", range(len(BAD_INPUTS)))
def test_unphysical_input_one_line_exit_2_and_no_folder(i, capsys, tmp_path):
    argv, message = BAD_INPUTS[i]
    case = tmp_path / "case.toml"
    case.write_text(CASE_FILES.get(i, ""))
    out = tmp_path / "out"
    code, err = cli(capsys, *[a.replace("{case}", str(case)) for a in argv], "--out", out)
    assert code == 2
    assert message in one_line(err)
    assert not out.exists()  # bad input leaves no trace


def test_bad_petsc_option_is_one_line_exit_2(lcefem_cmd, tmp_path):
    """(Its own process: the rejected option would stay in this process's PETSc options
    database.)"""
    case = tmp_path / "case.toml"
    case.write_text('[petsc]\nsnes_type = "no_such_solver"\n')
    res = lcefem(lcefem_cmd, *STRIP, "--config", case, "--out", tmp_path / "out")
    # refused by the allow-list of case-file options (issue 45), before PETSc sees it
    assert (
        res.returncode == 2
        and "[petsc] snes_type = 'no_such_solver': must be one of" in one_line(res)
    )
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "command",
    [
        BEAM,
        ["validate", "tension_law", "--quick", "--quiet"],
        ["converge", "rod_closed_forms", "--quiet"],
    ],
)
@pytest.mark.parametrize("kind", ["empty", "file", "under a file"])
def test_unusable_out_one_line_exit_2(command, kind, capsys, tmp_path):
    (tmp_path / "f").write_text("not a folder")
    out = {"empty": "", "file": tmp_path / "f", "under a file": tmp_path / "f" / "sub"}[kind]
    code, err = cli(capsys, *command, "--out", out)
    assert code == 2
    expected = {
        "empty": "--out = '': must name a folder",
        "file": "is a file, not a folder",
        "under a file": "cannot write there",
    }[kind]
    assert expected in one_line(err)
    assert (tmp_path / "f").read_text() == "not a folder"


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_out_one_line_exit_2(capsys, tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir(mode=0o555)
    code, err = cli(capsys, *BEAM, "--out", ro / "out")
    assert code == 2 and "cannot write there" in one_line(err)


def test_full_disk_during_a_run_one_line_exit_2_and_partial_files(capsys, tmp_path, monkeypatch):
    """The disk fills after two rows of history: one line naming the file, converged rows kept as
    partial, no failure.json (not a physics failure), no summary."""
    import errno

    from lcefem.solvers.runtime.files import CSVTable

    append = CSVTable.append

    def filling(self, row):
        if len(self.rows) == 2 and self.path is not None:
            raise OSError(errno.ENOSPC, "No space left on device", str(self.path) + ".part")
        append(self, row)

    monkeypatch.setattr(CSVTable, "append", filling)
    out = tmp_path / "full"
    code, err = cli(capsys, *BEAM, "--out", out)
    assert code == 2
    assert (
        f"cannot write '{out / 'history.csv.part'}': no space left on the device (ENOSPC)"
        in one_line(err)
    )
    assert {"history.partial.csv", "beam_steps.partial", "beam.partial.pvd"} == results(out)
    assert len((out / "history.partial.csv").read_text().splitlines()) == 3  # header + 2 rows


# -- 2b. physical bounds of results -------------------------------------------------------------
def test_result_above_decomposition_stops_with_exit_3_and_keeps_converged_steps(capsys, tmp_path):
    """1 A (5 x the experiments) heats the coil past 300 C within the first 1 s step."""
    out = tmp_path / "hot"
    code, err = cli(capsys, *STRIP, "--current", "1", "--duration", "4", "--dt", "1", "--out", out)
    assert code == 3
    line = one_line(err)
    assert "result out of physical bounds at t = 1 s: T_max [C] = " in line and "< 300 C" in line
    assert results(out) == {"failure.json", "history.partial.csv"}
    failure = json.loads((out / "failure.json").read_text())
    assert (
        failure["kind"] == "out of physical bounds" and failure["last_converged"]["time [s]"] == 0.0
    )


# -- 3. Ctrl-C and SIGTERM ----------------------------------------------------------------------
def _wait_for(condition, timeout=120.0):
    end = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < end, "timed out"
        time.sleep(0.2)


def _rows(path) -> int:
    return len(path.read_text().splitlines()) - 1 if path.exists() else 0


def _interrupt_strip(cmd, out, sig):
    """Start a long strip run, let it converge two steps, send ``sig``; returns the process
    result."""
    proc = subprocess.Popen(
        cmd + STRIP + ["--duration", "3000", "--dt", "1", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for(lambda: _rows(out / "history.csv.part") >= 3)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupt_keeps_converged_steps_and_is_not_a_failure(sig, code, lcefem_cmd, tmp_path):
    out = tmp_path / "int"
    rc, err = _interrupt_strip(lcefem_cmd, out, sig)
    assert rc == code, err
    assert "interrupted" in err and "no convergence" not in err and "Traceback" not in err
    assert results(out) == {"history.partial.csv"}  # no failure.json, nothing .part or complete
    assert _rows(out / "history.partial.csv") >= 3
    assert not (out / LOCK).exists()


@pytest.mark.mpi
def test_ctrl_c_under_mpiexec_stops_every_rank(lcefem_cmd, mpiexec, tmp_path):
    out = tmp_path / "int"
    rc, err = _interrupt_strip([mpiexec, "-n", "2"] + lcefem_cmd, out, signal.SIGINT)
    assert rc == 130, err
    assert err.count("lcefem: interrupted") == 1  # printed once, by rank 0
    assert results(out) == {"history.partial.csv"}


@pytest.mark.mpi
@pytest.mark.parametrize(
    "argv, message",
    [
        (STRIP + ["--current", "1e200"], "run.current = 1e+200: must be <= 1.0 A"),
        (STRIP + ["--mesh-level", "1.5"], "invalid int value: '1.5'"),
        (STRIP + ["--out", ""], "--out = '': must name a folder"),
    ],
)
def test_bad_input_under_mpiexec_one_line_exit_2(argv, message, lcefem_cmd, mpiexec, tmp_path):
    res = lcefem(
        lcefem_cmd, *argv, *([] if "--out" in argv else ["--out", tmp_path / "o"]), mpi=mpiexec
    )
    assert res.returncode == 2 and message in one_line(res)


ONE_RANK_FAILS = """
import dolfinx_solver  # noqa: F401
from mpi4py import MPI

from lcefem.validation.app import cli

comm = MPI.COMM_WORLD
cli._ERRORS = comm.Dup()
if comm.rank == 1:
    raise SystemExit(cli._end(2, "lcefem: error: only rank 1 saw this", comm))
comm.barrier()  # rank 0 waits in a collective, as inside a solver: never matched
"""


@pytest.mark.mpi
def test_an_error_on_one_rank_aborts_every_rank(mpiexec, tmp_path):
    """The command line's exit path: a rank that fails alone aborts the others instead of
    hanging."""
    script = tmp_path / "one_rank_fails.py"
    script.write_text(ONE_RANK_FAILS)
    res = subprocess.run(
        [mpiexec, "-n", "2", sys.executable, str(script)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert res.returncode == 2
    # Only the failing rank prints, with its rank. Distinct lines: under load MPICH's launcher has
    # been seen to forward the aborting rank's stderr twice (the MPI_Abort notice repeated with it).
    lines = {line for line in res.stderr.splitlines() if "only rank 1 saw this" in line}
    assert lines == {"lcefem: error: only rank 1 saw this [rank 1; aborting the other ranks]"}


@pytest.mark.mpi
@pytest.mark.parametrize("argv", [["run", "ribbon"], BEAM])
def test_serial_only_target_refuses_mpiexec(argv, lcefem_cmd, mpiexec, tmp_path):
    res = lcefem(lcefem_cmd, *argv, "--out", tmp_path / "o", mpi=mpiexec)
    assert res.returncode == 2 and "runs in serial only" in one_line(res)
    assert not (tmp_path / "o").exists()


def test_interrupted_validate_stops_and_reports_every_case(lcefem_cmd, tmp_path):
    """Ctrl-C during the first case: validate stops (the second case never starts), and the report
    lists both cases with their state and says it is incomplete."""
    out = tmp_path / "v"
    proc = subprocess.Popen(
        lcefem_cmd
        + [
            "validate",
            "strip_transient_0p2A",
            "tension_law",
            "--quick",
            "--quiet",
            "--out",
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for(lambda: any((out / "strip_transient_0p2A").glob("**/history.csv.part")))
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert not (out / "tension_law").exists()
    report = (out / "report.md").read_text()
    assert (
        "| strip_transient_0p2A | interrupted |" in report and "| tension_law | not run |" in report
    )
    assert "INCOMPLETE" in report
    assert not list(out.rglob("failure.json")) and not list(out.rglob("*.part"))


# -- 8. the .part convention for the rod ribbon's VTK frames ------------------------------------
def test_interrupted_ribbon_leaves_only_partial_frames(lcefem_cmd, tmp_path):
    out = tmp_path / "rib"
    proc = subprocess.Popen(
        lcefem_cmd
        + ["run", "ribbon", "--duration", "60", "--nodes", "20", "--quiet", "--out", str(out)],
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for(lambda: len(list((out / "centerline_steps.part").glob("*.vtp"))) >= 2)
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=60) == 143, proc.stderr.read()
    assert results(out) == {
        "centerline_steps.partial",
        "surface_steps.partial",
        "centerline.partial.pvd",
        "surface.partial.pvd",
        "history.partial.csv",
        "centroid.partial.csv",
    }
    assert not list(out.rglob("*.part"))


def test_a_reader_closing_the_pipe_ends_the_listing_quietly(lcefem_cmd):
    """`lcefem validate --list | head -1`: the closed pipe stops lcefem as it stops a Unix tool
    (status 141 = 128 + SIGPIPE), without PETSc's signal handler aborting MPI with a crash report.
    The reader is gone before lcefem writes (a listing fits in the pipe's buffer otherwise)."""
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        proc = subprocess.run(
            [*lcefem_cmd, "validate", "--list"],
            stdout=write_end,
            stderr=subprocess.PIPE,
            timeout=120,
        )
    finally:
        os.close(write_end)
    err = proc.stderr.decode()
    assert proc.returncode == 141, err
    assert "PETSC ERROR" not in err and "Traceback" not in err, err


def test_a_signal_wrapped_in_a_library_error_is_an_interrupt_not_a_case_error(
    tmp_path, monkeypatch
):
    """numba's compiler turns a SIGTERM that arrives while it compiles a kernel into a RuntimeError
    (seen in ribbon_twist_density): the case is reported interrupted, with no error.log."""
    from lcefem.solvers import interrupts
    from lcefem.validation.app.validate import _run_or_reuse
    from lcefem.validation.cases import Case

    def compiling(ctx):
        interrupts.received.append(signal.SIGTERM)  # what the handler records before raising
        try:
            raise interrupts.Terminated()
        except KeyboardInterrupt as exc:
            raise RuntimeError("no compiled object yet") from exc

    monkeypatch.setattr(interrupts, "received", [])
    case = Case(
        "wrapped_signal", compiling, "raises a wrapped SIGTERM", fe=False, convergence=False
    )
    result = _run_or_reuse(case, tmp_path, quick=True, resume=False, quiet=True)
    assert result.status == "interrupted" and isinstance(result.interrupt, interrupts.Terminated)
    assert not (tmp_path / "wrapped_signal" / "error.log").exists()


def test_a_wrapped_signal_ends_a_command_with_the_signal_status(monkeypatch):
    """The same wrapped SIGTERM ending `lcefem run ...` exits 143 with the interrupt line, not as a
    bug (status 1 and a traceback)."""
    from lcefem.solvers import interrupts
    from lcefem.validation.app.cli import _classify

    monkeypatch.setattr(interrupts, "received", [signal.SIGTERM])
    code, message = _classify(RuntimeError("no compiled object yet"))
    assert code == 143 and message.startswith("lcefem: interrupted (SIGTERM)")
    monkeypatch.setattr(interrupts, "received", [])
    assert _classify(RuntimeError("a bug"))[0] == 1
