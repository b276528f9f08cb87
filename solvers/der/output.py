"""Files a ParaView or spreadsheet user expects, written so an unfinished run never looks complete.

* :class:`PolylineSeries`: a VTK PolyData time series, frames ``<name>_steps/<name>_NNNNN.vtp`` (in
  ``<name>_steps.part/`` during the run) and the index ``<name>.pvd`` (``.partial`` names for a
  failed run), the convention of lcefem.solvers.runtime.files.FrameSeries.
* ``CSVSeries``: the run skeleton's CSV table (units in the headers, same naming rules).

Only numpy and VTK (the ``vtk`` wheel that pyvista uses); no FEniCSx.
"""

from __future__ import annotations

import pathlib
from typing import TYPE_CHECKING

import numpy as np

from lcefem.solvers.runtime.files import CSVTable, FrameSeries

# VTK is imported where a frame is written: 0.7 s that a refused input never needs.
if TYPE_CHECKING:
    import vtk


def polydata(
    points: np.ndarray,
    lines: list[np.ndarray] | None = None,
    quads: np.ndarray | None = None,
    point_data: dict[str, np.ndarray] | None = None,
) -> vtk.vtkPolyData:
    """vtkPolyData with the given points (n, 3), polylines (lists of point ids), quads (m, 4) and
    point arrays ((n,) or (n, 3))."""
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

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


class PolylineSeries(FrameSeries):
    """A ParaView time series of PolyData frames (lcefem.solvers.runtime.files.FrameSeries)."""

    def __init__(self, folder: pathlib.Path, name: str):
        super().__init__(folder, name)

    def write(self, time: float, data: vtk.vtkPolyData) -> pathlib.Path:
        return super().write(time, lambda path: write_vtp(path, data))


def write_vtp(path: pathlib.Path, data: vtk.vtkPolyData) -> None:
    """VTK XML PolyData (binary) at ``path``, whatever its suffix (e.g. a ``.part`` name)."""
    import vtk

    writer = vtk.vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(data)
    writer.SetDataModeToBinary()
    if writer.Write() != 1:
        raise OSError(f"could not write {path}")


CSVSeries = CSVTable  # one CSV writer for every run (lcefem.solvers.runtime.files)
