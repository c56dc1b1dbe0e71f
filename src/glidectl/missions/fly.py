"""Fly a mission: :func:`fly_mission` runs the actuated 3-D glider through the dives, surfacings and legs of a
:class:`~glidectl.missions.mission.Mission` in a current, and returns a :class:`MissionRun`.

Sequence
--------
The glider starts at rest at the surface at the launch point, heading for the first waypoint, with the pump and
battery at the dive's settings. Each phase (dive to the bottom depth, climb to the top depth or to the surface) is
one integration of the :class:`~glidectl.missions.loop.MissionLoop` (LSODA through :func:`~glidectl.simulate`),
ended by the depth of the inflection or by an arrival at the waypoint by dead reckoning (the glider then steers for
the next waypoint). At the surface the glider gets a GPS fix (true position plus ``gps_noise``), measures the
dead-reckoning error, updates its depth-averaged current estimate by ``(fix - dead reckoning) / dive time``, drifts
with the surface current for ``surface_time`` (the water's velocity at depth 0), takes a second fix, resets its dead
reckoning there and dives again from rest with the heading it surfaced with, steering for its waypoint with the
current correction.

Legs end when the waypoint is reached (by dead reckoning under water or by a fix within ``arrival_radius``), when
the current estimated at a surfacing leaves the glider no speed toward the waypoint (``"unreachable"``: the
cross current is at least the glider's horizontal speed, or the speed made good toward the waypoint would be below
5 % of it), or when the leg's time limit passes (``"timeout"``). The mission ends at the first surfacing after its
last leg, or at ``duration``.

Energy
------
Per dive and per leg: the pump energy integrated with the motion (the loop's ``pump_energy`` state,
:func:`~glidectl.controllers.dive_cycle.pump_power` with the vehicle's ``pump_efficiency`` and surface water density:
pushing oil out against the sea pressure); per leg also ``hotel_power`` times the duration.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..environment import Current
from ..errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError, SolverError
from ..models._validate import require_glider
from ..models.actuated3d import ActuatedGlider3D
from ..params import Vehicle
from ..sim import simulate
from .behaviours import DiveLQR, DivePlan, GliderBehaviours, pitch_heading
from .fast import DiveProfile, calibrate_dive, replay_dive
from .loop import MISSION_STATES, MissionLoop, current_corrected_heading, rest_state
from .mission import MAX_MISSION_DEPTH, Mission

__all__ = ["CONTROLLER_SETS", "DiveMetrics", "GliderFlight", "LegMetrics", "MissionRun", "fly_mission"]

#: Named controller sets of :func:`fly_mission`.
CONTROLLER_SETS = ("behaviours", "lqr")
_UNREACHABLE_FRACTION = 0.05   # speed made good toward the waypoint below this fraction of U: unreachable
_PHASE_MARGIN = 4.0            # phase time limit: this many times the designed phase time, plus ten minutes


@dataclass(frozen=True)
class DiveMetrics:
    """One dive, from leaving the surface to the next surfacing.

    Attributes
    ----------
    start, end : float
        Times (s) of the dive start and of the surfacing.
    max_depth, overshoot : float
        Deepest point (m) and how far it passed the bottom inflection depth (m).
    energy : float
        Pump energy (J).
    fix : ndarray, shape (2,)
        GPS fix ``(east, north)`` (m) at the surfacing.
    dead_reckoning_error : float
        Distance (m) between the dead-reckoned position and the fix at the surfacing.
    current_estimate : ndarray, shape (2,)
        Depth-averaged current ``(east, north)`` (m/s) estimated at the surfacing.
    """

    start: float
    end: float
    max_depth: float
    overshoot: float
    energy: float
    fix: np.ndarray
    dead_reckoning_error: float
    current_estimate: np.ndarray

    @property
    def duration(self) -> float:
        """Dive time (s)."""
        return self.end - self.start


@dataclass(frozen=True)
class LegMetrics:
    """One leg, toward one waypoint.

    Attributes
    ----------
    waypoint : ndarray, shape (2,)
        ``(east, north)`` (m).
    start, end : float
        Times (s).
    reason : str
        How the leg ended: ``"arrived"``, ``"unreachable: ..."``, ``"timeout: ..."`` or ``"mission end: ..."``.
    distance_made_good : float
        Reduction of the distance to the waypoint over the leg (m).
    energy : float
        Pump energy plus hotel energy (J).
    arrival_error : float
        True distance (m) to the waypoint where the leg ended.
    dead_reckoning_error : float
        Dead-reckoning error (m) at the leg's last surfacing (NaN if it had none).
    current_estimate : ndarray, shape (2,)
        Depth-averaged current ``(east, north)`` (m/s) estimated at the leg's end.
    dives : int
        Surfacings during the leg.
    """

    waypoint: np.ndarray
    start: float
    end: float
    reason: str
    distance_made_good: float
    energy: float
    arrival_error: float
    dead_reckoning_error: float
    current_estimate: np.ndarray
    dives: int

    @property
    def duration(self) -> float:
        """Leg time (s)."""
        return self.end - self.start

    @property
    def arrived(self) -> bool:
        """Whether the leg reached its waypoint."""
        return self.reason == "arrived"

    @property
    def energy_per_km(self) -> float:
        """Energy per kilometre made good (J/km; NaN without progress)."""
        return self.energy / (self.distance_made_good / 1000.0) if self.distance_made_good > 0 else math.nan


@dataclass(frozen=True)
class MissionRun:
    """A flown mission (module docstring of :mod:`glidectl.missions.fly`).

    Attributes
    ----------
    t : ndarray, shape (N,)
        Mission times (s) of the samples, non-decreasing: a phase boundary (inflection, surfacing, arrival) appears
        twice, at the end of one phase and the start of the next (the state is continuous, the actuator rates jump).
    states : ndarray, shape (N, 22)
        :data:`~glidectl.missions.loop.MISSION_STATES` at the samples (the plant's 19, the dead reckoning and the
        pump energy spent since the start, J); at the surface the glider is held at rest and drifts with the
        current.
    phase : ndarray of int, shape (N,)
        ``+1`` dive, ``-1`` climb, ``0`` at the surface.
    leg : ndarray of int, shape (N,)
        Index of the leg being flown.
    legs : tuple of LegMetrics
    dives : tuple of DiveMetrics
    ended_by : str
        Why the mission ended.
    mission : Mission
    current : Current
    controller : str
        The controller set flown.
    seed : int
    vehicle : Vehicle
    provenance : str
        The vehicle's parameter hash.
    """

    t: np.ndarray
    states: np.ndarray
    phase: np.ndarray
    leg: np.ndarray
    legs: tuple[LegMetrics, ...]
    dives: tuple[DiveMetrics, ...]
    ended_by: str
    mission: Mission
    current: Current
    controller: str
    seed: int
    vehicle: Vehicle = field(repr=False)
    plant: ActuatedGlider3D = field(repr=False)
    provenance: str = ""

    state_names = MISSION_STATES

    @property
    def position(self) -> np.ndarray:
        """``(east, north, depth)`` (m), shape ``(N, 3)``."""
        return self.states[:, [1, 0, 2]]

    @property
    def dead_reckoned(self) -> np.ndarray:
        """The glider's own ``(east, north)`` estimate (m), shape ``(N, 2)``."""
        return self.states[:, 19:21]

    @property
    def heading(self) -> np.ndarray:
        """Heading (rad, from north toward east, in ``(-pi, pi]``)."""
        return pitch_heading(self.states)[1]

    @property
    def pitch(self) -> np.ndarray:
        """Pitch angle (rad)."""
        return pitch_heading(self.states)[0]

    def state(self, name: str) -> np.ndarray:
        """Samples of the state ``name`` (:data:`~glidectl.missions.loop.MISSION_STATES`).

        Raises
        ------
        ArgumentError
            If ``name`` is not a state.
        """
        if name not in self.state_names:
            raise ArgumentError(f"unknown state {name!r}; states: {', '.join(self.state_names)}")
        return self.states[:, self.state_names.index(name)]

    def actuator(self, name: str) -> np.ndarray:
        """Samples of an actuator's setting: ``"r_P1"`` (m), ``"roll"`` (rad), ``"m0"`` (kg), ``"rudder"`` (rad).

        Raises
        ------
        ArgumentError
            If ``name`` is not one of them.
        """
        if name not in self.plant.actuator_names:
            raise ArgumentError(f"unknown actuator {name!r}; actuators: {', '.join(self.plant.actuator_names)}")
        return self.state(name)

    @property
    def duration(self) -> float:
        """Mission time (s)."""
        return float(self.t[-1] - self.t[0])

    @property
    def energy(self) -> float:
        """Energy of all legs (J)."""
        return float(sum(leg.energy for leg in self.legs))

    @property
    def distance_made_good(self) -> float:
        """Distance made good over all legs (m)."""
        return float(sum(leg.distance_made_good for leg in self.legs))

    @property
    def energy_per_km(self) -> float:
        """Energy per kilometre made good (J/km)."""
        d = self.distance_made_good
        return self.energy / (d / 1000.0) if d > 0 else math.nan

    def table(self) -> str:
        """The per-leg table as text."""
        head = (f"{'leg':>3} {'waypoint (E, N) m':>20} {'reason':>12} {'time h':>7} {'DMG km':>7} {'energy kJ':>9} "
                f"{'J/km':>8} {'arrival m':>9} {'DR err m':>8} {'current E,N m/s':>16}")
        rows = [head]
        for i, leg in enumerate(self.legs):
            rows.append(f"{i:>3} {f'({leg.waypoint[0]:.0f}, {leg.waypoint[1]:.0f})':>20} "
                        f"{leg.reason.split(':')[0]:>12} {leg.duration / 3600:>7.2f} "
                        f"{leg.distance_made_good / 1000:>7.3f} {leg.energy / 1000:>9.2f} {leg.energy_per_km:>8.0f} "
                        f"{leg.arrival_error:>9.1f} {leg.dead_reckoning_error:>8.1f} "
                        f"{f'({leg.current_estimate[0]:+.3f}, {leg.current_estimate[1]:+.3f})':>16}")
        return "\n".join(rows)

    def summary(self) -> str:
        """A short text summary: legs, time, energy per km, why it ended."""
        arrived = sum(leg.arrived for leg in self.legs)
        return (f"{self.vehicle.name}, {self.controller}: {arrived}/{len(self.legs)} waypoints reached in "
                f"{self.duration / 3600:.2f} h, {len(self.dives)} dives, {self.distance_made_good / 1000:.2f} km made "
                f"good, {self.energy / 1000:.1f} kJ ({self.energy_per_km:.0f} J/km); ended by {self.ended_by}")

    def as_dict(self) -> dict[str, Any]:
        """Scalars and per-leg metrics, JSON-ready."""
        return {"vehicle": self.vehicle.name, "controller": self.controller, "seed": self.seed,
                "duration_s": self.duration, "dives": len(self.dives), "energy_J": self.energy,
                "distance_made_good_m": self.distance_made_good, "energy_per_km_J": self.energy_per_km,
                "ended_by": self.ended_by,
                "legs": [{"waypoint": leg.waypoint.tolist(), "reason": leg.reason, "duration_s": leg.duration,
                          "distance_made_good_m": leg.distance_made_good, "energy_J": leg.energy,
                          "arrival_error_m": leg.arrival_error, "dead_reckoning_error_m": leg.dead_reckoning_error,
                          "current_estimate_m_s": leg.current_estimate.tolist()} for leg in self.legs]}

    def plot(self, ax: Any = None) -> Any:
        """Map view (track, dead reckoning, waypoints, current arrows), depth against time and the actuators.

        Parameters
        ----------
        ax : sequence of 3 Axes, optional
            Map, depth and actuator Axes; a new figure when omitted.

        Returns
        -------
        ndarray of Axes, shape (3,)
        """
        from ..plotting import plot_mission_run
        return plot_mission_run(self, ax)

    def plot_3d(self, ax: Any = None) -> Any:
        """The track in 3-D (east, north, depth down) with the waypoints at the surface.

        Returns
        -------
        Axes3D
        """
        from ..plotting import plot_mission_3d
        return plot_mission_3d(self, ax)


