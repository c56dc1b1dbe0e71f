"""
Elevator and buoyancy control (chapter 6, Fig 6.2)
==================================================

§6.3 steers the glider with an aft elevator (moment ``K_M u2 V^2``, coupled force along body 3) and holds its
speed with the buoyancy engine (6.21)-(6.22). :func:`glidectl.elevator_equilibrium` gives the closed-loop glide of a
requested speed and flight-path angle and checks Theorem 3's conditions; :func:`glidectl.elevator_example`
simulates the loop on :class:`glidectl.ElevatorBuoyancyGlider` as in Fig 6.2: 1 m/s at -45 deg on the
``elevator_ch6`` vehicle, starting from the glide it flies with the elevator neutral and 2.5 kg of buoyancy.
"""

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

veh = gc.load_vehicle("elevator_ch6")
eq = gc.elevator_equilibrium(veh, speed=1.0, gamma=-np.pi / 4)
print(f"m0e = {eq.m0e:.4f} kg (printed 2.657), alpha_e = {np.degrees(eq.alpha):.3f} deg (printed 3.51), "
      f"u2e = {np.degrees(eq.u2e):.3f} deg, Theorem 3 conditions hold: {eq.certified}")

run = gc.elevator_example(veh, 1.0, -np.pi / 4, t_final=10.0)
print(run.initial_condition)
print(f"largest pump rate {run.max_abs_m0dot:.3f} kg/s, largest elevator angle {np.degrees(run.max_abs_u2):.2f} deg")

# %%
# Speed, flight-path angle, angle of attack and buoyancy against time. The sign conventions of §6.3 are
# inconsistent in the printed equations; glidectl uses an elevator force that pushes the tail down for a nose-up
# moment (erratum E6.5), which changes no trajectory, only the sign of ``u2``.
axes = run.sim.plot(names=("V", "gamma", "alpha", "m0"),
                    scale={"gamma": (180 / np.pi, "deg"), "alpha": (180 / np.pi, "deg")})
for ax, target in zip(axes, (eq.speed, eq.gamma * 180 / np.pi, eq.alpha * 180 / np.pi, eq.m0e), strict=True):
    ax.axhline(target, color="k", ls=":", lw=0.8)
axes[0].set_title("elevator and buoyancy control to 1 m/s, -45 deg (dotted: the equilibrium)")
plt.show()
