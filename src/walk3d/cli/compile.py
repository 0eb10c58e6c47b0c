"""Compiling the solver's derivatives (``walk3d compile``, and before a large ``walk3d campaign``).

Compiling takes several minutes on 2 cores, once per sex and criterion, and makes each solve
about twice as fast (docs/solver.md, "Compiled derivatives"), so a campaign compiles first
when it has enough starts to run (:data:`COMPILE_FROM_STARTS`). The libraries go to the
model cache, where every worker process, and every later ``walk3d predict`` with the same sex
and criterion (any mass and stature: :mod:`walk3d.problem.similarity`), finds them.
"""

from __future__ import annotations

import logging
import sys
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from walk3d.cli.common import EXIT_WRITE, fail
from walk3d.problem.settings import PredictionSettings
from walk3d.solve import compiled
from walk3d.solve.solver import compile_solver, compiled_status

COMPILE_FROM_STARTS = 30
"""Starts to run from which a campaign compiles by default. Why 30: compiling costs minutes,
once, and halves every start's solve time, so a campaign of 30 starts gains from it."""


def worth_compiling(starts: int) -> bool:
    """Whether a campaign of ``starts`` starts to run compiles by default (a compiler found)."""
    return starts >= COMPILE_FROM_STARTS and compiled.compiler() is not None


def compile_with_progress(settings: PredictionSettings, console: Console) -> None:
    """Compile (or find compiled) the derivatives of ``settings``, with a progress bar; a
    missing or failing compiler ends the command with one line and exit code 2, a cache folder
    that cannot be written (a full disk, a lock that is a folder) with one line and exit code
    3. Holds the background compile's lock (:mod:`walk3d.cli.background`), waiting for a
    running one, and first removes the build folders of ended compiles. The solver's log
    warnings are printed after a compile that ends, once each, and not after one that fails."""
    try:
        compiled.require_compiler()  # before any model work
    except compiled.CompileError as exc:
        fail(f"walk3d compile: {exc}")
    with _held_warnings() as held:
        info = _compile_held(settings, console)
    for line in dict.fromkeys(held):
        sys.stderr.write(f"walk3d: warning: {line}\n")
    console.print(
        "walk3d compile: already compiled (model cache)" if info is None else
        f"walk3d compile: {info['compiled']} libraries in {info['wall_time_s']:.0f} s, "
        f"kept in {compiled.cache_dir()}"
    )  # fmt: skip


@contextmanager
def _held_warnings() -> Iterator[list[str]]:
    """The solver modules' log warnings of the block (a model cache entry that could not be
    written...), held instead of printed: a compile that fails prints its one error line alone
    (on a full disk each entry's write warns first), one that ends prints each once."""
    held: list[str] = []

    class Hold(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            held.append(" ".join(record.getMessage().split()))

    logger, handler = logging.getLogger("walk3d.solve"), Hold(logging.WARNING)
    propagate, logger.propagate = logger.propagate, False
    logger.addHandler(handler)
    try:
        yield held
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate


def _compile_held(settings: PredictionSettings, console: Console) -> dict | None:
    """The compile under the background compile's lock (:func:`compile_with_progress`)."""
    from walk3d.cli import background

    lock = background.lock_path()
    try:
        with ExitStack() as stack:
            if background.running(lock):
                with console.status("walk3d compile: waiting for the background compile"):
                    stack.enter_context(background.hold(lock, wait=True))
            else:
                stack.enter_context(background.hold(lock, wait=True))
            folders, size = compiled.remove_leftover_builds()
            if folders:
                plural = "" if folders == 1 else "s"
                console.print(f"walk3d compile: removed {folders} build folder{plural} of an "
                              f"ended compile, {size / 1e6:.1f} MB")  # fmt: skip
            info = _compile(settings, console)
        background.clear_failed()
    except OSError as exc:
        where = exc.filename or compiled.cache_dir()
        why = (exc.strerror or str(exc)).lower()
        fail(f"walk3d compile: could not write {where}: {why}", code=EXIT_WRITE)
    return info


def _compile(settings: PredictionSettings, console: Console) -> dict | None:
    """The compile with a progress bar; None when there was nothing to compile."""
    missing = compiled_status(settings)["missing"]
    if not missing:
        return None
    columns = (TextColumn("compiling derivatives to C"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn(), TextColumn("{task.description}"))  # fmt: skip
    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task("", total=missing)

        def done(name: str, _i: int, _n: int) -> None:
            bar.update(task, advance=1, description=name)

        try:
            return compile_solver(settings, on_done=done)
        except compiled.CompileError as exc:  # the compiler's own full disk is exit 3 too
            full = "no space left on device" in str(exc).lower()
            fail(f"walk3d compile: {exc}", code=EXIT_WRITE if full else 2)
