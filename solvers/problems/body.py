"""A 3D FE thermo-mechanical LCE body assembled from a user's mesh and case file (``lcefem run
body --config robot.toml``; the case file's schema: :mod:`lcefem.solvers.problems.body_case`,
the user's page: docs/own_robot.md).

The physics is the strip's (:mod:`lcefem.solvers.problems.strip`), on any mesh with named sets:

* heat: backward Euler in the reference configuration pulled back with the lagging displacement
  (:class:`lcefem.solvers.heat.HeatProblem`); a coil's Joule power P = I^2 R
  (:meth:`lcefem.models.heat.Coil.power`) spread uniformly over its region, q = P / (s V_mesh)
  [mW/mm^3] with s the case's symmetry factor (the mesh is 1/s of the body); convection h (T -
  T_inf) and linearised grey-body radiation per boundary, fixed temperatures as Dirichlet
  conditions; other boundaries adiabatic (or mirror planes);
* heat capacity rho c and conductivity k per region (DG0; [thermal] where a region gives none);
* mechanics: W(F F_s(T)^-1) in LCE regions (director per region, a vector, a through-thickness
  twist or three expressions of x, y, z, :mod:`.body_expression`), compressible neo-Hookean passive
  regions, dead loads (force, pressure on the reference normal, gravity on each region's
  density), supports (:mod:`lcefem.solvers.supports`); staggered with the one path
  follower (:class:`lcefem.solvers.thermomechanics.ThermoMechanicalModel`: a heat step, then the
  mechanics from the old to the new temperature, halving on failure).

Drives (:meth:`BodyProblem.set_drives`): the current [A] of each ``[[coils]]`` entry by name; the
program also sets fixed boundary temperatures [C] and load factors [-] by name.

Observables, "name [unit]": ``T_mean [C]``, ``T_max [C]`` (whole mesh), ``T_mean <set> [C]``,
``T_max <set> [C]`` per cell set, ``power <coil> [mW]`` (whole coil), per probe ``u_x|u_y|u_z
<probe> [mm]`` and ``T <probe> [C]`` (a boundary's mean over its reference area, or a point's
value), per clamp or roller ``reaction_<c> <name> [N]`` (the support's force on the body, its
component c, times the symmetry factor: a block pulled by +F along x shows -F on its x roller),
per ``[[contact]]`` ``contact_force <name> [N]`` (sum of k A <-g>_+ over its node pairs, times the
symmetry factor) and ``min_gap <name> [mm]`` (negative: penetration).

Contact (``[[contact]]``): frictionless node-to-node penalty between two named facet sets
(:func:`lcefem.solvers.contact.facing_pairs`; serial only).

Stretch ramp (``[program] stretches``, ``[path]``): LCE cell sets with a prescribed spontaneous
stretch lambda [-] instead of the temperature's, W(F U(1/a)), a = lambda / lambda_N, taken from the
as-built lambda_N to the targets along a load factor t: 0 -> 1 by the shared path follower
(:class:`lcefem.solvers.continuation.PathFollower`, with :class:`NodalDamping` across folds); no
heat steps. The history's clock is ``load factor [-]``, with ``stretch <set> [-]`` per driven set
and ``curvature <name> [1/mm]`` per ``[[curvature]]``
(:class:`lcefem.solvers.probes.StationCurvature`). examples/bodies/composite_beam is the FE
composite beam this way.
"""

from __future__ import annotations

import gc
import math
import pathlib
import time
from collections.abc import Mapping
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx

from lcefem.meshes.reader import read_tagged_mesh
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.heat import Coil, SurfaceExchange, ThermalProperties
from lcefem.models.hyperelastic import LCEElasticity, NeoHookeanSolid
from lcefem.models.lce import MeasuredContraction, NematicTransition, spontaneous_stretch
from lcefem.models.limits import check_current
from lcefem.solvers.contact import NodalDamping, NodePairContact, attach, facing_pairs
from lcefem.solvers.continuation import PathControl, PathFollower
from lcefem.solvers.contraction_curve import read_contraction_csv
from lcefem.solvers.exports import FEFields
from lcefem.solvers.heat import HeatSetup, settled
from lcefem.solvers.mechanics import assemble_global, surface_measure, volume_measure
from lcefem.solvers.probes import PointProbe, StationCurvature
from lcefem.solvers.problems.body_case import AXES, REGION_THERMAL, BodyCase
from lcefem.solvers.problems.protocol import LOAD, TIME, copy_arrays, put_arrays
from lcefem.solvers.runner import HistoryExport, PathProblem, StateExport, StateHistory, run
from lcefem.solvers.runtime.run import Progress
from lcefem.solvers.supports import clamp_face, plane_clamp, point_support, rigid_body_321
from lcefem.solvers.thermomechanics import LCERegion, PassiveRegion, ThermoMechanicalModel

_LAW = LCEElasticity()


