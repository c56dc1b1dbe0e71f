"""A flight model calibrated to a real glider's dive record: the deep Slocum 'ammonite', 608 m, 2008.

The record ships in the ``dbdreader`` wheel (``gc.example_record_path()``: 107 minutes, pitch, pumped oil volume,
pressure). glidectl reads it (``gc.read_dive_record``), fits three lift and drag laws to its vertical speed
(``gc.fit_flight_model``: hull volume and the law's parasitic drag, as the field calibrates): the thesis's
quadratic law, the Seaglider basestation's ``hd_a, hd_b, hd_c`` law and gliderflight's steady-state law, each with
standard errors, in-sample and blocked cross-validated RMS. gliderflight's own ``SteadyStateCalibrate`` fits the
same two coefficients on the same samples from the same start, in the same run, as the reference. The fitted
vehicle then gets its glide envelope and flies three dive cycles.

The glider: the ``slocum_shallow`` preset's dynamics with the deep Slocum's mass (70 kg, gliderflight's documented
value for this class; displaced mass 70 kg and hull mass 61 kg to match) and gliderflight's hull compressibility
5e-10 1/Pa. No publication prints these fits: the report is a results table, with gliderflight's numbers beside
ours.

Run ``glidectl report slocum_flight_fit`` or ``python designs/slocum_flight_fit.py [OUTDIR] [--quick]``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import glidectl as gc
from glidectl.report import Report, run_script

TITLE = "A flight model calibrated to a real Slocum dive record: three laws, gliderflight beside, fitted glider"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 6.0, "full": 8.0}
LAWS = ("thesis", "seaglider", "gliderflight")


@dataclass(frozen=True)
class Settings:
    """Every setting of the design."""

    record: str = "ammonite-2008-028-01-000.mbd"
    mass: float = 70.0  # kg, in air and displaced at neutral: gliderflight's documented Slocum value
    compressibility: float = 5e-10  # 1/Pa, gliderflight's default epsilon
    #: gliderflight's own start and fixed coefficients (its documentation and examples): Vg, Cd0, ah, Cd1
    gliderflight_start: tuple[tuple[str, float], ...] = (("volume", 0.070), ("Cd0", 0.16), ("ah", 3.8),
                                                         ("Cd1", 10.5), ("S", 0.1))
    holdout: int = 5  # blocks of the blocked cross-validation
    polar_pitch_deg: tuple[float, float, int] = (12.0, 45.0, 34)
    envelope_speeds: tuple[float, float, int] = (0.05, 0.8, 61)  # m/s
    envelope_gammas_deg: tuple[float, float, int] = (-60.0, 60.0, 97)
    depths: tuple[float, float] = (5.0, 100.0)  # m, the dive cycles
    cycles: int = 3
    speed: float = 0.35  # m/s
    gamma_deg: float = 25.0
    #: speeds (m/s) at which the thesis law matched to the fitted Seaglider law at 0.25 m/s is compared with it
    mismatch_speeds: tuple[float, ...] = (0.10, 0.25, 0.45)


FULL = Settings()
QUICK = Settings(holdout=3, polar_pitch_deg=(12.0, 45.0, 12), envelope_speeds=(0.05, 0.8, 21),
                 envelope_gammas_deg=(-60.0, 60.0, 31), depths=(5.0, 40.0), cycles=1)


def start_vehicle(s: Settings) -> gc.Vehicle:
    """The slocum_shallow preset as the deep Slocum: 70 kg, compressible hull, thesis law."""
    veh = gc.load_vehicle("slocum_shallow", m=s.mass, m_h=s.mass - 9.0)
    return veh.with_hydrodynamics(mass=s.mass, compressibility=s.compressibility,
                                  source="gliderflight documentation (Slocum: mg = 70 kg, epsilon = 5e-10 1/Pa)")


def gliderflight_start(veh: gc.Vehicle, s: Settings) -> gc.Vehicle:
    """The vehicle with the gliderflight law at gliderflight's own start values."""
    return veh.with_hydrodynamics("gliderflight", source="gliderflight documentation and examples",
                                  **dict(s.gliderflight_start))


