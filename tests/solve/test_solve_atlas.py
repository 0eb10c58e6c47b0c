"""The atlas of starts: lookup and blending, refusal of a stale atlas, the shipped files against
the current model, and the fallback to standing."""

import json
import time
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from walk3d.campaign.atlas import ENTRY_TOLERANCE, atlas_settings, fingerprint, violation
from walk3d.problem import layout
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import SOLVE_REVISION, atlas, starts
from walk3d.solve.landing import LANDING, LANDING_MAX_ITER
from walk3d.solve.plan import SUCCESS


def _write(root, speeds, revision=SOLVE_REVISION, sex="male", preset="natural", settings=None):
    settings = settings or atlas.settings_key(atlas_settings(sex, preset))
    entries = [{"speed": v, "period": 1.0 + v, "double_support": 0.1 * v,
                "x": [float(k) * v for k in range(layout.N_X)]} for v in speeds]  # fmt: skip
    data = {"format": atlas.FORMAT, "sex": sex, "preset": preset, "solve_revision": revision,
            "settings": settings, "entries": entries}  # fmt: skip
    atlas.atlas_path(sex, preset, root).write_text(json.dumps(data))


def _ref(speed, **kw):
    return atlas_settings("male", "natural").replace(speed=speed, **kw)


def test_a_start_blends_the_two_bracketing_speeds(tmp_path):
    _write(tmp_path, [1.0, 1.2, 1.4])
    start, why = atlas.start_for(_ref(1.25), tmp_path)
    assert why is None and start.speeds == (1.2, 1.4)
    assert start.weights == pytest.approx((0.75, 0.25))
    assert start.period == pytest.approx(1.0 + 1.25)
    assert start.double_support == pytest.approx(0.125)
    assert start.x[3] == pytest.approx(3 * 1.25)
    exact, _ = atlas.start_for(_ref(1.2), tmp_path)
    assert exact.speeds == (1.2,) and exact.x[3] == pytest.approx(3.6)


def test_candidates_are_the_blend_then_single_entries_by_distance(tmp_path):
    _write(tmp_path, [1.0, 1.2, 1.4, 1.6])
    found, _ = atlas.candidates(_ref(1.25), tmp_path, tries=4)
    assert [c.speeds for c in found] == [(1.2, 1.4), (1.2,), (1.4,), (1.0,)]
    assert [c.speeds for c in atlas.candidates(_ref(1.2), tmp_path)[0]] == [(1.2,), (1.0,), (1.4,)]


def test_outside_the_atlas_the_nearest_entry_serves_until_too_far(tmp_path):
    _write(tmp_path, [1.0, 1.2])
    near, _ = atlas.start_for(_ref(0.8), tmp_path)
    assert near.speeds == (1.0,)
    far, why = atlas.start_for(_ref(1.2 + atlas.MAX_EXTRAPOLATION + 0.05), tmp_path)
    assert far is None and "outside" in why


def test_a_stale_or_foreign_atlas_is_not_used(tmp_path):
    _write(tmp_path, [1.0, 1.2], revision=SOLVE_REVISION - 1)
    start, why = atlas.start_for(_ref(1.1), tmp_path)
    assert start is None and "rebuild" in why
    other = atlas.settings_key(atlas_settings("male", "natural").replace(nodes=12))
    _write(tmp_path, [1.0, 1.2], settings=other)
    start, why = atlas.start_for(_ref(1.1), tmp_path)
    assert start is None and "other model or grid" in why
    _write(tmp_path, [1.0, 1.2])  # negative control: the same file, current revision and settings
    assert atlas.start_for(_ref(1.1), tmp_path)[0] is not None
    assert atlas.start_for(_ref(1.1, sex="female"), tmp_path)[0] is None  # no file
    # another criterion starts from the default preset's atlas, not from another model's
    start, _ = atlas.start_for(_ref(1.1, criterion="tor=1,accel=0.3"), tmp_path)
    assert start.preset == "natural"
    assert atlas.start_for(_ref(1.1, criterion="tor", friction=0.6), tmp_path)[0] is None


