"""Benchmark: a three-cycle dive-cycle mission between 5 and 100 m (``glidectl.dive_cycle``), target < 5 s.

Vehicle: ROGUE (``rogue``, §2.3.1) with an actuator table for development: pump ``m0`` in [-0.8, 0.8] kg at
0.02 kg/s, battery ``r_P1`` in [-0.04, 0.04] m at 5 mm/s, ``r_P3`` fixed at 0.02 m (bottom-heavy). Mission: glides
at 0.35 m/s and +-25 deg, 3 cycles. The whole ``dive_cycle`` call is timed (designs, supervisor, integration with
LSODA, metrics); median over ``--repeats`` after one untimed warm-up. Prints the timings, the right-hand-side
evaluations and the per-cycle metrics, and writes ``bench/results/dive_cycle.json``.

``--vehicle slocum_shallow`` flies the preset of issue 16 instead. (A scalar copy of the right-hand side once made
this 9x faster; it was removed because the model must have one right-hand side, and the mission meets its target
without it: about 3.6 s on an idle 2-core machine.)

Usage::

    python bench/bench_dive_cycle.py                      # LQR, 3 repeats
    python bench/bench_dive_cycle.py --vehicle slocum_shallow
    python bench/bench_dive_cycle.py --controller pid --repeats 1
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

import glidectl as gc

ACTUATORS = {"m0": {"min": -0.8, "max": 0.8, "rate": 0.02}, "r_P1": {"min": -0.04, "max": 0.04, "rate": 0.005},
             "r_P3": {"fixed": 0.02}}
TARGET = 5.0


def timed(veh: gc.Vehicle, controller: str, mission: dict) -> tuple[float, gc.DiveCycleRun]:
    t0 = time.perf_counter()
    run = gc.dive_cycle(veh, controller, **mission)
    return time.perf_counter() - t0, run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--controller", default="lqr")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--bottom", type=float, default=100.0)
    ap.add_argument("--vehicle", default="rogue", choices=("rogue", "slocum_shallow"))
    args = ap.parse_args()
    if args.vehicle == "rogue":
        veh = gc.load_vehicle("rogue").with_actuators(**ACTUATORS)
    else:
        veh = gc.load_vehicle("slocum_shallow")
    mission = dict(depths=(5.0, args.bottom), gamma=math.radians(25.0), speed=0.35, cycles=args.cycles, seed=0)
    run = gc.dive_cycle(veh, args.controller, **mission)  # warm-up (imports, caches)
    times = []
    for _ in range(args.repeats):
        dt, run = timed(veh, args.controller, mission)
        times.append(dt)
    med = float(np.median(times))
    print(run.summary())
    print(f"{args.vehicle}, {args.controller}: {args.cycles} cycles 5-{args.bottom:g} m, simulated {run.t[-1]:.0f} s, "
          f"{run.nfev} right-hand-side evaluations; wall time median {med:.2f} s over {args.repeats} repeats "
          f"(all: {', '.join(f'{t:.2f}' for t in times)}); target < {TARGET:g} s: "
          f"{'met' if med < TARGET else 'NOT met'}")
    result = {"vehicle": args.vehicle, "controller": args.controller, "cycles": args.cycles,
              "depths": [5.0, args.bottom], "times_s": times, "median_s": med, "nfev": run.nfev,
              "simulated_s": float(run.t[-1]), "cycles_metrics": [run.as_dict()]}
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "dive_cycle.json").write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
