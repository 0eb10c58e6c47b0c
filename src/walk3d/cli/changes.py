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

REPEAT = " Repeated options add up; a name given twice must have one value."

Strength = Annotated[
    list[str] | None,
    typer.Option("--strength", metavar="JOINT=FACTOR[,...]", rich_help_panel=CHANGES,
                 help="Scale a joint's strengths (both directions) by 0.01 to 10, e.g. ankle=0.5 "
                 "(both sides) or ankle_r=0.5 (one side: the full cycle is solved): C_tor and the "
                 "effort terms then cost more per N·m." + REPEAT),
]  # fmt: skip
Range = Annotated[
    list[str] | None,
    typer.Option("--range", metavar="DOF=MIN:MAX[,...]", rich_help_panel=CHANGES,
                 help="Bound a joint angle, deg, on the whole cycle as an orthosis does, e.g. "
                 "ankle_dorsiflexion_r=-5:5 (the braced foot's heel may then rise from 30 % of "
                 "its stance)." + REPEAT),
]  # fmt: skip
AddedMass = Annotated[
    list[str] | None,
    typer.Option("--added-mass", metavar="SEGMENT=KG[,...]", rich_help_panel=CHANGES,
                 help="A point mass at a segment's centre of mass, e.g. torso=10 (a backpack); "
                 "foot=1 puts 1 kg on each foot, foot_r=1 on the right one." + REPEAT),
]  # fmt: skip
LegLength = Annotated[
    list[float] | None,
    typer.Option("--leg-length-difference", metavar="M", rich_help_panel=CHANGES,
                 help="The right shank shorter (negative) or longer, m, e.g. -0.02 (one-sided: "
                 "the full cycle is solved). Given once: one number cannot add up."),
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
                 "the stride splits freely, at a cost; docs/what-if.md); needs --full-cycle or "
                 "a one-sided change."),
]  # fmt: skip


Specs = list[str] | str | None
"""A what-if option's value: each ``--strength`` given (a list), one spec, or None."""


def _items(specs: Specs, option: str) -> list[tuple[str, str]]:
    """``(name, value)`` texts of every spec of ``option``, in order: one error line and exit 2
    for an empty spec or item (``''``, ``ankle=0.5,,knee=0.3``) and one without a name or a
    value (``ankle=``, ``=0.5``)."""
    out = []
    for text in [specs] if isinstance(specs, str) else specs or []:
        if not text.strip():
            fail(f"{option} is empty: it takes NAME=VALUE[,...]")
        for part in text.split(","):
            name, sep, value = part.strip().partition("=")
            if not part.strip():
                fail(f"{option} {text!r} has an empty item: it takes NAME=VALUE[,...]")
            if not sep or not name.strip() or not value.strip():
                fail(f"{option} takes NAME=VALUE[,...], got {part.strip()!r}")
            out.append((name.strip(), value.strip()))
    return out


def _number(text: str, option: str, name: str) -> float:
    """``text`` as a number, or one error line and exit 2 for one that is not finite or not
    plainly decimal (``1_0``, which ``float()`` reads as 10)."""
    from walk3d.decimals import decimal

    v = decimal(text)
    if not math.isfinite(v):
        fail(f"{option}: {name}={text!r} is not a finite decimal number (like 0.5)")
    return v


def _once(rows: list[tuple]) -> list[tuple]:
    """``rows`` without repeats of the same name and value (the same change given twice); a
    name with two values stays twice, for :func:`walk3d.body.changes.check_changes` to refuse."""
    return list(dict.fromkeys(rows))


def changes_option(
    strength: Specs,
    limits: Specs,
    added_mass: Specs,
    full_cycle: bool = False,
    leg_length: list[float] | float | None = None,
    equal_steps: bool = False,
) -> dict:
    """``{"changes": {...}, "full_cycle": True, "equal_steps": True}`` for the settings from the
    options (each only when given; repeated list options merge), or one error line and exit 2
    for one that does not parse or a repeated ``--leg-length-difference`` (names and values are
    checked by the settings)."""
    changes: dict[str, list] = {}
    lengths = leg_length if isinstance(leg_length, list) else [leg_length]
    if len(lengths) > 1:
        given = " and ".join(f"{v:g}" for v in lengths)
        fail(f"--leg-length-difference is given {len(lengths)} times ({given}): it takes one "
             "number, give it once")  # fmt: skip
    if lengths and lengths[0]:
        changes["shank_length"] = [("shank_r", lengths[0])]
    if rows := [(n, _number(v, "--strength", n)) for n, v in _items(strength, "--strength")]:
        changes["strength"] = _once(rows)
    if rows := [(n, _number(v, "--added-mass", n))
                for n, v in _items(added_mass, "--added-mass")]:  # fmt: skip
        changes["added_mass"] = _once(rows)
    rows = []
    for n, v in _items(limits, "--range"):
        lo, sep, hi = v.partition(":")
        if not sep:
            fail(f"--range takes DOF=MIN:MAX in degrees, got {n}={v!r}")
        lo_deg, hi_deg = _number(lo, "--range", n), _number(hi, "--range", n)
        if max(abs(lo_deg), abs(hi_deg)) > 180.0:
            fail(f"--range {n}={v} is beyond ±180° (the limits are joint angles in degrees)")
        rows.append((n, math.radians(lo_deg), math.radians(hi_deg)))
    if rows:
        changes["limits"] = _once(rows)
    flags = {"full_cycle": full_cycle, "equal_steps": equal_steps}
    return ({"changes": changes} if changes else {}) | {k: True for k, v in flags.items() if v}