def test_an_atlas_of_another_file_format_is_refused_with_the_reason(tmp_path):
    _write(tmp_path, [1.0, 1.2])
    path = atlas.atlas_path("male", "natural", tmp_path)
    data = json.loads(path.read_text())
    data["format"] = atlas.FORMAT - 1
    path.write_text(json.dumps(data))
    start, why = atlas.start_for(_ref(1.1), tmp_path)
    assert start is None and "format" in why and "rebuild" in why
    data["format"] = atlas.FORMAT  # negative control: the current format is used
    path.write_text(json.dumps(data))
    assert atlas.start_for(_ref(1.1), tmp_path)[0] is not None


def test_noise_is_off_for_seed_0_and_bounded_otherwise():
    assert not atlas_noise_any(0)
    n = starts.atlas_noise(3, 0.02)
    assert 0 < np.abs(n).max() <= 0.02 * starts.ATLAS_NOISE_FRACTION
    assert not n[layout.fixed_zero_mask()].any() and n[layout.I_HALF_STEP] == 0.0
    assert np.array_equal(n, starts.atlas_noise(3, 0.02))
    assert not np.array_equal(n, starts.atlas_noise(4, 0.02))


def atlas_noise_any(seed):
    return bool(starts.atlas_noise(seed, 0.05).any())


@pytest.mark.model
@pytest.mark.parametrize("sex", ["male", "female"])
def test_the_shipped_atlas_matches_the_model_and_solver(sex):
    """The default preset's atlas exists for both sexes, was made by this solve revision for
    these settings, and the current NLP gives its recorded objective and constraint norm at its
    recorded start: a change of the model or the criterion fails here until `walk3d atlas
    build` is run again."""
    a = atlas.load_atlas(sex, "natural")
    assert a is not None, f"no atlas for {sex}: run `walk3d atlas build`"
    settings = atlas_settings(sex, "natural")
    assert a.solve_revision == SOLVE_REVISION
    assert a.settings == atlas.settings_key(settings)
    assert a.speeds[0] <= 0.8 and a.speeds[-1] >= 1.8 and np.all(np.diff(a.speeds) <= 0.21)
    fp = a.fingerprint
    i = int(np.argmin(np.abs(a.speeds - fp["speed"])))
    entry = {"speed": fp["speed"], "period": float(a.periods[i]),
             "double_support": float(a.double_supports[i]), "x": a.x[i]}  # fmt: skip
    now = fingerprint(settings, entry)
    assert now["objective"] == pytest.approx(fp["objective"], rel=1e-7)
    assert now["constraint_norm"] == pytest.approx(fp["constraint_norm"], rel=1e-7, abs=1e-9)
    # negative control: another model (the other sex's segments) gives another fingerprint
    other = fingerprint(atlas_settings("female" if sex == "male" else "male", "natural"), entry)
    assert other["objective"] != pytest.approx(fp["objective"], rel=1e-4)


@pytest.mark.solve
def test_an_atlas_entry_is_the_optimum_of_its_problem(monkeypatch):
    """At an entry's own speed the start is its problem's optimum: every shipped entry was
    checked when written (``write_atlas``), one is checked here. Negative control: on a grid
    with one double-support interval more, the same entry violates the node rows."""
    from walk3d.problem import descriptors
    from walk3d.solve.solver import forget_solvers

    a = atlas.load_atlas("male", "natural")
    settings = atlas_settings("male", "natural")
    i = int(np.argmin(np.abs(a.speeds - 1.4)))
    entry = {"speed": float(a.speeds[i]), "period": float(a.periods[i]),
             "double_support": float(a.double_supports[i]), "x": a.x[i]}  # fmt: skip
    try:
        assert violation(settings, entry) <= ENTRY_TOLERANCE
        forget_solvers()
        n_ds = descriptors.ds_intervals(settings.solver.nodes)
        monkeypatch.setattr(descriptors, "ds_intervals", lambda nodes: n_ds + 1)
        assert violation(settings, entry) > 0.01
    finally:
        forget_solvers()  # no solver of the patched grid stays cached for later tests


