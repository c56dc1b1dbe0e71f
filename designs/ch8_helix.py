"""Chapter 8 design: three-dimensional steady motions of the Slocum-like glider (Table 8.1), the §8.2.2 simulation
converging to a circular helix (Fig 8.2-8.4), helix maps versus the control parameters (Fig 8.5-8.12) with the
qualitative statements of §8.2.2 tested against them, stability versus bottom-heaviness (Fig 8.13-8.14) and inverse
helix design.

Run ``glidectl report ch8_helix`` or ``python designs/ch8_helix.py [OUTDIR] [--quick]``;
writes ``OUTDIR/ch8_helix/``.

The claim checks (``existence_claim``, ``r_p1_claims``, ``r_p2_claims``, ``r_p3_claims``, ``m0_claims``) take
computed sweeps (:class:`glidectl.HelixSweep`) or the existence scan and return :class:`Claim` records: the
thesis's sentence, what our model gives, and whether the statement holds. No claim check changes a sweep; thresholds
are stated in each function and are not tuned to make a claim hold.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

import glidectl as gc
from glidectl.report import BHATTA_2006, Report, new_figure, run_script

TITLE = "Chapter 8: circular helices of a Slocum-like glider, their maps, stability and inverse design"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 44.0, "full": 122.0}

Vec3 = tuple[float, float, float]
Grid = tuple[float, float, int]  # np.linspace(start, stop, num)
#: one helix map: (figure key, swept parameter, grid of the swept values, fixed r_P (m), fixed m0 (kg))
MapCase = tuple[str, str, Grid, Vec3, float]


@dataclass(frozen=True)
class Settings:
    """Everything the study computes with. ``FULL`` reproduces the published report; ``QUICK`` is a smoke build."""

    repro_tol: float = 0.01  # relative tolerance for the printed helix and r_bh numbers
    r_p: Vec3 = (0.02, 0.02, 0.04)  # m, §8.2.2
    m0: float = 0.25  # kg
    sim_ypr0_deg: Vec3 = (0.0, -26.654, 14.419)  # printed initial attitude (yaw, pitch, roll)
    sim_v0: Vec3 = (0.802, 0.014, 0.025)  # m/s
    sim_omega0: Vec3 = (0.0046, 0.0025, 0.0077)  # rad/s
    sim_t: float = 2000.0  # s
    sim_samples: int = 8001  # output points of the simulation
    plot_window: float = 300.0  # s shown in Fig 8.3-8.4
    rbh_r_p: Vec3 = (0.02, -0.02, 0.04)  # §8.3 nominal
    rbh_grid: Grid = (-0.03, 0.10, 261)  # m
    resolved_step: float = 5e-4  # m: step of the re-solved branch walk (then bisection to 1e-9 m)
    design_targets: tuple[tuple[tuple[str, float], ...], ...] = (
        (("radius", 50.0), ("pitch", 150.0)), (("radius", 30.0), ("speed", 0.6)),
        (("radius", 50.0), ("pitch", -150.0)), (("radius", 1.0), ("pitch", 1000.0)),
    )
    map_cases: tuple[MapCase, ...] = (
        ("fig8_5", "r_P1", (0.002, 0.06, 59), (0.02, 0.02, 0.04), 0.25),
        ("fig8_6", "r_P1", (-0.06, -0.002, 59), (-0.02, 0.02, 0.04), -0.25),
        ("fig8_7", "r_P2", (-0.05, 0.05, 101), (0.02, 0.02, 0.04), 0.25),
        ("fig8_8", "r_P2", (-0.05, 0.05, 101), (-0.02, 0.02, 0.04), -0.25),
        ("fig8_9", "r_P3", (0.0, 0.10, 101), (0.02, 0.02, 0.04), 0.25),
        ("fig8_10", "r_P3", (0.0, 0.10, 101), (-0.02, 0.02, 0.04), -0.25),
        ("fig8_11", "m0", (0.05, 0.6, 56), (0.02, 0.02, 0.04), 0.25),
        ("fig8_12", "m0", (-0.6, -0.05, 56), (-0.02, 0.02, 0.04), -0.25),
    )
    scan_r_p1: Grid = (-0.04, 0.04, 9)  # m
    scan_m0: tuple[float, ...] = (-0.5, -0.25, -0.1, 0.1, 0.25, 0.5)  # kg
    scan_starts: int = 30  # random Newton starts per scan point
    fold_step: float = 2e-6  # m: step of the warm-started walk that locates the ends of a branch (Fig 8.9 folds)
    workers: int = 4  # process pool size (capped by the CPU count)


FULL = Settings()
QUICK = Settings(
    sim_t=300.0, sim_samples=1201, rbh_grid=(-0.03, 0.10, 27),
    design_targets=((("radius", 50.0), ("pitch", 150.0)), (("radius", 1.0), ("pitch", 1000.0))),
    map_cases=(
        ("fig8_5", "r_P1", (0.005, 0.035, 7), (0.02, 0.02, 0.04), 0.25),
        ("fig8_6", "r_P1", (-0.03, -0.001, 7), (-0.02, 0.02, 0.04), -0.25),
        ("fig8_7", "r_P2", (-0.04, 0.04, 9), (0.02, 0.02, 0.04), 0.25),
        ("fig8_8", "r_P2", (-0.04, 0.04, 9), (-0.02, 0.02, 0.04), -0.25),
        ("fig8_9", "r_P3", (0.01, 0.03, 21), (0.02, 0.02, 0.04), 0.25),  # 1 mm: the fold after 1.5 cm shows
        ("fig8_10", "r_P3", (0.01, 0.03, 21), (-0.02, 0.02, 0.04), -0.25),
        ("fig8_11", "m0", (0.05, 0.6, 8), (0.02, 0.02, 0.04), 0.25),
        ("fig8_12", "m0", (-0.6, -0.05, 8), (-0.02, 0.02, 0.04), -0.25),
    ),
    scan_r_p1=(-0.02, 0.02, 3), scan_m0=(-0.25, 0.25), scan_starts=4, fold_step=2e-5, workers=2,
)

# ---------------------------------------------------------------------------------------------- thesis values
THESIS_HELIX = {"helix_radius_m": 66.60, "helix_speed_mps": 0.729, "helix_pitch_m": 206.2, "helix_period_s": 639.6}
THESIS_RBH_NOMINAL = 0.0481  # m, §8.3
THESIS_RBH_BIFURCATION = -0.004  # m, §8.3 "near -0.004 m", read off Fig 8.14 (A)
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
MAP_TITLES = {"fig8_5": "r_P1, m0 > 0", "fig8_6": "r_P1, m0 < 0", "fig8_7": "r_P2, m0 > 0", "fig8_8": "r_P2, m0 < 0",
              "fig8_9": "r_P3, m0 > 0", "fig8_10": "r_P3, m0 < 0", "fig8_11": "m0 > 0", "fig8_12": "m0 < 0"}


# ---------------------------------------------------------------------------------------------- claim checks
@dataclass(frozen=True)
class Claim:
    """One statement of the thesis checked against our computation.

    Attributes
    ----------
    name : str
        Ledger key.
    source : str
        Where the statement is made (section, figure).
    thesis : str
        The statement, quoted or closely paraphrased.
    value : Any
        The number (or list) our computation gives for it.
    unit : str
    reproduced : bool or None
        Whether the statement is reproduced in our model (None: a finding the thesis does not state).
    note : str
        What we found and why it differs.
    """

    name: str
    source: str
    thesis: str
    value: Any
    unit: str
    reproduced: bool | None
    note: str


def _deg(x: Any) -> Any:
    return np.degrees(x)


def _cm(x: float) -> str:
    return f"{100 * x:.2f} cm"


def _monotone_prefix(y: np.ndarray, sign: int) -> int:
    """Length of the leading run of ``y`` that changes with the given sign (+1 increasing, -1 decreasing)."""
    d = sign * np.diff(y)
    bad = np.flatnonzero(~(d > 0))
    return int(bad[0] + 1) if bad.size else int(y.size)


def existence_claim(scan: gc.ExistenceScan) -> Claim:
    """§8.2.2: "We could not find any equilibrium solutions for a combination of negative buoyancy (m0 > 0) and aft
    center of gravity (r_P1 < 0) or for a combination of positive buoyancy (m0 < 0) and fore center of gravity
    (r_P1 > 0)"."""
    cr = scan.claim_region
    n_cr = int(np.sum(cr))
    n_found = int(np.sum(scan.exists & cr))
    n_su = int(np.sum((scan.n_stable_upright > 0) & cr))
    ce = scan.counterexamples(stable_only=True, upright_only=True)
    heavy = [c for c in ce if c["m0"] > 0]
    light = [c for c in ce if c["m0"] < 0]

    def rng(cs: list[dict[str, Any]], key: str) -> str:
        v = _deg(np.array([c[key] for c in cs]))
        return f"{v.min():.1f} to {v.max():.1f} deg" if v.size else "-"

    note = (f"Grid {scan.m0.size} m0 x {scan.r_P1.size} r_P1 (r_P2 = {_cm(scan.r_P2)}, r_P3 = {_cm(scan.r_P3)}); "
            f"steady motions exist at {n_found} of the {n_cr} claimed-empty points, a stable upright one at {n_su}. "
            f"Heavy glider with aft mass (m0 > 0, r_P1 < 0): stable descending helices with alpha "
            f"{rng(heavy, 'alpha')}, pitch {rng(heavy, 'theta')} (nose up while sinking); the larger alphas lie "
            "beyond the range of a linear lift / quadratic drag model (no stall in (2.9)-(2.11)). Light glider with "
            f"fore mass (m0 < 0, r_P1 > 0): stable ascending helices with small alpha {rng(light, 'alpha')} but roll "
            f"{rng(light, 'phi')}. These are equilibria of the thesis's own equations (8.23)-(8.25); the claim may "
            "reflect the thesis's search (its initial guesses), not the model.")
    return Claim("claim_no_equilibria_m0_rP1_opposite", "8.2.2", "no equilibria for m0 > 0 with r_P1 < 0 or m0 < 0 "
                 "with r_P1 > 0", n_found, "points with motions", n_found == 0, note)


