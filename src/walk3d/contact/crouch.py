"""Is a gait crouched? The mean hip flexion over mid-stance against walking's largest.

Most random standing starts end in crouched local optima (C_tor 4–7 against 1.9–3.7 for
walking, docs/solver.md): the knee still flexes in swing, but the hip stays flexed through
stance. A long stride flexes the hip as much at heel strike, and extends it by mid-stance, so
the check reads mid-stance (:attr:`walk3d.contact.phases.GaitPhases.mid_stance`). The solver
reads it from the NLP's nodes (:mod:`walk3d.solve.upright`), the gait checks from the
evaluated cycle (:mod:`walk3d.results.gait_checks`).
"""

from __future__ import annotations

import numpy as np

from walk3d.contact.phases import GaitPhases

HIP_MIDSTANCE_MAX_DEG = 27.0
"""Mean hip flexion over the middle third of stance above which a gait counts as crouched,
deg: between walk3d's walking optima (at most 25°, the man at 1.9 m/s) and its crouched ones
(32° and more); measured adults: 5° (Falisse 2019). Evidence: docs/solver.md, the crouch
check that reads mid-stance."""


def midstance_mean(values: np.ndarray, since_heel_strike: np.ndarray,
                   phases: GaitPhases) -> float:  # fmt: skip
    """Mean of ``values`` over the samples whose time since the right heel strike
    (``since_heel_strike``, s) lies in mid-stance; NaN when none does."""
    lo, hi = phases.mid_stance
    since = np.asarray(since_heel_strike)
    inside = (since >= lo) & (since <= hi)
    return float(np.asarray(values)[inside].mean()) if inside.any() else float("nan")


def upright(hip_midstance_deg: float) -> bool:
    """Whether a mean mid-stance hip flexion, deg, is walking's: at most
    :data:`HIP_MIDSTANCE_MAX_DEG` (NaN is not)."""
    return bool(hip_midstance_deg <= HIP_MIDSTANCE_MAX_DEG)
