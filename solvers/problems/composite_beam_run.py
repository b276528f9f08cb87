"""One run of the FE composite beam (``lcefem run beam --model fe``): the configuration sections
(:class:`BeamFEConfig`) and :func:`run_beam_fe` through the run skeleton
(lcefem.solvers.runtime.run), around the problems of :mod:`lcefem.solvers.problems.composite_beam`,
both through the runner (:mod:`lcefem.solvers.runner`): the lambda ramp of
:class:`~lcefem.solvers.problems.composite_beam.BeamFE`, or a coil current through
:class:`~lcefem.solvers.problems.composite_beam.HeatedBeamFE` in time."""

from __future__ import annotations

import pathlib
import time
from dataclasses import dataclass, field

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.composite_beam_fe import BeamFEMesh
from lcefem.models.empirical import Eq2, eq2_curvature
from lcefem.models.errors import InputError
from lcefem.models.heat import GridSegmentCoil
from lcefem.models.hyperelastic import LCEElasticity, NeoHookeanSolid
from lcefem.models.limits import check_lambda
from lcefem.solvers.contact import PenaltyContact
from lcefem.solvers.continuation import PathControl
from lcefem.solvers.exports import FEFields, Fields, History
from lcefem.solvers.problems.composite_beam import (
    HEATED_STRIPS,
    BeamActuation,
    BeamFE,
    FEMaterials,
    HeatedBeamFE,
    HeatedBeamRun,
)
from lcefem.solvers.problems.composite_beam_bh import SIGN_CONVENTION, BeamRun
from lcefem.solvers.program import Program
from lcefem.solvers.runner import HistoryExport, run_in_time, run_quasi_static
from lcefem.solvers.runtime.checks import check_config, resolved
from lcefem.solvers.runtime.run import Progress


@dataclass(frozen=True)
class BeamFEConfig:
    """The FE beam's sections: run (lambdas), heat_run (a coil current instead), geometry, mesh,
    kapton, lce, actuation, contact, path, eq2."""

    run: BeamRun = field(default_factory=BeamRun)
    heat_run: HeatedBeamRun = field(default_factory=HeatedBeamRun)
    geometry: CompositeBeamGeometry = field(default_factory=CompositeBeamGeometry)
    mesh: BeamFEMesh = field(default_factory=BeamFEMesh)
    kapton: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)
    lce: LCEElasticity = field(default_factory=LCEElasticity)
    actuation: BeamActuation = field(default_factory=BeamActuation)
    contact: PenaltyContact = field(default_factory=PenaltyContact)
    path: PathControl = field(default_factory=PathControl)
    eq2: Eq2 = field(default_factory=Eq2)

    def validated(self) -> "BeamFEConfig":
        check_config(self)
        self.geometry.checked()
        self.mesh.checked()
        self.heat_run.checked()
        for name in ("lambda_top", "lambda_bottom"):
            check_lambda(f"run.{name}", getattr(self.run, name), self.actuation.lambda_N)
        return self

    @property
    def materials(self) -> FEMaterials:
        return FEMaterials(self.kapton, self.lce)

    def resolved(self) -> dict:
        return resolved(self)


def beam_fe_problem(cfg: BeamFEConfig):
    """The FE beam of a (validated) configuration: :class:`BeamFE` (lambdas prescribed) or, when
    ``heat_run.current`` > 0, :class:`HeatedBeamFE` (the current through ``heat_run.heated``)."""
    cfg = cfg.validated()
    if cfg.heat_run.current > 0:
        return HeatedBeamFE(
            HEATED_STRIPS[cfg.heat_run.heated],
            cfg.geometry,
            cfg.mesh,
            cfg.materials,
            cfg.contact,
            None,
            None,
            None,
            None,
            GridSegmentCoil(),
            dt=cfg.heat_run.dt,
        )
    return BeamFE(cfg.geometry, cfg.mesh, cfg.materials, cfg.actuation, cfg.contact, cfg.path)


