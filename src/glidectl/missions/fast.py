"""A fast vehicle model for long missions and fleets: the full model's own dive, replayed along a turning track.

:func:`calibrate_dive` flies one surface-to-surface dive of the mission (``yos`` yos) with the full 3-D actuated
model in still water on a fixed heading and keeps its samples: depth, horizontal speed through the water, the dead
reckoning's speed estimate, pump energy and every state (attitude, velocities, actuators), transients at the
inflections included. :func:`replay_dive` then flies that dive from any start, heading, waypoint and current: at
each sample

    psi' = psidot_turn(setpoint(psi_ref - psi)),
    position' = u(t) (sin psi, cos psi) + c(t, position, z(t)),
    dead reckoning' = u_dr(t) (sin psi, cos psi) + c_est,

with ``psi_ref`` the current-corrected heading from the dead-reckoned position (as the full loop's) and the turn
rate the behaviours' steering setpoint gives in a steady turn: the setpoint ``dz(wrap(psi_ref - psi)) /
(heading_time dpsidot/du)`` of the heading law, then the steady turn rate of that setting, interpolated in a table
of helices of the glide (:func:`~glidectl.trim.turn.turn_helix`, up to the actuator's limit or the end of the
stable branch). Position is advanced by the midpoint
rule on the profile's samples. What it leaves out: the turn's own effect on the glide (speed and sink in a banked
turn) and the transient of the heading loop. Its error against the full model on the same mission is measured by
the tests and ``bench/README.md``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..environment import Current
from ..errors import GlidectlError
from ..models.actuated3d import ActuatedGlider3D
from ..sim import simulate
from ..trim.turn import turn_helix
from .behaviours import DivePlan, dead_zone, pitch_heading, wrap_angle
from .loop import MissionLoop, current_corrected_heading, rest_state

__all__ = ["TURN_TABLE_FRACTIONS", "DiveProfile", "ReplayedDive", "calibrate_dive", "replay_dive", "replay_errors",
           "tightest_turn", "turn_table"]

_ATOL = np.array([1e-3] * 3 + [1e-8] * 4 + [1e-7] * 3 + [1e-8] * 3 + [1e-8, 1e-9, 1e-7, 1e-8, 1e-7, 1e-7] + [1e-3] * 3)


@dataclass(frozen=True)
class DiveProfile:
    """One surface-to-surface dive of the full model in still water on a fixed heading (:func:`calibrate_dive`).

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time from the dive's start (s), non-decreasing (each inflection recorded twice).
    states : ndarray, shape (N, 22)
        The loop's states (:data:`~glidectl.missions.loop.MISSION_STATES`) from the rest state at the origin,
        heading north.
    phase : ndarray of int, shape (N,)
        ``+1`` dive, ``-1`` climb.
    speed, dr_speed : ndarray, shape (N,)
        Horizontal speed through the water (m/s) and the dead reckoning's estimate of it (m/s).
    turn_tables : dict of int to (ndarray, ndarray)
        Steering settings (rad) and the steady turn rates (rad/s) they give, on the dive (+1) and the climb (-1)
        (:func:`~glidectl.trim.turn.turn_helix`); the heading law's setpoint, clipped to the table, gives the turn
        rate by linear interpolation.
    heading_deadband, heading_time : float
        Deadband (rad) and time constant (s) of the replayed heading law: the onboard law's time constant and no
        deadband (the full model's turn transients carry the heading on past the deadband's edge: measured, a
        replay with the deadband misses the full model's surfacings by twice as much).
    """

    t: np.ndarray
    states: np.ndarray
    phase: np.ndarray
    speed: np.ndarray
    dr_speed: np.ndarray
    turn_tables: dict[int, tuple[np.ndarray, np.ndarray]]
    heading_deadband: float
    heading_time: float
    plan: DivePlan = field(repr=False)

    @property
    def duration(self) -> float:
        """Dive time, surface to surface (s)."""
        return float(self.t[-1])

    @property
    def energy(self) -> float:
        """Pump energy of the dive (J)."""
        return float(self.states[-1, 21] - self.states[0, 21])


def _heading_law(law: Any) -> Any:
    """The behaviours whose heading law the controller flies (``law`` itself, or the LQR's ``heading``)."""
    return getattr(law, "heading", law)


def calibrate_dive(plant: ActuatedGlider3D, plan: DivePlan, law: Any, depths: tuple[float, float], yos: int = 1,
                   record_period: float = 2.0, rtol: float = 1e-6) -> DiveProfile:
    """Fly one dive of the full model in still water on a fixed heading and keep it (module docstring).

    Parameters
    ----------
    plant : ActuatedGlider3D
        The glider (its current is ignored: the calibration is in still water).
    plan : DivePlan
    law : object
        The prepared onboard law (``GliderBehaviours`` or a prepared ``DiveLQR``).
    depths : (float, float)
        Top and bottom inflection depths (m).
    yos : int
        Yos before the glider surfaces.
    record_period : float
        Spacing of the samples (s).
    rtol : float
        Relative tolerance of the integration.

    Returns
    -------
    DiveProfile
    """
    still = ActuatedGlider3D(plant.vehicle, None, plant.servo_time, plant.pump_gain, plant.rudder_gain)
    x = rest_state(plan, np.zeros(2), np.zeros(2), 0.0)
    t0, ts, xs, ph = 0.0, [], [], []
    top, bottom = depths
    for yo in range(yos):
        for phase, depth in ((1, bottom), (-1, top if yo < yos - 1 else 0.0)):
            loop = MissionLoop(still, plan, law, phase, None, (0.0, 0.0), t0, 0.0)
            g = plan.glide(phase)
            cap = 4.0 * abs(depth - x[2]) / max(abs(g.speed * math.sin(g.gamma)), 1e-3) + 600.0

            def stop(t: float, y: np.ndarray, p: int = phase, d: float = depth) -> float:
                return p * (d - y[2])

            sim = simulate(loop, x, cap, t_eval=np.arange(0.0, cap, record_period), stop=stop, method="BDF",
                           rtol=rtol, atol=_ATOL, on_budget="stop")
            end = sim.stopped_at if sim.stopped_at is not None else cap
            ts.append(np.append(t0 + sim.t, t0 + end))
            xs.append(np.vstack([sim.x, sim.x_end]))
            ph.append(np.full(sim.t.size + 1, phase))
            x, t0 = sim.x_end.copy(), t0 + end
    t, X, phase = np.concatenate(ts), np.concatenate(xs), np.concatenate(ph)
    loop_rate = np.empty((t.size, 2))
    for p in (1, -1):
        sel = phase == p
        loop = MissionLoop(still, plan, law, p, None)
        d = loop.rhs(X[sel])
        loop_rate[sel, 0] = np.hypot(d[:, 0], d[:, 1])        # horizontal speed through still water
        loop_rate[sel, 1] = np.hypot(d[:, 19], d[:, 20])      # the dead reckoning's speed
    heading = _heading_law(law)
    i = plant.actuator_names.index(plan.steer)
    lim = min(abs(plant.lower[i]), abs(plant.upper[i]))
    tables = {p: turn_table(plant, plan, p, lim) for p in (1, -1)}
    # no deadband in the replay: in the full model the turn's yaw and roll transients carry the heading on after the
    # steering centres at the deadband's edge, so it settles near the reference (halves the per-dive error)
    return DiveProfile(t, X, phase, loop_rate[:, 0], loop_rate[:, 1], tables, 0.0, float(heading.heading_time),
                       plan)


#: Fractions of the steering range at which :func:`calibrate_dive` trims the steady turns of each glide.
TURN_TABLE_FRACTIONS = (0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 1.0)


def turn_table(plant: ActuatedGlider3D, plan: DivePlan, phase: int, limit: float) -> tuple[np.ndarray, np.ndarray]:
    """Steady turn rate (rad/s) against the steering setting (rad) of one glide, on the stable branch continued
    from the straight glide (odd in the setting by symmetry); the table ends where the branch does."""
    g = plan.glide(phase)
    settings, rates, guess = [0.0], [0.0], None
    for frac in TURN_TABLE_FRACTIONS[1:]:
        u = frac * limit
        try:
            h = turn_helix(plant.vehicle, g, plan.steer, u, guess=guess)
        except GlidectlError:
            break
        if not h.stable or (rates[-1] != 0.0 and h.psidot * rates[-1] <= 0):
            break
        settings.append(u)
        rates.append(h.psidot)
        guess = h
    s, r = np.array(settings), np.array(rates)
    return np.r_[-s[:0:-1], s], np.r_[-r[:0:-1], r]


@dataclass
class ReplayedDive:
    """What :func:`replay_dive` returns: the samples of the replayed dive and where it stopped."""

    t: np.ndarray
    states: np.ndarray
    phase: np.ndarray
    stopped: str                   # "surface" or "arrival"
    index: int                     # profile sample where it stopped


def replay_dive(profile: DiveProfile, start: np.ndarray, t0: float, *, target: Any, current: Current,
                current_estimate: np.ndarray, arrival_radius: float, first: int = 0,
                arrived: Callable[[np.ndarray], bool] | None = None) -> ReplayedDive:
    """Fly ``profile`` from sample ``first`` with the loop state ``start`` (shape (22,): position, heading in its
    quaternion, dead reckoning, energy) from mission time ``t0`` (s) toward ``target`` (east, north; None: hold the
    heading) through ``current``; stops at the surface or when the dead reckoning comes within ``arrival_radius``
    (m) of the target (module docstring)."""
    prof = profile
    k_end = prof.t.size - 1
    pos = np.array([start[1], start[0]], dtype=float)            # east, north
    dr = np.array(start[19:21], dtype=float)
    psi = float(pitch_heading(start[:19])[1])
    hold = psi
    e0 = float(start[21]) - float(prof.states[first, 21])
    U = {p: prof.plan.horizontal_speed(p) for p in (1, -1)}
    out_t, out_x = [t0], [_state(prof, first, pos, psi, dr, e0)]
    k = first
    while k < k_end:
        dt = prof.t[k + 1] - prof.t[k]
        p = int(prof.phase[k + 1])
        if dt > 0:
            ref = hold if target is None else float(current_corrected_heading(dr, target, current_estimate, U[p]))
            setting = dead_zone(wrap_angle(ref - psi), prof.heading_deadband) / (
                prof.heading_time * prof.plan.turn_gain[p])          # the behaviours' steering setpoint
            table_u, table_r = prof.turn_tables[p]
            rate = float(np.interp(setting, table_u, table_r))    # clipped to the table's ends
            psi_mid = psi + 0.5 * dt * rate
            u, udr = 0.5 * (prof.speed[k] + prof.speed[k + 1]), 0.5 * (prof.dr_speed[k] + prof.dr_speed[k + 1])
            z_mid = 0.5 * (prof.states[k, 2] + prof.states[k + 1, 2])
            tm = t0 + 0.5 * (prof.t[k] + prof.t[k + 1]) - prof.t[first]
            heading = np.array([math.sin(psi_mid), math.cos(psi_mid)])
            c_mid = current.at(tm, np.array([*pos, z_mid]))
            pos = pos + dt * (u * heading + c_mid)
            dr = dr + dt * (udr * heading + current_estimate)
            psi = float(wrap_angle(psi + dt * rate))
        k += 1
        out_t.append(t0 + prof.t[k] - prof.t[first])
        out_x.append(_state(prof, k, pos, psi, dr, e0))
        if target is not None and math.hypot(dr[0] - target[0], dr[1] - target[1]) <= arrival_radius:
            return ReplayedDive(np.array(out_t), np.array(out_x), prof.phase[first:k + 1].copy(), "arrival", k)
    return ReplayedDive(np.array(out_t), np.array(out_x), prof.phase[first:k + 1].copy(), "surface", k)


def _state(prof: DiveProfile, k: int, pos: np.ndarray, psi: float, dr: np.ndarray, e0: float) -> np.ndarray:
    """The loop state at profile sample ``k`` with its position, heading, dead reckoning and energy replaced."""
    x = prof.states[k].copy()
    _, psi0 = pitch_heading(x[:19])
    rot = _yaw_quaternion(psi - float(psi0))
    x[3:7] = _quat_mul(rot, x[3:7])                 # the calibrated attitude turned to heading psi
    x[0], x[1] = pos[1], pos[0]
    x[19], x[20] = dr
    x[21] = x[21] + e0
    return x


def _yaw_quaternion(dpsi: float) -> np.ndarray:
    return np.array([math.cos(dpsi / 2), 0.0, 0.0, math.sin(dpsi / 2)])


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def tightest_turn(plant: ActuatedGlider3D, plan: DivePlan) -> float:
    """Radius (m) of the tightest steady turn both glides of ``plan`` can fly with the steering actuator in its
    range (the larger of the dive's and the climb's tightest radius, from :func:`turn_table`)."""
    i = plant.actuator_names.index(plan.steer)
    lim = min(abs(plant.lower[i]), abs(plant.upper[i]))
    radii = []
    for p in (1, -1):
        _, rates = turn_table(plant, plan, p, lim)
        top = float(np.max(np.abs(rates)))
        radii.append(plan.horizontal_speed(p) / top if top > 0 else math.inf)
    return max(radii)


def replay_errors(run: Any, law: Any = None) -> np.ndarray:
    """How far the fast model strays from a full-model run, dive by dive: each dive of ``run`` (a
    :class:`~glidectl.missions.fly.MissionRun` of the full model) without a waypoint switch under water is replayed
    from the same start toward the same waypoint with the same current estimate, and its surfacing compared with
    the full model's fix.

    Parameters
    ----------
    run : MissionRun
    law : object, optional
        The onboard law the run flew (default the glider behaviours).

    Returns
    -------
    ndarray, shape (k, 2)
        Per compared dive: the distance (m) between the replay's surfacing and the fix, and that distance over the
        dive's horizontal displacement.
    """
    from .behaviours import GliderBehaviours

    m = run.mission
    plan = DivePlan(run.plant, m.gamma, m.speed)
    law = GliderBehaviours() if law is None else law
    prof = calibrate_dive(run.plant, plan, law.prepare(plan) if hasattr(law, "prepare") else law, m.depths, m.yos)
    rows = []
    for i, d in enumerate(run.dives):
        sel = (run.t >= d.start) & (run.t <= d.end)
        if len(set(run.leg[sel])) > 1:
            continue
        k = int(np.argmax(sel))
        x0 = run.states[k]
        c_est = run.dives[i - 1].current_estimate if i else np.zeros(2)
        rep = replay_dive(prof, x0, d.start, target=tuple(m.waypoints[run.leg[k]]), current=run.current,
                          current_estimate=c_est, arrival_radius=-1.0)
        end = rep.states[-1]
        err = math.hypot(end[1] - d.fix[0], end[0] - d.fix[1])
        rows.append((err, err / math.hypot(d.fix[0] - x0[1], d.fix[1] - x0[0])))
    return np.array(rows).reshape(-1, 2)
