"""The robotic surface of seed 001 in 3D finite strain, heated route (issue 14): the FE gridshell
of :mod:`lcefem.solvers.problems.gridshell` driven by its coils (:class:`HeatedGridshellFE`: coil
currents per strip through the Joule-heated heat equation, run in time, or held to a steady state).

Units: mm, N, MPa, mJ, s, C, A (README).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import pathlib
import time
from collections.abc import Callable, Mapping

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc
import dolfinx.io

from lcefem.meshes.gridshell_fe import cell_group
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.heat import Coil, ThermalProperties
from lcefem.models.lce import NematicTransition, contraction_ratio, spontaneous_stretch
from lcefem.models.lumped_heat import grid_segment_resistance, grid_thermal
from lcefem.solvers.continuation import PathControl
from lcefem.solvers.exports import write_snapshot
from lcefem.solvers.heat import HeatProblem, HeatSetup
from lcefem.solvers.mechanics import QUADRATURE_DEGREE, assemble_global, volume_measure
from lcefem.solvers.problems.gridshell import GridshellConfig, GridshellFE
from lcefem.solvers.problems.protocol import StepRecord, copy_arrays, put_arrays
from lcefem.solvers.thermomechanics import TemperatureFollower, temperature_path

_prefix = itertools.count()
#: Largest change [K] of the steady temperature between two sweeps of
#: :meth:`HeatedGridshellFE.steady_hold` that ends them (chosen: lambda_s(T) is steepest at T_NI,
#: 0.0169 per K for models.lce.NematicTransition, so 1e-3 K moves lambda by at most 1.7e-5).
STEADY_TEMPERATURE_TOL = 1e-3
#: Where the coils' heat goes (HeatedGridshellFE ``junction_heating``): "off" the strips only,
#: "added" also the pads and glue squares the coils pass, at the strips' power density (the default,
#: :data:`JUNCTION_HEATING_DEFAULT`), "spread" the same with each coil's power unchanged (spread
#: over its strips and those pads).
JUNCTION_HEATING = ("off", "added", "spread")
#: The experiment's coil path (issue 31): the coil runs through the junctions at the strips' linear
#: power density. Source: seed 001, Materials and Methods: the LCE was injected into "a high-density
#: polyethylene mold with grid-shaped channels with heating coils placed inside" and "the heating
#: coil is integrated inside each LCE strip" (Results), so each coil lies in its line of the moulded
#: grid, through the junction crossings; it is wound at a uniform pitch ("the resistance of the coil
#: is 1.25 ohms/mm on average before stretch", fig. S8), so a junction piece is heated per unit
#: length as a segment. The density is the measured coil over the measured active length (126-134
#: ohm over 80 mm isotropic, "preserved in the 3x3 grid design"), the same density as the lumped
#: grid strip (models.lumped_heat.GRID_STRIP) of the bar-and-hinge current route, whose one exchange
#: factor was calibrated with it. Not "off": a coil that skips the junctions contradicts the
#: grid-shaped channels. Not "spread": it rescales the measured density by the FE's own pad volumes
#: (the published layout's bottom line is ~98 mm isotropic at 1.63 ohm/mm with its pads and tabs,
#: the top ~122 mm with its crowns and glue squares, against the measured 80 mm), a model geometry.
JUNCTION_HEATING_DEFAULT = "added"
#: Distance [mm] within which two strip cells count as equally near a pad
#: (HeatedGridshellFE._junction_coil_map; the round-off of cell midpoints of ~100 mm coordinates,
#: ~1e-14 mm, far below the level-3 cell size). Measured: at level 0, full model, 24 of the 216 top
#: pads in the coils' bands lie exactly midway between two top strips' cells.
PAD_TIE_TOL = 1e-9
#: Picard iterations allowed to the steady heat equation (HeatProblem.steady's radiation update).
#: Measured: the table's 0.2 A on every strip, junctions heated, settles at 315 C with the change
#: per iteration shrinking by ~0.63 (1e-10 relative after ~55 iterations, more than HeatProblem's
#: 50); the holds of 0.04-0.08 A settle in ~12.
STEADY_PICARD_ITERATIONS = 200


class HeatedGridshellFE(GridshellFE):
    """The FE gridshell driven by its coils (issue 14, heated route): each strip's coil current
    heats it through the Joule-heated heat equation (:class:`lcefem.solvers.heat.HeatProblem`,
    pulled back with the displacement; convection and radiation on every exterior face but the
    mirror planes, which are adiabatic by symmetry; no conduction into the table), and the strips'
    relative length is a = lambda_s(T)/lambda_N of the nematic transition
    (:func:`lcefem.models.lce.contraction_ratio`), bond pads passive, as the heated FE beam
    (:class:`lcefem.solvers.problems.composite_beam.HeatedBeamFE`). Each time step: heat, then the
    mechanics from the old to the new temperature (:class:`lcefem.solvers.thermomechanics.
    TemperatureFollower`).

    Power: the grid strip's coil (issue 31, :data:`lcefem.models.lumped_heat.GRID_STRIP`: ~130 ohm
    over 80 mm isotropic, seed 001) spread uniformly, i.e. the part of it in one 30 mm segment
    (:func:`lcefem.models.lumped_heat.grid_segment_resistance`, 34.8 ohm; the earlier 25 ohm segment
    reading under-powered the strips by 28 %) over a 30 mm strip's as-built volume,
    q = I^2 R / (L W_s H) [mW/mm^3], in every LCE cell of a driven strip (cell-wise field: each
    strip tag its own current); the glue squares where the top strips cross (4.2 of a top strip's 30
    mm) are heated by the coil passing through them at its strips' power density
    (``junction_heating`` "added", the default, :data:`JUNCTION_HEATING_DEFAULT`: the experiment's
    coil path); "off" heats the strips only (neither the glue squares nor the bond pads); "spread"
    spreads each coil's unchanged power over its strips and the pads it passes
    (:meth:`_junction_coil_map`; the seed's coils lie in the grid-shaped mould channels, so they run
    through the junctions): the controlled changes that measure the heat the strips lose into
    unheated junctions. Exchange: the free strip's calibrated convection times the grid's one
    calibrated factor (:func:`lcefem.models.lumped_heat.grid_thermal`, calibrated on the
    bar-and-hinge dome protocol), and radiation.

    Drive: :meth:`set_drives` (currents [A]) per channel, group or strip tag (as
    :meth:`GridshellFE.set_drives`); step: :meth:`advance_time`; a schedule: :meth:`run_protocol`.
    The mesh is built at the transition's as-built stretch (``transition.lambda_N``; the heated
    beam's choice).
    """

    def __init__(
        self,
        config: GridshellConfig = GridshellConfig(),
        *,
        transition=None,
        thermal=None,
        exchange=None,
        coil=None,
        dt: float = 1.0,
        junction_heating: str = JUNCTION_HEATING_DEFAULT,
        comm: MPI.Comm | None = None,
        petsc_options: dict | None = None,
    ):
        self.transition = transition or NematicTransition()
        if junction_heating not in JUNCTION_HEATING:
            raise InputError(
                f"junction_heating = {junction_heating!r}: allowed {', '.join(JUNCTION_HEATING)}"
            )
        self.junction_heating = junction_heating
        self.coil = coil or Coil(resistance=grid_segment_resistance())
        self._heat_materials = (thermal or ThermalProperties(), exchange or grid_thermal().exchange)
        super().__init__(
            dataclasses.replace(config, lambda_N=self.transition.lambda_N), comm, petsc_options
        )
        g = self.config.geometry
        self._segment_volume = (
            g.segment_length * self.info["strip_width"] * self.info["strip_thickness"]
        )
        self.stepper = TemperatureFollower(
            self.heat,
            self.T_mech,
            self.problem,
            PathControl(first_step=dt, max_step=dt),
            self.damping,
        )
        self.currents = np.zeros(self.lam.x.array.size)  # [A] per cell (0 outside the strips)
        self._tag_current = dict.fromkeys(self.strip_tags.values(), 0.0)  # [A] per strip tag
        dx = volume_measure(self.tmesh, QUADRATURE_DEGREE)
        comm_ = self.tmesh.mesh.comm
        self._channel_T = {}
        for ch in ("Tx", "Ty", "Bx", "By"):
            if ch in self.info["cell_groups"]:
                tags = cell_group(self.tmesh, ch)
                self._channel_T[ch] = (
                    dolfinx.fem.form(self.heat.T * dx(tags)),
                    assemble_global(dolfinx.fem.form(1.0 * dx(tags)), comm_),
                )
        # Output of the heated state (write_fields): lambda_s(T) [-] on the temperature space and
        # at the strips' cell midpoints; the pads, glue and ribbons are passive (lambda_N).
        lam_T = spontaneous_stretch(self.heat.T, self.transition)
        self.lambda_s = dolfinx.fem.Function(self.heat.V, name="spontaneous_stretch")
        self._lambda_s_expr = dolfinx.fem.Expression(
            lam_T, self.heat.V.element.interpolation_points
        )
        self._lam_cells = dolfinx.fem.Function(self.V0, name="lambda")
        self._lam_cells_expr = dolfinx.fem.Expression(lam_T, self.V0.element.interpolation_points)
        tags = self.tmesh.cell_tags
        self._strip_cells = tags.indices[np.isin(tags.values, list(self.strip_tags.values()))]
        self._pad_sources, self.coil_share = None, {}
        if self.junction_heating != "off":
            self._pad_sources = self._junction_coil_map()

    def _junction_coil_map(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """The coil continued through the unheated LCE of a layer (``junction_heating`` "added" or
        "spread", :data:`JUNCTION_HEATING`): for every
        bond pad ("bottom_pads": under the junctions and tabs; "top_pads": the crowns) and glue
        square (the top strips' crossing) DG0 dof, the strip whose power density it takes, once
        per coil passing through it. A coil passes where the pad lies in its strip's band
        (|y - c_r| < W_s/2 for an x strip of ribbon r, |x - c_r| < W_s/2 for a y strip): one coil
        in the arms and crowns, two where the x and y bands cross (the junction's centre square, the
        glue square). The strip is the one of the nearest strip cell of the same layer and
        direction in the whole model: its current is the current of the coil through the pad.
        Returns [(pad dofs, strip cell tags)], one pair per (layer, direction). For "spread" it
        also sets the share of each channel's coil power that stays in its strips
        (:attr:`coil_share`: strip volume / (strip volume + the volume of the pads its coil
        passes), the model's own volumes).

        On N ranks the nearest strip cell is searched among every rank's owned strip cells
        (gathered in rank order; on one rank the same points in the same order as the local dofs,
        so the serial answer is unchanged): a rank's own and ghost cells alone can miss it (the
        nearest strip cell of a pad may lie beyond the ghost layer, and a pad then took a strip of
        another current); the volumes are sums over owned cells."""
        from scipy.spatial import cKDTree

        msh = self.tmesh.mesh
        comm = msh.comm
        owned = self.V0.dofmap.index_map.size_local  # DG0: dofs < owned are this rank's cells
        ncells = msh.topology.index_map(3).size_local + msh.topology.index_map(3).num_ghosts
        mid = dolfinx.mesh.compute_midpoints(msh, 3, np.arange(ncells, dtype=np.int32))
        dof_mid = np.empty((self.lam.x.array.size, 3))
        dof_mid[self._cell_dof] = mid
        centres = np.asarray(self.info["junction_centres"])
        half = 0.5 * self.info["strip_width"] + 1e-9
        strips = self.info["strips"]
        tag_of = {name: self.tmesh.cell_tag(name) for name in strips}
        volume = dolfinx.fem.assemble_vector(
            dolfinx.fem.form(
                ufl.TestFunction(self.V0) * volume_measure(self.tmesh, QUADRATURE_DEGREE)
            )
        ).array  # [mm^3]
        out = []
        for layer, pad_groups in (("bottom", ("bottom_pads",)), ("top", ("top_pads", "glue"))):
            pad_tags = [
                t
                for g in pad_groups
                if g in self.info["cell_groups"]
                for t in cell_group(self.tmesh, g)
            ]
            pads = np.flatnonzero(np.isin(self._dof_tag, pad_tags))
            for d, across in (("x", 1), ("y", 0)):
                own = [
                    tag_of[n]
                    for n, s in strips.items()
                    if s["layer"] == layer and s["direction"] == d
                ]
                sdofs = np.flatnonzero(np.isin(self._dof_tag, own))
                mine = sdofs[sdofs < owned]
                points = np.concatenate(comm.allgather(dof_mid[mine]))
                tags = np.concatenate(comm.allgather(self._dof_tag[mine]))
                dist = np.abs(dof_mid[pads, across][:, None] - centres[None, :]).min(axis=1)
                in_band = pads[dist < half]
                if points.shape[0] == 0 or comm.allreduce(int(np.sum(in_band < owned))) == 0:
                    continue
                if in_band.size:
                    tree = cKDTree(points)
                    near, _ = tree.query(dof_mid[in_band])
                    # a pad equidistant from two strips (the crowns and glue squares between two
                    # top halves) takes the smaller tag: the same strip on any partition
                    ties = tree.query_ball_point(dof_mid[in_band], near + PAD_TIE_TOL)
                    out.append((in_band, np.array([tags[i].min() for i in ties], dtype=tags.dtype)))
                if self.junction_heating == "spread":
                    v = comm.allreduce(volume[mine].sum())
                    pad_v = comm.allreduce(volume[in_band[in_band < owned]].sum())
                    self.coil_share[f"{layer[0].upper()}{d}"] = float(v / (v + pad_v))
        return out

    def _strip_stretch_ratio(self, u):
        """a = lambda_s(T)/lambda_N (UFL) with T the temperature the mechanics sees; builds the
        heat problem on the same mesh (its source: the cell-wise power density)."""
        thermal, exchange = self._heat_materials
        exposed = [f for f in self.tmesh.facets if f not in ("sym_x", "sym_y")]
        self.power = dolfinx.fem.Function(self.V0, name="power_density")  # [mW/mm^3]
        self.heat = HeatProblem(
            self.tmesh,
            HeatSetup(thermal, exchange, exposed_facets=exposed),
            displacement=u,
            extra_source=self.power,
            prefix=f"lcefem_gridshell_heat{next(_prefix)}_",
        )
        self.T_mech = dolfinx.fem.Function(self.heat.V, name="temperature_mechanics")
        self.T_mech.x.array[:] = self.heat.T.x.array
        return contraction_ratio(self.T_mech, self.transition)

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.stepper.time

    def power_density(self, current: float) -> float:
        """Joule power density q = I^2 R / (L W_s H) [mW/mm^3] of a grid segment's strip carrying
        ``current`` [A] (refuses I < 0 by name)."""
        return self.coil.power(float(current)) / self._segment_volume

    def adiabatic_rate(self, current: float) -> float:
        """Temperature rate q/(rho c) [K/s] of a strip at ``current`` [A] losing no heat: the upper
        bound of its early heating."""
        return self.power_density(current) / self._heat_materials[0].volumetric_heat_capacity

    def heat_content(self) -> float:
        """rho c times the integral of T over the whole model [mJ] (its change over a step is the
        heat stored: the Joule energy minus the losses, the energy balance of the heated route)."""
        dx = volume_measure(self.tmesh, QUADRATURE_DEGREE)
        rho_c = self._heat_materials[0].volumetric_heat_capacity
        return rho_c * assemble_global(dolfinx.fem.form(self.heat.T * dx), self.tmesh.mesh.comm)

    def joule_power(self) -> float:
        """The coils' total power in the model [mW] (the integral of the power density)."""
        dx = volume_measure(self.tmesh, QUADRATURE_DEGREE)
        return assemble_global(dolfinx.fem.form(self.power * dx), self.tmesh.mesh.comm)

    def _set_current(self, drives: Mapping[str, float]) -> None:
        """Coil current I [A] per strip tag, group or channel (a later key overrides an earlier
        one on shared strips), from now on; power density :meth:`power_density` in its LCE cells."""
        for selector, current in drives.items():
            q = self.power_density(current)
            tags = self._tags_of(selector)
            cells = np.isin(self._dof_tag, tags)
            self.currents[cells] = float(current)
            self.power.x.array[cells] = q
            self._tag_current.update(dict.fromkeys(tags, float(current)))
        # each strip's power density [mW/mm^3] on every rank (a pad's strip may lie on another
        # rank), the value its cells get here
        tag_power = {t: np.float64(self.power_density(c)) for t, c in self._tag_current.items()}
        for ch, share in self.coil_share.items():  # "spread": each coil's power unchanged
            if ch in self.info["cell_groups"]:
                cells = np.isin(self._dof_tag, cell_group(self.tmesh, ch))
                self.power.x.array[cells] = share * np.vectorize(self.power_density)(
                    self.currents[cells]
                )
                for t in cell_group(self.tmesh, ch):
                    tag_power[t] = share * tag_power[t]
        if self._pad_sources:  # the coils through the pads and glue squares
            pad_all = np.unique(np.concatenate([p for p, _ in self._pad_sources]))
            self.power.x.array[pad_all] = 0.0
            for pads, sources in self._pad_sources:
                q = np.array([tag_power[t] for t in sources.tolist()], dtype=np.float64)
                np.add.at(self.power.x.array, pads, q)

    def _set_lambda(self, drives):
        raise InputError(
            "the heated gridshell is driven by currents [A] (set_drives); "
            "prescribed lambdas belong to the prescribed-lambda route (GridshellFE)"
        )

    def observables(self) -> dict[str, float]:
        """:meth:`GridshellFE.observables` plus time [s], the channels' mean temperature [C],
        their spontaneous stretch at that temperature [-] and current [A]."""
        out = {"time [s]": self.time}
        comm = self.tmesh.mesh.comm
        for ch, (form, volume) in self._channel_T.items():
            T = assemble_global(form, comm) / volume
            out[f"T_mean {ch} [C]"] = T
            out[f"lambda {ch} [-]"] = float(spontaneous_stretch(T, self.transition))
            mine = self.currents[np.isin(self._dof_tag, cell_group(self.tmesh, ch))]
            # a rank may hold none of a channel's cells
            out[f"current {ch} [A]"] = float(
                comm.allreduce(mine.max() if mine.size else -math.inf, op=MPI.MAX)
            )
        out["T_max [C]"] = self.heat.max_temperature()
        out.update(super().observables())
        return out

    def _cell_fields(self) -> list[dolfinx.fem.Function]:
        """As :meth:`GridshellFE._cell_fields`, with lambda the strips' spontaneous stretch
        lambda_s(T) [-] at their cell midpoints (the prescribed-lambda field is not used here)."""
        self._lam_cells.x.array[:] = self.lambda_N
        self._lam_cells.interpolate(self._lam_cells_expr, cells0=self._strip_cells)
        self._lam_cells.x.scatter_forward()
        return [self._lam_cells, *super()._cell_fields()[1:]]

    def write_fields(self, folder, t: float | None = None) -> list[pathlib.Path]:
        """:meth:`GridshellFE.write_fields` at the simulated time (default) plus temperature.bp
        (VTX): the temperature T [C] and the spontaneous stretch lambda_s(T) [-] on Q1 (meaningful
        in the LCE strips; the pads, glue and ribbons are passive)."""
        t = self.time if t is None else t
        files = super().write_fields(folder, t)
        self.lambda_s.interpolate(self._lambda_s_expr)
        files.append(write_snapshot(folder, "temperature.bp", [self.heat.T, self.lambda_s], t))
        return files

    def advance_time(self, dt: float) -> dict[str, float]:
        """One heat step of ``dt`` [s] and the mechanics to the new temperature; returns the
        observables with the step's Newton iterations."""
        started = time.perf_counter()
        try:
            its = self.stepper.advance(dt, where=f"heated gridshell, t = {self.time + dt:.4g} s")
        finally:
            self.wall_time += time.perf_counter() - started
        return {**self.observables(), "newton iterations [-]": its}

    def run_protocol(
        self,
        protocol,
        duration: float = 60.0,
        dt: float = 1.0,
        on_step: Callable[[dict], None] | None = None,
    ) -> list[dict]:
        """Currents switched at the protocol's times ((t [s], {selector: I [A]}), first at 0),
        held until the next switch, stepped with ``dt`` [s] up to ``duration`` [s]; one row of
        observables per step (the first at t = 0)."""
        times = [float(t) for t, _ in protocol]
        if not times or times[0] != 0.0 or any(b <= a for a, b in zip(times, times[1:])):
            raise InputError(f"protocol times {times}: must start at 0 s and increase")
        if not (duration > 0 and dt > 0):
            raise InputError(f"duration = {duration} s, dt = {dt} s: both must be > 0")
        rows = [{**self.observables(), "newton iterations [-]": 0}]
        if on_step is not None:
            on_step(rows[-1])
        k = 0
        while self.time < duration - 1e-9:
            while k < len(protocol) and times[k] <= self.time + 1e-9:
                self._set_current(protocol[k][1])
                k += 1
            nxt = times[k] if k < len(protocol) else duration
            step = min(dt, nxt - self.time, duration - self.time)
            rows.append(self.advance_time(step))
            if on_step is not None:
                on_step(rows[-1])
        return rows

    def hold(
        self,
        currents: Mapping[str, float],
        until: float,
        first_dt: float,
        growth: float = 2.0,
        on_step: Callable[[dict], None] | None = None,
    ) -> list[dict]:
        """Hold ``currents`` [A] from now up to ``until`` [s] with time steps growing geometrically
        (``first_dt`` [s], x ``growth``; the last one cut at ``until``). Backward Euler is
        unconditionally stable and tends to the steady state, so the held shape is reached in a few
        steps where equal steps take hundreds; the mechanics' step limit follows each time step
        (it steps the temperature change of a long heat step in increments it chooses itself,
        cut on failure). One row of observables per step."""
        if not (first_dt > 0 and growth >= 1.0 and until > self.time):
            raise InputError(
                f"hold: first_dt = {first_dt} s (> 0), growth = {growth} (>= 1), "
                f"until = {until} s (> the current time {self.time:g} s)"
            )
        self._set_current(currents)
        follower = self.stepper.follower
        control = follower.control
        rows, dt = [], float(first_dt)
        try:
            while self.time < until - 1e-9:
                step = min(dt, until - self.time)
                follower.control = dataclasses.replace(control, max_step=step)
                rows.append(self.advance_time(step))
                if on_step is not None:
                    on_step(rows[-1])
                dt *= growth
        finally:
            follower.control = control
        return rows

    def steady_hold(
        self,
        currents: Mapping[str, float],
        *,
        temperature_tol: float = STEADY_TEMPERATURE_TOL,
        max_sweeps: int = 8,
        on_step: Callable[[dict], None] | None = None,
    ) -> list[dict]:
        """The held shape at constant ``currents`` [A] directly, without the transient: the steady
        heat equation (rho c dT/dt = 0, :meth:`HeatProblem.steady`) on the current deformed body
        -> temperature -> lambda_s(T) -> the mechanics from the temperature it last saw to that
        one (the path follower of the lambda route, in T_mech = T_0 + s (T_steady - T_0));
        repeated while the deformation (the exchange on the deformed faces) moves the steady
        temperature by more than ``temperature_tol`` [K]. The limit of :meth:`hold` as t -> oo;
        the clock does not move. One row of observables per sweep."""
        if not (temperature_tol > 0 and max_sweeps >= 1):
            raise InputError(
                f"steady_hold: temperature_tol = {temperature_tol} K (> 0), "
                f"max_sweeps = {max_sweeps} (>= 1)"
            )
        self._set_current(currents)
        rows, previous = [], None
        for sweep in range(1, max_sweeps + 1):
            self.heat.steady(max_iterations=STEADY_PICARD_ITERATIONS)
            T1 = self.heat.T.x.array.copy()
            follower = temperature_path(
                self.problem, self.T_mech, T1, self.config.control, self.damping
            )
            started = time.perf_counter()
            try:
                follower.follow(1.0, where=f"heated gridshell, steady hold, sweep {sweep}")
            finally:
                self.wall_time += time.perf_counter() - started
                self.last_follower = follower
            self.T_mech.x.array[:] = T1
            change = math.inf if previous is None else float(np.max(np.abs(T1 - previous)))
            rows.append(
                {
                    **self.observables(),
                    "newton iterations [-]": follower.iterations,
                    "steady sweep [-]": sweep,
                    "temperature change [K]": change,
                }
            )
            if on_step is not None:
                on_step(rows[-1])
            if change <= temperature_tol:
                return rows
            previous = T1
        raise ConvergenceError(
            "heated gridshell, steady hold",
            f"the steady temperature still moves {change:.3g} K after {max_sweeps} sweeps",
        )

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "current [A]"

    def set_drives(self, drives: Mapping[str, float]) -> None:
        self._set_current(drives)

    def advance(self, dt: float, **unused) -> StepRecord:
        """One time step of ``dt`` [s] (:meth:`advance_time`): the heated gridshell's time is
        simulated time; its lambda follows the temperature, not targets."""
        row = self.advance_time(dt)
        its = int(row["newton iterations [-]"])
        return StepRecord(self.time, row, its)

    def fields(self) -> dict:
        out = super().fields()
        out["lambda [-]"] = self._cell_fields()[0]  # lambda_s(T) at the strips' midpoints
        self.lambda_s.interpolate(self._lambda_s_expr)
        return {**out, "temperature [C]": self.heat.T, "spontaneous stretch [-]": self.lambda_s}

    def memory_state(self) -> dict:
        return {
            **super().memory_state(),
            "heat": copy_arrays([self.heat.T, self.heat.T_old, self.T_mech]),
            "time": self.time,
            "currents": self.currents.copy(),
            "tag currents": dict(self._tag_current),
            "power": copy_arrays([self.power]),
        }

    def restore_state(self, state: dict) -> None:
        super().restore_state(state)
        put_arrays([self.heat.T, self.heat.T_old, self.T_mech], state["heat"])
        put_arrays([self.power], state["power"])
        self.currents[:] = state["currents"]
        self._tag_current = dict(state["tag currents"])
        self.stepper.time = state["time"]


__all__ = [
    "JUNCTION_HEATING",
    "JUNCTION_HEATING_DEFAULT",
    "STEADY_PICARD_ITERATIONS",
    "STEADY_TEMPERATURE_TOL",
    "HeatedGridshellFE",
]
