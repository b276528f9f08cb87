"""Outputs a ParaView or spreadsheet user expects, written so that an unfinished run never looks complete.

Every file is written under a ``.part`` name and renamed when :meth:`finalize` is called; a failed
run calls :meth:`finalize(complete=False)`, which renames to ``*.partial.*`` instead (the convention
of lcefem.solvers.run, whose CSV and JSON writers are re-exported here).
"""

from __future__ import annotations

import pathlib

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import dolfinx

from lcefem.solvers.run import CSVTable as HistoryCSV  # noqa: F401  (one CSV writer for every run)
from lcefem.solvers.run import part_name, partial_name, replace, write_json  # noqa: F401


class FieldExport:
    """VTX (ADIOS2 .bp) time series of dolfinx Functions sharing one element, readable by ParaView."""

    def __init__(self, path: pathlib.Path, functions: list[dolfinx.fem.Function], comm: MPI.Comm):
        self.path = pathlib.Path(path)
        self.comm = comm
        self._writer = dolfinx.io.VTXWriter(comm, part_name(self.path), functions, engine="BP4")

    def write(self, t: float) -> None:
        self._writer.write(t)

    def finalize(self, complete: bool = True) -> None:
        self._writer.close()
        self.comm.barrier()
        if self.comm.rank == 0 and part_name(self.path).exists():
            replace(part_name(self.path), self.path if complete else partial_name(self.path))
        self.comm.barrier()


def write_snapshot(folder, name: str, functions: list[dolfinx.fem.Function], t: float = 0.0
                   ) -> pathlib.Path:
    """One VTX file ``folder/name`` of ``functions`` at time ``t`` (written as .part, then renamed);
    the ``write_fields`` of the problems in lcefem.solvers.problems."""
    folder = pathlib.Path(folder)
    if functions[0].function_space.mesh.comm.rank == 0:
        folder.mkdir(parents=True, exist_ok=True)
    export = FieldExport(folder / name, functions, functions[0].function_space.mesh.comm)
    export.write(t)
    export.finalize()
    return export.path
