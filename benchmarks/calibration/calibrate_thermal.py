"""Calibrate the heat-exchange and transition parameters against seed 001's strip measurements.

Free parameters (with bounds from shared/reference/materials.md):
    T_NI [C] and transition width w [K] of Q(T) (models.lce), convective film coefficient h
    [W/(m^2 K)], specific heat c [J/(g K)].
Targets (seed 001, 'Actuation of the LCE strips'):
    Eq. 1 at the six hold currents 0.04-0.09 A (P = I^2 R), weight 1/0.01 in stretch;
    at 0.2 A the surface reaches T_NI 'within 10 s' (10 +- 2 s) and full contraction takes
    'about 20 s' (20 +- 3 s, taken as 95 % of lambda_N -> 1); at 0.1 A 'almost 120 s' (120 +- 15 s);
    T_NI '~70 C' as a prior (70 +- 5 C).
Model used inside the fit (fast surrogate): the 3D FE heat equation on the quarter strip mesh,
pulled back with the homogeneous free contraction a = lambda/lambda_N of the current mean
temperature field, with stretch = lambda_N mean(a(T)). The fitted set is then checked with the full
coupled thermo-mechanical model and both are written to validation/data/thermal_calibration.json.

Run:  .venv/bin/python benchmarks/calibration/calibrate_thermal.py [--no-check]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib
import time

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

import numpy as np
import ufl
from scipy.optimize import least_squares

import dolfinx

from lcefem.meshes.strip import StripGeometry, StripMesh, build_strip_mesh
from lcefem.models import units
from lcefem.models.empirical import eq1_stretch
from lcefem.models.heat import Coil, SurfaceExchange, ThermalProperties
from lcefem.models.lce import NematicTransition, contraction_ratio
from lcefem.solvers.heat import HeatProblem, HeatSetup

OUT = (
    pathlib.Path(__file__).resolve().parents[2] / "validation" / "data" / "thermal_calibration.json"
)
HOLD_CURRENTS = (0.04, 0.05, 0.06, 0.07, 0.08, 0.09)  # A, seed 001 Fig. 2C text
TARGETS = {  # name: (value, sigma, unit, source)
    "t_NI_0.2A": (10.0, 2.0, "s", "seed 001: 'reach T_NI (~70 C) within 10 s' at 0.2 A"),
    "t_full_0.2A": (20.0, 3.0, "s", "seed 001: 'about 20 s until full contraction' at 0.2 A"),
    "t_full_0.1A": (120.0, 15.0, "s", "seed 001: '0.1-A current requires almost 120 s'"),
    "T_NI_prior": (70.0, 5.0, "C", "seed 001: 'T_NI (~70 C)'"),
}
EQ1_SIGMA = 0.01  # stretch; Eq. 1 is a fit to data with SD bands of about this size (Fig. 2C)
NAMES = ("T_NI [C]", "width [K]", "h [W/(m^2 K)]", "c [J/(g K)]")
BOUNDS = ([55.0, 1.0, 2.0, 1.5], [80.0, 15.0, 25.0, 2.0])


class Surrogate:
    """Heat-only strip model with the homogeneous free contraction (see module docstring)."""

    def __init__(self, coil: Coil = Coil(), transition: NematicTransition = NematicTransition()):
        self.coil = coil
        self.lambda_N = transition.lambda_N
        self.tm = build_strip_mesh(StripGeometry(), self.lambda_N, StripMesh())
        info = self.tm.info
        mesh = self.tm.mesh
        Vu = dolfinx.fem.functionspace(mesh, ("Lagrange", 1, (3,)))
        self.u = dolfinx.fem.Function(Vu)
        setup = HeatSetup(
            ThermalProperties(),
            SurfaceExchange(),
            heated_cells=["coil"],
            exposed_facets=["sides", "end"],
        )
        self.heat = HeatProblem(self.tm, setup, displacement=self.u, prefix="calib_heat_")
        self.coil_volume = info["coil_area"] * info["length"]
        self.W, self.H = info["width"], info["thickness"]
        # Lumped volume weights of the temperature nodes, for volume means of nonlinear functions of
        # T.
        w = ufl.TestFunction(self.heat.V)
        vec = dolfinx.fem.assemble_vector(dolfinx.fem.form(w * ufl.dx(domain=mesh)))
        self.weights = vec.array[: self.heat.V.dofmap.index_map.size_local].copy()
        self.weights /= self.weights.sum()

    def set_parameters(self, x) -> NematicTransition:
        T_NI, width, h, c = x
        thermal = ThermalProperties(specific_heat=c * units.J_PER_G_K)
        exchange = SurfaceExchange(film_coefficient=h * units.W_PER_M2_K)
        self.heat.set_materials(thermal, exchange)
        return NematicTransition(T_NI=T_NI, width=width)

    def _deform(self, a: float) -> None:
        b = a**-0.5
        W2, H2 = 0.5 * self.W, 0.5 * self.H
        self.u.interpolate(
            lambda X: np.vstack(
                [(a - 1.0) * X[0], (b - 1.0) * (X[1] - W2), (b - 1.0) * (X[2] - H2)]
            )
        )

    def _mean_ratio(self, transition) -> float:
        T = self.heat.T.x.array[: len(self.weights)]
        return float(np.dot(self.weights, contraction_ratio(T, transition)))

    def _reset(self, current: float) -> None:
        self.heat.T.x.array[:] = 25.0
        self.heat.power_density.value = self.coil.power(current) / self.coil_volume
        self._deform(1.0)

    def steady_stretch(self, current: float, transition) -> float:
        self._reset(current)
        a = 1.0
        for _ in range(50):
            self.heat.steady()
            a_new = self._mean_ratio(transition)
            self._deform(a_new)
            if abs(a_new - a) < 1e-9:
                break
            a = a_new
        return self.lambda_N * a_new

    def transient(self, current: float, transition, duration: float, dt: float = 0.5):
        """Times [s]: surface reaching T_NI and 95 % contraction (nan when not reached)."""
        self._reset(current)
        sides = self.tm.facet_tags.find(self.tm.facet_tag("sides"))
        side_dofs = dolfinx.fem.locate_dofs_topological(self.heat.V, 2, sides)
        target = self.lambda_N - 0.95 * (self.lambda_N - 1.0)
        t_NI = t_95 = float("nan")
        prev = (0.0, 25.0, self.lambda_N)
        for n in range(1, int(round(duration / dt)) + 1):
            self.heat.step(dt)
            a = self._mean_ratio(transition)
            self._deform(a)
            t, Ts, lam = n * dt, float(np.mean(self.heat.T.x.array[side_dofs])), self.lambda_N * a
            if np.isnan(t_NI) and Ts >= transition.T_NI:
                t_NI = prev[0] + dt * (transition.T_NI - prev[1]) / (Ts - prev[1])
            if np.isnan(t_95) and lam <= target:
                t_95 = prev[0] + dt * (prev[2] - target) / (prev[2] - lam)
                break
            prev = (t, Ts, lam)
        return t_NI, t_95


def residuals(x, model: Surrogate, coil: Coil) -> np.ndarray:
    tr = model.set_parameters(x)
    res = []
    for current in HOLD_CURRENTS:
        target = float(eq1_stretch(coil.power(current)))
        res.append((model.steady_stretch(current, tr) - target) / EQ1_SIGMA)
    t_NI, t_full = model.transient(0.2, tr, 40.0)
    _, t_full_01 = model.transient(0.1, tr, 250.0, dt=1.0)
    for value, key in (
        (t_NI, "t_NI_0.2A"),
        (t_full, "t_full_0.2A"),
        (t_full_01, "t_full_0.1A"),
        (x[0], "T_NI_prior"),
    ):
        ref, sigma = TARGETS[key][:2]
        res.append((value - ref) / sigma if np.isfinite(value) else 10.0)
    return np.array(res)


def check_with_full_model(x) -> dict:
    """Steady stretch at the hold currents and the two transients with the coupled FE model."""
    from lcefem.solvers.problems.strip import (
        StripConfig,
        StripRun,
        StripSimulation,
        transient_metrics,
    )
    from lcefem.validation.cases.programs import SEED_T_NI

    T_NI, width, h, c = x
    base = StripConfig(
        transition=NematicTransition(T_NI=T_NI, width=width),
        thermal=ThermalProperties(specific_heat=c * units.J_PER_G_K),
        exchange=SurfaceExchange(film_coefficient=h * units.W_PER_M2_K),
    )
    out = {"steady": []}
    for current in HOLD_CURRENTS:
        sim = StripSimulation(dataclasses.replace(base, run=StripRun(current=current)))
        obs = sim.steady_state()
        target = float(eq1_stretch(base.coil.power(current)))
        out["steady"].append(
            {
                "current [A]": current,
                "stretch [-]": obs["stretch [-]"],
                "eq1 [-]": target,
                "T_mean [C]": obs["T_mean [C]"],
            }
        )
    for current, duration, dt in ((0.2, 30.0, 0.5), (0.1, 180.0, 1.0)):
        sim = StripSimulation(
            dataclasses.replace(base, run=StripRun(current=current, duration=duration, dt=dt))
        )
        res = sim.run(None, progress=False)
        out[f"transient_{current}A"] = transient_metrics(res.history, base.transition, SEED_T_NI)
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-check", action="store_true", help="skip the full-model check")
    args = parser.parse_args(argv)
    coil = Coil()
    model = Surrogate(coil)
    x0 = np.array([70.0, 5.5, 10.0, 1.75])  # the uncalibrated starting point
    started = time.perf_counter()
    fit = least_squares(
        residuals,
        x0,
        args=(model, coil),
        bounds=BOUNDS,
        diff_step=1e-3,
        x_scale=np.array([5.0, 2.0, 5.0, 0.2]),
    )
    x = fit.x
    print(
        f"fit in {time.perf_counter() - started:.0f} s, cost {fit.cost:.4g}, {fit.nfev} evaluations"
    )
    for name, value in zip(NAMES, x):
        print(f"  {name:16s} {value:.4g}")
    labels = [f"eq1 {i} A" for i in HOLD_CURRENTS] + list(TARGETS)
    for label, r in zip(labels, fit.fun):
        print(f"  residual/sigma {label:14s} {r:+.3f}")
    result = {
        "parameters": dict(zip(NAMES, map(float, x))),
        "residuals_over_sigma": dict(zip(labels, map(float, fit.fun))),
        "targets": TARGETS,
        "eq1_sigma": EQ1_SIGMA,
        "bounds": dict(zip(NAMES, zip(*BOUNDS))),
        "fixed": {
            "conductivity [W/(m K)]": ThermalProperties().conductivity,
            "density [g/cm^3]": ThermalProperties().density / units.G_PER_CM3,
            "emissivity [-]": SurfaceExchange().emissivity,
            "resistance [ohm]": coil.resistance,
        },
    }
    if not args.no_check:
        result["full_model_check"] = check_with_full_model(x)
        print(json.dumps(result["full_model_check"], indent=1))
    tmp = OUT.with_suffix(".json.part")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    tmp.replace(OUT)
    print(f"written {OUT}")


if __name__ == "__main__":
    main()
