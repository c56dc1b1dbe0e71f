"""
A steady helix of the Slocum model (chapter 8)
==============================================

With the moving mass off the plane of symmetry (``r_P2 != 0``) a glider does not glide straight: it turns in a
circular helix about the vertical, a relative equilibrium of (8.23)-(8.25) with ``Omega = psidot zeta`` (8.31).
:func:`glidectl.helix_trim` solves for it; here with the control parameters of §8.2.2 on the Table 8.1 vehicle
(``slocum_ch8``): ``r_P = (2, 2, 4)`` cm, ``m0 = 0.25`` kg.
"""

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

slo = gc.load_vehicle("slocum_ch8")
h = gc.helix_trim(slo, r_p=(0.02, 0.02, 0.04), m0=0.25)
print(f"radius {h.radius:.2f} m, drop per turn {h.pitch:.1f} m, period {h.period:.1f} s, speed {h.speed:.3f} m/s")
print(f"alpha {np.degrees(h.alpha):.2f} deg, beta {np.degrees(h.beta):.2f} deg, "
      f"pitch {np.degrees(h.theta):.2f} deg, roll {np.degrees(h.phi):.2f} deg, stable: {h.stable}")

# %%
# The thesis prints radius 66.60 m, speed 0.729 m/s, drop per turn 206.2 m and period 639.6 s: reproduced. To see
# the helix, simulate the fixed-mass model (:class:`glidectl.FixedMassGlider3D`) for two periods from the trimmed
# state with the pitch disturbed by 10 deg (a quaternion perturbation would do the same): the track returns to a
# helix of the trimmed radius.
model = gc.FixedMassGlider3D(slo, r_p=(0.02, 0.02, 0.04), m0=0.25)
x0 = h.initial_state()
x0[7] += 0.1  # v1 + 0.1 m/s: a speed disturbance
sim = gc.simulate(model, x0, 2 * h.period, t_eval=np.linspace(0.0, 2 * h.period, 1201))

fig = plt.figure(figsize=(6.5, 5.5), layout="constrained")
ax3 = fig.add_subplot(projection="3d")
ax3.plot(sim.state("y"), sim.state("x"), -sim.state("z"))  # east, north, height
ax3.set_xlabel("east [m]")
ax3.set_ylabel("north [m]")
ax3.set_zlabel("height [m]")
ax3.set_title(f"two periods of the helix ({2 * h.period:.0f} s)")
plt.show()

# %%
# How the helix changes with the battery position along the hull: :func:`glidectl.helix_sweep` follows the branch
# by continuation (one panel of Fig 8.5). Near ``r_P1 = 3.5`` cm the yaw rate passes through zero: the radius goes
# to infinity and the turn reverses (erratum E8.12).
sweep = gc.helix_sweep(slo, "r_P1", np.linspace(0.005, 0.06, 45), r_p=(0.02, 0.02, 0.04), m0=0.25)
fig, ax = plt.subplots(figsize=(6.5, 4), layout="constrained")
sweep.plot(ax=ax, column="radius")
ax.axvline(0.02, color="k", ls=":", lw=0.8)
ax.set_title("helix radius against $r_{P1}$ (dotted: the helix above; Fig 8.5)")
plt.show()
