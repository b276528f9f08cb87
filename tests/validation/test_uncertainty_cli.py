"""``lcefem uncertainty gridshell``: bad input refused in one line before the out folder is made."""

import subprocess

import pytest


@pytest.mark.parametrize(
    "args, field",
    [
        (["--shape", "blob"], "--shape"),
        (["--samples", "2"], "--samples"),
        (["--sobol-samples", "1000"], "--sobol-samples"),
        (["--model-set", "fitted"], "--model-set"),
    ],
)
def test_bad_input_is_refused_in_one_line(tmp_path, lcefem_cmd, args, field):
    out = tmp_path / "o"
    p = subprocess.run(
        [*lcefem_cmd, "uncertainty", "gridshell", *args, "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 2
    assert p.stderr.strip().count("\n") == 0 and field in p.stderr
    assert not out.exists()
