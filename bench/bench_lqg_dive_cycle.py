"""Benchmark: the default "lqg" dive cycle against the default "lqr" one on ``slocum_shallow`` (target: "lqg" at
most 3 times the wall time of "lqr"), with the actuator metrics that show whether the LQG chatters on the noise.

What is timed: the whole ``gc.dive_cycle(veh, controller, seed=SEED)`` call with every other argument at its
default (3 cycles between 5 and 100 m at 0.35 m/s and +-25 deg; "lqr": every state measured, no noise; "lqg":
depth, pitch and pitch rate with the default simulated sensor noise sampled every second), in one process, the
controllers alternating (lqr, lqg, lqr, lqg, ...) after one untimed warm-up each; medians over ``--repeats``.
``--same-noise`` also times "lqr" flown with the "lqg"'s simulated noise (``noise=LQG_NOISE``), the comparison at
equal sensor sampling. "lqg analog" is the LQG with its continuous Kalman filter on noise-free sensors
(``noise={}, sensor_period=0``), the noise-free comparison with "lqr". The script uses only arguments that every
version of ``dive_cycle`` has (the analog case aside), so it also times an older checkout:
``PYTHONPATH=/path/to/old/src python bench/bench_lqg_dive_cycle.py``.

Reported per controller: median wall time (s), right-hand-side evaluations, the fraction of the mission during
which some actuator is at a limit (``run.saturated``: a rate cut by the limiter, or within 1e-3 of its range width
from an end), saturated time per cycle (s) and pump energy per cycle (J); and the ratio lqg/lqr of the medians.

Usage::

    python bench/bench_lqg_dive_cycle.py                  # 3 repeats
    python bench/bench_lqg_dive_cycle.py --repeats 5 --same-noise

Writes ``bench/results/lqg_dive_cycle.json``.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import glidectl as gc
from glidectl.controllers.dive_cycle import LQG_NOISE

SEED = 0
TARGET = 3.0


def fly(veh: gc.Vehicle, controller: str, extra: dict) -> tuple[float, gc.DiveCycleRun]:
    t0 = time.perf_counter()
    run = gc.dive_cycle(veh, controller, seed=SEED, **extra)
    return time.perf_counter() - t0, run


def metrics(run: gc.DiveCycleRun) -> dict:
    sat = run.saturated.astype(float)
    row = run.as_dict()
    return {"nfev": int(run.nfev), "saturated_fraction": float(np.trapezoid(sat, run.t) / (run.t[-1] - run.t[0])),
            "saturated_time_per_cycle_s": row["saturated_time_per_cycle"],
            "energy_per_cycle_J": row["energy_per_cycle"], "max_overshoot_m": row["max_overshoot"],
            "duration_per_cycle_s": row["duration_per_cycle"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--same-noise", action="store_true", help="also time 'lqr' with the 'lqg' simulated noise")
    args = ap.parse_args()
    veh = gc.load_vehicle("slocum_shallow")
    cases = {"lqr": ("lqr", {}), "lqg": ("lqg", {}), "lqg analog": ("lqg", {"noise": {}, "sensor_period": 0.0})}
    if args.same_noise:
        cases["lqr+noise"] = ("lqr", {"noise": dict(LQG_NOISE)})
    times: dict[str, list[float]] = {k: [] for k in cases}
    runs = {k: fly(veh, c, extra)[1] for k, (c, extra) in cases.items()}  # warm-up (imports, caches)
    for rep in range(args.repeats):
        for k, (c, extra) in cases.items():
            dt, runs[k] = fly(veh, c, extra)
            times[k].append(dt)
            print(f"repeat {rep + 1}: {k:10s} {dt:8.2f} s", flush=True)
    med = {k: float(np.median(v)) for k, v in times.items()}
    result = {"vehicle": veh.name, "seed": SEED, "repeats": args.repeats, "times_s": times, "median_s": med,
              "metrics": {k: metrics(r) for k, r in runs.items()}, "ratio_lqg_lqr": med["lqg"] / med["lqr"],
              "ratio_analog_lqg_lqr": med["lqg analog"] / med["lqr"],
              "target_ratio": TARGET, "glidectl": str(Path(gc.__file__).parent)}
    print(f"\n{'controller':10s} {'median [s]':>10s} {'nfev':>8s} {'at a limit':>10s} {'sat/cycle [s]':>13s} "
          f"{'pump/cycle [J]':>14s}")
    for k in cases:
        m = result["metrics"][k]
        print(f"{k:10s} {med[k]:10.2f} {m['nfev']:8d} {100 * m['saturated_fraction']:9.1f}% "
              f"{m['saturated_time_per_cycle_s']:13.1f} {m['energy_per_cycle_J']:14.1f}")
    ratio = result["ratio_lqg_lqr"]
    print(f"lqg / lqr wall time: {ratio:.1f} (target <= {TARGET:g}: {'met' if ratio <= TARGET else 'NOT met'})")
    print(f"analog lqg (noise-free, continuous filter) / lqr: {med['lqg analog'] / med['lqr']:.2f} "
          f"(target <= {TARGET:g})")
    if "lqr+noise" in med:
        print(f"lqg / (lqr with the same noise): {med['lqg'] / med['lqr+noise']:.2f}")
    out = Path(__file__).resolve().parent / "results"
    out.mkdir(exist_ok=True)
    (out / "lqg_dive_cycle.json").write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
