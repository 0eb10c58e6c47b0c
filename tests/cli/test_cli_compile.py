"""walk3d compile on a full disk, with a compile lock that is a folder, and after a killed
compile: one line and exit code 3, never a traceback; the build folders that a killed compile
left are removed when it starts. The derivatives are replaced by two one-line functions, built
with the system's compiler (well under a second); the full disk is an ENOSPC from a sync."""

import shutil

import pytest
from disk_support import full_disk
from helpers import cli

needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")


@pytest.fixture
def small(tmp_path, monkeypatch):
    """A cache folder of its own, and a compile of two small functions in place of the
    solver's derivatives; the compiler is the system's ``cc``."""
    import casadi as ca

    import walk3d.cli.compile as compile_command
    from walk3d.solve import compiled

    monkeypatch.setenv("WALK3D_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.setattr(compile_command, "compiled_status", lambda s: {"missing": 2})

    def compile_solver(settings, on_done=None, jobs=None):
        x = ca.SX.sym("x")
        fns = {name: ca.Function(name, [x], [k * x]) for k, name in enumerate(("f", "g"), 1)}
        compiled.compile_functions("small", fns, jobs, on_done)
        return {"compiled": 2, "wall_time_s": 0.1}

    monkeypatch.setattr(compile_command, "compile_solver", compile_solver)
    return tmp_path


def _one_line_exit_3(result, *words) -> None:
    code, _, err = result
    lines = err.strip().splitlines()
    assert code == 3 and len(lines) == 1 and lines[0].startswith("walk3d: error:"), err
    assert "Traceback" not in err and all(w in lines[0] for w in words), err


@needs_cc
def test_compile_on_a_full_disk_exits_3_with_one_line(small, capsys, monkeypatch):
    """It printed a traceback (ENOSPC) and exited 1."""
    synced = full_disk(monkeypatch)
    _one_line_exit_3(cli(capsys, "compile"), "walk3d compile: could not write",
                     "no space left on device")  # fmt: skip
    assert synced == []  # control: the first library was compiled, its digest did not fit
    assert not list(small.glob(".build-*")) and not list(small.glob("lib-*"))


def _entries_first(monkeypatch, entry_fails):
    """The small compile writing two model cache entries first (the same one twice), as the
    real compile does while it builds the model functions; ``entry_fails``: their writes end in
    ENOSPC while the libraries still fit."""
    import errno

    import casadi as ca

    import walk3d.cli.compile as compile_command
    from walk3d.solve import model_cache

    small_compile = compile_command.compile_solver
    if entry_fails:

        def no_room(*a):
            raise OSError(errno.ENOSPC, "No space left on device")

        monkeypatch.setattr(model_cache, "atomic_write_text", no_room)

    def compile_solver(settings, on_done=None, jobs=None):
        x = ca.SX.sym("x")
        for key in ("a", "b", "b"):
            model_cache.write_functions(key, {"f": ca.Function("f", [x], [x])})
        return small_compile(settings, on_done, jobs)

    monkeypatch.setattr(compile_command, "compile_solver", compile_solver)


@needs_cc
def test_compile_on_a_full_disk_prints_no_warning_before_its_error(small, capsys, monkeypatch,
                                                                    caplog):  # fmt: skip
    """The model cache's entries that did not fit gave three warning lines (one repeated) before
    the error line; now the error line is alone. Outside pytest, a log record that reaches no
    handler is printed on stderr; here pytest's log capture stands for that."""
    _entries_first(monkeypatch, entry_fails=False)
    full_disk(monkeypatch)
    _one_line_exit_3(cli(capsys, "compile"), "walk3d compile: could not write",
                     "no space left on device")  # fmt: skip
    assert [r.getMessage() for r in caplog.records if r.name.startswith("walk3d.")] == []


@needs_cc
def test_a_compile_that_ends_prints_each_cache_warning_once(small, capsys, monkeypatch):
    """Negative control: with room for the libraries, the compile ends (exit 0) and says, once
    per entry, which model cache entries could not be written."""
    _entries_first(monkeypatch, entry_fails=True)
    code, out, err = cli(capsys, "compile")
    lines = err.strip().splitlines()
    assert code == 0 and "walk3d compile: 2 libraries" in out, err
    warning = "walk3d: warning: could not write the model cache entry"
    assert len(lines) == 2 and all(line.startswith(warning) for line in lines), err


@needs_cc
def test_compile_with_room_compiles(small, capsys):
    """Negative control: the same compile without the full disk."""
    code, out, err = cli(capsys, "compile")
    assert code == 0 and "walk3d compile: 2 libraries" in out, err
    assert len(list(small.glob("lib-*.so"))) == 2


def test_a_compiler_that_runs_out_of_space_is_exit_3(small, capsys, monkeypatch):
    """The linker's "No space left on device" is the disk, not bad input (exit 2); its last
    line only said that it failed."""
    cc = small / "cc"
    cc.write_text("#!/bin/sh\necho '/usr/bin/ld: final link failed: No space left on device' >&2"
                  "\necho 'collect2: error: ld returned 1 exit status' >&2\nexit 1\n")  # fmt: skip
    cc.chmod(0o755)
    monkeypatch.setenv("CC", str(cc))
    _one_line_exit_3(cli(capsys, "compile"), "final link failed: No space left on device")


def test_compile_with_a_lock_that_is_a_folder_exits_3_with_one_line(small, capsys):
    """IsADirectoryError escaped as a traceback."""
    (small / "compile.lock").mkdir()
    _one_line_exit_3(cli(capsys, "compile"), "compile.lock", "is a directory")


@needs_cc
def test_compile_removes_the_build_folders_of_ended_compiles(small, capsys):
    left = small / ".build-999999999-xyz"
    left.mkdir()
    (left / "walk3d_full_hess_1.c").write_bytes(b"x" * 300_000)
    code, out, err = cli(capsys, "compile")
    assert code == 0, err
    assert "removed 1 build folder of an ended compile, 0.3 MB" in out and not left.exists()
