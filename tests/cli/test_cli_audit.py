"""``walk3d audit`` on result folders whose summary cannot be evaluated again: one line naming
summary.json and exit 2 (they were tracebacks, found by the fuzz set), with an undamaged
folder as the control."""

from __future__ import annotations

import json
import shutil

import pytest
from helpers import cli, one_line_error, replace_result_file
from result_support import result_folder


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    return result_folder(tmp_path_factory.mktemp("audit") / "pred")


def _damaged(good, tmp_path, change) -> object:
    folder = shutil.copytree(good, tmp_path / "pred")
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    data = change(summary)
    replace_result_file(folder, "summary.json", data if isinstance(data, bytes) else
                        json.dumps(summary).encode())  # fmt: skip
    return folder


DAMAGE = {
    "no coefficients": lambda s: s.pop("coefficients"),
    "coefficients a list": lambda s: s.update(coefficients=[1, 2]),
    "x of words": lambda s: s["coefficients"].update(x=["x"] * 166),
    "x too short": lambda s: s["coefficients"].update(x=s["coefficients"]["x"][:-1]),
    "x not finite": lambda s: s["coefficients"]["x"].__setitem__(3, float("nan")),
    "x overflows": lambda s: s["coefficients"]["x"].__setitem__(3, 10**400),
    "speed a word": lambda s: s["settings"]["gait"].update(speed="fast"),
    "period negative": lambda s: s["settings"]["gait"].update(period=-1.0),
    "settings a list": lambda s: s.update(settings=[]),
    "deep": lambda s: b'{"a": ' + b"[" * 100_000 + b"]" * 100_000 + b"}",
    "an array": lambda s: b"[1, 2]",
}


@pytest.mark.parametrize("damage", sorted(DAMAGE))
@pytest.mark.parametrize("role", ["tracked", "predicted"])
def test_a_summary_that_cannot_be_evaluated_is_one_line(good, tmp_path, capsys, damage, role):
    bad = _damaged(good, tmp_path, DAMAGE[damage])
    pair = (bad, good) if role == "tracked" else (good, bad)
    result = cli(capsys, "audit", *pair, "--out", tmp_path / "audit.json")
    one_line_error(result, "summary.json")
    assert not (tmp_path / "audit.json").exists()


def test_an_undamaged_pair_is_audited(good, tmp_path, capsys):
    """Control: the same folders, undamaged, give the audit (a prediction as TRACKED: with its
    one warning line)."""
    folder = _damaged(good, tmp_path, lambda s: None)
    code, _, err = cli(capsys, "audit", folder, good, "--out", tmp_path / "audit.json")
    assert code == 0 and err == PREDICTION_WARNING.format(folder=folder), err
    assert "terms" in json.loads((tmp_path / "audit.json").read_text(encoding="utf-8"))


PREDICTION_WARNING = ("walk3d: warning: TRACKED {folder} is a prediction, not a tracking (walk3d "
                      "track): the audit compares two predicted gaits, its 'tracked' columns are "
                      "{folder}'s\n")  # fmt: skip

EARLIER = '{"criterion": "natural", "terms": [], "limb_work": {}, "bursts": {}}'
"""An earlier audit as walk3d knows one (:data:`walk3d.results.audit.AUDIT_KEYS`)."""


def _audit_reached(monkeypatch) -> None:
    import walk3d.tracking as tracking

    def audit(*args, **kwargs):
        raise ValueError("the audit started")

    monkeypatch.setattr(tracking, "audit", audit)


OUTS = {
    "TRACKED's summary": ("t/summary.json", "is inside the walk3d result folder"),
    "TRACKED's manifest": ("t/manifest.json", "is inside the walk3d result folder"),
    "a new file in TRACKED": ("t/other.json", "is inside the walk3d result folder"),
    "PREDICTED's new file": ("p/audit.json", "is inside the walk3d result folder"),
    "a user's json": ("user.json", "exists and is not a walk3d audit"),
    "a read-only user's json": ("readonly.json", "exists and is not a walk3d audit"),
}  # fmt: skip


