"""The bar-and-hinge tangent's factorisation: our LDL^T against SuperLU and MUMPS (issue 47 item 5).

Ramps the 5 x 5 layout's Fig. 4 dome under the clamp (``layout_benchmark.py``'s ``5x5-dome-clamp``)
and takes the reduced tangent K (free DOFs) of Newton iteration ``--iteration``; on it, CPU ms per
call (``time.process_time``, one thread) of:

- ours: the numeric up-looking LDL^T (solvers/bar_hinge/ldl.py; the symbolic analysis once);
- SuperLU in symmetric mode (MMD on A^T + A, diagonal pivots: Newton's fallback) and SuperLU's
  default (COLAMD, partial pivoting), ordering included (scipy has no reuse of it);
- MUMPS through petsc4py (PCCHOLESKY on a matrix not flagged SPD: sym = 2, LDL^T with 2 x 2
  pivots), upper triangle in SBAIJ or the full AIJ, orderings AMD (ICNTL(7) = 0) and MUMPS's
  choice (7); its first set-up (analysis and factorisation) once, then new values and the
  numeric factorisation only.

Per solver: the negative pivots (ours: of D; MUMPS: INFOG(12)), the solution's relative distance
from ours (K is ill-conditioned near floating parts: ~1e-8 between any two solvers) and the
factor's size. ``--path``: the whole ramp again with every factorisation of Newton by MUMPS (SBAIJ,
AMD, analysis once per pattern of closed contacts) and ours side by side on each matrix: CPU
seconds, inertia disagreements and the end state's curvatures.

    OMP_NUM_THREADS=1 python benchmarks/bh_factorization.py [--iteration 150] [--path]

Not a test: it prints figures for docs/notes/performance_log.md.
"""

from __future__ import annotations

import argparse
import importlib
import time

import dolfinx_solver  # noqa: F401  (before petsc4py: the wheel's PETSc)
from petsc4py import PETSc

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

import layout_benchmark as lb
from lcefem.solvers.bar_hinge.ldl import SymbolicLDL

# the module (lcefem.solvers.bar_hinge exports the function newton under the same name)
newton_module = importlib.import_module("lcefem.solvers.bar_hinge.newton")


class Captured(Exception):
    """Raised by the hook once the tangent is taken (stops the ramp)."""


def capture_tangent(iteration: int) -> tuple[sp.csc_matrix, np.ndarray]:
    """The reduced tangent and right-hand side of Newton iteration ``iteration`` (clamp dome)."""
    original = newton_module._descent_step
    seen, out = [0], {}

    def hook(kmat, rhs, *args, **kwargs):
        seen[0] += 1
        if seen[0] == iteration:
            out["k"], out["rhs"] = kmat.copy(), np.array(rhs)
            raise Captured
        return original(kmat, rhs, *args, **kwargs)

    newton_module._descent_step = hook
    try:
        lb.run_one("5x5-dome-clamp", "fe-calibrated")
    except Captured:
        pass
    finally:
        newton_module._descent_step = original
    if "k" not in out:
        raise SystemExit(f"--iteration {iteration}: the ramp has fewer Newton iterations")
    return out["k"], out["rhs"]


def cpu_ms(f, repeats: int):
    f()
    t0 = time.process_time()
    for _ in range(repeats):
        out = f()
    return (time.process_time() - t0) / repeats * 1e3, out


class Mumps:
    """MUMPS LDL^T (sym = 2) of symmetric CSC matrices of one pattern, analysis once."""

    def __init__(self, k: sp.csc_matrix, fmt: str = "sbaij", ordering: int = 0):
        n = k.shape[0]
        self.n = n
        # a symmetric K's CSC arrays are its CSR arrays
        rows = np.repeat(np.arange(n), np.diff(k.indptr))
        self.keep = k.indices >= rows if fmt == "sbaij" else np.ones(k.nnz, bool)
        self.ip = np.concatenate([[0], np.cumsum(np.bincount(rows[self.keep], minlength=n))])
        self.ip = self.ip.astype(PETSc.IntType)
        self.ii = k.indices[self.keep].astype(PETSc.IntType)
        self.diag = np.flatnonzero(k.indices[self.keep] == rows[self.keep])
        csr = (self.ip, self.ii, k.data[self.keep])
        create = PETSc.Mat().createSBAIJ if fmt == "sbaij" else PETSc.Mat().createAIJ
        self.a = create((n, n), 1, csr=csr) if fmt == "sbaij" else create((n, n), csr=csr)
        self.a.assemble()
        self.a.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        self.ksp = PETSc.KSP().create(PETSc.COMM_SELF)
        self.ksp.setOperators(self.a)
        self.ksp.setType("preonly")
        pc = self.ksp.getPC()
        pc.setType("cholesky")
        pc.setFactorSolverType("mumps")
        pc.setFactorSetUpSolverType()
        self.f = pc.getFactorMatrix()
        self.f.setMumpsIcntl(7, ordering)
        self.b = PETSc.Vec().createSeq(n, comm=PETSc.COMM_SELF)
        self.x = self.b.duplicate()

    def factorize(self, data: np.ndarray, shift: float = 0.0) -> int:
        """Numeric factorisation of the values ``data`` (+ shift I); the negative pivots."""
        values = data[self.keep]
        if shift:
            values[self.diag] += shift
        self.a.setValuesCSR(self.ip, self.ii, values)
        self.a.assemble()
        self.ksp.setOperators(self.a)
        self.ksp.setUp()
        return self.f.getMumpsInfog(12)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        self.b.setArray(rhs)
        self.ksp.solve(self.b, self.x)
        return self.x.getArray().copy()


