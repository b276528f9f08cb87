"""The compiled element loops (solvers/der/kernels.py) against the vectorised numpy formulas of
models/rod.py: same energy, gradient and banded Hessian to round-off (1e-12 of the largest entry:
the two differ only in the order of the floating-point sums), at a state away from its transport
source so that the holonomy terms are exercised."""

import numpy as np
import pytest

from lcefem.models import rod as rodlaw
from lcefem.models.contact import ContactLaw, contact_energy, friction_potential, normal_force
from lcefem.solvers.der import contact_kernels, frame_kernels, kernels
from lcefem.solvers.der.assembly import (
    EDGE_SLOTS,
    STENCIL_SLOTS,
    Assembly,
    ContactSampling,
    FrictionLag,
    friction_lag,
)
from tests.solvers.test_der_derivatives import ribbon_rod, ribbon_state

TOL = 1e-12


def numpy_elastic(asm: Assembly, rod, state):
    """The elastic terms assembled from the numpy element functions of models/rod.py."""
    sec, rest, geo = rod.section, rod.rest, state.geometry()
    e, m1, m2 = geo.e, geo.m1, geo.m2
    es, gs, hs = rodlaw.stretching(e, rest.edge_length, sec.EA)
    eb, gb, hb = rodlaw.bend_twist(
        e[:-1],
        e[1:],
        m1[:-1],
        m2[:-1],
        m1[1:],
        m2[1:],
        geo.twist,
        rest.curvature,
        rest.twist,
        rest.voronoi_length,
        sec.EI1,
        sec.EI2,
        sec.GJ,
    )
    n = len(e)
    g_edges = np.zeros((n, 7))
    g_edges[:, 0:3], g_edges[:, 4:7] = -gs, gs
    h_edges = np.zeros((n, 7, 7))
    h_edges[:, 0:3, 0:3] = h_edges[:, 4:7, 4:7] = hs
    h_edges[:, 0:3, 4:7] = h_edges[:, 4:7, 0:3] = -hs
    g_sten = gb @ rodlaw.STENCIL_MAP.T
    h_sten = rodlaw.STENCIL_MAP @ hb @ rodlaw.STENCIL_MAP.T
    db, ddb = rodlaw.source_change(state.source_tangents, geo.t, geo.length)
    g_sten, h_sten = rodlaw.apply_source_change(
        g_sten, h_sten, STENCIL_SLOTS, (db[:-1], db[1:]), (ddb[:-1], ddb[1:])
    )
    grad = asm.gradient(g_edges, g_sten)
    band = asm.band([("edge", h_edges, None), ("stencil", h_sten, None)], None)
    return float(es.sum() + eb.sum()), grad, band


def test_compiled_elastic_equals_numpy_elastic():
    rng = np.random.default_rng(7)
    n = 9
    rod = ribbon_rod(n, 2)
    start = ribbon_state(n, rng)
    state = start.moved(0.05 * rng.standard_normal(4 * n - 1))  # frames transported from `start`
    asm = Assembly(n)
    e_ref, g_ref, b_ref = numpy_elastic(asm, rod, state)
    energy, grad, terms = asm.elastic(rod, state, 2)
    band = asm.band(terms, None)
    assert abs(energy - e_ref) <= TOL * abs(e_ref)
    assert np.max(np.abs(grad - g_ref)) <= TOL * np.max(np.abs(g_ref))
    assert np.max(np.abs(band - b_ref)) <= TOL * np.max(np.abs(b_ref))
    assert asm.elastic(rod, state, 0)[0] == energy  # the line search's energy is the same function


def test_compiled_source_change_equals_numpy():
    rng = np.random.default_rng(11)
    n = 9
    start = ribbon_state(n, rng)
    state = start.moved(0.05 * rng.standard_normal(4 * n - 1))
    geo = state.geometry()
    ref = rodlaw.source_change(state.source_tangents, geo.t, geo.length)
    got = kernels.source_change(state.source_tangents, geo.t, geo.length)
    for a, b in zip(got, ref):
        assert np.max(np.abs(a - b)) <= TOL * np.max(np.abs(b))