@pytest.mark.solve
def test_an_entry_handover_optimum_is_feasible_for_the_handover_problem():
    """``x_handover`` at 1.4 m/s meets the handover problem's rows at the entry's V, T and Td
    to the entry tolerance (:func:`walk3d.campaign.atlas.add_handover` solved it to 1e-8).
    Negative control: the entry's free-landing optimum does not."""
    from walk3d.solve.ipopt import build_solver, full_stage_start, lifted_z
    from walk3d.solve.progress import bound_violation
    from walk3d.solve.solver import forget_solvers

    a = atlas.load_atlas("male", "natural")
    i = int(np.argmin(np.abs(a.speeds - 1.4)))
    given = atlas_settings("male", "natural").replace(
        handover=True, free=(), speed=float(a.speeds[i]), period=float(a.periods[i]),
        double_support=float(a.double_supports[i]))  # fmt: skip

    def worst(x):
        solver = build_solver(given)
        z = full_stage_start(solver, lifted_z(solver, np.asarray(x)))
        b = solver.nlp_bounds("full")
        g = np.array(solver.constraints(z)).ravel()
        return max(bound_violation(z, b.lbz, b.ubz), bound_violation(g, b.lbg, b.ubg))

    try:
        assert worst(a.x_handover[i]) <= ENTRY_TOLERANCE
        assert worst(a.x[i]) > 1e-3
    finally:
        forget_solvers()


@pytest.mark.parametrize("free", [("period",), ("double_support",)])
def test_a_given_descriptor_keeps_its_value_in_an_atlas_start(monkeypatch, free):
    """With one descriptor predicted, the atlas start takes the entry's value of that one only;
    the given one starts (and stays, by its equal bounds) at the user's value."""
    seen = []

    def fake_warm_stage(solver, stage, x, scale, on_stage, s0, warm=None):
        seen.append(s0)
        return SimpleNamespace(converged=True, stages=[{}], handover=False)

    monkeypatch.setattr(starts, "warm_stage", fake_warm_stage)
    monkeypatch.setattr(starts, "build_solver", lambda ref, method: SimpleNamespace(plan={}))
    monkeypatch.setattr(starts, "_last_stage", lambda *a, **k: None)
    settings = _ref(1.25, period=1.111, double_support=0.123, free=free)
    starts.solve_from_atlas(settings)
    (s0,) = seen
    ref_start = atlas.start_for(_ref(1.25, free=free))[0]
    given = "double_support" if free == ("period",) else "period"
    k_given, k_free = (1, 0) if given == "double_support" else (0, 1)
    assert s0[k_given] == pytest.approx(getattr(settings.gait, given))
    assert s0[k_free] == pytest.approx(getattr(ref_start, free[0]))
    # negative control: the entry's value of the given descriptor is another number
    assert getattr(ref_start, given) != pytest.approx(getattr(settings.gait, given), abs=1e-3)


def _outcome(converged, stages):
    return SimpleNamespace(converged=converged, stages=stages, attempts=1, iterations=5,
                           wall_time_s=1.0, x=np.zeros(layout.N_X), z=np.zeros(3),
                           status="Solve_Succeeded" if converged else "Maximum_Iterations",
                           max_constraint_violation=0.0, compiled_derivatives=[],
                           descriptors={}, handover=False, split=None)  # fmt: skip


def test_a_failed_atlas_start_falls_back_to_standing(monkeypatch):
    from walk3d.solve import ipopt

    calls = []
    monkeypatch.setattr(starts, "solve_from_atlas",
                        lambda *a, **k: _outcome(False, [{"start": "atlas"}]))  # fmt: skip
    monkeypatch.setattr(ipopt, "solve", lambda *a, **k: calls.append(1) or _outcome(True, [{}]))
    out = starts.solve_start(PredictionSettings(), 0, on_stage=lambda m: None)
    assert calls and out.converged and out.stages[0]["start"] == "atlas" and out.attempts == 2
    # negative controls: a converged atlas start is kept; --start standing never asks the atlas
    calls.clear()
    monkeypatch.setattr(starts, "solve_from_atlas", lambda *a, **k: _outcome(True, [{}]))
    assert starts.solve_start(PredictionSettings()).iterations == 5 and not calls
    monkeypatch.setattr(starts, "solve_from_atlas", lambda *a, **k: pytest.fail("asked"))
    starts.solve_start(PredictionSettings(start="standing"))
    assert calls


