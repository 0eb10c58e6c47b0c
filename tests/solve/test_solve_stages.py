"""Stage solvers are built on first use, once."""

import numpy as np
import pytest

from walk3d.problem import layout, similarity
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import ipopt
from walk3d.solve import solver as solver_mod

SETTINGS = PredictionSettings(nodes=6, max_iter=3, balance_max_iter=3, restarts=0)
"""Few iterations: no stage converges. Without restarts, so one standing start's stages."""


@pytest.mark.solve
def test_stages_are_built_once_on_first_use():
    solver = solver_mod._build.__wrapped__(SETTINGS, "ipopt", False)
    assert solver.stage_build_s == {}  # nothing built yet
    solver.stage("full")
    solver.stage("balance_direct")
    assert set(solver.stage_build_s) == {"nlp:full", "full:3", "nlp:balance", "balance:3"}
    # stages of one NLP and iteration limit share a solver
    assert solver.stage("full") is solver.stage("full_direct")
    assert solver.stage("balance") is solver.stage("balance_direct")
    other = solver_mod._build.__wrapped__(SETTINGS.replace(posture_balance_max_iter=2), "ipopt",
                                          False)  # fmt: skip
    assert other.stage("balance") is not other.stage("balance_direct")  # limits 2 and 3
    assert "nlp:posture" not in solver.stage_build_s
    z0 = ipopt.initial_guess(solver, 0)
    g = np.array(solver.constraints(ipopt.full_stage_start(solver, z0))).ravel()
    assert solver.constraints is solver.constraints  # built once
    assert g.size == solver.bounds.lbg.size


@pytest.mark.solve
def test_a_solve_builds_only_the_stages_it_runs():
    settings = SETTINGS.replace(**{"posture_stage": "off"})
    solver_mod._build.cache_clear()
    outcome = ipopt.solve(settings, seed=0)
    solver = ipopt.build_solver(settings)
    assert [st["stage"] for st in outcome.stages] == ["balance", "full"]
    assert set(solver.stage_build_s) == {"nlp:balance", "balance:3", "nlp:full", "full:3"}


@pytest.mark.solve
def test_progress_reports_every_iteration_of_every_stage():
    settings = SETTINGS.replace(**{"posture_stage": "off"})
    messages: list[str] = []
    outcome = ipopt.solve(settings, seed=0, on_stage=messages.append)
    per_stage = [sum(1 for m in messages if m.startswith(prefix) and ": iteration" in m)
                 for prefix in ("stage 1/2", "stage 2/2")]  # fmt: skip
    # IPOPT reports its starting point (iteration 0) and then every iteration
    assert per_stage == [st["iterations"] + 1 for st in outcome.stages]
    last = [m for m in messages if ": iteration" in m][-1]
    assert len(last) < 72 and last.startswith("stage 2/2 (C_tor): ")
    assert f"iteration {outcome.stages[-1]['iterations']}," in last
    # without a listener the shared callback stays silent (and a solve still works)
    assert all(r._listener is None for r in ipopt.build_solver(settings).reporters.values())


@pytest.mark.solve
def test_the_sqp_method_builds_its_stages_with_casadis_own_derivatives():
    # sqpmethod refuses IPOPT's grad_f / jac_g / hess_lag options (it used to fail here)
    sqp = solver_mod._build.__wrapped__(SETTINGS, "sqp", False)
    for name in ("balance", "full"):
        fn = sqp.stage(name)
        assert fn.class_name() == "Sqpmethod"


