"""
A flight model fitted to a real dive record
===========================================

A 107-minute dive of the deep Slocum glider 'ammonite' to 608 m (2008), shipped with ``dbdreader``
(:func:`glidectl.example_record_path`), against the steady-state flight model of three lift and drag laws, each
with the hull volume and its parasitic drag fitted to the measured vertical speed (:func:`glidectl.fit_flight_model`).
"""

import matplotlib.pyplot as plt

import glidectl as gc

record = gc.read_dive_record(gc.example_record_path())
# the slocum_shallow dynamics with the deep Slocum's mass (70 kg) and a compressible hull (1/Pa)
veh = gc.load_vehicle("slocum_shallow", m=70.0, m_h=61.0).with_hydrodynamics(mass=70.0, compressibility=5e-10)

fits = {law: gc.fit_flight_model(veh, record, law=law, holdout=5) for law in ("thesis", "seaglider", "gliderflight")}
print(f"{record.depth.max():.0f} m, {(record.time[-1] - record.time[0]) / 60:.0f} min, {len(record)} samples")
for law, fit in fits.items():  # fit.summary() says the same, with the record's path
    coefficients = ", ".join(f"{k} = {v:.5g} +- {fit.stderr[k]:.2g}" for k, v in fit.params.items())
    print(f"{law:12s} {coefficients}; RMS {1000 * fit.rms:.1f} mm/s, cross-validated {1000 * fit.cv_rms:.1f} mm/s")

# %%
# The fit of gliderflight's law: modelled against measured vertical speed over the record (red: samples the
# default mask leaves out, near the surface and the inflections, where the glider is not in steady flight), and
# the residual against depth. The thesis law and gliderflight's are the same quadratic drag polar in different
# coefficients, so they fit identically; the Seaglider law's drag falls with dynamic pressure and fits a little
# worse on this record. The residual (about 6 cm/s RMS) is sensor noise and unsteady flight, not the law.
axes = fits["gliderflight"].plot()
axes[0].figure.set_size_inches(9, 6.5)
plt.show()
