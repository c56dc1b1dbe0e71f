"""
Phugoid orbits and Lanchester's C (Fig 4.1)
===========================================

Without drag, with equal added masses and the moving mass at the centre of buoyancy, the longitudinal glider
reduces to the phugoid-mode model (4.1)-(4.4), :class:`glidectl.PhugoidModel`. It conserves energy and
Lanchester's second constant ``C`` (4.5), which sorts its trajectories into four classes
(:func:`glidectl.classify_C`): steady level flight at ``C = 2/3``, waves for ``0 < C < 2/3``, cusps at ``C = 0``
and loops for ``C < 0``. The vehicle is that of Fig 4.1: ``m1 + mbar = 14`` kg, ``m0 = 1`` kg, ``K = 100`` kg/m.
"""

import matplotlib.pyplot as plt

import glidectl as gc

model = gc.PhugoidModel(mass=14.0, m0=1.0, K=100.0)
print(f"steady level speed xdot_e = {model.xdot_e:.3f} m/s")

# %%
# Each orbit starts level at its fastest point (``initial_state_for_C``, the default "fast" branch) and is
# simulated for 6 s as in Fig 4.1; :func:`glidectl.orbit_period` gives the time per wave, cusp or loop. The
# period at ``C = 0`` is finite (about 2 s): the thesis's "infinite time interval" is erratum E4.10.
fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
for C in (gc.C_STEADY, 0.4, 0.0, -0.5):
    x0 = gc.initial_state_for_C(model, C)
    sim = gc.simulate(model, x0, 6.0)
    print(f"C = {C:+.3f}: {gc.classify_C(C).value}, period {gc.orbit_period(model, C):.3f} s, "
          f"C along the run {model.lanchester_C(sim.x[-1]):+.6f}")
    ax.plot(sim.state("x"), sim.state("z"), label=f"C = {C:+.2f}: {gc.classify_C(C).value}")
ax.invert_yaxis()  # z is depth, positive down
ax.set_xlabel("x [m]")
ax.set_ylabel("z [m] (down)")
ax.set_title("phugoid-mode trajectories, 6 s each (analogue of Fig 4.1)")
ax.legend(fontsize=8)
plt.show()
