"""
From a vehicle file to a certified controller
=============================================

This tutorial takes one glider through the whole toolbox: a vehicle file, the steady glides its actuators can hold,
a linear model and its modes, an LQR, a dive-cycle mission, a region-of-attraction certificate, and a report. It
uses the longitudinal model of the thesis (§2.3): body axis 1 forward, 3 down, depth ``z`` positive down, SI
units, angles in radians (degrees only where we print or plot them). A downward glide has a negative flight-path
angle ``gamma``.

Everything below is the public API: ``import glidectl as gc``.
"""

import math
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

# %%
# 1. A vehicle file
# -----------------
# A vehicle is a TOML file: a ``[vehicle]`` header, a ``[parameters]`` table in which every value carries its unit
# and its source, and optionally ``[actuators]`` with the range and rate of what the glider moves in flight. The
# numbers here are those of a Slocum-class glider (the ``slocum_shallow`` preset, after Graver 2005), reduced to
# what the longitudinal model needs. ``m`` is the displaced-fluid mass and ``m_f1``, ``m_f3`` the added masses
# (the ``added`` mass model of chapter 8); the pitch damping is the linear ``K_Omega1_2 Omega2`` term.
VEHICLE_FILE = """
[vehicle]
name = "my_glider"
kind = "underwater_glider"
title = "A Slocum-class glider, longitudinal model"

[parameters]
g    = { value = 9.81,   unit = "m/s^2",        source = "standard gravity" }
m    = { value = 52.0,   unit = "kg",           source = "displaced-fluid mass (Slocum specification)" }
m_h  = { value = 43.0,   unit = "kg",           source = "hull mass: m - mbar at neutral buoyancy" }
mbar = { value = 9.0,    unit = "kg",           source = "pitch battery, Graver 2005" }
m_f1 = { value = 5.0,    unit = "kg",           source = "added mass, Graver 2005" }
m_f2 = { value = 60.0,   unit = "kg",           source = "added mass, Graver 2005" }
m_f3 = { value = 70.0,   unit = "kg",           source = "added mass, Graver 2005" }
J1   = { value = 4.0,    unit = "kg*m^2",       source = "Graver 2005" }
J2   = { value = 12.0,   unit = "kg*m^2",       source = "Graver 2005" }
J3   = { value = 11.0,   unit = "kg*m^2",       source = "Graver 2005" }
K_L0 = { value = 0.0,    unit = "kg/m",         source = "symmetric wing" }
K_L  = { value = 132.5,  unit = "kg/m/rad",     source = "Graver 2005" }
K_D0 = { value = 2.15,   unit = "kg/m",         source = "Graver 2005" }
K_D  = { value = 25.0,   unit = "kg/m/rad^2",   source = "Graver 2005" }
K_M0 = { value = 0.0,    unit = "kg",           source = "symmetric hull" }
K_M  = { value = -100.0, unit = "kg/rad",       source = "Graver 2005" }
K_q  = { value = 0.0,    unit = "kg*s/rad",     source = "no V^2 pitch damping: see K_Omega1_2" }
K_Omega1_2 = { value = -60.0, unit = "kg*m^2*s/rad", source = "Graver 2005 (pitch damping)" }
m0   = { value = 0.0,    unit = "kg",           source = "neutral at the surface" }
r_P1 = { value = 0.0,    unit = "m",            source = "battery centred" }
r_P3 = { value = 0.05,   unit = "m",            source = "battery 5 cm below the centre of buoyancy" }
pump_efficiency = { value = 0.5, unit = "1",    source = "assumption: electrical to hydraulic" }

[actuators]
m0   = { min = -0.25,  max = 0.25,  rate = 0.01,  unit = "kg", source = "pump +-250 cm^3 at 10 cm^3/s" }
r_P1 = { min = -0.025, max = 0.025, rate = 0.005, unit = "m",  source = "battery +-2.5 cm at 5 mm/s" }
r_P3 = { fixed = 0.05, unit = "m", source = "the battery does not move vertically" }
"""
path = Path(tempfile.mkdtemp()) / "my_glider.toml"
path.write_text(VEHICLE_FILE)

# %%
# Loading validates the whole file: unknown keys, wrong units, missing sources, non-finite or implausible values
# and inconsistent mass models are refused with a :class:`glidectl.VehicleFileError` that names the key and the
# file. Values are never converted: a unit other than the one glidectl expects is an error.
veh = gc.load_vehicle(path)
print(veh.title, "| provenance", veh.provenance)
print({k: veh.params[k] for k in ("m", "mbar", "K_L", "K_D0", "K_M")})
print(veh.actuators["m0"])

try:
    gc.load_vehicle(path, K_L=float("nan"))  # overrides are checked like the file
except gc.VehicleFileError as err:
    print("refused:", err)

