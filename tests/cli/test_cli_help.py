"""``walk3d --help`` lists each command on one line (its short help); each command's own
``--help`` keeps its whole description."""

import os
import subprocess
import sys

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
    for words in ("Exit code 0 if the solve converged", "130 on Ctrl-C",
                  "V, T and Td come from the trial unless"):  # fmt: skip
        assert words in text, text[:2000]
