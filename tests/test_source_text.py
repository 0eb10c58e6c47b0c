"""The project speaks of itself as it is: no line of the README, CHANGELOG, docs, benchmarks or
source names a numbered development session (provenance is a version or a commit)."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CHECKED = ("README.md", "CHANGELOG.md", "docs", "benchmarks", "src")
"""What users read: the README, the changelog, docs/, benchmarks/ and the package source."""
SUFFIXES = {".md", ".py", ".json", ".toml", ".txt", ".csv", ".html", ".cfg"}
RUN = re.compile(r"\bsessions?(?:[\s-]+|\s*#\s*)\d+|\bsession-\d+", re.IGNORECASE)
"""'session 23', 'sessions 20-22', 'session-17 preset', 'Session #4'."""


def text_files(root: Path, names=CHECKED) -> list[Path]:
    """The text files named (a file, or every text file below a folder) under ``root``."""
    out = []
    for name in names:
        path = root / name
        if path.is_file():
            out.append(path)
        elif path.is_dir():
            found = (p for p in path.rglob("*") if p.is_file() and p.suffix in SUFFIXES)
            out.extend(p for p in sorted(found) if "runs" not in p.relative_to(root).parts)
    return out


def numbered_sessions(root: Path, names=CHECKED) -> list[str]:
    """``path:line`` of every line that names a numbered development session."""
    hits = []
    for path in text_files(root, names):
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if RUN.search(line):
                hits.append(f"{path.relative_to(root)}:{i}")
    return hits


def test_no_line_names_a_development_session():
    assert numbered_sessions(ROOT) == []


def test_the_check_reads_every_place_users_read():
    files = {p.relative_to(ROOT).parts[0] for p in text_files(ROOT)}
    assert {"README.md", "docs", "benchmarks", "src"} <= files


def test_the_check_finds_a_numbered_session(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "src").mkdir()
    (tmp_path / "README.md").write_text("Fast (session 23).\nthe session-17 preset\n")
    (tmp_path / "docs" / "a.md").write_text("ok\nsessions 20–22 measured\nSession #4\n")
    (tmp_path / "src" / "m.py").write_text('"""Measured in session 9."""\n')
    (tmp_path / "src" / "ok.py").write_text('"""A Dask session; the sessions of a campaign."""\n')
    assert numbered_sessions(tmp_path) == [
        "README.md:1", "README.md:2", "docs/a.md:2", "docs/a.md:3", "src/m.py:1",
    ]  # fmt: skip
