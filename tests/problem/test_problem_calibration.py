"""A calibration (roll-over samples, transition ratios) reaches the body model and the split."""

import json
import subprocess
import sys

import numpy as np
import pytest

from walk3d.body.model import build_body
from walk3d.contact.phases import GaitPhases
from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings, body_for, ratios_for
from walk3d.results import evaluate as ev

KNOTS = (-0.3, -0.1, 0.0, 0.1, 0.3)


def _samples(shift: float):
    ro = build_body().rollover
    pts = np.array([[float(np.squeeze(c)) for c in ro.evaluate(s)[0]] for s in KNOTS])
    pts[:, 0] += shift
    return tuple(map(tuple, pts))


def test_calibrated_rollover_replaces_the_default_one():
    s = PredictionSettings(rollover_s=KNOTS, rollover_ankle=_samples(0.01))
    default, calibrated = build_body().rollover, body_for(s).rollover
    for q in (-0.2, 0.05, 0.25):
        d = np.array([float(np.squeeze(c)) for c in default.evaluate(q)[0]])
        c = np.array([float(np.squeeze(c)) for c in calibrated.evaluate(q)[0]])
        assert c[0] - d[0] == pytest.approx(0.01, abs=2e-3)
    assert body_for(PredictionSettings()).rollover == default


def test_rollover_fields_go_together():
    with pytest.raises(ValueError, match="together"):
        PredictionSettings(rollover_s=KNOTS)


def test_ratios_set_the_trailing_foot_load_at_heel_strike():
    ratios = (0.2, 0.03, 0.1, -0.05)
    s = PredictionSettings(transition_ratios=ratios)
    assert ratios_for(PredictionSettings().model) is None
    rng = np.random.default_rng(0)
    x = rng.uniform(-0.05, 0.05, layout.N_X)
    x[layout.I_HALF_STEP] = 0.08
    ph = GaitPhases(s.gait.period, s.gait.double_support)
    f, m = ev._hs_wrench(build_body(), s, ph, x, ph.heel_strike_r, "r")  # left foot trails
    assert f[0] == pytest.approx(0.2 * f[1]) and f[2] == pytest.approx(-0.03 * f[1])
    assert m[0] == pytest.approx(-0.1 * m[2]) and m[1] == pytest.approx(0.05 * m[2])


def test_cli_rejects_a_malformed_calibration_in_one_line(tmp_path):
    bad = tmp_path / "cal.json"
    bad.write_text(json.dumps({"walk3d_calibration": 1, "rollover": {}}))
    cmd = [sys.executable, "-m", "walk3d.cli", "predict", "--calibration", str(bad),
           "--out", str(tmp_path / "o")]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "cal.json" in lines[0], r.stderr
