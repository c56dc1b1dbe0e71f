"""
Dive cycles under LQR: depth, pitch and actuators
=================================================

:func:`glidectl.dive_cycle` flies a sawtooth between two depths on the actuated longitudinal glider
(:class:`glidectl.ActuatedGlider`: the pump and the battery obey the range and rate limits of ``[actuators]``).
With ``"lqr"`` each leg is flown by an LQR on the battery acceleration and the pump rate about the leg's steady
glide; a supervisor switches legs at the measured depth limits.
"""

import matplotlib.pyplot as plt

import glidectl as gc

veh = gc.load_vehicle("slocum_shallow")
run = gc.dive_cycle(veh, "lqr", depths=(5.0, 60.0), cycles=2)  # 0.35 m/s, +-25 deg by default
print(run.summary())

# %%
# Depth with its limits and the inflections, pitch, and the commanded against the achieved pump mass and battery
# position (dashed red: the actuator ranges). At each inflection the commands ask for more than the actuators can
# give; the rate limits (10 g/s of pump, 5 mm/s of battery) hold them back for about a minute per cycle, and the
# glider overshoots the depth limits by about 1.3 m.
axes = run.plot()  # depth, pitch, pump, battery
plt.show()

# %%
# The same mission with the pitch PID baseline (battery on pitch, pump run to its end at the inflections), for
# comparison of the cost per cycle:
pid = gc.dive_cycle(veh, "pid", depths=(5.0, 60.0), cycles=2)
print(pid.summary())
