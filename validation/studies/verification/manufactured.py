"""Manufactured solutions for the heat and mechanics solvers (verification; for tests and cases).

Heat: T_e = (1 + t/2)(30 + 10 sin(pi x/2) cos(pi y/3)(1 + z^2)) [C] on the unit cube, linear in time
so that backward Euler is exact in time and the error is spatial, O(h^(p+1)) in L2 for degree p. The
solver's pull-back is exercised by a prescribed quadratic displacement (exact in P2/Q2), and its
Robin condition (film coefficient, area ratio) on x = 1 by a manufactured inward flux.

Mechanics: u_e = A (sin(pi y/2) z, x^2 y, sin(pi x/2) cos(pi z/2)) [mm] in an LCE block with a
temperature gradient T = 40 + 20 x [C] and an oblique director, so F_s varies in space; body force
b = -Div P(u_e) and traction P(u_e) N on all faces but x = 0 (Dirichlet). L2 error O(h^3) for P2/Q2.
The manufactured field changes volume, which dead loads can only hold with a hydrostatic stress
kappa (J - 1); with the strip's kappa = 20 MPa that exceeds the shear modulus and the equilibrium is
unstable (the tangent loses positive definiteness at A = 0.02), so this check uses a compressible
variant of the law (kappa = 1 MPa) and A = 0.05 mm.
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
from mpi4py import MPI

import numpy as np
import ufl

import dolfinx

from lcefem.meshes.block import build_block
from lcefem.models.heat import SurfaceExchange, ThermalProperties
from lcefem.models.hyperelastic import LCEElasticity, lce_strain_energy
from lcefem.models.lce import NematicTransition, inverse_spontaneous_deformation
from lcefem.solvers import continuation
from lcefem.solvers.heat import HeatProblem, HeatSetup
from lcefem.solvers.mechanics import HyperelasticProblem, displacement_space
from lcefem.solvers.thermomechanics import LCERegion, lce_energy_density

MMS_THERMAL = ThermalProperties(density=1.2e-9, specific_heat=1.6e9, conductivity=0.3)
MMS_EXCHANGE = SurfaceExchange(film_coefficient=0.02, emissivity=0.0, ambient_temperature=20.0)


def observed_orders(sizes, errors) -> list[float]:
    """p_i = log(e_i / e_(i+1)) / log(h_i / h_(i+1)) for successive pairs; sizes are element sizes
    h."""
    return [
        float(np.log(errors[i] / errors[i + 1]) / np.log(sizes[i] / sizes[i + 1]))
        for i in range(len(errors) - 1)
    ]


def _l2(mesh, expr, degree) -> float:
    form = dolfinx.fem.form(expr**2 * ufl.dx(domain=mesh, metadata={"quadrature_degree": degree}))
    return float(np.sqrt(mesh.comm.allreduce(dolfinx.fem.assemble_scalar(form), op=MPI.SUM)))


def heat_error(n: int, degree: int, cell: str, comm: MPI.Comm | None = None) -> float:
    """L2 error [C mm^(3/2)] of the heat solver on an n^3 unit cube after two steps of 0.5 s."""
    tm = build_block((1.0, 1.0, 1.0), (n, n, n), cell, comm)
    mesh = tm.mesh
    x = ufl.SpatialCoordinate(mesh)
    t = dolfinx.fem.Constant(mesh, 0.0)
    spatial = 30.0 + 10.0 * ufl.sin(np.pi * x[0] / 2) * ufl.cos(np.pi * x[1] / 3) * (1 + x[2] ** 2)
    T_exact = (1.0 + 0.5 * t) * spatial
    u_expr = ufl.as_vector([0.05 * x[0] * x[1], 0.04 * x[1] ** 2 - 0.02 * x[2], 0.03 * x[0] * x[2]])
    Vu = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(Vu)
    u.interpolate(dolfinx.fem.Expression(u_expr, Vu.element.interpolation_points))
    F = ufl.Identity(3) + ufl.grad(u_expr)
    J = ufl.det(F)
    flux = MMS_THERMAL.conductivity * J * ufl.inv(F.T * F) * ufl.grad(T_exact)
    source = MMS_THERMAL.volumetric_heat_capacity * 0.5 * spatial - ufl.div(flux)
    N = ufl.FacetNormal(mesh)
    area_ratio = J * ufl.sqrt(ufl.dot(ufl.inv(F).T * N, ufl.inv(F).T * N))
    robin = MMS_EXCHANGE.film_coefficient * area_ratio * (
        T_exact - MMS_EXCHANGE.ambient_temperature
    ) + ufl.dot(flux, N)
    held = {}

    def dirichlet(V):
        held["g"] = dolfinx.fem.Function(V)
        held["expr"] = dolfinx.fem.Expression(T_exact, V.element.interpolation_points)
        facets = np.concatenate(
            [tm.facet_tags.find(tm.facet_tag(f)) for f in ("x0", "y0", "y1", "z0", "z1")]
        )
        return [
            dolfinx.fem.dirichletbc(held["g"], dolfinx.fem.locate_dofs_topological(V, 2, facets))
        ]

    setup = HeatSetup(
        MMS_THERMAL, MMS_EXCHANGE, exposed_facets=["x1"], degree=degree, radiation=False
    )
    heat = HeatProblem(
        tm,
        setup,
        displacement=u,
        extra_source=source,
        extra_flux=robin,
        bcs=dirichlet,
        prefix=f"mms_heat_{degree}_{cell}_{n}_",
        quadrature_degree=degree + 4,
    )
    heat.T.interpolate(dolfinx.fem.Expression(T_exact, heat.V.element.interpolation_points))
    dt = 0.5
    for step in (1, 2):
        t.value = step * dt
        held["g"].interpolate(held["expr"])
        heat.step(dt)
    return _l2(mesh, heat.T - T_exact, 2 * degree + 4)


MMS_ELASTICITY = LCEElasticity(bulk_modulus=1.0)


def mechanics_error(
    n: int, cell: str, amplitude: float = 0.05, comm: MPI.Comm | None = None
) -> float:
    """L2 error [mm^(5/2)] of the finite-strain LCE solver (P2/Q2) on an n^3 unit cube."""
    tm = build_block((1.0, 1.0, 1.0), (n, n, n), cell, comm)
    mesh = tm.mesh
    x = ufl.SpatialCoordinate(mesh)
    A = dolfinx.fem.Constant(mesh, 0.0)  # ramped from 0 to ``amplitude`` by continuation
    u_exact = A * ufl.as_vector(
        [
            ufl.sin(np.pi * x[1] / 2) * x[2],
            x[0] ** 2 * x[1],
            ufl.sin(np.pi * x[0] / 2) * ufl.cos(np.pi * x[2] / 2),
        ]
    )
    temperature = 40.0 + 20.0 * x[0]
    region = LCERegion(
        ["body"], ufl.as_vector([0.8, 0.6, 0.0]), NematicTransition(), MMS_ELASTICITY
    )
    F_e = ufl.variable(ufl.Identity(3) + ufl.grad(u_exact))

    # P(u_e) = dW/dF from the same energy density the solver uses
    W_exact = lce_strain_energy(
        F_e * inverse_spontaneous_deformation(temperature, region.director, region.transition),
        region.elasticity,
    )
    P_exact = ufl.diff(W_exact, F_e)
    body_force = -ufl.div(P_exact)
    N = ufl.FacetNormal(mesh)
    V = displacement_space(mesh, 2)
    u = dolfinx.fem.Function(V, name="displacement")
    u_D = dolfinx.fem.Function(V)
    u_D_expr = dolfinx.fem.Expression(u_exact, V.element.interpolation_points)
    x0 = tm.facet_tags.find(tm.facet_tag("x0"))
    bcs = [dolfinx.fem.dirichletbc(u_D, dolfinx.fem.locate_dofs_topological(V, 2, x0))]
    dx = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": 6})
    ds = ufl.Measure(
        "ds", domain=mesh, subdomain_data=tm.facet_tags, metadata={"quadrature_degree": 6}
    )
    traction_faces = tuple(tm.facet_tag(f) for f in ("x1", "y0", "y1", "z0", "z1"))
    energy = (
        lce_energy_density(u, temperature, region) * dx
        - ufl.dot(body_force, u) * dx
        - ufl.dot(P_exact * N, u) * ds(traction_faces)
    )
    problem = HyperelasticProblem(u, energy, bcs, prefix=f"mms_mech_{cell}_{n}_")

    def set_load(s: float) -> None:
        A.value = s * amplitude
        u_D.interpolate(u_D_expr)

    continuation.advance(
        set_load, problem.solve, problem.save, problem.restore, where=f"mechanics MMS n = {n}"
    )
    return _l2(mesh, u - u_exact, 8)
