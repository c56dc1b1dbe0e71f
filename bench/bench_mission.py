"""Benchmark: a 24-hour waypoint mission of the ``slocum_shallow`` preset with ``gc.fly_mission``.

Five waypoints on a pentagon of 6 km sides (longer than a day's flight, so the mission ends at ``duration``),
100 m dives at 28 deg and 0.4 m/s (close to the steepest glide the battery travel holds), one minute at the surface
per dive, a depth-varying current, the default glider behaviours (rudder), samples every 2 s. Target: under 30 s on
one core. The same mission with the fast model (``model="fast"``) is timed too, and its per-dive error measured:
each full-model dive without a waypoint switch under water is replayed from the same start and compared with the
full model's fix. BLAS runs on one thread (threadpoolctl); the median over ``--repeats`` is reported with the
dives flown.

Usage::

    python bench/bench_mission.py                 # 3 repeats
    python bench/bench_mission.py --repeats 1
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

import glidectl as gc
from glidectl.missions.fast import replay_errors

ROOT = Path(__file__).resolve().parents[1]
TARGET_S = 30.0


def mission() -> tuple[gc.Mission, gc.Current]:
    """The benchmark's mission and current."""
    angles = np.radians(90.0 + 72.0 * np.arange(5))
    side = 6000.0
    r = side / (2 * math.sin(math.pi / 5))
    waypoints = np.c_[r * np.cos(angles), r * np.sin(angles) + r]
    m = gc.Mission(waypoints=waypoints, depths=(5.0, 100.0), gamma=math.radians(28.0), speed=0.4, surface_time=60.0,
                   arrival_radius=150.0)
    current = gc.Current.profile([0.0, 50.0, 100.0], [0.10, 0.05, 0.02], [0.05, 0.03, 0.0])
    return m, current


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    veh = gc.load_vehicle("slocum_shallow")
    m, current = mission()
    times = []
    with threadpool_limits(1):
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            run = gc.fly_mission(veh, m, current=current, duration=86400.0)
            times.append(time.perf_counter() - t0)
        fast_times = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            fast = gc.fly_mission(veh, m, current=current, duration=86400.0, model="fast")
            fast_times.append(time.perf_counter() - t0)
    med = float(np.median(times))
    errors = replay_errors(run)
    out = {"fast_wall_median_s": float(np.median(fast_times)), "fast_dives": len(fast.dives),
           "fast_speedup": med / float(np.median(fast_times)),
           "fast_per_dive_error_median_m": float(np.median(errors[:, 0])),
           "fast_per_dive_error_max_m": float(np.max(errors[:, 0])),
           "fast_per_dive_relative_error_median": float(np.median(errors[:, 1])),
           "fast_dives_compared": int(errors.shape[0]),
           "mission_hours": run.duration / 3600.0, "dives": len(run.dives), "legs_arrived":
           sum(leg.arrived for leg in run.legs), "wall_median_s": med, "wall_all_s": times, "target_s": TARGET_S,
           "ratio_to_target": med / TARGET_S, "energy_per_km_J": run.energy_per_km, "samples": int(run.t.size)}
    print(json.dumps(out, indent=2))
    (ROOT / "bench" / "results").mkdir(exist_ok=True)
    (ROOT / "bench" / "results" / "mission.json").write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
