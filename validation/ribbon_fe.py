"""Static 3D FE of an LCE ribbon (straight or twisted) under a prescribed temperature field, and the
rod-like quantities measured on it the way Discrete Elastic Rods measure them: centreline
curvatures in the material frame, twist density and stretch.

The end x = 0 is held without reactions to free thermal strain: u_x = 0 on the end face (it stays
plane and normal to the axis, which the free shapes compared here allow: sections of a bent or
uniformly contracted strip remain plane), the section centre is fixed and the end's width axis
cannot turn about x. The ribbon is measured between L/6 and 5L/6, away from that end and from the
free one. The energy is that of the FE strip, W(F F_s^-1) (``LCEElasticity``, director along the
twisted fibres, as ``solvers.thermomechanics.lce_energy_density``), with the spontaneous stretch
a = lambda_s(T)/lambda_N ramped from 1 to its value in the target temperature field by continuation.

Measured on stations x_k along the reference centreline (snapped to element faces, where the
trilinear mesh and the analytic helicoid coincide), from the deformed centre and edge points, with
the discrete formulas of Discrete Elastic Rods (Bergou et al. 2008; :mod:`lcefem.models.rod`):

- edges e_k between stations, tangents t_k; material frame m1 = width direction (edge points'
  difference at the edge midpoint, made normal to t_k), m2 = t_k x m1 (thickness direction, towards
  the face z = +t/2 of the straight strip);
- stretch: deformed centreline length / reference length between the first and last station;
- material curvatures (kappa_1 towards m1, kappa_2 towards m2) [1/mm]: (kappa b)_k projected on the
  mean frame of the two edges, over the Voronoi length, averaged over the interior stations;
- twist rate: sum of the signed angles between m1 of an edge parallel-transported to the next edge
  and that edge's m1 (DER's discrete twist), over the summed Voronoi length.

These are second-order accurate in the station spacing s (on a helix of curvature kappa and torsion
tau the curvature's relative error is about -tau^2 s^2/4: -0.6 % for the twisted ribbons at s = 0.5 mm),
so the shapes reported are Richardson-extrapolated from the spacings s and 2 s
(:func:`measure_extrapolated`; tests/validation/test_ribbon_fe.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx

from lcefem.meshes.twisted_ribbon import RibbonMesh, build_twisted_ribbon, helicoid
from lcefem.models.errors import InputError
from lcefem.models.hyperelastic import LCEElasticity, lce_strain_energy
from lcefem.models.lce import NematicTransition, contraction_ratio, isochoric_uniaxial, twisted_director
from lcefem.models.rod import cross, material_curvatures, parallel_transport, signed_angle
from lcefem.solvers import continuation
from lcefem.solvers.mechanics import (HyperelasticProblem, deformation_gradient, displacement_space,
                                      volume_measure)
from lcefem.solvers.probes import PointProbe

__all__ = ["RIBBON_NEWTON", "RibbonShape", "RibbonSolution", "circle_curvature", "measure_extrapolated",
           "measure_shape", "parallel_transport", "solve_ribbon"]

#: Newton settings of the ribbon: full Newton steps. On this thin, nearly incompressible body
#: (K/mu ~ 110) the full steps alternate: one raises the residual 10-1000 times (the linearised
#: rotation and volume change leave O(K theta^2) stresses), the next removes it, and the solve converges
#: in 4-15 iterations; the line searches tried (cp, bt on the residual or on the energy, newtontr)
#: cut those steps and creep (20-40 iterations per step even at 1/500 of the load). A failed step
#: (an inverted element) is cut by the continuation instead.
RIBBON_NEWTON = {"snes_linesearch_type": "basic", "snes_max_it": 30}


@dataclass
class RibbonShape:
    """Rod-like description of a ribbon, measured as Discrete Elastic Rods measure a rod."""

    stretch: float  #: centreline length / reference length [-]
    curvature: float  #: mean |kappa| of the centreline [1/mm]
    material_curvature: np.ndarray  #: mean (kappa_1, kappa_2): towards width m1, thickness m2 [1/mm]
    twist_rate: float  #: [rad/mm]
    circle_curvature: float  #: of the least-squares circle through the stations (planar shapes) [1/mm]
    centreline: np.ndarray  #: (n, 3) stations [mm]


@dataclass
class RibbonSolution:
    """As-built and deformed shapes, the displacement [mm] and the cost of the solve."""

    as_built: RibbonShape
    deformed: RibbonShape
    displacement: object  #: dolfinx Function
    steps: continuation.StepReport
    dofs: int
    element_size: float  #: along the ribbon [mm]


def circle_curvature(points: np.ndarray) -> float:
    """Curvature [1/mm] of the least-squares circle through 3D points (0 for collinear points)."""
    centred = points - points.mean(axis=0)
    _, s, vt = np.linalg.svd(centred)
    if s[1] < 1e-9 * max(s[0], 1e-300):
        return 0.0
    xy = centred @ vt[:2].T  # coordinates in the best-fit plane
    A = np.column_stack([2 * xy, np.ones(len(xy))])
    c, *_ = np.linalg.lstsq(A, (xy ** 2).sum(axis=1), rcond=None)
    radius = np.sqrt(c[2] + c[0] ** 2 + c[1] ** 2)
    return 1.0 / radius


def measure_shape(centre: np.ndarray, edge_plus: np.ndarray, edge_minus: np.ndarray) -> dict:
    """DER measures of a ribbon from its centre and edge points (n, 3) [mm] at n >= 3 stations
    (``edge_plus`` at +w/2 along the width, i.e. m1 points from ``edge_minus`` to ``edge_plus``).

    Returns arc_length [mm], material_curvature (kappa_1, kappa_2) [1/mm] and curvature (mean
    |kappa|) [1/mm] averaged over the interior stations, twist_rate [rad/mm], circle_curvature [1/mm].
    """
    centre = np.asarray(centre, float)
    if len(centre) < 3:
        raise InputError(f"{len(centre)} stations: need at least 3")
    e = np.diff(centre, axis=0)
    length = np.linalg.norm(e, axis=1)
    t = e / length[:, None]
    widths = np.asarray(edge_plus, float) - np.asarray(edge_minus, float)
    mids = 0.5 * (widths[1:] + widths[:-1])
    m1 = mids - np.einsum("ki,ki->k", mids, t)[:, None] * t
    m1 /= np.linalg.norm(m1, axis=1)[:, None]
    m2 = cross(t, m1)
    voronoi = 0.5 * (length[1:] + length[:-1])
    kappa = material_curvatures(e[:-1], e[1:], m1[:-1], m2[:-1], m1[1:], m2[1:]) / voronoi[:, None]
    twist = signed_angle(parallel_transport(m1[:-1], t[:-1], t[1:]), m1[1:], t[1:])
    return {"arc_length": float(length.sum()), "material_curvature": kappa.mean(axis=0),
            "curvature": float(np.linalg.norm(kappa, axis=1).mean()),
            "twist_rate": float(twist.sum() / voronoi.sum()), "circle_curvature": circle_curvature(centre)}


def measure_extrapolated(centre: np.ndarray, edge_plus: np.ndarray, edge_minus: np.ndarray) -> dict:
    """:func:`measure_shape` at the stations' spacing s and at 2 s (every other station; give an odd
    number of equally spaced stations), Richardson-extrapolated to s -> 0: (4 m(s) - m(2 s))/3 for the
    arc length, the curvatures and the twist rate, whose error is O(s^2) (O(s^4) after)."""
    if len(centre) % 2 == 0 or len(centre) < 5:
        raise InputError(f"{len(centre)} stations: need an odd number >= 5")
    fine = measure_shape(centre, edge_plus, edge_minus)
    coarse = measure_shape(centre[::2], edge_plus[::2], edge_minus[::2])
    out = dict(fine)
    for key in ("arc_length", "material_curvature", "curvature", "twist_rate"):
        out[key] = (4.0 * np.asarray(fine[key]) - np.asarray(coarse[key])) / 3.0
        out[key] = float(out[key]) if np.ndim(out[key]) == 0 else out[key]
    return out


def _stations(length: float, element: float, count: int | None) -> np.ndarray:
    """Stations in [L/6, 5L/6] on element faces (x = multiples of ``element``): ``count`` of them, or
    one per face when None (an odd number: the last face is dropped if needed)."""
    first, last = np.ceil(length / 6 / element - 1e-9), np.floor(5 * length / 6 / element + 1e-9)
    if count is None:
        last -= (last - first) % 2
        return element * np.arange(first, last + 1)
    xs = element * np.unique(np.round(np.linspace(first, last, count)))
    if len(xs) != count:
        raise InputError(f"stations = {count}: more than the {int(last - first) + 1} element faces "
                         "in [L/6, 5L/6]")
    return xs


def solve_ribbon(length: float, width: float, thickness: float, twist_rate: float,
                 temperature: Callable, *, transition: NematicTransition = NematicTransition(),
                 elasticity: LCEElasticity = LCEElasticity(), resolution: RibbonMesh = RibbonMesh(),
                 stations: int | None = None, comm: MPI.Comm = MPI.COMM_WORLD, prefix: str = "ribbon_fe_",
                 petsc_options: dict | None = None, first: float = 0.25,
                 predictor: str = "none") -> RibbonSolution:
    """Static equilibrium of the ribbon (lengths [mm], twist rate [rad/mm]) under
    ``temperature(y, z) -> UFL`` [C] given in the straight strip's section coordinates (y across the
    width, z through the thickness, both centred; the section turns with the twist).

    Args:
        resolution: mesh divisions and level (use an even number across the width).
        stations: measuring stations in [L/6, 5L/6], an odd number (default: one per level-0
            element face; they are placed on level-0 element faces, which every finer level keeps).
        petsc_options: overrides of :data:`RIBBON_NEWTON` (itself over the mechanics defaults).
        first: first load increment of the continuation (fraction of a(T) - 1).
        predictor: "none" (each increment starts from the last converged state) or "tangent"
            (:class:`lcefem.solvers.continuation.PathFollower`'s Euler predictor).
    """
    tm = build_twisted_ribbon(length, width, thickness, twist_rate, resolution, comm)
    mesh = tm.mesh
    V = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(V, name="displacement")
    X = ufl.SpatialCoordinate(mesh)
    theta = twist_rate * X[0]
    y = X[1] * ufl.cos(theta) + X[2] * ufl.sin(theta)  # back to the straight strip's section
    z = -X[1] * ufl.sin(theta) + X[2] * ufl.cos(theta)
    # The load is ramped in the spontaneous stretch, a = 1 + s (a(T) - 1), not in T: a(T) is a
    # sigmoid, and equal steps in T would put most of the actuation into the last few.
    s = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
    a = 1.0 + s * (contraction_ratio(temperature(y, z), transition) - 1.0)
    F_s_inv = isochoric_uniaxial(1.0 / a, twisted_director(X, twist_rate))  # = F_s(T)^-1 at s = 1
    energy = lce_strain_energy(deformation_gradient(u) * F_s_inv, elasticity)
    end = tm.facet_tags.find(tm.facet_tag("x0"))
    bcs = [dolfinx.fem.dirichletbc(PETSc.ScalarType(0), dolfinx.fem.locate_dofs_topological(V.sub(0), 2, end),
                                   V.sub(0))]
    tol = 1e-6 * thickness
    for comp, point in ((1, (0.0, 0.0, 0.0)), (2, (0.0, 0.0, 0.0)), (2, (0.0, 0.5 * width, 0.0))):
        Vc, _ = V.sub(comp).collapse()
        dofs = dolfinx.fem.locate_dofs_geometrical(
            (V.sub(comp), Vc), lambda x, p=point: np.isclose(x[0], p[0], atol=tol)
            & np.isclose(x[1], p[1], atol=tol) & np.isclose(x[2], p[2], atol=tol))[0]
        if comm.allreduce(len(dofs), op=MPI.SUM) == 0:
            raise ValueError(f"no node at {point}: use an even number of elements across the width")
        bcs.append(dolfinx.fem.dirichletbc(PETSc.ScalarType(0), dofs, V.sub(comp)))
    options = dict(RIBBON_NEWTON)
    options.update(petsc_options or {})
    problem = HyperelasticProblem(u, energy * volume_measure(tm), bcs,
                                  prefix=prefix, petsc_options=options)

    def set_load(value: float) -> None:
        s.value = value

    if predictor == "none":
        steps = continuation.advance(set_load, problem.solve, problem.save, problem.restore,
                                     where="ribbon heating", first=first)
    else:
        follower = continuation.PathFollower(problem, set_load, continuation.PathControl(
            first_step=min(1.0, first), max_step=1.0, min_step=1.0 / 256.0, predictor=predictor))
        follower.follow(1.0, "ribbon heating")
        steps = follower.report()
    h0 = length / resolution.along  # level-0 element faces are faces at every level
    xs = _stations(length, h0, stations)
    straight = {name: np.column_stack([xs, np.full_like(xs, yv), np.zeros_like(xs)])
                for name, yv in (("centre", 0.0), ("plus", 0.5 * width), ("minus", -0.5 * width))}
    reference = {k: helicoid(v, twist_rate) for k, v in straight.items()}
    probe = PointProbe(mesh, np.vstack([reference["centre"], reference["plus"], reference["minus"]]))
    disp = probe(u)
    n = len(xs)
    deformed = {k: reference[k] + disp[i * n:(i + 1) * n] for i, k in enumerate(("centre", "plus", "minus"))}
    shapes = []
    for pts in (reference, deformed):
        m = measure_extrapolated(pts["centre"], pts["plus"], pts["minus"])
        shapes.append(RibbonShape(m["arc_length"] / (xs[-1] - xs[0]), m["curvature"], m["material_curvature"],
                                  m["twist_rate"], m["circle_curvature"], pts["centre"]))
    return RibbonSolution(shapes[0], shapes[1], u, steps, V.dofmap.index_map.size_global * V.dofmap.index_map_bs,
                          tm.info["element_size"])
