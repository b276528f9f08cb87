"""Example 1: the LCE strip heated by its coil (seed 001, Fig. 2), through the one door.

What it shows
    A free strip (one end clamped) whose embedded coil carries 0.2 A. Joule heat raises its
    temperature; above the nematic-isotropic transition the strip contracts. The run goes through
    ``lcefem.solvers.runner.run(problem, program, exports, out)``: the body's registration builds
    the problem, a ``Program`` holds the current against time, ``History`` and ``Probe`` exports
    write what we plot.

Equations
    Heat (backward Euler in time):  rho c dT/dt = div(k grad T) + q_coil - h (T - T_amb) on the
    skin,
    q_coil = I^2 R / V_coil  [mW/mm^3].
    Mechanics (quasi-static, each step):  W(F F_s(T)^-1) minimised, with the spontaneous stretch
    F_s = diag(lambda_s, lambda_s^-1/2, lambda_s^-1/2) along the director and lambda_s(T) the
    nematic transition (1 at high T, lambda_N = 1.426 in the nematic state).

Key number
    The strip's stretch L / L_iso [-] at the end of the run (quick: 4 s, level 0; the golden value
    of tests/regression/test_golden.py).

Run: ``python docs/examples/ex01_strip.py`` (``LCEFEM_EXAMPLE_QUICK=1``: 4 s of heating instead of
20 s; output in ``results/examples/ex01_strip`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

from mpi4py import MPI

import matplotlib
import numpy as np

from lcefem.meshes.strip import StripMesh
from lcefem.solvers.exports import History, Probe
from lcefem.solvers.problems.strip import StripConfig, StripRun
from lcefem.solvers.program import Program
from lcefem.solvers.registry import body
from lcefem.solvers.runner import run

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUICK = os.environ.get("LCEFEM_EXAMPLE_QUICK") == "1"
OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex01_strip"
DURATION, DT = (4.0, 2.0) if QUICK else (20.0, 1.0)  # [s]

# The body from its registration: configuration class and problem factory.
strip_body = body("strip")
config = StripConfig(run=StripRun(current=0.2, bc="free"), mesh=StripMesh(level=0))
strip = strip_body.build(config)

# 0.2 A in the coil for DURATION seconds; the history and the temperature at the strip's centre.
program = Program.in_time({"coil": 0.2}, duration=DURATION, dt=DT)
centre = (0.5 * strip.dims["length"], 0.0, 0.0)
exports = [History(), Probe("centre.csv", "temperature [C]", centre)]
summary = run(strip, program, exports, OUT, config=config.resolved(), progress=None)

# Every rank reads the finished history; rank 0 draws the figure.
history = np.genfromtxt(OUT / "history.csv", delimiter=",", names=True)
t, stretch, t_max = history["time_s"], history["stretch_"], history["T_max_C"]
if MPI.COMM_WORLD.rank == 0:
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
    a.plot(t, t_max, "o-", label="max")
    a.plot(t, history["T_mean_C"], "s-", label="mean")
    a.set(xlabel="time [s]", ylabel="temperature [C]", title="coil at 0.2 A")
    a.legend()
    b.plot(t, stretch, "o-")
    b.set(xlabel="time [s]", ylabel="stretch L / L_iso [-]", title="free strip contracts")
    fig.tight_layout()
    fig.savefig(OUT / "ex01_strip.png", dpi=100)

result = float(stretch[-1])
print(f"stretch at {DURATION:g} s [-] = {result!r}")
