"""Benchmark: calibrating a flight model on the ammonite record, against gliderflight's calibration in the same run.

(A) ``gc.fit_flight_model`` of ``volume`` and ``Cd0`` (gliderflight law, the design's start: gliderflight's own
values) on the record's default mask (about 1,300 samples). (B) gliderflight's ``SteadyStateCalibrate`` of ``Vg``
and ``Cd0`` on the same samples from the same start (``designs/slocum_flight_fit.py``'s
``gliderflight_calibration``, timed around its ``calibrate`` call only). Both alternate after one untimed warm-up;
medians over ``--repeats``. (C) ``gc.steady_flight`` of 10,000 samples (the record's pitch and heaviness tiled).
BLAS runs on one thread (threadpoolctl), the process on one core. Targets: (A) under 2 s, (C) under 50 ms.

Usage::

    python bench/bench_flight_fit.py                 # 7 repeats
    python bench/bench_flight_fit.py --repeats 3
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

import glidectl as gc
from glidectl.report import load_design

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    design = load_design(ROOT / "designs" / "slocum_flight_fit.py").module
    s = design.FULL
    record = gc.read_dive_record(gc.example_record_path(s.record))
    used = record.mask()
    start = design.gliderflight_start(design.start_vehicle(s), s)
    fits, refs, solves = [], [], []
    with threadpool_limits(1):
        gc.fit_flight_model(start, record)  # warm-up
        design.gliderflight_calibration(record, used, start)
        theta = np.resize(record.pitch[used], 10_000)
        m0 = np.resize(gc.excess_mass(start, record.depth[used], record.buoyancy_volume[used]), 10_000)
        gc.steady_flight(start, theta, m0)
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            fit = gc.fit_flight_model(start, record)
            fits.append(time.perf_counter() - t0)
            ref = design.gliderflight_calibration(record, used, start)
            refs.append(ref["seconds"])
            t0 = time.perf_counter()
            gc.steady_flight(start, theta, m0)
            solves.append(time.perf_counter() - t0)
    out = {"samples_used": int(used.sum()), "fit_median_s": float(np.median(fits)),
           "gliderflight_median_s": float(np.median(refs)), "ratio_gliderflight_over_glidectl":
           float(np.median(refs) / np.median(fits)), "steady_flight_10k_median_s": float(np.median(solves)),
           "fit_rms": fit.rms, "gliderflight_rms": ref["rms"], "fit_nfev": fit.context["nfev"],
           "fit": fit.params, "gliderflight": {"volume": ref["volume"], "Cd0": ref["Cd0"]}, "repeats": args.repeats}
    for k, v in out.items():
        print(f"{k:36s} {v}")
    res = ROOT / "bench" / "results"
    res.mkdir(exist_ok=True)
    (res / "flight_fit.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
