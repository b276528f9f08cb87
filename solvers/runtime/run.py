"""One run into an output folder: progress bar, history (checked against physical bounds), outputs
finalized together, ``failure.json`` on a physics failure, ``summary.json`` last on success."""

from __future__ import annotations

import contextlib
import pathlib
import sys

from lcefem.models.errors import ConvergenceError, InputError, PhysicalBoundsError
from lcefem.solvers.interrupts import raise_if_interrupted
from lcefem.solvers.runtime.checks import check_row
from lcefem.solvers.runtime.files import CSVTable, salvage_parts, write_json
from lcefem.solvers.runtime.outdir import claim_out, claimed
from lcefem.solvers.runtime.ranks import barrier, rank
from lcefem.solvers.runtime.signals import reinstall_signal_handlers


class Progress:
    """A tqdm bar on stderr (rank 0 only) over a quantity: simulated time, load factor, ..."""

    def __init__(
        self, total: float, desc: str, unit: str, fmt: str = ".1f", enabled: bool = True, comm=None
    ):
        self.bar = None
        if enabled and rank(comm) == 0:
            from tqdm import tqdm

            self.bar = tqdm(
                total=total,
                desc=desc,
                unit=unit,
                file=sys.stderr,
                bar_format="{l_bar}{bar}| {n:"
                + fmt
                + "}/{total:"
                + fmt
                + "} "
                + unit
                + " [{elapsed}<{remaining}{postfix}]",
            )

    def to(self, value: float, postfix: str | None = None) -> None:
        if self.bar is not None:
            if postfix:
                self.bar.set_postfix_str(postfix, refresh=False)
            self.bar.update(min(value, self.bar.total) - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


class Run:
    """One run into ``out`` (or in memory when ``out`` is None), used as a context manager::

        with Run(out, config=cfg.resolved(), columns=COLUMNS, progress=Progress(...)) as run:
            run.output(FieldExport(...))        # anything with finalize(complete)
            for step ...:
                run.record(row, where=f"t = {t} s", at=t)
            run.complete(summary)               # outputs renamed, summary.json written

    On ConvergenceError (also a result out of physical bounds) the outputs become ``*.partial.*``
    and ``failure.json`` records where, why, the last converged row and the configuration; on an
    interrupt (Ctrl-C, SIGTERM) or any other error the outputs become ``*.partial.*`` and no
    failure.json is written (it would claim a physics failure). The exception propagates.
    """

    def __init__(
        self,
        out: pathlib.Path | None,
        *,
        config: dict,
        columns: list[str] | None = None,
        history: str = "history.csv",
        progress: Progress | None = None,
        comm=None,
    ):
        # the problem was just built: gmsh and PETSc may have taken them
        reinstall_signal_handlers()
        self.out = None if out is None else pathlib.Path(out)
        self.config = config
        self.comm = comm
        self.progress = progress or Progress(0, "", "", enabled=False)
        self.outputs: list = []
        self._failure_hooks: list = []
        # The library's runs (run_strip(config, out), ...) claim their folder as the command line
        # does: another run's results are refused, a lock is held while writing (issue 45). A
        # folder the caller claimed (the command line, validate's cases) is not claimed again.
        self._claim = contextlib.ExitStack()
        if self.out is not None and not claimed(self.out):
            try:
                self._claim.enter_context(
                    claim_out(
                        self.out,
                        resume=None,
                        overwrite=False,
                        comm=comm,
                        flag="out",
                        command="library run",
                    )
                )
            except InputError as exc:
                raise InputError(
                    f"{exc} (a library run: to replace them, claim the folder first, "
                    "with lcefem.solvers.runtime.outdir.claim_out(out, overwrite=True): ...)"
                ) from None
        if self.out is not None and rank(comm) == 0:
            self.out.mkdir(parents=True, exist_ok=True)
            for stale in ("failure.json", "summary.json"):  # this run owns the folder's state
                (self.out / stale).unlink(missing_ok=True)
        barrier(comm)
        self.history = None
        if columns is not None:
            self.history = self.output(
                CSVTable(None if self.out is None else self.out / history, columns, comm)
            )
        self.done = False

    def output(self, writer):
        self.outputs.append(writer)
        return writer

    def open_history(self, columns: list[str], name: str = "history.csv") -> CSVTable:
        """The run's history (checked rows, failure.json's last converged row) opened once its
        columns are known (a run built without ``columns``: the one door,
        lcefem.solvers.runner.run)."""
        if self.history is None:
            self.history = self.output(
                CSVTable(None if self.out is None else self.out / name, columns, self.comm)
            )
        return self.history

    def on_failure(self, hook) -> None:
        """``hook(out)`` runs after a ConvergenceError, e.g. to save the last converged state."""
        self._failure_hooks.append(hook)

    def record(
        self, row: dict, where: str, at: float | None = None, postfix: str | None = None
    ) -> None:
        """Check ``row`` against physical bounds, append it to the history, advance the bar. An
        interrupt a library swallowed (raised inside one of its callbacks) stops the run here at
        the latest."""
        raise_if_interrupted()
        check_row(row, where)
        if self.history is not None:
            self.history.append(row)
        if at is not None:
            self.progress.to(at, postfix)

    def last_row(self) -> dict | None:
        if self.history is None or not self.history.rows:
            return None
        return dict(zip(self.history.columns, self.history.rows[-1]))

    def complete(self, summary: dict) -> dict:
        """Finalize every output under its final name; write summary.json LAST (the marker of a
        complete run)."""
        self.progress.close()
        for w in self.outputs:
            w.finalize(True)
        summary = {"status": "completed", **summary, "config": self.config}
        if self.out is not None:
            write_json(self.out / "summary.json", summary, self.comm)
        self.done = True
        return summary

    def __enter__(self) -> "Run":
        return self

    def __exit__(self, kind, exc, tb) -> bool:
        try:
            return self._exit(exc)
        finally:
            self._claim.close()

    def _exit(self, exc) -> bool:
        if exc is None:
            if not self.done:
                raise RuntimeError("Run ended without complete(summary)")
            return False
        self.progress.close()
        if not isinstance(exc, ConvergenceError) and self.comm is not None and self.comm.size > 1:
            # An interrupt or error may have reached only some ranks; the others may wait in a
            # collective, so closing the outputs (collective) here could hang: the command line
            # closes them once the ranks agree (finish_pending), or renames them and aborts.
            pending.append(self)
            return False
        failed = isinstance(exc, ConvergenceError) and self.out is not None
        for hook in self._failure_hooks if failed else ():  # before the outputs close
            with contextlib.suppress(Exception):
                hook(self.out)
        for w in self.outputs:
            with contextlib.suppress(Exception):  # keep the original error
                w.finalize(False)
        if failed:
            kept = (
                sorted(
                    p.name
                    for p in self.out.iterdir()
                    if ".partial" in p.name or p.name.startswith("last_converged")
                )
                if rank(self.comm) == 0
                else []
            )
            write_json(
                self.out / "failure.json",
                {
                    "status": "failed",
                    "kind": "out of physical bounds"
                    if isinstance(exc, PhysicalBoundsError)
                    else "no convergence",
                    "where": exc.where,
                    "reason": exc.reason,
                    "last_converged": self.last_row(),
                    "kept": kept,
                    "config": self.config,
                },
                self.comm,
            )
        return False


pending: list = []  # runs whose outputs wait for the ranks to agree (MPI)


def finish_pending(agreed: bool) -> None:
    """Close the outputs of runs that ended by an interrupt or error under MPI: collectively when
    every rank got here (``agreed``), else by renaming rank-locally before an abort."""
    while pending:
        run = pending.pop()
        if agreed:
            for w in run.outputs:
                with contextlib.suppress(Exception):
                    w.finalize(False)
        elif run.out is not None:
            salvage_parts(run.out)
