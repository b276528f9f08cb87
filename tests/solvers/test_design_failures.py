"""The design loop (solvers/bar_hinge/design.solve_design) across design points without an
equilibrium: a trial point where the forward solve fails is a rejected step, not the end of the
design. A fake equilibrium map with obs(p) = p^2 and no equilibrium for p in a band stands for the
gridshell dome, whose ramp from as built meets a fold at some lambdas."""

import numpy as np
import pytest

from lcefem.models.errors import ConvergenceError
from lcefem.solvers.bar_hinge.design import ForwardStats, solve_design


class HoleMap:
    """obs(p) = p^2, d obs/dp = 2 p; no equilibrium for ``lo`` < p < ``hi``."""

    def __init__(self, lo: float, hi: float):
        self.lo, self.hi, self.stats, self.hits = lo, hi, ForwardStats(), 0

    def state(self, p, jacobian: bool = True):
        p = np.asarray(p, dtype=float)
        if self.lo < p[0] < self.hi:
            self.hits += 1
            raise ConvergenceError("fake ramp", "fold")
        self.stats.solves += 1
        return type(
            "S",
            (),
            {"p": p, "observables": p**2, "jacobian": np.diag(2.0 * p) if jacobian else None},
        )()


def test_a_trial_without_equilibrium_is_rejected_and_the_design_still_reaches_its_target():
    # From 1.05 the first trial step towards 1.28^2 (dogbox's Gauss-Newton step, design.METHOD)
    # overshoots to 1.3052, inside the band (1.30, 1.31): rejected, the trust region shrinks, and
    # the design reaches the target from below the band.
    eq = HoleMap(1.30, 1.31)
    res = solve_design(eq, [1.28**2], [1.05], 1.05, 1.4, absolute=1e-9)
    assert eq.hits >= 1
    assert res.p[0] == pytest.approx(1.28, abs=1e-6)
    assert res.residual[0] == pytest.approx(0.0, abs=1e-8)


def test_no_equilibrium_at_the_start_is_an_error():
    with pytest.raises(ConvergenceError):
        solve_design(HoleMap(1.0, 1.3), [1.5], [1.2], 1.05, 1.4)
