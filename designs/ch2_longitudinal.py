"""Chapter 2 design: ROGUE steady glides, linear analysis, r_bh root locus, LQR/placement, glide switch.

Longitudinal steady glides, linear analysis (eigenvalues, controllability, observability), root loci in r_bh and
mbar (Fig 2.7), LQR and pole placement on the glide path with nonlinear recovery runs, and the decoupled
acceleration feedback (2.37) switching from the -45 deg to the +45 deg glide (Fig 2.8).

Run ``glidectl report ch2_longitudinal`` or ``python designs/ch2_longitudinal.py [OUTDIR] [--quick]``;
writes ``OUTDIR/ch2_longitudinal/``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib import pyplot as plt

import glidectl as gc
from glidectl.report import BHATTA_2006, Report, new_figure, run_script

TITLE = "Chapter 2: longitudinal steady glides, stability and linear control of ROGUE"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 10.0, "full": 18.0}

# ------------------------------------------------------------------------------------ printed thesis values
THESIS_EIG_M45 = 0.099 + 2.325j  # 1/s, 2.3.1: the 'slow unstable mode' of the uncontrolled -45 deg glide
THESIS_RBH_BOUNDARY = -0.0068  # m, 2.3.2 / Fig 2.7: 'approximately -0.0068 m'
THESIS_MBAR_THRESHOLD = 0.257  # kg, 2.3.1
THESIS_K_DIAG = (100.0, 300.0, 100.0, 300.0, 50.0)  # printed diag of K in (2.37): 100 * [1 3 1 3 0.5]


@dataclass(frozen=True)
class Settings:
    """Every setting of the design (FULL: the values of the published report)."""

    speed: float = 0.3  # m/s, §2.3.1
    r_p3: float = 0.05  # m, our choice of the family member (the thesis does not state its r_P3)
    gammas_deg: tuple[float, ...] = (-45.0, -30.0, 30.0, 45.0)  # must contain -45 and +45
    rbh_grid: tuple[float, float, int] = (-0.03, 0.06, 400)  # m, linspace of the Fig 2.7 locus
    mbar_grid: tuple[float, float, int] = (0.01, 10.0, 300)  # kg, geometric
    nearest_grid: tuple[float, float, int] = (-0.1, 0.15, 501)  # m, r_bh scan for the thesis eigenvalue
    family_points: int = 200  # gamma samples per branch of the glide-family figure
    k_diag: tuple[float, ...] = THESIS_K_DIAG  # gains of (2.37)
    place_poles: tuple[float, ...] = (-0.15, -0.3, -0.5, -0.7, -0.9, -1.2, -1.5, -2.0, -2.5, -3.0)  # 1/s
    #: initial glide-path offsets z'(0) (m) of the nonlinear recovery runs, per design
    recovery_offsets: tuple[tuple[str, tuple[float, ...]], ...] = (("lqr", (0.5,)), ("place", (0.1, 0.2)))
    recovery_horizon: float = 120.0  # s
    diverged_zp: float = 10.0  # a recovery run is stopped (and called diverged) once |z'| exceeds this x z'(0)
    switch_time: float = 5.0  # s, -45 -> +45 deg switch of Fig 2.8
    switch_horizon: float = 60.0  # s
    switch_samples: int = 3001
    repro_tol: float = 0.01  # relative: "reproduced" means within 1 % of the printed value (uniform policy)


FULL = Settings()
QUICK = Settings(rbh_grid=(-0.03, 0.06, 120), mbar_grid=(0.01, 10.0, 80), nearest_grid=(-0.1, 0.15, 51),
                 family_points=40, recovery_horizon=60.0, switch_horizon=30.0, switch_samples=601)


@dataclass(frozen=True)
class Ch2Results:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    vehicle: gc.Vehicle
    permissible: tuple[float, float]
    glides: dict[float, gc.SteadyGlide]
    uncontrolled: dict[float, np.ndarray]
    accel_eta_r: dict[float, np.ndarray]
    ranks: list[dict[str, Any]]
    nearest_thesis_eig: dict[str, float]
    axis3_sawtooth: dict[str, float]
    rbh: gc.ParameterLocus
    mbar: gc.ParameterLocus
    mbar_rbh0: gc.ParameterLocus
    lqr: gc.LinearGlideController
    place: gc.LinearGlideController
    recovery: dict[tuple[str, float], gc.Simulation]  # (method, z'(0) in m) -> run
    k_printed_poles: np.ndarray
    k_corrected_poles: np.ndarray
    switch: gc.Simulation
    switch_glides: tuple[gc.SteadyGlide, gc.SteadyGlide]


def _eta_r_block(veh: gc.Vehicle, g: gc.SteadyGlide) -> np.ndarray:
    lin = gc.linearize_glide(veh, g, "acceleration")
    idx = [lin.state_labels.index(s) for s in ("theta", "Omega2", "v1", "v3")]
    return np.linalg.eigvals(np.asarray(lin.A)[np.ix_(idx, idx)])


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> Ch2Results:
    """Run every computation of the chapter-2 study (ROGUE, V = 0.3 m/s, r_P3 = 0.05 m)."""
    veh = gc.load_vehicle("rogue")
    progress("steady glides and permissible set (2.26)")
    lo, hi = gc.permissible_gamma(veh)
    glides = {gd: gc.steady_glide(veh, s.speed, math.radians(gd), r_p3=s.r_p3) for gd in s.gammas_deg}

    progress("linearization, eigenvalues, controllability and observability")
    uncontrolled = {gd: gc.uncontrolled_eigs(veh, s.speed, g.gamma, r_p3=s.r_p3) for gd, g in glides.items()}
    accel = {gd: _eta_r_block(veh, g) for gd, g in glides.items()}
    ranks: list[dict[str, Any]] = []
    for gd, g in glides.items():
        sf, sa = gc.linearize_glide(veh, g, "force"), gc.linearize_glide(veh, g, "acceleration")
        tests = [
            ("controllability", "force, inputs u1 u3 u4", gc.controllability(sf)),
            ("controllability", "force, inputs u1 u3 (no buoyancy)", gc.controllability(sf, inputs=["u1", "u3"])),
            ("controllability", "acceleration, inputs w1 w3 w4", gc.controllability(sa)),
            ("controllability", "mass on body-1 axis only: w1 w4, r_P3 locked",
             gc.controllability(sa, inputs=["w1", "w4"], states=[x for x in sa.state_labels
                                                                 if x not in ("r_P3", "rdot_P3")])),
            ("controllability", "mass on body-3 axis only: w3 w4, r_P1 locked",
             gc.controllability(sa, inputs=["w3", "w4"], states=[x for x in sa.state_labels
                                                                 if x not in ("r_P1", "rdot_P1")])),
            ("observability", "force, y = (r_P1, r_P3, m0)", gc.observability(sf, ["r_P1", "r_P3", "m0"])),
            ("observability", "force, y = (theta, r_P1, m0)", gc.observability(sf, ["theta", "r_P1", "m0"])),
            ("observability", "force, y = (theta, r_P3, m0)", gc.observability(sf, ["theta", "r_P3", "m0"])),
            ("observability", "force, y = (z', r_P1, r_P3, m0)",
             gc.observability(sf, ["z_prime", "r_P1", "r_P3", "m0"])),
        ]
        for kind, what, r in tests:
            ranks.append({"gamma_deg": gd, "test": kind, "case": what, "rank": r.rank, "n": r.n, "tol": r.tol,
                          "pbh_min": float(np.min(r.pbh_min)), "failing": r.uncontrollable_modes})

    progress("thesis eigenvalue 0.099 +- 2.325i: nearest member of the r_bh family")
    grid = np.linspace(*s.nearest_grid)
    dists = []
    for r in grid:
        lam = gc.uncontrolled_eigs(veh, s.speed, math.radians(-45), r_bh=r)
        dists.append(np.min(np.abs(lam - THESIS_EIG_M45)))
    k = int(np.argmin(dists))
    nearest = {"r_bh": float(grid[k]), "distance": float(dists[k])}

    g_down, g_up = glides[-45.0], glides[45.0]
    # 2.3.1 claim: mass motion on the body-3 axis alone cannot give both up and down glides
    a_perp = g_down.r_p1 * math.cos(g_down.theta) + g_down.r_p3 * math.sin(g_down.theta)
    rp3_axis = a_perp / math.sin(g_down.theta)
    d3 = gc.steady_glide(veh, s.speed, math.radians(-45), r_p3=rp3_axis)
    u3 = gc.steady_glide(veh, s.speed, math.radians(45), r_p3=rp3_axis)
    axis3 = {"r_p3": rp3_axis, "r_p1_down": d3.r_p1, "r_p1_up": u3.r_p1,
             "max_re_down": float(np.max(_eta_r_block(veh, d3).real)),
             "max_re_up": float(np.max(_eta_r_block(veh, u3).real))}

    progress(f"root locus over r_bh (Fig 2.7), {s.rbh_grid[2]} points")
    rbh = gc.rbh_locus(veh, s.speed, math.radians(-45), np.linspace(*s.rbh_grid))
    progress("eigenvalues versus mbar (0.257 kg statement)")
    mgrid = np.geomspace(*s.mbar_grid)
    mb = gc.mbar_locus(veh, s.speed, math.radians(-45), mgrid, r_p3=s.r_p3)
    mb0 = gc.mbar_locus(veh, s.speed, math.radians(-45), mgrid, r_bh=0.0)

    progress("LQR and pole placement on the glide path (z' included); nonlinear recovery simulations")
    lqr = gc.lqr_glide(veh, g_down)
    plc = gc.place_glide(veh, g_down, s.place_poles)
    model = gc.LongitudinalGlider(veh)
    offsets = dict(s.recovery_offsets)
    recovery: dict[tuple[str, float], gc.Simulation] = {}
    for c in (lqr, plc):
        for off in offsets[c.method]:
            x0 = g_down.force_state()
            x0[1] = off / math.cos(g_down.gamma)  # start off the path by z' = off (x = 0)
            recovery[(c.method, off)] = gc.simulate(
                model, x0, s.recovery_horizon, c,
                stop=lambda t, x, c=c, off=off: s.diverged_zp * off - abs(float(c.reduced_state(x)[0])))

    progress("decoupled acceleration feedback (2.37) and the -45 -> +45 deg switch (Fig 2.8)")
    kd = s.k_diag
    K_printed = -gc.decoupled_gain_matrix(*kd)  # w = +K (zeta - zeta_e) as printed, i.e. -(-K)
    fb_printed = gc.DecoupledAccelerationFeedback(K_printed, (g_down,))
    fb = gc.DecoupledAccelerationFeedback(gc.decoupled_gain_matrix(*kd), (g_down, g_up), (0.0, s.switch_time))
    switch = gc.simulate(gc.AccelerationControlledGlider(veh), g_down.accel_state(), s.switch_horizon, fb,
                         t_eval=np.linspace(0, s.switch_horizon, s.switch_samples))
    return Ch2Results(s, veh, (lo, hi), glides, uncontrolled, accel, ranks, nearest, axis3, rbh, mb, mb0, lqr, plc,
                      recovery, fb_printed.zeta_closed_loop_poles, fb.zeta_closed_loop_poles, switch,
                      (g_down, g_up))


# ---------------------------------------------------------------------------------------------- figures
def figures(res: Ch2Results) -> dict[str, tuple[Any, str]]:
    """Figures of the study: ``{stem: (figure, caption)}``."""
    out: dict[str, tuple[Any, str]] = {}
    veh, s = res.vehicle, res.settings

    # glide family vs gamma
    fig, ax = new_figure(1, 2, width=9, height=3.6)
    lo, hi = res.permissible
    n = s.family_points
    for rng in (np.linspace(-89.0, math.degrees(lo) - 0.05, n), np.linspace(math.degrees(hi) + 0.05, 89.0, n)):
        gl = [gc.steady_glide(veh, s.speed, math.radians(gd), r_p3=s.r_p3) for gd in rng]
        ax[0].plot(rng, [math.degrees(g.alpha) for g in gl], "C0")
        ax[1].plot(rng, [g.m0 for g in gl], "C1")
    for a in ax:
        a.axvspan(math.degrees(lo), math.degrees(hi), color="0.85", label="no steady glide (2.26)")
        a.set_xlabel(r"flight-path angle $\gamma$ [deg]")
        a.grid(True, alpha=0.3)
    ax[0].set_ylabel(r"angle of attack $\alpha$ [deg]")
    ax[1].set_ylabel(r"net buoyancy $m_0$ [kg]")
    ax[0].legend(fontsize=8)
    out["glide_family"] = (fig, f"ROGUE steady glides at V = {s.speed} m/s: angle of attack and net buoyancy "
                           f"versus flight-path angle; the shaded band |gamma| < {math.degrees(hi):.3f} deg is "
                           "outside the reconstructed permissible set (2.26). No thesis figure.")

    fig, ax = new_figure(1, 2, width=10.5, height=4.2)
    res.rbh.plot(ax=ax[0], zoom=(-1.1, -0.4, -0.25, 0.25))
    res.rbh.plot(ax=ax[1], kind="real")
    ax[0].set_title(r"eigenvalues of $\partial q_r/\partial \eta_r$, $r_{bh}$ as gain", fontsize=9)
    ax[1].set_title("real parts versus bottom-heaviness", fontsize=9)
    out["fig2_7_rbh_locus"] = (fig, "Analogue of Fig 2.7: eigenvalues of dq_r/deta_r of the acceleration-"
                               "controlled ROGUE (2.35) at the -45 deg, 0.3 m/s glide versus r_bh "
                               f"({s.rbh_grid[2]} points, branches matched). Left: root locus coloured by r_bh; "
                               "right: real parts. The stability boundary is r_bh = "
                               f"{res.rbh.crossings[0]:.5f} m (thesis: {THESIS_RBH_BOUNDARY} m).")

    fig, ax = new_figure(1, 1, width=7, height=3.8)
    for j in range(res.mbar.branches.shape[1]):
        ax.semilogx(res.mbar.values, res.mbar.branches[:, j].real, lw=1.6)
    ax.axhline(0, color="0.3", ls="--", lw=0.8)
    for c in res.mbar.crossings:
        ax.axvline(c, color="C3", lw=0.8)
    ax.axvline(veh.mbar, color="k", ls=":", lw=1, label=r"ROGUE $\bar m$ = 2 kg")
    ax.set_xlabel(r"moving mass $\bar m$ [kg]")
    ax.set_ylabel(r"Re $\lambda$ [1/s]")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3, which="both")
    out["mbar_locus"] = (fig, "Real parts of the nonzero eigenvalues of the uncontrolled ROGUE (u = 0) at the -45 deg,"
                         " 0.3 m/s glide versus the moving mass, r_P3 = 0.05 m held fixed (red lines: sign changes "
                         f"of max Re, at {', '.join(f'{c:.4g}' for c in res.mbar.crossings)} kg). Supports the "
                         "0.257 kg statement of 2.3.1; no thesis figure.")

    fig, ax = new_figure(4, 1, width=7, height=7.2, sharex=True)
    for k, ((name, off), sim) in enumerate(res.recovery.items()):
        c = res.lqr if name == "lqr" else res.place
        zp = c.reduced_state(sim.x)[:, 0]
        tag = "LQR" if name == "lqr" else "placement"
        lab = f"{tag}, z'(0) = {off:g} m" + (f" (diverged, stopped at {sim.stopped_at:.1f} s)"
                                             if sim.stopped_at is not None else "")
        ax[0].plot(sim.t, zp / off, color=f"C{k}", label=lab)
        for a, u in zip(ax[1:], ("u1", "u3", "u4"), strict=True):
            a.plot(sim.t, sim.state(u), color=f"C{k}")
    ax[0].set_ylim(-1.5, 1.5)
    # input axes scaled to the runs that converged (a diverging run leaves the axes)
    ok = [sim for sim in res.recovery.values() if sim.stopped_at is None]
    for a, u in zip(ax[1:], ("u1", "u3", "u4"), strict=True):
        lim = 1.2 * max(float(np.max(np.abs(sim.state(u)))) for sim in ok) if ok else 1.0
        a.set_ylim(-lim, lim)
    ax[0].set_ylabel(r"$z'/z'(0)$ [-]")
    ax[1].set_ylabel(r"$u_1$ [N]")
    ax[2].set_ylabel(r"$u_3$ [N]")
    ax[3].set_ylabel(r"$u_4$ [kg/s]")
    ax[3].set_xlabel("t [s]")
    for a in ax:
        a.grid(True, alpha=0.3)
    ax[0].legend(fontsize=8)
    out["glide_path_recovery"] = (fig, "Nonlinear ROGUE (force inputs) under the LQR and pole-placement laws "
                                  "designed on the linearization with z' (2.30), recovering the -45 deg glide path "
                                  "from an offset z'(0) (z' normalized by it; input axes scaled to the converging "
                                  "runs). "
                                  + _recovery_summary(res) + " No thesis figure.")

    sim = res.switch
    fig = plt.figure(figsize=(10, 6.5), layout="constrained")
    gs = fig.add_gridspec(3, 2)
    axp = fig.add_subplot(gs[:, 0])
    axp.plot(sim.state("x"), sim.state("z"), "C0")
    i5 = int(np.searchsorted(sim.t, s.switch_time))
    axp.plot(sim.state("x")[i5], sim.state("z")[i5], "o", color="C3", label=f"switch at t = {s.switch_time:g} s")
    axp.invert_yaxis()
    axp.set_aspect("equal", adjustable="datalim")
    axp.set_xlabel("x [m]")
    axp.set_ylabel("z [m] (down)")
    axp.legend(fontsize=8)
    axp.grid(True, alpha=0.3)
    th = sim.state("theta")
    alpha = np.arctan2(sim.state("v3"), sim.state("v1"))
    axes = [fig.add_subplot(gs[k, 1]) for k in range(3)]
    axes[0].plot(sim.t, np.degrees(th), label=r"$\theta$")
    axes[0].plot(sim.t, np.degrees(th - alpha), label=r"$\gamma$")
    axes[0].plot(sim.t, np.degrees(alpha), label=r"$\alpha$")
    axes[0].set_ylabel("angle [deg]")
    axes[0].legend(fontsize=8, ncol=3)
    axes[1].plot(sim.t, 100 * sim.state("r_P1"), label=r"$r_{P1}$")
    axes[1].plot(sim.t, 100 * sim.state("r_P3"), label=r"$r_{P3}$")
    axes[1].set_ylabel("moving-mass position [cm]")
    axes[1].legend(fontsize=8)
    axes[2].plot(sim.t, sim.state("m0"), "C2", label=r"$m_0$")
    ax2 = axes[2].twinx()
    ax2.plot(sim.t, np.hypot(sim.state("v1"), sim.state("v3")), "C4", label="V")
    axes[2].set_ylabel(r"$m_0$ [kg]", color="C2")
    ax2.set_ylabel("V [m/s]", color="C4")
    axes[2].set_xlabel("t [s]")
    for a in axes:
        a.grid(True, alpha=0.3)
    out["fig2_8_glide_switch"] = (fig, "Analogue of Fig 2.8: acceleration-controlled ROGUE with the decoupled "
                                  "feedback (2.37), K corrected to w = -K(zeta - zeta_e) with gains "
                                  "100*[1 3 1 3 0.5] (PD on each mass axis, P on buoyancy), switching from the "
                                  "-45 deg to the +45 deg glide (0.3 m/s, r_P3 = 0.05 m) at "
                                  f"t = {s.switch_time:g} s.")
    return out


# ---------------------------------------------------------------------------------------------- report
def _recovery_outcome(res: Ch2Results, key: tuple[str, float]) -> str:
    sim = res.recovery[key]
    s = res.settings
    if sim.stopped_at is not None:
        return f"diverges (|z'| > {s.diverged_zp:g} z'(0) at t = {sim.stopped_at:.1f} s)"
    c = res.lqr if key[0] == "lqr" else res.place
    return (f"converges (|z'({s.recovery_horizon:g} s)| = "
            f"{abs(float(c.reduced_state(sim.x[-1])[0])):.1e} m)")


def _recovery_summary(res: Ch2Results) -> str:
    parts = [f"{'LQR' if m == 'lqr' else 'placement'} from {off:g} m {_recovery_outcome(res, (m, off))}"
             for (m, off) in res.recovery]
    return "; ".join(parts) + "."


def _pairs(lam: np.ndarray) -> list[list[float]]:
    lam = np.asarray(lam)
    lam = lam[np.lexsort((-lam.imag, -lam.real))]
    return [[float(z.real), float(z.imag)] for z in lam]


def report(res: Ch2Results) -> Report:
    """Assemble the report (numbers with thesis values, tables, figures, notes)."""
    s = res.settings
    rep = Report(TITLE, vehicle=[res.vehicle], reference=BHATTA_2006)
    lo, hi = res.permissible
    rep.number("permissible_gamma_deg", math.degrees(hi), "deg", "(2.26) reconstructed, 2.3",
               note="(2.26) is missing from the text; reconstructed from the lift/drag model: |tan gamma| >= "
                    "2 K_D alpha*/K_L with alpha* = sqrt(K_D0/K_D) for K_L0 = 0. Down glides need gamma < "
                    f"{math.degrees(lo):.4f} deg, up glides gamma > {math.degrees(hi):.4f} deg. No printed value.")
    rep.number("r_P3_choice_m", s.r_p3, "m", "our choice",
               note="The thesis does not state which member of the r_P family its ROGUE numbers use; every "
                    f"equilibrium here has r_P3 = 0.05 m (r_bh = {res.glides[-45.0].r_bh:.4f} m at -45 deg).")
    ev = res.uncontrolled[-45.0]
    rep.number("eig_uncontrolled_m45", _pairs(ev), "1/s", "2.3.1",
               published=[[THESIS_EIG_M45.real, THESIS_EIG_M45.imag], [THESIS_EIG_M45.real, -THESIS_EIG_M45.imag]],
               verdict=False,
               note="Nonzero eigenvalues of the uncontrolled (u1 = u3 = u4 = 0) ROGUE at -45 deg, 0.3 m/s, "
                    "r_P3 = 0.05 m. The thesis's unstable pair 0.099 +- 2.325i is NOT reproduced: with our r_P3 all "
                    "modes are stable. Scanning the whole family r_bh in [-0.1, 0.15] m, the closest eigenvalue to "
                    f"0.099+2.325i is {res.nearest_thesis_eig['distance']:.3f} 1/s away (at r_bh = "
                    f"{res.nearest_thesis_eig['r_bh']:.4f} m), so no member of the family reproduces it with the "
                    "printed parameters and K_L0 = K_M0 = 0. Unstated parameters (K_L0, K_M0, g) or a different "
                    "model in [6] are possible causes; we do not fit them.")
    rep.number("rbh_stability_boundary_m", res.rbh.crossings[0], "m", "2.3.2, Fig 2.7", published=THESIS_RBH_BOUNDARY,
               tolerance=s.repro_tol,
               note="Located by Brent's method on max Re(lambda) of dq_r/deta_r (xtol 1e-13). The thesis's "
                    "'approximately -0.0068 m' is 12 % away; the boundary depends on K_L0 and K_M0, which 2.3.1 "
                    "does not print (we take 0).")
    for bp, lab in zip(res.rbh.breakpoints, ("A", "B"), strict=False):
        rep.number(f"rbh_{bp.kind.replace('-', '_')}_{lab}_m", bp.parameter, "m", "2.3.2, Fig 2.7 point " + lab,
                   note=f"{bp.kind}: two real eigenvalues meet at lambda = {bp.eigenvalue:.4f} 1/s. The thesis "
                        "names A and B 'break in and break away points respectively', the reverse of the usual "
                        "root-locus names (and of chapter 8's usage); we use the usual ones: real -> complex "
                        "with increasing r_bh is break-away.")
    rep.number("mbar_threshold_kg", res.mbar.crossings[0], "kg", "2.3.1", published=THESIS_MBAR_THRESHOLD,
               tolerance=s.repro_tol,
               note="Smallest mbar at which max Re of the nonzero uncontrolled eigenvalues crosses zero "
                    "(r_P3 = 0.05 m held fixed, glide re-trimmed at each mbar). Holding r_bh = 0 instead gives "
                    f"{res.mbar_rbh0.crossings[0]:.4f} kg. Further crossings at "
                    f"{', '.join(f'{c:.4f}' for c in res.mbar.crossings[1:])} kg: the stability in mbar is not "
                    "a single threshold, and ROGUE's mbar = 2 kg is stable at -45 deg with r_P3 = 0.05 m "
                    "(see uncontrolled_unstable_glides_deg).")
    unstable = [gd for gd, lam in res.uncontrolled.items() if np.max(lam.real) > 0]
    rep.number("uncontrolled_unstable_glides_deg", unstable, "deg", "2.3.1", published=list(res.glides),
               verdict=sorted(unstable) == sorted(res.glides),
               note="Glides (r_P3 = 0.05 m) whose uncontrolled linearization (u = 0) has an eigenvalue with positive "
                    "real part. The thesis says all four have a slow unstable mode. Here: " + "; ".join(
                        f"{gd:+.0f} deg max Re = {np.max(lam.real):.4f} 1/s" for gd, lam in res.uncontrolled.items())
                    + ". The up glides' unstable mode is real and not slow (about 2 1/s); the up/down spectra "
                    "differ because no sign change of the states maps the equations (2.15)-(2.25) onto "
                    "themselves with gamma -> -gamma (only the steady-glide equations are symmetric; checked "
                    "exhaustively in tests/test_longitudinal.py). The thesis's r_P choice is not stated "
                    "(see r_P3_choice_m).")
    rep.number("lqr_closed_loop_poles", _pairs(res.lqr.closed_loop_poles), "1/s", "our design",
               note="LQR with Bryson weights (glidectl.controllers.linear.DEFAULT_MAX_DEVIATION) on the force "
                    "model with z'.")
    rep.number("place_closed_loop_poles", _pairs(res.place.closed_loop_poles), "1/s", "our design",
               note="Real poles spread over [-3, -0.15] 1/s (control.place).")
    for (m, off), sim in res.recovery.items():
        c = res.lqr if m == "lqr" else res.place
        rep.number(f"recovery_{m}_{off:g}m_final_zprime", float(c.reduced_state(sim.x[-1])[0]), "m", "our design",
                   note=f"Nonlinear closed loop from z'(0) = {off:g} m: {_recovery_outcome(res, (m, off))}. "
                        "Both laws are linearly stable (all closed-loop poles in the left half plane); whether "
                        "the nonlinear glider returns to the path depends on the offset, so the linear design "
                        "alone does not certify a useful region of attraction.")
    rep.number("K_printed_zeta_poles", _pairs(res.k_printed_poles), "1/s", "(2.37), 2.3.2",
               note="K = diag(100*[1 3 1 3 0.5]) cannot multiply zeta (5) to give w (3) as printed; read as PD on "
                    "each mass axis and P on m0 with w = +K(zeta - zeta_e) as printed, A + BK has eigenvalues "
                    "with positive real part (it is positive feedback). The stabilizing structure is "
                    "w = -K(zeta - zeta_e) with K = [[100, 300, 0, 0, 0], [0, 0, 100, 300, 0], [0, 0, 0, 0, 50]].")
    rep.number("K_corrected_zeta_poles", _pairs(res.k_corrected_poles), "1/s", "(2.37) corrected")
    sim = res.switch
    g_up = res.switch_glides[1]
    err = float(np.max(np.abs(sim.x[-1, 2:] - g_up.accel_state()[2:])))
    rep.number("switch_final_state_error", err, "SI", "Fig 2.8",
               note=f"max |x({s.switch_horizon:g} s) - x_e(+45 deg)| over theta, Omega2, v1, v3, zeta after the "
                    "switch.")
    rep.number("axis3_sawtooth_r_p3_m", res.axis3_sawtooth["r_p3"], "m", "2.3.1 claim",
               note="2.3.1 says mass motion restricted to the body-3 axis does not allow both up and down glides. "
                    "With r_P1 = 0 the +-45 deg, 0.3 m/s glides both exist with r_P3 = "
                    f"{res.axis3_sawtooth['r_p3']:.5f} m (r_P1 = {res.axis3_sawtooth['r_p1_down']:.2e} / "
                    f"{res.axis3_sawtooth['r_p1_up']:.2e} m), differing only in m0, and both are stable under "
                    f"acceleration control (max Re = {res.axis3_sawtooth['max_re_down']:.3f} / "
                    f"{res.axis3_sawtooth['max_re_up']:.3f} 1/s): for this symmetric vehicle (K_L0 = K_M0 = 0) the "
                    "claim is not reproduced; it needs the r_P1 of a particular glide to be kept.")

    rows = []
    for gd, g in res.glides.items():
        rows.append([f"{gd:+.0f}", f"{g.speed:.3f}", f"{math.degrees(g.alpha):.4f}", f"{math.degrees(g.theta):.4f}",
                     f"{g.m0:.5f}", f"{100 * g.r_p1:.4f}", f"{100 * g.r_p3:.4f}", f"{100 * g.r_bh:.4f}",
                     f"{g.residual:.1e}"])
    rep.table("Steady glides of ROGUE (V = 0.3 m/s, r_P3 = 5 cm chosen)",
              ["gamma [deg]", "V [m/s]", "alpha [deg]", "theta [deg]", "m0 [kg]", "r_P1 [cm]", "r_P3 [cm]",
               "r_bh [cm]", "residual"], rows)
    erows = []
    for gd in res.glides:
        erows.append([f"{gd:+.0f}", "uncontrolled, u = 0",
                      "; ".join(f"{z.real:.4f}{z.imag:+.4f}i" for z in sorted(res.uncontrolled[gd],
                                                                            key=lambda z: -z.real))])
        erows.append([f"{gd:+.0f}", "dq_r/deta_r (acceleration)",
                      "; ".join(f"{z.real:.4f}{z.imag:+.4f}i" for z in sorted(res.accel_eta_r[gd],
                                                                            key=lambda z: -z.real))])
    rep.table("Eigenvalues [1/s] at the four glides (structural zeros removed)", ["gamma [deg]", "matrix",
                                                                                 "eigenvalues"], erows)
    rrows = [[f"{r['gamma_deg']:+.0f}", r["test"], r["case"], f"{r['rank']}/{r['n']}", f"{r['tol']:.1e}",
              f"{r['pbh_min']:.2e}", ", ".join(f"{z.real:.3g}" for z in np.unique(np.round(r["failing"], 9)))]
             for r in res.ranks]
    rep.table("Controllability / observability (Kalman rank on balanced (A, B) with tolerance; PBH margins)",
              ["gamma", "test", "case", "rank", "tol", "min PBH", "failing eigenvalues"], rrows)
    for stem, (fig, cap) in figures(res).items():
        rep.figure(stem, fig, cap)
    rep.text("Method and reproduction policy", (
        "All equilibria are closed-form (module glidectl.trim.glide) and checked by evaluating the one right-hand "
        "side (glidectl.models.longitudinal.LongitudinalGlider.rhs); residuals are printed in the table. "
        "Jacobians are exact (complex step, glidectl.derivatives) and tested against central differences. "
        "\n\nA thesis number counts as reproduced when our value is within 1 % of the printed one (the same rule "
        "for every number; printed values have 2-4 significant digits and several ROGUE parameters are not "
        "printed). Parameters were never adjusted to approach a printed value.\n\n"
        "Corrections to the text used here: (2.32) has the wrong sign on Z (derived: Z = -[X1/m1 + rdot_P3 Om + "
        "r_P3 Y/J2, X3/m3 - rdot_P1 Om - r_P1 Y/J2]); a test pins that rddot_P = w. (2.26) is missing and is "
        "reconstructed. (2.28) returns theta, not gamma. The gain K of (2.37) must be applied as "
        "w = -K(zeta - zeta_e) with a 3 x 5 PD/P structure. J2 is printed in Nm^2 (kg m^2 meant). K_L0 and K_M0 "
        "of ROGUE are not printed and are taken as 0."))
    return rep


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The chapter-2 design: compute everything, then assemble the report (not written here)."""
    res = compute(QUICK if quick else FULL, progress)
    progress("figures and report")
    return report(res)


if __name__ == "__main__":
    run_script(__file__)
