"""Whether each atlas entry walks by walk3d's own check (:mod:`walk3d.results.gait_checks`),
for ``walk3d atlas show`` and the tests that keep the shipped atlas walking."""

from __future__ import annotations

import numpy as np

from walk3d.campaign.atlas import atlas_settings
from walk3d.problem.settings import body_for
from walk3d.results.evaluate import evaluate_cycle
from walk3d.results.gait_checks import walking_checks
from walk3d.solve.atlas import Atlas

__all__ = ["entry_checks", "walking_entries"]


def entry_checks(atlas: Atlas, handover: bool = False) -> list[dict | None]:
    """Per entry, the gait checks of its free-landing optimum (``handover``: of its handover
    optimum; None where it has none), each at its own speed, period and double support."""
    base = atlas_settings(atlas.sex, atlas.preset).replace(free=(), handover=handover)
    xs = atlas.x_handover if handover else atlas.x
    out: list[dict | None] = []
    for i, v in enumerate(atlas.speeds):
        x = None if xs is None else xs[i]
        if x is None or not np.isfinite(x).all():
            out.append(None)
            continue
        s = base.replace(speed=float(v), period=float(atlas.periods[i]),
                         double_support=float(atlas.double_supports[i]))  # fmt: skip
        ev = evaluate_cycle(body_for(s), s, np.asarray(x, dtype=float))
        g = s.gait
        out.append(walking_checks(ev.prediction_arrays, g.period, g.double_support, g.mass,
                                  g.speed))  # fmt: skip
    return out


def walking_entries(atlas: Atlas, handover: bool = False) -> np.ndarray:
    """Per entry, whether its optimum looks like walking (False where it has none)."""
    return np.array([bool(c and c["looks_like_walking"]) for c in entry_checks(atlas, handover)])
