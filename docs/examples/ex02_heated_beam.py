"""Example 2: the composite beam (Fig. 3) in 3D FE, bent by a coil current in its bottom strips.

What it shows
    A Kapton ribbon with LCE strips bonded above and below it through pads. A 0.2 A coil current
    heats the bottom strips; as they pass the nematic-isotropic transition they contract and the
    beam curls. The heated FE beam is the registered body ``beam-fe`` with ``heat_run.current > 0``;
    the run goes through the one door with its default program (the current against time) and a
    ``History`` export.

Equations
    Heat:  rho c dT/dt = div(k grad T) + I^2 R / V_strip in the heated strips, convection and
    radiation on every exterior face.
    Mechanics: W_Kapton(F) + W_LCE(F F_s(T)^-1), F_s the spontaneous stretch of the nematic
    transition along the strip; each time step followed from the old to the new temperature by the
    path follower.
    Curvature: kappa [1/mm] of a circle fitted to the ribbon's mid-line.

Key number
    The curvature at the end of the run [1/mm] (a stored value; quick: 2 segments, level 0, 3 s).

Run: ``python docs/examples/ex02_heated_beam.py`` (``LCEFEM_EXAMPLE_QUICK=1``: 3 s of heating
instead of 12 s; output in ``results/examples/ex02_heated_beam`` or ``$LCEFEM_EXAMPLE_OUT``). Also
under MPI: ``mpiexec -n 2 python docs/examples/ex02_heated_beam.py`` (the same curvature: each
station is read on the rank that owns its node; rank 0 writes the history and draws the figure).
"""

import os
import pathlib

from mpi4py import MPI

import matplotlib
import numpy as np

from lcefem.meshes.composite_beam import CompositeBeamGeometry
from lcefem.meshes.composite_beam_fe import BeamFEMesh
from lcefem.solvers.exports import History
from lcefem.solvers.problems.composite_beam import HeatedBeamRun
from lcefem.solvers.problems.composite_beam_run import BeamFEConfig
from lcefem.solvers.registry import body
from lcefem.solvers.runner import run

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUICK = os.environ.get("LCEFEM_EXAMPLE_QUICK") == "1"
OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex02_heated_beam"
DURATION = 3.0 if QUICK else 12.0  # [s]

beam_body = body("beam-fe")
config = BeamFEConfig(
    heat_run=HeatedBeamRun(current=0.2, heated="bottom", duration=DURATION, dt=1.0),
    geometry=CompositeBeamGeometry(segments=2),
    mesh=BeamFEMesh(level=0),
)
beam = beam_body.build(config)  # a HeatedBeamFE: the current flows in the bottom strips
run(
    beam,
    beam_body.default_program(config),
    [History()],
    OUT,
    config=config.resolved(),
    progress=None,
)

history = np.genfromtxt(OUT / "history.csv", delimiter=",", names=True)
t = history["time_s"]
if MPI.COMM_WORLD.rank == 0:  # every rank reads the history, rank 0 draws
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
    a.plot(t, history["T_mean_bottom_strips_C"], "o-", label="bottom strips (heated)")
    a.plot(t, history["T_mean_top_strips_C"], "s-", label="top strips")
    a.set(xlabel="time [s]", ylabel="mean temperature [C]", title="0.2 A in the bottom strips")
    a.legend()
    b.plot(t, history["curvature_1mm"], "o-")
    b.set(xlabel="time [s]", ylabel="curvature [1/mm]", title="the beam curls")
    fig.tight_layout()
    fig.savefig(OUT / "ex02_heated_beam.png", dpi=100)

result = float(history["curvature_1mm"][-1])
print(f"curvature at {DURATION:g} s [1/mm] = {result!r}")
