"""Every built-in FE mesh (strip, beam, gridshell, ribbon, specimen at level 0) written as .msh,
.xdmf and .vtu (meshes/io.py, what `lcefem mesh NAME --format F` writes) and read back by
meshes/reader.py's read_tagged_mesh (what `lcefem run body` reads: .msh through dolfinx's gmsh
reader, .xdmf/.vtu through meshio and the sidecar <stem>.tags.json) has the built mesh's names,
cells per tag and volume per cell tag / area per facet tag; and the strip's case file run on the
exported strip (`lcefem mesh strip --format msh|xdmf|vtu`) gives the answer of its .geo."""

import shutil
import subprocess

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import numpy as np
import pytest

from lcefem.meshes.io import FORMATS, write_mesh
from lcefem.meshes.reader import physical_names, read_tagged_mesh
from tests.conftest import REPO
from tests.meshes.test_io import FE, built, fe_counts, measures

STRIP = REPO / "examples" / "bodies" / "strip"


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("request_", FE, ids=lambda r: r.body)
def test_every_fe_mesh_reads_back_into_a_body(tmp_path, request_, fmt):
    tm, m = built(request_)
    path = write_mesh(m, tmp_path, request_.stem, fmt)[-1]
    # the case file's checks see the names before any mesh is built
    assert physical_names(path, comm=MPI.COMM_SELF) == (tm.cells, tm.facets)
    read = read_tagged_mesh(path, MPI.COMM_SELF)
    assert (read.cell_names, read.facet_names) == (tm.cells, tm.facets)
    counts = {
        n: int(np.count_nonzero(read.cell_tags.values == t)) for n, t in read.cell_names.items()
    }
    counts.update(
        {n: int(np.count_nonzero(read.facet_tags.values == t)) for n, t in read.facet_names.items()}
    )
    assert counts == fe_counts(tm)
    assert read.mesh.topology.cell_name() == tm.mesh.topology.cell_name()
    assert read.info["cells"] == tm.mesh.topology.index_map(3).size_global
    ours = measures(tm.mesh, tm.cell_tags, tm.facet_tags, tm.cells, tm.facets)
    theirs = measures(read.mesh, read.cell_tags, read.facet_tags, read.cell_names, read.facet_names)
    assert theirs == pytest.approx(ours, rel=1e-12)  # same nodes: the sums differ by rounding


def read_history(path):
    import csv

    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


@pytest.mark.slow
def test_strip_case_on_the_exported_strip(tmp_path, lcefem_cmd):
    """`lcefem mesh strip --format F --mesh-level 0` for F = msh, xdmf, vtu, then the strip's case
    file with ``file = "mesh/strip.F"``: the history of `lcefem run body` (0.2 A, 2 s) equals that
    of the case's own strip.geo at size factor 1 (the same level-0 mesh, test_reader.py) to 1e-9
    relative (the node numbering differs, so the solves' rounding does)."""
    shutil.copy(STRIP / "strip.geo", tmp_path / "strip.geo")
    text = (STRIP / "case.toml").read_text()
    assert 'file = "strip.geo"' in text
    (tmp_path / "geo.toml").write_text(text)
    for fmt in FORMATS:
        res = subprocess.run(
            lcefem_cmd
            + [
                "mesh",
                "strip",
                "--format",
                fmt,
                "--mesh-level",
                "0",
                "--out",
                str(tmp_path / f"mesh_{fmt}"),
            ],
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert res.returncode == 0, res.stderr
        (tmp_path / f"{fmt}.toml").write_text(
            text.replace('file = "strip.geo"', f'file = "mesh_{fmt}/strip.{fmt}"')
        )
    histories = {}
    for name in ("geo", *FORMATS):
        res = subprocess.run(
            lcefem_cmd
            + [
                "run",
                "body",
                "--config",
                str(tmp_path / f"{name}.toml"),
                "--size-factor",
                "1",
                "--duration",
                "2",
                "--dt",
                "1",
                "--no-fields",
                "--quiet",
                "--out",
                str(tmp_path / name),
            ],
            capture_output=True,
            text=True,
            timeout=600,
        )
        assert res.returncode == 0, res.stderr
        histories[name] = read_history(tmp_path / name / "history.csv")
    geo = histories.pop("geo")
    for fmt, h in histories.items():
        assert geo.keys() == h.keys(), fmt
        for key in geo:
            np.testing.assert_allclose(
                h[key], geo[key], rtol=1e-9, atol=1e-12, err_msg=f"{fmt}: {key}"
            )
    assert geo["T_max coil [C]"][-1] > 30.0  # the coil did heat
