"""Files a ParaView or spreadsheet user expects, written so that an unfinished run never looks complete.

* :class:`PolylineSeries`: a VTK PolyData time series, one ``<name>_NNNNN.vtp`` per frame (each
  written under a ``.part`` name and renamed once complete) and the index ``<name>.pvd``, kept as
  ``<name>.pvd.part`` during the run and renamed by :meth:`finalize` (to ``<name>.partial.pvd``
  for a failed run).
* :class:`CSVSeries`: a CSV table with units in the headers (``time [s]``), same naming rules.

Only numpy and VTK (the ``vtk`` wheel that pyvista uses); no FEniCSx.
"""

from __future__ import annotations

import csv
import os
import pathlib
from xml.sax.saxutils import quoteattr

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk


def _partial_name(path: pathlib.Path) -> pathlib.Path:
    return path.with_name(f"{path.stem}.partial{path.suffix}")


def polydata(points: np.ndarray, lines: list[np.ndarray] | None = None, quads: np.ndarray | None = None,
             point_data: dict[str, np.ndarray] | None = None) -> vtk.vtkPolyData:
    """vtkPolyData with the given points (n, 3), polylines (lists of point ids), quads (m, 4) and
    point arrays ((n,) or (n, 3))."""
    pd = vtk.vtkPolyData()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=float), deep=True))
    pd.SetPoints(pts)
    if lines:
        cells = vtk.vtkCellArray()
        for ids in lines:
            line = vtk.vtkPolyLine()
            line.GetPointIds().SetNumberOfIds(len(ids))
            for k, i in enumerate(ids):
                line.GetPointIds().SetId(k, int(i))
            cells.InsertNextCell(line)
        pd.SetLines(cells)
    if quads is not None and len(quads):
        cells = vtk.vtkCellArray()
        for q in np.asarray(quads, dtype=np.int64):
            cell = vtk.vtkQuad()
            for k in range(4):
                cell.GetPointIds().SetId(k, int(q[k]))
            cells.InsertNextCell(cell)
        pd.SetPolys(cells)
    for name, values in (point_data or {}).items():
        arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
        arr.SetName(name)
        pd.GetPointData().AddArray(arr)
    return pd


class PolylineSeries:
    """A ParaView time series of PolyData frames (see module docstring)."""

    def __init__(self, folder: pathlib.Path, name: str):
        self.folder = pathlib.Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.name = name
        self.frames: list[tuple[float, str]] = []
        self.index = self.folder / f"{name}.pvd"
        self._part = self.folder / f"{name}.pvd.part"

    def write(self, time: float, data: vtk.vtkPolyData) -> pathlib.Path:
        fname = f"{self.name}_{len(self.frames):05d}.vtp"
        final = self.folder / fname
        tmp = self.folder / (fname + ".part")
        writer = vtk.vtkXMLPolyDataWriter()
        writer.SetFileName(str(tmp))
        writer.SetInputData(data)
        writer.SetDataModeToBinary()
        if writer.Write() != 1:
            raise OSError(f"could not write {tmp}")
        os.replace(tmp, final)
        self.frames.append((float(time), fname))
        self._write_index(self._part)
        return final

    def _write_index(self, path: pathlib.Path) -> None:
        rows = "\n".join(f'    <DataSet timestep="{t:.10g}" part="0" file={quoteattr(f)}/>' for t, f in self.frames)
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
                f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(text)
        os.replace(tmp, path)

    def finalize(self, complete: bool = True) -> pathlib.Path:
        target = self.index if complete else _partial_name(self.index)
        if self._part.exists():
            os.replace(self._part, target)
        return target


class CSVSeries:
    """A CSV table, one row per call, header with units; ``.part`` until :meth:`finalize`."""

    def __init__(self, path: pathlib.Path, columns: list[str]):
        self.path = pathlib.Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.columns = list(columns)
        self._part = self.path.with_name(self.path.name + ".part")
        self._fh = self._part.open("w", newline="")
        self._csv = csv.writer(self._fh)
        self._csv.writerow(self.columns)

    def append(self, row: dict) -> None:
        self._csv.writerow([f"{float(row[c]):.10g}" for c in self.columns])
        self._fh.flush()

    def finalize(self, complete: bool = True) -> pathlib.Path:
        if not self._fh.closed:
            self._fh.close()
        target = self.path if complete else _partial_name(self.path)
        if self._part.exists():
            os.replace(self._part, target)
        return target
