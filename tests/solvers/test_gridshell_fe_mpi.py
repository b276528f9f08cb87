"""Every drive of the FE gridshell on two ranks gives the serial answer (issue 46 item 1): the
heated route's coils through the pads and glue squares (each pad takes the current of the nearest
strip in the whole model, ties to the smaller tag), the current route and a --layout run (the gmsh
mesh, built on rank 0) from the command line under ``mpiexec -n 2``."""

import json
import subprocess
import sys

import numpy as np
import pytest

from tests.conftest import REPO

#: The level-0 full model heated with every strip its own current (0.01 + 0.005 k A, k the strip's
#: place in the sorted tags) and the junctions heated ("added", "spread"): the power density of
#: every cell [mW/mm^3], by original cell index, the channels' coil shares and the total power.
_PADS = """
import json, sys
import dolfinx_solver  # noqa: F401
import numpy as np
from lcefem.meshes.gridshell_fe import GridshellFEMesh
from lcefem.solvers.problems.gridshell import GridshellConfig
from lcefem.solvers.problems.gridshell_heated import HeatedGridshellFE

out = {}
for heating in ("added", "spread"):
    m = HeatedGridshellFE(GridshellConfig(mesh=GridshellFEMesh(level=0), symmetry="full"),
                          junction_heating=heating)
    comm = m.tmesh.mesh.comm
    m.set_drives({t: 0.01 + 0.005 * k for k, t in enumerate(sorted(m.strip_tags))})
    owned = m.V0.dofmap.index_map.size_local
    local = m._cell_dof < owned
    cells = np.empty(owned, dtype=np.int64)  # original cell index of each owned DG0 dof
    cells[m._cell_dof[local]] = np.asarray(m.tmesh.mesh.topology.original_cell_index)[
        np.flatnonzero(local)]
    c = np.concatenate(comm.allgather(cells))
    p = np.concatenate(comm.allgather(m.power.x.array[:owned]))
    pads = sum(int(np.sum(pd < owned)) for pd, _ in m._pad_sources)
    out[heating] = {"power": p[np.argsort(c)].tolist(), "share": m.coil_share,
                    "joule [mW]": m.joule_power(), "pads": comm.allreduce(pads),
                    "ranks": comm.size}
if comm.rank == 0:
    json.dump(out, open(sys.argv[1], "w"))
"""


@pytest.mark.mpi
def test_pad_coils_on_two_ranks_take_the_serial_strips(tmp_path, mpiexec):
    # Before the global search each rank took the nearest strip among its own and ghost cells,
    # ties by its tree's order: measured 2026-12-07, 18 of the 2520 cells of this drive took
    # another strip's power density on 2 ranks (total power 47029 against the serial 46982 mW);
    # the global search without the tie rule still left 8 (24 of the 216 top pads in the bands
    # lie exactly midway between two top strips).
    script = tmp_path / "pads.py"
    script.write_text(_PADS)
    res = {}
    for ranks in (1, 2):
        out = tmp_path / f"{ranks}.json"
        subprocess.run(
            [mpiexec, "-n", str(ranks), sys.executable, str(script), str(out)],
            check=True,
            timeout=600,
        )
        res[ranks] = json.loads(out.read_text())
    for heating in ("added", "spread"):
        s, p = res[1][heating], res[2][heating]
        assert s["ranks"] == 1 and p["ranks"] == 2
        assert s["pads"] > 0 and p["pads"] == s["pads"]  # the pads in the coils' bands
        # the same cell values (copied, not summed): exact
        assert p["power"] == s["power"] and p["share"] == s["share"]
        assert p["joule [mW]"] == pytest.approx(s["joule [mW]"], rel=1e-13)
        assert len(set(s["power"])) > 50  # every strip its own power density
    assert set(res[1]["spread"]["share"]) == {"Tx", "Ty", "Bx", "By"}


def _two_ranks(serial_and_two_ranks, cmd, argv) -> dict:
    """The summary of ``lcefem run gridshell --model fe ARGV`` under ``mpiexec -n 2``."""
    (parallel,) = serial_and_two_ranks(
        [*cmd, "run", "gridshell", "--model", "fe", *argv, "--quiet", "--out", "{out}"],
        ranks=(2,),
        timeout=1200,
    )
    return json.loads((parallel.out / "summary.json").read_text())


