"""Design study for chapter 8: three-dimensional steady motions of the Slocum-like glider (Table 8.1), the §8.2.2
simulation converging to a circular helix (Fig 8.2-8.4), helix maps versus the control parameters (Fig 8.5-8.12),
stability versus bottom-heaviness (Fig 8.13-8.14) and inverse helix design.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..analysis.helix_maps import ExistenceScan, HelixSweep, existence_scan, helix_sweep
from ..analysis.helix_stability import HelixRbhLocus, helix_rbh_locus, resolved_crossing
from ..errors import InfeasibleGlideError
from ..models.glider3d import FixedMassGlider3D, R_to_ypr, quat_to_R, ypr_to_quat
from ..params import Vehicle, load_vehicle
from ..report.document import Report
from ..sim import Simulation, simulate
from ..trim.helix import Helix, classify_motion, helix_trim
from ..trim.helix_design import HelixDesign, design_helix
from . import ch8_claims

NAME = "ch8_helix"
TITLE = "Chapter 8: circular helices of a Slocum-like glider, their maps, stability and inverse design"

REPRO_TOL = 0.01
R_P = (0.02, 0.02, 0.04)  # m, §8.2.2
M0 = 0.25  # kg
SIM_X0_YPR_DEG = (0.0, -26.654, 14.419)
SIM_V0 = (0.802, 0.014, 0.025)
SIM_OMEGA0 = (0.0046, 0.0025, 0.0077)
SIM_T = 2000.0
RBH_R_P = (0.02, -0.02, 0.04)  # §8.3 nominal
RBH_GRID = np.linspace(-0.03, 0.10, 261)
DESIGN_TARGETS: tuple[dict[str, float], ...] = (
    {"radius": 50.0, "pitch": 150.0}, {"radius": 30.0, "speed": 0.6}, {"radius": 50.0, "pitch": -150.0},
    {"radius": 1.0, "pitch": 1000.0},
)
THESIS_TYPOS: tuple[tuple[str, str, str, str, str], ...] = (
    ("typo_2_5_torque", "(2.5)", "Tbar = (J Omega + r_P^ P_P) x Omega + ...",
     "Tbar = J Omega x Omega + r_P x (P_P x Omega) + ...",
     "The literal form differs by P_P x (Omega x r_P); it disagrees with the longitudinal (2.20) in the plane and "
     "with the fixed-mass (8.25), both of which the corrected form reproduces (tests/test_glider3d.py)."),
    ("typo_2_6_ppdot", "(2.6)", "P_P = ubar", "dP_P/dt = ubar",
     "The time derivative is missing: (2.6) is the moving-mass momentum equation."),
    ("typo_table_8_2_2", "8.2.2", "vehicle parameters as indicated in Table 8.2.2", "Table 8.1",
     "There is no Table 8.2.2; the parameters are those of Table 8.1 (vehicles/slocum_ch8.toml)."),
    ("typo_8_3_rbh_equilibrium", "8.3", "the bottom-heaviness parameter does not affect the relative equilibrium",
     "it does", "Changing r_bh at fixed r_P1, r_P2 (moving r_P along R^T k) leaves the gravity moment "
     "r_P x (mbar g zeta) unchanged, but r_P also enters the inertia coupling mbar r_P x (v + Omega x r_P) of (8.23)-"
     "(8.25); the frozen state has residual up to the value in rbh_bifurcation_m's note and the re-solved branch "
     "moves (rbh_bifurcation_resolved_m)."),
)
THESIS_HELIX = {"helix_radius_m": 66.60, "helix_speed_mps": 0.729, "helix_pitch_m": 206.2, "helix_period_s": 639.6}


@dataclass(frozen=True)
class Ch8Results:
    vehicle: Vehicle
    helix: Helix
    sim: Simulation
    theorem7: list[tuple[str, str, float, float]]
    rbh_frozen: HelixRbhLocus
    rbh_resolved: HelixRbhLocus
    resolved_cross: float | None
    resolved_helix: Helix
    designs: list[tuple[dict[str, float], HelixDesign | None, str]]
    maps: dict[str, HelixSweep]
    scan: ExistenceScan
    claims: tuple[ch8_claims.Claim, ...]


def compute(progress: Callable[[str], None] = lambda s: None) -> Ch8Results:
    """Run every computation of the chapter-8 study."""
    veh = load_vehicle("slocum_ch8")
    progress("helix trim at r_P = (2, 2, 4) cm, m0 = 0.25 kg (8.2.2)")
    h = helix_trim(veh, R_P, M0)
    progress(f"{SIM_T:.0f} s simulation from the printed initial conditions (Fig 8.2-8.4)")
    model = FixedMassGlider3D(veh, R_P, M0)
    q0 = ypr_to_quat(*np.radians(SIM_X0_YPR_DEG))
    x0 = np.r_[0.0, 0.0, 0.0, q0, SIM_V0, SIM_OMEGA0]
    sim = simulate(model, x0, SIM_T, t_eval=np.linspace(0.0, SIM_T, 8001))
    v, Om = h.v, h.Omega
    th7 = [("steady helix of 8.2.2", *_cls(v, Om)), ("Omega = 0", *_cls(v, 0 * Om)),
           ("v = 0", *_cls(0 * v, Om)), ("Omega parallel to v", *_cls(v, 0.01 * v / np.linalg.norm(v)))]

    progress("stability versus bottom-heaviness (Fig 8.13-8.14): frozen and re-solved equilibria")
    fro = helix_rbh_locus(veh, RBH_R_P, M0, RBH_GRID, frozen=True)
    res = helix_rbh_locus(veh, RBH_R_P, M0, RBH_GRID, frozen=False)
    rc, rh = resolved_crossing(veh, RBH_R_P, M0)

    progress("inverse helix design")
    designs: list[tuple[dict[str, float], HelixDesign | None, str]] = []
    for tgt in DESIGN_TARGETS:
        try:
            designs.append((tgt, design_helix(veh, **tgt), ""))
        except InfeasibleGlideError as exc:
            designs.append((tgt, None, str(exc)))
    with ProcessPoolExecutor(max_workers=max(1, min(4, os.cpu_count() or 1))) as ex:
        progress("helix maps versus r_P1, r_P2, r_P3, m0 (Fig 8.5-8.12)")
        maps = compute_maps(veh, ex)
        progress("existence scan of the (m0, r_P1) sign claim of 8.2.2")
        scan = existence_scan(veh, SCAN_R_P1, SCAN_M0, n_starts=SCAN_STARTS, executor=ex)
    claims = (ch8_claims.existence_claim(scan), *ch8_claims.r_p1_claims(veh, maps["fig8_5"], maps["fig8_6"]),
              *ch8_claims.r_p2_claims(maps["fig8_7"], maps["fig8_8"]),
              *ch8_claims.r_p3_claims(veh, maps["fig8_9"], maps["fig8_10"]),
              *ch8_claims.m0_claims(maps["fig8_11"], maps["fig8_12"]))
    return Ch8Results(veh, h, sim, th7, fro, res, rc, rh, designs, maps, scan, claims)


def _cls(v: np.ndarray, Om: np.ndarray) -> tuple[str, float, float]:
    c = classify_motion(v, Om)
    return c["kind"], c["curvature"], c["torsion"]


def compute_maps(veh: Vehicle, executor: Executor | None = None) -> dict[str, HelixSweep]:
    """The eight helix maps of Fig 8.5-8.12 (:data:`MAP_CASES`), by continuation."""
    return {key: helix_sweep(veh, param, values, r_p=r_p, m0=m0, executor=executor)
            for key, (param, values, r_p, m0) in MAP_CASES.items()}


MAP_CASES: dict[str, tuple[str, np.ndarray, tuple[float, float, float], float]] = {
    "fig8_5": ("r_P1", np.linspace(0.002, 0.06, 59), (0.02, 0.02, 0.04), 0.25),
    "fig8_6": ("r_P1", np.linspace(-0.06, -0.002, 59), (-0.02, 0.02, 0.04), -0.25),
    "fig8_7": ("r_P2", np.linspace(-0.05, 0.05, 101), (0.02, 0.02, 0.04), 0.25),
    "fig8_8": ("r_P2", np.linspace(-0.05, 0.05, 101), (-0.02, 0.02, 0.04), -0.25),
    "fig8_9": ("r_P3", np.linspace(0.0, 0.10, 101), (0.02, 0.02, 0.04), 0.25),
    "fig8_10": ("r_P3", np.linspace(0.0, 0.10, 101), (-0.02, 0.02, 0.04), -0.25),
    "fig8_11": ("m0", np.linspace(0.05, 0.6, 56), (0.02, 0.02, 0.04), 0.25),
    "fig8_12": ("m0", np.linspace(-0.6, -0.05, 56), (-0.02, 0.02, 0.04), -0.25),
}
SCAN_R_P1 = np.linspace(-0.04, 0.04, 9)  # m
SCAN_M0 = np.array([-0.5, -0.25, -0.1, 0.1, 0.25, 0.5])  # kg
SCAN_STARTS = 30
MAP_TITLES = {"fig8_5": "r_P1, m0 > 0", "fig8_6": "r_P1, m0 < 0", "fig8_7": "r_P2, m0 > 0", "fig8_8": "r_P2, m0 < 0",
              "fig8_9": "r_P3, m0 > 0", "fig8_10": "r_P3, m0 < 0", "fig8_11": "m0 > 0", "fig8_12": "m0 < 0"}


# ---------------------------------------------------------------------------------------------- figures
def figures(res: Ch8Results) -> dict[str, tuple[Any, str]]:
    from matplotlib import pyplot as plt

    from ..report.figures import new_figure

    out: dict[str, tuple[Any, str]] = {}
    sim, h = res.sim, res.helix
    fig = plt.figure(figsize=(7.5, 6.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    ax.plot(sim.state("x"), sim.state("y"), sim.state("z"), lw=1.0)
    ax.plot([0], [0], [0], "ko", ms=4)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m] (down)")
    ax.invert_zaxis()
    out["fig8_2_trajectory"] = (fig, f"Analogue of Fig 8.2: {SIM_T:.0f} s simulation of the fixed-mass glider "
                                "(8.23) from the printed initial conditions, r_P = (2, 2, 4) cm, m0 = 0.25 kg; it "
                                "converges to the "
                                f"helix of radius {h.radius:.2f} m and pitch {h.pitch:.1f} m (z axis points down).")
    ypr = R_to_ypr(quat_to_R(sim.x[:, 3:7]))
    m = sim.t <= 300.0
    fig, axs = new_figure(3, 2, width=9, height=7, sharex=True)
    for a, (lab, y) in zip(axs[:, 0], (("x [m]", sim.state("x")), ("y [m]", sim.state("y")),
                                       ("z [m] (down)", sim.state("z"))), strict=True):
        a.plot(sim.t[m], y[m])
        a.set_ylabel(lab)
    for a, (lab, k) in zip(axs[:, 1], ((r"yaw $\psi$ [deg]", 0), (r"pitch $\theta$ [deg]", 1),
                                       (r"roll $\varphi$ [deg]", 2)), strict=True):
        a.plot(sim.t[m], np.degrees(np.unwrap(ypr[m, k])))
        a.set_ylabel(lab)
    axs[1, 1].axhline(math.degrees(h.theta), color="C1", ls="--", lw=1, label="helix")
    axs[2, 1].axhline(math.degrees(h.phi), color="C1", ls="--", lw=1)
    axs[1, 1].legend(fontsize=8)
    for a in axs[-1]:
        a.set_xlabel("t [s]")
    for a in axs.flat:
        a.grid(True, alpha=0.3)
    out["fig8_3_position_orientation"] = (fig, "Analogue of Fig 8.3: position and YPR attitude (8.26), first 300 s; "
                                          "dashed: the steady helix's pitch and roll.")
    fig, axs = new_figure(3, 2, width=9, height=7, sharex=True)
    for k in range(3):
        axs[k, 0].plot(sim.t[m], sim.x[m, 7 + k])
        axs[k, 0].axhline(h.v[k], color="C1", ls="--", lw=1)
        axs[k, 0].set_ylabel(f"$v_{k + 1}$ [m/s]")
        axs[k, 1].plot(sim.t[m], sim.x[m, 10 + k])
        axs[k, 1].axhline(h.Omega[k], color="C1", ls="--", lw=1)
        axs[k, 1].set_ylabel(f"$\\Omega_{k + 1}$ [rad/s]")
    for a in axs[-1]:
        a.set_xlabel("t [s]")
    for a in axs.flat:
        a.grid(True, alpha=0.3)
    out["fig8_4_velocities"] = (fig, "Analogue of Fig 8.4: body velocity and angular velocity, first 300 s; dashed: "
                                "the steady helix.")

    for key, sw in res.maps.items():
        out[key] = _map_figure(sw, key)
    out["fig8_existence_scan"] = _scan_figure(res.scan)

    from ..report.figures import plot_locus, plot_locus_real

    fig, axs = new_figure(1, 2, width=10, height=4.4)
    plot_locus_real(res.rbh_frozen.locus, axs[0])
    axs[0].set_title("equilibrium frozen at the nominal r_bh (as 8.3)", fontsize=9)
    plot_locus_real(res.rbh_resolved.locus, axs[1])
    axs[1].set_title("equilibrium re-solved at every r_bh", fontsize=9)
    for a in axs:
        a.axvline(res.rbh_frozen.nominal.r_bh, color="k", ls=":", lw=0.8)
    out["fig8_13_rbh_real_parts"] = (fig, "Analogue of Fig 8.13: real parts of the eigenvalues of the reduced helix "
                                     "linearization (position and yaw dropped) versus r_bh; r_P = (2, -2, 4) cm, "
                                     "m0 = 0.25 kg (dotted: nominal r_bh). Left, the thesis's frozen equilibrium; "
                                     "right, re-solved (continuation from the nominal point).")
    fig, ax = new_figure(1, 1, width=7, height=5)
    plot_locus(res.rbh_frozen.locus, ax, zoom=None)
    ax.set_xlim(-0.3, 0.05)
    ax.set_ylim(-0.1, 0.1)
    out["fig8_14_rbh_locus"] = (fig, "Analogue of Fig 8.14: root locus of the slow eigenvalues versus r_bh (frozen "
                                "equilibrium), zoomed near the imaginary axis; crossings (x) and break points (o, "
                                "lettered; our letters, not the thesis's A-D) located by root finding and bisection.")
    return out


def _map_figure(sw: Any, key: str) -> tuple[Any, str]:
    from ..report.figures import new_figure

    fig, axs = new_figure(2, 3, width=10, height=5.6, sharex=True)
    x = np.asarray(sw.values) * (100.0 if sw.parameter.startswith("r_P") else 1.0)
    xl = f"{sw.parameter} [{'cm' if sw.parameter.startswith('r_P') else 'kg'}]"
    cols = [("radius", "radius [m]", 1.0), ("pitch", "pitch (drop per turn) [m]", 1.0), ("period", "period [s]", 1.0),
            ("speed", "speed V [m/s]", 1.0), ("alpha", r"$\alpha$, $\beta$ [deg]", 180 / math.pi),
            ("theta", r"pitch $\theta$, roll $\varphi$ [deg]", 180 / math.pi)]
    # break the curves where the continuation jumps between branches (folds)
    cut = np.isin(sw.values, sw.branch_jumps)
    xs = np.insert(x, np.flatnonzero(cut) + 1, np.nan)
    unstable = sw.exists & ~sw.stable

    def curve(name: str) -> np.ndarray:
        return np.insert(np.asarray(sw.column(name), float), np.flatnonzero(cut) + 1, np.nan)

    for a, (c, lab, f) in zip(axs.flat, cols, strict=True):
        a.plot(xs, curve(c) * f, "C0", label={"alpha": r"$\alpha$", "theta": r"$\theta$"}.get(c))
        if c == "alpha":
            a.plot(xs, curve("beta") * f, "C1", label=r"$\beta$")
        if c == "theta":
            a.plot(xs, curve("phi") * f, "C1", label=r"$\varphi$")
        if np.any(unstable):
            a.plot(x[unstable], np.asarray(sw.column(c))[unstable] * f, "x", color="C3", ms=4,
                   label="unstable" if c in ("alpha", "theta") else None)
        yv = np.asarray(sw.column(c))
        yv = yv[np.isfinite(yv) & (yv > 0)]
        if c in ("radius", "period") and yv.size and yv.max() > 20 * yv.min():
            a.set_yscale("log")
        if c in ("alpha", "theta"):
            a.legend(fontsize=7)
        a.set_ylabel(lab)
        a.grid(True, alpha=0.3)
    for a in axs[-1]:
        a.set_xlabel(xl)
    n_missing = int(np.sum(~np.asarray(sw.exists)))
    n_unstable = int(np.sum(np.asarray(sw.exists) & (np.asarray(sw.column("max_re_eig")) >= 0)))
    fixed = {k: v for k, v in zip(("r_P1", "r_P2", "r_P3", "m0"), (*MAP_CASES[key][2], MAP_CASES[key][3]),
                                  strict=True) if k != sw.parameter}
    jumps = f" (at {', '.join(f'{v:g}' for v in sw.branch_jumps)})" if sw.branch_jumps.size else ""
    cap = (f"Analogue of Fig {key[3:].replace('_', '.')}: helix parameters versus {MAP_TITLES[key]} "
           f"(fixed: {', '.join(f'{k} = {v:g}' for k, v in fixed.items())}; r_P in m, m0 in kg), by continuation. "
           f"Points without a steady motion: {n_missing}; unstable points (x): {n_unstable}. Radius and period on log "
           "scales when they span more than a factor 20 (infinite at a straight glide); pitch is the drop per turn "
           "(negative: ascending). Curves are broken "
           f"where the continuation jumps between branches{jumps}.")
    return fig, cap


def _scan_figure(scan: ExistenceScan) -> tuple[Any, str]:
    from ..report.figures import new_figure

    fig, ax = new_figure(1, 1, width=7, height=4.8)
    R, M = np.meshgrid(scan.r_P1 * 100, scan.m0)
    cr = scan.claim_region
    # the claim region: m0 > 0 with r_P1 < 0 (upper left) and m0 < 0 with r_P1 > 0 (lower right)
    ax.fill_between([min(scan.r_P1.min(), 0) * 105, 0], 0, max(scan.m0.max(), 0) * 1.1, color="C3", alpha=0.1, lw=0,
                    label="8.2.2: no equilibria here")
    ax.fill_between([0, max(scan.r_P1.max(), 0) * 105], min(scan.m0.min(), 0) * 1.1, 0, color="C3", alpha=0.1, lw=0)
    su = scan.n_stable_upright > 0
    other = scan.exists & ~su
    ax.plot(R[su], M[su], "o", color="C2", label="stable upright motion found")
    ax.plot(R[other], M[other], "^", color="C1", label="motions found, none stable upright")
    ax.plot(R[~scan.exists], M[~scan.exists], "x", color="k", label="no motion found")
    for i, j in zip(*np.nonzero(scan.exists), strict=True):
        ax.annotate(str(int(scan.n_solutions[i, j])), (R[i, j], M[i, j]), textcoords="offset points",
                    xytext=(5, 4), fontsize=7)
    ax.axhline(0, color="k", lw=0.6)
    ax.axvline(0, color="k", lw=0.6)
    ax.set_xlabel("$r_{P1}$ [cm]")
    ax.set_ylabel("$m_0$ [kg]")
    ax.legend(fontsize=8, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, frameon=False)
    ax.grid(True, alpha=0.3)
    cap = (f"Existence of steady motions on the (r_P1, m0) grid, r_P2 = {scan.r_P2 * 100:g} cm, r_P3 = "
           f"{scan.r_P3 * 100:g} cm (numbers: distinct motions found by {scan.provenance['n_starts']} random Newton "
           "starts, the straight-glide continuation and r_P1 continuation). Shaded: where 8.2.2 says no equilibria "
           f"exist; we find motions at {int(np.sum(scan.exists & cr))} of its {int(np.sum(cr))} points.")
    return fig, cap


# ---------------------------------------------------------------------------------------------- report
def report(res: Ch8Results) -> Report:
    h = res.helix
    rep = Report(NAME, TITLE, vehicles=[res.vehicle])
    note = ("Helix of 8.2.2 (r_P = (2, 2, 4) cm, m0 = 0.25 kg), g = 9.8 m/s^2, hydrodynamic forces rotated from the "
            "wind frame with the side force opposing sideslip, moments about the body axes.")
    rep.number("helix_radius_m", h.radius, "m", "8.2.2", thesis=66.60, tolerance=REPRO_TOL, note=note)
    rep.number("helix_speed_mps", h.speed, "m/s", "8.2.2", thesis=0.729, tolerance=REPRO_TOL)
    rep.number("helix_pitch_m", h.pitch, "m", "8.2.2", thesis=206.2, tolerance=REPRO_TOL,
               note="Drop per turn (vertical speed times period).")
    rep.number("helix_period_s", h.period, "s", "8.2.2", thesis=639.6, tolerance=REPRO_TOL)
    for k, val in (("helix_alpha_deg", h.alpha), ("helix_beta_deg", h.beta), ("helix_theta_deg", h.theta),
                   ("helix_phi_deg", h.phi), ("helix_gamma_deg", h.gamma)):
        rep.number(k, math.degrees(val), "deg", "8.2.2")
    rep.number("helix_residual", h.residual, "SI", "(8.23)")
    rep.number("helix_max_re_eig", float(np.max(h.eigenvalues.real)), "1/s", "8.3 (reduced linearization)")
    xf = res.sim.x[-1]
    rep.number("sim_final_error", float(np.max(np.abs(np.r_[xf[7:13] - np.r_[h.v, h.Omega]]))), "SI",
               "Fig 8.2-8.4", note="max |(v, Omega)(2000 s) - helix|: the simulation converges to the trimmed helix.")
    nom = res.rbh_frozen.nominal
    rep.number("rbh_nominal_m", nom.r_bh, "m", "8.3", thesis=0.0481, tolerance=REPRO_TOL)
    cr = res.rbh_frozen.crossings
    rep.number("rbh_bifurcation_m", cr[0] if cr else float("nan"), "m", "8.3, Fig 8.14 (A)", thesis=-0.004,
               tolerance=REPRO_TOL,
               note="Stability crossing of the frozen-equilibrium locus (the thesis's method), by Brent's method. "
                    "The thesis reads 'near -0.004 m' off a plot; the frozen state is not an exact equilibrium away "
                    f"from the nominal r_bh (residual up to {np.max(res.rbh_frozen.residual):.2e}).")
    rep.number("rbh_bifurcation_resolved_m", res.resolved_cross if res.resolved_cross is not None else float("nan"),
               "m", "8.3 (re-solved)",
               note="First loss of stability along the re-solved helix branch walked down from the nominal r_bh in "
                    "0.5 mm steps (bisection to 1e-9 m); the helix there has radius "
                    f"{res.resolved_helix.radius:.2f} m: "
                    "r_bh does change the equilibrium, strongly below about -0.005 m, against 8.3's statement.")
    bps = res.rbh_frozen.locus.breakpoints
    rep.number("rbh_break_points_frozen", [[b.parameter, b.eigenvalue] for b in bps], "m, 1/s", "8.3 B, C, D",
               verdict=None, note="(r_bh, eigenvalue) of the break-away/break-in points of the frozen locus: "
                    + "; ".join(f"{b.kind} at {b.parameter:.5f} m" for b in bps)
                    + ". The thesis names two break-away (B, D) and one break-in (C) point without values.")
    for tgt, d, why in res.designs:
        name = "design_" + "_".join(f"{k}{v:g}" for k, v in tgt.items()).replace("-", "m").replace(".", "p")
        if d is None:
            rep.number(name, "infeasible", "-", "inverse design (beyond the thesis)", note=why)
        else:
            rep.number(name, [*d.r_p, d.m0], "m, m, m, kg", "inverse design (beyond the thesis)",
                       note=f"radius {d.helix.radius:.4f} m, pitch {d.helix.pitch:.4f} m, speed {d.helix.speed:.4f} "
                            f"m/s, max Re = {np.max(d.helix.eigenvalues.real):.4f} 1/s, relative error {d.error:.1e}, "
                            f"{d.evaluations} trims.")
    for key, sw in res.maps.items():
        ex = np.asarray(sw.exists)
        rep.number(f"{key}_points_without_motion", int(np.sum(~ex)), "-", f"Fig {key[3:].replace('_', '.')}",
                   note=f"of {ex.size} points; branch jumps (folds) after "
                        f"{[round(float(v), 5) for v in sw.branch_jumps]}; unstable points "
                        f"{int(np.sum(ex & ~sw.stable))}.")
    for c in res.claims:
        rep.number(c.name, c.value, c.unit, c.source, thesis=c.thesis, verdict=c.holds, note=c.note)
    for name, eq, printed, used, why in THESIS_TYPOS:
        rep.number(name, used, "-", eq, thesis=printed, verdict=False, note=why)
    rows = [[a, b, f"{c:.4g}", f"{d:.4g}"] for a, b, c, d in res.theorem7]
    rep.table("Theorem 7: relative-equilibrium classes (curvature (8.18), torsion (8.22) in 1/m)",
              ["(v, Omega)", "class", "curvature", "torsion"], rows)
    hrow = [[k, f"{v:.6g}"] for k, v in h.as_dict().items()]
    rep.table("Steady helix of 8.2.2 (SI units, radians)", ["quantity", "value"], hrow)
    for stem, (fig, cap) in figures(res).items():
        rep.figure(stem, fig, cap)
    rep.text("Model and corrections", (
        "Model: glidectl.models.glider3d (force form (2.1)-(2.8) and acceleration form (8.23)-(8.25), tested equal, "
        "and equal to the longitudinal model in the plane). (2.5) is read as J Omega x Omega + r_P x (P_P x Omega): "
        "the literal (J Omega + r_P^ P_P) x Omega disagrees with (2.20) and (8.25). Forces (-D, -SF, -L) are rotated "
        "from the wind frame (DESIGN.md), moments act about the body axes (this reproduces all four printed helix "
        "numbers). Chapter-8 damping K_Omega1_i Omega_i without V^2 (DESIGN.md). The trim solves (v', Omega') = 0 "
        "with Omega = psidot R^T k (8.31), exact Jacobian."))
    return rep


def build(outdir: str | Path = "reports", progress: Callable[[str], None] = lambda s: None) -> Path:
    """Compute the study and write ``<outdir>/ch8_helix/`` (report.pdf, PNGs, numbers.json)."""
    from . import build_study

    return build_study(sys.modules[__name__], outdir, progress)
