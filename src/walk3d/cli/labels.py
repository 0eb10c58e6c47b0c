"""How the commands label a result: the warning line of a command that reads a result which is
not a valid walking prediction (:func:`walk3d.results.labels.invalid_reason`; ``compare``,
``validate`` and ``animate`` keep their exit codes, as ``walk3d report`` does, and say so on
standard error; ``predict`` prints the same line beside its exit code), and where a prediction
started."""

from __future__ import annotations

import os
import sys
from typing import Any

from walk3d.cli.common import exit_code
from walk3d.results.labels import invalid_reason

__all__ = ["predict_exit_code", "start_text", "warn_if_invalid"]


def warn_if_invalid(folder: str | os.PathLike[str], summary: dict[str, Any]) -> str | None:
    """Print ``walk3d: warning: FOLDER: <reason>`` when the result in ``folder`` did not
    converge or does not walk; returns the reason (None: nothing printed)."""
    reason = invalid_reason(summary)
    if reason is not None:
        sys.stderr.write(f"walk3d: warning: {os.fspath(folder)}: {reason}\n")
    return reason


def predict_exit_code(folder: str | os.PathLike[str], summary: dict[str, Any]) -> int:
    """``walk3d predict``'s exit code for the result written in ``folder``
    (:func:`~walk3d.cli.common.exit_code`), after its :func:`warn_if_invalid` line if any."""
    warn_if_invalid(folder, summary)
    return exit_code(summary)


def start_text(summary: dict) -> str:
    """Where a prediction started, for the printed tables."""
    start = summary.get("start", "standing")
    first = (summary.get("stages") or [{}])[0]
    if start == "atlas":
        speeds = ", ".join(f"{v:.2f}" for v in first.get("atlas_speeds", []))
        return f"atlas (walk3d's solutions at {speeds} m/s, reference subject)"
    if first.get("start") == "atlas":
        return "standing (after the atlas start did not converge)"
    return start