# --- flight -------------------------------------------------------------------------------------------------------

def _law(controller: Any) -> tuple[Any, str]:
    if isinstance(controller, str):
        checks.choice("controller", controller, CONTROLLER_SETS)
        return (GliderBehaviours() if controller == "behaviours" else DiveLQR()), controller
    if not callable(getattr(controller, "rates", None)):
        raise ArgumentTypeError(f"controller must be one of {CONTROLLER_SETS} or an object with rates(plant, plan, x, "
                                f"phase, heading_ref) (e.g. glidectl.GliderBehaviours(...)); got "
                                f"{type(controller).__name__}")
    return controller, str(getattr(controller, "name", type(controller).__name__))


class _Recorder:
    """Samples of the mission as it is flown."""

    def __init__(self) -> None:
        self.t: list[np.ndarray] = []
        self.x: list[np.ndarray] = []
        self.phase: list[np.ndarray] = []
        self.leg: list[np.ndarray] = []

    def add(self, t: np.ndarray, x: np.ndarray, phase: Any, leg: int) -> None:
        # a phase boundary is recorded twice, once per phase: the state is continuous there, the actuator rates jump
        self.t.append(t)
        self.x.append(x)
        self.phase.append(np.broadcast_to(np.asarray(phase), t.shape).copy())
        self.leg.append(np.full(t.size, leg))

    def arrays(self) -> tuple[np.ndarray, ...]:
        return tuple(np.concatenate(a) for a in (self.t, self.x, self.phase, self.leg))

    def max_depth_since(self, t0: float) -> float:
        return max(float(np.max(x[:, 2])) for t, x in zip(self.t, self.x, strict=True) if t.size and t[-1] >= t0)


