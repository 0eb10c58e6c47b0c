"""The subject the settings describe: the body model (with a calibrated roll-over and the
what-if changes) and the calibrated transition ratios. Importable from
:mod:`walk3d.problem.settings` as well."""

from __future__ import annotations

from typing import Any


def body_for(settings: Any) -> Any:
    """The :class:`~walk3d.body.model.BodyModel` of these :class:`PredictionSettings`: with the
    calibrated roll-over, if any, and the what-if strengths, added masses and shank lengths."""
    from dataclasses import replace

    import numpy as np

    from walk3d.body.changes import apply_changes
    from walk3d.body.model import build_body
    from walk3d.body.rollover import RollOver

    g, m = settings.gait, settings.model
    body = build_body(g.mass, g.height, g.sex)
    body = apply_changes(body, m.changes.strength, m.changes.added_mass, m.changes.shank_length)
    if m.rollover_s is None:
        return body
    ro = RollOver.from_samples(np.array(m.rollover_s), np.array(m.rollover_ankle))
    return replace(body, rollover=ro)


def ratios_for(model: Any) -> Any:
    """The calibrated :class:`~walk3d.contact.transition.TransitionRatios` of these
    :class:`ModelSettings`, or None."""
    from walk3d.contact.transition import TransitionRatios

    r = model.transition_ratios
    return None if r is None else TransitionRatios(*r)
