"""Outputs a ParaView or spreadsheet user expects, written so that an unfinished run never looks complete.

Every file is written under a ``.part`` name and renamed when :meth:`finalize` is called; a failed
run calls :meth:`finalize(complete=False)`, which renames to ``*.partial.*`` instead (the convention
of lcefem.solvers.runtime.files).

* :class:`FieldExport`, :func:`write_snapshot` — VTX (ADIOS2 .bp) series of dolfinx Functions (the
  FE problems); FEniCSx is imported when one is built, so the bar-and-hinge and rod runs start
  without it.
* :class:`BarHingeVTK` — one VTK PolyData file (.vtp) per converged step in ``<stem>_steps/`` and a
  ParaView collection ``<stem>.pvd`` over them (lcefem.solvers.runtime.files.FrameSeries): the ribbon's N5B8
  triangles and the strip and glue bars as lines, with point data ``displacement [mm]`` and cell data
  ``element`` (0 ribbon, 1 bottom strip, 2 top strip, 3 glue) and ``axial force [N]`` (tension
  positive; 0 on triangles).
* :class:`BarHingeFrames`, :class:`FEFields` — export objects of a run (lcefem.solvers.runner):
  each opens its writer in the run's folder, writes one frame per converged step and, for the
  bar-and-hinge frames, the last converged state of a failed run.
"""

from __future__ import annotations

import pathlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.solvers.der.output import write_vtp
from lcefem.solvers.runtime.files import (FrameSeries, library_os_error, part_name, partial_name,
                                          refuse_link, replace)
from lcefem.solvers.runtime.run import Run

if TYPE_CHECKING:  # annotations only: FEniCSx is imported when an FE export is built
    import dolfinx
    from mpi4py import MPI


class FieldExport:
    """VTX (ADIOS2 .bp) time series of dolfinx Functions sharing one element, readable by ParaView."""

    def __init__(self, path: pathlib.Path, functions: list[dolfinx.fem.Function], comm: MPI.Comm):
        import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
        import dolfinx

        self.path = pathlib.Path(path)
        self.comm = comm
        self._broken = False
        refuse_link(part_name(self.path))  # ADIOS2 would write into a planted link's target
        try:
            self._writer = dolfinx.io.VTXWriter(comm, part_name(self.path), functions, engine="BP4")
        except RuntimeError as exc:
            raise library_os_error(exc) or exc from None

    def _fail(self, exc: RuntimeError) -> BaseException:
        """The error of a failed ADIOS2 write or close (a full disk) as an OSError naming the file.
        ADIOS2's engine then retries the write in its C++ destructor, which throws there and aborts
        the process (std::terminate, exit 134): the broken writer is kept alive to the end of the
        process (one reference never released), so the command ends with its own exit status."""
        import ctypes

        if not self._broken:
            self._broken = True
            ctypes.pythonapi.Py_IncRef(ctypes.py_object(self._writer._cpp_object))
        return library_os_error(exc) or exc

    def write(self, t: float) -> None:
        if self._broken:
            return
        try:
            self._writer.write(t)
        except RuntimeError as exc:
            raise self._fail(exc) from None

    def finalize(self, complete: bool = True) -> None:
        error = None
        if not self._broken:
            try:
                self._writer.close()
            except RuntimeError as exc:  # the series is incomplete: it goes under its partial name
                error, complete = self._fail(exc), False
        self.comm.barrier()
        if self.comm.rank == 0 and part_name(self.path).exists():
            replace(part_name(self.path), self.path if complete else partial_name(self.path))
        self.comm.barrier()
        if error is not None:
            raise error


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


# -- bar-and-hinge structures ---------------------------------------------------------------
ELEMENT_CODES = {"ribbon": 0, "bottom_strips": 1, "top_strips": 2, "glue": 3}


def ribbon_triangles(structure: BarHingeStructure) -> np.ndarray:
    """The N5B8 triangles (4 per panel: centre and each edge), (4p, 3) node indices."""
    p = structure.panels
    c = structure.panel_centres
    nxt = np.roll(p, -1, axis=1)
    return np.stack([np.repeat(c, 4), p.reshape(-1), nxt.reshape(-1)], axis=1)


