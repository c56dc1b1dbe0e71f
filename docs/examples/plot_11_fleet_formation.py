"""
A fleet in formation (chapter 3, AOSN-II)
=========================================

Three gliders hold an equilateral triangle carried by a virtual body, coordinated only when they surface, as in
the AOSN-II demonstration of §3.2.1 (virtual bodies and artificial potentials: :class:`glidectl.FormationControl`).
The side is commanded from 3 km to 1.5 km halfway; a current of 0.07 m/s, unknown to the coordinator, sets the
gliders off their slots between surfacings. :func:`glidectl.fly_fleet` flies each glider's dives (the fast model:
one full-model dive replayed along each track) and asks the coordinator for new waypoints at every surfacing.
"""

import matplotlib.pyplot as plt

import glidectl as gc

veh = gc.load_vehicle("slocum_shallow")
triangle = gc.FormationControl("triangle", [(0, 3000), (12 * 3600, 1500)],  # (time s, side m)
                               leader_path=[(0, 0), (12000, 0)], leader_speed=0.12)  # east, north in m; m/s
dives = gc.Mission(waypoints=[(1, 0)], depths=(5, 60), surface_time=300)  # dive settings; waypoints unused
fleet = gc.fly_fleet([veh] * 3, triangle, mission=dives, current=(0.05, -0.05), duration=24 * 3600)

times, spacing = fleet.mean_spacing()  # s, m
late = times > 16 * 3600
print(f"mean spacing after 16 h: {spacing[late].mean():.0f} m (commanded 1500 m), "
      f"std {spacing[late].std():.0f} m")

# %%
# Left: the tracks with snapshots of the formation (as Fig 3.2); right: the mean of the three spacings against the
# commanded one (as Fig 3.3).
axes = fleet.plot()
axes[0].figure.set_size_inches(11, 4.5)
plt.show()
