"""A converged but crouched optimum is recognised from the nodes and relabelled for a retry."""

from types import SimpleNamespace

import numpy as np

from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import upright
from walk3d.solve.ipopt import _reject_crouch
from walk3d.solve.plan import SUCCESS

RATIO = 0.16 / 1.08
"""Td/T of the settings' default gait (mid-stance: nodes 9–17 of 20)."""


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
    assert abs(upright.midstance_hip_flexion_deg(z, lay, RATIO) - 12.0) < 1e-9
    # control: one node inside the window moves the mean by its share
    hip = _stance(50.0, 12.0)
    hip[13] = 21.0
    z, lay = _z(hip)
    assert abs(upright.midstance_hip_flexion_deg(z, lay, RATIO) - 13.0) < 1e-9


def test_extra_heel_strike_nodes_do_not_shift_the_window():
    fr = upright.node_fractions(23, 20)
    assert len(fr) == 23 and np.all(np.diff(fr) > 0)
    assert np.allclose(fr[[0, 4, 5]], [0.0, 1 / 40, 2 / 40])


def test_a_crouched_optimum_is_relabelled_only_when_the_check_is_on():
    z, lay = _z(_stance(55.0, 62.0))
    notes = []
    for on in (True, False):
        solver = SimpleNamespace(settings=PredictionSettings(reject_crouch=on), layout=lay)
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
        _reject_crouch(SimpleNamespace(settings=PredictionSettings(), layout=lay), z, record,
                       notes.append)  # fmt: skip
        assert (record["status"] == upright.CROUCHED) is crouched
