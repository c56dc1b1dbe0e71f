"""
Monte Carlo: what the trim costs when the coefficients are uncertain
====================================================================

Hydrodynamic coefficients of a new glider are rarely known to better than 20-30 %. Give the vehicle an
``[uncertainty]`` table (here from Python with ``veh.with_uncertainty``; a vehicle file can carry the same table),
then run any function of a vehicle over vehicles drawn from it with :func:`glidectl.monte_carlo`. Here the study
is the 0.35 m/s, -25 deg steady glide: which pump mass, battery position and pitch angle does each sampled glider
need?
"""

import math

import matplotlib.pyplot as plt

import glidectl as gc

veh = gc.load_vehicle("slocum_shallow").with_uncertainty(
    {"K_L": {"rel": 0.2}, "K_D0": {"rel": 0.3}, "K_D": {"rel": 0.3}, "K_M": {"rel": 0.3}})  # +-20-30 % intervals
R_P3 = veh.actuators["r_P3"].fixed  # m, the vertical battery offset the file fixes


def down_glide(v):
    """Trim of one sampled vehicle: pump mass (kg), battery position (mm), pitch (deg)."""
    g = gc.steady_glide(v, 0.35, math.radians(-25.0), r_p3=R_P3)
    return {"m0": g.m0, "r_P1": 1000 * g.r_p1, "theta": math.degrees(g.theta)}


down_glide.units = {"m0": "kg", "r_P1": "mm", "theta": "deg"}  # the plot labels its axes with these

mc = gc.monte_carlo(down_glide, veh, n=300, seed=0)
print(mc.summary())

# %%
# One row per number: its histogram (median and 5-95 % dotted), and a scatter against the coefficient with the
# largest rank correlation. The pump mass follows the parasitic drag ``K_D0`` almost exactly, the battery
# position mostly the pitch stiffness ``K_M``. Every sample stays inside the pump's +-0.25 kg and the battery's
# +-25 mm.
axes = mc.plot()
plt.show()