def gliderflight_calibration(record: gc.DiveRecord, used: np.ndarray, start: gc.Vehicle) -> dict[str, Any]:
    """gliderflight's ``SteadyStateCalibrate`` of ``Vg`` and ``Cd0`` on the samples ``used`` of ``record``.

    It gets the record's own arrays (pressure in bar, oil volume in cm^3, the measured vertical speed as its
    ``dhdt``), constant density, the start's mass, compressibility, ``ah``, ``Cd1`` and ``S``, and its mask set to
    leave out what ``used`` leaves out, so both fits see the same samples and the same target. Returns the fitted
    values, the RMS of its model's vertical speed against the measured one over ``used`` and the calibration's wall
    time; ``{"error": ...}`` when gliderflight is not installed.
    """
    try:
        import gliderflight
    except ImportError:
        return {"error": "gliderflight is not installed (pip install 'glidectl[data]')"}
    p = start.params
    rho = start.density
    gm = gliderflight.SteadyStateCalibrate(rho0=rho)
    gm.define(ah=p["ah"], Cd1=p["Cd1"], S=p["S"], epsilon=p["compressibility"])
    gm.set_input_data(time=record.time, pressure=record.pressure / 1e5, pitch=record.pitch,
                      buoyancy_change=record.buoyancy_volume * 1e6, density=np.full(len(record), rho),
                      dhdt=record.vertical_speed)
    gm.set_mask(~used)  # gliderflight's mask is True where a sample is left out
    gm.define(mg=p["mass"], Vg=p["volume"], Cd0=p["Cd0"])
    t0 = time.perf_counter()
    fitted = gm.calibrate("Vg", "Cd0")
    seconds = time.perf_counter() - t0
    gm.define(Vg=float(fitted["Vg"]), Cd0=float(fitted["Cd0"]))  # the model holds its last evaluation, not the best
    w = gm.solve(gm.input_data).w
    resid = (w - record.vertical_speed)[used]
    return {"volume": float(fitted["Vg"]), "Cd0": float(fitted["Cd0"]), "rms": float(np.sqrt(np.mean(resid**2))),
            "seconds": seconds, "version": getattr(gliderflight, "__version__", "?")}


@dataclass(frozen=True)
class FitResults:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    record: gc.DiveRecord
    start: gc.Vehicle
    uncalibrated_rms: float
    fits: dict[str, gc.FlightFit]
    fit_seconds: dict[str, float]
    reference: dict[str, Any]
    best: str
    envelope: gc.GlideEnvelope
    dive: gc.DiveCycleRun | None
    dive_message: str
    mismatch: tuple[tuple[float, float, float, float], ...]  # (speed, pitch, m0, thesis-law speed) per speed


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> FitResults:
    """Read, fit three laws, run gliderflight, then the fitted glider's envelope and dive cycles."""
    progress("read the record")
    record = gc.read_dive_record(gc.example_record_path(s.record))
    veh = start_vehicle(s)
    used = record.mask()
    before = gc.predict_flight(veh, record, used)
    uncal = float(np.sqrt(np.mean((before.vertical_speed - record.vertical_speed[used]) ** 2)))
    fits, seconds = {}, {}
    for law in LAWS:
        progress(f"fit the {law} law")
        start = gliderflight_start(veh, s) if law == "gliderflight" else veh
        t0 = time.perf_counter()
        fits[law] = gc.fit_flight_model(start, record, law=law, holdout=s.holdout)
        seconds[law] = time.perf_counter() - t0
    progress("gliderflight's calibration")
    reference = gliderflight_calibration(record, used, gliderflight_start(veh, s))
    best = min(LAWS, key=lambda k: fits[k].cv_rms)
    fitted = fits[best].vehicle
    progress("envelope and dive cycles of the fitted glider")
    env = gc.glide_envelope(fitted, np.linspace(*s.envelope_speeds), np.radians(np.linspace(*s.envelope_gammas_deg)))
    try:
        dive = gc.dive_cycle(fitted, "lqr", depths=s.depths, gamma=math.radians(s.gamma_deg), speed=s.speed,
                             cycles=s.cycles)
        msg = dive.summary().splitlines()[0]
    except gc.GlidectlError as exc:
        dive, msg = None, f"{type(exc).__name__}: {exc}"
    return FitResults(s, record, veh, uncal, fits, seconds, reference, best, env, dive, msg, _mismatch(fits, s))


