"""Bar-and-hinge simulations of the seed-001 experiments, shared by ``lcefem run beam``,
``lcefem run ribbon-buckling``, the validation cases and the benchmark.

* :func:`solve_beam` — the composite beam actuated by prescribing the strips' relative lengths
  lambda_T and lambda_B (the paper's quasi-static route): the rest lengths are ramped linearly from the
  as-built (nematic) lengths to lambda/lambda_N times them; statically determinate supports at the
  middle panel; the curvature is measured by :func:`lcefem.solvers.analysis.curvature.beam_curvature`.
* :func:`solve_ribbon_buckling` — the fixed-fixed specimen shortened by a prescribed end
  displacement; force from the reaction at the moving clamp.
* :func:`critical_load` — the bifurcation load of the perfect (flat) specimen: the end shortening at
  which the tangent stiffness of the straight equilibrium first loses positive definiteness
  (Sylvester inertia of the sparse LDL^T), found by bisection.
* Closed forms: :mod:`lcefem.models.buckling` (Euler, elastica),
  :func:`lcefem.models.bar_hinge.n5b8_ribbon_bending_stiffness`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry, build_beam_bar_hinge
from lcefem.meshes.kapton_ribbon import KaptonBarHingeMesh, KaptonSpecimenGeometry, build_ribbon_bar_hinge
from lcefem.models import bar_hinge as law
from lcefem.models.bar_hinge import BarHingeMaterials
from lcefem.models.empirical import Eq2
from lcefem.models.errors import InputError
from lcefem.models.limits import check_lambda
from lcefem.models.hyperelastic import OgdenLaw, ogden_uniaxial_nominal_stress
from lcefem.solvers.analysis.curvature import beam_curvature
from lcefem.solvers.bar_hinge import (BarHingeModel, NewtonOptions, PathOptions, PathResult,
                                      PathState, follow_path, held_dofs, isostatic_supports, newton)

#: Default stepping of the actuation ramp (see PathOptions).
BEAM_PATH = PathOptions(initial_increment=0.05, max_increment=0.2, easy_iterations=10)
#: Default stepping of the end shortening (0 -> 50 %); small increments resolve the force curve.
RIBBON_PATH = PathOptions(initial_increment=0.01, max_increment=0.02, easy_iterations=10)


def bar_hinge_model(structure: BarHingeStructure,
                    materials: BarHingeMaterials = BarHingeMaterials()) -> BarHingeModel:
    """The bar-and-hinge model of ``structure`` with the laws of ``materials``."""
    return BarHingeModel.from_materials(structure, materials)


# --------------------------------------------------------------------------- composite beam
@dataclass
class BeamSolution:
    lambda_top: float
    lambda_bottom: float
    structure: BarHingeStructure
    model: BarHingeModel
    path: PathResult
    curvature: float  # [1/mm], at the end of the ramp

    @property
    def final(self) -> PathState:
        return self.path.states[-1]


def beam_load(model: BarHingeModel, lambda_top: float, lambda_bottom: float, held: np.ndarray
              ) -> Callable[[float], np.ndarray]:
    """Load path t -> held DOF values: rest fractions f(t) = 1 + t (lambda/lambda_N - 1)."""
    targets = {"top_strips": float(model.lce.rest_fraction(lambda_top)),
               "bottom_strips": float(model.lce.rest_fraction(lambda_bottom))}
    names = {b.name for b in model.strip_sets()}
    fixed = model.reference.reshape(-1)[held].copy()

    def load(t: float) -> np.ndarray:
        model.set_rest_fractions({k: 1.0 + t * (v - 1.0) for k, v in targets.items() if k in names})
        return fixed

    return load


def lambdas_at(t: float, lambda_top: float, lambda_bottom: float, lambda_N: float) -> tuple[float, float]:
    """(lambda_T, lambda_B) along the linear ramp at load factor t."""
    return (lambda_N + t * (lambda_top - lambda_N), lambda_N + t * (lambda_bottom - lambda_N))


@dataclass
class BeamSetup:
    """The beam's structure, model, held DOFs and load path, built before solving."""

    lambda_top: float
    lambda_bottom: float
    structure: BarHingeStructure
    model: BarHingeModel
    held: np.ndarray
    load: Callable[[float], np.ndarray]


def setup_beam(lambda_top: float, lambda_bottom: float,
               geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
               mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
               materials: BarHingeMaterials = BarHingeMaterials()) -> BeamSetup:
    """Structure, model, statically determinate supports at the middle panel, and the ramp."""
    lam_n = materials.lce.lambda_N
    check_lambda("lambda_top", lambda_top, lam_n)
    check_lambda("lambda_bottom", lambda_bottom, lam_n)
    structure = build_beam_bar_hinge(geometry, mesh)
    model = bar_hinge_model(structure, materials)
    held = isostatic_supports(*structure.node_sets["centre_support"])
    return BeamSetup(lambda_top, lambda_bottom, structure, model, held,
                     beam_load(model, lambda_top, lambda_bottom, held))


