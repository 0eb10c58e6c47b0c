"""The on-disk model cache: a solver built from cached functions is the same solver, and a
damaged entry is rebuilt (walk3d.solve.model_cache)."""

from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from walk3d.model.settings import role
from walk3d.problem import nlp
from walk3d.problem.settings import ModelSettings, PredictionSettings, body_for
from walk3d.solve import ipopt, model_cache, solver

SETTINGS = PredictionSettings(nodes=6, max_iter=3, balance_max_iter=3)


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    monkeypatch.setenv(model_cache.ENV_DIR, str(tmp_path))
    monkeypatch.delenv(model_cache.ENV_SWITCH, raising=False)
    return tmp_path


def _key(settings: PredictionSettings) -> str:
    return solver.model_key(body_for(settings), settings.model)


def _small_functions() -> dict[str, ca.Function]:
    x = ca.SX.sym("x", 3)
    return {"f": ca.Function("f", [x], [ca.sin(x) * 2.5]), "g": ca.Function("g", [x], [x.T @ x])}


def _run(fn: ca.Function, z0: np.ndarray, b) -> np.ndarray:
    sol = fn(x0=z0, lbx=b.lbz, ubx=b.ubz, lbg=b.lbg, ubg=b.ubg)
    assert fn.stats()["iter_count"] == 3
    return np.array(sol["x"]).ravel()


@pytest.mark.model
def test_solver_from_cache_equals_a_fresh_one(cache_dir):
    fresh = solver._build.__wrapped__(SETTINGS, "ipopt", True)  # empty cache: built and stored
    assert not list(cache_dir.glob("model-*.casadi"))  # nothing is made before it is used
    made = [fresh.functions[n] for n in fresh.functions]
    assert not fresh.from_cache and len(list(cache_dir.glob("model-*.casadi"))) == len(made) == 7
    cached = solver._build.__wrapped__(SETTINGS, "ipopt", True)
    assert [cached.functions[n] for n in cached.functions] and cached.from_cache
    z0 = ipopt.initial_guess(fresh, 0)
    np.testing.assert_array_equal(z0, ipopt.initial_guess(cached, 0))
    # the full NLP's values and derivatives (the custom grad_f, jac_g, hess_lag) at one point
    z = ipopt.full_stage_start(fresh, z0)
    lam = np.random.default_rng(1).normal(size=fresh.stage_bounds("full").lbg.size)
    for name, args in [("nlp_f", [z, []]), ("nlp_g", [z, []]), ("nlp_jac_g", [z, []]),
                       ("nlp_grad_f", [z, []]), ("nlp_hess_l", [z, [], 0.7, lam])]:  # fmt: skip
        a = fresh.stage("full").get_function(name)(*args)
        b = cached.stage("full").get_function(name)(*args)
        for u, v in zip(a if isinstance(a, tuple) else [a], b if isinstance(b, tuple) else [b],
                        strict=True):  # fmt: skip
            assert u.sparsity() == v.sparsity(), name
            np.testing.assert_array_equal(np.array(u.nonzeros()), np.array(v.nonzeros()), name)
    # a few IPOPT iterations take the same steps
    for stage in ("balance", "posture"):
        b = fresh.stage_bounds(stage)
        x_fresh = _run(fresh.stage(stage), z0, b)
        np.testing.assert_array_equal(x_fresh, _run(cached.stage(stage), z0, b), stage)
    zf = ipopt.full_stage_start(fresh, z0)
    full = [(sv.stage("full"), zf, sv.stage_bounds("full")) for sv in (fresh, cached)]
    np.testing.assert_array_equal(_run(*full[0]), _run(*full[1]))


