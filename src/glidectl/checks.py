"""Argument checks shared by every public function: one wording, one exception class per failure kind.

Every public callable of glidectl checks its arguments with these functions before computing, so that a bad input
gets a :class:`~glidectl.GlidectlError` whose message names the argument, says what was received and what is
accepted:

- wrong type (``bool``, ``str``, ``None``, complex where a real number is needed): :class:`ArgumentTypeError`
  (also a :class:`TypeError`);
- a value outside its range, NaN or infinity, an array of the wrong shape: :class:`ArgumentError` (also a
  :class:`ValueError`);
- a result used with a vehicle other than the one it was computed for: :class:`VehicleMismatchError`;
- a vehicle of the wrong kind: :class:`~glidectl.ModelError`.

Real numbers are Python or numpy real scalars (0-d arrays included); ``bool`` is never a number here.

Examples
--------
>>> from glidectl.checks import real
>>> real("speed", 0.3, lo=0.0, lo_open=True, unit="m/s")
0.3
"""

from __future__ import annotations

import math
import numbers
import time
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np

from .errors import ArgumentError, ArgumentTypeError, BudgetError, ModelError, VehicleMismatchError

__all__ = [
    "Deadline",
    "array",
    "boolean",
    "choice",
    "function",
    "integer",
    "nonnegative",
    "numeric",
    "positive",
    "real",
    "same_vehicle",
    "vehicle",
]


def _unit(unit: str) -> str:
    return f" {unit}" if unit else ""


def _is_real_scalar(value: Any) -> bool:
    if isinstance(value, bool | np.bool_):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and value.dtype.kind in "iuf"
    return isinstance(value, numbers.Real)


def real(name: str, value: Any, *, lo: float | None = None, hi: float | None = None, lo_open: bool = False,
         hi_open: bool = False, allow_inf: bool = False, unit: str = "") -> float:
    """``float(value)`` for a real number within ``[lo, hi]`` (open ends on request); a clear error otherwise.

    Parameters
    ----------
    name : str
        The argument's name, used in the message.
    value : Any
        What the caller passed.
    lo, hi : float, optional
        Bounds (inclusive unless ``lo_open`` / ``hi_open``); ``None`` means unbounded.
    lo_open, hi_open : bool
        Make the bound strict.
    allow_inf : bool
        Accept ``+-inf`` (NaN is never accepted).
    unit : str
        Unit printed after the bounds in the message (e.g. ``"m/s"``).

    Returns
    -------
    float
        The value as a Python float.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number (``bool``, ``str``, ``None``, complex, arrays of size > 1).
    ArgumentError
        If it is NaN, infinite (unless ``allow_inf``) or outside the bounds.
    """
    if not _is_real_scalar(value):
        raise ArgumentTypeError(f"{name} must be a real number{' in ' + unit if unit else ''}, got "
                                f"{type(value).__name__} {value!r}")
    v = float(value)
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise ArgumentError(f"{name} must be a finite number{' in ' + unit if unit else ''}, got {v!r}")
    below = lo is not None and (v <= lo if lo_open else v < lo)
    above = hi is not None and (v >= hi if hi_open else v > hi)
    if below or above:
        left = "-inf" if lo is None else f"{lo:g}"
        right = "inf" if hi is None else f"{hi:g}"
        rng = f"{'(' if lo_open or lo is None else '['}{left}, {right}{')' if hi_open or hi is None else ']'}"
        raise ArgumentError(f"{name} must lie in {rng}{_unit(unit)}, got {v!r}")
    return v


def positive(name: str, value: Any, *, allow_inf: bool = False, unit: str = "") -> float:
    """A real number > 0 (see :func:`real`).

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.
    allow_inf : bool
        Accept ``+inf``.
    unit : str
        Unit for the message.

    Returns
    -------
    float
        The value.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number.
    ArgumentError
        If it is not > 0, or not finite (unless ``allow_inf``).
    """
    return real(name, value, lo=0.0, lo_open=True, allow_inf=allow_inf, unit=unit)


def nonnegative(name: str, value: Any, *, unit: str = "") -> float:
    """A finite real number >= 0 (see :func:`real`).

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.
    unit : str
        Unit for the message.

    Returns
    -------
    float
        The value.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number.
    ArgumentError
        If it is negative or not finite.
    """
    return real(name, value, lo=0.0, unit=unit)