@pytest.mark.solve
@pytest.mark.parametrize("descriptors_from", ["atlas", "solve"])
def test_a_prediction_from_the_atlas_walks_in_few_iterations(descriptors_from):
    """The default prediction's path: T and Td from the atlas and one solve of the handover
    from its handover optima; with ``descriptors_from="solve"``, the full problem alone with the
    free landing, then the handover at its T and Td (walk3d.solve.landing)."""
    from walk3d.pipeline import predict

    settings = PredictionSettings(
        mass=62.0,
        height=1.70,
        sex="female",
        speed=1.27,
        criterion="natural",
        free=("period", "double_support"),
        descriptors_from=descriptors_from,
    )
    pred = predict(settings, 0)
    s = pred.summary
    assert s["start"] == "atlas" and s["converged"] and s["status"] in SUCCESS
    if descriptors_from == "atlas":
        assert [st.get("start") for st in s["stages"]] == ["atlas"]
        assert s["stages"][0]["atlas_landing"] == "handover"
        assert s["stages"][0]["warm_start"]  # the entries' primal-dual points (8 iterations)
        assert s["descriptors"]["predicted_by"] == "atlas"
        assert s["iterations"] <= 20
    else:
        assert [st.get("start") for st in s["stages"]][-2:] == ["atlas", LANDING]
        assert all(st.get("start") == "atlas" for st in s["stages"][:-1])
        assert s["descriptors"]["predicted_by"] == "solve"
        assert s["iterations"] <= starts.ATLAS_TRIES * starts.ATLAS_MAX_ITER + LANDING_MAX_ITER
    assert s["landing"] == "handover" and s["settings"]["model"]["handover"]
    assert s["gait_checks"]["looks_like_walking"]
    assert 0.9 < s["descriptors"]["period"] < 1.25


def test_stage_titles_say_where_they_start():
    solver = SimpleNamespace(plan={"full": replace(starts.descriptor_stage(PredictionSettings()),
                                                   problem="full")})  # fmt: skip
    given = starts._last_stage(solver, PredictionSettings(), "the atlas")
    assert given.problem == "full" and given.title.startswith("from the atlas: minimizing")
    free = starts._last_stage(solver, PredictionSettings(free=("period",)), "a neighbour")
    assert free.problem == "free" and "period" in free.title


def test_a_handover_problem_starts_from_the_entries_handover_optima(tmp_path):
    _write(tmp_path, [1.0, 1.2, 1.4])
    path = atlas.atlas_path("male", "natural", tmp_path)
    data = json.loads(path.read_text())
    for e in data["entries"][1:]:  # 1.2 and 1.4 m/s have one, 1.0 not
        e["x_handover"] = [-float(k) * e["speed"] for k in range(layout.N_X)]
    path.write_text(json.dumps(data))
    ho = atlas.start_for(_ref(1.25, handover=True), tmp_path)[0]
    assert ho.landing == "handover" and ho.x[3] == pytest.approx(-3 * 1.25)
    assert ho.period == pytest.approx(1.0 + 1.25)  # T and Td: the free landing's, blended
    assert ho.describe()["atlas_landing"] == "handover"
    # negative controls: the free landing, and a blend with an entry that has none
    free = atlas.start_for(_ref(1.25, handover=False), tmp_path)[0]
    assert free.landing == "free" and free.x[3] == pytest.approx(3 * 1.25)
    mixed = atlas.start_for(_ref(1.1, handover=True), tmp_path)[0]
    assert mixed.landing == "free" and mixed.x[3] == pytest.approx(3 * 1.1)
    data["entries"][1]["x_handover"] = [1.0, float("nan")]
    path.write_text(json.dumps(data))
    atlas._read.cache_clear()
    with pytest.raises(ValueError, match="x_handover"):
        atlas.read_atlas(path)


def _write_warm(root, speeds, masks):
    n = len(speeds)
    np.savez(atlas.warm_path(atlas.atlas_path("male", "natural", root)), speeds=np.array(speeds),
             z=np.outer(speeds, np.ones(4)), lam_x=-np.outer(speeds, np.ones(4)),
             lam_g=np.outer(speeds, np.arange(5.0)), rows=np.array(masks[:n]))  # fmt: skip


