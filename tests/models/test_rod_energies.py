"""Discrete-elastic-rod energies of lcefem.models.rod: finite-difference checks of every analytic
gradient and Hessian, and the section properties.

Frames: the energies are differentiated with the reference frame transported from a source
tangent (:func:`lcefem.models.rod.parallel_transport`); the checks evaluate the energy of perturbed
configurations with exactly that transport. Tolerances: gradients to 1e-7 of their largest entry
(central differences, h = 1e-6), Hessians to 1e-6 of their largest entry (second differences,
h = 1e-4, truncation ~h^2).
"""

import math

import numpy as np
import pytest

from lcefem.models import rod
from lcefem.solvers.der import frames as fr

EYE11 = np.eye(11)


def stencil_setup(seed, move_source=False):
    rng = np.random.default_rng(seed)
    xs = np.array(
        [[0.0, 0.0, 0.0], [1.0, 0.1, 0.05], [1.8, 0.6, -0.2]]
    ) + 0.1 * rng.standard_normal((3, 3))
    s = fr.unit(fr.edges_of(xs))
    a1s = fr.transport_directors(fr.perpendicular_director(s, rng.standard_normal(3)), s, s)
    refs = fr.reference_twist(a1s, s)
    x = xs + (0.15 * rng.standard_normal((3, 3)) if move_source else 0.0)
    theta = rng.standard_normal(2)
    q0 = np.concatenate([x[0], [theta[0]], x[1], [theta[1]], x[2]])
    return s, a1s, refs, q0


def unpack(q):
    return np.array([q[0:3], q[4:7], q[8:11]]), np.array([q[3], q[7]])


def frames_at(q, s, a1s, refs):
    x, th = unpack(q)
    t = fr.unit(fr.edges_of(x))
    a1 = rod.parallel_transport(a1s, s, t)
    ref = fr.reference_twist(a1, t, refs)
    m1, m2 = fr.material_frames(a1, t, th)
    return x, th, t, a1, ref, m1, m2


KBAR = np.array([[0.3, -0.2]])
TBAR = np.array([0.4])
VOR = np.array([1.1])
STIFF = (2.0, 0.7, 0.5)


def bend_twist_energy(q, s, a1s, refs):
    x, th, t, a1, ref, m1, m2 = frames_at(q, s, a1s, refs)
    e, f = x[1] - x[0], x[2] - x[1]
    return rod.bend_twist(
        e[None],
        f[None],
        m1[:1],
        m2[:1],
        m1[1:],
        m2[1:],
        th[1] - th[0] + ref,
        KBAR,
        TBAR,
        VOR,
        *STIFF,
    )[0][0]


def fd_gradient(fun, q0, h=1e-6):
    return np.array(
        [(fun(q0 + h * EYE11[i]) - fun(q0 - h * EYE11[i])) / (2 * h) for i in range(len(q0))]
    )


def fd_hessian(fun, q0, h=1e-4):
    n = len(q0)
    H = np.empty((n, n))
    for i in range(n):
        for j in range(i, n):
            ei, ej = EYE11[i][:n], EYE11[j][:n]
            H[i, j] = H[j, i] = (
                fun(q0 + h * (ei + ej))
                - fun(q0 + h * (ei - ej))
                - fun(q0 - h * (ei - ej))
                + fun(q0 - h * (ei + ej))
            ) / (4 * h * h)
    return H


def test_stretching_derivatives():
    rng = np.random.default_rng(0)
    e = rng.standard_normal((4, 3))
    rest = np.array([1.0, 2.0, 0.5, 1.5])
    E, g, H = rod.stretching(e, rest, 3.0)
    for k in range(4):
        fun = lambda v, k=k: rod.stretching(v[None], rest[k : k + 1], 3.0)[0][0]  # noqa: E731
        g_fd = np.array([(fun(e[k] + 1e-6 * d) - fun(e[k] - 1e-6 * d)) / 2e-6 for d in np.eye(3)])
        H_fd = np.array(
            [
                (
                    rod.stretching((e[k] + 1e-6 * d)[None], rest[k : k + 1], 3.0)[1][0]
                    - rod.stretching((e[k] - 1e-6 * d)[None], rest[k : k + 1], 3.0)[1][0]
                )
                / 2e-6
                for d in np.eye(3)
            ]
        )
        assert np.allclose(g[k], g_fd, rtol=0, atol=1e-7 * np.abs(g[k]).max())
        assert np.allclose(H[k], H_fd, rtol=0, atol=1e-6 * np.abs(H[k]).max())
    assert E[1] == pytest.approx(0.5 * 3.0 * (np.linalg.norm(e[1]) / 2.0 - 1) ** 2 * 2.0)


