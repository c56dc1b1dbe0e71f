"""CVXOPT_MOMENT against Clarabel on the same certificate, in the same run: wall time, solver time, volume.

Usage::

    OMP_NUM_THREADS=1 python bench/bench_sdp_solvers.py --cases glider2,ctol

Each (case, solver) runs in its own subprocess of this checkout, the solvers alternating; the cases and settings
are those of ``bench/bench_roa.py`` (``glider2``: chapter-5 glider, K_M = -50, degree 2, 8 iterations; ``ctol``:
the CTOL closed loop, degree 2, 1 iteration). Results are printed as JSON and written to
``bench/results/sdp_solvers.json``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

SOLVERS = ("CLARABEL", "CVXOPT_MOMENT")


def worker(case: str, solver: str) -> dict:
    sys.path.insert(0, str(Path(__file__).parent))
    import bench_roa
    import glidectl as gc

    model, kw = bench_roa._model(case)
    t0, c0 = time.perf_counter(), time.process_time()
    cert = bench_roa.certify(gc, model, **kw, solver=solver)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {"case": case, "solver": solver, "wall_s": wall, "cpu_s": cpu, "certified": bool(cert.certified),
            "volume": float(cert.volume()),
            "solver_s": float(sum(h.solver_time for h in cert.history if h.solver_time == h.solver_time))}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", default="glider2")
    ap.add_argument("--worker", nargs=2, default=None)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(worker(*args.worker)))
        return
    src = str(Path(__file__).resolve().parents[1] / "src")
    out = {}
    for case in [c for c in args.cases.split(",") if c]:
        row = {}
        for solver in SOLVERS:
            r = subprocess.run([sys.executable, __file__, "--worker", case, solver], capture_output=True, text=True,
                               env=dict(os.environ, PYTHONPATH=src), check=False)
            lines = [ln for ln in r.stdout.splitlines() if ln.startswith("{")]
            row[solver] = json.loads(lines[-1]) if lines else {"error": (r.stderr or r.stdout)[-600:]}
        a, b = row["CVXOPT_MOMENT"], row["CLARABEL"]
        if "error" not in a and "error" not in b:
            row["time_ratio_moment_over_clarabel"] = a["wall_s"] / b["wall_s"]
            row["volume_ratio_moment_over_clarabel"] = a["volume"] / b["volume"]
        out[case] = row
        print(json.dumps({case: row}, indent=1), flush=True)
    res = Path(__file__).parent / "results"
    res.mkdir(exist_ok=True)
    (res / "sdp_solvers.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
