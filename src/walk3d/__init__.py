"""walk3d: predict three-dimensional whole-body human walking.

Conventions used everywhere in the package (see ``docs/conventions.md``):

* global frame: X forward, Y up, Z to the walker's right (OpenSim);
* quaternions are scalar-first ``[w, x, y, z]``;
* SI units inside the package (radians, metres, newtons); degrees and N/kg only at the edges
  (command line, files, figures);
* time is the first axis of every array.
"""

import os as _os
import signal as _signal
import sys as _sys
import threading as _threading


def _exit_at_once(signum: int, _frame: object) -> None:
    """Ctrl-C or SIGTERM while the ``walk3d`` command is still importing: nothing is written
    yet, so one line and exit code 130 (143) at once (the command line then takes over)."""
    terminated = signum == _signal.SIGTERM
    try:
        _os.write(2, b"walk3d: terminated\n" if terminated else b"walk3d: interrupted\n")
    except OSError:
        pass
    _os._exit(143 if terminated else 130)


def _is_the_command() -> bool:
    """Whether this process is the ``walk3d`` command (or ``python -m walk3d.cli``), not a
    program that imports walk3d, nor a worker process started from the command."""
    argv, orig = _sys.argv, _sys.orig_argv
    if argv and argv[0] == "-m":  # while ``python -m MODULE`` imports MODULE's package
        module = orig[-len(argv)] if len(orig) >= len(argv) else ""
        return module.removeprefix("-m") == "walk3d.cli"
    script = argv[0] if argv else ""
    return _os.path.basename(script) in ("walk3d", "walk3d.exe") and orig[1:2] == [script]


def _install(handler) -> None:
    """``handler`` for SIGINT and SIGTERM, but not where the caller ignores them (a background
    job of a non-interactive shell ignores Ctrl-C)."""
    for sig in (_signal.SIGINT, _signal.SIGTERM):
        if _signal.getsignal(sig) is not _signal.SIG_IGN:
            _signal.signal(sig, handler)


if _is_the_command() and _threading.current_thread() is _threading.main_thread():
    _install(_exit_at_once)

from walk3d.constants import G, __version__  # noqa: E402

__all__ = ["G", "Node", "Prediction", "Term", "__version__", "load_result", "predict",
           "register_term", "track"]  # fmt: skip

_API = ("Prediction", "load_result", "predict", "track")
_TERMS = {"Term": "Term", "Node": "Node", "register_term": "register"}


def __getattr__(name: str):  # noqa: ANN202 - lazy: ``import walk3d`` stays light for the CLI
    """``predict``, ``load_result`` and ``Prediction`` from :mod:`walk3d.api`; ``Term``,
    ``Node`` and ``register_term`` (:func:`walk3d.model.terms.register`), on first use."""
    if name in _API:
        from walk3d import api

        return getattr(api, name)
    if name in _TERMS:
        from walk3d.model import terms

        return getattr(terms, _TERMS[name])
    raise AttributeError(f"module 'walk3d' has no attribute {name!r}")
