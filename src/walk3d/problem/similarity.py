"""Dynamic similarity: every subject's prediction is solved as one reference subject's.

The body model scales exactly (:mod:`walk3d.body.anthropometry`): segment masses and joint
strengths in proportion to body mass m, every length (segments, joint offsets, foot, roll-over)
in proportion to stature h. The NLP's rows are normalized by body weight, and the criteria
by strength (C_tor) or by a fixed power (C_en). So:

* **Mass drops out.** At any m the NLP's rows are those at the reference mass, and C_en (J)
  is ``m / m_ref`` times the reference's: the same minimizer. The predicted motion does not
  depend on body mass (forces and moments scale with it); this is a property of the model,
  not of the solver.
* **Stature is a change of units.** With ``s = h / h_ref``, a subject walking with
  ``(V, T, Td)`` moves like the reference subject walking with ``(V, T, Td) / √s`` with every
  length scaled by ``s`` and time by ``√s``: accelerations, and so forces per body weight, are
  unchanged, and moments scale by ``s`` (C_tor by ``s√s``, a constant factor). The joint
  rotations, as Fourier series over the cycle, are the same; only the half step width (m) scales.

:func:`reference_problem` gives the reference subject's settings, which
:func:`walk3d.solve.ipopt.solve` and ``walk3d compile`` use: one model cache entry and one set
of compiled derivatives serve every mass and stature of a sex and criterion. The settings'
lengths are those of the reference stature and scale with the subject's (the free-moment radius,
the minimum ankle separation, and the solver's bounds on the half step width and loop checks),
like the foot and hips they describe; for the reference subject nothing changes. A calibrated
roll-over (``rollover_ankle``, m) is scaled too. The solver's own figures (stage objectives,
``max_constraint_violation``) are the reference problem's; ``summary.json`` gives the scale
under ``solved_as``. The smoothed criterion of the SLSQP baseline (``absolute="smooth"``) is
not exactly similar (its smoothing widths are absolute), a difference of the order of the
smoothing. The results (:func:`walk3d.results.evaluate.evaluate_cycle`) are always evaluated
with the subject's own body and descriptors.
"""

from __future__ import annotations

import math

import numpy as np

from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings

REFERENCE_MASS_KG = 68.8
"""Body mass of the reference subject (the paper's)."""
REFERENCE_HEIGHT_M = 1.77
"""Stature of the reference subject (the paper's)."""


def length_scale(settings: PredictionSettings) -> float:
    """``s = h / h_ref`` by which the subject's lengths exceed the reference subject's."""
    return settings.gait.height / REFERENCE_HEIGHT_M


def reference_problem(settings: PredictionSettings) -> tuple[PredictionSettings, float]:
    """The reference subject's settings whose solution is this subject's, and ``s``.

    Mass and stature become the reference's, the descriptors ``V, T, Td`` are divided by
    ``√s``, a calibrated roll-over's ankle path and shank length changes by ``s`` and added
    masses by the mass ratio; everything else is kept. The reference subject's own settings come
    back unchanged (the same object), so its solves are exactly those of the settings given.
    """
    s = length_scale(settings)
    g, m = settings.gait, settings.model
    if g.mass == REFERENCE_MASS_KG and s == 1.0:
        return settings, 1.0
    gait: dict[str, object] = {"mass": REFERENCE_MASS_KG}
    model: dict[str, object] = {}
    if s != 1.0:
        root = math.sqrt(s)
        gait |= {"height": REFERENCE_HEIGHT_M, "speed": g.speed / root,
                 "period": g.period / root, "double_support": g.double_support / root}  # fmt: skip
        if m.rollover_ankle is not None:  # the spline is linear in its samples
            model["rollover_ankle"] = tuple(tuple(c / s for c in p) for p in m.rollover_ankle)
    changes: dict[str, object] = {}
    if m.changes.added_mass:  # a fixed fraction of the body mass, as every segment's
        k = REFERENCE_MASS_KG / g.mass
        changes["added_mass"] = tuple((name, kg * k) for name, kg in m.changes.added_mass)
    if m.changes.shank_length and s != 1.0:  # a fixed fraction of the stature
        changes["shank_length"] = tuple((name, dm / s) for name, dm in m.changes.shank_length)
    if changes:
        model["changes"] = m.changes.model_copy(update=changes)
    # not revalidated: the scaled descriptors may leave the user-facing ranges
    groups = {"gait": g.model_copy(update=gait), "model": m.model_copy(update=model)}
    return settings.model_copy(update=groups), s


def subject_x(x_ref: np.ndarray, s: float) -> np.ndarray:
    """The subject's decision vector (``layout``; or the full cycle's ``X``) from the reference
    subject's solution: the Fourier coefficients are the same, the half step width and the
    full cycle's step shift (m) ``s`` times larger."""
    x = np.array(x_ref, dtype=float, copy=True)
    x[layout.I_HALF_STEP] *= s
    if x.size == layout.N_XF:
        x[layout.I_STEP_SHIFT] *= s
    return x
