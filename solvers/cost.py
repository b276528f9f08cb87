"""What a run will cost, estimated before any work starts, and refused when it cannot fit this host.

A command adds up the memory of its parts (the interpreter and libraries, the FE factorisation, the
rod, the history of its time steps); when the sum exceeds the memory of this host
(:func:`host_memory`: the physical RAM, 24 GiB on the machine the estimates were measured on), the
run is refused in one line (exit 2) naming the input field that costs most. Swap is not counted:
a direct solver that pages does not finish.

The estimates are lower bounds fitted to measured peaks (``/usr/bin/time -f %M``, 24 GiB host,
2026-11-28), so a refusal is certain and an acceptance only says the run can start:

* :data:`BASE_MEMORY`: Python, dolfinx, PETSc, numba (``lcefem run strip --mesh-level 0``: 448 MB;
  ``lcefem run ribbon --nodes 1000``: 413 MB);
* :func:`fe_memory`: a 3D quadratic-element displacement problem factorised by MUMPS: fill of a
  nested-dissection factorisation of a 3D mesh grows as N^(4/3) (George 1973, Lipton-Rose-Tarjan
  1979); the constant is fitted on the strip (``--mesh-level 1 / 2``: 14,823 / 46,137 DOFs, peaks
  518 / 803 MB against 530 / 813 MB from the law);
* :data:`ROD_NODE_MEMORY`: the discrete elastic rod per node (``lcefem run ribbon --nodes 1000 /
  3000``: 413 / 434 MB: 10 kB a node, its section heat grid included);
* :data:`ROW_MEMORY`: one time step of history kept in memory (a row of ~20 floats in Python lists
  and the problem's arrays: assumed 1 kB, an upper round figure of 20 x (24 + 8) B plus list
  overhead).

Besides memory, a count may have a stated bound (:meth:`Estimate.bound`): work that fits in memory
but would not end in any useful time (a gridshell schedule's heat steps and outputs,
lcefem.solvers.problems.gridshell_bh_sequence.schedule_estimate).
"""

from __future__ import annotations

import math
import os

from lcefem.models.errors import InputError

GiB = 1024.0**3
BASE_MEMORY = (
    0.40 * GiB
)  #: [B] interpreter and libraries (measured 413-448 MB, see the module docstring)
FE_FILL_COEFFICIENT = (
    220.0  #: [B] per DOF^(4/3): MUMPS factor + assembly of a 3D Q2 problem (fitted)
)
ROD_NODE_MEMORY = 10e3  #: [B] per rod node (measured, 1000 -> 3000 nodes)
ROW_MEMORY = 1e3  #: [B] per time step of history (assumed upper round figure)


def host_memory() -> float:
    """Physical memory of this host [B] (``LCEFEM_MEMORY`` [GiB] overrides it, e.g. for a batch
    job's share of a node)."""
    override = os.environ.get("LCEFEM_MEMORY")
    if override:
        try:
            value = float(override) * GiB
        except ValueError:
            raise InputError(f"LCEFEM_MEMORY = {override!r}: must be a number of GiB") from None
        if value > 0 and math.isfinite(value):
            return value
        raise InputError(f"LCEFEM_MEMORY = {override!r}: must be a positive number of GiB")
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 24.0 * GiB  # the machine the estimates were measured on


def fe_memory(dofs: float) -> float:
    """[B] factorising and assembling a 3D quadratic displacement problem of ``dofs`` unknowns."""
    return FE_FILL_COEFFICIENT * dofs ** (4.0 / 3.0) if math.isfinite(dofs) else math.inf


def steps(duration: float, dt: float) -> float:
    """Time steps of ``duration`` [s] at ``dt`` [s] (a float: may be huge or infinite)."""
    return math.ceil(duration / dt - 1e-9) if dt > 0 and math.isfinite(duration / dt) else math.inf


def _fmt(value: float) -> str:
    return f"{value:.3g}" if math.isfinite(value) else "infinitely many"


class Estimate:
    """The cost of one run: counts (steps, cells, DOFs, nodes) and memory terms, each charged to the
    input field that sets it. :meth:`check` refuses it when it cannot fit; :meth:`as_dict` is kept
    in summary.json."""

    def __init__(self):
        self.counts: dict[str, float] = {}
        self.terms: list[tuple[str, str, float]] = [("", "libraries", BASE_MEMORY)]
        self.bounds: list[tuple[str, str, float, float, str]] = []

    def count(self, name: str, value: float) -> "Estimate":
        self.counts[name] = float(value)
        return self

    def memory(self, field: str, what: str, nbytes: float) -> "Estimate":
        """``nbytes`` [B] for ``what`` (e.g. '3.6e+303 time steps'), set by input ``field``."""
        self.terms.append((field, what, float(nbytes)))
        return self

    def bound(self, field: str, what: str, count: float, limit: float, why: str) -> "Estimate":
        """``count`` of ``what`` (e.g. 'heat steps'), set by input ``field``, may not exceed
        ``limit`` (``why``: the bound's reason, stated in the refusal); checked by :meth:`check`."""
        self.counts[what] = float(count)
        self.bounds.append((field, what, float(count), float(limit), why))
        return self

    def total(self) -> float:
        return sum(b for _, _, b in self.terms)

    def check(self) -> "Estimate":
        for field, what, count, bound, why in self.bounds:
            if not count <= bound:
                raise InputError(
                    f"{field}: {_fmt(count)} {what}, more than the bound {bound:.3g} ({why}; "
                    "estimate: lcefem.solvers.cost)"
                )
        limit, total = host_memory(), self.total()
        if total <= limit:
            return self
        field, what, nbytes = max(self.terms[1:], key=lambda t: t[2])
        need = (
            "more than any machine's"
            if not math.isfinite(nbytes)
            else f"at least {nbytes / GiB:.3g} GiB"
        )
        raise InputError(
            f"{field}: {what} need {need} memory; this host has {limit / GiB:.3g} GiB "
            f"(estimate: lcefem.solvers.cost; LCEFEM_MEMORY sets another limit)"
        )

    def as_dict(self) -> dict:
        return {
            **{k: v if math.isfinite(v) else None for k, v in self.counts.items()},
            "memory [GiB]": self.total() / GiB,
            "memory limit [GiB]": host_memory() / GiB,
        }


def time_steps(
    field: str, duration: float, dt: float, estimate: Estimate | None = None
) -> Estimate:
    """The history of ``duration / dt`` steps, charged to ``field`` (the step, e.g. 'run.dt = 1e-300
    s')."""
    n = steps(duration, dt)
    est = estimate or Estimate()
    return est.count("steps", n).memory(field, f"{_fmt(n)} time steps", n * ROW_MEMORY)


def describe(count: float, what: str) -> str:
    return f"{_fmt(count)} {what}"
