"""walk3d.solve.landing: T and Td predicted with the free landing, then the handover at them."""

from dataclasses import replace

import numpy as np
import pytest

from walk3d import api
from walk3d.pipeline import with_predicted
from walk3d.problem import layout
from walk3d.solve import landing, starts
from walk3d.solve.ipopt import SolveOutcome

FOUND = {"period": 1.1, "double_support": 0.12}


def _outcome(value: float, converged: bool = True, handover: bool = False, **kw) -> SolveOutcome:
    z = np.full(layout.N_X + 2, value)
    status = "Solve_Succeeded" if converged else "Maximum_Iterations_Exceeded"
    return SolveOutcome(x=z[: layout.N_X] * 2, z=z, converged=converged, status=status,
                        iterations=10, wall_time_s=1.0,
                        stages=[{"start": "atlas", "attempt": 0, "status": status}],
                        max_constraint_violation=value, handover=handover, **kw)  # fmt: skip


@pytest.fixture
def recorded(monkeypatch):
    """The settings each solve was asked for; the handover solve converges unless told not to."""
    calls = {"first": [], "warm": [], "smooth_converges": True}

    def first(settings):
        calls["first"].append(settings)
        return _outcome(1.0, descriptors=dict(FOUND) if settings.gait.free else {})

    def warm(settings, x_ref, method, on_stage, origin, max_iter):
        calls["warm"].append((settings, np.array(x_ref), max_iter))
        return _outcome(3.0, calls["smooth_converges"], handover=settings.model.handover)

    monkeypatch.setattr(starts, "solve_warm", warm)
    calls["run"] = lambda s: landing.solve_with_landing(s, first)
    return calls


def test_predicted_descriptors_come_from_the_free_landing_then_the_handover_at_them(recorded):
    out = recorded["run"](api.settings(1.3, threads=1))
    (free,) = recorded["first"]
    assert not free.model.handover and free.gait.free
    (given, x_ref, limit), = recorded["warm"]  # fmt: skip
    assert given.model.handover and not given.gait.free
    assert (given.gait.period, given.gait.double_support) == (1.1, 0.12)
    assert np.all(x_ref == 1.0) and x_ref.size == layout.N_X  # the free optimum, reference units
    assert limit == landing.LANDING_MAX_ITER
    assert out.converged and out.handover and np.all(out.x == 6.0)
    assert out.descriptors == FOUND and out.iterations == 20
    assert [r["start"] for r in out.stages] == ["atlas", landing.LANDING]
    assert landing.landing_of(out) == "handover"


def test_a_handover_that_does_not_converge_keeps_the_free_landing(recorded):
    recorded["smooth_converges"] = False
    out = recorded["run"](api.settings(1.3, threads=1))
    assert out.converged and not out.handover
    assert np.all(out.x == 2.0) and out.max_constraint_violation == 1.0
    assert out.stages[-1]["status"] == "Maximum_Iterations_Exceeded"
    assert landing.landing_of(out).startswith("free: the handover")


@pytest.mark.parametrize(
    "options",
    [{"period": 1.1, "double_support": 0.12}, {"handover": False}],
    ids=["descriptors given", "free landing"],
)
def test_one_solve_when_nothing_is_predicted_or_no_handover_is_asked(recorded, options):
    settings = api.settings(1.3, threads=1, **options)
    out = recorded["run"](settings)
    assert recorded["first"] == [settings] and not recorded["warm"]
    assert landing.landing_of(out) == "free"  # the fake first solve reports no handover


def test_the_evaluated_settings_take_the_landing_the_cycle_was_solved_with():
    settings = api.settings(1.3, threads=1)
    assert settings.model.handover
    kept = with_predicted(settings, FOUND, handover=False)
    assert not kept.model.handover and kept.gait.period == 1.1
    assert with_predicted(settings, FOUND).model.handover


@pytest.fixture
def one_solve(monkeypatch, recorded):
    """The atlas path: a handover atlas start at 1.3 m/s (reference subject) and a fake
    ``solve_from_atlas`` that records the given settings it was asked to solve."""
    from walk3d.solve import atlas

    start = atlas.AtlasStart(x=np.zeros(layout.N_X), period=1.05, double_support=0.11,
                             speeds=(1.3,), weights=(1.0,), preset="natural",
                             landing="handover")  # fmt: skip
    calls = {"given": [], "converges": True, "start": start}
    monkeypatch.setattr(atlas, "candidates", lambda ref, tries=3: ([calls["start"]], None))

    def from_atlas(settings, seed, method, on_stage):
        calls["given"].append(settings)
        return _outcome(4.0, calls["converges"], handover=settings.model.handover)

    monkeypatch.setattr(starts, "solve_from_atlas", from_atlas)
    calls["run"] = lambda s: landing.solve_with_landing(s, recorded["first_fn"], seed=0)
    recorded["first_fn"] = lambda s: (recorded["first"].append(s),
                                      _outcome(1.0, descriptors=dict(FOUND)))[1]  # fmt: skip
    return calls


def test_with_a_handover_atlas_the_default_is_one_solve_at_the_atlas_t_and_td(one_solve, recorded):
    settings = api.settings(1.3 * np.sqrt(1.6 / 1.77), height=1.6, threads=1)
    out = one_solve["run"](settings)
    (given,) = one_solve["given"]
    k = np.sqrt(1.6 / 1.77)  # the subject's times: the reference subject's × √(h / 1.77 m)
    assert given.model.handover and not given.gait.free
    assert given.gait.period == pytest.approx(1.05 * k)
    assert given.gait.double_support == pytest.approx(0.11 * k)
    assert out.descriptors == pytest.approx({"period": 1.05 * k, "double_support": 0.11 * k})
    assert out.stages[-1]["descriptors_from"] == landing.ATLAS_DESCRIPTORS
    assert not recorded["first"] and not recorded["warm"]  # no free-landing solve


def test_the_two_solves_follow_when_the_atlas_path_fails_or_is_not_asked(one_solve, recorded):
    one_solve["converges"] = False
    out = one_solve["run"](api.settings(1.3, threads=1))
    assert len(one_solve["given"]) == 1 and len(recorded["first"]) == 1  # then the free landing
    assert [r["start"] for r in out.stages] == ["atlas", "atlas", landing.LANDING]
    assert out.descriptors == FOUND and out.converged
    # negative controls: an atlas of free-landing optima only, or descriptors_from = solve
    for start, options in ((replace(one_solve["start"], landing="free"), {}),
                           (one_solve["start"], {"descriptors_from": "solve"})):  # fmt: skip
        one_solve["start"], one_solve["given"], recorded["first"] = start, [], []
        one_solve["run"](api.settings(1.3, threads=1, **options))
        assert not one_solve["given"] and len(recorded["first"]) == 1
