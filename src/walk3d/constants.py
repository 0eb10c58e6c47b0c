"""Package-wide constants: the version and gravity (no imports, so any module may use them)."""

__version__ = "0.1.0"

G = 9.81
"""Gravitational acceleration magnitude, m/s^2. Gravity is ``(0, -G, 0)`` in the global frame."""
