"""`lcefem mesh NAME --format F --out DIR`: the files and summary of a written mesh, one-line errors
(exit 2, nothing written) for bad input, and under mpiexec the serial files."""

import json
import subprocess

import meshio
import numpy as np
import pytest


def run(cmd, *args):
    return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize(
    "args, message",
    [
        (["rocket", "--format", "msh"], "argument NAME: invalid choice: 'rocket'"),
        (["strip", "--format", "stl"], "argument --format: invalid choice: 'stl'"),
        (["strip"], "the following arguments are required: --format"),
        (
            ["strip", "--format", "msh", "--mesh-level", "9"],
            "--mesh-level = 9: the strip mesh takes 0 to 8",
        ),
        (
            ["ribbon", "--format", "msh", "--mesh-level", "-1"],
            "--mesh-level = -1: the ribbon mesh takes 0 to 6",
        ),
        (
            ["strip", "--format", "vtu", "--model", "bar-hinge"],
            "--model bar-hinge: strip has only the FE mesh",
        ),
        (
            ["beam", "--format", "vtu", "--model", "bar-hinge", "--mesh-level", "0"],
            "--mesh-level = 0: a bar-and-hinge structure has no refinement level",
        ),
        (
            ["strip", "--format", "msh", "--layout", "5x5"],
            "--layout: only with NAME gridshell (given strip)",
        ),
        (
            ["gridshell", "--format", "msh", "--layout", "lattice"],
            "--layout = 'lattice': a name (published",
        ),
        (
            ["gridshell", "--format", "msh", "--layout", "triangular"],
            "--layout: kind 'triangular': the FE mesh is built for orthogonal, rhombic",
        ),
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, lcefem_cmd, args, message):
    out = tmp_path / "out"
    res = run(lcefem_cmd, "mesh", *args, "--out", str(out))
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], res.stderr
    assert not out.exists()


def test_specimen_as_vtu_and_its_summary(tmp_path, lcefem_cmd):
    out = tmp_path / "mesh"
    res = run(
        lcefem_cmd, "mesh", "specimen", "--format", "vtu", "--mesh-level", "0", "--out", str(out)
    )
    assert res.returncode == 0, res.stderr
    assert {p.name for p in out.iterdir()} == {
        "specimen.vtu",
        "specimen.tags.json",
        "summary.json",
        ".lcefem-out",
    }
    summary = json.loads((out / "summary.json").read_text())
    entry = summary["meshes"]["specimen"]
    # level 0: 1 mm elements on the half specimen, 36 x 4 (3.5 mm) x 1 hexahedra; end faces 4 x 1
    assert entry["cells per tag"] == {"kapton": 144, "clamp_left": 4, "clamp_right": 4, "sym_y": 36}
    assert entry["tags"]["kapton"] == {"tag": 1, "dim": 3}
    m = meshio.read(out / "specimen.vtu")
    assert m.points[:, 0].max() == pytest.approx(36.0) and m.points[:, 1].max() == pytest.approx(
        3.5
    )
    # the folder is lcefem's: a second write needs --overwrite
    again = run(lcefem_cmd, "mesh", "specimen", "--format", "vtu", "--out", str(out))
    assert again.returncode == 2 and "pass --overwrite" in again.stderr


def test_rhombic_layout_mesh_as_msh(tmp_path, lcefem_cmd):
    """``--layout rhombic60``: the whole 3 x 3 grid made by gmsh and mapped (x, y) -> x e1 + y e2,
    e2 at 60 deg: its plan spans l + (2 p + d) cos a in x and l sin a in y, l = 4 L + 3 d + 2 tab
    the ribbon with its tabs (d = 7 mm / sin a the junction along a ribbon, L = p - d, pitch p = 37
    mm); every strip tag of the full model (24 bottom, 36 top halves) and no mirror plane."""
    import math

    from lcefem.meshes.gridshell_fe import GridshellFEMesh

    out = tmp_path / "mesh"
    res = run(
        lcefem_cmd,
        "mesh",
        "gridshell",
        "--layout",
        "rhombic60",
        "--format",
        "msh",
        "--mesh-level",
        "0",
        "--out",
        str(out),
    )
    assert res.returncode == 0, res.stderr
    entry = json.loads((out / "summary.json").read_text())["meshes"]["gridshell_rhombic60"]
    names = set(entry["tags"])
    assert sum(n.startswith(("bottom_x_", "bottom_y_")) for n in names) == 24
    assert sum(n.startswith(("top_x_", "top_y_")) for n in names) == 36
    assert (
        not names & {"sym_x", "sym_y"}
        and {"ribbon_ends_x", "ribbon_ends_y", "centre_junction"} <= names
    )
    assert entry["info"]["shear_angle"] == 60.0
    a = math.radians(60.0)
    d = 7.0 / math.sin(a)
    length = 4 * (37.0 - d) + 3 * d + 2 * GridshellFEMesh().end_tab
    m = meshio.read(out / "gridshell_rhombic60.msh")
    span = m.points.max(axis=0) - m.points.min(axis=0)
    # x: from the lowest x ribbon's start (band edge c_0 - d/2) to the highest one's end (c_2 + d/2)
    assert span[0] == pytest.approx(length + (2 * 37.0 + d) * math.cos(a), rel=1e-12)
    assert span[1] == pytest.approx(length * math.sin(a), rel=1e-12)


@pytest.mark.mpi
def test_under_mpiexec_the_gathered_meshes_equal_the_serial_ones(lcefem_cmd, serial_and_two_ranks):
    """Two ranks build each FE mesh shared, as `lcefem run` does, and rank 0 writes the gathered
    mesh: the same names, cells per tag, nodes and (sorted) coordinates as one process writes."""
    args = ["mesh", "all", "--format", "msh", "--mesh-level", "0"]
    one_rank, two_ranks = serial_and_two_ranks(
        lcefem_cmd + args + ["--out", "{out}", "--quiet"], timeout=600
    )
    serial, parallel = one_rank.out, two_ranks.out
    assert len(two_ranks.stdout.strip().splitlines()) == 1  # rank 0 prints
    one, two = (json.loads((f / "summary.json").read_text()) for f in (serial, parallel))
    assert two["processes"] == 2 and set(one["meshes"]) == set(two["meshes"])
    for stem, entry in one["meshes"].items():
        assert two["meshes"][stem]["cells per tag"] == entry["cells per tag"], stem
        assert two["meshes"][stem]["tags"] == entry["tags"], stem
        a, b = meshio.read(serial / f"{stem}.msh"), meshio.read(parallel / f"{stem}.msh")
        assert a.points.shape == b.points.shape, stem
        assert np.allclose(
            np.unique(a.points, axis=0), np.unique(b.points, axis=0), rtol=0, atol=1e-12
        )
        ca, cb = centroids(a), centroids(b)  # the same cells
        assert ca.keys() == cb.keys() and all(
            np.allclose(ca[k], cb[k], rtol=0, atol=1e-9) for k in ca
        ), stem


def centroids(m) -> dict:
    """Sorted cell centroids [mm] per (cell type, physical tag) of a mesh read back."""
    out = {}
    for block, tags in zip(m.cells, m.cell_data["gmsh:physical"]):
        for tag in np.unique(tags):
            c = m.points[block.data[tags == tag]].mean(axis=1)
            key = (block.type, int(tag))
            out[key] = np.concatenate([out[key], c]) if key in out else c
    out = {k: np.round(v, 9) for k, v in out.items()}  # the sums' last bits differ with node order
    return {k: v[np.lexsort(v.T[::-1])] for k, v in out.items()}
