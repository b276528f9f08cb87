"""Our Discrete Elastic Rods beside DisMech (the Jawed lab's implicit DER) on DisMech's own rod
cantilever, at matched accuracy, CPU seconds on one core, both codes in one process.

    python benchmarks/dismech_benchmark.py [--target 0.05]
        [--csv validation/data/dismech_benchmark.csv]

The peer: dismech-python (github.com/StructuresComp/dismech-python, commit f9d1e2c, 2025-07-24; not
on PyPI, so ``pip install <its source>``: a benchmark-only dependency, never imported by our
solvers). Its C++ sibling dismech-rods was not built. dismech-python has no contact yet (its
README's TODO: "IMC rod contact and friction modeling"), so the shared problem is contact-free.

The problem: ``experiments/rod_cantilever_n51.ipynb`` of dismech-python, unchanged: a 100 mm strip
(20 mm wide, 1 mm thick: A = b h, I = b h^3/12 for the soft bending, J = b h^3/6 as DisMech takes
it), E = 2 MPa, nu = 0.5, rho = 1200 kg/m^3, 51 nodes, nodes 0-5 clamped (the first 10 mm), released
straight and horizontal under g = 9.81 m/s^2; implicit Euler at dt = 0.01 s for 1 s. q L^3/EI = 51
over the free 90 mm: a large deflection (the tip hangs 83 mm down), so the small-deflection formula
does not apply; the static reference is the inextensible heavy elastica EI theta'' = q (L - s) cos
theta, theta(0) = 0, theta'(L) = 0, solved by scipy's ``solve_bvp`` (:func:`heavy_elastica_tip`).

1. Static: ours by Newton (``solve_static``), DisMech by its ``static_sim`` (Newton without inertia,
   one step); each tip against the elastica (the discretisation error of 51 nodes, the same in
   both).
2. The example's run: 1 s at dt = 0.01 s, both codes; their tip paths (x, z every 0.01 s) and
   energies at the end (elastic + gravity + kinetic, 0 at the start; implicit Euler dissipates it)
   compared.
   Not converged in time (at 0.01 s the first swing is 37 % off, and after ~0.5 s the whipping strip
   is path-sensitive: ours at dt 1.25e-4 and 6.25e-5 s differ by 9 % of the tip displacement), so:
3. Matched accuracy over the first swing (0.3 s): each code's tip path against its own run at
   dt = 7.8e-5 s, for dt = 0.01 ... 0.000625 s; the error is the largest tip distance over the
   elastica's static tip displacement (106.6 mm). Each code is timed at the largest step of that
   ladder whose error is <= ``--target`` (5 %), so both are then equally accurate.
   Tolerances: DisMech's example (|F| < 1e-4 N, or |F| < 1e-4 |F_0|, or max |dq|/dt < 0.01 m/s,
   at most 25 iterations); ours |gradient| < 1e-4 N (the same force bound), our default otherwise.
CPU time (``time.process_time``) with this process pinned to one core and the thread pools at one
thread. Not a test (the problem's physics is: ``tests/validation/test_dismech_benchmark.py``).
"""

from __future__ import annotations

import os

# One core for both codes: the thread pools read these when numpy / numba load.
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import csv  # noqa: E402
import dataclasses  # noqa: E402
import importlib.util  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

DISMECH_COMMIT = "f9d1e2c6c0295827f41ba05ff536b8943b09a891"
DT_LADDER = (0.01, 0.005, 0.0025, 0.00125, 0.000625)  # [s] the steps tried for matched accuracy
REFERENCE_DT = 0.01 / 128  # [s] each code's own reference for the ladder
MATCH_TIME = 0.3  # [s] the fall and the first rebound (later the whipping strip is path-sensitive)
SAMPLE = 0.01  # [s] the tip path is compared at multiples of this