def r_p1_claims(veh: gc.Vehicle, heavy: gc.HelixSweep, light: gc.HelixSweep) -> list[Claim]:
    """Fig 8.5 (m0 > 0, r_P1 > 0) and Fig 8.6 (m0 < 0, r_P1 < 0) trends stated in §8.2.2."""
    out = []
    x = heavy.values
    trends = {"theta": -1, "gamma": -1, "alpha": -1, "beta": -1, "speed": 1, "Omega_norm": -1, "radius": 1,
              "pitch": 1, "period": 1}
    ends = {k: _monotone_prefix(heavy.column(k), s) for k, s in trends.items()}
    n_all = min(ends.values())
    x_end = float(x[n_all - 1])
    first_fail = min(ends, key=ends.get)  # type: ignore[arg-type]
    fail_txt = (f"the first to fail is {first_fail} (at {_cm(float(x[ends[first_fail]]))})" if n_all < x.size
                else "none fails on the map")
    pos = bool(np.all(heavy.alpha > 0) and np.all(heavy.beta > 0))
    sg = gc.straight_glides(veh, heavy)
    sg_txt = "; ".join(f"straight glide (Omega = 0) at r_P1 = {_cm(h.r_p[0])} with beta = {_deg(h.beta):.3f} deg"
                       for h in sg)
    out.append(Claim(
        "claim_fig8_5_trends", "8.2.2, Fig 8.5",
        "m0 > 0: as r_P1 increases theta and gamma decrease, alpha and beta decrease (both positive), V increases, "
        "|Omega| decreases; radius, pitch and period increase", x_end, "m (end of the range where all hold)",
        None,
        f"All nine trends hold from r_P1 = {_cm(float(x[0]))} to {_cm(x_end)}; {fail_txt}. alpha, beta > 0 on the "
        f"whole map: {pos}. Further on, |Omega| passes through zero and the helix reverses its turn: "
        f"{sg_txt or 'none found'}. The thesis does not give its r_P1 range, so we cannot say whether its plot stops "
        "before this."))
    a = light.alpha
    neg = bool(np.all(a < 0) and np.all(light.beta < 0))
    # walk r_P1 downwards from the value closest to 0
    order = np.argsort(-light.values)
    ad, vd, xd = a[order], light.speed[order], light.values[order]
    ia, iv = int(np.argmin(ad)), int(np.argmin(vd))
    holds = neg and 0 < ia < ad.size - 1 and 0 < iv < vd.size - 1
    out.append(Claim(
        "claim_fig8_6_critical_rP1", "8.2.2, Fig 8.6",
        "m0 < 0: alpha and beta negative; as r_P1 decreases from small |r_P1|, alpha first decreases (V decreases), "
        "beyond a critical value alpha increases (V increases)", float(xd[ia]), "m (alpha minimum)", holds,
        f"alpha, beta < 0 everywhere: {neg}. Along decreasing r_P1, alpha reaches its minimum "
        f"{_deg(ad[ia]):.4f} deg at r_P1 = {_cm(float(xd[ia]))} and V its minimum {vd[iv]:.4f} m/s at "
        f"{_cm(float(xd[iv]))} (grid resolution {_cm(float(abs(np.diff(light.values)).max()))}); the two critical "
        "values differ slightly, the thesis gives one."))
    return out


