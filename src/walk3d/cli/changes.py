"""The what-if options of ``walk3d predict``, ``campaign`` and ``sweep`` (issue #43):
``--strength``, ``--range``, ``--added-mass`` and ``--leg-length-difference``, parsed into
:class:`walk3d.model.whatif.Changes` fields (degrees at this edge, rad inside), and
``--full-cycle``."""

from __future__ import annotations

import math
from typing import Annotated

import typer

from walk3d.cli.common import fail

CHANGES = "What if (docs/what-if.md)"

Strength = Annotated[
    str | None,
    typer.Option("--strength", metavar="JOINT=FACTOR[,...]", rich_help_panel=CHANGES,
                 help="Scale a joint's strengths (both directions), e.g. ankle=0.5 (both sides) or "
                 "ankle_r=0.5 (one side: the full cycle is solved): C_tor and the effort terms "
                 "then cost more per N·m."),
]  # fmt: skip
Range = Annotated[
    str | None,
    typer.Option("--range", metavar="DOF=MIN:MAX[,...]", rich_help_panel=CHANGES,
                 help="Bound a joint angle, deg, on the whole cycle as an orthosis does, e.g. "
                 "ankle_dorsiflexion_r=-5:5 (the braced foot's heel may then rise from 30 % of "
                 "its stance)."),
]  # fmt: skip
AddedMass = Annotated[
    str | None,
    typer.Option("--added-mass", metavar="SEGMENT=KG[,...]", rich_help_panel=CHANGES,
                 help="A point mass at a segment's centre of mass, e.g. torso=10 (a backpack); "
                 "foot=1 puts 1 kg on each foot, foot_r=1 on the right one."),
]  # fmt: skip
LegLength = Annotated[
    float | None,
    typer.Option("--leg-length-difference", metavar="M", rich_help_panel=CHANGES,
                 help="The right shank shorter (negative) or longer, m, e.g. -0.02 (one-sided: "
                 "the full cycle is solved)."),
]  # fmt: skip
FullCycle = Annotated[
    bool,
    typer.Option("--full-cycle", rich_help_panel=CHANGES,
                 help="Solve the full cycle, each side with its own series, after the half "
                 "cycle (always with a one-sided change)."),
]  # fmt: skip


EqualSteps = Annotated[
    bool,
    typer.Option("--equal-steps", rich_help_panel=CHANGES,
                 help="Hold the full cycle's right and left steps equal in length (by default "
                 "the stride splits freely, at a cost; docs/what-if.md)."),
]  # fmt: skip


def _items(text: str, option: str) -> list[tuple[str, str]]:
    out = []
    for part in text.split(","):
        name, sep, value = part.strip().partition("=")
        if not sep or not name.strip() or not value.strip():
            fail(f"{option} takes NAME=VALUE[,...], got {part.strip()!r}")
        out.append((name.strip(), value.strip()))
    return out


def _number(text: str, option: str, name: str) -> float:
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not math.isfinite(v):
        fail(f"{option}: {name}={text!r} is not a finite number")
    return v


def changes_option(
    strength: str | None,
    limits: str | None,
    added_mass: str | None,
    full_cycle: bool = False,
    leg_length: float | None = None,
    equal_steps: bool = False,
) -> dict:
    """``{"changes": {...}, "full_cycle": True, "equal_steps": True}`` for the settings from the
    options (each only when given), or one error line and exit 2 for one that does not parse
    (names and values are checked by the settings)."""
    changes: dict[str, list] = {}
    if leg_length:
        changes["shank_length"] = [("shank_r", leg_length)]
    if strength:
        changes["strength"] = [(n, _number(v, "--strength", n))
                               for n, v in _items(strength, "--strength")]  # fmt: skip
    if added_mass:
        changes["added_mass"] = [(n, _number(v, "--added-mass", n))
                                 for n, v in _items(added_mass, "--added-mass")]  # fmt: skip
    if limits:
        rows = []
        for n, v in _items(limits, "--range"):
            lo, sep, hi = v.partition(":")
            if not sep:
                fail(f"--range takes DOF=MIN:MAX in degrees, got {n}={v!r}")
            lo_deg, hi_deg = _number(lo, "--range", n), _number(hi, "--range", n)
            rows.append((n, math.radians(lo_deg), math.radians(hi_deg)))
        changes["limits"] = rows
    flags = {"full_cycle": full_cycle, "equal_steps": equal_steps}
    return ({"changes": changes} if changes else {}) | {k: True for k, v in flags.items() if v}