def compare(k: sp.csc_matrix, rhs: np.ndarray, repeats: int) -> None:
    n = k.shape[0]
    print(f"tangent: {n} free DOFs, {k.nnz} stored entries")
    t0 = time.process_time()
    symbolic = SymbolicLDL(k.indices, k.indptr, n)
    t_sym = (time.process_time() - t0) * 1e3
    ms, ours = cpu_ms(lambda: symbolic.factorize(k.data), repeats)
    ms_solve, x0 = cpu_ms(lambda: ours.solve(rhs), repeats)
    print(
        f"ours LDL^T: numeric {ms:.2f} ms, solve {ms_solve:.2f} ms (symbolic once {t_sym:.0f} ms), "
        f"L entries {int(symbolic.lp[-1])}, negative pivots {int(np.sum(ours.pivots < 0))}"
    )

    def off(x):
        return np.linalg.norm(x - x0) / np.linalg.norm(x0)

    for name, kwargs in (
        (
            "SuperLU symmetric mode (MMD)",
            dict(
                permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
            ),
        ),
        ("SuperLU default (COLAMD)", {}),
    ):
        ms, lu = cpu_ms(lambda kw=kwargs: sla.splu(k, **kw), max(repeats // 3, 1))
        print(
            f"{name}: {ms:.2f} ms with its ordering, L+U entries {lu.L.nnz + lu.U.nnz}, "
            f"solution off by {off(lu.solve(rhs)):.1e}"
        )
    for fmt in ("sbaij", "aij"):
        for ordering, label in ((0, "AMD"), (7, "auto")):
            t0 = time.process_time()
            m = Mumps(k, fmt, ordering)
            m.factorize(k.data)
            t_first = (time.process_time() - t0) * 1e3
            ms, negative = cpu_ms(lambda m=m: m.factorize(k.data), repeats)
            ms_solve, x = cpu_ms(lambda m=m: m.solve(rhs), repeats)
            print(
                f"MUMPS {fmt} {label}: numeric {ms:.2f} ms, solve {ms_solve:.2f} ms (first set-up "
                f"{t_first:.1f} ms), INFOG(12) {negative}, flops {m.f.getMumpsRinfog(3):.2e}, "
                f"solution off by {off(x):.1e}"
            )


def path_with_mumps() -> None:
    """The clamp dome's ramp with Newton's LDL^T replaced by MUMPS (inertia from INFOG(12); zero
    pivots: our count on the same matrix, as MUMPS's null-pivot test is another criterion)."""
    original = newton_module.factorize
    cache: dict[int, tuple] = {}
    stats = {"calls": 0, "mumps cpu [s]": 0.0, "ours cpu [s]": 0.0, "negative differs": 0}

    def factorize(matrix, diagonal=None, shift=0.0, ldl=None):
        if ldl is None:
            return original(matrix, diagonal, shift, ldl)
        t0 = time.process_time()
        _, negative, zero = original(matrix, diagonal, shift, ldl)
        stats["ours cpu [s]"] += time.process_time() - t0
        t0 = time.process_time()
        entry = cache.get(id(ldl))
        if entry is None or entry[0] is not ldl:
            entry = cache[id(ldl)] = (ldl, Mumps(matrix))
        m = entry[1]
        mumps_negative = m.factorize(matrix.data, shift)
        stats["mumps cpu [s]"] += time.process_time() - t0
        stats["calls"] += 1
        stats["negative differs"] += int(mumps_negative != negative)
        return m, mumps_negative, zero

    newton_module.factorize = factorize
    try:
        row = lb.run_one("5x5-dome-clamp", "fe-calibrated")
    finally:
        newton_module.factorize = original
    print(
        f"ramp with MUMPS: {row['newton iterations']} Newton iterations, circle kx/ky "
        f"{row['circle kappa_x [1/mm]']:.10f}/{row['circle kappa_y [1/mm]']:.10f} 1/mm; "
        + ", ".join(
            f"{k} {v:.2f}" if isinstance(v, float) else f"{k} {v}" for k, v in stats.items()
        )
    )
    row = lb.run_one("5x5-dome-clamp", "fe-calibrated")
    print(
        f"ramp with ours: {row['newton iterations']} Newton iterations, circle kx/ky "
        f"{row['circle kappa_x [1/mm]']:.10f}/{row['circle kappa_y [1/mm]']:.10f} 1/mm"
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--iteration", type=int, default=150, help="Newton iteration of the tangent")
    p.add_argument("--repeats", type=int, default=10, help="timed calls per solver")
    p.add_argument("--path", action="store_true", help="also the ramp with MUMPS factorisations")
    args = p.parse_args(argv)
    if args.iteration < 1:
        p.error(f"--iteration = {args.iteration}: must be >= 1")
    if args.repeats < 1:
        p.error(f"--repeats = {args.repeats}: must be >= 1")
    compare(*capture_tangent(args.iteration), args.repeats)
    if args.path:
        path_with_mumps()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
