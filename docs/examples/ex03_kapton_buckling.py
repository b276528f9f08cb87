"""Example 3: the Kapton ribbon's buckling test (seed 001, Fig. 2G), bar-and-hinge and 3D FE.

What it shows
    A Kapton ribbon clamped at both ends is shortened (displacement control). It stays straight
    until the Euler load of a fixed-fixed column, then buckles and the force plateaus. The
    bar-and-hinge specimen (the registered body ``ribbon-buckling``) runs its shortening through the
    one door with its body's run; the FE specimen (``ribbon-buckling-fe``) gives the linearised
    buckling load (an eigenvalue problem, SLEPc). Both are compared with the closed form.

Equations
    Euler load of a fixed-fixed column:  P_cr = 4 pi^2 E I / L^2,  I = w t^3 / 12.
    Bar-and-hinge: the ribbon is a chain of panels (N5B8: five nodes, eight bars per panel) whose
    fold hinges carry the bending stiffness; its own E I follows from the hinge stiffness
    (``closed_forms``). Its critical load is where the tangent stiffness first loses positive
    definiteness along the straight path (negative pivots, bisection).
    FE: (K_0 + P K_sigma) phi = 0 on the Q2 hexahedral mesh, the smallest P.

Key number
    The bar-and-hinge critical load over the chain's Euler load [-] (close to 1).

Run: ``python docs/examples/ex03_kapton_buckling.py`` (``LCEFEM_EXAMPLE_QUICK=1``: shortening to 5 %
instead of 50 %; output in ``results/examples/ex03_kapton_buckling`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

from mpi4py import MPI

import matplotlib
import numpy as np

from lcefem.meshes.kapton_ribbon import KaptonFEMesh
from lcefem.solvers.problems.kapton_specimen import KaptonSpecimenFEConfig
from lcefem.solvers.problems.kapton_specimen_bh import (
    KaptonSpecimenConfig,
    KaptonSpecimenRun,
    closed_forms,
    critical_load,
)
from lcefem.solvers.registry import body

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUICK = os.environ.get("LCEFEM_EXAMPLE_QUICK") == "1"
OUT = (
    pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex03_kapton_buckling"
)
COMPRESSION = 0.05 if QUICK else 0.5  # end shortening / length [-]

# Bar-and-hinge: the shortening path (history.csv: compression, force) and the bifurcation load.
# The chain is a serial model: under mpiexec rank 0 runs its path (one folder, one writer) and
# every rank finds the same bifurcation load; the FE specimen below is shared by the ranks.
config = KaptonSpecimenConfig(run=KaptonSpecimenRun(compression=COMPRESSION))
if MPI.COMM_WORLD.rank == 0:
    body("ribbon-buckling").runner()(config, OUT / "bar_hinge", progress=False)
p_bh, shortening_bh = critical_load(config.specimen, config.mesh, config.materials)
euler = closed_forms(config)

# 3D FE (level 0): the linearised buckling load of the perfect specimen.
fe_config = KaptonSpecimenFEConfig(mesh=KaptonFEMesh(level=0))
specimen_fe = body("ribbon-buckling-fe").build(fe_config.specimen, fe_config.mesh)
p_fe = specimen_fe.critical_load().force

if MPI.COMM_WORLD.rank == 0:  # rank 0 wrote the bar-and-hinge history and draws
    history = np.genfromtxt(OUT / "bar_hinge" / "history.csv", delimiter=",", names=True)
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    ax.plot(history["compression_"], history["force_N"], "-", label="bar-and-hinge path")
    for name, value in euler.items():
        ax.axhline(value, ls=":", lw=1, color="grey")
        ax.annotate(name, (COMPRESSION, value), ha="right", va="bottom", fontsize=7)
    ax.axhline(p_fe, ls="--", color="C1", label=f"FE linearised buckling (level 0): {p_fe:.3f} N")
    ax.plot(
        [shortening_bh / config.specimen.length],
        [p_bh],
        "ko",
        label=f"bar-and-hinge bifurcation: {p_bh:.3f} N",
    )
    ax.set(
        xlabel="end shortening / length [-]",
        ylabel="compressive force [N]",
        title="Kapton ribbon buckling",
    )
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(OUT / "ex03_kapton_buckling.png", dpi=100)

result = p_bh / euler["Euler, bar-and-hinge chain EI"]
print(f"bar-and-hinge critical load [N] = {p_bh!r}")
print(f"FE (level 0) linearised buckling load [N] = {p_fe!r}")
print(f"bar-and-hinge critical load / chain Euler load [-] = {result!r}")