def integer(name: str, value: Any, *, lo: int | None = None, hi: int | None = None) -> int:
    """An integer (Python or numpy; a float with an integral value is refused) within ``[lo, hi]``.

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.
    lo, hi : int, optional
        Inclusive bounds.

    Returns
    -------
    int
        The value.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not an integer (``bool``, ``float``, ``str``, ``None``...).
    ArgumentError
        If it is outside ``[lo, hi]``.
    """
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
        raise ArgumentTypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    v = int(value)
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise ArgumentError(f"{name} must be an integer in [{'-inf' if lo is None else lo}, "
                            f"{'inf' if hi is None else hi}], got {v}")
    return v


def boolean(name: str, value: Any) -> bool:
    """A ``bool`` (or numpy bool).

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.

    Returns
    -------
    bool
        The value.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a boolean (``0``/``1`` and strings are refused).
    """
    if not isinstance(value, bool | np.bool_):
        raise ArgumentTypeError(f"{name} must be True or False, got {type(value).__name__} {value!r}")
    return bool(value)


def choice(name: str, value: Any, options: Iterable[Any]) -> Any:
    """One of ``options``.

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.
    options : iterable
        The accepted values.

    Returns
    -------
    Any
        The value.

    Raises
    ------
    ArgumentError
        If ``value`` is not one of ``options`` (the message lists them).
    """
    opts = list(options)
    try:
        ok = value in opts
    except TypeError:  # unhashable or incomparable
        ok = False
    if not ok:
        raise ArgumentError(f"{name} must be one of {', '.join(repr(o) for o in opts)}; got {value!r}")
    return value


def numeric(name: str, value: Any) -> np.ndarray:
    """``np.asarray(value)`` for a number or an array of real or complex numbers, any shape (the inputs of
    vectorized, complex-step-safe model functions); no finiteness check.

    Parameters
    ----------
    name : str
        The argument's name, used in the message.
    value : Any
        What the caller passed.

    Returns
    -------
    ndarray

    Raises
    ------
    ArgumentTypeError
        If ``value`` is None, a string, ragged, or holds booleans or objects.
    """
    if value is None or isinstance(value, str | bytes):
        raise ArgumentTypeError(f"{name} must be a number or an array of numbers, got {type(value).__name__} "
                                f"{value!r}")
    try:
        a = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise ArgumentTypeError(f"{name} must be a number or an array of numbers: {exc}") from exc
    if a.dtype.kind not in "iufc":
        raise ArgumentTypeError(f"{name} must hold numbers, got {type(value).__name__} of dtype {a.dtype}")
    return a


def array(name: str, value: Any, *, shape: Sequence[int | None] | None = None, ndim: int | None = None,
          finite: bool = True, min_size: int = 0, allow_complex: bool = False) -> np.ndarray:
    """A real float array of the given shape (``None`` in ``shape`` matches any length).

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed (array_like).
    shape : sequence of int or None, optional
        Required shape; ``None`` entries match any length.
    ndim : int, optional
        Required number of dimensions (when ``shape`` is not given).
    finite : bool
        Refuse NaN and infinities.
    min_size : int
        Smallest number of elements.
    allow_complex : bool
        Accept complex arrays (functions that are differentiated by complex steps must); they keep their dtype.

    Returns
    -------
    ndarray
        ``np.asarray(value, dtype=float)`` (a copy when needed), or the complex array when ``allow_complex``.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is ``None``, a string, or does not convert to a real array (complex, objects, ragged lists).
    ArgumentError
        If the shape, size or finiteness is wrong.
    """
    if value is None or isinstance(value, str | bytes):
        raise ArgumentTypeError(f"{name} must be an array of real numbers, got {type(value).__name__} {value!r}")
    if allow_complex and np.iscomplexobj(value):
        arr = np.asarray(value)
        if arr.dtype.kind != "c":
            raise ArgumentTypeError(f"{name} must hold numbers, got an array of dtype {arr.dtype}")
        return _shape_checked(name, value, arr, shape, ndim, finite, min_size)
    if isinstance(value, np.ndarray) and value.dtype.kind in "cbOUS":
        raise ArgumentTypeError(f"{name} must hold real numbers, got an array of dtype {value.dtype}")
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArgumentTypeError(f"{name} must be an array of real numbers: {exc}") from exc
    return _shape_checked(name, value, arr, shape, ndim, finite, min_size)


