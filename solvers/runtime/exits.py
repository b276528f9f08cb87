"""Exit codes of every lcefem command, and the one of an interrupt."""

from __future__ import annotations

import signal

from lcefem.solvers.interrupts import Terminated

EXIT_OK = 0
EXIT_CASE_ERROR = 1  #: validate: a case raised an error (the others still ran)
EXIT_INPUT = 2  #: bad input, or an output folder that cannot be used
EXIT_SOLVER = 3  #: the solver failed, or a result left its physical bounds
EXIT_SIGINT = 128 + signal.SIGINT  # 130, the shell's convention
EXIT_SIGTERM = 128 + signal.SIGTERM  # 143


def interrupt_exit_code(exc: KeyboardInterrupt) -> int:
    return EXIT_SIGTERM if isinstance(exc, Terminated) else EXIT_SIGINT