def _with_handover(root, periods=True):
    """An atlas of 1.0, 1.2 and 1.4 m/s, each with a handover optimum; 1.2 and 1.4 with warm
    points and, with ``periods``, levels (``_write_periods``). Returns the atlas file."""
    _write(root, [1.0, 1.2, 1.4])
    path = atlas.atlas_path("male", "natural", root)
    data = json.loads(path.read_text())
    for e in data["entries"]:
        e["x_handover"] = [0.0] * layout.N_X
    path.write_text(json.dumps(data))
    same = [True, False, True, True, False]
    _write_warm(root, [1.2, 1.4], [same, same])
    if periods:
        _write_periods(root, [1.2, 1.4])
    return path


def test_a_handover_start_blends_the_entries_primal_dual_points(tmp_path):
    path = _with_handover(tmp_path, periods=False)
    same = [True, False, True, True, False]
    start = atlas.start_for(_ref(1.25, handover=True), tmp_path)[0]
    np.testing.assert_allclose(start.warm["z"], 1.25)
    np.testing.assert_allclose(start.warm["lam_x"], -1.25)
    np.testing.assert_allclose(start.warm["lam_g"], 1.25 * np.array([0.0, 2.0, 3.0]))  # kept rows
    np.testing.assert_array_equal(start.warm["rows"], [0, 2, 3])
    # negative controls: an entry without one, other stage rows, a damaged file, the free landing
    assert atlas.start_for(_ref(1.1, handover=True), tmp_path)[0].warm is None
    assert atlas.start_for(_ref(1.25, handover=False), tmp_path)[0].warm is None
    _write_warm(tmp_path, [1.2, 1.4], [same, [True] * 5])
    assert atlas.start_for(_ref(1.25, handover=True), tmp_path)[0].warm is None
    atlas.warm_path(path).write_bytes(b"not an npz")
    assert atlas.start_for(_ref(1.25, handover=True), tmp_path)[0].warm is None


def test_a_primal_dual_start_is_used_only_where_it_fits_the_solver():
    solver = SimpleNamespace(stage_bounds=lambda kind: SimpleNamespace(lbz=np.zeros(4)),
                             stage_rows={"full": np.array([0, 2, 3])},
                             layout=SimpleNamespace(n_split=0))  # fmt: skip
    warm = {"z": np.ones(4), "rows": np.array([0, 2, 3])}
    assert starts._usable_warm(solver, warm) is warm
    assert starts._usable_warm(solver, {**warm, "rows": np.array([0, 1, 3])}) is None
    assert starts._usable_warm(solver, {**warm, "z": np.ones(5)}) is None
    assert starts._usable_warm(solver, None) is None


def test_a_start_of_the_papers_split_starts_a_free_split_at_zero():
    """The atlas's points (the paper's split) fit a free split's NLP once its coefficients are
    put in at 0, after W0, in ``z`` and ``lam_x``; a point of another size (the control) does
    not."""
    lay = layout.NlpLayout(nodes=2, n_split=12)
    solver = SimpleNamespace(stage_bounds=lambda kind: SimpleNamespace(lbz=np.zeros(lay.n_z)),
                             stage_rows={"full": np.array([0, 1])}, layout=lay)  # fmt: skip
    n = lay.n_z - 12
    warm = {"z": np.arange(n) + 1.0, "lam_x": np.arange(n) + 1.0, "rows": np.array([0, 1])}
    got = starts._usable_warm(solver, warm)
    c = slice(lay.z("w0").start + layout.N_W0, lay.z("w0").stop)
    assert got["z"].size == lay.n_z and not got["z"][c].any() and not got["lam_x"][c].any()
    np.testing.assert_array_equal(np.delete(got["z"], np.r_[c]), warm["z"])
    assert starts._usable_warm(solver, {**warm, "z": np.ones(n + 1)}) is None


