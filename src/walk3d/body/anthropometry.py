"""De Leva (1996) segment parameters scaled to a subject, lumped into walk3d's 13 segments.

The paper's segments map onto de Leva's as follows: *torso* = upper + middle trunk, *pelvis* =
lower trunk, *head* = head + neck, *forearm* = forearm + hand. Lumped segments get their mass,
centre of mass and inertia by summation and the parallel-axis theorem; de Leva's radii of
gyration give principal moments about the segment's centre of mass.

Scaling: lengths scale with stature / de Leva's reference stature, masses with body mass.

Axes: a segment's longitudinal axis is y (vertical in upright standing) for every segment but the
foot, whose longitudinal axis is x (heel to toe); the foot's remaining axes take de Leva's
transverse radius about z (pitch) and the sagittal radius about y.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from importlib import resources
from typing import Any

SEXES = ("male", "female")


@dataclass(frozen=True)
class DeLevaSegment:
    """One de Leva row scaled to a subject (SI units)."""

    length: float
    mass: float
    com_fraction: float
    inertia_xyz: tuple[float, float, float]
    """Principal moments about the centre of mass, in the walk3d segment frame (x, y, z)."""


@cache
def load_parameters() -> dict[str, Any]:
    """The parsed ``body/data/parameters.toml`` (cached; do not mutate)."""
    text = resources.files("walk3d.body").joinpath("data/parameters.toml").read_bytes()
    return tomllib.loads(text.decode("utf-8"))


def scaled_de_leva(mass: float, height: float, sex: str) -> dict[str, DeLevaSegment]:
    """De Leva segments (head, trunk parts, arm parts, leg parts) scaled to mass and height."""
    if sex not in SEXES:
        raise ValueError(f"sex must be one of {SEXES}, got {sex!r}")
    table = load_parameters()["anthropometry"][sex]
    k = height / table["reference_stature_m"]
    out: dict[str, DeLevaSegment] = {}
    for name, row in table["segments"].items():
        length = row["length_m"] * k
        seg_mass = row["mass_fraction"] * mass
        r_sag = row["r_sagittal"] * length
        r_trans = row["r_transverse"] * length
        r_long = row["r_longitudinal"] * length
        if name == "foot":
            inertia = (seg_mass * r_long**2, seg_mass * r_sag**2, seg_mass * r_trans**2)
        else:
            inertia = (seg_mass * r_sag**2, seg_mass * r_long**2, seg_mass * r_trans**2)
        out[name] = DeLevaSegment(length, seg_mass, row["com_fraction"], inertia)
    return out


def lump(parts: list[tuple[float, tuple[float, float, float], tuple[float, float, float]]]):
    """Combine rigid parts ``(mass, com_xyz, inertia_xyz)`` given in one frame.

    Returns ``(mass, com, inertia_xyz)``: the principal moments of the combination about its
    common centre of mass, assuming the parts' centres lie on one axis-aligned line so that the
    product terms vanish (true for walk3d's collinear segment parts).
    """
    mass = sum(p[0] for p in parts)
    com = tuple(sum(p[0] * p[1][i] for p in parts) / mass for i in range(3))
    inertia = [0.0, 0.0, 0.0]
    for pm, pc, pi in parts:
        d = [pc[i] - com[i] for i in range(3)]
        inertia[0] += pi[0] + pm * (d[1] ** 2 + d[2] ** 2)
        inertia[1] += pi[1] + pm * (d[0] ** 2 + d[2] ** 2)
        inertia[2] += pi[2] + pm * (d[0] ** 2 + d[1] ** 2)
    return mass, com, tuple(inertia)