# %%
# To start from a preset instead, write it out and edit the copy: ``veh.to_toml()`` returns the text of a complete
# vehicle file that :func:`glidectl.load_vehicle` reads back to the same values (``gc.list_presets()`` lists
# them).
print(gc.list_presets())
text = gc.load_vehicle("slocum_shallow").to_toml()
print("\n".join(line for line in text.splitlines() if line.startswith(("[", "K_L ", "K_M "))))

# %%
# 2. The glide envelope
# ---------------------
# Which steady glides can this glider hold? A steady glide exists only outside a band of shallow flight-path
# angles (the permissible set (2.26)); on top of that the pump mass ``m0`` and the battery position ``r_P1`` it
# needs must lie within their ranges. :func:`glidectl.glide_envelope` answers both on a grid, in one vectorized
# call.
lo, hi = gc.permissible_gamma(veh)
print(f"no steady glide between {math.degrees(lo):.2f} and {math.degrees(hi):.2f} deg")

envelope = gc.glide_envelope(veh, np.linspace(0.05, 0.8, 46), np.radians(np.linspace(-60.0, 60.0, 61)))
print(envelope.summary())
ax = envelope.plot()
plt.show()

# %%
# 3. A steady glide
# -----------------
# Pick the glide the mission will fly down: 0.35 m/s at -25 deg. For a requested speed and angle the steady glide
# is a one-parameter family of moving-mass positions; the vehicle file fixes ``r_P3``, which picks one member
# (the other choice is the bottom-heaviness ``r_bh=``). The trim residual is checked to 1e-9 relative.
R_P3 = veh.actuators["r_P3"].fixed
glide = gc.steady_glide(veh, speed=0.35, gamma=math.radians(-25.0), r_p3=R_P3)
print(f"alpha {math.degrees(glide.alpha):.2f} deg, pitch {math.degrees(glide.theta):.2f} deg, "
      f"pump m0 {1000 * glide.m0:.1f} g, battery r_P1 {1000 * glide.r_p1:.1f} mm, r_bh {1000 * glide.r_bh:.1f} mm")

# %%
# 4. Linear model, modes, controllability and observability
# ---------------------------------------------------------
# :func:`glidectl.linearize_glide` returns a :class:`control.StateSpace` with named states, exact to rounding
# (complex-step Jacobians). With ``inputs="acceleration"`` the inputs are the battery acceleration ``w1``
# (m/s^2) and the pump rate ``w4`` (kg/s) after the transformation (2.31)-(2.34); the file fixes ``r_P3``, so its
# states and input are left out. ``z_prime`` is the distance from the desired glide path (m, positive below it).
sys = gc.linearize_glide(veh, glide, inputs="acceleration")
print(sys.state_labels, sys.input_labels)
print(gc.modes(sys))

# %%
# Four eigenvalues sit at zero: the glide-path deviation, and the battery position, battery rate and pump mass,
# which are integrators of the inputs. The four others are the glider's own modes, all stable and real here
# (a slow speed mode of 35 s and a 14 s pitch/path mode, then faster heave and pitch-rate modes). The model is
# controllable from the battery and the pump, and every state but ``z_prime`` is observable from pitch, battery
# position and pump mass, as §2.3.1 states for ROGUE:
print(gc.controllability(sys))
print(gc.observability(sys, ("theta", "r_P1", "m0")))

# %%
# 5. An LQR to the glide path
# ---------------------------
# :func:`glidectl.lqr_glide` designs an LQR with :func:`control.lqr` and Bryson weights (one over the square of
# each acceptable deviation, overridable with ``max_deviation=``). It regulates the glide-path deviation too, so
# the glider returns to the line, not only to the glide.
ctrl = gc.lqr_glide(veh, glide, inputs="acceleration")
print("closed-loop poles [1/s]:", np.round(np.sort_complex(ctrl.closed_loop_poles), 3))

# %%
# A controller closes into an input-free model (:func:`glidectl.closed_loop`) that simulates, linearizes and
# certifies like any other. Its states are those of the design model, in SI units. Start 1 m below the path and
# simulate five minutes; the dashed lines are the battery and pump ranges of the vehicle file, which this loop (the
# linear law on the nonlinear glider) does not know about: a 2 m start already drives the battery past its travel.
# Section 6 flies the actuators with their limits.
loop = gc.closed_loop(ctrl)
x0 = loop.equilibrium.copy()
x0[loop.state_names.index("z_prime")] += 1.0  # m below the glide path
sim = gc.simulate(loop, x0, 300.0)
axes = sim.plot(names=("z_prime", "theta", "r_P1", "m0"), scale={"theta": (180 / math.pi, "deg")})
for ax, name in zip(axes[2:], ("r_P1", "m0"), strict=True):
    for bound in veh.actuator_bounds(name):
        ax.axhline(bound, color="r", ls="--", lw=0.8)
