"""Validation against measured walking (paper section 3, Tables 2–3, Figs. 2–7).

* :mod:`.quantities`, :mod:`.reference`, :mod:`.compare`: Table 2, a prediction against a cycle
  table or trial files, quantity by quantity with explicit sign conventions;
* :mod:`.projection`, :mod:`.measured`, :mod:`.criteria`: the measured gait through walk3d's
  Fourier series and inverse dynamics, and Table 3;
* :mod:`.figures`, :mod:`.run`: figures and one complete validation run (``walk3d validate``);
* :mod:`.target`, :mod:`.target_checks`: the same measured quantities as a tracking target on
  walk3d's 24 DoFs (``walk3d track``, issue #58).

Trials, their descriptors and measured kinematics are read by :mod:`walk3d.trials`; roll-over
and transition ratios are fitted by :mod:`walk3d.calibration`.
"""

from walk3d.validation.compare import Comparison, align_prediction, compare
from walk3d.validation.measured import GaitFit, fit_measured_gait, measured_prediction
from walk3d.validation.reference import Reference, reference_from_table, trial_reference
from walk3d.validation.run import Validation, validate
from walk3d.validation.target import TrackingTarget, tracking_target

__all__ = [
    "Comparison",
    "GaitFit",
    "Reference",
    "TrackingTarget",
    "Validation",
    "align_prediction",
    "compare",
    "fit_measured_gait",
    "measured_prediction",
    "reference_from_table",
    "tracking_target",
    "trial_reference",
    "validate",
]
