"""Exceptions raised by glidectl.

Every failure a user can act on is a :class:`GlidectlError` subclass whose message says what was asked, what went
wrong and what would work instead. Nothing in glidectl returns ``None`` or NaN to signal failure.
"""

from __future__ import annotations

__all__ = [
    "ArgumentError",
    "ArgumentTypeError",
    "BudgetError",
    "DesignError",
    "GlidectlError",
    "InfeasibleGlideError",
    "ModelError",
    "OutputError",
    "RecordError",
    "SolverError",
    "VehicleFileError",
    "VehicleMismatchError",
]


class GlidectlError(Exception):
    """Base class of every error glidectl raises on purpose."""


class VehicleFileError(GlidectlError, ValueError):
    """A vehicle file or a parameter override is invalid (unknown/missing key, bad unit, non-finite value...)."""


class InfeasibleGlideError(GlidectlError, ValueError):
    """A requested steady motion does not exist for this vehicle (e.g. gamma outside the permissible set)."""


class ModelError(GlidectlError, ValueError):
    """A model was asked for something its vehicle cannot provide (e.g. moving-mass dynamics with mbar = 0)."""


class RecordError(GlidectlError, ValueError):
    """A dive record is unusable: a file that cannot be read, a missing field, non-finite values, time that does not
    increase, duplicated samples, no dive, values in the wrong unit, too few usable samples for a fit."""


class SolverError(GlidectlError, RuntimeError):
    """A numerical solver (root finder, integrator, SDP) did not converge or returned an invalid result."""


class DesignError(GlidectlError, ValueError):
    """A design file cannot be found or loaded, or does not define ``TITLE`` and ``design(progress, quick)``."""


class OutputError(GlidectlError, OSError):
    """An output folder cannot be created or written (checked before any computation starts)."""


class ArgumentError(GlidectlError, ValueError):
    """An argument has the right type but a value glidectl cannot use: NaN or infinity, out of its range, an array
    of the wrong shape, an unknown option. The message names the argument and what is accepted."""


class ArgumentTypeError(GlidectlError, TypeError):
    """An argument has the wrong type: a string, ``None``, a bool or a complex number where a real number is needed,
    a name where a Vehicle is needed. The message names the argument and the type expected."""


class VehicleMismatchError(GlidectlError, ValueError):
    """A result (glide, equilibrium, certificate) is used with a vehicle other than the one it was computed for."""


class BudgetError(GlidectlError, RuntimeError):
    """A computation hit one of its documented budgets (integration steps, right-hand-side evaluations, wall time,
    memory or program size) and stopped; the message says which and what to change."""
