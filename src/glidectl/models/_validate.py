"""Argument checks shared by the models and the controllers: vehicle kind, result types and the state and input
arrays of right-hand sides.

Right-hand sides accept batches (``x[..., n]``) and complex values (complex-step Jacobians), so their arrays are
checked for a numeric dtype and the trailing dimension only (cheap enough for every call); finiteness of a state is
the integrator's business (:func:`glidectl.sim.simulate` refuses non-finite states). Everything else uses
:mod:`glidectl.checks`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError
from ..params import Vehicle

__all__ = ["SPEED_MAX", "angle_arg", "numeric_array", "require_ctol_vehicle", "require_glider",
           "require_instance", "single_real_state", "speed_arg", "trailing_array"]

#: Largest speed (m/s; normalized units for the CTOL aircraft) accepted as an argument: a plausibility limit.
SPEED_MAX = 100.0


def require_glider(veh: Any, name: str = "vehicle") -> Vehicle:
    """``veh`` if it is an underwater glider.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a :class:`~glidectl.Vehicle`.
    ModelError
        If it is a vehicle of another kind.
    """
    return checks.vehicle(name, veh, "underwater_glider")


def require_ctol_vehicle(veh: Any, name: str = "vehicle") -> Vehicle:
    """``veh`` if it is a CTOL aircraft.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a :class:`~glidectl.Vehicle`.
    ModelError
        If it is a vehicle of another kind.
    """
    return checks.vehicle(name, veh, "ctol")


def require_instance(name: str, value: Any, cls: type | tuple[type, ...], hint: str = "") -> Any:
    """``value`` if it is an instance of ``cls``.

    Raises
    ------
    ArgumentTypeError
        Otherwise (the message names the expected class and ``hint``, e.g. the function that makes one).
    """
    if not isinstance(value, cls):
        want = " or ".join(c.__name__ for c in (cls if isinstance(cls, tuple) else (cls,)))
        article = "an" if want[0] in "AEIOU" else "a"
        raise ArgumentTypeError(f"{name} must be {article} {want}{hint}, got {type(value).__name__}")
    return value


def numeric_array(name: str, value: Any) -> np.ndarray:
    """``np.asarray(value)`` for an array of real or complex numbers (any shape): :func:`glidectl.checks.numeric`.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is None, a string, ragged, or holds booleans or objects.
    """
    return checks.numeric(name, value)


def trailing_array(name: str, value: Any, n: int, names: tuple[str, ...] = ()) -> np.ndarray:
    """``np.asarray(value)`` for a (batch of) vector(s) of length ``n`` along the last axis (real or complex).

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not an array of numbers.
    ArgumentError
        If its last dimension is not ``n``.
    """
    if type(value) is np.ndarray and value.dtype.kind in "fc" and value.ndim and value.shape[-1] == n:
        return value  # already a float or complex array of the right width (what numeric_array would return)
    a = numeric_array(name, value)
    if a.ndim == 0 or a.shape[-1] != n:
        what = f" {tuple(names)}" if names else ""
        raise ArgumentError(f"{name} must have a trailing dimension {n}{what}, got shape {a.shape}")
    return a


def single_real_state(a: np.ndarray, b: np.ndarray | None = None) -> bool:
    """True when ``a`` (and ``b``), arrays from :func:`trailing_array`, are one real state: one-dimensional float
    arrays (the calls of a simulation). A right-hand side may then take numpy-scalar columns ``a[i]``: the same IEEE
    operations as a batch row, only cheaper (no 0-d arrays, no broadcasting). Anything else (batches, complex steps,
    integers) keeps the column views ``a[..., i]``; a single complex state in particular keeps its arithmetic to the
    last bit (numpy's scalar complex division rounds differently from its array loop).

    Returns
    -------
    bool
        Whether the fast single-state path applies.
    """
    return a.ndim == 1 and a.dtype.kind == "f" and (b is None or (b.ndim == 1 and b.dtype.kind == "f"))


def speed_arg(name: str, value: Any, unit: str = "m/s") -> float:
    """A speed in ``(0, SPEED_MAX]``.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number.
    ArgumentError
        If it is not finite or outside ``(0, SPEED_MAX]``.
    """
    return checks.real(name, value, lo=0.0, lo_open=True, hi=SPEED_MAX, unit=unit)


def angle_arg(name: str, value: Any, limit: float | None = None, *, open_ends: bool = False) -> float:
    """A finite angle (rad), optionally with ``|value| <= limit`` (``< limit`` with ``open_ends``).

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number.
    ArgumentError
        If it is not finite or outside the limits.
    """
    if limit is None:
        return checks.real(name, value, unit="rad")
    return checks.real(name, value, lo=-limit, hi=limit, lo_open=open_ends, hi_open=open_ends, unit="rad")
