"""A treadmill trial whose IK and ID hold no whole cycle (OpenSim's subject01: 1.20 s of IK,
T = 1.224 s) is read as periodic, so validate compares its angles and moments; a shorter IK
is not (the negative control)."""

from dataclasses import replace

from walk3d.trials.trial import load_trial
from walk3d.validation.reference import periodic_storage, trial_reference


def _trial(folder):
    return load_trial(folder / "subject01_walk1_ik.mot", folder / "subject01_walk1_grf.mot",
                      folder / "inverse_dynamics.sto", speed=1.12)  # fmt: skip


def test_periodic_ik_and_id_give_angles_and_moments(subject01):
    ref = trial_reference([_trial(subject01)], 72.6)
    for key in ("angle:knee_flexion", "angle:hip_flexion", "moment:knee_flexion"):
        assert ref.has(key), key
    assert any("no complete cycle in the IK" in n for n in ref.notes)
    knee = ref.mean["angle:knee_flexion"]
    assert 50 < knee.max() < 80 and knee.min() < 10  # a walking knee, flexion positive


def test_an_ik_much_shorter_than_a_cycle_stays_missing(subject01):
    trial = _trial(subject01)
    ik = trial.ik
    keep = ik.time <= ik.time[0] + 0.9
    short = replace(ik, time=ik.time[keep], data=ik.data[keep])
    ref = trial_reference([replace(trial, ik=short)], 72.6)
    assert not ref.has("angle:knee_flexion")
    assert ref.has("grf:grf_vertical")


def test_periodic_storage_repeats_outside_its_span(subject01):
    ik = _trial(subject01).ik
    p = periodic_storage(ik, 1.224)
    assert p.time[0] < ik.time[0] and p.time[-1] > ik.time[-1]
    inside = (p.time >= ik.time[0]) & (p.time <= ik.time[-1])
    assert (p.data[inside] == ik.data).all()
