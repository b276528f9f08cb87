"""One run of ``lcefem run gridshell --model fe``: the 3D FE gridshell
(:class:`lcefem.solvers.problems.gridshell.GridshellFE`, prescribed lambdas, or
:class:`lcefem.solvers.problems.gridshell_heated.HeatedGridshellFE`, coil currents) for every drive
the bar-and-hinge run takes (issue 46): lambdas or currents per selection (a named shape, a
published recipe, the user's), a schedule of currents in time, on the published supports or the
table, at mesh levels 0-3; every route also on N MPI ranks (:mod:`lcefem.solvers.contact`; the
heated routes' pad coils: :meth:`HeatedGridshellFE._junction_coil_map`).

The drives are given per selection, as to the bar-and-hinge run
(:func:`lcefem.meshes.gridshell.resolve_bar_values`): a channel Tx, Ty, Bx, By, a layer T or B, a
family XD, YD, XU, YU, a group XD1..YU3, a half plane "XD:x<70.5", or an FE strip tag or group of
:mod:`lcefem.meshes.gridshell_fe` (``bottom_x_r1_s2``, ``top_x_r1_j1``); later keys override earlier
ones. They are resolved on every strip of the full surface (:func:`strip_values`), and the run takes
the smallest mirror model that is valid for them (:func:`smallest_symmetry`: a mirror plane only
where every strip carries the drive of its mirror image; the published recipes give
:data:`lcefem.meshes.gridshell_fe.RECIPE_SYMMETRY`).

Routes (``GridshellFERun.drive``):

* "lambda": the strips ramped from the as-built state to their lambdas (:meth:`GridshellFE.advance`,
  the path of the validation case gridshell_shapes_fe; a recipe's rest fraction P0 is
  lambda = lambda_N P0, lambda_N = 1.4);
* "current": the held shape at constant coil currents [A], straight to the steady state
  (:meth:`HeatedGridshellFE.steady_hold`);
* "schedule": currents switched at given times, stepped in time
  (:meth:`HeatedGridshellFE.run_protocol`): a programmed sequence such as Fig. 5A.

Outputs in the run's folder: history.csv (one row per converged path step, steady sweep or time
step; curvatures by both of the paper's measures, z range, apex, contact force, Newton iterations;
channel temperatures and stretches on the heated routes), displacement.bp (VTX, one frame per row),
fields/ (the final state: displacement.bp, cells.xdmf with lambda, von Mises stress, director;
temperature.bp on the heated routes), summary.json (the final observables, the junction centres,
per-strip drives, the model's size and cost).

Units: mm, N, MPa, s, C, A (README).
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import resource
import time
from dataclasses import dataclass, field

import numpy as np

from lcefem.meshes.gridshell import CHANNELS, FAMILIES
from lcefem.meshes.gridshell_fe import junction_centres, strip_catalogue
from lcefem.models.errors import InputError
from lcefem.models.limits import check_current
from lcefem.models.parameters import check, describe, param
from lcefem.solvers.exports import FEFields
from lcefem.solvers.problems.gridshell import GridshellConfig, GridshellSupports
from lcefem.solvers.problems.protocol import LOAD, TIME
from lcefem.solvers.runner import HistoryExport, PathProblem, StateExport, StateHistory, run
from lcefem.solvers.runtime.run import Progress

#: Routes of the FE run (GridshellFERun.drive).
DRIVES = ("lambda", "current", "schedule")
#: The bar-and-hinge supports (lcefem.solvers.problems.gridshell_bh.SUPPORTS) in the FE
#: (GridshellSupports.kind); 'middle_rollers' (our former reading of the rollers) has no FE twin.
FE_SUPPORTS = {"clamp": "centre_clamp", "rollers": "rollers", "table": "table"}
#: Largest difference [-] (lambda) or [A] (current) between a strip's drive and its mirror image's
#: that still counts as symmetric (round-off of the values given).
SYMMETRY_TOL = 1e-12
#: History columns of every route (observables of GridshellFE, "name [unit]").
SHAPE_COLUMNS = (
    "kappa_circle_x [1/mm]",
    "kappa_circle_y [1/mm]",
    "kappa_quad_x [1/mm]",
    "kappa_quad_y [1/mm]",
    "z_range [mm]",
    "apex_z [mm]",
    "contact_force [N]",
    "newton iterations [-]",
)
HEAT_COLUMNS = tuple(
    f"{q} {c} [{u}]"
    for c in ("Tx", "Ty", "Bx", "By")
    for q, u in (("T_mean", "C"), ("lambda", "-"))
)


def fe_support(kind: str) -> str:
    """The FE support kind (GridshellSupports.kind) of a bar-and-hinge support name."""
    if kind not in FE_SUPPORTS:
        raise InputError(
            f"--support {kind}: not in the 3D FE (it holds {', '.join(FE_SUPPORTS)}; "
            "'middle_rollers' is a bar-and-hinge departure)"
        )
    return FE_SUPPORTS[kind]


def _selected(catalogue: dict, key, name: str) -> list[str]:
    """FE strip tags of one selection key (module docstring)."""
    if isinstance(key, int) or (isinstance(key, str) and key.isdigit()):
        raise InputError(
            f"{name}: strip id {key}: bar-and-hinge numbering; in the 3D FE name a channel, "
            "group or FE strip tag (e.g. bottom_x_r1_s2)"
        )
    key = str(key)
    if ":" in key:
        family, cond = key.split(":", 1)
        op = "<" if "<" in cond else ">" if ">" in cond else None
        parts = cond.split(op) if op else []
        try:
            bound = (
                float(parts[1])
                if family in FAMILIES and len(parts) == 2 and parts[0] in "xy"
                else None
            )
        except ValueError:
            bound = None
        if bound is None:
            raise InputError(
                f"{name}: bad selection {key!r} (form 'XD:x<70.5': family XD, YD, XU or "
                "YU, axis x or y, < or >, a coordinate in mm)"
            )
        k = 0 if parts[0] == "x" else 1
        mine = _selected(catalogue, family, name)
        # every FE piece lies on one side: the top halves end at the glue square, the bottom
        # strips at the junctions (no piece straddles a junction centre)
        return [t for t in mine if (catalogue[t]["midpoint"][k] < bound) == (op == "<")]
    if key in catalogue:
        return [key]
    if key in ("T", "B"):
        layer = "top" if key == "T" else "bottom"
        return [t for t, s in catalogue.items() if s["layer"] == layer]
    if key in CHANNELS or key in FAMILIES:
        channel = key if key in CHANNELS else FAMILIES[key]
        return [t for t, s in catalogue.items() if s["channel"] == channel]
    groups = {s["group"] for s in catalogue.values()}
    if key in groups:
        return [t for t, s in catalogue.items() if s["group"] == key]
    whole = [t for t in catalogue if t.startswith(key + "_")]  # top_x_r1_j1 = both halves
    if key.startswith("top_") and whole:
        return whole
    segment = [
        t
        for t, s in catalogue.items()
        if s["layer"] == "top"
        and key == f"top_{s['direction']}_r{s['ribbon']}_s{s['paper_segment']}"
    ]
    if segment:
        return segment
    raise InputError(
        f"{name}: unknown strip selection {key!r} (channels Tx, Ty, Bx, By; T, B; "
        "families XD, YD, XU, YU; groups XD1..YU3; half planes like 'XD:x<70.5'; FE "
        "strip tags like bottom_x_r1_s2, top_x_r1_j1)"
    )


def strip_values(
    assignments: dict, catalogue: dict, default: float, name: str = "lambda"
) -> dict[str, float]:
    """The value of every FE strip tag of the full surface (``catalogue``:
    :func:`lcefem.meshes.gridshell_fe.strip_catalogue`) from ``{selection: value}`` applied in
    order; strips not named get ``default``."""
    out = dict.fromkeys(catalogue, float(default))
    for key, value in assignments.items():
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or not math.isfinite(value)
        ):
            raise InputError(f"{name} {key} = {value!r}: must be a finite number")
        for tag in _selected(catalogue, key, name):
            out[tag] = float(value)
    return out


def mirror_image(catalogue: dict, tag: str, axis: int, centre: float) -> str:
    """The strip tag whose as-built midpoint is the mirror image of ``tag``'s in the plane
    x_axis = ``centre`` [mm] (same layer and direction)."""
    s = catalogue[tag]
    p = list(s["midpoint"])
    p[axis] = 2.0 * centre - p[axis]
    for other, o in catalogue.items():
        if (
            (o["layer"], o["direction"]) == (s["layer"], s["direction"])
            and abs(o["midpoint"][0] - p[0]) < 1e-6
            and abs(o["midpoint"][1] - p[1]) < 1e-6
        ):
            return other
    raise RuntimeError(f"strip {tag}: no mirror image in the plane {'xy'[axis]} = {centre} mm")


def smallest_symmetry(fields: list[dict], catalogue: dict, centre: float) -> str:
    """The smallest mirror model (meshes.gridshell_fe.SYMMETRIES) in which every drive field of
    ``fields`` ({strip tag: value}) is mirror-symmetric: 'quarter', 'half_x' (mirror plane x = c),
    'half_y' or 'full'."""
    sym = []
    for axis in (0, 1):
        pairs = [(t, mirror_image(catalogue, t, axis, centre)) for t in catalogue]
        sym.append(all(abs(f[a] - f[b]) <= SYMMETRY_TOL for f in fields for a, b in pairs))
    return {
        (True, True): "quarter",
        (True, False): "half_x",
        (False, True): "half_y",
        (False, False): "full",
    }[tuple(sym)]


@dataclass(frozen=True)
class GridshellFERun:
    """What the run does (module docstring)."""

    drive: str = param(
        "lambda",
        "-",
        "'lambda' (ramp from as built), 'current' (steady hold) or 'schedule' (currents in time)",
    )
    symmetry: str = param(
        "",
        "-",
        "mirror model: '' (the smallest valid for the drives, "
        "smallest_symmetry), 'quarter', 'half_x', 'half_y' or 'full'",
    )
    duration: float = param(0.0, "s", "schedule: end time", minimum=0.0)
    dt: float = param(
        5.0, "s", "schedule: time step (the schedule's output interval)", positive=True
    )
    label: str = param("", "-", "what is run (a shape, a recipe), for the summary and the bar")


@dataclass(frozen=True)
class GridshellFERunConfig:
    """The FE gridshell (``model``: mesh, supports, materials, contact, path control; its symmetry
    is set by the run) and its drives per selection: lambdas [-] (route 'lambda'), currents [A]
    ('current'), or a protocol ((start time [s], {selection: current [A]}), ...) ('schedule')."""

    model: GridshellConfig = field(default_factory=GridshellConfig)
    run: GridshellFERun = field(default_factory=GridshellFERun)
    lambdas: dict = field(default_factory=dict)
    currents: dict = field(default_factory=dict)
    protocol: tuple = ()
    #: What the caller knows of the drive (the shape, recipe or schedule behind it, the rule behind
    #: its currents), written into the summary.
    notes: dict = field(default_factory=dict)

    def catalogue(self) -> dict:
        m = self.model
        # the as-built strip width W_s = w_a / sqrt(lambda_N) of the mesh (meshes.gridshell_fe)
        return strip_catalogue(m.geometry, m.cells, m.geometry.strip_width / math.sqrt(m.lambda_N))

    def drive_fields(self) -> list[dict]:
        """The per-strip drives of the full surface: one field for a ramp or a hold, one per switch
        of a schedule."""
        cat, r = self.catalogue(), self.run
        if r.drive == "lambda":
            return [strip_values(self.lambdas, cat, self.model.lambda_N, "lambda")]
        if r.drive == "current":
            return [strip_values(self.currents, cat, 0.0, "current")]
        fields, running = [], {}
        for _, currents in self.protocol:  # a switch keeps the currents it does not name
            running = {**running, **currents}
            fields.append(strip_values(running, cat, 0.0, "current"))
        return fields

    def validated(self) -> "GridshellFERunConfig":
        r = self.run
        check(r, "run")
        if r.drive not in DRIVES:
            raise InputError(f"run.drive = {r.drive!r}: allowed {', '.join(DRIVES)}")
        if r.symmetry and r.symmetry not in ("quarter", "half_x", "half_y", "full"):
            raise InputError(
                f"run.symmetry = {r.symmetry!r}: allowed quarter, half_x, half_y, full"
            )
        check(self.model.mesh, "mesh")
        if not 0 <= self.model.mesh.level <= 3:
            raise InputError(f"--mesh-level = {self.model.mesh.level}: allowed 0..3")
        self.model.supports.checked()
        if r.drive == "schedule":
            times = [float(t) for t, _ in self.protocol]
            if not times or times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
                raise InputError(f"schedule times {times}: must start at 0 s and increase")
            if not r.duration > 0:
                raise InputError(f"schedule end = {r.duration} s: must be > 0")
        for f in self.drive_fields():
            for tag, v in f.items():
                if r.drive == "lambda":
                    if not 1.0 <= v <= self.model.lambda_N + 1e-12:
                        raise InputError(
                            f"lambda {tag} = {v}: must be between 1 (isotropic) and "
                            f"lambda_N = {self.model.lambda_N}"
                        )
                else:
                    check_current(f"current {tag}", v)
        return self

    @property
    def symmetry(self) -> str:
        """The mirror model the run uses (``run.symmetry``, else the smallest valid one; a rhombic
        mesh, ``mesh.shear_angle`` other than 90 deg, has no mirror plane x = c or y = c: full)."""
        if self.run.symmetry:
            return self.run.symmetry
        m = self.model
        if m.mesh.shear_angle != 90.0:
            return "full"
        centre = float(np.mean(junction_centres(m.geometry, m.cells)))
        return smallest_symmetry(self.drive_fields(), self.catalogue(), centre)

    def resolved(self) -> dict:
        m = self.model
        return {
            "run": describe(self.run),
            "symmetry (resolved)": self.symmetry,
            "mesh": describe(m.mesh),
            "supports": describe(m.supports),
            "contact": describe(m.contact),
            "control": describe(m.control),
            "lambda_N [-]": m.lambda_N,
            "cells": m.cells,
            "lambda": {str(k): v for k, v in self.lambdas.items()},
            "current": {str(k): v for k, v in self.currents.items()},
            "protocol": [[t, {str(k): v for k, v in c.items()}] for t, c in self.protocol],
        }


def build_model(cfg: GridshellFERunConfig, comm=None):
    """The FE gridshell of the run: :class:`GridshellFE` (lambda route) or
    :class:`HeatedGridshellFE` (current, schedule), on the run's mirror model."""
    model_cfg = dataclasses.replace(cfg.model, symmetry=cfg.symmetry)
    if cfg.run.drive == "lambda":
        from lcefem.solvers.problems.gridshell import GridshellFE

        return GridshellFE(model_cfg, comm)
    from lcefem.solvers.problems.gridshell_heated import HeatedGridshellFE

    return HeatedGridshellFE(model_cfg, comm=comm)


