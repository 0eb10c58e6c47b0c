"""inverse_dynamics.sto: walk3d's joint moments as model.osim's generalized forces, which are
power-conjugate to the coordinates: Σ τ_i q̇_i = M · ω for every joint."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from walk3d.body.model import JOINT_NAMES, build_body
from walk3d.io.storage import read_storage
from walk3d.results.inverse_dynamics import generalized_forces, write_inverse_dynamics
from walk3d.results.osim_model import osim_model

N = 7
H = 1e-6


def _rot(axis, angle):
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def _joint_rotation(model_joint, q):
    r = np.eye(3)
    for c, v in zip(model_joint.rotations, q, strict=False):
        r = r @ _rot(np.asarray(c.axis), v)
    return r


@pytest.fixture(scope="module")
def case():
    body = build_body()
    rng = np.random.default_rng(3)
    angle = rng.uniform(-0.6, 0.6, (N, 24))
    rate = rng.normal(size=(N, 24))
    moment_vec = rng.normal(size=(N, 12, 3)) * 30  # parent frame, N m
    slots = np.einsum("njk,jlk->njl", moment_vec, np.array([j.axes for j in body.joints]))
    for j, joint in enumerate(body.joints):  # hinges and ankles: slot z about the hinge axis
        if joint.kind != "ball":
            slots[:, j, 2] = moment_vec[:, j] @ joint.axis
    pred = SimpleNamespace(
        n_nodes=N, time=np.arange(N) * 0.01, dof_names=body.dof_names, joint_names=JOINT_NAMES,
        joint_angle=angle, joint_moment=slots,
    )  # fmt: skip
    return body, pred, rate, moment_vec


def _power_mismatch(body, pred, rate, moment_vec, tau_of):
    model = {j.name: j for j in osim_model(body).joints}
    from walk3d.results.osim_model import JOINT_NAMES as OSIM_JOINTS

    worst, i = 0.0, 0
    for j, joint in enumerate(body.joints):
        if joint.kind != "ball":
            i += joint.n_dof
            continue
        mj = model[OSIM_JOINTS[joint.name]]
        order = (2, 0, 1)  # model order flexion, adduction, rotation in slots (x, y, z)
        for n in range(N):
            q = pred.joint_angle[n, i : i + 3][list(order)]
            qd = rate[n, i : i + 3][list(order)]
            r0, r1 = _joint_rotation(mj, q - H * qd), _joint_rotation(mj, q + H * qd)
            w = (r1 - r0) / (2 * H) @ _joint_rotation(mj, q).T
            omega = np.array([w[2, 1], w[0, 2], w[1, 0]])
            tau = tau_of(n, i)[list(order)]
            worst = max(worst, abs(tau @ qd - moment_vec[n, j] @ omega))
        i += 3
    return worst


def test_ball_joint_forces_are_power_conjugate_to_the_coordinates(case):
    body, pred, rate, moment_vec = case
    _, data = generalized_forces(pred, body)
    mismatch = _power_mismatch(body, pred, rate, moment_vec, lambda n, i: data[n, 6 + i : 9 + i])
    assert mismatch < 1e-6
    # negative control: walk3d's own slots (moments on the parent's axes) are not
    raw = _power_mismatch(
        body, pred, rate, moment_vec, lambda n, i: pred.joint_moment.reshape(N, -1)[n, i : i + 3]
    )
    assert raw > 1.0


def test_labels_pelvis_and_hinges(case, tmp_path):
    body, pred, _, _ = case
    labels, data = generalized_forces(pred, body)
    assert labels[:6] == ("pelvis_tilt_moment", "pelvis_list_moment", "pelvis_rotation_moment",
                          "pelvis_tx_force", "pelvis_ty_force", "pelvis_tz_force")  # fmt: skip
    assert "knee_angle_r_moment" in labels and "neck_flexion_moment" in labels
    assert np.all(data[:, :6] == 0.0)
    k = labels.index("knee_angle_l_moment")
    assert np.array_equal(data[:, k], pred.joint_moment[:, JOINT_NAMES.index("knee_l"), 2])
    sto = read_storage(write_inverse_dynamics(tmp_path / "id.sto", pred, body))
    assert sto.columns == labels and np.array_equal(sto.data, data) and not sto.in_degrees
