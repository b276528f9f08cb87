"""Signal handlers of the command line: Ctrl-C and SIGTERM raise KeyboardInterrupt (SIGTERM as
:class:`~lcefem.solvers.interrupts.Terminated`) so every ``finally`` runs; each signal is recorded
in lcefem.solvers.interrupts.received, where solvers that catch library errors look for it."""

from __future__ import annotations

import contextlib
import os
import signal

from lcefem.solvers import interrupts
from lcefem.solvers.interrupts import Terminated, raise_if_interrupted

_installed: list[bool] = []  # [True] while the command line owns SIGINT and SIGTERM

_deferred: list[
    bool
] = []  # [True] inside deferred_signals(): record the signal, raise at the next check


def _on_signal(signum, frame):
    interrupts.received.append(signum)
    if _deferred:
        return
    raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


@contextlib.contextmanager
def deferred_signals():
    """Within this block SIGINT/SIGTERM are recorded, not raised where they land: the next
    :func:`raise_if_interrupted` (every :meth:`Run.record`) raises them. For loops of compiled code
    (numba) whose steps take milliseconds: an exception raised inside numba's or ctypes' C callbacks
    (e.g. while numba loads a cached kernel) crashed the process with SIGSEGV instead of exit 143,
    measured in test_interrupted_ribbon_leaves_only_partial_frames on a fresh clone."""
    _deferred[:] = [True]
    try:
        yield
    finally:
        _deferred.clear()
    raise_if_interrupted()


def install_signal_handlers() -> dict:
    """Ctrl-C and SIGTERM raise in the main thread (Python ignores SIGINT when started in the
    background of a script; SIGTERM would kill without clean-up). Returns the previous handlers."""
    interrupts.received.clear()
    _installed[:] = [True]
    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    if hasattr(signal, "SIGPIPE"):
        previous[signal.SIGPIPE] = signal.signal(signal.SIGPIPE, signal.SIG_IGN)
    return previous


def reinstall_signal_handlers() -> None:
    """Take SIGINT and SIGTERM back from C libraries that set their own behind Python's back (PETSc
    at initialisation, gmsh when a mesh is built), if :func:`install_signal_handlers` was called."""
    if _installed:
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, _on_signal)
        if hasattr(signal, "SIGPIPE"):
            # Python's own setting: a closed pipe (``lcefem validate --list | head``) raises
            # BrokenPipeError, which the command line ends quietly; PETSc's handler would abort MPI.
            signal.signal(signal.SIGPIPE, signal.SIG_IGN)


def keep_petsc_off_signals() -> None:
    """PETSc, when it initialises (the first import of petsc4py.PETSc, which may come inside a case
    or a plot long after the command line took the signals), installs a handler of its own that ends
    the process on SIGTERM with status 15 ("Caught signal number 15") and no clean-up: the lock
    stays, .part files stay. PETSc's option -no_signal_handler, read from PETSC_OPTIONS at
    initialisation, stops that at the root; :func:`reinstall_signal_handlers` still guards the cases
    where PETSc was initialised before (a library user's own session)."""
    options = os.environ.get("PETSC_OPTIONS", "")
    if "-no_signal_handler" not in options.split():
        os.environ["PETSC_OPTIONS"] = f"{options} -no_signal_handler".strip()


def restore_signal_handlers(previous: dict) -> None:
    _installed.clear()
    # a later run in this process (lcefem as a library) starts uninterrupted
    interrupts.received.clear()
    for sig, handler in previous.items():
        signal.signal(sig, handler)
