"""The moment route's KKT step (``glidectl.roa.sdp_solvers._SparseKKT``: Schur complement and factorizations), per
CVXOPT iteration, on the first level program of a ``bench/bench_roa.py`` case, against a baseline checkout in the
same run.

Usage::

    OMP_NUM_THREADS=1 python bench/bench_moment_kkt.py --cases ctol,glider4 --baseline-src /path/to/old/src

Each (case, checkout) runs in its own subprocess, alternating, ``--repeats`` times; a worker times the first
``--calls`` KKT factorizations of the case's first moment-route program (``__call__``, which forms the Schur
complement and factors it) and reports their median. The ratio is new over baseline (lower is faster).

Measured 2026-12-03 06:52 (2-core machine, ``OMP_NUM_THREADS=1``, ``--cases ctol --repeats 3 --baseline-src
<checkout of abe1ee5>/src``), the CTOL first level (a 103 x 103 Gram block, m = 1740 moment variables, 628
equations): **0.344 s per KKT call against 0.469 s (ratio 0.73)** with the row-grouped Schur complement and
``A'A`` formed once. A variant that also formed ``A (H + A'A)^-1 A'`` as ``X'X`` (``X = L^-1 A'``, one triangular
solve) reached 0.63 but changed where the CTOL margin programs stop (see ``_SparseKKT``) and was not kept.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path


def worker(case: str, calls: int) -> dict:
    sys.path.insert(0, str(Path(__file__).parent))
    import numpy as np

    import bench_roa
    import glidectl as gc
    from glidectl.roa import sdp_solvers as sd

    times: list[float] = []
    real = sd._SparseKKT.__call__

    class Done(Exception):
        pass

    def timed(self: object, W: object) -> object:
        t0 = time.perf_counter()
        f = real(self, W)
        times.append(time.perf_counter() - t0)
        if len(times) >= calls:
            raise Done
        return f

    sd._SparseKKT.__call__ = timed
    model, kw = bench_roa._model(case)
    kw.update(iterations=1)
    try:
        bench_roa.certify(gc, model, **kw)
    except Done:
        pass
    if not times:
        return {"case": case, "error": "no moment-route program"}
    return {"case": case, "median_call_s": float(np.median(times)), "calls": len(times),
            "glidectl": os.path.dirname(gc.__file__)}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", default="ctol")
    ap.add_argument("--baseline-src", default=None, help="src folder of the baseline checkout")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--calls", type=int, default=12)
    ap.add_argument("--worker", nargs=2, default=None)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(worker(args.worker[0], int(args.worker[1]))))
        return
    srcs = {"new": str(Path(__file__).resolve().parents[1] / "src")}
    if args.baseline_src:
        srcs["baseline"] = args.baseline_src
    out = {}
    for case in [c for c in args.cases.split(",") if c]:
        med: dict[str, list[float]] = {k: [] for k in srcs}
        for _ in range(args.repeats):
            for name, src in srcs.items():
                r = subprocess.run([sys.executable, __file__, "--worker", case, str(args.calls)], capture_output=True,
                                   text=True, env=dict(os.environ, PYTHONPATH=src), check=False)
                lines = [ln for ln in r.stdout.splitlines() if ln.startswith("{")]
                res = json.loads(lines[-1]) if lines else {"error": (r.stderr or r.stdout)[-600:]}
                if "median_call_s" not in res:
                    raise SystemExit(f"{case} ({name}): {res}")
                med[name].append(res["median_call_s"])
        row = {name: statistics.median(v) for name, v in med.items()}
        if "baseline" in row:
            row["ratio_new_over_baseline"] = row["new"] / row["baseline"]
        out[case] = row
        print(json.dumps({case: row}), flush=True)


if __name__ == "__main__":
    main()
