"""Example 10: closed-loop shape control of the robotic surface.

What it shows
    A simulated surface (the plant: the bar-and-hinge gridshell of Example 5, every strip a
    lumped coil-heated segment whose resistance, current factor and lambda_N are drawn from the
    measured spreads) is driven from flat to the Fig. 4 dome by four channel currents. Open loop,
    the nominal feed-forward currents miss the dome because the real strips differ from the
    nominal one; closed loop, a model-based controller fed by a noisy curvature sensor corrects
    the currents. ``lcefem.solvers.control``: ``build_surface`` (the target's equilibrium and its
    exact sensitivities), ``draw_plant``, ``simulate``.

Equations
    Strip heat (implicit Euler):  C dT/dt = I^2 R_j - G (T - T_amb),
    lambda_j = min(lambda_s(T), lambda_N,j).
    Surface: y(p) = y(p_a) + J (p - p_a) between full equilibria at anchor instants.
    Controller (internal-model control):
    disturbance d = kappa_measured - (kappa* + J_k,u (p_hat - p*)),
    low-pass filtered; reference p_ref = p* + argmin |J_k,u dp + d_f|^2 + mu |dp|^2; current =
    holding current of p_ref + K (T_ref - T_hat), clipped to the paper's limits.
    Error: e = max |kappa - kappa*| of the two circle curvatures [1/mm].

Key number
    The closed loop's error at the end of the settling phase [1/mm]; it must be well below the
    open loop's (stored value; quick: 120 s settling on the tangent map, normal: 300 s with
    re-anchoring full solves).

Run: ``python docs/examples/ex10_control.py`` (``LCEFEM_EXAMPLE_QUICK=1``: the short scenario;
output in ``results/examples/ex10_control`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

import matplotlib

from lcefem.models.shape_control import PlantSpread
from lcefem.solvers import control
from lcefem.validation.cases.programs import SHAPE_DRIVES

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUICK = os.environ.get("LCEFEM_EXAMPLE_QUICK") == "1"
OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex10_control"
OUT.mkdir(parents=True, exist_ok=True)
if QUICK:
    scenario = control.Scenario(settle=120.0, load_phase=0.0, failure_phase=0.0, refine=0.0)
else:
    scenario = control.Scenario(settle=300.0, load_phase=0.0, failure_phase=0.0)

surface = control.build_surface("dome", SHAPE_DRIVES["dome"])
plant = control.draw_plant(surface, PlantSpread(), seed=2)  # one drawn set of real strips
loops = {
    name: control.simulate(surface, plant, feedback=feedback, scenario=scenario, seed=1)
    for name, feedback in (("open loop", False), ("closed loop", True))
}

fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
for name, r in loops.items():
    a.semilogy(r.times, r.errors, label=name)
    b.plot(r.times, r.inputs, lw=1)
a.set(xlabel="time [s]", ylabel="curvature error [1/mm]", title="from flat to the dome")
a.legend()
b.set(xlabel="time [s]", ylabel="channel currents [A] (both loops)", title="inputs")
fig.tight_layout()
fig.savefig(OUT / "ex10_control.png", dpi=100)

open_error = loops["open loop"].phase_errors["target"]
result = loops["closed loop"].phase_errors["target"]
print(f"open-loop error [1/mm] = {open_error!r}")
print(f"closed-loop error [1/mm] = {result!r}")
