"""Numbers typed as text, read as the user sees them: Python's ``float()`` also reads ``1_0`` as
10, ``inf``, `` 1`` and non-ASCII digits, which a user who typed them did not mean as numbers."""

from __future__ import annotations

import math
import re

_DECIMAL = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?", re.ASCII)


def decimal(text: str) -> float:
    """The number a plain decimal text writes (``1.2``, ``-5``, ``2e-3``; surrounding spaces
    allowed), or NaN for any other text."""
    text = text.strip()
    return float(text) if _DECIMAL.fullmatch(text) else math.nan
