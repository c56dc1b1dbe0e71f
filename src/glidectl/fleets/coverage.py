"""Coordinated coverage (thesis §3.2.3; Leonard et al. 2010, ASAP): gliders spaced in phase on a closed curve,
scored by the objective-analysis mapping error.

**Mapping error.** The field sampled by the gliders is modelled as a random field with covariance
``C(dx, dt) = exp(-|dx|^2 / L^2 - |dt| / tau)`` (space scale ``L``, time scale ``tau``). From measurements at
``(x_k, t_k)`` with noise variance ``eta`` (relative to the field's variance), the objective-analysis estimate at
``(x, t)`` has the normalized error variance

    e(x, t) = 1 - c^T (C_dd + eta I)^-1 c,   c_k = C(x - x_k, t - t_k),  (C_dd)_kl = C(x_k - x_l, t_k - t_l),

between 0 (known exactly) and 1 (nothing known). :func:`coverage_metric` averages it over a grid of the domain at
a series of times, using the measurements of the last ``window`` (default three time scales).

**Patterns.** :class:`CurvePatrol` sends each glider along a closed polyline at a common speed, glider ``i`` a
fraction ``i / n`` of the curve's length behind glider 0 (phase spacing): at a surfacing, its waypoint is its
phase's point at its next surfacing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError

__all__ = ["Coverage", "CurvePatrol", "coverage_metric", "mapping_error"]


def _cov(dx2: np.ndarray, dt: np.ndarray, L: float, tau: float) -> np.ndarray:
    return np.exp(-dx2 / (L * L) - np.abs(dt) / tau)


def mapping_error(points: Any, t: float, samples: Any, sample_times: Any, *, space_scale: float,
                  time_scale: float, noise: float = 0.1) -> np.ndarray:
    """Normalized objective-analysis error variance (module docstring) at ``points`` (shape ``(m, 2)``, m) and
    time ``t`` (s) from measurements at ``samples`` (shape ``(k, 2)``, m) taken at ``sample_times`` (s).

    Parameters
    ----------
    points : array_like, shape (m, 2)
    t : float
    samples : array_like, shape (k, 2)
    sample_times : array_like, shape (k,)
    space_scale, time_scale : float
        ``L`` (m) and ``tau`` (s) of the covariance, > 0.
    noise : float
        Measurement noise variance relative to the field's, > 0 (default 0.1).

    Returns
    -------
    ndarray, shape (m,)
        Error variance in [0, 1] (1 without measurements).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If an array has the wrong shape or a scale is not positive.
    """
    P = checks.array("points", points)
    S = checks.array("samples", samples)
    ts = checks.array("sample_times", sample_times, ndim=1)
    L = checks.positive("space_scale", space_scale, unit="m")
    tau = checks.positive("time_scale", time_scale, unit="s")
    eta = checks.positive("noise", noise)
    if P.ndim != 2 or P.shape[1] != 2:
        raise ArgumentError(f"points must have shape (m, 2), got {P.shape}")
    if S.size == 0:
        return np.ones(P.shape[0])
    if S.ndim != 2 or S.shape[1] != 2 or S.shape[0] != ts.size:
        raise ArgumentError(f"samples must have shape (k, 2) with one time each; got {S.shape} and {ts.shape}")
    Cdd = _cov(np.sum((S[:, None] - S[None]) ** 2, -1), ts[:, None] - ts[None], L, tau) + eta * np.eye(ts.size)
    c = _cov(np.sum((P[:, None] - S[None]) ** 2, -1), t - ts[None], L, tau)       # (m, k)
    sol = np.linalg.solve(Cdd, c.T)                                                  # (k, m)
    return np.clip(1.0 - np.sum(c.T * sol, axis=0), 0.0, 1.0)


@dataclass(frozen=True)
class Coverage:
    """Mapping error of a fleet run over a domain (:func:`coverage_metric`).

    Attributes
    ----------
    times : ndarray
        Evaluation times (s).
    error : ndarray, shape (len(times),)
        Mean mapping error over the grid at each time.
    mean : float
        Its mean over the times (the score: lower is better).
    grid : ndarray, shape (m, 2)
        The grid points (east, north; m).
    space_scale, time_scale, noise : float
    """

    times: np.ndarray
    error: np.ndarray
    mean: float
    grid: np.ndarray = field(repr=False)
    space_scale: float = 0.0
    time_scale: float = 0.0
    noise: float = 0.0


def coverage_metric(run: Any, grid: Any, *, space_scale: float, time_scale: float, noise: float = 0.1,
                    sample_period: float = 600.0, times: Any = None, window: float | None = None) -> Coverage:
    """Objective-analysis mapping error of a fleet run (module docstring).

    Parameters
    ----------
    run : FleetRun
        The gliders' tracks; each glider measures at its horizontal position every ``sample_period`` seconds.
    grid : array_like, shape (m, 2)
        Points (east, north; m) where the error is averaged.
    space_scale, time_scale, noise : float
        As :func:`mapping_error`.
    sample_period : float
        Spacing of the measurements along each track (s), > 0.
    times : array_like, optional
        Evaluation times (s); default every ``time_scale / 4`` from one time scale in.
    window : float, optional
        Measurements older than this (s) are left out; default ``3 time_scale``.

    Returns
    -------
    Coverage

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If a value is not valid.
    """
    tau = checks.positive("time_scale", time_scale, unit="s")
    dt = checks.positive("sample_period", sample_period, unit="s")
    W = 3.0 * tau if window is None else checks.positive("window", window, unit="s")
    end = min(float(t[-1]) for t in run.t)
    st = np.arange(0.0, end + 1e-9, dt)
    pos = run.positions_at(st)                       # (len(st), n, 2)
    S = pos.reshape(-1, 2)
    ts = np.repeat(st, run.size)
    ev = np.arange(min(tau, end), end + 1e-9, tau / 4) if times is None else checks.array("times", times, ndim=1)
    G = checks.array("grid", grid)
    err = np.empty(ev.size)
    for k, t in enumerate(ev):
        sel = (ts <= t) & (ts >= t - W)
        err[k] = float(np.mean(mapping_error(G, float(t), S[sel], ts[sel], space_scale=space_scale, time_scale=tau,
                                             noise=noise)))
    return Coverage(ev, err, float(np.mean(err)) if err.size else math.nan, G, float(space_scale), tau, float(noise))


@dataclass(frozen=True)
class CurvePatrol:
    """Gliders spaced in phase along a closed curve (module docstring).

    Parameters
    ----------
    curve : array_like, shape (k, 2)
        Vertices (east, north; m) of a closed polyline (the last joins the first), at least three.
    speed : float
        Speed along the curve (m/s), > 0; below the gliders' horizontal speed.
    spacing : {"even", "none"}
        ``"even"``: glider ``i`` a fraction ``i / n`` of the length behind glider 0; ``"none"``: all at the same
        phase (a comparison without coordination).

    Raises
    ------
    ArgumentError
        If the curve has fewer than three distinct vertices or a value is out of range.
    """

    curve: Any
    speed: float
    spacing: str = "even"
    _pts: np.ndarray = field(init=False, repr=False, compare=False)
    _cum: np.ndarray = field(init=False, repr=False, compare=False)
    name = "curve patrol"

    def __post_init__(self) -> None:
        p = checks.array("curve (east, north), m", self.curve)
        if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
            raise ArgumentError(f"curve must have at least three (east, north) vertices, got shape {p.shape}")
        closed = np.vstack([p, p[:1]])
        seg = np.hypot(*np.diff(closed, axis=0).T)
        if np.any(seg <= 0):
            raise ArgumentError("curve has two equal consecutive vertices")
        object.__setattr__(self, "_pts", closed)
        object.__setattr__(self, "_cum", np.r_[0.0, np.cumsum(seg)])
        object.__setattr__(self, "speed", checks.positive("speed", self.speed, unit="m/s"))
        checks.choice("spacing", self.spacing, ("even", "none"))

    @property
    def leader_speed(self) -> float:
        """Speed along the curve (m/s): the fleet checks it against the gliders' speed."""
        return self.speed

    @property
    def length(self) -> float:
        """Length of the closed curve (m)."""
        return float(self._cum[-1])

    def point(self, s: float) -> np.ndarray:
        """Point (east, north; m) at arc length ``s`` (m, taken modulo the length)."""
        s = s % self._cum[-1]
        k = int(min(np.searchsorted(self._cum, s, side="right") - 1, len(self._cum) - 2))
        seg = self._pts[k + 1] - self._pts[k]
        return self._pts[k] + (s - self._cum[k]) / np.hypot(*seg) * seg

    def slots(self, n: int, t: float) -> np.ndarray:
        """The ``n`` gliders' points at time ``t`` (s)."""
        lag = self.length / n if self.spacing == "even" else 0.0
        return np.array([self.point(self.speed * t - i * lag) for i in range(n)])

    def waypoint(self, i: int, n: int, t: float, horizon: float,
                 reports: Mapping[int, tuple[float, Any]]) -> np.ndarray:
        """Glider ``i``'s phase point at its next surfacing ``t + horizon``."""
        return self.slots(n, t + horizon)[i]
