"""Example 9: inverse design, which channel lambdas give the gridshell a wanted curvature.

What it shows
    The forward problem (Example 5) maps the four channel lambdas (Tx, Ty, Bx, By) to the surface's
    centre curvatures. The inverse asks for lambdas whose equilibrium has given curvatures
    (kappa_x, kappa_y). Here a round trip: the Fig. 4 dome's lambdas give, by a forward run from the
    as-built state, the target curvatures; the design starts from mid-range lambdas and finds a
    set that reproduces them, checked by another forward run from as built (the design continues
    on another branch if the ramp ends elsewhere).

Equations
    min_p  1/2 |W (kappa(p) - kappa*)|^2  subject to  1.05 <= p <= lambda_N (bounded least squares),
    with the exact sensitivities d kappa / d p from the implicit-function theorem at each
    equilibrium:  K_t dx/dp = -d(grad E)/dp,  d kappa/dp = (d kappa/dx) dx/dp  (K_t the tangent
    stiffness of the bar-and-hinge model).

Key number
    The centre curvature kappa_x reached by the forward check [1/mm]; it must equal the target
    within 1e-4 1/mm (the design's tolerance).

Run: ``python docs/examples/ex09_inverse_design.py`` (``LCEFEM_EXAMPLE_QUICK=1``: one grid cell
instead of the 3 x 3 grid; output in ``results/examples/ex09_inverse_design`` or
``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

import matplotlib
import numpy as np

from lcefem.meshes.gridshell import GridshellLayout
from lcefem.validation.cases.programs import SHAPE_DRIVES
from lcefem.validation.studies.design import gridshell_design as design

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUICK = os.environ.get("LCEFEM_EXAMPLE_QUICK") == "1"
OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex09_inverse_design"
OUT.mkdir(parents=True, exist_ok=True)

problem = design.setup_design("4", "rollers", layout=GridshellLayout(ribbons=1 if QUICK else 3))
p_dome = np.array([SHAPE_DRIVES["dome"]["lambdas"][name] for name in problem.names])
target = design.forward_check(problem, p_dome)  # the dome's curvatures, from as built
found = design.inverse(problem, target["circle_x"], target["circle_y"])
reached = found.check  # a forward run from as built at the lambdas found

fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
idx = np.arange(len(problem.names))
a.bar(idx - 0.2, p_dome, 0.4, label="dome (Fig. 4)")
a.bar(idx + 0.2, found.p, 0.4, label="found")
a.set(
    xticks=idx,
    xticklabels=problem.names,
    ylim=(1.0, 1.45),
    ylabel="lambda [-]",
    title="channel lambdas",
)
a.legend(fontsize=8)
b.bar([0, 1], [target["circle_x"], target["circle_y"]], 0.4, label="target")
b.bar([0.4, 1.4], [reached["circle_x"], reached["circle_y"]], 0.4, label="reached")
b.set(
    xticks=[0.2, 1.2],
    xticklabels=["kappa_x", "kappa_y"],
    ylabel="curvature [1/mm]",
    title="curvatures",
)
b.legend(fontsize=8)
fig.tight_layout()
fig.savefig(OUT / "ex09_inverse_design.png", dpi=100)

result = float(reached["circle_x"])
print(f"lambdas found: {dict(zip(problem.names, np.round(found.p, 4)))}")
print(f"target kappa_x [1/mm] = {target['circle_x']!r}, reached [1/mm] = {result!r}")
