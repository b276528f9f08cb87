"""``mpiexec -n N lcefem validate``: the selected cases farmed over N MPI ranks, one case per rank.

Each case runs whole on one rank, inside ``case_communicator(MPI.COMM_SELF)``
(:mod:`lcefem.meshes.communicator`), so its meshes, PETSc objects and collectives are its own; the
answers are those of the serial run, whatever N. What is farmed is an *affinity group*: cases that
share an in-process cache (:data:`lcefem.validation.cases.AFFINITY`) run on one rank in their
registry order, as in the serial run, so the shared work is done once.

Order: groups by expected cost, largest first (:func:`schedule`; the cost of a case is its wall time
in the last full or quick run, ``validation/data/case_costs.toml``; a missing entry counts as the
largest; a case that ``--resume`` will reuse costs nothing). Hand-out: dynamic. Rank 0 runs cases
like every other rank; a thread of rank 0 (:func:`_serve`) answers the other ranks' "next?" between
its polls, hands out the next group, collects each finished case's result and rewrites
``DIR/report.md`` and ``DIR/metrics.json``. A thread, because MPI one-sided counters
(``MPI.Win.Fetch_and_op``) do not progress while the target rank computes: measured with MPICH 5.0.2
(the venv's), a fetch-and-add on rank 0's window waited 3.5 s for rank 0 to leave a 4 s compute
loop.

Each case keeps its own folder, completion marker and error.log, written by the rank that ran it;
rank 0 owns the folder itself (claimed by the command line) and the run-level files.

Interrupts: SIGINT/SIGTERM from mpiexec reach every rank; each stops its case (reported
"interrupted"), no new group is handed out, and rank 0 waits up to :data:`DRAIN_SECONDS` for the
other ranks' reports; then every rank raises the interrupt (exit 130 / 143, as the serial run).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import pathlib
import threading
import time
import tomllib

from lcefem.validation.app.report import CaseResult
from lcefem.validation.cases import AFFINITY, Case

COSTS = pathlib.Path(__file__).parents[1] / "data" / "case_costs.toml"
TAG_NEXT, TAG_WORK, TAG_RESULT, TAG_END = 31, 32, 33, 34  #: message tags on the farm's communicator
STOP = -1  #: the answer to "next?" when no group is left
STOPPED = "stopped"  #: a rank's "next?" after an interrupt: hand it nothing more
POLL_SECONDS = (
    0.02  #: how often a waiting rank looks for a message (a signal is handled in between)
)
#: After an interrupt, how long rank 0 waits for the other ranks' reports [s]: longer than a numba
#: kernel's compilation, which Python cannot interrupt (15 s seen, solvers/interrupts.py
#: interrupt_in).
DRAIN_SECONDS = 60.0
#: How long rank 0 waits for its dispatcher thread to return once told to [s]: it looks at its quit
#: flag every POLL_SECONDS, between two MPI calls.
QUIT_SECONDS = 5.0


def petsc_world_per_rank() -> None:
    """Make PETSc's world this rank alone (``MPI.COMM_SELF``); called before PETSc starts.

    The farmed ranks run different cases, so PETSc's own collectives on its world (PetscInitialize
    and PetscFinalize, petsc4py's garbage clean-up at exit, an object made without a communicator)
    must never wait for another rank. Measured: with COMM_WORLD as PETSc's world, a farmed quick run
    ended its last case and then hung at exit (rank 0 in the MPI_Comm_dup of petsc4py's
    garbage_cleanup, rank 1 in MPI_Finalize)."""
    import sys

    if "petsc4py.PETSc" in sys.modules:
        raise RuntimeError("PETSc was started before the farm could give each rank its own world")
    import dolfinx_solver  # noqa: F401  (orders MPI before dolfinx/petsc4py)
    import petsc4py
    from mpi4py import MPI

    petsc4py.init(comm=MPI.COMM_SELF)


@functools.cache
def case_costs(quick: bool) -> dict[str, float]:
    """Expected wall time [s] of each case at the quick or default level (case_costs.toml)."""
    data = tomllib.loads(COSTS.read_text(encoding="utf-8"))
    return {name: float(t) for name, t in data["quick" if quick else "full"].items()}


def affinity_groups(cases: list[Case]) -> list[list[int]]:
    """Indices into ``cases``: one list per affinity group (members in ``cases`` order), a case of
    no group alone; groups in the order of their first member."""
    group_of = {name: g for g, names in AFFINITY.items() for name in names}
    groups: dict[str, list[int]] = {}
    for i, case in enumerate(cases):
        groups.setdefault(group_of.get(case.name, f"case:{case.name}"), []).append(i)
    return list(groups.values())


def schedule(cases: list[Case], cost) -> list[list[int]]:
    """:func:`affinity_groups` sorted by the summed ``cost(case)`` [s], largest first (stable)."""
    groups = affinity_groups(cases)
    return sorted(groups, key=lambda g: -sum(cost(cases[i]) for i in g))


def makespan(group_costs: list[float], ranks: int) -> tuple[float, list[float]]:
    """Wall time [s] of farming groups of these costs, in this order, each to the first free rank
    (list scheduling; the costs sorted largest first give LPT, within 4/3 of the optimum); and each
    rank's busy time."""
    busy = [0.0] * ranks
    for c in group_costs:
        busy[busy.index(min(busy))] += c
    return max(busy), busy