axes[0].set_title("LQR recovery from 1 m below the glide path")
plt.show()

# %%
# 6. A dive-cycle mission
# -----------------------
# Linear design is about one glide; a mission switches between a down and an up glide at depth limits.
# :func:`glidectl.dive_cycle` flies a sawtooth on the actuated model (the pump and battery keep to their ranges and
# rates, with a servo on each), one LQR per leg designed as above, a supervisor switching at the measured depth.
# The summary gives distance, time, overshoot, time spent saturated and the pump energy (with the file's
# ``pump_efficiency``) per cycle.
run = gc.dive_cycle(veh, "lqr", depths=(5.0, 60.0), cycles=2, speed=0.35, gamma=math.radians(25.0))
print(run.summary())
axes = run.plot()
plt.show()

# %%
# ``"lqg"`` flies the same legs from noisy depth, pitch and pitch-rate sensors through a sampled Kalman filter,
# ``"pid"`` the operational battery-on-pitch baseline and ``"nonlinear"`` the chapter-6 steady-glide controller;
# :func:`glidectl.compare_missions` tabulates several of them on one mission.
#
# 7. How far can the glider be disturbed? A certificate
# -----------------------------------------------------
# Linear stability is local. A region-of-attraction certificate proves a set of states from which the nonlinear
# closed loop returns to the glide. The actuators saturate, so certify the loop with its limits:
# :func:`glidectl.saturated_loop` extracts the LQR law, the pump rate limit and the actuator ranges and battery
# rate as state-dependent limits, and :func:`glidectl.certify_roa` certifies it by linear matrix inequalities
# (an ellipsoid, a quadratic Lyapunov function; about 10 s).
saturated = gc.saturated_loop(loop)
cert = gc.certify_roa(saturated)
print(f"certified: {cert.certified} (method {cert.method}); every a-posteriori check:")
print(cert.verification.summary())

# %%
# ``cert.rigorous`` tells whether the set is proved for the true model or only checked by sampling (the LMI path
# bounds the nonlinear remainder on a box from Hessian samples, so it is sampled-sound). To judge the size, compare
# the certified interval along each state axis with the interval from which simulations of the same loop
# converge (:func:`glidectl.convergent_extent`); the bars are fractions of the validity box (actuator ranges,
# documented half-widths of the glider states).
print("rigorous:", cert.rigorous)
certified = cert.extent()
converging = gc.convergent_extent(saturated, box=cert.box, within_box=cert.in_box, n=8, steps=6)
ax = certified.plot(other=converging)
plt.show()

# %%
# The ellipsoid is small next to what simulation shows (a few centimetres of path deviation, a fraction of a
# degree of pitch): a quadratic function with a bounded remainder is conservative. The polynomial (SOS) route,
# ``gc.certify_roa(loop, degree=2)``, reaches further at the cost of a minute or more; the how-to
# :ref:`sphx_glr_auto_howto_plot_04_certify_closed_loop.py` shows both routes.
#
# 8. A report
# -----------
# Reports are built from design files: a Python file that defines ``TITLE`` and ``design(progress, quick=False)``
# returning a ``glidectl.report.Report`` (numbers with units and sources, tables, figures with captions, text;
# the :doc:`/report-api` lists every method). A minimal one for this glider (run from the folder that holds
# ``my_glider.toml``)::
#
#     """my_glider: envelope and LQR."""
#     import math
#     import glidectl as gc
#     from glidectl.report import Report
#
#     TITLE = "my_glider: envelope and LQR"
#
#     def design(progress, quick=False):
#         veh = gc.load_vehicle("my_glider.toml")
#         rep = Report(TITLE, vehicle=veh)
#         glide = gc.steady_glide(veh, 0.35, math.radians(-25), r_p3=veh.actuators["r_P3"].fixed)
#         rep.number("pump_mass_down", glide.m0, "kg", source="gc.steady_glide")
#         rep.figure("envelope", gc.glide_envelope(veh, [0.2, 0.35, 0.5], [-0.6, -0.44, 0.44, 0.6]).plot().figure,
#                    "Glide envelope.")
#         return rep
#
# Build it from the shell; the report folder gets ``report.pdf``, one PNG per figure and ``numbers.json``, and a
# rebuild with nothing changed comes from the cache:
#
# .. code-block:: console
#
#     $ glidectl report my_design.py --out reports
#     $ glidectl report my_design.py --quick         # the design's quick settings, if it has them
#     $ glidectl list                                 # presets and the designs in ./designs
#
# The designs shipped in the repository's ``designs/`` folder (``glidectl report all``) are complete examples:
# ``slocum_dive_cycle`` is this tutorial at full size.