@dataclasses.dataclass(frozen=True)
class StripCantilever:
    """dismech-python's rod cantilever in our units (mm, t, s, N, MPa)."""

    length: float = 100.0  # [mm] (the example's node file: 51 nodes 2 mm apart)
    width: float = 20.0  # [mm] (b = 0.02 m)
    thickness: float = 1.0  # [mm] (h = 0.001 m)
    youngs_modulus: float = 2.0  # [MPa] (2e6 Pa)
    poisson: float = 0.5  # [-]
    density: float = 1.2e-9  # [t/mm^3] (1200 kg/m^3)
    gravity: float = 9810.0  # [mm/s^2] (the example's 9.81 m/s^2)
    nodes: int = 51
    clamped_length: float = 10.0  # [mm] (nodes 0-5 of 51 fixed)
    total_time: float = 1.0  # [s]

    @property
    def area(self) -> float:
        return self.width * self.thickness

    @property
    def bending_stiffness(self) -> float:
        """E b h^3/12 [N mm^2] (the soft direction, along gravity)."""
        return self.youngs_modulus * self.width * self.thickness**3 / 12.0

    @property
    def weight_per_length(self) -> float:
        """q = rho A g [N/mm]."""
        return self.density * self.area * self.gravity

    @property
    def clamped_nodes(self) -> int:
        return int(round(self.clamped_length / (self.length / (self.nodes - 1)))) + 1


def heavy_elastica_tip(c: StripCantilever) -> tuple[float, float]:
    """Tip (x, z) [mm] of the inextensible clamped heavy elastica, the clamp at x = clamped_length.

    EI theta'' = q (L_f - s) cos theta on 0 <= s <= L_f = L - clamped_length, theta(0) = 0 (clamped
    horizontal), theta'(L_f) = 0 (free end); x' = cos theta, z' = sin theta. The load is raised in
    ten steps, each solution the guess of the next (q L_f^3/EI = 51 is far from the straight guess).
    """
    from scipy.integrate import solve_bvp

    lf, ei = c.length - c.clamped_length, c.bending_stiffness
    s = np.linspace(0.0, lf, 201)
    y = np.zeros((4, s.size))
    y[2] = s
    for q in np.linspace(0.1, 1.0, 10) * c.weight_per_length:

        def rhs(s, y, q=q):
            return np.vstack([y[1], q * (lf - s) * np.cos(y[0]) / ei, np.cos(y[0]), np.sin(y[0])])

        def bc(ya, yb):
            return np.array([ya[0], yb[1], ya[2], ya[3]])

        sol = solve_bvp(rhs, bc, s, y, tol=1e-10, max_nodes=100000)
        if not sol.success:
            raise RuntimeError(
                f"heavy elastica: solve_bvp failed at q = {q:.4g} N/mm: {sol.message}"
            )
        s, y = sol.x, sol.y
    return c.clamped_length + float(y[2, -1]), float(y[3, -1])


# ----------------------------------------------------------------------------------------------
# Ours
# ----------------------------------------------------------------------------------------------
def our_rod(c: StripCantilever):
    """(DiscreteRod, RodState): DisMech's section constants (J = b h^3/6, edge inertia rho J), m1
    along y (the wide direction: EI1 = E h b^3/12), m2 along z (EI2 = E b h^3/12, soft)."""
    from lcefem.models.rod import RodSection
    from lcefem.solvers.der.model import DiscreteRod, RestShape, RodState, lumped_masses, n_dofs

    b, h, e = c.width, c.thickness, c.youngs_modulus
    polar = b * h**3 / 6.0  # [mm^4] DisMech's jxs
    sec = RodSection(
        EA=e * b * h,
        EI1=e * h * b**3 / 12.0,
        EI2=c.bending_stiffness,
        GJ=e / (2.0 * (1.0 + c.poisson)) * polar,
        mass_per_length=c.density * b * h,
        inertia_per_length=c.density * polar,
        width=0.0,
        thickness=0.0,
    )
    x = np.zeros((c.nodes, 3))
    x[:, 0] = np.linspace(0.0, c.length, c.nodes)
    state = RodState.from_positions(x, first_director=np.array([0.0, 1.0, 0.0]))
    rest = RestShape.straight(np.full(c.nodes - 1, c.length / (c.nodes - 1)))
    nm, ei = lumped_masses(sec, rest.edge_length)
    fixed = np.zeros(n_dofs(c.nodes), bool)
    fixed[: 4 * c.clamped_nodes - 1] = True  # the clamped nodes and the edge angles between them
    rod = DiscreteRod(sec, rest, nm, ei, gravity=np.array([0.0, 0.0, -c.gravity]), fixed=fixed)
    return rod, state


