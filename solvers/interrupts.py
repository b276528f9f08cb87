"""What numerics need to know about interrupts, and nothing else of the application runtime.

A solver that catches a library's errors (PETSc's, numba's) must not turn Ctrl-C into a failed
solve: :func:`raise_if_interrupted` re-raises the interrupt hidden in such an error, or one this
process received while a library swallowed it. The record of received signals (:data:`received`) is
filled by the command line's handlers (lcefem.solvers.runtime.signals); this module imports neither
the runtime nor any library, so every numerics module may use it.
"""

from __future__ import annotations

import signal


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that the same clean-up runs; exit status 143."""


#: signals received by this process (appended by lcefem.solvers.runtime.signals' handler, read here)
received: list[int] = []


def interrupt_in(exc: BaseException | None) -> KeyboardInterrupt | None:
    """The interrupt behind ``exc``: itself or one in its cause/context chain (a callback of PETSc's
    interrupted by Ctrl-C surfaces as a PETSc error; numba's compiler turns a signal that arrives
    while it compiles a kernel into a RuntimeError), or, when this process has received SIGINT or
    SIGTERM, a new one of that kind; None otherwise."""
    seen = exc
    while seen is not None:
        if isinstance(seen, KeyboardInterrupt):
            return seen
        seen = seen.__cause__ or seen.__context__
    if received:
        return Terminated() if received[-1] == signal.SIGTERM else KeyboardInterrupt()
    return None


def raise_if_interrupted(exc: BaseException | None = None) -> None:
    """Re-raise the interrupt hidden inside a library's error (:func:`interrupt_in`); no-op
    otherwise."""
    interrupt = interrupt_in(exc)
    if interrupt is not None:
        raise interrupt
