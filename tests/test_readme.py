"""The README's first screen (its first 40 lines) holds the two commands, what the first one
prints, and a Python example of at most five lines."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"
SCREEN = 40
"""Lines a newcomer sees before scrolling."""
COMMANDS = ("pip install . && walk3d predict --out", "pip install '.[test]' && python -m pytest")


def first_screen_problems(text: str) -> list[str]:
    """What the first screen of README ``text`` lacks (empty when it has everything)."""
    screen = "\n".join(text.splitlines()[:SCREEN])
    blocks = dict.fromkeys(("bash", "text", "python"), "")
    for lang, body in reversed(re.findall(r"```(\w+)\n(.*?)```", screen, re.DOTALL)):
        blocks[lang] = body  # the first block of each language
    problems = [f"command {c!r}" for c in COMMANDS if c not in blocks["bash"]]
    if "converged" not in blocks["text"]:
        problems.append("what the first command prints")
    code = [line for line in blocks["python"].splitlines() if line.strip()]
    if not code or len(code) > 5 or "walk3d.predict(" not in blocks["python"]:
        problems.append("a Python example of at most five lines")
    return problems


def test_the_first_screen_holds_the_commands_their_output_and_a_python_example():
    assert first_screen_problems(README.read_text(encoding="utf-8")) == []


def test_the_check_fails_when_the_example_falls_below_the_first_screen():
    text = README.read_text(encoding="utf-8")
    pushed = "\n" * SCREEN + text
    assert len(first_screen_problems(pushed)) == 4
    no_output = re.sub(r"```text\n.*?```", "", text, count=1, flags=re.DOTALL)
    assert first_screen_problems(no_output) == ["what the first command prints"]
