"""What a glider is asked to do: :class:`Mission`, a list of waypoints flown in sawtooth dives."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError

__all__ = ["MAX_MISSION_DEPTH", "Mission"]

#: Deepest dive a mission may ask for (m) when the vehicle file gives no depth rating (``[hydrodynamics]`` has no
#: field for one): the rating of deep gliders (Deepglider, 6000 m).
MAX_MISSION_DEPTH = 6000.0


def _waypoints(value: Any) -> np.ndarray:
    w = checks.array("waypoints (east, north), m", value)
    if w.ndim != 2 or w.shape[1] != 2 or w.shape[0] < 1:
        raise ArgumentError(f"waypoints must be a sequence of (east, north) pairs in m, at least one; got shape "
                            f"{w.shape}")
    steps = np.hypot(*np.diff(w, axis=0).T) if len(w) > 1 else np.zeros(0)
    if np.any(steps < 1.0):
        k = int(np.argmax(steps < 1.0))
        raise ArgumentError(f"waypoints {k} and {k + 1} are the same point ({w[k].tolist()} m, {steps[k]:.3g} m "
                            "apart): a leg of zero length has no heading; remove the repeat")
    return w


@dataclass(frozen=True)
class Mission:
    """Waypoints flown in dives between two depths.

    The glider starts at the surface at ``start`` and flies to each waypoint in turn. Each dive goes from the
    surface to ``depths[1]``, climbs, and turns down again at ``depths[0]`` for ``yos`` yos before it climbs to the
    surface, spends ``surface_time`` there (GPS fix, data) and dives again. A waypoint is reached when the glider's
    dead-reckoned position comes within ``arrival_radius`` of it (underwater, as Slocum does) or a surface fix does.

    Parameters
    ----------
    waypoints : array_like, shape (k, 2)
        ``(east, north)`` positions (m) of the waypoints, in order; consecutive waypoints at least 1 m apart.
    depths : (float, float)
        ``(top, bottom)`` inflection depths (m), ``0 <= top < bottom <= MAX_MISSION_DEPTH``; at least 2 m apart.
    gamma : float
        Glide-path angle magnitude (rad) of the dives, in ``(0, pi/2)``: down at ``-gamma``, up at ``+gamma``.
    speed : float
        Speed through the water (m/s) of the designed glides, in ``(0, 3]``.
    surface_time : float
        Time at the surface per surfacing (s), >= 0 (default 600 s).
    arrival_radius : float
        Distance (m) at which a waypoint counts as reached, > 0 (default 100 m).
    start : (float, float)
        ``(east, north)`` of the launch (m), default the origin.
    yos : int
        Dives between surfacings, >= 1 (default 1: surface after every dive).
    max_leg_time : float, optional
        Longest time (s) spent on one leg before it ends with reason ``"timeout"``; default three times the leg's
        length over the glide's horizontal speed plus six hours.

    Raises
    ------
    ArgumentTypeError
        If a value is not a number or array of numbers.
    ArgumentError
        If the waypoints are not finite ``(east, north)`` pairs (an empty mission, NaN, or a repeated waypoint), or
        a value is outside its range.
    """

    waypoints: Any
    depths: tuple[float, float] = (5.0, 100.0)
    gamma: float = math.radians(25.0)
    speed: float = 0.35
    surface_time: float = 600.0
    arrival_radius: float = 100.0
    start: tuple[float, float] = (0.0, 0.0)
    yos: int = 1
    max_leg_time: float | None = None

    def __post_init__(self) -> None:
        w = _waypoints(self.waypoints)
        w.setflags(write=False)
        object.__setattr__(self, "waypoints", w)
        d = checks.array("depths (top, bottom), m", self.depths, shape=(2,))
        top, bottom = float(d[0]), float(d[1])
        if not 0.0 <= top < bottom <= MAX_MISSION_DEPTH or bottom - top < 2.0:
            raise ArgumentError(f"depths = ({top:g}, {bottom:g}) m: need 0 <= top < bottom <= {MAX_MISSION_DEPTH:g} m "
                                "and at least 2 m between them")
        object.__setattr__(self, "depths", (top, bottom))
        object.__setattr__(self, "gamma", checks.real("gamma", self.gamma, lo=0.0, hi=math.pi / 2, lo_open=True,
                                                      hi_open=True, unit="rad"))
        object.__setattr__(self, "speed", checks.real("speed", self.speed, lo=0.0, hi=3.0, lo_open=True, unit="m/s"))
        object.__setattr__(self, "surface_time", checks.real("surface_time", self.surface_time, lo=0.0, hi=86400.0,
                                                             unit="s"))
        object.__setattr__(self, "arrival_radius", checks.positive("arrival_radius", self.arrival_radius, unit="m"))
        s = checks.array("start (east, north), m", self.start, shape=(2,))
        object.__setattr__(self, "start", (float(s[0]), float(s[1])))
        object.__setattr__(self, "yos", checks.integer("yos", self.yos, lo=1, hi=1000))
        if self.max_leg_time is not None:
            object.__setattr__(self, "max_leg_time", checks.positive("max_leg_time", self.max_leg_time, unit="s"))

    @property
    def legs(self) -> int:
        """Number of legs (one per waypoint)."""
        return len(self.waypoints)

    def leg_start(self, k: int) -> np.ndarray:
        """Planned start ``(east, north)`` (m) of leg ``k``: the launch point or the previous waypoint."""
        return np.asarray(self.start, dtype=float) if k == 0 else np.asarray(self.waypoints[k - 1], dtype=float)

    def leg_time_limit(self, k: int, horizontal_speed: float) -> float:
        """Time limit (s) of leg ``k`` at a horizontal speed (m/s): ``max_leg_time`` or its default."""
        if self.max_leg_time is not None:
            return float(self.max_leg_time)
        length = float(np.hypot(*(self.waypoints[k] - self.leg_start(k))))
        return 3.0 * length / horizontal_speed + 6 * 3600.0
