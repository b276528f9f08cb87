"""Shared test fixtures. Tests assert physics: closed forms, manufactured solutions, measured values."""

import os
import pathlib
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[1]
VENV_BIN = pathlib.Path(sys.executable).parent


@pytest.fixture
def lcefem_cmd():
    """Argument list that runs the installed ``lcefem`` console command of this environment."""
    return [str(VENV_BIN / "lcefem")]


@pytest.fixture
def mpiexec():
    """Path of the MPICH ``mpiexec`` installed in this environment (from the PyPI wheel)."""
    path = VENV_BIN / "mpiexec"
    if not path.exists():
        pytest.fail(f"mpiexec not found next to {sys.executable}")
    return str(path)


os.environ.setdefault("OMP_NUM_THREADS", "1")
