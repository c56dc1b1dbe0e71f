"""
Regions of attraction of the chapter-5 glider
=============================================

Chapter 5 proves that the steady glide of a spherical glider (``sphere_ch5``) is asymptotically stable with a
composite Lyapunov function (Theorem 2, (5.83)) and estimates its region of attraction ``L*`` (5.85). With
``K_M = -100`` kg/rad the condition ``mu < mu_d`` holds (§5.3.1). glidectl evaluates every constant of
Propositions 1-2 and Theorem 2 (:func:`glidectl.composite_lyapunov`), and certifies the reduced (slow) subsystem
(5.33) directly with an SOS program (:func:`glidectl.certify_roa`): the two estimates side by side, over the set
from which simulations converge.
"""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FuncFormatter

import glidectl as gc

sph = gc.load_vehicle("sphere_ch5", K_M=-100.0)
sp = gc.singular_perturbation(sph)
print(f"V_e = {sp.speed:.3f} m/s, tau_s = {sp.tau_s:.3f} s, eps1 = {sp.eps1:.3e}, eps2 = {sp.eps2:.3e}")

composite = gc.composite_lyapunov(sph, Vbar=(-0.4, 0.4), alphabar=(-0.2, 0.2))
print(f"mu = {composite.mu:.3e} < mu_d = {composite.mu_d:.3e}: {composite.certified} (d = {composite.d:.3f})")

# %%
# The SOS certificate of the reduced subsystem ``(Vbar, gammabar)`` (nondimensional speed and flight-path angle
# deviations, time ``t_n = t / tau_s``): the model is recast exactly as a polynomial system (``sin``, ``1 - cos``,
# ``1/V`` cleared) and a degree-2 Lyapunov function is searched for, then checked a posteriori.
reduced = sp.reduced_model()
cert = gc.certify_roa(reduced, degree=2)
print(cert.verification.summary())
converging = gc.convergent_slice(reduced, dims=("Vbar", "gammabar"), n=31)

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
composite.plot(ax=ax1)  # L* in the (Vbar, gammabar) plane at alphabar = Omegabar2 = 0, gammabar in rad
ax1.set_yticks(np.radians(np.arange(-180, 181, 45)))  # label it in degrees
ax1.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{np.degrees(y):.0f}"))
ax1.set_ylabel(r"$\bar\gamma$ [deg]")
converging.plot(ax=ax2)  # grey: simulations of the reduced subsystem that converge
cert.plot(ax=ax2, dims=("Vbar", "gammabar"), samples=False)  # angles in degrees
plt.show()

# %%
# Theorem 2's set (left) reaches about +-30 deg of flight-path angle at the nominal speed; the SOS set of the slow
# states (right) reaches about +-90 deg and covers most of the region from which the slow subsystem converges.
# The two are not the same statement: ``L*`` holds for the full four-state model (angle of attack and pitch rate
# included), the SOS set for the reduced one. The full model certifies the same way (``sp.full_model()``, about
# 10 s).
