"""``walk3d cache [--clear]``: the model cache folder, what it holds, and clearing it."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Annotated

import typer

from walk3d.cli.common import app, console, fail


@app.command(name="cache", short_help="Show the model cache, or clear it.")
def cache_info(
    clear: Annotated[
        bool,
        typer.Option(
            "--clear",
            help="Delete every cached model, compiled library and BLAS bridge, and the build "
            "folders that ended compiles left.",
        ),
    ] = False,
) -> None:
    """Show the model cache folder ($WALK3D_CACHE_DIR, else the user cache folder) and what it
    holds; with --clear, delete its entries (always safe: they are rebuilt, or recompiled with
    walk3d compile, when needed) and the build folders of compiles that were killed (those of
    a compile in progress are kept)."""
    from walk3d.cli import background
    from walk3d.solve import compiled, model_cache

    problem = model_cache.not_a_folder()
    if problem is not None and clear:
        fail(f"{problem}: nothing to clear (set {model_cache.ENV_DIR} to a folder)")
    state = "" if model_cache.cache_enabled() else " (off: WALK3D_CACHE)"
    console.print(f"walk3d cache: {model_cache.cache_dir()}{state}", markup=False, highlight=False)
    if problem is not None:  # as predict says it
        sys.stderr.write(f"walk3d: warning: {problem}: walk3d runs without the cache\n")
        return
    use = model_cache.cache_usage()
    console.print(f"{use['models']} model entries, {use['libraries']} compiled libraries, "
                  f"{use['bridges']} BLAS bridges, {use['bytes'] / 1e6:.1f} MB")  # fmt: skip
    compiling = background.running(background.lock_path())
    builds = compiled.build_folders()
    left = [] if compiling else compiled.leftover_builds()
    busy = [f for f in builds if f not in left]
    if busy:
        what = "a compile" if compiling else "a build"
        console.print(f"{_folders(len(busy))} of {what} in progress, {_mb(busy)} MB"
                      + (" (kept)" if clear else ""))  # fmt: skip
    if left and not clear:
        console.print(f"{_folders(len(left))} left by ended compiles, {_mb(left)} MB "
                      "(--clear removes them)")  # fmt: skip
    if clear:
        files, freed = model_cache.clear_entries()
        folders, size = _clear_builds() if left else (0, 0)
        builds_part = f", and {_folders(folders)} of ended compiles, {size / 1e6:.1f} MB"
        console.print(f"deleted {files} files, {freed / 1e6:.1f} MB"
                      + (builds_part if folders else ""))  # fmt: skip


def _folders(n: int) -> str:
    return f"{n} build folder{'' if n == 1 else 's'}"


def _mb(folders: list[Path]) -> str:
    from walk3d.solve.compiled import folder_bytes

    return f"{sum(folder_bytes(f) for f in folders) / 1e6:.1f}"


def _clear_builds() -> tuple[int, int]:
    """Delete the build folders of ended compiles, holding the compile lock so that no compile
    starts meanwhile: ``(folders, bytes)``; none while a compile holds it."""
    from walk3d.cli import background
    from walk3d.solve import compiled

    try:
        with background.hold(background.lock_path(), wait=False) as held:
            return compiled.remove_leftover_builds() if held else (0, 0)
    except OSError as exc:  # a lock that is a folder, or not ours to open
        why = (exc.strerror or str(exc)).lower()
        console.print(f"build folders kept: the compile lock {background.lock_path()} cannot be "
                      f"taken ({why})", markup=False, highlight=False)  # fmt: skip
        return 0, 0
