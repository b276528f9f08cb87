"""Example 5: the robotic surface (seed 001, Fig. 4) as a bar-and-hinge model, programmed to a dome.

What it shows
    The gridshell is a square grid of Kapton ribbons with LCE strips bonded above (T) and below (B)
    each ribbon, wired as four channels (Tx, Ty, Bx, By). Fig. 4's dome contracts the top strips
    to lambda = 1.33 of their isotropic length and the bottom strips to 1.05 (lambda_N = 1.4 as
    built): the top shortens more, every ribbon curls upwards and the grid becomes a dome. The
    registered body ``gridshell`` runs the ramp from the as-built state with the path follower;
    the Fig. 4 drives are data (``lcefem.validation.cases.programs.SHAPE_DRIVES``, programs.toml).

Equations
    Bar-and-hinge (Filipov et al. 2017; the published reduced-order model): bars with axial
    stiffness EA/L and rest length L_0 f, f = lambda / lambda_N the strip's rest fraction; fold
    hinges with rotational stiffness k; equilibrium grad E(x) = 0 with the held DOFs of the
    rollers, followed in the load factor t (rest fraction 1 -> f) with inertia control.
    Circle curvature: 1/R of the circle through the two ends and the centre of the middle ribbon
    in x and in y [1/mm].

Key number
    The dome's circle curvature kappa_x [1/mm] (stored value; by the dome's symmetry kappa_y is the
    same).

Run: ``python docs/examples/ex05_gridshell_bh.py`` (the same at ``LCEFEM_EXAMPLE_QUICK=1``; output
in ``results/examples/ex05_gridshell_bh`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

import matplotlib
import numpy as np

from lcefem.solvers.problems.gridshell_bh_run import GridshellBHRunConfig, GridshellRun
from lcefem.solvers.registry import body
from lcefem.validation.cases.programs import SHAPE_DRIVES

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex05_gridshell_bh"

config = GridshellBHRunConfig(run=GridshellRun(shape="dome"), shapes=SHAPE_DRIVES)
summary = body("gridshell").runner()(config, OUT, progress=False)
kx = summary["results"]["circle_x"]
ky = summary["results"]["circle_y"]

nodes = np.genfromtxt(OUT / "nodes.csv", delimiter=",", names=True)
fig = plt.figure(figsize=(5.5, 4.2))
ax = fig.add_subplot(projection="3d")
x, y, z = (nodes[n] for n in nodes.dtype.names[-3:])
ax.scatter(x, y, z, c=z, s=2, cmap="viridis")
ax.set(
    xlabel="x [mm]",
    ylabel="y [mm]",
    zlabel="z [mm]",
    title=f"dome (Tx Ty 1.33, Bx By 1.05)\nkappa_x, kappa_y = {kx:.4f}, {ky:.4f} 1/mm",
)
ax.set_box_aspect((1, 1, 0.4))
fig.tight_layout()
fig.savefig(OUT / "ex05_gridshell_bh.png", dpi=100)

result = float(kx)
print(f"dome circle curvature kappa_x [1/mm] = {result!r}, kappa_y [1/mm] = {ky!r}")
