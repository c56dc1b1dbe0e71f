"""
Design a turn
=============

A glider turns by flying a steady helix: with the rudder over (Slocum) or the battery rolled (Seaglider, Spray)
the straight glide becomes a circular helix about the vertical, a relative equilibrium of the 3-D model (thesis
chapter 8, (8.23)-(8.31)). :func:`glidectl.design_turn` finds the steering setting that gives a requested turn
radius on a mission's dive and on its climb (the same setting turns the two legs differently, so each gets its
own), and reports each helix with its stability. This guide designs a 120 m turn for the rudder-steered
``slocum_shallow`` preset, shows what happens when a radius is out of reach, designs a roll-steered variant, and
flies the rudder turn on the actuated 3-D model.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

veh = gc.load_vehicle("slocum_shallow")  # rudder +-0.45 rad at 0.1 rad/s in its [actuators]
GAMMA, SPEED = math.radians(25.0), 0.35  # the mission's glides: +-25 deg at 0.35 m/s

turn = gc.design_turn(veh, radius=120.0, gamma=GAMMA, speed=SPEED, direction=1)  # +1: to starboard
for leg, name in ((1, "dive"), (-1, "climb")):
    h = turn.helices[leg]
    print(f"{name:5s}: {turn.steer} {math.degrees(turn.settings[leg]):+6.2f} deg -> radius {h.radius:.1f} m, "
          f"drop per turn {h.pitch:+.0f} m, period {h.period / 60:.1f} min, roll {math.degrees(h.phi):+.1f} deg, "
          f"stable {h.stable}")

# %%
# The climb needs a rudder angle of the opposite sign and much smaller: on the way up the angle of attack, and with
# it the banked lift, reverses (conventions: "Rudder"). ``design_turn`` takes the sign from the helices, so the
# mission layer flies the right one on each leg.
#
# A radius out of reach
# ---------------------
# Tighter turns need more rudder, and the rudder's range (or the helix's stability) ends somewhere. The error says
# where:
try:
    gc.design_turn(veh, radius=50.0, gamma=GAMMA, speed=SPEED)
except gc.InfeasibleGlideError as err:
    print(err)

# %%
# Steering by battery roll
# ------------------------
# A glider without a rudder rolls its battery about the hull axis: ``[actuators] roll`` (rad). Here the same
# vehicle with its rudder removed and a +-0.5 rad battery roll added (``with_actuators``; in a vehicle file this is
# the ``roll`` entry). ``steer="auto"`` picks the actuator the vehicle has.
rolling = veh.with_actuators(rudder=None, r_P2=None,
                             roll={"min": -0.5, "max": 0.5, "rate": 0.1, "unit": "rad",
                                   "source": "battery roll +-29 deg at 6 deg/s (design choice)"})
roll_turn = gc.design_turn(rolling, radius=200.0, gamma=GAMMA, speed=SPEED)
print(f"{roll_turn.steer}: dive {math.degrees(roll_turn.settings[1]):+.1f} deg, "
      f"climb {math.degrees(roll_turn.settings[-1]):+.1f} deg for a 200 m turn")

# %%
# Fly the turn
# ------------
# :class:`glidectl.GliderBehaviours` with ``turn=`` holds the designed setting instead of steering for a heading.
# One dive to 180 m and the climb back, toward a waypoint far away so that it never arrives, on the full actuated
# 3-D model (:func:`glidectl.fly_mission`):
spiral = gc.Mission(waypoints=[(1e5, 0.0)], depths=(5.0, 180.0), gamma=GAMMA, speed=SPEED, surface_time=0.0)
run = gc.fly_mission(veh, spiral, gc.GliderBehaviours(turn=turn, pitch_deadband=0.0), duration=2600.0)


def circle_radius(xy):
    """Radius (m) of the least-squares circle through the points ``xy`` (m)."""
    a = np.c_[2 * xy, np.ones(len(xy))]
    c, *_ = np.linalg.lstsq(a, (xy**2).sum(axis=1), rcond=None)
    return math.sqrt(c[2] + c[0] ** 2 + c[1] ** 2), c[:2]


position = run.position  # (east, north, depth) in m
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
for phase, name, color in ((1, "dive", "C0"), (-1, "climb", "C1")):
    steady = (run.phase == phase) & (position[:, 2] > 30.0) & (position[:, 2] < 160.0)  # away from inflections
    radius, centre = circle_radius(position[steady, :2])
    print(f"{name}: flown radius {radius:.1f} m (designed {turn.radius:.0f} m)")
    ax1.plot(position[run.phase == phase, 0], position[run.phase == phase, 1], color=color, label=name)
    ax2.plot(run.t[run.phase == phase] / 60, np.degrees(run.actuator("rudder")[run.phase == phase]), color=color,
             label=f"{name}: designed {math.degrees(turn.settings[phase]):+.1f} deg")
    ax2.axhline(math.degrees(turn.settings[phase]), color=color, ls=":", lw=0.8)
ax1.set_aspect("equal")
ax1.set_xlabel("east [m]")
ax1.set_ylabel("north [m]")
ax1.set_title("track of one dive and climb (launched heading east)")
ax1.legend(fontsize=8)
ax2.set_xlabel("time [min]")
ax2.set_ylabel("rudder [deg]")
ax2.set_title("rudder angle on each leg (dotted: the design)")
ax2.legend(fontsize=8)
plt.show()

# %%
# The flown radius matches the design: the helices of ``design_turn`` are equilibria of the same 3-D model, and the
# rudder reaches each setting within seconds (0.1 rad/s); the battery holds the helix's pitch, which differs from
# the straight glide's. In a waypoint mission the heading controller uses the steady turn rate per unit of
# steering of the same glides (``turn_gain`` of :class:`glidectl.DivePlan`); see
# :ref:`sphx_glr_auto_howto_plot_03_waypoint_mission.py`.
