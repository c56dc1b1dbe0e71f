"""A fleet of gliders coordinated at their surfacings (thesis chapter 3): :func:`fly_fleet` and :class:`FleetRun`.

Each glider is a :class:`~glidectl.missions.fly.GliderFlight` (its own vehicle file, controller and dive settings;
the fast vehicle model by default). The fleet advances in **rounds**: in each round every glider still in the run
flies one dive (surface to surface, surface time included) toward the waypoint the coordinator gave it when it
surfaced. A glider's surfacing report (time, GPS fix) reaches the coordinator ``delay`` seconds later; the waypoint
of glider ``i`` surfacing at ``t_i`` uses the reports that have arrived by ``t_i`` (its own fix at once). Within a
round the gliders are independent, so the round's dives run on ``executor`` (``concurrent.futures`` or dask's
``Client.get_executor()``, as :func:`~glidectl.helix_sweep`), and the run is the same whatever the executor: every
dive depends only on its glider's state and waypoint.

Causality: a round holds each glider to one dive, so a decision could miss a report from a glider a whole dive
ahead of it. :attr:`FleetRun.late_reports` counts the reports that a decision did not see although they arrived
in time (0 when the gliders' dives take the same time, as in the designs).
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, GlidectlError, InfeasibleGlideError, SolverError
from ..missions.fast import tightest_turn
from ..missions.fly import GliderFlight
from ..missions.mission import Mission
from ..params import Vehicle

__all__ = ["DEFAULT_DIVES", "FleetRun", "fly_fleet"]


def _fly_one(flight: GliderFlight, waypoint: np.ndarray) -> tuple[GliderFlight, Any, Any]:
    """One dive of one glider (the unit of work an executor runs); returns the glider, its dive and samples."""
    dive, samples = flight.dive(waypoint)
    return flight, dive, samples


@dataclass(frozen=True)
class FleetRun:
    """A fleet's run (module docstring of :mod:`glidectl.fleets.fleet`).

    Attributes
    ----------
    t : tuple of ndarray
        Sample times (s) of each glider.
    states : tuple of ndarray
        Each glider's samples (:data:`~glidectl.missions.loop.MISSION_STATES`).
    surfacings : tuple of (float, int, ndarray)
        ``(time, glider, fix)`` of every surfacing, in time order.
    waypoints : tuple of (float, int, ndarray)
        ``(time, glider, waypoint)`` of every waypoint issued.
    late_reports : int
        Reports a decision missed although they had arrived (module docstring).
    coordinator : object
    vehicles : tuple of Vehicle
    seed : int
    executor : str
        The executor's class, or ``"serial"``.
    ended_by : str
        ``"duration"``, or why the run stopped early (a glider that could not fly its dive, with the message).
    """

    t: tuple[np.ndarray, ...]
    states: tuple[np.ndarray, ...]
    surfacings: tuple[tuple[float, int, np.ndarray], ...]
    waypoints: tuple[tuple[float, int, np.ndarray], ...]
    late_reports: int
    coordinator: Any = field(repr=False)
    vehicles: tuple[Vehicle, ...] = field(repr=False)
    seed: int = 0
    executor: str = "serial"
    ended_by: str = "duration"

    @property
    def size(self) -> int:
        """Number of gliders."""
        return len(self.t)

    def position(self, i: int) -> np.ndarray:
        """``(east, north, depth)`` (m) of glider ``i`` at its samples, shape ``(N_i, 3)``.

        Raises
        ------
        ArgumentError
            If ``i`` is not a glider of the fleet.
        """
        i = checks.integer("i", i, lo=0, hi=self.size - 1)
        return self.states[i][:, [1, 0, 2]]

    def positions_at(self, times: Any) -> np.ndarray:
        """Horizontal positions (east, north; m) of every glider at ``times`` (s), shape ``(len(times), n, 2)``
        (linear between samples, held before the first and after the last)."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        out = np.empty((times.size, self.size, 2))
        for i in range(self.size):
            t, pos = self.t[i], self.position(i)
            keep = np.r_[True, np.diff(t) > 0]
            out[:, i, 0] = np.interp(times, t[keep], pos[keep, 0])
            out[:, i, 1] = np.interp(times, t[keep], pos[keep, 1])
        return out

    def mean_spacing(self, step: float = 600.0) -> tuple[np.ndarray, np.ndarray]:
        """Mean distance (m) between the gliders, every ``step`` seconds over the run (Fig 3.3): ``(times,
        spacing)``."""
        step = checks.positive("step", step, unit="s")
        end = min(float(t[-1]) for t in self.t)
        times = np.arange(0.0, end + 1e-9, step)
        P = self.positions_at(times)
        pairs = list(itertools.combinations(range(self.size), 2))
        d = np.mean([np.hypot(*(P[:, i] - P[:, j]).T) for i, j in pairs], axis=0)
        return times, d

    def desired_spacing(self, times: Any) -> np.ndarray:
        """The coordinator's scheduled spacing (m) at ``times`` (s) (NaN without a schedule)."""
        f = getattr(self.coordinator, "spacing_at", None)
        return np.array([f(float(t)) if f else math.nan for t in np.atleast_1d(times)])

    def plot(self, ax: Any = None) -> Any:
        """Map of the tracks with snapshots of the formation (Fig 3.2) and the mean spacing against the desired one
        (Fig 3.3).

        Returns
        -------
        ndarray of Axes, shape (2,)
        """
        from ..plotting import plot_fleet_run
        return plot_fleet_run(self, ax)


