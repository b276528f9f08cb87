"""Example 7: your own robot from a mesh and a case file, here the LCE strip of seed 001.

What it shows
    A new body needs no Python: a gmsh geometry with named physical groups and a TOML case file
    (regions with their director and transition, coils, heat boundary conditions, supports,
    probes, a program). ``lcefem run body --config case.toml`` runs it; from Python the same is
    ``load_case`` (every value checked, one line naming the key on bad input) and ``run_body``.
    The case is ``examples/bodies/strip/case.toml``: the free strip of Example 1, written out.

Equations
    The same thermo-mechanics as Example 1: heat with Joule sources in the coil regions and the
    case's convection/radiation boundaries; quasi-static W(F F_s(T)^-1) with the spontaneous
    stretch of each region's transition along its director.

Key number
    The maximum temperature at the end of the run [C] (stored value; quick: 2 s at size factor 1).

Run: ``python docs/examples/ex07_own_robot.py`` (``LCEFEM_EXAMPLE_QUICK=1``: 2 s instead of 20 s on
the coarser mesh; output in ``results/examples/ex07_own_robot`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

from mpi4py import MPI

import matplotlib
import numpy as np

from lcefem.solvers.problems.body import run_body
from lcefem.solvers.problems.body_case import load_case

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUICK = os.environ.get("LCEFEM_EXAMPLE_QUICK") == "1"
OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex07_own_robot"
CASE = pathlib.Path(__file__).resolve().parents[2] / "examples" / "bodies" / "strip" / "case.toml"

# Command-line style overrides {(section, key): value}, checked like the file's own values.
overrides = {("mesh", "size_factor"): 1.0, ("program", "duration"): 2.0} if QUICK else {}
case = load_case(CASE, overrides=overrides)
result_run = run_body(case, OUT, progress=False)

# Every rank reads the finished history; rank 0 draws the figure.
history = np.genfromtxt(OUT / "history.csv", delimiter=",", names=True)
if MPI.COMM_WORLD.rank == 0:
    fig, ax = plt.subplots(figsize=(5.5, 3.4))
    ax.plot(history["time_s"], history["T_max_C"], "o-", ms=3, label="T_max")
    ax.plot(history["time_s"], history["T_mean_C"], "s-", ms=3, label="T_mean")
    ax.set(
        xlabel="time [s]",
        ylabel="temperature [C]",
        title="own robot: examples/bodies/strip at 0.2 A",
    )
    ax.legend()
    fig.tight_layout()
    fig.savefig(OUT / "ex07_own_robot.png", dpi=100)

result = float(history["T_max_C"][-1])
power = float(history["power_coil_mW"][-1])  # Joule power I^2 R = 0.2^2 x 146.6 ohm = 5864 mW
print(f"coil power [mW] = {power!r}")
print(f"T_max at the end [C] = {result!r}")