def r_p2_claims(heavy: gc.HelixSweep, light: gc.HelixSweep) -> list[Claim]:
    """Fig 8.7 (m0 > 0) and Fig 8.8 (m0 < 0): radius to infinity and beta to 0 as r_P2 -> 0; roll ranges; the sign
    rule for beta; symmetry about r_P2 = 0."""
    out = []
    sym = max(sw.mirror_error(c, p) for sw in (heavy, light)
              for c, p in (("radius", 1), ("speed", 1), ("alpha", 1), ("beta", -1), ("phi", -1)))
    i0 = [int(np.argmin(np.where(sw.values != 0, np.abs(sw.values), np.inf))) for sw in (heavy, light)]
    r0 = [float(sw.radius[i]) for sw, i in zip((heavy, light), i0, strict=True)]
    rend = [float(np.nanmax(sw.radius[[0, -1]])) for sw in (heavy, light)]
    b0 = [float(_deg(abs(sw.beta[i]))) for sw, i in zip((heavy, light), i0, strict=True)]
    grows = all(a > 4 * b for a, b in zip(r0, rend, strict=True))
    out.append(Claim(
        "claim_fig8_7_8_straight_limit", "8.2.2, Fig 8.7-8.8",
        "radius -> infinity and beta -> 0 as r_P2 -> 0 (straight glide in the longitudinal plane)", r0, "m",
        grows and max(b0) < 0.5,
        f"Radius at the smallest |r_P2| on the grid ({_cm(float(abs(heavy.values[i0[0]])))}): {r0[0]:.1f} m "
        f"(m0 > 0), {r0[1]:.1f} m (m0 < 0), against {rend[0]:.1f} and {rend[1]:.1f} m at |r_P2| = "
        f"{_cm(float(abs(heavy.values[0])))}; |beta| there {b0[0]:.3f} and {b0[1]:.3f} deg; at r_P2 = 0 exactly the "
        "motion is the longitudinal straight glide (radius infinite, beta = 0)."))
    rh = float(_deg(np.nanmax(heavy.phi) - np.nanmin(heavy.phi)))
    rl = float(_deg(np.nanmax(light.phi) - np.nanmin(light.phi)))
    out.append(Claim("claim_fig8_7_8_roll_range", "8.2.2, Fig 8.7-8.8",
                     "the range of the roll angle is smaller for m0 = 0.25 kg than for m0 = -0.25 kg", [rh, rl],
                     "deg", rh < rl, f"roll range over the r_P2 sweep: {rh:.1f} deg (m0 > 0), {rl:.1f} deg "
                     "(m0 < 0)."))
    agree, total = 0, 0
    for sw in (heavy, light):
        m = sw.exists & (sw.values != 0)
        s_beta = np.sign(sw.beta[m])
        s_rule = -np.sign(sw.m0 * sw.values[m])  # thesis: beta > 0 when m0 and r_P2 have opposite signs
        agree += int(np.sum(s_beta == s_rule))
        total += int(np.sum(m))
    out.append(Claim(
        "claim_beta_sign_rule", "8.2.2, Fig 8.7-8.8",
        "beta_e > 0 when m0 and r_P2 have opposite signs, negative otherwise", f"{agree}/{total}",
        "points obeying the rule", agree == total,
        f"The rule holds at {agree} of {total} points: in our model sign(beta) = sign(m0 r_P2) everywhere, the "
        "reverse. The thesis's own 8.2.2 example agrees with us: r_P2 = +2 cm, m0 = +0.25 kg (same signs) and its "
        "printed initial condition v2 = +0.014 m/s (beta > 0) converges to our helix with beta = +1.16 deg. The "
        "rule as printed has its sign flipped (or uses a different sideslip convention)."))
    out.append(Claim("claim_fig8_7_8_symmetry", "8.2.2, Fig 8.7-8.8",
                     "for a given m0 the equilibria are symmetric about r_P2 = 0", sym, "max mirror error (SI/rad)",
                     sym < 1e-6, "Largest |y(r_P2) - y(-r_P2)| over radius, speed, alpha and |beta(r_P2) + "
                     "beta(-r_P2)|, |phi(r_P2) + phi(-r_P2)| on mirrored grid points (the trim tolerance is 1e-10)."))
    return out