def numpy_points(state, sampling):
    """Positions, offsets and tangents of all sample points from models/rod.py: per kind, arrays
    (rows, p, 3)."""
    geo = state.geometry()
    n_edges = len(geo.t)
    out = {}
    if sampling.interpolated:
        st = sampling.stencil
        rows, cols = np.meshgrid(np.arange(n_edges - 1), np.arange(len(st.side)), indexing="ij")
        pos, r, t = rodlaw.stencil_points(
            state.x, state.a1, geo.t, state.theta, geo.twist, st, rows.ravel(), cols.ravel()
        )
        out["stencil"] = [a.reshape(rows.shape + (3,)) for a in (pos, r, t)]
    ids = sampling.end_edges(n_edges)
    sig = sampling.end_sigma_rows(n_edges)
    pos = rodlaw.section_points(
        state.x[ids], state.x[ids + 1], geo.m1[ids], geo.m2[ids], sampling.end_offsets, sig
    )
    r = pos - state.x[ids][:, None] - sig[..., None] * geo.e[ids][:, None]
    out["edge"] = [pos, r, np.broadcast_to(geo.t[ids][:, None], pos.shape)]
    return out


def numpy_contact(asm, rod, state, sampling, lag, step):
    """Contact + friction energy, gradient and band from the numpy functions (the pre-numba
    assembly)."""
    law, nrm = rod.contact, rod.ground.unit_normal()
    geo = state.geometry()
    db, ddb = rodlaw.source_change(state.source_tangents, geo.t, geo.length)
    energy, grad, terms = 0.0, np.zeros(asm.ndof), []
    for kind, (pos, r, t) in numpy_points(state, sampling).items():
        gap = pos @ nrm - rod.ground.height
        lag_n = lag.stencil_normal if kind == "stencil" else lag.end_normal
        lag_p = lag.stencil_points if kind == "stencil" else lag.end_points
        elem, col = np.nonzero((gap < law.clearance + law.delta) | (lag_n > 0))
        E, d1, d2 = contact_energy(gap[elem, col], law)
        fn = lag_n[elem, col]
        u = np.where((fn > 0)[:, None], pos[elem, col] - np.nan_to_num(lag_p[elem, col]), 0.0)
        D, gD, hD = friction_potential(u, nrm, fn, step, rod.friction)
        energy += law.stiffness * E.sum() + D.sum()
        g_pt = (law.stiffness * d1)[:, None] * nrm + gD
        if kind == "stencil":
            st = sampling.stencil
            jac, h = rodlaw.stencil_point_derivatives(
                geo.e[elem],
                geo.e[elem + 1],
                r[elem, col],
                t[elem, col],
                st.side[col],
                st.sigma[col],
                g_pt,
            )
            slots, dbs, ddbs = STENCIL_SLOTS, (db[elem], db[elem + 1]), (ddb[elem], ddb[elem + 1])
        else:
            ids = sampling.end_edges(len(geo.t))[elem]
            sig = sampling.end_sigma_rows(len(geo.t))[elem, col]
            jac, h = rodlaw.section_point_derivatives(
                state.x[ids],
                state.x[ids + 1],
                geo.m1[ids],
                geo.m2[ids],
                sampling.end_offsets[col][:, None],
                g_pt[:, None],
                sig[:, None],
            )
            jac, h = jac[:, 0], h[:, 0]
            slots, dbs, ddbs = EDGE_SLOTS, (db[ids],), (ddb[ids],)
        jn = np.einsum("kci,c->ki", jac, nrm)
        h = (
            h
            + (law.stiffness * d2)[:, None, None] * jn[:, :, None] * jn[:, None, :]
            + np.swapaxes(jac, 1, 2) @ (hD @ jac)
        )
        g_loc, h = rodlaw.apply_source_change(
            np.einsum("kc,kci->ki", g_pt, jac), h, slots, dbs, ddbs
        )
        if kind == "stencil":
            grad += asm.gradient(None, g_loc, stencil_rows=elem)
            terms.append(("stencil", h, elem))
        else:
            grad += asm.gradient(g_loc, None, edge_rows=ids)
            terms.append(("edge", h, ids))
    return energy, grad, asm.band(terms, None)