def test_write_warm_solves_only_the_entries_it_has_no_point_for(tmp_path, monkeypatch):
    """``add_handover`` hands over the points of the solves it ran; ``write_warm`` solves again
    only the other entries with a handover optimum (negative control: without points, all)."""
    import walk3d.campaign.atlas as campaign_atlas

    _write(tmp_path, [1.0, 1.2, 1.4])
    path = atlas.atlas_path("male", "natural", tmp_path)
    data = json.loads(path.read_text())
    for e in data["entries"][1:]:
        e["x_handover"] = [0.0] * layout.N_X
    path.write_text(json.dumps(data))
    solved = []

    def fake_solve(given, x, origin, max_iter):
        solved.append(given.gait.speed)
        return SimpleNamespace(speed=given.gait.speed)

    def point(speed):
        return {"z": np.full(2, speed), "lam_x": np.zeros(2), "lam_g": np.zeros(3),
                "rows": np.ones(3, dtype=bool)}  # fmt: skip

    monkeypatch.setattr(starts, "solve_warm", fake_solve)
    monkeypatch.setattr(campaign_atlas, "_warm_point", lambda given, out: point(out.speed))
    campaign_atlas.write_warm(path, {1.4: point(1.4)})
    assert solved == [1.2]  # 1.0 has no handover optimum, 1.4's point was given
    with np.load(atlas.warm_path(path)) as warm:
        np.testing.assert_array_equal(warm["speeds"], [1.2, 1.4])
        np.testing.assert_array_equal(warm["z"][:, 0], [1.2, 1.4])
    solved.clear()
    campaign_atlas.write_warm(path)
    assert solved == [1.2, 1.4]


def test_period_weights_bracket_the_ratio_and_never_extrapolate():
    f = np.array([1.0, 0.9, 1.1])
    assert atlas.period_weights(f, 0.95) == [(1, pytest.approx(0.5)), (0, pytest.approx(0.5))]
    assert atlas.period_weights(f, 1.075) == [(0, pytest.approx(0.25)), (2, pytest.approx(0.75))]
    assert dict(atlas.period_weights(f, 1.3))[2] == pytest.approx(1.0)  # the end, not beyond
    assert dict(atlas.period_weights(f, 0.5))[1] == pytest.approx(1.0)
    # negative control: the other side of 1 takes the other neighbour
    assert dict(atlas.period_weights(f, 1.05))[2] == pytest.approx(0.5)


def _write_periods(root, speeds, factors=(0.9, 1.1)):
    """Each entry's point at factor f is its own (z = speed) times 10 f."""
    k = np.array(factors)
    v = np.array(speeds)[:, None, None]
    np.savez(atlas.periods_path(atlas.atlas_path("male", "natural", root)), speeds=np.array(speeds),
             factors=k, z=v * 10 * k[None, :, None] * np.ones(4),
             lam_x=-v * 10 * k[None, :, None] * np.ones(4),
             lam_g=v * 10 * k[None, :, None] * np.arange(5.0))  # fmt: skip


def test_a_given_period_blends_the_entries_optima_that_bracket_it(tmp_path):
    """T given 5 % above the blended entries' (2.25 s at 1.25 m/s in ``_write``): half of each
    entry's own point and half of its point at 1.1 T."""
    path = _with_handover(tmp_path)
    start = atlas.start_for(_ref(1.25, handover=True, free=(), period=2.25 * 1.05), tmp_path)[0]
    expect = 1.25 * (0.5 + 0.5 * 11.0)
    np.testing.assert_allclose(start.warm["z"], expect)
    np.testing.assert_allclose(start.warm["lam_g"], expect * np.array([0.0, 2.0, 3.0]))
    assert start.period_ratio == pytest.approx(1.05)
    assert start.describe()["atlas_period_ratio"] == pytest.approx(1.05)
    # negative controls: the atlas's own period, predicted descriptors, a failed level (NaN)
    for ref in (_ref(1.25, handover=True, free=(), period=2.25), _ref(1.25, handover=True)):
        own = atlas.start_for(ref, tmp_path)[0]
        np.testing.assert_allclose(own.warm["z"], 1.25)
        assert own.period_ratio is None and "atlas_period_ratio" not in own.describe()
    p = atlas.periods_path(path)
    data = dict(np.load(p))
    data["z"][1, 1] = np.nan
    np.savez(p, **data)
    kept = atlas.start_for(_ref(1.25, handover=True, free=(), period=2.25 * 1.05), tmp_path)[0]
    np.testing.assert_allclose(kept.warm["z"], 1.25)
    assert kept.period_ratio is None


