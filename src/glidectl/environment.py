"""The water a glider flies in: currents.

A :class:`Current` gives the horizontal water velocity at a time and a place. Positions and velocities at this
interface are **(east, north, depth)** and **(east, north)** (m, m/s), the way a mission is planned; the models'
inertial frame is north-east-down (x north, y east, z down), and :meth:`Current.velocity` returns the velocity in
that frame for the right-hand sides. The water density is the vehicle file's (``Vehicle.water_density``).

Three kinds:

* uniform: ``Current.uniform(east, north)``, or a pair ``(east, north)`` wherever a current is accepted;
* a depth profile: ``Current.profile(depths, east, north)``, linear between the tabulated depths and constant
  beyond the ends (a table from an ADCP cast or a model);
* any callable ``f(t, position) -> (east, north)`` of the time (s) and the position ``(east, north, depth)`` (m):
  ``Current.field(f)``, or the callable itself;
* a gridded field (an ocean model's or an HF-radar product's): ``Current.gridded(east, north, u, v, times=None)``
  on a rectangular grid, linear in space (and time) and constant beyond the grid's edges, or
  ``Current.from_dataset(ds, u="u", v="v")`` from an ``xarray.Dataset`` with coordinates ``east``, ``north`` (m)
  and optionally ``time`` (s).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import checks
from .errors import ArgumentError, ArgumentTypeError

__all__ = ["CURRENT_MAX", "Current", "as_current"]

#: Largest current speed accepted (m/s): faster than any ocean current (the Gulf Stream peaks near 2.5 m/s).
CURRENT_MAX = 5.0


def _speed_checked(name: str, east: Any, north: Any) -> tuple[np.ndarray, np.ndarray]:
    e = checks.array(f"{name} east component", east)
    n = checks.array(f"{name} north component", north)
    if e.shape != n.shape:
        raise ArgumentError(f"{name}: east and north components must have the same shape, got {e.shape} and "
                            f"{n.shape}")
    speed = np.hypot(e, n)
    if np.any(speed > CURRENT_MAX):
        raise ArgumentError(f"{name}: a current of {float(np.max(speed)):.3g} m/s is faster than any ocean current "
                            f"(CURRENT_MAX = {CURRENT_MAX:g} m/s); give the velocity in m/s")
    return e, n


@dataclass(frozen=True)
class Current:
    """Horizontal water velocity as a function of time and position (module docstring).

    Build one with :meth:`uniform`, :meth:`profile` or :meth:`field`.

    Attributes
    ----------
    kind : str
        ``"uniform"``, ``"profile"`` or ``"field"``.
    east, north : ndarray
        Uniform: the two components (m/s, 0-d arrays); profile: the components at ``depths``.
    depths : ndarray
        Profile: the tabulated depths (m, increasing); empty otherwise.
    function : callable or None
        Field: the user's ``f(t, (east, north, depth)) -> (east, north)``.
    """

    kind: str
    east: np.ndarray = field(default_factory=lambda: np.zeros(()), compare=False)
    north: np.ndarray = field(default_factory=lambda: np.zeros(()), compare=False)
    depths: np.ndarray = field(default_factory=lambda: np.zeros(0), compare=False)
    function: Callable[[float, np.ndarray], Any] | None = None
    _gridded_in_time: bool | None = field(default=None, repr=False)
    _ned: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        ned = np.array([float(self.north), float(self.east), 0.0]) if self.kind == "uniform" else np.zeros(3)
        object.__setattr__(self, "_ned", ned)

    @classmethod
    def uniform(cls, east: float, north: float) -> Current:
        """A current that is the same everywhere and always: ``(east, north)`` (m/s).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If a component is not a finite real number, or the speed exceeds :data:`CURRENT_MAX`.
        """
        e = checks.real("current east component", east, unit="m/s")
        n = checks.real("current north component", north, unit="m/s")
        _speed_checked("current", e, n)
        return cls("uniform", np.asarray(e), np.asarray(n))

    @classmethod
    def profile(cls, depths: Any, east: Any, north: Any) -> Current:
        """A current that varies with depth only: linear between ``depths`` (m, increasing, at least two) and
        constant beyond the first and last.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If the arrays are not finite 1-D arrays of one length (at least 2), the depths are not strictly
            increasing or negative, or a speed exceeds :data:`CURRENT_MAX`.
        """
        d = checks.array("current profile depths", depths)
        if d.ndim != 1 or d.size < 2:
            raise ArgumentError(f"current profile depths must be a 1-D array of at least two depths (m), got shape "
                                f"{d.shape}")
        if np.any(np.diff(d) <= 0) or d[0] < 0:
            raise ArgumentError(f"current profile depths must be >= 0 and strictly increasing (m), got {d.tolist()}")
        e, n = _speed_checked("current profile", east, north)
        if e.shape != d.shape:
            raise ArgumentError(f"current profile: {d.size} depths but {e.size} velocities; give one (east, north) "
                                "pair per depth")
        return cls("profile", e, n, d)

    @classmethod
    def field(cls, function: Callable[[float, np.ndarray], Any]) -> Current:
        """A current given by ``function(t, position) -> (east, north)`` (m/s), ``t`` in s and ``position`` =
        ``(east, north, depth)`` (m).

        Raises
        ------
        ArgumentTypeError
            If ``function`` is not callable.
        """
        if not callable(function):
            raise ArgumentTypeError(f"a current field must be callable f(t, (east, north, depth)) -> (east, north), "
                                    f"got {type(function).__name__}")
        return cls("field", function=function)

    @classmethod
    def gridded(cls, east: Any, north: Any, u: Any, v: Any, times: Any = None) -> Current:
        """A current tabulated on a rectangular grid: ``u``, ``v`` (east, north components, m/s) of shape
        ``(len(north), len(east))``, or ``(len(times), len(north), len(east))`` with ``times`` (s); linear in
        between, constant beyond the edges (depth-independent).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If an axis is not strictly increasing with at least two points, the components do not have the grid's
            shape, or a speed exceeds :data:`CURRENT_MAX`.
        """
        from scipy.interpolate import RegularGridInterpolator

        axes = [("north", north), ("east", east)] if times is None else [("times", times), ("north", north),
                                                                          ("east", east)]
        grid = []
        for name, a in axes:
            arr = checks.array(f"gridded current {name}", a, ndim=1, min_size=2)
            if np.any(np.diff(arr) <= 0):
                raise ArgumentError(f"gridded current {name} must be strictly increasing")
            grid.append(arr)
        shape = tuple(g.size for g in grid)
        U = checks.array("gridded current u", u)
        V = checks.array("gridded current v", v)
        if U.shape != shape or V.shape != shape:
            raise ArgumentError(f"gridded current u and v must have shape {shape} ({', '.join(n for n, _ in axes)}), "
                                f"got {U.shape} and {V.shape}")
        _speed_checked("gridded current", U, V)
        interp = RegularGridInterpolator(tuple(grid), np.stack([U, V], -1), bounds_error=False, fill_value=None)
        lo = np.array([g[0] for g in grid])
        hi = np.array([g[-1] for g in grid])

        def f(t: float, pos: np.ndarray) -> np.ndarray:
            q = np.array([pos[1], pos[0]] if times is None else [t, pos[1], pos[0]])
            return interp(np.clip(q, lo, hi)[None])[0]

        return cls("field", function=f, depths=np.zeros(0), east=np.zeros(()), north=np.zeros(()),
                   _gridded_in_time=times is not None)

    @classmethod
    def from_dataset(cls, ds: Any, u: str = "u", v: str = "v") -> Current:
        """A gridded current from an ``xarray.Dataset`` (or anything with the same item access): variables ``u``,
        ``v`` (m/s) over the coordinates ``north`` and ``east`` (m), and ``time`` (s) when they have it (in that
        order of dimensions: ``(time, north, east)``).

        Raises
        ------
        ArgumentError
            If a variable or coordinate is missing or the dimensions are not ``(north, east)`` or ``(time, north,
            east)``.
        """
        try:
            U, V = ds[u], ds[v]
            dims = tuple(U.dims)
        except (KeyError, AttributeError, TypeError) as exc:
            raise ArgumentError(f"the dataset has no current variables {u!r} and {v!r} with dimensions: "
                                f"{exc}") from None
        if dims not in (("north", "east"), ("time", "north", "east")) or tuple(V.dims) != dims:
            raise ArgumentError(f"current variables must have dimensions (north, east) or (time, north, east), got "
                                f"{dims}")
        times = np.asarray(ds["time"].values, dtype=float) if dims[0] == "time" else None
        return cls.gridded(np.asarray(ds["east"].values, dtype=float), np.asarray(ds["north"].values, dtype=float),
                           np.asarray(U.values, dtype=float), np.asarray(V.values, dtype=float), times)

    @property
    def time_varying(self) -> bool:
        """Whether the current may change in time (a user field; a gridded field with a time axis)."""
        return self.kind == "field" and (self.function is not None and self._gridded_in_time is not False)

    @property
    def still(self) -> bool:
        """Whether this is still water (a uniform current of 0)."""
        return self.kind == "uniform" and not np.any(self._ned)

    def at(self, t: float, position: Any) -> np.ndarray:
        """Water velocity ``(east, north)`` (m/s) at time ``t`` (s) and ``position = (east, north, depth)`` (m);
        positions of shape ``(..., 3)`` give velocities of shape ``(..., 2)``.

        Raises
        ------
        ArgumentError
            If a user field returns something that is not a finite (east, north) pair no faster than
            :data:`CURRENT_MAX`.
        """
        pos = np.asarray(position, dtype=float)
        if self.kind == "uniform":
            return np.broadcast_to(np.array([float(self.east), float(self.north)]), (*pos.shape[:-1], 2)).copy()
        if self.kind == "profile":
            z = pos[..., 2]
            return np.stack([np.interp(z, self.depths, self.east), np.interp(z, self.depths, self.north)], -1)
        out = np.empty((*pos.shape[:-1], 2))
        for idx in np.ndindex(pos.shape[:-1]):
            out[idx] = self._call(t, pos[idx])
        return out

    def _call(self, t: float, pos: np.ndarray) -> np.ndarray:
        assert self.function is not None
        value = np.asarray(self.function(float(t), pos.copy()), dtype=float)
        if value.shape != (2,) or not np.all(np.isfinite(value)):
            raise ArgumentError(f"the current field returned {value!r} at t = {t:g} s, position {pos.tolist()} m; it "
                                "must return a finite (east, north) pair in m/s")
        if float(np.hypot(*value)) > CURRENT_MAX:
            raise ArgumentError(f"the current field returned {float(np.hypot(*value)):.3g} m/s at t = {t:g} s: faster "
                                f"than any ocean current (CURRENT_MAX = {CURRENT_MAX:g} m/s)")
        return value

    def velocity(self, t: float, xyz: Any) -> Any:
        """Water velocity in the models' north-east-down frame (m/s, shape ``(..., 3)``, no vertical component) at
        inertial positions ``xyz = (x north, y east, z down)`` (shape ``(..., 3)``; the real part of complex
        positions is used, so complex-step derivatives see the current as a function of time only through its
        value)."""
        if self.kind == "uniform":
            return self._ned
        pos = np.real(np.asarray(xyz))
        en = self.at(t, np.stack([pos[..., 1], pos[..., 0], pos[..., 2]], -1))
        return np.stack([en[..., 1], en[..., 0], np.zeros(en.shape[:-1])], -1)


def as_current(current: Any) -> Current:
    """A :class:`Current` from what the API accepts: ``None`` (still water), a Current, a pair ``(east, north)``
    (m/s, uniform) or a callable ``f(t, (east, north, depth)) -> (east, north)``.

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``current`` is none of these, or its values are not finite or faster than :data:`CURRENT_MAX`.
    """
    if current is None:
        return Current.uniform(0.0, 0.0)
    if isinstance(current, Current):
        return current
    if callable(current):
        return Current.field(current)
    if isinstance(current, str) or np.ndim(current) != 1 or np.size(current) != 2:
        raise ArgumentTypeError(f"current must be None, a Current, a pair (east, north) in m/s or a callable f(t, "
                                f"position) -> (east, north); got {current!r}")
    east, north = current
    return Current.uniform(east, north)
