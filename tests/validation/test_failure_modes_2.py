"""The second catalogue (issue 36): work that cannot fit, encodings, signals, full disks, folder
rules, ignored inputs. Each ends in one line, a documented exit status (docs/failure_modes.md) and
an output folder that says what happened. In-process where possible
(lcefem.validation.app.cli.main); the option values are refused in argument checking, before any
output folder is claimed (checked by a claim that fails the test instead of running).
"""

import errno
import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from lcefem.models.errors import ConvergenceError
from lcefem.solvers import cost
from lcefem.solvers.interrupts import Terminated
from lcefem.solvers.runtime.files import CSVTable, library_os_error, write_text
from lcefem.solvers.runtime.outdir import STAMP_TEXT, stamped_command
from lcefem.validation.app import cli as cli_module
from lcefem.validation.app.cli import main as cli_main

# The first catalogue's helpers: the same in-process command line, one-line check and folder
# listing.
from tests.validation.test_failure_modes import (  # noqa: E402
    BEAM,
    LOCK,
    STRIP,
    cli,
    one_line,
    results,
)

# -- 1. every option of every command with nonsense values: refused in argument checking --------
OPTIONS = {
    "run strip": [
        "--current",
        "--duration",
        "--dt",
        "--tip-load",
        "--mesh-level",
        "--mesh-size",
        "--resistance",
    ],
    "run ribbon": [
        "--ground-temperature",
        "--twist-density",
        "--duration",
        "--nodes",
        "--dt",
        "--error-tolerance",
        "--helix-radius",
    ],
    "run beam": ["--lambda-top", "--lambda-bottom", "--segments", "--mesh-level"],
    "run beam --model fe": ["--current", "--duration", "--mesh-level"],
    "run ribbon-buckling": ["--compression"],
    "run ribbon-buckling --model fe": ["--mesh-level"],
    "run gridshell": ["--ribbons"],
    "converge strip_transient_0p2A": ["--levels"],
    "uncertainty gridshell": ["--samples", "--sobol-samples", "--seed"],
    "design --target-ky -0.016": ["--target-kx"],
    "design --target-kx -0.016 --target-ky -0.016": ["--ribbons", "--target-height"],
}
VALUES = ["nan", "inf", "-inf", "0", "-1", "1e300", "abc"]
#: values that mean something (a cold start, zero load, the coarsest level, a flat target...) or
#: that the run's own checks of results stop (exit 3): they are not refused in argument checking
MEANINGFUL = {
    ("run strip", "--current", "0"),
    ("run strip", "--tip-load", "0"),
    ("run strip", "--tip-load", "1e300"),
    ("run strip", "--mesh-level", "0"),
    ("run strip", "--mesh-size", "1e300"),
    ("run strip", "--resistance", "1e300"),
    ("run ribbon", "--ground-temperature", "0"),
    ("run ribbon", "--ground-temperature", "-1"),
    ("run ribbon", "--twist-density", "0"),
    ("run ribbon", "--error-tolerance", "0"),
    ("run ribbon", "--error-tolerance", "1e300"),
    ("run ribbon", "--helix-radius", "0"),
    ("run ribbon", "--helix-radius", "1e300"),
    ("run beam --model fe", "--current", "0"),
    ("run beam --model fe", "--mesh-level", "0"),
    ("run ribbon-buckling --model fe", "--mesh-level", "0"),
    ("uncertainty gridshell", "--seed", "0"),
    ("design --target-ky -0.016", "--target-kx", "0"),
    *(("design --target-kx -0.016 --target-ky -0.016", "--target-height", v) for v in ("0", "-1")),
}
NONSENSE = [
    (c, o, v)
    for c, opts in OPTIONS.items()
    for o in opts
    for v in VALUES
    if (c, o, v) not in MEANINGFUL
]


class _Claimed(Exception):
    """The command got past argument checking (it would now claim its folder and run)."""


