"""Per-iteration progress from IPOPT, through CasADi's ``iteration_callback``.

A stage solver is built once per settings and shared by every solve in a process, so the
callback object is too; a solve points it at its own listener for as long as it runs
(:meth:`IterationReporter.listening`). Without a listener or stop rule the callback does
nothing and returns 0 (go on). IPOPT's iterates do not depend on it, except where a stop rule
ends a stage.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from types import FrameType
from typing import TypeVar

import casadi as ca
import numpy as np

Listener = Callable[[int, float, float], None]
"""``listener(iteration, objective, max_constraint_violation)``."""
StopRule = Callable[[int, float, float], bool]
"""``stop(iteration, objective, max_constraint_violation)``: True stops IPOPT there (status
``User_Requested_Stop``)."""


class Terminated(KeyboardInterrupt):
    """SIGTERM (a scheduler, ``timeout``, ``kill``): stops a run as Ctrl-C does, so that its
    temporaries are removed on the way out (exit code 143 at the command line)."""


class _Interrupt:
    """Whether Ctrl-C or SIGTERM came while IPOPT was running (:func:`interruptible`)."""

    requested = False
    terminated = False
    """Whether a SIGTERM came (it stays set: the process is ending)."""
    depth = 0
    """How many :func:`interruptible` blocks are open."""


INTERRUPT = _Interrupt()


_CASADI = os.path.dirname(ca.__file__) + os.sep


def raises_safely(frame: FrameType | None) -> bool:
    """Whether an exception raised in ``frame`` propagates to walk3d: not inside a call that
    CasADi made (its bindings' argument conversion, a callback such as IPOPT's iteration
    reporter), where it would be swallowed."""
    innermost = True
    while frame is not None:
        if isinstance(frame.f_locals.get("self"), ca.Callback):
            return False
        if not innermost and frame.f_code.co_filename.startswith(_CASADI):
            return False
        innermost, frame = False, frame.f_back
    return True


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """Inside this block (a solve), SIGINT (Ctrl-C) and SIGTERM set a flag, and raise
    KeyboardInterrupt (:class:`Terminated`) at once where that is safe
    (:func:`raises_safely`). Raised inside CasADi it would be swallowed: as a failed stage
    (``NonIpopt_Exception_Thrown``) in IPOPT's callback, or silently by the argument conversion
    of CasADi's Python bindings while the model builds. There the flag alone stops IPOPT at its
    next iteration, and :func:`raise_if_interrupted` raises after the stage; the outermost
    block raises on leaving if nothing did. Outside it, in threads other than the main one, and
    where SIGINT is ignored, Ctrl-C behaves as usual."""
    main = threading.current_thread() is threading.main_thread()
    if not main or signal.getsignal(signal.SIGINT) == signal.SIG_IGN:  # e.g. a background job
        yield
        return

    def handler(signum, frame) -> None:
        INTERRUPT.requested = True
        INTERRUPT.terminated |= signum == signal.SIGTERM
        if raises_safely(frame):  # the flag stays: if this is swallowed anyway, a check raises
            raise Terminated if INTERRUPT.terminated else KeyboardInterrupt

    outermost = INTERRUPT.depth == 0
    if outermost:  # a new solve: no interrupt of an earlier one is pending
        INTERRUPT.requested = False
    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    INTERRUPT.depth += 1
    try:
        yield
    finally:
        INTERRUPT.depth -= 1
        for s, h in previous.items():
            signal.signal(s, h)
    if outermost:
        raise_if_interrupted()


T = TypeVar("T")

SYMBOLICS = threading.RLock()
"""Held while a model's symbolic functions are built (:func:`awaited`): CasADi's symbolic
operations are not thread-safe, so one build runs at a time."""
_ABANDONED: list[threading.Thread] = []


def awaited(make: Callable[[], T]) -> T:
    """``make()``, run in a worker thread while the main thread waits where Ctrl-C and SIGTERM
    raise at once. Why: a model's symbolic build is a few long CasADi calls (a node Hessian
    takes 1-4 s) that release the GIL but keep the main thread's signal handler from running
    until they return. A build left by an interrupt runs on to its end in the background
    (:func:`_join_abandoned`). Off the main thread, ``make()`` runs in the calling thread."""
    if threading.current_thread() is not threading.main_thread():
        with SYMBOLICS:
            return make()
    box: dict[str, object] = {}
    done = threading.Event()

    def work() -> None:
        try:
            with SYMBOLICS:
                box["value"] = make()
        except BaseException as exc:  # noqa: BLE001 - raised again in the waiting thread
            box["error"] = exc
        finally:
            done.set()

    worker = threading.Thread(target=work, name="walk3d-build", daemon=True)
    worker.start()
    try:
        while not done.wait(0.05):
            pass
    except BaseException:
        if not _ABANDONED:
            atexit.register(_join_abandoned)
        _ABANDONED.append(worker)
        raise
    if "error" in box:
        raise box["error"]  # type: ignore[misc]
    return box["value"]  # type: ignore[return-value]


def _join_abandoned() -> None:
    """At exit, wait for the builds that an interrupt left (:func:`awaited`, a few seconds):
    Python must not free CasADi objects under a build that still runs. A second Ctrl-C ends the
    process at once (exit code 130). (The command ends with ``os._exit`` and never waits.)"""
    try:
        for worker in _ABANDONED:
            worker.join()
    except KeyboardInterrupt:
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        os._exit(130)


def raise_if_interrupted() -> None:
    """Raise KeyboardInterrupt (:class:`Terminated` for SIGTERM) if Ctrl-C or SIGTERM came
    during the last :func:`interruptible` block."""
    if INTERRUPT.requested:
        INTERRUPT.requested = False
        raise Terminated if INTERRUPT.terminated else KeyboardInterrupt


def bound_violation(v: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """Largest violation of ``lo <= v <= hi`` (0 when inside)."""
    return float(max(np.max(lo - v, initial=0.0), np.max(v - hi, initial=0.0)))


class IterationReporter(ca.Callback):
    """CasADi callback with the inputs of ``nlpsol``'s outputs (x, f, g, lam_x, lam_g, lam_p).

    ``lbg``/``ubg`` are the row bounds used to report the largest violation of ``g``.
    """

    def __init__(self, name: str, n_x: int, n_g: int) -> None:
        ca.Callback.__init__(self)
        self._n = {"x": n_x, "lam_x": n_x, "g": n_g, "lam_g": n_g, "f": 1}
        self._listener: Listener | None = None
        self._stop: StopRule | None = None
        self._bounds: tuple[np.ndarray, np.ndarray] | None = None
        self.iteration = 0
        self.construct(name, {})

    def get_n_in(self) -> int:
        return ca.nlpsol_n_out()

    def get_n_out(self) -> int:
        return 1

    def get_name_in(self, i: int) -> str:
        return ca.nlpsol_out(i)

    def get_name_out(self, i: int) -> str:
        return "ret"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        n = self._n.get(ca.nlpsol_out(i), 0)
        return ca.Sparsity.dense(n, 1) if n else ca.Sparsity(0, 0)

    def eval(self, arg: list) -> list:
        stop = False
        if self._listener is not None or self._stop is not None:
            g = np.array(arg[2]).ravel()
            lo, hi = self._bounds if self._bounds is not None else (g, g)
            viol = bound_violation(g, lo, hi)
            if self._listener is not None:
                self._listener(self.iteration, float(arg[1]), viol)
            if self._stop is not None:
                stop = bool(self._stop(self.iteration, float(arg[1]), viol))
        self.iteration += 1
        return [1 if stop or INTERRUPT.requested else 0]  # Ctrl-C: stop IPOPT here

    @contextlib.contextmanager
    def listening(
        self,
        listener: Listener | None,
        lbg: np.ndarray,
        ubg: np.ndarray,
        stop: StopRule | None = None,
    ) -> Iterator[None]:
        """Report the iterations of the stage run inside this block to ``listener``, and stop
        it where ``stop`` says so."""
        self._listener, self._stop, self._bounds = listener, stop, (lbg, ubg)
        self.iteration = 0
        try:
            yield
        finally:
            self._listener, self._stop, self._bounds = None, None, None
