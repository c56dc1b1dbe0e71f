"""Robustness layer speed: the worst-case search over ten coefficients, dive-cycle missions over sampled vehicles
(serial and on a process pool), and a dask LocalCluster with 1 against 2 workers.

    python bench/bench_robustness.py [--missions 1000] [--dask-missions 400] [--skip-unbatched]
                                     [--out bench/results/robustness.json]

The vehicle is slocum_shallow with +-30 % on its lift, drag, moment and damping coefficients and added masses
(:data:`COEFFICIENTS`), the loop its LQR dive-cycle loop (0.35 m/s, -25 deg, acceleration inputs). Times are wall
times of one run each (the searches are deterministic; a mission ensemble is long enough to average itself). The
missions fly batched (``dive_cycle_ensemble``'s default: the samples of a chunk together), against the one-by-one
baseline (``batched=False``) in the same run; the dask comparison gives both clusters the same 4 chunks.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

COEFFICIENTS = ("K_L", "K_D0", "K_D", "K_M", "K_Omega1_1", "K_Omega1_2", "K_Omega1_3", "m_f1", "m_f3", "J2")


def _vehicle():
    import glidectl as gc

    veh = gc.load_vehicle("slocum_shallow")
    return veh.with_uncertainty({k: {"rel": 0.3, "source": "+-30 %, bench"} for k in COEFFICIENTS})


def worst_case() -> dict:
    import glidectl as gc

    veh = _vehicle()
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    ctrl = gc.lqr_glide(veh, glide, inputs="acceleration")
    t = time.perf_counter()
    rs = gc.robust_stability(ctrl, n=1000, seed=0, margin=False)
    total = time.perf_counter() - t
    return {"coefficients": len(COEFFICIENTS), "samples_s": rs.times["samples"], "worst_case_s": rs.times["worst case"],
            "total_s": total, "evaluations": rs.worst_case.evaluations, "worst_max_real": rs.worst_case.max_real,
            "probability": rs.probability, "nominal_max_real": rs.nominal_max_real}


def missions(n: int, workers: int, batched: bool = True) -> dict:
    import glidectl as gc

    veh = _vehicle()
    t = time.perf_counter()
    if workers == 0:
        mc = gc.dive_cycle_ensemble(veh, n=n, seed=0, cycles=3, batched=batched)
    else:
        with ProcessPoolExecutor(workers) as ex:
            mc = gc.dive_cycle_ensemble(veh, n=n, seed=0, cycles=3, executor=ex, batched=batched)
    return {"n": n, "workers": workers, "batched": batched, "wall_s": time.perf_counter() - t,
            "ran": int(mc.ok.sum()), "energy_per_km_median": float(mc.quantiles("energy_per_km", 0.5)),
            "cycle_time_median": float(mc.quantiles("cycle_time", 0.5))}


def dask_missions(n: int, workers: int, chunks: int = 4) -> dict:
    from dask.distributed import Client, LocalCluster

    import glidectl as gc

    veh = _vehicle()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        ex = client.get_executor()
        gc.dive_cycle_ensemble(veh, n=2 * workers, seed=99, cycles=1, executor=ex)    # warm the workers (imports)
        t = time.perf_counter()
        mc = gc.dive_cycle_ensemble(veh, n=n, seed=0, cycles=3, executor=ex, chunks=chunks)
        wall = time.perf_counter() - t
    return {"n": n, "dask_workers": workers, "wall_s": wall, "ran": int(mc.ok.sum())}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--missions", type=int, default=1000)
    ap.add_argument("--dask-missions", type=int, default=400)
    ap.add_argument("--skip-unbatched", action="store_true", help="leave out the one-by-one baseline (157 s)")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "robustness.json")
    args = ap.parse_args()
    out = {"worst_case": worst_case()}
    print("worst case over 10 coefficients:", out["worst_case"], flush=True)
    out["missions_serial_50"] = missions(50, 0, batched=False)
    print("50 missions, one by one, one process:", out["missions_serial_50"], flush=True)
    out["missions_batched_1"] = missions(args.missions, 0)
    print(f"{args.missions} missions, batched, one process:", out["missions_batched_1"], flush=True)
    out["missions_pool"] = missions(args.missions, 2)
    print(f"{args.missions} missions, batched, 2 processes:", out["missions_pool"], flush=True)
    if not args.skip_unbatched:
        out["missions_pool_unbatched"] = missions(args.missions, 2, batched=False)
        out["batched_speedup"] = out["missions_pool_unbatched"]["wall_s"] / out["missions_pool"]["wall_s"]
        print(f"{args.missions} missions, one by one, 2 processes:", out["missions_pool_unbatched"],
              f"batched speedup {out['batched_speedup']:.2f}", flush=True)
    out["dask_1"] = dask_missions(args.dask_missions, 1)
    out["dask_2"] = dask_missions(args.dask_missions, 2)
    out["dask_speedup"] = out["dask_1"]["wall_s"] / out["dask_2"]["wall_s"]
    print("dask 1 worker:", out["dask_1"], "2 workers:", out["dask_2"], f"speedup {out['dask_speedup']:.2f}",
          flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