@pytest.mark.solve
def test_an_entry_optimum_at_another_period_is_feasible_there():
    """The shipped optimum at 1.1 T of the 1.4 m/s entry meets the handover problem's rows at
    1.1 T and 1.1 Td to the entry tolerance. Negative control: at the entry's own T and Td it
    does not."""
    from walk3d.solve.ipopt import build_solver
    from walk3d.solve.progress import bound_violation
    from walk3d.solve.solver import forget_solvers

    a = atlas.load_atlas("male", "natural")
    levels = atlas.load_periods(a)
    n = int(np.argmin(np.abs(levels["speeds"] - 1.4)))
    i = int(np.argmin(np.abs(a.speeds - levels["speeds"][n])))
    m = int(np.flatnonzero(np.isclose(levels["factors"], 1.1))[0])
    z = levels["z"][n, m]

    def worst(f):
        given = atlas_settings("male", "natural").replace(
            handover=True, free=(), speed=float(a.speeds[i]), period=float(a.periods[i]) * f,
            double_support=float(a.double_supports[i]) * f)  # fmt: skip
        solver = build_solver(given)
        b = solver.nlp_bounds("full")
        g = np.array(solver.constraints(z)).ravel()
        return max(bound_violation(z, b.lbz, b.ubz), bound_violation(g, b.lbg, b.ubg))

    try:
        assert worst(1.1) <= ENTRY_TOLERANCE
        assert worst(1.0) > 1e-3
    finally:
        forget_solvers()


@pytest.mark.solve
@pytest.mark.parametrize(
    ("case", "ratio", "fewer"),
    [((1.5, 1.02, 0.11, 72.0, 1.78, "male"), 0.993, 4),  # the entries' rows, 0.7 % below
     ((1.7, 0.96, 0.10, 60.0, 1.72, "female"), 1.106, 10)],  # 10.6 % above: a half-way level
)  # fmt: skip
def test_a_given_period_away_from_the_atlas_takes_fewer_iterations_from_its_optima(
    monkeypatch, case, ratio, fewer
):
    """T and Td given away from the atlas's period: from the entries' optima blended at that
    period in at least ``fewer`` fewer iterations than from their own optima alone (negative
    control, which records no ratio), to the same optimum."""
    import walk3d
    from walk3d.solve.solver import forget_solvers

    v, t, td, mass, height, sex = case

    def run():
        p = walk3d.predict(v, period=t, double_support=td, mass=mass, height=height, sex=sex,
                           threads=1)  # fmt: skip
        forget_solvers()
        return p.summary

    fast = run()
    monkeypatch.setattr(atlas, "load_periods", lambda _a: None)
    slow = run()
    assert fast["converged"] and slow["converged"]
    assert fast["stages"][-1]["atlas_period_ratio"] == pytest.approx(ratio, abs=0.002)
    assert "atlas_period_ratio" not in slow["stages"][-1]
    assert fast["iterations"] + fewer <= slow["iterations"]
    w = fast["objective"]["C_weighted"]["total"]
    assert w == pytest.approx(slow["objective"]["C_weighted"]["total"], rel=1e-5)


def test_optima_at_other_periods_need_the_entries_primal_dual_points(tmp_path):
    from walk3d.campaign.atlas import write_periods

    _write(tmp_path, [1.0, 1.2])
    path = atlas.atlas_path("male", "natural", tmp_path)
    with pytest.raises(ValueError, match="no primal-dual points"):
        write_periods(path)
    assert not atlas.periods_path(path).exists()


