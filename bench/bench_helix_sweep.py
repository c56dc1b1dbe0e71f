"""Benchmark: helix map over r_P1 by continuation (helix_sweep) vs independent cold-started helix trims.

(A) ``glidectl.analysis.helix_maps.helix_sweep(veh, "r_P1", R_P1, r_p=(., 0.02, 0.04), m0=M0)``: one cold solve at the
    first point, then each point warm-started from the previous solution (cold fallback when the warm start fails).
(B) ``glidectl.helix_trim(veh, (r_P1, 0.02, 0.04), M0)`` (``guess=None``) at every point: the longitudinal straight
    glide continued in r_P2 in 12 steps, then up to 40 random starts.
(C) optional: (A) through ``ProcessPoolExecutor(--workers)`` (chunked, reconciled to the serial result).

Two cases of 200 points each, r_P1 in [-6, 6] cm with r_P2 = 2 cm, r_P3 = 4 cm: m0 = +0.25 kg (one branch of
motions) and m0 = -0.25 kg (several coexisting motions for r_P1 > 0, where the cold start and the continuation can
land on different ones).

Usage::

    python bench/bench_helix_sweep.py [--repeats N] [--workers W]

Prints a table and writes ``bench/results/helix_sweep.json`` (the folder is created at run time).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import scipy

import glidectl
from glidectl.analysis.continuation import AGREE_TOL, COLUMNS
from glidectl.analysis.helix_sweeps import HelixSweep, helix_sweep

VEHICLE = "slocum_ch8"
R_P1 = np.linspace(-0.06, 0.06, 200)  # m
R_P23 = (0.02, 0.04)  # m
CASES = (0.25, -0.25)  # m0, kg
RESULTS = Path(__file__).resolve().parent / "results" / "helix_sweep.json"
T = TypeVar("T")


def cold_solves(veh: glidectl.Vehicle, m0: float) -> tuple[np.ndarray, np.ndarray]:
    """(B): every point cold-started; returns (exists, rows of COLUMNS with NaN where no motion was found)."""
    exists = np.zeros(R_P1.size, bool)
    rows = np.full((R_P1.size, len(COLUMNS)), np.nan)
    unknowns = np.full((R_P1.size, 6), np.nan)
    for i, x in enumerate(R_P1):
        try:
            h = glidectl.helix_trim(veh, (float(x), *R_P23), m0)
        except glidectl.InfeasibleGlideError:
            continue
        exists[i] = True
        d = h.as_dict()
        rows[i] = [*(d[c] for c in COLUMNS[:14]), *h.v]
        unknowns[i] = h.unknowns
    return exists, np.c_[rows, unknowns]


def timed(fn: Callable[[], T]) -> tuple[float, T]:
    t0 = time.perf_counter()
    res = fn()
    return time.perf_counter() - t0, res


def compare(sw: HelixSweep, cold: tuple[np.ndarray, np.ndarray]) -> dict[str, Any]:
    """Where both found a motion: same motion (trim unknowns within AGREE_TOL) or another branch; max differences."""
    ex_c, rows_c = cold
    both = sw.exists & ex_c
    du = np.max(np.abs(sw.unknowns - rows_c[:, len(COLUMNS):]), axis=1)
    same = both & (du <= AGREE_TOL)
    other = both & (du > AGREE_TOL)
    ref = rows_c[:, :len(COLUMNS)]
    with np.errstate(invalid="ignore"):
        rel = np.abs(sw.data - ref) / np.maximum(1.0, np.abs(ref))
    rel[~np.isfinite(rel)] = 0.0  # inf radius/pitch/period of a straight glide on both sides
    return {
        "points_both": int(both.sum()), "points_same_motion": int(same.sum()),
        "points_other_branch": int(other.sum()),
        "other_branch_r_P1": [float(x) for x in R_P1[other]],
        "max_abs_unknowns_diff_same_motion": float(du[same].max()) if same.any() else None,
        "max_rel_column_diff_same_motion": float(rel[same].max()) if same.any() else None,
    }


def run_case(veh: glidectl.Vehicle, m0: float, repeats: int, pool: ProcessPoolExecutor | None) -> dict[str, Any]:
    """Time (A), (B) and (C) alternately after one untimed warm-up each; compare the results."""
    r_p = (0.0, *R_P23)

    def run_a() -> HelixSweep:
        return helix_sweep(veh, "r_P1", R_P1, r_p=r_p, m0=m0)

    def run_b() -> tuple[np.ndarray, np.ndarray]:
        return cold_solves(veh, m0)

    def run_c() -> HelixSweep:
        return helix_sweep(veh, "r_P1", R_P1, r_p=r_p, m0=m0, executor=pool)

    sw, cold = run_a(), run_b()
    swp = run_c() if pool is not None else None
    t_a: list[float] = []
    t_b: list[float] = []
    t_c: list[float] = []
    for _ in range(repeats):  # alternate so that drift in machine load affects all alike
        t_a.append(timed(run_a)[0])
        t_b.append(timed(run_b)[0])
        if pool is not None:
            t_c.append(timed(run_c)[0])
    med_a, med_b = statistics.median(t_a), statistics.median(t_b)
    case: dict[str, Any] = {
        "m0": m0,
        "continuation": {"times_s": t_a, "median_s": med_a, "success": int(sw.exists.sum()),
                         "how": {h: sw.how.count(h) for h in sorted(set(sw.how))},
                         "branch_jumps_r_P1": [float(x) for x in sw.branch_jumps]},
        "cold": {"times_s": t_b, "median_s": med_b, "success": int(cold[0].sum())},
        "ratio_cold_over_continuation": med_b / med_a,
        **compare(sw, cold),
    }
    if swp is not None:
        with np.errstate(invalid="ignore"):
            d = float(np.nanmax(np.abs(swp.data - sw.data) / np.maximum(1.0, np.abs(sw.data))))
        case["executor"] = {"times_s": t_c, "median_s": statistics.median(t_c), "success": int(swp.exists.sum()),
                            "chunks": swp.context["chunks"], "reconciliation": swp.context["reconciliation"],
                            "max_rel_diff_vs_serial": d}
    return case


def report(case: dict[str, Any], workers: int) -> None:
    n = R_P1.size
    a, b = case["continuation"], case["cold"]
    print(f"\nm0 = {case['m0']:+g} kg")
    print(f"  {'method':<42}  {'median':>9}  {'found':>7}  all runs (s)")
    rows = [("(A) helix_sweep, continuation", a), ("(B) cold helix_trim at every point", b)]
    if "executor" in case:
        rows.append((f"(C) (A) on ProcessPoolExecutor({workers})", case["executor"]))
    for name, r in rows:
        runs = ", ".join(f"{t:.3f}" for t in r["times_s"])
        print(f"  {name:<42}  {r['median_s']:>8.3f}s  {r['success']:>3}/{n}  {runs}")
    print(f"  ratio (B)/(A), medians                    : {case['ratio_cold_over_continuation']:.1f}x")
    print(f"  (A) points by method                      : {a['how']}; branch jumps at r_P1 = {a['branch_jumps_r_P1']}")
    print(f"  both found a motion                       : {case['points_both']} points; the same motion at "
          f"{case['points_same_motion']}, another one at {case['points_other_branch']}")
    if case["points_other_branch"]:
        xs = case["other_branch_r_P1"]
        print(f"  points with another motion (r_P1, m)      : {min(xs):.4g} .. {max(xs):.4g}")
    print(f"  max |d unknowns|, same motion             : {case['max_abs_unknowns_diff_same_motion']:.3e}")
    print(f"  max relative column diff, same motion     : {case['max_rel_column_diff_same_motion']:.3e}")
    if "executor" in case:
        ex = case["executor"]
        print(f"  (C) vs (A) max relative diff              : {ex['max_rel_diff_vs_serial']:.3e} "
              f"({ex['chunks']} chunks, {len(ex['reconciliation'])} re-walked)")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3, help="timed repeats per method (median reported)")
    ap.add_argument("--workers", type=int, default=2, help="ProcessPoolExecutor workers for (C); 0 skips it")
    args = ap.parse_args(argv)
    if args.repeats < 1 or args.workers < 0:
        ap.error("--repeats must be >= 1 and --workers >= 0")
    veh = glidectl.load_vehicle(VEHICLE)
    print(f"helix sweep: vehicle={VEHICLE}, {R_P1.size} points r_P1 in [{R_P1[0]:g}, {R_P1[-1]:g}] m, "
          f"(r_P2, r_P3) = {R_P23} m, repeats={args.repeats}, workers={args.workers}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
          f"cpus {os.cpu_count()}")
    cases = {}
    pool = ProcessPoolExecutor(args.workers) if args.workers else None
    try:
        for m0 in CASES:
            cases[f"m0={m0:+g}"] = case = run_case(veh, m0, args.repeats, pool)
            report(case, args.workers)
    finally:
        if pool is not None:
            pool.shutdown()
    result = {
        "benchmark": "helix_sweep",
        "config": {"vehicle": VEHICLE, "provenance": veh.provenance, "r_P1_min": float(R_P1[0]),
                   "r_P1_max": float(R_P1[-1]), "n_points": int(R_P1.size), "r_P2": R_P23[0], "r_P3": R_P23[1],
                   "repeats": args.repeats, "workers": args.workers, "agree_tol": AGREE_TOL},
        "environment": {"python": platform.python_version(), "platform": platform.platform(),
                        "numpy": np.__version__, "scipy": scipy.__version__, "cpus": os.cpu_count(),
                        "executable": sys.executable},
        "cases": cases,
    }
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(result, indent=2) + "\n")
    print(f"\nwrote {RESULTS}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
