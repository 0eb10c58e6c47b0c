"""The values a subject's calibration may take (``walk3d calibrate``, ``--calibration FILE``,
``ModelSettings.rollover_s``/``rollover_ankle``/``transition_ratios``): one check shared by the
file reader and the settings, so the API refuses what the command line refuses, before any
solve."""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = ["MAX_ANKLE_M", "RATIO_NAMES", "RATIO_RANGES", "problem"]

MAX_ANKLE_M = 1.0
"""m: a bound on the ankle's displacement at a roll-over knot, well above the calibrations seen
(Falisse ``gait_1``: 0.17 m; OpenSim subject01 on a treadmill: 0.47 m)."""
RATIO_NAMES = ("mu_x", "mu_z", "varpi_x", "varpi_y")
"""The transition ratios of Eqs. 7–8, in the order of ``transition_ratios``."""
RATIO_RANGES = {"mu_x": (0.0, 1.0), "mu_z": (-1.0, 1.0), "varpi_x": (-5.0, 5.0),
                "varpi_y": (-5.0, 5.0)}  # fmt: skip
"""Accepted transition ratios: the trailing foot pushes forward at heel strike (``μ_x ≥ 0``)
with a horizontal force under its vertical one; the moment ratios of measured walking are
about 0.1 (Falisse ``gait_1``: 0.14, −0.007)."""


def number(value: object) -> bool:
    """Whether ``value`` is a finite int or float (a bool is not a number here)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def rollover_problem(s: Sequence, ankle: Sequence) -> tuple[str, str] | None:
    """``(reason, key)`` of the first thing wrong with roll-over knots ``s`` (``sin(θ/2)``) and
    ankle points ``ankle`` (m), or None; ``key`` names the offending entry."""
    if not isinstance(s, (list, tuple)) or len(s) < 3 or not all(number(v) for v in s):
        return "'rollover.s' must be a list of at least 3 numbers", "s"
    if any(b <= a for a, b in zip(s[:-1], s[1:], strict=True)):
        return "'rollover.s' must be strictly increasing", "s"
    if not -1 < s[0] < 0 < s[-1] < 1:
        reason = ("'rollover.s' must run from below 0 to above 0 (the flat foot) within (-1, 1) "
                  f"(sin of half the foot's rotation); it runs {s[0]:g} to {s[-1]:g}")  # fmt: skip
        return reason, "s"
    if (not isinstance(ankle, (list, tuple)) or len(ankle) != len(s)
            or not all(isinstance(p, (list, tuple)) and len(p) == 3 and all(number(c) for c in p)
                       for p in ankle)):  # fmt: skip
        return f"'rollover.ankle_m' must hold {len(s)} [x, y, z] number triples", "ankle_m"
    if max(abs(c) for p in ankle for c in p) > MAX_ANKLE_M:
        return (f"'rollover.ankle_m' moves the ankle by more than {MAX_ANKLE_M:g} m: not a "
                "roll-over of a foot", "ankle_m")  # fmt: skip
    return None


def ratio_problem(name: str, value: object) -> tuple[str, str] | None:
    """``(reason, key)`` if transition ratio ``name`` is not a finite number in its range."""
    if not number(value):
        return f"'transition.{name}' must be a finite number", name
    lo, hi = RATIO_RANGES[name]
    if not lo <= value <= hi:
        return f"'transition.{name}' must be in [{lo:g}, {hi:g}], got {value:g}", name
    return None


def problem(s: Sequence | None, ankle: Sequence | None,
            ratios: Sequence | None) -> str | None:  # fmt: skip
    """The first thing wrong with a calibration given as settings (None: not calibrated), or
    None."""
    if s is not None or ankle is not None:
        found = rollover_problem(s, ankle)
        if found:
            return found[0]
    if ratios is not None:
        if len(ratios) != len(RATIO_NAMES):
            return f"transition_ratios must hold {len(RATIO_NAMES)} numbers"
        for name, value in zip(RATIO_NAMES, ratios, strict=True):
            found = ratio_problem(name, value)
            if found:
                return found[0]
    return None