def r_p3_claims(veh: gc.Vehicle, heavy: gc.HelixSweep, light: gc.HelixSweep, fold_step: float) -> list[Claim]:
    """Fig 8.9 (m0 > 0): a critical r_P3 with a straight glide out of the longitudinal plane; Fig 8.10 (m0 < 0):
    smooth dependence. ``fold_step`` (m) is the step of the walk that locates the ends of each branch."""
    sg = gc.straight_glides(veh, heavy)
    jumps_h = [float(x) for x in heavy.branch_jumps]
    holds = len(sg) >= 1 and all(abs(h.beta) > 1e-3 for h in sg)
    folds = []
    for xj in jumps_h:
        i = int(np.flatnonzero(heavy.values == xj)[0])
        lo = heavy.branch_end(i, float(heavy.values[i + 1]) + 1e-3, fold_step)
        hi = heavy.branch_end(i + 1, float(heavy.values[i]) - 1e-3, fold_step)
        folds.append((lo, hi))
    fold_txt = "; ".join(
        f"the branch from small r_P3 continues up to {100 * lo[0]:.4f} cm (max Re eig {lo[1]:.5f} 1/s), the branch "
        f"of the nominal helix down to {100 * hi[0]:.4f} cm (max Re eig {hi[1]:.5f} 1/s)" for lo, hi in folds)
    txt = "; ".join(f"r_P3 = {_cm(h.r_p[2])}: beta = {_deg(h.beta):.3f} deg, roll {_deg(h.phi):.2f} deg, "
                    f"V = {h.speed:.4f} m/s, {'stable' if h.stable else 'unstable'}" for h in sg)
    out = [Claim("claim_fig8_9_critical_rP3", "8.2.2, Fig 8.9",
                 "m0 > 0: a critical r_P3 gives a straight glide (Omega = 0) out of the longitudinal plane (beta != "
                 "0)", [h.r_p[2] for h in sg], "m", holds,
                 f"psidot changes sign on the continued branch at {txt or 'no point'}. The map also jumps between "
                 f"branches after r_P3 = {', '.join(_cm(x) for x in jumps_h) or 'nowhere'}. Walking each branch in "
                 f"{100 * fold_step:g} cm steps: {fold_txt or '-'}. Overlapping ends are a hysteresis pair of "
                 "folds (saddle-nodes: a real eigenvalue approaches 0), with two coexisting helices between them; "
                 "the thesis's figure shows one smooth curve.")]
    sg_l = gc.straight_glides(veh, light)
    jumps_l = list(light.branch_jumps)
    smooth = bool(np.all(light.exists)) and not jumps_l and not sg_l
    out.append(Claim("claim_fig8_10_smooth", "8.2.2, Fig 8.10", "m0 < 0: helix parameters vary smoothly with r_P3",
                     len(jumps_l) + len(sg_l), "jumps + straight glides", smooth,
                     f"All {light.values.size} points found by continuation: {bool(np.all(light.exists))}; branch "
                     f"jumps: {len(jumps_l)}; Omega = 0 crossings: {len(sg_l)}."))
    return out