def _pair(good, tmp_path):
    tracked = shutil.copytree(good, tmp_path / "t")
    predicted = shutil.copytree(good, tmp_path / "p")
    (tmp_path / "user.json").write_text('{"mine": 1}')
    (tmp_path / "readonly.json").write_text('{"mine": 2}')
    (tmp_path / "readonly.json").chmod(0o444)  # replaced all the same when run as root
    return tracked, predicted


def _snapshot(folder) -> dict:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


@pytest.mark.parametrize("case", OUTS)
def test_audit_refuses_an_out_walk3d_must_not_replace(good, tmp_path, capsys, monkeypatch, case):
    """--out replaced a result folder's summary.json or manifest.json, or any user's .json."""
    _audit_reached(monkeypatch)
    tracked, predicted = _pair(good, tmp_path)
    name, words = OUTS[case]
    before = _snapshot(tmp_path)
    one_line_error(cli(capsys, "audit", tracked, predicted, "--out", tmp_path / name),
                   f"--out {tmp_path / name}", words)  # fmt: skip
    assert _snapshot(tmp_path) == before


@pytest.mark.parametrize("name", ["new.json", "earlier.json", "t/audit.json"])
def test_audit_takes_a_new_file_an_earlier_audit_or_its_default(good, tmp_path, capsys,
                                                                monkeypatch, name):  # fmt: skip
    """Negative control: each reaches the audit."""
    _audit_reached(monkeypatch)
    tracked, predicted = _pair(good, tmp_path)
    (tmp_path / "earlier.json").write_text(EARLIER)
    (tracked / "audit.json").write_text(EARLIER)  # TRACKED's own earlier audit
    one_line_error(cli(capsys, "audit", tracked, predicted, "--out", tmp_path / name),
                   "the audit started")  # fmt: skip


@pytest.mark.parametrize("given", [False, True], ids=["default", "named"])
def test_the_default_audit_is_recorded_in_trackeds_manifest(good, tmp_path, capsys, given):
    """TRACKED/audit.json, by default or named, is listed in TRACKED's manifest, so that
    predict --out TRACKED still takes the folder."""
    from walk3d.results.prediction import check_result_folder

    tracked, predicted = _pair(good, tmp_path)
    out = ["--out", tracked / "audit.json"] if given else []
    code, _, err = cli(capsys, "audit", tracked, predicted, *out)
    assert code == 0 and err == PREDICTION_WARNING.format(folder=tracked), err
    manifest = json.loads((tracked / "manifest.json").read_text(encoding="utf-8"))
    assert manifest["files"]["audit.json"] == (tracked / "audit.json").stat().st_size
    check_result_folder(tracked)


def test_a_tracking_is_known_from_its_settings(good, tmp_path):
    """The warning's test: a summary whose settings follow a measured gait is a tracking (the
    control: the prediction is not; an unreadable summary is not)."""
    from walk3d.results.audit import is_tracking

    (tmp_path / "summary.json").write_text(
        json.dumps({"settings": {"gait": {}, "model": {"tracking": {"dofs": []}}, "solver": {}}})
    )
    assert is_tracking(tmp_path)
    assert not is_tracking(good)
    assert not is_tracking(tmp_path / "missing")


def test_an_out_in_a_missing_folder_is_made(good, tmp_path, capsys):
    """--out nodir/aud.json passed the check, ran the audit, then could not be written (exit
    3): its folders are made, as calibrate, report and animate make theirs. Control: a parent
    that is a file is still refused (exit 2) before the audit."""
    out = tmp_path / "nodir" / "sub" / "aud.json"
    code, _, err = cli(capsys, "audit", good, good, "--out", out)
    assert code == 0, err
    assert "terms" in json.loads(out.read_text(encoding="utf-8"))
    (tmp_path / "file").write_text("x")
    one_line_error(cli(capsys, "audit", good, good, "--out", tmp_path / "file" / "aud.json"),
                   "cannot be created", "is a file")  # fmt: skip
