"""Measured walking trials, shared by validation and calibration.

* :mod:`.c3d_trial`: a C3D file as a walking trial in walk3d's ground frame;
* :mod:`.events`: gait events from the vertical force, and cycle normalisation;
* :mod:`.descriptors`: V, T and Td of a trial (``walk3d predict --from-trial``);
* :mod:`.trial`: a trial's IK, GRF and ID files (or a C3D file) read together;
* :mod:`.kinematics`: measured joint angles as walk3d coordinates and poses.
"""

from walk3d.trials.c3d_trial import C3dTrial, read_c3d_trial
from walk3d.trials.descriptors import GaitDescriptors, descriptors_from_trial
from walk3d.trials.events import (
    FootEvents,
    detect_contacts,
    detect_foot_events,
    mean_sd,
    normalize_cycles,
    percent_axis,
    stride_periods,
)
from walk3d.trials.kinematics import (
    MeasuredKinematics,
    kinematics_from_storage,
    kinematics_from_table,
)
from walk3d.trials.trial import Trial, load_c3d_trial, load_trial

__all__ = [
    "C3dTrial",
    "FootEvents",
    "GaitDescriptors",
    "MeasuredKinematics",
    "Trial",
    "descriptors_from_trial",
    "detect_contacts",
    "detect_foot_events",
    "kinematics_from_storage",
    "kinematics_from_table",
    "load_c3d_trial",
    "load_trial",
    "mean_sd",
    "normalize_cycles",
    "percent_axis",
    "read_c3d_trial",
    "stride_periods",
]
