"""Standard output that cannot be written: a closed pipe or a full disk, told apart from a
command's own errors so that :func:`walk3d.cli.main` ends each with one fixed behaviour; and
standard error that cannot be written, which must not change a command's exit code."""

from __future__ import annotations

import errno
import os
from typing import Any, TextIO

__all__ = ["CLOSED_PIPE_EXIT", "GuardedStdout", "OutputClosed", "OutputFailed", "QuietStderr",
           "silence_stdout"]  # fmt: skip

CLOSED_PIPE_EXIT = 141
"""Exit code when the reader of stdout went away (``walk3d body | head -1``): 128 + SIGPIPE,
what a shell reports for a Unix tool ended by that signal; no message is printed."""


class OutputClosed(Exception):
    """Standard output's reader closed the pipe (not an OSError: Rich would swallow it)."""


class OutputFailed(Exception):
    """Standard output could not be written (disk full, I/O error); the message is the reason."""


class GuardedStdout:
    """``stream`` whose write and flush errors become :class:`OutputClosed` or
    :class:`OutputFailed`; everything else is passed through."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

    def _guard(self, method: str, *args: Any) -> Any:
        try:
            return getattr(self._stream, method)(*args)
        except BrokenPipeError:
            raise OutputClosed from None
        except OSError as exc:
            if exc.errno == errno.EPIPE:
                raise OutputClosed from None
            raise OutputFailed(exc.strerror or type(exc).__name__) from None

    def write(self, text: str) -> int:
        return self._guard("write", text)

    def writelines(self, lines: Any) -> None:
        self._guard("writelines", lines)

    def flush(self) -> None:
        self._guard("flush")

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


class QuietStderr:
    """``stream`` (standard error) whose write and flush errors are dropped: when an error line
    cannot be written (``2>/dev/full``), the exit code (2 for bad input) still says what
    happened. After the first failure the stream's file descriptor points at /dev/null, so that
    the interpreter's own flush at exit does not fail either (which would make it exit 120)."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

    def _quiet(self, method: str, *args: Any) -> Any:
        try:
            return getattr(self._stream, method)(*args)
        except OSError:
            silence_stdout(self._stream)
            return None

    def write(self, text: str) -> int:
        self._quiet("write", text)
        return len(text)

    def writelines(self, lines: Any) -> None:
        self._quiet("writelines", lines)

    def flush(self) -> None:
        self._quiet("flush")

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def silence_stdout(stream: TextIO) -> None:
    """Point ``stream``'s file descriptor (standard output's, or error's) at /dev/null, so that
    the interpreter's own flush at exit does not print a second error about the same output."""
    try:
        fd = stream.fileno()
    except (OSError, ValueError, AttributeError):
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)
