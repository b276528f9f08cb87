"""The robotic surface with its cover scales (seed 001, Fig. 5) in the bar-and-hinge model.

:func:`cover_setup` turns a :class:`~lcefem.solvers.problems.gridshell_bh.GridshellSetup` into the
same setup whose model carries the cover-scale layer (:mod:`lcefem.solvers.bar_hinge.cover_scales`);
:func:`add_scales_to` ramps the layer in from an equilibrium of the bare surface (the strips held at
their targets), :func:`solve_covered` ramps the strips of a covered surface from flat.

Units: mm, N, t, s.
"""

from __future__ import annotations

import numpy as np

from lcefem.meshes.bar_hinge_structure import BarHingeStructure
from lcefem.models.bar_hinge_materials import BarHingeMaterials
from lcefem.models.cover_scales import CoverScales
from lcefem.solvers.bar_hinge import NewtonOptions, PathOptions, PathResult, follow_path
from lcefem.solvers.bar_hinge.cover_scales import CoveredModel
from lcefem.solvers.bar_hinge.strip_beams import StripBeamModel
from lcefem.solvers.problems import gridshell_bh as gs


class CoveredStripBeamModel(CoveredModel, StripBeamModel):
    """The cover-scale layer on the model with the strips' bending elements (``mesh.strip_element``
    'bending' or 'beam', e.g. the FE-calibrated model set): energy = the strip-beam model's + the
    layer's."""


def covered_model(
    structure: BarHingeStructure,
    materials: BarHingeMaterials = BarHingeMaterials(),
    scales: CoverScales = CoverScales(),
    factor: float = 1.0,
) -> CoveredModel:
    """The model of ``structure`` (with its strip bending elements if it has them, as
    :func:`lcefem.solvers.bar_hinge.strip_beams.bar_hinge_model`) carrying the cover-scale layer."""
    cls = CoveredStripBeamModel if len(structure.info.get("strip_beams", ())) else CoveredModel
    return cls.from_materials(structure, materials).attach_scales(scales, factor)


def cover_setup(
    setup: gs.GridshellSetup,
    scales: CoverScales = CoverScales(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    factor: float = 1.0,
) -> gs.GridshellSetup:
    """The setup with a :class:`CoveredModel` (:func:`covered_model`: with the strips' bending
    elements when the structure has them; same structure, supports, targets and dead loads; the
    rest fractions copied)."""
    model = covered_model(setup.structure, materials, scales, factor)
    model.set_rest_fractions(setup.model.rest_fractions())
    model.set_external_forces(setup.model.external_force)
    return gs.GridshellSetup(
        setup.structure, model, setup.held, setup.targets, setup.support, setup.weight
    )


def add_scales_to(
    solution: gs.GridshellSolution,
    scales: CoverScales = CoverScales(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    *,
    newton_options: NewtonOptions = gs.GRIDSHELL_NEWTON,
    path: PathOptions = gs.GRIDSHELL_PATH,
) -> tuple[gs.GridshellSetup, PathResult]:
    """Ramp the layer's factor 0 -> 1 from a bare equilibrium (strips at their targets); returns the
    covered setup and the path (its last state: the covered equilibrium)."""
    covered = cover_setup(solution.setup, scales, materials, factor=0.0)
    covered.load(1.0)
    model = covered.model

    def load(t: float) -> np.ndarray:
        model.factor = t
        return model.reference.reshape(-1)[covered.held]

    result = follow_path(
        model,
        solution.final.x,
        covered.held,
        load,
        newton_options=newton_options,
        path_options=path,
    )
    model.factor = 1.0
    return covered, result


def ramp_layer(
    covered: gs.GridshellSetup,
    x: np.ndarray,
    start: float,
    end: float,
    *,
    newton_options: NewtonOptions = gs.GRIDSHELL_NEWTON,
    path: PathOptions = gs.GRIDSHELL_PATH,
) -> PathResult:
    """Follow the equilibrium of a covered setup (strips at their targets) from ``x`` at layer
    factor ``start`` to ``end`` (e.g. 1 -> 0: take the scales off); the model's factor is left at
    ``end``."""
    covered.load(1.0)
    model = covered.model

    def load(t: float) -> np.ndarray:
        model.factor = start + t * (end - start)
        return model.reference.reshape(-1)[covered.held]

    result = follow_path(
        model, x, covered.held, load, newton_options=newton_options, path_options=path
    )
    model.factor = end
    return result


def solve_covered(
    setup: gs.GridshellSetup,
    scales: CoverScales = CoverScales(),
    materials: BarHingeMaterials = BarHingeMaterials(),
    **kw,
) -> gs.GridshellSolution:
    """Ramp the strips of the covered surface from the as-built state to their targets."""
    return gs.solve_gridshell(cover_setup(setup, scales, materials), **kw)
