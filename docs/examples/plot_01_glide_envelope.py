"""
Glide envelope of a Slocum-class glider
=======================================

Which steady glides can the glider hold with the pump and battery it has? :func:`glidectl.glide_envelope` trims the
longitudinal model on a grid of speeds and flight-path angles (closed form, vectorized) and checks each glide's
pump mass ``m0`` and battery position ``r_P1`` against the ``[actuators]`` ranges of the vehicle file.
"""

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

veh = gc.load_vehicle("slocum_shallow")  # pump +-0.25 kg, battery +-2.5 cm, r_P3 fixed at 5 cm
speeds = np.linspace(0.05, 0.8, 61)  # m/s
gammas = np.radians(np.linspace(-60.0, 60.0, 97))  # rad; negative glides down
env = gc.glide_envelope(veh, speeds, gammas)
print(env.summary())

# %%
# The polar: horizontal speed against sink rate, coloured by the limit that binds. The band of shallow angles
# around zero has no steady glide at all (the permissible set (2.26): ``gc.permissible_gamma``). The black
# triangles are the 0.35 m/s, +-25 deg glides that the dive-cycle examples fly.
lo, hi = gc.permissible_gamma(veh)
print(f"no steady glide for {np.degrees(lo):.1f} deg < gamma < {np.degrees(hi):.1f} deg")

ax = env.plot()
for gamma, marker in ((-np.radians(25.0), "v"), (np.radians(25.0), "^")):
    ax.plot(0.35 * np.cos(gamma), -0.35 * np.sin(gamma), marker, color="k", ms=9,
            label=f"0.35 m/s, {np.degrees(gamma):+.0f} deg")
ax.legend(fontsize=7, loc="upper right")
plt.show()

# %%
# The fastest feasible horizontal speed and sink rate on the grid:
feasible = env.feasible
print(f"max horizontal speed {np.nanmax(np.where(feasible, env.horizontal_speed, np.nan)):.3f} m/s, "
      f"max sink rate {np.nanmax(np.where(feasible, env.vertical_speed, np.nan)):.3f} m/s")
