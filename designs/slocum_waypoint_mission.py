"""A waypoint mission of the Slocum-class ``slocum_shallow`` preset in a depth-varying current: the glider flies
a box of four waypoints 2 km apart in 100 m dives, surfaces after each dive for a GPS fix, estimates the
depth-averaged current from its dead-reckoning error and steers into it with its rudder.

Two controller sets fly the same mission (``gc.fly_mission``): the glider behaviours of Slocum and Seaglider
flight software (``"behaviours"``: pump only at the inflections, battery on pitch and rudder on heading with
deadbands) and the LQR dive controller (``"lqr"``: the longitudinal LQG design's regulator as full-state feedback,
the behaviours' heading law). The per-leg table gives the distance made good, time, energy, arrival error,
dead-reckoning error and current estimate; the estimate is compared with the depth average of the current the
simulation applied. A designed turn closes the report: ``gc.design_turn`` gives the rudder angle of a 150 m turn,
the glider flies it as a spiral dive, and the simulated radius is compared with the helix of ``gc.helix_trim``.

No publication prints this mission: the report is a results table. Run ``glidectl report slocum_waypoint_mission``
or ``python designs/slocum_waypoint_mission.py [OUTDIR] [--quick]``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import glidectl as gc
from glidectl.report import Report, run_script

TITLE = "A waypoint mission in a depth-varying current: glider behaviours against the LQR dive controller"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 8.0, "full": 30.0}
CONTROLLERS = ("behaviours", "lqr")


@dataclass(frozen=True)
class Settings:
    """Every setting of the design."""

    vehicle: str = "slocum_shallow"
    waypoints: tuple[tuple[float, float], ...] = ((2000.0, 0.0), (2000.0, 2000.0), (0.0, 2000.0), (0.0, 0.0))
    depths: tuple[float, float] = (5.0, 100.0)  # m
    gamma_deg: float = 25.0
    speed: float = 0.35  # m/s
    surface_time: float = 600.0  # s per surfacing: GPS fix and data
    arrival_radius: float = 100.0  # m
    #: current profile (design choice: a surface-intensified flow to the north-east): depths (m), east, north (m/s)
    current_depths: tuple[float, ...] = (0.0, 30.0, 60.0, 100.0)
    current_east: tuple[float, ...] = (0.12, 0.08, 0.04, 0.02)
    current_north: tuple[float, ...] = (0.06, 0.05, 0.03, 0.0)
    gps_noise: float = 5.0  # m, standard deviation per coordinate of a fix (design assumption)
    hotel_power: float = 0.5  # W: computer and sensors (design assumption of the order of a Slocum's)
    seed: int = 2026
    turn_radius: float = 150.0  # m, the designed turn
    turn_depths: tuple[float, float] = (5.0, 150.0)  # m, the spiral dive that flies it
    turn_window: tuple[float, float] = (60.0, 140.0)  # m, depths whose track is fitted with a circle


FULL = Settings()
QUICK = Settings(waypoints=((800.0, 0.0), (800.0, 800.0)), depths=(5.0, 40.0), surface_time=120.0,
                 turn_depths=(5.0, 120.0), turn_window=(50.0, 110.0))


@dataclass(frozen=True)
class MissionResults:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    vehicle: gc.Vehicle
    mission: gc.Mission
    current: gc.Current
    runs: dict[str, gc.MissionRun]
    depth_mean_current: np.ndarray  # (east, north) m/s over the dive's depth range
    turn: gc.TurnDesign
    turn_run: gc.MissionRun
    turn_radius_flown: float


def depth_mean(current: gc.Current, top: float, bottom: float) -> np.ndarray:
    """Depth average (east, north; m/s) of a current between two depths: what a glider sinking and rising at
    constant speeds measures."""
    z = np.linspace(top, bottom, 2001)
    c = current.at(0.0, np.c_[np.zeros((z.size, 2)), z])
    return np.trapezoid(c, z, axis=0) / (bottom - top)


def circle_radius(xy: np.ndarray) -> float:
    """Radius (m) of the least-squares circle through horizontal positions (m)."""
    A = np.c_[2 * xy, np.ones(len(xy))]
    sol, *_ = np.linalg.lstsq(A, (xy ** 2).sum(1), rcond=None)
    return float(math.sqrt(sol[2] + sol[0] ** 2 + sol[1] ** 2))


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> MissionResults:
    """Both controller sets on the mission, and the designed turn flown as a spiral."""
    veh = gc.load_vehicle(s.vehicle)
    gamma = math.radians(s.gamma_deg)
    mission = gc.Mission(waypoints=s.waypoints, depths=s.depths, gamma=gamma, speed=s.speed,
                         surface_time=s.surface_time, arrival_radius=s.arrival_radius)
    current = gc.Current.profile(s.current_depths, s.current_east, s.current_north)
    runs = {}
    for name in CONTROLLERS:
        progress(f"mission with '{name}'")
        runs[name] = gc.fly_mission(veh, mission, name, current=current, seed=s.seed, gps_noise=s.gps_noise,
                                    hotel_power=s.hotel_power)
    progress("designed turn")
    turn = gc.design_turn(veh, s.turn_radius, gamma=gamma, speed=s.speed)
    spiral = gc.Mission(waypoints=[(1e5, 0.0)], depths=s.turn_depths, gamma=gamma, speed=s.speed)
    turn_run = gc.fly_mission(veh, spiral, gc.GliderBehaviours(turn=turn, pitch_deadband=0.0),
                              duration=1.05 * s.turn_depths[1] / (s.speed * math.sin(gamma)))
    z = turn_run.position[:, 2]
    window = (turn_run.phase == 1) & (z > s.turn_window[0]) & (z < s.turn_window[1])
    return MissionResults(s, veh, mission, current, runs, depth_mean(current, 0.0, s.depths[1]), turn, turn_run,
                          circle_radius(turn_run.position[window, :2]))


def _pump_per_km(run: gc.MissionRun, hotel: float) -> float:
    pump = sum(leg.energy - hotel * leg.duration for leg in run.legs)
    return pump / (run.distance_made_good / 1000.0)


def report(res: MissionResults) -> Report:
    """Numbers, per-leg tables, map and 3-D figures, the turn comparison."""
    s, veh = res.settings, res.vehicle
    rep = Report(TITLE, vehicle=veh)
    truth = res.depth_mean_current
    rep.number("depth_mean_current", truth.tolist(), "m/s", "Current.profile",
               note=f"Depth average (east, north) of the applied current over 0-{s.depths[1]:g} m: what the glider's "
                    "fixes measure.")
    for name, run in res.runs.items():
        rep.number(f"{name}_mission_hours", run.duration / 3600.0, "h", "fly_mission", note=run.ended_by)
        rep.number(f"{name}_dives", len(run.dives), "-", "fly_mission")
        rep.number(f"{name}_waypoints_reached", sum(leg.arrived for leg in run.legs), "-", "fly_mission",
                   note=f"of {len(run.legs)}")
        rep.number(f"{name}_distance_made_good", run.distance_made_good / 1000.0, "km", "fly_mission")
        rep.number(f"{name}_energy_per_km", run.energy_per_km, "J/km", "fly_mission",
                   note=f"pump plus {s.hotel_power:g} W hotel load")
        rep.number(f"{name}_pump_energy_per_km", _pump_per_km(run, s.hotel_power), "J/km", "fly_mission",
                   note="pump only (pushing oil out against the sea pressure, efficiency of the vehicle file)")
        later = [d.current_estimate for d in run.dives[1:]]
        err = float(np.max(np.hypot(*(np.array(later) - truth).T))) if later else math.nan
        rep.number(f"{name}_current_estimate_error", err, "m/s", "fly_mission",
                   note="Largest distance between a surfacing's current estimate (after the first dive) and the "
                        "depth-mean current: the dead reckoning's own speed error and the GPS noise enter it.")
        rep.number(f"{name}_first_dive_time", run.dives[0].duration, "s", "fly_mission",
                   note="surface to surface")
        rep.number(f"{name}_first_dive_dr_error", run.dives[0].dead_reckoning_error, "m", "fly_mission",
                   note="Before any fix the glider knows no current: about |depth-mean current| x dive time "
                        f"= {float(np.hypot(*truth)) * run.dives[0].duration:.0f} m.")
    t = res.turn
    for phase, leg in ((1, "dive"), (-1, "climb")):
        rep.number(f"turn_{leg}_rudder", t.settings[phase], "rad", "design_turn",
                   note=f"rudder angle of a {t.radius:g} m turn to starboard on the {leg} glide")
    rep.number("turn_radius_flown", res.turn_radius_flown, "m", "fly_mission (circle fit)",
               note=f"spiral dive's track between {s.turn_window[0]:g} and {s.turn_window[1]:g} m; designed "
                    f"{t.radius:g} m ({100 * (res.turn_radius_flown / t.radius - 1):+.2f} %)")
    _tables(rep, res)
    _figures(rep, res)
    _notes(rep, res)
    return rep


def _tables(rep: Report, res: MissionResults) -> None:
    s = res.settings
    for name, run in res.runs.items():
        rows = [[str(i), f"({leg.waypoint[0]:.0f}, {leg.waypoint[1]:.0f})", leg.reason.split(":")[0],
                 f"{leg.duration / 3600:.2f}", f"{leg.distance_made_good / 1000:.3f}", f"{leg.energy / 1000:.2f}",
                 f"{leg.energy_per_km:.0f}", f"{leg.arrival_error:.0f}", f"{leg.dead_reckoning_error:.1f}",
                 f"({leg.current_estimate[0]:+.3f}, {leg.current_estimate[1]:+.3f})"] for i, leg in
                enumerate(run.legs)]
        rep.table(f"Legs flown with '{name}' ({s.depths[0]:g}-{s.depths[1]:g} m dives at {s.speed:g} m/s, "
                  f"+-{s.gamma_deg:g} deg; energy includes {s.hotel_power:g} W hotel load)",
                  ["leg", "waypoint (E, N) m", "end", "time [h]", "made good [km]", "energy [kJ]", "[J/km]",
                   "arrival [m]", "DR error [m]", "current est. (E, N) [m/s]"], rows)
    rep.table("Controller sets compared",
              ["controller", "time [h]", "dives", "reached", "made good [km]", "energy [J/km]", "pump [J/km]",
               "mean overshoot [m]"],
              [[name, f"{run.duration / 3600:.2f}", str(len(run.dives)),
                f"{sum(leg.arrived for leg in run.legs)}/{len(run.legs)}", f"{run.distance_made_good / 1000:.2f}",
                f"{run.energy_per_km:.0f}", f"{_pump_per_km(run, s.hotel_power):.0f}",
                f"{np.mean([d.overshoot for d in run.dives]):.2f}"] for name, run in res.runs.items()])
    t = res.turn
    rep.table(f"A designed {t.radius:g} m turn (rudder): design_turn and helix_trim against the flown spiral",
              ["glide", "rudder [deg]", "radius [m]", "drop per turn [m]", "period [s]", "stable"],
              [[leg, f"{math.degrees(t.settings[p]):+.3f}", f"{t.helices[p].radius:.2f}",
                f"{t.helices[p].pitch:.1f}", f"{t.helices[p].period:.0f}", str(t.helices[p].stable)]
               for p, leg in ((1, "dive"), (-1, "climb"))]
              + [["dive, flown", f"{math.degrees(t.settings[1]):+.3f}", f"{res.turn_radius_flown:.2f}", "", "", ""]])


def _figures(rep: Report, res: MissionResults) -> None:
    for name, run in res.runs.items():
        axes = run.plot()
        rep.figure(f"mission_{name}", axes[0].figure,
                   f"'{name}': map (track, dead reckoning between fixes, GPS fixes, waypoints with their arrival "
                   f"circles, surface current), depth and actuators. {run.summary()}.")
    ax = res.runs["behaviours"].plot_3d()
    rep.figure("mission_3d", ax.figure, "The behaviours' mission in 3-D: dives to the bottom depth between fixes.")
    rep.figure("designed_turn", _turn_axes(res).figure,
               f"The designed {res.turn.radius:g} m turn flown as a spiral dive (rudder held at the design's "
               f"setting, battery on the helix's pitch): fitted radius {res.turn_radius_flown:.1f} m.")


def _turn_axes(res: MissionResults) -> Any:
    """The spiral dive's horizontal track with the fitted and the designed circles."""
    import matplotlib.pyplot as plt

    s, run = res.settings, res.turn_run
    _, ax = plt.subplots(figsize=(6.0, 5.5), layout="constrained")
    pos, z = run.position, run.position[:, 2]
    window = (run.phase == 1) & (z > s.turn_window[0]) & (z < s.turn_window[1])
    ax.plot(pos[:, 0], pos[:, 1], color="0.4", lw=1.5, zorder=3, label="track (from the surface)")
    ax.plot(pos[window, 0], pos[window, 1], "C0", lw=3, zorder=4,
            label=f"fitted part ({s.turn_window[0]:g}-{s.turn_window[1]:g} m)")
    xy = pos[window, :2]
    A = np.c_[2 * xy, np.ones(len(xy))]
    (cx, cy, _), *_ = np.linalg.lstsq(A, (xy ** 2).sum(1), rcond=None)
    phi = np.linspace(0, 2 * np.pi, 361)
    for r, style, what in ((res.turn_radius_flown, "C1--", "fitted circle"), (res.turn.radius, "k:", "design")):
        ax.plot(cx + r * np.cos(phi), cy + r * np.sin(phi), style, lw=1, label=f"{what}, {r:.1f} m")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_title(f"rudder {math.degrees(res.turn.settings[1]):+.2f} deg on the dive glide", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    return ax


def _notes(rep: Report, res: MissionResults) -> None:
    s = res.settings
    rep.text("Mission, current and controllers",
             f"The glider starts at rest at the surface at (0, 0) heading for the first waypoint. Each dive goes to "
             f"{s.depths[1]:g} m and back to the surface, where the glider spends {s.surface_time:g} s: a GPS fix "
             f"(noise {s.gps_noise:g} m per coordinate), the dead-reckoning error, the current estimate "
             "(fix minus dead reckoning over the dive time, accumulated over the dives), a drift with the surface "
             "current and a second fix. Under water the glider dead-reckons from its depth rate, pitch and heading "
             "with the designed glide's angle of attack and its current estimate, and heads so that its track, with "
             "the estimated current, points at the waypoint; a waypoint is reached when the dead-reckoned position "
             f"comes within {s.arrival_radius:g} m of it. The current (a design choice) is "
             + ", ".join(f"({e:+.2f}, {n:+.2f}) m/s at {d:g} m" for d, e, n in
                         zip(s.current_depths, s.current_east, s.current_north, strict=True))
             + ", linear in between; the glider never sees it, only its fixes.\n\n"
             "'behaviours' moves the pump only after the inflections (to the next glide's buoyancy), the battery "
             "only when the pitch error exceeds 1 deg, and the rudder only when the heading error exceeds 2 deg. "
             "'lqr' feeds back pitch, pitch rate, body velocities, battery and pump to battery acceleration and "
             "pump rate (the regulator of gc.lqg_glide at each leg's glide): it uses the body velocities, which a "
             "glider does not measure, so it is the full-information bound, and it trims the speed with the pump "
             "throughout the dive, which costs pump energy at depth.")
    rep.text("Turn",
             "gc.design_turn keeps the glide's buoyancy and battery position and solves helix_trim's radius for the "
             "rudder angle (the dive and the climb turn the same way with rudder angles of opposite signs on this "
             "model: in a climb the lift reverses with the angle of attack, and the turn is the banked lift's). "
             "The spiral dive holds that angle; the battery holds the helix's pitch.")


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The waypoint mission study with the ``QUICK`` or ``FULL`` settings."""
    return report(compute(QUICK if quick else FULL, progress))


if __name__ == "__main__":
    run_script(__file__)