@pytest.mark.solve
@pytest.mark.parametrize(
    ("update", "expected"),
    [
        # the balance stage from standing converges, the full stage does not (3 iterations):
        # the solve retries once from standing through the posture stage
        ({"balance_max_iter": 400}, ["balance_direct", "full", "posture", "balance", "full"]),
        # the balance stage from standing fails: posture fallback, and no second retry
        ({"balance_max_iter": 3}, ["balance_direct", "posture", "balance", "full"]),
        # the balance stage from standing is stopped by the progress check: posture fallback
        (
            {"balance_max_iter": 400, "balance_progress_check": (2, 1e-12)},
            ["balance_direct", "posture", "balance", "full"],
        ),
        # of two checks, the one whose violation is exceeded stops it (at iteration 3, not 2)
        (
            {"balance_max_iter": 400, "balance_progress_check": ((2, 1e30), (3, 1e-12))},
            ["balance_direct", "posture", "balance", "full"],
        ),
        ({"posture_stage": "first"}, ["posture", "balance", "full"]),
        # the balance stage after the posture stage stops at its own limit (below max_iter)
        ({"posture_stage": "first", "posture_balance_max_iter": 2}, ["posture", "balance", "full"]),
        ({"posture_stage": "off", "balance_max_iter": 400}, ["balance", "full"]),
        # the full stage stops at its own limit (below max_iter)
        (
            {"posture_stage": "off", "balance_max_iter": 400, "full_max_iter": 2},
            ["balance", "full"],
        ),
    ],
)
def test_stage_sequence_of_the_posture_fallback(update, expected):
    outcome = ipopt.solve(SETTINGS.replace(**update), seed=0)
    assert [st["stage"] for st in outcome.stages] == expected
    if expected[:2] == ["balance_direct", "full"]:  # the retry follows a converged first stage
        assert outcome.stages[0]["status"] in ipopt.IPOPT_SUCCESS
    if update.get("balance_progress_check"):  # stopped right at the check's iteration
        stop_at = PredictionSettings(**update).solver.balance_progress_check[-1][0]
        assert outcome.stages[0]["status"] == "User_Requested_Stop"
        assert outcome.stages[0]["iterations"] == stop_at
    if update.get("full_max_iter"):
        assert outcome.stages[-1]["iterations"] == 2
        assert outcome.stages[-1]["status"] == "Maximum_Iterations_Exceeded"
    if update.get("posture_balance_max_iter"):
        assert outcome.stages[1]["iterations"] == 2
        assert outcome.stages[1]["status"] == "Maximum_Iterations_Exceeded"
    assert not outcome.converged and outcome.status == outcome.stages[-1]["status"]
    assert outcome.iterations == sum(st["iterations"] for st in outcome.stages)


@pytest.mark.solve
def test_a_start_that_did_not_converge_restarts_from_new_standing_starts():
    settings = SETTINGS.replace(**{"posture_stage": "off", "restarts": 2})
    outcome = ipopt.solve(settings, seed=0)
    # a balance stage that did not converge ends its attempt, except on the last one
    assert [(st["stage"], st["attempt"]) for st in outcome.stages] == [
        ("balance", 0), ("balance", 1), ("balance", 2), ("full", 2)
    ]  # fmt: skip
    assert outcome.attempts == 3 and not outcome.converged
    assert outcome.iterations == sum(st["iterations"] for st in outcome.stages)
    # each attempt started elsewhere: its first stage ended elsewhere after as many iterations
    objectives = [st["objective"] for st in outcome.stages if st["stage"] == "balance"]
    assert len(set(objectives)) == 3
    solver = ipopt.build_solver(settings)
    z = [ipopt.initial_guess(solver, 0, k) for k in range(3)]
    # attempt 0 is the seed's own start; restarts draw other noise, reproducibly, and not
    # another seed's start
    assert np.array_equal(z[0], ipopt.initial_guess(solver, 0))
    assert np.array_equal(z[1], ipopt.initial_guess(solver, 0, 1))
    assert not np.allclose(z[0], z[1]) and not np.allclose(z[1], z[2])
    assert not any(np.allclose(z[k], ipopt.initial_guess(solver, 1)) for k in range(3))


@pytest.mark.solve
def test_another_mass_and_stature_are_solved_as_the_reference_subjects_problem(monkeypatch):
    """solve() builds only the reference subject's NLP (shared node functions, cache entry and
    compiled derivatives) and returns the subject's x: the same coefficients, the half step
    width scaled by stature (the similarity itself: tests/problem/test_problem_similarity.py)."""
    subject = SETTINGS.replace(**{"mass": 55.0, "height": 1.6, "speed": 1.2})
    ref, s = similarity.reference_problem(subject)
    built = []
    build = solver_mod.build_solver
    monkeypatch.setattr(ipopt, "build_solver", lambda st, m: built.append(st) or build(st, m))
    a = ipopt.solve(subject, seed=4)
    b = ipopt.solve(ref, seed=4)
    assert built == [ref, ref]
    np.testing.assert_array_equal(a.x, similarity.subject_x(b.x, s))
    assert a.x[layout.I_HALF_STEP] == pytest.approx(b.x[layout.I_HALF_STEP] * 1.6 / 1.77)
    assert a.iterations == b.iterations


@pytest.mark.solve
def test_a_failed_balance_stage_after_the_posture_stage_restarts_at_once():
    settings = SETTINGS.replace(**{"restarts": 1, "posture_balance_max_iter": 2})
    outcome = ipopt.solve(settings, seed=0)
    assert [(st["stage"], st["attempt"]) for st in outcome.stages] == [
        ("balance_direct", 0), ("posture", 0), ("balance", 0),
        ("balance_direct", 1), ("posture", 1), ("balance", 1), ("full", 1),
    ]  # fmt: skip
    assert outcome.stages[2]["status"] == "Maximum_Iterations_Exceeded"
    assert outcome.attempts == 2 and outcome.status == outcome.stages[-1]["status"]
