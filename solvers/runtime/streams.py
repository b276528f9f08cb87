"""The reporting streams of the command line (stdout: tables and the printed line; stderr: progress
bars and one-line errors), guarded so that how they are connected never changes a run's outcome:

* a stream that cannot encode a character (``PYTHONIOENCODING=ascii``, a terminal in Latin-1)
  gets a replacement (``?``) instead of raising UnicodeEncodeError after the run has finished;
* stderr that cannot be written (``2>/dev/full``, a closed descriptor) is given up quietly: the
  exit status stays the one the run earned (2 for bad input, not 1 from a traceback);
* a closed pipe on stdout (``lcefem validate --list | head``) still raises BrokenPipeError, which
  the command line ends quietly (exit 141, as Unix tools).
"""

from __future__ import annotations

import contextlib
import os
import sys


class GuardedStream:
    """A text stream wrapper: writes that cannot be encoded are written with replacements; on
    stderr (``quiet_errors``) an OSError ends all further writes, and the descriptor is pointed at
    /dev/null so that the interpreter's final flush cannot fail either."""

    def __init__(self, stream, quiet_errors: bool):
        self._stream = stream
        self._quiet = quiet_errors
        self._dead = False

    def _give_up(self) -> None:
        self._dead = True
        with contextlib.suppress(Exception):
            os.dup2(os.open(os.devnull, os.O_WRONLY), self._stream.fileno())

    def write(self, text: str) -> int:
        if self._dead:
            return len(text)
        try:
            try:
                return self._stream.write(text)
            except UnicodeEncodeError:
                encoding = getattr(self._stream, "encoding", None) or "ascii"
                return self._stream.write(
                    text.encode(encoding, "replace").decode(encoding, "replace")
                )
        except BrokenPipeError:
            if not self._quiet:
                raise
            self._give_up()
        except (OSError, ValueError) as exc:  # a full device, a closed file
            if not self._quiet:
                raise self._named(exc) from None
            self._give_up()
        return len(text)

    def _named(self, exc: BaseException) -> BaseException:
        """An OSError without a file name as one naming this stream (``'<stdout>'``), so that the
        message does not send the user to --out for a full device behind ``> file``."""
        if isinstance(exc, OSError) and exc.filename is None and exc.errno is not None:
            return OSError(exc.errno, exc.strerror, getattr(self._stream, "name", "<stream>"))
        return exc

    def flush(self) -> None:
        if self._dead:
            return
        try:
            self._stream.flush()
        except BrokenPipeError:
            if not self._quiet:
                raise
            self._give_up()
        except (OSError, ValueError) as exc:
            if not self._quiet:
                raise self._named(exc) from None
            self._give_up()

    def __getattr__(self, name):  # isatty, encoding, fileno, ...: the wrapped stream's
        return getattr(self._stream, name)


@contextlib.contextmanager
def guarded_streams():
    """sys.stdout and sys.stderr guarded (:class:`GuardedStream`) for the duration of a command."""
    previous = sys.stdout, sys.stderr
    sys.stdout = GuardedStream(previous[0], quiet_errors=False) if previous[0] is not None else None
    sys.stderr = GuardedStream(previous[1], quiet_errors=True) if previous[1] is not None else None
    try:
        yield
    finally:
        with contextlib.suppress(Exception):
            sys.stderr.flush()
        sys.stdout, sys.stderr = previous