def our_static(c: StripCantilever, increments: int = 1) -> dict:
    """Tip (x, z) [mm], CPU [s] and Newton iterations of ``solve_static`` from the straight rod."""
    from lcefem.solvers.der.static import solve_static

    rod, state = our_rod(c)
    t0 = time.process_time()
    res = solve_static(rod, state, increments=increments)
    cpu = time.process_time() - t0
    tip = res.state.x[-1]
    return {
        "tip": (float(tip[0]), float(tip[2])),
        "cpu_s": cpu,
        "iterations": getattr(res, "iterations", 0),
    }


def our_dynamics(
    c: StripCantilever, dt: float, total_time: float | None = None, force_tol: float = 1e-4
) -> dict:
    """Implicit Euler at fixed dt for total_time [s] (default the problem's): tip (x, z) [mm] every
    SAMPLE s, CPU [s], Newton iterations per step."""
    from lcefem.solvers.der.integrator import Integrator, StepOptions
    from lcefem.solvers.der.newton import NewtonOptions

    options = StepOptions(method="euler", newton=NewtonOptions(force_tol=force_tol))
    rod, state = our_rod(c)
    integ = Integrator(rod, state, options)
    steps = int(round((total_time or c.total_time) / dt))
    every = int(round(SAMPLE / dt))
    tip = [(state.x[-1, 0], state.x[-1, 2])]
    t0 = time.process_time()
    for i in range(1, steps + 1):
        integ.step(dt)
        if i % every == 0:
            tip.append((integ.state.x[-1, 0], integ.state.x[-1, 2]))
    cpu = time.process_time() - t0
    return {
        "path": np.array(tip),
        "cpu_s": cpu,
        "newton_per_step": integ.total_iterations / steps,
        "energy_mJ": our_energy(rod, integ.state),
    }


def our_energy(rod, state) -> float:
    """Elastic + gravity + kinetic energy [mJ], zero in the straight start at rest:
    E = E_el - sum_i m_i g . x_i + 1/2 sum_i m_i |v_i|^2 + 1/2 sum_e I_e omega_e^2."""
    from lcefem.solvers.der.assembly import Assembly

    elastic = Assembly(rod.n_nodes).elastic(rod, state, 0)[0]
    potential = -float(np.sum(rod.node_mass[:, None] * rod.gravity[None, :] * state.x))
    kinetic = 0.5 * float(
        np.sum(rod.node_mass * np.sum(state.v**2, axis=1))
        + np.sum(rod.edge_inertia * state.omega**2)
    )
    return float(elastic) + potential + kinetic


