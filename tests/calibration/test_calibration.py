"""Calibration: file round trip, malformed files, body update, Falisse trial fit (Figs. 2–3)."""

import json

import numpy as np
import pytest
from helpers import sample_calibration

from walk3d.body.model import build_body
from walk3d.calibration.calibrate import calibrate_from_trial, load_calibration
from walk3d.calibration.fit import apply_calibration
from walk3d.io import DataFileError, read_calibration, write_calibration


def test_calibration_file_round_trip(tmp_path):
    cal = sample_calibration()
    path = write_calibration(tmp_path / "sub" / "cal.json", cal.to_dict())
    back = load_calibration(path)
    assert back == cal
    s = np.linspace(cal.rollover_s[0], cal.rollover_s[-1], 13)
    np.testing.assert_array_equal(
        np.column_stack(back.rollover().evaluate(s)[0]),
        np.column_stack(cal.rollover().evaluate(s)[0]),
    )


def test_apply_calibration_changes_only_the_rollover():
    body = build_body(62.0, 1.70, "female")
    cal = sample_calibration()
    new = apply_calibration(body, cal)
    assert new.rollover == cal.rollover() and body.rollover != new.rollover
    assert new.segments == body.segments and new.joints == body.joints


@pytest.mark.parametrize(
    "edit,message,line",
    [
        (lambda d: d["transition"].pop("mu_z"), "transition.mu_z", True),
        (lambda d: d["rollover"]["s"].reverse(), "strictly increasing", True),
        (lambda d: d["rollover"]["ankle_m"].pop(), "number triples", True),
        (lambda d: d.update(walk3d_calibration=7), "version 1", True),
        (lambda d: d["rollover"]["ankle_m"][0].__setitem__(0, 1e9), "more than 1 m", True),
        (lambda d: d["rollover"]["ankle_m"][2].__setitem__(1, 5.0), "more than 1 m", True),
        (lambda d: d["transition"].update(mu_x=-0.2), "mu_x' must be in", True),
        (lambda d: d["transition"].update(mu_x=40.0), "mu_x' must be in", True),
        (lambda d: d["rollover"].update(s=[0.1, 0.2, 0.3, 0.4, 0.5]), "flat foot", True),
    ],
)
def test_malformed_calibration_names_file_and_line(tmp_path, edit, message, line):
    data = sample_calibration().to_dict()
    edit(data)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data, indent=2))
    with pytest.raises(DataFileError, match=message) as info:
        read_calibration(path)
    assert str(info.value).startswith("bad.json:" if line else "bad.json")
    assert info.value.line is not None


BAD_FILES = [
    (lambda d: d["rollover"]["ankle_m"][0].__setitem__(0, 1e9), "more than 1 m"),
    (lambda d: d["rollover"]["ankle_m"][2].__setitem__(1, 5.0), "more than 1 m"),
    (lambda d: d["transition"].update(mu_x=-0.2), "mu_x' must be in"),
    (lambda d: d["transition"].update(mu_x=40.0), "mu_x' must be in"),
    (lambda d: d["transition"].update(varpi_y=1e300), "varpi_y' must be in"),
    (
        lambda d: d["rollover"].update(s=[0.1 * (i + 1) for i in range(len(d["rollover"]["s"]))]),
        "flat foot",
    ),
    (lambda d: d["rollover"]["s"].reverse(), "strictly increasing"),
]


def _as_settings(d: dict) -> dict:
    """The settings fields ``walk3d predict --calibration`` makes of a calibration dict."""
    tr = d["transition"]
    return {
        "rollover_s": tuple(d["rollover"]["s"]),
        "rollover_ankle": tuple(tuple(p) for p in d["rollover"]["ankle_m"]),
        "transition_ratios": tuple(tr[k] for k in ("mu_x", "mu_z", "varpi_x", "varpi_y")),
    }


@pytest.mark.parametrize("edit,message", BAD_FILES)
def test_the_api_refuses_what_the_file_reader_refuses(edit, message):
    """``ModelSettings`` runs the calibration file's value checks (one validator), before any
    solve; the file's own values (the control) pass."""
    from walk3d.model.settings import ModelSettings

    data = sample_calibration().to_dict()
    ModelSettings(**_as_settings(data))
    edit(data)
    with pytest.raises(ValueError, match=message):
        ModelSettings(**_as_settings(data))


def test_calibration_that_is_not_json(tmp_path):
    path = tmp_path / "cal.json"
    path.write_text('{"walk3d_calibration": 1,\n "rollover": [1, 2,\n')
    with pytest.raises(DataFileError, match=r"^cal\.json:3: invalid JSON"):
        read_calibration(path)


def test_falisse_calibration(falisse, tmp_path):
    body = build_body(62.0, 1.70, "female")
    result = calibrate_from_trial(falisse / "gait_1_ik.mot", falisse / "gait_1_grf.mot", body,
                                  tmp_path / "falisse.json")  # fmt: skip
    cal = result.calibration
    assert load_calibration(result.path) == cal
    assert [p.name for p in result.figures] == ["falisse_rollover.png", "falisse_transition.png"]
    q = cal.quality["rollover"]
    assert q["stances"] == 2 and q["rms_m"] < 0.015 and q["flat_drift_m"] < 0.03
    lo, hi = q["theta_range_deg"]
    assert lo < -50 and hi > 15  # push-off plantarflexion to heel-strike dorsiflexion
    ro = cal.rollover()
    flat = np.column_stack(ro.evaluate(np.array([0.0]))[0])[0]
    assert flat == pytest.approx([0.0, body.foot.ankle_height, 0.0], abs=0.01)
    # trailing foot in double support: forward shear on it, fits within a fraction of body weight
    r = cal.ratios
    assert 0.1 < r.mu_x < 0.5 and abs(r.mu_z) < 0.1
    rmse = result.transition.rmse
    assert rmse["Fy"] < 1.5 and rmse["Mz"] < 0.3  # N/kg, N m/kg (peaks ~9 and ~1.4)
    assert rmse["Fx"] <= result.transition.rmse_heel_strike_ratios["Fx"] + 1e-12
