"""The Newton loop of one implicit time step, compiled (numba):
:func:`lcefem.solvers.der.newton.minimise` on the incremental potential of
:class:`lcefem.solvers.der.integrator.StepPotential`, in one call.

Same algorithm, step for step: iterates reached from the source by one displacement with frames
transported from the source's tangents (``RodState.moved``), a new source when an edge turns by
more than ``resource_angle``, the elastic and contact/friction kernels of
:mod:`lcefem.solvers.der.kernels` added into the inertial gradient and band, fixed dofs masked, the
banded Cholesky factor of H + lambda I (Levenberg shift grown tenfold), the lagged-Hessian (chord)
steps below ``lag_residual``, the step limits, the unchecked steps, the Armijo test with the
watchdog and the backtracking line search (and ``StepOptions.elastic_hessian_at_source``). Why: at
the ribbon's sizes the Python around the kernels (state objects, masks, the trial logic, scipy's
LAPACK wrappers) cost as much as the kernels (issue 17).

The banded Cholesky (:func:`banded.band_cholesky`) is LAPACK's unblocked lower ``dpbtf2`` /
``dpbtrs`` written out (dpbtrf takes the unblocked path for half-bandwidths below its block size,
10 < 32 here), so the factors agree with the Python path's to round-off (the order of the rank-one
updates is LAPACK's; BLAS kernels may fuse multiply-adds differently).
``tests/solvers/test_der_compiled_newton.py`` checks that both paths take the same steps
(iterations, cuts, states to round-off) on a ribbon on the hot plate, a rod thrown at a wall and a
clamped rod.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from lcefem.solvers.der import contact_kernels, frame_kernels, kernels
from lcefem.solvers.der.banded import band_cholesky, band_cholesky_solve

# Return codes of :func:`minimise_step` (the reasons of ``newton.NewtonResult``).
REASONS = (
    "residual below force_tol",
    "update below step_tol",
    "non-finite residual",
    "singular Hessian",
    "line search failed",
    "too many iterations",
)
CONVERGED_CODES = (0, 1)


@njit(cache=True, error_model="numpy")
def _own_geometry(x, theta, a1, ref):
    """(x, theta, a1, ref, e, length, t, m1, m2, twist) of a state with its own frames
    (``RodState.geometry``)."""
    e, length, t = frame_kernels.edge_tangents(x)
    m1, m2, twist = frame_kernels.material_frames_twist(t, a1, theta, ref)
    return x, theta, a1, ref, e, length, t, m1, m2, twist


@njit(cache=True, error_model="numpy")
def _moved(src, dq):
    """``RodState.moved``: the source displaced by dq, frames transported from the source's
    tangents."""
    x0, theta0, a10, ref0 = src[0], src[1], src[2], src[3]
    t0 = src[6]
    n = len(x0)
    x = np.empty((n, 3))
    for i in range(n):
        for c in range(3):
            x[i, c] = x0[i, c] + dq[4 * i + c]
    theta = np.empty(n - 1)
    for k in range(n - 1):
        theta[k] = theta0[k] + dq[4 * k + 3]
    e, length, t, a1, ref, m1, m2, twist = frame_kernels.moved_geometry(x, theta, a10, t0, ref0)
    return x, theta, a1, ref, e, length, t, m1, m2, twist


@njit(cache=True, error_model="numpy")
def _q(st):
    x, theta = st[0], st[1]
    n = len(x)
    q = np.empty(4 * n - 1)
    for i in range(n):
        for c in range(3):
            q[4 * i + c] = x[i, c]
    for k in range(n - 1):
        q[4 * k + 3] = theta[k]
    return q


@njit(cache=True, error_model="numpy")
def _evaluate(
    st,
    own,
    src_t,
    inertia,
    rest,
    sampling,
    contact,
    order,
    no_db,
    no_ddb,
    no_band,
    source_elastic,
    elastic_band,
):
    """``StepPotential.evaluate``: (energy, grad, band) of the state ``st`` (``own``: its frames are
    its own, no source change); order 0 energy, 1 with gradient, 2 with the lower band.
    ``source_elastic`` (``StepOptions.elastic_hessian_at_source``): the elastic part of the band of
    a source (own) state is stored in ``elastic_band`` and a moved state takes that one instead of
    its own."""
    mass, q_n, q_star, load, diag, h, damping = inertia
    rest_length, kappa_bar, twist_bar, voronoi, EA, EI1, EI2, GJ = rest
    side, sigma, offsets, end_ids, end_sigma, end_offsets = sampling
    (
        normals,
        heights,
        boxes,
        clearance,
        delta,
        K1,
        stiffness,
        fric,
        lag_ns,
        lag_ps,
        lag_ne,
        lag_pe,
        mu,
        K2,
    ) = contact
    x, theta, a1, ref, e, length, t, m1, m2, twist = st
    nd = len(mass)
    q = _q(st)
    dq = q - q_star
    dn = q - q_n
    energy = (
        0.5 / h**2 * np.dot(mass, dq**2) + 0.5 * damping / h * np.dot(mass, dn**2) - np.dot(load, q)
    )
    grad = np.zeros(nd)
    band = no_band
    if order >= 1:
        for i in range(nd):
            grad[i] = mass[i] * (dq[i] / h**2 + damping * dn[i] / h) - load[i]
        if order >= 2:
            band = np.zeros((11, nd))
            band[0, :] = diag
    with_source = False
    db, ddb = no_db, no_ddb
    if order >= 1 and not own:
        if np.max(np.abs(src_t - t)) != 0.0:
            db, ddb = kernels.source_change(src_t, t, length)
            with_source = True
    # with source_elastic a source (own) state's elastic Hessian goes to elastic_band, a moved state
    # computes none of its own, and both take elastic_band into the band
    keep_source = order >= 2 and source_elastic
    if keep_source and own:
        elastic_band[:, :] = 0.0
    energy += kernels.elastic(
        x,
        m1,
        m2,
        twist,
        rest_length,
        kappa_bar,
        twist_bar,
        voronoi,
        EA,
        EI1,
        EI2,
        GJ,
        db,
        ddb,
        with_source,
        order >= 2 and (own or not source_elastic),
        grad,
        (elastic_band if own else no_band) if keep_source else band,
    )
    if keep_source:
        band += elastic_band
    if len(heights):
        no_box = np.zeros(8)
        pos_s, r_s, pos_e, r_e = contact_kernels.sample_points(
            x, a1, t, theta, twist, m1, m2, side, sigma, offsets, end_ids, end_sigma, end_offsets
        )
        e_contact = 0.0
        n_planes = len(heights)
        for p in range(n_planes + len(boxes)):
            is_box = p >= n_planes
            box = boxes[p - n_planes] if is_box else no_box
            plane = 0 if is_box else p
            e_contact += contact_kernels.contact(
                pos_s,
                r_s,
                pos_e,
                r_e,
                x,
                t,
                length,
                side,
                sigma,
                end_ids,
                end_sigma,
                normals[plane],
                heights[plane],
                clearance,
                delta,
                K1,
                stiffness,
                fric,
                lag_ns[p],
                lag_ps[p],
                lag_ne[p],
                lag_pe[p],
                mu,
                K2,
                h,
                db,
                ddb,
                with_source,
                order,
                grad,
                band,
                box,
                is_box,
            )
        energy += e_contact
    return energy, grad, band


@njit(cache=True, error_model="numpy")
def _mask(fixed, grad, band, with_band):
    """``newton._FixedMask.apply``: prescribed rows and columns out of the gradient and the band."""
    nd = len(fixed)
    for j in range(nd):
        if fixed[j]:
            grad[j] = 0.0
    if not with_band:
        return
    for r in range(band.shape[0]):
        for j in range(nd - r):
            if fixed[j] or fixed[j + r]:
                band[r, j] = 0.0
    for j in range(nd):
        if fixed[j]:
            band[0, j] = 1.0


@njit(cache=True, error_model="numpy")
def _factorise(band, shift0, max_tries):
    """``newton.factorise_banded_spd``: (factor of H + lambda I, lambda, ok)."""
    lam = 0.0
    scale = np.max(np.abs(band[0]))
    if scale == 0.0:
        scale = 1.0
    for _ in range(max_tries + 1):
        factor = band.copy()
        if lam > 0.0:
            for j in range(factor.shape[1]):
                factor[0, j] += lam
        if band_cholesky(factor) == 0:
            return factor, lam, True
        lam = max(shift0, 1e-10 * scale) if lam == 0.0 else lam * 10.0
    return band, lam, False


@njit(cache=True, error_model="numpy")
def _max_abs_nodes_twists(step):
    n_dof = len(step)
    dx = 0.0
    dth = 0.0
    for i in range(n_dof):
        a = abs(step[i])
        if i % 4 == 3:
            dth = max(dth, a)
        else:
            dx = max(dx, a)
    return dx, dth


@njit(cache=True, error_model="numpy")
def minimise_step(
    start_x,
    start_theta,
    start_a1,
    start_ref,
    fixed,
    inertia,
    rest,
    sampling,
    contact,
    options,
    source_elastic,
):
    """``newton.minimise`` of the step potential from the state (start_x, start_theta, start_a1,
    start_ref) (its own frames: the start is the first source); ``source_elastic``: the iterates
    moved from a source take its elastic Hessian (``StepOptions.elastic_hessian_at_source``).

    options = (max_iterations, force_tol, step_tol, armijo, min_step, max_shift_tries, watchdog,
    cos(resource_angle), max_rotation, max_displacement, unchecked_step, lag_residual,
    lag_contraction).

    Returns (code, iterations, residual, state, own, source tangents): code indexes ``REASONS``;
    state = (x, theta, a1, ref_twist, e, length, t, m1, m2, twist); own: the state is its own
    source.
    """
    (
        max_iterations,
        force_tol,
        step_tol,
        armijo,
        min_step,
        max_shift_tries,
        watchdog,
        cos_limit,
        max_rotation,
        max_displacement,
        unchecked_step,
        lag_residual,
        lag_contraction,
    ) = options
    no_db = np.zeros((1, 3))
    no_ddb = np.zeros((1, 3, 3))
    no_band = np.zeros((1, 1))
    # Runtime (not literal) orders and flags: numba would compile _evaluate and _mask once per
    # literal argument (5 + 2 specialisations, ~45 s of compilation on an empty cache) for nothing.
    energy_only, with_gradient, with_band = np.int64(0), np.int64(1), np.int64(2)
    moved_state, yes = np.bool_(False), np.bool_(True)
    source = _own_geometry(start_x, start_theta, start_a1, start_ref)
    nd = len(fixed)
    elastic_band = np.zeros((11, nd)) if source_elastic else no_band  # the source's elastic Hessian
    total = np.zeros(nd)
    state = source
    own = yes  # the current state is the source itself
    shift = 0.0
    residual = np.inf
    have_checkpoint = False
    cp_total, cp_state, cp_own, cp_energy, cp_step, cp_slope = total, state, own, 0.0, total, 0.0
    watched = 0
    gradient_only = lag_residual > 0.0
    have_d = False  # derivatives of ``state`` known
    d_energy, d_grad, d_band, d_has_band = 0.0, total, no_band, False
    factor = no_band
    have_factor = False
    for it in range(1, max_iterations + 1):
        if not have_checkpoint and not own:
            src_t, t = source[6], state[6]
            low = np.inf
            for k in range(len(t)):
                low = min(
                    low, src_t[k, 0] * t[k, 0] + src_t[k, 1] * t[k, 1] + src_t[k, 2] * t[k, 2]
                )
            if low < cos_limit:
                source, total = state, np.zeros(nd)
                own, have_d, have_factor = yes, False, False
        previous = residual
        if not have_d:
            d_energy, d_grad, d_band = _evaluate(
                state,
                own,
                source[6],
                inertia,
                rest,
                sampling,
                contact,
                with_band,
                no_db,
                no_ddb,
                no_band,
                source_elastic,
                elastic_band,
            )
            d_has_band = True
            have_d = True
        _mask(fixed, d_grad, d_band, d_has_band)
        residual = np.max(np.abs(d_grad))
        if not np.isfinite(residual):
            return 2, it, residual, state, own, source[6]
        if have_checkpoint and d_energy <= cp_energy + armijo * cp_slope:
            have_checkpoint, watched = False, 0
        if residual <= force_tol and not have_checkpoint:
            return 0, it - 1, residual, state, own, source[6]
        if not d_has_band and (not have_factor or residual > lag_contraction * previous):
            d_energy, d_grad, d_band = _evaluate(
                state,
                own,
                source[6],
                inertia,
                rest,
                sampling,
                contact,
                with_band,
                no_db,
                no_ddb,
                no_band,
                source_elastic,
                elastic_band,
            )
            d_has_band = True
            _mask(fixed, d_grad, d_band, yes)
        if d_has_band:
            factor, shift, ok = _factorise(d_band, max(shift * 0.1, 0.0), max_shift_tries)
            if not ok:
                return 3, it, residual, state, own, source[6]
            have_factor = True
        step = -d_grad
        band_cholesky_solve(factor, step)
        for j in range(nd):
            if fixed[j]:
                step[j] = 0.0
        dx, dth = _max_abs_nodes_twists(step)
        if max(dx, dth) <= step_tol and not have_checkpoint:
            return 1, it, residual, _moved(source, total + step), moved_state, source[6]
        scale = min(
            1.0, max_rotation / dth if dth > 0 else 1.0, max_displacement / dx if dx > 0 else 1.0
        )
        if scale < 1.0:
            step *= scale
        slope = np.dot(d_grad, step)
        allowance = 1e-12 * abs(d_energy) + 1e-300
        lag = gradient_only and residual <= lag_residual
        trial = _moved(source, total + step)
        if not have_checkpoint and max(dx, dth) * scale <= unchecked_step:
            state, total, own = trial, total + step, moved_state
            if lag:
                d_energy, d_grad, d_band = _evaluate(
                    state,
                    own,
                    source[6],
                    inertia,
                    rest,
                    sampling,
                    contact,
                    with_gradient,
                    no_db,
                    no_ddb,
                    no_band,
                    source_elastic,
                    elastic_band,
                )
                d_has_band = False
            else:
                have_d = False
            continue
        t_energy, t_grad, t_band = _evaluate(
            trial,
            moved_state,
            source[6],
            inertia,
            rest,
            sampling,
            contact,
            with_gradient if lag else with_band,
            no_db,
            no_ddb,
            no_band,
            source_elastic,
            elastic_band,
        )
        finite = np.isfinite(t_energy)
        if finite and t_energy <= d_energy + armijo * slope + allowance:
            state, total, own = trial, total + step, moved_state
            d_energy, d_grad, d_band, d_has_band = t_energy, t_grad, t_band, not lag
            continue
        if finite and watched < watchdog:
            if not have_checkpoint:
                cp_total, cp_state, cp_own, cp_energy, cp_step, cp_slope = (
                    total,
                    state,
                    own,
                    d_energy,
                    step,
                    slope,
                )
                have_checkpoint = True
            watched += 1
            state, total, own = trial, total + step, moved_state
            d_energy, d_grad, d_band, d_has_band = t_energy, t_grad, t_band, not lag
            continue
        # Back to the checkpoint (if any) and backtrack along its direction.
        if have_checkpoint:
            total, state, own, energy0, step, slope = (
                cp_total,
                cp_state,
                cp_own,
                cp_energy,
                cp_step,
                cp_slope,
            )
            have_checkpoint, watched = False, 0
        else:
            energy0 = d_energy
        alpha = 0.5
        while True:
            trial = _moved(source, total + alpha * step)
            e_trial = _evaluate(
                trial,
                moved_state,
                source[6],
                inertia,
                rest,
                sampling,
                contact,
                energy_only,
                no_db,
                no_ddb,
                no_band,
                source_elastic,
                elastic_band,
            )[0]
            if np.isfinite(e_trial) and e_trial <= energy0 + armijo * alpha * slope + allowance:
                break
            alpha *= 0.5
            if alpha < min_step:
                return 4, it, residual, state, own, source[6]
        state, total, own, have_d = trial, total + alpha * step, moved_state, False
    return 5, max_iterations, residual, state, own, source[6]