def solve_beam(lambda_top: float, lambda_bottom: float,
               geometry: CompositeBeamGeometry = CompositeBeamGeometry(),
               mesh: BeamBarHingeMesh = BeamBarHingeMesh(),
               materials: BarHingeMaterials = BarHingeMaterials(), *,
               newton_options: NewtonOptions = NewtonOptions(), path: PathOptions = BEAM_PATH,
               on_step: Callable[[PathState], None] | None = None,
               progress: Callable[[float], None] | None = None,
               setup: BeamSetup | None = None) -> BeamSolution:
    """Composite beam at (lambda_T, lambda_B), ramped from the as-built state (see module docstring).

    ``setup`` (from :func:`setup_beam` with the same arguments) lets a caller hold the model, e.g.
    to write bar forces in ``on_step``.
    """
    setup = setup or setup_beam(lambda_top, lambda_bottom, geometry, mesh, materials)
    result = follow_path(setup.model, setup.structure.nodes, setup.held, setup.load,
                         newton_options=newton_options, path_options=path, on_step=on_step,
                         progress=progress)
    return BeamSolution(lambda_top, lambda_bottom, setup.structure, setup.model, result,
                        beam_curvature(setup.structure, result.states[-1].x))


def eq2_parameters(eq2: Eq2 = Eq2()) -> str:
    """Eq. 2's inputs as text for captions, from the one definition in :class:`Eq2`."""
    return (f"eta = {eq2.eta:g}, l_p = {eq2.ribbon_length:g} mm, t_a = {eq2.strip_thickness:g} mm, "
            f"lambda_N = {eq2.lambda_N:g}")


def eq2_inputs_note(eq2: Eq2 = Eq2()) -> str:
    return (f"Eq. 2 with l_p = {eq2.ribbon_length:g} mm (the segment's straight length, as the beam's "
            f"bottom strips span it), t_a = {eq2.strip_thickness:g} mm (the cast strip thickness), "
            f"lambda_N = {eq2.lambda_N:g} (the published model's isotropic/nematic ratio, the same "
            "lambda_N the bar-and-hinge rest lengths use, so that lambda_T = lambda_B = lambda_N is the "
            f"flat as-built beam in both), eta = {eq2.eta:g} (seed 001)")


# --------------------------------------------------------------------------- ribbon buckling
@dataclass
class KaptonSpecimenSolution:
    structure: BarHingeStructure
    model: BarHingeModel
    path: PathResult
    compression: np.ndarray  # end shortening / free length [-], per state
    force: np.ndarray  # compressive force [N], per state
    max_compression: float


def ribbon_model(specimen: KaptonSpecimenGeometry, mesh: KaptonBarHingeMesh, materials: BarHingeMaterials):
    """(structure, model, held DOFs of the left clamp, of the right clamp)."""
    structure = build_ribbon_bar_hinge(specimen, mesh)
    model = bar_hinge_model(structure, materials)
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


def setup_ribbon(max_compression: float = 0.5, specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
                 mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
                 materials: BarHingeMaterials = BarHingeMaterials()) -> KaptonSpecimenSetup:
    """Clamps held, the right one moved by -t * max_compression * length along x."""
    if not isinstance(max_compression, (int, float)) or not 0.0 < max_compression < 0.95:
        raise InputError(f"compression = {max_compression}: must be in (0, 0.95) (end shortening / "
                         f"free length)")
    structure, model, left, right = ribbon_model(specimen, mesh, materials)
    held = np.concatenate([left, right])
    right_x = right[right % 3 == 0]
    base = structure.nodes.reshape(-1)[held].copy()
    shift = np.where(np.isin(held, right_x), -max_compression * specimen.length, 0.0)
    return KaptonSpecimenSetup(specimen, float(max_compression), structure, model, held, right_x,
                       lambda t: base + t * shift)


def solve_ribbon_buckling(max_compression: float = 0.5,
                          specimen: KaptonSpecimenGeometry = KaptonSpecimenGeometry(),
                          mesh: KaptonBarHingeMesh = KaptonBarHingeMesh(),
                          materials: BarHingeMaterials = BarHingeMaterials(), *,
                          newton_options: NewtonOptions = NewtonOptions(),
                          path: PathOptions = RIBBON_PATH,
                          on_step: Callable[[PathState], None] | None = None,
                          progress: Callable[[float], None] | None = None,
                          setup: KaptonSpecimenSetup | None = None) -> KaptonSpecimenSolution:
    """Fixed-fixed specimen shortened to ``max_compression`` of its free length (displacement control).

    The compressive force is the sum of the x-components of the internal forces on the right
    clamp's nodes (the reaction the testing machine applies).
    """
    setup = setup or setup_ribbon(max_compression, specimen, mesh, materials)
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
    structure, model, left, right = ribbon_model(specimen, flat, materials)
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


def lce_strain_under_force(force: float, section: float, ogden: OgdenLaw = OgdenLaw()) -> float:
    """Strain lambda - 1 [-] of the isotropic LCE strip (Ogden law, section [mm^2]) under ``force`` [N]."""
    target = force / section
    lam = brentq(lambda s: float(ogden_uniaxial_nominal_stress(s, ogden)) - target, 1.0, 3.0)
    return lam - 1.0


