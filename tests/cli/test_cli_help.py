"""``walk3d --help`` lists each command on one line (its short help); each command's own
``--help`` keeps its whole description."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import typer

from walk3d.cli import app


def _help(*args: str, columns: int = 80) -> str:
    env = os.environ | {"COLUMNS": str(columns), "TERMINAL_WIDTH": str(columns)}
    r = subprocess.run([sys.executable, "-m", "walk3d.cli", *args, "--help"], capture_output=True,
                       text=True, timeout=60, env=env)  # fmt: skip
    assert r.returncode == 0, r.stderr
    return r.stdout


def _commands_panel(text: str) -> list[str]:
    """The rows of the help's Commands panel, without its frame."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if "─ Commands ─" in line)
    end = next(i for i in range(start + 1, len(lines)) if lines[i].lstrip().startswith("╰"))
    return [line.strip().strip("│").strip() for line in lines[start + 1 : end]]


def _names(*path: str) -> list[str]:
    group = typer.main.get_command(app)
    for name in path:
        group = group.commands[name]
    return sorted(group.commands)


@pytest.mark.parametrize("group", [(), ("atlas",)])
@pytest.mark.parametrize("columns", [80, 120])
def test_the_command_list_is_one_line_per_command(group, columns):
    """The whole first paragraph of each docstring made it about 80 lines."""
    rows = _commands_panel(_help(*group, columns=columns))
    assert sorted(row.split()[0] for row in rows) == _names(*group), "\n".join(rows)


def test_a_command_help_keeps_its_long_description():
    """Negative control: walk3d predict --help still says all its docstring."""
    text = " ".join(_help("predict", columns=100).replace("│", " ").split())
    for words in ("Exit codes: 0 the solve converged", "130 Ctrl-C",
                  "V, T and Td come from the trial unless"):  # fmt: skip
        assert words in text, text[:2000]


PREDICT_CODES = {0, 1, 2, 3, 4, 130, 143}
"""walk3d predict's exit codes (docs/usage.md, Exit codes)."""


def _listed_codes(text: str) -> set[int]:
    """The codes of the ``Exit codes: N what; N what; ...`` sentence of a help text."""
    found = re.search(r"Exit codes: (.*?)\. ", text)
    return {int(c) for c in re.findall(r"(?:^|; )(\d+) ", found.group(1))} if found else set()


def test_predict_help_lists_every_exit_code_of_the_usage_doc():
    """It left out 4 (converged, not walking) and 143 (SIGTERM), which the docs list."""
    text = " ".join(_help("predict", columns=100).replace("│", " ").split())
    assert _listed_codes(text) == PREDICT_CODES, text[:3000]
    usage = (Path(__file__).parents[2] / "docs" / "usage.md").read_text(encoding="utf-8")
    section = usage.split("## Exit codes", 1)[1].split("\n## ", 1)[0]
    assert PREDICT_CODES <= {int(c) for c in re.findall(r"(\d+):\s", section)}
    short = "Exit codes: 0 done; 1 not converged; 2 bad input; 3 not written; 130 Ctrl-C. More"
    assert _listed_codes(short) == {0, 1, 2, 3, 130}  # negative control: a list without 4, 143
