"""The ``walk3d`` command line (Typer + Rich).

Bad input gives one clear error line on stderr and exit code 2. Commands live in
:mod:`walk3d.cli.commands` (body, predict, compile), :mod:`walk3d.cli.cache_command`,
:mod:`walk3d.cli.atlas_command`, :mod:`walk3d.cli.campaign_command`,
:mod:`walk3d.cli.sweep_command`,
:mod:`walk3d.cli.validation` (validate, calibrate), :mod:`walk3d.cli.verify_command` and
:mod:`walk3d.cli.animate_command` and :mod:`walk3d.cli.report_command`;
shared options in :mod:`walk3d.cli.common`.
"""

from __future__ import annotations

import _thread
import functools
import logging
import os
import signal
import sys
import threading
import time

import typer

from walk3d.cli import (  # noqa: F401  (register the commands)
    animate_command,
    atlas_command,
    cache_command,
    campaign_command,
    commands,
    compare_command,
    fit_command,
    report_command,
    sweep_command,
    track_command,
    validation,
    verify_command,
)
from walk3d.cli.common import EXIT_WRITE, app, err_console, fail
from walk3d.cli.numbers import plain_numbers
from walk3d.cli.stdout import (
    CLOSED_PIPE_EXIT,
    GuardedStdout,
    OutputClosed,
    OutputFailed,
    QuietStderr,
    silence_stdout,
)

__all__ = ["app", "fail", "main"]


@app.callback()
def _root() -> None:
    """Predict three-dimensional whole-body human walking."""


_TERMINATED: list[bool] = []
"""Set once a SIGTERM came (the process is ending)."""


def _progress_module():
    """:mod:`walk3d.solve.progress` if it is imported, else None: a signal may come while a
    module is half imported, so the handlers never import."""
    module = sys.modules.get("walk3d.solve.progress")
    return module if hasattr(module, "INTERRUPT") else None


def _interrupted() -> None:
    """Ctrl-C (SIGTERM): one line and exit code 130 (143) at once; the temporaries were removed
    while the exception unwound, and nothing is left to write."""
    progress = _progress_module()
    terminated = bool(_TERMINATED) or bool(progress and progress.INTERRUPT.terminated)
    err_console.print("walk3d: terminated" if terminated else "walk3d: interrupted", markup=False)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(143 if terminated else 130)


def _on_sigterm(_signum, _frame) -> None:
    """SIGTERM stops the run as Ctrl-C does (temporaries removed on the way out), exit 143."""
    _TERMINATED.append(True)
    progress = _progress_module()
    if progress is not None:
        progress.INTERRUPT.terminated = progress.INTERRUPT.requested = True
        raise progress.Terminated
    raise KeyboardInterrupt


def _on_sigint(_signum, _frame) -> None:
    """Ctrl-C: KeyboardInterrupt, and the flag that a stage checks when it ends, in case CasADi
    swallows the exception inside IPOPT (:func:`walk3d.solve.progress.raise_if_interrupted`)."""
    progress = _progress_module()
    if progress is not None:
        progress.INTERRUPT.requested = True
    raise KeyboardInterrupt


RESEND_AFTER_S = 0.02
"""s: a swallowed signal is sent again once the hook that saw it has long returned."""


def _on_unraisable(unraisable, previous=sys.__unraisablehook__) -> None:
    """A Ctrl-C or SIGTERM that Python swallowed because it came inside a finalizer or a weakref
    callback ("Exception ignored in ..."): the signal is sent again from a thread, so that the
    main thread gets it at its next step, in code that can stop; anything else goes to the
    ``previous`` hook."""
    exc = unraisable.exc_value
    if not isinstance(exc, KeyboardInterrupt):
        previous(unraisable)
        return
    progress = _progress_module()
    term = bool(_TERMINATED) or (progress is not None and isinstance(exc, progress.Terminated))
    sig = signal.SIGTERM if term else signal.SIGINT
    try:  # a thread that does not make this hook wait, and signals once it has returned
        _thread.start_new_thread(_send_later, (sig,))
    except BaseException:  # noqa: BLE001 - a hook must not raise; the signal comes again
        _send_later(sig, 0.0)


def _send_later(sig: int, after_s: float = RESEND_AFTER_S) -> None:
    """Send ``sig`` to this process after ``after_s`` s."""
    time.sleep(after_s)
    os.kill(os.getpid(), sig)