def lce_elasticity(shear_modulus: float) -> LCEElasticity:
    """The project's LCE law (:class:`LCEElasticity`) scaled to the small-strain shear modulus
    ``shear_modulus`` [MPa]: every coefficient and the bulk modulus times mu / mu_0 (its Poisson
    ratio kept); mu_0 gives the law itself."""
    k = shear_modulus / _LAW.shear_modulus
    if k == 1.0:
        return _LAW
    return LCEElasticity(
        c10=_LAW.c10 * k, c01=_LAW.c01 * k, c30=_LAW.c30 * k, bulk_modulus=_LAW.bulk_modulus * k
    )


def twisted_layer_director(
    x, axis: int, bounds: tuple[float, float], from_deg: float, to_deg: float
):
    """Director [-] turning through the thickness along ``axis`` (UFL, reference coordinates x
    [mm]): n = cos(theta) e_1 + sin(theta) e_2 with (e_1, e_2) the next two axes in cyclic order
    (axis z: x then y) and theta going linearly from ``from_deg`` at x_axis = bounds[0] to
    ``to_deg`` at bounds[1] [deg]."""
    lo, hi = bounds
    s = (x[axis] - lo) / (hi - lo)
    theta = math.radians(from_deg) + math.radians(to_deg - from_deg) * s
    e1, e2 = (axis + 1) % 3, (axis + 2) % 3
    comps = [0.0, 0.0, 0.0]
    comps[e1], comps[e2] = ufl.cos(theta), ufl.sin(theta)
    return ufl.as_vector(comps)


def contraction_law(region: dict) -> NematicTransition | MeasuredContraction:
    """The spontaneous-stretch law lambda_s(T) of an LCE region of the case file: a measured curve
    when the region names one (``curve``, a CSV of stretch or strain against temperature, read by
    :func:`lcefem.solvers.contraction_curve.read_contraction_csv`; the path is resolved against the
    case file by the checks), else the present law (:mod:`lcefem.models.lce`: Warner-Terentjev's
    order parameter with T_NI [C], width [K], lambda_N [-], T_ref [C])."""
    if region.get("curve") is not None:
        return read_contraction_csv(region["curve"], T_ref=region["T_ref"])
    return NematicTransition(
        T_NI=region["T_NI"],
        width=region["width"],
        lambda_N=region["lambda_N"],
        T_ref=region["T_ref"],
    )


def region_thermal(case: BodyCase) -> dict[str, ThermalProperties]:
    """{cell set: ThermalProperties} of the regions that give any of density [t/mm^3],
    specific_heat [mJ/(t K)] or conductivity [mW/(mm K)] (the other keys from [thermal]); the
    cell sets of the other regions use [thermal] and are not listed."""
    th, out = case.thermal, {}
    for r in case.regions:
        own = {k: r.get(k) for k in REGION_THERMAL if r.get(k) is not None}
        if own:
            props = ThermalProperties(**{k: own.get(k, th[k]) for k in REGION_THERMAL})
            out.update({n: props for n in r["name"]})
    return out


def gravity_work(case: BodyCase, tm, mesh, g, u, dx):
    """The work of gravity sum_r rho_r g . u over the regions [N mm]: rho_r [t/mm^3] a region's own
    density, else [thermal] density; ``g`` [mm/s^2]."""
    th = case.thermal
    if all(r.get("density") is None for r in case.regions):  # one density: one integral
        return (
            ufl.dot(
                dolfinx.fem.Constant(mesh, np.asarray(g, dtype=PETSc.ScalarType) * th["density"]), u
            )
            * dx
        )
    rho = {n: (r.get("density") or th["density"]) for r in case.regions for n in r["name"]}
    work = 0
    for name, value in rho.items():
        rho_g = dolfinx.fem.Constant(mesh, np.asarray(g, dtype=PETSc.ScalarType) * value)
        work += ufl.dot(rho_g, u) * dx(tm.cell_tag(name))
    return work


@dataclass
class BodyResult:
    history: dict[str, np.ndarray]
    summary: dict
    out: pathlib.Path | None


