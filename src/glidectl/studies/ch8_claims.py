"""The qualitative statements of §8.2.2 about the helix maps (Fig 8.5-8.12), each tested against our maps.

Every function takes computed sweeps (:class:`glidectl.analysis.helix_maps.HelixSweep`) or the existence scan and
returns :class:`Claim` records: the thesis's sentence, what our model gives, and whether the statement holds. No
computation here changes a sweep; thresholds are stated in each function and are not tuned to make a claim hold.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.helix_maps import ExistenceScan, HelixSweep, straight_glides
from ..params import Vehicle

FOLD_STEP = 2e-6  # m: step of the warm-started walk that locates the ends of a branch

__all__ = ["Claim", "existence_claim", "m0_claims", "r_p1_claims", "r_p2_claims", "r_p3_claims"]


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
    holds : bool or None
        Whether the statement holds in our model (None: a finding the thesis does not state).
    note : str
        What we found and why it differs.
    """

    name: str
    source: str
    thesis: str
    value: Any
    unit: str
    holds: bool | None
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


def existence_claim(scan: ExistenceScan) -> Claim:
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


def r_p1_claims(veh: Vehicle, heavy: HelixSweep, light: HelixSweep) -> list[Claim]:
    """Fig 8.5 (m0 > 0, r_P1 > 0) and Fig 8.6 (m0 < 0, r_P1 < 0) trends stated in §8.2.2."""
    out = []
    x = heavy.values
    trends = {"theta": -1, "gamma": -1, "alpha": -1, "beta": -1, "speed": 1, "Omega_norm": -1, "radius": 1,
              "pitch": 1, "period": 1}
    ends = {k: _monotone_prefix(heavy.column(k), s) for k, s in trends.items()}
    n_all = min(ends.values())
    x_end = float(x[n_all - 1])
    first_fail = min(ends, key=ends.get)  # type: ignore[arg-type]
    pos = bool(np.all(heavy.alpha > 0) and np.all(heavy.beta > 0))
    sg = straight_glides(veh, heavy)
    sg_txt = "; ".join(f"straight glide (Omega = 0) at r_P1 = {_cm(h.r_p[0])} with beta = {_deg(h.beta):.3f} deg"
                       for h in sg)
    out.append(Claim(
        "claim_fig8_5_trends", "8.2.2, Fig 8.5",
        "m0 > 0: as r_P1 increases theta and gamma decrease, alpha and beta decrease (both positive), V increases, "
        "|Omega| decreases; radius, pitch and period increase", x_end, "m (end of the range where all hold)",
        None,
        f"All nine trends hold from r_P1 = {_cm(float(x[0]))} to {_cm(x_end)}; the first to fail is "
        f"{first_fail} (at {_cm(float(x[ends[first_fail]]))}). alpha, beta > 0 on the whole map: {pos}. Further "
        f"on, |Omega| passes through zero and the helix reverses its turn: {sg_txt or 'none found'}. The thesis "
        "does not give its r_P1 range, so we cannot say whether its plot stops before this."))
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


def _mirror(sw: HelixSweep, col: str, parity: int) -> float:
    """max |y(x) - parity * y(-x)| over the sweep points whose mirror is also a sweep point."""
    x = sw.values
    y = sw.column(col)
    errs = []
    for i, xi in enumerate(x):
        if xi == 0:
            continue
        j = np.flatnonzero(np.isclose(x, -xi, atol=1e-12))
        if j.size and sw.exists[i] and sw.exists[j[0]]:
            errs.append(abs(y[i] - parity * y[j[0]]))
    return float(np.max(errs)) if errs else float("nan")


def r_p2_claims(heavy: HelixSweep, light: HelixSweep) -> list[Claim]:
    """Fig 8.7 (m0 > 0) and Fig 8.8 (m0 < 0): radius to infinity and beta to 0 as r_P2 -> 0; roll ranges; the sign
    rule for beta; symmetry about r_P2 = 0."""
    out = []
    sym = max(_mirror(sw, c, p) for sw in (heavy, light)
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


def _branch_end(veh: Vehicle, sw: HelixSweep, i: int, target: float, step: float) -> tuple[float, float]:
    """Walk the branch through point ``i`` towards ``target`` in steps of ``step`` (warm starts only); return the
    last value reached and the max real part of the eigenvalues there (near 0 at a fold)."""
    from ..errors import GlidectlError
    from ..trim.helix import helix_trim

    x0 = float(sw.values[i])
    guess: Any = sw.unknowns[i]
    last = (x0, float(sw.max_re_eig[i]))
    n = int(abs(target - x0) / step)
    prev = float("inf")
    for k in range(1, n + 1):
        x = x0 + np.sign(target - x0) * k * step
        r_p, m0 = list(sw.r_p), sw.m0
        r_p[["r_P1", "r_P2", "r_P3"].index(sw.parameter)] = x
        try:
            h = helix_trim(veh, r_p, m0, guess=guess, n_random=0)
        except GlidectlError:
            break
        d = float(np.linalg.norm(h.unknowns - guess))
        if d > 10 * prev:
            break  # a step ten times the previous one: Newton jumped to another branch
        prev = d
        guess, last = h.unknowns, (x, float(np.max(h.eigenvalues.real)))
    return last


def r_p3_claims(veh: Vehicle, heavy: HelixSweep, light: HelixSweep) -> list[Claim]:
    """Fig 8.9 (m0 > 0): a critical r_P3 with a straight glide out of the longitudinal plane; Fig 8.10 (m0 < 0):
    smooth dependence."""
    sg = straight_glides(veh, heavy)
    jumps_h = [float(x) for x in heavy.branch_jumps]
    holds = len(sg) >= 1 and all(abs(h.beta) > 1e-3 for h in sg)
    folds = []
    for xj in jumps_h:
        i = int(np.flatnonzero(heavy.values == xj)[0])
        lo = _branch_end(veh, heavy, i, float(heavy.values[i + 1]) + 1e-3, FOLD_STEP)
        hi = _branch_end(veh, heavy, i + 1, float(heavy.values[i]) - 1e-3, FOLD_STEP)
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
                 f"{100 * FOLD_STEP:g} cm steps: {fold_txt or '-'}. Overlapping ends are a hysteresis pair of "
                 "folds (saddle-nodes: a real eigenvalue approaches 0), with two coexisting helices between them; "
                 "the thesis's figure shows one smooth curve.")]
    sg_l = straight_glides(veh, light)
    jumps_l = list(light.branch_jumps)
    smooth = bool(np.all(light.exists)) and not jumps_l and not sg_l
    out.append(Claim("claim_fig8_10_smooth", "8.2.2, Fig 8.10", "m0 < 0: helix parameters vary smoothly with r_P3",
                     len(jumps_l) + len(sg_l), "jumps + straight glides", smooth,
                     f"All {light.values.size} points found by continuation: {bool(np.all(light.exists))}; branch "
                     f"jumps: {len(jumps_l)}; Omega = 0 crossings: {len(sg_l)}."))
    return out


def m0_claims(heavy: HelixSweep, light: HelixSweep) -> list[Claim]:
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

