"""The crouch check reads the middle third of stance and its threshold tells walking."""

import math

import numpy as np

from walk3d.contact.crouch import HIP_MIDSTANCE_MAX_DEG, midstance_mean, upright
from walk3d.contact.phases import GaitPhases

PHASES = GaitPhases(1.08, 0.16)
"""Stance 0.7 s: mid-stance from 0.2333 to 0.4667 s after heel strike."""


def test_the_mean_is_over_mid_stance_alone():
    since = np.linspace(0.0, 0.7, 71)
    values = np.where((since > 0.235) & (since < 0.465), 10.0, 70.0)
    assert abs(midstance_mean(values, since, PHASES) - 10.0) < 1e-12
    # control: one sample inside the window moves the mean, one outside does not
    inside, outside = values.copy(), values.copy()
    inside[35], outside[5] = 31.0, 0.0
    assert midstance_mean(inside, since, PHASES) > 10.0
    assert midstance_mean(outside, since, PHASES) == midstance_mean(values, since, PHASES)


def test_no_sample_in_mid_stance_is_nan_and_not_upright():
    value = midstance_mean(np.ones(3), np.array([0.0, 0.1, 0.6]), PHASES)
    assert math.isnan(value) and not upright(value)


def test_the_threshold_separates_walking_from_a_crouch():
    assert upright(HIP_MIDSTANCE_MAX_DEG) and upright(5.0)
    assert not upright(HIP_MIDSTANCE_MAX_DEG + 0.1) and not upright(40.0)
