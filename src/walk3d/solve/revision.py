"""The solve revision, in a module of its own so that every solve module can read it."""

SOLVE_REVISION = 17
"""Increased whenever a change makes a start of the same settings and seed run other stages or
solve another problem; recorded in each summary.json. A campaign folder records it and refuses
to resume under another revision, so that its starts stay comparable (the history of the
revisions is in docs/solver.md)."""
