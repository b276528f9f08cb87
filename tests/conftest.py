"""Shared test fixtures.

Tests assert physics: closed forms, manufactured solutions, measured values.
"""

import dataclasses
import os
import pathlib
import subprocess
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


@dataclasses.dataclass(frozen=True)
class RankRun:
    """One finished run of :func:`run_serial_and_two_ranks`: its number of ranks (1 = serial, no
    mpiexec), the path that replaced ``"{out}"`` in the command, and what it printed."""

    ranks: int
    out: pathlib.Path
    stdout: str
    stderr: str


def run_serial_and_two_ranks(
    argv, root, *, ranks=(1, 2), env=None, cwd=None, timeout=900
) -> tuple[RankRun, ...]:
    """Run the command ``argv`` (a list of str) once per entry of ``ranks``: 1 as a plain process,
    n > 1 under this environment's ``mpiexec -n n``; return one :class:`RankRun` each, in order.

    Every ``"{out}"`` in ``argv`` becomes ``root / "serial"`` for the serial run and
    ``root / f"mpi{n}"`` for n ranks (a folder for ``--out``, or a file for a script that writes
    JSON there). ``env``: variables added to this process's environment (``OMP_NUM_THREADS=1`` is
    always set: a rank per core). Each run must exit 0, else the test fails with that run's stderr
    tail. The comparison is the test's own: this only owns the subprocess plumbing (issue 48), e.g.

        serial, parallel = serial_and_two_ranks(lcefem_cmd + ["run", "strip", "--out", "{out}"])
        assert read(parallel.out / "history.csv") == approx(read(serial.out / "history.csv"))

    ``ranks=(2,)`` runs only the two ranks (a test against a stored serial value)."""
    mpiexec = VENV_BIN / "mpiexec"
    if not mpiexec.exists():
        pytest.fail(f"mpiexec not found next to {sys.executable}")
    env = {**os.environ, **(env or {}), "OMP_NUM_THREADS": "1"}
    runs = []
    for n in ranks:
        out = pathlib.Path(root) / ("serial" if n == 1 else f"mpi{n}")
        prefix = [] if n == 1 else [str(mpiexec), "-n", str(n)]
        done = subprocess.run(
            prefix + [str(a).replace("{out}", str(out)) for a in argv],
            env=env,
            cwd=cwd,
            capture_output=True,
            text=True,
            timeout=timeout,
        )
        assert done.returncode == 0, f"{n} rank(s): exit {done.returncode}\n{done.stderr[-3000:]}"
        runs.append(RankRun(n, out, done.stdout, done.stderr))
    return tuple(runs)


@pytest.fixture
def serial_and_two_ranks(tmp_path):
    """:func:`run_serial_and_two_ranks` with its outputs under the test's ``tmp_path``: call it as
    ``serial, parallel = serial_and_two_ranks(argv, **options)`` (mark the test ``mpi``)."""

    def run(argv, **options):
        return run_serial_and_two_ranks(argv, tmp_path, **options)

    return run


#: The ``fast`` tier (``pytest -m fast``, run first by .ci/run): the material laws and closed forms
#: of tests/models and the fast checks of the tree (layers, docs, packaging), no mesh and no solve.
#: Measured: ``pytest -m fast`` 194 tests, 10.5 s user CPU with the collection of the whole suite
#: (39 s wall with the 2 cores at load ~10); the slowest, the layer checks' AST walks, 1.7-6.7 s
#: wall there.
FAST = (
    "tests/models/",
    "tests/test_layers.py",
    "tests/test_docs.py",
    "tests/test_docs_paths.py",
    "tests/test_docs_titles.py",
    "tests/test_packaging.py",
)


def pytest_collection_modifyitems(config, items):
    """The mpiexec tests (marker ``mpi``) run one after the other on one xdist worker (``make
    test``: ``-n 2 --dist loadgroup``): two of them side by side would put 4 ranks on the 2 cores.
    They come first in the order (a long unit started last leaves the other worker idle). The tests
    of :data:`FAST` get the marker ``fast``."""
    for item in items:
        if item.get_closest_marker("mpi"):
            item.add_marker(pytest.mark.xdist_group("mpi"))
        path = pathlib.Path(item.path).resolve()
        if path.is_relative_to(REPO) and path.relative_to(REPO).as_posix().startswith(FAST):
            item.add_marker(pytest.mark.fast)
    # The mpi group is one work unit of 4-5 minutes on one worker: collected first, it starts
    # first, and the other worker takes the rest meanwhile, instead of a lone tail at the end.
    items.sort(key=lambda item: item.get_closest_marker("mpi") is None)


def run_quick_case(name: str, out: pathlib.Path) -> list[dict]:
    """Run one registered validation case at its quick (CI) resolution; return its metrics as
    dicts."""
    from lcefem.validation.app.validate import run_case
    from lcefem.validation.cases import CaseContext, registry

    case = registry()[name]
    result = run_case(case, CaseContext(out=out / name, quick=True, progress=False), out)
    return result.metrics


def assert_phenomena_shown(name: str, metrics: list[dict]) -> None:
    """Every phenomenon declared for case ``name`` (validation/data/phenomena.toml) holds on its
    metrics: the resolution run shows the physics the case is about (issue 16)."""
    from lcefem.validation.app.phenomena import evaluate

    missing = [
        f"{p['phenomenon']} ({p['selector']} {p['condition']}: {p['values'] or 'no such metric'})"
        for p in evaluate(name, metrics)
        if not p["holds"]
    ]
    assert not missing, f"{name} does not show: " + "; ".join(missing)


def assert_failures_known(metrics: list[dict], level: str = "quick") -> None:
    """Every failing row is a known disagreement (validation/data/known_disagreements.toml) expected
    at ``level``: an explained disagreement with experiment passes, an unexplained failure does
    not."""
    from lcefem.validation.cases.reference_data import known_disagreements

    assert metrics, "the case returned no metrics"
    known = known_disagreements()

    def expected(m: dict) -> bool:
        k = known.get((m["case"], m["metric"]))
        return k is not None and k.level in (level, "both")

    unexplained = [
        f"{m['case']}: {m['metric']}: {m['value']} {m['unit']} vs {m['reference']} +- "
        f"{m['tolerance']}"
        for m in metrics
        if m["passed"] is False and not expected(m)
    ]
    assert not unexplained, "unexplained failures: " + "; ".join(unexplained)


def assert_metrics_pass(metrics: list[dict]) -> None:
    """Every checked metric passes; the message lists the failures with value, reference and
    tolerance."""
    assert metrics, "the case returned no metrics"
    failed = [
        f"{m['metric']}: {m['value']:.6g} {m['unit']} vs {m['reference']} +- {m['tolerance']}"
        for m in metrics
        if m["passed"] is False
    ]
    assert not failed, "; ".join(failed)
