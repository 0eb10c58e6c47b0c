"""Validation against measured walking (paper section 3, Tables 2–3, Figs. 2–7).

* :mod:`.quantities`, :mod:`.reference`, :mod:`.trial`, :mod:`.compare`: Table 2, a prediction
  against a cycle table or trial files, quantity by quantity with explicit sign conventions;
* :mod:`.descriptors`: V, T and Td of a trial (``walk3d predict --from-trial``);
* :mod:`.kinematics`, :mod:`.projection`, :mod:`.measured`, :mod:`.criteria`: the measured gait
  through walk3d's Fourier series and inverse dynamics, and Table 3;
* :mod:`.calibration`, :mod:`.calibrate`: roll-over and transition ratios from a trial;
* :mod:`.figures`, :mod:`.run`: figures and one complete validation run (``walk3d validate``).
"""

from walk3d.validation.calibrate import calibrate_from_trial, load_calibration
from walk3d.validation.calibration import Calibration, apply_calibration
from walk3d.validation.compare import Comparison, align_prediction, compare
from walk3d.validation.descriptors import GaitDescriptors, descriptors_from_trial
from walk3d.validation.measured import GaitFit, fit_measured_gait, measured_prediction
from walk3d.validation.reference import Reference, reference_from_table
from walk3d.validation.run import Validation, validate
from walk3d.validation.trial import load_trial, trial_reference

__all__ = [
    "Calibration",
    "Comparison",
    "GaitDescriptors",
    "GaitFit",
    "Reference",
    "Validation",
    "align_prediction",
    "apply_calibration",
    "calibrate_from_trial",
    "compare",
    "descriptors_from_trial",
    "fit_measured_gait",
    "load_calibration",
    "load_trial",
    "measured_prediction",
    "reference_from_table",
    "trial_reference",
    "validate",
]
