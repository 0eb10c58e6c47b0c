"""A converged but crouched optimum is recognised from the nodes and relabelled for a retry."""

from types import SimpleNamespace

import numpy as np

from walk3d.contact.phases import GaitPhases
from walk3d.problem import layout
from walk3d.problem.schedule import schedule
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import upright
from walk3d.solve.ipopt import _reject_crouch
from walk3d.solve.plan import SUCCESS

PHASES = GaitPhases(1.08, 0.16)
"""The settings' default gait (mid-stance: nodes 9–17 of 20)."""
TAU = np.arange(20) * 1.08 / 40
"""Its 20 regular nodes' times since the right heel strike, s."""


def _z(hip_deg: np.ndarray) -> tuple[np.ndarray, layout.NlpLayout]:
    lay = layout.NlpLayout(nodes=len(hip_deg))
    z = np.zeros(lay.n_z)
    y = np.zeros((lay.nodes, layout.N_Y))
    y[:, upright.HIP_FLEXION_COORD] = np.sin(np.radians(hip_deg) / 2)
    y[:, upright.HIP_FLEXION_COORD + 1] = 0.3  # the knee: not read
    z[lay.z("y")] = y.ravel()
    return z, lay


def _stance(heel_strike_deg: float, mid_deg: float) -> np.ndarray:
    """20 nodes: ``heel_strike_deg`` at nodes 0–3, ``mid_deg`` at 9–17, 70° elsewhere."""
    hip = np.full(20, 70.0)
    hip[:4], hip[9:18] = heel_strike_deg, mid_deg
    return hip


def test_midstance_hip_flexion_is_read_at_the_middle_third_of_stance():
    z, lay = _z(_stance(50.0, 12.0))
    assert abs(upright.midstance_hip_flexion_deg(z, lay, TAU, PHASES) - 12.0) < 1e-9
    # control: one node inside the window moves the mean by its share
    hip = _stance(50.0, 12.0)
    hip[13] = 21.0
    z, lay = _z(hip)
    assert abs(upright.midstance_hip_flexion_deg(z, lay, TAU, PHASES) - 13.0) < 1e-9


def test_a_crouched_optimum_is_relabelled_only_when_the_check_is_on():
    z, lay = _z(_stance(55.0, 62.0))
    notes = []
    for on in (True, False):
        settings = PredictionSettings(reject_crouch=on)
        solver = SimpleNamespace(settings=settings, layout=lay, schedule=schedule(settings))
        record = {"status": "Solve_Succeeded"}
        _reject_crouch(solver, z, record, notes.append)
        assert (record["status"] in SUCCESS) is (not on)
    assert record == {"status": "Solve_Succeeded"}
    assert len(notes) == 1 and "crouched" in notes[0] and "62" in notes[0]


def test_a_long_stride_is_not_relabelled():
    """Hip flexed 50° at heel strike, 15° in mid-stance: walking (control: 40° is crouched)."""
    notes = []
    for mid, crouched in ((15.0, False), (40.0, True)):
        z, lay = _z(_stance(50.0, mid))
        record = {"status": "Solve_Succeeded"}
        solver = SimpleNamespace(settings=PredictionSettings(), layout=lay,
                                 schedule=schedule(PredictionSettings()))  # fmt: skip
        _reject_crouch(solver, z, record, notes.append)
        assert (record["status"] == upright.CROUCHED) is crouched


def test_the_free_grid_window_follows_the_solved_period_and_double_support():
    """With T and Td predicted the nodes follow them (4 of 20 intervals in double support), so
    mid-stance is nodes 8–16 at T 1.0 s, Td 0.148 s, not the regular grid's 9–17; control:
    the same hips read on the regular grid give another mean."""
    from walk3d.problem import descriptors

    period, ds = 1.0, 0.148
    tau = np.array(descriptors.free_grid(20).tau(period, ds), dtype=float)
    hip = np.full(20, 70.0)
    hip[8:17] = 10.0
    z, lay = _z(hip)
    phases = GaitPhases(period, ds)
    assert abs(upright.midstance_hip_flexion_deg(z, lay, tau, phases) - 10.0) < 1e-9
    regular = np.arange(20) * period / 40
    assert upright.midstance_hip_flexion_deg(z, lay, regular, phases) > 15.0
