"""Which MPI communicator the FE builders use when the caller names none.

It lives in meshes/ because a mesh is where a communicator is first consumed (every later FE object
takes its mesh's), and meshes/ may be imported by solvers/ and validation/ but imports neither.
Every builder (meshes, problems, manufactured solutions) takes ``comm: MPI.Comm | None = None`` and
resolves it with :func:`resolve_comm`: :func:`default_comm` is ``MPI.COMM_WORLD`` (``mpiexec -n N
lcefem run strip`` shares one problem over N ranks) unless a :func:`case_communicator` block is
active. ``lcefem validate`` under mpiexec farms whole cases over the ranks and runs each case inside
``case_communicator(MPI.COMM_SELF)``: the case's meshes, PETSc objects and collectives then live on
its own rank, and no rank waits in a collective for another rank that runs a different case.

The default is looked up at call time (not bound as a default argument at import), so the block
reaches builders imported long before it.
"""

from __future__ import annotations

import contextlib

_stack: list = []  # communicators of the active case_communicator blocks, innermost last


def default_comm():
    """The communicator of the innermost :func:`case_communicator` block, else
    ``MPI.COMM_WORLD``."""
    if _stack:
        return _stack[-1]
    import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
    from mpi4py import MPI

    return MPI.COMM_WORLD


def resolve_comm(comm=None):
    """``comm`` when given, else :func:`default_comm`."""
    return default_comm() if comm is None else comm


@contextlib.contextmanager
def case_communicator(comm):
    """Builders called inside the block without a ``comm`` use ``comm`` (e.g. ``MPI.COMM_SELF``)."""
    _stack.append(comm)
    try:
        yield comm
    finally:
        _stack.pop()
