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
    """Control: the same folders, undamaged, give the audit."""
    folder = _damaged(good, tmp_path, lambda s: None)
    code, _, err = cli(capsys, "audit", folder, good, "--out", tmp_path / "audit.json")
    assert code == 0 and err == "", err
    assert "terms" in json.loads((tmp_path / "audit.json").read_text(encoding="utf-8"))
