"""The compiled-derivative path of the solver (walk3d.solve.solver.compile_solver): which
libraries are compiled, that a new build loads them, and that the NLP derivatives assembled
from them equal the VM ones. The C compiler is replaced by the uncompiled SX blocks here (the
real compiler is tested in tests/solve/test_solve_compiled_functions.py; a real compile takes
minutes)."""

import casadi as ca
import numpy as np
import pytest

from walk3d.problem import derivatives
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import compiled, model_cache, solver

pytestmark = pytest.mark.model

SETTINGS = PredictionSettings(nodes=6, criterion="en", start="standing")


@pytest.fixture
def fake_compiler(tmp_path, monkeypatch):
    """compile_functions stores the SX functions in a dict; load_functions reads them back."""
    monkeypatch.setenv(model_cache.ENV_DIR, str(tmp_path))
    store: dict[tuple[str, str], ca.Function] = {}
    calls: list[tuple[str, int]] = []

    def compile_functions(key, functions, jobs=None, on_done=None):
        calls.append((key, len(functions)))
        for i, (name, fn) in enumerate(functions.items(), 1):
            store[key, name] = fn
            if on_done:
                on_done(name, i, len(functions))
        return {n: store[key, n] for n in functions}

    def load_functions(key, names):
        if all((key, n) in store for n in names):
            return {n: store[key, n] for n in names}
        return None

    monkeypatch.setattr(compiled, "compile_functions", compile_functions)
    monkeypatch.setattr(compiled, "load_functions", load_functions)
    monkeypatch.setattr(compiled, "any_libraries", lambda: bool(store))
    solver._build.cache_clear()
    yield calls
    solver._build.cache_clear()


def _dense(m) -> np.ndarray:
    return np.array(ca.densify(ca.DM(m)))


def test_compile_then_build_uses_the_compiled_blocks(fake_compiler, monkeypatch):
    kinds = ["balance", "full", "full_hs"]  # the full NLP's node 0 too
    assert solver.compiled_status(SETTINGS) == {"compiled": [], "missing": 6 * solver.CHUNKS}
    assert solver.build_solver(SETTINGS).compiled == {}
    names: list[str] = []
    info = solver.compile_solver(SETTINGS, on_done=lambda n, i, t: names.append(n))
    assert info["compiled"] == 6 * solver.CHUNKS == len(names)
    assert [c[1] for c in fake_compiler] == [2 * solver.CHUNKS] * 3
    assert len({c[0] for c in fake_compiler}) == 3  # one key per node function
    assert solver.compiled_status(SETTINGS) == {"compiled": kinds, "missing": 0}
    assert solver.compile_solver(SETTINGS)["compiled"] == 0  # nothing left to compile

    comp = solver.build_solver(SETTINGS)  # the cache was cleared: loads the blocks
    assert sorted(comp.compiled) == kinds
    with monkeypatch.context() as m:  # the full NLP differentiates no node function itself
        m.setattr(derivatives, "node_derivatives", lambda *a: pytest.fail("differentiated"))
        comp.nlp_problem("full")
    plain = solver._build.__wrapped__(SETTINGS, "ipopt", False)  # no cache: VM derivatives
    assert plain.compiled == {}
    rng = np.random.default_rng(2)
    for kind in ("balance", "full"):  # the full NLP's Hessian and Jacobian include node 0's
        a = comp.nlp_problem(kind)["derivatives"]
        b = plain.nlp_problem(kind)["derivatives"]
        z = rng.uniform(-0.1, 0.1, comp.bounds.lbz.size)
        lam = rng.normal(size=comp.bounds.lbg.size if kind == "full" else
                         comp.bounds_balance.lbg.size)  # fmt: skip
        h_ref = _dense(b["hess_lag"](z, [], 0.3, lam))
        assert np.abs(h_ref).max() > 1.0
        np.testing.assert_allclose(_dense(a["hess_lag"](z, [], 0.3, lam)), h_ref, rtol=0,
                                   atol=1e-12 * np.abs(h_ref).max())  # fmt: skip
        np.testing.assert_allclose(_dense(a["jac_g"](z, [])[1]), _dense(b["jac_g"](z, [])[1]),
                                   rtol=0, atol=1e-11)  # fmt: skip


def test_compiled_libraries_follow_the_node_functions(fake_compiler):
    """The key is what the blocks are made of: another sex's body needs its own libraries;
    settings that leave the node functions unchanged (nodes, threads; the speed, which enters
    through node parameters; mass and stature, solved as the reference subject's problem)
    share them."""
    solver.compile_solver(SETTINGS)
    other = SETTINGS.replace(**{"sex": "female"})
    assert solver.compiled_status(other)["missing"] == 6 * solver.CHUNKS
    other_criterion = SETTINGS.replace(**{"criterion": "tor"})
    assert solver.compiled_status(other_criterion)["missing"] == 6 * solver.CHUNKS
    for same in ({"nodes": 8, "threads": 2}, {"speed": 1.2}, {"mass": 80.0, "height": 1.6}):
        assert solver.compiled_status(SETTINGS.replace(**same))["missing"] == 0


def test_a_start_from_the_atlas_compiles_the_full_nlp_alone(fake_compiler):
    """The atlas start runs only the full NLP: its node 0 and other nodes are compiled, the
    balance NLP's are not (negative control: standing starts compile all three)."""
    atlas = SETTINGS.replace(start="atlas")
    assert solver.compiled_status(atlas)["missing"] == 4 * solver.CHUNKS
    assert solver.compile_solver(atlas)["compiled"] == 4 * solver.CHUNKS
    assert solver.compiled_status(atlas) == {"compiled": ["full", "full_hs"], "missing": 0}
    assert solver.compiled_status(SETTINGS)["missing"] == 2 * solver.CHUNKS  # balance left
