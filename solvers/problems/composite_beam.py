"""The composite beam of seed 001 (Fig. 3) in 3D finite strain (FEniCSx): the FE composite-beam
problem, used by ``lcefem run beam --model fe``, the validation cases of
:mod:`lcefem.validation.cases.beam_fe` and the benchmark. (The Kapton buckling specimen is
:mod:`lcefem.solvers.problems.kapton_specimen`.)

* :class:`BeamFE` — the composite beam of :func:`lcefem.meshes.composite_beam_fe.build_beam_fe`:
  Kapton as a compressible neo-Hookean solid, the LCE strips with the elastic energy
  W(F U(a)^-1) of :mod:`lcefem.models.hyperelastic`, U(a) = a n(x)n + a^-1/2 (I - n(x)n) along the
  strip axis n = e_x (:func:`lcefem.models.lce.isochoric_uniaxial`) with a = lambda/lambda_N the
  strips' length relative to the as-built (nematic) state; bond pads passive (a = 1), as the
  published model has no LCE over the bonds. Strip-ribbon contact: :mod:`lcefem.solvers.contact`.
  Supports: symmetry planes (quarter model) plus one point held in z; the half model holds a point
  in x and z and a second point in z (statically determinate, as the bar-and-hinge beam).
  Drives per strip tag (:meth:`BeamFE.set_drives`, ``top_strips``/``bottom_strips``);
  :meth:`BeamFE.advance` takes them from their current values to the targets with the
  shared step controller :class:`lcefem.solvers.continuation.PathFollower` (tangent predictor,
  step size from the Newton iteration count, cutting, damped relaxation across folds);
  :func:`curvature_map_fe` sweeps a grid with one model.
* :class:`HeatedBeamFE` — the same beam driven by a coil current through the heat model
  (:class:`lcefem.solvers.thermomechanics.ThermoMechanicalModel`); its run without outputs is
  :func:`lcefem.solvers.problems.composite_beam_run.beam_fe_heated`.
* ``lcefem run beam --model fe`` (its configuration sections and one run through the run
  skeleton) is :mod:`lcefem.solvers.problems.composite_beam_run`.

Curvature: the same stations and circle fit as the bar-and-hinge beam
(:func:`lcefem.meshes.composite_beam.middle_station_indices`,
:func:`~lcefem.solvers.analysis.curvature.signed_circle_curvature`): junction centres on the
ribbon's mid-surface, positive when the beam bends towards its bottom strips (Eq. 2's sign).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import pathlib
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes.composite_beam import CompositeBeamGeometry, middle_station_indices
from lcefem.meshes.composite_beam_fe import BeamFEMesh, build_beam_fe
from lcefem.models.bar_hinge_materials import PUBLISHED_LAMBDA_N
from lcefem.models.errors import InputError
from lcefem.models.heat import GridSegmentCoil
from lcefem.models.hyperelastic import (
    LCEElasticity,
    NeoHookeanSolid,
    lce_strain_energy,
    neo_hookean_strain_energy,
)
from lcefem.models.lce import isochoric_uniaxial
from lcefem.models.limits import check_lambda, current_param
from lcefem.models.parameters import param
from lcefem.solvers.analysis.curvature import signed_circle_curvature
from lcefem.solvers.contact import NodalDamping, NodePairContact, PenaltyContact, attach, face_pairs
from lcefem.solvers.continuation import PathControl, PathFollower
from lcefem.solvers.exports import write_snapshot
from lcefem.solvers.mechanics import (
    HyperelasticProblem,
    assemble_global,
    deformation_gradient,
    displacement_space,
    volume_measure,
)
from lcefem.solvers.problems.protocol import (
    LOAD,
    StepRecord,
    check_quasi_static_step,
    copy_arrays,
    put_arrays,
)
from lcefem.solvers.supports import plane_clamp, point_support

PUBLISHED = (
    "published reduced-order model (Daraio-lab/RoboticSurface_SciRob_LiuK; "
    "shared/reference/published_reduced_model.md)"
)
_prefix = itertools.count()
#: Newton settings of the beam: full steps (the critical-point line search's single secant step
#: stalls on the as-built beam's near-mechanism), few iterations before a cut; converged when the
#: nodal force residual is below 1e-7 N (the strips carry 0.1-1 N; round-off leaves ~1e-8 N on the
#: thin Kapton elements) or the Newton step has shrunk to round-off (relative 1e-11).
#: (``pc_type = "cholesky"``: MUMPS LDL^T at every size, not the automatic iterative path above
#: ``mechanics.ITERATIVE_PATH_DOFS``: CG + p-multigrid did not finish the level-0 ramp to (1.33,
#: 1.05) in 900 s wall, where LDL^T takes 98 Newton iterations and 6.8 s CPU; 2026-11-25.)
BEAM_NEWTON = {
    "snes_linesearch_type": "basic",
    "snes_max_it": 14,
    "snes_atol": 1e-7,
    "snes_stol": 1e-11,
    "pc_type": "cholesky",
}

#: Fill-reducing ordering of the beam's LDL^T: MUMPS's approximate minimum degree with quasi-dense
#: row detection (QAMD, ICNTL(7) = 6) instead of MUMPS's automatic choice, METIS's nested
#: dissection. On the slender beam a minimum-degree elimination runs along the length with about
#: one cross-section in its front; the nested dissection's separators are cross-sections too, and
#: METIS placed them worse at levels 0 and 1: factorisation flops (MUMPS RINFOG(3)) at level 0
#: 1.33e8 -> 7.63e7, level 1 1.18e9 -> 7.29e8 (numeric factorisation 0.260 -> 0.194 s CPU, same
#: tangent, interleaved), level 2 4.6e9 both; AMD (ICNTL(7) = 0) gives QAMD's flops.
BEAM_ORDERING = {"mat_mumps_icntl_7": 6}

#: Step control of the beam's lambda ramps: the shared controller aiming at 12 Newton iterations
#: per step with steps up to 0.25 of the ramp (the defaults aim at 10 with steps up to 0.2). Chosen
#: by the ramp to (1.33, 1.05) (``fe_benchmark --beam-levels 0 1 --beam-variants newton t10``,
#: issue 13): level 0 89 Newton iterations in 13 steps against 98 in 15; level 1 (18,072 DOFs, quiet
#: machine, one process per core) 90 iterations / 33.5 s CPU against 93 / 37.1 s, the curvature the
#: same to 1e-9 (validation/data/fe_benchmark_beam_ramp.csv). A Newton step on this beam costs
#: the same however long the path step (README, "Newton variants of the 4-segment beam's ramp"),
#: so fewer, longer steps pay until they start to be cut.
BEAM_CONTROL = PathControl(target_iterations=12, max_step=0.25)


def _unique_prefix(stem: str) -> str:
    """dolfinx 0.11 NonlinearProblems need distinct PETSc options prefixes."""
    return f"lcefem_{stem}{next(_prefix)}_"


@dataclass(frozen=True)
class BeamActuation:
    """How the prescribed relative lengths enter the FE beam."""

    lambda_N: float = param(
        PUBLISHED_LAMBDA_N,
        "-",
        PUBLISHED + ": isotropic/nematic length ratio 1/0.7143 (the "
        "bar-and-hinge beam and Eq. 2 use the same value)",
        minimum=1.0,
    )


@dataclass(frozen=True)
class FEMaterials:
    """Materials of the FE beam and ribbon (defaults: datasheet Kapton, the fitted LCE law)."""

    kapton: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)
    lce: LCEElasticity = field(default_factory=LCEElasticity)


# --------------------------------------------------------------------------- composite beam
def beam_supports(tmesh, V) -> list:
    """Dirichlet conditions of the FE beam: symmetry planes (u_x = 0 on x = x_mid in the quarter
    model, u_y = 0 on y = W/2) and a statically determinate set of point supports on the ribbon's
    mid-surface at x = x_mid (quarter: u_z; half: u_x and u_z, plus u_z at the next station)."""
    info = tmesh.info
    planes = [("sym_y", 1)] + ([("sym_x", 0)] if info["symmetry"] == "quarter" else [])
    bcs = [bc for face, comp in planes for bc in plane_clamp(tmesh, V, face, comp)]
    W = info["ribbon_width"]
    a = (info["x_mid"], 0.5 * W, info["mid_surface_height"])
    bcs += point_support(V, a, (2,))
    if info["symmetry"] == "half":
        bcs += point_support(V, a, (0,))
        bcs += point_support(
            V, (info["second_support_x"], 0.5 * W, info["second_support_height"]), (2,)
        )
    return bcs


class BeamStations:
    """Deformed curvature stations of the FE beam from the nodes at the reference points of
    :func:`lcefem.meshes.composite_beam_fe.fe_stations` (mirrored about x = x_mid in the quarter
    model).

    On several ranks each point is the node of the one rank that owns it (owned nodes only, never a
    ghost; exactly one rank per point, checked when built); the deformed positions of all points
    are combined with one allreduce, so :meth:`points`, :meth:`up` and :meth:`curvature` are
    collective and give every rank the same numbers (serial: the node positions themselves)."""

    def __init__(self, tmesh, V):
        info = tmesh.info
        self.comm = V.mesh.comm
        self.X = V.tabulate_dof_coordinates()
        self._owned = V.dofmap.index_map.size_local  # nodes this rank owns (then its ghosts)
        self.quarter = info["symmetry"] == "quarter"
        self.x_mid = info["x_mid"]
        points, self.groups = [], []
        for pts in info["stations"]:
            group = []
            for p in pts:
                mirrored = self.quarter and p[0] < self.x_mid - 1e-9
                q = np.array([2.0 * self.x_mid - p[0], p[1], p[2]]) if mirrored else np.asarray(p)
                group.append((len(points), mirrored))
                points.append(q)
            self.groups.append(group)
        tp = info["ribbon_thickness"]
        z0 = info["mid_surface_height"]
        self.up_rows = (len(points), len(points) + 1)
        for dz in (-0.5 * tp, 0.5 * tp):
            points.append(np.array((self.x_mid, 0.5 * info["ribbon_width"], z0 + dz)))
        self._rows, self._nodes = self._owned_nodes(np.asarray(points))
        self._count = len(points)
        self.segments = info["segments"]

    def _owned_nodes(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(rows of ``points``, this rank's owned node at each) for the points this rank owns;
        every point owned by exactly one rank (collective)."""
        X = self.X[: self._owned]
        rows, nodes, nearest = [], [], np.full(len(points), np.inf)
        owners = np.zeros(len(points), dtype=np.int64)  # owned nodes at each point
        for k, point in enumerate(points):
            if X.shape[0] == 0:
                continue
            d = np.linalg.norm(X - point, axis=1)
            i = int(np.argmin(d))
            nearest[k] = d[i]
            if d[i] <= 1e-6:
                rows.append(k)
                nodes.append(i)
                owners[k] = np.count_nonzero(d <= 1e-6)  # a second node there: ambiguous
        if self.comm.size > 1:
            self.comm.Allreduce(MPI.IN_PLACE, owners, op=MPI.SUM)
            self.comm.Allreduce(MPI.IN_PLACE, nearest, op=MPI.MIN)
        for k, point in enumerate(points):
            if owners[k] != 1:
                raise RuntimeError(
                    f"station point {tuple(point)}: {owners[k]} owned nodes there over the ranks, "
                    f"expected one (nearest {nearest[k]:.3g} mm away)"
                )
        return np.asarray(rows, dtype=np.int64), np.asarray(nodes, dtype=np.int64)

    def _positions(self, u: dolfinx.fem.Function) -> np.ndarray:
        """Deformed positions (points, 3) [mm] of every station point, on every rank
        (collective)."""
        x = np.zeros((self._count, 3))
        nodes = self._nodes
        x[self._rows] = self.X[nodes] + u.x.array.reshape(-1, 3)[nodes]
        if self.comm.size > 1:  # one owner per point, zeros elsewhere: the sum is exact
            self.comm.Allreduce(MPI.IN_PLACE, x, op=MPI.SUM)
        return x

    def points(self, u: dolfinx.fem.Function) -> np.ndarray:
        """Stations (N + 1, 3) [mm] in the deformed state (collective)."""
        return self._stations(self._positions(u))

    def _stations(self, x: np.ndarray) -> np.ndarray:
        rows = []
        for group in self.groups:
            pts = []
            for row, mirrored in group:
                p = x[row].copy()
                if mirrored:
                    p[0] = 2.0 * self.x_mid - p[0]
                pts.append(p)
            rows.append(np.mean(pts, axis=0))
        return np.asarray(rows)

    def _up(self, x: np.ndarray) -> np.ndarray:
        v = x[self.up_rows[1]] - x[self.up_rows[0]]
        return v / np.linalg.norm(v)

    def up(self, u) -> np.ndarray:
        """Unit vector [-] across the ribbon at x_mid (bottom to top face; collective)."""
        return self._up(self._positions(u))

    def curvature(self, u) -> float:
        """Signed curvature [1/mm] through the middle stations (Eq. 2's sign; collective)."""
        x = self._positions(u)
        pts = self._stations(x)
        return signed_circle_curvature(pts[middle_station_indices(self.segments)], self._up(x))


