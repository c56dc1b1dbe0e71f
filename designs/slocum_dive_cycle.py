"""A glider that is not in the thesis, end to end: the Slocum-class ``slocum_shallow`` preset flying dive cycles.

The vehicle file (every value cited; pump +-0.25 kg at 0.01 kg/s, pitch battery +-2.5 cm at 5 mm/s, vertical
battery offset fixed at 5 cm, pump efficiency 0.5) gives the parameter and actuator tables; the glide envelope
shows which steady glides its actuators can hold; the controller designs are LQR on battery and pump (``w1``,
``w4``) and LQG from depth, pitch and pitch rate; the four controllers of :func:`glidectl.dive_cycle` fly the same
sawtooth mission with the same noisy sensors, and the comparison table gives distance, duration, overshoot,
saturation and pump energy per cycle. No published results exist for this glider: the report is a plain results
table, not a ledger.

Run ``glidectl report slocum_dive_cycle`` or ``python designs/slocum_dive_cycle.py [OUTDIR] [--quick]``; writes
``OUTDIR/slocum_dive_cycle/``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import glidectl as gc
from glidectl.report import Report, cached, run_script

TITLE = "A Slocum-class glider end to end: envelope, LQR and LQG designs, dive-cycle missions"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 40.0, "full": 150.0}
CONTROLLERS = ("lqr", "lqg", "nonlinear", "pid")


@dataclass(frozen=True)
class Settings:
    """Every setting of the design (FULL: the mission of issue 16)."""

    vehicle: str = "slocum_shallow"
    speed: float = 0.35  # m/s, both legs
    gamma_deg: float = 25.0  # glide-path angle magnitude of both legs
    depths: tuple[float, float] = (5.0, 100.0)  # m, top and bottom of the sawtooth
    cycles: int = 3
    #: sensor noise standard deviations (m, rad, rad/s) seen by every controller: depth (pressure sensor), pitch,
    #: pitch rate; assumed levels of this design (glidectl.controllers.dive_cycle.LQG_NOISE), not datasheet values
    noise: tuple[tuple[str, float], ...] = (("z", 0.05), ("theta", math.radians(0.5)),
                                            ("Omega2", math.radians(0.2)))
    sensor_period: float = 2.0  # s, sample-and-hold of the noise
    seed: int = 2026  # noise seed (same for every controller)
    envelope_speeds: tuple[float, float, int] = (0.05, 0.8, 76)  # m/s, linspace
    envelope_gammas_deg: tuple[float, float, int] = (-60.0, 60.0, 121)  # deg, linspace
    #: s, budget of gc.certify_roa on the down leg's LQR loop (degree 2), None: none. FULL has none: a budget is a
    #: safety net, not a result, and a FULL build beside the other designs once exceeded 120 s (BudgetError in the
    #: final verification, a certificate that another build had): the report must not depend on the machine's load
    #: (measured 2026-12-02). Without a budget, certify_roa also skips the sampled checks of a first remainder-box
    #: round that the second replaces. QUICK gives it 20 s and shows the budget answer.
    roa_time_limit: float | None = None
    roa_slice_n: int = 31  # grid per axis of the simulated converging (theta, m0) slice under the certificate


#: gc.certify_roa's arguments for the down leg's LQR loop (with the settings' time limit). designs/roa_certification.py
#: certifies the same loop with the same arguments under the same cache key (``_certify_lqr_loop``), so a build
#: computes it once.
ROA_ARGS = {"degree": 2}


def _certify_lqr_loop(veh: gc.Vehicle, controller: Any, loop: gc.ClosedLoop,
                      time_limit: float | None) -> gc.ROACertificate:
    """``gc.certify_roa(loop, budget=time_limit, **ROA_ARGS)`` for the closed loop of ``controller`` (a
    ``gc.lqr_glide``) on ``veh``, cached under a key of the vehicle, the gain, the loop's equilibrium and every
    argument (the time limit too: a budget can stop the second remainder-box round and return the first round's
    certificate). In a build, a design that asks while another computes it waits and reads it."""
    args = dict(ROA_ARGS, budget=gc.BudgetOptions(time_limit=time_limit))
    key = ("certify_roa", "lqr_glide loop", veh, np.asarray(controller.K), np.asarray(loop.equilibrium), args)
    return cached(key, lambda: gc.certify_roa(loop, **args))


FULL = Settings()
QUICK = Settings(depths=(5.0, 30.0), cycles=1, envelope_speeds=(0.05, 0.8, 31),
                 envelope_gammas_deg=(-60.0, 60.0, 49), roa_time_limit=20.0, roa_slice_n=9)


@dataclass(frozen=True)
class SlocumResults:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    vehicle: gc.Vehicle
    envelope: gc.GlideEnvelope
    mission_envelope: gc.GlideEnvelope
    glides: tuple[gc.SteadyGlide, gc.SteadyGlide]
    lqr_path: tuple[gc.LinearGlideController, gc.LinearGlideController]
    lqg: tuple[gc.LQGController, gc.LQGController]
    comparison: gc.MissionComparison
    roa_message: str
    roa_volume: float | None  # cert.volume() of the certificate (free-state units), None when not certified
    roa_loop: gc.ClosedLoop  # gc.closed_loop of the down leg's lqr_glide
    roa_box: tuple[np.ndarray, np.ndarray]  # its default box in certify_roa (gc.validity_box)
    roa_extent: gc.Extent | None  # cert.extent() of the certificate, None when there is none
    convergent_extent: gc.Extent  # gc.convergent_extent of the loop in that box
    roa_cert: gc.ROACertificate | None  # the certificate, None when there is none
    convergent_slice: gc.ConvergentSlice  # the (theta, m0) slice of the loop that converges in that box


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> SlocumResults:
    """Envelope, leg designs and the four-controller mission comparison."""
    veh = gc.load_vehicle(s.vehicle)
    gamma = math.radians(s.gamma_deg)
    r_p3 = veh.actuators["r_P3"].fixed
    progress("glide envelope")
    env = gc.glide_envelope(veh, np.linspace(*s.envelope_speeds), np.radians(np.linspace(*s.envelope_gammas_deg)))
    mission_env = gc.glide_envelope(veh, [s.speed], [-gamma, gamma])
    glides = (gc.steady_glide(veh, s.speed, -gamma, r_p3=r_p3), gc.steady_glide(veh, s.speed, gamma, r_p3=r_p3))
    progress("LQR and LQG leg designs")
    noise = dict(s.noise)
    sensors = tuple(noise)
    # the mission's LQR is lqg_glide's regulator (the same Bryson weights on the z'-free states, inputs w1, w4);
    # lqr_glide also regulates z' (the glide path through the origin): shown for comparison
    lqg = tuple(gc.lqg_glide(veh, g, sensors, noise, inputs="acceleration") for g in glides)
    lqr_path = tuple(gc.lqr_glide(veh, g, inputs="acceleration") for g in glides)
    progress("region of attraction of the LQR loop")
    loop = gc.closed_loop(lqr_path[0])
    roa_box = gc.validity_box(loop)  # certify_roa's default box (the same as gc.saturated_loop's)
    roa_volume = roa_extent = cert = None
    try:
        cert = _certify_lqr_loop(veh, lqr_path[0], loop, s.roa_time_limit)
        roa_message = f"{'certified' if cert.certified else 'NOT certified'}: {cert}"
        roa_volume = cert.volume() if cert.certified else None
        roa_extent = cert.extent() if cert.certified else None
    except gc.GlidectlError as exc:
        roa_message = f"{type(exc).__name__}: {exc}"
    progress("convergent extent of the LQR loop (simulations along each state axis)")
    within = cert.in_box if cert is not None else True
    conv_extent = gc.convergent_extent(loop, box=roa_box, within_box=within)
    # the slice over the certificate's own box (its plot's limits), the runs judged against the default box
    k = [loop.state_names.index(d) for d in ("theta", "m0")]
    window = None if cert is None else tuple((cert.box[0][i], cert.box[1][i]) for i in k)
    conv_slice = gc.convergent_slice(loop, dims=("theta", "m0"), box=roa_box, n=s.roa_slice_n, within_box=within,
                                     window=window)
    mission: dict[str, Any] = dict(depths=s.depths, gamma=gamma, speed=s.speed, cycles=s.cycles, noise=noise,
                                   seed=s.seed, sensor_period=s.sensor_period)
    progress(f"missions: {', '.join(CONTROLLERS)} ({s.cycles} cycles, {s.depths[0]:g}-{s.depths[1]:g} m)")
    comparison = gc.compare_missions(veh, CONTROLLERS, **mission)
    return SlocumResults(s, veh, env, mission_env, glides, lqr_path, lqg, comparison, roa_message,
                         roa_volume, loop, roa_box, roa_extent, conv_extent,
                         cert if roa_extent is not None else None, conv_slice)


def _poles(lam: np.ndarray) -> list[list[float]]:
    return [[float(z.real), float(z.imag)] for z in sorted(np.asarray(lam), key=lambda z: (z.real, z.imag))]


def _fmt_poles(lam: np.ndarray) -> str:
    return ", ".join(f"{z.real:.3f}{z.imag:+.3f}i" if abs(z.imag) > 1e-12 else f"{z.real:.3f}"
                     for z in sorted(np.asarray(lam), key=lambda z: (z.real, z.imag)))


def report(res: SlocumResults) -> Report:
    """The report: parameter and actuator tables (from the vehicle), results table, tables, figures, notes."""
    s, veh = res.settings, res.vehicle
    rep = Report(TITLE, vehicle=veh)
    env = res.envelope
    feas = env.feasible
    rep.number("envelope_feasible_fraction", float(np.mean(feas)), "-", "glide_envelope",
               note=f"Share of the {feas.shape[0]} x {feas.shape[1]} grid (V in {s.envelope_speeds[:2]} m/s, gamma "
                    f"in {s.envelope_gammas_deg[:2]} deg) where the glide exists and m0, r_P1 are within the "
                    f"[actuators] ranges at the fixed r_P3 = {veh.actuators['r_P3'].fixed:g} m.")
    rep.number("envelope_max_horizontal_speed", float(np.nanmax(np.where(feas, env.horizontal_speed, np.nan))),
               "m/s", "glide_envelope", note="Fastest feasible horizontal speed V cos(gamma) on the grid.")
    rep.number("envelope_max_sink_rate", float(np.nanmax(np.where(feas, env.vertical_speed, np.nan))), "m/s",
               "glide_envelope", note="Fastest feasible sink rate -V sin(gamma) on the grid.")
    me = res.mission_envelope
    rep.number("mission_glides_feasible", bool(np.all(me.feasible)), "-", "glide_envelope",
               note=f"The mission's glides ({s.speed:g} m/s, +-{s.gamma_deg:g} deg) are inside the envelope.")
    g_down, g_up = res.glides
    rep.number("mission_glide_m0", [g_down.m0, g_up.m0], "kg", "steady_glide",
               note=f"Pump mass of the down and up glides (pump range {veh.actuators['m0'].bounds} kg).")
    rep.number("mission_glide_r_p1", [g_down.r_p1, g_up.r_p1], "m", "steady_glide",
               note=f"Battery position of the down and up glides (travel {veh.actuators['r_P1'].bounds} m).")
    for leg, d in zip(("down", "up"), res.lqg, strict=True):
        rep.number(f"lqr_{leg}_poles", _poles(d.regulator_poles), "1/s", "our design",
                   note=f"LQR (Bryson weights, python-control) on battery w1 and pump w4 at the {leg} glide, states "
                        f"{', '.join(d.regulated_states)} (r_P3 fixed: w3 and its states left out; z' not "
                        "regulated: a dive cycle holds the glide, not a path). The gain the mission's 'lqr' flies.")
        rep.number(f"lqg_{leg}_estimator_poles", _poles(d.estimator_poles), "1/s", "our design",
                   note=f"Kalman filter (control.lqe) from {', '.join(d.sensors.names)} with noise "
                        f"{', '.join(f'{v:.3g}' for v in d.noise)} (m, rad, rad/s) at the {leg} glide; estimates "
                        f"{', '.join(d.estimated_states)}.")
    for leg, c in zip(("down", "up"), res.lqr_path, strict=True):
        rep.number(f"lqr_path_{leg}_max_real_pole", float(np.max(np.real(
            c.closed_loop_poles[np.abs(c.closed_loop_poles) > 1e-9]))), "1/s", "our design",
                   note="gc.lqr_glide with the file's default inputs (w1, w4), which also regulates the "
                        "glide-path deviation z' (on the model without the fixed r_P3 states: no poles at 0).")
    rows = []
    for r in res.comparison.rows:
        name = r["controller"]
        if r.get("error"):
            rep.number(f"mission_{name}_refused", r["error"], "-", "dive_cycle", note="Why the controller cannot "
                       "fly this mission.")
            continue
        for key, unit in (("distance_per_cycle", "m"), ("duration_per_cycle", "s"), ("max_overshoot", "m"),
                          ("saturated_time_per_cycle", "s"), ("energy_per_cycle", "J")):
            rep.number(f"mission_{name}_{key}", r[key], unit, "dive_cycle")
        rows.append(name)
    rep.number("roa_lqr_certified", res.roa_message.startswith("certified"), "-", "certify_roa",
               note=res.roa_message[:400])
    if res.roa_volume is not None:
        rep.number("roa_lqr_volume", res.roa_volume, "-", "ROACertificate.volume",
                   note="volume of the certified set in the 8 free states' own units (product of the units)")
    if res.roa_extent is not None:
        below, above = res.roa_extent.ratio(res.convergent_extent)
        rep.number("roa_lqr_min_extent_ratio", float(np.nanmin(np.concatenate([below, above]))), "-",
                   "ROACertificate.extent / gc.convergent_extent",
                   note="smallest certified / convergent extent over the state axes and directions (goal >= 0.5); "
                        f"{res.convergent_extent.what}; certificate "
                        f"{'rigorous' if res.roa_extent.rigorous else 'not rigorous'}")
        ax = res.roa_extent.plot(other=res.convergent_extent)
        rep.figure("roa_lqr_extent", ax.figure,
                   "Down leg's LQR loop: certified extent per state axis through the glide (blue) against the "
                   "extent from which simulations of the loop converge (grey), as fractions of the default box's "
                   "half-width on each side; the number on a bar is the ratio (the goal is 0.5, dotted).")
        ax = res.convergent_slice.plot()
        rep.figure("roa_lqr_slice", res.roa_cert.plot(ax=ax, dims=("theta", "m0"), n=61, samples=False).figure,
                   "Down leg's LQR loop: the certified set's (theta, m0) slice through the glide over the part of the "
                   "slice from which simulations of the loop converge without leaving the default box (grey, a "
                   f"{len(res.convergent_slice.x)} x {len(res.convergent_slice.y)} grid).")
        rep.table("Certified against convergent extent of the down leg's LQR loop (state units)",
                  ["state", "certified", "convergent", "ratio lo", "ratio hi"],
                  [[k, f"[{res.roa_extent.lo[i]:.4g}, {res.roa_extent.hi[i]:.4g}]",
                    f"[{res.convergent_extent.lo[i]:.4g}, {res.convergent_extent.hi[i]:.4g}]", f"{below[i]:.3g}",
                    f"{above[i]:.3g}"] for i, k in enumerate(res.roa_extent.names)])

    # ---------------------------------------------------------------- tables
    rep.table(f"Mission glides ({s.speed:g} m/s, r_P3 = {veh.actuators['r_P3'].fixed:g} m fixed)",
              ["leg", "gamma [deg]", "alpha [deg]", "theta [deg]", "m0 [kg]", "r_P1 [cm]", "horizontal [m/s]",
               "sink [m/s]"],
              [[leg, f"{math.degrees(g.gamma):+.1f}", f"{math.degrees(g.alpha):.3f}", f"{math.degrees(g.theta):.3f}",
                f"{g.m0:.4f}", f"{100 * g.r_p1:.3f}", f"{g.speed * math.cos(g.gamma):.3f}",
                f"{-g.speed * math.sin(g.gamma):.3f}"] for leg, g in zip(("down", "up"), res.glides, strict=True)])
    d0 = res.lqg[0]
    cols = list(d0.regulated_states)
    gain_rows = []
    for leg, d in zip(("down", "up"), res.lqg, strict=True):
        names = list(d.state_names)
        for inp in d.actuate:
            i = list(d.plant.input_labels).index(inp)
            gain_rows.append([leg, inp] + [f"{d.K[i, names.index(c)]:.4g}" for c in cols])
    rep.table("LQR gains of 'lqr' and of the regulator of 'lqg' (w1 m/s^2, w4 kg/s per SI state unit)",
              ["leg", "input", *cols], gain_rows)
    rep.table("Closed-loop poles (1/s)", ["leg", "LQR (regulator)", "LQG estimator"],
              [[leg, _fmt_poles(d.regulator_poles), _fmt_poles(d.estimator_poles)]
               for leg, d in zip(("down", "up"), res.lqg, strict=True)])
    comp_rows = []
    for r in res.comparison.rows:
        if r.get("error"):
            comp_rows.append([r["controller"], "-", "-", "-", "-", "-",
                              f"refused ({r['error'].split(':')[0]}): see 'Mission and controllers'"])
        else:
            comp_rows.append([r["controller"], f"{r['distance_per_cycle']:.1f}", f"{r['duration_per_cycle']:.0f}",
                              f"{r['max_overshoot']:.2f}", f"{r['saturated_time_per_cycle']:.0f}",
                              f"{r['energy_per_cycle']:.1f}", ""])
    rep.table(f"Four controllers, {s.cycles} cycle(s) {s.depths[0]:g}-{s.depths[1]:g} m, {s.speed:g} m/s, "
              f"+-{s.gamma_deg:g} deg (per-cycle means)",
              ["controller", "distance [m]", "duration [s]", "overshoot [m]", "saturated [s]", "pump energy [J]",
               "note"], comp_rows)

    # ---------------------------------------------------------------- figures
    ax = env.plot()
    fig = ax.figure
    for g, mk in zip(res.glides, ("v", "^"), strict=True):
        ax.plot(g.speed * math.cos(g.gamma), -g.speed * math.sin(g.gamma), mk, color="k", ms=9,
                label=f"mission glide {math.degrees(g.gamma):+.0f} deg")
    ax.legend(fontsize=7, loc="best")
    rep.figure("glide_envelope", fig, f"Glide envelope of {veh.name} (glide polar; colour: the limit that binds). "
               f"Black triangles: the mission's down and up glides at {s.speed:g} m/s.")
    for name, run in res.comparison.runs.items():
        rep.figure(f"mission_{name}", run.plot()[0].figure,
                   f"Dive cycles under '{name}': depth with the limits and inflections, pitch, and commanded versus "
                   f"achieved pump and battery. {run.summary().splitlines()[0]}.")

    # ---------------------------------------------------------------- notes
    refused = [r for r in res.comparison.rows if r.get("error")]
    rep.text("Mission and controllers",
             "Each leg flies one steady glide of the family at the file's fixed r_P3; the supervisor switches at the "
             "measured depth limit and ramps the references at 80 % of the actuator rates. Every controller sees "
             "the same noisy depth, pitch and pitch rate (standard deviations "
             + ", ".join(f"{k} {v:.3g}" for k, v in s.noise) + f" in m, rad, rad/s; held {s.sensor_period:g} s, seed "
             f"{s.seed}). 'lqr' is state "
             "feedback (every state measured; depth, pitch and pitch rate noisy); 'lqg' sees only the noisy depth, "
             "pitch and pitch rate and estimates the rest (with all three inputs these sensors leave two moving-mass "
             "modes unobservable; with r_P3 fixed the (w1, w4) design is observable); 'pid' is the operational "
             "baseline (PID on pitch through the battery, pump run to its end at each inflection); 'nonlinear' is the "
             "chapter-6 steady-glide controller.\n\n"
             + ("Refused: " + " ".join(f"{r['controller']}: {r['error']}" for r in refused) if refused else
                "Every controller flew the mission.") + _energy_note(res))
    rep.text("Actuator limits",
             "No controller saturates its own commands; all are run through the actuated model (ActuatedGlider in "
             "simulate_actuated), whose servo loops and rate/range limiter enforce the [actuators] table printed "
             "with the parameters: the pump and the battery never leave their ranges, and 'saturated' in the table "
             "is the time some actuator spent at a range end or at its rate limit.")
    loop = res.roa_loop
    rep.table("Default box of the down leg's LQR loop (gc.validity_box: certify_roa and saturated_loop)",
              ["state", "lo", "x_e", "hi"],
              [[k, f"{lo:.6g}", f"{x:.6g}", f"{hi:.6g}"]
               for k, lo, x, hi in zip(loop.state_names, res.roa_box[0], loop.equilibrium, res.roa_box[1],
                                       strict=True)])
    certified = res.roa_message.startswith("certified")
    rep.text("Region of attraction of the LQR loop",
             "gc.certify_roa takes this closed loop (gc.closed_loop of the down leg's gc.lqr_glide: the glide-path "
             "model without the fixed r_P3 and its rate, 8 states: the vehicle file fixes r_P3, and the design model "
             "drops a fixed actuator's states) with its default box, the validity box of its states "
             "(gc.validity_box, the table above; gc.saturated_loop uses the same box): the pump and battery ranges "
             "and the battery rate of the [actuators] table and the documented half-widths of z', theta, Omega2, v1 "
             "and v3 about the glide, each shrunk by 0.1 %, and certifies through a polynomial surrogate of the loop "
             "with a remainder bound. "
             + ("With degree 2 and no time limit" if res.settings.roa_time_limit is None else
                f"With degree 2 and a budget of {res.settings.roa_time_limit:g} s") + " it answered: "
             f"{res.roa_message[:500]}"
             + ("\n\nThe SOS route does not finish on this loop in this budget: without one (the FULL settings) it "
                "certifies it (about 80 s on one core, measured 2026-12-03). The LMI path certifies this "
                "loop too, unsaturated and saturated at the pump rate, with the same default box: see the "
                "roa_certification design, section 'Saturated loops' "
                "(gc.certify_roa_lmi(gc.saturated_loop(loop)))."
                if not certified else
                f"\n\nThe certified set has volume {res.roa_volume:.4g} in the free states' own units. The "
                "surrogate matches the loop to second order at the glide, so its remainder bound is cubic "
                "(a |y|^2 + b |y|^3 with a at rounding level) and costs the decrease condition only quartic terms; "
                "the bound holds on the box it was built on, so certify_roa first searched a smaller box (three "
                "times the extents of the best level set of its starting V, one level SDP per box: the "
                "'remainder box' steps of cert.history) and certified there, then re-certified on a box three "
                "times the extents of that set (a second round, kept if larger). The LMI path certifies this loop "
                "too, unsaturated and saturated at the pump rate: the roa_certification design, section "
                "'Saturated loops', compares the volumes of the two paths (sat_user_unsat_sos_volume_ratio)."))
    return rep


def _energy_note(res: SlocumResults) -> str:
    rows = {r["controller"]: r for r in res.comparison.rows if not r.get("error")}
    if not {"lqr", "lqg"} <= set(rows):
        return ""
    e1, e2 = rows["lqr"]["energy_per_cycle"], rows["lqg"]["energy_per_cycle"]
    return (f"\n\nPump energy: 'lqg' spends {e2 / e1:.1f} times the energy of 'lqr' per cycle ({e2:.0f} against "
            f"{e1:.0f} J). Its pump follows the estimate of the unmeasured pump mass and speeds, which the sensor "
            "noise keeps moving (see its mission figure): every small pumping-out stroke at depth is paid. A "
            "smaller allowed pump rate in the LQR weights (max_deviation['w4']) or a slower estimator trades "
            "regulation for energy; the design keeps the default Bryson weights of both.")


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The Slocum dive-cycle study with the ``QUICK`` or ``FULL`` settings."""
    return report(compute(QUICK if quick else FULL, progress))


if __name__ == "__main__":
    run_script(__file__)
