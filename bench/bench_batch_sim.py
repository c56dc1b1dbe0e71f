"""Benchmark: batch Rosenbrock integration of 10,000 glider initial conditions vs. a loop of solve_ivp calls.

Model: the chapter-5 sphere (``sphere_ch5``, default ``K_M = -50``; ``--km -100`` for the stiffer variant) in the
nondimensional coordinates of §5.1, ``dz/dt_n = tau_s * d(to_nondimensional(x))/dt`` with ``x' =
ReducedLongitudinalGlider.rhs(x)`` (one right-hand side, the same function in both methods). Initial conditions are
uniform in ``|Vbar| <= 0.4, |gammabar| <= pi/2, |alphabar| <= 0.2, |Omegabar2| <= 0.1``; horizon 10 ``t_n``.

(A) ``glidectl.batch.integrate_batch`` on all N runs at once (median of ``--repeats`` timings).
(B) ``scipy.integrate.solve_ivp`` (``--method``, default Radau, same rtol/atol, finite-difference Jacobian as a
    user would call it) in a Python loop over a random subset of ``--subset`` runs; the loop time is extrapolated
    linearly to N runs. The largest difference of the final states of (A) and (B) on the subset is printed.

Usage::

    python bench/bench_batch_sim.py                 # N = 10000, subset 200, K_M = -50
    python bench/bench_batch_sim.py --km -100 --method LSODA
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import glidectl
from glidectl.batch import integrate_batch


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--subset", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--km", type=float, default=-50.0)
    ap.add_argument("--method", default="Radau")
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--atol", type=float, default=1e-8)
    ap.add_argument("--horizon", type=float, default=10.0)
    args = ap.parse_args()

    veh = glidectl.load_vehicle("sphere_ch5").with_overrides(K_M=args.km)
    sp = glidectl.singular_perturbation(veh)
    scale = sp.tau_s * np.array([1.0 / sp.speed, 1.0, 1.0, sp.omega_scale])

    def rhs(z: np.ndarray) -> np.ndarray:
        return sp.model.rhs(sp.to_dimensional(z)) * scale

    lam = sp.full_eigenvalues
    print(f"sphere_ch5, K_M = {args.km:g}: tau_s = {sp.tau_s:.4g} s, full linearization eigenvalues on t_n: "
          + ", ".join(f"{v.real:.4g}{v.imag:+.3g}j" for v in lam)
          + f"  (stiffness ratio ~ {abs(lam.real).max() / abs(lam.real).min():.0f})")

    rng = np.random.default_rng(12345)
    box = np.array([0.4, np.pi / 2, 0.2, 0.1])
    Z0 = rng.uniform(-1.0, 1.0, (args.n, 4)) * box
    tol = dict(rtol=args.rtol, atol=args.atol)

    integrate_batch(rhs, Z0[:50], args.horizon, **tol)  # warm-up
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        res = integrate_batch(rhs, Z0, args.horizon, **tol)
        times.append(time.perf_counter() - t0)
    t_batch = float(np.median(times))
    print(f"(A) integrate_batch, N = {args.n}: median {t_batch:.3f} s over {args.repeats} repeats "
          f"({', '.join(f'{x:.3f}' for x in times)}); {res.summary()}")

    sub = rng.choice(args.n, size=min(args.subset, args.n), replace=False)
    t0 = time.perf_counter()
    finals, ok = [], []
    for i in sub:
        sol = solve_ivp(lambda t, z: rhs(z), (0.0, args.horizon), Z0[i], method=args.method, **tol)
        finals.append(sol.y[:, -1])
        ok.append(sol.success and sol.t[-1] == args.horizon)
    t_loop_sub = time.perf_counter() - t0
    t_loop = t_loop_sub * args.n / len(sub)
    finals = np.array(finals)
    both = np.array(ok) & res.finished[sub]
    diff = np.abs(finals[both] - res.x_final[sub][both])
    rel = diff / np.maximum(1.0, np.abs(finals[both]))
    print(f"(B) solve_ivp({args.method}) loop: {t_loop_sub:.3f} s for {len(sub)} runs (one timing), extrapolated "
          f"linearly to N = {args.n}: {t_loop:.1f} s")
    print(f"speed-up (B extrapolated) / (A) = {t_loop / t_batch:.1f}x")
    print(f"final states on the subset ({int(both.sum())}/{len(sub)} finished by both): max |diff| = "
          f"{diff.max():.2e}, max |diff| / max(1, |x|) = {rel.max():.2e}")

    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "batch_sim.json").write_text(json.dumps({
        "vehicle": "sphere_ch5", "K_M": args.km, "N": args.n, "subset": len(sub), "horizon_tn": args.horizon,
        "rtol": args.rtol, "atol": args.atol, "baseline_method": args.method, "t_batch_median_s": t_batch,
        "t_batch_all_s": times, "t_loop_subset_s": t_loop_sub, "t_loop_extrapolated_s": t_loop,
        "ratio": t_loop / t_batch, "max_abs_diff": float(diff.max()),
        "full_eigenvalues": [[v.real, v.imag] for v in lam]}, indent=2))


if __name__ == "__main__":
    main()