# ----------------------------------------------------------------------------------------------
# DisMech (SI units inside: m, kg, s, N; converted at the boundary)
# ----------------------------------------------------------------------------------------------
def dismech_robot(c: StripCantilever, dt: float, total_time: float, static: bool):
    """The notebook's robot and implicit Euler stepper; the node list built here equals its
    ``horizontal_rod_n51.txt`` (51 nodes, 2 mm apart, edges i-(i+1))."""
    import dismech

    b, h = c.width * 1e-3, c.thickness * 1e-3
    geom = dismech.GeomParams(
        rod_r0=0.001, shell_h=0, axs=b * h, ixs1=b * h**3 / 12, ixs2=h * b**3 / 12, jxs=b * h**3 / 6
    )
    material = dismech.Material(
        density=c.density * 1e12,
        youngs_rod=c.youngs_modulus * 1e6,
        youngs_shell=0,
        poisson_rod=c.poisson,
        poisson_shell=0,
    )
    params = dismech.SimParams(
        static_sim=static,
        two_d_sim=True,
        use_mid_edge=False,
        use_line_search=False,
        show_floor=False,
        log_data=True,
        log_step=1,
        dt=dt,
        max_iter=25,
        total_time=total_time,
        plot_step=1,
        tol=1e-4,
        ftol=1e-4,
        dtol=1e-2,
    )
    env = dismech.Environment()
    env.add_force("gravity", g=np.array([0.0, 0.0, -c.gravity * 1e-3]))
    nodes = np.zeros((c.nodes, 3))
    nodes[:, 0] = np.linspace(0.0, c.length * 1e-3, c.nodes)
    edges = np.stack([np.arange(c.nodes - 1), np.arange(1, c.nodes)], axis=1).astype(np.int64)
    geo = dismech.Geometry(nodes, edges, np.empty((0, 3), dtype=np.int64))
    robot = dismech.SoftRobot(geom, material, geo, params, env).fix_nodes(
        np.arange(c.clamped_nodes)
    )
    return dismech.ImplicitEulerTimeStepper(robot)


def dismech_static(c: StripCantilever) -> dict:
    stepper = dismech_robot(c, 0.01, 0.01, static=True)
    t0 = time.process_time()
    robots = stepper.simulate()
    cpu = time.process_time() - t0
    q = robots[-1].state.q
    n = 3 * (c.nodes - 1)
    return {"tip": (1e3 * q[n], 1e3 * q[n + 2]), "cpu_s": cpu}


def dismech_dynamics(c: StripCantilever, dt: float, total_time: float | None = None) -> dict:
    stepper = dismech_robot(c, dt, (total_time or c.total_time) + 0.5 * dt, static=False)
    t0 = time.process_time()
    robots = stepper.simulate()  # the states after steps 1 .. total_time/dt
    cpu = time.process_time() - t0
    every = int(round(SAMPLE / dt))
    n = 3 * (c.nodes - 1)
    tip = [(c.length, 0.0)] + [
        (1e3 * r.state.q[n], 1e3 * r.state.q[n + 2]) for r in robots[every - 1 :: every]
    ]
    return {"path": np.array(tip), "cpu_s": cpu, "energy_mJ": dismech_energy(stepper, robots[-1])}


def dismech_energy(stepper, robot) -> float:
    """The same energy as :func:`our_energy` from DisMech's state (SI, J -> mJ): its elastic energy,
    -sum M g . q over the node dofs, 1/2 sum M u^2 over all dofs (M: its lumped mass vector)."""
    mass, q, u = robot.mass_matrix, robot.state.q, robot.state.u
    nodes = robot.node_dof_indices  # (N, 3)
    potential = -float(np.sum(mass[nodes] * robot.env.g[None, :] * q[nodes]))
    kinetic = 0.5 * float(np.sum(mass * u**2))
    return 1e3 * (float(stepper.compute_total_elastic_energy(robot.state)) + potential + kinetic)


# ----------------------------------------------------------------------------------------------
def path_error(path: np.ndarray, ref: np.ndarray, scale: float) -> float:
    """Largest tip distance between two sampled paths [mm] over ``scale`` [mm]."""
    m = min(len(path), len(ref))
    return float(np.max(np.hypot(*(path[:m] - ref[:m]).T))) / scale