def _check_members(vehicles: Any, starts: Any, mission: Any) -> tuple[list[Vehicle], np.ndarray]:
    if isinstance(vehicles, Vehicle) or not isinstance(vehicles, Sequence) or len(vehicles) == 0:
        raise ArgumentError("vehicles must be a non-empty sequence of glidectl.Vehicle (one per glider)")
    for v in vehicles:
        checks.vehicle("vehicles[i]", v, "underwater_glider")
    if not isinstance(mission, Mission):
        raise ArgumentTypeError(f"mission must be a glidectl.Mission (the dive settings), got {type(mission).__name__}")
    s = checks.array("starts (east, north), m", starts)
    if s.shape != (len(vehicles), 2):
        raise ArgumentError(f"starts must give one (east, north) per glider, shape ({len(vehicles)}, 2); got {s.shape}")
    return list(vehicles), s


def _check_feasible(coordinator: Any, flights: list[GliderFlight]) -> None:
    """A leader slower than every glider; a spacing no tighter than any glider's tightest turn."""
    speed = getattr(coordinator, "leader_speed", None)
    sched = getattr(coordinator, "schedule", None)
    spacing = min(s for _, s in sched) if sched else getattr(coordinator, "spacing", None)
    for k, g in enumerate(flights):
        plan = g.plan
        u = min(plan.horizontal_speed(1), plan.horizontal_speed(-1))
        if speed is not None and speed >= u:
            raise InfeasibleGlideError(f"the leader moves at {speed:g} m/s, as fast as or faster than glider {k}'s "
                                       f"horizontal speed {u:.3g} m/s: the formation cannot keep up")
        if isinstance(spacing, float):
            r = tightest_turn(g.plant, plan)
            if spacing < r:
                raise InfeasibleGlideError(f"the formation asks for a spacing of {spacing:g} m, below glider {k}'s "
                                           f"tightest turn radius {r:.4g} m ({plan.steer}): it cannot hold its slot")


#: Dive settings of a fleet's gliders when ``fly_fleet`` is given none: 5-100 m dives at 25 deg and 0.35 m/s, five
#: minutes at the surface (its waypoint is a placeholder: the coordinator gives them).
DEFAULT_DIVES = Mission(waypoints=[(1.0, 0.0)], depths=(5.0, 100.0), surface_time=300.0)


