"""Ctrl-C during IPOPT stops the stage at its next iteration and surfaces as KeyboardInterrupt,
instead of being swallowed by CasADi as a failed stage."""

import signal

import numpy as np
import pytest

from walk3d.solve.progress import (
    INTERRUPT,
    IterationReporter,
    interruptible,
    raise_if_interrupted,
)


@pytest.fixture
def python_sigint():
    """Python's own Ctrl-C handler for the test: a run started as a background job of a
    non-interactive shell inherits SIGINT ignored, where :func:`interruptible` rightly leaves
    it alone."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_sigint_inside_the_block_sets_the_flag_and_raises_after_it(python_sigint):
    # raise_signal delivers to this (the main) thread at once; os.kill(getpid()) may reach
    # another thread of the process (BLAS, Dask, plots), and the handler then runs later
    with interruptible():
        signal.raise_signal(signal.SIGINT)  # no KeyboardInterrupt here
        assert INTERRUPT.requested
    with pytest.raises(KeyboardInterrupt):
        raise_if_interrupted()
    assert not INTERRUPT.requested
    raise_if_interrupted()  # nothing pending: no error
    # outside the block Ctrl-C is Python's own again
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
