"""Ctrl-C during IPOPT stops the stage at its next iteration and surfaces as KeyboardInterrupt,
instead of being swallowed by CasADi as a failed stage."""

import signal
import sys

import numpy as np
import pytest

from walk3d.solve.progress import (
    INTERRUPT,
    IterationReporter,
    interruptible,
    raise_if_interrupted,
    raises_safely,
)


@pytest.fixture
def python_sigint():
    """Python's own Ctrl-C handler for the test: a run started as a background job of a
    non-interactive shell inherits SIGINT ignored, where :func:`interruptible` rightly leaves
    it alone."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_sigint_in_walk3d_code_raises_at_once_and_in_a_callback_only_flags(python_sigint):
    """Ctrl-C in walk3d's own code inside the block raises at once; inside a CasADi callback
    (IPOPT's iteration reporter, where CasADi would swallow it) it only sets the flag, IPOPT is
    asked to stop, and the block raises as it ends. Outside the block (the control) Ctrl-C is
    Python's own."""
    # raise_signal delivers to this (the main) thread at once; os.kill(getpid()) may reach
    # another thread of the process (BLAS, Dask, plots), and the handler then runs later
    with pytest.raises(KeyboardInterrupt):
        with interruptible():
            signal.raise_signal(signal.SIGINT)
            pytest.fail("not raised at once")
    rep = IterationReporter("rep_flag_test", 2, 1)
    args = [np.zeros(2), 0.0, np.zeros(1), np.zeros(2), np.zeros(1), np.zeros(0)]
    seen = []

    def listener(*_a):
        seen.append(raises_safely(sys._getframe()))
        signal.raise_signal(signal.SIGINT)  # no KeyboardInterrupt here

    with pytest.raises(KeyboardInterrupt):
        with interruptible():
            with rep.listening(listener, np.zeros(1), np.zeros(1)):
                assert int(rep.eval(args)[0]) == 1  # IPOPT is asked to stop
            assert INTERRUPT.requested and seen == [False]
    assert not INTERRUPT.requested and raises_safely(sys._getframe())
    raise_if_interrupted()  # nothing pending: no error
    with pytest.raises(KeyboardInterrupt):
        signal.raise_signal(signal.SIGINT)


def test_the_iteration_callback_asks_ipopt_to_stop_while_an_interrupt_is_pending():
    rep = IterationReporter("rep_interrupt_test", 2, 1)
    args = [np.zeros(2), 0.0, np.zeros(1), np.zeros(2), np.zeros(1), np.zeros(0)]
    assert int(rep.eval(args)[0]) == 0
    INTERRUPT.requested = True
    try:
        assert int(rep.eval(args)[0]) == 1
    finally:
        INTERRUPT.requested = False
    assert int(rep.eval(args)[0]) == 0


def _long_build():
    """A symbolic Hessian that takes about a second: one CasADi call, which releases the GIL
    but keeps the main thread's signal handler from running until it returns."""
    import casadi as ca

    n = 70
    x = ca.SX.sym("x", n)
    e = 0
    for i in range(n):
        for j in range(n):
            e += ca.sin(x[i] * x[j] + 1e-3 * e) if (i * n + j) % 3 == 0 else ca.cos(x[i] - x[j])
    return lambda: ca.hessian(e, x)[0]


def _ctrl_c_latency(call) -> float:
    """s from a Ctrl-C sent 0.1 s into ``call()`` to its KeyboardInterrupt in this thread."""
    import threading
    import time

    sent: list[float] = []

    def send() -> None:
        sent.append(time.perf_counter())
        signal.raise_signal(signal.SIGINT)

    timer = threading.Timer(0.1, send)
    timer.start()
    try:
        call()
        time.sleep(0.5)  # the handler runs once the call has returned
    except KeyboardInterrupt:
        return time.perf_counter() - sent[0]
    finally:
        timer.join()
    pytest.fail("no KeyboardInterrupt")


def test_ctrl_c_during_a_long_symbolic_build_raises_at_once(python_sigint):
    """A build run through :func:`awaited` is interrupted within a fraction of a second; the
    same build called directly (the control) only when it returns. The abandoned build runs on
    and releases :data:`SYMBOLICS` when it ends."""
    from walk3d.solve.progress import SYMBOLICS, awaited

    build = _long_build()
    at_once = _ctrl_c_latency(lambda: awaited(build))
    with SYMBOLICS:  # the abandoned build has ended
        direct = _ctrl_c_latency(build)
    assert at_once < 0.3, at_once
    assert direct > 0.5, direct


def test_awaited_returns_the_value_and_raises_the_error():
    """The worker's result comes back, and so does its exception."""
    from walk3d.solve.progress import awaited

    assert awaited(lambda: 41 + 1) == 42
    with pytest.raises(ZeroDivisionError):
        awaited(lambda: 1 / 0)