def _from_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` was caused by Ctrl-C or SIGTERM: a C extension interrupted while it is
    imported raises ImportError ("initialization failed") from the KeyboardInterrupt, and
    pydantic, interrupted while it builds a model's validator, a SchemaError that names it."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        if type(exc).__name__ == "SchemaError" and "KeyboardInterrupt" in str(exc):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _needs_command(exc: Exception) -> str:
    """The line for a command group given no command (``walk3d atlas``), whose help Typer has
    just shown: its click error has no message."""
    ctx = getattr(exc, "ctx", None)
    group = getattr(ctx, "command", None)
    if ctx is None or not hasattr(group, "list_commands"):
        return "a command is missing (see --help)"
    return f"{ctx.command_path} needs a command: {', '.join(group.list_commands(ctx))}"


def _run(args: list[str]) -> None:
    """Run the command line on ``args``; always ends in SystemExit (or ``os._exit``)."""
    try:
        command = typer.main.get_command(app)
        if problem := plain_numbers(command, args):
            fail(problem)
        rv = command.main(args=args, prog_name="walk3d", standalone_mode=False)
    except KeyboardInterrupt:
        _interrupted()
    except Exception as exc:  # Typer vendors click: match its exceptions by shape
        if _from_interrupt(exc):
            _interrupted()
        kind = type(exc).__name__
        if kind == "Exit":
            sys.exit(getattr(exc, "exit_code", 0))
        if kind == "Abort":
            _interrupted()
        if hasattr(exc, "format_message") and hasattr(exc, "exit_code"):
            msg = " ".join(exc.format_message().split()) or _needs_command(exc)
            sys.stderr.write(f"walk3d: error: {msg}\n")
            sys.exit(2)
        raise
    if rv == 130:  # Typer returns Ctrl-C's exit code itself when not in standalone mode
        _interrupted()
    sys.exit(rv if isinstance(rv, int) else 0)


class _LogLines(logging.Handler):
    """walk3d's log records at the command line: one line each, ``walk3d: warning: ...``
    (``error`` from ERROR up), as the command's own warnings."""

    def emit(self, record: logging.LogRecord) -> None:
        kind = "error" if record.levelno >= logging.ERROR else "warning"
        try:
            sys.stderr.write(f"walk3d: {kind}: {' '.join(self.format(record).split())}\n")
        except Exception:  # noqa: BLE001, S110 - a line that cannot be written is dropped
            pass


def main(argv: list[str] | None = None) -> None:
    """Console-script entry point: usage errors become one line and exit code 2; output that
    cannot be written (disk full) one line and exit code 3; a closed pipe
    (``walk3d body | head -1``) a quiet exit with code 141, as a tool ended by SIGPIPE. An
    error line that cannot be written (``2>/dev/full``) is dropped: the exit code stays."""
    args = list(sys.argv[1:] if argv is None else argv) or ["--help"]
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for sig, handler in ((signal.SIGTERM, _on_sigterm),
                             (signal.SIGINT, _on_sigint)):  # fmt: skip
            if signal.getsignal(sig) is not signal.SIG_IGN:  # a background job's stays ignored
                previous[sig] = signal.signal(sig, handler)
    stream, errors, unraisable = sys.stdout, sys.stderr, sys.unraisablehook
    if previous:
        sys.unraisablehook = functools.partial(_on_unraisable, previous=unraisable)
    sys.stdout = GuardedStdout(stream)
    sys.stderr = QuietStderr(errors)
    log_lines = _LogLines(logging.WARNING)
    logging.getLogger("walk3d").addHandler(log_lines)
    try:
        try:
            _run(args)
        except SystemExit as exc:
            code = exc.code
        except KeyboardInterrupt:  # between the handlers' setup and the command's own guard
            _interrupted()
        sys.stdout.flush()
    except OutputClosed:
        silence_stdout(stream)
        code = CLOSED_PIPE_EXIT
    except OutputFailed as exc:
        silence_stdout(stream)
        sys.stderr.write(f"walk3d: error: cannot write the output: {str(exc).lower()}\n")
        code = EXIT_WRITE
    finally:
        sys.stdout, sys.stderr, sys.unraisablehook = stream, errors, unraisable
        logging.getLogger("walk3d").removeHandler(log_lines)
        for sig, handler in previous.items():  # an in-process caller gets its own back; the
            # command ignores a signal once its outcome is decided: Python's exit would restore
            # the default action, which kills it with its result complete and no line
            signal.signal(sig, handler if argv is not None else signal.SIG_IGN)
    if argv is None:
        _end_now(code)
    sys.exit(code)


def _end_now(code: object) -> None:
    """End the command at once with ``code``, its output flushed and its log closed: Python's
    own exit then frees every CasADi function one by one, 0.4 s after a prediction. Only when
    no other thread could still be writing (all daemons) and the code is a number."""
    if not isinstance(code, int | None) or any(
        not t.daemon for t in threading.enumerate() if t is not threading.main_thread()
    ):
        return
    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001, S110 - a closed or full stream: the code stays
            pass
    os._exit(code or 0)