def _mismatch(fits: dict[str, gc.FlightFit], s: Settings) -> tuple[tuple[float, float, float, float], ...]:
    """The fitted Seaglider law's glides at -gamma_deg and each speed, and the speed the thesis law matched to it at
    0.25 m/s (gc.law_start) flies at the same pitch and heaviness: what a quadratic drag law misses."""
    sg = fits["seaglider"].vehicle.with_actuators(m0=None, r_P1=None)
    thesis = gc.law_start(sg, "thesis")
    rows = []
    for V in s.mismatch_speeds:
        g = gc.steady_glide(sg, V, -math.radians(s.gamma_deg), r_p3=sg.r_P3)
        rows.append((V, g.theta, g.m0, float(gc.steady_flight(thesis, g.theta, g.m0).speed)))
    return tuple(rows)


def _polar_axes(res: FitResults) -> Any:
    """Glide polars of the three fitted laws at the record's dive and climb pumped volumes, 100 m deep."""
    import matplotlib.pyplot as plt

    s, rec = res.settings, res.record
    _, ax = plt.subplots(figsize=(7.0, 4.6), layout="constrained")
    pitch = np.radians(np.linspace(*s.polar_pitch_deg))
    dv = (np.min(rec.buoyancy_volume), np.max(rec.buoyancy_volume))
    for k, law in enumerate(LAWS):
        veh = res.fits[law].vehicle
        for sign, vol, ls in ((-1, dv[0], "-"), (1, dv[1], "--")):
            m0 = gc.excess_mass(veh, 100.0, vol)
            fl = gc.steady_flight(veh, sign * pitch, np.full(pitch.shape, float(m0)))
            ok = fl.feasible
            ax.plot(fl.horizontal_speed[ok], np.abs(fl.vertical_speed[ok]), ls, color=f"C{k}",
                    label=f"{law} ({'dive' if sign < 0 else 'climb'}, {vol * 1e6:+.0f} cm$^3$)")
    used = res.fits[res.best].used
    u = np.abs(rec.vertical_speed[used] / np.tan(np.abs(rec.pitch[used])))
    ax.plot(u, np.abs(rec.vertical_speed[used]), ".", color="0.6", ms=2, zorder=0,
            label="record (|w| / tan|pitch|, no angle of attack)")
    ax.set_xlabel("horizontal speed through the water [m/s]")
    ax.set_ylabel("vertical speed magnitude [m/s]")
    ax.set_title(f"Glide polars of the fitted laws, pitch {s.polar_pitch_deg[0]:g}-{s.polar_pitch_deg[1]:g} deg, "
                 "100 m")
    ax.legend(fontsize=7, loc="best")
    return ax


def _numbers(rep: Report, res: FitResults) -> None:
    ref = res.reference
    rep.number("uncalibrated_rms", res.uncalibrated_rms, "m/s", "gc.predict_flight",
               note="slocum_shallow's thesis coefficients with hull volume m / density, before any fit")
    for law in LAWS:
        f = res.fits[law]
        rep.number(f"{law}_rms", f.rms, "m/s", "gc.fit_flight_model",
                   note=f"in-sample, {f.context['n_used']} samples; fitted {', '.join(f.params)}")
        rep.number(f"{law}_cv_rms", f.cv_rms, "m/s", "gc.fit_flight_model",
                   note=f"cross-validation, {len(f.cv_fold_rms)} held-out {f.context['holdout_blocks']}")
        for k, v in f.params.items():
            rep.number(f"{law}_{k}", v, f.vehicle.units.get(k, ""), "gc.fit_flight_model",
                       note=f"standard error {f.stderr[k]:.3g}")
        rep.number(f"{law}_fit_seconds", res.fit_seconds[law], "s", "time.perf_counter",
                   note="fit and cross-validation, this build")
    for V, _, _, v_thesis in res.mismatch:
        rep.number(f"thesis_law_speed_error_at_{V:.2f}", v_thesis / V - 1, "-", "gc.steady_flight",
                   note="thesis law matched to the fitted Seaglider law at 0.25 m/s, flown at the Seaglider glide's "
                        "pitch and heaviness: relative speed error")
    if "error" in ref:
        rep.number("reference_gliderflight_rms", ref["error"], "-", "gliderflight")
        return
    gf = res.fits["gliderflight"]
    rep.number("reference_gliderflight_rms", ref["rms"], "m/s",
               f"gliderflight {ref['version']} SteadyStateCalibrate",
               note="same samples, same start, same fixed coefficients as glidectl's gliderflight-law fit")
    rep.number("reference_gliderflight_volume", ref["volume"], "m^3", "gliderflight SteadyStateCalibrate")
    rep.number("reference_gliderflight_Cd0", ref["Cd0"], "1", "gliderflight SteadyStateCalibrate")
    rep.number("reference_gliderflight_seconds", ref["seconds"], "s", "time.perf_counter")
    rep.number("rms_ratio_glidectl_to_gliderflight", gf.rms / ref["rms"], "-", "ratio",
               note="glidectl's gliderflight-law RMS over gliderflight's own, same samples (<= 1: no worse)")


