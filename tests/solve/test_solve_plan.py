"""The solve plan and its restart and fallback policy, on scripted stage outcomes (no IPOPT)."""

import pytest

from walk3d.problem.settings import SolverSettings
from walk3d.solve.plan import END, Plan, Stage, default_plan, run_plan

OK, FAILED = "Solve_Succeeded", "Maximum_Iterations_Exceeded"


def _scripted(plan: Plan, restarts: int, statuses: list[str]):
    """Run ``plan`` with stage outcomes taken from ``statuses`` in order; every status must be
    used. Returns the result, the (stage, attempt) sequence and the notes."""
    script = iter(statuses)
    notes: list[str] = []

    def run(stage: Stage, attempt: int) -> dict:
        return {"stage": stage.name, "status": next(script)}

    result = run_plan(plan, restarts, run, notes.append)
    assert next(script, None) is None, "the plan ran fewer stages than scripted"
    return result, [(r["stage"], r["attempt"]) for r in result.records], notes


FALLBACK = default_plan(SolverSettings())


@pytest.mark.parametrize(
    ("statuses", "expected"),
    [
        ([OK, OK], [("balance_direct", 0), ("full", 0)]),
        # the balance stage from standing fails: posture fallback, then balance and full
        (
            [FAILED, OK, OK, OK],
            [("balance_direct", 0), ("posture", 0), ("balance", 0), ("full", 0)],
        ),  # fmt: skip
        # the full stage after it fails: one retry through the posture stage
        (
            [OK, FAILED, OK, OK, OK],
            [("balance_direct", 0), ("full", 0), ("posture", 0), ("balance", 0), ("full", 0)],
        ),  # fmt: skip
        # a balance stage after the posture stage that fails ends the attempt (restart left)
        (
            [OK, FAILED, OK, FAILED, OK, OK],
            [
                ("balance_direct", 0),
                ("full", 0),
                ("posture", 0),
                ("balance", 0),
                ("balance_direct", 1),
                ("full", 1),
            ],
        ),  # fmt: skip
        # on the last attempt the full stage runs after a failed balance stage anyway
        (
            [FAILED, OK, FAILED, FAILED, OK, FAILED, OK],
            [
                ("balance_direct", 0),
                ("posture", 0),
                ("balance", 0),
                ("balance_direct", 1),
                ("posture", 1),
                ("balance", 1),
                ("full", 1),
            ],
        ),  # fmt: skip
    ],
)
def test_fallback_plan_sequences(statuses, expected):
    result, seq, _ = _scripted(FALLBACK, 1, statuses)
    assert seq == expected
    assert result.converged == (statuses[-1] == OK)
    assert result.attempts == (2 if ("balance_direct", 1) in expected else 1)


def test_the_policy_says_why_it_retries_or_restarts():
    _, _, notes = _scripted(FALLBACK, 1, [OK, FAILED, OK, FAILED, OK, OK])
    assert notes == [
        "the full stage did not converge: retrying from standing through the posture stage",
        "the balance stage did not converge: restarting instead of the full stage",
        "not converged: restarting from a new standing start (2 of 2)",
    ]
    _, _, last = _scripted(FALLBACK, 0, [FAILED, OK, FAILED, FAILED])
    assert last == []  # the last attempt's failed balance stage just goes on


def test_a_full_stage_that_fails_twice_ends_the_attempt_and_restarts():
    result, seq, _ = _scripted(FALLBACK, 1, [OK, FAILED, OK, OK, FAILED, OK, OK])
    assert seq[-2:] == [("balance_direct", 1), ("full", 1)]
    assert result.converged and result.attempts == 2
    result, _, _ = _scripted(FALLBACK, 0, [OK, FAILED, OK, OK, FAILED])
    assert not result.converged and result.attempts == 1  # no restart left


@pytest.mark.parametrize(
    ("mode", "statuses", "expected"),
    [
        ("first", [FAILED, OK, OK], ["posture", "balance", "full"]),
        # a failed balance stage after the posture stage ends the attempt while a restart is left
        ("first", [OK, FAILED, OK, OK, OK], ["posture", "balance", "posture", "balance", "full"]),
        ("off", [OK, OK], ["balance", "full"]),
        ("off", [FAILED, OK, OK], ["balance", "balance", "full"]),  # restart, then walks
    ],
)
def test_other_posture_modes(mode, statuses, expected):
    plan = default_plan(SolverSettings(posture_stage=mode))
    _, seq, _ = _scripted(plan, 1, statuses)
    assert [name for name, _ in seq] == expected


def test_stage_limits_starts_and_checks_come_from_the_settings():
    s = SolverSettings(max_iter=300, balance_max_iter=500, posture_balance_max_iter=350,
                       full_max_iter=120, balance_progress_check=((7, 2.0),))  # fmt: skip
    plan = default_plan(s, "en")
    limits = {st.key: st.max_iter for st in plan.stages}
    # the direct balance stage's own limit may exceed max_iter; the others are capped by it
    assert limits == {"balance_direct": 500, "full_direct": 120, "posture": 300,
                      "balance": 300, "full": 120}  # fmt: skip
    assert [st.start for st in plan.stages] == ["standing", "criterion", "standing", "previous",
                                                "criterion"]  # fmt: skip
    direct = plan["balance_direct"]
    assert direct.checks == ((7, 2.0),) and not plan["balance"].checks
    assert direct.stops(7, 2.5) and not direct.stops(7, 1.5) and not direct.stops(6, 9.0)
    assert plan["full"].title == "stage 2/2: minimizing C_en"


def test_a_plan_refuses_unknown_successors_and_repeated_keys():
    st = default_plan(SolverSettings(posture_stage="off")).stages
    with pytest.raises(ValueError, match="unknown stage 'posture'"):
        Plan((st[0], Stage(key="full", name="full", problem="full", start="criterion",
                           max_iter=5, on_failure="posture", title="", label="")))  # fmt: skip
    with pytest.raises(ValueError, match="unique"):
        Plan((st[0], st[1], st[1]))
    assert Plan(st).next(st[1], True, True) == END
    with pytest.raises(KeyError, match="unknown stage"):
        Plan(st)["walking"]


def test_progress_messages_of_the_default_plan():
    titles = {st.key: (st.title, st.label) for st in FALLBACK.stages}
    balance = "stage 1/2: balance (walking posture, total reaction under the feet)"
    assert titles == {
        "balance_direct": (balance, "stage 1/2 (balance)"),
        "full_direct": ("stage 2/2: minimizing C_tor", "stage 2/2 (C_tor)"),
        "posture": ("stage 0: walking posture (geometry only)", "stage 0 (posture)"),
        "balance": ("stage 1/2: balance, from the walking posture", "stage 1/2 (balance)"),
        "full": ("stage 2/2: minimizing C_tor", "stage 2/2 (C_tor)"),
    }
