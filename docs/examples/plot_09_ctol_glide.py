"""
Steady glides of the CTOL aircraft (chapter 7)
==============================================

Chapter 7 stabilizes steady glides of a conventional take-off and landing aircraft (the ``dc8_ctol`` preset, in
the normalized units of §7.1: ``rho A_W / 2 = m = g = J = 1``) with thrust and an elevator that also pushes the
airframe (``eps u2``). Theorem 4: for any speed ``V_e`` and flight-path angle ``gamma_e`` the gains ``k1, k2`` of
(7.18)-(7.19) make the requested glide an equilibrium of the closed loop (7.16)-(7.20)
(:func:`glidectl.ctol_glide`); the pitch gains ``k3, k4`` decide its stability.
"""

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

dc8 = gc.load_vehicle("dc8_ctol")
level = gc.ctol_glide(dc8, speed=0.155, gamma=0.0)
climb = gc.ctol_glide(dc8, speed=0.155, gamma=np.radians(5.0))
for name, g in (("level", level), ("5 deg climb", climb)):
    eig = gc.ctol_closed_loop_eigenvalues(dc8, g, k3=10.0, k4=5.0)
    print(f"{name}: alpha {np.degrees(g.alpha):.2f} deg, thrust {g.thrust:.4f}, "
          f"largest closed-loop real part {eig.real.max():.3f}")

# %%
# The equilibrium thrust over a grid of glides (:func:`glidectl.ctol_glide_map`): steep fast descents need a
# negative thrust (a brake), below the white zero-thrust contour. Slow glides (blank, left) need an angle of attack
# beyond the 0.35 rad (20 deg) that the linear lift model (7.1) is accepted for.
speeds = np.linspace(0.08, 0.4, 41)
gammas = np.radians(np.linspace(-20.0, 20.0, 41))
glide_map = gc.ctol_glide_map(dc8, speeds, gammas, gains=[(10.0, 5.0)])
print(glide_map.summary())

fig, ax1 = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
cs = ax1.contourf(speeds, np.degrees(gammas), glide_map.thrust.T, levels=20, cmap="viridis")
ax1.contour(speeds, np.degrees(gammas), glide_map.thrust.T, levels=[0.0], colors="w", linewidths=1.5)
fig.colorbar(cs, ax=ax1, label="equilibrium thrust $u_1$ [normalized]")
ax1.plot(level.speed, 0.0, "o", color="r", label="level glide")
ax1.plot(climb.speed, 5.0, "^", color="r", label="5 deg climb")
ax1.set_xlabel("speed $V_e$ [normalized]")
ax1.set_ylabel(r"flight-path angle $\gamma_e$ [deg]")
ax1.set_title("Theorem 4 glides (white: zero thrust)")
ax1.legend(fontsize=8, loc="lower right")
plt.show()

# %%
# From level flight, the controller of the climbing glide (:class:`glidectl.SteadyGlideController`, pitch gains
# ``k3 = 10``, ``k4 = 5``) takes the full aircraft (:class:`glidectl.CTOLAircraft`, state ``(x, y, xdot, ydot,
# theta, Omega2)``, y up) onto the 5 deg climb within a few time units; the elevator's force ``eps u2`` first pushes
# the path the wrong way (the non-minimum-phase response that chapter 7's tracking has to live with).
aircraft = gc.CTOLAircraft(dc8)
controller = gc.SteadyGlideController(dc8, climb, k3=10.0, k4=5.0)
x0 = np.array([0.0, 0.0, level.speed, 0.0, level.theta, 0.0])
sim = gc.simulate(aircraft, x0, 8.0, controller)
gamma = np.arctan2(sim.state("ydot"), sim.state("xdot"))
fig, ax2 = plt.subplots(figsize=(6.5, 4), layout="constrained")
ax2.plot(sim.t, np.degrees(gamma), label=r"$\gamma$")
ax2.plot(sim.t, np.degrees(sim.state("theta")), label=r"$\theta$")
ax2.axhline(5.0, color="k", ls=":", lw=0.8)
ax2.set_xlabel("t [normalized]")
ax2.set_ylabel("angle [deg]")
ax2.set_title("level flight to a 5 deg climb under (7.16)-(7.20)")
ax2.legend(fontsize=8)
plt.show()
