"""Compiled C functions in the cache folder: compiled once, loaded with equal values, a
damaged library counted as missing, a missing compiler reported as such."""

import hashlib
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
    (cache / "lib-k2-t_poly.so").write_bytes(b"not a shared library")
    assert compiled.load_functions("k2", ["t_poly"]) is None


def test_a_folder_in_a_librarys_place_is_missing_with_a_warning(cache, caplog):
    """A folder where a library goes counts as missing and says so; an absent library (the
    control) is missing silently."""
    (cache / "lib-k4-t_poly.so").mkdir()
    with caplog.at_level("WARNING", logger="walk3d.solve.compiled"):
        assert compiled.load_functions("k5", ["t_poly"]) is None
        assert not caplog.records
        assert compiled.load_functions("k4", ["t_poly"]) is None
    assert len(caplog.records) == 1 and "not a regular file" in caplog.records[0].getMessage()
    fn = {"t_poly": _functions()["t_poly"]}
    assert set(compiled.compile_functions("k4", fn)) == {"t_poly"}  # the repair builds it
    assert (cache / "lib-k4-t_poly.so").is_file()


@pytest.mark.parametrize("damage", ["truncate", "alter", "no digest", "cut, then digested"])
def test_a_library_that_does_not_match_its_digest_is_never_loaded(cache, damage, monkeypatch):
    """A truncated or altered library could crash the dynamic loader, so it is checked against
    the digest written when it was built, counts as missing and is built again. A library cut
    short before its digest was written (a matching digest) fails the ELF check."""
    compiled.compile_functions("k3", {"t_poly": _functions()["t_poly"]})
    lib = cache / "lib-k3-t_poly.so"
    assert compiled.load_functions("k3", ["t_poly"]) is not None  # control: as built, it loads
    data = lib.read_bytes()
    if damage == "truncate":
        lib.write_bytes(data[: len(data) // 2])
    elif damage == "alter":
        lib.write_bytes(data[:-64] + bytes(64))
    elif damage == "cut, then digested":
        lib.write_bytes(data[: len(data) // 2])
        compiled.digest_path(lib).write_text(hashlib.sha256(lib.read_bytes()).hexdigest() + "\n")
        assert "cut short" in compiled.verified(lib)
    else:
        compiled.digest_path(lib).unlink()
    loaded = []
    with monkeypatch.context() as m:
        m.setattr(compiled.ca, "external", lambda *a: loaded.append(a))
        assert compiled.load_functions("k3", ["t_poly"]) is None and not loaded
    compiled.compile_functions("k3", {"t_poly": _functions()["t_poly"]})  # the repair
    assert compiled.verified(lib) is None and compiled.load_functions("k3", ["t_poly"])


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