class BodyProblem:
    """The body of a checked case file (:func:`lcefem.solvers.problems.body_case.load_case`), built
    once: mesh, heat and mechanics forms, observables."""

    drive = "current [A]"

    def __init__(self, case: BodyCase, comm: MPI.Comm | None = None):
        self.case = case
        read = read_tagged_mesh(case.mesh_file, comm, case.mesh["size_factor"], case.mesh["refine"])
        self.tmesh = tm = read.tagged()
        self.mesh_info = read.info
        mesh = tm.mesh
        self.comm = comm = mesh.comm
        self.symmetry = case.mesh["symmetry_factor"]
        th = case.thermal
        thermal = ThermalProperties(
            density=th["density"],
            specific_heat=th["specific_heat"],
            conductivity=th["conductivity"],
        )
        # Heat exchange per boundary: one SurfaceExchange each (h and emissivity 0 when not given).
        exchange: dict[str, dict] = {}
        fixed = []
        for h in case.heat:
            for b in h["boundary"]:
                if h["type"] == "fixed":
                    continue
                e = exchange.setdefault(
                    b,
                    {"film_coefficient": 0.0, "emissivity": 0.0, "ambient_temperature": h["T_inf"]},
                )
                if h["type"] == "convection":
                    e["film_coefficient"] = h["h"]
                else:
                    e["emissivity"] = h["emissivity"]
            if h["type"] == "fixed":
                fixed.append(h)
        exchanges = {b: SurfaceExchange(**e) for b, e in exchange.items()}
        common = next(
            iter(exchanges.values()), SurfaceExchange(0.0, 0.0, th["initial_temperature"])
        )
        own = {b: e for b, e in exchanges.items() if e != common}
        self._fixed_T = {
            h["name"]: dolfinx.fem.Constant(mesh, PETSc.ScalarType(h["temperature"])) for h in fixed
        }

        def heat_bcs(V):
            bcs = []
            for h in fixed:
                for b in h["boundary"]:
                    dofs = dolfinx.fem.locate_dofs_topological(
                        V, 2, tm.facet_tags.find(tm.facet_tag(b))
                    )
                    bcs.append(dolfinx.fem.dirichletbc(self._fixed_T[h["name"]], dofs, V))
            return bcs

        setup = HeatSetup(
            thermal,
            common,
            heated_cells=[],
            exposed_facets=list(exchanges),
            initial_temperature=th["initial_temperature"],
            facet_exchange=own,
            cell_thermal=region_thermal(case),
        )
        # Coils: a DG0 power density, P / (s V) on each coil's cells.
        self.q = dolfinx.fem.Function(
            dolfinx.fem.functionspace(mesh, ("DG", 0)), name="power_density"
        )
        dx = volume_measure(tm)
        one = dolfinx.fem.Constant(mesh, PETSc.ScalarType(1.0))
        self._coil_cells, self._coil_volume, self.coils = {}, {}, {}
        for c in case.coils:
            self.coils[c["name"]] = Coil(resistance=c["resistance"])
            self._coil_cells[c["name"]] = tm.cell_tags.find(tm.cell_tag(c["region"]))
            self._coil_volume[c["name"]] = self.symmetry * assemble_global(
                dolfinx.fem.form(one * dx(tm.cell_tag(c["region"]))), comm
            )
        self.power = {name: 0.0 for name in self.coils}

        # Mechanics: regions, supports, loads.
        x = ufl.SpatialCoordinate(mesh)
        lce, passive, self._transitions = [], [], []
        self.stretches: dict[
            str, dict
        ] = {}  # prescribed stretch per LCE cell set ([program] stretches)
        for r in case.regions:
            if r["material"] == "lce":
                transition = contraction_law(r)
                if r["director"] is not None:
                    director = ufl.as_vector(r["director"])
                elif r.get("director_expression") is not None:
                    director = self._director_field(r)
                else:
                    tw = r["twist"]
                    axis = AXES[tw["axis"]]
                    director = twisted_layer_director(
                        x,
                        axis,
                        self._extent(r["name"], axis),
                        float(tw["from_deg"]),
                        float(tw["to_deg"]),
                    )
                lce += self._stretch_regions(
                    r, director, transition, lce_elasticity(r["shear_modulus"])
                )
                self._transitions.append((r["name"], transition))
            else:
                passive.append(
                    PassiveRegion(
                        r["name"], NeoHookeanSolid(youngs_modulus=r["E"], poisson_ratio=r["nu"])
                    )
                )
        ds = surface_measure(tm)
        self._factors = {
            ld["name"]: dolfinx.fem.Constant(mesh, PETSc.ScalarType(1.0)) for ld in case.loads
        }

        def external_work(u):
            work = 0
            for ld in case.loads:
                f = self._factors[ld["name"]]
                if ld["type"] == "force":
                    tag = tm.facet_tag(ld["boundary"])
                    area = assemble_global(dolfinx.fem.form(one * ds(tag)), comm)
                    t = dolfinx.fem.Constant(
                        mesh, np.asarray(ld["force"], dtype=PETSc.ScalarType) / area
                    )
                    work += f * ufl.dot(t, u) * ds(tag)
                elif ld["type"] == "pressure":
                    p = dolfinx.fem.Constant(mesh, PETSc.ScalarType(ld["pressure"]))
                    work += (
                        -f
                        * p
                        * ufl.dot(ufl.FacetNormal(mesh), u)
                        * ds(tm.facet_tag(ld["boundary"]))
                    )
                else:
                    work += f * gravity_work(case, tm, mesh, ld["g"], u, dx)
            return work

        def dirichlet(V):
            bcs = []
            for s in case.supports:
                t = s["type"]
                if t == "clamp":
                    bcs += clamp_face(tm, V, s["boundary"])
                elif t in ("roller", "mirror"):
                    bcs += plane_clamp(tm, V, s["boundary"], AXES[s["normal"]])
                elif t == "point":
                    bcs += point_support(V, s["point"], [AXES[c] for c in s["components"]])
                else:
                    bcs += rigid_body_321(V, *s["points"])
            return bcs

        self.model = ThermoMechanicalModel(
            tm,
            setup,
            lce,
            passive,
            dirichlet=dirichlet,
            external_work=external_work if case.loads else None,
            petsc_options=case.petsc,
            prefix="lcefem_body_",
            heat_source=self.q if case.coils else None,
            heat_bcs=heat_bcs,
        )
        self.contacts = self._contacts_setup(case)
        self.damping = self._ramp_setup()
        self._curvatures = self._curvature_setup(case)
        # the as-built state is the mesh at T_ref (F_s = I): the mechanics starts there, and the run
        # brings it to the initial temperature when that differs
        t_refs = {tr.T_ref for _, tr in self._transitions}
        if len(t_refs) == 1:
            self.model.T_mech.x.array[:] = t_refs.pop()
        self._observables_setup(case, one, ds, dx)
        self.lambda_s = dolfinx.fem.Function(self.model.heat.V, name="spontaneous_stretch")
        self._lambda_exprs = [
            (
                tm.cell_tags.find(tm.cell_tag(n)),
                dolfinx.fem.Expression(
                    spontaneous_stretch(self.model.heat.T, tr),
                    self.model.heat.V.element.interpolation_points,
                ),
            )
            for names, tr in self._transitions
            for n in names
        ]
        self.time = 0.0  # [s]
        self.last_report = None

    # -- set-up helpers ---------------------------------------------------------------------
    def _extent(self, names, axis: int) -> tuple[float, float]:
        """(min, max) [mm] of the reference coordinate ``axis`` over the cells of ``names``."""
        tm = self.tmesh
        cells = np.concatenate([tm.cell_tags.find(tm.cell_tag(n)) for n in names])
        nodes = dolfinx.mesh.entities_to_geometry(tm.mesh, 3, cells.astype(np.int32)).reshape(-1)
        coords = tm.mesh.geometry.x[nodes, axis] if nodes.size else np.array([np.inf])
        lo = self.comm.allreduce(float(np.min(coords, initial=np.inf)), op=MPI.MIN)
        hi = self.comm.allreduce(float(np.max(coords, initial=-np.inf)), op=MPI.MAX)
        if not hi > lo:
            raise InputError(
                f"twist of {names}: the region has no thickness along axis {'xyz'[axis]}"
            )
        return lo, hi

    def _director_field(self, region: dict):
        """The unit director n = d / |d| [-] of a region's ``director_expression`` (three checked
        expressions d(X) of the reference coordinates [mm], :mod:`.body_expression`) as UFL, used at
        the mechanics' quadrature points. |d| is evaluated on the region's nodes and at those
        quadrature points first: zero (or not finite) anywhere is an InputError naming the entry."""
        import basix

        from lcefem.solvers.mechanics import QUADRATURE_DEGREE
        from lcefem.solvers.problems.body_expression import (
            ExpressionError,
            check_expression,
            to_numpy,
            to_ufl,
        )

        tm, mesh = self.tmesh, self.tmesh.mesh
        index = next(i for i, r in enumerate(self.case.regions) if r is region)
        entry = f"{self.case.path.name}: [[regions]][{index}].director_expression"
        trees = [check_expression(t) for t in region["director_expression"]]
        x = ufl.SpatialCoordinate(mesh)
        try:
            d = ufl.as_vector([to_ufl(tree, x) for tree in trees])
        except ExpressionError as exc:
            raise InputError(f"{entry}: {exc}") from None
        cells = np.concatenate([tm.cell_tags.find(tm.cell_tag(n)) for n in region["name"]]).astype(
            np.int32
        )
        nodes = mesh.geometry.x[dolfinx.mesh.entities_to_geometry(mesh, 3, cells).reshape(-1)]
        cell_type = basix.CellType[mesh.topology.cell_name()]
        points, _ = basix.make_quadrature(cell_type, QUADRATURE_DEGREE)
        at_points = (
            dolfinx.fem.Expression(x, points).eval(mesh, cells).reshape(-1, 3)
            if cells.size
            else np.empty((0, 3))
        )
        where = np.vstack([nodes, at_points])
        length = (
            np.sqrt(sum(to_numpy(tree, where) ** 2 for tree in trees)) if where.size else np.ones(1)
        )
        bad = ~(np.isfinite(length) & (length > 1e-12))
        first = where[np.argmax(bad)].tolist() if bad.any() else None
        first = next((p for p in self.comm.allgather(first) if p is not None), None)
        if first is not None:
            raise InputError(
                f"{entry}: the director is zero or undefined at ({first[0]:.4g}, "
                f"{first[1]:.4g}, {first[2]:.4g}) mm; allowed a nonzero, finite vector "
                "everywhere in the region"
            )
        return d / ufl.sqrt(ufl.dot(d, d))

    def _contacts_setup(self, case: BodyCase) -> dict[str, NodePairContact]:
        """The ``[[contact]]`` entries as node-pair penalty terms on the mechanics' Newton problem
        (:func:`lcefem.solvers.contact.facing_pairs`, :class:`NodePairContact`): energy
        k A <-g>_+^2 / 2 per node of the boundary, g [mm] its gap to the target along the target's
        current normal, k [N/mm^3] the penalty, A [mm^2] the node's tributary area."""
        contacts = {}
        for c in case.contact:
            try:
                pairs, areas = facing_pairs(
                    self.tmesh,
                    self.model.u.function_space,
                    c["boundary"],
                    c["target"],
                    AXES[c["axis"]],
                )
            except ValueError as exc:
                raise InputError(f"{case.path.name}: [[contact]] {c['name']}: {exc}") from None
            contacts[c["name"]] = NodePairContact(self.model.u, pairs, areas, c["penalty"])
        if contacts:
            attach(self.model.mechanics, list(contacts.values()))
        return contacts

    # -- prescribed stretches, their ramp and the curvature observable ([program] stretches,
    #    [[curvature]]: the composite beam as a case file) ---------------------------------
    def _stretch_regions(self, r: dict, director, transition, elasticity) -> list[LCERegion]:
        """The LCE region ``r`` as one :class:`LCERegion`, or, when ``[program] stretches`` drives
        some of its cell sets, one per cell set, the driven ones with a prescribed stretch a =
        lambda / lambda_N [-] (a Constant, 1 as built) instead of the temperature's."""
        targets = self.case.program.get("stretches") or {}
        if not any(n in targets for n in r["name"]):
            return [LCERegion(r["name"], director, transition, elasticity)]
        out = []
        for n in r["name"]:
            a = None
            if n in targets:
                a = dolfinx.fem.Constant(self.tmesh.mesh, PETSc.ScalarType(1.0))
                self.stretches[n] = {
                    "a": a,
                    "lambda_N": r["lambda_N"],
                    "lambda": r["lambda_N"],
                    "target": targets[n],
                }
            out.append(LCERegion([n], director, transition, elasticity, stretch=a))
        return out

    def _ramp_setup(self) -> NodalDamping | None:
        """The proximal term the path follower relaxes with across a fold of the stretch ramp
        (:class:`lcefem.solvers.contact.NodalDamping`, zero weight off a fold); None without a
        ramp."""
        if not self.stretches:
            return None
        damping = NodalDamping(self.model.u)
        attach(self.model.mechanics, [damping])
        return damping

    def _curvature_setup(self, case: BodyCase) -> dict[str, StationCurvature]:
        """``[[curvature]]`` entries as :class:`lcefem.solvers.probes.StationCurvature`, mirrored
        across the case's mirror planes (each mirror support's facet set, its plane coordinate the
        mean of its nodes' along the normal)."""
        if not case.curvature:
            return {}
        tm = self.tmesh
        mirrors = []
        for s in case.supports:
            if s["type"] == "mirror":
                axis = AXES[s["normal"]]
                facets = tm.facet_tags.find(tm.facet_tag(s["boundary"]))
                nodes = dolfinx.mesh.entities_to_geometry(
                    tm.mesh, 2, facets.astype(np.int32)
                ).reshape(-1)
                mirrors.append((axis, float(np.mean(tm.mesh.geometry.x[nodes, axis]))))
        out = {}
        for c in case.curvature:
            try:
                out[c["name"]] = StationCurvature(
                    self.model.u.function_space, c["stations"], c["up"], mirrors
                )
            except ValueError as exc:
                raise InputError(f"{case.path.name}: [[curvature]] {c['name']}: {exc}") from None
        return out

    def set_stretches(self, stretches: Mapping[str, float]) -> None:
        """Spontaneous stretch lambda [-] of each driven LCE cell set now (as built: lambda_N; no
        solve): a = lambda / lambda_N."""
        for name, value in stretches.items():
            st = self.stretches[name]
            st["a"].value = value / st["lambda_N"]
            st["lambda"] = value

    def ramp(self, control: PathControl, on_step) -> PathFollower:
        """Take the driven cell sets linearly from their present stretches to the targets of
        ``[program] stretches`` (load factor t: 0 -> 1) with the shared step controller
        (:class:`lcefem.solvers.continuation.PathFollower`: tangent predictor, step size from the
        Newton count, cuts, damped relaxation across folds); ``on_step(t, iterations, cuts)`` after
        each accepted increment. Returns the follower (its iterations, cuts, folds crossed)."""
        start = {n: st["lambda"] for n, st in self.stretches.items()}

        def set_load(t: float) -> None:
            self.set_stretches(
                {n: l0 + t * (self.stretches[n]["target"] - l0) for n, l0 in start.items()}
            )

        follower = PathFollower(self.model.mechanics, set_load, control, self.damping)
        follower.follow(
            1.0,
            where="stretch ramp to "
            + ", ".join(f"{n} = {st['target']:g}" for n, st in self.stretches.items()),
            on_step=lambda t, its: on_step(t, its, follower.cuts),
        )
        return follower

    def _observables_setup(self, case: BodyCase, one, ds, dx) -> None:
        tm, comm, heat, u = self.tmesh, self.comm, self.model.heat, self.model.u
        V = u.function_space
        n_local = heat.V.dofmap.index_map.size_local
        self._set_dofs = {}
        self._set_T = {}
        for name in tm.cells:
            tag = tm.cell_tag(name)
            vol = assemble_global(dolfinx.fem.form(one * dx(tag)), comm)
            self._set_T[name] = (dolfinx.fem.form(heat.T * dx(tag)), vol)
            dofs = dolfinx.fem.locate_dofs_topological(heat.V, 3, tm.cell_tags.find(tag))
            self._set_dofs[name] = dofs[dofs < n_local]
        self._boundary_probes, self._point_probes = [], []
        for p in case.probes:
            if p["boundary"] is not None:
                tag = tm.facet_tag(p["boundary"])
                area = assemble_global(dolfinx.fem.form(one * ds(tag)), comm)
                forms = [dolfinx.fem.form(u[i] * ds(tag)) for i in range(3)] + [
                    dolfinx.fem.form(heat.T * ds(tag))
                ]
                self._boundary_probes.append((p["name"], forms, area))
            else:
                self._point_probes.append((p["name"], PointProbe(tm.mesh, np.array(p["point"]))))
        self._reactions = []
        for i, s in enumerate(case.supports):
            if s["type"] not in ("clamp", "roller"):
                continue
            comps = (0, 1, 2) if s["type"] == "clamp" else (AXES[s["normal"]],)
            facets = tm.facet_tags.find(tm.facet_tag(s["boundary"]))
            for c in comps:
                weight = dolfinx.fem.Function(V)
                dofs = dolfinx.fem.locate_dofs_topological(V.sub(c), 2, facets)
                weight.x.array[dofs] = 1.0
                label = f"reaction_{'xyz'[c]} {s['name'] or s['boundary']} [N]"
                self._reactions.append((label, self.model.mechanics.reaction_form(weight)))

    # -- drives -----------------------------------------------------------------------------
    def drive_tags(self) -> tuple[str, ...]:
        return tuple(self.coils)

    def set_drives(self, drives: Mapping[str, float]) -> None:
        """Coil current [A] per coil name: the Joule power P = I^2 R [mW] over the whole coil's
        volume (the mesh's share times the symmetry factor)."""
        for name, current in drives.items():
            if name not in self.coils:
                raise InputError(
                    f"drive {name!r}: not a coil of this body (allowed "
                    f"{', '.join(self.coils) or 'none'})"
                )
            check_current(f"current[{name}]", current)
            self.power[name] = self.coils[name].power(float(current))
        self._put_power()

    def _put_power(self) -> None:
        self.q.x.array[:] = 0.0
        for name, power in self.power.items():
            self.q.x.array[self._coil_cells[name]] = power / self._coil_volume[name]
        self.q.x.scatter_forward()

    def set_boundary_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """Fixed temperature [C] of each ``[[heat]]`` entry of type fixed, by name."""
        for name, value in temperatures.items():
            if name not in self._fixed_T:
                raise InputError(
                    f"temperature drive {name!r}: allowed {', '.join(self._fixed_T) or 'none'}"
                )
            self._fixed_T[name].value = float(value)

    def set_load_factors(self, factors: Mapping[str, float]) -> None:
        """Factor [-] of each ``[[loads]]`` entry, by name."""
        for name, value in factors.items():
            if name not in self._factors:
                raise InputError(
                    f"load drive {name!r}: allowed {', '.join(self._factors) or 'none'}"
                )
            self._factors[name].value = float(value)

    def set_program(self, t: float) -> None:
        """Every drive of the case's program at time ``t`` [s]."""
        d = self.case.drives
        self.set_drives({k: s(t) for k, s in d["currents"].items()})
        self.set_boundary_temperatures({k: s(t) for k, s in d["temperatures"].items()})
        self.set_load_factors({k: s(t) for k, s in d["loads"].items()})

    # -- stepping ---------------------------------------------------------------------------
    def advance(self, dt: float, where: str | None = None):
        """One backward-Euler heat step of ``dt`` [s], then the mechanics to the new temperature
        (the one path follower); returns the step report (iterations, cuts)."""
        self.last_report = self.model.step(dt, where=where or f"step of {dt:g} s")
        self.time += dt
        return self.last_report

    def equilibrate(self, where: str):
        self.last_report = self.model.equilibrate(where)
        return self.last_report

    def steady_state(self, rtol: float = 1e-8, max_iterations: int = 30):
        """Thermal and mechanical equilibrium at the present drives: fixed point between the steady
        heat equation (pulled back with the present displacement) and the mechanics."""
        u = self.model.u
        previous = u.x.array.copy()
        iterations, last = 0, np.inf
        for it in range(1, max_iterations + 1):
            self.model.heat.steady()
            iterations += self.equilibrate(f"steady state, fixed-point iteration {it}").iterations
            change = self.comm.allreduce(
                float(np.max(np.abs(u.x.array - previous), initial=0.0)), op=MPI.MAX
            )
            scale = self.comm.allreduce(float(np.max(np.abs(u.x.array), initial=0.0)), op=MPI.MAX)
            if settled(change, last, max(scale, 1e-12), rtol):  # round-off floor: solvers/heat.py
                return iterations
            previous, last = u.x.array.copy(), change
        raise ConvergenceError(
            "steady state",
            f"displacement still changing after {max_iterations} "
            "heat-mechanics fixed-point iterations",
        )

    # -- observables ------------------------------------------------------------------------
    def observables(self) -> dict[str, float]:
        heat, comm = self.model.heat, self.comm
        obs = {"T_mean [C]": heat.mean_temperature(), "T_max [C]": heat.max_temperature()}
        for name, (form, vol) in self._set_T.items():
            obs[f"T_mean {name} [C]"] = assemble_global(form, comm) / vol
            obs[f"T_max {name} [C]"] = comm.allreduce(
                float(np.max(heat.T.x.array[self._set_dofs[name]], initial=-np.inf)), op=MPI.MAX
            )
        for name, power in self.power.items():
            obs[f"power {name} [mW]"] = power
        for name, forms, area in self._boundary_probes:
            for c, form in zip("xyz", forms[:3]):
                obs[f"u_{c} {name} [mm]"] = assemble_global(form, comm) / area
            obs[f"T {name} [C]"] = assemble_global(forms[3], comm) / area
        for name, probe in self._point_probes:
            uu = probe(self.model.u)[0]
            for c, value in zip("xyz", uu):
                obs[f"u_{c} {name} [mm]"] = float(value)
            obs[f"T {name} [C]"] = float(probe(heat.T)[0][0])
        for label, form in self._reactions:
            obs[label] = self.symmetry * assemble_global(form, comm)
        for name, curvature in self._curvatures.items():
            obs[f"curvature {name} [1/mm]"] = curvature(self.model.u)
        for name, st in self.stretches.items():
            obs[f"stretch {name} [-]"] = st["lambda"]
        for name, contact in self.contacts.items():
            obs[f"contact_force {name} [N]"] = self.symmetry * contact.normal_force()
            gaps = contact.gaps()
            obs[f"min_gap {name} [mm]"] = float(np.min(gaps)) if gaps.size else math.nan
        return obs

    def fields(self) -> dict:
        self._update_stretch()
        return {
            "displacement [mm]": self.model.u,
            "temperature [C]": self.model.heat.T,
            "spontaneous stretch [-]": self.lambda_s,
        }

    def _update_stretch(self) -> None:
        self.lambda_s.x.array[:] = 1.0  # passive regions: no spontaneous stretch
        for cells, expr in self._lambda_exprs:
            self.lambda_s.interpolate(expr, cells0=cells)
        for name, st in self.stretches.items():  # prescribed, whatever the temperature
            dofs = dolfinx.fem.locate_dofs_topological(
                self.lambda_s.function_space,
                3,
                self.tmesh.cell_tags.find(self.tmesh.cell_tag(name)),
            )
            self.lambda_s.x.array[dofs] = st["lambda"]
        self.lambda_s.x.scatter_forward()

    def _state_functions(self) -> list:
        return [self.model.u, self.model.heat.T, self.model.heat.T_old, self.model.T_mech]

    def save_state(self) -> dict:
        return {
            "arrays": copy_arrays(self._state_functions()),
            "time": self.time,
            "power": dict(self.power),
            "stretches": {n: st["lambda"] for n, st in self.stretches.items()},
            "fixed": {k: float(c.value) for k, c in self._fixed_T.items()},
            "factors": {k: float(c.value) for k, c in self._factors.items()},
        }

    def restore_state(self, state: dict) -> None:
        put_arrays(self._state_functions(), state["arrays"])
        self.time, self.power = state["time"], dict(state["power"])
        self._put_power()
        self.set_boundary_temperatures(state["fixed"])
        self.set_load_factors(state["factors"])
        self.set_stretches(state.get("stretches", {}))


