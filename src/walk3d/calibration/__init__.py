"""Calibration from a measured trial: the stance-foot roll-over and the transition ratios.

* :mod:`.fit`: the fits themselves and :func:`apply_calibration` (a body with the calibrated
  roll-over);
* :mod:`.calibrate`: ``walk3d calibrate``, a trial into a calibration file and its figures;
* :mod:`.figures`, :mod:`.tables`: Figs. 2–3 and the command line's table.

The calibration file format (``calib.json``) is :mod:`walk3d.io.calibration`.
"""

from walk3d.calibration.calibrate import CalibrationResult, calibrate_from_trial, load_calibration
from walk3d.calibration.fit import Calibration, apply_calibration

__all__ = [
    "Calibration",
    "CalibrationResult",
    "apply_calibration",
    "calibrate_from_trial",
    "load_calibration",
]
