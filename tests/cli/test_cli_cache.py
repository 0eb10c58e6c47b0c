"""walk3d cache: shows the cache folder and its entries; --clear deletes the entries only."""

import os
import subprocess
import sys


def _cache(tmp_path, *args):
    env = os.environ | {"WALK3D_CACHE_DIR": str(tmp_path)}
    cmd = [sys.executable, "-m", "walk3d.cli", "cache", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env)


K1, K2, M = "1" * 32, "2" * 24, "a" * 32
"""Key digests as walk3d writes them (hex, 32 or 24 digits)."""


def test_cache_lists_and_clears_only_finished_entries(tmp_path):
    entries = [tmp_path / f"model-{M}-node.casadi", tmp_path / f"lib-{K1}-walk3d_full_hess_0.so",
               tmp_path / f"lib-{K1}-walk3d_full_jac_0.so", tmp_path / f"blas-{K2}.so"]  # fmt: skip
    for i, path in enumerate(entries):
        path.write_bytes(b"x" * 1000 * (i + 1))
    # a write in progress, files that are not walk3d's (a user's folder named by
    # $WALK3D_CACHE_DIR: they were deleted), and a running build (its pid this test's)
    others = [tmp_path / ".model-def.casadi.0a1b.tmp", tmp_path / "notes.txt",
              tmp_path / "lib-mine.so", tmp_path / "model-thesis.casadi"]  # fmt: skip
    (tmp_path / ".build-mine").mkdir()
    (tmp_path / ".build-mine" / "thesis.tex").write_text("keep")
    for path in others:
        path.write_text("keep")
    running = _build_folder(tmp_path, f".build-{os.getpid()}-abc", 1000)
    r = _cache(tmp_path)
    assert r.returncode == 0, r.stderr
    assert str(tmp_path) in r.stdout
    assert "1 model entries, 2 compiled libraries, 1 BLAS bridges, 0.0 MB" in r.stdout
    assert "1 build folder of a build in progress, 0.0 MB" in r.stdout
    assert all(p.exists() for p in entries)  # listing deletes nothing
    r = _cache(tmp_path, "--clear")
    assert r.returncode == 0, r.stderr
    assert "deleted 4 files" in r.stdout
    assert not any(p.exists() for p in entries)
    assert all(p.exists() for p in others) and running.is_dir()
    assert (tmp_path / ".build-mine" / "thesis.tex").exists()
    r = _cache(tmp_path)
    assert "0 model entries, 0 compiled libraries" in r.stdout


def test_cache_of_a_missing_folder_is_empty(tmp_path):
    r = _cache(tmp_path / "none", "--clear")
    assert r.returncode == 0, r.stderr
    assert "0 model entries, 0 compiled libraries" in r.stdout and "deleted 0 files" in r.stdout
    assert not (tmp_path / "none").exists()


def _build_folder(cache, name: str, size: int):
    folder = cache / name
    folder.mkdir()
    (folder / "walk3d_full_hess_1.c").write_bytes(b"x" * size)
    return folder


def test_cache_reports_and_clears_the_build_folders_of_ended_compiles(tmp_path):
    """A killed compile left 68 MB of .build-* folders that --clear neither reported nor
    removed."""
    left = [_build_folder(tmp_path, ".build-999999999-xyz", 2_000_000),
            _build_folder(tmp_path, ".build-999999999-abc", 1_000_000)]  # fmt: skip
    r = _cache(tmp_path)
    assert r.returncode == 0, r.stderr
    assert "2 build folders left by ended compiles, 3.0 MB (--clear removes them)" in r.stdout
    assert all(f.is_dir() for f in left)
    r = _cache(tmp_path, "--clear")
    assert r.returncode == 0, r.stderr
    assert "deleted 0 files, 0.0 MB, and 2 build folders of ended compiles, 3.0 MB" in r.stdout
    assert not any(f.exists() for f in left)
    assert "build folders" not in _cache(tmp_path).stdout


