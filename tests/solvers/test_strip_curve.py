"""The FE strip with a measured contraction curve ([lce] curve, issue 44), at the coarsest mesh
(level 0) for 6 s at 0.2 A (dt 1 s: the mean temperature rises 25 -> 50 C, through the sigmoid's
onset).

- A table sampled from the present sigmoid reproduces the sigmoid's strip within the interpolation
  error, and the difference falls quadratically with the row spacing (measured: max |stretch
  difference| over the history 1.91e-3, 4.63e-4, 1.26e-4 at 8, 4, 2 K; ratios 4.1, 3.7).
- A curve with a steeper onset (same amplitude, same onset temperature) contracts the strip earlier
  (measured: 1 % contraction at 0.33 s against 1.44 s; stretch 1.099 against 1.331 at 6 s).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)

import numpy as np
import pytest

from lcefem.meshes.strip import StripMesh
from lcefem.models.lce import MeasuredContraction, NematicTransition, spontaneous_stretch
from lcefem.solvers.contraction_curve import LCECurve, write_contraction_csv
from lcefem.solvers.problems.strip import StripConfig, StripRun, StripSimulation, first_crossing

RUN = StripRun(current=0.2, duration=6.0, dt=1.0)


def history(curve: str = "") -> dict:
    cfg = StripConfig(run=RUN, mesh=StripMesh(level=0), lce=LCECurve(curve=curve))
    return StripSimulation(cfg).run(None, progress=False).history


@pytest.fixture(scope="module")
def sigmoid_history():
    return history()


def test_sampled_sigmoid_converges_quadratically_to_the_sigmoid_strip(sigmoid_history, tmp_path):
    tr = NematicTransition()
    differences = []
    for h in (8.0, 4.0, 2.0):
        T = np.arange(0.0, 200.0 + 0.5 * h, h)
        curve = MeasuredContraction.from_rows(
            T, spontaneous_stretch(T, tr), source=f"sigmoid every {h:g} K"
        )
        h_history = history(str(write_contraction_csv(tmp_path / f"sigmoid_{h:g}.csv", curve)))
        # same heat problem: the temperatures differ only through the deformed geometry
        np.testing.assert_allclose(
            h_history["T_mean [C]"], sigmoid_history["T_mean [C]"], rtol=1e-4
        )
        differences.append(
            float(np.max(np.abs(h_history["stretch [-]"] - sigmoid_history["stretch [-]"])))
        )
    ratios = [a / b for a, b in zip(differences, differences[1:])]
    assert all(3.0 < r < 5.5 for r in ratios), (differences, ratios)
    # the contraction itself (1.426 -> 1.360) is 30-500 x the table's error
    contraction = sigmoid_history["stretch [-]"][0] - sigmoid_history["stretch [-]"][-1]
    assert differences[-1] < 5e-3 * contraction


def test_steeper_onset_contracts_the_strip_earlier(sigmoid_history, tmp_path):
    """Two curves with the sigmoid's lambda_N, flat to 30 C, then linear to the isotropic length: at
    45 C (steep) or at 120 C (gentle). At the same current the steep one's stretch is below the
    gentle one's at every step after the onset, and it passes 1 % contraction earlier."""
    lam_n = NematicTransition().lambda_N
    runs = {}
    for name, end in (("steep", 45.0), ("gentle", 120.0)):
        curve = MeasuredContraction.from_rows(
            [25.0, 30.0, end, 200.0], [lam_n, lam_n, 1.0, 1.0], source=name
        )
        runs[name] = history(str(write_contraction_csv(tmp_path / f"{name}.csv", curve)))
    steep, gentle = runs["steep"]["stretch [-]"], runs["gentle"]["stretch [-]"]
    assert steep[0] == pytest.approx(lam_n, rel=1e-12) and gentle[0] == pytest.approx(
        lam_n, rel=1e-12
    )
    after_onset = runs["steep"]["T_mean [C]"] > 31.0
    assert np.all(steep[after_onset] < gentle[after_onset])
    t = runs["steep"]["time [s]"]
    level = 0.99 * lam_n
    assert first_crossing(t, steep, level, rising=False) < first_crossing(
        t, gentle, level, rising=False
    )