class BarHingeVTK(FrameSeries):
    """VTK PolyData time series of a bar-and-hinge structure (see module docstring)."""

    def __init__(self, out: pathlib.Path, stem: str, structure: BarHingeStructure):
        import pyvista  # imported here: only runs that write fields pay for it

        super().__init__(out, stem)
        self._pv = pyvista
        self.structure = structure
        tri = ribbon_triangles(structure)
        self._faces = np.hstack([np.full((tri.shape[0], 1), 3), tri]).ravel()
        self._line_groups = [g for g in ("bottom_strips", "top_strips", "glue") if g in structure.bars]
        pairs = [structure.bars[g] for g in self._line_groups]
        lines = np.vstack(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)
        self._lines = np.hstack([np.full((lines.shape[0], 1), 2), lines]).ravel()
        self._codes = np.concatenate(
            [np.full(tri.shape[0], ELEMENT_CODES["ribbon"])]
            + [np.full(structure.bars[g].shape[0], ELEMENT_CODES[g]) for g in self._line_groups])

    def polydata(self, x: np.ndarray, bar_forces: dict[str, np.ndarray]):
        """The state with positions x (n, 3) [mm] and bar forces by group [N]."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        poly = self._pv.PolyData(x, faces=self._faces, lines=self._lines)
        # VTK orders cells: vertices, lines, polygons. Build cell data in that order.
        n_tri = self._faces.size // 4
        n_lin = self._lines.size // 3
        codes = np.concatenate([self._codes[n_tri:], self._codes[:n_tri]])
        forces = np.concatenate([*(bar_forces[g] for g in self._line_groups), np.zeros(n_tri)]) \
            if n_lin else np.zeros(n_tri)
        poly.cell_data["element"] = codes.astype(np.int32)
        poly.cell_data["axial force [N]"] = forces
        poly.point_data["displacement [mm]"] = x - self.structure.nodes
        return poly

    def write(self, t: float, x: np.ndarray, bar_forces: dict[str, np.ndarray]) -> pathlib.Path:
        """Write the state at load factor ``t``."""
        poly = self.polydata(x, bar_forces)
        return super().write(t, lambda path: write_vtp(path, poly))

    def write_single(self, path: pathlib.Path, x: np.ndarray, bar_forces: dict[str, np.ndarray]) -> None:
        """Write one state to ``path`` (.vtp) atomically (e.g. the last converged state of a failed run)."""
        path = pathlib.Path(path)
        tmp = part_name(path)
        refuse_link(tmp)
        write_vtp(tmp, self.polydata(x, bar_forces))
        replace(tmp, path)


@dataclass(frozen=True)
class BarHingeFrames:
    """Export object: ParaView frames of a bar-and-hinge run, ``<stem>.pvd`` + ``<stem>_steps/*.vtp``
    (one per converged increment, at its load factor), and ``last_converged.vtp`` when it fails.
    :meth:`open` gives the writer of one run."""

    stem: str
    structure: BarHingeStructure
    model: object  # the BarHingeModel (its bar forces)

    def open(self, run: Run, out: pathlib.Path) -> "_BarHingeFramesWriter":
        return _BarHingeFramesWriter(run.output(BarHingeVTK(out, self.stem, self.structure)), self.model)


class _BarHingeFramesWriter:
    def __init__(self, vtk: BarHingeVTK, model):
        self.vtk, self.model = vtk, model

    def write(self, state) -> None:
        self.vtk.write(state.t, state.x, self.model.bar_forces(state.x))

    def last_converged(self, folder: pathlib.Path, state) -> None:
        self.vtk.write_single(folder / "last_converged.vtp", state.x, self.model.bar_forces(state.x))


@dataclass(frozen=True)
class FEFields:
    """Export object: a VTX (.bp) series of dolfinx Functions (``name`` in the run's folder), the
    start at time 0 (unless ``start`` is False: a run that records its start as a step) and then
    one frame per converged step at ``time(state)``; with ``every`` > 1, only at the steps
    ``step(state)`` that are multiples of it. ``update()`` (optional) refreshes derived Functions
    (an interpolated field) before a frame."""

    name: str
    functions: tuple
    comm: object
    time: Callable[[object], float]
    start: bool = True
    every: int = 1
    step: Callable[[object], int] | None = None
    update: Callable[[], None] | None = None

    def open(self, run: Run, out: pathlib.Path) -> "_FEFieldsWriter":
        fields = run.output(FieldExport(out / self.name, list(self.functions), self.comm))
        if self.start:
            fields.write(0.0)
        return _FEFieldsWriter(fields, self)


class _FEFieldsWriter:
    def __init__(self, fields: FieldExport, spec: FEFields):
        self.fields, self.spec = fields, spec

    def write(self, state) -> None:
        spec = self.spec
        if spec.every > 1 and spec.step(state) % spec.every != 0:
            return
        if spec.update is not None:
            spec.update()
        self.fields.write(spec.time(state))

    def last_converged(self, folder: pathlib.Path, state) -> None:
        pass  # the series itself is kept as *.partial.* up to the last converged step
