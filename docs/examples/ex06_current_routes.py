"""Example 6: from a coil current to a strip's lambda, three routes behind one interface.

What it shows
    The gridshell's strips are driven by coil currents, the bar-and-hinge model by lambdas. The
    ``CurrentRoute`` protocol (``lcefem.solvers.current_routes``) maps {selection: current [A]} to
    {selection: steady lambda [-]}; this example compares the lumped heat balance of one grid strip
    (``LumpedRoute``, the default route of ``lcefem run gridshell --route current``) with the
    paper's own estimate (``Eq1Route``, Eq. 1 at the coil's Joule power) over 0 - 0.2 A, and reads
    off the lambdas of the Fig. 4 dome's hold currents. (The third route, ``FEHeatedRoute``, holds
    the 3D FE heated gridshell at the currents; it takes minutes and is left out here.)

Equations
    Lumped strip, steady:  I^2 R = h_eff A (T - T_amb) + eps sigma A (T^4 - T_amb^4),
    lambda = min(lambda_s(T), lambda_N),  lambda_s(T) the calibrated nematic transition.
    Eq. 1 (seed 001):  lambda = 1 + gamma_1 (1 - tanh(gamma_2 (P - gamma_3))) / 2 style fit of the
    measured contraction against the Joule power P = I^2 R [mW], capped at lambda_N.

Key number
    The lumped route's lambda of a grid strip at 0.07 A (the dome's bottom channels) [-], a stored
    value. (At the top channels' 0.04 A the strip stays at lambda_N = 1.4: too little heat to pass
    the transition.)

Run: ``python docs/examples/ex06_current_routes.py`` (seconds; output in
``results/examples/ex06_current_routes`` or ``$LCEFEM_EXAMPLE_OUT``).
"""

import os
import pathlib

import matplotlib
import numpy as np

from lcefem.solvers.current_routes import CurrentRoute, Eq1Route, route_from_config
from lcefem.validation.cases.programs import SHAPE_DRIVES

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = pathlib.Path(os.environ.get("LCEFEM_EXAMPLE_OUT", "results/examples")) / "ex06_current_routes"
OUT.mkdir(parents=True, exist_ok=True)

routes = [route_from_config(), Eq1Route()]  # lumped strip (the default configuration), Eq. 1
assert all(isinstance(r, CurrentRoute) for r in routes)
currents = np.linspace(0.0, 0.2, 81)  # [A]

fig, ax = plt.subplots(figsize=(5.5, 3.6))
for route in routes:
    lam = route.lambdas({f"{i:.4f}": i for i in currents})
    ax.plot(currents, list(lam.values()), label=f"route '{route.name}'")
dome = SHAPE_DRIVES["dome"]["currents"]  # Fig. 4 dome hold currents per channel [A]
held = routes[0].lambdas(dome)
ax.plot(list(dome.values()), list(held.values()), "ko", label="dome's hold currents (lumped)")
ax.set(
    xlabel="coil current [A]", ylabel="steady lambda [-]", title="current -> lambda of a grid strip"
)
ax.legend()
fig.tight_layout()
fig.savefig(OUT / "ex06_current_routes.png", dpi=100)

result = held["Bx"]
print("dome hold currents -> lambdas (lumped):", {k: round(v, 4) for k, v in held.items()})
print(f"lambda at 0.07 A (lumped strip) [-] = {result!r}")
