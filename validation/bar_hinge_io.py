"""Outputs of the bar-and-hinge runs, with the conventions of :mod:`lcefem.solvers.exports` but
without FEniCSx: every file or folder carries a ``.part`` name until the run completes and is then
renamed; a failed run renames to ``*.partial.*`` instead, so nothing incomplete looks complete.

* :class:`BarHingeVTK` — one VTK PolyData file (.vtp) per converged step in ``<stem>_steps/`` and a
  ParaView collection ``<stem>.pvd`` over them: the ribbon's N5B8 triangles and the strip and glue
  bars as lines, with point data ``displacement [mm]`` and cell data ``element`` (0 ribbon, 1 bottom
  strip, 2 top strip, 3 glue) and ``axial force [N]`` (tension positive; 0 on triangles).
* :class:`CSVHistory` — one row per step, units in the headers.
* :func:`write_json` — atomic JSON (strict: NaN -> null).
"""

from __future__ import annotations

import csv
import json
import math
import os
import pathlib
import shutil

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure

ELEMENT_CODES = {"ribbon": 0, "bottom_strips": 1, "top_strips": 2, "glue": 3}


def _partial(path: pathlib.Path) -> pathlib.Path:
    """history.csv -> history.partial.csv; beam_steps -> beam_steps.partial."""
    return path.with_name(f"{path.stem}.partial{path.suffix}")


def _replace(src: pathlib.Path, dst: pathlib.Path) -> None:
    if dst.is_dir():
        shutil.rmtree(dst)
    elif dst.exists():
        dst.unlink()
    os.replace(src, dst)


def _finite(obj):
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {str(k): _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def _jsonable(obj):
    if isinstance(obj, (np.floating, np.integer, np.bool_)):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, pathlib.Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


def write_json(path: pathlib.Path, data: dict) -> None:
    """Write JSON atomically (``.part`` name, then rename)."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".part")
    # Round-trip through the encoder first so numpy scalars become floats before the NaN check.
    plain = json.loads(json.dumps(data, default=_jsonable))
    tmp.write_text(json.dumps(_finite(plain), indent=2, allow_nan=False) + "\n")
    os.replace(tmp, path)


class CSVHistory:
    """A CSV history written row by row to ``<name>.part`` and renamed by :meth:`finalize`."""

    def __init__(self, path: pathlib.Path, columns: list[str]):
        self.path = pathlib.Path(path)
        self.part = self.path.with_name(self.path.name + ".part")
        self.columns = list(columns)
        self.rows: list[list[float]] = []
        self.part.parent.mkdir(parents=True, exist_ok=True)
        self._fh = self.part.open("w", newline="")
        self._csv = csv.writer(self._fh)
        self._csv.writerow(self.columns)

    def append(self, row: dict[str, float]) -> None:
        values = [float(row[c]) for c in self.columns]
        self.rows.append(values)
        self._csv.writerow([f"{v:.10g}" for v in values])
        self._fh.flush()

    def column(self, name: str) -> np.ndarray:
        return np.array([r[self.columns.index(name)] for r in self.rows])

    def finalize(self, complete: bool = True) -> pathlib.Path:
        self._fh.close()
        target = self.path if complete else _partial(self.path)
        _replace(self.part, target)
        return target


def ribbon_triangles(structure: BarHingeStructure) -> np.ndarray:
    """The N5B8 triangles (4 per panel: centre and each edge), (4p, 3) node indices."""
    p = structure.panels
    c = structure.panel_centres
    nxt = np.roll(p, -1, axis=1)
    return np.stack([np.repeat(c, 4), p.reshape(-1), nxt.reshape(-1)], axis=1)


class BarHingeVTK:
    """VTK PolyData time series of a bar-and-hinge structure (see module docstring)."""

    def __init__(self, out: pathlib.Path, stem: str, structure: BarHingeStructure):
        import pyvista  # imported here: only runs that write fields pay for it

        self._pv = pyvista
        self.out = pathlib.Path(out)
        self.stem = stem
        self.structure = structure
        self.steps_dir = self.out / f"{stem}_steps"
        self.part_dir = self.out / f"{stem}_steps.part"
        if self.part_dir.exists():
            shutil.rmtree(self.part_dir)
        self.part_dir.mkdir(parents=True)
        self.entries: list[tuple[float, str]] = []
        tri = ribbon_triangles(structure)
        self._faces = np.hstack([np.full((tri.shape[0], 1), 3), tri]).ravel()
        self._line_groups = [g for g in ("bottom_strips", "top_strips", "glue") if g in structure.bars]
        pairs = [structure.bars[g] for g in self._line_groups]
        lines = np.vstack(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)
        self._lines = np.hstack([np.full((lines.shape[0], 1), 2), lines]).ravel()
        self._codes = np.concatenate(
            [np.full(tri.shape[0], ELEMENT_CODES["ribbon"])]
            + [np.full(structure.bars[g].shape[0], ELEMENT_CODES[g]) for g in self._line_groups])

    def write(self, t: float, x: np.ndarray, bar_forces: dict[str, np.ndarray]) -> pathlib.Path:
        """Write the state at load factor ``t`` (positions x (n, 3) [mm], bar forces by group [N])."""
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
        name = f"step_{len(self.entries):04d}.vtp"
        poly.save(self.part_dir / name, binary=True)
        self.entries.append((float(t), name))
        return self.part_dir / name

    def finalize(self, complete: bool = True) -> pathlib.Path:
        """Rename the step folder and write the .pvd collection (``.partial`` names if incomplete)."""
        folder = self.steps_dir if complete else _partial(self.steps_dir)
        _replace(self.part_dir, folder)
        pvd = self.out / (f"{self.stem}.pvd" if complete else f"{self.stem}.partial.pvd")
        rows = "\n".join(f'    <DataSet timestep="{t:.10g}" group="" part="0" '
                         f'file="{folder.name}/{name}"/>' for t, name in self.entries)
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                f"{rows}\n  </Collection>\n</VTKFile>\n")
        tmp = pvd.with_name(pvd.name + ".part")
        tmp.write_text(text)
        os.replace(tmp, pvd)
        return pvd

    def write_single(self, path: pathlib.Path, x: np.ndarray, bar_forces: dict[str, np.ndarray]) -> None:
        """Write one state to ``path`` (.vtp) atomically (e.g. the last converged state of a failed run)."""
        path = pathlib.Path(path)
        saved = self.write(float("nan"), x, bar_forces)
        self.entries.pop()
        _replace(saved, path)