def m0_claims(heavy: gc.HelixSweep, light: gc.HelixSweep) -> list[Claim]:
    """Fig 8.11-8.12: V nearly linear in |m0|; |Omega| grows faster than V; radius decreases with |m0|."""
    out = []
    exps, r2s, faster, rdec = [], [], [], []
    for sw in (heavy, light):
        m = np.abs(sw.values)
        p = np.polyfit(np.log(m), np.log(sw.speed), 1)
        q = np.polyfit(np.log(m), np.log(sw.Omega_norm), 1)
        exps.append(float(p[0]))
        lin = np.polyfit(m, sw.speed, 1)
        res = sw.speed - np.polyval(lin, m)
        r2s.append(float(1 - np.sum(res**2) / np.sum((sw.speed - sw.speed.mean()) ** 2)))
        faster.append(bool(q[0] > p[0]))
        o = np.argsort(m)
        rdec.append(bool(np.all(np.diff(sw.radius[o]) < 0)))
    out.append(Claim(
        "claim_speed_linear_in_m0", "8.2.2, Fig 8.11-8.12", "the translational speed is almost linear in |m0|",
        exps, "exponent of V ~ |m0|^n (m0 > 0, m0 < 0)", bool(all(abs(e - 1) < 0.2 for e in exps)),
        f"Log-log fit V ~ |m0|^n gives n = {exps[0]:.3f} (m0 > 0) and {exps[1]:.3f} (m0 < 0): V grows like "
        f"sqrt(|m0|), as the force balance |m0| g ~ V^2 (lift, drag ~ V^2) demands at near-constant angles. A "
        f"straight-line fit has R^2 = {r2s[0]:.4f}, {r2s[1]:.4f} over the plotted range, so the curve can look "
        f"almost straight on a narrow range, but V(0) = 0 and the intercept of that line is not."))
    out.append(Claim("claim_m0_radius_decreases", "8.2.2, Fig 8.11-8.12",
                     "|Omega| grows faster than V, so the radius decreases with |m0|", [*faster, *rdec], "-",
                     all(faster) and all(rdec),
                     f"d ln|Omega| / d ln|m0| > d ln V / d ln|m0|: {faster}; radius strictly decreasing in |m0|: "
                     f"{rdec} (m0 > 0, m0 < 0)."))
    return out