@dataclass
class _Flight:
    """Mutable state of a mission in flight."""

    plant: ActuatedGlider3D
    plan: DivePlan
    law: Any
    mission: Mission
    rng: np.random.Generator
    gps_noise: float
    record_period: float
    rtol: float
    t_end: float
    rec: _Recorder = field(default_factory=_Recorder)
    t: float = 0.0
    leg: int = 0
    c_est: np.ndarray = field(default_factory=lambda: np.zeros(2))
    fix_time: float = 0.0
    leg_ends: list[tuple[float, str, np.ndarray, float]] = field(default_factory=list)
    dives: list[DiveMetrics] = field(default_factory=list)
    dive_start: float = 0.0
    dive_energy: float = 0.0
    leg_surfacings: list[int] = field(default_factory=list)
    profile: DiveProfile | None = None

    @property
    def done(self) -> bool:
        return self.leg >= self.mission.legs

    def target(self) -> tuple[float, float]:
        w = self.mission.waypoints[min(self.leg, self.mission.legs - 1)]
        return float(w[0]), float(w[1])

    def leg_start_time(self) -> float:
        return self.leg_ends[-1][0] if self.leg_ends else 0.0

    def end_leg(self, x: np.ndarray, reason: str) -> None:
        self.leg_ends.append((self.t, reason, np.array([x[1], x[0]]), float(x[21])))
        self.leg += 1

    def phase(self, x: np.ndarray, phase: int, depth: float) -> tuple[np.ndarray, str]:
        """Fly one dive or climb from ``x`` until ``depth``; returns the final state and what ended it."""
        while True:
            target = None if self.done else self.target()
            loop = MissionLoop(self.plant, self.plan, self.law, phase, target, tuple(self.c_est), self.t,
                               float(pitch_heading(x)[1]))
            if loop.distance_to_target(x) <= self.mission.arrival_radius:
                self.end_leg(x, "arrived")
                continue
            break
        g = self.plan.glide(phase)
        span = abs(depth - x[2])
        cap = _PHASE_MARGIN * span / max(abs(g.speed * math.sin(g.gamma)), 1e-3) + 600.0
        cap = min(cap, self.t_end - self.t)
        if cap <= 1.0:
            return x, "duration"
        radius = self.mission.arrival_radius

        def stop(t: float, y: np.ndarray) -> float:
            margin = phase * (depth - y[2])
            return min(margin, loop.distance_to_target(y) - radius)

        te = np.arange(0.0, cap, self.record_period)
        sim = simulate(loop, x, cap, t_eval=te, stop=stop, method="BDF", rtol=self.rtol,
                       atol=_ATOL, on_budget="stop")
        tt = self.t + sim.t
        end = sim.stopped_at if sim.stopped_at is not None else cap
        xe = sim.x_end
        X = np.vstack([sim.x, xe])
        self.rec.add(np.append(tt, self.t + end), X, phase, min(self.leg, self.mission.legs - 1))
        self.t += end
        if sim.stopped_by not in ("stop", "t_final"):
            return xe, f"integration budget ({sim.stopped_by})"
        if sim.stopped_by == "t_final":
            return xe, "duration" if self.t >= self.t_end - 1e-6 else "stalled"
        if phase * (depth - xe[2]) <= 1e-6:
            return xe, "depth"
        self.end_leg(xe, "arrived")
        return xe, "arrival"