#: The serial answers of the two command-line runs below (the same commands, one process), stored
#: so that only the 2-rank run is solved here (39 s CPU saved, issue 48); a change of the FE
#: gridshell's serial answer shows first in tests/regression and the gallery's ex08.
SERIAL = REPO / "tests" / "regression" / "data" / "gridshell_fe_mpi_serial.json"


def _stored_serial(run: str) -> dict:
    return json.loads(SERIAL.read_text())["runs"][run]


def _same(serial: dict, parallel: dict, keys) -> None:
    # the same answer up to the factorisations' round-off
    assert serial["status"] == parallel["status"] == "completed"
    assert serial["ranks"] == 1 and parallel["ranks"] == 2
    # Not the Newton iteration count: on 2 ranks it varies from run to run on a loaded machine
    # (the --layout run: 50, 51 and 55 against the serial 50, measured 2026-12-07), while the
    # answer stays within 1.3e-12: the path's rejected attempts end on round-off.
    assert parallel["newton iterations [-]"] > 0
    s, p = serial["results"], parallel["results"]
    for key, rel in keys.items():
        assert p[key] == pytest.approx(s[key], rel=rel, abs=0.0), key
    assert np.allclose(p["junction_centres [mm]"], s["junction_centres [mm]"], atol=1e-8, rtol=0)


@pytest.mark.mpi
@pytest.mark.slow
def test_current_route_on_two_ranks_gives_the_serial_answer(
    tmp_path, lcefem_cmd, serial_and_two_ranks
):
    # Measured 2026-12-07 (quarter, level 0, 26904 DOFs, 47 Newton iterations each): circle
    # -0.0014990269347 1/mm both, 3.3e-11 relative apart; channel temperatures 33.0687 / 45.9976 C
    # within 8e-16 relative; junction centres within 1.5e-10 mm; 21 s CPU serial, 36 s on 2 ranks.
    argv = ["--current", "Tx=0.03,Ty=0.03,Bx=0.05,By=0.05"]
    serial = _stored_serial("current")
    parallel = _two_ranks(serial_and_two_ranks, lcefem_cmd, argv)
    assert parallel["drive"] == "current" and parallel["symmetry"] == "quarter"
    r = parallel["results"]
    assert 30.0 < r["T_mean Tx [C]"] < r["T_mean Bx [C]"]  # heated, the bottom coils more
    assert r["kappa_circle_x [1/mm]"] < 0.0  # the bottom layer shorter: a dome
    temperatures = {f"T_mean {c} [C]": 1e-13 for c in ("Tx", "Ty", "Bx", "By")}
    curvatures = {f"kappa_{m}_{a} [1/mm]": 1e-9 for m in ("circle", "quad") for a in ("x", "y")}
    _same(serial, parallel, {**temperatures, **curvatures, "z_range [mm]": 1e-9})
    assert (tmp_path / "mpi2" / "fields" / "temperature.bp").is_dir()


@pytest.mark.mpi
@pytest.mark.slow
def test_layout_on_two_ranks_gives_the_serial_answer(lcefem_cmd, serial_and_two_ranks):
    # The published layout's gmsh mesh (model on rank 0, dolfinx.io.gmsh.model_to_mesh), the top
    # layer ramped to lambda 1.36. Measured 2026-12-07 (quarter, level 0, 50 Newton iterations
    # each): circle 0.0035936834 1/mm, 8e-13 relative apart; 18 s CPU serial, 31 s on 2 ranks. The
    # rhombic60 layout (full model, 101880 DOFs) also: 1.2e-10 relative, 98 s / 145 s CPU.
    argv = ["--layout", "published", "--lambda", "T=1.36"]
    serial = _stored_serial("layout")
    parallel = _two_ranks(serial_and_two_ranks, lcefem_cmd, argv)
    assert parallel["layout"] == "published" and parallel["results"]["kappa_circle_x [1/mm]"] > 0.0
    curvatures = {f"kappa_{m}_{a} [1/mm]": 1e-9 for m in ("circle", "quad") for a in ("x", "y")}
    _same(serial, parallel, {**curvatures, "z_range [mm]": 1e-9})