# ---------------------------------------------------------------------------------------------- computation
@dataclass(frozen=True)
class Ch8Results:
    settings: Settings
    vehicle: gc.Vehicle
    helix: gc.Helix
    sim: gc.Simulation
    theorem7: list[tuple[str, str, float, float]]
    rbh_frozen: gc.HelixRbhLocus
    rbh_resolved: gc.HelixRbhLocus
    resolved_cross: float | None
    resolved_helix: gc.Helix
    designs: list[tuple[dict[str, float], gc.HelixDesign | None, str]]
    maps: dict[str, gc.HelixSweep]
    scan: gc.ExistenceScan
    claims: tuple[Claim, ...]


def _linspace(grid: Grid) -> np.ndarray:
    return np.linspace(grid[0], grid[1], grid[2])


def _cls(v: np.ndarray, Om: np.ndarray) -> tuple[str, float, float]:
    c = gc.classify_motion(v, Om)
    return c["kind"], c["curvature"], c["torsion"]


def compute_maps(veh: gc.Vehicle, s: Settings, executor: Executor | None = None) -> dict[str, gc.HelixSweep]:
    """The eight helix maps of Fig 8.5-8.12 (``s.map_cases``), by continuation."""
    return {key: gc.helix_sweep(veh, param, _linspace(grid), r_p=r_p, m0=m0, executor=executor)
            for key, param, grid, r_p, m0 in s.map_cases}


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> Ch8Results:
    """Run every computation of the chapter-8 study."""
    veh = gc.load_vehicle("slocum_ch8")
    progress("helix trim at r_P = (2, 2, 4) cm, m0 = 0.25 kg (8.2.2)")
    h = gc.helix_trim(veh, s.r_p, s.m0)
    progress(f"{s.sim_t:.0f} s simulation from the printed initial conditions (Fig 8.2-8.4)")
    model = gc.FixedMassGlider3D(veh, s.r_p, s.m0)
    q0 = gc.ypr_to_quat(*np.radians(s.sim_ypr0_deg))
    x0 = np.r_[0.0, 0.0, 0.0, q0, s.sim_v0, s.sim_omega0]
    sim = gc.simulate(model, x0, s.sim_t, t_eval=np.linspace(0.0, s.sim_t, s.sim_samples))
    v, Om = h.v, h.Omega
    th7 = [("steady helix of 8.2.2", *_cls(v, Om)), ("Omega = 0", *_cls(v, 0 * Om)),
           ("v = 0", *_cls(0 * v, Om)), ("Omega parallel to v", *_cls(v, 0.01 * v / np.linalg.norm(v)))]

    # the sweeps submit library functions, the vehicle and plain data to the pool: nothing of this file is pickled.
    # The r_bh loci and the inverse designs are independent of the maps: they go to the pool first.
    with ProcessPoolExecutor(max_workers=max(1, min(s.workers, os.cpu_count() or 1))) as ex:
        progress("stability versus bottom-heaviness (Fig 8.13-8.14): frozen and re-solved equilibria; inverse "
                 "helix design (on the pool)")
        rbh_grid = _linspace(s.rbh_grid)
        f_fro = ex.submit(gc.helix_rbh_locus, veh, s.rbh_r_p, s.m0, rbh_grid, frozen=True)
        f_res = ex.submit(gc.helix_rbh_locus, veh, s.rbh_r_p, s.m0, rbh_grid, frozen=False)
        f_rc = ex.submit(gc.resolved_crossing, veh, s.rbh_r_p, s.m0, step=s.resolved_step)
        f_designs = [(dict(target), ex.submit(gc.design_helix, veh, **dict(target))) for target in s.design_targets]
        progress("helix maps versus r_P1, r_P2, r_P3, m0 (Fig 8.5-8.12)")
        maps = compute_maps(veh, s, ex)
        progress("existence scan of the (m0, r_P1) sign claim of 8.2.2")
        scan = gc.existence_scan(veh, _linspace(s.scan_r_p1), np.array(s.scan_m0), n_starts=s.scan_starts,
                                 executor=ex)
        fro, res = f_fro.result(), f_res.result()
        rc, rh = f_rc.result()
        designs: list[tuple[dict[str, float], gc.HelixDesign | None, str]] = []
        for tgt, fut in f_designs:
            try:
                designs.append((tgt, fut.result(), ""))
            except gc.InfeasibleGlideError as exc:
                designs.append((tgt, None, str(exc)))
    progress("claims of 8.2.2 about the maps")
    claims = (existence_claim(scan), *r_p1_claims(veh, maps["fig8_5"], maps["fig8_6"]),
              *r_p2_claims(maps["fig8_7"], maps["fig8_8"]),
              *r_p3_claims(veh, maps["fig8_9"], maps["fig8_10"], s.fold_step),
              *m0_claims(maps["fig8_11"], maps["fig8_12"]))
    return Ch8Results(s, veh, h, sim, th7, fro, res, rc, rh, designs, maps, scan, claims)