_ATOL = np.array([1e-3] * 3 + [1e-8] * 4 + [1e-7] * 3 + [1e-8] * 3 + [1e-8, 1e-9, 1e-7, 1e-8, 1e-7, 1e-7] + [1e-3] * 2
                 + [1e-3])



def _leg_decision(f: _Flight, x: np.ndarray, fix: np.ndarray) -> None:
    """At a surfacing: end the leg if its waypoint is reached, unreachable in the estimated current, or late."""
    m = f.mission
    wp = np.asarray(f.target())
    U = min(f.plan.horizontal_speed(1), f.plan.horizontal_speed(-1))
    d = wp - fix
    dist = float(np.hypot(*d))
    dhat = d / max(dist, 1e-9)
    c_par = float(f.c_est @ dhat)
    c_perp = float(np.hypot(*(f.c_est - c_par * dhat)))
    made_good = math.sqrt(max(U * U - c_perp * c_perp, 0.0)) + c_par
    limit = m.leg_time_limit(f.leg, U)
    if dist <= m.arrival_radius:
        f.end_leg(x, "arrived")
    elif c_perp >= U or made_good < _UNREACHABLE_FRACTION * U:
        f.end_leg(x, f"unreachable: the depth-averaged current estimated at the surfacing, ({f.c_est[0]:+.3f}, "
                     f"{f.c_est[1]:+.3f}) m/s, leaves {made_good:.3f} m/s toward the waypoint at the glider's "
                     f"{U:.3f} m/s")
    elif f.t - f.leg_start_time() > limit:
        f.end_leg(x, f"timeout: {limit / 3600:.3g} h on the leg without arriving")