def fly_fleet(vehicles: Sequence[Vehicle], coordinator: Any, *, mission: Mission = DEFAULT_DIVES, starts: Any = None,
              current: Any = None, duration: float, delay: float = 0.0, seed: int = 0, executor: Any = None,
              model: str = "fast", controller: Any = "behaviours", record_period: float = 10.0) -> FleetRun:
    """Fly a fleet coordinated at its surfacings (module docstring).

    Parameters
    ----------
    vehicles : sequence of Vehicle
        One vehicle file per glider (3D, with a heading actuator).
    coordinator : object
        ``coordinator.waypoint(i, n, t, horizon, reports)`` returns glider ``i``'s next waypoint (east, north; m),
        e.g. :class:`~glidectl.fleets.formation.FormationControl`. The run flies a copy (a stateful coordinator
        such as :class:`~glidectl.fleets.formation.GradientClimbing` starts afresh; :attr:`FleetRun.coordinator`
        is the copy, with its state at the end).
    mission : Mission
        Dive settings of every glider (depths, gamma, speed, surface time, arrival radius); its waypoints are not
        used. Default :data:`DEFAULT_DIVES`.
    starts : array_like, shape (n, 2), optional
        Launch points (east, north; m); default the coordinator's slots at ``t = 0`` (``coordinator.slots``).
    current : Current, (east, north), callable or None
        The water's velocity, the same for every glider and unknown to the coordinator.
    duration : float
        Length of the run (s): gliders stop diving after it.
    delay : float
        Communication delay (s) of a surfacing report, in ``[0, one dive)``.
    seed : int
        Seed (>= 0); each glider's stream is spawned from it.
    executor : concurrent.futures.Executor, optional
        Runs each round's dives (``executor.submit``); ``None``: in this process.
    model : {"fast", "full"}
        As :class:`~glidectl.missions.fly.GliderFlight` (default the fast model).
    controller : str, controller object, or a sequence of them
        Each glider's onboard controller (one for all, or one per glider), as :func:`~glidectl.fly_mission`
        (default the glider behaviours).
    record_period : float
        Spacing (s) of the recorded samples and of the fast model's calibrated dive (default 10 s: a glider's state
        travels to an executor's worker and back every dive, and its size is the calibrated dive's).

    Returns
    -------
    FleetRun

    Raises
    ------
    ArgumentTypeError
        If an argument has the wrong type (a coordinator without ``waypoint``, an executor without ``submit``).
    ArgumentError
        An empty fleet, starts not one per glider, a delay outside ``[0, one dive)``, a formation that needs
        another number of gliders.
    InfeasibleGlideError
        A leader as fast as a glider, a spacing below a glider's tightest turn, or a glide a vehicle cannot fly.
    ModelError
        A vehicle that is not a 3D underwater glider with a heading actuator.
    SolverError
        If a glider cannot fly its first dive (a later failure ends the run with :attr:`FleetRun.ended_by`).
    """
    if not callable(getattr(coordinator, "waypoint", None)):
        raise ArgumentTypeError(f"coordinator must have waypoint(i, n, t, horizon, reports), got "
                                f"{type(coordinator).__name__}")
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise ArgumentTypeError(f"executor must be a concurrent.futures.Executor (with submit), got "
                                f"{type(executor).__name__}")
    n = len(vehicles) if isinstance(vehicles, Sequence) and not isinstance(vehicles, Vehicle) else 0
    if starts is None and n and callable(getattr(coordinator, "slots", None)):
        starts = coordinator.slots(n, 0.0)
    vehs, S = _check_members(vehicles, starts, mission)
    T = checks.positive("duration", duration, unit="s")
    seed = checks.integer("seed", seed, lo=0)
    seeds = [int(s.generate_state(1)[0] % (2**31)) for s in np.random.SeedSequence(seed).spawn(n)]
    per_glider = isinstance(controller, Sequence) and not isinstance(controller, str)
    if per_glider and len(controller) != n:
        raise ArgumentError(f"controller gives {len(controller)} controllers for {n} gliders; give one, or one per "
                            "glider")
    profiles: dict[Any, Any] = {}
    flights = []
    for k, v in enumerate(vehs):
        ctrl = controller[k] if per_glider else controller
        m = Mission(waypoints=[tuple(S[k] + (1.0, 0.0))], depths=mission.depths, gamma=mission.gamma,
                    speed=mission.speed, surface_time=mission.surface_time, arrival_radius=mission.arrival_radius,
                    start=tuple(S[k]), yos=mission.yos)
        key = (v.provenance, repr(ctrl))
        g = GliderFlight(v, m, ctrl, current=current, seed=seeds[k], model=model, record_period=record_period,
                         profile=profiles.get(key))
        profiles.setdefault(key, g.profile)
        flights.append(g)
    coordinator = copy.deepcopy(coordinator)     # a stateful coordinator starts every run afresh
    _check_feasible(coordinator, flights)
    dive_min = min(g.dive_time for g in flights)
    delay = checks.real("delay", delay, lo=0.0, hi=dive_min, hi_open=True, unit="s")
    return _rounds(flights, coordinator, T, delay, executor, vehs, seed)


