"""Design study: region-of-attraction certification by SOS programs (glidectl.roa) against Drake's
``RegionOfAttraction``, the thesis's estimates (Phi < 2/3 of (5.35), L* of (5.85)) and the true regions from batch
simulation, on the Van der Pol benchmark and the chapter-5 glider (reduced 2-state and full 4-state models).

``compute()`` does the numerical work; ``figures()`` draws; ``report()`` builds the ledger; ``build(outdir)`` writes
``<outdir>/roa_certification/``. ``designs/roa_certification.py`` and ``glidectl report roa_certification`` call
:func:`build`.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import quad
from scipy.stats import qmc

from ..analysis.jacobian import hessian
from ..batch import integrate_batch
from ..benchmarks import drake_van_der_pol, van_der_pol, van_der_pol_limit_cycle
from ..controllers.ctol import ClosedLoopCTOL
from ..controllers.torque import design_torque_control
from ..params import load_vehicle
from ..report.document import Report
from ..roa import ROACertificate, certify_roa, dVdt, lyapunov_matrix, lyapunov_quadratic, max_level, recast
from ..roa.systems import taylor_system
from ..stability.composite import CompositeCertificate, composite_lyapunov
from ..stability.ctol_lyapunov import ctol_lyapunov
from ..stability.singular_perturbation import SingularPerturbation, singular_perturbation
from ..trim.ctol import ctol_glide

NAME = "roa_certification"
TITLE = "Region-of-attraction certification by SOS programs: Van der Pol and the chapter-5 glider"

DRAKE_RHO = 2.3045          # Drake 1.51 RegionOfAttraction on the time-reversed Van der Pol (issue 7)
BACKOFF = 0.003
VDP = {"degree": 6, "iterations": 6}
REDUCED = {"degree": 4, "iterations": 4}
FULL = {"degree": 2, "iterations": 8}
FULL_KM = (-50.0, -100.0)
N_VOLUME = 2**16            # quasi-MC points for areas and volumes
N_TRUTH_2D = 201            # grid per axis for the simulated true region (2-state models)
N_TRUTH_4D = 4096           # Sobol points for the simulated true region (4-state model)
TORQUE_SPEED: float | None = 1.5   # m/s: the chapter-6 torque design certified as a closed loop (None: skip)
CTOL: dict[str, Any] | None = {"degree": 2, "iterations": 1, "k3": 10.0, "k4": 5.0}   # None: skip (~20 min)
TAYLOR_ORDER = 3
N_TRAP = 200_000
N_GUIDE = 2048              # simulated box points that steer the V step (certify_roa's n_truth)


@dataclass(frozen=True)
class Problem:
    """One certified problem and its comparisons."""

    name: str
    cert: ROACertificate
    measure: float               # certified area/volume in the box
    true_measure: float          # simulated region of attraction in the box
    reference: float             # thesis estimate (or Drake) in the box
    reference_name: str
    box_measure: float
    extra: dict[str, Any]


@dataclass(frozen=True)
class ROAResults:
    vdp: Problem
    vdp_rho: float
    vdp_rho_time: float
    drake: dict[str, float] | None
    cycle: np.ndarray
    reduced: Problem
    reduced_sp: SingularPerturbation
    reduced_truth: tuple[np.ndarray, np.ndarray, np.ndarray]
    trap: dict[str, Any]
    full: dict[str, Problem]
    full_composite: dict[str, CompositeCertificate]
    ctol: dict[str, Any] | None


def _converged(rhs: Any, X: np.ndarray, horizon: float) -> np.ndarray:
    """Simulated region of attraction of the origin (batch integrator), one flag per row of ``X``."""
    res = integrate_batch(rhs, X, horizon, rtol=1e-6, atol=1e-9, max_steps=50_000, bound=1e3)
    return res.converged_to(np.zeros(X.shape[1]), 1e-3)


def _phi_area() -> float:
    """Area of the thesis set {Phi < 2/3} of (5.35): -1 < Vbar < sqrt(3 cos g) - 1, |g| < pi/2."""
    return math.sqrt(3.0) * quad(lambda g: math.sqrt(math.cos(g)), -math.pi / 2, math.pi / 2)[0]


def compute(progress: Callable[[str], None] = lambda s: None) -> ROAResults:
    """Run every certification and comparison of the study."""
    progress("Van der Pol: fixed-V level (Drake's problem), Drake itself if installed, degree-6 certificate")
    vdp = van_der_pol()
    t0 = time.perf_counter()
    lvl = max_level(vdp, lyapunov_quadratic(vdp))
    t_lvl = time.perf_counter() - t0
    drake = drake_van_der_pol()
    cycle, area = van_der_pol_limit_cycle()
    vc = certify_roa(vdp, backoff=BACKOFF, n_truth=N_GUIDE, **VDP)
    drake_area = math.pi * DRAKE_RHO / math.sqrt(np.linalg.det(lyapunov_matrix(vdp)))   # ellipse x'Px <= rho
    lo, hi = vdp.box
    vprob = Problem("van_der_pol", vc, vc.volume(n=N_VOLUME), area, drake_area, "Drake (fixed quadratic V)",
                    float(np.prod(hi - lo)), {})
    progress("reduced 2-state glider (K_M = -50): degree-4 certificate, Phi < 2/3, simulated region")
    sp = singular_perturbation(load_vehicle("sphere_ch5"))
    rm = sp.reduced_model()
    rc = certify_roa(rm, backoff=BACKOFF, n_truth=N_GUIDE, **REDUCED)
    lo, hi = rm.box
    Vg = np.linspace(lo[0], hi[0], N_TRUTH_2D)
    Gg = np.linspace(lo[1], hi[1], N_TRUTH_2D)
    VV, GG = np.meshgrid(Vg, Gg)
    X = np.stack([VV.ravel(), GG.ravel()], axis=1)
    conv = _converged(rm.rhs, X, 60.0).reshape(VV.shape)
    box = float(np.prod(hi - lo))
    phi_in_box = box * float(np.mean(CompositeCertificate.Phi(
        lo + (hi - lo) * qmc.Sobol(2, seed=0).random(N_VOLUME)) < 2 / 3))
    rprob = Problem("reduced", rc, rc.volume(n=N_VOLUME), box * float(np.mean(conv)), _phi_area(),
                    "thesis Phi < 2/3 (5.35)", box, {"phi_area_in_box": phi_in_box})
    progress("Taylor trap: Drake's problem on the degree-3 Taylor model of the reduced glider, checked on the truth")
    trap = _taylor_trap(rm)
    full: dict[str, Problem] = {}
    comp: dict[str, CompositeCertificate] = {}
    cases: list[tuple[str, Any, str]] = [(f"KM{abs(int(KM))}", load_vehicle("sphere_ch5", K_M=KM),
                                          f"glider K_M = {KM:g}") for KM in FULL_KM]
    if TORQUE_SPEED is not None:
        progress(f"chapter-6 torque design for V_e = {TORQUE_SPEED} m/s (closed loop = glider with new moments)")
        td = design_torque_control(load_vehicle("sphere_ch5"), speed=TORQUE_SPEED, Vbar=(-0.4, 0.4),
                                   alphabar=(-0.2, 0.2))
        cases.append(("ch6_torque", td.closed_loop_vehicle, f"torque law (6.5), V_e = {TORQUE_SPEED} m/s"))
    for key, veh, label in cases:
        progress(f"full 4-state model, {label}: degree-{FULL['degree']} certificate, L* (5.85), simulations")
        spk = singular_perturbation(veh)
        fm = spk.full_model()
        cl = composite_lyapunov(veh)
        lo, hi = fm.box
        Xs = lo + (hi - lo) * qmc.Sobol(4, seed=0).random(N_VOLUME)
        bvol = float(np.prod(hi - lo))
        lstar = bvol * float(np.mean(cl.in_estimate(Xs)))
        fc = certify_roa(fm, backoff=BACKOFF, n_truth=N_GUIDE, **FULL)
        Xt = lo + (hi - lo) * qmc.Sobol(4, seed=9).random(N_TRUTH_4D)
        truth = bvol * float(np.mean(_converged(fm.rhs, Xt, 40.0)))
        full[key] = Problem(label, fc, fc.volume(n=N_VOLUME), truth, lstar, "thesis L* (5.85)", bvol,
                            {"mu": spk.mu, "mu_d": cl.mu_d, "thesis_certified": cl.certified, "K_M": veh.K_M,
                             "K_q": veh.K_q, "K_M0": veh.K_M0})
        comp[key] = cl
    ctol = _ctol(progress) if CTOL is not None else None
    return ROAResults(vprob, lvl.rho, t_lvl, drake, cycle, rprob, sp, (VV, GG, conv), trap, full, comp, ctol)


def _ctol(progress: Callable[[str], None]) -> dict[str, Any]:
    """The chapter-7 closed loop at the level glide: certificate against Theorem 5's estimate and simulations."""
    assert CTOL is not None
    veh = load_vehicle("dc8_ctol")
    gl = ctol_glide(veh, speed=0.85 / math.sqrt(veh.a_L), gamma=0.0)
    cl = ClosedLoopCTOL(veh, gl, CTOL["k3"], CTOL["k4"])
    model = cl.roa_model()
    progress(f"CTOL closed loop (k3, k4) = ({CTOL['k3']:g}, {CTOL['k4']:g}) at the level glide: degree-"
             f"{CTOL['degree']} certificate in 7 lifted variables (slow: ~100 s per SDP), Theorem 5, simulations")
    cert = certify_roa(model, degree=CTOL["degree"], iterations=CTOL["iterations"], backoff=BACKOFF,
                       n_truth=N_GUIDE // 2)
    th5 = ctol_lyapunov(veh, gl, CTOL["k3"], CTOL["k4"])
    # {Q <= level} is tiny: its volume is that of the ellipsoid of the Hessian of Q at 0 (level ~ 1e-8)
    H = hessian(th5.Q, np.zeros(4))
    ball4 = math.pi**2 / 2
    th_vol = ball4 * (2 * th5.level) ** 2 / math.sqrt(np.linalg.det(H)) if th5.certified else 0.0
    lo, hi = model.box
    bvol = float(np.prod(hi - lo))
    Xt = lo + (hi - lo) * qmc.Sobol(4, seed=9).random(N_TRUTH_4D)
    truth = bvol * float(np.mean(_converged(model.rhs, Xt, 40.0)))
    return {"cert": cert, "model": model, "volume": cert.volume(n=N_VOLUME), "theorem5_volume": th_vol,
            "r_a": th5.r_a, "ball_volume": ball4 * th5.r_a**4, "true_volume": truth, "box_volume": bvol,
            "theorem5_certified": th5.certified}


def _taylor_trap(model: Any) -> dict[str, Any]:
    """Certify the degree-3 Taylor model (what a polynomial-only tool sees) with Drake's fixed-V problem and count
    the certified points where the *true* dV/dt is positive."""
    ps = recast(model)
    tp = taylor_system(ps, TAYLOR_ORDER)
    V = lyapunov_quadratic(tp)
    lvl = max_level(tp, V)
    rng = np.random.default_rng(0)
    X = rng.uniform([-1.5, -math.pi], [2.5, math.pi], (N_TRAP, 2))
    inside = X[V(X) <= lvl.rho]          # V is quadratic: its sublevel set is one ellipse
    vd_true = dVdt(V, tp.lift, ps.rhs, inside)
    vd_taylor = dVdt(V, tp.lift, tp.rhs, inside)
    return {"rho": lvl.rho, "V": V, "n_inside": int(inside.shape[0]), "n_true_positive": int(np.sum(vd_true > 0)),
            "n_taylor_positive": int(np.sum(vd_taylor > 0)), "min_Vbar": float(np.min(inside[:, 0])),
            "bad": inside[vd_true > 0]}


def figures(res: ROAResults) -> dict[str, tuple[Any, str]]:
    """Figures of the study: ``{stem: (figure, caption)}``."""
    from ..report.figures import new_figure

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
    V0 = lyapunov_quadratic(res.vdp.cert.system)          # Drake's V = x'Px
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
    ax.contour(Vp, Gp, CompositeCertificate.Phi(np.stack([Vp, Gp], -1)), levels=[2 / 3], colors="C3",
               linestyles="--")
    ax.axvline(-0.9, color="k", lw=0.8, ls=":")
    TV = res.trap["V"](np.stack([Vp, Gp], -1))
    ax.contour(Vp, Gp, TV, levels=[res.trap["rho"]], colors="C2", linestyles="-.")
    bad = res.trap["bad"]
    ax.plot(bad[:, 0], bad[:, 1], ".", color="C1", ms=2)
    ax.plot([], [], "C2-.", label=f"Drake's problem on the degree-{TAYLOR_ORDER} Taylor model")
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
        for col, (j, name) in enumerate(((2, "alphabar [rad]"), (1, "gammabar [rad]"))):
            ax = axs[row, col]
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
                                   "certified set (shaded) and of the thesis's L* (dashed) through the equilibrium, "
                                   f"over the box of the study. Simulations from {N_TRUTH_4D} box points that "
                                   f"converge: {conv}.")
    if res.ctol is not None:
        c = res.ctol["cert"]
        lo, hi = res.ctol["model"].box
        fig, axs = new_figure(1, 2, width=11, height=4.6)
        for ax, (i, j) in zip(axs, ((0, 1), (2, 3)), strict=True):
            A, B = np.meshgrid(np.linspace(lo[i], hi[i], 161), np.linspace(lo[j], hi[j], 161))
            Xsl = np.zeros((A.size, 4))
            Xsl[:, i], Xsl[:, j] = A.ravel(), B.ravel()
            ins = c.contains(Xsl).reshape(A.shape).astype(float)
            ax.contourf(A, B, ins, levels=[0.5, 1.5], colors=["C0"], alpha=0.35)
            ax.contour(A, B, ins, levels=[0.5], colors="C0")
            names = c.system.state_names
            rest = [names[k] for k in range(4) if k not in (i, j)]
            ax.set(xlabel=names[i], ylabel=names[j], title=f"slice {rest[0]} = {rest[1]} = 0")
            ax.title.set_fontsize(9)
        fig.suptitle(f"CTOL closed loop, level glide, (k3, k4) = ({CTOL['k3']:g}, {CTOL['k4']:g}): certified set "
                     f"(volume {res.ctol['volume']:.3g}); Theorem 5 certifies ||x|| <= {res.ctol['r_a']:.2g}",
                     fontsize=9)
        out["ctol_roa_slices"] = (fig, "CTOL closed loop (7.16)-(7.20) at the level glide: slices of the certified "
                                       "set (shaded) through the equilibrium (alphabar = thetabar - gammabar). The "
                                       "Theorem 5 estimate is far too small to draw at this scale.")
    return out