def _drift(f: _Flight, east_north: np.ndarray, hold: np.ndarray) -> np.ndarray:
    """Drift at the surface for ``surface_time`` with the water at depth 0 (recorded); returns the final position."""
    T = min(f.mission.surface_time, max(f.t_end - f.t, 0.0))      # no drift past the end of the run
    leg = min(f.leg, f.mission.legs - 1)
    if T <= 0:
        return east_north
    n = max(1, math.ceil(T / f.record_period))
    h = T / n
    pos = np.empty((n + 1, 2))
    pos[0] = east_north
    for k in range(n):   # midpoint rule: exact for a current that is uniform in space
        tm = f.t + (k + 0.5) * h
        half = pos[k] + 0.5 * h * f.plant.current.at(tm, np.array([*pos[k], 0.0]))
        pos[k + 1] = pos[k] + h * f.plant.current.at(tm, np.array([*half, 0.0]))
    X = np.tile(hold, (n + 1, 1))
    X[:, 0], X[:, 1], X[:, 2], X[:, 7:13] = pos[:, 1], pos[:, 0], 0.0, 0.0
    f.rec.add(f.t + h * np.arange(n + 1), X, 0, leg)
    f.t += T
    return pos[-1]


def _surface(f: _Flight, x: np.ndarray) -> np.ndarray:
    """Surfacing: GPS fix, dead-reckoning error, current estimate, leg decision, drift, second fix; returns the
    state the next dive starts from."""
    true = np.array([x[1], x[0]])
    fix = true + (f.rng.normal(0.0, f.gps_noise, 2) if f.gps_noise > 0 else 0.0)
    dr = x[19:21].copy()
    f.c_est = f.c_est + (fix - dr) / max(f.t - f.fix_time, 1e-9)
    deepest = f.rec.max_depth_since(f.dive_start)
    f.dives.append(DiveMetrics(f.dive_start, f.t, deepest, deepest - f.mission.depths[1], float(x[21] - f.dive_energy),
                               fix, float(np.hypot(*(fix - dr))), f.c_est.copy()))
    f.leg_surfacings.append(f.leg)
    if not f.done:
        _leg_decision(f, x, fix)
    pos = _drift(f, true, x)
    fix = pos + (f.rng.normal(0.0, f.gps_noise, 2) if f.gps_noise > 0 else 0.0)
    heading = float(pitch_heading(x)[1])   # the glider turns under water, not at the surface
    f.fix_time = f.dive_start = f.t
    f.dive_energy = float(x[21])
    return rest_state(f.plan, pos, fix, heading, f.dive_energy)


def _fast_dive(f: _Flight, x: np.ndarray) -> tuple[np.ndarray, str]:
    """One surfacing-to-surfacing dive of the fast model (:func:`~glidectl.missions.fast.replay_dive` of the
    calibrated dive), switching waypoints on arrival as the full model does."""
    assert f.profile is not None
    k = 0
    while True:
        if f.t >= f.t_end:
            return x, "duration"
        target = None if f.done else f.target()
        if target is not None and math.hypot(x[19] - target[0], x[20] - target[1]) <= f.mission.arrival_radius:
            f.end_leg(x, "arrived")
            continue
        rep = replay_dive(f.profile, x, f.t, target=target, current=f.plant.current, current_estimate=f.c_est,
                          arrival_radius=f.mission.arrival_radius, first=k)
        keep = rep.t <= f.t_end
        keep[0] = True                     # the dive's start (at or before the end of the run)
        late = not np.all(keep)
        t, X, phase = rep.t[keep], rep.states[keep], rep.phase[keep]
        f.rec.add(t, X, phase, min(f.leg, f.mission.legs - 1))
        f.t, x = float(t[-1]), X[-1].copy()
        if late:
            return x, "duration"
        if rep.stopped == "surface":
            return x, "surface"
        f.end_leg(x, "arrived")
        k = rep.index


