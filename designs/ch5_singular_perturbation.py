"""Chapter 5 design: singular-perturbation reduction, composite Lyapunov certificate and region of attraction of the
spherical glider (§5.1-§5.4).

Run ``glidectl report ch5_singular_perturbation`` or ``python designs/ch5_singular_perturbation.py [OUTDIR] [--quick]``;
writes ``OUTDIR/ch5_singular_perturbation/``.

``compute(settings)`` does the numerical work; ``figures(res)`` draws; ``report(res)`` builds the ledger;
``design(progress, quick)`` runs both with the ``FULL`` or ``QUICK`` settings.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.lines import Line2D

import glidectl as gc
from glidectl.report import BHATTA_2006, Report, new_figure, run_script

TITLE = "Chapter 5: singular perturbation, composite Lyapunov function and region of attraction of a spherical glider"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 6.0, "full": 20.0}

# ---------------------------------------------------------------------------------------------- thesis data
DOMAIN = {"Vbar": (-0.4, 0.4), "alphabar": (-0.2, 0.2)}  # §5.3.1; gammabar in [-pi, pi], Omegabar unbounded
VARIANTS: dict[str, dict[str, float]] = {  # the four designs of §5.3.1 (overrides of sphere_ch5)
    "baseline (K_M = -50, J2 = 0.02)": {},
    "K_M = -100": {"K_M": -100.0},
    "J2 = 0.01": {"J2": 0.01},
    "K_M = -100, J2 = 0.01": {"K_M": -100.0, "J2": 0.01},
}
THESIS_CERTIFIED = {"baseline (K_M = -50, J2 = 0.02)": False, "K_M = -100": True, "J2 = 0.01": True,
                    "K_M = -100, J2 = 0.01": True}  # §5.3.1: "K_M = -100 and/or J2 = 0.01 ... mu < mu_d"
FIG51_FULL_X0 = (1.730, -0.91, 0.03, 2.50)  # V (m/s), gamma (rad), alpha (rad), Omega2 (rad/s), §5.1.3
FIG51_SLOW_X0 = (1.765, -0.93)
SLICES = {"A": (math.pi / 12, 0.01), "B": (math.pi / 8, 0.01), "C": (math.pi / 12, 0.1), "D": (math.pi / 8, 0.1)}

# printed values compared in the ledger (5.8)-(5.84), 5.4
PUBLISHED = {"eps1": 4.784e-3, "eps2": 4.403e-4, "tau_s": 8.361, "V_e": 1.684, "gamma_e_deg": -53.566,
             "reduced_eigenvalues": [[-1.5, 0.916], [-1.5, -0.916]], "boundary_layer_eigenvalues": [-363.796, -84.582],
             "mu": 4.784e-3, "mu_d": 3.635e-3, "d": 0.4423, "kappa_5110": 1.243}


# ---------------------------------------------------------------------------------------------- settings
@dataclass(frozen=True)
class Settings:
    """Numerical settings of the study (grids, sample counts, horizons, seeds, tolerances)."""

    repro_tol: float = 0.01  # relative: "reproduced" means within 1 % of the printed value (same policy as chapter 2)
    fig51_t: float = 40.0  # s (the thesis's time span is not printed)
    fig51_points: int = 2001  # output times of the Fig 5.1 runs
    lstar_grid: int = 241  # (Vbar, alphabar) grid side for the L* projections of Fig 5.2
    roa_grid: int = 15  # (Vbar, alphabar) grid side of the simulated initial states of Fig 5.2
    roa_horizon: float = 8.0  # simulated time of Fig 5.2, in units of tau_s
    converged_tol: float = 1e-3  # |z(t_final)| (nondimensional) below which a run counts as converged
    n_verify: int = 200_000  # samples of B_p x B_q per design for the bound check
    verify_seed: int = 1
    n_claim: int = 50_000  # samples for the printed-C_W claim (a quarter of n_verify)
    claim_seed: int = 2
    dm_grid: tuple[float, float, int] = (0.0, 1.5, 16)  # linspace of Delta m / m1 for the sampled check of Fig 5.3
    vmin_grid: tuple[float, float, int] = (-0.8, -0.05, 16)  # linspace of Vbar_min for Fig 5.3
    n_unequal: int = 4000  # samples of B_p per (Delta m, Vbar_min) point


FULL = Settings()
QUICK = Settings(lstar_grid=31, roa_grid=4, n_verify=4000, n_claim=1000, dm_grid=(0.0, 0.2, 2),
                 vmin_grid=(-0.4, -0.4, 1))


# ---------------------------------------------------------------------------------------------- computation
@dataclass(frozen=True)
class Ch5Results:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    vehicle: gc.Vehicle
    sp: gc.SingularPerturbation
    sp_g981: gc.SingularPerturbation
    fig51_full: gc.Simulation
    fig51_slow: gc.Simulation
    certs: dict[str, gc.CompositeCertificate]
    verifications: dict[str, gc.CompositeVerification]  # CompositeCertificate.verify() results
    thesis_cw: gc.CompositeCertificate
    thesis_cw_claim_ratio: float
    roa_cert: gc.CompositeCertificate
    lstar: dict[str, np.ndarray]  # slice -> bool mask on (alphabar, Vbar) grid
    lstar_axes: tuple[np.ndarray, np.ndarray]
    roa_points: np.ndarray  # (k, 2) Vbar, alphabar
    roa_converged: dict[str, np.ndarray]  # slice -> bool per point (all slice samples converge)
    roa_t_final: float
    kappa: float
    dm_grid: np.ndarray
    vmin_grid: np.ndarray
    sampled_max_dphi: np.ndarray  # (len(vmin), len(dm)) max dPhi/dt_n / psi^2
    bound_5109_margin: float


def _slice_samples(gb: float, ob: float) -> np.ndarray:
    """(gammabar, Omegabar2) samples of a slice: the four corners and the centre."""
    return np.array([[gb, ob], [gb, -ob], [-gb, ob], [-gb, -ob], [0.0, 0.0]])


def compute(s: Settings = FULL, progress: Callable[[str], None] = lambda msg: None) -> Ch5Results:
    """Run every computation of the chapter-5 study."""
    veh = gc.load_vehicle("sphere_ch5")
    progress("equilibrium, time scales, small parameters, subsystem eigenvalues (5.8)-(5.33)")
    sp = gc.singular_perturbation(veh)
    sp981 = gc.singular_perturbation(veh.with_overrides(g=9.81))

    progress("Fig 5.1: full and reduced simulations from the printed initial conditions")
    te = np.linspace(0.0, s.fig51_t, s.fig51_points)
    full = gc.simulate(gc.ReducedLongitudinalGlider(veh), np.array(FIG51_FULL_X0), s.fig51_t, t_eval=te, rtol=1e-10,
                       atol=1e-12)
    slow = gc.simulate(sp.slow_model(), np.array(FIG51_SLOW_X0), s.fig51_t, t_eval=te, rtol=1e-10, atol=1e-12)

    progress(f"composite Lyapunov constants for the {len(VARIANTS)} designs of 5.3.1; {s.n_verify} samples each")
    certs, vers = {}, {}
    for name, ov in VARIANTS.items():
        c = gc.composite_lyapunov(gc.load_vehicle("sphere_ch5", **ov), **DOMAIN)
        certs[name] = c
        vers[name] = c.verify(s.n_verify, seed=s.verify_seed)
    thesis_cw = gc.composite_lyapunov(veh, cw="thesis", **DOMAIN)
    claim = dataclasses.replace(thesis_cw, a2=thesis_cw.sp.r2).verify(s.n_claim, seed=s.claim_seed)
    claim_ratio = 1.0 / claim.margins["Prop1.2: dW/dtau <= -a2 sigma^2"]  # left/right (the ledger reports a ratio)

    progress("Fig 5.2: projections of L* and simulated region of attraction (K_M = -100)")
    cert = certs["K_M = -100"]
    vb = np.linspace(*DOMAIN["Vbar"], s.lstar_grid)
    ab = np.linspace(*DOMAIN["alphabar"], s.lstar_grid)
    VV, AA = np.meshgrid(vb, ab)
    lstar = {}
    for sl, (gb, ob) in SLICES.items():
        inside = np.ones_like(VV, dtype=bool)
        for g_, o_ in _slice_samples(gb, ob)[:4]:  # nu is largest at the corners of the slice (see caption)
            z = np.stack([VV, np.full_like(VV, g_), AA, np.full_like(VV, o_)], axis=-1)
            inside &= cert.in_estimate(z)
        lstar[sl] = inside
    pv = np.linspace(*DOMAIN["Vbar"], s.roa_grid)
    pa = np.linspace(*DOMAIN["alphabar"], s.roa_grid)
    P = np.array([(v, a) for a in pa for v in pv])
    Z, owner = [], []
    for sl, (gb, ob) in SLICES.items():
        for g_, o_ in _slice_samples(gb, ob):
            Z.append(np.column_stack([P[:, 0], np.full(len(P), g_), P[:, 1], np.full(len(P), o_)]))
            owner.append(sl)
    Zall = np.concatenate(Z)
    csp = cert.sp
    t_final = s.roa_horizon * csp.tau_s
    # the batch Rosenbrock integrator: every run its own step size (one stacked RK45 shares the step of the stiffest
    # run, and the boundary layer is stiff: eigenvalues ~ -1/eps2); same tolerances as simulate_many's defaults, a run
    # whose speed falls below 5 % of the glide speed stops (the model is singular at V = 0) and does not converge
    ens = gc.integrate_batch(gc.ReducedLongitudinalGlider(csp.model.vehicle).rhs, csp.to_dimensional(Zall), t_final,
                             rtol=1e-6, atol=1e-9, diverged=lambda X: X[:, 0] < 0.05 * csp.speed)
    zf = csp.to_nondimensional(ens.x_final)
    conv_all = (np.max(np.abs(zf), axis=1) < s.converged_tol) & (ens.status == gc.batch.FINISHED)
    conv = {sl: np.ones(len(P), dtype=bool) for sl in SLICES}
    for k, sl in enumerate(owner):
        conv[sl] &= conv_all[k * len(P):(k + 1) * len(P)]

    progress("Fig 5.3: unequal added masses, condition (5.110) against sampled dPhi/dt")
    dm_grid = np.linspace(*s.dm_grid)
    vmin_grid = np.linspace(*s.vmin_grid)
    kappa = abs(veh.m0) * veh.g / (sp.K_De * sp.speed**2)
    mx = np.zeros((vmin_grid.size, dm_grid.size))
    worst_5109 = math.inf
    for j, r in enumerate(dm_grid):
        vj = veh.with_overrides(m3=veh.m1 * (1 + r))
        for i, vmin in enumerate(vmin_grid):
            chk = gc.unequal_mass_check(vj, Vbar=(vmin, -vmin), n=s.n_unequal, seed=i)
            mx[i, j] = chk.max_dPhi
            if r > 0:
                worst_5109 = min(worst_5109, chk.bound_margin)
    return Ch5Results(s, veh, sp, sp981, full, slow, certs, vers, thesis_cw, claim_ratio, cert, lstar, (vb, ab), P,
                      conv, t_final, kappa, dm_grid, vmin_grid, mx, worst_5109)


# ---------------------------------------------------------------------------------------------- figures
def figures(res: Ch5Results) -> dict[str, tuple[Any, str]]:
    """Figures of the study: ``{stem: (figure, caption)}``."""
    out: dict[str, tuple[Any, str]] = {}
    sp = res.sp
    full, slow = res.fig51_full, res.fig51_slow
    fig, ax = new_figure(2, 2, width=9, height=5.6, sharex=True)
    ax[0, 0].plot(full.t, full.state("V"), "C0", label="full (5.4)-(5.7)")
    ax[0, 0].plot(slow.t, slow.state("V"), "C1--", label="reduced (5.33)")
    ax[0, 0].axhline(sp.speed, color="k", lw=0.6, ls=":", label="$V_e$")
    ax[0, 0].set_ylabel("speed V [m/s]")
    ax[0, 1].plot(full.t, np.degrees(full.state("gamma")), "C0")
    ax[0, 1].plot(slow.t, np.degrees(slow.state("gamma")), "C1--")
    ax[0, 1].axhline(math.degrees(sp.gamma), color="k", lw=0.6, ls=":")
    ax[0, 1].set_ylabel(r"flight-path angle $\gamma$ [deg]")
    ax[1, 0].plot(full.t, np.degrees(full.state("alpha")), "C0")
    ax[1, 0].axhline(math.degrees(sp.alpha), color="C1", ls="--", label=r"$\alpha_e$ (reduced model)")
    ax[1, 0].set_ylabel(r"angle of attack $\alpha$ [deg]")
    ax[1, 1].plot(full.t, full.state("Omega2"), "C0")
    ax[1, 1].axhline(0.0, color="C1", ls="--")
    ax[1, 1].set_ylabel(r"pitch rate $\Omega_2$ [rad/s]")
    for a in ax[1]:
        a.set_xlabel("t [s]")
    for a in ax.flat:
        a.grid(True, alpha=0.3)
    ax[0, 0].legend(fontsize=8)
    ax[1, 0].legend(fontsize=8)
    out["fig5_1_reduction"] = (fig, "Analogue of Fig 5.1: full model (5.4)-(5.7) from V = 1.730 m/s, "
                               "gamma = -0.91 rad, alpha = 0.03 rad, Omega2 = 2.50 rad/s and the reduced model (5.33) "
                               "from V = 1.765 "
                               f"m/s, gamma = -0.93 rad (printed initial conditions); sphere_ch5, g = {res.vehicle.g} "
                               "m/s^2. The fast states settle within a fraction of a second; the slow states of the "
                               "two models stay close and converge to the same glide.")

    fig, ax = new_figure(1, 1, width=7, height=4.8)
    d = np.linspace(0.005, 0.995, 400)
    for k, (name, c) in enumerate(res.certs.items()):
        ax.plot(d, c.mu_d_of(d) * 1e3, color=f"C{k}", label=f"{name}: $\\mu_d(d)$")
        ax.axhline(c.mu * 1e3, color=f"C{k}", ls=":", lw=1)
        ax.plot([c.d], [c.mu_d * 1e3], "o", color=f"C{k}", ms=6, mfc="white" if not c.certified else f"C{k}")
    ax.set_xlabel("composite weight d [-]")
    ax.set_ylabel(r"$\mu_d$, $\mu$ [$10^{-3}$]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
    ax.set_ylim(0, None)
    out["mu_vs_d"] = (fig, "mu_d(d) of (5.54) for the four designs of 5.3.1 (solid) against the design's "
                      "mu = max(eps1, eps2) (dotted, same colour; the baseline and J2 = 0.01 share mu). Circles: the "
                      "d of (5.84) (v0/(v0 + w0)); filled when mu < mu_d "
                      "(certified). Domain |Vbar| <= 0.4, |alphabar| <= 0.2, constants with the corrected C_W. "
                      "No thesis figure.")

    vb, ab = res.lstar_axes
    fig, axes = new_figure(2, 2, width=8.5, height=6.6, sharex=True, sharey=True)
    for a, (sl, (gb, ob)) in zip(axes.flat, SLICES.items(), strict=True):
        a.contourf(vb, ab, res.lstar[sl].astype(float), levels=[0.5, 1.5], colors=["C0"], alpha=0.45)
        a.contour(vb, ab, res.lstar[sl].astype(float), levels=[0.5], colors=["C0"], linewidths=1.2)
        cv = res.roa_converged[sl]
        a.plot(res.roa_points[cv, 0], res.roa_points[cv, 1], ".", color="C2", ms=3)
        a.plot(res.roa_points[~cv, 0], res.roa_points[~cv, 1], "x", color="C3", ms=4)
        a.set_title(f"({sl}) $|\\bar\\gamma| \\leq \\pi/{round(math.pi / gb)}$, $|\\bar\\Omega_2| \\leq {ob:g}$",
                    fontsize=9)
        a.grid(True, alpha=0.3)
    for a in axes[1]:
        a.set_xlabel(r"$\bar V$ [-]")
    for a in axes[:, 0]:
        a.set_ylabel(r"$\bar\alpha$ [rad]")
    handles = [Line2D([], [], color="C0", lw=6, alpha=0.45, label="$L^*$ (5.85) for every slice state"),
               Line2D([], [], color="C2", marker=".", ls="", label="simulation converges"),
               Line2D([], [], color="C3", marker="x", ls="", label="simulation does not converge")]
    axes[0, 0].legend(handles=handles, fontsize=7, loc="lower left")
    ncv = {sl: int(np.sum(~c)) for sl, c in res.roa_converged.items()}
    out["fig5_2_roa"] = (fig, "Analogue of Fig 5.2 (K_M = -100, J2 = 0.02): shaded, the (Vbar, alphabar) for which "
                         "every (gammabar, Omegabar2) of the slice lies in L* (nu is largest at the slice corners: "
                         "Phi grows "
                         "with |gammabar| and W is convex in Omegabar2). Dots: initial states whose full nonlinear "
                         "simulation (corners and centre of the slice, "
                         f"{res.roa_t_final:.0f} s) reaches |z| < {res.settings.converged_tol:g}; non-converging per "
                         f"slice: {ncv}. "
                         "The estimate is conservative: the simulated region spans the whole box, as 5.3.1 says.")

    fig, ax = new_figure(1, 1, width=7, height=5.0)
    vm = np.linspace(-0.95, 0.0, 200)
    ax.plot(vm, gc.allowable_delta_m_ratio(res.kappa, vm), "C0", lw=2,
            label=f"(5.110) boundary, $m_0 g/(K_{{De}} V_e^2)$ = {res.kappa:.3f}")
    ax.fill_between(vm, 0, gc.allowable_delta_m_ratio(res.kappa, vm), color="C0", alpha=0.2)
    Vg, Dg = np.meshgrid(res.vmin_grid, res.dm_grid, indexing="ij")
    ok = res.sampled_max_dphi < 0
    ax.plot(Vg[ok], Dg[ok], "o", color="C2", ms=4, mfc="none", label=r"sampled: $d\Phi/dt_n < 0$ on $B_p$")
    ax.plot(Vg[~ok], Dg[~ok], "x", color="C3", ms=5, label=r"sampled: $d\Phi/dt_n \geq 0$ somewhere")
    ax.set_xlabel(r"$\bar V_{min}$ [-] (domain $\bar V_{min} \leq \bar V \leq -\bar V_{min}$)")
    ax.set_ylabel(r"$|\Delta m| / m_1$ [-]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=2)
    out["fig5_3_unequal_mass"] = (fig, "Analogue of Fig 5.3: (Vbar_min, |Delta m|/m1) pairs for which (5.110) lets Phi "
                                  "(5.106) prove stability of the reduced subsystem (shaded), and what sampling the "
                                  "model's reduced subsystem (5.103)-(5.104) on B_p shows (markers). (5.110) is "
                                  "sufficient and very conservative.")
    return out


# ---------------------------------------------------------------------------------------------- report
def _pairs(lam: np.ndarray) -> list[list[float]]:
    return [[float(z.real), float(z.imag)] for z in lam]


def report(res: Ch5Results) -> Report:
    """The report: ledger, tables, figures, notes."""
    sp, sp981 = res.sp, res.sp_g981
    n_verify = res.settings.n_verify
    rep = Report(TITLE, vehicle=[res.vehicle], reference=BHATTA_2006)
    tol = res.settings.repro_tol
    pub = PUBLISHED
    gnote = (f"g = 9.8 m/s^2 (vehicle file; with 9.81: tau_s = {sp981.tau_s:.4f} s, eps1 = {sp981.eps1:.4e}, "
             f"eps2 = {sp981.eps2:.4e}, V_e = {sp981.speed:.4f} m/s).")
    rep.number("eps1", sp.eps1, "-", "(5.16), 5.1.3/5.3.1", published=pub["eps1"], tolerance=tol, note=gnote)
    rep.number("eps2", sp.eps2, "-", "(5.17), 5.1.3/5.3.1", published=pub["eps2"], tolerance=tol)
    rep.number("tau_s", sp.tau_s, "s", "(5.18), 5.3.1", published=pub["tau_s"], tolerance=tol)
    rep.number("V_e", sp.speed, "m/s", "(5.8), 5.3.1", published=pub["V_e"], tolerance=tol,
               note=f"The printed 1.684 is a digit transposition of 1.648: tau_s = m1/(K_De V_e) = 8.361 s and eps2 "
                    f"as printed both require V_e = {sp.speed:.4f} m/s (with 1.684, tau_s would be "
                    f"{sp.model.masses[1] / (sp.K_De * 1.684):.3f} s).")
    rep.number("gamma_e_deg", math.degrees(sp.gamma), "deg", "(5.9), 5.3.1", published=pub["gamma_e_deg"],
               tolerance=tol)
    rep.number("alpha_e_deg", math.degrees(sp.alpha), "deg", "(5.10)")
    rep.number("reduced_eigenvalues", _pairs(sp.reduced_eigenvalues), "-", "5.1.3 (t_n scale)",
               published=pub["reduced_eigenvalues"],
               verdict=bool(np.allclose(sorted(np.abs(sp.reduced_eigenvalues.imag)), [0.916, 0.916], atol=6e-4)
                            and np.allclose(sp.reduced_eigenvalues.real, -1.5, atol=5e-4)),
               note="Eigenvalues of df/dp at the origin of the reduced subsystem (5.33), complex-step Jacobian.")
    bl = sp.boundary_layer_eigenvalues
    rep.number("boundary_layer_eigenvalues", [float(x.real) for x in bl], "-", "5.1.3 (t_n scale)",
               published=pub["boundary_layer_eigenvalues"], verdict=False,
               note="Eigenvalues of the boundary layer (5.30) at p = 0 on the t_n scale, i.e. roots of "
                    "s^2 + s/eps2 + 1/(eps1 eps2): their sum is -1/eps2 = "
                    f"{-1 / sp.eps2:.1f} and product 1/(eps1 eps2) = {1 / (sp.eps1 * sp.eps2):.4g}. The printed pair "
                    "has sum -448.4 and product 3.077e4; no single printed parameter (g, the V_e misprint, J2, "
                    "K_q, K_M) "
                    "explains it, and the printed eps1, eps2 (which we reproduce) contradict it. Not reproduced. "
                    f"The full 4x4 linearization has {', '.join(f'{x.real:.2f}' for x in sp.full_eigenvalues[:2])} "
                    "(fast) on t_n, close to our boundary-layer pair as Theorem 1 predicts.")
    rep.number("full_eigenvalues", _pairs(sp.full_eigenvalues), "-", "(5.28)-(5.29) linearized, t_n scale")
    rep.number("mu", sp.mu, "-", "(5.26), 5.3.1", published=pub["mu"], tolerance=tol)
    base = res.certs["baseline (K_M = -50, J2 = 0.02)"]
    cnote = ("Constants with the corrected C_W (c1 = 1 + 2 r2 a / r1; the printed c1 does not cancel the cross term "
             "of dW/dtau), k3, k4 = half the eigenvalues of C_W, gamma2'' by the derivation in "
             "glidectl.stability.composite. ")
    rep.number("mu_d", base.mu_d, "-", "(5.54), 5.3.1", published=pub["mu_d"], tolerance=tol,
               note=cnote + "Same verdict as the thesis (mu > mu_d: not certified), different value: the thesis's "
                            "constants cannot be reproduced exactly because its C_W and gamma2'' (5.81) are wrong or "
                            "ambiguous (see the notes on the constants).")
    rep.number("d", base.d, "-", "(5.84), 5.3.1", published=pub["d"], tolerance=tol,
               note=f"d = v0/(v0 + w0) with v0 = {base.v0:.5f} (largest Phi level inside B_p, closed form) and "
                    f"w0 = {base.w0:.5f} (largest W level inside B_q; the alphabar bound binds, Omegabar unbounded).")
    rep.number("mu_star", base.mu_star, "-", "Theorem 2",
               note=f"max over d of mu_d(d), attained at d = {base.d_best:.4f}.")
    for name, c in res.certs.items():
        key = "certified_" + name.split(" (")[0].replace(" ", "").replace(",", "_").replace("=", "").replace("-", "m")
        rep.number(key, c.certified, "-", "5.3.1", published=THESIS_CERTIFIED[name],
                   verdict=c.certified == THESIS_CERTIFIED[name],
                   note=f"{name}: mu = {c.mu:.4e}, mu_d = {c.mu_d:.4e} at d = {c.d:.4f}, mu* = {c.mu_star:.4e}.")
    worst = min(min(v.margins.values()) for v in res.verifications.values())
    rep.number("worst_bound_margin", worst, "-", "Props 1-2, Theorem 2",
               note=f"Smallest margin (right/left at the worst sample) of every inequality over {n_verify} samples of "
                    "B_p x B_q, for all four designs (>= 1 means every bound holds at every sample).")
    rep.number("thesis_CW_claimed_a2_ratio", res.thesis_cw_claim_ratio, "-", "(5.31)-(5.32)",
               note="With the printed C_W, dW/dtau <= -r2 sigma^2 (a2 = r2) fails (ratio > 1). Its true a2 is "
                    f"{res.thesis_cw.a2:.4f} instead of r2 = {res.thesis_cw.sp.r2:.4f}.")
    rep.number("kappa_5110", res.kappa, "-", "5.4, Fig 5.3", published=pub["kappa_5110"], tolerance=tol,
               note="m0 g/(K_De V_e^2) = 1/|sin gamma_e|.")
    rep.number("bound_5109_worst_margin", res.bound_5109_margin, "-", "(5.109)",
               note="Smallest sampled margin (bound psi^2)/R over the Fig 5.3 grid (>= 1 holds): (5.109) holds with a "
                    "wide margin.")

    rows = [["V_e [m/s]", f"{sp.speed:.5f}"], ["gamma_e [deg]", f"{math.degrees(sp.gamma):.4f}"],
            ["alpha_e [rad]", f"{sp.alpha:.5f}"], ["K_De, K_Le [kg/m]", f"{sp.K_De:.4f}, {sp.K_Le:.4f}"],
            ["tau_s [s]", f"{sp.tau_s:.4f}"], ["eps1, eps2", f"{sp.eps1:.5e}, {sp.eps2:.5e}"],
            ["mu, r1, r2", f"{sp.mu:.5e}, {sp.r1:.4f}, {sp.r2:.4f}"]]
    rep.table("Steady glide and time scales of sphere_ch5 (5.8)-(5.27)", ["quantity", "value"], rows)
    crows = []
    for name, c in res.certs.items():
        crows.append([name, f"{c.k1:.4f}", f"{c.k2:.4f}", f"{c.k3:.4f}", f"{c.k4:.3f}", f"{c.b1:.4f}", f"{c.a2:.3f}",
                      f"{c.beta1:.2f}", f"{c.beta2p:.2f}", f"{c.gamma2p:.2f}", f"{c.gamma2pp:.1f}", f"{c.v0:.4f}",
                      f"{c.w0:.4f}", f"{c.d:.4f}", f"{c.mu:.3e}", f"{c.mu_d:.3e}", "yes" if c.certified else "no"])
    rep.table("Constants of Propositions 1-2 and Theorem 2 (a1 = 1, gamma1 = beta2'' = 0)",
              ["design", "k1", "k2", "k3", "k4", "b1", "a2", "beta1", "beta2'", "gamma2'", "gamma2''", "v0", "w0",
               "d", "mu", "mu_d", "certified"], crows)
    vrows = []
    keys = list(next(iter(res.verifications.values())).margins)
    for k in keys:
        vrows.append([k] + [f"{v.margins.get(k, float('nan')):.4f}" for v in res.verifications.values()])
    rep.table(f"Sampled margin right/left of each bound at the worst sample ({n_verify} samples; >= 1 holds)",
              ["inequality", *[n.split(" (")[0] for n in res.verifications]], vrows)
    for stem, (fig, cap) in figures(res).items():
        rep.figure(stem, fig, cap)
    rep.text("Method and corrections", (
        "One model: glidectl.models.reduced.ReducedLongitudinalGlider (the foundation model with r_P = 0, tested equal "
        "to it). The nondimensional f, g of (5.28)-(5.29), the boundary-layer and reduced subsystems are that "
        "right-hand side seen through (5.12)-(5.19); every inequality of Propositions 1-2 and Theorem 2 is checked by "
        "sampling with those vector fields, not with the thesis's algebra.\n\n"
        "Corrections: (1) C_W of (5.31): the cross term of dW/dtau vanishes for c1 = 1 + 2 r2 a / r1, not the printed "
        "r1 + r1 a + r2 a (with the printed matrix dW/dtau <= -r2 sigma^2 fails). (2) k3, k4 are half the eigenvalues "
        "of C_W because W = q^T C_W q / 2. (3) beta2' re-derived for the corrected c1. (4) gamma2'' of (5.81) is "
        "ambiguous (named C_3, terms not following from (5.79)); we bound |dW/dVbar f1| directly. (5) beta1 uses "
        "max|Vbar|. (6) tau_s uses m3 so that (5.103)-(5.107) hold as printed for m1 != m3 (m1 = m3 in 5.1-5.3). "
        "(7) V_e = 1.684 m/s is a misprint of 1.648 m/s. (8) (5.103): the Delta m term has the wrong sign (it must be "
        "-(Delta m cos alpha_e / m1) f inside the bracket; (5.108) agrees with the corrected form). (9) (5.92): "
        "sin(alphabar + 2 alpha_e) cos(alphabar) should be sin(alphabar) cos(alphabar + 2 alpha_e) (as printed the "
        "boundary layer does not vanish at q = 0). (10) (5.109): 2 Delta m |m0 g| should be 2 |Delta m m0 g|. (11) "
        "5.1: the reciprocals of the reduced eigenvalues do not sum to 3 tau_s; what holds is "
        "lambda1 + lambda2 = -3/tau_s "
        "(tests/test_singular_perturbation.py). g = 9.8 m/s^2 reproduces tau_s, eps1 and eps2 to all "
        "printed digits; 9.81 does not.\n\nReproduction policy: within 1 % of the printed value, uniform; no "
        "parameter was adjusted to approach a printed number."))
    return rep


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The chapter-5 study with the ``QUICK`` or ``FULL`` settings."""
    return report(compute(QUICK if quick else FULL, progress))


if __name__ == "__main__":
    run_script(__file__)