def report(res: FitResults) -> Report:
    """Tables of fitted coefficients and RMS, figures, the fitted glider's envelope and dive cycles."""
    s = res.settings
    rep = Report(TITLE, vehicle=[res.start, res.fits[res.best].vehicle])
    _numbers(rep, res)
    rows = []
    for law in LAWS:
        f = res.fits[law]
        coeffs = "; ".join(f"{k} = {v:.5g} +- {f.stderr[k]:.2g}" for k, v in f.params.items())
        rows.append([law, coeffs, f"{f.rms:.4f}", f"{f.cv_rms:.4f}", f"{res.fit_seconds[law]:.2f}"])
    ref = res.reference
    if "error" not in ref:
        rows.append([f"gliderflight {ref['version']} (its own fit)",
                     f"Vg = {ref['volume']:.5g}; Cd0 = {ref['Cd0']:.5g}", f"{ref['rms']:.4f}", "-",
                     f"{ref['seconds']:.2f}"])
    rep.table(f"Fits to {s.record} ({res.fits['thesis'].context['n_used']} samples of {len(res.record)}; "
              f"uncalibrated RMS {res.uncalibrated_rms:.4f} m/s)",
              ["law", "fitted coefficients +- standard error", "RMS [m/s]", "CV RMS [m/s]", "time [s]"], rows)
    rep.table(f"What a quadratic drag law misses: the fitted Seaglider law's glides at -{s.gamma_deg:g} deg, and the "
              "thesis law matched to it at 0.25 m/s flown at the same pitch and heaviness",
              ["Seaglider speed [m/s]", "pitch [deg]", "m0 [kg]", "thesis-law speed [m/s]", "error"],
              [[f"{V:.2f}", f"{math.degrees(th):.2f}", f"{m0:.4f}", f"{vt:.3f}", f"{100 * (vt / V - 1):+.1f} %"]
               for V, th, m0, vt in res.mismatch])
    rep.figure("dive_record", res.record.plot()[0].figure,
               "The record: depth, pitch and pumped oil volume; green samples are those the fits use (surface, "
               "20 m about the inflection and pitch under 10 deg left out).")
    for law in LAWS:
        rep.figure(f"fit_{law}", res.fits[law].plot()[0].figure,
                   f"{law} law: measured (-dz/dt, central differences) against modelled vertical speed over the "
                   "record, and the residual against depth.")
    rep.figure("glide_polars", _polar_axes(res).figure,
               "Steady glide polars of the three fitted laws at the record's dive and climb oil volumes, with the "
               "record's samples (horizontal speed estimated without angle of attack).")
    fig = res.envelope.plot().figure
    rep.figure("fitted_envelope", fig, f"Glide envelope of the glider with the fitted {res.best} law (lowest "
               "cross-validated RMS), slocum_shallow's actuators.")
    if res.dive is not None:
        rep.figure("fitted_dive_cycles", res.dive.plot()[0].figure,
                   f"{s.cycles} LQR dive cycles of the fitted glider, {s.depths[0]:g}-{s.depths[1]:g} m.")
    rep.text("What is fitted and how",
             "Each sample's steady glide balances weight, lift and drag at the recorded pitch and the net "
             "heaviness mass - rho (volume (1 - epsilon p) + pumped volume) (gc.excess_mass, gc.steady_flight); "
             "scipy's least_squares fits the hull volume and the parasitic drag (K_D0, hd_b, Cd0) to the measured "
             "vertical speed. The thesis and Seaglider laws start from slocum_shallow's thesis coefficients "
             f"({res.fits['seaglider'].start.sources['hd_a']}); the gliderflight law starts from "
             "gliderflight's own documented values, as its SteadyStateCalibrate does. gliderflight interpolates the "
             "angle of attack from a 100-point table and minimises with Nelder-Mead (stopping at an absolute "
             "tolerance of 1e-4 on the mean square); glidectl solves each sample's balance to rounding. "
             f"Dive cycles: {res.dive_message}")
    return rep


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The flight-model fit study with the ``QUICK`` or ``FULL`` settings."""
    return report(compute(QUICK if quick else FULL, progress))


if __name__ == "__main__":
    run_script(__file__)
