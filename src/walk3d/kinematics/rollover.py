"""The stance foot's roll-over shape, which forward kinematics follows (paper Eq. 1): a body
property, defined in :mod:`walk3d.body.rollover` and named here for the kinematics' users."""

from walk3d.body.rollover import RollOver

__all__ = ["RollOver"]
