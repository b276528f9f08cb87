"""The third catalogue (issue 45, causes 1-8): a case file must not run code, --resume and
--overwrite must not eat a user's folder, writers never follow links, parsers raise only their
decode error, start-up checks come before any library, and the reporting streams never change an
outcome (docs/failure_modes.md, "Case files, folders and environment: the contract").

Each probe runs as a user would: a subprocess of the installed ``lcefem`` entry point, so the
start-up path (argument and environment checks before dolfinx and numba are imported) is covered.
The cheapest targets: the 2-segment bar-and-hinge beam, ``validate tension_law --quick`` and
refusals that come before any solve.
"""

import os
import shutil
import socket
import subprocess
import time

import pytest

from lcefem.models.errors import InputError
from lcefem.solvers.petsc_options import check_case_options
from lcefem.solvers.runtime.files import disk_error_message
from lcefem.solvers.runtime.outdir import STAMP_TEXT
from tests.conftest import REPO, VENV_BIN

BEAM = [
    "run",
    "beam",
    "--segments",
    "2",
    "--lambda-top",
    "1.38",
    "--quiet",
]  # ~3 s bar-and-hinge run
STRIP = ["run", "strip", "--mesh-level", "0", "--quiet", "--no-fields"]
TENSION = ["validate", "tension_law", "--quick", "--quiet"]  # ~3 s, no FE solve
LOCK = ".lcefem.lock"


def lcefem(cmd, *args, env=None, cwd=None, **kwargs):
    """``lcefem ARGS`` in a subprocess; ``env`` entries are added to this environment."""
    return subprocess.run(
        cmd + [a if isinstance(a, bytes) else str(a) for a in args],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=cwd,
        env={**os.environ, **(env or {})},
        **kwargs,
    )


def one_line(res) -> str:
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert "Traceback" not in lines[0]
    return lines[0]