def _rounds(flights: list[GliderFlight], coordinator: Any, T: float, delay: float, executor: Any,
            vehs: list[Vehicle], seed: int) -> FleetRun:
    n = len(flights)
    ended_by = "duration"
    reports: list[tuple[float, int, np.ndarray]] = [(0.0, k, g.position) for k, g in enumerate(flights)]
    samples: list[list[tuple[np.ndarray, np.ndarray]]] = [[] for _ in range(n)]
    issued: list[tuple[float, int, np.ndarray]] = []
    late = 0
    while True:
        active = [k for k, g in enumerate(flights) if g.time < T]
        if not active:
            break
        wps = {}
        decided = {k: flights[k].time for k in active}
        for k in active:
            t = flights[k].time
            known: dict[int, tuple[float, np.ndarray]] = {}
            for (tr, j, p) in reports:      # reports in time order: the last one that has arrived wins
                if (j == k and tr <= t) or (j != k and tr + delay <= t):
                    known[j] = (tr, p)
            wps[k] = np.asarray(coordinator.waypoint(k, n, t, flights[k].dive_time, known), dtype=float)
            issued.append((t, k, wps[k]))
        try:
            if executor is None:
                results = [_fly_one(flights[k], wps[k]) for k in active]
            else:
                futures = [executor.submit(_fly_one, flights[k], wps[k]) for k in active]
                results = [f.result() for f in futures]
        except GlidectlError as exc:     # a glider that cannot fly its dive ends the run, with the reason
            ended_by = f"a glider could not fly its dive: {exc}"
            break
        new = []
        for k, (g, dive, (t, X, _)) in zip(active, results, strict=True):
            flights[k] = g
            samples[k].append((t, X))
            new.append((dive.end, k, dive.fix))
        # a report of this round that had arrived before another glider's decision of this round: missed
        late += sum(1 for (tr, j, _) in new for k, td in decided.items() if j != k and tr + delay <= td)
        reports = sorted(reports + new, key=lambda r: (r[0], r[1]))
    if any(not s for s in samples):
        raise SolverError(f"the fleet flew no dive: {ended_by}")
    ts = tuple(np.concatenate([a for a, _ in s]) for s in samples)
    xs = tuple(np.concatenate([b for _, b in s]) for s in samples)
    surf = tuple((tr, j, p) for tr, j, p in reports if tr > 0)
    ex = "serial" if executor is None else f"{type(executor).__module__}.{type(executor).__qualname__}"
    return FleetRun(ts, xs, surf, tuple(issued), late, coordinator, tuple(vehs), seed, ex, ended_by)