# ---------------------------------------------------------------------------------------------- figures
def figures(res: Ch8Results) -> dict[str, tuple[Any, str]]:
    from matplotlib import pyplot as plt

    s = res.settings
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
    out["fig8_2_trajectory"] = (fig, f"Analogue of Fig 8.2: {s.sim_t:.0f} s simulation of the fixed-mass glider "
                                "(8.23) from the printed initial conditions, r_P = (2, 2, 4) cm, m0 = 0.25 kg; it "
                                "converges to the "
                                f"helix of radius {h.radius:.2f} m and pitch {h.pitch:.1f} m (z axis points down).")
    ypr = gc.R_to_ypr(gc.quat_to_R(sim.x[:, 3:7]))
    m = sim.t <= s.plot_window
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
    out["fig8_3_position_orientation"] = (fig, "Analogue of Fig 8.3: position and YPR attitude (8.26), first "
                                          f"{s.plot_window:.0f} s; dashed: the steady helix's pitch and roll.")
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
    out["fig8_4_velocities"] = (fig, f"Analogue of Fig 8.4: body velocity and angular velocity, first "
                                f"{s.plot_window:.0f} s; dashed: the steady helix.")

    cases = {case[0]: case for case in s.map_cases}
    for key, sw in res.maps.items():
        out[key] = _map_figure(sw, cases[key])
    out["fig8_existence_scan"] = _scan_figure(res.scan)

    fig, axs = new_figure(1, 2, width=10, height=4.4)
    res.rbh_frozen.locus.plot(ax=axs[0], kind="real")
    axs[0].set_title("equilibrium frozen at the nominal r_bh (as 8.3)", fontsize=9)
    res.rbh_resolved.locus.plot(ax=axs[1], kind="real")
    axs[1].set_title("equilibrium re-solved at every r_bh", fontsize=9)
    for a in axs:
        a.axvline(res.rbh_frozen.nominal.r_bh, color="k", ls=":", lw=0.8)
    out["fig8_13_rbh_real_parts"] = (fig, "Analogue of Fig 8.13: real parts of the eigenvalues of the reduced helix "
                                     "linearization (position and yaw dropped) versus r_bh; r_P = (2, -2, 4) cm, "
                                     "m0 = 0.25 kg (dotted: nominal r_bh). Left, the thesis's frozen equilibrium; "
                                     "right, re-solved (continuation from the nominal point).")
    fig, ax = new_figure(1, 1, width=7, height=5)
    res.rbh_frozen.locus.plot(ax=ax)
    ax.set_xlim(-0.3, 0.05)
    ax.set_ylim(-0.1, 0.1)
    out["fig8_14_rbh_locus"] = (fig, "Analogue of Fig 8.14: root locus of the slow eigenvalues versus r_bh (frozen "
                                "equilibrium), zoomed near the imaginary axis; crossings (x) and break points (o, "
                                "lettered; our letters, not the thesis's A-D) located by root finding and bisection.")
    return out


def _map_figure(sw: gc.HelixSweep, case: MapCase) -> tuple[Any, str]:
    key, _, _, r_p, m0 = case
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
    fixed = {k: v for k, v in zip(("r_P1", "r_P2", "r_P3", "m0"), (*r_p, m0), strict=True) if k != sw.parameter}
    jumps = f" (at {', '.join(f'{v:g}' for v in sw.branch_jumps)})" if sw.branch_jumps.size else ""
    cap = (f"Analogue of Fig {key[3:].replace('_', '.')}: helix parameters versus {MAP_TITLES[key]} "
           f"(fixed: {', '.join(f'{k} = {v:g}' for k, v in fixed.items())}; r_P in m, m0 in kg), by continuation. "
           f"Points without a steady motion: {n_missing}; unstable points (x): {n_unstable}. Radius and period on log "
           "scales when they span more than a factor 20 (infinite at a straight glide); pitch is the drop per turn "
           "(negative: ascending). Curves are broken "
           f"where the continuation jumps between branches{jumps}.")
    return fig, cap


