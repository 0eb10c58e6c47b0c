"""An IK and a GRF whose times overlap only where no plate cycle is: the reference had no
angles, and validate warned that "the reference lacks" them and scored huge RMSEs. It is
refused in one line naming the heel strikes and the IK's time span."""

from dataclasses import replace

import pytest

from walk3d.trials.trial import load_trial
from walk3d.validation.reference import trial_reference


def test_cycles_outside_the_ik_are_refused(falisse):
    trial = load_trial(falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot")
    ik = trial.ik
    last = max(float(ev.heel_strikes.max()) for ev in trial.descriptors.events.values())
    after = replace(ik, time=ik.time - ik.time[0] + last + 2 * trial.descriptors.period)
    with pytest.raises(ValueError, match=r"heel strikes .* fall outside its IK's .*no gait cycle"):
        trial_reference([replace(trial, ik=after)], 62.0)
    assert trial_reference([trial], 62.0).has("angle:knee_flexion")  # control: the same files
