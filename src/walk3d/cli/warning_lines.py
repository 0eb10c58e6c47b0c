"""Warnings on the command line as one ``walk3d: warning: ...`` line each, not in Python's
two-line form (file, line, source)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager


def _warning_line(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
    sys.stderr.write(f"walk3d: warning: {' '.join(str(message).split())}\n")


@contextmanager
def warning_lines() -> Iterator[None]:
    """In the block, each warning is printed once per place as it happens, as one line
    (``walk3d: warning: ...``), not in Python's two-line form (a long run's, e.g. sweep's)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = _warning_line
        yield


def warned(func, *args, **kwargs):  # noqa: ANN001, ANN201 - passes func's result through
    """``func(*args, **kwargs)`` with every warning it raises printed as one line
    (``walk3d: warning: ...``) instead of Python's two-line form."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = func(*args, **kwargs)
    for w in caught:
        sys.stderr.write(f"walk3d: warning: {' '.join(str(w.message).split())}\n")
    return result
