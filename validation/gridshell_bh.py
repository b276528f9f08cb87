"""Bar-and-hinge study of the robotic surface (seed 001, Fig. 4 and 5), shared by the validation
cases, the benchmark and the tests: the paper's Fig. 4 settings with the curvatures it reports
(:data:`SHAPES`, validation data of validation/data/seed001.toml).

Everything else is re-exported from where it is defined, for the studies, cases and benchmarks
that import it from here: the problem, its supports, ramp, observables, the paper's programs
(:data:`~lcefem.solvers.problems.gridshell_bh.SHAPE_DRIVES`), the published recipes and
:func:`setup_gridshell` from :mod:`lcefem.solvers.problems.gridshell_bh`; the current route
(currents per channel/group -> lambdas through the strip's thermal model, :func:`stretch_from_current`)
from :mod:`lcefem.models.lumped_heat`.

Units: mm, N, t, s, A, 1/mm.
"""

from __future__ import annotations

from lcefem.models.lumped_heat import (  # noqa: F401
    THERMAL_MODELS, CurrentRoute, lambda_assignments_from_currents, stretch_from_current)
from lcefem.solvers.problems.gridshell_bh import (  # noqa: F401
    DEPARTURES, GRIDSHELL_NEWTON, GRIDSHELL_PATH, RECIPE_SOURCE, RECIPES, SHAPE_DRIVE_SOURCES, SHAPE_DRIVES, SUPPORTS,
    GridshellBH, GridshellBHConfig, GridshellSetup, GridshellSolution, add_table, centre_height,
    check_lambda_values, lumped_node_weights, payload_forces, prepare_structure, published_configuration,
    ribbon_nodes,
    setup_from_model, setup_gridshell, shape_summary, solve_gridshell, solve_payload, support_dofs,
    targets_from_lambdas, targets_from_recipe)
from lcefem.validation.reference_data import reference

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
    name: {**drive,
           "paper_sim": (0.0, 0.0) if name == "table" else _paper_curvatures(name, "sim"),
           "paper_exp": (None, None) if name == "table" else _paper_curvatures(name, "exp")}
    for name, drive in SHAPE_DRIVES.items()}
SHAPE_SOURCES = {
    **SHAPE_DRIVE_SOURCES,
    "curvatures": "seed 001, Results (dome) and Materials and Methods (saddle, cylinder): principal "
                  "curvatures at the centre joint, simulation / experiment; table: flat (0, 0) by "
                  "symmetry, no number published",
}