class _Board:
    """Rank 0's state shared by its main thread and its dispatcher thread (under one lock)."""

    def __init__(self, groups: list[list[int]], results: list[CaseResult], flush, bar):
        self.groups, self.results, self._flush, self.bar = groups, results, flush, bar
        self.lock = threading.Lock()
        self.next = 0
        self.stopping = False
        self.main_done = threading.Event()
        self.quit = (
            threading.Event()
        )  # the dispatcher returns at once (before the farm frees its comm)
        self.current: dict[int, int] = {}  # rank -> the group it was handed last
        self.ended: set[int] = set()  # ranks that have asked for work after their last group

    def take(self, rank: int) -> int:
        with self.lock:
            self.current.pop(rank, None)
            if self.stopping or self.next >= len(self.groups):
                self.ended.add(rank)
                return STOP
            g, self.next = self.next, self.next + 1
            self.current[rank] = g
            return g

    def stop(self) -> None:
        with self.lock:
            self.stopping = True

    def record(self, index: int, result: CaseResult) -> None:
        with self.lock:
            self.results[index] = result
            if result.status == "interrupted":
                self.stopping = True
            self._flush()
            self.bar.set_postfix_str(f"{result.case} (rank {result.rank})")
            self.bar.update(1)


def _serve(board: _Board, comm) -> None:
    """Rank 0's dispatcher thread: answer every other rank's "next?" until each got its STOP."""
    from mpi4py import MPI

    active = comm.size - 1
    deferred: list[int] = []  # stopped ranks; they get STOP once rank 0's own case has ended
    while active > 0 and not board.quit.is_set():
        if deferred and board.main_done.is_set():
            for rank in deferred:
                comm.send(STOP, dest=rank, tag=TAG_WORK)
            active -= len(deferred)
            deferred.clear()
            continue
        status = MPI.Status()
        if not comm.iprobe(source=MPI.ANY_SOURCE, tag=MPI.ANY_TAG, status=status):
            time.sleep(POLL_SECONDS)
            continue
        rank, tag = status.Get_source(), status.Get_tag()
        message = comm.recv(source=rank, tag=tag)
        if tag == TAG_RESULT:
            index, data = message
            board.record(index, CaseResult.from_dict(data))
            continue
        if message == STOPPED:
            board.stop()
        g = board.take(rank)
        if g == STOP and board.stopping and not board.main_done.is_set():
            # An interrupted rank leaves only once rank 0 has stopped too, so that all of them reach
            # the command line's exit agreement together (a rank that gets there alone aborts the
            # rest).
            deferred.append(rank)
            continue
        comm.send(g, dest=rank, tag=TAG_WORK)
        if g == STOP:
            active -= 1


def _receive(comm, tag: int):
    """The next message with ``tag`` from rank 0, polled so that a signal is handled while waiting;
    returns (message, the interrupt received meanwhile or None)."""
    interrupt = None
    while True:
        try:
            while not comm.iprobe(source=0, tag=tag):
                time.sleep(POLL_SECONDS)
            return comm.recv(source=0, tag=tag), interrupt
        except KeyboardInterrupt as exc:  # the answer is still owed to us: keep waiting for it
            interrupt = interrupt or exc


def _interrupt_named(error: str) -> KeyboardInterrupt:
    from lcefem.solvers.interrupts import Terminated

    return Terminated() if "Terminated" in error else KeyboardInterrupt()