@pytest.mark.parametrize("move_source", [False, True])
def test_bend_twist_derivatives(move_source):
    """At the transport source the element derivatives are exact; away from it, after the chain rule
    of apply_source_change (the holonomy of the transport)."""
    s, a1s, refs, q0 = stencil_setup(1, move_source)
    fun = lambda q: bend_twist_energy(q, s, a1s, refs)  # noqa: E731
    x, th, t, a1, ref, m1, m2 = frames_at(q0, s, a1s, refs)
    e, f = x[1] - x[0], x[2] - x[1]
    E, g8, H8 = rod.bend_twist(
        e[None],
        f[None],
        m1[:1],
        m2[:1],
        m1[1:],
        m2[1:],
        th[1] - th[0] + ref,
        KBAR,
        TBAR,
        VOR,
        *STIFF,
    )
    g = g8 @ rod.STENCIL_MAP.T
    H = rod.STENCIL_MAP @ H8 @ rod.STENCIL_MAP.T
    if move_source:
        db, ddb = rod.source_change(s, t, np.linalg.norm(fr.edges_of(x), axis=1))
        g, H = rod.apply_source_change(
            g, H, ((0, 3, 4), (4, 7, 8)), (db[:1], db[1:]), (ddb[:1], ddb[1:])
        )
    assert E[0] == pytest.approx(fun(q0), rel=1e-12)
    g_fd, H_fd = fd_gradient(fun, q0), fd_hessian(fun, q0)
    assert np.max(np.abs(g[0] - g_fd)) < 1e-7 * np.max(np.abs(g))
    assert np.max(np.abs(H[0] - H_fd)) < 1e-6 * np.max(np.abs(H))


def test_without_source_change_the_gradient_is_wrong_away_from_the_source():
    """The holonomy term matters: the check above would fail without it (so it can fail)."""
    s, a1s, refs, q0 = stencil_setup(1, True)
    fun = lambda q: bend_twist_energy(q, s, a1s, refs)  # noqa: E731
    x, th, t, a1, ref, m1, m2 = frames_at(q0, s, a1s, refs)
    e, f = x[1] - x[0], x[2] - x[1]
    g8 = rod.bend_twist(
        e[None],
        f[None],
        m1[:1],
        m2[:1],
        m1[1:],
        m2[1:],
        th[1] - th[0] + ref,
        KBAR,
        TBAR,
        VOR,
        *STIFF,
    )[1]
    assert np.max(np.abs(g8 @ rod.STENCIL_MAP.T - fd_gradient(fun, q0))) > 1e-3


def test_section_point_derivatives():
    """Corner points of an edge section (frame of the edge) at sigma = 0.3."""
    rng = np.random.default_rng(4)
    x = np.array([[0.0, 0.0, 0.0], [1.2, 0.3, -0.1]])
    s = fr.unit(fr.edges_of(x))
    a1s = fr.perpendicular_director(s, rng.standard_normal(3))
    offsets = rod.CORNER_SIGNS * np.array([1.5, 0.3])
    g = rng.standard_normal((1, 4, 3))
    q0 = np.concatenate([x[0], [0.4], x[1]])

    def points(q):
        xx = np.array([q[0:3], q[4:7]])
        t = fr.unit(fr.edges_of(xx))
        m1, m2 = fr.material_frames(rod.parallel_transport(a1s, s, t), t, np.array([q[3]]))
        return rod.section_points(xx[:1], xx[1:], m1, m2, offsets, 0.3)

    m1, m2 = fr.material_frames(a1s, s, np.array([0.4]))
    jac, hess = rod.section_point_derivatives(x[:1], x[1:], m1, m2, offsets, g, 0.3)
    eye = np.eye(7)
    j_fd = np.stack([(points(q0 + 1e-6 * d) - points(q0 - 1e-6 * d)) / 2e-6 for d in eye], axis=-1)
    assert np.max(np.abs(jac - j_fd)) < 1e-8
    fun = lambda q: float(np.sum(g * points(q)))  # noqa: E731
    H_fd = np.array(
        [
            [
                (
                    fun(q0 + 1e-4 * (a + b))
                    - fun(q0 + 1e-4 * (a - b))
                    - fun(q0 - 1e-4 * (a - b))
                    + fun(q0 - 1e-4 * (a + b))
                )
                / 4e-8
                for b in eye
            ]
            for a in eye
        ]
    )
    assert np.max(np.abs(hess.sum(axis=1)[0] - H_fd)) < 1e-6 * np.max(np.abs(H_fd))


