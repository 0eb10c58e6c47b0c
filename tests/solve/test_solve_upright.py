"""A converged but crouched optimum is recognised from the nodes and relabelled for a retry."""

from types import SimpleNamespace

import numpy as np

from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import upright
from walk3d.solve.ipopt import _reject_crouch
from walk3d.solve.plan import SUCCESS


def _z(hip_deg: np.ndarray) -> tuple[np.ndarray, layout.NlpLayout]:
    lay = layout.NlpLayout(nodes=len(hip_deg))
    z = np.zeros(lay.n_z)
    y = np.zeros((lay.nodes, layout.N_Y))
    y[:, upright.HIP_FLEXION_COORD] = np.sin(np.radians(hip_deg) / 2)
    y[:, upright.HIP_FLEXION_COORD + 1] = 0.3  # the knee: not read
    z[lay.z("y")] = y.ravel()
    return z, lay


def test_stance_hip_flexion_is_read_at_the_nodes():
    z, lay = _z(np.array([30.0, 38.0, 12.0, -10.0]))
    assert abs(upright.stance_hip_flexion_deg(z, lay) - 38.0) < 1e-9
    assert not upright.crouched(z, lay)
    z, lay = _z(np.array([30.0, 58.0, 40.0, 5.0]))
    assert upright.crouched(z, lay)


def test_a_crouched_optimum_is_relabelled_only_when_the_check_is_on():
    z, lay = _z(np.array([50.0, 62.0, 55.0, 40.0]))
    notes = []
    for on in (True, False):
        solver = SimpleNamespace(settings=PredictionSettings(reject_crouch=on), layout=lay)
        record = {"status": "Solve_Succeeded"}
        _reject_crouch(solver, z, record, notes.append)
        assert (record["status"] in SUCCESS) is (not on)
    assert record == {"status": "Solve_Succeeded"}
    assert len(notes) == 1 and "crouched" in notes[0] and "62" in notes[0]
    walking, lay = _z(np.array([30.0, 35.0, 10.0, -15.0]))
    record = {"status": "Solve_Succeeded"}
    _reject_crouch(SimpleNamespace(settings=PredictionSettings(), layout=lay), walking, record,
                   notes.append)  # fmt: skip
    assert record["status"] == "Solve_Succeeded"
