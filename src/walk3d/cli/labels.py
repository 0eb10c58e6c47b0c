"""The warning line of a command that reads a result which is not a valid walking prediction
(:func:`walk3d.results.labels.invalid_reason`): ``compare``, ``validate`` and ``animate`` keep
their exit codes, as ``walk3d report`` does, and say so on standard error."""

from __future__ import annotations

import os
import sys
from typing import Any

from walk3d.results.labels import invalid_reason

__all__ = ["warn_if_invalid"]


def warn_if_invalid(folder: str | os.PathLike[str], summary: dict[str, Any]) -> str | None:
    """Print ``walk3d: warning: FOLDER: <reason>`` when the result in ``folder`` did not
    converge or does not walk; returns the reason (None: nothing printed)."""
    reason = invalid_reason(summary)
    if reason is not None:
        sys.stderr.write(f"walk3d: warning: {os.fspath(folder)}: {reason}\n")
    return reason