def in_model(model, values: dict[str, float]) -> dict[str, float]:
    """The drives of the strip tags this (mirror) model holds."""
    return {tag: v for tag, v in values.items() if tag in model.strip_tags}


def ramp_cost(model, seconds: float, cpu: float) -> dict:
    """The cost of a solve: DOFs, Newton iterations, path steps and cuts (the last path follower),
    wall and CPU time [s], the process's peak resident memory so far [MiB] (getrusage)."""
    f = model.last_follower
    return {
        "dofs [-]": model.ndofs,
        "newton iterations [-]": f.iterations if f is not None else 0,
        "path steps [-]": getattr(f, "substeps", 0),
        "step cuts [-]": getattr(f, "cuts", 0),
        "wall time [s]": seconds,
        "cpu time [s]": cpu,
        "process peak memory [MiB]": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    }


def run_gridshell_fe(
    cfg: GridshellFERunConfig, out: pathlib.Path, progress: bool = True, report=None, comm=None
) -> dict:
    """Run the FE gridshell (module docstring) through the runner
    (the door, :func:`lcefem.solvers.runner.run`) into ``out``; returns the summary. ``report(out,
    cfg, model) -> dict`` (optional: the validation's render) runs before the summary is written;
    its entries join the results; ``cfg.notes`` join the summary. A steady hold also gives "held"
    (the final observables) and "cpu [s]", the entries
    lcefem.validation.studies.gridshell.gridshell_fe_current_store reads."""
    cfg = cfg.validated()
    out = pathlib.Path(out)
    r = cfg.run
    model = build_model(cfg, comm)
    comm = model.tmesh.mesh.comm
    heated = r.drive != "lambda"
    columns = [
        "load factor [-]"
        if r.drive == "lambda"
        else "steady sweep [-]"
        if r.drive == "current"
        else "time [s]",
        *SHAPE_COLUMNS,
        *(HEAT_COLUMNS if heated else ()),
    ]
    started, cpu0 = time.perf_counter(), time.process_time()
    fields = cfg.drive_fields()
    total = {"lambda": 1.0, "current": 1.0, "schedule": r.duration}[r.drive]
    bar = Progress(
        total,
        f"gridshell (FE, {cfg.symmetry}) {r.label}".rstrip(),
        "load" if r.drive == "lambda" else "s",
        ".3f",
        progress,
        comm=comm,
    )
    key = columns[0]

    def row(state: dict) -> dict:
        return {c: float(state.get(c, math.nan)) for c in columns}

    def where(state: dict) -> str:
        return f"{key.split(' [')[0]} {state.get(key, math.nan):.4g}"

    def at(state: dict) -> float:
        return state.get(key, 0.0) if r.drive != "current" else 0.0

    history = HistoryExport(tuple(columns), row, where=where, at=at)
    export = FEFields(
        "displacement.bp", (model.u,), comm, lambda s: float(s.get(key, 0.0)), start=False
    )

    newton = [0]  # Newton iterations of every row (a path step, a steady sweep, a time step)

    def drive(record):
        def on_step(state: dict) -> None:
            newton[0] += int(state.get("newton iterations [-]", 0))
            record(state)

        if r.drive == "lambda":
            model.set_drives(in_model(model, fields[0]))
            on_step({key: 0.0, **model.observables(), "newton iterations [-]": 0})
            return model.advance(
                1.0,
                on_step=lambda st: on_step(
                    {key: st.load_factor, **st.observables, "newton iterations [-]": st.iterations}
                ),
            )
        if r.drive == "current":
            rows = model.steady_hold(
                in_model(model, fields[0]),
                on_step=lambda row: on_step({**row, key: row["steady sweep [-]"]}),
            )
            bar.to(1.0)
            return rows
        protocol = [(t, in_model(model, f)) for (t, _), f in zip(cfg.protocol, fields)]
        return model.run_protocol(
            protocol, r.duration, r.dt, on_step=lambda row: on_step({**row, key: row["time [s]"]})
        )

    def summarize(run, result) -> dict:
        obs = model.observables()
        n = model.info["cells_per_direction"]
        centres = model.junction_centres().reshape(n, n, 3)
        extra = report(out, cfg, model) if report is not None else {}
        model.write_fields(out / "fields")
        drives = "lambda [-]" if r.drive == "lambda" else "current [A]"
        summary = {
            "model": "3D FE gridshell (lcefem.solvers.problems."
            + (
                "gridshell.GridshellFE)"
                if r.drive == "lambda"
                else "gridshell_heated.HeatedGridshellFE)"
            ),
            "drive": r.drive,
            "label": r.label,
            "symmetry": cfg.symmetry,
            "mesh level": cfg.model.mesh.level,
            "support": cfg.model.supports.kind,
            "ranks": comm.size,
            "results": {
                **{k: v for k, v in obs.items() if not k.startswith("junction_")},
                "junction_centres [mm]": centres.tolist(),
                **(extra or {}),
                "sign convention": "kappa + for a bowl, - for a dome (seed 001, Fig. 4)",
            },
            f"per-strip {drives} (full surface, the last switch)": fields[-1],
            **ramp_cost(model, time.perf_counter() - started, time.process_time() - cpu0),
            "newton iterations [-]": newton[0],
            **cfg.notes,
        }
        if r.drive == "current":
            summary.update(
                {
                    "held": {k: v for k, v in obs.items() if not k.startswith("junction_")},
                    "sweeps": len(result),
                    "cpu [s]": summary["cpu time [s]"],
                    "current [A]": {str(k): v for k, v in cfg.currents.items()},
                    "junction_heating": model.junction_heating,
                }
            )
        return summary

    problem = PathProblem(
        drive,
        clock=TIME if r.drive == "schedule" else LOAD,
        end=total,
        at=lambda s: min(float(s.get(key, 0.0)), total),
        comm=comm,
    )
    return run(
        problem,
        problem.program(),
        [StateHistory(history), StateExport(export)],
        out,
        config=cfg.resolved(),
        progress=bar,
        comm=comm,
        summarize=lambda skeleton, records: summarize(skeleton, records[-1].detail),
    )


def supports_of(kind: str, **kw) -> GridshellSupports:
    """GridshellSupports of a bar-and-hinge support name (:func:`fe_support`)."""
    return GridshellSupports(kind=fe_support(kind), **kw)


__all__ = [
    "DRIVES",
    "FE_SUPPORTS",
    "GridshellFERun",
    "GridshellFERunConfig",
    "build_model",
    "fe_support",
    "in_model",
    "mirror_image",
    "ramp_cost",
    "run_gridshell_fe",
    "smallest_symmetry",
    "strip_values",
    "supports_of",
]
