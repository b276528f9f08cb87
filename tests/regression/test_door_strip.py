"""The strip's run through the one door (lcefem.solvers.runner.run) writes the history the run
wrote before it (byte for byte): the README's first run at the coarsest mesh,
``lcefem run strip --current 0.2 --duration 20 --mesh-level 0 --dt 1``. The stored file
(data/strip_0p2A_20s_level0_dt1_history.csv) is that command's history.csv at 029ea8c, before the
strip's transient moved onto the door; the same case through a case file's [program] and
[[exports]] gives it too."""

from __future__ import annotations

import pathlib
import subprocess

DATA = pathlib.Path(__file__).resolve().parent / "data"
GOLDEN = DATA / "strip_0p2A_20s_level0_dt1_history.csv"


def test_the_strip_through_the_door_writes_the_golden_history(tmp_path, lcefem_cmd):
    out = tmp_path / "flags"
    subprocess.run(
        [
            *lcefem_cmd,
            "run",
            "strip",
            "--current",
            "0.2",
            "--duration",
            "20",
            "--mesh-level",
            "0",
            "--dt",
            "1",
            "--no-fields",
            "--out",
            str(out),
            "--quiet",
        ],
        check=True,
        timeout=600,
        capture_output=True,
    )
    assert (out / "history.csv").read_bytes() == GOLDEN.read_bytes()


def test_a_case_file_program_gives_the_same_history(tmp_path):
    """The README's first run as a [program] (0.2 A from 0 to 20 s, dt 1 s) and [[exports]]
    (the history only), through the library: the same bytes."""
    from lcefem.solvers.problems.strip import COLUMNS, StripConfig, run_strip
    from lcefem.validation.app.config import config_from_toml, door_from_toml

    case = tmp_path / "case.toml"
    case.write_text(
        '[mesh]\nlevel = 0\n\n[program]\nclock = "time"\nduration = 20.0\ndt = 1.0\n'
        '[[program.drives]]\nat = 0.0\ncoil = 0.2\n\n[[exports]]\nkind = "history"\n'
        f'columns = {list(COLUMNS)!r}\n'.replace("'", '"')
    )
    cfg = config_from_toml(case, StripConfig(), door=True)
    program, exports = door_from_toml(case)
    result = run_strip(cfg, tmp_path / "case", progress=False, program=program, exports=exports)
    assert (tmp_path / "case" / "history.csv").read_bytes() == GOLDEN.read_bytes()
    assert result.summary["steps"] == 20 and not (tmp_path / "case" / "thermal.bp").exists()
