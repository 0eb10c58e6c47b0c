"""C3D files as validation references: lab axes, plates to feet, Plug-in Gait angles, cycles."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from c3d_support import write_c3d
from validation_support import cli_env

from walk3d.io import DataFileError
from walk3d.results.prediction import save_prediction
from walk3d.trials.c3d_trial import read_c3d_trial
from walk3d.trials.trial import load_c3d_trial
from walk3d.validation.reference import trial_reference
from walk3d.validation.run import sort_references, validate

pytest.importorskip("ezc3d")

PERIOD, STANCE, SPEED = 1.1, 0.62 * 1.1, 1.3
MASS, G = 70.0, 9.81
POINT_RATE, ANALOG_RATE, DURATION = 100.0, 1000.0, 2.6
STRIKES = {"R": (0.1, 1.2, 2.3), "L": (-0.45, 0.65, 1.75)}
PLATE_X = {"R": -350.0, "L": 350.0}  # mm; the lab is Z up and the walker faces -Y: right is -X


def _phase(t: np.ndarray, side: str) -> np.ndarray:
    """Time since the side's last heel strike (s), NaN before the first."""
    out = np.full(t.shape, np.nan)
    for hs in STRIKES[side]:
        out[t >= hs] = t[t >= hs] - hs
    return out


def _knee(s: np.ndarray) -> np.ndarray:
    """Knee flexion (deg): 5 at heel strike, 60 at mid-cycle."""
    return 32.5 - 27.5 * np.cos(2 * np.pi * s / PERIOD)


def _plate(side: str) -> np.ndarray:
    """Channels of the side's plate: the foot's action on it (plate frame = lab frame)."""
    t = np.arange(int(DURATION * ANALOG_RATE)) / ANALOG_RATE
    s = _phase(t, side)
    on = np.isfinite(s) & (s < STANCE)
    u = np.where(on, np.nan_to_num(s) / STANCE, 0.0)
    peak = MASS * G * np.pi / (4 * 0.62)  # half-sines averaging half the weight per foot
    vertical = np.where(on, peak * np.sin(np.pi * u), 0.0)
    fore_aft = np.where(on, -0.2 * MASS * G * np.sin(2 * np.pi * u), 0.0)  # brake, then push
    cop_forward = -100.0 + 250.0 * u  # mm from the plate centre, heel to toe
    ch = np.zeros((t.size, 6))
    ch[:, 1] = fore_aft  # reaction fore_aft * (0, -1, 0); the action is its negative
    ch[:, 2] = -vertical
    ch[:, 3] = -cop_forward * ch[:, 2]  # Mx = CoP_y * Fz with CoP_y = -cop_forward
    return ch


def _write_gait(path: Path, markers: str = "all", idle_plate: bool = False) -> Path:
    """The synthetic gait; ``markers``: ``all``, ``pelvis`` (no foot markers) or ``none``;
    ``idle_plate`` adds a third plate nobody steps on."""
    t = np.arange(int(DURATION * POINT_RATE)) / POINT_RATE
    y_pelvis = 500.0 - 1000.0 * SPEED * t
    labels, points = [], []

    def add(label, x, y, z):
        labels.append(label)
        points.append(np.column_stack(np.broadcast_arrays(x, y, z)))

    for name, dx, dy in (("LASI", 120, -60), ("RASI", -120, -60), ("LPSI", 50, 90),
                         ("RPSI", -50, 90)):  # fmt: skip
        if markers != "none":
            add(name, dx, y_pelvis + dy, 950.0)
    for side in "RL":
        if markers == "all":
            add(f"{side}HEE", PLATE_X[side], y_pelvis + 100.0, 50.0)
            add(f"{side}TOE", PLATE_X[side], y_pelvis - 150.0, 30.0)
        s = _phase(t, side)
        s = np.where(np.isfinite(s), s, t - STRIKES[side][0] + PERIOD)  # before the 1st strike
        add(f"Subj:{side}HipAngles", 20 * np.cos(2 * np.pi * s / PERIOD), 0.0, 0.0)
        add(f"Subj:{side}KneeAngles", _knee(s), 0.0, 0.0)
        add(f"Subj:{side}AnkleAngles", 10 * np.sin(2 * np.pi * s / PERIOD), 0.0, 0.0)
    base = np.array([[300, 200, 0], [-300, 200, 0], [-300, -200, 0], [300, -200, 0]], float)
    corners = [base + [PLATE_X[s], 0.0, 0.0] for s in "RL"]
    plates = [_plate("R"), _plate("L")]
    if idle_plate:
        corners.append(base + [0.0, 2000.0, 0.0])
        plates.append(np.zeros_like(plates[0]))
    return write_c3d(path, point_rate=POINT_RATE, labels=labels, points=np.stack(points, 1),
                     analog_rate=ANALOG_RATE, plates=plates, corners=corners)  # fmt: skip


@pytest.fixture(scope="module")
def gait_c3d(tmp_path_factory) -> Path:
    return _write_gait(tmp_path_factory.mktemp("c3d") / "walk_01.c3d")