@pytest.fixture(scope="module")
def validated(tmp_path_factory):
    """A finished ``validate tension_law --quick`` folder to copy."""
    out = tmp_path_factory.mktemp("validated") / "v"
    res = subprocess.run(
        [str(VENV_BIN / "lcefem"), *TENSION, "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 0, res.stderr
    return out


def _copy(folder, to):
    shutil.copytree(folder, to, symlinks=True)
    return to


# -- 1. code from data: a case file's [petsc] sets numerics only ----------------------------------
EVIL = {
    "python preconditioner": 'pc_type = "python"\npc_python_type = "{dir}/evil.py:run"\n',
    "python type alone": 'pc_python_type = "{dir}/evil.py:run"\n',
    "monitor to a file": 'snes_monitor = "ascii:{dir}/monitor.txt"\n',
    "viewer": 'ksp_view = "binary:{dir}/ksp.bin"\n',
    "options file": 'options_file = "{dir}/more.opts"\n',
    "help": 'help = "1"\n',
    "a viewer as a value": 'snes_max_it = "ascii:{dir}/monitor.txt"\n',
}


@pytest.mark.parametrize("name", EVIL)
def test_case_file_petsc_section_cannot_run_code_or_write_files(name, lcefem_cmd, tmp_path):
    (tmp_path / "evil.py").write_text(
        f"def run(pc):\n    open({str(tmp_path / 'ran')!r}, 'w').write('x')\n"
    )
    (tmp_path / "more.opts").write_text("-snes_monitor\n")
    case = tmp_path / "case.toml"
    case.write_text("[petsc]\n" + EVIL[name].format(dir=tmp_path))
    res = lcefem(lcefem_cmd, *STRIP, "--config", case, "--out", tmp_path / "out")
    assert res.returncode == 2
    assert one_line(res).startswith("lcefem: error: [petsc] ")
    assert not (tmp_path / "out").exists()  # refused before the folder was claimed
    assert not (tmp_path / "ran").exists() and not (tmp_path / "monitor.txt").exists()


def test_petsc_allow_list_accepts_numerics_and_refuses_the_rest():
    ok = check_case_options(
        {
            "pc_type": "gamg",
            "pc_gamg_threshold": 0.02,
            "snes_max_it": 40,
            "mat_mumps_icntl_14": "50",
            "mat_mumps_cntl_1": "0.01",
            "mg_levels_ksp_type": "chebyshev",
            "mg_coarse_pc_type": "cholesky",
            "snes_ksp_ew": True,
            "pmg_smoother_blocks": "planes",
        }
    )
    assert (
        ok["pc_gamg_threshold"] == "0.02"
        and ok["snes_max_it"] == "40"
        and ok["snes_ksp_ew"] == "true"
    )
    for table in (
        {"pc_type": "shell"},
        {"snes_max_it": "1.5"},
        {"snes_rtol": "nan"},
        {"ksp_rtol": "١"},
        {"mg_levels_pc_python_type": "x:y"},
        {"snes_linesearch_monitor": ""},
        {"log_view": ""},
        {"lcefem_mech_pc_type": "lu"},
        {"pc_type": ["lu"]},
    ):
        with pytest.raises(InputError):
            check_case_options(table)


def test_petsc_options_environment_is_ignored_in_one_line(lcefem_cmd, tmp_path):
    """Honoured, -lcefem_mech_snes_max_it 0 would stop the strip's first solve (exit 3)."""
    res = lcefem(
        lcefem_cmd,
        *STRIP,
        "--duration",
        "2",
        "--dt",
        "1",
        "--out",
        tmp_path / "out",
        env={"PETSC_OPTIONS": "-lcefem_mech_snes_max_it 0 -log_view"},
    )
    assert res.returncode == 0, res.stderr
    assert res.stderr.strip().splitlines() == [
        "lcefem: PETSC_OPTIONS ignored (-lcefem_mech_snes_max_it 0 -log_view): solver options "
        "come only "
        "from a case file's [petsc] section (docs/failure_modes.md)"
    ]


def test_a_petscrc_in_the_working_folder_is_ignored_in_one_line(lcefem_cmd, tmp_path):
    """PETSc reads ./.petscrc at start: honoured, -log_view :path would write that file."""
    (tmp_path / ".petscrc").write_text(f"-log_view :{tmp_path / 'log.txt'}\n")
    res = lcefem(
        lcefem_cmd, *STRIP, "--duration", "2", "--dt", "1", "--out", tmp_path / "out", cwd=tmp_path
    )
    assert res.returncode == 0, res.stderr
    assert res.stderr.strip().splitlines() == [
        "lcefem: .petscrc ignored: solver options come only from a case file's [petsc] section "
        "(docs/failure_modes.md)"
    ]
    assert not (tmp_path / "log.txt").exists()


# -- 2. --resume continues only a folder lcefem wrote, of the same command, outside the source tree
def test_resume_refuses_a_folder_lcefem_never_wrote(lcefem_cmd, tmp_path):
    (tmp_path / "u" / "tension_law").mkdir(parents=True)
    (tmp_path / "u" / "tension_law" / "mine.txt").write_text("mine")
    (tmp_path / "u" / "report.md").write_text("my report")
    res = lcefem(lcefem_cmd, *TENSION, "--resume", "--out", tmp_path / "u")
    assert res.returncode == 2 and "--resume continues only a folder lcefem wrote" in one_line(res)
    assert (tmp_path / "u" / "tension_law" / "mine.txt").read_text() == "mine"
    assert (tmp_path / "u" / "report.md").read_text() == "my report"
    assert sorted(p.name for p in (tmp_path / "u").iterdir()) == ["report.md", "tension_law"]


@pytest.mark.parametrize("flags", [["--resume"], [], ["--overwrite"]])
def test_no_command_writes_into_the_source_tree(flags, lcefem_cmd, tmp_path):
    before = sorted(p.name for p in (REPO / "validation").iterdir())
    res = lcefem(lcefem_cmd, *TENSION, *flags, "--out", "validation", cwd=REPO)
    assert res.returncode == 2 and "inside lcefem's own source tree" in one_line(res)
    assert sorted(p.name for p in (REPO / "validation").iterdir()) == before


# -- 3. writers never follow links inside --out ---------------------------------------------------
def test_a_linked_marker_is_refused_and_its_target_kept(lcefem_cmd, tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / ".lcefem-out").symlink_to(victim)
    res = lcefem(lcefem_cmd, *BEAM, "--out", tmp_path / "out")
    assert res.returncode == 2 and "is a link or not a file" in one_line(res)
    assert victim.read_text() == "precious"


@pytest.mark.parametrize("planted", ["report.md.part", "metrics.json.part"])
def test_a_planted_part_link_is_refused_naming_it(planted, validated, lcefem_cmd, tmp_path):
    out = _copy(validated, tmp_path / "v")
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (out / planted).symlink_to(victim)
    res = lcefem(lcefem_cmd, *TENSION, "--resume", "--out", out)
    assert res.returncode == 2
    assert one_line(res) == (
        f"lcefem: error: '{out / planted}': a symbolic link inside the output folder; "
        "lcefem does not write through links: remove it or choose another --out"
    )
    assert victim.read_text() == "precious"


def test_a_linked_case_folder_is_removed_not_followed(validated, lcefem_cmd, tmp_path):
    out = _copy(validated, tmp_path / "v")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "data.csv").write_text("1,2\n")
    shutil.rmtree(out / "tension_law")
    (out / "tension_law").symlink_to(mine, target_is_directory=True)
    res = lcefem(lcefem_cmd, *TENSION, "--resume", "--out", out)
    assert res.returncode == 0, res.stderr
    assert (mine / "data.csv").read_text() == "1,2\n" and sorted(
        p.name for p in mine.iterdir()
    ) == ["data.csv"]
    assert (out / "tension_law").is_dir() and not (out / "tension_law").is_symlink()


# -- 4. a lock without a readable pid is stale after a short grace period -------------------------
@pytest.mark.parametrize("content", ["", "garbage\n"])
def test_a_lock_without_a_pid_is_taken_over(content, lcefem_cmd, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / LOCK).write_text(content)
    old = time.time() - 60.0  # left by a run that died a minute ago
    os.utime(out / LOCK, (old, old))
    res = lcefem(lcefem_cmd, *BEAM, "--out", out)
    assert res.returncode == 0, res.stderr
    assert "taking over" in res.stderr and f"{out / LOCK}" in res.stderr
    assert (out / "summary.json").exists() and not (out / LOCK).exists()


def test_lock_contents_without_a_readable_pid(tmp_path):
    from lcefem.solvers.runtime.outdir import _lock_owner

    lock = tmp_path / LOCK
    for content in ("", "garbage\n", "0 \n", "-5 host\n", "12", "\xff\xfe"):
        lock.write_text(content, encoding="latin-1")
        assert _lock_owner(lock) is None, content
    lock.write_text("4242 somehost\n")
    assert _lock_owner(lock) == (4242, "somehost")


def test_a_lock_of_a_live_pid_keeps_the_folder(lcefem_cmd, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / LOCK).write_text(f"{os.getpid()} {socket.gethostname()}\n")  # this test process: alive
    res = lcefem(lcefem_cmd, *BEAM, "--out", out)
    assert res.returncode == 2 and f"in use by another lcefem run (pid {os.getpid()}" in one_line(
        res
    )
    assert sorted(p.name for p in out.iterdir()) == [LOCK]


# -- 5. inputs checked before --overwrite empties; a live run's subfolder is never deleted --------
@pytest.fixture(scope="module")
def finished_beam(tmp_path_factory):
    out = tmp_path_factory.mktemp("beam") / "done"
    res = subprocess.run(
        [str(VENV_BIN / "lcefem"), *BEAM, "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 0, res.stderr
    return out


@pytest.mark.parametrize(
    "case",
    [
        '[petsc]\nsnes_typo = "1"\n',
        "[run]\nsegments = 2\nno_such_key = 1\n",
        "[run]\nlambda_top = 1e400\n",
    ],
)
def test_overwrite_with_bad_input_keeps_the_previous_run(case, finished_beam, lcefem_cmd, tmp_path):
    out = _copy(finished_beam, tmp_path / "done")
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    (tmp_path / "case.toml").write_text(case)
    res = lcefem(lcefem_cmd, *BEAM, "--config", tmp_path / "case.toml", "--out", out, "--overwrite")
    assert res.returncode == 2 and one_line(res).startswith("lcefem: error: ")
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before


def test_input_error_found_during_the_run_restores_the_previous_run(lcefem_cmd, tmp_path):
    """An option a case file may set but the solver never reads is found only after the first
    solve: the previous run, set aside by --overwrite, is put back (exit 2: nothing new)."""
    out = tmp_path / "strip"
    out.mkdir()  # an earlier strip run's folder (its marker and results)
    (out / ".lcefem-out").write_text(STAMP_TEXT.format(command="run strip"))
    (out / "summary.json").write_text('{"status": "completed"}\n')
    (out / "history.csv").write_text("time [s]\n0\n")
    args = [*STRIP, "--duration", "2", "--dt", "1", "--out", out]
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    (tmp_path / "case.toml").write_text('[petsc]\npc_gamg_threshold = "0.1"\n')
    res = lcefem(lcefem_cmd, *args, "--config", tmp_path / "case.toml", "--overwrite")
    assert (
        res.returncode == 2
        and "[petsc] pc_gamg_threshold: not read by this problem's solver" in one_line(res)
    )
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before
    assert sorted(p.name for p in out.iterdir()) == sorted(before)


def test_overwrite_of_a_parent_spares_a_subfolder_a_live_run_holds(validated, lcefem_cmd, tmp_path):
    out = _copy(validated, tmp_path / "v")
    (out / "tension_law" / LOCK).write_text(f"{os.getpid()} {socket.gethostname()}\n")
    inside = sorted(p.name for p in (out / "tension_law").iterdir())
    res = lcefem(lcefem_cmd, *TENSION, "--overwrite", "--out", out)
    assert res.returncode == 2 and "in use by another lcefem run" in one_line(res)
    assert sorted(p.name for p in (out / "tension_law").iterdir()) == inside


# -- 6. parsers raise only their decode error -----------------------------------------------------
PARSER_INPUTS = {
    "2,000-deep array": "[run]\nduration = " + "[" * 2000 + "]" * 2000 + "\n",
    "2,000-deep inline table": "[run]\nduration = " + "{a = " * 2000 + "1" + "}" * 2000 + "\n",
    "5,000-digit integer": "[run]\nduration = " + "9" * 5000 + "\n",
    "odd unicode key": "[run]\n\"²\" = 1\n",
}


@pytest.mark.parametrize("name", PARSER_INPUTS)
def test_case_file_parser_errors_are_one_line(name, lcefem_cmd, tmp_path):
    (tmp_path / "case.toml").write_text(PARSER_INPUTS[name], encoding="utf-8")
    res = lcefem(lcefem_cmd, *BEAM, "--config", tmp_path / "case.toml", "--out", tmp_path / "out")
    assert res.returncode == 2 and one_line(res).startswith("lcefem: error: ")
    assert not (tmp_path / "out").exists()


def test_schedule_with_a_unicode_digit_key_is_one_line(lcefem_cmd, tmp_path):
    """ "²" is a digit to str.isdigit but not to int(): a selection name, refused as unknown."""
    (tmp_path / "s.toml").write_text(
        '[schedule]\ntimes = [0.0]\nend = 10.0\noutput_interval = 5.0\n[currents]\n"²" = [0.1]\n',
        encoding="utf-8",
    )
    res = lcefem(
        lcefem_cmd,
        "run",
        "gridshell",
        "--schedule",
        tmp_path / "s.toml",
        "--quiet",
        "--out",
        tmp_path / "out",
    )
    assert res.returncode == 2 and one_line(res).startswith(
        "lcefem: error: currents.²: unknown strip selection"
    )


@pytest.mark.parametrize(
    "stored",
    [
        "[1, 2]",
        '{"case": "tension_law", "status": "done", "quick": true, "metrics": [1], "figures": []}',
        '{"case": "tension_law", "status": "done", "quick": true, '
        '"metrics": [], "figures": [{"path": 3}]}',
    ],
)
def test_resume_with_a_metrics_json_of_the_wrong_shape_is_one_line(
    stored, validated, lcefem_cmd, tmp_path
):
    out = _copy(validated, tmp_path / "v")
    (out / "tension_law" / "metrics.json").write_text(stored)
    res = lcefem(lcefem_cmd, *TENSION, "--resume", "--out", out)
    assert res.returncode == 2 and "is not a case result lcefem wrote" in one_line(res)


# -- 7. start-up checks before dolfinx and numba are imported -------------------------------------
def test_out_not_utf8_is_refused_before_dolfinx_starts(lcefem_cmd, tmp_path):
    res = subprocess.run(
        [
            os.fsencode(lcefem_cmd[0]),
            *[a.encode() for a in STRIP],
            b"--out",
            os.fsencode(tmp_path) + b"/o/bad\xffx",
        ],
        capture_output=True,
        timeout=120,
    )
    err = res.stderr.decode("utf-8", "replace")
    assert res.returncode == 2 and len(err.strip().splitlines()) == 1, err
    assert "--out = " in err and "not valid UTF-8" in err
    assert list(tmp_path.iterdir()) == []


def test_out_with_a_newline_is_refused_in_one_line(lcefem_cmd, tmp_path):
    res = lcefem(lcefem_cmd, *BEAM, "--out", tmp_path / "a\nb")
    assert res.returncode == 2 and "contains a control character" in one_line(res)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "var, value",
    [
        ("NUMBA_NUM_THREADS", "0"),
        ("NUMBA_NUM_THREADS", "-2"),
        ("NUMBA_NUM_THREADS", "many"),
        ("LCEFEM_MEMORY", "-1"),
        ("LCEFEM_MEMORY", "nan"),
        ("PMI_RANK", "x"),
    ],
)
def test_bad_numeric_environment_is_one_line(var, value, lcefem_cmd, tmp_path):
    res = lcefem(
        lcefem_cmd, "run", "ribbon", "--quiet", "--out", tmp_path / "out", env={var: value}
    )
    assert res.returncode == 2
    assert one_line(res).startswith(
        f"lcefem: error: environment variable {var} = '{value}': must be "
    )
    assert not (tmp_path / "out").exists()


# -- 8. OSErrors blamed on their own folder; the reporting streams protected ----------------------
def test_disk_errors_blame_out_only_for_files_in_out(tmp_path):
    import errno

    inside = OSError(errno.EROFS, "Read-only file system", str(tmp_path / "out" / "history.csv"))
    elsewhere = OSError(errno.EROFS, "Read-only file system", "/elsewhere/file")
    assert disk_error_message(inside, tmp_path / "out").endswith("choose a writable --out")
    assert "--out" not in disk_error_message(elsewhere, tmp_path / "out")
    numba = OSError(errno.EACCES, "Permission denied", str(tmp_path / "nc" / "x.nbi"))
    os.environ["NUMBA_CACHE_DIR"] = str(tmp_path / "nc")
    try:
        message = disk_error_message(numba, tmp_path / "out")
    finally:
        del os.environ["NUMBA_CACHE_DIR"]
    assert "set NUMBA_CACHE_DIR to a folder you may write to" in message and "--out" not in message


def test_an_unwritable_jit_cache_names_its_variable(lcefem_cmd, tmp_path):
    (tmp_path / "file").write_text("not a folder")  # unwritable for every user, also root
    res = lcefem(
        lcefem_cmd,
        *STRIP,
        "--out",
        tmp_path / "out",
        env={"XDG_CACHE_HOME": str(tmp_path / "file"), "MPLCONFIGDIR": str(tmp_path / "mpl")},
    )
    assert res.returncode == 2
    line = one_line(res)
    assert "set XDG_CACHE_HOME to a folder you may write to" in line and "--out" not in line
    assert not (tmp_path / "out").exists()


def test_ascii_stdout_never_turns_a_finished_run_into_a_traceback(validated, lcefem_cmd, tmp_path):
    out = _copy(validated, tmp_path / "v")
    res = lcefem(
        lcefem_cmd,
        *TENSION,
        "--resume",
        "--out",
        out,
        env={"PYTHONIOENCODING": "ascii", "LC_ALL": "C"},
    )
    assert res.returncode == 0, res.stderr
    assert "reference ? tol" in res.stdout  # "±" replaced, the table printed
    assert "Traceback" not in res.stderr


@pytest.mark.parametrize(
    "argv, code",
    [(["run", "beam", "--segments", "-1"], 2), (["validate", "no_such_case"], 2), (BEAM, 0)],
)
def test_stderr_on_a_full_device_keeps_the_exit_status(argv, code, lcefem_cmd, tmp_path):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full here")
    with open("/dev/full", "w") as full:
        res = subprocess.run(
            lcefem_cmd + argv + ["--out", str(tmp_path / "out")],
            stdout=subprocess.PIPE,
            stderr=full,
            timeout=120,
        )
    assert res.returncode == code


def test_the_library_checks_petsc_options_as_the_command_line(tmp_path):
    """A library caller's StripConfig.petsc goes through the same allow-list (before PETSc sees
    it)."""
    from lcefem.meshes.strip import StripMesh
    from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation

    evil = {"pc_type": "python", "pc_python_type": f"{tmp_path}/evil.py:run"}
    with pytest.raises(InputError, match=r"\[petsc\] pc_type = 'python'"):
        StripSimulation(StripConfig(run=StripRun(current=0.0), mesh=StripMesh(level=0), petsc=evil))