def _dive(f: _Flight, x: np.ndarray) -> tuple[np.ndarray, str]:
    """One surfacing-to-surfacing dive (``yos`` yos); returns the state at the surface and what ended the dive
    (``"surface"`` or the reason the flight cannot go on)."""
    if f.profile is not None:
        return _fast_dive(f, x)
    top, bottom = f.mission.depths
    for yo in range(f.mission.yos):
        for phase, depth in ((1, bottom), (-1, top if yo < f.mission.yos - 1 else 0.0)):
            x, why = f.phase(x, phase, depth)
            while why == "arrival":       # the next waypoint, same phase
                x, why = f.phase(x, phase, depth)
            if why != "depth":
                return x, why
    return x, "surface"


def _legs(f: _Flight, hotel_power: float) -> tuple[LegMetrics, ...]:
    m = f.mission
    out = []
    start_t, start_pos, start_e = 0.0, np.asarray(m.start, dtype=float), 0.0
    for k, (t_end, reason, pos, energy) in enumerate(f.leg_ends):
        wp = np.asarray(m.waypoints[k], dtype=float)
        surf = [d for d, leg in zip(f.dives, f.leg_surfacings, strict=True) if leg == k]
        c_est = surf[-1].current_estimate if surf else (out[-1].current_estimate if out else np.zeros(2))
        out.append(LegMetrics(wp, start_t, t_end, reason,
                              float(np.hypot(*(wp - start_pos)) - np.hypot(*(wp - pos))),
                              energy - start_e + hotel_power * (t_end - start_t), float(np.hypot(*(wp - pos))),
                              surf[-1].dead_reckoning_error if surf else math.nan, np.array(c_est), len(surf)))
        start_t, start_pos, start_e = t_end, pos, energy
    return tuple(out)


def _setup(veh: Any, mission: Mission, controller: Any, current: Any, seed: int, steer: str, gps_noise: float,
           record_period: float, rtol: float, model: str, t_end: float,
           profile: DiveProfile | None = None, design_vehicle: Any = None) -> tuple[_Flight, str]:
    """The checked flight state of a mission (the arguments of :func:`fly_mission`)."""
    veh = require_glider(veh)
    if not isinstance(mission, Mission):
        raise ArgumentTypeError(f"mission must be a glidectl.Mission, got {type(mission).__name__}")
    rating = float(veh.params.get("depth_rating", MAX_MISSION_DEPTH))
    if mission.depths[1] > rating:
        raise InfeasibleGlideError(f"the mission dives to {mission.depths[1]:g} m, below the depth rating "
                                   f"{rating:g} m of vehicle '{veh.name}' ([parameters] depth_rating)")
    seed = checks.integer("seed", seed, lo=0)
    gps = checks.nonnegative("gps_noise", gps_noise, unit="m")
    period = checks.real("record_period", record_period, lo=0.1, hi=60.0, unit="s")
    rtol = checks.real("rtol", rtol, lo=1e-10, hi=1e-3)
    checks.choice("model", model, ("full", "fast"))
    law, name = _law(controller)
    plant = ActuatedGlider3D(veh, current)
    plan = DivePlan(_design_plant(plant, design_vehicle, current), mission.gamma, mission.speed, steer)
    if callable(getattr(law, "prepare", None)):
        law = law.prepare(plan)
    f = _Flight(plant, plan, law, mission, np.random.default_rng(seed), gps, period, rtol, t_end)
    if model == "fast":
        f.profile = profile if profile is not None else calibrate_dive(plant, plan, law, mission.depths, mission.yos,
                                                                       period, rtol)
    return f, name


def _design_plant(plant: ActuatedGlider3D, design_vehicle: Any, current: Any) -> ActuatedGlider3D:
    """The plant the dive plan (glides, set points, dead reckoning) is computed on: the flying one, or the
    ``design_vehicle``'s (checked: a glider with the same actuators)."""
    if design_vehicle is None:
        return plant
    dv = require_glider(design_vehicle, "design_vehicle")
    if dict(dv.actuators) != dict(plant.vehicle.actuators):
        raise ArgumentError(f"design_vehicle '{dv.name}' has other actuators than the flying vehicle "
                            f"'{plant.vehicle.name}': the controller must command the actuators the vehicle has")
    return ActuatedGlider3D(dv, current)