def test_write_periods_tries_the_own_point_a_neighbour_then_continuation_and_resumes(
    tmp_path, monkeypatch
):
    """Which starts each level's solve gets, with a fake solve that never converges at 1.1 T for
    the 0.8 m/s entry (its own point, the neighbour's level, then from the half-way optimum), so
    the half-way optimum is kept at 1.05; a second run solves only what is NaN (negative control:
    a level that never converges at all stays NaN and is tried again)."""
    import walk3d.campaign.atlas as campaign_atlas

    _write(tmp_path, [0.6, 0.8])
    path = atlas.atlas_path("male", "natural", tmp_path)
    same = [True, False, True, True, False]
    _write_warm(tmp_path, [0.6, 0.8], [same, same])
    calls = []

    def fake(given, start, mask):
        ratio = round(given.gait.period / (1.0 + given.gait.speed), 3)
        calls.append((given.gait.speed, ratio, float(start["z"][0])))
        if given.gait.speed == 0.8 and ratio == 1.1:
            return None
        value = 8.0 if ratio == 1.05 else 7.0
        return {k: np.full(start[k].shape, value) for k in ("z", "lam_x", "lam_g")}

    monkeypatch.setattr(campaign_atlas, "_period_point", fake)
    campaign_atlas.write_periods(path)
    assert calls == [(0.6, 0.9, 0.6), (0.6, 1.1, 0.6), (0.8, 0.9, 0.8),
                     (0.8, 1.1, 0.8), (0.8, 1.1, 7.0),  # own, then 0.6's level: both fail
                     (0.8, 1.05, 0.8), (0.8, 1.1, 8.0)]  # half-way, then from there  # fmt: skip
    levels = atlas.load_periods_file(atlas.periods_path(path))
    assert np.isfinite(levels["z"]).all() and levels["z"][1, 1, 0] == 8.0
    np.testing.assert_allclose(levels["reached"], [[0.9, 1.1], [0.9, 1.05]])
    calls.clear()
    campaign_atlas.write_periods(path)
    assert calls == []  # all kept
    data = dict(np.load(atlas.periods_path(path)))
    data["z"][1, 1] = np.nan
    data["reached"][1, 1] = np.nan
    np.savez(atlas.periods_path(path), **data)
    monkeypatch.setattr(campaign_atlas, "_period_point", lambda given, start, mask: None)
    campaign_atlas.write_periods(path)
    levels = atlas.load_periods_file(atlas.periods_path(path))
    assert np.isnan(levels["z"][1, 1]).all() and np.isfinite(levels["z"][0]).all()
    assert np.isnan(levels["reached"][1, 1]) and levels["reached"][0, 1] == 1.1


def test_a_level_kept_half_way_is_placed_at_the_factor_it_was_solved_at(tmp_path):
    """A 1.1 T level solved only at 1.05 T: a given period 5 % above the entries' takes that
    level alone; 2.5 % above, half of it (negative control: read as a 1.1 T level, the 5 % start
    would be the half-and-half blend)."""
    path = _with_handover(tmp_path)
    p = atlas.periods_path(path)
    levels = dict(np.load(p))
    np.savez(p, **levels, reached=np.array([[0.9, 1.05], [0.9, 1.05]]))

    def z(ratio):
        ref = _ref(1.25, handover=True, free=(), period=2.25 * ratio)
        return atlas.start_for(ref, tmp_path)[0].warm["z"]

    np.testing.assert_allclose(z(1.05), 1.25 * 11.0)
    np.testing.assert_allclose(z(1.025), 1.25 * (0.5 + 0.5 * 11.0))
    np.savez(p, **levels)  # without ``reached``: at the nominal 1.1
    np.testing.assert_allclose(z(1.05), 1.25 * (0.5 + 0.5 * 11.0))


def test_ctrl_c_in_an_atlas_try_ends_the_solve_without_another_try(monkeypatch):
    """Ctrl-C while the first atlas start solves (sent from inside the fake stage, as IPOPT's
    callback would see it): the stage stops on the flag, KeyboardInterrupt follows, and no
    second start is tried. The control: a try that does not converge without a signal is
    followed by the next start. Whoever calls ``solve_from_atlas`` (the landing's T and Td
    from the atlas too) gets this."""
    import os
    import signal

    from walk3d.solve.progress import INTERRUPT

    tries: list = []

    def fake_warm_stage(solver, stage, x, scale, on_stage, s0, warm=None, signal_it=True):
        tries.append(s0)
        if signal_it and len(tries) == 1:
            try:
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(0.05)
            except KeyboardInterrupt:  # raised inside IPOPT's callback, CasADi swallows it
                pass
        return _outcome(False, [{}])

    monkeypatch.setattr(starts, "warm_stage", fake_warm_stage)
    monkeypatch.setattr(starts, "build_solver", lambda ref, method: SimpleNamespace(plan={}))
    monkeypatch.setattr(starts, "_last_stage", lambda *a, **k: None)
    monkeypatch.setattr(starts, "merged", lambda first, free, method: free)
    with pytest.raises(KeyboardInterrupt):
        starts.solve_from_atlas(_ref(1.25))
    assert len(tries) == 1 and not INTERRUPT.requested
    tries.clear()
    monkeypatch.setattr(starts, "warm_stage",
                        lambda *a, **k: fake_warm_stage(*a, **k, signal_it=False))  # fmt: skip
    starts.solve_from_atlas(_ref(1.25))
    assert len(tries) > 1
