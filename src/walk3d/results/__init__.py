"""Prediction results: the :class:`PredictedCycle` container, its result folder and joint
angles."""

from walk3d.results.angles import ball_joint_angles, pelvis_angles, zxy_angles
from walk3d.results.prediction import RESULT_FILES, PredictedCycle, load_result, save_prediction

__all__ = [
    "RESULT_FILES",
    "PredictedCycle",
    "ball_joint_angles",
    "load_result",
    "pelvis_angles",
    "save_prediction",
    "zxy_angles",
]
