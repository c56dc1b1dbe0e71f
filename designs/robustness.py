"""Robust to what we do not know: slocum_shallow with +-30 % on its hydrodynamic and damping coefficients.

Hydrodynamic coefficients are known to 10-30 % at best: the added masses, the moment and damping coefficients of a
new glider are scaled from another vehicle. This design gives slocum_shallow an ``[uncertainty]`` table of +-30 %
intervals on its lift, drag, pitching-moment and pitch-damping coefficients and its added masses and inertia
(``veh.with_uncertainty``), keeps the controllers designed on the nominal vehicle, and asks:

* how likely each dive-cycle controller (LQR; pole placement at the LQR's poles made 1.5 times faster; the
  Slocum-style pitch behaviour out of its deadband, ``GliderBehaviours.pitch_loop``) keeps the glide stable: the
  probability over 1,000 sampled vehicles, the worst case in the box (corners, worst samples, a bounded local
  search) and the margin (how far the box can grow before an unstable vehicle is found), with the dominant pole's
  sensitivity to each coefficient (``gc.robust_stability``);
* what three dive cycles between 5 and 100 m cost with the coefficients we do not know: energy per km, cycle time,
  saturated time and overshoot over 1,000 sampled vehicles flown by the nominal LQR design, flown together
  (``gc.dive_cycle_ensemble``);
* how far from its glide the LQR loop (with its actuators' range and rate limits) is certain to recover on every
  vehicle of the box of the three most influential coefficients: one ellipsoid shape about each vehicle's own
  equilibrium (``gc.certify_roa_robust``), against the nominal vehicle's certificate (``gc.certify_roa``), checked
  by simulations from the members' boundaries at the corners and at sampled vehicles.

The samples are drawn before anything runs, so the numbers are those of the seed whatever the executor. No
publication prints these numbers: the report is a results table.

Run ``glidectl report robustness`` or ``python designs/robustness.py [OUTDIR] [--quick]``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import glidectl as gc
from glidectl.report import Report, map_parts, run_script

TITLE = "Robust to what we do not know: slocum_shallow with +-30 % on its hydrodynamic and damping coefficients"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 30.0, "full": 75.0}
#: the uncertain coefficients: lift, parasitic and induced drag, pitching moment, pitch damping, added masses, inertia
COEFFICIENTS = ("K_L", "K_D0", "K_D", "K_M", "K_Omega1_2", "m_f1", "m_f3", "J2")


@dataclass(frozen=True)
class Settings:
    """Every setting of the design."""

    relative: float = 0.3                   # half-width of every interval, relative to the nominal value
    speed: float = 0.35                     # m/s, the dive legs (designs/slocum_dive_cycle.py)
    gamma_deg: float = 25.0                 # deg
    n_stability: int = 1000                 # sampled vehicles of each robust-stability study
    n_missions: int = 1000                  # sampled vehicles flying the dive cycles (together: batched)
    cycles: int = 3
    depths: tuple[float, float] = (5.0, 100.0)
    seed: int = 0
    place_speedup: float = 1.5              # pole placement at the LQR's closed-loop poles times this
    certificate_keys: tuple[str, ...] = ("K_L", "K_D0", "K_M")   # the robust certificate's box (8 corners)
    certificate_samples: int = 16           # interior points of its interpolation residual and checks
    certificate_search: tuple[tuple[str, int], ...] = ()          # shorter searches for the quick build
    verify_vehicles: int = 20               # vehicles of the box whose members are simulated again


FULL = Settings()
QUICK = Settings(n_stability=100, n_missions=8, cycles=1, depths=(5.0, 40.0), certificate_samples=4,
                 certificate_search=(("rounds", 2), ("n_radii", 4), ("refine", 2), ("n_hessian", 128)),
                 verify_vehicles=4)


def uncertain_vehicle(s: Settings) -> gc.Vehicle:
    """slocum_shallow with a +-``relative`` interval on each of :data:`COEFFICIENTS`."""
    veh = gc.load_vehicle("slocum_shallow")
    src = f"+-{100 * s.relative:g} %: coefficients scaled from another vehicle (design assumption)"
    return veh.with_uncertainty({k: {"rel": s.relative, "source": src} for k in COEFFICIENTS})


@dataclass(frozen=True)
class Results:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    vehicle: gc.Vehicle
    stability: dict[str, gc.RobustStability]
    missions: gc.MonteCarlo
    nominal_mission: dict[str, float]
    nominal_certificate: gc.Certificate
    robust_certificate: gc.RobustEllipsoidCertificate
    robust_check: gc.RobustVerification
    seconds: dict[str, float]


def _controllers(s: Settings) -> tuple[gc.Vehicle, dict[str, object]]:
    """The uncertain vehicle and the three loops designed on its nominal coefficients."""
    veh = uncertain_vehicle(s)
    glide = gc.steady_glide(veh, s.speed, -math.radians(s.gamma_deg), r_p3=veh.actuators["r_P3"].fixed)
    lqr = gc.lqr_glide(veh, glide, inputs="acceleration")
    place = gc.place_glide(veh, glide, s.place_speedup * lqr.closed_loop_poles, inputs="acceleration")
    return veh, {"lqr": lqr, "place": place, "behaviours": gc.GliderBehaviours().pitch_loop(veh, glide)}


def _part(task: tuple[str, Settings]) -> tuple[object, dict[str, float]]:
    """One independent part of :func:`compute` (module level: ``map_parts`` runs it on the build's workers): a
    robust-stability study (``"lqr"``, ``"place"``, ``"behaviours"``), the missions or the certificates."""
    what, s = task
    veh, loops = _controllers(s)
    seconds: dict[str, float] = {}
    t0 = time.perf_counter()
    if what in loops:
        out: object = gc.robust_stability(loops[what], n=s.n_stability, seed=s.seed)
        seconds[f"stability_{what}"] = time.perf_counter() - t0
    elif what == "missions":
        out = gc.dive_cycle_ensemble(veh, n=s.n_missions, seed=s.seed, cycles=s.cycles, depths=s.depths,
                                     speed=s.speed, gamma=math.radians(s.gamma_deg))
        seconds["missions"] = time.perf_counter() - t0
    else:
        out = certificates(s, veh, loops["lqr"], seconds)
    return out, seconds


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> Results:
    """Robust stability of the LQR, pole-placement and pitch-behaviour loops, the dive cycles of sampled vehicles and
    the robust against the nominal certificate: independent parts (``map_parts``: side by side under
    ``glidectl report``)."""
    veh, _ = _controllers(s)
    progress(f"robust stability of three loops over {s.n_stability} vehicles, {s.n_missions} vehicles flying "
             f"{s.cycles} dive cycles, the robust and nominal certificates")
    tasks = ["certificates", "missions", "lqr", "place", "behaviours"]              # longest first
    parts = map_parts(_part, [(t, s) for t in tasks])
    seconds = {k: v for _, sec in parts for k, v in sec.items()}
    out = dict(zip(tasks, (p[0] for p in parts), strict=True))
    stability = {k: out[k] for k in ("lqr", "place", "behaviours")}
    nominal = gc.robustness.DiveStudy(veh, "lqr", s.cycles, (("depths", s.depths), ("gamma", math.radians(
        s.gamma_deg)), ("speed", s.speed)))(veh)
    nominal_cert, robust, check = out["certificates"]
    return Results(s, veh, stability, out["missions"], nominal, nominal_cert, robust, check, seconds)


def certificates(s: Settings, veh: gc.Vehicle, lqr: gc.LinearGlideController,
                 seconds: dict[str, float]) -> tuple[gc.Certificate, gc.RobustEllipsoidCertificate,
                                                     gc.RobustVerification]:
    """The nominal certificate of the saturated LQR loop and the robust one over :attr:`Settings.certificate_keys`
    (+-``relative``), with its check by simulation at sampled vehicles."""
    search = dict(s.certificate_search)
    t0 = time.perf_counter()
    nominal = gc.certify_roa_lmi(gc.saturated_loop(gc.closed_loop(lqr)), **search)   # as certify_roa(loop) chooses
    seconds["nominal_certificate"] = time.perf_counter() - t0
    box = veh.with_uncertainty({k: {"rel": s.relative, "source": veh.uncertainty[k].source}
                                for k in s.certificate_keys})
    t0 = time.perf_counter()
    robust = gc.certify_roa_robust(lqr, vehicle=box, n_samples=s.certificate_samples, seed=s.seed, **search)
    seconds["robust_certificate"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    check = robust.verify_by_simulation(s.verify_vehicles, 16, seed=s.seed + 1)
    seconds["robust_check"] = time.perf_counter() - t0
    return nominal, robust, check


def _stability_numbers(rep: Report, key: str, rs: gc.RobustStability, s: Settings) -> list[str]:
    rep.number(f"{key}_probability_stable", rs.probability, "-", f"gc.robust_stability, {rs.max_real.size} sampled "
               "vehicles", note=f"seed {rs.seed}; {int(rs.valid.sum())} valid vehicles")
    rep.number(f"{key}_nominal_max_real", rs.nominal_max_real, "1/s", "largest closed-loop real part, nominal")
    wc = rs.worst_case
    rep.number(f"{key}_worst_max_real", wc.max_real, "1/s", "worst case in the box (corners, worst samples, Powell)",
               note=", ".join(f"{k} = {v:.4g}" for k, v in wc.coefficients.items())
               + f"; {wc.evaluations} loops solved; dominant pole {wc.pole:.4g}")
    rep.number(f"{key}_margin", rs.margin, "-", "largest box scaling with no unstable vehicle found (bisection)",
               note=("an unstable vehicle is found beyond it" if rs.margin_bounded else
                     f"none found up to {rs.margin:g} times the box"))
    top = sorted(rs.sensitivities.items(), key=lambda kv: -abs(kv[1].real))
    for k, v in top:
        rep.number(f"{key}_sensitivity_{k}", v.real, "1/s", "dominant pole real part per half-range of the "
                   "coefficient (central differences)")
    for stage, t in rs.times.items():
        rep.number(f"{key}_time_{stage.replace(' ', '_')}_s", t, "s", "gc.robust_stability")
    return [key, f"{rs.probability:.1%}", f"{rs.nominal_max_real:.4f}", f"{wc.max_real:.4f}",
            ("" if rs.margin_bounded else ">= ") + f"{rs.margin:.3g}", top[0][0], f"{rs.times['total']:.1f}"]


def report(res: Results) -> Report:
    """Tables, ledger rows and figures."""
    s = res.settings
    rep = Report(TITLE, vehicle=[res.vehicle])
    rows = [_stability_numbers(rep, key, rs, s) for key, rs in res.stability.items()]
    rep.table(f"Closed-loop stability over {s.n_stability} sampled vehicles, controllers designed on the nominal "
              "vehicle", ["controller", "stable", "nominal max Re [1/s]", "worst max Re [1/s]", "margin [box]",
                          "most sensitive", "time [s]"], rows)
    mc = res.missions
    mrows = []
    for name, unit in gc.robustness.DIVE_METRICS.items():
        lo, med, hi = mc.quantiles(name)
        nom = res.nominal_mission[name]
        rep.number(f"missions_{name}_median", med, unit, f"gc.dive_cycle_ensemble, {int(mc.ok.sum())} of {mc.n}",
                   note=f"5-95 %: [{lo:.5g}, {hi:.5g}]; nominal vehicle {nom:.5g}")
        rep.number(f"missions_{name}_p95", hi, unit, "95th percentile over the sampled vehicles")
        infl = mc.influence(name)
        key = next(iter(infl))
        mrows.append([name, unit, f"{nom:.4g}", f"{med:.4g}", f"[{lo:.4g}, {hi:.4g}]", f"{key} ({infl[key]:+.2f})"])
    rep.number("missions_failed", mc.n - int(mc.ok.sum()), "-", "samples whose mission failed",
               note="; ".join(f"{c} x {why[:120]}" for why, c in mc.failures.items()) or "none")
    rep.number("missions_time_s", res.seconds["missions"], "s", f"{mc.n} missions, {s.cycles} cycles each, flown "
               "together (batched) in one process")
    rep.table(f"{s.cycles} dive cycles ({s.depths[0]:g}-{s.depths[1]:g} m) of {mc.n} sampled vehicles under the "
              "nominal LQR design", ["metric", "unit", "nominal", "median", "5-95 %", "most influential (rank corr.)"],
              mrows)
    for key, rs in res.stability.items():
        rep.figure(f"stability_{key}", rs.plot()[0].figure,
                   f"{key} loop: largest closed-loop real part over {rs.max_real.size} sampled vehicles (stability "
                   "boundary at 0, worst case dashed), the dominant pole's change per half-range of each coefficient, "
                   "and the largest real part against the most sensitive coefficient.")
    rep.figure("missions", mc.plot(["energy_per_km", "cycle_time", "saturated_time"])[0, 0].figure,
               f"Dive cycles of {mc.n} sampled vehicles under the nominal LQR design: energy per km of horizontal "
               "distance, cycle time and saturated time, with their most influential coefficient.")
    _certificate_report(rep, res)
    rep.text("What is computed and what is not yet",
             "Each sampled vehicle keeps the controller designed on the nominal one (gain and set point); its "
             "closed-loop equilibrium moves and is found by Newton's method from the nominal one (gc.loop_poles), "
             "and the loop is stable when every pole there has a negative real part. The worst case is a search, "
             "not a proof: the margin is an upper bound of the true one. The behaviours row is the pitch behaviour "
             "out of its deadband (battery rate proportional to the pitch error, time constant 20 s, the pump held "
             "at the glide's setting): inside the deadband the battery holds and the glider flies open loop, so "
             "the row says whether the behaviour's correction converges once it acts. The heading behaviour is "
             "lateral and is not in this longitudinal study.\n\n"
             "The robust certificate is one ellipsoid shape about each vehicle's own equilibrium (the controller "
             "keeps its set point, so the equilibrium moves): LMIs at the 8 corners of the box with common "
             "multipliers, the sampled residual of the interpolation of the linearization between the corners as "
             "a remainder term. It is sampled-sound, not a proof, as the nominal LMI certificate; both are "
             "checked by sampled dV/dt and by simulations from their boundaries.")
    return rep


def _certificate_report(rep: Report, res: Results) -> None:
    """The robust against the nominal certificate: extents per state axis, ratio, checks and the slices."""
    s, nom, rob, chk = res.settings, res.nominal_certificate, res.robust_certificate, res.robust_check
    en, er = nom.extent(), rob.extent()
    ratio = rob.extent_ratio(nom)
    rows = []
    for k, name in enumerate(er.names):
        if not math.isfinite(ratio[k]):
            continue                                            # a held state
        unit = gc.STATE_UNITS.get(name, "")
        scale, unit = (math.degrees(1.0), unit.replace("rad", "deg")) if unit.startswith("rad") else (1.0, unit)
        rows.append([name, unit, f"{scale * en.above[k]:.4g}", f"{scale * er.above[k]:.4g}", f"{ratio[k]:.3f}"])
        rep.number(f"robust_extent_ratio_{name}", float(ratio[k]), "-", "gc.certify_roa_robust half-width over "
                   "gc.certify_roa_lmi's (nominal vehicle)")
    box = ", ".join(f"{k} in [{a:.4g}, {b:.4g}]" for k, a, b in zip(rob.keys, *rob.coefficient_box, strict=True))
    rep.number("robust_extent_ratio_min", float(min(r for r in ratio if math.isfinite(r))), "-",
               "smallest robust / nominal half-width over the states", note=box)
    rep.number("robust_certificate_time_s", res.seconds["robust_certificate"], "s", "gc.certify_roa_robust",
               note=f"nominal certificate {res.seconds['nominal_certificate']:.1f} s")
    rep.number("robust_certificate_certified", bool(rob.certified), "-", "every check at every member passed",
               note=rob.verification.summary())
    rep.number("robust_check_converged", chk.n_converged, "-", f"of {chk.n_simulated} simulations from the members' "
               f"boundaries at {len(chk.kinds)} vehicles of the box (corners and drawn)", note=chk.summary())
    rep.table(f"Recovery certified about the glide, per state axis (half-width of the ellipsoid): nominal vehicle "
              f"against every vehicle of the box of {', '.join(rob.keys)} (+-{100 * s.relative:g} %), LQR loop with "
              "its actuators' range and rate limits", ["state", "unit", "nominal", "robust", "robust / nominal"], rows)
    ax = rob.plot(dims=("theta", "Omega2"))
    rep.figure("robust_certificate", ax.figure,
               f"Slices of the robust certificate in pitch and pitch rate: the member about the nominal equilibrium "
               f"and members about corner vehicles' equilibria (one ellipsoid shape for every vehicle with "
               f"{', '.join(rob.keys)} in the box); the equilibrium itself moves with the coefficients.")


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The robustness study with the ``QUICK`` or ``FULL`` settings."""
    return report(compute(QUICK if quick else FULL, progress))


if __name__ == "__main__":
    run_script(__file__)

