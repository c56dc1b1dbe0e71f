"""Formation control of a glider fleet by a virtual body and artificial potentials (thesis §3.2.1; Leonard and
Fiorelli 2001; Fiorelli et al. 2006, as flown by Slocum gliders in AOSN-II).

The **virtual body** moves along ``leader_path`` (a polyline of (east, north) points, m) at ``leader_speed`` (m/s)
and carries the formation: glider ``i``'s slot is ``c_i(t) = p_vb(t) + R(t) o_i(d(t))``, the offsets ``o_i`` of the
shape with side ``d(t)`` (the spacing schedule) turned to the path's direction. When glider ``i`` surfaces at time
``t`` it gets the waypoint for its next surfacing, ``h`` seconds later (its dive time)::

    w_i = c_i(t + h) - k_spacing sum_j (|c_i - xhat_j| - d) (c_i - xhat_j) / |c_i - xhat_j|,

the slot minus the gradient of the spacing potentials ``V_ij = (|x_i - x_j| - d_ij)^2 / 2`` (``d_ij = |o_i -
o_j|``, the pair's designed distance) toward the other
gliders, each at its last reported position carried along with the virtual body to ``t + h``
(``xhat_j = x_j + v_vb (t + h - t_j)``). With every glider on its slot the potential terms vanish: the equilibrium
of the potentials is the desired shape (tested).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from dataclasses import field as dataclasses_field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError

__all__ = ["SHAPES", "FormationControl", "GradientClimbing", "shape_offsets"]

#: Formation shapes and their number of gliders.
SHAPES = {"triangle": 3, "line": None}


def shape_offsets(shape: str, n: int, spacing: float) -> np.ndarray:
    """Offsets ``(along, across)`` (m, shape ``(n, 2)``) of the formation's slots about its centre, the path's
    direction along the first axis: an equilateral triangle of side ``spacing`` with a vertex ahead, or ``n``
    gliders abreast ``spacing`` apart (``"line"``).

    Raises
    ------
    ArgumentError
        If the shape is unknown or needs another number of gliders.
    """
    checks.choice("shape", shape, tuple(SHAPES))
    need = SHAPES[shape]
    if need is not None and n != need:
        raise ArgumentError(f"a {shape} formation has {need} gliders, got {n}")
    if shape == "triangle":
        r = spacing / math.sqrt(3.0)
        ang = np.radians([0.0, 120.0, 240.0])
        return np.c_[r * np.cos(ang), r * np.sin(ang)]
    return np.c_[np.zeros(n), spacing * (np.arange(n) - (n - 1) / 2)]


def _polyline(points: Any) -> np.ndarray:
    p = checks.array("leader_path (east, north), m", points)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 2:
        raise ArgumentError(f"leader_path must be at least two (east, north) points in m, got shape {p.shape}")
    if np.any(np.hypot(*np.diff(p, axis=0).T) <= 0):
        raise ArgumentError("leader_path has two equal consecutive points: a segment of zero length has no direction")
    return p


@dataclass(frozen=True)
class FormationControl:
    """Virtual body and artificial potentials (module docstring).

    Parameters
    ----------
    shape : {"triangle", "line"}
    spacing : float or sequence of (time, spacing)
        Side of the formation (m), or a schedule: the spacing from each time (s) on, e.g. ``[(0, 6000), (86400,
        3000)]``.
    leader_path : array_like, shape (k, 2)
        The virtual body's path, (east, north) points (m); it stops at the last point.
    leader_speed : float
        Its speed along the path (m/s), > 0.
    k_spacing : float
        Weight of the spacing potentials, in ``[0, 1)`` (default 0.5).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If a value is not a number or outside its range, or the schedule is not increasing in time.
    """

    shape: str
    spacing: Any
    leader_path: Any
    leader_speed: float
    k_spacing: float = 0.5
    schedule: tuple[tuple[float, float], ...] = field(init=False, repr=False)
    _path: np.ndarray = field(init=False, repr=False, compare=False)
    _cum: np.ndarray = field(init=False, repr=False, compare=False)
    name = "formation"

    def __post_init__(self) -> None:
        checks.choice("shape", self.shape, tuple(SHAPES))
        if np.ndim(self.spacing) == 0:
            sched = ((0.0, checks.positive("spacing", self.spacing, unit="m")),)
        else:
            arr = checks.array("spacing schedule (time, spacing)", self.spacing)
            if arr.ndim != 2 or arr.shape[1] != 2 or np.any(np.diff(arr[:, 0]) <= 0) or np.any(arr[:, 1] <= 0):
                raise ArgumentError("spacing must be a positive number (m) or (time s, spacing m) pairs with "
                                    f"increasing times and positive spacings, got {self.spacing!r}")
            sched = tuple((float(a), float(b)) for a, b in arr)
        object.__setattr__(self, "schedule", sched)
        path = _polyline(self.leader_path)
        object.__setattr__(self, "_path", path)
        object.__setattr__(self, "_cum", np.r_[0.0, np.cumsum(np.hypot(*np.diff(path, axis=0).T))])
        object.__setattr__(self, "leader_speed", checks.positive("leader_speed", self.leader_speed, unit="m/s"))
        object.__setattr__(self, "k_spacing", checks.real("k_spacing", self.k_spacing, lo=0.0, hi=1.0, hi_open=True))

    def spacing_at(self, t: float) -> float:
        """The scheduled spacing (m) at time ``t`` (s)."""
        d = self.schedule[0][1]
        for t0, s in self.schedule:
            if t >= t0:
                d = s
        return d

    def leader(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Virtual body's position (east, north; m) and unit direction at time ``t`` (s); it stops at the path's
        end (velocity 0 there)."""
        s = min(self.leader_speed * max(t, 0.0), self._cum[-1])
        k = int(min(np.searchsorted(self._cum, s, side="right") - 1, len(self._cum) - 2))
        seg = self._path[k + 1] - self._path[k]
        u = seg / np.hypot(*seg)
        return self._path[k] + (s - self._cum[k]) * u, u

    def leader_velocity(self, t: float) -> np.ndarray:
        """Virtual body's velocity (east, north; m/s) at time ``t``."""
        _, u = self.leader(t)
        moving = self.leader_speed * t < self._cum[-1]
        return self.leader_speed * u if moving else np.zeros(2)

    def slots(self, n: int, t: float) -> np.ndarray:
        """The ``n`` gliders' slots (east, north; m) at time ``t``."""
        pos, u = self.leader(t)
        off = shape_offsets(self.shape, n, self.spacing_at(t))
        across = np.array([u[1], -u[0]])          # to starboard of the path
        return pos + off[:, :1] * u + off[:, 1:] * across

    def waypoint(self, i: int, n: int, t: float, horizon: float,
                 reports: Mapping[int, tuple[float, Any]]) -> np.ndarray:
        """Waypoint (east, north; m) of glider ``i`` of ``n`` surfacing at ``t`` (s) for its next surfacing
        ``horizon`` seconds later, from the other gliders' last reports ``{j: (time, (east, north))}``."""
        tt = t + horizon
        c = self.slots(n, tt)[i]
        off = shape_offsets(self.shape, n, self.spacing_at(tt))
        v = self.leader_velocity(t)
        grad = np.zeros(2)
        for j, (tj, pj) in reports.items():
            if j == i:
                continue
            d = float(np.hypot(*(off[i] - off[j])))           # the pair's designed distance
            xj = np.asarray(pj, dtype=float) + v * (tt - tj)
            delta = c - xj
            r = float(np.hypot(*delta))
            if r > 1e-9:
                grad += (r - d) * delta / r
        return c - self.k_spacing * grad

    def potential(self, X: Any, t: float) -> float:
        """Total potential (m^2) of positions ``X`` (shape ``(n, 2)``) at time ``t``: ``sum_i |x_i - c_i|^2 / 2 +
        k_spacing sum_{i<j} (|x_i - x_j| - d_ij)^2 / 2`` with the pairs' designed distances; zero exactly on the
        slots."""
        X = np.asarray(X, dtype=float)
        n = X.shape[0]
        c = self.slots(n, t)
        off = shape_offsets(self.shape, n, self.spacing_at(t))
        v = 0.5 * float(np.sum((X - c) ** 2))
        for i in range(n):
            for j in range(i + 1, n):
                d = float(np.hypot(*(off[i] - off[j])))
                v += 0.5 * self.k_spacing * (float(np.hypot(*(X[i] - X[j]))) - d) ** 2
        return v


