"""Benchmark: a three-cycle dive-cycle mission between 5 and 100 m (``glidectl.dive_cycle``), target < 5 s.

Vehicle: ROGUE (``rogue``, §2.3.1) with an actuator table for development: pump ``m0`` in [-0.8, 0.8] kg at
0.02 kg/s, battery ``r_P1`` in [-0.04, 0.04] m at 5 mm/s, ``r_P3`` fixed at 0.02 m (bottom-heavy). Mission: glides
at 0.35 m/s and +-25 deg, 3 cycles. The whole ``dive_cycle`` call is timed (designs, supervisor, integration with
LSODA, metrics); median over ``--repeats`` after one untimed warm-up. Prints the timings, the right-hand-side
evaluations and the per-cycle metrics, and writes ``bench/results/dive_cycle.json``.

``--compare`` also times, in the same process and interleaved with the default runs, the mission with the
one-point fast paths of the right-hand side disabled (every call goes through the array path, as before the fast
path existed: ``ActuatedGlider.rhs`` and ``acceleration_rates`` on 1 x 11 arrays), checks that both give the same
metrics, and prints the ratio of the medians. ``--vehicle slocum_shallow`` flies the preset of issue 16 instead.

Usage::

    python bench/bench_dive_cycle.py                      # LQR, 3 repeats
    python bench/bench_dive_cycle.py --compare --repeats 5
    python bench/bench_dive_cycle.py --controller pid --repeats 1
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

import glidectl as gc

ACTUATORS = {"m0": {"min": -0.8, "max": 0.8, "rate": 0.02}, "r_P1": {"min": -0.04, "max": 0.04, "rate": 0.005},
             "r_P3": {"fixed": 0.02}}
TARGET = 5.0


@contextlib.contextmanager
def array_path() -> Iterator[None]:
    """Route the one-point calls of the actuated right-hand side through the array path (the code before the fast
    path): the same equations on 1 x 11 arrays."""
    cls = gc.ActuatedGlider
    rhs, acc = cls.rhs, cls.acceleration_rates
    cls.rhs = lambda self, x, u: rhs(self, np.asarray(x)[None], np.asarray(u)[None])[0]  # type: ignore[method-assign]
    cls.acceleration_rates = lambda self, x, w: acc(self, np.asarray(x)[None], np.asarray(w)[None])[0]  # type: ignore[method-assign]
    try:
        yield
    finally:
        cls.rhs, cls.acceleration_rates = rhs, acc  # type: ignore[method-assign]


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
    ap.add_argument("--compare", action="store_true", help="also time the array path (before the fast path)")
    args = ap.parse_args()
    if args.vehicle == "rogue":
        veh = gc.load_vehicle("rogue").with_actuators(**ACTUATORS)
    else:
        veh = gc.load_vehicle("slocum_shallow")
    mission = dict(depths=(5.0, args.bottom), gamma=math.radians(25.0), speed=0.35, cycles=args.cycles, seed=0)
    run = gc.dive_cycle(veh, args.controller, **mission)  # warm-up (imports, caches)
    times, before = [], []
    old = None
    for _ in range(args.repeats):
        dt, run = timed(veh, args.controller, mission)
        times.append(dt)
        if args.compare:
            with array_path():
                dt, old = timed(veh, args.controller, mission)
            before.append(dt)
    med = float(np.median(times))
    print(run.summary())
    print(f"{args.vehicle}, {args.controller}: {args.cycles} cycles 5-{args.bottom:g} m, simulated {run.t[-1]:.0f} s, "
          f"{run.nfev} right-hand-side evaluations; wall time median {med:.2f} s over {args.repeats} repeats "
          f"(all: {', '.join(f'{t:.2f}' for t in times)}); target < {TARGET:g} s: "
          f"{'met' if med < TARGET else 'NOT met'}")
    result = {"vehicle": args.vehicle, "controller": args.controller, "cycles": args.cycles,
              "depths": [5.0, args.bottom], "times_s": times, "median_s": med, "nfev": run.nfev,
              "simulated_s": float(run.t[-1]), "cycles_metrics": [run.as_dict()]}
    if args.compare and old is not None:
        mb = float(np.median(before))
        new_row, old_row = run.as_dict(), old.as_dict()
        worst = max(abs(new_row[k] - old_row[k]) / max(1.0, abs(old_row[k])) for k in new_row
                    if isinstance(new_row[k], float))
        print(f"array path (before): median {mb:.2f} s (all: {', '.join(f'{t:.2f}' for t in before)}), "
              f"{old.nfev} evaluations; speed-up {mb / med:.2f}x; largest relative difference of the metrics "
              f"{worst:.1e}")
        result.update({"before_times_s": before, "before_median_s": mb, "before_nfev": old.nfev,
                       "speedup": mb / med, "metrics_max_rel_diff": worst})
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "dive_cycle.json").write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
