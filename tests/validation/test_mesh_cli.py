"""`lcefem mesh NAME --format F --out DIR`: the files and summary of a written mesh, one-line errors
(exit 2, nothing written) for bad input, and the one-line refusal under mpiexec."""

import json
import subprocess

import meshio
import pytest


def run(cmd, *args):
    return subprocess.run(cmd + list(args), capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("args, message", [
    (["rocket", "--format", "msh"], "argument NAME: invalid choice: 'rocket'"),
    (["strip", "--format", "stl"], "argument --format: invalid choice: 'stl'"),
    (["strip"], "the following arguments are required: --format"),
    (["strip", "--format", "msh", "--mesh-level", "9"], "--mesh-level = 9: the strip mesh takes 0 to 8"),
    (["ribbon", "--format", "msh", "--mesh-level", "-1"], "--mesh-level = -1: the ribbon mesh takes 0 to 6"),
    (["strip", "--format", "vtu", "--model", "bar-hinge"], "--model bar-hinge: strip has only the FE mesh"),
    (["beam", "--format", "vtu", "--model", "bar-hinge", "--mesh-level", "0"],
     "--mesh-level = 0: a bar-and-hinge structure has no refinement level"),
])
def test_bad_input_one_line_exit_2(tmp_path, lcefem_cmd, args, message):
    out = tmp_path / "out"
    res = run(lcefem_cmd, "mesh", *args, "--out", str(out))
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], res.stderr
    assert not out.exists()


def test_specimen_as_vtu_and_its_summary(tmp_path, lcefem_cmd):
    out = tmp_path / "mesh"
    res = run(lcefem_cmd, "mesh", "specimen", "--format", "vtu", "--mesh-level", "0", "--out", str(out))
    assert res.returncode == 0, res.stderr
    assert {p.name for p in out.iterdir()} == {"specimen.vtu", "specimen.tags.json", "summary.json",
                                               ".lcefem-out"}
    summary = json.loads((out / "summary.json").read_text())
    entry = summary["meshes"]["specimen"]
    # level 0: 1 mm elements on the half specimen, 36 x 4 (3.5 mm) x 1 hexahedra; end faces 4 x 1
    assert entry["cells per tag"] == {"kapton": 144, "clamp_left": 4, "clamp_right": 4, "sym_y": 36}
    assert entry["tags"]["kapton"] == {"tag": 1, "dim": 3}
    m = meshio.read(out / "specimen.vtu")
    assert m.points[:, 0].max() == pytest.approx(36.0) and m.points[:, 1].max() == pytest.approx(3.5)
    # the folder is lcefem's: a second write needs --overwrite
    again = run(lcefem_cmd, "mesh", "specimen", "--format", "vtu", "--out", str(out))
    assert again.returncode == 2 and "pass --overwrite" in again.stderr


@pytest.mark.mpi
def test_refused_under_mpiexec(tmp_path, lcefem_cmd, mpiexec):
    out = tmp_path / "out"
    res = subprocess.run([mpiexec, "-n", "2"] + lcefem_cmd + ["mesh", "strip", "--format", "msh",
                                                              "--out", str(out)],
                         capture_output=True, text=True, timeout=600)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "mesh: runs in serial only (one process writes the mesh file" in lines[0]
    assert not out.exists()