def beam_fe_program(cfg: BeamFEConfig) -> Program:
    """The lambda ramp (a load program, a record per converged increment, no start row) or the
    coil current for heat_run.duration [s] in steps of at most heat_run.dt [s]."""
    h = cfg.heat_run
    if h.current > 0:
        return Program.in_time(
            {tag: h.current for tag in HEATED_STRIPS[h.heated]}, h.duration, h.dt
        )
    return Program.quasi_static(
        {"top_strips": cfg.run.lambda_top, "bottom_strips": cfg.run.lambda_bottom},
        record_start=False,
    )


def beam_fe_exports(problem) -> list:
    """history.csv of the observables and displacement.bp."""
    return [History(), Fields("displacement.bp", ("displacement [mm]",))]


FE_COLUMNS = [
    "load factor [-]",
    "lambda_top [-]",
    "lambda_bottom [-]",
    "curvature [1/mm]",
    "eq2 curvature [1/mm]",
    "contact force [N]",
    "min gap [mm]",
    "newton iterations [-]",
]
HEAT_COLUMNS = [
    "time [s]",
    "curvature [1/mm]",
    "T_mean bottom_strips [C]",
    "T_mean top_strips [C]",
    "T_mean kapton [C]",
    "contact force [N]",
    "newton iterations [-]",
]


def run_beam_fe(cfg: BeamFEConfig, out: pathlib.Path, progress: bool = True, report=None) -> dict:
    """Run the FE beam through the run skeleton: the lambda ramp (history.csv of :data:`FE_COLUMNS`,
    displacement.bp, summary.json) or, when ``heat_run.current`` > 0, the coil current
    (:func:`run_beam_fe_heated`; history.csv of :data:`HEAT_COLUMNS`). Returns the summary.
    ``report(out, cfg, model, history) -> dict`` (optional: the validation's plots and notes) runs
    before the summary is written; its entries join the results."""
    cfg = cfg.validated()
    out = pathlib.Path(out)
    if cfg.heat_run.current > 0:
        return run_beam_fe_heated(cfg, out, progress, report)
    lam_t, lam_b = cfg.run.lambda_top, cfg.run.lambda_bottom
    started = time.perf_counter()
    model = BeamFE(cfg.geometry, cfg.mesh, cfg.materials, cfg.actuation, cfg.contact, cfg.path)
    check_lambda("lambda_top", lam_t, cfg.actuation.lambda_N)
    check_lambda("lambda_bottom", lam_b, cfg.actuation.lambda_N)

    def row(state) -> dict:
        return {
            "load factor [-]": state.load_factor,
            "lambda_top [-]": state.lambda_top,
            "lambda_bottom [-]": state.lambda_bottom,
            "curvature [1/mm]": state.curvature,
            "eq2 curvature [1/mm]": float(
                eq2_curvature(state.lambda_top, state.lambda_bottom, cfg.eq2)
            ),
            "contact force [N]": state.contact_force,
            "min gap [mm]": state.min_gap,
            "newton iterations [-]": state.iterations,
        }

    def summarize(run, states) -> dict:
        history = run.history
        extra = report(out, cfg, model, history) if report is not None else {}
        follower = model.last_follower
        return {
            "model": "fe",
            "results": {
                "curvature [1/mm]": model.curvature(),
                "eq2 curvature [1/mm]": float(eq2_curvature(lam_t, lam_b, cfg.eq2)),
                **(extra or {}),
                "sign convention": SIGN_CONVENTION,
                "contact force [N]": model.contact_force(),
                "min gap [mm]": model.min_gap(),
                "folds crossed": follower.snaps,
            },
            "dofs": model.ndofs,
            "cells": model.tmesh.info["cells"],
            "symmetry": model.tmesh.info["symmetry"],
            "ranks": model.comm.size,
            "steps": len(history.rows),
            "newton_iterations": follower.iterations,
            "cut_steps": follower.cuts,
            "wall_time [s]": time.perf_counter() - started,
        }

    history = HistoryExport(
        tuple(FE_COLUMNS),
        row,
        where=lambda s: f"lambda = ({s.lambda_top:.5g}, {s.lambda_bottom:.5g})",
        at=lambda s: s.load_factor,
    )
    fields = FEFields("displacement.bp", (model.u,), model.tmesh.mesh.comm, lambda s: s.load_factor)
    return run_quasi_static(
        model,
        {"top_strips": lam_t, "bottom_strips": lam_b},
        out,
        config=cfg.resolved(),
        history=history,
        fields=fields,
        progress=Progress(
            1.0, f"beam (FE) lambda_T={lam_t:g} lambda_B={lam_b:g}", "load", ".3f", progress
        ),
        summarize=summarize,
        progress_scale=None,
    )


