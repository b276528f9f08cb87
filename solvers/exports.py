"""Outputs a ParaView or spreadsheet user expects, written so that an unfinished run never looks complete.

Every file is written under a ``.part`` name and renamed when :meth:`finalize` is called; a failed
run calls :meth:`finalize(complete=False)`, which renames to ``*.partial.*`` instead.
"""

from __future__ import annotations

import csv
import json
import os
import pathlib
import shutil

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import dolfinx


def _partial_name(path: pathlib.Path) -> pathlib.Path:
    """history.csv -> history.partial.csv; fields.bp -> fields.partial.bp."""
    return path.with_name(f"{path.stem}.partial{path.suffix}")


def _move(src: pathlib.Path, dst: pathlib.Path) -> None:
    if dst.is_dir():
        shutil.rmtree(dst)
    elif dst.exists():
        dst.unlink()
    os.replace(src, dst)


class _Atomic:
    def __init__(self, path: pathlib.Path, comm: MPI.Comm):
        self.path = pathlib.Path(path)
        self.part = self.path.with_name(self.path.name + ".part")
        self.comm = comm

    def _finish(self, complete: bool) -> None:
        self.comm.barrier()
        if self.comm.rank == 0 and self.part.exists():
            _move(self.part, self.path if complete else _partial_name(self.path))
        self.comm.barrier()


class FieldExport(_Atomic):
    """VTX (ADIOS2 .bp) time series of dolfinx Functions sharing one element, readable by ParaView."""

    def __init__(self, path: pathlib.Path, functions: list[dolfinx.fem.Function], comm: MPI.Comm):
        super().__init__(path, comm)
        self._writer = dolfinx.io.VTXWriter(comm, self.part, functions, engine="BP4")

    def write(self, t: float) -> None:
        self._writer.write(t)

    def finalize(self, complete: bool = True) -> None:
        self._writer.close()
        self._finish(complete)


class HistoryCSV(_Atomic):
    """A CSV time history, one row per step, header with units (e.g. ``time [s]``), flushed every row."""

    def __init__(self, path: pathlib.Path, columns: list[str], comm: MPI.Comm):
        super().__init__(path, comm)
        self.columns = list(columns)
        self.rows: list[list[float]] = []
        self._fh = None
        if comm.rank == 0:
            self.part.parent.mkdir(parents=True, exist_ok=True)
            self._fh = self.part.open("w", newline="")
            self._csv = csv.writer(self._fh)
            self._csv.writerow(self.columns)

    def append(self, row: dict[str, float]) -> None:
        values = [float(row[c]) for c in self.columns]
        self.rows.append(values)
        if self._fh is not None:
            self._csv.writerow([f"{v:.10g}" for v in values])
            self._fh.flush()

    def column(self, name: str):
        import numpy as np
        return np.array([r[self.columns.index(name)] for r in self.rows])

    def finalize(self, complete: bool = True) -> None:
        if self._fh is not None:
            self._fh.close()
        self._finish(complete)


def write_json(path: pathlib.Path, data: dict, comm: MPI.Comm = MPI.COMM_WORLD) -> None:
    """Write JSON atomically (temporary name, then rename) from rank 0."""
    path = pathlib.Path(path)
    if comm.rank == 0:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.name + ".part")
        tmp.write_text(json.dumps(_finite(data), indent=2, default=_jsonable, allow_nan=False) + "\n")
        os.replace(tmp, path)
    comm.barrier()


def _finite(obj):
    """NaN and infinities become null: strict JSON has no NaN."""
    import math
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def _jsonable(obj):
    import numpy as np
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, pathlib.Path):
        return str(obj)
    if isinstance(obj, tuple):
        return list(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