@pytest.mark.parametrize("command, option, value", NONSENSE, ids=[" ".join(x) for x in NONSENSE])
def test_nonsense_option_value_refused_in_argument_checking(
    command, option, value, capsys, monkeypatch, tmp_path
):
    def claimed(*args, **kwargs):
        raise _Claimed()

    monkeypatch.setattr(cli_module, "claim_out", claimed)
    out = tmp_path / "out"
    code, err = cli(capsys, *command.split(), option, value, "--out", out, "--quiet")
    assert code == 2, err
    line = one_line(err)
    assert "error" in line and "Traceback" not in line
    assert not out.exists()


# -- 2. cost: work that cannot fit this host ----------------------------------------------------
@pytest.mark.parametrize(
    "argv, field",
    [
        (["run", "strip", "--dt", "1e-300", "--duration", "1"], "run.dt = 1e-300 s"),
        (["run", "strip", "--mesh-size", "1e-4"], "mesh.size = 0.0001 mm"),
        (["run", "strip", "--mesh-size", "1e-320"], "mesh.size = 1e-320 mm"),
        (["run", "ribbon", "--nodes", "100000000"], "numerics.nodes = 100000000"),
        (["run", "ribbon", "--dt", "1e-300"], "numerics.dt = 1e-300 s"),
    ],
)
def test_work_that_cannot_fit_is_refused_naming_the_field(argv, field, capsys, tmp_path):
    out = tmp_path / "out"
    code, err = cli(capsys, *argv, "--quiet", "--out", out)
    assert code == 2
    line = one_line(err)
    assert line.startswith(f"lcefem: error: {field}") and "memory; this host has" in line
    assert not out.exists()


def test_cost_estimate_of_the_strip_counts_the_mesh_it_builds():
    """The counts without gmsh equal the built meshes' (levels 0-2: 60 / 480 / 1620 hexahedra,
    2325 / 14823 / 46137 displacement DOFs, measured from summary.json)."""
    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.problems.strip import StripConfig

    for level, cells, dofs in ((0, 60, 2325), (1, 480, 14823), (2, 1620, 46137)):
        est = StripConfig(mesh=StripMesh(level=level)).estimate()
        assert est.counts["cells"] == cells and est.counts["dofs"] == dofs


