"""The DisMech benchmark's problem is the same physics in both codes (never its timing).

benchmarks/dismech_benchmark.py: dismech-python's rod cantilever (a 100 x 20 x 1 mm
strip, E = 2 MPa, 51 nodes, the first 10 mm clamped, under its weight). Measured values (this
branch, 2026-12-07): our static tip is 1.50 / 0.79 / 0.41 / 0.21 mm from the heavy elastica at
51 / 101 / 201 / 401 nodes (first order: the lumped node masses and the clamp's half edge); the
Richardson extrapolation of 101 and 201 nodes lands 0.033 mm from it, the rest being the rod's
stretch under its weight, q L^2 / (2 EA) = 0.024 mm (the elastica is inextensible). DisMech's static
tip is 0.0071 mm from ours; their 1 s paths at dt 0.01 s differ by 0.365 % of the tip displacement,
their energies after it by 0.12 %.
"""

import dataclasses
import math

import numpy as np
import pytest

import dismech_benchmark as bench


def test_heavy_elastica_reference_tends_to_the_linear_cantilever():
    """At 1e-4 of the load the elastica's tip sag is q L^4/(8 EI) (Euler-Bernoulli) to 1e-4:
    the second-order term is O((q L^3/EI)^2) ~ 3e-5 of it there."""
    c = bench.StripCantilever()
    light = dataclasses.replace(c, gravity=c.gravity * 1e-4)
    lf = c.length - c.clamped_length
    linear = light.weight_per_length * lf**4 / (8.0 * light.bending_stiffness)
    _, z = bench.heavy_elastica_tip(light)
    assert -z == pytest.approx(linear, rel=1e-4)


def test_our_der_converges_to_the_heavy_elastica():
    c = bench.StripCantilever()
    x_ref, z_ref = bench.heavy_elastica_tip(c)
    scale = math.hypot(c.length - x_ref, z_ref)
    tips = {
        n: np.array(bench.our_static(dataclasses.replace(c, nodes=n))["tip"])
        for n in (51, 101, 201)
    }
    err = {n: float(np.hypot(*(t - (x_ref, z_ref)))) for n, t in tips.items()}
    assert err[51] / scale < 0.016  # measured 1.405 % of the 106.6 mm tip displacement
    assert 1.8 < err[51] / err[101] < 2.1  # first order (measured 1.90)
    assert 1.8 < err[101] / err[201] < 2.1  # (measured 1.92)
    extrapolated = 2.0 * tips[201] - tips[101]
    stretch = (
        c.weight_per_length * (c.length - c.clamped_length) ** 2 / (2.0 * c.youngs_modulus * c.area)
    )
    assert (
        float(np.hypot(*(extrapolated - (x_ref, z_ref)))) < 2.0 * stretch
    )  # measured 0.033 mm, stretch 0.024


def test_dismech_solves_the_same_problem():
    pytest.importorskip("dismech")
    c = bench.StripCantilever()
    ours, peer = bench.our_static(c), bench.dismech_static(c)
    assert float(np.hypot(*np.subtract(ours["tip"], peer["tip"]))) < 0.02  # [mm] measured 0.0071
    x_ref, z_ref = bench.heavy_elastica_tip(c)
    scale = math.hypot(c.length - x_ref, z_ref)
    ours, peer = bench.our_dynamics(c, 0.01), bench.dismech_dynamics(c, 0.01)
    assert (
        bench.path_error(ours["path"], peer["path"], scale) < 0.005
    )  # measured 0.365 % (DisMech stops Newton
    # at |dq| < 0.1 mm per 0.01 s step)
    # the energy implicit Euler leaves after 1 s (0 at the start): -0.6332 / -0.6324 mJ measured
    assert ours["energy_mJ"] == pytest.approx(peer["energy_mJ"], rel=0.003)


def test_bad_target_exits_2(capsys):
    assert bench.main(["--target", "2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--target" in err[0]
