"""
Certify a closed loop
=====================

A linear design proves stability for infinitesimal disturbances. A region-of-attraction certificate proves a set
of states from which the nonlinear closed loop returns to its equilibrium: a Lyapunov function ``V`` and a level
``rho`` with ``dV/dt < 0`` on ``{V <= rho}`` minus the equilibrium, found by semidefinite programs in cvxpy and
checked afterwards. :func:`glidectl.certify_roa` takes any input-free glidectl model with an equilibrium (a
:func:`glidectl.closed_loop`, a :func:`glidectl.saturated_loop`, a polynomial system) and chooses the route:

* **SOS** (sum-of-squares) programs for a polynomial ``V`` of degree 2, 4, ...: exact when the model can be recast
  as a polynomial system, else on a polynomial surrogate with a bounded remainder;
* **LMI** for a saturated loop with state-dependent actuator limits: a quadratic ``V``, the saturation handled by a
  generalized sector condition.

Every certificate has the same attributes (:class:`glidectl.Certificate`): ``certified`` (every a-posteriori check
passed), ``rigorous`` (proved for the true model, not only checked by sampling), ``contains``, ``volume``,
``extent`` and ``plot``. This guide certifies a benchmark, a glider loop, and a saturated one, and measures each
certificate against simulation.
"""

import matplotlib.pyplot as plt

import glidectl as gc

# %%
# A benchmark first
# -----------------
# The time-reversed Van der Pol oscillator (:mod:`glidectl.benchmarks`): its region of attraction is bounded by the
# limit cycle. A degree-4 ``V`` (the alternation runs degree 2, then 4):
vdp = gc.benchmarks.van_der_pol()
cert = gc.certify_roa(vdp, degree=4)
print(f"certified {cert.certified}, rigorous {cert.rigorous}, method {cert.method}, area {cert.volume():.2f}")
print(cert.verification.summary())
for row in cert.history:
    print(f"  degree {row.degree} {row.step:>14s}: rho {row.rho:.4f}, area {row.volume:.3f}")

# %%
# The a-posteriori checks: the Gram matrices' margins (the SOS proof itself), the Hessian of ``V`` at the
# equilibrium, ``dV/dt`` sampled in the set, and simulations from the set's boundary that must converge.
ax = cert.plot()
plt.show()

# %%
# A glider loop: chapter-6 torque control
# ---------------------------------------
# §6.1 closes the chapter-5 glider (``sphere_ch5``) with a pure pitch torque that reshapes its pitching moment
# (6.5); :func:`glidectl.design_torque_control` picks the gains for a target speed of 1.5 m/s so that Theorem 2's
# composite Lyapunov function certifies the domain. Its closed loop is a model with states ``(V, gamma, alpha,
# Omega2)`` (m/s, rad, rad, rad/s).
sph = gc.load_vehicle("sphere_ch5")
torque = gc.design_torque_control(sph, speed=1.5)
loop = gc.closed_loop(torque)
print(loop.state_names, loop.equilibrium)

# %%
# The lift and drag make the loop non-polynomial in ``alpha``, so ``certify_roa`` certifies a polynomial surrogate
# with a remainder bound (``method = "surrogate+remainder"``: valid for every right-hand side within the bound, the
# true one included). The bound rests on derivatives sampled on a grid of the box with a safety factor, so the
# certificate is sampled-sound, not a proof (``rigorous`` is False). The default region of interest is the loop's
# validity box (:func:`glidectl.validity_box`); pass ``box=`` (state units) for another.
glider_cert = gc.certify_roa(loop, degree=2)
print(f"certified {glider_cert.certified}, rigorous {glider_cert.rigorous}, method {glider_cert.method}")
print(glider_cert.verification.summary())

# %%
# How large is it? A volume in mixed units says little. Compare instead, along each state axis through the
# equilibrium, the certified interval with the interval from which simulations of the same loop converge without
# leaving the box (:func:`glidectl.convergent_extent`): a certificate in that box can at best reach the latter.
# The ratio (the number on each bar) is what to read; 0.5 or more is a certificate that decides something.
certified = glider_cert.extent()
converging = gc.convergent_extent(loop, box=glider_cert.box, within_box=glider_cert.in_box)
below, above = certified.ratio(converging)
for i, name in enumerate(certified.names):
    print(f"{name:7s} certified [{certified.lo[i]:+.4f}, {certified.hi[i]:+.4f}], "
          f"convergent [{converging.lo[i]:+.4f}, {converging.hi[i]:+.4f}], ratio {below[i]:.2f} / {above[i]:.2f}")
ax = certified.plot(other=converging)
plt.show()

# %%
# A 2-D slice: the certified set over the states from which simulations converge (grey,
# :func:`glidectl.convergent_slice`); angles in degrees.
dims = ("V", "gamma")
window = tuple((glider_cert.box[0][i], glider_cert.box[1][i]) for i in (0, 1))
slice_ = gc.convergent_slice(loop, dims=dims, box=glider_cert.box, n=15, within_box=glider_cert.in_box,
                             window=window)
ax = slice_.plot()
glider_cert.plot(ax=ax, dims=dims, samples=False)
plt.show()

# %%
# A saturated loop: buoyancy control with a rate-limited pump
# -----------------------------------------------------------
# §6.2's buoyancy law (6.9) commands the pump rate, and the pump saturates (``[actuators] m0`` rate).
# :func:`glidectl.saturated_loop` writes the loop as ``X' = F(X, sat(K (X - X_e)))`` with the saturation made
# explicit. The LMI route (``method="lmi"``) certifies it in seconds with a quadratic ``V``; the SOS route with the
# saturation graph (``certify_roa(sat)``, the default for constant saturation levels) reaches further in about a
# minute.
equilibrium = gc.buoyancy_equilibrium(sph, 1.5)  # the m0 that glides at 1.5 m/s, (6.7)
sat = gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(equilibrium, sph, 5.0)))  # K_b = 5
print(sat.state_names, sat.feedback_names)
ellipsoid = gc.certify_roa(sat, method="lmi")
print(f"certified {ellipsoid.certified}, rigorous {ellipsoid.rigorous}, method {ellipsoid.method}")
print(ellipsoid.verification.summary())
converging_sat = gc.convergent_extent(sat, box=ellipsoid.box, within_box=ellipsoid.in_box, n=6, steps=6)
ax = ellipsoid.extent().plot(other=converging_sat)
plt.show()

# %%
# The ellipsoid is proved, but small along the speed and flight-path angle: a quadratic ``V`` with a sector
# condition is conservative, while simulations recover from anywhere in the box along most axes. On the saturated
# loops measured, the SOS route's degree-2 set reaches 2-4 times further per axis, in 10-12 times the time.

# %%
# Budgets and sizes
# -----------------
# SOS programs grow fast with the number of states and the degree. ``gc.estimate_sos_size(system, degree)`` gives
# the size and memory of the largest program before anything is built, ``budget=`` (seconds, or a
# :class:`glidectl.BudgetOptions`) stops a run with a :class:`glidectl.BudgetError` that says where it stopped, and
# ``gc.installed_sdp_solvers()`` lists the solvers available.
print(gc.estimate_sos_size(loop, 4))
print(gc.installed_sdp_solvers())
