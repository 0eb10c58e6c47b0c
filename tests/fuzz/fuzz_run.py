"""Running one fuzz case: ``walk3d ARGS`` in this process under a time limit, and the checks of
its outcome (an allowed exit code, no traceback, one error line)."""

from __future__ import annotations

import contextlib
import dataclasses
import faulthandler
import io
import json
import math
import os
import re
import signal
import sys
import threading
import time
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

INTERNAL = re.compile(
    r"zero-size array|has no identity|could not convert|has no attribute|NoneType|out of bounds"
    r"|unhashable|not subscriptable|positional argument|division by zero|invalid literal"
    r"|could not be broadcast|unsupported operand|must be real number|list index|tuple index"
)
"""Words of Python's and NumPy's own messages: an error line that holds them tells the user
what broke inside walk3d, not what is wrong with the file."""
LIMIT_S = 60.0
"""A case that runs longer hangs (the slowest, a validation drawing its figures, takes ~5 s)."""


class CaseTimeout(BaseException):
    """Raised in the case by SIGALRM: not an Exception, so that no ``except`` of walk3d's
    takes it for an error of its own."""


@contextlib.contextmanager
def time_limit(seconds: float, name: str) -> Iterator[None]:
    """CaseTimeout after ``seconds`` (in the main thread), and as a backstop for a hang in C
    code, where no signal handler runs: every thread's stack dumped and the process ended
    after twice that (pytest-xdist then names the case whose worker died)."""
    main = threading.current_thread() is threading.main_thread()

    def on_alarm(_signum, _frame) -> None:  # noqa: ANN001
        raise CaseTimeout(f"{name}: no end after {seconds:g} s")

    old = signal.signal(signal.SIGALRM, on_alarm) if main else None
    if main:
        signal.setitimer(signal.ITIMER_REAL, seconds)
    faulthandler.dump_traceback_later(2 * seconds, exit=True, file=sys.__stderr__)
    try:
        yield
    finally:
        faulthandler.cancel_dump_traceback_later()
        if main:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)


@dataclass(frozen=True)
class Outcome:
    """What ``walk3d ARGS`` did: exit code, standard output and error, wall time (s)."""

    code: int | str | None
    out: str
    err: str
    seconds: float
    warnings: tuple[str, ...] = ()
    """Python warnings the command let through (printed as two lines outside pytest)."""


def run_cli(args: list, name: str, limit: float = LIMIT_S) -> Outcome:
    """``walk3d ARGS`` in this process (:func:`walk3d.cli.main`); any exception but SystemExit
    (a traceback) and CaseTimeout (a hang) propagates to the test."""
    from walk3d.cli import main

    out, err = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    code: int | str | None = None
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        with time_limit(limit, name), warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                main([str(a) for a in args])
            except SystemExit as exc:
                code = exc.code
    seen = tuple(f"{w.category.__name__}: {w.message} ({Path(w.filename).name}:{w.lineno})"
                 for w in caught)  # fmt: skip
    return Outcome(code, out.getvalue(), err.getvalue(), time.perf_counter() - t0, seen)


def check_outcome(outcome: Outcome, allowed: tuple[int, ...]) -> None:
    """An allowed exit code, no traceback, only ``walk3d:`` lines on stderr, and exactly one
    ``walk3d: error:`` line when the command failed."""
    err = outcome.err
    where = f"exit {outcome.code}, stderr:\n{err[-2000:]}"
    assert outcome.code in allowed, where
    assert "Traceback" not in outcome.out + err, where
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert all(ln.startswith("walk3d: ") for ln in lines), where
    errors = sum(ln.startswith("walk3d: error:") for ln in lines)
    assert errors == (1 if outcome.code not in (0, 1) else 0), where
    assert not INTERNAL.search(err), where


def non_finite(value, where: str = "") -> list[str]:  # noqa: ANN001 - any nested value
    """Paths of the NaN or infinite numbers inside ``value`` (dicts, sequences, arrays,
    dataclasses and pydantic models)."""
    if hasattr(value, "model_dump"):
        value = value.model_dump()
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        value = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in non_finite(v, f"{where}.{k}")]
    if isinstance(value, list | tuple):
        return [p for i, v in enumerate(value) for p in non_finite(v, f"{where}[{i}]")]
    if isinstance(value, np.ndarray) and value.dtype.kind in "fc":
        return [] if np.isfinite(value).all() else [where]
    if isinstance(value, float) and not math.isfinite(value):
        return [where]
    return []


def log_case(name: str, outcome: Outcome) -> None:
    """Append the case's exit code, time and error line to ``$WALK3D_FUZZ_LOG`` when set."""
    path = os.environ.get("WALK3D_FUZZ_LOG")
    if not path:
        return
    last = (outcome.err.strip().splitlines() or [""])[-1][:300]
    record = {
        "case": name,
        "code": outcome.code,
        "s": round(outcome.seconds, 3),
        "err": last,
        "warnings": sorted(set(outcome.warnings)),
    }
    with open(path, "a", encoding="utf-8") as handle:
        handle.write(json.dumps(record) + "\n")
