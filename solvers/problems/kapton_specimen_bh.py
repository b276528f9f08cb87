"""The passive Kapton buckling specimen (seed 001, Fig. 2G) in the bar-and-hinge model, fixed-fixed.

* :func:`solve_specimen_buckling` — the specimen shortened by a prescribed end displacement; force
  from the reaction at the moving clamp.
* :func:`critical_load` — the bifurcation load of the perfect (flat) specimen: the end shortening at
  which the tangent stiffness of the straight equilibrium first loses positive definiteness
  (Sylvester inertia of the sparse LDL^T), found by bisection.
* Closed forms: :mod:`lcefem.models.buckling` (Euler, elastica),
  :func:`lcefem.models.bar_hinge.n5b8_ribbon_bending_stiffness`.

Units: mm, N, mJ.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.kapton_ribbon import KaptonBarHingeMesh, KaptonSpecimenGeometry, build_ribbon_bar_hinge
from lcefem.models.bar_hinge import BarHingeMaterials
from lcefem.models.errors import InputError
from lcefem.solvers.bar_hinge import (BarHingeModel, NewtonOptions, PathOptions, PathResult, PathState,
                                      follow_path, held_dofs, newton)

#: Default stepping of the end shortening (0 -> 50 %); small increments resolve the force curve.
SPECIMEN_PATH = PathOptions(initial_increment=0.01, max_increment=0.02, easy_iterations=10)


@dataclass
class KaptonSpecimenSolution:
    structure: BarHingeStructure
    model: BarHingeModel
    path: PathResult
    compression: np.ndarray  # end shortening / free length [-], per state
    force: np.ndarray  # compressive force [N], per state
    max_compression: float


def specimen_model(specimen: KaptonSpecimenGeometry, mesh: KaptonBarHingeMesh, materials: BarHingeMaterials):
    """(structure, model, held DOFs of the left clamp, of the right clamp)."""
    structure = build_ribbon_bar_hinge(specimen, mesh)
    model = BarHingeModel.from_materials(structure, materials)
    left = held_dofs(structure.node_sets["left_clamp"])
    right = held_dofs(structure.node_sets["right_clamp"])
    return structure, model, left, right


def compressive_force(reactions: np.ndarray, held: np.ndarray, right_x: np.ndarray) -> float:
    """Compressive end force [N]: minus the x-forces the supports apply to the moving clamp (the
    gradient of the energy at the held DOFs is the force the supports apply)."""
    mask = np.isin(held, right_x)
    return -float(np.sum(reactions[mask]))


@dataclass
class KaptonSpecimenSetup:
    """The specimen's structure, model, held DOFs and end-shortening path, built before solving."""

    specimen: KaptonSpecimenGeometry
    max_compression: float
    structure: BarHingeStructure
    model: BarHingeModel
    held: np.ndarray
    right_x: np.ndarray  # x DOFs of the moving clamp
    load: Callable[[float], np.ndarray]

    def force(self, state: PathState) -> float:
        """Compressive force [N] at a converged state."""
        return compressive_force(state.reactions, self.held, self.right_x)


def setup_specimen(max_compression: float = 0.5,
                   specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
                   mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
                   materials: BarHingeMaterials = BarHingeMaterials()) -> KaptonSpecimenSetup:
    """Clamps held, the right one moved by -t * max_compression * length along x."""
    if not isinstance(max_compression, (int, float)) or not 0.0 < max_compression < 0.95:
        raise InputError(f"compression = {max_compression}: must be in (0, 0.95) (end shortening / "
                         f"free length)")
    structure, model, left, right = specimen_model(specimen, mesh, materials)
    held = np.concatenate([left, right])
    right_x = right[right % 3 == 0]
    base = structure.nodes.reshape(-1)[held].copy()
    shift = np.where(np.isin(held, right_x), -max_compression * specimen.length, 0.0)
    return KaptonSpecimenSetup(specimen, float(max_compression), structure, model, held, right_x,
                               lambda t: base + t * shift)


def solve_specimen_buckling(max_compression: float = 0.5,
                            specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
                            mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
                            materials: BarHingeMaterials = BarHingeMaterials(), *,
                            newton_options: NewtonOptions = NewtonOptions(),
                            path: PathOptions = SPECIMEN_PATH,
                            on_step: Callable[[PathState], None] | None = None,
                            progress: Callable[[float], None] | None = None,
                            setup: KaptonSpecimenSetup | None = None) -> KaptonSpecimenSolution:
    """Fixed-fixed specimen shortened to ``max_compression`` of its free length (displacement control).

    The compressive force is the sum of the x-components of the internal forces on the right
    clamp's nodes (the reaction the testing machine applies).
    """
    setup = setup or setup_specimen(max_compression, specimen, mesh, materials)
    forces: list[float] = []

    def record(state: PathState) -> None:
        forces.append(setup.force(state))
        if on_step is not None:
            on_step(state)

    result = follow_path(setup.model, setup.structure.nodes, setup.held, setup.load,
                         newton_options=newton_options, path_options=path, on_step=record,
                         progress=progress)
    compression = np.array([s.t * setup.max_compression for s in result.states])
    return KaptonSpecimenSolution(setup.structure, setup.model, result, compression, np.array(forces),
                                  setup.max_compression)


def critical_load(specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
                  mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
                  materials: BarHingeMaterials = BarHingeMaterials(), *,
                  rel_tol: float = 1e-4) -> tuple[float, float]:
    """Bifurcation of the perfect (flat) specimen: (critical compressive force [N], end shortening [mm]).

    Along the straight path (imperfection 0) the equilibrium is computed with plain Newton (no
    inertia control, so it stays straight) and the number of negative pivots of the tangent is
    counted; the first end shortening where it becomes positive is bracketed by doubling and
    refined by bisection to ``rel_tol``.
    """
    flat = KaptonBarHingeMesh(panels=mesh.panels, clamp_length=mesh.clamp_length, imperfection=0.0)
    structure, model, left, right = specimen_model(specimen, flat, materials)
    held = np.concatenate([left, right])
    right_x = right[right % 3 == 0]
    free = np.setdiff1d(np.arange(model.ndof), held)
    plain = NewtonOptions(inertia_control=False)
    base = structure.nodes.reshape(-1).copy()

    def state(shortening: float):
        # Start from the straight state under uniform strain (x = X (1 - e/L) inside the span).
        x = base.copy()
        x[right_x] -= shortening
        inner = free[free % 3 == 0]
        x[inner] = base[inner] * (1.0 - shortening / specimen.length)
        res = newton(model, x, free, plain)
        if not res.converged:
            raise RuntimeError(f"straight path lost at shortening {shortening} mm: {res.reason}")
        grad = model.evaluate(res.x, derivatives=1)[1]
        return res.negative_pivots, -float(np.sum(grad[right_x]))

    lo, hi = 0.0, 1e-4 * specimen.length
    while state(hi)[0] == 0:
        lo, hi = hi, 2.0 * hi
        if hi > 0.5 * specimen.length:
            raise RuntimeError("no bifurcation up to 50 % shortening")
    while hi - lo > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        if state(mid)[0] == 0:
            lo = mid
        else:
            hi = mid
    return state(lo)[1], lo
