"""The twisted LCE ribbon (seed 000) as a static 3D finite-strain body under a prescribed
temperature field: :class:`TwistedRibbonFE` (built once, :meth:`~TwistedRibbonFE.advance` to the
load, rod-like observables), and :func:`solve_twisted_ribbon`, the one-call version the FE vs DER
case uses. (The rolling ribbon on a hot plate is the Discrete Elastic Rod problem
:mod:`lcefem.solvers.der.ribbon`.)

Mesh: :func:`lcefem.meshes.twisted_ribbon.build_twisted_ribbon` (Q2 hexahedra of the helicoid; a
straight strip at zero twist). Energy: W(F F_s^-1) of the FE strip (``LCEElasticity``, director
along the twisted fibres, as ``solvers.thermomechanics.lce_energy_density``), with the spontaneous
stretch a = lambda_s(T)/lambda_N ramped from 1 to its value in the target temperature field: the
load parameter s in a = 1 + s (a(T) - 1), by the shared step controller
(:mod:`lcefem.solvers.continuation`).

Supports: the end x = 0 is held without reactions to free thermal strain: u_x = 0 on the end face
(it stays plane and normal to the axis, which the free shapes compared here allow: sections of a
bent or uniformly contracted strip remain plane), the section centre is fixed and the end's width
axis cannot turn about x.

Observables: the rod-like measures of :mod:`lcefem.solvers.analysis.rod_shape` (stretch, material
curvatures, twist rate, circle curvature) on stations in [L/6, 5L/6], away from the held end and
from the free one, placed on level-0 element faces (where the trilinear mesh and the analytic
helicoid coincide, and which every finer level keeps), Richardson-extrapolated from s and 2 s.

Units: mm, rad/mm, C, MPa, N.
"""

from __future__ import annotations

import itertools
import pathlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI
from petsc4py import PETSc

import numpy as np
import ufl

import dolfinx

from lcefem.meshes.twisted_ribbon import TwistedRibbonMesh, build_twisted_ribbon, helicoid
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import LCEElasticity, lce_strain_energy
from lcefem.models.lce import (
    NematicTransition,
    contraction_ratio,
    isochoric_uniaxial,
    twisted_director,
)
from lcefem.solvers import continuation
from lcefem.solvers.analysis.rod_shape import RodLikeShape, measure_extrapolated
from lcefem.solvers.exports import write_snapshot
from lcefem.solvers.mechanics import (
    HyperelasticProblem,
    deformation_gradient,
    displacement_space,
    volume_measure,
)
from lcefem.solvers.probes import PointProbe
from lcefem.solvers.problems.protocol import (
    LOAD,
    StepRecord,
    check_quasi_static_step,
    copy_arrays,
    put_arrays,
)

__all__ = [
    "TWISTED_RIBBON_NEWTON",
    "TwistedRibbonFE",
    "TwistedRibbonSolution",
    "solve_twisted_ribbon",
]

#: Newton settings of the ribbon: full Newton steps. On this thin, nearly incompressible body
#: (K/mu ~ 110) the full steps alternate: one raises the residual 10-1000 times (the linearised
#: rotation and volume change leave O(K theta^2) stresses), the next removes it, and the solve
#: converges in 4-15 iterations; the line searches tried (cp, bt on the residual or on the energy,
#: newtontr) cut those steps and creep (20-40 iterations per step even at 1/500 of the load). A
#: failed step (an inverted element) is cut by the continuation instead.
TWISTED_RIBBON_NEWTON = {"snes_linesearch_type": "basic", "snes_max_it": 30}

_prefix = itertools.count()


@dataclass
class TwistedRibbonSolution:
    """As-built and deformed shapes, the displacement [mm] and the cost of the solve."""

    as_built: RodLikeShape
    deformed: RodLikeShape
    displacement: object  #: dolfinx Function
    steps: continuation.StepReport
    dofs: int
    element_size: float  #: along the ribbon [mm]


def _stations(length: float, element: float, count: int | None) -> np.ndarray:
    """Stations in [L/6, 5L/6] on element faces (x = multiples of ``element``): ``count`` of them,
    or one per face when None (an odd number: the last face is dropped if needed)."""
    first, last = np.ceil(length / 6 / element - 1e-9), np.floor(5 * length / 6 / element + 1e-9)
    if count is None:
        last -= (last - first) % 2
        return element * np.arange(first, last + 1)
    xs = element * np.unique(np.round(np.linspace(first, last, count)))
    if len(xs) != count:
        raise InputError(
            f"stations = {count}: more than the {int(last - first) + 1} element faces "
            "in [L/6, 5L/6]"
        )
    return xs