def _history_rows(name: str, cert: ROACertificate) -> list[list[str]]:
    return [[name, str(h["degree"]), h["step"][:60], f"{h['rho']:.6g}", f"{h['volume']:.4g}", f"{h['sdp_time']:.2f}"]
            for h in cert.history]


def report(res: ROAResults) -> Report:
    """The report: ledger, tables, figures, notes."""
    rep = Report(NAME, TITLE, vehicles=[res.reduced_sp.model.vehicle])
    v = res.vdp
    rep.number("vdp_fixed_V_rho", res.vdp_rho, "-", "Drake RegionOfAttraction example (issue 7)", thesis=DRAKE_RHO,
               tolerance=1e-3 / DRAKE_RHO,
               note="Reference is Drake 1.51's published rho (not the thesis). Same problem: V = x'Px, A'P + PA = -I.")
    rep.number("vdp_fixed_V_time_s", res.vdp_rho_time, "s", "one SDP (Clarabel)")
    if res.drake is not None:
        rep.number("vdp_drake_rho_same_run", res.drake["rho"], "-", "pydrake RegionOfAttraction, this run",
                   note=f"median time {res.drake['time'] * 1e3:.1f} ms over 5 calls")
        rep.number("vdp_drake_time_s", res.drake["time"], "s", "pydrake, this run")
    rep.number("vdp_true_area", v.true_measure, "-", "simulated limit cycle (shoelace)", thesis=13.72,
               tolerance=1e-3, note="Reference value from the issue.")
    rep.number("vdp_certified_area", v.measure, "-", f"degree-{v.cert.degree} certificate, quasi-MC {N_VOLUME}")
    rep.number("vdp_fraction_of_true", v.measure / v.true_measure, "-", "target >= 0.95")
    rep.number("vdp_drake_fraction_of_true", v.reference / v.true_measure, "-", "ellipse x'Px <= 2.3045")
    rep.number("vdp_verified", v.cert.verified, "-", v.cert.verification.summary())
    rep.number("vdp_wall_time_s", v.cert.wall_time, "s", "certify_roa, target < 60 s",
               note=f"SDP solver time {v.cert.solve_time:.2f} s")
    r = res.reduced
    rep.number("reduced_certified_area", r.measure, "-", f"degree-{r.cert.degree} certificate in (Vbar, gammabar)")
    rep.number("reduced_thesis_phi_area", r.reference, "-", "(5.35): {Phi < 2/3}, closed form",
               note=f"{r.extra['phi_area_in_box']:.4f} of it lies in the box Vbar >= -0.9 used here.")
    rep.number("reduced_ratio_to_thesis", r.measure / r.reference, "-", "target >= 1.5")
    rep.number("reduced_true_area_in_box", r.true_measure, "-", f"{N_TRUTH_2D}^2 simulations, 60 t_n")
    rep.number("reduced_fraction_of_true", r.measure / r.true_measure, "-", "in the box")
    rep.number("reduced_verified", r.cert.verified, "-", r.cert.verification.summary())
    rep.number("reduced_wall_time_s", r.cert.wall_time, "s", "certify_roa")
    rep.number("reduced_recast_residual", r.cert.system.recast_residual, "-", "exact polynomial recasting")
    t = res.trap
    rep.number("taylor_trap_rho", t["rho"], "-", f"Drake's fixed-V problem on the degree-{TAYLOR_ORDER} Taylor model")
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
        rep.number(f"{k}_true_volume", p.true_measure, "-", f"{N_TRUTH_4D} simulations, 40 t_n")
        rep.number(f"{k}_fraction_of_true", p.measure / p.true_measure, "-", "in the box")
        rep.number(f"{k}_fraction_of_box", p.measure / p.box_measure, "-", "box volume "
                   f"{p.box_measure:.4f}")
        rep.number(f"{k}_verified", p.cert.verified, "-", p.cert.verification.summary())
        rep.number(f"{k}_wall_time_s", p.cert.wall_time, "s", "certify_roa",
                   note=f"SDP solver time {p.cert.solve_time:.1f} s; closed-loop K_M0 = {p.extra['K_M0']:.4g} kg, "
                        f"K_M = {p.extra['K_M']:.4g} kg/rad, K_q = {p.extra['K_q']:.4g} kg s/rad")
    if res.ctol is not None:
        ct = res.ctol
        rep.number("ctol_certified_volume", ct["volume"], "-", f"degree-{ct['cert'].degree} certificate in the box "
                   "|Vbar| <= 0.5, |gammabar| <= 0.5, |alphabar| <= 0.3, |Omega2bar| <= 1")
        rep.number("ctol_theorem5_volume", ct["theorem5_volume"], "-", "{Q <= level} of Theorem 5 (ellipsoid of "
                   "the Hessian of Q; the level is ~1e-8)",
                   note=f"Theorem 5 certified: {ct['theorem5_certified']}; its ball r_a = {ct['r_a']:.3g} has "
                        f"volume {ct['ball_volume']:.3g}.")
        rep.number("ctol_ratio_to_theorem5", ct["volume"] / ct["theorem5_volume"] if ct["theorem5_volume"] > 0
                   else math.inf, "-", "certified / Theorem 5 estimate")
        rep.number("ctol_true_volume", ct["true_volume"], "-", f"{N_TRUTH_4D} simulations, 40 s")
        rep.number("ctol_fraction_of_true", ct["volume"] / ct["true_volume"], "-", "in the box")
        rep.number("ctol_verified", ct["cert"].verified, "-", ct["cert"].verification.summary())
        rep.number("ctol_wall_time_s", ct["cert"].wall_time, "s", "certify_roa (7 lifted variables)",
                   note=f"SDP solver time {ct['cert'].solve_time:.0f} s")
    rows = _history_rows("Van der Pol", v.cert) + _history_rows("reduced", r.cert)
    for p in res.full.values():
        rows += _history_rows(p.name, p.cert)
    if res.ctol is not None:
        rows += _history_rows("CTOL", res.ctol["cert"])
    rep.table("Alternation history: degree, step, level of the level problem (1 = the V step's level kept), sampled "
              "area/volume in the box, SDP time [s]", ["problem", "deg", "step", "rho", "measure", "SDP s"], rows)
    for stem, (fig, cap) in figures(res).items():
        rep.figure(stem, fig, cap)
    rep.text("Method", (
        "glidectl.roa: a small polynomial layer (Poly, monomials), SOS programs compiled as sparse coefficient "
        "equalities with PSD Gram matrices in cvxpy (Clarabel), exact recasting of the glider models "
        "(gammabar -> (sin, 1 - cos) with s^2 + c^2 = 2c, the 1/V factor cleared with the cut V >= 0.1 V_e; the "
        "polynomial is recovered from the model's own right-hand side and checked to 1e-15), the level problem "
        "(Vdot = 0 => V >= rho, linear in rho and the multiplier, one SDP), the V step (multiplier fixed, V free), "
        "and degree raising 2 -> 4 -> 6. The V step minimizes mean(max(V - 1, 0)) over simulated converging points "
        "of the box, so the search is steered towards the true region; the certificate does not depend on the "
        f"simulations. Every certificate is stated at (1 - backoff) rho* (backoff {BACKOFF:g}, tripled while the "
        "Gram margins do not cover the residuals), re-solved at that level and verified: exact "
        "SOS from Gram eigenvalue margins against coefficient residuals, the local conditions at the equilibrium, "
        "true dV/dt < 0 at sampled points of the set and convergence of the 256 outermost samples."))
    rep.text("Left alone", (
        "Degree 2 for the 4-state models and the closed loops: a degree-4 V in the 5 lifted variables of the glider "
        "needs a 104 x 104 Gram matrix per constraint and one level SDP takes about 100 s with Clarabel on 2 cores "
        "(measured); the CTOL closed loop (7 lifted variables: alphabar kept and enclosed by Taylor bounds) takes "
        "about 110 s per SDP already at degree 2, so it runs one alternation. An LMI path with linear-plus-sector "
        "bounds was not built (the degree-2 SOS certificate is the quadratic-V path). When Clarabel fails on a V step "
        "the alternation stops there and keeps the best V found (rows 'V step failed' in the history table)."))
    return rep


def build(outdir: str | Path = "reports", progress: Callable[[str], None] = lambda s: None) -> Path:
    """Compute the study and write ``<outdir>/roa_certification/`` (report.pdf, PNGs, numbers.json)."""
    from . import build_study

    return build_study(sys.modules[__name__], outdir, progress)