def farm_validation(
    cases: list[Case], groups: list[list[int]], results: list[CaseResult], run_one, flush, bar, comm
) -> list[CaseResult]:
    """Farm ``groups`` (indices into ``cases``, in hand-out order) over the ranks of ``comm``;
    ``run_one(case)`` runs one case on this rank and returns its CaseResult (an interrupt in
    ``.interrupt``). Rank 0 fills ``results`` and calls ``flush()`` after each finished case;
    every rank returns the final results, or raises the interrupt that stopped the run."""
    comm = comm.Dup()  # the farm's messages never meet a case's
    servers: list[threading.Thread] = []
    try:
        if comm.rank == 0:
            return _lead(cases, groups, results, run_one, flush, bar, comm, servers)
        return _follow(cases, groups, run_one, comm)
    finally:
        # The dispatcher thread must have ended before its communicator goes (else it meets a null
        # communicator, issue 45); one still inside an MPI call after its quit leaves the
        # communicator to MPI_Finalize.
        if not any(t.is_alive() for t in servers):
            comm.Free()


def _run_group(cases, group, run_one, report) -> KeyboardInterrupt | None:
    """Run a group's cases in order on this rank; ``report(index, result)`` each; stop at an
    interrupt."""
    for i in group:
        result = run_one(cases[i])
        report(i, result)
        if result.status == "interrupted":
            return getattr(result, "interrupt", None) or _interrupt_named(result.error)
    return None


def _lead(cases, groups, results, run_one, flush, bar, comm, servers: list) -> list[CaseResult]:
    board = _Board(groups, results, flush, bar)
    server = threading.Thread(target=_serve, args=(board, comm), name="lcefem-farm", daemon=True)
    server.start()
    servers.append(server)
    try:
        return _lead_cases(cases, groups, results, run_one, flush, comm, board, server)
    finally:
        # whatever ended the wait (drained, deadline, an error): the thread returns
        board.quit.set()
        server.join(QUIT_SECONDS)


def _lead_cases(cases, groups, results, run_one, flush, comm, board, server) -> list[CaseResult]:
    interrupt = None
    try:
        while interrupt is None:
            g = board.take(0)
            if g == STOP:
                break
            interrupt = _run_group(cases, groups[g], run_one, board.record)
    except KeyboardInterrupt as exc:  # between two cases
        interrupt = exc
    with board.lock:
        board.ended.add(0)
    if interrupt is not None:
        board.stop()
    board.main_done.set()
    deadline = math.inf if interrupt is None else time.monotonic() + DRAIN_SECONDS
    while server.is_alive() and time.monotonic() < deadline:
        try:
            server.join(POLL_SECONDS * 5)
        except KeyboardInterrupt as exc:  # a signal while the other ranks finish: stop waiting soon
            interrupt = interrupt or exc
            board.stop()
            deadline = min(deadline, time.monotonic() + DRAIN_SECONDS)
    with board.lock:
        for rank, g in board.current.items():  # still in a case when the wait ended: say so
            i = next((i for i in groups[g] if results[i].status == "not run"), None)
            if rank not in board.ended and i is not None:
                results[i] = dataclasses.replace(
                    results[i],
                    status="interrupted",
                    rank=rank,
                    error=f"interrupted (rank {rank} did not report)",
                )
        flush()
        finished = [r.as_dict() for r in results]
    if interrupt is None:
        stopped = [r for r in results if r.status == "interrupted"]
        interrupt = _interrupt_named(stopped[0].error) if stopped else None
    ending = None if interrupt is None else type(interrupt).__name__
    for rank in range(1, comm.size):
        comm.send((finished, ending), dest=rank, tag=TAG_END)
    if interrupt is not None:
        raise interrupt
    return results


def _follow(cases, groups, run_one, comm) -> list[CaseResult]:
    def report(i, result):
        comm.send((i, result.as_dict()), dest=0, tag=TAG_RESULT)

    interrupt = None
    while True:
        comm.send(None if interrupt is None else STOPPED, dest=0, tag=TAG_NEXT)
        g, late = _receive(comm, TAG_WORK)
        interrupt = interrupt or late
        if g == STOP:
            break
        if interrupt is None:
            try:
                interrupt = _run_group(cases, groups[g], run_one, report)
            except KeyboardInterrupt as exc:  # between two cases
                interrupt = exc
    (finished, ending), _ = _receive(comm, TAG_END)
    results = [CaseResult.from_dict(d) for d in finished]
    if ending is not None:
        raise _interrupt_named(ending) if interrupt is None else interrupt
    return results