def _scan_figure(scan: gc.ExistenceScan) -> tuple[Any, str]:
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
           f"{scan.r_P3 * 100:g} cm (numbers: distinct motions found by {scan.context['n_starts']} random Newton "
           "starts, the straight-glide continuation and r_P1 continuation). Shaded: where 8.2.2 says no equilibria "
           f"exist; we find motions at {int(np.sum(scan.exists & cr))} of its {int(np.sum(cr))} points.")
    return fig, cap


# ---------------------------------------------------------------------------------------------- report
def report(res: Ch8Results) -> Report:
    s = res.settings
    h = res.helix
    rep = Report(TITLE, vehicle=[res.vehicle], reference=BHATTA_2006)
    note = ("Helix of 8.2.2 (r_P = (2, 2, 4) cm, m0 = 0.25 kg), g = 9.8 m/s^2, hydrodynamic forces rotated from the "
            "wind frame with the side force opposing sideslip, moments about the body axes.")
    th = THESIS_HELIX
    rep.number("helix_radius_m", h.radius, "m", "8.2.2", published=th["helix_radius_m"], tolerance=s.repro_tol,
               note=note)
    rep.number("helix_speed_mps", h.speed, "m/s", "8.2.2", published=th["helix_speed_mps"], tolerance=s.repro_tol)
    rep.number("helix_pitch_m", h.pitch, "m", "8.2.2", published=th["helix_pitch_m"], tolerance=s.repro_tol,
               note="Drop per turn (vertical speed times period).")
    rep.number("helix_period_s", h.period, "s", "8.2.2", published=th["helix_period_s"], tolerance=s.repro_tol)
    for k, val in (("helix_alpha_deg", h.alpha), ("helix_beta_deg", h.beta), ("helix_theta_deg", h.theta),
                   ("helix_phi_deg", h.phi), ("helix_gamma_deg", h.gamma)):
        rep.number(k, math.degrees(val), "deg", "8.2.2")
    rep.number("helix_residual", h.residual, "SI", "(8.23)")
    rep.number("helix_max_re_eig", float(np.max(h.eigenvalues.real)), "1/s", "8.3 (reduced linearization)")
    xf = res.sim.x[-1]
    rep.number("sim_final_error", float(np.max(np.abs(np.r_[xf[7:13] - np.r_[h.v, h.Omega]]))), "SI",
               "Fig 8.2-8.4", note=f"max |(v, Omega)({s.sim_t:.0f} s) - helix|: the simulation converges to the "
               "trimmed helix.")
    nom = res.rbh_frozen.nominal
    rep.number("rbh_nominal_m", nom.r_bh, "m", "8.3", published=THESIS_RBH_NOMINAL, tolerance=s.repro_tol)
    cr = res.rbh_frozen.crossings
    rep.number("rbh_bifurcation_m", cr[0] if cr else float("nan"), "m", "8.3, Fig 8.14 (A)",
               published=THESIS_RBH_BIFURCATION, tolerance=s.repro_tol,
               note="Stability crossing of the frozen-equilibrium locus (the thesis's method), by Brent's method. "
                    "The thesis reads 'near -0.004 m' off a plot; the frozen state is not an exact equilibrium away "
                    f"from the nominal r_bh (residual up to {np.max(res.rbh_frozen.residual):.2e}).")
    rep.number("rbh_bifurcation_resolved_m", res.resolved_cross if res.resolved_cross is not None else float("nan"),
               "m", "8.3 (re-solved)",
               note="First loss of stability along the re-solved helix branch walked down from the nominal r_bh in "
                    f"{1000 * s.resolved_step:g} mm steps (bisection to 1e-9 m); the helix there has radius "
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
        rep.number(c.name, c.value, c.unit, c.source, published=c.thesis, verdict=c.reproduced, note=c.note)
    for name, eq, printed, used, why in THESIS_TYPOS:
        rep.number(name, used, "-", eq, published=printed, verdict=False, note=why)
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
        "from the wind frame (docs/conventions.md), moments act about the body axes (this reproduces all four "
        "printed helix numbers). Chapter-8 damping K_Omega1_i Omega_i without V^2 (docs/conventions.md). The trim "
        "solves (v', Omega') = 0 "
        "with Omega = psidot R^T k (8.31), exact Jacobian."))
    return rep


def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """Compute the chapter-8 study (``QUICK`` or ``FULL`` settings) and return its report."""
    res = compute(QUICK if quick else FULL, progress)
    progress("figures and report")
    return report(res)


if __name__ == "__main__":
    run_script(__file__)
