"""Errors shared by every layer of lcefem."""


class InputError(ValueError):
    """Bad user input: the message names the field and what is allowed, on one line."""


class ConvergenceError(RuntimeError):
    """A nonlinear solve failed even after step cutting.

    Attributes:
        where: a short description of the state reached (e.g. ``"t = 12.5 s"``).
        reason: why it stopped (solver's converged reason, smallest step tried).
    """

    def __init__(self, where: str, reason: str):
        super().__init__(f"no convergence at {where}: {reason}")
        self.where = where
        self.reason = reason


class PhysicalBoundsError(ConvergenceError):
    """A result left its physical bounds (exit 3): the model is outside what it describes."""

    def __str__(self) -> str:
        return f"result out of physical bounds at {self.where}: {self.reason}"
