"""Shared test fixtures.

Tests assert physics: closed forms, manufactured solutions, measured values.
"""

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
    The tests of :data:`FAST` get the marker ``fast``."""
    for item in items:
        if item.get_closest_marker("mpi"):
            item.add_marker(pytest.mark.xdist_group("mpi"))
        path = pathlib.Path(item.path).resolve()
        if path.is_relative_to(REPO) and path.relative_to(REPO).as_posix().startswith(FAST):
            item.add_marker(pytest.mark.fast)


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