def compare_dynamics(
    name: str, run, c: StripCantilever, scale: float, target: float
) -> tuple[list[dict], dict]:
    """The first swing (MATCH_TIME) at each dt of the ladder against the same code at REFERENCE_DT;
    marks the largest dt within ``target``. Returns the rows and the reference run."""
    ref = run(c, REFERENCE_DT, MATCH_TIME)
    rows, matched = [], None
    for dt in DT_LADDER:
        r = run(c, dt, MATCH_TIME)
        err = path_error(r["path"], ref["path"], scale)
        row = {
            "code": name,
            "problem": f"first swing {MATCH_TIME:g} s",
            "dt_s": dt,
            "cpu_s": r["cpu_s"],
            "error": err,
            "reference": f"same code at dt {REFERENCE_DT:g} s",
            "newton_per_step": r.get("newton_per_step"),
            "tip_x_mm": float(r["path"][-1, 0]),
            "tip_z_mm": float(r["path"][-1, 1]),
            "energy_mJ": r["energy_mJ"],
            "matched": False,
        }
        rows.append(row)
        print(
            f"  {name:8s} dt {dt:9.6f} s: CPU {r['cpu_s']:7.3f} s, path error {100 * err:6.2f} %, "
            "energy "
            "at "
            f"{MATCH_TIME:g} s {r['energy_mJ']:.5f} mJ (reference {ref['energy_mJ']:.5f})"
            + (f", {r['newton_per_step']:.2f} Newton/step" if "newton_per_step" in r else ""),
            flush=True,
        )
        if err <= target and matched is None:
            matched = row
    if matched is not None:
        matched["matched"] = True
    return rows, ref


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--target",
        type=float,
        default=0.05,
        help="matched accuracy: tip path error over the static tip displacement [-]",
    )
    parser.add_argument(
        "--csv", help="write the table here (e.g. validation/data/dismech_benchmark.csv)"
    )
    args = parser.parse_args(argv)
    if not 0 < args.target < 1:
        print(f"--target {args.target}: must be in (0, 1)", file=sys.stderr)
        return 2
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    c = StripCantilever()
    have_peer = importlib.util.find_spec("dismech") is not None
    print(
        f"DisMech benchmark: {platform.processor() or platform.machine()}, python "
        f"{platform.python_version()}, "
        f"one core, CPU seconds; dismech-python {DISMECH_COMMIT[:7]}"
        + ("" if have_peer else " NOT INSTALLED (pip install <its source>): ours only")
    )
    x_ref, z_ref = heavy_elastica_tip(c)
    scale = math.hypot(
        c.length - x_ref, z_ref
    )  # [mm] the static tip's distance from the straight tip
    print(
        f"static reference (heavy elastica, solve_bvp): tip ({x_ref:.4f}, {z_ref:.4f}) mm, "
        f"tip displacement {scale:.3f} mm"
    )
    our_static(c)  # numba compilation / cache load outside the timing
    rows = []
    statics = [("ours", our_static)] + ([("DisMech", dismech_static)] if have_peer else [])
    for name, run in statics:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # DisMech's np.divide(where=) warning, harmless here
            r = run(c)
        err = math.hypot(r["tip"][0] - x_ref, r["tip"][1] - z_ref) / scale
        print(
            f"  {name:8s} static: tip ({r['tip'][0]:.4f}, {r['tip'][1]:.4f}) mm, error "
            f"{100 * err:.3f} "
            "% "
            f"of the tip displacement, CPU {r['cpu_s']:.4f} s"
        )
        rows.append(
            {
                "code": name,
                "problem": "static",
                "dt_s": None,
                "cpu_s": r["cpu_s"],
                "error": err,
                "reference": "heavy elastica",
                "tip_x_mm": r["tip"][0],
                "tip_z_mm": r["tip"][1],
                "matched": True,
            }
        )
    for _ in range(2):  # compilation and numba cache loads outside the timing
        our_dynamics(c, 0.01)
    codes = [("ours", our_dynamics)] + ([("DisMech", dismech_dynamics)] if have_peer else [])
    print(f"the example's run (implicit Euler, dt 0.01 s, {c.total_time:g} s):")
    example = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # DisMech's np.divide(where=) warning, harmless here
        for name, run in codes:
            example[name] = r = run(c, 0.01)
            print(
                f"  {name:8s}: CPU {r['cpu_s']:.3f} s, tip at {c.total_time:g} s "
                f"({r['path'][-1, 0]:.3f}, "
                f"{r['path'][-1, 1]:.3f}) mm, energy {r['energy_mJ']:.5f} mJ"
                + (f", {r['newton_per_step']:.2f} Newton/step" if "newton_per_step" in r else "")
            )
            rows.append(
                {
                    "code": name,
                    "problem": f"example run {c.total_time:g} s",
                    "dt_s": 0.01,
                    "cpu_s": r["cpu_s"],
                    "newton_per_step": r.get("newton_per_step"),
                    "tip_x_mm": float(r["path"][-1, 0]),
                    "tip_z_mm": float(r["path"][-1, 1]),
                    "energy_mJ": r["energy_mJ"],
                    "reference": "",
                    "matched": False,
                }
            )
        if have_peer:
            gap = path_error(example["ours"]["path"], example["DisMech"]["path"], scale)
            print(
                f"  the two paths differ by at most {100 * gap:.3f} % of the tip displacement "
                "(same "
                "discretisation"
                " and scheme); DisMech / ours CPU: "
                f"{example['DisMech']['cpu_s'] / example['ours']['cpu_s']:.1f} "
                "x"
            )
            rows.append(
                {
                    "code": "ours vs DisMech",
                    "problem": f"example run {c.total_time:g} s",
                    "dt_s": 0.01,
                    "error": gap,
                    "reference": "the other code",
                }
            )
        print(
            f"matched accuracy (implicit Euler, first {MATCH_TIME:g} s; error: largest tip "
            "distance to the "
            "same "
            f"code at dt {REFERENCE_DT:g} s over the {scale:.2f} mm tip displacement; target "
            f"{100 * args.target:g} %):"
        )
        dyn, refs = {}, {}
        for name, run in codes:
            dyn[name], refs[name] = compare_dynamics(name, run, c, scale, args.target)
            rows += dyn[name]
    summary = {name: next((r for r in v if r["matched"]), None) for name, v in dyn.items()}
    print("summary (CPU seconds, one core):")
    for name, r in summary.items():
        if r is None:
            print(f"  {name:8s}: no step of the ladder within {100 * args.target:g} %")
        else:
            print(
                f"  {name:8s}: dt {r['dt_s']:g} s, {r['cpu_s']:.3f} s (error "
                f"{100 * r['error']:.2f} "
                "%)"
            )
    if have_peer:
        gap = path_error(refs["ours"]["path"], refs["DisMech"]["path"], scale)
        print(f"  the two references differ by {100 * gap:.1e} % of the tip displacement")
        rows.append(
            {
                "code": "ours vs DisMech",
                "problem": f"first swing {MATCH_TIME:g} s",
                "dt_s": REFERENCE_DT,
                "error": gap,
                "reference": "the other code's reference",
            }
        )
        if summary.get("ours") and summary.get("DisMech"):
            print(
                "  DisMech / ours at matched accuracy: "
                f"{summary['DisMech']['cpu_s'] / summary['ours']['cpu_s']:.1f} "
                "x"
            )
    if args.csv:
        keys = [
            "code",
            "problem",
            "dt_s",
            "cpu_s",
            "error",
            "matched",
            "reference",
            "newton_per_step",
            "tip_x_mm",
            "tip_z_mm",
            "energy_mJ",
        ]
        header = [
            "code",
            "problem",
            "dt [s]",
            "cpu [s]",
            "error [-] (tip distance / static tip displacement)",
            "matched [bool]",
            "reference",
            "newton per step [-]",
            "tip x [mm]",
            "tip z [mm]",
            "energy at the end [mJ] (elastic + gravity + kinetic; 0 at the start)",
        ]
        tmp = args.csv + ".part"
        with open(tmp, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            for r in rows:
                w.writerow(
                    [
                        ""
                        if r.get(k) is None
                        else (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k])
                        for k in keys
                    ]
                )
        os.replace(tmp, args.csv)
        print(f"written {args.csv}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
