"""The composite beam (seed 001, Fig. 3) in the bar-and-hinge model: actuated by prescribing the
strips' relative lengths lambda_T and lambda_B (the paper's quasi-static route). The rest lengths are
ramped linearly from the as-built (nematic) lengths to lambda/lambda_N times them; statically
determinate supports at the middle panel; the curvature is measured by
:func:`lcefem.solvers.analysis.curvature.beam_curvature`. Used by ``lcefem run beam``, the validation
cases and the benchmarks.

* :func:`setup_beam` — structure, model, held DOFs and the ramp, built before solving;
* :func:`solve_beam` — the ramp from the as-built state (:func:`lcefem.solvers.bar_hinge.follow_path`).

Units: mm, N, mJ.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.meshes.composite_beam import BeamBarHingeMesh, CompositeBeamGeometry, build_beam_bar_hinge
from lcefem.models.bar_hinge import BarHingeMaterials
from lcefem.models.limits import check_lambda
from lcefem.solvers.analysis.curvature import beam_curvature
from lcefem.solvers.bar_hinge import (BarHingeModel, NewtonOptions, PathOptions, PathResult, PathState,
                                      follow_path, isostatic_supports)

#: Default stepping of the actuation ramp (see PathOptions).
BEAM_PATH = PathOptions(initial_increment=0.05, max_increment=0.2, easy_iterations=10)


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
    model = BarHingeModel.from_materials(structure, materials)
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