def test_lab_axes_and_ground_reactions(gait_c3d):
    trial = read_c3d_trial(gait_c3d)
    np.testing.assert_array_equal(trial.axes.forward, [0, -1, 0])
    np.testing.assert_array_equal(trial.axes.up, [0, 0, 1])
    np.testing.assert_array_equal(trial.axes.right, [-1, 0, 0])
    assert trial.axes.reaction_sign == -1.0 and "heel-to-toe" in trial.axes.method
    grf = trial.grf
    fy = grf.column("ground_force_1_vy") + grf.column("ground_force_2_vy")
    assert np.mean(fy) == pytest.approx(MASS * G, rel=0.02)  # body weight, upward
    loaded = grf.column("ground_force_1_vy") > 50
    assert np.all(grf.column("ground_force_1_pz")[loaded] == pytest.approx(0.35, abs=1e-6))
    ik = trial.ik
    assert ik is not None and ik.in_degrees is True
    assert {"knee_angle_r", "hip_flexion_l", "ankle_angle_r", "pelvis_tx"} <= set(ik.columns)
    assert np.max(ik.column("knee_angle_r")) == pytest.approx(60.0, abs=0.1)  # degrees, not mm


@pytest.mark.parametrize(
    ("markers", "forward", "method"),
    [("pelvis", None, "marker progression"), ("none", None, "centre-of-pressure motion"),
     ("none", "-Y", "given")],
)  # fmt: skip
def test_walking_direction_without_foot_markers(tmp_path, markers, forward, method):
    axes = read_c3d_trial(_write_gait(tmp_path / "w.c3d", markers), forward=forward).axes
    np.testing.assert_array_equal(axes.matrix, [[0, -1, 0], [0, 0, 1], [-1, 0, 0]])
    assert method in axes.method


def test_c3d_reference_cycles(gait_c3d):
    trial = load_c3d_trial(gait_c3d)
    d = trial.descriptors
    assert d.period_method == "strides" and d.period == pytest.approx(PERIOD, abs=2e-3)
    assert d.speed == pytest.approx(SPEED, rel=1e-3)
    np.testing.assert_allclose(d.events["right"].heel_strikes, STRIKES["R"], atol=0.02)
    ref = trial_reference([trial], MASS)
    assert ref.n_cycles["angle:knee_flexion"] == 3 and ref.n_cycles["grf:grf_vertical"] == 3
    body_weight = 2.0 * np.mean(ref.mean["grf:grf_vertical"][:-1]) * MASS
    assert body_weight == pytest.approx(MASS * G, rel=0.02)
    knee = ref.mean["angle:knee_flexion"]
    assert int(np.argmax(knee)) == pytest.approx(50, abs=2)
    assert knee.max() == pytest.approx(60.0, abs=0.5) and knee[0] == pytest.approx(5.0, abs=1.0)
    assert ref.mean["angle:hip_flexion"][0] == pytest.approx(20.0, abs=1.0)
    fore_aft = ref.mean["grf:grf_fore_aft"]
    assert fore_aft[15] < -1.0 and fore_aft[45] > 1.0  # braking, then propulsion
    assert "angle:subtalar_inversion" not in ref.mean and "moment:knee_flexion" not in ref.mean
    assert "knee sign +1" in ref.notes


def test_idle_plate_is_left_out(tmp_path):
    trial = load_c3d_trial(_write_gait(tmp_path / "w.c3d", idle_plate=True))
    assert "w.c3d: plate(s) 3 never loaded, left out" in trial.notes
    assert trial.loads.right.force[:, 1].max() > 500.0 < trial.loads.left.force[:, 1].max()


def test_validate_accepts_c3d(gait_c3d, synthetic_prediction, tmp_path):
    tables, trials = sort_references([gait_c3d])
    assert tables == [] and trials == [{"c3d": gait_c3d}]
    v = validate({"p": synthetic_prediction}, [gait_c3d], tmp_path, figures=False)
    assert v.reference.name == "walk_01" and (tmp_path / "table2.csv").is_file()
    rows = {r["quantity"]: r for r in v.table2 if r["group"] == "angle"}
    assert rows["knee_flexion"]["n_cycles"] == 3
    assert rows["pelvis_tilt"]["status"] == "missing in reference"


def test_malformed_c3d(gait_c3d, synthetic_prediction, tmp_path):
    cut = tmp_path / "cut.c3d"
    cut.write_bytes(gait_c3d.read_bytes()[:20000])
    with pytest.raises(DataFileError, match=r"^cut\.c3d: "):
        load_c3d_trial(cut)
    pred = save_prediction(synthetic_prediction, tmp_path / "pred")
    for ref, extra, start in ((cut, [], "cut.c3d: "), (gait_c3d, ["--forward", "up"], "forward")):
        cmd = [sys.executable, "-m", "walk3d.cli", "validate", str(pred), "--reference", str(ref)]
        r = subprocess.run(cmd + extra, capture_output=True, text=True, timeout=120, env=cli_env())
        assert r.returncode == 2, r.stdout + r.stderr
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith(f"walk3d: error: {start}"), r.stderr
