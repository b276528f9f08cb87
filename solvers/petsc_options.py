"""lcefem's entries in PETSc's options database (numerics; no import of PETSc at module level)."""

from __future__ import annotations

import contextlib
import sys


def forget_solver_options(prefix: str = "lcefem_") -> None:
    """Remove lcefem's solver options (prefix ``lcefem_``) from PETSc's options database when a
    command ends. Each problem puts its options there for its own SNES, KSP and factorisation, which
    read them when they first need them; a problem that never needed one (a beam confirmed in 0
    Newton iterations never factorises, so ``mat_mumps_icntl_7`` is never read) left it for PETSc to
    report at exit as "options you set that were not used". Options a user gives are checked
    when the solver has read its own (lcefem.solvers.mechanics: an unread [petsc] option is refused)."""
    petsc = sys.modules.get("petsc4py.PETSc")
    if petsc is None:
        return
    with contextlib.suppress(Exception):
        db = petsc.Options()
        for name in db.getAll():
            if name.startswith(prefix):
                db.delValue(name)