@dataclass
class GradientClimbing:
    """A formation that climbs the gradient of a scalar field it samples (thesis §3.2.1; Ogren, Fiorelli and
    Leonard 2004): the virtual body moves at ``speed`` along the gradient estimated by least squares, ``f ~ a + g .
    x``, from the field's values at the gliders' last reported positions, and carries the formation's slots
    (:func:`shape_offsets`) as :class:`FormationControl` does. With fewer than three reports (or collinear ones) the
    virtual body keeps its direction.

    Parameters
    ----------
    field : callable
        ``field(east, north) -> value`` (m, m; any unit), the quantity the gliders measure at the surface.
    shape : {"triangle", "line"}
    spacing : float
        Side of the formation (m), > 0.
    speed : float
        Speed of the virtual body (m/s), > 0.
    start : (float, float)
        The virtual body's position (east, north; m) at ``t = 0``.
    stop_gradient : float
        Below this gradient magnitude (field units per m) the virtual body stops (default 0).

    Attributes
    ----------
    history : list of (float, ndarray, ndarray)
        ``(time, virtual body position, estimated gradient)`` at each decision.
    """

    field: Any
    shape: str
    spacing: float
    speed: float
    start: Any = (0.0, 0.0)
    stop_gradient: float = 0.0
    history: list[tuple[float, np.ndarray, np.ndarray]] = dataclasses_field(default_factory=list, repr=False)
    name = "gradient climbing"

    def __post_init__(self) -> None:
        if not callable(self.field):
            raise ArgumentError("field must be callable: field(east, north) -> value")
        checks.choice("shape", self.shape, tuple(SHAPES))
        self.spacing = checks.positive("spacing", self.spacing, unit="m")
        self.speed = checks.positive("speed", self.speed, unit="m/s")
        self.start = checks.array("start (east, north), m", self.start, shape=(2,)).astype(float)
        self.stop_gradient = checks.nonnegative("stop_gradient", self.stop_gradient)
        self._state = [0.0, self.start.copy(), np.array([1.0, 0.0]), math.inf]   # time, position, direction, |g|

    @property
    def leader_speed(self) -> float:
        """The virtual body's speed (m/s): the fleet checks it against the gliders'."""
        return self.speed

    def spacing_at(self, t: float) -> float:
        """The formation's side (m)."""
        return self.spacing

    def gradient(self, reports: Mapping[int, tuple[float, Any]]) -> np.ndarray | None:
        """Least-squares gradient (field units per m) from the field at the reported positions; None when the
        positions do not determine a plane."""
        pts = np.array([np.asarray(p, dtype=float) for _, p in reports.values()])
        if len(pts) < 3:
            return None
        A = np.c_[np.ones(len(pts)), pts - pts.mean(0)]
        if np.linalg.matrix_rank(A) < 3:
            return None
        vals = np.array([float(self.field(p[0], p[1])) for p in pts])
        coef, *_ = np.linalg.lstsq(A, vals, rcond=None)
        return coef[1:]

    def _advance(self, t: float) -> None:
        t0, p, u, gnorm = self._state
        if t > t0:
            moving = gnorm > self.stop_gradient
            self._state = [t, p + (self.speed * (t - t0) if moving else 0.0) * u, u, gnorm]

    def slots(self, n: int, t: float) -> np.ndarray:
        """The slots at time ``t`` (s) about the virtual body carried forward along its current direction."""
        t0, p, u, gnorm = self._state
        moving = gnorm > self.stop_gradient
        pos = p + (self.speed * max(t - t0, 0.0) if moving else 0.0) * u
        off = shape_offsets(self.shape, n, self.spacing)
        across = np.array([u[1], -u[0]])
        return pos + off[:, :1] * u + off[:, 1:] * across

    def waypoint(self, i: int, n: int, t: float, horizon: float,
                 reports: Mapping[int, tuple[float, Any]]) -> np.ndarray:
        """Update the virtual body to ``t`` and its direction from the reports' gradient, then glider ``i``'s slot
        at its next surfacing."""
        self._advance(t)
        g = self.gradient(reports)
        if g is not None:           # else the virtual body keeps its direction and its pace
            norm = float(np.hypot(*g))
            if norm > 0:
                self._state[2] = g / norm
            self._state[3] = norm
        self.history.append((t, self._state[1].copy(), np.zeros(2) if g is None else g.copy()))
        return self.slots(n, t + horizon)[i]
