"""Benchmark: the vectorized glide envelope on a 100 x 100 grid vs. a loop of ``steady_glide`` calls.

Vehicle: the ``slocum_ch8`` preset with the actuator table of issue 16 (pump m0 in [-0.25, 0.25] kg at 0.01 kg/s,
moving mass r_P1 in [-2.5, 2.5] cm at 5 mm/s, r_P3 fixed at the preset's 4 cm: the preset already gives r_P3 =
0.04 m, and a fixed actuator must agree with it). Grid: speeds 0.05..1 m/s, gammas -89..89 deg.

(A) ``glidectl.glide_envelope(veh, speeds, gammas)``: all points at once; median of ``--repeats`` timings.
(B) ``glidectl.steady_glide`` in a Python loop (catching InfeasibleGlideError for points without a glide or out of
    the actuator ranges) over a random subset of ``--subset`` points, extrapolated linearly to the grid; the
    subset's results are compared with (A) (feasibility and m0, r_P1).

Target: (A) under 0.5 s for 10,000 points. Writes ``bench/results/glide_envelope.json``.

Usage::

    python bench/bench_glide_envelope.py
    python bench/bench_glide_envelope.py --n 200 --repeats 7
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import glidectl as gc


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100, help="points per axis (grid n x n)")
    ap.add_argument("--subset", type=int, default=500)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()

    veh = gc.load_vehicle("slocum_ch8").with_actuators(
        m0={"min": -0.25, "max": 0.25, "rate": 0.01, "source": "issue 16 example"},
        r_P1={"min": -0.025, "max": 0.025, "rate": 0.005, "source": "issue 16 example"},
        r_P3={"fixed": 0.04, "source": "slocum_ch8 nominal r_P3 (§8.2.2)"})
    speeds = np.linspace(0.05, 1.0, args.n)
    gammas = np.radians(np.linspace(-89.0, 89.0, args.n))
    npts = speeds.size * gammas.size

    env = gc.glide_envelope(veh, speeds, gammas)  # warm-up
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        env = gc.glide_envelope(veh, speeds, gammas)
        times.append(time.perf_counter() - t0)
    t_env = float(np.median(times))

    rng = np.random.default_rng(2026)
    idx = rng.choice(npts, size=min(args.subset, npts), replace=False)
    ii, jj = np.unravel_index(idx, env.feasible.shape)
    t0 = time.perf_counter()
    results = []
    for i, j in zip(ii, jj, strict=True):
        try:
            g = gc.steady_glide(veh, float(speeds[i]), float(gammas[j]), r_p3=env.r_p3)
            results.append((True, g.m0, g.r_p1))
        except gc.InfeasibleGlideError:
            results.append((False, np.nan, np.nan))
    t_loop = (time.perf_counter() - t0) / idx.size * npts
    agree = all(ok == bool(env.feasible[i, j]) for (ok, _, _), i, j in zip(results, ii, jj, strict=True))
    dm0 = max((abs(m - env.m0[i, j]) for (ok, m, _), i, j in zip(results, ii, jj, strict=True) if ok), default=0.0)
    drp = max((abs(r - env.r_p1[i, j]) for (ok, _, r), i, j in zip(results, ii, jj, strict=True) if ok), default=0.0)

    print(env.summary())
    print(f"(A) glide_envelope, {npts} points: median {t_env:.4f} s over {args.repeats} repeats "
          f"({'meets' if t_env < 0.5 else 'MISSES'} the 0.5 s target)")
    print(f"(B) steady_glide loop: {t_loop:.3f} s for {npts} points (extrapolated from {idx.size})")
    print(f"speed-up (B)/(A): {t_loop / t_env:.0f}x; subset agrees on feasibility: {agree}; "
          f"max |dm0| = {dm0:.2e} kg, max |dr_P1| = {drp:.2e} m")
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "glide_envelope.json").write_text(json.dumps({
        "points": npts, "envelope_median_s": t_env, "repeats": args.repeats, "loop_extrapolated_s": t_loop,
        "loop_subset": int(idx.size), "speedup": t_loop / t_env, "feasible_points": int(env.feasible.sum()),
        "subset_agrees": bool(agree), "max_abs_dm0_kg": dm0, "max_abs_dr_p1_m": drp}, indent=2))


if __name__ == "__main__":
    main()