class GliderFlight:
    """A glider flown dive by dive toward waypoints given one dive at a time (a fleet's member): the flight of
    :func:`fly_mission` with the waypoint chosen at each surfacing by someone else.

    Parameters
    ----------
    veh : Vehicle
        As :func:`fly_mission`.
    mission : Mission
        Depths, glide, surface time and arrival radius of every dive; its ``start`` is the launch point (its
        waypoints are replaced dive by dive).
    controller, current, seed, steer, gps_noise, record_period, rtol, model :
        As :func:`fly_mission` (default ``model="fast"``).
    profile : DiveProfile, optional
        A calibrated dive of the same vehicle and settings to share between gliders (``model="fast"``).

    Attributes
    ----------
    time : float
        Mission time (s) at which the glider is next at the surface, ready to dive.
    position : ndarray, shape (2,)
        Its ``(east, north)`` there (m).
    """

    def __init__(self, veh: Any, mission: Mission, controller: Any = "behaviours", *, current: Any = None,
                 seed: int = 0, steer: str = "auto", gps_noise: float = 0.0, record_period: float = 2.0,
                 rtol: float = 1e-6, model: str = "fast", profile: DiveProfile | None = None) -> None:
        self._f, self.controller = _setup(veh, mission, controller, current, seed, steer, gps_noise, record_period,
                                          rtol, model, math.inf, profile)
        start = np.asarray(mission.start, dtype=float)
        self._x = rest_state(self._f.plan, start, start, 0.0)
        self._launched = False

    @property
    def time(self) -> float:
        """Mission time (s) of the glider's next dive start."""
        return self._f.t

    @property
    def position(self) -> np.ndarray:
        """``(east, north)`` (m) of the glider's next dive start."""
        return np.array([self._x[1], self._x[0]])

    @property
    def plan(self) -> DivePlan:
        """The designed glides the glider flies."""
        return self._f.plan

    @property
    def plant(self) -> ActuatedGlider3D:
        """The actuated glider (its vehicle, actuators and the current)."""
        return self._f.plant

    @property
    def profile(self) -> DiveProfile | None:
        """The calibrated dive of the fast model (None for the full model)."""
        return self._f.profile

    @property
    def dive_time(self) -> float:
        """Nominal time (s) of one dive and surfacing: the calibrated dive plus the surface time (for the full
        model the designed glides' time over the dive's depth spans, ``yos`` yos, plus the surface time: a few
        percent short, the inflections' transients left out)."""
        f = self._f
        if f.profile is not None:
            return f.profile.duration + f.mission.surface_time
        top, bottom = f.mission.depths
        sink = {p: abs(f.plan.glide(p).speed * math.sin(f.plan.glide(p).gamma)) for p in (1, -1)}
        yos = f.mission.yos
        down = bottom + (yos - 1) * (bottom - top)          # surface to bottom, then top to bottom
        up = bottom + (yos - 1) * (bottom - top)            # bottom to top, then bottom to the surface
        return down / sink[1] + up / sink[-1] + f.mission.surface_time

    def dive(self, waypoint: Any) -> tuple[DiveMetrics, tuple[np.ndarray, ...]]:
        """Fly one dive toward ``waypoint`` (east, north; m) and surface.

        Returns
        -------
        DiveMetrics
            The dive (its ``fix`` is the surfacing report).
        (t, states, phase) : tuple of ndarray
            The dive's samples (:data:`~glidectl.missions.loop.MISSION_STATES`), the surface time included.

        Raises
        ------
        ArgumentError
            If ``waypoint`` is not a finite (east, north) pair.
        SolverError
            If the dive cannot be flown (the glider stalls or the integration fails).
        """
        wp = checks.array("waypoint (east, north), m", waypoint, shape=(2,))
        f = self._f
        f.mission = dataclasses.replace(f.mission, waypoints=[tuple(wp)])
        f.leg, f.leg_ends = 0, []
        if not self._launched:          # the launch: pointing at the first waypoint
            heading = float(current_corrected_heading(self.position, wp, f.c_est, f.plan.horizontal_speed(1)))
            self._x = rest_state(f.plan, self.position, self._x[19:21], heading, float(self._x[21]))
            self._launched = True
        f.rec = _Recorder()
        x, why = _dive(f, self._x)
        if why != "surface":
            raise SolverError(f"the glider could not fly its dive toward {tuple(wp)}: {why}")
        self._x = _surface(f, x)
        t, X, phase, _ = f.rec.arrays()
        dive = f.dives[-1]
        # keep the flight's state small: it travels to an executor's worker and back every dive
        f.rec, f.dives, f.leg_surfacings, f.leg_ends = _Recorder(), [], [], []
        return dive, (t, X, phase)


