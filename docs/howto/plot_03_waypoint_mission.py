"""
Fly a waypoint mission in a current
===================================

A glider between surfacings is blind: it dead-reckons from its heading, pitch and a model of its speed, and only
a GPS fix at the surface tells it where the water took it. :func:`glidectl.fly_mission` flies that loop on the
actuated 3-D model (:class:`glidectl.ActuatedGlider3D`: pump, battery and rudder or battery roll, each with the
range and rate of ``[actuators]``): dives between two depths, a fix at each surfacing, the depth-averaged current
estimated from the dead-reckoning error, and the heading corrected for it on the next dive. This guide flies a
triangle of waypoints through a depth-varying current with two controller sets and reads the per-leg results.

Positions are ``(east, north, depth)`` in metres, velocities ``(east, north)`` in m/s.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

veh = gc.load_vehicle("slocum_shallow")  # pump, battery, rudder; depth rating 200 m

# %%
# The mission and the water
# -------------------------
# :class:`glidectl.Mission`: the waypoints in order, the dive depths (top and bottom inflections, m), the glide
# (+-25 deg at 0.35 m/s through the water), the time at the surface per surfacing (GPS fix, data) and the radius
# within which a waypoint counts as reached. The current (:class:`glidectl.Current`) is a profile, strongest at the
# surface; ``Current.uniform`` and ``Current.field`` (any function of time and position) work the same way.
mission = gc.Mission(waypoints=[(1500.0, 0.0), (750.0, 1300.0), (0.0, 0.0)], depths=(5.0, 80.0),
                     gamma=math.radians(25.0), speed=0.35, surface_time=300.0, arrival_radius=100.0)
current = gc.Current.profile([0.0, 40.0, 80.0], east=[0.10, 0.06, 0.02], north=[-0.06, -0.03, 0.0])

depths = np.linspace(0.0, 80.0, 161)
applied = current.at(0.0, np.c_[np.zeros((depths.size, 2)), depths])  # (east, north) at each depth
mean_current = np.trapezoid(applied, depths, axis=0) / 80.0
print(f"depth-averaged current over 0-80 m: east {mean_current[0]:+.3f}, north {mean_current[1]:+.3f} m/s")

# %%
# Fly it
# ------
# ``"behaviours"`` is what Slocum and Seaglider flight software does: the pump runs only at the inflections, the
# battery holds pitch and the rudder holds heading, each with a deadband (:class:`glidectl.GliderBehaviours`).
# ``"lqr"`` replaces the pitch and pump behaviours by the LQR dive controller (:class:`glidectl.DiveLQR`, the
# regulator of the longitudinal LQG design of each glide) and keeps the heading law. GPS fixes carry 5 m of noise
# per coordinate; ``hotel_power`` (W) adds the computer and sensors to the energy.
runs = {name: gc.fly_mission(veh, mission, name, current=current, seed=0, gps_noise=5.0, hotel_power=0.5)
        for name in ("behaviours", "lqr")}
for name, run in runs.items():
    print(f"--- {name}: {run.ended_by}, {run.duration / 3600:.2f} h, {run.energy_per_km:.0f} J/km")
    print(run.table())

# %%
# Reading the table: the arrival errors of about 100 m are the arrival radius (a leg ends when the dead-reckoned
# position comes within it, under water, as Slocum does); the dead-reckoning error at the surfacings is about 10 m
# per dive once the current estimate is in; the LQR holds the glide more tightly and pays for it in pump energy
# (it pumps along the glide, against the pressure at depth). Each leg's last current estimate is close to the
# depth average computed above: the glider learns the water it cannot see.
for leg in runs["behaviours"].legs:
    print(f"leg to {leg.waypoint}: {leg.dives} dives, estimated current {np.round(leg.current_estimate, 3)} m/s")

# %%
# The map (track, dead-reckoned track, fixes, waypoints with their arrival circles, current arrows), depth against
# time and the actuators, for the behaviours:
axes = runs["behaviours"].plot()
axes[0].figure.set_size_inches(12, 6.5)
plt.show()

# %%
# Long missions and many gliders
# ------------------------------
# ``model="fast"`` integrates one dive in still water with the full model and replays it along each dive's
# turning track through the current: tens of times faster, for long missions, Monte Carlo studies
# (:func:`glidectl.mission_ensemble`) and fleets (:func:`glidectl.fly_fleet`). Against the full model it differs
# here by under a metre of arrival error and a few minutes of leg time:
fast = gc.fly_mission(veh, mission, "behaviours", current=current, seed=0, gps_noise=5.0, hotel_power=0.5,
                      model="fast")
for full_leg, fast_leg in zip(runs["behaviours"].legs, fast.legs, strict=True):
    full_minutes, fast_minutes = (full_leg.end - full_leg.start) / 60, (fast_leg.end - fast_leg.start) / 60
    print(f"arrival error full {full_leg.arrival_error:6.1f} m, fast {fast_leg.arrival_error:6.1f} m; "
          f"leg time full {full_minutes:5.1f} min, fast {fast_minutes:5.1f} min")
