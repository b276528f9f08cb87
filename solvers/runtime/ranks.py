"""Rank and barrier of an optional communicator (None: a serial run without MPI)."""

from __future__ import annotations

import os
import sys


def rank(comm) -> int:
    return 0 if comm is None else comm.rank


def barrier(comm) -> None:
    if comm is not None and comm.size > 1:
        comm.barrier()


def barrier_quietly(comm) -> None:
    """A barrier only when no exception is in flight: on an interrupt the ranks may not all get
    here; the lock is rank 0's, so don't wait for them."""
    if comm is not None and comm.size > 1 and sys.exc_info()[0] is None:
        comm.barrier()


def mpi_launched() -> bool:
    """Started by mpiexec (its environment variables are set), whether or not MPI is imported
    yet."""
    return any(k in os.environ for k in ("PMI_RANK", "PMI_SIZE", "OMPI_COMM_WORLD_SIZE"))


def world():
    """COMM_WORLD when running under mpiexec with more than one rank, else None."""
    if "mpi4py.MPI" not in sys.modules and not mpi_launched():
        return None
    import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
    from mpi4py import MPI

    return MPI.COMM_WORLD if MPI.COMM_WORLD.size > 1 else None


def world_rank() -> int:
    """This process's rank under mpiexec, read from the launcher's environment (MPI not
    imported)."""
    return int(os.environ.get("PMI_RANK", os.environ.get("OMPI_COMM_WORLD_RANK", "0")))
