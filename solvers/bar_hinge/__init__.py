"""Our bar-and-hinge (MERLIN-type) solver: energy assembly, Newton with line search and inertia
control, and load-path following with step halving from the last converged state.

Entry points: :class:`BarHingeModel` (structure + materials -> energy, gradient, sparse Hessian),
:func:`newton`, :func:`follow_path`, :func:`held_dofs`.
"""

from lcefem.solvers.bar_hinge.model import BarHingeModel, ReducedHessian
from lcefem.solvers.bar_hinge.newton import (
    NewtonOptions,
    NewtonResult,
    PathOptions,
    PathResult,
    PathState,
    follow_path,
    newton,
)
from lcefem.solvers.bar_hinge.supports import held_dofs, isostatic_supports

__all__ = [
    "BarHingeModel",
    "ReducedHessian",
    "NewtonOptions",
    "NewtonResult",
    "PathOptions",
    "PathResult",
    "PathState",
    "follow_path",
    "newton",
    "held_dofs",
    "isostatic_supports",
]