def fly_mission(veh: Any, mission: Mission, controller: Any = "behaviours", *, current: Any = None, seed: int = 0,
                steer: str = "auto", gps_noise: float = 0.0, hotel_power: float = 0.0, record_period: float = 2.0,
                duration: float | None = None, rtol: float = 1e-6, model: str = "full",
                design_vehicle: Any = None) -> MissionRun:
    """Fly ``mission`` with vehicle ``veh`` (module docstring of :mod:`glidectl.missions.fly`).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with the 3D parameters and ``[actuators]`` for the pump (``m0``), the battery
        (``r_P1``) and a heading actuator (``roll`` or ``rudder``).
    mission : Mission
        Waypoints, depths, glide and surfacing settings.
    controller : str or object
        ``"behaviours"`` (:class:`~glidectl.missions.behaviours.GliderBehaviours` with its defaults), ``"lqr"``
        (:class:`~glidectl.missions.behaviours.DiveLQR`), or an object with ``rates(plant, plan, x, phase,
        heading_ref)`` (and optionally ``prepare(plan)`` returning the law to fly) such as a configured
        ``GliderBehaviours``.
    current : Current, (east, north), callable or None
        The water's velocity (m/s), unknown to the glider (:func:`~glidectl.environment.as_current`).
    seed : int
        Seed of the GPS noise (>= 0); the run is deterministic for a seed.
    steer : {"auto", "roll", "rudder"}
        Heading actuator (``"auto"``: roll when the vehicle rolls its battery, else the rudder).
    gps_noise : float
        Standard deviation (m) of each GPS fix coordinate, >= 0 (default 0).
    hotel_power : float
        Power (W) of everything but the pump (computer, sensors), >= 0, added to each leg's energy (default 0).
    record_period : float
        Spacing (s) of the recorded samples, in ``[0.1, 60]`` (default 2 s).
    duration : float, optional
        Longest mission time (s); default: until the last leg ends.
    rtol : float
        Relative tolerance of the integrator, in ``[1e-10, 1e-3]``.
    model : {"full", "fast"}
        ``"full"``: every dive integrated with the 3-D actuated model. ``"fast"``: one dive of the full model in
        still water, replayed along each dive's turning track through the current
        (:mod:`glidectl.missions.fast`); for long missions and fleets, its error against the full model is in
        ``bench/README.md``.
    design_vehicle : Vehicle, optional
        The vehicle the dive plan is computed on (the glides' pump and battery set points, the speeds of dead
        reckoning; default ``veh``): ``veh`` then flies a plan made for another vehicle, as a glider whose
        coefficients are not known exactly does (:func:`glidectl.mission_ensemble`). Its actuators must be
        ``veh``'s.

    Returns
    -------
    MissionRun

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``mission`` not a Mission, ``controller`` not a controller, or a number is not
        real.
    ArgumentError
        If a number is outside its range or the current is not a current.
    ModelError
        If the vehicle lacks the 3D parameters, the pump or battery actuators, or a heading actuator (the message
        names what is missing).
    InfeasibleGlideError
        If the mission's glides are outside the flight envelope or the actuator ranges, or its bottom depth is below
        the vehicle's ``depth_rating``.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("slocum_shallow")
    >>> mission = gc.Mission(waypoints=[(150.0, 0.0)], depths=(5.0, 20.0), surface_time=60.0, arrival_radius=50.0)
    >>> run = gc.fly_mission(veh, mission, model="fast")
    >>> leg = run.legs[0]
    >>> print(f"{leg.reason} after {leg.dives} dive, {run.duration / 60:.1f} min")
    arrived after 1 dive, 13.5 min
    """
    hotel = checks.nonnegative("hotel_power", hotel_power, unit="W")
    t_end = math.inf if duration is None else checks.positive("duration", duration, unit="s")
    f, name = _setup(veh, mission, controller, current, seed, steer, gps_noise, record_period, rtol, model, t_end,
                     design_vehicle=design_vehicle)
    plant, plan = f.plant, f.plan
    start = np.asarray(mission.start, dtype=float)
    heading = float(current_corrected_heading(start, f.target(), f.c_est, plan.horizontal_speed(1)))
    x = rest_state(plan, start, start, heading)
    ended_by = "last leg ended"
    while not f.done:
        x, why = _dive(f, x)
        if why != "surface":
            ended_by = why
            break
        x = _surface(f, x)
    if ended_by != "last leg ended":
        while not f.done:
            f.end_leg(x, f"mission end: {ended_by}")
    t, X, phase, leg = f.rec.arrays()
    return MissionRun(t, X, phase, leg, _legs(f, hotel), tuple(f.dives), ended_by, mission,
                      plant.current, name, seed, veh, plant, veh.provenance)
