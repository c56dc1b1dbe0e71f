"""Benchmark: r_bh root locus, complex-step Jacobians (glidectl) vs python-control finite differences.

(A) ``glidectl.analysis.locus.rbh_locus`` for the ROGUE vehicle at V = 0.3 m/s, gamma = -45 deg over 400
    values of r_bh in [-0.03, 0.06] m: per point a steady-glide trim, a complex-step Jacobian of the
    acceleration-controlled glider, the eigenvalues of the eta_r = (theta, Omega2, v1, v3) block and branch
    matching, plus the Brent stability-boundary search and the break-point bisection.
(B) The same computation with the Jacobian from ``control.linearize`` (python-control's forward differences)
    on a ``control.nlsys`` wrapping the same right-hand side ``AccelerationControlledGlider.rhs``; the
    eigenvalues are fed to the same ``parameter_locus`` so matching, boundary and break-point searches are
    identical work.

Usage::

    python bench/bench_rbh_locus.py [--repeats N]

Prints a table and writes ``bench/results/rbh_locus.json`` (the folder is created at run time).
"""

from __future__ import annotations

import argparse
import inspect
import json
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

import control
import numpy as np
import scipy
from scipy.optimize import linear_sum_assignment

import glidectl
from glidectl.analysis.locus import ETA_R, ParameterLocus, parameter_locus, rbh_locus
from glidectl.models.longitudinal import AccelerationControlledGlider
from glidectl.trim.glide import steady_glide

VEHICLE = "rogue"
SPEED = 0.3  # m/s
GAMMA = float(np.radians(-45.0))  # rad
RBH = np.linspace(-0.03, 0.06, 400)  # m
RESULTS = Path(__file__).resolve().parent / "results" / "rbh_locus.json"


def make_baseline(veh: glidectl.params.Vehicle):
    """``values -> ParameterLocus`` doing (B): python-control linearize + the same locus machinery."""
    acc = AccelerationControlledGlider(veh)
    nl = control.nlsys(lambda t, x, u, params: acc.rhs(x, u), None, states=11, inputs=3, outputs=11)
    idx = [acc.state_names.index(s) for s in ETA_R]  # indices 2..5
    u0 = np.zeros(3)

    def eig_fn(r: float) -> np.ndarray:
        g = steady_glide(veh, SPEED, GAMMA, r_bh=r)
        lin = control.linearize(nl, g.accel_state(), u0)
        return np.linalg.eigvals(np.asarray(lin.A)[np.ix_(idx, idx)])

    def run(values: np.ndarray) -> ParameterLocus:
        return parameter_locus(eig_fn, values, "r_bh", "m",
                               {"vehicle": veh.name, "jacobian": "control.linearize (forward differences)"},
                               vehicle=veh)

    return run, idx


def max_matched_diff(a: np.ndarray, b: np.ndarray) -> tuple[float, int]:
    """Largest |lambda_a - lambda_b| over rows after optimal (multiset) matching of each row; and its row."""
    worst, where = 0.0, -1
    for i in range(a.shape[0]):
        cost = np.abs(a[i][:, None] - b[i][None, :])
        r, c = linear_sum_assignment(cost)
        d = float(cost[r, c].max())
        if d > worst:
            worst, where = d, i
    return worst, where


