"""The fuzz set's own machinery, in the default suite: its plan (500 cases or more, every
mutation of every format), the mutations (deterministic, each changes its file), and the
checks of a case, each shown to fail on what it must catch."""

from __future__ import annotations

import json

import numpy as np
import pytest
from fuzz_binary import npz_bytes
from fuzz_mutations import KINDS, case_rng, mutate
from fuzz_run import CaseTimeout, Outcome, check_outcome, run_cli, time_limit
from test_fuzz_commands import CASES, SEEDS


def test_the_plan_has_500_cases_and_every_mutation():
    assert len(CASES) >= 500
    for fmt in {f for f, _, _ in SEEDS.values()}:
        kinds = {k for _, s, k, _ in CASES if SEEDS[s][0] == fmt}
        assert kinds == set(KINDS[fmt]), fmt


@pytest.fixture(scope="module")
def small_seeds(tmp_path_factory) -> dict[str, bytes]:
    """A small valid file of each format."""
    import fuzz_seeds

    from walk3d.io.storage import write_storage

    root = tmp_path_factory.mktemp("harness")
    t = np.linspace(0.0, 1.0, 21)
    data = np.column_stack([np.sin(6 * t), np.cos(6 * t), t**2])
    mot = write_storage(root / "m.mot", t, ["a", "b", "c"], data).read_bytes()
    arrays = {"time": t, "joint_angle": data, "dof_names": np.array(["a", "b", "c"]),
              "joint_axis_active": np.ones((21, 3), bool)}  # fmt: skip
    return {
        "table": mot,
        "json": json.dumps({"a": 1.5, "b": [1, 2, {"c": "x"}], "d": {"e": 2.0}}).encode(),
        "toml": b"[criterion]\ntor = 1.0\naccel = 0.5\nhead = 2\n",
        "xml": b'<?xml version="1.0" encoding="UTF-8" ?>\n<a>\n<b>1.5</b>\n<c>x</c>\n</a>\n',
        "npz": npz_bytes(arrays),
        "c3d": fuzz_seeds.gait_c3d(root / "walk.c3d").read_bytes(),
    }


@pytest.mark.parametrize(("fmt", "kind"), [(f, k) for f, kinds in KINDS.items() for k in kinds])
def test_each_mutation_is_deterministic_and_changes_the_file(small_seeds, fmt, kind):
    seed = small_seeds[fmt]
    names = [f"harness-{fmt}-{kind}-{i}" for i in range(3)]
    out = [mutate(seed, fmt, kind, case_rng(n)) for n in names]
    assert out == [mutate(seed, fmt, kind, case_rng(n)) for n in names]  # the same each run
    assert any(o != seed for o in out)


def test_an_unknown_mutation_is_refused(small_seeds):
    with pytest.raises(ValueError, match="no mutation"):
        mutate(small_seeds["json"], "json", "time_scale", case_rng("x"))


@pytest.mark.parametrize(
    ("outcome", "allowed"),
    [(Outcome(1, "", "", 0.1), (0, 2)),
     (Outcome(2, "", "Traceback (most recent call last):\nKeyError: 'x'\n", 0.1), (0, 2)),
     (Outcome(2, "", "walk3d: error: a\nwalk3d: error: b\n", 0.1), (0, 2)),
     (Outcome(2, "", "walk3d: error: zero-size array to reduction operation fmax\n", 0.1),
      (0, 2)),
     (Outcome(0, "", "m.py:3: RuntimeWarning: invalid value\n  x = a / b\n", 0.1), (0, 2)),
     (Outcome(2, "", "", 0.1), (0, 2))],
    ids=["exit-1", "traceback", "two-errors", "numpy-words", "python-warning", "no-line"],
)  # fmt: skip
def test_the_outcome_check_fails_on_what_it_must_catch(outcome, allowed):
    with pytest.raises(AssertionError):
        check_outcome(outcome, allowed)


def test_a_refusal_in_one_line_passes_the_check():
    check_outcome(Outcome(2, "", "walk3d: warning: w\nwalk3d: error: a.mot:3: bad\n", 0.1),
                  (0, 2))  # fmt: skip
    check_outcome(Outcome(1, "table\n", "", 0.1), (0, 1, 2))


def test_a_command_exception_reaches_the_test(monkeypatch):
    """A traceback is not taken for an exit code: the exception propagates."""
    import walk3d.body.model

    def broken(*args, **kwargs):
        raise KeyError("broken")

    monkeypatch.setattr(walk3d.body.model, "build_body", broken)
    with pytest.raises(KeyError, match="broken"):
        run_cli(["body"], "harness-body")
    monkeypatch.undo()  # control: the command itself ends in an exit code
    check_outcome(run_cli(["body", "--mass", "nan"], "harness-body"), (2,))


def test_a_case_that_runs_too_long_is_stopped():
    with pytest.raises(CaseTimeout, match="no end after 0.2 s"), time_limit(0.2, "harness"):
        while True:
            pass