@pytest.mark.parametrize("samples", [1, 2, 4])
def test_compiled_contact_and_friction_equal_numpy(samples):
    """Ground contact with friction on every point (random lagged normal forces), away from the
    transport source, for one midpoint section per edge and for interpolated sections."""
    rng = np.random.default_rng(13)
    n = 9
    rod = ribbon_rod(n, samples)
    start = ribbon_state(n, rng)
    sampling = ContactSampling.of(rod)
    lag = friction_lag(rod, start, sampling, all_points=True)
    lag = FrictionLag(
        None if lag.stencil_normal is None else 1e-3 * (1 + rng.random(lag.stencil_normal.shape)),
        lag.stencil_points,
        1e-3 * (1 + rng.random(lag.end_normal.shape)),
        lag.end_points,
    )
    state = start.moved(0.05 * rng.standard_normal(4 * n - 1))
    asm = Assembly(n)
    e_ref, g_ref, b_ref = numpy_contact(asm, rod, state, sampling, lag, 0.01)
    energy, grad, terms = asm.contact(rod, state, sampling, 2, friction=lag, step=0.01)
    band = asm.band(terms, None)
    assert e_ref > 0
    assert abs(energy - e_ref) <= TOL * abs(e_ref)
    assert np.max(np.abs(grad - g_ref)) <= TOL * np.max(np.abs(g_ref))
    assert np.max(np.abs(band - b_ref)) <= TOL * np.max(np.abs(b_ref))
    assert asm.contact(rod, state, sampling, 0, friction=lag, step=0.01)[0] == energy


def test_compiled_frame_transport_equals_numpy():
    from lcefem.solvers.der import frames as fr

    rng = np.random.default_rng(17)
    n = 9
    state = ribbon_state(n, rng)
    t_old = state.tangents
    e = np.diff(state.x + 0.1 * rng.standard_normal(state.x.shape), axis=0)
    t_new = e / np.linalg.norm(e, axis=1)[:, None]
    a1_ref = fr.transport_directors(state.a1, t_old, t_new)
    ref_ref = fr.reference_twist(
        a1_ref, t_new, state.ref_twist + 2 * np.pi
    )  # continued past a full turn
    a1, ref = frame_kernels.transport_frames(state.a1, t_old, t_new, state.ref_twist + 2 * np.pi)
    assert np.max(np.abs(a1 - a1_ref)) <= TOL
    assert np.max(np.abs(ref - ref_ref)) <= TOL * np.max(np.abs(ref_ref))


def test_compiled_normal_force_equals_numpy():
    """All three pieces of the smooth contact law (quadratic, softplus band, no contact)."""
    law = ContactLaw(delta=0.05, stiffness=2.0, clearance=0.1)
    gap = np.linspace(-0.2, 0.3, 301).reshape(7, 43)
    ref = normal_force(gap, law)
    got = contact_kernels.normal_force(gap, law.clearance, law.delta, law.K1, law.stiffness)
    assert np.max(np.abs(got - ref)) <= TOL * np.max(np.abs(ref))


def test_moved_state_geometry_equals_numpy():
    """RodState.moved's one compiled pass (frame_kernels.moved_geometry) gives the tangents,
    transported directors, material frames and twists of the numpy formulas (frames.py)."""
    from lcefem.solvers.der import frames as fr

    rng = np.random.default_rng(19)
    n = 9
    state = ribbon_state(n, rng)
    moved = state.moved(0.05 * rng.standard_normal(4 * n - 1))
    geo = moved.geometry()  # set by moved()
    e = np.diff(moved.x, axis=0)
    t = e / np.linalg.norm(e, axis=1)[:, None]
    a1 = fr.transport_directors(state.a1, state.tangents, t)
    ref = fr.reference_twist(a1, t, state.ref_twist)
    m1, m2 = fr.material_frames(a1, t, moved.theta)
    assert np.max(np.abs(geo.t - t)) <= TOL
    assert np.max(np.abs(moved.a1 - a1)) <= TOL and np.max(np.abs(moved.ref_twist - ref)) <= TOL
    assert np.max(np.abs(geo.m1 - m1)) <= TOL and np.max(np.abs(geo.m2 - m2)) <= TOL
    assert np.max(np.abs(geo.twist - (np.diff(moved.theta) + ref))) <= TOL