def _shape_checked(name: str, value: Any, arr: np.ndarray, shape: Sequence[int | None] | None, ndim: int | None,
                   finite: bool, min_size: int) -> np.ndarray:
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == a for s, a in zip(shape, arr.shape, strict=False))
        if not ok:
            want = "(" + ", ".join("N" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
            raise ArgumentError(f"{name} must have shape {want}, got {arr.shape}")
    elif ndim is not None and arr.ndim != ndim:
        raise ArgumentError(f"{name} must have {ndim} dimension(s), got shape {arr.shape}")
    if arr.size < min_size:
        raise ArgumentError(f"{name} must have at least {min_size} element(s), got {arr.size}")
    if finite and not np.all(np.isfinite(arr)):
        raise ArgumentError(f"{name} must be finite (no NaN or inf), got {value!r}")
    return arr


def function(name: str, value: Any) -> Callable[..., Any]:
    """A callable.

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.

    Returns
    -------
    callable
        The value.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not callable.
    """
    if not callable(value):
        raise ArgumentTypeError(f"{name} must be callable, got {type(value).__name__} {value!r}")
    return value


def vehicle(name: str, value: Any, kind: str | Sequence[str] | None = None) -> Any:
    """A :class:`~glidectl.Vehicle`, optionally of a given ``kind``.

    Parameters
    ----------
    name : str
        The argument's name.
    value : Any
        What the caller passed.
    kind : str or sequence of str, optional
        Accepted vehicle kinds (``"underwater_glider"``, ``"ctol"``).

    Returns
    -------
    Vehicle
        The vehicle.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a Vehicle (for example a preset name: load it with ``gc.load_vehicle`` first).
    ModelError
        If the vehicle is of another kind.
    """
    from .params import Vehicle

    if not isinstance(value, Vehicle):
        hint = f" (load it first: gc.load_vehicle({value!r}))" if isinstance(value, str) else ""
        raise ArgumentTypeError(f"{name} must be a glidectl Vehicle, got {type(value).__name__}{hint}")
    kinds = (kind,) if isinstance(kind, str) else tuple(kind or ())
    if kinds and value.kind not in kinds:
        wanted = " or ".join(_KIND_NAMES.get(k, f"a '{k}' vehicle") for k in kinds)
        raise ModelError(f"{name} '{value.name}' is of kind '{value.kind}', not {wanted}")
    return value


#: Readable names of the vehicle kinds, for messages.
_KIND_NAMES = {"underwater_glider": "an underwater glider", "ctol": 'a CTOL aircraft (kind = "ctol")'}


def same_vehicle(what: str, result: Any, veh: Any) -> None:
    """Refuse a result (glide, equilibrium, certificate) used with a vehicle other than the one it came from.

    Parameters
    ----------
    what : str
        Name of the result argument, for the message.
    result : Any
        An object with ``provenance`` (str) and ``vehicle`` (Vehicle) as in the naming table.
    veh : Vehicle
        The vehicle it is used with.

    Raises
    ------
    VehicleMismatchError
        If the provenance hashes differ.
    """
    prov = getattr(result, "provenance", None)
    if isinstance(prov, str) and prov and prov != veh.provenance:
        origin = getattr(getattr(result, "vehicle", None), "name", "another vehicle")
        raise VehicleMismatchError(f"{what} was computed for vehicle '{origin}' (provenance {prov}), not for "
                                   f"'{veh.name}' (provenance {veh.provenance}); recompute it for this vehicle")


class Deadline:
    """A wall-time budget: ``check()`` raises :class:`BudgetError` once ``limit`` seconds have passed.

    Parameters
    ----------
    limit : float or None
        Seconds allowed (``None``: no limit).
    what : str
        What is being timed, for the message.
    """

    def __init__(self, limit: float | None, what: str) -> None:
        self.limit = None if limit is None else positive("time_limit", limit, unit="s")
        self.what = what
        self.start = time.perf_counter()

    @property
    def elapsed(self) -> float:
        """Seconds since the deadline was set."""
        return time.perf_counter() - self.start

    def check(self, detail: str = "") -> None:
        """Raise :class:`BudgetError` when the time is up.

        Parameters
        ----------
        detail : str
            Where the computation was (for the message).

        Raises
        ------
        BudgetError
            If more than ``limit`` seconds have passed.
        """
        if self.limit is not None and self.elapsed > self.limit:
            at = f" ({detail})" if detail else ""
            raise BudgetError(f"{self.what} stopped at its time limit of {self.limit:g} s{at}; raise time_limit "
                              "or ask for less")
