"""walk3d cache: shows the cache folder and its entries; --clear deletes the entries only."""

import os
import subprocess
import sys


def _cache(tmp_path, *args):
    env = os.environ | {"WALK3D_CACHE_DIR": str(tmp_path)}
    cmd = [sys.executable, "-m", "walk3d.cli", "cache", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env)


def test_cache_lists_and_clears_only_finished_entries(tmp_path):
    entries = [tmp_path / "model-abc.casadi", tmp_path / "lib-k1-walk3d_full_hess_0.so",
               tmp_path / "lib-k1-walk3d_full_jac_0.so", tmp_path / "blas-k2.so"]  # fmt: skip
    for i, path in enumerate(entries):
        path.write_bytes(b"x" * 1000 * (i + 1))
    # a compile and a write in progress, and a file that is not walk3d's
    (tmp_path / ".build-xyz").mkdir()
    (tmp_path / ".build-xyz" / "walk3d_full_hess_1.c").write_text("int f;")
    others = [tmp_path / ".model-def.casadi.0a1b.tmp", tmp_path / "notes.txt"]
    for path in others:
        path.write_text("keep")
    r = _cache(tmp_path)
    assert r.returncode == 0, r.stderr
    assert str(tmp_path) in r.stdout
    assert "1 model entries, 2 compiled libraries, 1 BLAS bridges, 0.0 MB" in r.stdout
    assert all(p.exists() for p in entries)  # listing deletes nothing
    r = _cache(tmp_path, "--clear")
    assert r.returncode == 0, r.stderr
    assert "deleted 4 files" in r.stdout
    assert not any(p.exists() for p in entries)
    assert all(p.exists() for p in others) and (tmp_path / ".build-xyz").is_dir()
    r = _cache(tmp_path)
    assert "0 model entries, 0 compiled libraries" in r.stdout


def test_cache_of_a_missing_folder_is_empty(tmp_path):
    r = _cache(tmp_path / "none", "--clear")
    assert r.returncode == 0, r.stderr
    assert "0 model entries, 0 compiled libraries" in r.stdout and "deleted 0 files" in r.stdout
    assert not (tmp_path / "none").exists()
