"""Compiled C functions in the cache folder: compiled once, loaded with equal values, a
damaged library counted as missing, a missing compiler reported as such."""

from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from walk3d.solve import compiled

pytestmark = pytest.mark.skipif(compiled.compiler() is None, reason="no C compiler on PATH")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("WALK3D_CFLAGS", "-O0")
    return tmp_path


def _functions() -> dict[str, ca.Function]:
    x = ca.SX.sym("x", 3)
    p = ca.SX.sym("p")
    f = ca.Function("t_poly", [x, p], [ca.vertcat(x[0] ** 2 * p, ca.sin(x[1]) * x[2])])
    h = ca.Function("t_hess", [x, p], [ca.hessian(ca.sumsqr(ca.sin(x)) * p, x)[0]])
    return {"t_poly": f, "t_hess": h}


def test_compiled_functions_equal_and_are_built_once(cache):
    fns = _functions()
    done = []
    out = compiled.compile_functions("k1", fns, on_done=lambda n, i, t: done.append((n, i, t)))
    assert sorted(d[0] for d in done) == ["t_hess", "t_poly"] and done[-1][1:] == (2, 2)
    x, p = np.array([0.3, -1.2, 2.0]), 1.7
    for name, fn in fns.items():
        assert "external" in out[name].class_name().lower() or out[name].is_a("External")
        np.testing.assert_allclose(np.array(out[name](x, p)), np.array(fn(x, p)), rtol=1e-14)
    # a second call finds both in the cache and compiles nothing
    done.clear()
    again = compiled.compile_functions("k1", fns, on_done=lambda *a: done.append(a))
    assert done == [] and set(again) == set(fns)
    assert not list(cache.glob(".build-*"))  # no temporary folder left behind
    # another key is another entry
    assert compiled.load_functions("k2", list(fns)) is None


def test_damaged_library_is_missing(cache):
    compiled.compile_functions("k3", _functions())
    lib = next(cache.glob("lib-k3-t_poly.so"))
    lib.write_bytes(b"not a library")
    assert compiled.load_functions("k3", ["t_poly"]) is None
    assert compiled.load_functions("k3", ["t_hess"]) is not None
    compiled.compile_functions("k3", _functions())  # rebuilt
    assert compiled.load_functions("k3", ["t_poly", "t_hess"]) is not None


def test_missing_compiler_is_a_clear_error(cache, monkeypatch):
    monkeypatch.setenv("CC", "/nonexistent/cc")
    assert compiled.compiler() is None
    with pytest.raises(compiled.CompileError, match="no C compiler"):
        compiled.compile_functions("k4", _functions())


def test_failing_compiler_is_a_clear_error(cache, monkeypatch):
    monkeypatch.setenv("WALK3D_CFLAGS", "-fno-such-flag-walk3d")
    with pytest.raises(compiled.CompileError, match="failed on t_"):
        compiled.compile_functions("k5", _functions(), jobs=1)
    assert not list(cache.glob("lib-k5-*"))


def test_native_flags_key_the_library_to_the_cpu(monkeypatch):
    # a library tuned with -march=native must not be loaded on another CPU of a shared cache
    monkeypatch.setattr(compiled, "cpu_fingerprint", lambda: "cpu A")
    portable, native = ("-O1",), ("-O1", "-march=native")
    a_portable, a_native = compiled.library_key("k", portable), compiled.library_key("k", native)
    monkeypatch.setattr(compiled, "cpu_fingerprint", lambda: "cpu B")
    assert compiled.library_key("k", portable) == a_portable
    assert compiled.library_key("k", native) != a_native
    assert a_native != a_portable
    monkeypatch.undo()
    if Path("/proc/cpuinfo").is_file():  # Linux: the instruction-set flags are in it
        assert "flags" in compiled.cpu_fingerprint()
