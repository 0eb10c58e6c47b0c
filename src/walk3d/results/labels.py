"""Whether a result is a valid walking prediction, as its summary records it: the label that
``walk3d report``'s banners, and ``compare``, ``validate`` and ``animate``'s warnings, show.

Only a recorded JSON ``true`` is converged (``"no"`` or ``1`` is not); a summary without
``converged`` records no solve (a fitted or atlas motion) and is not labelled as failed.
"""

from __future__ import annotations

from typing import Any

__all__ = ["did_not_converge", "invalid_reason", "is_converged"]


def is_converged(summary: dict[str, Any]) -> bool:
    """Whether ``summary["converged"]`` is ``True`` itself."""
    return summary.get("converged") is True


def did_not_converge(summary: dict[str, Any]) -> bool:
    """Whether the summary records a solve that did not converge (any value but ``True``)."""
    return "converged" in summary and summary.get("converged") is not True


def invalid_reason(summary: dict[str, Any]) -> str | None:
    """Why the result is not a valid walking prediction, one phrase; None when nothing says so
    (a result that records no solve included)."""
    if did_not_converge(summary):
        status = summary.get("status", "unknown status")
        return f"the solve did not converge ({status!s:.60}): not a valid prediction"
    checks = summary.get("gait_checks")
    if isinstance(checks, dict) and checks.get("looks_like_walking") is False:
        return "the gait does not look like walking (summary gait_checks)"
    return None
