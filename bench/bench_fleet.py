"""Benchmark: a fleet of 10 Slocum-class gliders for 3 days with ``gc.fly_fleet`` (fast vehicle model), serially and
on executors.

Ten gliders abreast in a line 2 km apart carried at 0.12 m/s along a straight path, 100 m dives, 5 minutes at the
surface, a depth-varying current. Timed: serial (one process), a ``ProcessPoolExecutor`` with 2 processes, and a
dask ``LocalCluster`` with 1 and with 2 single-threaded workers (``Client.get_executor()``); the runs are checked
equal to the serial one. Targets: under 5 minutes on 2 cores; dask with 2 workers at least 1.7 times faster than
with 1. The cost per glider-day gives the extrapolation to a season.

Usage::

    python bench/bench_fleet.py                  # 1 repeat (each run is long)
    python bench/bench_fleet.py --days 1         # a shorter check
    python bench/bench_fleet.py --days 0.25 --model full   # the full 3-D model: heavier tasks
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import glidectl as gc

ROOT = Path(__file__).resolve().parents[1]


def fleet_args(days: float, model: str = "fast") -> tuple[list, gc.FormationControl, dict]:
    veh = gc.load_vehicle("slocum_shallow")
    T = days * 86400.0
    fc = gc.FormationControl("line", 2000.0, leader_path=[(0.0, 0.0), (0.12 * T * 1.2, 0.0)], leader_speed=0.12)
    kw = dict(mission=gc.Mission(waypoints=[(1.0, 0.0)], depths=(5.0, 100.0), surface_time=300.0),
              current=gc.Current.profile([0.0, 100.0], [0.08, 0.04], [0.05, 0.0]), duration=T, model=model)
    return [veh] * 10, fc, kw


def timed(fn) -> tuple[float, gc.FleetRun]:
    t0 = time.perf_counter()
    run = fn()
    return time.perf_counter() - t0, run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--days", type=float, default=3.0)
    ap.add_argument("--model", choices=("fast", "full"), default="fast")
    args = ap.parse_args()
    vehs, fc, kw = fleet_args(args.days, args.model)
    out: dict = {"gliders": 10, "days": args.days, "model": args.model}
    t_serial, serial = timed(lambda: gc.fly_fleet(vehs, fc, **kw))
    out["serial_s"] = t_serial
    with ProcessPoolExecutor(2) as pool:
        t_pool, run = timed(lambda: gc.fly_fleet(vehs, fc, executor=pool, **kw))
    out["process_pool_2_s"] = t_pool
    out["process_pool_equal"] = all(np.array_equal(a, b) for a, b in zip(serial.states, run.states, strict=True))
    from dask.distributed import Client, LocalCluster

    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
                Client(cl) as client:
            ex = client.get_executor()
            gc.fly_fleet(vehs, fc, executor=ex, **{**kw, "duration": 3600.0})       # warm-up: imports on workers
            t_dask, run = timed(lambda ex=ex: gc.fly_fleet(vehs, fc, executor=ex, **kw))
        out[f"dask_{workers}_workers_s"] = t_dask
        out[f"dask_{workers}_equal"] = all(np.array_equal(a, b) for a, b in zip(serial.states, run.states,
                                                                                strict=True))
    out["dask_speedup_2_over_1"] = out["dask_1_workers_s"] / out["dask_2_workers_s"]
    out["glider_days"] = 10 * args.days
    out["serial_s_per_glider_day"] = t_serial / out["glider_days"]
    out["season_50_gliders_100_days_serial_h"] = out["serial_s_per_glider_day"] * 50 * 100 / 3600.0
    print(json.dumps(out, indent=2))
    (ROOT / "bench" / "results").mkdir(exist_ok=True)
    (ROOT / "bench" / "results" / f"fleet_{args.model}.json").write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
