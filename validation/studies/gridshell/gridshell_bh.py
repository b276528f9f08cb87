"""Bar-and-hinge study of the robotic surface (seed 001, Fig. 4 and 5), shared by the validation
cases, the benchmark and the tests: the paper's Fig. 4 settings with the curvatures it reports
(:data:`SHAPES`, validation data of validation/data/seed001.toml).

The problem, its supports, ramp and observables are :mod:`lcefem.solvers.problems.gridshell_bh`'s;
the paper's programs and the published recipes are :mod:`lcefem.validation.cases.programs`'
(validation/data/ programs.toml); the current route (currents per channel/group ->
lambdas through the strip's thermal model) is :mod:`lcefem.models.lumped_heat`'s: import them from
there.

Units: mm, N, t, s, A, 1/mm.
"""

from __future__ import annotations

from lcefem.validation.cases.programs import SHAPE_DRIVE_SOURCES, SHAPE_DRIVES
from lcefem.validation.cases.reference_data import reference

SEED = "seed 001"


def _paper_curvatures(shape: str, kind: str) -> tuple[float, float]:
    """(kappa_x, kappa_y) [1/mm] the paper reports at the centre joint, ``kind`` "sim" or "exp"
    (validation/data/seed001.toml, each with its quote)."""
    ref = reference(f"surface.{shape}.curvature_{kind}")
    return (ref["kx"], ref["ky"])


#: The paper's Fig. 4 settings (lambda and current per channel, support: SHAPE_DRIVES) and the
#: curvatures it reports at the centre joint [1/mm] (simulation, experiment), sign: dome negative
#: (seed 001, Results and Methods). The table is the flat shape (0, 0) of the paper's
#: classification; no measured value is given.
SHAPES = {
    name: {
        **drive,
        "paper_sim": (0.0, 0.0) if name == "table" else _paper_curvatures(name, "sim"),
        "paper_exp": (None, None) if name == "table" else _paper_curvatures(name, "exp"),
    }
    for name, drive in SHAPE_DRIVES.items()
}
SHAPE_SOURCES = {
    **SHAPE_DRIVE_SOURCES,
    "curvatures": "seed 001, Results (dome) and Materials and Methods (saddle, cylinder): "
    "principal "
    "curvatures at the centre joint, simulation / experiment; table: flat (0, 0) by "
    "symmetry, no number published",
}
