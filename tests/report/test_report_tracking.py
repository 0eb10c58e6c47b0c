"""The report's tracking sections (``tracking.csv``, ``binding.csv``, ``audit.json``): a damaged
file is a note on the page, not a traceback (found by the fuzz set), and a readable one is
shown (the control)."""

from __future__ import annotations

import json

import pytest
from helpers import cli

from walk3d.results.prediction import record_file

TRACKING = "quantity,unit,rmse,max_abs\nknee_flexion_r,deg,4.2,9.9\n"
BINDING = "kind,name,multiplier,nodes\nbound,knee_flexion_r,0.41,3-7\n"
AUDIT = {"criterion": "tor=1", "terms": [], "limb_work": {"tracked": {}, "predicted": {}},
         "bursts": {"tracked": {}, "predicted": {}}, "C_weighted tracked": 1.0,
         "C_weighted predicted": 2.0}  # fmt: skip
DAMAGED = {
    "tracking.csv": "quantity,unit,rmse,max_abs\nknee," + "1" * 200_000 + ",4,5\n",
    "binding.csv": "kind,name,multiplier,nodes\nbound," + "x" * 200_000 + ",0.4,3\n",
    "audit.json": '{"terms": ' + "[" * 100_000 + "]" * 100_000 + "}",
    "audit.json ": json.dumps(AUDIT | {"limb_work": {"tracked": [5], "predicted": [1]}}),
}


def _page(folder, capsys, files: dict[str, str]) -> str:
    for name, text in files.items():
        (folder / name.strip()).write_text(text, encoding="utf-8")
        record_file(folder, name.strip())
    code, _, err = cli(capsys, "report", folder)
    assert code == 0 and "Traceback" not in err, err
    return (folder / "report.html").read_text(encoding="utf-8")


@pytest.mark.parametrize("damaged", sorted(DAMAGED))
def test_a_damaged_tracking_file_is_a_note(fresh_folder, capsys, damaged):
    files = {"tracking.csv": TRACKING, "binding.csv": BINDING, "audit.json": json.dumps(AUDIT)}
    page = _page(fresh_folder, capsys, files | {damaged: DAMAGED[damaged]})
    assert "the tracking files could not be read" in page


def test_readable_tracking_files_are_shown(fresh_folder, capsys):
    files = {"tracking.csv": TRACKING, "binding.csv": BINDING, "audit.json": json.dumps(AUDIT)}
    page = _page(fresh_folder, capsys, files)
    assert "could not be read" not in page and "Cost audit" in page and "0.41" in page