@pytest.mark.model
def test_a_damaged_entry_is_rebuilt_and_rewritten(cache_dir, caplog, recorded):
    body, key = body_for(SETTINGS), _key(SETTINGS)
    model_cache.write_functions(f"{key}-loop", {"loop": recorded[0]["loop"]})
    lazy = solver._model_functions(body, SETTINGS.model, True)
    assert lazy["loop"].serialize() == recorded[0]["loop"].serialize() and lazy.hits == {"loop"}
    (entry,) = cache_dir.glob("model-*.casadi")
    text = entry.read_text()
    entry.write_text(text[: len(text) // 2] + "x" + text[len(text) // 2 + 1 :])
    again = solver._model_functions(body, SETTINGS.model, True)
    assert again["loop"].serialize() == recorded[0]["loop"].serialize()
    assert again.misses == {"loop"} and not again.hits and "damaged" in caplog.text
    assert set(model_cache.read_functions(f"{key}-loop")) == {"loop"}  # rewritten


def test_lazy_functions_are_made_once_on_first_use_and_read_back_from_the_cache(cache_dir):
    built = []
    small = _small_functions()

    def build(name):
        built.append(name)
        return small[name]

    lazy = model_cache.LazyFunctions(("f", "g"), build, "0123456789abcdef")
    assert len(lazy) == 2 and list(lazy) == ["f", "g"] and not built
    assert lazy["f"] is lazy["f"] and built == ["f"] and lazy.misses == {"f"}
    again = model_cache.LazyFunctions(("f", "g"), build, "0123456789abcdef")
    x = np.array([0.1, -0.2, 0.3])
    np.testing.assert_array_equal(np.array(again["f"](x)), np.array(small["f"](x)))
    assert built == ["f"] and again.hits == {"f"}  # read back, not built
    assert again["g"] is small["g"] and built == ["f", "g"]  # negative control: not cached yet
    with pytest.raises(KeyError):
        lazy["h"]
    off = model_cache.LazyFunctions(("f",), build, None)  # no key: the cache is off
    assert off["f"] is small["f"] and off.misses == {"f"} and built == ["f", "g", "f"]


@pytest.mark.parametrize(
    "damage",
    [
        lambda t: t[: len(t) // 3],  # truncated
        lambda t: "garbage\n" + t,  # wrong header
        lambda t: t.replace("\n", " 1\n", 1),  # header with an extra field
        lambda t: t.split("\n", 1)[0] + "\nabcdefgh",  # payload that does not match the checksum
    ],
)
def test_damaged_entries_read_as_misses(cache_dir, damage):
    key = "0123456789abcdef"
    path = model_cache.write_functions(key, _small_functions())
    assert path is not None and set(model_cache.read_functions(key)) == {"f", "g"}
    path.write_text(damage(path.read_text()))
    assert model_cache.read_functions(key) is None


def test_unreadable_payload_with_a_valid_checksum_reads_as_a_miss(cache_dir):
    key = "fedcba9876543210"
    path = model_cache.write_functions(key, _small_functions())
    other = model_cache.write_functions("0" * 16, _small_functions())
    path.write_text(other.read_text())  # intact, but stored under another key
    assert model_cache.read_functions(key) is None
    path.write_bytes(b"\xff\xfe binary")
    assert model_cache.read_functions(key) is None


def _within(seconds: float, call):
    """``call()``'s value, or a failure if it has not returned after ``seconds`` (it runs in a
    daemon thread, so a read blocked for ever does not hold the test run)."""
    import threading

    out = []
    worker = threading.Thread(target=lambda: out.append(call()), daemon=True)
    worker.start()
    worker.join(seconds)
    assert out, f"still blocked after {seconds} s"
    return out[0]


def test_a_fifo_in_the_cache_is_never_read(cache_dir):
    """A ``.sha256`` digest that is a FIFO made walk3d predict hang in its read; so did a
    model entry. Each is refused as not a regular file, and counts as missing."""
    import hashlib
    import os

    from walk3d.solve import compiled

    lib = cache_dir / "lib-k-f.so"
    elf = next(Path(ca.__file__).parent.glob("_casadi*.so")).read_bytes()  # a whole ELF
    lib.write_bytes(elf)
    digest = compiled.digest_path(lib)
    digest.write_text(hashlib.sha256(elf).hexdigest() + "\n")
    assert _within(5, lambda: compiled.verified(lib)) is None  # control: a regular digest
    digest.unlink()
    os.mkfifo(digest)
    assert "not a regular file" in _within(5, lambda: compiled.verified(lib))
    key = "0123456789abcdef"
    entry = model_cache.write_functions(key, _small_functions())
    assert set(_within(5, lambda: model_cache.read_functions(key))) == {"f", "g"}  # control
    entry.unlink()
    os.mkfifo(entry)
    assert _within(5, lambda: model_cache.read_functions(key)) is None


def test_cached_functions_evaluate_like_the_originals(cache_dir):
    fns = _small_functions()
    model_cache.write_functions("k", fns)
    loaded = model_cache.read_functions("k")
    x = np.array([0.1, -0.2, 0.3])
    for name, fn in fns.items():
        np.testing.assert_array_equal(np.array(fn(x)), np.array(loaded[name](x)))


def test_a_cache_that_cannot_be_written_is_skipped(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(model_cache.ENV_DIR, str(blocker / "cache"))
    assert model_cache.write_functions("k", _small_functions()) is None
    assert model_cache.read_functions("k") is None


@pytest.mark.parametrize("below", ["", "sub", "sub/deeper"])
def test_a_cache_folder_that_is_a_file_is_one_warning(tmp_path, monkeypatch, caplog, below):
    """A file where the cache folder or one of its parents goes: one warning line for the
    process, not one per entry read and written (below a file: six in a predict); the
    control, a folder there, caches."""
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(model_cache.ENV_DIR, str(blocker / below) if below else str(blocker))
    with caplog.at_level("WARNING", logger="walk3d.solve.model_cache"):
        for key in ("k1", "k2"):
            assert model_cache.read_functions(key) is None
            assert model_cache.write_functions(key, _small_functions()) is None
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) == 1 and "is not a folder" in lines[0], lines
    monkeypatch.setenv(model_cache.ENV_DIR, str(tmp_path / "folder"))
    assert model_cache.write_functions("k1", _small_functions()) is not None


def test_switch_and_location(monkeypatch, tmp_path):
    monkeypatch.setenv(model_cache.ENV_DIR, str(tmp_path))
    assert model_cache.cache_dir() == tmp_path
    monkeypatch.delenv(model_cache.ENV_DIR)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    if model_cache.sys.platform.startswith("linux"):
        assert model_cache.cache_dir() == tmp_path / "xdg" / "walk3d"
    for value, on in [("0", False), ("off", False), ("False", False), ("1", True), ("", True)]:
        monkeypatch.setenv(model_cache.ENV_SWITCH, value)
        assert model_cache.cache_enabled() is on
        assert model_cache.cache_enabled(True) is True
    monkeypatch.delenv(model_cache.ENV_SWITCH)
    assert model_cache.cache_enabled()


def test_key_follows_the_model_not_the_solver_options():
    base = _key(SETTINGS)
    assert base == _key(SETTINGS.replace(**{"nodes": 20, "max_iter": 50, "tol": 1e-8}))
    descriptors = {"speed": 1.1, "period": 1.2, "double_support": 0.2}  # node parameters
    assert base == _key(SETTINGS.replace(**descriptors))
    # the heel-strike map and the bounds are the NLP's, not the node functions'
    for change in [{"transition_ratios": (0.2, 0.05, 0.1, 0.3)}, {"swing_clearance": 0.01}]:
        assert _key(SETTINGS.replace(**change)) == base, change
    for change in [{"mass": 70.0}, {"criterion": "en"}, {"cop_margin": 0.01}]:
        assert _key(SETTINGS.replace(**change)) != base, change


class _Recorder:
    """Settings that record which fields are read."""

    model_fields = ModelSettings.model_fields  # the roles, read off the class

    def __init__(self, settings: PredictionSettings):
        self._settings, self.read = settings, set()

    def __getattr__(self, name: str):
        self.read.add(name)
        return getattr(self._settings, name)


@pytest.fixture(scope="module")
def recorded() -> tuple[dict[str, ca.Function], set[str]]:
    """The model functions of SETTINGS, and the settings fields their construction read."""
    rec = _Recorder(SETTINGS.model)
    return nlp.model_functions(body_for(SETTINGS), rec), rec.read


def test_model_functions_read_only_the_model_settings_of_the_key(recorded):
    """The key is the body and the whole model group, and the model functions receive nothing
    else: they read model fields (a recorder on the group sees them), and a field they read
    changes both the functions and the key (negative control)."""
    fns, read = recorded
    assert set(fns) == {"loop"} | {nlp.node_name(d, b, h) for d, b in nlp.STAGES.values()
                                   for h in (True, False)}  # fmt: skip
    # passive is in the key when on; off, it is left out and the functions are those before it
    assert read == {"absolute", "balance_split", "changes", "cop_margin", "criterion",
                    "free_moment_radius", "friction", "handover", "passive",
                    "smoothing", "split_terms"}  # fmt: skip
    # the model's other fields shape the body (calibrated roll-over, what-if changes) or the
    # NLP's bounds and heel-strike map, not these functions: the key leaves them out
    assert read < set(ModelSettings.model_fields)
    assert read - {"changes"} <= {n for n in ModelSettings.model_fields
                                  if role(ModelSettings, n).nodes}  # fmt: skip
    rougher = SETTINGS.replace(friction=0.6)
    assert _key(rougher) != _key(SETTINGS)
    node = nlp.node_function(body_for(rougher), rougher.model)
    assert node.serialize() != fns[nlp.node_name(True, True, False)].serialize()
    # a weakened joint's overload term is in the node function, and its changes in the key
    weak = SETTINGS.replace(changes={"strength": {"ankle_r": 0.5}})
    assert _key(weak) != _key(SETTINGS)
    node = nlp.node_function(body_for(weak), weak.model)
    assert node.serialize() != fns[nlp.node_name(True, True, False)].serialize()


@pytest.mark.model
def test_gait_descriptors_leave_the_node_functions_unchanged(recorded):
    """V, T and Td reach the node functions as node parameters (schedule.node_params), so the
    functions, and with them the key of their compiled derivatives (walk3d compile), are the
    same for any descriptors; the body is not a parameter, so another mass changes them."""
    fns, _ = recorded
    other = SETTINGS.replace(**{"speed": 1.1, "period": 1.25, "double_support": 0.2})
    assert other.gait.stride_length != SETTINGS.gait.stride_length
    again = nlp.model_functions(body_for(other), other.model)
    assert {k: f.serialize() for k, f in again.items()} == {
        k: f.serialize() for k, f in fns.items()
    }
    for kind in solver.COMPILED_NODES:
        assert solver._compiled_key(again, other, kind) == solver._compiled_key(fns, SETTINGS, kind)
    heavier = SETTINGS.replace(**{"mass": 80.0})
    node = nlp.node_function(body_for(heavier), heavier.model)
    assert node.serialize() != fns[nlp.node_name(True, True, False)].serialize()
