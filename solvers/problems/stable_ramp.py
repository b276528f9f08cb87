"""A load ramp that watches the stability of its path and leaves a lost stability the same way
whatever the step history (issue 47, known disagreement layout_5x5_fold).

:func:`lcefem.solvers.bar_hinge.follow_path` steps the load factor t and, where increments keep
failing (a fold), lets Newton descend from the last converged state to whatever stable state it
finds a little further on: where that happens depends on the increment sequence and on Newton's
settings, and so may the end state. :func:`follow_stable_path` steps exactly as ``follow_path``
does (the same predictor, growth and halving, so a path that meets no instability is the same to
the last bit) and in addition, after every converged increment, computes the lowest eigenpairs
of the tangent K on the free DOFs, leaving out floating modes (:func:`structural_modes`: a mode
with SETTLE_SHARE of |v|^2 on at most SETTLE_MAX_NODES nodes, e.g. the rigid motion of a raised
square on slack strips). Its stability is lambda_s, the lowest eigenvalue left.

* A converged state with lambda_s < ``unstable_stiffness`` (Newton with inertia control accepts a
  saddle whose negative curvature is below its NEGLIGIBLE_CURVATURE): the critical load factor
  t_c is bracketed by bisection between the last stable state and it, to ``critical_tolerance``.
* Increments failing below PathOptions.snap_increment (a fold): t_c is the last converged t.

At t_c the path is left by a branch switch: from the last stable state x_c (at t_lo <= t_c),
Newton (the same options, with the snap-through budget and no early settle) at t_hi = t_lo +
``critical_tolerance`` starts from x_c + s a v for s = +1 and -1, v the critical mode (lowest
structural eigenvector at x_c, its largest component made positive, scaled so that its largest
nodal move is ``kick`` [mm]); of the converged stable candidates the one of least energy is kept
(mirror images tie to round-off; the first, s = +1, is kept then). Both starts are independent of
how x_c was reached, so the state after the switch depends on the path before only through t_c
(to ``critical_tolerance``) and x_c.

Units: mm, N, mJ; the load factor t is dimensionless.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as sla

from lcefem.models.errors import ConvergenceError
from lcefem.models.parameters import check, param
from lcefem.solvers.bar_hinge import (
    BarHingeModel,
    NewtonOptions,
    NewtonResult,
    PathOptions,
    PathResult,
    PathState,
    ReducedHessian,
    newton,
)
from lcefem.solvers.bar_hinge.newton import SETTLE_MAX_NODES, SETTLE_SHARE, path_setup

#: Increments looked ahead by the linear extrapolation of the lowest structural eigenvalue (chosen:
#: on the 5 x 5 dome's symmetric branch it falls linearly, 2.1e-7 N/mm at t = 0.80, 1.24e-7 at
#: 0.82, 8.9e-8 at 0.828, and Newton leaves the branch within the next 0.02 increment with both
#: ends stable, so one increment ahead sees nothing; benchmarks/bh_fold_path.py, 2026-12-07).
LOOK_AHEAD = 2.0


@dataclass(frozen=True)
class StabilityOptions:
    """Stability watch and branch switch of :func:`follow_stable_path` (module docstring)."""

    modes: int = param(
        6,
        "-",
        "chosen: eigenpairs computed per state; the 5 x 5 gridshell's raised squares give up to 4 "
        "floating modes below its lowest structural one (benchmarks/bh_fold_path.py)",
        minimum=1,
    )
    unstable_stiffness: float = param(
        0.0,
        "N/mm",
        "chosen: a state whose lowest structural eigenvalue is below this has lost stability",
    )
    critical_tolerance: float = param(
        1.0e-3,
        "-",
        "chosen: the load-factor bracket of a located critical point (as PathOptions."
        "snap_increment, the resolution of a fold)",
        positive=True,
    )
    kick: float = param(
        0.5,
        "mm",
        "chosen: largest nodal move of the start along the critical mode (a tenth of the "
        "structures' 1-10 mm features; the descent after it is Newton's)",
        positive=True,
    )
    max_switches: int = param(4, "-", "chosen: branch switches per ramp", minimum=0)


@dataclass
class StabilityRecord:
    """The lowest structural eigenvalue [N/mm] at a converged load factor t, and the branch
    switches made (t_lo, t_hi, sign kept, candidates' energies [mJ])."""

    t: list[float] = dataclasses.field(default_factory=list)
    lowest: list[float] = dataclasses.field(default_factory=list)
    switches: list[dict] = dataclasses.field(default_factory=list)


def floating_mode(v: np.ndarray) -> bool:
    """True when the mode v (3n,) is a floating block's: SETTLE_SHARE of |v|^2 on at most
    SETTLE_MAX_NODES nodes and at most a tenth of the n nodes (newton.floating_block's measure on
    a residual; the tenth keeps a small structure's own modes, e.g. a 32-node ribbon's buckle)."""
    w = np.sort((v.reshape(-1, 3) ** 2).sum(axis=1))[::-1]
    total = float(w.sum())
    few = min(SETTLE_MAX_NODES, w.size // 10)
    return total > 0.0 and few > 0 and float(w[:few].sum()) >= SETTLE_SHARE * total


def structural_modes(
    model: BarHingeModel, reduced: ReducedHessian, x: np.ndarray, free: np.ndarray, modes: int
) -> tuple[np.ndarray, np.ndarray]:
    """The lowest ``modes`` eigenpairs of the tangent on the free DOFs at positions x, without the
    floating ones (:func:`floating_mode`): eigenvalues [N/mm] ascending and modes (3n, m), zero on
    the held DOFs. Dense eigh up to 600 free DOFs, else shift-invert Lanczos about
    -1e-9 x the largest diagonal entry (below the whole spectrum of a stable state), at most 300
    Arnoldi restarts; no structural mode (or no convergence): eigenvalue +inf."""
    coo = model.evaluate(np.asarray(x).reshape(-1))[2]
    kmat = reduced.matrix(coo)
    n = kmat.shape[0]
    if n <= 600:
        vals, vecs = np.linalg.eigh(kmat.toarray())
        vals, vecs = vals[: modes + SETTLE_MAX_NODES], vecs[:, : modes + SETTLE_MAX_NODES]
    else:
        scale = max(float(np.max(np.abs(kmat.diagonal()))), 1e-300)
        k = min(modes + 4, n - 1)
        try:
            vals, vecs = sla.eigsh(
                kmat.tocsc(), k=k, sigma=-1e-9 * scale, which="LM", v0=np.ones(n), maxiter=300
            )
        except sla.ArpackNoConvergence:
            # a cluster at the bottom of the spectrum (the flat published gridshell: its 12
            # lowest eigenvalues within 1e-13 N/mm of 3.26e-9 N/mm): no lowest mode to
            # tell, the state counts as stable (the watch resumes when the spectrum separates)
            return np.full(1, np.inf), np.zeros((model.ndof, 1))
    order = np.argsort(vals)
    out_v, out_m = [], []
    for i in order:
        full = np.zeros(model.ndof)
        full[free] = vecs[:, i]
        if not floating_mode(full):
            out_v.append(float(vals[i]))
            out_m.append(full)
    if not out_v:
        return np.full(1, np.inf), np.zeros((model.ndof, 1))
    return np.array(out_v), np.column_stack(out_m)


def follow_stable_path(
    model: BarHingeModel,
    x_start: np.ndarray,
    held: np.ndarray,
    load: Callable[[float], np.ndarray],
    *,
    newton_options: NewtonOptions = NewtonOptions(),
    path_options: PathOptions = PathOptions(),
    stability: StabilityOptions = StabilityOptions(),
    on_step: Callable[[PathState], None] | None = None,
    progress: Callable[[float], None] | None = None,
    record: StabilityRecord | None = None,
) -> PathResult:
    """Follow the equilibrium path from t = 0 to t = 1 as :func:`follow_path` (same arguments and
    result), watching its stability and leaving a lost stability by a branch switch (module
    docstring). ``record``: filled with the lowest structural eigenvalue of every converged state
    and the switches. Raises ConvergenceError (with ``last_state`` and ``result``) when the
    increment falls below its minimum or no candidate of a switch converges."""
    held, free, reduced = path_setup(model, held, newton_options, path_options)
    check(stability, "stability")
    started = time.perf_counter()
    result = PathResult()
    record = record if record is not None else StabilityRecord()
    snap_options = dataclasses.replace(
        newton_options,
        max_iterations=newton_options.max_iterations + newton_options.snap_iterations,
        settle_stall=0,
    )
    plain = dataclasses.replace(newton_options, inertia_control=False)

    def solve(t, guess, options=newton_options) -> NewtonResult:
        x = np.array(guess, dtype=float).reshape(-1)
        x[held] = load(t)
        return newton(model, x, free, options, reduced)

    def lowest(x) -> tuple[float, np.ndarray]:
        vals, vecs = structural_modes(model, reduced, x, free, stability.modes)
        return float(vals[0]), vecs[:, 0]

    def keep(t, res, snapped=False) -> PathState:
        state = PathState.of(model, held, t, res, snapped)
        result.states.append(state)
        if on_step is not None:
            on_step(state)
        return state

    def fail(last, t_try, reason):
        load(last.t)
        result.seconds = time.perf_counter() - started
        err = ConvergenceError(
            f"load factor t = {last.t:.6g} (last converged; trying t = {t_try:.6g})", reason
        )
        err.last_state = last
        err.result = result
        return err

    def switch(lo: PathState, t_hi: float) -> tuple[NewtonResult, float, dict]:
        """Leave the stable state ``lo`` along its critical mode at t_hi (module docstring)."""
        _, v = lowest(lo.x)
        v = v * (1.0 if v[np.argmax(np.abs(v))] > 0 else -1.0)
        v = v * (stability.kick / float(np.max(np.linalg.norm(v.reshape(-1, 3), axis=1))))
        best, energies = None, []
        for s in (1.0, -1.0):
            res = solve(t_hi, lo.x.reshape(-1) + s * v, snap_options)
            ok = res.converged and (lowest(res.x)[0] >= stability.unstable_stiffness)
            energies.append(res.energy if ok else float("nan"))
            # mirror images tie to round-off: keep the first unless the other is clearly lower
            if ok and (best is None or res.energy < best[0].energy - 1e-9 * abs(best[0].energy)):
                best = (res, s)
        info = {"t_lo": lo.t, "t_hi": t_hi, "energies [mJ]": energies}
        if best is None:
            return None, 0.0, info
        info["sign"] = best[1]
        return best[0], best[1], info

    def locate(lo: PathState, t_hi: float) -> tuple[PathState, float | None]:
        """Continue the branch of ``lo`` (Newton without inertia control, which also converges
        to saddles) towards t_hi: (the last stable state kept, None) if it stays stable to t_hi,
        else (the last stable state, the load factor beyond it) bracketing the loss of stability
        to critical_tolerance (bisection; where plain Newton fails the ramp's Newton is tried, and a
        failure of both counts as beyond)."""
        t_end = t_hi
        while True:
            r = solve(t_hi, lo.x, plain)
            if not r.converged:
                # plain Newton's budget spent (e.g. a long descent, or at a kink): the ramp's
                # own Newton decides (a failure of both counts as beyond)
                r = solve(t_hi, lo.x)
            stable = r.converged and lowest(r.x)[0] >= stability.unstable_stiffness
            if stable:
                lo = keep(t_hi, r)
                record.t.append(t_hi)
                record.lowest.append(lowest(r.x)[0])
                if t_hi >= t_end:
                    return lo, None
                t_hi = t_end
            elif t_hi - lo.t <= stability.critical_tolerance:
                return lo, t_hi
            else:
                t_hi = 0.5 * (lo.t + t_hi)

    def crossing_ahead(t_try: float) -> bool:
        """The lowest structural eigenvalue, extrapolated linearly from the last two kept states,
        below ``unstable_stiffness`` at last.t + LOOK_AHEAD (t_try - last.t)."""
        if len(record.t) < 2 or record.t[-1] <= record.t[-2]:
            return False
        slope = (record.lowest[-1] - record.lowest[-2]) / (record.t[-1] - record.t[-2])
        ahead = record.lowest[-1] + slope * LOOK_AHEAD * (t_try - record.t[-1])
        return bool(np.isfinite(ahead)) and ahead < stability.unstable_stiffness

    res = solve(0.0, x_start)
    if not res.converged:
        raise ConvergenceError("load factor t = 0 (the start)", res.reason)
    last = keep(0.0, res)
    lam = lowest(last.x)[0]
    record.t.append(0.0)
    record.lowest.append(lam)
    previous = None
    dt = path_options.initial_increment
    while last.t < 1.0:
        dt = min(dt, 1.0 - last.t)
        t_try = 1.0 if 1.0 - (last.t + dt) < 1e-12 else last.t + dt
        guesses = [last.x]
        if previous is not None and not last.snapped:
            ratio = (t_try - last.t) / (last.t - previous.t)
            guesses.insert(0, last.x + ratio * (last.x - previous.x))
        critical = None  # the load factor just past a located critical point
        pred = np.array(guesses[0], dtype=float).reshape(-1)
        pred[held] = load(t_try)
        if crossing_ahead(t_try) or lowest(pred)[0] < stability.unstable_stiffness:
            # the increment may cross a critical point: the lowest structural eigenvalue, linear
            # in t through the last two kept states, falls below the threshold within two
            # increments, or the predicted state is unstable
            last, critical = locate(last, t_try)
            if critical is None:  # stable to t_try on the branch: the increment as usual
                previous = result.states[-2]
                continue
            res = None
        else:
            for guess in guesses:
                res = solve(t_try, guess)
                if res.converged:
                    break
            if res.converged:
                lam_new = lowest(res.x)[0]
                if lam_new >= stability.unstable_stiffness:
                    previous, last = last, keep(t_try, res)
                    record.t.append(t_try)
                    record.lowest.append(lam_new)
                    if progress is not None:
                        progress(t_try)
                    if res.iterations <= path_options.easy_iterations:
                        dt = min(dt * path_options.growth, path_options.max_increment)
                    continue
                last, critical = locate(last, t_try)  # a converged saddle
                if critical is None:
                    previous = result.states[-2]
                    continue
        if res is not None and not res.converged and dt < path_options.snap_increment:
            critical = min(1.0, last.t + stability.critical_tolerance)  # a fold at last.t
        if critical is not None and len(record.switches) < stability.max_switches:
            res, _, info = switch(last, critical)
            record.switches.append(info)
            if res is None:
                raise fail(last, critical, "no branch of the switch converged")
            previous, last = last, keep(critical, res, snapped=True)
            record.t.append(critical)
            record.lowest.append(lowest(res.x)[0])
            if progress is not None:
                progress(critical)
            dt = path_options.snap_increment
            continue
        result.failed_increments += 1
        load(last.t)
        dt *= 0.5
        if dt < path_options.min_increment:
            raise fail(
                last,
                t_try,
                f"{res.reason if res is not None else 'stability lost'}; increment halved below "
                f"{path_options.min_increment:g}",
            )
    result.seconds = time.perf_counter() - started
    return result
