"""3D finite-element (FEniCSx) simulations of seed 001's passive ribbon and composite beam, shared by
``lcefem run ribbon-buckling --model fe``, ``lcefem run beam --model fe``, the validation cases of
:mod:`lcefem.validation.cases.beam_fe` and the benchmark.

* :class:`BeamFE` — the composite beam of :func:`lcefem.meshes.composite_beam.build_beam_fe`:
  Kapton as a compressible neo-Hookean solid, the LCE strips with the elastic energy
  W(F U(a)^-1) of :mod:`lcefem.models.hyperelastic`, U(a) = a n(x)n + a^-1/2 (I - n(x)n) along the
  strip axis n = e_x (:func:`lcefem.models.lce.isochoric_uniaxial`) with a = lambda/lambda_N the
  strips' length relative to the as-built (nematic) state; bond pads passive (a = 1), as the
  published model has no LCE over the bonds. Strip-ribbon contact: :mod:`lcefem.solvers.contact`.
  Supports: symmetry planes (quarter model) plus one point held in z; the half model holds a point
  in x and z and a second point in z (statically determinate, as the bar-and-hinge beam).
  :meth:`BeamFE.ramp` takes (lambda_T, lambda_B) from their current values to targets with
  :class:`PathFollower` (secant predictor, adaptive steps with cutting, damped relaxation across
  folds); :func:`curvature_map_fe` sweeps a grid with one model.
* :func:`beam_fe_heated` — the same beam driven by a coil current through the heat model
  (:class:`lcefem.solvers.thermomechanics.ThermoMechanicalModel`).
* :class:`RibbonFE` — the fixed-fixed buckling specimen: critical load of the perfect specimen
  (linearised buckling about the straight state, SLEPc generalised eigenproblem, repeated at the
  estimate: a secant refinement), first mode as imperfection, displacement-controlled path to 50 %
  compression.

Curvature: the same stations and circle fit as the bar-and-hinge beam
(:func:`lcefem.meshes.composite_beam.middle_station_indices`,
:func:`~lcefem.solvers.analysis.curvature.signed_circle_curvature`): junction centres on the ribbon's
mid-surface, positive when the beam bends towards its bottom strips (Eq. 2's sign).
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
import dolfinx.fem.petsc

from lcefem.meshes.composite_beam import (BeamFEMesh, CompositeBeamGeometry, build_beam_fe,
                                          middle_station_indices)
from lcefem.meshes.kapton_ribbon import RibbonFEMesh, RibbonSpecimen, build_ribbon_fe
from lcefem.models.errors import ConvergenceError, InputError
from lcefem.models.hyperelastic import (LCEElasticity, NeoHookeanSolid, lce_strain_energy,
                                        neo_hookean_strain_energy)
from lcefem.models.bar_hinge import PUBLISHED_LAMBDA_N
from lcefem.models.heat import GridSegmentCoil
from lcefem.models.lce import isochoric_uniaxial
from lcefem.models.parameters import param
from lcefem.solvers.analysis.curvature import signed_circle_curvature
from lcefem.solvers.contact import (NodalDamping, NodePairContact, PenaltyContact, attach,
                                    face_pairs)
from lcefem.solvers.mechanics import (HyperelasticProblem, assemble_global, deformation_gradient,
                                      displacement_space, volume_measure)

PUBLISHED = ("published reduced-order model (Daraio-lab/RoboticSurface_SciRob_LiuK; "
             "shared/reference/published_reduced_model.md)")
_prefix = itertools.count()
#: Newton settings of the beam: full steps (the critical-point line search's single secant step
#: stalls on the as-built beam's near-mechanism), few iterations before a cut; converged when the
#: nodal force residual is below 1e-7 N (the strips carry 0.1-1 N; round-off leaves ~1e-8 N on the
#: thin Kapton elements) or the Newton step has shrunk to round-off (relative 1e-11).
BEAM_NEWTON = {"snes_linesearch_type": "basic", "snes_max_it": 14, "snes_atol": 1e-7,
               "snes_stol": 1e-11}


def _unique_prefix(stem: str) -> str:
    """dolfinx 0.11 NonlinearProblems need distinct PETSc options prefixes."""
    return f"lcefem_{stem}{next(_prefix)}_"


@dataclass(frozen=True)
class BeamActuation:
    """How the prescribed relative lengths enter the FE beam."""

    lambda_N: float = param(PUBLISHED_LAMBDA_N, "-", PUBLISHED + ": isotropic/nematic length ratio 1/0.7143 (the "
                            "bar-and-hinge beam and Eq. 2 use the same value)", minimum=1.0)


@dataclass(frozen=True)
class FEMaterials:
    """Materials of the FE beam and ribbon (defaults: datasheet Kapton, the fitted LCE law)."""

    kapton: NeoHookeanSolid = field(default_factory=NeoHookeanSolid)
    lce: LCEElasticity = field(default_factory=LCEElasticity)


# --------------------------------------------------------------------------- path following
@dataclass(frozen=True)
class PathControl:
    """Adaptive stepping of a load path t: 0 -> 1 (a ramp of strip lengths or an end shortening)."""

    first_step: float = param(0.01, "-", "chosen: first increment of t (the as-built beam is almost a "
                              "mechanism: its first increments rotate thin Kapton a lot)", positive=True,
                              maximum=1.0)
    max_step: float = param(0.1, "-", "chosen: largest increment of t", positive=True, maximum=1.0)
    min_step: float = param(1.0e-4, "-", "chosen: an increment below this that still fails marks a "
                            "fold of the path (a snap-through), crossed by relaxation", positive=True)
    growth: float = param(1.5, "-", "chosen: increment growth after an easy step", minimum=1.0)
    easy_iterations: int = param(8, "-", "chosen: a step converged within this many Newton "
                                 "iterations lets the next grow (fewest iterations over the ramp of "
                                 "the beam at (1.33, 1.05) among 5, 6, 8)", minimum=1)
    snap_step: float = param(0.01, "-", "chosen: increment of t across a fold", positive=True)
    relaxation_steps: int = param(60, "-", "chosen: most damped (proximal) Newton steps across a fold",
                                  minimum=1)
    damping: float = param(1.0e-3, "N/mm", "chosen: first proximal weight c of the relaxation "
                           "(energy + c/2 sum |u - u_k|^2 over the nodes), divided by 4 after each "
                           "success down to damping_floor", positive=True)
    damping_floor: float = param(1.0e-9, "N/mm", "chosen: proximal weight below which the "
                                 "relaxation ends with an undamped solve", positive=True)


class PathFollower:
    """Follows an equilibrium path in a load parameter t with a secant predictor, adaptive
    increments and step cutting from the last converged state; across a fold (a snap-through: no
    nearby equilibrium beyond it) it relaxes at the next load with damped Newton steps
    (proximal point: minimise Pi(u) + c/2 sum_nodes |u - u_k|^2, c -> 0), which descend to a stable
    state. Raises ConvergenceError (the model keeps the last converged state).

    (:func:`lcefem.solvers.continuation.advance` has no predictor and grows its step only after a
    cut; the as-built beam, almost a mechanism, needs both to converge in reasonable time.)

    Args:
        problem: the Newton problem.
        set_load: sets the model's load at path parameter t.
        damping: a :class:`lcefem.solvers.contact.NodalDamping` attached to the problem (None: folds
            raise ConvergenceError).
    """

    def __init__(self, problem: HyperelasticProblem, set_load: Callable[[float], None],
                 control: PathControl = PathControl(), damping: NodalDamping | None = None,
                 t0: float = 0.0):
        self.problem, self.set_load, self.control = problem, set_load, control
        self.damping = damping
        self.t = t0
        self.history = [(t0, problem.save())]
        self.step = control.first_step
        self.iterations = 0
        self.cuts = 0
        self.snaps = 0

    def _predict(self, t: float) -> None:
        (t1, u1), (t2, u2) = (self.history[-2], self.history[-1]) if len(self.history) > 1 \
            else (self.history[-1], self.history[-1])
        self.problem.restore(u2 + (t - t2) / (t2 - t1) * (u2 - u1) if t2 != t1 else u2)

    def _accept(self, t: float) -> None:
        self.t = t
        self.history = [self.history[-1], (t, self.problem.save())]

    def _solve(self) -> tuple[bool, int, str]:
        ok, its, reason = self.problem.solve()
        self.iterations += its
        return ok, its, reason

    def follow(self, t_to: float, where: str,
               on_step: Callable[[float, int], None] | None = None) -> None:
        """From the current t to ``t_to``; ``on_step(t, iterations)`` after each accepted step."""
        c = self.control
        while self.t < t_to - 1e-12:
            t_new = min(t_to, self.t + self.step)
            self.set_load(t_new)
            self._predict(t_new)
            ok, its, reason = self._solve()
            if ok:
                self._accept(t_new)
                if its <= c.easy_iterations:
                    self.step = min(c.max_step, c.growth * self.step)
                if on_step is not None:
                    on_step(self.t, its)
                continue
            self.cuts += 1
            self.problem.restore(self.history[-1][1])
            self.set_load(self.t)
            self.step *= 0.5
            if self.step >= c.min_step:
                continue
            t_new = min(t_to, self.t + c.snap_step)
            its = self._relax(t_new, f"{where}: fold at t = {self.t:.5g} ({reason})")
            self._accept(t_new)
            self.history = self.history[-1:]  # no secant across the jump
            self.step = c.first_step
            self.snaps += 1
            if on_step is not None:
                on_step(self.t, its)

    def _relax(self, t_new: float, where: str) -> int:
        if self.damping is None:
            raise ConvergenceError(where, "no relaxation available for this model")
        c = self.control
        start = self.problem.save()
        self.set_load(t_new)
        weight, its_total = c.damping, 0
        try:
            for _ in range(c.relaxation_steps):
                self.damping.anchor[:] = self.problem.save()
                self.damping.weight = weight
                ok, its, reason = self._solve()
                its_total += its
                if not ok:
                    self.problem.restore(self.damping.anchor.copy())
                    weight *= 10.0
                    continue
                if weight < c.damping_floor:
                    break
                weight *= 0.25
            self.damping.weight = 0.0
            ok, its, reason = self._solve()
            its_total += its
        finally:
            self.damping.weight = 0.0
        if not ok:
            self.problem.restore(start)
            self.set_load(self.t)
            raise ConvergenceError(where, f"relaxation at t = {t_new:.5g} failed: {reason}")
        return its_total


# --------------------------------------------------------------------------- composite beam
def check_lambda(name: str, value: float, lambda_N: float) -> float:
    """Relative strip length lambda (isotropic = 1, as built = lambda_N): must lie in [1, lambda_N]."""
    if not isinstance(value, (int, float)) or not math.isfinite(value) or not 1.0 <= value <= lambda_N:
        raise InputError(f"{name} = {value}: must be between 1 (isotropic) and lambda_N = "
                         f"{lambda_N} (as built)")
    return float(value)


def _point_dofs(V, comp: int, point, tol: float) -> np.ndarray:
    """DOFs of component ``comp`` at the node located at ``point`` [mm]."""
    Vc, _ = V.sub(comp).collapse()
    p = np.asarray(point, dtype=float)
    dofs = dolfinx.fem.locate_dofs_geometrical(
        (V.sub(comp), Vc), lambda x: np.linalg.norm(x.T - p, axis=1) < tol)[0]
    if dofs.size == 0:
        raise RuntimeError(f"no node at {tuple(p)}")
    return dofs


def beam_supports(tmesh, V) -> list:
    """Dirichlet conditions of the FE beam: symmetry planes (u_x = 0 on x = x_mid in the quarter
    model, u_y = 0 on y = W/2) and a statically determinate set of point supports on the ribbon's
    mid-surface at x = x_mid (quarter: u_z; half: u_x and u_z, plus u_z at the next station)."""
    info = tmesh.info
    fdim = tmesh.mesh.topology.dim - 1
    zero = PETSc.ScalarType(0.0)
    bcs = []
    planes = [("sym_y", 1)] + ([("sym_x", 0)] if info["symmetry"] == "quarter" else [])
    for name, comp in planes:
        facets = tmesh.facet_tags.find(tmesh.facet_tag(name))
        dofs = dolfinx.fem.locate_dofs_topological(V.sub(comp), fdim, facets)
        bcs.append(dolfinx.fem.dirichletbc(zero, dofs, V.sub(comp)))
    W, tol = info["ribbon_width"], 1e-6
    x_mid = info["x_mid"]
    a = (x_mid, 0.5 * W, info["mid_surface_height"])
    bcs.append(dolfinx.fem.dirichletbc(zero, _point_dofs(V, 2, a, tol), V.sub(2)))
    if info["symmetry"] == "half":
        bcs.append(dolfinx.fem.dirichletbc(zero, _point_dofs(V, 0, a, tol), V.sub(0)))
        b = (info["second_support_x"], 0.5 * W, info["second_support_height"])
        bcs.append(dolfinx.fem.dirichletbc(zero, _point_dofs(V, 2, b, tol), V.sub(2)))
    return bcs


class BeamStations:
    """Deformed curvature stations of the FE beam from the nodes at the reference points of
    :func:`lcefem.meshes.composite_beam.fe_stations` (mirrored about x = x_mid in the quarter model)."""

    def __init__(self, tmesh, V):
        info = tmesh.info
        self.X = V.tabulate_dof_coordinates()
        self.quarter = info["symmetry"] == "quarter"
        self.x_mid = info["x_mid"]
        self.groups = []
        for pts in info["stations"]:
            group = []
            for p in pts:
                mirrored = self.quarter and p[0] < self.x_mid - 1e-9
                q = np.array([2.0 * self.x_mid - p[0], p[1], p[2]]) if mirrored else np.asarray(p)
                group.append((self._node(q), mirrored))
            self.groups.append(group)
        tp = info["ribbon_thickness"]
        z0 = info["mid_surface_height"]
        self.up_nodes = (self._node((self.x_mid, 0.5 * info["ribbon_width"], z0 - 0.5 * tp)),
                         self._node((self.x_mid, 0.5 * info["ribbon_width"], z0 + 0.5 * tp)))
        self.segments = info["segments"]

    def _node(self, point) -> int:
        d = np.linalg.norm(self.X - np.asarray(point), axis=1)
        i = int(np.argmin(d))
        if d[i] > 1e-6:
            raise RuntimeError(f"no node at station point {tuple(point)} (nearest {d[i]:.3g} mm away)")
        return i

    def points(self, u: dolfinx.fem.Function) -> np.ndarray:
        """Stations (N + 1, 3) [mm] in the deformed state."""
        x = self.X + u.x.array.reshape(-1, 3)
        rows = []
        for group in self.groups:
            pts = []
            for node, mirrored in group:
                p = x[node].copy()
                if mirrored:
                    p[0] = 2.0 * self.x_mid - p[0]
                pts.append(p)
            rows.append(np.mean(pts, axis=0))
        return np.asarray(rows)

    def up(self, u) -> np.ndarray:
        x = self.X + u.x.array.reshape(-1, 3)
        v = x[self.up_nodes[1]] - x[self.up_nodes[0]]
        return v / np.linalg.norm(v)

    def curvature(self, u) -> float:
        """Signed curvature [1/mm] through the middle stations (Eq. 2's sign)."""
        pts = self.points(u)
        return signed_circle_curvature(pts[middle_station_indices(self.segments)], self.up(u))


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
    """The FE composite beam, forms compiled once; :meth:`ramp` prescribes (lambda_T, lambda_B).

    Args:
        geometry: shared beam dimensions (:class:`CompositeBeamGeometry`).
        mesh: FE discretisation (:class:`BeamFEMesh`).
        materials: Kapton and LCE laws.
        actuation: lambda_N.
        control: stepping of the ramps (:class:`PathControl`).
        contact: strip-ribbon penalty contact.
        petsc_options: overrides of the Newton options.
    """

    def __init__(self, geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
                 mesh: BeamFEMesh = BeamFEMesh(), materials: FEMaterials = FEMaterials(),
                 actuation: BeamActuation = BeamActuation(), contact: PenaltyContact = PenaltyContact(),
                 control: PathControl | None = None, petsc_options: dict | None = None,
                 comm: MPI.Comm = MPI.COMM_WORLD):
        self.geometry, self.mesh_options, self.materials = geometry, mesh, materials
        self.control = control or PathControl()
        options = dict(BEAM_NEWTON)
        options.update(petsc_options or {})
        self.actuation, self.contact_options = actuation, contact
        self.tmesh = tm = build_beam_mesh(geometry, actuation.lambda_N, mesh, comm)
        self.V = V = displacement_space(tm.mesh, 2)
        self.u = u = dolfinx.fem.Function(V, name="displacement")
        self.a_top = dolfinx.fem.Constant(tm.mesh, PETSc.ScalarType(1.0))
        self.a_bottom = dolfinx.fem.Constant(tm.mesh, PETSc.ScalarType(1.0))
        self.energy_density = beam_energy_terms(u, materials, self.a_top, self.a_bottom)
        dx = volume_measure(tm)
        energy = sum(w * dx(tm.cell_tag(name)) for name, w in self.energy_density.items())
        self.bcs = beam_supports(tm, V)
        self.problem = HyperelasticProblem(u, energy, self.bcs, prefix=_unique_prefix("beamfe"),
                                           petsc_options=options)
        self.contacts = make_contacts(tm, u, contact)
        self.damping = NodalDamping(u)  # proximal term of PathFollower's relaxation across folds
        attach(self.problem.snes, [*self.contacts, self.damping], self.bcs, homogeneous=True)
        self.stations = BeamStations(tm, V)
        self.lambda_top = self.lambda_bottom = actuation.lambda_N
        self.ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs

    def set_lambdas(self, lambda_top: float, lambda_bottom: float) -> None:
        """Relative lengths of the top and bottom strips (as built: lambda_N)."""
        lam_n = self.actuation.lambda_N
        self.a_top.value = lambda_top / lam_n
        self.a_bottom.value = lambda_bottom / lam_n
        self.lambda_top, self.lambda_bottom = lambda_top, lambda_bottom

    def curvature(self) -> float:
        return self.stations.curvature(self.u)

    def contact_force(self) -> float:
        """Total contact force [N] on the whole beam (the mesh's times the symmetry factor)."""
        return self.tmesh.info["symmetry_factor"] * sum(c.normal_force() for c in self.contacts)

    def min_gap(self) -> float:
        return min((float(np.min(c.gaps())) for c in self.contacts), default=float("nan"))

    def ramp(self, lambda_top: float, lambda_bottom: float, *,
             on_step: Callable[[BeamState], None] | None = None,
             progress: Callable[[float], None] | None = None) -> list[BeamState]:
        """Take the strips linearly from their current lengths to (lambda_T, lambda_B) (load
        parameter t: 0 -> 1) with :class:`PathFollower`; one :class:`BeamState` per accepted step.
        Raises ConvergenceError (the model keeps the last converged state)."""
        lam_n = self.actuation.lambda_N
        check_lambda("lambda_top", lambda_top, lam_n)
        check_lambda("lambda_bottom", lambda_bottom, lam_n)
        lt0, lb0 = self.lambda_top, self.lambda_bottom

        def set_load(t: float) -> None:
            self.set_lambdas(lt0 + t * (lambda_top - lt0), lb0 + t * (lambda_bottom - lb0))

        follower = PathFollower(self.problem, set_load, self.control, self.damping)
        states: list[BeamState] = []

        def record(t: float, its: int) -> None:
            state = BeamState(t, self.lambda_top, self.lambda_bottom, self.curvature(), its,
                              follower.cuts, self.contact_force(), self.min_gap())
            states.append(state)
            if on_step is not None:
                on_step(state)
            if progress is not None:
                progress(t)

        follower.follow(1.0, where=f"beam ramp to lambda_T = {lambda_top:g}, lambda_B = "
                        f"{lambda_bottom:g}", on_step=record)
        self.last_follower = follower
        return states

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

    return {"kapton": neo_hookean_strain_energy(F, materials.kapton),
            "bottom_strips": lce(a_bottom), "top_strips": lce(a_top),
            "bottom_pads": lce_strain_energy(F, materials.lce),
            "top_pads": lce_strain_energy(F, materials.lce)}


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


def solve_beam_fe(lambda_top: float, lambda_bottom: float,
                  geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
                  mesh: BeamFEMesh = BeamFEMesh(), materials: FEMaterials = FEMaterials(),
                  actuation: BeamActuation = BeamActuation(),
                  contact: PenaltyContact = PenaltyContact(), control: PathControl | None = None,
                  **kw) -> tuple[BeamFE, list[BeamState]]:
    """Build the FE beam and ramp it from the as-built state to (lambda_T, lambda_B); returns
    (model, states)."""
    model = BeamFE(geometry, mesh, materials, actuation, contact, control)
    states = model.ramp(lambda_top, lambda_bottom, **kw)
    return model, states


# --------------------------------------------------------------------------- ribbon buckling
@dataclass(frozen=True)
class RibbonFEPath:
    """Stepping of the FE buckling test and its imperfection."""

    imperfection: float = param(1.0e-3, "-", "chosen: amplitude/length of the first buckling "
                                "eigenmode added to the geometry (the bar-and-hinge run uses the "
                                "same amplitude of the fixed-fixed mode shape)", minimum=0.0,
                                maximum=0.1)
    step: float = param(0.02, "-", "chosen: compression increment in the post-buckling range",
                        positive=True, maximum=0.25)
    onset_steps: int = param(12, "-", "chosen: geometric increments from 0.2 to 50 x the critical "
                             "compression (resolves the rise of the force to its plateau)",
                             minimum=2, maximum=200)


@dataclass
class CriticalLoad:
    force: float  # [N]
    shortening: float  # [mm]
    mode: dolfinx.fem.Function  # first buckling mode (max |u_z| = 1)
    secant_change: float  # relative change of the critical shortening in the last secant step


class RibbonFE:
    """The fixed-fixed Kapton specimen in 3D finite strain (neo-Hookean, datasheet E and nu).

    The left clamp face is held, the right one moved by (-shortening, 0, 0); with the half model
    u_y = 0 on the mid-plane y = W/2. The compressive force is minus the x-reaction on the right
    clamp face, times the symmetry factor.
    """

    def __init__(self, specimen: RibbonSpecimen = RibbonSpecimen(), mesh: RibbonFEMesh = RibbonFEMesh(),
                 solid: NeoHookeanSolid = NeoHookeanSolid(), petsc_options: dict | None = None,
                 comm: MPI.Comm = MPI.COMM_WORLD):
        self.specimen, self.solid = specimen, solid
        self.tmesh = tm = build_ribbon_fe(specimen, mesh, comm)
        self.V = V = displacement_space(tm.mesh, 2)
        self.u = u = dolfinx.fem.Function(V, name="displacement")
        fdim = tm.mesh.topology.dim - 1
        tm.mesh.topology.create_connectivity(fdim, tm.mesh.topology.dim)
        left = dolfinx.fem.locate_dofs_topological(V, fdim, tm.facet_tags.find(tm.facet_tag("clamp_left")))
        right = dolfinx.fem.locate_dofs_topological(V, fdim, tm.facet_tags.find(tm.facet_tag("clamp_right")))
        self.end = dolfinx.fem.Constant(tm.mesh, np.zeros(3, dtype=PETSc.ScalarType))
        zero = dolfinx.fem.Constant(tm.mesh, np.zeros(3, dtype=PETSc.ScalarType))
        self.bcs = [dolfinx.fem.dirichletbc(zero, left, V), dolfinx.fem.dirichletbc(self.end, right, V)]
        if "sym_y" in tm.facets:
            dofs = dolfinx.fem.locate_dofs_topological(V.sub(1), fdim, tm.facet_tags.find(tm.facet_tag("sym_y")))
            self.bcs.append(dolfinx.fem.dirichletbc(PETSc.ScalarType(0.0), dofs, V.sub(1)))
        dx = volume_measure(tm)
        energy = neo_hookean_strain_energy(deformation_gradient(u), solid) * dx
        self.problem = HyperelasticProblem(u, energy, self.bcs, prefix=_unique_prefix("ribbonfe"),
                                           petsc_options=petsc_options)
        weight = dolfinx.fem.Function(V)
        weight.x.array[3 * right] = 1.0
        self._reaction = self.problem.reaction_form(weight)
        self._jacobian = dolfinx.fem.form(ufl.derivative(self.problem.residual, u, ufl.TrialFunction(V)))
        self.factor = tm.info["symmetry_factor"]
        self.length = specimen.length
        self.ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        self._mid = self._node((0.5 * self.length, 0.0, 0.5 * specimen.thickness))

    def _node(self, point) -> int:
        X = self.V.tabulate_dof_coordinates()
        return int(np.argmin(np.linalg.norm(X - np.asarray(point), axis=1)))

    def set_shortening(self, shortening: float) -> None:
        self.end.value = np.array([-shortening, 0.0, 0.0])

    def force(self) -> float:
        """Compressive end force [N] on the whole specimen."""
        return -self.factor * assemble_global(self._reaction, self.tmesh.mesh.comm)

    def mid_deflection(self) -> float:
        """z displacement [mm] of the mid-span node on the ribbon's mid-plane, edge y = 0."""
        return float(self.u.x.array[3 * self._mid + 2])

    def axial_stiffness(self, shortening: float) -> float:
        """Secant axial stiffness F/shortening [N/mm] of the straight specimen."""
        self.straight_state(shortening)
        return self.force() / shortening

    def straight_state(self, shortening: float) -> None:
        """Equilibrium of the perfect (flat) specimen on its straight (unbuckled) path, from the
        uniform-strain guess u_x = -shortening x/L (Newton stays on the symmetric path)."""
        X = self.V.tabulate_dof_coordinates()
        guess = np.zeros_like(X)
        guess[:, 0] = -shortening * X[:, 0] / self.length
        self.problem.restore(guess.ravel())
        self.set_shortening(shortening)
        ok, its, reason = self.problem.solve()
        if not ok:
            raise ConvergenceError(f"straight state at shortening {shortening:g} mm", reason)

    def tangent(self) -> PETSc.Mat:
        A = dolfinx.fem.petsc.assemble_matrix(self._jacobian, bcs=self.bcs, diag=1.0)
        A.assemble()
        return A

    def critical_load(self, secant_steps: int = 2) -> CriticalLoad:
        """Linearised buckling about the straight state: with K(d) the tangent at shortening d and
        K0 = K(0), K(d) ~ K0 + (d/d_r)(K(d_r) - K0) vanishes first at d = -d_r/theta, theta the most
        negative eigenvalue of (K(d_r) - K0) phi = theta K0 phi (SLEPc, generalised Hermitian);
        repeated with d_r = d so that the linearisation is taken at the critical state.
        Starts from the Euler load of the specimen (4 pi^2 E I/L^2)."""
        from slepc4py import SLEPc

        spec = self.specimen
        area = spec.width * spec.thickness
        euler = 4.0 * math.pi ** 2 * self.solid.youngs_modulus * spec.second_moment / spec.length ** 2
        d_r = euler * spec.length / (self.solid.youngs_modulus * area)
        self.problem.restore(np.zeros(self.u.x.array.size))
        self.set_shortening(0.0)
        K0 = self.tangent()
        change = float("nan")
        for _ in range(secant_steps):
            self.straight_state(d_r)
            dK = self.tangent()
            dK.axpy(-1.0, K0)
            eps = SLEPc.EPS().create(self.tmesh.mesh.comm)
            eps.setOperators(dK, K0)
            eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
            eps.setDimensions(1, PETSc.DECIDE)
            eps.setWhichEigenpairs(SLEPc.EPS.Which.SMALLEST_REAL)
            eps.setTolerances(1e-10, 500)
            ksp = eps.getST().getKSP()
            ksp.setType("preonly")
            ksp.getPC().setType("lu")
            ksp.getPC().setFactorSolverType("mumps")
            eps.solve()
            if eps.getConverged() < 1:
                raise ConvergenceError("buckling eigenproblem", "SLEPc found no eigenpair")
            vr = dK.createVecRight()
            theta = eps.getEigenpair(0, vr).real
            eps.destroy()
            dK.destroy()
            if not theta < 0:
                raise ConvergenceError("buckling eigenproblem", f"no negative eigenvalue ({theta:g})")
            d_new = -d_r / theta
            change = abs(d_new - d_r) / d_new
            d_r = d_new
        K0.destroy()
        self.straight_state(d_r)
        force = self.force()
        mode = dolfinx.fem.Function(self.V, name="buckling_mode")
        mode.x.array[:] = vr.array
        scale = np.max(np.abs(mode.x.array.reshape(-1, 3)[:, 2]))
        mode.x.array[:] /= scale
        self.problem.restore(np.zeros(self.u.x.array.size))
        self.set_shortening(0.0)
        return CriticalLoad(force, d_r, mode, change)

    def add_imperfection(self, mode: dolfinx.fem.Function, amplitude: float) -> None:
        """Move the mesh (the stress-free reference) by ``amplitude`` [mm] x the mode (max |u_z| = 1)."""
        from scipy.spatial import cKDTree

        X = self.V.tabulate_dof_coordinates()
        geom = self.tmesh.mesh.geometry.x
        dist, idx = cKDTree(X).query(geom)
        if np.max(dist) > 1e-9:
            raise RuntimeError("geometry nodes are not displacement nodes")
        geom[:, :] += amplitude * mode.x.array.reshape(-1, 3)[idx]

    def compression_schedule(self, c_cr: float, c_max: float, path: RibbonFEPath) -> np.ndarray:
        """Compressions: geometric from 0.2 to 50 c_cr, then steps of ``path.step`` to c_max."""
        onset = np.geomspace(0.2 * c_cr, min(50.0 * c_cr, c_max), path.onset_steps)
        start = onset[-1]
        n = max(1, int(math.ceil((c_max - start) / path.step - 1e-9)))
        return np.concatenate([onset, np.linspace(start, c_max, n + 1)[1:]])

    def follow(self, compressions, control: PathControl = PathControl(first_step=1.0, max_step=1.0,
                                                                         min_step=1e-3),
               on_step: Callable[[float, int], None] | None = None) -> PathFollower:
        """Displacement-controlled path through the given compressions (end shortening / L) with
        adaptive sub-steps (load parameter t = compression); ``on_step(compression, iterations)``
        after each given compression is reached. Returns the follower (iteration counts)."""
        follower = PathFollower(self.problem, lambda t: self.set_shortening(t * self.length), control)
        for c in compressions:
            before = follower.iterations
            follower.step = max(follower.step, float(c) - follower.t)
            follower.follow(float(c), where=f"ribbon compression {100 * float(c):.3g} %")
            if on_step is not None:
                on_step(float(c), follower.iterations - before)
        return follower


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


def curvature_map_fe(lambdas, geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
                     mesh: BeamFEMesh = BeamFEMesh(), materials: FEMaterials = FEMaterials(),
                     actuation: BeamActuation = BeamActuation(),
                     contact: PenaltyContact = PenaltyContact(), control: PathControl | None = None,
                     on_point: Callable[[float, float, float, int], None] | None = None
                     ) -> tuple[np.ndarray, dict, "BeamFE"]:
    """kappa[i, j] [1/mm] at (lambdas[i], lambdas[j]) = (lambda_T, lambda_B), one model swept
    through the grid (:func:`sweep_order`: the first point is ramped from the as-built state, each
    next one from its neighbour). Returns (kappa, stats, model): Newton iterations, folds crossed,
    the largest contact force and smallest strip-ribbon gap over the grid, the wall time; the model
    in its last state."""
    lam = [float(v) for v in lambdas]
    model = BeamFE(geometry, mesh, materials, actuation, contact, control)
    kappa = np.full((len(lam), len(lam)), np.nan)
    stats = {"iterations": 0, "snaps": 0, "max_contact_force [N]": 0.0, "min_gap [mm]": math.inf,
             "points": 0, "dofs": model.ndofs}
    started = time.perf_counter()
    for lt, lb in sweep_order(lam):
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
    stats["wall_time [s]"] = time.perf_counter() - started
    return kappa, stats, model


# --------------------------------------------------------------------------- heat-driven beam
@dataclass(frozen=True)
class HeatedBeamRun:
    """A coil current through one group of strips (the heat model has one power density)."""

    current: float = param(0.0, "A", "0 (default) prescribes lambda_T, lambda_B instead; seed 001 used "
                           "0.2 A for rapid contraction, 0.1 A for slow (Fig. 2A-B)", minimum=0.0)
    heated: str = param("bottom", "-", "strips carrying the current: 'bottom', 'top' or 'both' (the "
                        "others stay at room temperature, as built)")
    duration: float = param(12.0, "s", "chosen: part of the 0.2 A transient (T_NI reached in about 10 s, "
                            "seed 001)", positive=True)
    dt: float = param(1.0, "s", "chosen: time step (backward Euler)", positive=True)

    def checked(self) -> "HeatedBeamRun":
        from lcefem.models.parameters import check
        check(self, "heat_run")
        if self.heated not in ("bottom", "top", "both"):
            raise InputError(f"heat_run.heated = {self.heated!r}: allowed 'bottom', 'top' or 'both'")
        if self.dt > self.duration:
            raise InputError(f"heat_run.dt = {self.dt} s: must be <= heat_run.duration = {self.duration} s")
        return self


def beam_fe_heated(run: HeatedBeamRun = HeatedBeamRun(),
                   geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
                   mesh: BeamFEMesh = BeamFEMesh(), materials: FEMaterials = FEMaterials(),
                   contact: PenaltyContact = PenaltyContact(), control: PathControl | None = None,
                   transition=None, thermal=None, exchange=None, coil: GridSegmentCoil = GridSegmentCoil(),
                   on_step: Callable[[dict], None] | None = None):
    """The FE beam driven by a coil current (seed 001's actuation) through
    :class:`lcefem.solvers.thermomechanics.ThermoMechanicalModel`: Joule power I^2 R per strip
    (R of one 30 mm grid segment's ``coil``, seed 001) spread uniformly over each
    heated strip's volume (the coil is not resolved), conduction into the ribbon through the bonded
    pads only, convection and radiation on every exterior face; the LCE of the strips follows the
    nematic transition, the bond pads are passive. Each time step's mechanics is brought from the
    old to the new temperature with :class:`PathFollower` (secant predictor in time).

    Returns (model, history rows, stations).
    """
    from lcefem.models.heat import SurfaceExchange, ThermalProperties
    from lcefem.models.lce import NematicTransition
    from lcefem.solvers.heat import HeatSetup
    from lcefem.solvers.thermomechanics import LCERegion, PassiveRegion, ThermoMechanicalModel

    run = run.checked()
    if not run.current > 0:
        raise InputError(f"heat_run.current = {run.current} A: must be > 0 A for a heated run")
    transition = transition or NematicTransition()
    tm = build_beam_mesh(geometry, transition.lambda_N, mesh, MPI.COMM_WORLD)
    n = ufl.as_vector([1.0, 0.0, 0.0])
    exposed = [f for f in ("ribbon_top", "ribbon_bottom", "top_strip_underside", "bottom_strip_topside",
                           "surface") if f in tm.facets]
    heated = {"bottom": ["bottom_strips"], "top": ["top_strips"],
              "both": ["bottom_strips", "top_strips"]}[run.heated]
    setup = HeatSetup(thermal or ThermalProperties(), exchange or SurfaceExchange(), heated_cells=heated,
                      exposed_facets=exposed)
    passive_lce = NematicTransition(lambda_N=1.0)  # no order, no spontaneous strain: bond pads
    lce = [LCERegion(["bottom_strips"], n, transition, materials.lce),
           LCERegion(["top_strips"], n, transition, materials.lce),
           LCERegion(["bottom_pads", "top_pads"], n, passive_lce, materials.lce)]
    model = ThermoMechanicalModel(tm, setup, lce, [PassiveRegion(["kapton"], materials.kapton)],
                                  dirichlet=lambda V: beam_supports(tm, V),
                                  petsc_options=dict(BEAM_NEWTON), prefix=_unique_prefix("heatbeam"))
    contacts = make_contacts(tm, model.u, contact)
    damping = NodalDamping(model.u)
    attach(model.mechanics.snes, [*contacts, damping], model.bcs, homogeneous=True)
    strip_volume = geometry.segment_length * tm.info["strip_width"] * tm.info["strip_thickness"]
    power = coil.power(run.current)  # mW per strip
    model.heat.power_density.value = power / strip_volume
    stations = BeamStations(tm, model.u.function_space)
    dx = volume_measure(tm)
    mean_T = {name: (dolfinx.fem.form(model.heat.T * dx(tm.cell_tag(name))),
                     assemble_global(dolfinx.fem.form(1.0 * dx(tm.cell_tag(name))), tm.mesh.comm))
              for name in ("bottom_strips", "top_strips", "kapton")}
    current = {"T0": model.T_mech.x.array.copy(), "T1": model.T_mech.x.array.copy(), "t0": 0.0, "dt": 1.0}

    def set_load(t: float) -> None:
        s = (t - current["t0"]) / current["dt"]
        model.T_mech.x.array[:] = current["T0"] + s * (current["T1"] - current["T0"])

    follower = PathFollower(model.mechanics, set_load, control or PathControl(first_step=run.dt,
                                                                              max_step=run.dt),
                            damping)
    steps = max(1, int(math.ceil(run.duration / run.dt - 1e-9)))
    dt = run.duration / steps
    rows = []

    def observe(t: float, its: int) -> dict:
        row = {"time [s]": t, "curvature [1/mm]": stations.curvature(model.u),
               "newton iterations [-]": its,
               "contact force [N]": tm.info["symmetry_factor"] * sum(c.normal_force() for c in contacts)}
        for name, (form, vol) in mean_T.items():
            row[f"T_mean {name} [C]"] = assemble_global(form, tm.mesh.comm) / vol
        return row

    rows.append(observe(0.0, 0))
    if on_step is not None:
        on_step(rows[0])
    for k in range(1, steps + 1):
        current.update(T0=model.T_mech.x.array.copy(), t0=(k - 1) * dt, dt=dt)
        model.heat.step(dt)
        current["T1"] = model.heat.T.x.array.copy()
        before = follower.iterations
        follower.step = min(follower.step, dt)
        follower.follow(k * dt, where=f"heated beam, t = {k * dt:.4g} s")
        rows.append(observe(k * dt, follower.iterations - before))
        if on_step is not None:
            on_step(rows[-1])
    return model, rows, stations
