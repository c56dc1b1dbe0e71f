"""
Fit a flight model to dive records
==================================

The hydrodynamic coefficients of a vehicle file are estimates until they meet the water. A dive record (depth,
pitch and pumped volume against time) calibrates them: at each sample the glider is assumed in steady flight at
the recorded pitch and net buoyancy, and the coefficients are fitted so that the modelled vertical speed matches
the measured ``-d depth/dt`` in the least-squares sense, as gliderflight's ``SteadyStateCalibrate`` does
(Merckelbach et al. 2019). This guide reads a real Slocum record, fits three lift and drag laws, checks the fit by
cross-validation and writes the fitted vehicle file, with the fit's standard errors as its ``[uncertainty]`` table.

Reading Slocum files needs the optional extra ``pip install "glidectl[data]"`` (``dbdreader``, which also ships the
record used here).
"""

import math
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

# %%
# Read a record
# -------------
# :func:`glidectl.read_dive_record` reads Slocum binary files (``.dbd``, ``.sbd``, ``.mbd``, ...) through
# ``dbdreader`` and CSV files with the columns ``time, depth, pitch, buoyancy_volume`` in SI units; your own arrays
# go through ``gc.DiveRecord.from_arrays(time, depth, pitch, buoyancy_volume)``. Every record is checked: time must
# increase, pitch must be in radians and the volume in m^3 (a record that looks like degrees or cm^3 is refused).
record = gc.read_dive_record(gc.example_record_path())  # the deep Slocum 'ammonite', 2008: one dive to 605 m
print(f"{len(record)} samples over {(record.time[-1] - record.time[0]) / 60:.0f} min, "
      f"deepest {record.depth.max():.0f} m, pumped volume {1e6 * record.buoyancy_volume.min():.0f} to "
      f"{1e6 * record.buoyancy_volume.max():.0f} cm^3")

# %%
# The fit uses only samples where steady flight is plausible: :meth:`glidectl.DiveRecord.mask` leaves out the
# surface layer, the pumping and pitching-over near each inflection and near-level pitch (the thresholds are a
# :class:`glidectl.MaskSettings`). ``record.plot()`` marks them:
used = record.mask()
print(f"{used.sum()} of {len(record)} samples used by default")
axes = record.plot()
plt.show()

# %%
# Start from a vehicle
# --------------------
# The model needs the hull: its mass in air and volume (``[hydrodynamics] mass``, ``volume``; the volume defaults
# to ``m / density``), its compressibility (1/Pa) and, if the record has temperature, its thermal expansion. Here:
# the ``slocum_shallow`` dynamics with the deep Slocum's 70 kg and gliderflight's default compressibility. Before
# any fit, the model is off by the hull volume it does not know: :func:`glidectl.predict_flight` gives the steady
# flight at every sample.
veh = gc.load_vehicle("slocum_shallow", m=70.0, m_h=61.0).with_hydrodynamics(
    mass=70.0, compressibility=5e-10, source="gliderflight documentation (Slocum 70 kg, 5e-10 1/Pa)")
before = gc.predict_flight(veh, record, used)
rms = np.sqrt(np.mean((before.vertical_speed - record.vertical_speed[used]) ** 2))
print(f"uncalibrated: RMS vertical-speed error {100 * rms:.1f} cm/s")

# %%
# Fit three laws
# --------------
# :func:`glidectl.fit_flight_model` fits, by default, the hull volume and the law's parasitic drag: ``K_D0`` of the
# thesis law (2.9), ``hd_b`` of the Seaglider basestation law and ``Cd0`` of gliderflight's. ``law=`` switches the
# vehicle to that law first, matched to its current lift and drag at 0.25 m/s; ``fit=`` names other coefficients
# (the record must be able to tell them apart, or the fit says which ones it cannot); ``holdout=5`` adds a blocked
# cross-validation (each fifth of the record predicted by a fit to the other four).
fits = {law: gc.fit_flight_model(veh, record, law=law, holdout=5) for law in ("thesis", "seaglider", "gliderflight")}
for law, fit in fits.items():
    coefficients = ", ".join(f"{k} = {v:.5g} +- {fit.stderr[k]:.2g}" for k, v in fit.params.items())
    print(f"{law:12s} {coefficients}")
    print(f"{'':12s} RMS {100 * fit.rms:.2f} cm/s, cross-validated {100 * fit.cv_rms:.2f} cm/s")

# %%
# The cross-validated error stays close to the in-sample one: two coefficients do not over-fit 1,300 samples. The
# thesis law and gliderflight's are both ``D = (a + b alpha^2) V^2`` and fit identically. Modelled against measured
# vertical speed for the gliderflight law, and its residual against depth (no trend with depth: the
# compressibility is about right):
best = fits["gliderflight"]
axes = best.plot()
plt.show()

# %%
# A fit with more freedom: also the induced-drag coefficient ``Cd1``. Its standard error says how well this one
# dive pins it down (a record with a range of pitch angles does better).
wider = gc.fit_flight_model(veh, record, law="gliderflight", fit=("volume", "Cd0", "Cd1"), holdout=5)
for k, v in wider.params.items():
    print(f"{k} = {v:.5g} +- {wider.stderr[k]:.2g}")
print(f"RMS {100 * wider.rms:.2f} cm/s, cross-validated {100 * wider.cv_rms:.2f} cm/s")

# %%
# Use the fitted vehicle
# ----------------------
# ``fit.vehicle`` is a complete vehicle with the fitted values; ``fit.to_toml(path)`` writes it as a vehicle file,
# with each fitted coefficient's standard error (and their correlations) as normal entries of its
# ``[uncertainty]`` table, ready for :func:`glidectl.monte_carlo` and :func:`glidectl.robust_stability`.
path = best.to_toml(Path(tempfile.mkdtemp()) / "ammonite_fitted.toml")
fitted = gc.load_vehicle(path)
print(fitted.law, {k: fitted.params[k] for k in ("volume", "Cd0")})
print({k: f"{u.kind}, std {u.std:.3g}" for k, u in fitted.uncertainty.items()})

# %%
# Every model reads its lift and drag through the same law, so the fitted glider's envelope, linear designs and
# missions follow. Its steady glide at 0.35 m/s, -25 deg needs most of the pump's +-250 g: the drag this record
# shows is three times the preset's (``K_D0`` 7.5 against 2.15 kg/m), so the deep glider is flown slower.
glide = gc.steady_glide(fitted, 0.35, math.radians(-25.0), r_p3=fitted.actuators["r_P3"].fixed)
print(f"alpha {math.degrees(glide.alpha):.2f} deg, pump m0 {1000 * glide.m0:.1f} g, battery {1000 * glide.r_p1:.1f} mm")