@dataclass
class BeamState:
    """One converged state of the ramp."""

    load_factor: float
    lambda_top: float
    lambda_bottom: float
    curvature: float  # [1/mm]
    iterations: int
    cuts: int
    contact_force: float  # [N], whole beam
    min_gap: float  # [mm], negative: penetration


class BeamFE:
    """The FE composite beam, forms compiled once; drives are the strip groups' lambda.

    Build: ``BeamFE(geometry, mesh, ...)``. Drive: :meth:`set_drives` (lambdas) per strip tag
    (``top_strips``, ``bottom_strips``: the same call shape as the gridshell's 48 strips).
    Solve: :meth:`advance` (to the targets set) or :meth:`ramp` (set and advance). Observe:
    :meth:`observables`, :meth:`curvature`. Output: :meth:`write_fields`.

    Args:
        geometry: shared beam dimensions (:class:`CompositeBeamGeometry`).
        mesh: FE discretisation (:class:`BeamFEMesh`).
        materials: Kapton and LCE laws.
        actuation: lambda_N.
        control: stepping of the ramps (:class:`PathControl`).
        contact: strip-ribbon penalty contact.
        petsc_options: overrides of the Newton options.
    """

    #: The strip tags that carry a drive (cell tags of :func:`build_beam_fe`).
    STRIPS = ("top_strips", "bottom_strips")

    def __init__(
        self,
        geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
        mesh: BeamFEMesh = BeamFEMesh(),
        materials: FEMaterials = FEMaterials(),
        actuation: BeamActuation = BeamActuation(),
        contact: PenaltyContact = PenaltyContact(),
        control: PathControl | None = None,
        petsc_options: dict | None = None,
        comm: MPI.Comm | None = None,
    ):
        self.geometry, self.mesh_options, self.materials = geometry, mesh, materials
        self.control = control or BEAM_CONTROL
        options = {**BEAM_NEWTON, **BEAM_ORDERING}
        options.update(petsc_options or {})
        self.actuation, self.contact_options = actuation, contact
        self.tmesh = tm = build_beam_mesh(geometry, actuation.lambda_N, mesh, comm)
        self.comm = tm.mesh.comm  # the runner claims and writes the run's folder on it
        self.V = V = displacement_space(tm.mesh, 2)
        self.u = u = dolfinx.fem.Function(V, name="displacement")
        self.a_top = dolfinx.fem.Constant(tm.mesh, PETSc.ScalarType(1.0))
        self.a_bottom = dolfinx.fem.Constant(tm.mesh, PETSc.ScalarType(1.0))
        self.energy_density = beam_energy_terms(u, materials, self.a_top, self.a_bottom)
        dx = volume_measure(tm)
        energy = sum(w * dx(tm.cell_tag(name)) for name, w in self.energy_density.items())
        self.bcs = beam_supports(tm, V)
        self.problem = HyperelasticProblem(
            u,
            energy,
            self.bcs,
            prefix=_unique_prefix("beamfe"),
            petsc_options=options,
            user_options=tuple(petsc_options or ()),
        )
        self.contacts = make_contacts(tm, u, contact)
        self.damping = NodalDamping(u)  # proximal term of PathFollower's relaxation across folds
        attach(self.problem, [*self.contacts, self.damping])
        self.stations = BeamStations(tm, V)
        self.lambda_top = self.lambda_bottom = actuation.lambda_N
        self.target = {"top_strips": actuation.lambda_N, "bottom_strips": actuation.lambda_N}
        self.ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        self.last_follower = None

    def set_lambdas(self, lambda_top: float, lambda_bottom: float) -> None:
        """Relative lengths of the top and bottom strips now (as built: lambda_N; no solve)."""
        lam_n = self.actuation.lambda_N
        self.a_top.value = lambda_top / lam_n
        self.a_bottom.value = lambda_bottom / lam_n
        self.lambda_top, self.lambda_bottom = lambda_top, lambda_bottom

    def _set_lambda(self, drives: Mapping[str, float]) -> None:
        """Target spontaneous stretches lambda [-] (relative to the isotropic length; as built:
        lambda_N) per strip tag (:attr:`STRIPS`); reached by :meth:`advance`."""
        for tag, value in drives.items():
            if tag not in self.STRIPS:
                raise InputError(
                    f"drive {tag!r}: not a strip tag of the beam (allowed {', '.join(self.STRIPS)})"
                )
            self.target[tag] = check_lambda(f"lambda[{tag}]", value, self.actuation.lambda_N)

    def curvature(self) -> float:
        """Signed curvature [1/mm] through the middle stations (module docstring)."""
        return self.stations.curvature(self.u)

    def contact_force(self) -> float:
        """Total contact force [N] on the whole beam (the mesh's times the symmetry factor)."""
        return self.tmesh.info["symmetry_factor"] * sum(c.normal_force() for c in self.contacts)

    def min_gap(self) -> float:
        """Smallest strip-ribbon gap [mm] (negative: penetration; nan without contact)."""
        return min((float(np.min(c.gaps())) for c in self.contacts), default=float("nan"))

    def observables(self) -> dict[str, float]:
        """Named observables, keys "name [unit]"."""
        return {
            "lambda_top [-]": self.lambda_top,
            "lambda_bottom [-]": self.lambda_bottom,
            "curvature [1/mm]": self.curvature(),
            "contact force [N]": self.contact_force(),
            "min gap [mm]": self.min_gap(),
        }

    def advance(
        self,
        dt: float = 1.0,
        *,
        on_step: Callable[[BeamState], None] | None = None,
        progress: Callable[[float], None] | None = None,
    ) -> StepRecord:
        """Take the strips linearly from their current lengths to the targets of :meth:`set_drives`
        (load parameter t: 0 -> 1; ``dt`` < 1 stops at that fraction of the way) with
        :class:`PathFollower`; ``on_step`` sees one :class:`BeamState` per accepted step (the
        record's ``detail``: their list). Raises ConvergenceError (the model keeps the last
        converged state)."""
        dt = check_quasi_static_step(dt)
        lambda_top, lambda_bottom = self.target["top_strips"], self.target["bottom_strips"]
        lt0, lb0 = self.lambda_top, self.lambda_bottom

        def set_load(t: float) -> None:
            self.set_lambdas(lt0 + t * (lambda_top - lt0), lb0 + t * (lambda_bottom - lb0))

        follower = PathFollower(self.problem, set_load, self.control, self.damping)
        states: list[BeamState] = []

        def record(t: float, its: int) -> None:
            state = BeamState(
                t,
                self.lambda_top,
                self.lambda_bottom,
                self.curvature(),
                its,
                follower.cuts,
                self.contact_force(),
                self.min_gap(),
            )
            states.append(state)
            if on_step is not None:
                on_step(state)
            if progress is not None:
                progress(t)

        follower.follow(
            dt,
            where=f"beam ramp to lambda_T = {lambda_top:g}, lambda_B = {lambda_bottom:g}",
            on_step=record,
        )
        self.last_follower = follower
        return StepRecord(
            dt, self.observables(), follower.iterations, follower.cuts, clock=LOAD, detail=states
        )

    def increment_record(self, state: BeamState) -> StepRecord:
        """The :class:`StepRecord` of one converged increment of :meth:`advance` (``at``: its
        fraction of the way; the one door, lcefem.solvers.runner.run, records every increment)."""
        return StepRecord(
            state.load_factor,
            {
                "lambda_top [-]": state.lambda_top,
                "lambda_bottom [-]": state.lambda_bottom,
                "curvature [1/mm]": state.curvature,
                "contact force [N]": state.contact_force,
                "min gap [mm]": state.min_gap,
            },
            state.iterations,
            state.cuts,
            clock=LOAD,
            detail=state,
        )

    def ramp(self, lambda_top: float, lambda_bottom: float, **kw) -> list[BeamState]:
        """:meth:`set_drives` of (lambda_T, lambda_B) then :meth:`advance`; the states of the
        ramp."""
        lam_n = self.actuation.lambda_N
        check_lambda("lambda_top", lambda_top, lam_n)
        check_lambda("lambda_bottom", lambda_bottom, lam_n)
        self._set_lambda({"top_strips": lambda_top, "bottom_strips": lambda_bottom})
        return self.advance(**kw).detail

    def write_fields(self, folder, t: float = 0.0) -> list[pathlib.Path]:
        """displacement.bp (Q2, VTX, ParaView) of the current state in ``folder``."""
        return [write_snapshot(folder, "displacement.bp", [self.u], t)]

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "lambda [-]"

    def drive_tags(self) -> tuple[str, ...]:
        return self.STRIPS

    def set_drives(self, drives: Mapping[str, float]) -> None:
        self._set_lambda(drives)

    def fields(self) -> dict:
        return {"displacement [mm]": self.u}

    def save_state(self) -> dict:
        return {
            "u": copy_arrays([self.u]),
            "lambdas": (self.lambda_top, self.lambda_bottom),
            "target": dict(self.target),
        }

    def restore_state(self, state: dict) -> None:
        put_arrays([self.u], state["u"])
        self.set_lambdas(*state["lambdas"])
        self.target = dict(state["target"])


