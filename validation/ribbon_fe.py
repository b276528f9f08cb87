"""Static 3D FE of an LCE ribbon (straight or twisted) under a prescribed temperature field, and the
rod-like quantities measured on it: centreline curvature, twist rate and stretch.

The end x = 0 is held without reactions to free thermal strain: u_x = 0 on the end face (it stays
plane and normal to the axis, which the free shapes compared here allow: sections of a bent or
uniformly contracted strip remain plane), the section centre is fixed and the end's width axis
cannot turn about x. The ribbon is measured between L/6 and 5L/6. Temperature is ramped from T_ref
to the target field by continuation.

Measured on stations x_k along the reference centreline, from the deformed centre and edge points:
- stretch: deformed centreline arc length / reference length between the first and last station;
- curvature: of the circle through the deformed centreline stations (least squares, 3D);
- twist rate: sum of the signed angles between successive width vectors after parallel transport
  of one tangent onto the next (the discrete twist of Discrete Elastic Rods), over the arc length.
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
from lcefem.models.hyperelastic import LCEElasticity
from lcefem.models.lce import NematicTransition, twisted_director
from lcefem.solvers import continuation
from lcefem.solvers.mechanics import HyperelasticProblem, displacement_space, volume_measure
from lcefem.solvers.probes import PointProbe
from lcefem.solvers.thermomechanics import LCERegion, lce_energy_density


@dataclass
class RibbonShape:
    """Rod-like description of a deformed ribbon."""

    stretch: float  #: [-]
    curvature: float  #: [1/mm]
    twist_rate: float  #: [rad/mm]
    centreline: np.ndarray  #: (n, 3) [mm]


def parallel_transport(v: np.ndarray, t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """Transport v from unit tangent t0 to t1 by the rotation about t0 x t1 (seed 000, DER)."""
    b = np.cross(t0, t1)
    nb = np.linalg.norm(b)
    if nb < 1e-14:
        return v
    b /= nb
    n0, n1 = np.cross(t0, b), np.cross(t1, b)
    return np.dot(v, t0) * t1 + np.dot(v, n0) * n1 + np.dot(v, b) * b


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
    """Stretch-free measures of a deformed ribbon from its centre and edge points at stations."""
    seg = np.diff(centre, axis=0)
    lengths = np.linalg.norm(seg, axis=1)
    tangents = seg / lengths[:, None]
    widths = edge_plus - edge_minus
    # width vector at the edges' midpoints, made normal to the local tangent
    mids = 0.5 * (widths[1:] + widths[:-1])
    twist = 0.0
    e_prev = None
    for k, t in enumerate(tangents):
        e = mids[k] - np.dot(mids[k], t) * t
        e /= np.linalg.norm(e)
        if e_prev is not None:
            moved = parallel_transport(e_prev, tangents[k - 1], t)
            twist += np.arctan2(np.dot(np.cross(moved, e), t), np.dot(moved, e))
        e_prev = e
    arc_mid = 0.5 * (lengths[1:] + lengths[:-1]).sum()
    return {"arc_length": float(lengths.sum()), "curvature": circle_curvature(centre),
            "twist_rate": float(twist / arc_mid)}


def solve_ribbon(length: float, width: float, thickness: float, twist_rate: float,
                 temperature: Callable, *, transition: NematicTransition = NematicTransition(),
                 elasticity: LCEElasticity = LCEElasticity(), resolution: RibbonMesh = RibbonMesh(),
                 stations: int = 21, comm: MPI.Comm = MPI.COMM_WORLD, prefix: str = "ribbon_fe_",
                 petsc_options: dict | None = None) -> tuple[RibbonShape, RibbonShape, object]:
    """Static equilibrium under ``temperature(y, z) -> UFL`` [C] given in the straight strip's section
    coordinates (y across the width, z through the thickness, both centred).

    Returns the as-built and the deformed :class:`RibbonShape` and the solved displacement Function.
    """
    tm = build_twisted_ribbon(length, width, thickness, twist_rate, resolution, comm)
    mesh = tm.mesh
    X = ufl.SpatialCoordinate(mesh)
    theta = twist_rate * X[0]
    y = X[1] * ufl.cos(theta) + X[2] * ufl.sin(theta)  # back to the straight strip's section
    z = -X[1] * ufl.sin(theta) + X[2] * ufl.cos(theta)
    s = dolfinx.fem.Constant(mesh, PETSc.ScalarType(0.0))
    T = transition.T_ref + s * (temperature(y, z) - transition.T_ref)
    region = LCERegion(["body"], twisted_director(X, twist_rate), transition, elasticity)
    V = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(V, name="displacement")
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
    problem = HyperelasticProblem(u, lce_energy_density(u, T, region) * volume_measure(tm), bcs,
                                  prefix=prefix, petsc_options=petsc_options)

    def set_load(value: float) -> None:
        s.value = value

    continuation.advance(set_load, problem.solve, problem.save, problem.restore,
                         where="ribbon heating", first=0.25)
    xs = np.linspace(length / 6, 5 * length / 6, stations)
    straight = {name: np.column_stack([xs, np.full_like(xs, yv), np.zeros_like(xs)])
                for name, yv in (("centre", 0.0), ("plus", 0.5 * width), ("minus", -0.5 * width))}
    reference = {k: helicoid(v, twist_rate) for k, v in straight.items()}
    probe = PointProbe(mesh, np.vstack([reference["centre"], reference["plus"], reference["minus"]]))
    disp = probe(u)
    n = len(xs)
    deformed = {k: reference[k] + disp[i * n:(i + 1) * n] for i, k in enumerate(("centre", "plus", "minus"))}
    shapes = []
    for pts in (reference, deformed):
        m = measure_shape(pts["centre"], pts["plus"], pts["minus"])
        shapes.append(RibbonShape(m["arc_length"] / (xs[-1] - xs[0]), m["curvature"], m["twist_rate"],
                                  pts["centre"]))
    return shapes[0], shapes[1], u
