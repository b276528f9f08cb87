"""Example 4: a twisted LCE ribbon rolling on a hot plate (seed 000), as a discrete elastic rod.

What it shows
    A ribbon, stretched and twisted when built, is laid on a plate at 100 C. Heat enters through
    contact and the warm air; the side near the plate contracts, which bends and untwists the
    ribbon, and it rolls away from where it was laid. The rod is the registered body ``ribbon``;
    its run (``run_ribbon``, the body's runner) steps the rod with contact and friction and writes
    history.csv (centroid, spin, temperature).

Equations
    Discrete elastic rods (Bergou et al. 2008): stretching, bending and twisting energies of a
    centre-line with a material frame per edge, E = sum_e k_s (|e|/|e_0| - lambda_s)^2 |e_0| / 2 +
    sum_i (kappa_i - kappa_s,i)^T B (kappa_i - kappa_s,i) / (2 l_i)
    + sum_i GJ (tau_i - tau_0)^2 / (2 l_i),
    the natural stretch and curvature following the LCE's spontaneous stretch lambda_s(T) across
    the thickness; penalty contact with the plate, regularised Coulomb friction; lumped heat per
    edge from the plate (contact conductance) and the air.

Key number
    The distance the centroid moved on the plate in 15 s [mm] (stored value; the ribbon starts
    rolling after about 4 s, when its lower side has passed the transition).

Run: ``python docs/examples/ex04_rolling_ribbon.py`` (the same at ``LCEFEM_EXAMPLE_QUICK=1``: a few
seconds once the rod's kernels are compiled, about 40 s the first time; output in
``results/examples/ex04_rolling_ribbon`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

import matplotlib

from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig, RibbonRun
from lcefem.solvers.registry import body

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex04_rolling_ribbon"
DURATION = 15.0  # [s] on the plate

config = RibbonConfig(
    run=RibbonRun(ground_temperature=100.0, duration=DURATION, output_interval=0.0)
)
ribbon = body("ribbon").runner()(config, OUT, progress=False)  # a RibbonResult
h = ribbon.history

fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
a.plot(h["time [s]"], h["centroid_x [mm]"] - h["centroid_x [mm]"][0], "-", label="x")
a.plot(h["time [s]"], h["centroid_y [mm]"] - h["centroid_y [mm]"][0], "--", label="y")
a.set(xlabel="time [s]", ylabel="centroid displacement [mm]", title="on the plate (100 C)")
a.legend()
b.plot(h["time [s]"], h["T_mean [C]"], "-")
b.set(xlabel="time [s]", ylabel="mean temperature [C]", title="the ribbon heats")
fig.tight_layout()
fig.savefig(OUT / "ex04_rolling_ribbon.png", dpi=100)

result = float(ribbon.metrics["total_distance [mm]"])
print(f"average speed [mm/s] = {float(ribbon.metrics['average_speed [mm/s]'])!r}")
print(f"centroid distance after {DURATION:g} s [mm] = {result!r}")