def run_beam_fe_heated(cfg: BeamFEConfig, out: pathlib.Path, progress: bool, report) -> dict:
    """The heated FE beam (:class:`HeatedBeamFE`, ``heat_run.current`` through the
    ``heat_run.heated`` strips) in time through the runner
    (:func:`lcefem.solvers.runner.run_in_time`)."""
    run_cfg = cfg.heat_run.checked()
    if not run_cfg.current > 0:
        raise InputError(f"heat_run.current = {run_cfg.current} A: must be > 0 A for a heated run")
    started = time.perf_counter()
    coil = GridSegmentCoil()
    beam = HeatedBeamFE(
        HEATED_STRIPS[run_cfg.heated],
        cfg.geometry,
        cfg.mesh,
        cfg.materials,
        cfg.contact,
        None,
        None,
        None,
        None,
        coil,
        dt=run_cfg.dt,
    )

    def summarize(run, rows) -> dict:
        extra = report(out, cfg, beam.model, run.history) if report is not None else {}
        return {
            "model": "fe",
            "drive": "current",
            "results": {
                "curvature [1/mm]": float(run.history.column("curvature [1/mm]")[-1]),
                "T_mean bottom strips [C]": float(
                    run.history.column("T_mean bottom_strips [C]")[-1]
                ),
                "coil resistance per strip [ohm]": coil.resistance,
                **(extra or {}),
            },
            "steps": len(rows) - 1,
            "ranks": beam.comm.size,
            "wall_time [s]": time.perf_counter() - started,
        }

    return run_in_time(
        beam,
        {tag: run_cfg.current for tag in beam.heated},
        out,
        duration=run_cfg.duration,
        dt=run_cfg.dt,
        config=cfg.resolved(),
        columns=HEAT_COLUMNS,
        progress=Progress(
            run_cfg.duration,
            f"beam (FE) {run_cfg.current:g} A {run_cfg.heated} strips",
            "s",
            enabled=progress,
        ),
        summarize=summarize,
    )


def beam_fe_heated(
    run: HeatedBeamRun = HeatedBeamRun(),
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    mesh: BeamFEMesh = BeamFEMesh(),
    materials: FEMaterials = FEMaterials(),
    contact: PenaltyContact = PenaltyContact(),
    control: PathControl | None = None,
    transition=None,
    thermal=None,
    exchange=None,
    coil: GridSegmentCoil = GridSegmentCoil(),
):
    """A :class:`HeatedBeamFE` with ``run.current`` through the ``run.heated`` strips for
    ``run.duration`` in equal steps of at most ``run.dt``, through the runner without outputs
    (:func:`lcefem.solvers.runner.run_in_time`, ``out`` None: the rows checked against the
    physical bounds, nothing written). Returns (model, history rows, stations): model the
    ThermoMechanicalModel."""
    run = run.checked()
    if not run.current > 0:
        raise InputError(f"heat_run.current = {run.current} A: must be > 0 A for a heated run")
    beam = HeatedBeamFE(
        HEATED_STRIPS[run.heated],
        geometry,
        mesh,
        materials,
        contact,
        control,
        transition,
        thermal,
        exchange,
        coil,
        dt=run.dt,
    )
    rows: list[dict] = []
    run_in_time(
        beam,
        {tag: run.current for tag in beam.heated},
        None,
        duration=run.duration,
        dt=run.dt,
        config={},
        columns=HEAT_COLUMNS,
        progress=Progress(run.duration, "", "s", enabled=False),
        summarize=lambda _, found: rows.extend(found) or {},
    )
    return beam.model, rows, beam.stations