def run_body(
    case: BodyCase,
    out: pathlib.Path | None = None,
    progress: bool = True,
    comm: MPI.Comm | None = None,
) -> BodyResult:
    """Build the body of ``case`` and run its program (a transient of equal steps to the duration,
    the drives at the end of each step; or the steady state) through the run skeleton
    (the door, :func:`lcefem.solvers.runner.run`): history.csv, temperature.bp / displacement.bp,
    summary.json with every resolved value."""
    result = _run_body(case, out, progress, comm)
    # The problem's solvers sit in reference cycles (closures); freed by the cyclic collector at a
    # moment of each rank's own, their collective destroy (MUMPS duplicates a communicator) met
    # another rank's different collective and deadlocked under mpiexec (ex07, CI of 5bfec1f).
    # Collected here, every rank frees them at the same point of the program.
    gc.collect()
    return result


def _run_body(case: BodyCase, out, progress: bool, comm) -> BodyResult:
    started = time.perf_counter()
    problem = BodyProblem(case, comm)
    prog, output = case.program, case.output
    steady = prog["steady"]
    n_steps = 1 if steady else max(1, int(math.ceil(prog["duration"] / prog["dt"] - 1e-9)))
    dt = prog["duration"] / n_steps
    problem.set_program(0.0)
    first = problem.observables()
    ramp = bool(problem.stretches)  # a quasi-static stretch ramp: the clock is the load factor
    clock, end = ("load factor [-]", 1.0) if ramp else ("time [s]", prog["duration"])
    columns = (clock, *first, "newton_iterations [-]", "step_cuts [-]")
    bar = Progress(
        end,
        f"body {case.path.stem}",
        "load" if ramp else "s",
        enabled=progress and not steady,
        comm=problem.comm,
    )

    def row(state) -> dict:
        return state[0]

    history = HistoryExport(
        columns,
        row,
        where=lambda s: s[2],
        at=lambda s: min(s[0][clock], end),
        postfix=lambda s: f"T_max={s[0]['T_max [C]']:.1f}C",
    )
    exports = ()
    if out is not None and output["fields"]:
        common = dict(
            comm=problem.comm,
            time=lambda s: s[0][clock] if math.isfinite(s[0][clock]) else 0.0,
            start=False,
            every=output["every"],
            step=lambda s: s[1],
        )
        exports = (
            FEFields(
                "temperature.bp",
                (problem.model.heat.T, problem.lambda_s),
                update=problem._update_stretch,
                **common,
            ),
            FEFields("displacement.bp", (problem.model.u,), **common),
        )

    def observe(t: float, report) -> dict:
        return {
            clock: t,
            **problem.observables(),
            "newton_iterations [-]": report.iterations if report else 0,
            "step_cuts [-]": report.cuts if report else 0,
        }

    def drive(on_step) -> dict:
        needs_start = bool(case.loads or case.drives["temperatures"]) or any(
            tr.T_ref != case.thermal["initial_temperature"] for _, tr in problem._transitions
        )
        if ramp:
            return ramp_stretches(problem, on_step, needs_start)
        if steady:
            its = problem.steady_state()
            on_step((observe(math.inf, None), 0, "steady state"))
            return {"steady_state": {"newton_iterations": its}}
        report = problem.equilibrate("t = 0 s (initial state)") if needs_start else None
        on_step((observe(0.0, report), 0, "t = 0 s"))
        total = 0
        for k in range(1, n_steps + 1):
            t = k * dt
            problem.set_program(t)
            report = problem.advance(dt, f"t = {t:.4g} s")
            problem.time = t
            total += report.iterations
            on_step((observe(t, report), k, f"t = {t:.4g} s"))
        return {"steps": n_steps, "dt [s]": dt, "newton_iterations": total}

    def ramp_stretches(problem, on_step, needs_start: bool) -> dict:
        """The as-built state (load factor 0), then one row per accepted increment of the ramp."""
        report = problem.equilibrate("load factor 0 (as built)") if needs_start else None
        on_step((observe(0.0, report), 0, "load factor 0"))
        steps = []

        def record(t: float, its: int, cuts: int) -> None:
            steps.append(t)
            row = {
                clock: t,
                **problem.observables(),
                "newton_iterations [-]": its,
                "step_cuts [-]": cuts,
            }
            on_step((row, len(steps), f"load factor {t:.4g}"))

        follower = problem.ramp(PathControl(**case.path_control), record)
        return {
            "steps": len(steps),
            "newton_iterations": follower.iterations,
            "cut_steps": follower.cuts,
            "folds crossed": follower.snaps,
        }

    found = {}

    def summarize(run, result: dict) -> dict:
        found["history"] = run.history
        final = run.last_row() if hasattr(run, "last_row") else None
        return {
            "mesh": {**problem.mesh_info, "mpi_ranks": problem.comm.size},
            **result,
            "final": final,
            "wall_time [s]": time.perf_counter() - started,
        }

    path = PathProblem(
        drive,
        clock=LOAD if ramp else TIME,
        end=end,
        comm=problem.comm,
        at=lambda s: min(s[0][clock], end),
    )  # the steady state's inf: the end
    summary = run(
        path,
        path.program(),
        [StateHistory(history), *(StateExport(e) for e in exports)],
        out,
        config=case.resolved(),
        progress=bar,
        comm=problem.comm,
        summarize=lambda skeleton, records: summarize(skeleton, records[-1].detail),
    )
    return BodyResult(found["history"].as_arrays(), summary, out)
