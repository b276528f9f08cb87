"""Static equilibrium of a discrete rod: minimum of E_elastic + k E_contact - f.q over free dofs.

Loads (gravity, external forces) and the rest shape can be applied in increments (load stepping):
at increment i of n the load is i/n of the full one and the rest shape is interpolated linearly
from ``rest_from`` to ``rod.rest``. A free rod (no prescribed dofs) has six zero-energy rigid
modes; the Levenberg shift of the Newton solver handles them, or prescribe a statically
determinate set of dofs (:func:`statically_determinate_support`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lcefem.models.errors import ConvergenceError, InputError
from lcefem.solvers.der.assembly import Assembly, ContactSampling, Derivatives
from lcefem.solvers.der.integrator import generalised_load
from lcefem.solvers.der.model import DiscreteRod, RestShape, RodState, n_dofs
from lcefem.solvers.der.newton import NewtonOptions, NewtonResult, minimise


class StaticPotential:
    def __init__(self, rod: DiscreteRod, assembly: Assembly, load: np.ndarray):
        self.rod, self.asm, self.load = rod, assembly, load
        self.sampling = ContactSampling.of(rod)

    def __call__(self, state: RodState, hessian: bool) -> Derivatives:
        order = 2 if hessian else 0
        ee, ge, te = self.asm.elastic(self.rod, state, order)
        ec, gc, tc = self.asm.contact(self.rod, state, self.sampling, order)
        energy = ee + ec - float(self.load @ state.q())
        if not hessian:
            return Derivatives(energy, None, None)
        grad = ge - self.load
        if gc is not None:
            grad += gc
        return Derivatives(energy, grad, self.asm.band(te + tc, None))


@dataclass
class StaticResult:
    state: RodState
    iterations: int
    increments: int
    residual: float


def interpolate_rest(a: RestShape, b: RestShape, s: float) -> RestShape:
    return RestShape(
        (1 - s) * a.edge_length + s * b.edge_length,
        (1 - s) * a.curvature + s * b.curvature,
        (1 - s) * a.twist + s * b.twist,
    )


def solve_static(
    rod: DiscreteRod,
    state: RodState,
    increments: int = 1,
    rest_from: RestShape | None = None,
    options: NewtonOptions = NewtonOptions(max_iterations=60),
) -> StaticResult:
    """Equilibrium reached from ``state`` by ``increments`` load increments.

    Raises:
        InputError: increments < 1.
        ConvergenceError: an increment failed even after being split in two 8 times.
    """
    if increments < 1:
        raise InputError(f"increments = {increments}: must be >= 1")
    asm = Assembly(rod.n_nodes)
    full_load = generalised_load(rod)
    target = rod.rest
    total_its = 0
    done = 0.0
    step = 1.0 / increments
    cuts = 0
    count = 0
    while done < 1.0 - 1e-12:
        s = min(1.0, done + step)
        rest = target if rest_from is None else interpolate_rest(rest_from, target, s)
        trial_rod = rod.replace(rest=rest)
        result: NewtonResult = minimise(
            state, rod.fixed, StaticPotential(trial_rod, asm, s * full_load), options
        )
        total_its += result.iterations
        if result.converged:
            state = result.state
            done = s
            count += 1
            step = min(step * 1.5, 1.0 / increments) if cuts else step
        else:
            step *= 0.5
            cuts += 1
            if cuts > 8 * increments:
                raise ConvergenceError(
                    f"load factor {done:.4g}",
                    f"static Newton failed ({result.reason}, "
                    f"residual {result.residual:.3g}) at increment size {step:.3g}",
                )
    return StaticResult(state, total_its, count, result.residual)


def statically_determinate_support(n_nodes: int, axis: int = 0) -> np.ndarray:
    """Fix node 0 (3 dofs), theta_0, and the two coordinates of node 1 other than ``axis``: removes
    the six rigid modes of a free rod whose first edge lies along ``axis`` without loading it."""
    fixed = np.zeros(n_dofs(n_nodes), bool)
    fixed[0:4] = True
    for c in range(3):
        if c != axis:
            fixed[4 + c] = True
    return fixed