def test_memory_limit_override_refuses_what_the_host_would_run(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("LCEFEM_MEMORY", "0.3")  # GiB: below the libraries alone
    code, err = cli(capsys, *STRIP, "--out", tmp_path / "out")
    assert code == 2 and "this host has 0.3 GiB" in one_line(err)
    monkeypatch.setenv("LCEFEM_MEMORY", "lots")
    code, err = cli(capsys, *STRIP, "--out", tmp_path / "out")
    assert code == 2 and "LCEFEM_MEMORY = 'lots': must be a number of GiB" in one_line(err)


def test_host_memory_is_the_physical_memory():
    assert cost.host_memory() == os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def test_converge_levels_beyond_the_meshes_are_refused(capsys, tmp_path):
    code, err = cli(
        capsys, "converge", "strip_transient_0p2A", "--levels", "10", "--out", tmp_path / "c"
    )
    assert code == 2 and "--levels = 10: must be between 4 and 9" in one_line(err)


# -- 3. encodings -------------------------------------------------------------------------------
CASE_BYTES = {
    "utf-16": ("[run]\ncurrent = 0.1\n".encode("utf-16"), "UTF-16 text; save it as UTF-8"),
    "binary": (bytes(range(256)), "a binary file (NUL bytes)"),
    "latin-1": ("[run]\n# température\n".encode("latin-1"), "not UTF-8 text (byte 0xe9 at offset"),
    "folder": (None, "not a file"),
}


@pytest.mark.parametrize("kind", CASE_BYTES)
@pytest.mark.parametrize("command", [STRIP, BEAM, ["run", "ribbon", "--quiet"]])
def test_case_file_in_another_encoding_one_line_exit_2(command, kind, capsys, tmp_path):
    data, message = CASE_BYTES[kind]
    case = tmp_path / "case.toml"
    case.mkdir() if data is None else case.write_bytes(data)
    code, err = cli(capsys, *command, "--config", case, "--out", tmp_path / "out")
    assert code == 2
    assert f"config = '{case}': {message}" in one_line(err)
    assert not (tmp_path / "out").exists()


def test_schedule_in_utf16_one_line_exit_2(capsys, tmp_path):
    schedule = tmp_path / "s.toml"
    schedule.write_bytes("[run]\n".encode("utf-16"))
    code, err = cli(capsys, "run", "gridshell", "--schedule", schedule, "--out", tmp_path / "out")
    assert code == 2 and f"--schedule '{schedule}': UTF-16 text" in one_line(err)


def test_utf8_case_file_with_a_byte_order_mark_is_read(tmp_path):
    from lcefem.validation.app.config import load_toml

    case = tmp_path / "case.toml"
    case.write_bytes("\ufeff[run]\ncurrent = 0.1\n".encode("utf-8"))
    assert load_toml(case, {"run"}) == {"run": {"current": 0.1}}


@pytest.mark.parametrize("command", [BEAM, ["validate", "tension_law", "--quick"]])
def test_out_name_not_utf8_one_line_exit_2(command, capsys, tmp_path):
    out = os.fsdecode(os.fsencode(str(tmp_path)) + b"/r\xffsults")  # as Python gets such argv bytes
    code, err = cli(capsys, *command, "--out", out)
    assert code == 2 and "not valid UTF-8" in one_line(err)
    assert list(tmp_path.iterdir()) == []


# -- 4. signals ---------------------------------------------------------------------------------
def test_petsc_never_takes_sigterm(tmp_path):
    """Started after the command line, PETSc would end the process with status 15 on SIGTERM (its
    handler, "Caught signal number 15"); with -no_signal_handler the run's own handler raises."""
    code = (
        "import os, signal, sys, time\n"
        "from lcefem.solvers.runtime import signals\n"
        "signals.install_signal_handlers(); signals.keep_petsc_off_signals()\n"
        "import dolfinx_solver\nfrom petsc4py import PETSc\n"
        "try:\n    os.kill(os.getpid(), signal.SIGTERM); time.sleep(5)\n"
        "except signals.Terminated:\n    sys.exit(143)\n"
    )
    res = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PETSC_OPTIONS": ""},
    )
    assert res.returncode == 143, res.stderr
    assert "PETSC ERROR" not in res.stderr


def _fake_study(monkeypatch):
    from lcefem.validation.app import converge

    h = [2.0, 1.0, 0.5, 0.25]
    studies = [converge.analyse(h, [1.0 + x**2 for x in h], "m", "mm")]
    monkeypatch.setattr(converge, "run_study", lambda *a, **k: (h, "mm", studies, []))


def test_converge_interrupted_while_plotting_leaves_no_final_names(capsys, tmp_path, monkeypatch):
    from lcefem.validation.app import plots

    _fake_study(monkeypatch)

    def killed(*args, **kwargs):
        raise Terminated()

    monkeypatch.setattr(plots, "convergence_plot", killed)
    out = tmp_path / "study"
    code, err = cli(capsys, "converge", "rod_closed_forms", "--quiet", "--out", out)
    assert code == 143 and "interrupted (SIGTERM)" in one_line(err)
    assert results(out) == {"study.partial"}  # levels.csv, gci.csv, convergence.json only in there
    assert {p.name for p in (out / "study.partial").iterdir()} == {
        "levels.csv",
        "gci.csv",
        "convergence.json",
    }
    assert not (out / LOCK).exists()


