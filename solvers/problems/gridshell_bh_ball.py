"""Fig. 5B of seed 001: a rigid ball rolling under gravity on the morphing, covered surface.

The surface is quasi-static (bar-and-hinge equilibria along a programmed morph, the ball's weight
not fed back: the seed notes that it "affects the overall posture", an effect left out here); the
ball is dynamic. The surface the ball rolls on is the quadratic fit through the nine scale centres
(the paper's own description of the covered surface, Fig. 5A), z = f(x, y, t), over the scales'
footprint (|x - x_c|, |y - y_c| <= pitch + disk radius); its coefficients are interpolated linearly
in time between the computed equilibria. Beyond the footprint the ball has left the surface
(released).

The ball's centre rides at r along the normal above the contact point, c = p + r n; we approximate
its path by h(x, y, t) = f + r sqrt(1 + |grad f|^2) over the contact point (the centre's height, its
horizontal shift -r grad f/sqrt(1 + |grad f|^2) neglected): exact on a plane, the path's curvature
kappa (1 + r kappa) instead of 1/(1/kappa - r) in a bowl (3.7 % less at r kappa = 0.19, the bowl
here; periods 1.9 % long; tests/solvers/test_gridshell_ball.py). It rolls
without slipping (checked: the friction the rolling needs, (2/7) m g sin(theta), against mu N), so
its kinetic energy is (7/5) m |v_c|^2 / 2. Lagrange's equations in q = (x, y) with z = h(q, t):

    (I + grad h grad h^T) q'' = -(g/k) grad h - grad h (q'^T H q' + 2 grad h_t . q' + h_tt)
                                + Q_rr/(k m),

k = 7/5, with the rolling resistance Q_rr = -C_rr N v_c/max(|v_c|, v_creep) projected on q
(N = m g / sqrt(1 + |grad h|^2), the quasi-static normal force). Derivatives of h in closed form
(f quadratic in u, v and linear in t between frames). Integrated by scipy's RK45 (max step 5 ms)
with a terminal event at the footprint's edge.

Units: mm, t, s, N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from lcefem.models import units
from lcefem.models.ball import Ball
from lcefem.solvers.analysis.curvature import junction_centre_points


def quadratic_coefficients(structure, x, centre: np.ndarray) -> np.ndarray:
    """Least-squares z = c0 + c1 u + c2 v + c3 u^2 + c4 u v + c5 v^2 through the scale (junction)
    centres, u, v = x - x_c, y - y_c [mm]; returns (6,)."""
    p = junction_centre_points(structure, np.asarray(x).reshape(-1, 3)).reshape(-1, 3)
    u, v = p[:, 0] - centre[0], p[:, 1] - centre[1]
    a = np.column_stack([np.ones_like(u), u, v, u * u, u * v, v * v])
    return np.linalg.lstsq(a, p[:, 2], rcond=None)[0]


@dataclass
class SurfaceHistory:
    """The ball's surface over time: fit coefficients at times [s] (linear in between)."""

    times: np.ndarray  # (k,) [s], increasing
    coefficients: np.ndarray  # (k, 6)
    centre: np.ndarray  # (2,) [mm]
    half_width: float  # [mm] of the square footprint

    def coeffs(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(c(t), dc/dt) [mm^(1-i)...]: linear interpolation between the frames (rate of the
        segment)."""
        t = float(np.clip(t, self.times[0], self.times[-1]))
        k = int(np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, len(self.times) - 2))
        t0, t1 = self.times[k], self.times[k + 1]
        rate = (self.coefficients[k + 1] - self.coefficients[k]) / (t1 - t0)
        return self.coefficients[k] + (t - t0) * rate, rate

    @staticmethod
    def surface(c: np.ndarray, u: float, v: float) -> float:
        return c[0] + c[1] * u + c[2] * v + c[3] * u * u + c[4] * u * v + c[5] * v * v

    def centre_height(self, u: float, v: float, t: float, radius: float, derivatives: bool = False):
        """h [mm]: the ball centre's height above the contact point's (u, v) (module docstring);
        with ``derivatives`` also grad h, its Hessian, grad h_t, h_t and h_tt (f quadratic: closed
        forms)."""
        c, cd = self.coeffs(t)
        g = np.array([c[1] + 2.0 * c[3] * u + c[4] * v, c[2] + c[4] * u + 2.0 * c[5] * v])
        s = np.sqrt(1.0 + g @ g)
        h = self.surface(c, u, v) + radius * s
        if not derivatives:
            return h
        hf = np.array([[2.0 * c[3], c[4]], [c[4], 2.0 * c[5]]])
        gt = np.array([cd[1] + 2.0 * cd[3] * u + cd[4] * v, cd[2] + cd[4] * u + 2.0 * cd[5] * v])
        hft = np.array([[2.0 * cd[3], cd[4]], [cd[4], 2.0 * cd[5]]])
        hg = hf @ g
        grad = g + radius * hg / s
        hess = hf + radius * (hf @ hf / s - np.outer(hg, hg) / s**3)
        gg_t = g @ gt
        h_t = self.surface(cd, u, v) + radius * gg_t / s
        grad_t = gt + radius * ((hft @ g + hf @ gt) / s - hg * gg_t / s**3)
        h_tt = radius * (gt @ gt / s - gg_t**2 / s**3)
        return h, grad, hess, grad_t, h_t, h_tt


def roll(
    history: SurfaceHistory,
    ball: Ball,
    start: tuple[float, float],
    t_start: float,
    t_end: float,
    gravity: float = units.STANDARD_GRAVITY,
    max_step: float = 5.0e-3,
    samples: int = 400,
) -> dict:
    """The ball from rest at ``start`` (u, v) [mm] (relative to the centre) from ``t_start`` to
    ``t_end`` [s], or until it leaves the footprint. Returns time [s], u, v, z of its centre [mm],
    speed [mm/s], the friction it needs over mu N (max), and the exit (None, '+x', '-x', '+y',
    '-y')."""
    r, k = ball.radius, ball.rolling_inertia_factor

    def h(u, v, t):
        return history.centre_height(u, v, t, r)

    def derivs(u, v, t):
        return history.centre_height(u, v, t, r, derivatives=True)

    def rhs(t, y):
        u, v, qu, qv = y
        _, g1, hess, gt, ht, htt = derivs(u, v, t)
        qd = np.array([qu, qv])
        a = np.eye(2) + np.outer(g1, g1)
        vz = g1 @ qd + ht
        speed = np.sqrt(qd @ qd + vz * vz)
        normal = gravity / np.sqrt(1.0 + g1 @ g1)  # N/m
        resist = -ball.rolling_resistance * normal * (qd + g1 * vz) / max(speed, ball.creep_speed)
        b = -(gravity / k) * g1 - g1 * (qd @ hess @ qd + 2.0 * gt @ qd + htt) + resist / k
        acc = np.linalg.solve(a, b)
        return [qu, qv, acc[0], acc[1]]

    hw = history.half_width

    def leave(t, y):
        return hw - max(abs(y[0]), abs(y[1]))

    leave.terminal = True
    leave.direction = -1

    sol = solve_ivp(
        rhs,
        (t_start, t_end),
        [start[0], start[1], 0.0, 0.0],
        method="RK45",
        max_step=max_step,
        events=leave,
        dense_output=True,
        rtol=1e-7,
        atol=1e-9,
    )
    t_stop = float(sol.t[-1])
    times = np.linspace(t_start, t_stop, samples)
    y = sol.sol(times)
    z = np.array([h(ui, vi, ti) for ui, vi, ti in zip(y[0], y[1], times)])
    demand = 0.0
    for ui, vi, ti in zip(y[0], y[1], times):
        g1 = derivs(ui, vi, ti)[1]
        tan = np.sqrt(g1 @ g1)
        demand = max(demand, (2.0 / 7.0) * tan / ball.friction)  # (2/7) m g sin / (mu m g cos)
    exit_side = None
    if sol.status == 1:
        ue, ve = y[0][-1], y[1][-1]
        exit_side = ("+x" if ue > 0 else "-x") if abs(ue) >= abs(ve) else ("+y" if ve > 0 else "-y")
    return {
        "time [s]": times,
        "u [mm]": y[0],
        "v [mm]": y[1],
        "z [mm]": z,
        "speed [mm/s]": np.hypot(y[2], y[3]),
        "friction demand [-]": demand,
        "exit": exit_side,
        "end time [s]": t_stop,
    }
