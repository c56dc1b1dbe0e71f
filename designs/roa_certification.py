"""Region-of-attraction certification by SOS programs (``gc.certify_roa``): Van der Pol against Drake's
``RegionOfAttraction``, the reduced 2-state glider against the thesis's Phi < 2/3 set of (5.35), the full 4-state
glider (K_M = -50, -100) and the chapter-6 torque closed loop against L* of (5.85), the chapter-7 CTOL closed loop
against Theorem 5, and all of them against the true regions from batch simulation.

Run ``glidectl report roa_certification`` or ``python designs/roa_certification.py [OUTDIR] [--quick]``;
writes ``OUTDIR/roa_certification/`` (default ``reports/``) with report.pdf, the figures and numbers.json.
The FULL build takes about 6 minutes on 2 cores beside the other designs (2026-12-04); the CTOL closed-loop
certificate takes about 40 s of it (``Settings(ctol=False)`` skips it), the saturated user glider's SOS path about
2 minutes.

Saturated loops (issue 17, ``Settings(saturated=False)`` skips them): the user glider's LQR dive-cycle loop
(slocum_shallow, unsaturated and saturated at the pump rate) and the chapter-6 buoyancy and elevator loops by the LMI
path (``gc.certify_roa_lmi``), the SOS path with the saturation graph (``gc.certify_roa`` of a SaturatedLoop,
method ``"sos-sector"``) on a polynomial saturated loop. Measured: about 440 s at load average 26-28 on the 2 shared
cores (2026-12-01); the single certificates took 12-14 s (chapter 6) and 48 s (user glider, 6 rounds) at load 1.9,
so the user glider runs 2 rounds of the remainder-box search (``sat_user_rounds``).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.stats import qmc

import glidectl as gc
from glidectl.report import BHATTA_2006, Report, cached, map_parts, new_figure, run_script

TITLE = "Region-of-attraction certification by SOS programs: Van der Pol and the chapter-5 glider"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 72.0, "full": 540.0}      # FULL: 516-534 s alone on an idle machine (2026-12-03)

# Published references (printed values)
DRAKE_RHO = 2.3045          # Drake 1.51 RegionOfAttraction on the time-reversed Van der Pol (issue 7)
VDP_TRUE_AREA = 13.72       # area inside the Van der Pol limit cycle, reference value from issue 7


@dataclass(frozen=True)
class Settings:
    """Every setting of the study (FULL = today's values)."""

    backoff: float = 0.003                  # certify_roa: certificate stated at (1 - backoff) rho*
    vdp_degree: int = 6                     # Van der Pol certificate: final degree and alternation iterations
    vdp_iterations: int = 6
    reduced_degree: int = 4                 # reduced 2-state glider
    reduced_iterations: int = 4
    full_degree: int = 2                    # full 4-state glider and the chapter-6 torque closed loop
    full_iterations: int = 8
    full_KM: tuple[float, ...] = (-50.0, -100.0)   # K_M of the full-model cases (kg/rad)
    n_volume: int = 2**16                   # quasi-MC points for areas and volumes
    n_truth_2d: int = 201                   # grid per axis for the simulated true region (2-state models)
    n_truth_4d: int = 4096                  # Sobol points for the simulated true region (4-state models)
    n_guide: int = 2048                     # simulated box points that steer the V step (certify_roa's n_truth)
    horizon_2d: float = 60.0                # simulation horizon of the 2-state truth (t_n)
    horizon_4d: float = 40.0                # simulation horizon of the 4-state truths (t_n; CTOL: s)
    converged_tol: float = 1e-3             # |x| at the horizon that counts as converged
    seed_volume: int = 0                    # Sobol seed of the L*/Phi volume samples
    seed_truth: int = 9                     # Sobol seed of the 4-state truth samples
    torque_speed: float | None = 1.5        # m/s: chapter-6 torque design certified as a closed loop (None: skip)
    torque_Vbar: tuple[float, float] = (-0.4, 0.4)       # design_torque_control box
    torque_alphabar: tuple[float, float] = (-0.2, 0.2)
    ctol: bool = True                       # the chapter-7 CTOL closed loop (~40 s)
    ctol_degree: int = 2
    ctol_iterations: int = 4                # 0.84 % of the true volume in 51 s, against 0.18 % in 24 s with 1
    ctol_k3: float = 10.0
    ctol_k4: float = 5.0
    ctol_speed_factor: float = 0.85         # level glide at speed ctol_speed_factor / sqrt(a_L)
    taylor_order: int = 3                   # Taylor trap: degree of the Taylor model
    n_trap: int = 200_000                   # Taylor trap: uniform samples
    seed_trap: int = 0
    # saturated loops (issue 17, part 7): LMI path (gc.certify_roa_lmi) on the user glider and the chapter-6 loops
    saturated: bool = True
    sat_rounds: int = 6                     # certify_roa_lmi: rounds, grid and refinements of the remainder box
    sat_n_radii: int = 8
    sat_refine: int = 5
    sat_user_rounds: int = 2                # the 8-free-state user glider (6 rounds: ~50 s at load 2, ~10 % larger)
    sat_n_verify: int = 4000                # certify_roa_lmi's a-posteriori samples and simulations
    sat_n_simulate: int = 32
    sat_n_truth: int = 256                  # Sobol box points simulated for the true converging fraction
    sat_slice_n: int = 25                   # grid per axis of the simulated converging slice under each ellipsoid
    slice_n_4d: int = 41                    # the same under the 4-state certificates' slices (chapter 5, CTOL)
    sat_sos_degree: int = 2                 # the SOS path with the saturation graph on the polynomial example
    # the SOS path on the glider loops (gc.certify_roa: surrogate with its cubic remainder bound, the saturation
    # graph for the saturated ones, the remainder-box search), against the LMI path's ellipsoids
    # (the unsaturated user loop runs with USER_ROA_ARGS instead: the certificate slocum_dive_cycle shares)
    sat_sos_cases: tuple[str, ...] = ("user_unsat", "user_sat", "buoyancy", "elevator")
    sat_sos_iterations: int = 4


FULL = Settings()
# the cheap values of the old report test (low degrees, few samples, one full-model case, no CTOL)
QUICK = Settings(vdp_degree=4, vdp_iterations=2, reduced_degree=4, reduced_iterations=1, full_degree=2,
                 full_iterations=1, full_KM=(-100.0,), n_volume=2**12, n_truth_2d=21, n_truth_4d=64, n_guide=256,
                 ctol=False)
QUICK = dataclasses.replace(QUICK, sat_rounds=2, sat_n_radii=4, sat_refine=1, sat_user_rounds=1, sat_n_verify=500,
                            sat_n_simulate=4, sat_n_truth=32, sat_sos_cases=("elevator",), sat_sos_iterations=1,
                            sat_slice_n=9, slice_n_4d=9)


@dataclass(frozen=True)
class _Problem:
    """One certified problem and its comparisons."""

    name: str
    cert: gc.ROACertificate
    measure: float               # certified area/volume in the box
    true_measure: float          # simulated region of attraction in the box
    reference: float             # thesis estimate (or Drake) in the box
    reference_name: str
    box_measure: float
    extra: dict[str, Any]


@dataclass(frozen=True)
class _Results:
    settings: Settings
    vdp: _Problem
    vdp_rho: float
    vdp_rho_time: float
    drake: dict[str, float] | None
    cycle: np.ndarray
    reduced: _Problem
    reduced_sp: gc.SingularPerturbation
    reduced_truth: tuple[np.ndarray, np.ndarray, np.ndarray]
    trap: dict[str, Any]
    full: dict[str, _Problem]
    full_composite: dict[str, gc.CompositeCertificate]
    ctol: dict[str, Any] | None
    sat: dict[str, Any] | None


def _converged(s: Settings, rhs: Any, X: np.ndarray, horizon: float) -> np.ndarray:
    """Simulated region of attraction of the origin (batch integrator), one flag per row of ``X``."""
    res = gc.integrate_batch(rhs, X, horizon, rtol=1e-6, atol=1e-9, max_steps=50_000, bound=1e3)
    return res.converged_to(np.zeros(X.shape[1]), s.converged_tol)


def _compute(s: Settings, progress: Callable[[str], None]) -> _Results:
    """Run every certification and comparison of the study: independent parts, on the build's workers
    (``glidectl report --jobs N``; serially otherwise), the longest first."""
    tasks: list[tuple[Settings, str, Any]] = []
    if s.saturated:             # the saturated user glider's SOS path is the longest part (~5 min on one core)
        tasks.append((s, "sat", "user_sat"))
    if s.ctol:
        tasks.append((s, "ctol", None))
    tasks += [(s, "full", KM) for KM in s.full_KM]
    if s.torque_speed is not None:
        tasks.append((s, "torque", s.torque_speed))
    if s.saturated:
        tasks += [(s, "sat", "buoyancy"), (s, "sat", "elevator")]
    tasks += [(s, "reduced", None), (s, "vdp", None)]
    if s.saturated:
        # the unsaturated user glider last: its SOS certificate is the one slocum_dive_cycle computes (the same
        # cache key), which a full build has usually finished by then, so this part reads it instead of waiting
        tasks += [(s, "sat", "poly"), (s, "sat", "user_unsat")]
    progress(f"{len(tasks)} independent parts: Van der Pol (degree {s.vdp_degree}, Drake's fixed-V level), the "
             f"reduced glider (degree {s.reduced_degree}, Phi < 2/3, Taylor trap), the full glider for K_M in "
             f"{s.full_KM} (degree {s.full_degree}, L*)"
             + (f", the chapter-6 torque loop at {s.torque_speed} m/s" if s.torque_speed is not None else "")
             + (f", the CTOL closed loop (degree {s.ctol_degree}, Theorem 5)" if s.ctol else "")
             + (", the saturated loops (user glider, chapter-6 loops, the SOS sector path)" if s.saturated else ""))
    out = dict(zip([(k, a) for _, k, a in tasks], map_parts(_part, tasks), strict=True))
    vprob, lvl_rho, t_lvl, drake, cycle = out[("vdp", None)]
    rprob, sp, truth2d, trap = out[("reduced", None)]
    full: dict[str, _Problem] = {}
    comp: dict[str, gc.CompositeCertificate] = {}
    for kind, arg in out:
        if kind in ("full", "torque"):
            key, prob, cl = out[(kind, arg)]
            full[key], comp[key] = prob, cl
    sat = _saturated([v for (k, _), v in out.items() if k == "sat"]) if s.saturated else None
    return _Results(s, vprob, lvl_rho, t_lvl, drake, cycle, rprob, sp, truth2d, trap, full, comp,
                    out.get(("ctol", None)), sat)


def _part(task: tuple[Settings, str, Any]) -> Any:
    """One independent part of the study (a module-level function: ``map_parts`` runs it in a worker)."""
    s, kind, arg = task
    if kind == "vdp":
        return _vdp(s)
    if kind == "reduced":
        return _reduced(s)
    if kind == "full":
        return _full(s, f"KM{abs(int(arg))}", gc.load_vehicle("sphere_ch5", K_M=arg), f"glider K_M = {arg:g}")
    if kind == "sat":
        return _saturated_part(s, arg)
    if kind == "torque":
        td = gc.design_torque_control(gc.load_vehicle("sphere_ch5"), speed=arg, Vbar=s.torque_Vbar,
                                      alphabar=s.torque_alphabar)
        return _full(s, "ch6_torque", td.closed_loop_vehicle, f"torque law (6.5), V_e = {arg} m/s")
    return _ctol(s, lambda msg: None)


def _vdp(s: Settings) -> tuple[_Problem, float, float, dict[str, float] | None, np.ndarray]:
    """Van der Pol: the fixed-V level (Drake's problem), Drake itself if installed, the certificate."""
    vdp = gc.benchmarks.van_der_pol()
    t0 = time.perf_counter()
    lvl = gc.max_level(vdp, gc.lyapunov_quadratic(vdp))
    t_lvl = time.perf_counter() - t0
    drake = gc.benchmarks.drake_van_der_pol()
    cycle, area = gc.benchmarks.van_der_pol_limit_cycle()
    vc = gc.certify_roa(vdp, degree=s.vdp_degree, iterations=s.vdp_iterations,
                        solver=gc.SolverOptions(backoff=s.backoff), sampling=gc.SamplingOptions(n_truth=s.n_guide))
    drake_area = math.pi * DRAKE_RHO / math.sqrt(np.linalg.det(gc.lyapunov_matrix(vdp)))   # ellipse x'Px <= rho
    lo, hi = vdp.box
    vprob = _Problem("van_der_pol", vc, vc.volume(n=s.n_volume), area, drake_area, "Drake (fixed quadratic V)",
                     float(np.prod(hi - lo)), {})
    return vprob, lvl.rho, t_lvl, drake, cycle


def _reduced(s: Settings) -> tuple[_Problem, gc.SingularPerturbation, tuple[np.ndarray, np.ndarray, np.ndarray],
                                   dict[str, Any]]:
    """The reduced 2-state glider (K_M = -50): certificate, Phi < 2/3, simulated region, Taylor trap."""
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    rm = sp.reduced_model()
    rc = gc.certify_roa(rm, degree=s.reduced_degree, iterations=s.reduced_iterations,
                        solver=gc.SolverOptions(backoff=s.backoff), sampling=gc.SamplingOptions(n_truth=s.n_guide))
    lo, hi = rm.box
    Vg = np.linspace(lo[0], hi[0], s.n_truth_2d)
    Gg = np.linspace(lo[1], hi[1], s.n_truth_2d)
    VV, GG = np.meshgrid(Vg, Gg)
    X = np.stack([VV.ravel(), GG.ravel()], axis=1)
    conv = _converged(s, rm.rhs, X, s.horizon_2d).reshape(VV.shape)
    box = float(np.prod(hi - lo))
    phi_in_box = gc.CompositeCertificate.phi_area((lo, hi), n=s.n_volume, seed=s.seed_volume)
    rprob = _Problem("reduced", rc, rc.volume(n=s.n_volume), box * float(np.mean(conv)),
                     gc.CompositeCertificate.phi_area(), "thesis Phi < 2/3 (5.35)", box,
                     {"phi_area_in_box": phi_in_box})
    return rprob, sp, (VV, GG, conv), _taylor_trap(s, rm)


def _slices(s: Settings, cert: Any, model: Any, planes: tuple[tuple[int, int], ...]) -> list[Any]:
    """The converging part of each slice plane of ``model`` (``gc.convergent_slice`` over the certificate's box,
    judged as :func:`_extents` judges the runs), drawn under the certified set's slices."""
    return [gc.convergent_slice(model, dims=ij, box=cert.box, n=s.slice_n_4d, horizon=s.horizon_4d,
                                within_box=cert.in_box) for ij in planes]


def _extents(cert: Any, loop: Any, horizon: float | None = None) -> dict[str, Any]:
    """The certificate's extent per state axis and the extent from which simulations of the true ``loop`` converge
    (``gc.convergent_extent`` in the loop's default box, the box certify_roa was asked for; staying in it when the
    certified set does)."""
    return {"certified": cert.extent(),
            "convergent": gc.convergent_extent(loop, horizon=horizon, within_box=cert.in_box)}


FULL_PLANES = ((0, 2), (0, 1))     # slices of the 4-state glider: (Vbar, alphabar), (Vbar, gammabar)
CTOL_PLANES = ((0, 1), (2, 3))     # slices of the CTOL loop: (Vbar, gammabar), (alphabar, Omega2bar)


def _draw_converging(ax: Any, sl: Any) -> None:
    """The converging part of a slice (``gc.convergent_slice``) in light grey, under a certified set."""
    if sl.converged.any():
        ax.contourf(sl.x, sl.y, sl.converged.astype(float), levels=[0.5, 1.5], colors=["0.82"])
    ax.fill([], [], color="0.82", label=f"runs converge ({sl.fraction:.0%} of the slice)")


def _full(s: Settings, key: str, veh: gc.Vehicle, label: str) -> tuple[str, _Problem, gc.CompositeCertificate]:
    """The full 4-state model of ``veh``: certificate, the thesis's L* (5.85), simulated region."""
    spk = gc.singular_perturbation(veh)
    fm = spk.full_model()
    cl = gc.composite_lyapunov(veh)
    lo, hi = fm.box
    bvol = float(np.prod(hi - lo))
    lstar = cl.estimate_volume((lo, hi), n=s.n_volume, seed=s.seed_volume)
    fc = gc.certify_roa(fm, degree=s.full_degree, iterations=s.full_iterations,
                        solver=gc.SolverOptions(backoff=s.backoff), sampling=gc.SamplingOptions(n_truth=s.n_guide))
    truth = gc.box_measure(lambda X, rhs=fm.rhs: _converged(s, rhs, X, s.horizon_4d), (lo, hi), n=s.n_truth_4d,
                           seed=s.seed_truth)
    prob = _Problem(label, fc, fc.volume(n=s.n_volume), truth, lstar, "thesis L* (5.85)", bvol,
                    {"mu": spk.mu, "mu_d": cl.mu_d, "thesis_certified": cl.certified, "K_M": veh.K_M,
                     "K_q": veh.K_q, "K_M0": veh.K_M0, "extents": _extents(fc, fm, s.horizon_4d),
                     "slices": _slices(s, fc, fm, FULL_PLANES)})
    return key, prob, cl


def _ctol(s: Settings, progress: Callable[[str], None]) -> dict[str, Any]:
    """The chapter-7 closed loop at the level glide: certificate against Theorem 5's estimate and simulations."""
    veh = gc.load_vehicle("dc8_ctol")
    gl = gc.ctol_glide(veh, speed=s.ctol_speed_factor / math.sqrt(veh.a_L), gamma=0.0)
    cl = gc.ClosedLoopCTOL(veh, gl, s.ctol_k3, s.ctol_k4)
    model = cl.roa_model()
    progress(f"CTOL closed loop (k3, k4) = ({s.ctol_k3:g}, {s.ctol_k4:g}) at the level glide: degree-"
             f"{s.ctol_degree} certificate in 7 lifted variables (slow: ~100 s per SDP), Theorem 5, simulations")
    cert = gc.certify_roa(model, degree=s.ctol_degree, iterations=s.ctol_iterations,
                          solver=gc.SolverOptions(backoff=s.backoff),
                          sampling=gc.SamplingOptions(n_truth=s.n_guide // 2))
    th5 = gc.ctol_lyapunov(veh, gl, s.ctol_k3, s.ctol_k4)
    # {Q <= level} is tiny: its volume is that of the ellipsoid of the Hessian of Q at 0 (level ~ 1e-8)
    H = gc.hessian(th5.Q, np.zeros(4))
    ball4 = math.pi**2 / 2
    th_vol = ball4 * (2 * th5.level) ** 2 / math.sqrt(np.linalg.det(H)) if th5.certified else 0.0
    lo, hi = model.box
    bvol = float(np.prod(hi - lo))
    truth = gc.box_measure(lambda X: _converged(s, model.rhs, X, s.horizon_4d), (lo, hi), n=s.n_truth_4d,
                           seed=s.seed_truth)
    return {"cert": cert, "model": model, "volume": cert.volume(n=s.n_volume), "theorem5_volume": th_vol,
            "r_a": th5.r_a, "ball_volume": ball4 * th5.r_a**4, "true_volume": truth, "box_volume": bvol,
            "theorem5_certified": th5.certified, "extents": _extents(cert, model, s.horizon_4d),
            "slices": _slices(s, cert, model, CTOL_PLANES)}


def _taylor_trap(s: Settings, model: Any) -> dict[str, Any]:
    """Certify the degree-3 Taylor model (what a polynomial-only tool sees) with Drake's fixed-V problem and count
    the certified points where the *true* dV/dt is positive."""
    ps = gc.recast(model)
    tp = gc.taylor_system(ps, s.taylor_order)
    V = gc.lyapunov_quadratic(tp)
    lvl = gc.max_level(tp, V)
    rng = np.random.default_rng(s.seed_trap)
    X = rng.uniform([-1.5, -math.pi], [2.5, math.pi], (s.n_trap, 2))
    inside = X[V(X) <= lvl.rho]          # V is quadratic: its sublevel set is one ellipse
    vd_true = gc.dVdt(V, tp.lift, ps.rhs, inside)
    vd_taylor = gc.dVdt(V, tp.lift, tp.rhs, inside)
    return {"rho": lvl.rho, "V": V, "n_inside": int(inside.shape[0]), "n_true_positive": int(np.sum(vd_true > 0)),
            "n_taylor_positive": int(np.sum(vd_taylor > 0)), "min_Vbar": float(np.min(inside[:, 0])),
            "bad": inside[vd_true > 0]}


def _figures(res: _Results) -> dict[str, tuple[Any, str]]:
    """Figures of the study: ``{stem: (figure, caption)}``."""
    s = res.settings
    out: dict[str, tuple[Any, str]] = {}
    # Van der Pol
    fig, ax = new_figure(width=6.5, height=5.5)
    vc = res.vdp.cert
    x = np.linspace(-3, 3, 301)
    y = np.linspace(-3.5, 3.5, 301)
    XX, YY = np.meshgrid(x, y)
    inside = vc.contains(np.stack([XX.ravel(), YY.ravel()], axis=1)).reshape(XX.shape)
    ax.contourf(XX, YY, inside.astype(float), levels=[0.5, 1.5], colors=["C0"], alpha=0.3)
    ax.contour(XX, YY, inside.astype(float), levels=[0.5], colors="C0")
    V0 = gc.lyapunov_quadratic(res.vdp.cert.system)          # Drake's V = x'Px
    ax.contour(XX, YY, V0(np.stack([XX, YY], -1)), levels=[DRAKE_RHO], colors="C3", linestyles="--")
    ax.plot(res.cycle[:, 0], res.cycle[:, 1], "k", lw=1.5)
    ax.plot([], [], color="C0", label=f"certified, degree {vc.degree} ({res.vdp.measure / res.vdp.true_measure:.1%})")
    ax.plot([], [], "C3--", label=f"Drake, rho = {DRAKE_RHO} ({res.vdp.reference / res.vdp.true_measure:.1%})")
    ax.plot([], [], "k", label=f"limit cycle (true region, area {res.vdp.true_measure:.3f})")
    ax.set(xlabel="x1", ylabel="x2", aspect="equal", title="Time-reversed Van der Pol: region of attraction")
    ax.legend(loc="lower right", fontsize=8)
    out["vdp_roa"] = (fig, "Van der Pol: certified set (shaded), Drake's certified ellipse (dashed) and the true "
                           "region (inside the limit cycle).")
    # reduced glider
    fig, ax = new_figure(width=7.5, height=6.0)
    rc = res.reduced.cert
    VV, GG, conv = res.reduced_truth
    ax.contourf(VV, GG, conv.astype(float), levels=[0.5, 1.5], colors=["0.85"])
    inside = rc.contains(np.stack([VV.ravel(), GG.ravel()], axis=1)).reshape(VV.shape)
    ax.contour(VV, GG, inside.astype(float), levels=[0.5], colors="C0")
    Vp, Gp = np.meshgrid(np.linspace(-1.0, 1.5, 401), np.linspace(-math.pi, math.pi, 401))
    ax.contour(Vp, Gp, gc.CompositeCertificate.Phi(np.stack([Vp, Gp], -1)), levels=[2 / 3], colors="C3",
               linestyles="--")
    ax.axvline(-0.9, color="k", lw=0.8, ls=":")
    TV = res.trap["V"](np.stack([Vp, Gp], -1))
    ax.contour(Vp, Gp, TV, levels=[res.trap["rho"]], colors="C2", linestyles="-.")
    bad = res.trap["bad"]
    ax.plot(bad[:, 0], bad[:, 1], ".", color="C1", ms=2)
    ax.plot([], [], "C2-.", label=f"Drake's problem on the degree-{s.taylor_order} Taylor model")
    ax.plot([], [], ".", color="C1", label="  ... its points where the true dV/dt > 0")
    ax.plot([], [], color="C0", label=f"certified, degree {rc.degree} (area {res.reduced.measure:.2f})")
    ax.plot([], [], "C3--", label=f"thesis Phi < 2/3 (area {res.reduced.reference:.2f})")
    ax.fill([], [], color="0.85", label=f"simulated region in the box ({res.reduced.true_measure:.2f})")
    ax.plot([], [], "k:", label="cut V = 0.1 V_e (1/V cleared)")
    ax.set(xlabel="Vbar", ylabel="gammabar [rad]", title="Reduced glider (5.33), sphere_ch5, K_M = -50",
           xlim=(-1.0, 1.5), ylim=(-math.pi, math.pi))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, fontsize=8)
    out["reduced_roa"] = (fig, "Reduced 2-state glider: certified set against the thesis's Phi < 2/3 and the "
                               "simulated region of attraction (grey) inside the box Vbar in [-0.9, 1.5]; "
                               "gammabar is an angle (the certificate is 2 pi periodic). The Taylor-model certificate "
                               "(dash-dot) contains points (orange) where the true dV/dt is positive.")
    # full glider slices: (Vbar, alphabar) at gammabar = Omegabar2 = 0 and (Vbar, gammabar) at alphabar = Omegabar2 = 0
    fig, axs = new_figure(len(res.full), 2, width=11, height=4.2 * len(res.full), squeeze=False)
    for row, (key, pr) in enumerate(res.full.items()):
        lo, hi = pr.cert.system.box
        for col, ((_, j), name) in enumerate(zip(FULL_PLANES, ("alphabar [rad]", "gammabar [rad]"), strict=True)):
            ax = axs[row, col]
            _draw_converging(ax, pr.extra["slices"][col])
            A, B = np.meshgrid(np.linspace(lo[0], hi[0], 161), np.linspace(lo[j], hi[j], 161))
            Xsl = np.zeros((A.size, 4))
            Xsl[:, 0], Xsl[:, j] = A.ravel(), B.ravel()
            ins = pr.cert.contains(Xsl).reshape(A.shape).astype(float)
            ax.contourf(A, B, ins, levels=[0.5, 1.5], colors=["C0"], alpha=0.35)
            ax.contour(A, B, ins, levels=[0.5], colors="C0")
            Ls = res.full_composite[key].in_estimate(Xsl).reshape(A.shape).astype(float)
            if Ls.any():
                ax.contour(A, B, Ls, levels=[0.5], colors="C3", linestyles="--")
            ax.fill([], [], color="C0", alpha=0.35, label=f"certified, degree {pr.cert.degree} "
                                                           f"(volume {pr.measure / pr.reference:.1f} x L*)")
            ax.plot([], [], "C3--", label="thesis L* (5.85)" + ("" if pr.extra["thesis_certified"] else
                                                                 ", not certified: mu > mu_d"))
            other = "gammabar" if j == 2 else "alphabar"
            ax.set(xlabel="Vbar", ylabel=name, xlim=(lo[0], hi[0]), ylim=(lo[j], hi[j]),
                   title=f"{pr.name}: slice {other} = 0, Omegabar2 = 0")
            ax.title.set_fontsize(9)
            ax.legend(loc="lower left", fontsize=7)
    conv = ", ".join(f"{p.name}: {p.true_measure / p.box_measure:.1%}" for p in res.full.values())
    out["full_roa_slices"] = (fig, "Full 4-state glider and the chapter-6 torque closed loop: slices of the "
                                   "certified set (shaded) and of the thesis's L* (dashed) through the equilibrium "
                                   "over the part of the slice whose runs converge (grey, simulated on a "
                                   f"{s.slice_n_4d} x {s.slice_n_4d} grid), "
                                   f"over the box of the study. Simulations from {s.n_truth_4d} box points that "
                                   f"converge: {conv}.")
    if res.ctol is not None:
        c = res.ctol["cert"]
        lo, hi = res.ctol["model"].box
        fig, axs = new_figure(1, 2, width=11, height=4.6)
        for k, (ax, (i, j)) in enumerate(zip(axs, CTOL_PLANES, strict=True)):
            _draw_converging(ax, res.ctol["slices"][k])
            A, B = np.meshgrid(np.linspace(lo[i], hi[i], 161), np.linspace(lo[j], hi[j], 161))
            Xsl = np.zeros((A.size, 4))
            Xsl[:, i], Xsl[:, j] = A.ravel(), B.ravel()
            ins = c.contains(Xsl).reshape(A.shape).astype(float)
            ax.contourf(A, B, ins, levels=[0.5, 1.5], colors=["C0"], alpha=0.35)
            ax.contour(A, B, ins, levels=[0.5], colors="C0")
            names = c.system.state_names
            rest = [names[k] for k in range(4) if k not in (i, j)]
            ax.set(xlabel=names[i], ylabel=names[j], title=f"slice {rest[0]} = {rest[1]} = 0")
            ax.fill([], [], color="C0", alpha=0.35, label="certified")
            ax.legend(loc="lower left", fontsize=7)
            ax.title.set_fontsize(9)
        fig.suptitle(f"CTOL closed loop, level glide, (k3, k4) = ({s.ctol_k3:g}, {s.ctol_k4:g}): certified set "
                     f"(volume {res.ctol['volume']:.3g}); Theorem 5 certifies ||x|| <= {res.ctol['r_a']:.2g}",
                     fontsize=9)
        out["ctol_roa_slices"] = (fig, "CTOL closed loop (7.16)-(7.20) at the level glide: slices of the certified "
                                       "set (shaded) through the equilibrium (alphabar = thetabar - gammabar), over "
                                       "the part of the slice whose runs converge (grey, simulated on a "
                                       f"{s.slice_n_4d} x {s.slice_n_4d} grid). The "
                                       "Theorem 5 estimate is far too small to draw at this scale.")
    for key, pr in res.full.items():
        e = pr.extra["extents"]
        out[f"{key}_extent"] = (e["certified"].plot(other=e["convergent"]).figure, _extent_caption(pr.name, e))
    if res.ctol is not None:
        e = res.ctol["extents"]
        out["ctol_extent"] = (e["certified"].plot(other=e["convergent"]).figure,
                              _extent_caption("CTOL closed loop", e))
    return out


def _extent_caption(name: str, e: dict[str, Any]) -> str:
    """Caption of a bar chart of certified against convergent extent."""
    below, above = e["certified"].ratio(e["convergent"])
    worst = float(np.nanmin(np.concatenate([below, above])))
    return (f"{name}: certified extent per state axis through the equilibrium (blue; "
            f"{'rigorous' if e['certified'].rigorous else 'not rigorous'}) against the extent from which simulations "
            f"of the true loop converge (grey), as fractions of the box's half-width on each side; the number on a "
            f"bar is the ratio certified / convergent (smallest {worst:.2g}; the goal is 0.5, dotted).")


def _extent_rows(name: str, e: dict[str, Any]) -> list[list[str]]:
    """Rows of the extent table: per state axis, certified and convergent intervals and their ratios."""
    c, v = e["certified"], e["convergent"]
    below, above = c.ratio(v)
    return [[name, c.names[k], f"[{c.lo[k]:.4g}, {c.hi[k]:.4g}]", f"[{v.lo[k]:.4g}, {v.hi[k]:.4g}]",
             f"{below[k]:.3g}", f"{above[k]:.3g}", "yes" if c.rigorous else "no"] for k in range(len(c.names))]


def _extent_number(rep: Report, key: str, name: str, e: dict[str, Any]) -> None:
    """Ledger row: the smallest ratio of certified to convergent extent over the axes and directions."""
    below, above = e["certified"].ratio(e["convergent"])
    rep.number(f"{key}_min_extent_ratio", float(np.nanmin(np.concatenate([below, above]))), "-",
               f"{name}: smallest certified / convergent extent per axis and direction (goal >= 0.5)",
               note=f"{e['convergent'].what}; certificate {'rigorous' if e['certified'].rigorous else 'not rigorous'}")


def _report_extents(rep: Report, res: _Results) -> None:
    """Certified against convergent extent per state axis: ledger rows and one table for every loop."""
    cases = [(key, pr.name, pr.extra["extents"]) for key, pr in res.full.items()]
    if res.ctol is not None:
        cases.append(("ctol", "CTOL closed loop", res.ctol["extents"]))
    if res.sat is not None:
        for key, c in res.sat["cases"].items():
            cases.append((f"sat_{key}", c["label"] + " (LMI)", c["extents"]))
            if "cert" in c.get("sos", {}):
                sos = c["sos"]["cert"]
                conv = c["extents"]["convergent"]       # the same reference when both sets lie in the loop's box
                e = ({"certified": sos.extent(), "convergent": conv} if sos.in_box else _extents(sos, c["loop"]))
                cases.append((f"sat_{key}_sos", c["label"] + f" (SOS, {sos.method})", e))
    rows = []
    for key, name, e in cases:
        _extent_number(rep, key, name, e)
        rows += _extent_rows(name, e)
    rep.table("Certified against convergent extent per state axis through the equilibrium (state units; the ratio "
              "certified / convergent towards lo and towards hi; the goal is 0.5 or more on every axis)",
              ["loop", "state", "certified", "convergent", "ratio lo", "ratio hi", "rigorous"], rows)


def _report(res: _Results) -> Report:
    """The report: ledger, tables, figures, notes."""
    s = res.settings
    rep = Report(TITLE, vehicle=[res.reduced_sp.vehicle], reference=BHATTA_2006)
    v = res.vdp
    rep.number("vdp_fixed_V_rho", res.vdp_rho, "-", "Drake RegionOfAttraction example (issue 7)", published=DRAKE_RHO,
               tolerance=1e-3 / DRAKE_RHO,
               note="Reference is Drake 1.51's published rho (not the thesis). Same problem: V = x'Px, A'P + PA = -I.")
    rep.number("vdp_fixed_V_time_s", res.vdp_rho_time, "s", "one SDP (Clarabel)")
    if res.drake is not None:
        rep.number("vdp_drake_rho_same_run", res.drake["rho"], "-", "pydrake RegionOfAttraction, this run",
                   note=f"median time {res.drake['time'] * 1e3:.1f} ms over 5 calls")
        rep.number("vdp_drake_time_s", res.drake["time"], "s", "pydrake, this run")
    rep.number("vdp_true_area", v.true_measure, "-", "simulated limit cycle (shoelace)", published=VDP_TRUE_AREA,
               tolerance=1e-3, note="Reference value from the issue.")
    rep.number("vdp_certified_area", v.measure, "-", f"degree-{v.cert.degree} certificate, quasi-MC {s.n_volume}")
    rep.number("vdp_fraction_of_true", v.measure / v.true_measure, "-", "target >= 0.95")
    rep.number("vdp_drake_fraction_of_true", v.reference / v.true_measure, "-", f"ellipse x'Px <= {DRAKE_RHO}")
    rep.number("vdp_verified", v.cert.certified, "-", v.cert.verification.summary())
    rep.number("vdp_wall_time_s", v.cert.wall_time, "s", "certify_roa, target < 60 s",
               note=f"SDP solver time {v.cert.solve_time:.2f} s")
    r = res.reduced
    rep.number("reduced_certified_area", r.measure, "-", f"degree-{r.cert.degree} certificate in (Vbar, gammabar)")
    rep.number("reduced_thesis_phi_area", r.reference, "-", "(5.35): {Phi < 2/3}, closed form",
               note=f"{r.extra['phi_area_in_box']:.4f} of it lies in the box Vbar >= -0.9 used here.")
    rep.number("reduced_ratio_to_thesis", r.measure / r.reference, "-", "target >= 1.5")
    rep.number("reduced_true_area_in_box", r.true_measure, "-",
               f"{s.n_truth_2d}^2 simulations, {s.horizon_2d:g} t_n")
    rep.number("reduced_fraction_of_true", r.measure / r.true_measure, "-", "in the box")
    rep.number("reduced_verified", r.cert.certified, "-", r.cert.verification.summary())
    rep.number("reduced_wall_time_s", r.cert.wall_time, "s", "certify_roa")
    rep.number("reduced_recast_residual", r.cert.system.recast_residual, "-", "exact polynomial recasting")
    t = res.trap
    rep.number("taylor_trap_rho", t["rho"], "-",
               f"Drake's fixed-V problem on the degree-{s.taylor_order} Taylor model")
    rep.number("taylor_trap_true_dVdt_positive", t["n_true_positive"], "points",
               f"of {t['n_inside']} sampled points of that certified set (Taylor model: {t['n_taylor_positive']})",
               note=f"The Taylor certificate reaches Vbar = {t['min_Vbar']:.3f} (V <= 0 is not a flight state); "
                    "a certificate of a Taylor model is not a certificate of the glider (issue 7).")
    for key, p in res.full.items():
        k = f"full_{key}"
        rep.number(f"{k}_certified_volume", p.measure, "-", f"degree-{p.cert.degree} certificate in the box")
        rep.number(f"{k}_thesis_Lstar_volume", p.reference, "-", "(5.85) inside the box",
                   note=(f"mu = {p.extra['mu']:.4g}, mu_d = {p.extra['mu_d']:.4g}: the thesis's nu "
                         + ("certifies" if p.extra["thesis_certified"] else "does NOT certify (mu > mu_d)")))
        rep.number(f"{k}_ratio_to_Lstar", p.measure / p.reference if p.reference > 0 else math.inf, "-",
                   "target >= 4 (glider)")
        rep.number(f"{k}_true_volume", p.true_measure, "-", f"{s.n_truth_4d} simulations, {s.horizon_4d:g} t_n")
        rep.number(f"{k}_fraction_of_true", p.measure / p.true_measure, "-", "in the box")
        rep.number(f"{k}_fraction_of_box", p.measure / p.box_measure, "-", "box volume "
                   f"{p.box_measure:.4f}")
        rep.number(f"{k}_verified", p.cert.certified, "-", p.cert.verification.summary())
        rep.number(f"{k}_wall_time_s", p.cert.wall_time, "s", "certify_roa",
                   note=f"SDP solver time {p.cert.solve_time:.1f} s; closed-loop K_M0 = {p.extra['K_M0']:.4g} kg, "
                        f"K_M = {p.extra['K_M']:.4g} kg/rad, K_q = {p.extra['K_q']:.4g} kg s/rad")
    if res.ctol is not None:
        ct = res.ctol
        rep.number("ctol_certified_volume", ct["volume"], "-", f"degree-{ct['cert'].degree} certificate in the box "
                   "|Vbar| <= 0.5, |gammabar| <= 0.5, |alphabar| <= 0.3, |Omega2bar| <= 1",
                   note="Smaller than the 0.0041-0.0045 of the builds before 2026-12-02, on purpose. Those "
                        "certificates left a solver residual of ~4e-8 on the constant monomial of the decrease "
                        "condition: the S-procedure multiplier of the speed cut had tau(0) ~ 4e-8 with linear terms "
                        "~3e-3, which no exact certificate can have (the decrease polynomial has no constant term, "
                        "so tau(0) g(0) = 0 forces tau(0) = 0, and then no linear terms), so they proved dV/dt < 0 "
                        "only outside a small ball around the glide. The multipliers of cuts now start at degree 1 "
                        "(an exact facial reduction) and the lifted angles of the recast follow the chain rule (the "
                        "old joint fit put 1e-3 (alpha - sin alpha) into d(1 - cos gamma)/dt: a linear term of dV/dt "
                        "no certificate can absorb, which the solver also left as residual). The level of the "
                        "starting V is then the exact program's: 0.00144 (Clarabel, qdldl), 0.00120 (Clarabel, "
                        "faer, level capped at 1; CVXOPT on the facially reduced dual agrees), against 0.0025-0.0044 "
                        "before (measured 2026-12-02). The Gram check takes every S-procedure multiplier made "
                        "exactly SOS (its Gram matrix shifted to PSD; in this build by up to "
                        f"{max((c.multiplier_shift for c in ct['cert'].verification.gram), default=0.0):.2g}), gives "
                        "the smallest slack "
                        f"{min((c.slack for c in ct['cert'].verification.gram), default=math.nan):.3g} (exactly SOS "
                        "when positive) and the largest radius "
                        f"{max((c.radius for c in ct['cert'].verification.gram), default=math.nan):.2g} below which "
                        "a residual of degree 0 or 1 could outweigh the Gram matrix (rounding level); every check of "
                        "the certificate "
                        f"{'passed' if ct['cert'].certified else 'did NOT pass'} (Gram, true dV/dt < 0 on the "
                        "samples, simulations from the outermost samples converge).")
        rep.number("ctol_theorem5_volume", ct["theorem5_volume"], "-", "{Q <= level} of Theorem 5 (ellipsoid of "
                   "the Hessian of Q; the level is ~1e-8)",
                   note=f"Theorem 5 certified: {ct['theorem5_certified']}; its ball r_a = {ct['r_a']:.3g} has "
                        f"volume {ct['ball_volume']:.3g}.")
        rep.number("ctol_ratio_to_theorem5", ct["volume"] / ct["theorem5_volume"] if ct["theorem5_volume"] > 0
                   else math.inf, "-", "certified / Theorem 5 estimate")
        rep.number("ctol_true_volume", ct["true_volume"], "-", f"{s.n_truth_4d} simulations, {s.horizon_4d:g} s")
        rep.number("ctol_fraction_of_true", ct["volume"] / ct["true_volume"], "-", "in the box")
        rep.number("ctol_verified", ct["cert"].certified, "-", ct["cert"].verification.summary())
        rep.number("ctol_wall_time_s", ct["cert"].wall_time, "s", "certify_roa (7 lifted variables)",
                   note=f"SDP solver time {ct['cert'].solve_time:.0f} s")
    rows = v.cert.history_table("Van der Pol") + r.cert.history_table("reduced")
    for p in res.full.values():
        rows += p.cert.history_table(p.name)
    if res.ctol is not None:
        rows += res.ctol["cert"].history_table("CTOL")
    rep.table("Alternation history: degree, step, level of the level problem (1 = the V step's level kept), sampled "
              "area/volume in the box, SDP time [s]", list(gc.ROACertificate.HISTORY_HEADER), rows)
    for stem, (fig, cap) in _figures(res).items():
        rep.figure(stem, fig, cap)
    _report_extents(rep, res)
    rep.text("Method", (
        "glidectl.roa: a small polynomial layer (Poly, monomials), SOS programs compiled as sparse coefficient "
        "equalities with PSD Gram matrices in cvxpy (programs with a Gram block of order 40 or more whose moment "
        "form is the smaller side solved by CVXOPT on that form, the others and the centering feasibility "
        "programs by Clarabel; from a Gram block of order 64 the centering is the level program capped at the "
        "lower level, on the moment form), exact "
        "recasting of the glider models "
        "(gammabar -> (sin, 1 - cos) with s^2 + c^2 = 2c, the 1/V factor cleared with the cut V >= 0.1 V_e; the "
        "polynomial is recovered from the model's own right-hand side and checked to 1e-15), the level problem "
        "(Vdot = 0 => V >= rho, linear in rho and the multiplier, one SDP), the V step (multiplier fixed, V free), "
        "and degree raising 2 -> 4 -> 6. The V step minimizes mean(max(V - 1, 0)) over simulated converging points "
        "of the box, so the search is steered towards the true region; the certificate does not depend on the "
        f"simulations. Every certificate is stated at (1 - backoff) rho* (backoff {s.backoff:g}, tripled while the "
        "Gram margins do not cover the residuals; the moment form stops at a singular Schur complement with "
        "residuals near 1e-6, so when no backoff passes there the same steps are taken with Clarabel), re-solved "
        "at that level and verified: exact "
        "SOS from Gram eigenvalue margins against coefficient residuals (with every S-procedure multiplier made "
        "exactly SOS first: its Gram matrix shifted to positive semidefinite; the residual is also spread onto the "
        "Gram entries that reach each monomial and the smallest eigenvalue of that projected matrix checked, "
        "whichever proves more), the local conditions at the "
        "equilibrium, "
        "true dV/dt < 0 at sampled points of the set and convergence of the 256 outermost samples."))
    rep.text("Left alone", (
        "Degree 2 for the 4-state models and the closed loops: a degree-4 V in the 5 lifted variables of the glider "
        "needs a 104 x 104 Gram matrix per constraint and one level SDP takes about 100 s with Clarabel on 2 cores "
        "(measured; 25 s for the V step on the moment form, coefficients matched modulo the angle equality: "
        "bench/bench_roa.py's glider4_staged case certifies it in about 50 s); the CTOL closed loop (7 lifted "
        "variables: alphabar kept and enclosed by Taylor bounds) takes about 110 s per SDP with Clarabel already at "
        "degree 2 (about 6 s on the moment form modulo the angle equalities, its V step about 17 s), and runs one "
        "alternation. An LMI path with "
        "linear-plus-sector "
        "bounds is now built: see 'Saturated loops'. When a V step fails (its SDP, or its new V has no positive "
        "level), it is tried once more with the multiplier centred deeper inside the current set (a row 'V step "
        "failed (...): retried' in the history table); if that fails too, the alternation stops there and keeps the "
        "best V found (a row 'V step failed')."))
    return rep


# --------------------------------------------------------------------------------------------- saturated loops
SAT_CASES = ("user_unsat", "user_sat", "buoyancy", "elevator")
"""The saturated loops of the report, in its order (one part of :func:`_saturated_part` each)."""


USER_SPEED, USER_GAMMA = 0.35, -math.radians(25.0)     # m/s, rad: the down leg of designs/slocum_dive_cycle.py
#: gc.certify_roa's arguments for the user glider's unsaturated loop: those of designs/slocum_dive_cycle.py (its
#: ROA_ARGS and its FULL time limit, none), which certifies the same loop under the same cache key
#: (:func:`_certify_lqr_loop`), so a build computes it once
USER_ROA_ARGS = {"degree": 2, "budget": gc.BudgetOptions(time_limit=None)}


def _user_glider_loop() -> tuple[gc.Vehicle, Any, Any]:
    """The LQR dive-cycle loop of the user glider (designs/slocum_dive_cycle.py, issue 16): slocum_shallow, the
    0.35 m/s, -25 deg leg, gc.lqr_glide with acceleration inputs (w1, w4: the vehicle file fixes r_P3, and the
    design model drops its states and w3).
    Returns the vehicle, the controller and the loop."""
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, USER_SPEED, USER_GAMMA, r_p3=veh.actuators["r_P3"].fixed)
    ctrl = gc.lqr_glide(veh, glide, inputs="acceleration")
    return veh, ctrl, gc.closed_loop(ctrl)


def _certify_lqr_loop(veh: gc.Vehicle, controller: Any, loop: Any) -> gc.ROACertificate:
    """``gc.certify_roa(loop, **USER_ROA_ARGS)`` cached under the key designs/slocum_dive_cycle.py uses for the same
    loop (its ``_certify_lqr_loop``: the vehicle, the gain, the loop's equilibrium, the arguments); in a build, the
    design that asks second waits for the first and reads its certificate."""
    key = ("certify_roa", "lqr_glide loop", veh, np.asarray(controller.K), np.asarray(loop.equilibrium),
           USER_ROA_ARGS)
    return cached(key, lambda: gc.certify_roa(loop, **USER_ROA_ARGS))


def _sat_case(label: str, sl: Any, lmi_kw: dict[str, Any], s: Settings, dims: tuple[str, str]) -> dict[str, Any]:
    """One LMI certificate with its diagnostics: fraction of the box, extents, which constraint binds, how far the
    same V could go (first scale of the ellipsoid with a sampled dV/dt >= 0), the simulated converging fraction."""
    t0 = time.perf_counter()
    cert = gc.certify_roa_lmi(sl, n_verify=s.sat_n_verify, n_simulate=s.sat_n_simulate, **lmi_kw)
    wall = time.perf_counter() - t0
    f = list(sl.free)
    ext = np.sqrt(np.diag(np.linalg.inv(cert.P)))
    half = cert.scale
    # tightness of the remainder bound: scale the certified ellipsoid until the true dV/dt >= 0 somewhere on its
    # boundary (or it leaves the box)
    Xb = cert.sample(4000, seed=1, boundary=True)
    tight: tuple[float, str] = (10.0, "no failure up to 10 (10 is the largest scale tried)")
    for k in (1.1, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0):
        Y = sl.equilibrium + k * (Xb - sl.equilibrium)
        dY = (Y - sl.equilibrium)[:, f]
        vd = 2 * np.einsum("ni,ij,nj->n", dY, cert.P, np.asarray(sl.rhs(Y))[:, f])
        if np.any(vd >= 0) or not np.all((Y >= sl.box[0]) & (Y <= sl.box[1])):
            tight = (k, "sampled dV/dt >= 0" if np.any(vd >= 0) else "leaves the box")
            break
    # simulated fraction of the box (free states) whose trajectories converge
    lo, hi = sl.box
    X = np.tile(sl.equilibrium, (s.sat_n_truth, 1))
    X[:, f] = lo[f] + (hi[f] - lo[f]) * qmc.Sobol(len(f), seed=s.seed_truth).random(s.sat_n_truth)
    res = gc.integrate_batch(sl.rhs, X, cert.verification.horizon, rtol=1e-6, atol=1e-9, max_steps=50_000,
                             bound=1e3 * float(np.max(np.abs(np.concatenate([lo, hi])))))
    conv = res.converged_to(sl.equilibrium, 1e-3 * float(np.linalg.norm(half)))
    return {"label": label, "loop": sl, "cert": cert, "wall": wall, "extent": ext / half, "tight": tight,
            "true_fraction": float(np.mean(conv)), "n_truth": int(X.shape[0]), "dims": dims,
            "names": [sl.state_names[i] for i in f], "extents": _extents(cert, sl),
            "slice": gc.convergent_slice(sl, dims=dims, n=s.sat_slice_n)}


def _sos_case(system: Any, lmi: Any, s: Settings, certify: Callable[[], Any] | None = None) -> dict[str, Any]:
    """The SOS path on one glider loop (a closed loop: surrogate route; a SaturatedLoop: the saturation graph with a
    surrogate of the plant), its volume against the LMI ellipsoid's ``lmi`` (same free states, same box).
    ``certify`` (optional) makes the certificate instead (the user glider's unsaturated loop: the cached one that
    designs/slocum_dive_cycle.py shares). The wall time is the certificate's own (``cert.wall_time``: the whole
    certify_roa call, also when the certificate came from the cache)."""
    t0 = time.perf_counter()
    try:
        sampling = gc.SamplingOptions(n_simulate=s.sat_n_simulate, n_verify=s.sat_n_verify)
        cert = certify() if certify is not None else gc.certify_roa(system, degree=s.sat_sos_degree,
                                                                    iterations=s.sat_sos_iterations, sampling=sampling)
    except gc.GlidectlError as exc:
        return {"error": f"{type(exc).__name__}: {exc}", "wall": time.perf_counter() - t0}
    vol = cert.volume() if cert.certified else 0.0
    return {"cert": cert, "wall": cert.wall_time, "volume": vol, "ratio": vol / lmi.volume(),
            "fraction": vol / lmi.volume() * lmi.volume_fraction}


def _binding(case: dict[str, Any]) -> str:
    """Which constraint limits the certified ellipsoid (from the certificate's own numbers)."""
    c = case["cert"]
    v = c.verification
    ext = np.sqrt(np.diag(np.linalg.inv(c.P)))
    rem = float(np.max(ext / c.remainder_box))
    why = []
    if v.box_max >= 0.98:
        why.append("the loop's box (the ellipsoid touches it)")
    if rem >= 0.95 and np.any(c.remainder_box < 0.999 * c.scale):
        r = c.remainder_box / c.scale
        why.append(f"the remainder bound (the ellipsoid fills its remainder box, {rem:.2f}, which is "
                   f"{np.min(r):.2g} to {np.max(r):.2g} of the box per state)")
    reach = _saturation_reach(c)
    if reach is not None:
        why.append(f"not the saturation: the ellipsoid reaches {reach:.2g} x the saturation level in K x"
                   if reach > 1 else f"saturation is not reached (max |K x| = {reach:.2g} x the level)")
    return "; ".join(why) if why else "the sector region / decrease LMI"


def _saturation_reach(cert: Any) -> float | None:
    """Largest ``|K_i (x - x_e)| / u0_i`` over the certified ellipsoid (saturating channels), None without any."""
    sl = cert.system
    sat = np.flatnonzero(sl.saturating)
    if len(sat) == 0:
        return None
    Kf = sl.K[np.ix_(sat, list(sl.free))]
    u0 = np.minimum(-sl.u_lo[sat], sl.u_hi[sat])
    return float(np.max(np.sqrt(np.einsum("ij,jk,ik->i", Kf, np.linalg.inv(cert.P), Kf)) / u0))


def _saturated_part(s: Settings, which: str) -> tuple[str, Any, float]:
    """One part of the saturated-loop section: one of :data:`SAT_CASES` (``"user_unsat"``, ``"user_sat"``: the user
    glider's LQR dive-cycle loop without and with its pump saturation; ``"buoyancy"``, ``"elevator"``: the
    chapter-6 loops, pump rate saturated), each by the LMI path and, if in ``s.sat_sos_cases``, the SOS path; or
    ``"poly"`` (the SOS path with the saturation graph against the LMI path on a polynomial loop). One part per
    loop, so that the build's workers run them side by side. Returns ``(which, result, wall time)``."""
    kw = dict(rounds=s.sat_rounds, n_radii=s.sat_n_radii, refine=s.sat_refine)
    t0 = time.perf_counter()
    if which in ("user_unsat", "user_sat"):
        veh, ctrl, loop = _user_glider_loop()
        ukw = dict(kw, rounds=s.sat_user_rounds)
        certify = None
        if which == "user_unsat":
            inf = [math.inf] * len(loop.plant.input_names)
            case = _sat_case("user glider LQR, unsaturated", gc.saturated_loop(
                loop, u_min=[-x for x in inf], u_max=inf, actuator_limits=False), ukw, s, ("theta", "m0"))
            system = loop           # the SOS path: the closed loop itself (no saturating channel)
            certify = functools.partial(_certify_lqr_loop, veh, ctrl, loop)
        else:
            case = _sat_case("user glider LQR, saturated (pump rate, pump and battery ranges, battery rate)",
                             gc.saturated_loop(loop), ukw, s, ("theta", "m0"))
            # the SOS path models constant levels only: its certificate is of the loop with the pump rate saturated
            system = gc.saturated_loop(loop, actuator_limits=False)
            case["sos_loop"] = "SOS path: the loop with its pump rate saturated only (constant levels)"
        if which in s.sat_sos_cases:
            case["sos"] = _sos_case(system, case["cert"], s, certify)
        return which, {which: case}, time.perf_counter() - t0
    if which in ("buoyancy", "elevator"):
        if which == "buoyancy":
            sph = gc.load_vehicle("sphere_ch5")
            cl = gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0))
            dims = ("V", "m0")
        else:
            ev = gc.load_vehicle("elevator_ch6")
            cl = gc.closed_loop(gc.ElevatorBuoyancyController(gc.elevator_equilibrium(ev, 1.0, -math.pi / 4), ev,
                                                              1.0))
            dims = ("gamma", "m0")
        sl = gc.saturated_loop(cl)
        case = _sat_case(f"chapter-6 {which} loop, pump rate saturated", sl, kw, s, dims)
        if which in s.sat_sos_cases:      # the SOS path: the saturation graph and a surrogate of the plant
            case["sos"] = _sos_case(sl, case["cert"], s)
        return which, {which: case}, time.perf_counter() - t0
    poly = gc.SaturatedLoop("x1' = x2, x2' = x1 + 0.3 x1^2 + sat(-2 x1 - 2 x2)", ("x1", "x2"), ("u",), _poly_field,
                            np.zeros(2), np.array([[-2.0, -2.0]]), np.array([-1.0]), np.array([1.0]),
                            (-2.0 * np.ones(2), 2.0 * np.ones(2)))
    sos = gc.certify_roa(poly, degree=s.sat_sos_degree, iterations=2,
                         solver=gc.SolverOptions(extra=0, backoff=s.backoff),
                         sampling=gc.SamplingOptions(n_truth=s.n_guide // 8))
    t_sos = time.perf_counter() - t0
    t1 = time.perf_counter()
    lmi = gc.certify_roa_lmi(poly, n_verify=s.sat_n_verify, n_simulate=s.sat_n_simulate, **kw)
    return which, {"loop": poly, "sos": sos, "sos_wall": t_sos, "lmi": lmi, "lmi_wall": time.perf_counter() - t1,
                   "sos_volume": sos.volume(n=s.n_volume), "box_volume": 16.0}, time.perf_counter() - t0


def _poly_field(X: np.ndarray, W: np.ndarray) -> np.ndarray:
    """The polynomial saturated example: ``x1' = x2``, ``x2' = x1 + 0.3 x1^2 + w``."""
    return np.stack([X[..., 1], X[..., 0] + 0.3 * X[..., 0] ** 2], -1) + W @ np.array([[0.0, 1.0]])


def _saturated(parts: list[tuple[str, Any, float]]) -> dict[str, Any]:
    """The saturated-loop section's results from its parts (:func:`_saturated_part`), in the order of
    :data:`SAT_CASES` whatever order the parts ran in."""
    order = {k: i for i, k in enumerate((*SAT_CASES, "poly"))}
    out: dict[str, Any] = {"cases": {}, "timing": {}}
    for which, value, wall in sorted(parts, key=lambda p: order[p[0]]):
        out["timing"][which] = wall
        if which == "poly":
            out["poly"] = value
        else:
            out["cases"].update(value)
    return out


def _report_saturated(rep: Report, s: Settings, sat: dict[str, Any]) -> None:
    """Ledger rows, a table, the figures and the notes of the saturated loops."""
    rows = []
    for key, c in sat["cases"].items():
        cert = c["cert"]
        v = cert.verification
        bind = _binding(c)
        ext = ", ".join(f"{n} {e:.3g}" for n, e in zip(c["names"], c["extent"], strict=True))
        rep.number(f"sat_{key}_fraction_of_box", cert.volume_fraction, "-",
                   f"{c['label']}: certified ellipsoid / box volume (free states), method {cert.method}",
                   note=f"Extent / box half-width per state: {ext}. Limited by: {bind}.")
        rep.number(f"sat_{key}_true_fraction", c["true_fraction"], "-",
                   f"{c['n_truth']} box points simulated (converged within {v.horizon:.0f} {cert.system.time_unit})")
        rep.number(f"sat_{key}_verified", cert.certified, "-", v.summary())
        rep.number(f"sat_{key}_wall_time_s", c["wall"], "s", f"certify_roa_lmi, {len(cert.history)} SDPs",
                   note=f"SDP solver {cert.solve_time:.1f} s, Hessian sampling {cert.hessian_time:.1f} s")
        k, why = c["tight"]
        rep.number(f"sat_{key}_tightness_scale", k, "-", "first scale of the certified ellipsoid with " + why,
                   note="how far the same quadratic V could go at best (sampled): well above 1 means the bounded "
                        "remainder, not V, limits the certificate")
        rows.append([c["label"], cert.method, f"{cert.volume_fraction:.3g}", f"{c['true_fraction']:.3g}",
                     f"{k:g}", "yes" if cert.certified else "NO", f"{c['wall']:.1f}", bind[:90]])
        if "sos" in c:
            o = c["sos"]
            if "error" in o:
                rep.number(f"sat_{key}_sos_certified", False, "-", "gc.certify_roa (SOS path)", note=o["error"][:400])
                rows.append([c["label"], "SOS path", "-", "-", "-", "NO", f"{o['wall']:.1f}", o["error"][:90]])
                continue
            sc = o["cert"]
            rb = sc.system.remainder_bound
            hist = [h for h in sc.history if h.step.startswith("remainder box")]
            rounds = [h.step for h in sc.history if h.step.startswith("remainder-box round")]
            second = ("round 2 not kept" if any("not kept" in r for r in rounds) else
                      "round 2 skipped (same box)" if any("skipped" in r for r in rounds) else
                      "round 2 stopped" if any("stopped" in r for r in rounds) else
                      "round 2 kept" if rounds else "one round")
            rep.number(f"sat_{key}_sos_certified", sc.certified, "-", f"gc.certify_roa, method {sc.method}",
                       note=sc.verification.summary())
            rep.number(f"sat_{key}_sos_volume_ratio", o["ratio"], "-",
                       f"{c['label']}: volume of the SOS certificate / volume of the LMI ellipsoid (free states)",
                       note=(c["sos_loop"] + "; " if "sos_loop" in c else "")
                       + f"SOS volume {o['volume']:.4g}, LMI {cert.volume():.4g}; degree {sc.degree}; "
                            + (rb.summary() if rb is not None else "") + f"; remainder-box search: {len(hist)} "
                            f"level SDPs, {second}, box used {np.round(sc.box[0], 4).tolist()} to "
                            f"{np.round(sc.box[1], 4).tolist()}")
            rep.number(f"sat_{key}_sos_wall_time_s", o["wall"], "s", "gc.certify_roa (SOS path)",
                       note=f"SDP time {sc.solve_time:.1f} s, {len(sc.history)} steps")
            rows.append([c["label"] + (" (pump rate only)" if "sos_loop" in c else ""), sc.method,
                         f"{o['fraction']:.3g}", f"{c['true_fraction']:.3g}", "-",
                         "yes" if sc.certified else "NO", f"{o['wall']:.1f}",
                         f"{o['ratio']:.3g} x the LMI volume"])
    p = sat["poly"]
    rep.number("sat_poly_sos_sector_fraction", p["sos_volume"] / p["box_volume"], "-",
               f"{p['loop'].name}: SOS path with the saturation graph, degree {p['sos'].degree}, method "
               f"{p['sos'].method}", note=p["sos"].verification.summary())
    rep.number("sat_poly_lmi_fraction", p["lmi"].volume_fraction, "-", "the same loop, LMI path (quadratic V, "
               "generalized sector, bounded remainder)", note=p["lmi"].verification.summary())
    rep.number("sat_poly_sos_wall_time_s", p["sos_wall"], "s", "certify_roa (sos-sector)")
    rep.number("sat_poly_lmi_wall_time_s", p["lmi_wall"], "s", "certify_roa_lmi")
    for k, t in sat["timing"].items():
        rep.number(f"sat_section_time_{k}_s", t, "s", "wall time of this part of the saturated-loop section")
    rows.append([p["loop"].name[:40], p["sos"].method, f"{p['sos_volume'] / p['box_volume']:.3g}", "-", "-",
                 "yes" if p["sos"].certified else "NO", f"{p['sos_wall']:.1f}", "polynomial: graph of sat exact"])
    rows.append([p["loop"].name[:40], p["lmi"].method, f"{p['lmi'].volume_fraction:.3g}", "-", "-",
                 "yes" if p["lmi"].certified else "NO", f"{p['lmi_wall']:.1f}", _binding(
                     {"cert": p["lmi"]})[:90]])
    rep.table("Saturated loops: certified fraction of the box, simulated converging fraction, tightness scale of V, "
              "verified, wall time [s], what limits the certificate",
              ["loop", "method", "certified", "simulated", "V scale", "verified", "s", "limited by"], rows)
    for key, c in sat["cases"].items():
        e = c["extents"]
        rep.figure(f"sat_{key}_extent", e["certified"].plot(other=e["convergent"]).figure,
                   _extent_caption(c["label"] + " (LMI path)", e))
        d = c["dims"]
        ax = c["slice"].plot()
        rep.figure(f"sat_{key}", c["cert"].plot(ax=ax, dims=d).figure,
                   f"{c['label']}: slice of the certified ellipsoid in ({d[0]}, {d[1]}) through the equilibrium, "
                   f"within the loop's box, over the part of the slice from which simulations converge without "
                   f"leaving the box (grey, a {len(c['slice'].x)} x {len(c['slice'].y)} grid).")
    fig = p["sos"].plot()
    rep.figure("sat_poly_sos_sector", getattr(fig, "figure", fig),
               f"{p['loop'].name}: certified set of the SOS path with the saturation graph (degree "
               f"{p['sos'].degree}) in the box |x_i| <= 2.")
    rep.text("Saturated loops", (
        "LMI path (gc.certify_roa_lmi on gc.saturated_loop(loop)): quadratic V, the generalized sector condition "
        "with its free matrix G, and a norm-bounded remainder of the plant's nonlinearity from sampled Hessians "
        "(safety factor 1.5) on a remainder box searched per round. SOS path (gc.certify_roa on a SaturatedLoop, "
        "method 'sos-sector'): each saturated input is an extra polynomial variable v restricted to the graph of "
        "sat by (v - lo)(hi - v) >= 0, (Kx - v) v >= 0 and (Kx - v)(v - lo)(hi - v) = 0 (exact), used as "
        "S-procedure terms in the level problem. A plant that is not polynomial in (x, v) (the glider loops: "
        "masses that depend on the ballast, angles) is replaced by a polynomial surrogate in (x, v) matched to "
        "second order at the equilibrium, with a cubic remainder bound a |y|^2 + b |y|^3 on the box that enters "
        "the decrease condition through Young's inequality (method 'sos-sector+remainder'; the unsaturated user "
        "loop takes the plain surrogate route, 'surrogate+remainder', with certify_roa's default checks: it is "
        "the certificate of the slocum_dive_cycle report, computed once per build and shared through the build "
        "cache, its SOS time that of the certify_roa call that made it); the bound holds on the whole box, so "
        "certify_roa first searches a smaller box (three times the extents of the best level set of the starting "
        "V, one level SDP per box) and certifies there, then runs a second round on the box three times the "
        "extents of that certified set, from its V, and keeps the larger certificate. The saturated user glider's "
        "SOS volume rests on that second round, whose path follows the solver's numerics: with Clarabel's "
        "iterative refinement off its volume is 2.98e-12 instead of 3.48e-12 (its first V step fails and is "
        "retried from a deeper multiplier; without the retry that round is lost and 4.7e-15 remains; "
        "bench/bench_roa_retry.py, 2026-12-04), so read its ratio to the LMI volume as an order of magnitude. "
        "The table compares the two "
        "paths on each glider loop (the SOS rows: volume of the SOS certificate over the LMI ellipsoid's; both "
        "sets lie in the loop's box). "
        "On a polynomial, open-loop unstable saturated loop the SOS path with the exact plant certifies more than "
        "the LMI path (it sees the quadratic term exactly; with the same quadratic V on a linear saturated loop "
        "both give the same level, tests/test_roa_sector.py). The LMI path's certified fractions of the glider "
        "boxes are small because the "
        "boxes are large in 5 (8) dimensions and the remainder bound, not the saturation, binds: the ellipsoid "
        "fills its remainder box while it reaches beyond the saturation level in K x (so the sector condition is "
        "not what stops it), and the same V stays decreasing on the sampled boundary of a scaled-up ellipsoid (the "
        "tightness scale). The first round of the remainder-box search (a box shaped like the loop's box) gives "
        "ellipsoids 1e5 to 1e6 times smaller than the later rounds (boxes shaped like the best ellipsoid): two "
        "rounds at least are needed for a meaningful region. For the buoyancy loop the Omega2 range of the default "
        "box (+-0.3 rad/s) binds as well (extent 0.995 of it): widening it to +-1 rad/s doubles the certified "
        "volume (4.35e-7 -> 8.53e-7, measured 2026-12-01) but lowers the fraction of the larger box (6.1e-7 -> "
        "3.6e-7); the default box is kept. "
        + (f"The user glider uses {s.sat_user_rounds} rounds of the remainder-box search instead of "
           f"{s.sat_rounds} (its 8-state SDPs make each round ~10-20 s)." if s.sat_user_rounds != s.sat_rounds
           else "")))


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """Build the report with ``QUICK`` or ``FULL`` settings."""
    s = QUICK if quick else FULL
    res = _compute(s, progress)
    progress("figures and report")
    rep = _report(res)
    if res.sat is not None:
        _report_saturated(rep, s, res.sat)
    return rep


if __name__ == "__main__":
    run_script(__file__)