def time_call(fn, repeats: int) -> list[float]:
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="timed repeats per method (median reported)")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")

    veh = glidectl.load_vehicle(VEHICLE)
    baseline, idx = make_baseline(veh)

    def run_a() -> ParameterLocus:
        return rbh_locus(veh, SPEED, GAMMA, RBH)

    def run_b() -> ParameterLocus:
        return baseline(RBH)

    # untimed warm-up; these results are the ones compared (the computation is deterministic)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        loc_a = run_a()
        loc_b = run_b()
    warn_msgs = sorted({f"{w.category.__name__}: {w.message}" for w in caught})

    # alternate A and B so drift in machine load affects both alike
    t_a: list[float] = []
    t_b: list[float] = []
    for _ in range(args.repeats):
        t_a += time_call(run_a, 1)
        t_b += time_call(run_b, 1)
    med_a, med_b = statistics.median(t_a), statistics.median(t_b)

    eig_diff, eig_row = max_matched_diff(loc_a.branches, loc_b.branches)
    eig_scale = float(np.max(np.abs(loc_a.branches)))
    cross_a = loc_a.crossings[0] if loc_a.crossings else float("nan")
    cross_b = loc_b.crossings[0] if loc_b.crossings else float("nan")
    bp_a = [(b.kind, b.parameter) for b in loc_a.breakpoints]
    bp_b = [(b.kind, b.parameter) for b in loc_b.breakpoints]
    bp_diff = ([abs(pa - pb) for (_, pa), (_, pb) in zip(bp_a, bp_b, strict=True)]
               if [k for k, _ in bp_a] == [k for k, _ in bp_b] else None)
    eps_param = inspect.signature(control.NonlinearIOSystem.linearize).parameters.get("eps")
    eps_default = None if eps_param is None else eps_param.default

    rows = [
        ("glidectl rbh_locus (complex step)", f"{med_a:.4f} s", ", ".join(f"{t:.4f}" for t in t_a)),
        ("control.linearize baseline", f"{med_b:.4f} s", ", ".join(f"{t:.4f}" for t in t_b)),
    ]
    w0 = max(len(r[0]) for r in rows)
    print(f"r_bh locus: vehicle={VEHICLE}, V={SPEED} m/s, gamma={np.degrees(GAMMA):.1f} deg, "
          f"{RBH.size} points in [{RBH[0]:g}, {RBH[-1]:g}] m, repeats={args.repeats}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
          f"control {control.__version__}")
    print()
    print(f"{'method':<{w0}}  {'median':>9}  all runs (s)")
    print(f"{'-' * w0}  {'-' * 9}  {'-' * 30}")
    for name, med, allt in rows:
        print(f"{name:<{w0}}  {med:>9}  {allt}")
    print()
    print(f"ratio baseline / glidectl (median)       : {med_b / med_a:.2f}x")
    print(f"max |eig diff| over matched branches     : {eig_diff:.3e} 1/s (at r_bh = {RBH[eig_row]:.6g} m; "
          f"max |eig| = {eig_scale:.3g} 1/s)")
    print(f"stability boundary crossings[0] glidectl : {cross_a:.15g} m")
    print(f"stability boundary crossings[0] baseline : {cross_b:.15g} m")
    print(f"|difference in crossings[0]|             : {abs(cross_a - cross_b):.3e} m")
    print(f"crossings found (glidectl / baseline)    : {len(loc_a.crossings)} / {len(loc_b.crossings)}")
    if bp_diff is not None:
        print(f"break points (same kinds), max |d r_bh|  : {max(bp_diff, default=0.0):.3e} m "
              f"({', '.join(k for k, _ in bp_a)})")
    else:
        print(f"break points differ: glidectl {bp_a}, baseline {bp_b}")
    print(f"control.linearize default eps            : {eps_default!r} (absolute forward-difference step)")
    if warn_msgs:
        print("warnings during the warm-up runs:")
        for m in warn_msgs:
            print(f"  {m}")

    result = {
        "benchmark": "rbh_locus",
        "config": {"vehicle": VEHICLE, "provenance": veh.provenance, "speed": SPEED, "gamma": GAMMA,
                   "rbh_min": float(RBH[0]), "rbh_max": float(RBH[-1]), "n_points": int(RBH.size),
                   "repeats": args.repeats, "eta_r": list(ETA_R), "eta_r_indices": idx},
        "environment": {"python": platform.python_version(), "platform": platform.platform(),
                        "numpy": np.__version__, "scipy": scipy.__version__, "control": control.__version__,
                        "executable": sys.executable},
        "glidectl": {"times_s": t_a, "median_s": med_a, "crossings": list(loc_a.crossings),
                     "breakpoints": [{"kind": k, "parameter": p} for k, p in bp_a],
                     "max_step_jump": loc_a.max_step_jump},
        "baseline_control_linearize": {"times_s": t_b, "median_s": med_b, "crossings": list(loc_b.crossings),
                                       "breakpoints": [{"kind": k, "parameter": p} for k, p in bp_b],
                                       "max_step_jump": loc_b.max_step_jump, "eps_default": eps_default},
        "ratio_baseline_over_glidectl": med_b / med_a,
        "max_abs_eig_diff": eig_diff,
        "max_abs_eig_diff_at_rbh": float(RBH[eig_row]) if eig_row >= 0 else None,
        "max_abs_eig": eig_scale,
        "crossing0_abs_diff": abs(cross_a - cross_b),
        "breakpoint_abs_diffs": bp_diff,
        "warnings": warn_msgs,
    }
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(result, indent=2) + "\n")
    print(f"\nwrote {RESULTS}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
