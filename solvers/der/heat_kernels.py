"""Compiled (numba) section heat step of the DER ribbon
(:meth:`lcefem.solvers.der.heat.SectionHeat.step`): exchange coefficients with the ground and the
air, the implicit solve and the fluxes.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from lcefem.models.units import STEFAN_BOLTZMANN, ZERO_CELSIUS_K
from lcefem.solvers.der.banded import band_cholesky_rows, band_cholesky_solve_rows


# ----------------------------------------------------------------------------------------------
# Section heat step (solvers.der.heat.SectionHeat.step)
# ----------------------------------------------------------------------------------------------
@njit(cache=True, error_model="numpy")
def heat_solve(C, G_g, G_a, T, T_ground, T_air, length, pair_a, pair_b, pair_g, k_axial):
    """Cell temperatures (n, n_cells) [C] of one implicit-Euler heat step: the banded system
    (C + G_g + G_a + conduction) T_new = C T + G_g T_ground + G_a T_air assembled (cells of edge k
    at rows n_cells k ..., in-section pairs (pair_a, pair_b) with conductance per length pair_g
    [mW/(K mm)], the same cell of neighbouring edges k_axial / mean length) and solved by
    :func:`band_cholesky`. C (n, 1) [mW/K] = capacity / dt; the rest (n, n_cells).
    The sums are taken in the order of the numpy assembly it replaces (diagonal: capacity and
    exchange, then the pair sums, then the axial terms)."""
    n, nc = G_g.shape
    nd = n * nc
    L = np.zeros((nd, nc + 1))  # L[j, i] = H[j + i, j] (band_cholesky_rows: no transposed copies)
    rhs = np.empty(nd)
    sum_a = np.zeros(nc)
    sum_b = np.zeros(nc)
    for k in range(n):
        base = nc * k
        sum_a[:] = 0.0
        sum_b[:] = 0.0
        for p in range(len(pair_a)):
            gl = length[k] * pair_g[p]
            L[base + pair_a[p], pair_b[p] - pair_a[p]] -= gl
            sum_a[pair_a[p]] += gl
            sum_b[pair_b[p]] += gl
        for c in range(nc):
            L[base + c, 0] = (C[k, 0] + G_g[k, c] + G_a[k, c]) + (sum_a[c] + sum_b[c])
            rhs[base + c] = C[k, 0] * T[k, c] + G_g[k, c] * T_ground[k, c] + G_a[k, c] * T_air[k, c]
    for k in range(n - 1):
        ga = k_axial / (0.5 * (length[k] + length[k + 1]))
        for c in range(nc):
            L[nc * k + c, nc] -= ga
            L[nc * k + c, 0] += ga
    for k in range(n - 1):  # the downstream cells second, as numpy added them
        ga = k_axial / (0.5 * (length[k] + length[k + 1]))
        for c in range(nc):
            L[nc * (k + 1) + c, 0] += ga
    info = band_cholesky_rows(L)
    if info != 0:
        raise ValueError("heat step: the conductance matrix is not positive definite")
    band_cholesky_solve_rows(L, rhs)
    return rhs.reshape(n, nc)


#: Largest ratio q of a row's off-diagonal conductances to its diagonal for which
#: :func:`heat_solve_fast` iterates (Gauss-Seidel contracts the max-norm error by q or better per
#: sweep); above it the banded Cholesky. At the ribbon's 0.005-0.01 s steps q ~ 0.04-0.08
#: (capacity/dt dominates), at the 0.5 s steps of the heat tests q > 1.
ITERATIVE_MAX_RATIO = 0.25


@njit(cache=True, error_model="numpy")
def heat_solve_fast(C, G_g, G_a, T, T_ground, T_air, length, pair_a, pair_b, pair_g, k_axial):
    """:func:`heat_solve`'s system solved by Gauss-Seidel sweeps from T when it is diagonally
    dominant (off-diagonal row sums at most ``ITERATIVE_MAX_RATIO`` of the diagonal), to round-off:
    the sweeps stop once no temperature moves by more than 8 ulp of the largest |T| (the error is
    then below q/(1-q) of that, q <= 0.25), at most 60 sweeps; otherwise (or without convergence)
    the banded Cholesky of :func:`heat_solve`. The same temperatures as the Cholesky to ~1e-13 K;
    ~5x cheaper at 100 edges x 24 cells (the band's fill-in, n_cells^2 per row, is what the Cholesky
    pays)."""
    n, nc = G_g.shape
    diag = np.empty((n, nc))
    rhs = np.empty((n, nc))
    # each cell's in-section neighbours and conductances per length (a cell has at most 4)
    deg = np.zeros(nc, np.int64)
    nb = np.zeros((nc, 4), np.int64)
    nbg = np.zeros((nc, 4))
    for p in range(len(pair_a)):
        a, b = pair_a[p], pair_b[p]
        nb[a, deg[a]] = b
        nbg[a, deg[a]] = pair_g[p]
        deg[a] += 1
        nb[b, deg[b]] = a
        nbg[b, deg[b]] = pair_g[p]
        deg[b] += 1
    ga = np.zeros(max(n - 1, 1))
    for k in range(n - 1):
        ga[k] = k_axial / (0.5 * (length[k] + length[k + 1]))
    q = 0.0
    for k in range(n):
        for c in range(nc):
            own = C[k, 0] + G_g[k, c] + G_a[k, c]
            off = 0.0
            for i in range(deg[c]):
                off += length[k] * nbg[c, i]
            if k > 0:
                off += ga[k - 1]
            if k < n - 1:
                off += ga[k]
            diag[k, c] = own + off
            rhs[k, c] = C[k, 0] * T[k, c] + G_g[k, c] * T_ground[k, c] + G_a[k, c] * T_air[k, c]
            q = max(q, off / diag[k, c])
    if q <= ITERATIVE_MAX_RATIO:
        x = T.copy()
        scale = 0.0
        for k in range(n):
            for c in range(nc):
                scale = max(scale, abs(rhs[k, c] / diag[k, c]))
        tol = 8.0 * 2.220446049250313e-16 * scale
        for _ in range(60):
            change = 0.0
            for k in range(n):
                lk = length[k]
                for c in range(nc):
                    s = rhs[k, c]
                    for i in range(deg[c]):
                        s += lk * nbg[c, i] * x[k, nb[c, i]]
                    if k > 0:
                        s += ga[k - 1] * x[k - 1, c]
                    if k < n - 1:
                        s += ga[k] * x[k + 1, c]
                    v = s / diag[k, c]
                    change = max(change, abs(v - x[k, c]))
                    x[k, c] = v
            if change <= tol:
                return x
    return heat_solve(C, G_g, G_a, T, T_ground, T_air, length, pair_a, pair_b, pair_g, k_axial)


@njit(cache=True, error_model="numpy")
def heat_exchange(
    T,
    centre,
    m1,
    m2,
    length,
    corner_gap,
    normal,
    plane_height,
    p_cell,
    p_area,
    p_axis,
    p_sign,
    p_off,
    corner_cells,
    corner_off,
    T_uniform,
    gradient,
    air,
    ground,
    K1,
):
    """``SectionHeat.coefficients`` in one loop over edges and patches: the conductances [mW/K] of
    each cell with the ground G_g and the air G_a (n, n_cells) and the conductance-weighted ground
    and air temperatures [C] (n, n_cells). air = (film coefficient [mW/(mm^2 K)], ambient
    temperature [C], emissivity), ground = (air conductivity [mW/(mm K)], gap floor z0 [mm], plate
    emissivity, boundary layer d_bl [mm], contact conductance G_c [mW/(mm K)])
    (``models.heat.SurfaceExchange``, ``models.ribbon.GroundHeatExchange``); the plate at T_uniform
    + gradient . x [C]. The formulas and their order of operations are those of the numpy reference,
    which stays: ``tests/solvers/test_der_ribbon.py`` compares both (the sums over a cell's patches
    are taken in patch order; numpy's matrix products add the same one or two nonzero terms)."""
    n, nc = T.shape
    film, ambient, emissivity = air
    k_air, gap_floor, plate_emissivity, boundary_layer, contact_conductance = ground
    sigma = STEFAN_BOLTZMANN  # [mW/(mm^2 K^4)]; numba freezes module globals at compilation
    kelvin = ZERO_CELSIUS_K
    tak_amb = ambient + kelvin
    G_g = np.zeros((n, nc))
    G_a = np.zeros((n, nc))
    Q_g = np.zeros((n, nc))
    Q_a = np.zeros((n, nc))
    for k in range(n):
        cz = (
            centre[k, 0] * normal[0] + centre[k, 1] * normal[1] + centre[k, 2] * normal[2]
        ) - plane_height
        m1z = m1[k, 0] * normal[0] + m1[k, 1] * normal[1] + m1[k, 2] * normal[2]
        m2z = m2[k, 0] * normal[0] + m2[k, 1] * normal[1] + m2[k, 2] * normal[2]
        gc = centre[k, 0] * gradient[0] + centre[k, 1] * gradient[1] + centre[k, 2] * gradient[2]
        g1 = m1[k, 0] * gradient[0] + m1[k, 1] * gradient[1] + m1[k, 2] * gradient[2]
        g2 = m2[k, 0] * gradient[0] + m2[k, 1] * gradient[1] + m2[k, 2] * gradient[2]
        for p in range(len(p_cell)):
            c = p_cell[p]
            height = cz + p_off[p, 0] * m1z + p_off[p, 1] * m2z
            nrm_z = (m1z if p_axis[p] == 0 else m2z) * p_sign[p]
            facing = max(0.0, -nrm_z)
            area = p_area[p] * length[k]
            tg = T_uniform + (gc + p_off[p, 0] * g1 + p_off[p, 1] * g2)
            tk = T[k, c] + kelvin
            tgk = tg + kelvin
            above = max(height, 0.0)
            h_ground = facing * (
                k_air / (above + gap_floor)
                + plate_emissivity * sigma * (tk**2 + tgk**2) * (tk + tgk)
            )
            h_amb = film + emissivity * sigma * (tk**2 + tak_amb**2) * (tk + tak_amb) * (
                1.0 - facing
            )
            t_air = ambient + (tg - ambient) * math.exp(-above / boundary_layer)
            G_g[k, c] += h_ground * area
            Q_g[k, c] += h_ground * area * tg
            G_a[k, c] += h_amb * area
            Q_a[k, c] += h_amb * area * t_air
        for j in range(len(corner_cells)):
            c = corner_cells[j]
            weight = 0.5 * (1.0 - math.tanh(0.5 * K1 * corner_gap[k, j]))
            g_contact = contact_conductance * length[k] * weight
            G_g[k, c] += g_contact
            Q_g[k, c] += g_contact * (
                T_uniform + gc + corner_off[j, 0] * g1 + corner_off[j, 1] * g2
            )
    for k in range(n):
        for c in range(nc):
            Q_a[k, c] /= max(G_a[k, c], 1e-300)
            Q_g[k, c] /= max(G_g[k, c], 1e-300)
    return G_g, G_a, Q_a, Q_g


@njit(cache=True, error_model="numpy")
def heat_step(T, dt, centre, m1, m2, length, corner_gap, T_uniform, gradient, model):
    """One implicit-Euler heat step in one call: :func:`heat_exchange`, :func:`heat_solve` and the
    fluxes. model = (capacity (n,) [mJ/K], plane normal (3,), plane height [mm], patch cells, areas
    per length [mm], frame axes, signs, offsets (n_patches, 2) [mm], corner cells, corner offsets
    (4, 2) [mm], air, ground, K1 [1/mm], pair_a, pair_b, pair_g [mW/(K mm)], k_axial [mW mm/K])
    (``SectionHeat._kernel_data``). Returns (T_new (n, n_cells) [C], power from the ground (n,)
    [mW], power to the air (n,) [mW])."""
    (
        capacity,
        normal,
        plane_height,
        p_cell,
        p_area,
        p_axis,
        p_sign,
        p_off,
        corner_cells,
        corner_off,
        air,
        ground,
        K1,
        pair_a,
        pair_b,
        pair_g,
        k_axial,
    ) = model
    G_g, G_a, T_air, T_ground = heat_exchange(
        T,
        centre,
        m1,
        m2,
        length,
        corner_gap,
        normal,
        plane_height,
        p_cell,
        p_area,
        p_axis,
        p_sign,
        p_off,
        corner_cells,
        corner_off,
        T_uniform,
        gradient,
        air,
        ground,
        K1,
    )
    n, nc = T.shape
    C = np.empty((n, 1))
    for k in range(n):
        C[k, 0] = capacity[k] / dt
    T_new = heat_solve_fast(
        C, G_g, G_a, T, T_ground, T_air, length, pair_a, pair_b, pair_g, k_axial
    )
    from_ground = np.zeros(n)
    to_air = np.zeros(n)
    for k in range(n):
        for c in range(nc):
            from_ground[k] += G_g[k, c] * (T_ground[k, c] - T_new[k, c])
            to_air[k] += G_a[k, c] * (T_new[k, c] - T_air[k, c])
    return T_new, from_ground, to_air
