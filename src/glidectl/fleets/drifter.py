"""Tracking a surface drifter with a glider (thesis §3.2.2; AOSN-II, Figs 3.4-3.5).

The drifter's position reaches the coordinator every ``report_period`` seconds, ``report_lag`` seconds late (in
AOSN-II: every 30 minutes, 15 minutes late). When the glider surfaces at ``t`` the coordinator knows the drifter
at the report times ``t_r <= t - report_lag`` and sends the glider to the next point of a circle of radius
``radius`` about a centre, so that the glider flies chords of the circle (one chord per dive, the chord a dive's
horizontal reach; counter-clockwise):

* ``"predicted"`` (real-time tracking): the centre is the drifter's position predicted for the glider's next
  surfacing ``t + h`` from its last two reports, ``p(t_r) + (p(t_r) - p(t_r - T)) (t + h - t_r) / T``;
* ``"delayed"`` (the variant §3.2.2 suggests): the centre is the drifter's last reported position, so the glider
  circles where the drifter was and criss-crosses its actual path.

:meth:`DrifterTracking.errors` measures both at the glider's surfacings: the distance to the drifter's actual
position at that time minus the radius (real-time tracking), and the distance to the drifter's path (the delayed
variant's aim).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..environment import as_current
from ..errors import ArgumentError

__all__ = ["DrifterTracking", "drift_track"]


def drift_track(current: Any, start: Any, duration: float, step: float = 60.0) -> tuple[np.ndarray, np.ndarray]:
    """Track of a surface drifter carried by ``current`` (at depth 0) from ``start`` for ``duration``.

    Parameters
    ----------
    current : Current, (east, north), callable or None
        The water's velocity (m/s); the drifter moves with it at the surface.
    start : (float, float)
        Its (east, north) at ``t = 0`` (m).
    duration, step : float
        Length of the track and integration step (s; midpoint rule).

    Returns
    -------
    (ndarray, ndarray)
        Times (s), shape ``(N,)``, and (east, north) positions (m), shape ``(N, 2)``.

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If the current, start, duration or step is not valid.
    """
    c = as_current(current)
    p = checks.array("start (east, north), m", start, shape=(2,)).astype(float)
    T = checks.positive("duration", duration, unit="s")
    h = checks.positive("step", step, unit="s")
    n = max(1, math.ceil(T / h))
    times = np.linspace(0.0, T, n + 1)
    out = np.empty((n + 1, 2))
    out[0] = p
    for k in range(n):
        dt = times[k + 1] - times[k]
        mid = out[k] + 0.5 * dt * c.at(times[k], np.array([*out[k], 0.0]))
        out[k + 1] = out[k] + dt * c.at(times[k] + 0.5 * dt, np.array([*mid, 0.0]))
    return times, out


@dataclass(frozen=True)
class DrifterTracking:
    """A glider circling a surface drifter known from delayed reports (module docstring).

    Parameters
    ----------
    drifter : (times, positions)
        The drifter's actual track: times (s, increasing) and (east, north) positions (m), e.g. :func:`drift_track`;
        linear between samples.
    radius : float
        Radius (m) of the circle the glider flies about the centre, > 0.
    report_period, report_lag : float
        Time between the drifter's reports and their lag (s); default 1800 and 900 (AOSN-II).
    mode : {"predicted", "delayed"}
        Centre of the circle (module docstring).
    chord : float, optional
        Length (m) of the chord per dive; default ``speed`` times the dive time.
    speed : float
        The glider's horizontal speed through the water (m/s), > 0, for the default chord (default 0.3).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If the track is not increasing times with one finite (east, north) each, or a value is out of range.
    """

    drifter: Any
    radius: float
    report_period: float = 1800.0
    report_lag: float = 900.0
    mode: str = "predicted"
    chord: float | None = None
    speed: float = 0.3
    _track: tuple[np.ndarray, np.ndarray] = field(init=False, repr=False, compare=False)
    name = "drifter tracking"

    def __post_init__(self) -> None:
        try:
            times, pos = self.drifter
        except (TypeError, ValueError):
            raise ArgumentError("drifter must be (times, positions): times in s and (east, north) positions in m "
                                "(glidectl.fleets.drift_track makes one)") from None
        t = checks.array("drifter times", times, ndim=1, min_size=2)
        p = checks.array("drifter positions", pos, shape=(t.size, 2))
        if np.any(np.diff(t) <= 0):
            raise ArgumentError("drifter times must be strictly increasing")
        object.__setattr__(self, "_track", (t, p))
        object.__setattr__(self, "radius", checks.positive("radius", self.radius, unit="m"))
        object.__setattr__(self, "report_period", checks.positive("report_period", self.report_period, unit="s"))
        object.__setattr__(self, "report_lag", checks.nonnegative("report_lag", self.report_lag, unit="s"))
        checks.choice("mode", self.mode, ("predicted", "delayed"))
        if self.chord is not None:
            object.__setattr__(self, "chord", checks.positive("chord", self.chord, unit="m"))
        object.__setattr__(self, "speed", checks.positive("speed", self.speed, unit="m/s"))

    def actual(self, t: Any) -> np.ndarray:
        """The drifter's actual position (east, north; m) at ``t`` (s)."""
        times, pos = self._track
        tt = np.asarray(t, dtype=float)
        return np.stack([np.interp(tt, times, pos[:, 0]), np.interp(tt, times, pos[:, 1])], -1)

    def last_report(self, t: float) -> float:
        """Time (s) of the last report the coordinator has at ``t`` (the first report is at ``t = 0``)."""
        return max(0.0, math.floor((t - self.report_lag) / self.report_period) * self.report_period)

    def predicted(self, t: float, at: float) -> np.ndarray:
        """The drifter's position at ``at`` (s) predicted at ``t`` from its last two reports (linear)."""
        tr = self.last_report(t)
        p1 = self.actual(tr)
        if tr < self.report_period:
            return p1
        p0 = self.actual(tr - self.report_period)
        return p1 + (p1 - p0) * (at - tr) / self.report_period

    def centre(self, t: float, horizon: float) -> np.ndarray:
        """Centre of the circle (east, north; m) for a glider surfacing at ``t`` with a dive of ``horizon`` s."""
        if self.mode == "delayed":
            return self.actual(self.last_report(t))
        return self.predicted(t, t + horizon)

    def waypoint(self, i: int, n: int, t: float, horizon: float,
                 reports: Mapping[int, tuple[float, Any]]) -> np.ndarray:
        """Next point of the circle (east, north; m) for glider ``i`` surfacing at ``t``: one chord
        counter-clockwise from its own last report's bearing from the centre."""
        c = self.centre(t, horizon)
        own = np.asarray(reports[i][1], dtype=float) if i in reports else c + np.array([self.radius, 0.0])
        bearing = math.atan2(own[1] - c[1], own[0] - c[0])
        chord = self.chord if self.chord is not None else self.speed * horizon
        step = 2.0 * math.asin(min(1.0, chord / (2.0 * self.radius)))
        return c + self.radius * np.array([math.cos(bearing + step), math.sin(bearing + step)])

    def errors(self, run: Any, glider: int = 0) -> dict[str, float]:
        """Tracking errors of ``glider`` at its surfacings (m): ``circle`` the mean of ``|distance to the actual
        drifter - radius|`` (real-time tracking's aim), ``path`` the mean distance to the drifter's path over the
        run (the delayed variant's aim: it crosses the path)."""
        fixes = [(t, p) for t, j, p in run.surfacings if j == glider]
        _, pos = self._track
        circle = [abs(float(np.hypot(*(p - self.actual(t)))) - self.radius) for t, p in fixes]
        path = [float(np.min(np.hypot(*(pos - p).T))) for _, p in fixes]
        return {"circle": float(np.mean(circle)), "path": float(np.mean(path)), "surfacings": float(len(fixes))}