def test_stencil_point_derivatives():
    """Section points between sections, frame angle interpolated with the node's twist."""
    s, a1s, refs, q0 = stencil_setup(2)
    pts = rod.StencilPoints.sampling(rod.CORNER_SIGNS * np.array([1.5, 0.3]), 4)
    rows = np.zeros(len(pts.sigma), int)
    cols = np.arange(len(pts.sigma))
    g = np.random.default_rng(7).standard_normal((len(cols), 3))

    def points(q):
        x, th, t, a1, ref, m1, m2 = frames_at(q, s, a1s, refs)
        return rod.stencil_points(x, a1, t, th, th[1:] - th[:1] + ref, pts, rows, cols)

    p, r, t = points(q0)
    x, _ = unpack(q0)
    jac, hess = rod.stencil_point_derivatives(
        np.repeat([x[1] - x[0]], len(cols), 0),
        np.repeat([x[2] - x[1]], len(cols), 0),
        r,
        t,
        pts.side,
        pts.sigma,
        g,
    )
    j_fd = np.stack(
        [(points(q0 + 1e-6 * d)[0] - points(q0 - 1e-6 * d)[0]) / 2e-6 for d in EYE11], axis=-1
    )
    assert np.max(np.abs(jac - j_fd)) < 1e-8
    fun = lambda q: float(np.sum(g * points(q)[0]))  # noqa: E731
    assert np.max(np.abs(hess.sum(axis=0) - fd_hessian(fun, q0))) < 1e-6 * np.max(
        np.abs(hess.sum(axis=0))
    )
    # The interpolated sections join the edges' own sections at sigma = 1/2 (no jump at the node).
    heights = rod.stencil_point_heights(
        x,
        fr.transport_directors(a1s, s, s),
        s,
        unpack(q0)[1],
        np.array([unpack(q0)[1][1] - unpack(q0)[1][0] + refs[0]]),
        pts,
        np.array([0.0, 0.0, 1.0]),
    )
    assert np.allclose(heights[0], p[:, 2], atol=1e-12)


def timoshenko_torsion_constant(w, t, terms=200):
    """Exact series J = w t^3/3 [1 - (192/pi^5)(t/w) sum_n odd tanh(n pi w/(2t))/n^5] (Timoshenko &
    Goodier, Theory of Elasticity, Sec. 109)."""
    n = np.arange(1, 2 * terms, 2)
    return (
        w
        * t**3
        / 3.0
        * (1.0 - 192.0 / math.pi**5 * (t / w) * np.sum(np.tanh(n * math.pi * w / (2 * t)) / n**5))
    )


@pytest.mark.parametrize("ratio", [1.0, 2.0, 5.0, 20.0])
def test_torsion_constant_against_exact_series(ratio):
    """Roark's formula is within 0.5 % of the exact series for every aspect ratio (Roark, Table
    10.7)."""
    assert rod.torsion_constant_rectangle(ratio, 1.0) == pytest.approx(
        timoshenko_torsion_constant(ratio, 1.0), rel=5e-3
    )


def test_thin_strip_limit_and_section():
    assert rod.torsion_constant_rectangle(1000.0, 1.0) == pytest.approx(1000.0 / 3.0, rel=1e-3)
    sec = rod.rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    assert sec.EA == pytest.approx(0.52 * 3.2)
    assert sec.EI1 == pytest.approx(0.52 * 0.8 * 64 / 12)  # in-plane (towards m1, the width)
    assert sec.EI2 == pytest.approx(0.52 * 4.0 * 0.512 / 12)
    assert sec.EI1 / sec.EI2 == pytest.approx(25.0)
    assert sec.inertia_per_length == pytest.approx(1.15e-9 * 3.2 * (16 + 0.64) / 12)


def test_curvature_sign_convention():
    """A polyline turning towards m1 has kappa_1 > 0 (= turning angle 2 tan(phi/2)), kappa_2 = 0."""
    phi = 0.3
    e = np.array([[1.0, 0.0, 0.0]])
    f = np.array([[math.cos(phi), math.sin(phi), 0.0]])
    m1 = np.array([[0.0, 1.0, 0.0]])
    m2 = np.array([[0.0, 0.0, 1.0]])
    # the frame of f is the parallel transport of e's
    t_f = f / np.linalg.norm(f)
    m1f = rod.parallel_transport(m1, e, t_f)
    m2f = rod.cross(t_f, m1f)
    k = rod.material_curvatures(e, f, m1, m2, m1f, m2f)[0]
    assert k[0] == pytest.approx(2 * math.tan(phi / 2))
    assert k[1] == pytest.approx(0.0, abs=1e-15)
