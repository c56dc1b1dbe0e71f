"""
Run a Monte Carlo study on a dask cluster
=========================================

The coefficients of a glider that has not been towed or flown are known to 20-30 % at best. This guide gives the
``slocum_shallow`` preset an uncertainty table, then asks three questions over vehicles drawn from it, each keeping
the designs made on the nominal vehicle:

1. what steady glide each sampled vehicle needs (any function of a vehicle, :func:`glidectl.monte_carlo`);
2. whether the nominal LQR keeps the glide stable: probability, worst case in the box, margin and sensitivities
   (:func:`glidectl.robust_stability`);
3. what dive cycles flown by the nominal design cost (:func:`glidectl.dive_cycle_ensemble`).

Each runs on a ``concurrent.futures`` executor: here a local ``dask.distributed`` cluster of two worker processes
(``pip install "glidectl[dask]"``); a process pool (``ProcessPoolExecutor(2)``) or a remote cluster's
``client.get_executor()`` work the same way. The samples are drawn before anything runs, so a seed gives the same
table whatever the executor and the chunking. The sample sizes are kept small here; the ``robustness`` design in
the repository runs 1,000 of each.
"""

import math

import matplotlib.pyplot as plt

import glidectl as gc

# %%
# The uncertainty table
# ---------------------
# ``with_uncertainty`` sets the vehicle's ``[uncertainty]`` table: ``{"rel": 0.3}`` is the interval nominal +-30 %,
# ``{"std": ...}`` or ``{"rel_std": ...}`` a normal distribution (optionally truncated), and correlations go in
# ``correlation=``. A vehicle file can carry the same table, and a flight-model fit writes its standard errors there
# (``fit.to_toml``). Here: lift, drag, pitch stiffness and damping, and the added masses and pitch inertia.
COEFFICIENTS = ("K_L", "K_D0", "K_D", "K_M", "K_Omega1_2", "m_f1", "m_f3", "J2")
veh = gc.load_vehicle("slocum_shallow").with_uncertainty(
    {k: {"rel": 0.3, "source": "+-30 %: scaled from another vehicle"} for k in COEFFICIENTS})
R_P3 = veh.actuators["r_P3"].fixed  # m
DOWN = (0.35, math.radians(-25.0))  # the dive leg: speed (m/s) and flight-path angle (rad)
draws = veh.sample(5, seed=0)  # five vehicles drawn from the table (a VehicleSample)
print(draws.keys)
print(draws.values.round(3))  # one row per draw, one column per key


# %%
# A study is any function of a vehicle returning numbers (a mapping of names to floats). It runs in the workers, so
# define it at module level; a ``units`` attribute labels the plots.
def down_glide(v):
    """The steady dive leg of vehicle ``v``: pump mass (kg), battery position (mm), pitch (deg)."""
    g = gc.steady_glide(v, *DOWN, r_p3=R_P3)
    return {"m0": g.m0, "r_P1": 1000 * g.r_p1, "theta": math.degrees(g.theta)}


down_glide.units = {"m0": "kg", "r_P1": "mm", "theta": "deg"}

# %%
# Start the cluster
# -----------------
# ``processes=True`` gives each worker its own Python process (the studies are CPU-bound; threads would share one
# interpreter). The workers are fresh processes that import this script again, so everything that starts the
# cluster or uses it stays under ``if __name__ == "__main__":`` (the same rule as for ``multiprocessing``); the
# definitions above are cheap and are what the workers need.
if __name__ == "__main__":
    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    executor = client.get_executor()  # a concurrent.futures.Executor on the cluster
    print(f"{len(client.scheduler_info()['workers'])} worker processes")

# %%
# 1. A Monte Carlo of any study
# -----------------------------
# :func:`glidectl.monte_carlo` draws ``n`` vehicles, splits them in chunks, runs the study on each, and collects one
# row per sample. A sample whose study fails (a glide that does not exist, an actuator out of range) is counted
# with its reason in ``mc.failures``, not raised.
if __name__ == "__main__":
    mc = gc.monte_carlo(down_glide, veh, n=200, seed=0, executor=executor)
    print(mc.summary())
    print("influence on m0 (rank correlations):", {k: round(v, 2) for k, v in mc.influence("m0").items()})
    axes = mc.plot(names=["m0", "r_P1"])
    plt.show()

# %%
# 2. Robust stability of the nominal LQR
# --------------------------------------
# The controller keeps the gain designed on the nominal vehicle; each sampled vehicle changes the plant.
# :func:`glidectl.robust_stability` finds each sampled loop's equilibrium and its largest closed-loop real part,
# then searches the box for the worst case (corners, then a bounded local search from the worst points), bisects
# the largest box scaling without an unstable vehicle (the margin), and gives the dominant pole's sensitivity to
# each coefficient.
if __name__ == "__main__":
    nominal = gc.steady_glide(veh, *DOWN, r_p3=R_P3)
    lqr = gc.lqr_glide(veh, nominal, inputs="acceleration")
    rs = gc.robust_stability(lqr, n=200, seed=0, executor=executor)
    print(rs.summary())
    axes = rs.plot()
    axes[0].figure.set_size_inches(13, 4)
    plt.show()

# %%
# Every sampled loop is stable, and the worst case in the box too; the margin says how far the +-30 % box can grow
# before an unstable vehicle is found. The pitch damping and the parasitic drag move the dominant pole most.
#
# 3. Dive cycles of sampled vehicles
# ----------------------------------
# :func:`glidectl.dive_cycle_ensemble` flies :func:`glidectl.dive_cycle` for each sampled vehicle under the
# controller designed on the nominal one (``design_vehicle``), the samples of a chunk integrated together as one
# stacked system. The numbers per sample: energy per km, cycle time, time saturated, depth overshoot, distance and
# energy per cycle.
if __name__ == "__main__":
    ens = gc.dive_cycle_ensemble(veh, n=24, seed=0, cycles=1, depths=(5.0, 40.0), executor=executor)
    print(ens.summary())
    low, median, high = ens.quantiles("energy_per_km")
    print(f"pump energy per km: median {median:.0f} J, 5-95 % [{low:.0f}, {high:.0f}] J")
    axes = ens.plot(names=["energy_per_km", "max_overshoot"])
    plt.show()

# %%
# Close the cluster when done (a ``with Client(...)`` block does it for you).
if __name__ == "__main__":
    client.close()
    cluster.close()

# %%
# The same studies without a cluster: leave out ``executor=`` (everything runs in this process), or pass
# ``concurrent.futures.ProcessPoolExecutor(2)``. To run them on a cluster elsewhere, connect a ``Client`` to its
# scheduler's address instead of starting a ``LocalCluster``; the workers need glidectl installed.