def build_beam_mesh(geometry, lambda_N, mesh, comm):
    """:func:`build_beam_fe` plus the support points the solver needs (kept out of the mesh
    builder's tags: they are nodes, not facets)."""
    tm = build_beam_fe(geometry, lambda_N, mesh, comm)
    g = geometry
    x_mid = tm.info["x_mid"]
    s_mid = x_mid - g.segment_start(min(int(x_mid // g.pitch), g.segments - 1))
    on_segment = 0.0 <= s_mid <= g.segment_length
    tm.info["mid_surface_height"] = float(g.arch_height(s_mid)) if on_segment else 0.0
    # the half model's second z support: the next junction edge (even N) or crown edge (odd N)
    if g.segments % 2 == 0:
        tm.info["second_support_x"] = x_mid + 0.5 * g.junction_length
        tm.info["second_support_height"] = 0.0
    else:
        tm.info["second_support_x"] = x_mid + 0.5 * g.crown_bond_length
        tm.info["second_support_height"] = g.top_strip_height
    return tm


def beam_energy_terms(u, materials: FEMaterials, a_top, a_bottom) -> dict:
    """Strain energy densities [mJ/mm^3] per cell group of the FE beam (UFL)."""
    F = deformation_gradient(u)
    n = ufl.as_vector([1.0, 0.0, 0.0])  # director: along the strips (seed 001, stage-2 stretch)

    def lce(a):
        return lce_strain_energy(F * isochoric_uniaxial(1.0 / a, n), materials.lce)

    return {
        "kapton": neo_hookean_strain_energy(F, materials.kapton),
        "bottom_strips": lce(a_bottom),
        "top_strips": lce(a_top),
        "bottom_pads": lce_strain_energy(F, materials.lce),
        "top_pads": lce_strain_energy(F, materials.lce),
    }


def make_contacts(tmesh, u, options: PenaltyContact) -> list[NodePairContact]:
    """Top strips over the ribbon (their undersides) and bottom strips under it (their topsides)."""
    if not options.enabled:
        return []
    out = []
    for face, above in (("top_strip_underside", True), ("bottom_strip_topside", False)):
        if face in tmesh.facets:
            pairs, areas = face_pairs(tmesh, u.function_space, face, "kapton", strip_above=above)
            out.append(NodePairContact(u, pairs, areas, options.stiffness))
    return out


def solve_beam_fe(
    lambda_top: float,
    lambda_bottom: float,
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    mesh: BeamFEMesh = BeamFEMesh(),
    materials: FEMaterials = FEMaterials(),
    actuation: BeamActuation = BeamActuation(),
    contact: PenaltyContact = PenaltyContact(),
    control: PathControl | None = None,
    **kw,
) -> tuple[BeamFE, list[BeamState]]:
    """Build the FE beam and ramp it from the as-built state to (lambda_T, lambda_B); returns
    (model, states)."""
    model = BeamFE(geometry, mesh, materials, actuation, contact, control)
    states = model.ramp(lambda_top, lambda_bottom, **kw)
    return model, states


# --------------------------------------------------------------------------- curvature map
def sweep_order(lambdas) -> list[tuple[float, float]]:
    """Grid points (lambda_T, lambda_B) in a serpentine order starting at the largest values, so
    that each solve continues from a neighbour (one coordinate changes by one grid step)."""
    lam = sorted((float(v) for v in lambdas), reverse=True)
    order = []
    for i, lt in enumerate(lam):
        row = lam if i % 2 == 0 else lam[::-1]
        order += [(lt, lb) for lb in row]
    return order


#: First increment of t on the ramp from one grid point to its neighbour (the ramp from the
#: as-built state keeps PathControl.first_step = 0.01). A neighbour is a small step from a converged
#: state, so the 0.01 start only adds growth steps: 5 x 5 map [1.05, 1.33]^2, level 0: 1058 Newton
#: iterations (105 s CPU) with 0.01, 858 (84 s) with 0.3; a whole neighbour step (1.0) fails twice
#: before it is cut to 0.25 (86.6 s with max_step 1.0). Same curvatures to 1e-6.
NEIGHBOUR_FIRST_STEP = 0.3


def curvature_map_fe(
    lambdas,
    geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
    mesh: BeamFEMesh = BeamFEMesh(),
    materials: FEMaterials = FEMaterials(),
    actuation: BeamActuation = BeamActuation(),
    contact: PenaltyContact = PenaltyContact(),
    control: PathControl | None = None,
    on_point: Callable[[float, float, float, int], None] | None = None,
    neighbour_first_step: float = NEIGHBOUR_FIRST_STEP,
    on_state: Callable[[float, float, "BeamFE"], None] | None = None,
) -> tuple[np.ndarray, dict, "BeamFE"]:
    """kappa[i, j] [1/mm] at (lambdas[i], lambdas[j]) = (lambda_T, lambda_B), one model swept
    through the grid (:func:`sweep_order`: the first point is ramped from the as-built state, each
    next one from its neighbour, starting with the increment ``neighbour_first_step`` of t).
    Returns (kappa, stats, model): Newton iterations, folds crossed, the largest contact force and
    smallest strip-ribbon gap over the grid, the wall time; the model in its last state.
    ``on_state(lambda_T, lambda_B, model)`` after each point (e.g. to keep its equilibrium)."""
    lam = [float(v) for v in lambdas]
    model = BeamFE(geometry, mesh, materials, actuation, contact, control)
    ramp_control = model.control
    neighbour = dataclasses.replace(
        ramp_control, first_step=max(model.control.first_step, neighbour_first_step)
    )
    kappa = np.full((len(lam), len(lam)), np.nan)
    stats = {
        "iterations": 0,
        "snaps": 0,
        "max_contact_force [N]": 0.0,
        "min_gap [mm]": math.inf,
        "points": 0,
        "dofs": model.ndofs,
    }
    started = time.perf_counter()
    for n, (lt, lb) in enumerate(sweep_order(lam)):
        if n == 1:
            model.control = neighbour
        model.ramp(lt, lb)
        k = model.curvature()
        kappa[lam.index(lt), lam.index(lb)] = k
        f = model.last_follower
        stats["iterations"] += f.iterations
        stats["snaps"] += f.snaps
        stats["points"] += 1
        stats["max_contact_force [N]"] = max(stats["max_contact_force [N]"], model.contact_force())
        stats["min_gap [mm]"] = min(stats["min_gap [mm]"], model.min_gap())
        if on_point is not None:
            on_point(lt, lb, k, f.iterations)
        if on_state is not None:
            on_state(lt, lb, model)
    stats["wall_time [s]"] = time.perf_counter() - started
    model.control = ramp_control
    return kappa, stats, model


# --------------------------------------------------------------------------- heat-driven beam
@dataclass(frozen=True)
class HeatedBeamRun:
    """A coil current through one group of strips (the heat model has one power density)."""

    current: float = current_param(
        0.0,
        "0 (default) prescribes lambda_T, lambda_B instead; seed 001 "
        "used 0.2 A for rapid contraction, 0.1 A for slow (Fig. 2A-B)",
    )
    heated: str = param(
        "bottom",
        "-",
        "strips carrying the current: 'bottom', 'top' or 'both' (the "
        "others stay at room temperature, as built)",
    )
    duration: float = param(
        12.0,
        "s",
        "chosen: part of the 0.2 A transient (T_NI reached in about 10 s, seed 001)",
        positive=True,
    )
    dt: float = param(1.0, "s", "chosen: time step (backward Euler)", positive=True)

    def checked(self) -> "HeatedBeamRun":
        from lcefem.models.parameters import check

        check(self, "heat_run")
        if self.heated not in ("bottom", "top", "both"):
            raise InputError(
                f"heat_run.heated = {self.heated!r}: allowed 'bottom', 'top' or 'both'"
            )
        if self.dt > self.duration:
            raise InputError(
                f"heat_run.dt = {self.dt} s: must be <= heat_run.duration = {self.duration} s"
            )
        return self


#: Strip groups a ``HeatedBeamRun.heated`` choice puts the coil current through.
HEATED_STRIPS = {
    "bottom": ("bottom_strips",),
    "top": ("top_strips",),
    "both": ("bottom_strips", "top_strips"),
}


class HeatedBeamFE:
    """The FE beam driven by a coil current (seed 001's actuation) through
    :class:`lcefem.solvers.thermomechanics.ThermoMechanicalModel`: Joule power I^2 R per strip
    (R of one 30 mm grid segment's ``coil``, seed 001) spread uniformly over each heated strip's
    volume (the coil is not resolved), conduction into the ribbon through the bonded pads only,
    convection and radiation on every exterior face; the LCE of the strips follows the nematic
    transition, the bond pads are passive. Each time step's mechanics is brought from the old to
    the new temperature with :class:`PathFollower` (tangent predictor in time).

    Build with the strip tags that carry a coil (``heated``: forms are compiled once, so the set
    is fixed); drive: :meth:`set_drives` (coil currents) per strip tag; advance: :meth:`advance` (dt
    [s]); observe: :meth:`observables`.
    """

    def __init__(
        self,
        heated=("bottom_strips",),
        geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
        mesh: BeamFEMesh = BeamFEMesh(),
        materials: FEMaterials = FEMaterials(),
        contact: PenaltyContact = PenaltyContact(),
        control: PathControl | None = None,
        transition=None,
        thermal=None,
        exchange=None,
        coil: GridSegmentCoil = GridSegmentCoil(),
        dt: float = 1.0,
    ):
        from lcefem.models.heat import SurfaceExchange, ThermalProperties
        from lcefem.models.lce import NematicTransition
        from lcefem.solvers.heat import HeatSetup
        from lcefem.solvers.thermomechanics import (
            LCERegion,
            PassiveRegion,
            TemperatureFollower,
            ThermoMechanicalModel,
        )

        unknown = [t for t in heated if t not in BeamFE.STRIPS]
        if unknown or not heated:
            raise InputError(
                f"heated = {tuple(heated)}: strip tags among {', '.join(BeamFE.STRIPS)}"
            )
        self.heated, self.coil = tuple(heated), coil
        transition = transition or NematicTransition()
        self.tmesh = tm = build_beam_mesh(geometry, transition.lambda_N, mesh, None)
        self.comm = tm.mesh.comm  # the runner claims and writes the run's folder on it
        n = ufl.as_vector([1.0, 0.0, 0.0])
        exposed = [
            f
            for f in (
                "ribbon_top",
                "ribbon_bottom",
                "top_strip_underside",
                "bottom_strip_topside",
                "surface",
            )
            if f in tm.facets
        ]
        setup = HeatSetup(
            thermal or ThermalProperties(),
            exchange or SurfaceExchange(),
            heated_cells=list(self.heated),
            exposed_facets=exposed,
        )
        passive_lce = NematicTransition(lambda_N=1.0)  # no order, no spontaneous strain: bond pads
        lce = [
            LCERegion(["bottom_strips"], n, transition, materials.lce),
            LCERegion(["top_strips"], n, transition, materials.lce),
            LCERegion(["bottom_pads", "top_pads"], n, passive_lce, materials.lce),
        ]
        self.model = model = ThermoMechanicalModel(
            tm,
            setup,
            lce,
            [PassiveRegion(["kapton"], materials.kapton)],
            dirichlet=lambda V: beam_supports(tm, V),
            petsc_options={**BEAM_NEWTON, **BEAM_ORDERING},
            prefix=_unique_prefix("heatbeam"),
        )
        self.u = model.u
        self.contacts = make_contacts(tm, model.u, contact)
        damping = NodalDamping(model.u)
        attach(model.mechanics, [*self.contacts, damping])
        self._strip_volume = (
            geometry.segment_length * tm.info["strip_width"] * tm.info["strip_thickness"]
        )
        self.stations = BeamStations(tm, model.u.function_space)
        dx = volume_measure(tm)
        self._mean_T = {
            name: (
                dolfinx.fem.form(model.heat.T * dx(tm.cell_tag(name))),
                assemble_global(dolfinx.fem.form(1.0 * dx(tm.cell_tag(name))), tm.mesh.comm),
            )
            for name in ("bottom_strips", "top_strips", "kapton")
        }
        self.stepper = TemperatureFollower(
            model.heat,
            model.T_mech,
            model.mechanics,
            control or PathControl(first_step=dt, max_step=dt),
            damping,
        )
        self.current = 0.0  # [A]

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.stepper.time

    @time.setter
    def time(self, value: float) -> None:
        self.stepper.time = value

    def _set_current(self, drives: Mapping[str, float]) -> None:
        """Coil current [A] per strip tag; the heat model has one power density, so every heated
        strip tag carries the same current (a different one is refused)."""
        values = {float(v) for k, v in drives.items() if k in self.heated}
        extra = [k for k in drives if k not in self.heated]
        if extra or len(values) != 1 or set(drives) != set(self.heated):
            raise InputError(
                f"current drives {dict(drives)}: give one current [A] for each of the "
                f"heated strip tags {', '.join(self.heated)} (one power density)"
            )
        self.current = values.pop()
        # mW per strip over its volume
        self.model.heat.power_density.value = self.coil.power(self.current) / self._strip_volume

    def observables(self, iterations: int = 0) -> dict[str, float]:
        """Named observables, keys "name [unit]"."""
        tm = self.tmesh
        row = {
            "time [s]": self.time,
            "curvature [1/mm]": self.stations.curvature(self.u),
            "newton iterations [-]": iterations,
            "contact force [N]": tm.info["symmetry_factor"]
            * sum(c.normal_force() for c in self.contacts),
        }
        for name, (form, vol) in self._mean_T.items():
            row[f"T_mean {name} [C]"] = assemble_global(form, tm.mesh.comm) / vol
        return row

    def advance(self, dt: float) -> StepRecord:
        """One backward-Euler heat step of ``dt`` [s], then the mechanics from the old to the new
        temperature (the one path follower, load parameter = time); returns its
        :class:`StepRecord` (the observables with the step's Newton iterations)."""
        its = self.stepper.advance(dt, where=f"heated beam, t = {self.time + dt:.4g} s")
        return StepRecord(self.time, self.observables(its), its)

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "current [A]"

    def drive_tags(self) -> tuple[str, ...]:
        return self.heated

    def set_drives(self, drives: Mapping[str, float]) -> None:
        self._set_current(drives)

    def fields(self) -> dict:
        return {"displacement [mm]": self.u, "temperature [C]": self.model.heat.T}

    def _state_functions(self) -> list:
        return [self.u, self.model.heat.T, self.model.heat.T_old, self.model.T_mech]

    def save_state(self) -> dict:
        return {
            "arrays": copy_arrays(self._state_functions()),
            "time": self.time,
            "current": self.current,
        }

    def restore_state(self, state: dict) -> None:
        put_arrays(self._state_functions(), state["arrays"])
        self.time = state["time"]
        self._set_current({tag: state["current"] for tag in self.heated})
