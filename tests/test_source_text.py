"""The source says what is: measurement history (numbered sessions) lives in docs/solver.md."""

import re
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "walk3d"
RUN = re.compile(r"\bsessions? \d+|\bsession\s*\d+\b", re.IGNORECASE)


def numbered_runs(root: Path) -> list[str]:
    """``path:line`` of every source line under ``root`` that names a numbered session."""
    hits = []
    for path in sorted(root.rglob("*.py")):
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if RUN.search(line):
                hits.append(f"{path.relative_to(root)}:{i}")
    return hits


def test_no_source_line_names_a_numbered_measurement_run():
    assert numbered_runs(SRC) == []


def test_the_check_finds_a_numbered_run(tmp_path):
    (tmp_path / "m.py").write_text('"""Measured in session 9 (docs)."""\nX = 1  # Session 12\n')
    (tmp_path / "ok.py").write_text('"""A session of the solver, seed-independent."""\n')
    assert numbered_runs(tmp_path) == ["m.py:1", "m.py:2"]
