"""walk3d fit-criterion's search: parameters on a log scale, the CMA-ES loop, its resume and
its outputs. The predictions are scripted: a score that is least at a known weight."""

import contextlib
import json
import math

import pytest

from walk3d.api import criterion_value
from walk3d.fitting import run as run_module
from walk3d.fitting import search
from walk3d.fitting.evaluate import evaluation_key
from walk3d.fitting.search import FitMismatch, criterion_of, parameter
from walk3d.fitting.trials import FitTrial
from walk3d.io.atomic import atomic_write_text
from walk3d.model import terms

TARGET = {"impact": 1.7, "arms": 0.3}
TRIALS = [FitTrial(name=n, speed=1.3, period=1.1, double_support=0.12, reference=["x.csv"])
          for n in ("a", "b", "c")]  # fmt: skip
CALLS: list[tuple[str, str]] = []


def scripted(trial_data, criterion, mode, records_dir, *, seed=0, solver="ipopt"):
    """A record whose score is the squared log distance of the weights from TARGET."""
    CALLS.append((criterion, trial_data["name"]))
    w = terms.parse(criterion)
    s = sum(math.log(w.get(k, 1e-9) / v) ** 2 for k, v in TARGET.items())
    record = {"criterion": criterion, "trial": trial_data["name"], "mode": mode, "score": s}
    path = f"{records_dir}/{evaluation_key(criterion, trial_data['name'], mode)}.json"
    atomic_write_text(path, json.dumps(record))
    return record


@pytest.fixture
def in_process(monkeypatch):
    """Evaluations in threads of this process, scripted."""
    from distributed import Client, LocalCluster

    @contextlib.contextmanager
    def client(workers, scheduler, pending):
        with (LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                           dashboard_address=":0") as cluster, Client(cluster) as c):  # fmt: skip
            yield c

    import walk3d.campaign.runner as runner

    monkeypatch.setattr(runner, "dask_client", client)
    monkeypatch.setattr(search, "evaluate", scripted)
    CALLS.clear()


def test_parameter_log_scale_round_trip():
    p = parameter("impact", "natural")
    assert (p.low, p.start, p.high) == pytest.approx((0.5, 5.0, 50.0))
    assert p.to_unit(p.start) == pytest.approx(0.5)
    assert p.from_unit(p.to_unit(3.3)) == pytest.approx(3.3)
    assert p.from_unit(2.0) == pytest.approx(p.high)  # clipped to the range
    q = parameter("effort=0.01:3", "natural")  # not in the preset: starts at 1
    assert (q.low, q.start, q.high) == (0.01, 1.0, 3.0)


@pytest.mark.parametrize("text, words", [
    ("nosuchterm", "not a criterion term"), ("tor", "scale"), ("impact=5:1", "low"),
    ("impact=6:9", "start (5)"), ("impact=a:b", "low:high"), ("impact=0.5:1_0", "low:high"),
    ("impact=0.5:１0", "low:high"), ("impact=0.5:2:3", "low:high"), ("impact=", "low:high"),
])  # fmt: skip
def test_parameter_refused(text, words):
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        parameter(text, "natural")


def test_criterion_of_changes_only_the_fitted_weights():
    params = [parameter("impact", "natural")]
    c = criterion_of("natural", params, [1.0])
    want = terms.parse("natural") | {"impact": 50.0}
    assert terms.parse(c) == pytest.approx(want)
    assert c == terms.canonical(c)  # canonical: the evaluation's cache key is stable


def test_fit_moves_towards_the_best_weights_and_resumes(tmp_path, in_process):
    params = [parameter("impact", "natural"), parameter("arms", "natural")]
    out = tmp_path / "fit"
    res = run_module.fit_criterion(TRIALS, params, out, generations=4, popsize=4, held_out=["c"])
    assert res.best_score < res.start_score
    best = terms.parse(res.best)
    start_error = sum(math.log(terms.parse(res.start)[k] / v) ** 2 for k, v in TARGET.items())
    assert sum(math.log(best[k] / v) ** 2 for k, v in TARGET.items()) < start_error
    assert set(res.per_trial["best"]) == {"a/given", "b/given", "c/given"}
    assert res.held_out == ("c",)
    # held-out c is solved for the start and the best only, never for a candidate
    assert {c for c, t in CALLS if t == "c"} == {res.start, res.best}
    assert len({c for c, t in CALLS if t == "a"}) > 2  # the candidates
    rows = (out / "fit.csv").read_text().splitlines()
    assert len(rows) == 1 + 4 * 4
    weights = terms.parse(criterion_value(str(out / "criterion.toml")))
    assert weights == pytest.approx(best)

    solved = len(CALLS)
    again = run_module.fit_criterion(TRIALS, params, out, generations=4, popsize=4,
                                     held_out=["c"])  # fmt: skip
    assert len(CALLS) == solved  # every record reused: nothing solved again
    assert again.best == res.best
    more = run_module.fit_criterion(TRIALS, params, out, generations=5, popsize=4,
                                    held_out=["c"])  # fmt: skip
    assert len(CALLS) > solved and more.best_score <= res.best_score


def test_fit_folder_of_another_fit_is_refused(tmp_path, in_process):
    params = [parameter("impact", "natural")]
    out = tmp_path / "fit"
    run_module.fit_criterion(TRIALS[:1], params, out, generations=1, popsize=2)
    with pytest.raises(FitMismatch, match="parameters"):
        run_module.fit_criterion(TRIALS[:1], [parameter("arms", "natural")], out,
                                 generations=1, popsize=2)  # fmt: skip
    other = tmp_path / "other"
    other.mkdir()
    (other / "mine.txt").write_text("keep")
    with pytest.raises(FitMismatch, match="other files"):
        run_module.fit_criterion(TRIALS[:1], params, other, generations=1, popsize=2)
    assert (other / "mine.txt").read_text() == "keep"


@pytest.mark.parametrize("kwargs, words", [
    ({"held_out": ["zz"]}, "not a trial"), ({"held_out": ["a", "b", "c"]}, "every trial"),
    ({"modes": ("sometimes",)}, "descriptors"), ({"generations": 0}, "generations"),
])  # fmt: skip
def test_bad_arguments_before_any_solve(tmp_path, in_process, kwargs, words):
    with pytest.raises(ValueError, match=words):
        run_module.fit_criterion(TRIALS, [parameter("impact", "natural")], tmp_path / "f",
                                 **kwargs)  # fmt: skip
    assert CALLS == [] and not (tmp_path / "f").exists()