def test_converge_resume_replaces_an_earlier_study_s_files(capsys, tmp_path, monkeypatch):
    _fake_study(monkeypatch)
    out = tmp_path / "study"
    out.mkdir()
    (out / ".lcefem-out").write_text(STAMP_TEXT.format(command="converge rod_closed_forms"))
    (out / "study.partial").mkdir()
    (out / "gci.csv").write_text("stale")
    code, err = cli(capsys, "converge", "rod_closed_forms", "--quiet", "--resume", "--out", out)
    assert code == 0, err
    assert results(out) == {"levels.csv", "gci.csv", "convergence.json", "convergence.png"}
    assert (out / "gci.csv").read_text() != "stale"


def test_interrupt_swallowed_inside_a_petsc_callback_still_stops_the_run(
    capsys, tmp_path, monkeypatch
):
    """A Ctrl-C that lands inside the Jacobian assembly of a strip run and is swallowed there (PETSc
    turns a callback's exception into an error code) ends the run with 130 and its converged steps,
    instead of running on (before: exit 0 after all 20 steps)."""
    import dolfinx.fem.petsc as fem_petsc

    assemble = fem_petsc.assemble_matrix
    calls = []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 4:
            try:
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(0.05)
            except KeyboardInterrupt:
                pass  # swallowed, as inside PETSc
        return assemble(*args, **kwargs)

    monkeypatch.setattr(fem_petsc, "assemble_matrix", interrupted)
    out = tmp_path / "int"
    code, err = cli(capsys, *STRIP, "--duration", "20", "--dt", "1", "--out", out)
    assert code == 130, err
    assert "interrupted (Ctrl-C)" in one_line(err)
    assert results(out) == {"history.partial.csv"}
    assert not (out / LOCK).exists()


