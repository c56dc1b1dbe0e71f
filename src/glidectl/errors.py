"""Exceptions raised by glidectl.

Every failure a user can act on is a :class:`GlidectlError` subclass whose message says what was asked, what went
wrong and what would work instead. Nothing in glidectl returns ``None`` or NaN to signal failure.
"""

from __future__ import annotations

__all__ = [
    "DesignError",
    "GlidectlError",
    "InfeasibleGlideError",
    "ModelError",
    "OutputError",
    "SolverError",
    "VehicleFileError",
]


class GlidectlError(Exception):
    """Base class of every error glidectl raises on purpose."""


class VehicleFileError(GlidectlError, ValueError):
    """A vehicle file or a parameter override is invalid (unknown/missing key, bad unit, non-finite value...)."""


class InfeasibleGlideError(GlidectlError, ValueError):
    """A requested steady motion does not exist for this vehicle (e.g. gamma outside the permissible set)."""


class ModelError(GlidectlError, ValueError):
    """A model was asked for something its vehicle cannot provide (e.g. moving-mass dynamics with mbar = 0)."""


class SolverError(GlidectlError, RuntimeError):
    """A numerical solver (root finder, integrator, SDP) did not converge or returned an invalid result."""


class DesignError(GlidectlError, ValueError):
    """A design file cannot be found or loaded, or does not define ``TITLE`` and ``design(progress, quick)``."""


class OutputError(GlidectlError, OSError):
    """An output folder cannot be created or written (checked before any computation starts)."""
