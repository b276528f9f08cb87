"""Outputs a ParaView or spreadsheet user expects, written so an unfinished run never looks whole.

Every file is written under a ``.part`` name and renamed when :meth:`finalize` is called; a failed
run calls :meth:`finalize(complete=False)`, which renames to ``*.partial.*`` instead (the convention
of lcefem.solvers.runtime.files).

* :class:`FieldExport`, :func:`write_snapshot` — VTX (ADIOS2 .bp) series of dolfinx Functions (the
  FE problems); FEniCSx is imported when one is built, so the bar-and-hinge and rod runs start
  without it.
* :class:`BarHingeVTK` — one VTK PolyData file (.vtp) per converged step in ``<stem>_steps/`` and a
  ParaView collection ``<stem>.pvd`` over them (lcefem.solvers.runtime.files.FrameSeries): the
  ribbon's N5B8 triangles and the strip and glue bars as lines, with point data ``displacement
  [mm]`` and cell data ``element`` (0 ribbon, 1 bottom strip, 2 top strip, 3 glue) and ``axial force
  [N]`` (tension positive; 0 on triangles).
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
from lcefem.solvers.runtime.files import (
    FrameSeries,
    library_os_error,
    part_name,
    partial_name,
    refuse_link,
    replace,
)
from lcefem.solvers.runtime.run import Run

if TYPE_CHECKING:  # annotations only: FEniCSx is imported when an FE export is built
    from mpi4py import MPI

    import dolfinx


class FieldExport:
    """VTX (ADIOS2 .bp) time series of dolfinx Functions sharing one element, readable by
    ParaView."""

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


def write_snapshot(
    folder, name: str, functions: list[dolfinx.fem.Function], t: float = 0.0
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
        self._line_groups = [
            g for g in ("bottom_strips", "top_strips", "glue") if g in structure.bars
        ]
        pairs = [structure.bars[g] for g in self._line_groups]
        lines = np.vstack(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)
        self._lines = np.hstack([np.full((lines.shape[0], 1), 2), lines]).ravel()
        self._codes = np.concatenate(
            [np.full(tri.shape[0], ELEMENT_CODES["ribbon"])]
            + [np.full(structure.bars[g].shape[0], ELEMENT_CODES[g]) for g in self._line_groups]
        )

    def polydata(self, x: np.ndarray, bar_forces: dict[str, np.ndarray]):
        """The state with positions x (n, 3) [mm] and bar forces by group [N]."""
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        poly = self._pv.PolyData(x, faces=self._faces, lines=self._lines)
        # VTK orders cells: vertices, lines, polygons. Build cell data in that order.
        n_tri = self._faces.size // 4
        n_lin = self._lines.size // 3
        codes = np.concatenate([self._codes[n_tri:], self._codes[:n_tri]])
        forces = (
            np.concatenate([*(bar_forces[g] for g in self._line_groups), np.zeros(n_tri)])
            if n_lin
            else np.zeros(n_tri)
        )
        poly.cell_data["element"] = codes.astype(np.int32)
        poly.cell_data["axial force [N]"] = forces
        poly.point_data["displacement [mm]"] = x - self.structure.nodes
        return poly

    def write(self, t: float, x: np.ndarray, bar_forces: dict[str, np.ndarray]) -> pathlib.Path:
        """Write the state at load factor ``t``."""
        poly = self.polydata(x, bar_forces)
        return super().write(t, lambda path: write_vtp(path, poly))

    def write_single(
        self, path: pathlib.Path, x: np.ndarray, bar_forces: dict[str, np.ndarray]
    ) -> None:
        """Write one state to ``path`` (.vtp) atomically (e.g. the last converged state of a failed
        run)."""
        path = pathlib.Path(path)
        tmp = part_name(path)
        refuse_link(tmp)
        write_vtp(tmp, self.polydata(x, bar_forces))
        replace(tmp, path)


@dataclass(frozen=True)
class BarHingeFrames:
    """Export object: ParaView frames of a bar-and-hinge run, ``<stem>.pvd`` +
    ``<stem>_steps/*.vtp`` (one per converged increment, at its load factor), and
    ``last_converged.vtp`` when it fails.
    :meth:`open` gives the writer of one run."""

    stem: str
    structure: BarHingeStructure
    model: object  # the BarHingeModel (its bar forces)

    def open(self, run: Run, out: pathlib.Path) -> "_BarHingeFramesWriter":
        return _BarHingeFramesWriter(
            run.output(BarHingeVTK(out, self.stem, self.structure)), self.model
        )


class _BarHingeFramesWriter:
    def __init__(self, vtk: BarHingeVTK, model):
        self.vtk, self.model = vtk, model

    def write(self, state) -> None:
        self.vtk.write(state.t, state.x, self.model.bar_forces(state.x))

    def last_converged(self, folder: pathlib.Path, state) -> None:
        self.vtk.write_single(
            folder / "last_converged.vtp", state.x, self.model.bar_forces(state.x)
        )


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


# -- exports typed on the Problem protocol (the one door, lcefem.solvers.runner.run)
# ------------------ A user lists them (a case file's [[exports]]: kind, name, times, fields;
# FESTIM's style). Each has ``times`` (None: every record; else only the records at those times,
# which the run adds to its steps as milestones) and ``open(run, out, problem)`` giving a writer
# with ``write(record, index)`` and ``last_converged(folder, record)``; ``record`` is a StepRecord
# (lcefem.solvers.problems.protocol), ``index`` its number in the run (0: the start).


def _due(times, record, scale: float) -> bool:
    """``record`` is at one of ``times`` (None: every record); the same tolerance as the program's
    stops (lcefem.solvers.program.SAME_STOP)."""
    if times is None:
        return True
    return any(abs(record.at - t) <= 1e-9 * scale for t in times)


def _unit(name: str) -> str:
    """The unit of a "name [unit]" key."""
    return name[name.rindex("[") + 1 : -1]


def _bare(name: str) -> str:
    return name[: name.rindex("[")].strip()


@dataclass(frozen=True)
class History:
    """history.csv (``name``): one row per record, the clock then the observables the problem gives
    (``observables()``, as carried by each StepRecord), "name [unit]" headers (a column without a
    unit is refused). ``columns``: which, in order (default: the clock, then every observable of
    the first record); ``row(record)`` (optional): a body's own columns from its records (its golden
    history); ``postfix(record)``: the progress bar's note; ``where(record)`` names a step whose
    row is out of physical bounds (failure.json). The first History of a run is the run's history
    (checked against physical bounds, the progress bar, failure.json's last converged row)."""

    name: str = "history.csv"
    columns: tuple[str, ...] | None = None
    times: tuple[float, ...] | None = None
    row: Callable | None = None
    postfix: Callable | None = None
    where: Callable | None = None

    def __post_init__(self):
        from lcefem.solvers.problems.protocol import unnamed

        bad = unnamed(self.columns or ())
        if bad:
            raise ValueError(f"history columns without a unit: {bad}")

    def row_of(self, record) -> dict:
        if self.row is not None:
            return dict(self.row(record))
        return {record.clock: record.at, **record.observables}

    def open(
        self, run: Run, out: pathlib.Path, problem=None, main: bool = False
    ) -> "_HistoryWriter":
        return _HistoryWriter(self, run, out, main)


class _HistoryWriter:
    def __init__(self, spec: History, run: Run, out, main: bool):
        self.spec, self.run, self.out, self.main = spec, run, out, main
        self.table = None

    def _open(self, row: dict):
        from lcefem.solvers.problems.protocol import unnamed
        from lcefem.solvers.runtime.files import CSVTable

        columns = list(self.spec.columns or row)
        bad = unnamed(columns)
        if bad:
            raise ValueError(f"history columns without a unit: {bad}")
        if self.main:
            self.table = self.run.open_history(columns, self.spec.name)
        else:
            self.table = self.run.output(
                CSVTable(
                    None if self.out is None else self.out / self.spec.name, columns, self.run.comm
                )
            )

    def write(self, record, index: int) -> None:
        import math

        if not _due(
            self.spec.times,
            record,
            1.0 if not math.isfinite(record.at) else max(1.0, abs(record.at)),
        ):
            return
        row = self.spec.row_of(record)
        if self.table is None:
            self._open(row)
        if not self.main:
            self.table.append(row)
            return
        where = (
            self.spec.where(record)
            if self.spec.where is not None
            else f"t = {record.at:.4g} s"
            if record.clock == "time [s]"
            else f"load factor {record.at:.4g}"
        )
        self.run.record(
            row,
            where=where,
            at=record.at if math.isfinite(record.at) else None,
            postfix=None if self.spec.postfix is None else self.spec.postfix(record),
        )

    def last_converged(self, folder, record) -> None:
        pass  # the rows so far are kept as history.partial.csv


@dataclass(frozen=True)
class Fields:
    """Fields of the problem (``fields()``, by "name [unit]"; ``fields`` selects them, empty: all)
    for ParaView: dolfinx Functions as one VTX series ``name`` (.bp; Functions of one element per
    file), node arrays of a reduced-order problem as ``<name>.pvd`` + ``<name>_steps/*.vtp`` (the
    bar-and-hinge frames: :class:`BarHingeVTK`, with ``last_converged.vtp`` when a run fails).
    ``every``: a frame every n records (by their number in the run); ``times``: only at those."""

    name: str
    fields: tuple[str, ...] = ()
    times: tuple[float, ...] | None = None
    every: int = 1

    def _selected(self, problem) -> dict:
        from lcefem.models.errors import InputError

        found = problem.fields()
        missing = [f for f in self.fields if f not in found]
        if missing:
            raise InputError(
                f"exports {self.name!r}: field {missing[0]!r} not among the problem's fields "
                f"({', '.join(found)})"
            )
        return {k: found[k] for k in (self.fields or found)}

    def open(self, run: Run, out: pathlib.Path, problem=None, main: bool = False):
        chosen = self._selected(problem)
        if out is None:  # a run in memory writes no files
            return _FieldsWriter(self, problem, lambda t: None, None)
        if all(hasattr(f, "function_space") for f in chosen.values()):
            name = self.name if self.name.endswith(".bp") else f"{self.name}.bp"
            functions = list(chosen.values())
            writer = run.output(
                FieldExport(out / name, functions, functions[0].function_space.mesh.comm)
            )
            return _FieldsWriter(self, problem, lambda t: writer.write(t), None)
        structure, model = getattr(problem, "structure", None), getattr(problem, "model", None)
        if isinstance(structure, BarHingeStructure) and hasattr(model, "bar_forces"):
            vtk = run.output(BarHingeVTK(out, self.name.removesuffix(".pvd"), structure))
            key = next(iter(chosen))

            def write(t):
                x = problem.fields()[key]
                vtk.write(t, x, model.bar_forces(x))

            def last(folder):
                x = problem.fields()[key]
                vtk.write_single(folder / "last_converged.vtp", x, model.bar_forces(x))

            return _FieldsWriter(self, problem, write, last)
        points = run.output(FrameSeries(out, self.name.removesuffix(".pvd")))
        return _FieldsWriter(
            self,
            problem,
            lambda t: points.write(t, lambda p: _write_points(p, self._selected(problem))),
            None,
        )


def _write_points(path: pathlib.Path, fields: dict) -> None:
    """Node arrays as a VTK point cloud: the first (n, 3) array of positions [mm] gives the points,
    every array of n rows is point data."""
    import pyvista

    arrays = {k: np.asarray(v, dtype=float) for k, v in fields.items()}
    pos = next(
        (a.reshape(-1, 3) for k, a in arrays.items() if _unit(k) == "mm" and a.size % 3 == 0), None
    )
    if pos is None:
        raise ValueError(f"no node positions [mm] among {', '.join(arrays)}")
    poly = pyvista.PolyData(pos)
    for k, a in arrays.items():
        if a.shape[0] == pos.shape[0] or a.size == pos.size:
            poly.point_data[k] = a.reshape(pos.shape[0], -1)
    write_vtp(path, poly)


class _FieldsWriter:
    def __init__(self, spec: Fields, problem, write, last):
        self.spec, self.problem, self._write, self._last = spec, problem, write, last

    def write(self, record, index: int) -> None:
        import math

        spec = self.spec
        if (spec.every > 1 and index % spec.every != 0) or not _due(
            spec.times, record, max(1.0, abs(record.at)) if math.isfinite(record.at) else 1.0
        ):
            return
        self.problem.fields()  # refreshes derived fields (an interpolated stretch) before the frame
        self._write(record.at if math.isfinite(record.at) else 0.0)

    def last_converged(self, folder, record) -> None:
        if self._last is not None:
            self._last(folder)


class _PointTable:
    """A CSV table of a run (``name`` in its folder), the clock then ``columns``."""

    def __init__(self, run: Run, out, name: str, columns: list[str]):
        from lcefem.solvers.runtime.files import CSVTable

        self.table = run.output(CSVTable(None if out is None else out / name, columns, run.comm))


@dataclass(frozen=True)
class Probe:
    """The value of one field (``field``, "name [unit]" of ``fields()``) at one reference point
    ``point`` (x, y, z) [mm] at every record (or at ``times``), into the table ``name`` (.csv):
    the clock then the value (vector fields: one column per component, name_x, name_y, name_z).
    A dolfinx Function is evaluated in the cell holding the point (on whichever rank owns it); a
    node array at the nearest node."""

    name: str
    field: str
    point: tuple[float, float, float]
    times: tuple[float, ...] | None = None

    def open(self, run: Run, out: pathlib.Path, problem=None, main: bool = False):
        from lcefem.models.errors import InputError

        found = problem.fields()
        if self.field not in found:
            raise InputError(
                f"exports {self.name!r}: field {self.field!r} not among the problem's fields "
                f"({', '.join(found)})"
            )
        nodes = _reference_nodes(problem, found)
        value = _point_value(found[self.field], self.point, nodes)
        base, unit = _bare(self.field), _unit(self.field)
        columns = (
            [f"{base} [{unit}]"]
            if value.size == 1
            else [
                f"{base}_{'xyz'[i] if value.size == 3 else i} [{unit}]" for i in range(value.size)
            ]
        )
        return _ProbeWriter(self, run, out, problem, columns, nodes)


def _reference_nodes(problem, found: dict):
    """The reference node positions (n, 3) [mm] of a reduced-order problem (its structure's nodes,
    else the first node array in mm of its fields at the start); None for an FE problem."""
    nodes = getattr(getattr(problem, "structure", None), "nodes", None)
    if nodes is not None:
        return np.asarray(nodes, dtype=float).reshape(-1, 3)
    for k, v in found.items():
        if (
            not hasattr(v, "function_space")
            and _unit(k) == "mm"
            and np.asarray(v).ndim == 2
            and np.asarray(v).shape[1] == 3
        ):
            return np.array(v, dtype=float)
    return None


def _point_value(f, point, nodes) -> np.ndarray:
    """Field ``f`` (a dolfinx Function or a node array) at ``point`` [mm] (reference coordinates;
    a node array: at the node of ``nodes`` (n, 3) [mm] nearest to it)."""
    p = np.asarray(point, dtype=float)
    if hasattr(f, "function_space"):
        from mpi4py import MPI

        import dolfinx

        mesh = f.function_space.mesh
        tree = dolfinx.geometry.bb_tree(mesh, mesh.topology.dim)
        cells = dolfinx.geometry.compute_colliding_cells(
            mesh, dolfinx.geometry.compute_collisions_points(tree, p.reshape(1, 3)), p.reshape(1, 3)
        )
        found = cells.links(0)
        bs = f.function_space.dofmap.index_map_bs
        local = (
            f.eval(p.reshape(1, 3), found[:1]).reshape(-1) if len(found) else np.full(bs, np.nan)
        )
        comm = mesh.comm
        owner = comm.allreduce(comm.rank if len(found) else comm.size, op=MPI.MIN)
        if owner == comm.size:
            from lcefem.models.errors import InputError

            raise InputError(f"probe point {tuple(point)} mm: outside the mesh")
        return np.atleast_1d(comm.bcast(local, root=owner))
    a = np.asarray(f, dtype=float)
    if nodes is None:
        raise ValueError("a node array without node positions [mm] to probe")
    i = int(np.argmin(np.linalg.norm(nodes - p, axis=1)))
    return np.atleast_1d(a.reshape(len(nodes), -1)[i])


class _ProbeWriter:
    def __init__(self, spec: Probe, run, out, problem, columns, nodes):
        self.spec, self.problem, self.columns, self.nodes = spec, problem, columns, nodes
        self.run, self.out, self.table = run, out, None

    def write(self, record, index: int) -> None:
        import math

        if not _due(
            self.spec.times, record, max(1.0, abs(record.at)) if math.isfinite(record.at) else 1.0
        ):
            return
        if self.table is None:
            self.table = _PointTable(
                self.run, self.out, self.spec.name, [record.clock, *self.columns]
            ).table
        value = _point_value(self.problem.fields()[self.spec.field], self.spec.point, self.nodes)
        self.table.append({record.clock: record.at, **dict(zip(self.columns, value, strict=True))})

    def last_converged(self, folder, record) -> None:
        pass


@dataclass(frozen=True)
class Reaction:
    """The support reaction [N] on the named boundary ``tag`` (a facet tag of the mesh), along
    ``component`` (0 x, 1 y, 2 z), of the whole body (symmetry included), at every record (or at
    ``times``), into the table ``name`` (.csv). The problem computes it (``reaction(tag,
    component) -> float`` [N]); a problem without it, or an unknown tag, is an InputError."""

    name: str
    tag: str
    component: int = 0
    times: tuple[float, ...] | None = None

    def open(self, run: Run, out: pathlib.Path, problem=None, main: bool = False):
        from lcefem.models.errors import InputError

        if not hasattr(problem, "reaction"):
            raise InputError(
                f"exports {self.name!r}: kind 'reaction' is not available for this body "
                "(its problem computes no support reactions)"
            )
        if self.component not in (0, 1, 2):
            raise InputError(
                f"exports {self.name!r}: component = {self.component}: allowed 0, 1, 2"
            )
        problem.reaction(
            self.tag, self.component
        )  # an unknown tag fails here, before the first step
        return _ReactionWriter(self, run, out, problem)


class _ReactionWriter:
    def __init__(self, spec: Reaction, run, out, problem):
        self.spec, self.run, self.out, self.problem, self.table = spec, run, out, problem, None
        self.column = f"reaction {spec.tag} {'xyz'[spec.component]} [N]"

    def write(self, record, index: int) -> None:
        import math

        if not _due(
            self.spec.times, record, max(1.0, abs(record.at)) if math.isfinite(record.at) else 1.0
        ):
            return
        if self.table is None:
            self.table = _PointTable(
                self.run, self.out, self.spec.name, [record.clock, self.column]
            ).table
        self.table.append(
            {
                record.clock: record.at,
                self.column: self.problem.reaction(self.spec.tag, self.spec.component),
            }
        )

    def last_converged(self, folder, record) -> None:
        pass


#: The export kinds a case file's ``[[exports]]`` may name.
EXPORT_KINDS = {"history": History, "fields": Fields, "probe": Probe, "reaction": Reaction}
EXPORT_KEYS = {
    "history": ("kind", "name", "times", "columns"),
    "fields": ("kind", "name", "times", "fields", "every"),
    "probe": ("kind", "name", "times", "field", "point"),
    "reaction": ("kind", "name", "times", "tag", "component"),
}


def exports_from_tables(tables, where: str = "exports") -> list:
    """The export objects of a case file's ``[[exports]]`` list (``kind`` among
    :data:`EXPORT_KINDS`, ``name``, optional ``times`` on the program's clock, and per kind:
    ``columns``; ``fields``, ``every``; ``field``, ``point`` [mm]; ``tag``, ``component``); one
    InputError naming ``where[i].key`` and what is allowed for a bad entry."""
    from lcefem.models.errors import InputError

    if not isinstance(tables, list) or not tables:
        raise InputError(f"{where}: must be a list of tables [[{where}]] with kind and name")
    out, names = [], set()
    for i, t in enumerate(tables):
        here = f"{where}[{i}]"
        if not isinstance(t, dict):
            raise InputError(f"{here}: must be a table with kind and name")
        kind = t.get("kind")
        if kind not in EXPORT_KINDS:
            raise InputError(f"{here}.kind = {kind!r}: allowed {', '.join(EXPORT_KINDS)}")
        unknown = [k for k in t if k not in EXPORT_KEYS[kind]]
        if unknown:
            raise InputError(
                f"{here}: unknown key {unknown[0]!r} for kind {kind!r} (allowed: "
                f"{', '.join(EXPORT_KEYS[kind])})"
            )
        name = t.get("name", "history.csv" if kind == "history" else None)
        if not isinstance(name, str) or not name or "/" in name or name in names:
            raise InputError(f"{here}.name = {name!r}: a file name, unique among the exports")
        names.add(name)
        kw = {"name": name}
        if "times" in t:
            times = t["times"]
            if (
                not isinstance(times, list)
                or not times
                or any(
                    isinstance(v, bool) or not isinstance(v, (int, float)) or v < 0 for v in times
                )
            ):
                raise InputError(
                    f"{here}.times = {times!r}: a list of times [s] or load fractions [-] >= 0"
                )
            kw["times"] = tuple(float(v) for v in times)
        for key, typ, what in (
            ("columns", list, "a list of \"name [unit]\""),
            ("fields", list, "a list of field names \"name [unit]\""),
            ("field", str, "a field name \"name [unit]\""),
            ("tag", str, "a facet tag of the mesh"),
        ):
            if key in t:
                if not isinstance(t[key], typ) or (
                    typ is list and not all(isinstance(v, str) for v in t[key])
                ):
                    raise InputError(f"{here}.{key} = {t[key]!r}: {what}")
                kw[key] = tuple(t[key]) if typ is list else t[key]
        if "columns" in kw:
            from lcefem.solvers.problems.protocol import unnamed

            bad = unnamed(kw["columns"])
            if bad:
                raise InputError(f"{here}.columns: {bad[0]!r} has no unit (\"name [unit]\")")
        for key, lo in (("every", 1), ("component", 0)):
            if key in t:
                if (
                    isinstance(t[key], bool)
                    or not isinstance(t[key], int)
                    or t[key] < lo
                    or (key == "component" and t[key] > 2)
                ):
                    raise InputError(
                        f"{here}.{key} = {t[key]!r}: an integer "
                        f"{'>= 1' if key == 'every' else '0 (x), 1 (y) or 2 (z)'}"
                    )
                kw[key] = t[key]
        if kind == "probe":
            p = t.get("point")
            if (
                not isinstance(p, list)
                or len(p) != 3
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in p)
            ):
                raise InputError(f"{here}.point = {p!r}: three coordinates [mm]")
            kw["point"] = tuple(float(v) for v in p)
            if "field" not in kw:
                raise InputError(f"{here}: missing key 'field'")
        if kind == "reaction" and "tag" not in kw:
            raise InputError(f"{here}: missing key 'tag'")
        out.append(EXPORT_KINDS[kind](**kw))
    return out