@pytest.mark.slow
def test_converge_sigterm_then_resume(lcefem_cmd, tmp_path):
    """SIGTERM during a study: exit 143, lock released, no study files; --resume reuses the finished
    levels and completes it."""
    out = tmp_path / "c"
    proc = subprocess.Popen(
        lcefem_cmd + ["converge", "rod_closed_forms", "--quiet", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    end = time.monotonic() + 120
    while not (out / "level0" / "metrics.json").exists():
        assert time.monotonic() < end and proc.poll() is None
        time.sleep(0.1)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err
    assert not (out / LOCK).exists() and not (out / "levels.csv").exists()
    res = subprocess.run(
        lcefem_cmd + ["converge", "rod_closed_forms", "--quiet", "--resume", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert res.returncode == 0, res.stderr
    assert json.loads((out / "level0" / "metrics.json").read_text())["status"] == "done"
    assert (out / "convergence.json").exists()


@pytest.mark.slow
def test_validate_sigkill_then_resume(lcefem_cmd, tmp_path):
    """SIGKILL (no clean-up at all) during validate: the lock names a dead pid and is taken over,
    --resume keeps the case whose completion marker exists and runs the rest."""
    out = tmp_path / "v"
    cases = ["tension_law", "ribbon_buckling_bh"]
    proc = subprocess.Popen(
        lcefem_cmd + ["validate", *cases, "--quick", "--quiet", "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    end = time.monotonic() + 120
    while not (out / "tension_law" / "metrics.json").exists():
        assert time.monotonic() < end and proc.poll() is None
        time.sleep(0.05)
    proc.kill()
    proc.wait(timeout=60)
    res = subprocess.run(
        lcefem_cmd + ["validate", *cases, "--quick", "--quiet", "--resume", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert res.returncode == 0, res.stderr
    report = (out / "report.md").read_text()
    assert "INCOMPLETE" not in report
    assert re.search(r"^\| tension_law \| reused \|", report, re.MULTILINE), report[:2000]
    assert not (out / LOCK).exists()


@pytest.mark.slow
def test_run_sigkill_then_overwrite(lcefem_cmd, tmp_path):
    """A run killed by SIGKILL leaves only .part files and its lock (nothing final-named); the next
    command into the folder takes the dead run's lock over with --overwrite and completes."""
    out = tmp_path / "rib"
    argv = ["run", "ribbon", "--duration", "2", "--nodes", "20", "--quiet", "--out", str(out)]
    proc = subprocess.Popen(lcefem_cmd + argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    end = time.monotonic() + 120
    while not list(out.glob("*.part")):
        assert time.monotonic() < end and proc.poll() is None
        time.sleep(0.05)
    proc.kill()
    proc.wait(timeout=60)
    assert not (out / "summary.json").exists() and not (out / "history.csv").exists()
    res = subprocess.run(
        lcefem_cmd + argv + ["--overwrite"], capture_output=True, text=True, timeout=300
    )
    assert res.returncode == 0, res.stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


# -- 5. full disks ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "code, cause",
    [
        (errno.ENOSPC, "no space left on the device (ENOSPC)"),
        (errno.EDQUOT, "disk quota exceeded (EDQUOT)"),
        (errno.EROFS, "read-only file system (EROFS)"),
        (errno.EACCES, "permission denied (EACCES)"),
    ],
)
def test_disk_errors_classified_by_cause_naming_the_file(
    code, cause, capsys, tmp_path, monkeypatch
):
    import csv

    append = CSVTable.append

    class Full:  # the history file on a disk that fails: write() raises without a file name
        closed = False

        def write(self, text):
            raise OSError(code, os.strerror(code))

        def flush(self):
            pass

        def close(self):
            self.closed = True

    def failing(self, row):
        if len(self.rows) == 1 and self.path is not None and not isinstance(self._fh, Full):
            self._fh.close()
            self._fh = Full()
            self._csv = csv.writer(self._fh)
        append(self, row)

    monkeypatch.setattr(CSVTable, "append", failing)
    out = tmp_path / "disk"
    rc, err = cli(capsys, *BEAM, "--out", out)
    assert rc == 2
    assert one_line(err).startswith(
        f"lcefem: error: cannot write '{out / 'history.csv.part'}': {cause}"
    )
    assert "history.partial.csv" in results(out) and "summary.json" not in results(out)


def test_a_failed_write_gives_its_space_back_and_keeps_the_old_file(tmp_path, monkeypatch):
    from lcefem.solvers.runtime import files

    target = tmp_path / "report.md"
    write_text(target, "old")
    real = files.open_new

    class Full:  # a file on a full disk: the first write lands half, then ENOSPC (no file name)
        def __init__(self, fh):
            self.fh = fh

        def write(self, text):
            self.fh.write("half")
            raise OSError(errno.ENOSPC, "No space left on device")

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

    monkeypatch.setattr(files, "open_new", lambda *a, **k: Full(real(*a, **k)))
    with pytest.raises(OSError) as info:
        write_text(target, "new")
    assert info.value.filename == str(tmp_path / "report.md.part")
    monkeypatch.undo()
    assert target.read_text() == "old" and not (tmp_path / "report.md.part").exists()


def test_adios2_error_text_becomes_an_os_error_naming_the_file():
    text = (
        "\x1b[1;36m[Sat Nov 28 2026]\x1b[1;34m [ADIOS2 EXCEPTION]\x1b[0m <Toolkit> "
        "<transport::file::"
        "FilePOSIX> <Write> : couldn't write to file /r/thermal.bp.part/md.0 : errno = 28: No "
        "space "
        "left on device\x1b[0m\n: iostream error"
    )
    exc = library_os_error(RuntimeError(text))
    assert (exc.errno, exc.filename) == (errno.ENOSPC, "/r/thermal.bp.part/md.0")
    assert library_os_error(RuntimeError("no errno here")) is None


def test_validate_on_a_full_disk_stops_with_report_incomplete(capsys, tmp_path, monkeypatch):
    from lcefem.validation.app import plots

    def full(fig, path, dpi):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(plots, "save_figure", full)
    out = tmp_path / "v"
    code, err = cli(
        capsys, "validate", "tension_law", "rod_closed_forms", "--quick", "--quiet", "--out", out
    )
    assert code == 2
    assert "no space left on the device (ENOSPC)" in one_line(err)
    report = (out / "report.md").read_text()
    assert (
        "INCOMPLETE" in report
        and "tension_law: error" in report
        and "rod_closed_forms: not run" in report
    )


# -- 6. folder rules ----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def beam_folder(tmp_path_factory):
    out = tmp_path_factory.mktemp("beam") / "done"
    assert cli_main([*BEAM, "--out", str(out)]) == 0
    return out


def test_the_folder_marker_records_the_command(beam_folder):
    assert stamped_command(beam_folder) == "run beam"


@pytest.mark.parametrize(
    "command", [["validate", "tension_law", "--quick"], ["converge", "rod_closed_forms"]]
)
def test_resume_into_another_command_s_folder_is_refused(command, beam_folder, capsys):
    before = sorted(p.name for p in beam_folder.iterdir())
    code, err = cli(capsys, *command, "--quiet", "--resume", "--out", beam_folder)
    assert code == 2
    assert "holds the results of `lcefem run beam`; --resume continues only" in one_line(err)
    assert sorted(p.name for p in beam_folder.iterdir()) == before


def test_overwrite_refuses_to_delete_the_case_file_it_reads(beam_folder, capsys, tmp_path):
    out = tmp_path / "again"
    subprocess.run(["cp", "-r", str(beam_folder), str(out)], check=True)
    case = out / "case.toml"
    case.write_text("[run]\nlambda_top = 1.35\n")
    code, err = cli(capsys, *BEAM, "--config", case, "--overwrite", "--out", out)
    assert code == 2 and f"--config = '{case}': inside --out" in one_line(err)
    assert case.exists() and (out / "summary.json").exists()


def test_exit_3_before_the_run_exists_leaves_failure_json(capsys, tmp_path, monkeypatch):
    from lcefem.validation.app.commands import beam

    def fails_in_set_up(args):
        raise ConvergenceError("the as-built state", "no equilibrium")

    monkeypatch.setattr(beam, "main", fails_in_set_up)
    out = tmp_path / "early"
    code, err = cli(capsys, *BEAM, "--out", out)
    assert code == 3 and "no convergence at the as-built state" in one_line(err)
    failure = json.loads((out / "failure.json").read_text())
    assert (
        failure["where"] == "the as-built state"
        and failure["config"]["run"]["lambda_top"]["value"] == 1.38
    )


# -- 7. inputs silently ignored -----------------------------------------------------------------
def test_unknown_petsc_option_is_refused_naming_it(capsys, tmp_path):
    case = tmp_path / "case.toml"
    # an option a case file may set but this solver never reads (GAMG's on the direct path); a
    # misspelt one (snes_typo) is refused before the run by the allow-list (test_failure_modes_3)
    case.write_text('[petsc]\npc_gamg_threshold = "0.1"\nsnes_max_it = "40"\n')
    out = tmp_path / "out"
    code, err = cli(capsys, *STRIP, "--duration", "2", "--dt", "1", "--config", case, "--out", out)
    assert code == 2
    assert one_line(err).startswith(
        "lcefem: error: [petsc] pc_gamg_threshold: not read by this problem's solver"
    )
    assert "summary.json" not in results(out)
    from petsc4py import PETSc

    assert not [
        n for n in PETSc.Options().getAll() if n.startswith("lcefem_")
    ]  # nothing left to warn


def test_helix_with_twist_density_is_refused(capsys, tmp_path):
    code, err = cli(
        capsys,
        "run",
        "ribbon",
        "--helix-radius",
        "2",
        "--twist-density",
        "0.1",
        "--out",
        tmp_path / "out",
    )
    assert code == 2 and "a helical ribbon (helix radius 2.0 mm) is untwisted" in one_line(err)
    case = tmp_path / "case.toml"
    case.write_text("[geometry]\nhelix_radius = 2.0\ntwist_density = 0.1\n")
    code, err = cli(capsys, "run", "ribbon", "--config", case, "--out", tmp_path / "out")
    assert code == 2 and "geometry.twist_density = 0.1 turns/mm: a helical ribbon" in one_line(err)


def test_helix_reports_no_twist(tmp_path):
    from argparse import Namespace

    from lcefem.validation.app.commands.ribbon import config_from_args

    args = Namespace(
        config=None,
        ground_temperature=None,
        duration=None,
        twist_density=None,
        helix_radius=2.0,
        nodes=None,
        dt=None,
        error_tolerance=None,
        obstacle=None,
        obstacle_offset=None,
        obstacle_distance=None,
    )
    assert config_from_args(args).geometry.twist_density == 0.0


def test_strip_ids_in_a_case_file_as_on_the_command_line(tmp_path):
    from lcefem.validation.app.commands.gridshell import config_from_toml, parse_assignments

    case = tmp_path / "case.toml"
    case.write_text("[lambda]\n3 = 1.2\nTx = 1.3\n[current]\n7 = 0.1\n")
    cfg = config_from_toml(case)
    assert cfg.lambdas == parse_assignments("3=1.2,Tx=1.3", "lambda") == {3: 1.2, "Tx": 1.3}
    assert cfg.currents == {7: 0.1}


def test_repeated_lambda_options_add_up_and_a_repeated_selection_is_refused():
    """`--lambda Tx=1.3 --lambda By=1.1` drives both (argparse kept only the last); the same
    selection twice is an error, not a silent choice of one value."""
    import argparse

    from lcefem.models.errors import InputError
    from lcefem.validation.app.commands.gridshell import add_arguments, parse_assignments

    p = argparse.ArgumentParser()
    add_arguments(p)
    args = p.parse_args(["--lambda", "Tx=1.3", "--lambda", "By=1.1", "--current", "Tx=0.1"])
    assert parse_assignments(args.lambdas, "lambda") == {"Tx": 1.3, "By": 1.1}
    assert parse_assignments(args.currents, "current") == {"Tx": 0.1}
    with pytest.raises(InputError, match="--lambda Tx: given twice"):
        parse_assignments("Tx=1.3,Tx=1.2", "lambda")


def test_curvature_chart_legend_lists_only_drawn_series(tmp_path, monkeypatch):
    from lcefem.validation.app import plots
    from lcefem.validation.studies.gridshell import gridshell_plots

    figures = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path, dpi: figures.append(fig) or path)
    gridshell_plots.curvature_bar_chart(
        tmp_path / "c.png",
        ["dome", "saddle"],
        {
            "ours (lambda route)": {"dome": (-0.01, -0.01), "saddle": (0.01, -0.01)},
            "ours (current route)": {"dome": (None, None)},
            "paper": {"dome": (-0.012, -0.011)},
        },
        ["seed"],
    )
    legend = figures[0].axes[1].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ["ours (lambda route)", "paper"]
    assert "no values, not drawn: ours (current route)" in " ".join(
        t.get_text() for t in figures[0].texts
    )


# -- 8. under mpiexec ---------------------------------------------------------------------------
@pytest.mark.mpi
@pytest.mark.parametrize(
    "argv, message",
    [
        (["run", "strip", "--dt", "1e-300", "--duration", "1"], "run.dt = 1e-300 s"),
        (["run", "strip", "--config", "{utf16}"], "UTF-16 text"),
    ],
)
def test_refusals_under_mpiexec_one_line_exit_2(argv, message, lcefem_cmd, mpiexec, tmp_path):
    case = tmp_path / "case.toml"
    case.write_bytes("[run]\n".encode("utf-16"))
    res = subprocess.run(
        [
            mpiexec,
            "-n",
            "2",
            *lcefem_cmd,
            *[a.replace("{utf16}", str(case)) for a in argv],
            "--quiet",
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert res.returncode == 2, res.stderr
    assert message in one_line(res.stderr)
    assert not (tmp_path / "out").exists()