HOLD = """
import sys, time
from pathlib import Path
from walk3d.cli.background import hold
with hold(Path(sys.argv[1]), wait=False) as held:
    print(held, flush=True)
    time.sleep(60)
"""


def test_cache_clear_keeps_the_build_folders_while_a_compile_holds_the_lock(tmp_path):
    """Negative control: the folders of a compile on another machine sharing the cache (its
    pid unknown here) stay while it runs, and go once it has ended."""
    folder = _build_folder(tmp_path, ".build-999999999-abc", 1_000_000)
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(tmp_path / "compile.lock")],
                              stdout=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert holder.stdout.readline().strip() == "True"
        r = _cache(tmp_path, "--clear")
    finally:
        holder.kill()
        holder.wait()
    assert r.returncode == 0, r.stderr
    assert "1 build folder of a compile in progress, 1.0 MB (kept)" in r.stdout
    assert "deleted 0 files, 0.0 MB\n" in r.stdout and folder.is_dir()
    assert "1 build folder of ended compiles" in _cache(tmp_path, "--clear").stdout
    assert not folder.exists()


def test_cache_clear_with_a_lock_that_is_a_folder_is_one_line(tmp_path):
    """The lock cannot be taken: the build folders stay, with a line that says why."""
    folder = _build_folder(tmp_path, ".build-999999999-xyz", 1000)
    (tmp_path / "compile.lock").mkdir()
    r = _cache(tmp_path, "--clear")
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert "build folders kept: the compile lock" in r.stdout and folder.is_dir()


def test_cache_clear_removes_a_folder_in_an_entrys_place(tmp_path):
    """A damaged cache where a library's name is a folder: --clear removes it with the rest
    (it was a traceback, after deleting the other entries)."""
    lib = tmp_path / f"lib-{K1}-walk3d_full_jac_3.so"
    (lib / "inner").mkdir(parents=True)
    (tmp_path / f"lib-{K1}-walk3d_full_jac_3.so.sha256").write_text("0" * 64)
    r = _cache(tmp_path, "--clear")
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert sorted(tmp_path.iterdir()) == []


def test_a_cache_path_that_is_a_file_is_said_so(tmp_path):
    """Was "0 model entries" and exit 0, for --clear too."""
    path = tmp_path / "afile"
    path.write_text("mine")
    r = _cache(path)
    assert r.returncode == 0 and "entries" not in r.stdout, r.stdout
    assert r.stderr == f"walk3d: warning: the model cache {path} is not a folder: walk3d runs " \
        "without the cache\n"  # fmt: skip
    r = _cache(path, "--clear")
    assert r.returncode == 2 and r.stderr.startswith("walk3d: error: the model cache"), r.stderr
    assert "not a folder: nothing to clear" in r.stderr and len(r.stderr.splitlines()) == 1
    assert path.read_text() == "mine"
    r = _cache(tmp_path)  # control: a folder is listed, without a warning
    assert r.returncode == 0 and "0 model entries" in r.stdout and r.stderr == ""


def test_a_cache_path_below_a_file_is_said_so(tmp_path):
    """WALK3D_CACHE_DIR=file/sub: was "0 model entries", and --clear "deleted 0 files" exit 0;
    said as for the file itself. Control: a missing folder below a folder is empty."""
    path = tmp_path / "afile"
    path.write_text("mine")
    r = _cache(path / "sub" / "deeper")
    assert r.returncode == 0 and "entries" not in r.stdout, r.stdout
    assert r.stderr == f"walk3d: warning: the model cache {path / 'sub' / 'deeper'} is not a " \
        f"folder ({path} is a file): walk3d runs without the cache\n"  # fmt: skip
    r = _cache(path / "sub", "--clear")
    assert r.returncode == 2 and "nothing to clear" in r.stderr, r.stderr
    assert len(r.stderr.splitlines()) == 1 and path.read_text() == "mine"
    r = _cache(tmp_path / "dir" / "sub")
    assert r.returncode == 0 and "0 model entries" in r.stdout and r.stderr == ""