class TwistedRibbonFE:
    """Static twisted (or straight, ``twist_rate`` 0) LCE ribbon, lengths [mm], twist rate [rad/mm],
    under ``temperature(y, z) -> UFL`` [C] given in the straight strip's section coordinates (y
    across the width, z through the thickness, both centred; the section turns with the twist).

    Args:
        resolution: mesh divisions and level (use an even number across the width).
        stations: measuring stations in [L/6, 5L/6], an odd number (default: one per level-0 element
            face).
        petsc_options: overrides of :data:`TWISTED_RIBBON_NEWTON` (itself over the mechanics
            defaults).
        prefix: PETSc options prefix (default: a fresh one per instance).
    """

    def __init__(
        self,
        length: float,
        width: float,
        thickness: float,
        twist_rate: float,
        temperature: Callable,
        *,
        transition: NematicTransition = NematicTransition(),
        elasticity: LCEElasticity = LCEElasticity(),
        resolution: TwistedRibbonMesh = TwistedRibbonMesh(),
        stations: int | None = None,
        comm: MPI.Comm | None = None,
        prefix: str | None = None,
        petsc_options: dict | None = None,
    ):
        self.length, self.width, self.twist_rate = length, width, twist_rate
        self.tmesh = tm = build_twisted_ribbon(
            length, width, thickness, twist_rate, resolution, comm
        )
        mesh = tm.mesh
        self.V = V = displacement_space(mesh, 2)
        self.u = u = dolfinx.fem.Function(V, name="displacement")
        X = ufl.SpatialCoordinate(mesh)
        theta = twist_rate * X[0]
        y = X[1] * ufl.cos(theta) + X[2] * ufl.sin(theta)  # back to the straight strip's section
        z = -X[1] * ufl.sin(theta) + X[2] * ufl.cos(theta)
        # The load is ramped in the spontaneous stretch, a = 1 + s (a(T) - 1), not in T: a(T) is a
        # sigmoid, and equal steps in T would put most of the actuation into the last few.
        self.load = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
        a = 1.0 + self.load * (contraction_ratio(temperature(y, z), transition) - 1.0)
        F_s_inv = isochoric_uniaxial(
            1.0 / a, twisted_director(X, twist_rate)
        )  # = F_s(T)^-1 at s = 1
        energy = lce_strain_energy(deformation_gradient(u) * F_s_inv, elasticity)
        self.bcs = self._supports(V, tm, width, 1e-6 * thickness, mesh.comm)
        options = dict(TWISTED_RIBBON_NEWTON)
        options.update(petsc_options or {})
        self.problem = HyperelasticProblem(
            u,
            energy * volume_measure(tm),
            self.bcs,
            prefix=prefix or f"lcefem_twisted_ribbon{next(_prefix)}_",
            petsc_options=options,
            user_options=tuple(petsc_options or ()),
        )
        self.ndofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        self.element_size = tm.info["element_size"]
        xs = _stations(
            length, length / resolution.along, stations
        )  # level-0 faces are faces at every level
        straight = {
            name: np.column_stack([xs, np.full_like(xs, yv), np.zeros_like(xs)])
            for name, yv in (("centre", 0.0), ("plus", 0.5 * width), ("minus", -0.5 * width))
        }
        self._reference = {k: helicoid(v, twist_rate) for k, v in straight.items()}
        self._span = xs[-1] - xs[0]
        self._probe = PointProbe(
            mesh, np.vstack([self._reference[k] for k in ("centre", "plus", "minus")])
        )
        self.target_load = 1.0  # [-] the load fraction advance() goes to

    @staticmethod
    def _supports(V, tm, width: float, tol: float, comm) -> list:
        """u_x = 0 on the end face x = 0; u_y = u_z = 0 at its centre; u_z = 0 at its edge y =
        w/2."""
        end = tm.facet_tags.find(tm.facet_tag("x0"))
        bcs = [
            dolfinx.fem.dirichletbc(
                PETSc.ScalarType(0), dolfinx.fem.locate_dofs_topological(V.sub(0), 2, end), V.sub(0)
            )
        ]
        for comp, point in (
            (1, (0.0, 0.0, 0.0)),
            (2, (0.0, 0.0, 0.0)),
            (2, (0.0, 0.5 * width, 0.0)),
        ):
            Vc, _ = V.sub(comp).collapse()
            dofs = dolfinx.fem.locate_dofs_geometrical(
                (V.sub(comp), Vc),
                lambda x, p=point: np.isclose(x[0], p[0], atol=tol)
                & np.isclose(x[1], p[1], atol=tol)
                & np.isclose(x[2], p[2], atol=tol),
            )[0]
            if comm.allreduce(len(dofs), op=MPI.SUM) == 0:
                raise ValueError(
                    f"no node at {point}: use an even number of elements across the width"
                )
            bcs.append(dolfinx.fem.dirichletbc(PETSc.ScalarType(0), dofs, V.sub(comp)))
        return bcs

    def set_load(self, value: float) -> None:
        """Fraction s [-] of the spontaneous-stretch change a(T) - 1 applied."""
        self.load.value = value

    def advance(
        self, dt: float = 1.0, *, first: float = 0.25, predictor: str = "none"
    ) -> StepRecord:
        """Ramp the load the fraction ``dt`` (0 < dt <= 1) of the way from the current state to its
        target (:meth:`set_drives`, as built 1: the full temperature field) by the shared step
        controller (:class:`continuation.PathFollower`, trying ``first`` as the first increment and
        halving failed ones down to 1/256); ``predictor``: "none" (each increment starts from the
        last converged state) or "tangent" (Euler predictor). The record's ``detail``: the
        controller's :class:`continuation.StepReport`."""
        start = float(self.load.value)
        target = start + check_quasi_static_step(dt) * (self.target_load - start)
        follower = continuation.PathFollower(
            self.problem,
            self.set_load,
            continuation.PathControl(
                first_step=min(1.0, first), max_step=1.0, min_step=1.0 / 256.0, predictor=predictor
            ),
            t0=float(self.load.value),
        )
        follower.follow(target, "twisted ribbon heating")
        report = follower.report()
        return StepRecord(
            float(dt), self.observables(), report.iterations, report.cuts, clock=LOAD, detail=report
        )

    def shape(self, deformed: bool = True) -> RodLikeShape:
        """Rod-like measures of the deformed (or as-built) ribbon."""
        pts = dict(self._reference)
        if deformed:
            disp = self._probe(self.u)
            n = len(pts["centre"])
            pts = {
                k: pts[k] + disp[i * n : (i + 1) * n]
                for i, k in enumerate(("centre", "plus", "minus"))
            }
        m = measure_extrapolated(pts["centre"], pts["plus"], pts["minus"])
        return RodLikeShape(
            m["arc_length"] / self._span,
            m["curvature"],
            m["material_curvature"],
            m["twist_rate"],
            m["circle_curvature"],
            pts["centre"],
        )

    def observables(self) -> dict[str, float]:
        """Named observables of the deformed ribbon, keys "name [unit]"."""
        s = self.shape()
        return {
            "load fraction [-]": float(self.load.value),
            "stretch [-]": s.stretch,
            "kappa_1 [1/mm]": float(s.material_curvature[0]),
            "kappa_2 [1/mm]": float(s.material_curvature[1]),
            "twist rate [rad/mm]": s.twist_rate,
            "circle curvature [1/mm]": s.circle_curvature,
        }

    def write_fields(self, folder, t: float = 0.0) -> list[pathlib.Path]:
        """displacement.bp (Q2, VTX, ParaView) of the current state in ``folder``."""
        return [write_snapshot(folder, "displacement.bp", [self.u], t)]

    # -- the Problem protocol (lcefem.solvers.problems.protocol) --------------------------------
    drive = "load fraction [-]"  # of the spontaneous-stretch change a(T) - 1 (set_load)

    def drive_tags(self) -> tuple[str, ...]:
        return ("body",)  # the mesh's one cell tag: the whole ribbon is heated

    def set_drives(self, drives: Mapping[str, float]) -> None:
        for tag, value in drives.items():
            if tag not in self.drive_tags():
                raise InputError(
                    f"drive {tag!r}: not a cell tag of the twisted ribbon (allowed body)"
                )
            if not isinstance(value, (int, float)) or not 0.0 <= value <= 1.0:
                raise InputError(f"load fraction[{tag}] = {value}: must be in [0, 1]")
            self.target_load = float(value)

    def fields(self) -> dict:
        return {"displacement [mm]": self.u}

    def save_state(self) -> dict:
        return {"u": copy_arrays([self.u]), "load": float(self.load.value)}

    def restore_state(self, state: dict) -> None:
        put_arrays([self.u], state["u"])
        self.set_load(state["load"])


def solve_twisted_ribbon(
    length: float,
    width: float,
    thickness: float,
    twist_rate: float,
    temperature: Callable,
    *,
    first: float = 0.25,
    predictor: str = "none",
    **options,
) -> TwistedRibbonSolution:
    """Build a :class:`TwistedRibbonFE` (``options``: its keyword arguments), ramp it to the full
    load and measure it: the as-built and deformed shapes."""
    ribbon = TwistedRibbonFE(length, width, thickness, twist_rate, temperature, **options)
    steps = ribbon.advance(1.0, first=first, predictor=predictor).detail
    return TwistedRibbonSolution(
        ribbon.shape(deformed=False),
        ribbon.shape(),
        ribbon.u,
        steps,
        ribbon.ndofs,
        ribbon.element_size,
    )
