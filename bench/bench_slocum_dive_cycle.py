"""Benchmark: ``compute`` of ``designs/slocum_dive_cycle.py`` (issue 18), this checkout against another.

What is timed: ``compute(FULL)`` (or ``QUICK`` with ``--quick``) of the design file, loaded from
``<src>/../designs/slocum_dive_cycle.py`` and run with ``PYTHONPATH=<src>``, in a fresh child process per repeat
(``OMP_NUM_THREADS=1``, ``OPENBLAS_NUM_THREADS=1``: one core). The child times the call with ``time.perf_counter``
after the imports; the two versions are run alternately (new, baseline, new, baseline, ...) so that both see the
same machine load, and the medians are compared. The FULL compute is the envelope (76 x 121 closed-form trims),
the LQR/LQG leg designs, the certify_roa attempt on the LQR loop and the four-controller mission comparison
(3 cycles 5-100 m, sample-and-hold sensor noise every 2 s): almost all of its time is the missions' integration.

With ``--out DIR`` the first repeat of each version also writes the design's report (``DIR/new``,
``DIR/baseline``; not timed) and the script compares the two ``numbers.json`` entry by entry (exact equality, and
the largest relative difference of the numeric entries).

Usage::

    python bench/bench_slocum_dive_cycle.py --baseline-src /path/to/base/src          # FULL, 1 repeat each
    python bench/bench_slocum_dive_cycle.py --baseline-src ../base/src --repeats 3 --out /tmp/slocum_bench
    python bench/bench_slocum_dive_cycle.py --quick --repeats 3                        # this checkout only

Writes ``bench/results/slocum_dive_cycle.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
NEW_SRC = HERE.parent / "src"

CHILD = r"""
import importlib.util, json, sys, time
from pathlib import Path
src, quick, out = sys.argv[1], sys.argv[2] == "1", sys.argv[3]
path = Path(src).resolve().parent / "designs" / "slocum_dive_cycle.py"
spec = importlib.util.spec_from_file_location("slocum_dive_cycle_bench", path)
mod = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = mod
spec.loader.exec_module(mod)
t0 = time.perf_counter()
res = mod.compute(mod.QUICK if quick else mod.FULL)
dt = time.perf_counter() - t0
nfev = {k: int(r.nfev) for k, r in res.comparison.runs.items()}
if out:
    mod.report(res).write(out)
print(json.dumps({"seconds": dt, "nfev": nfev, "rows": [{k: (v if not isinstance(v, float) or v == v else None)
                                                        for k, v in r.items()} for r in res.comparison.rows]}))
"""


def run_once(src: Path, quick: bool, out: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, "-c", CHILD, str(src), "1" if quick else "0", out], env=env,
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise SystemExit(f"child for {src} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def compare_numbers(a: Path, b: Path) -> dict:
    na = {e["name"]: e["value"] for e in json.loads(a.read_text())}
    nb = {e["name"]: e["value"] for e in json.loads(b.read_text())}
    differ, worst = [], 0.0
    for k in sorted(set(na) | set(nb)):
        if na.get(k) != nb.get(k):
            differ.append(k)
            try:
                x, y = np.asarray(na[k], dtype=float), np.asarray(nb[k], dtype=float)
                rel = float(np.max(np.abs(x - y) / np.maximum(np.abs(y), 1e-300)))
                worst = max(worst, rel)
            except (KeyError, TypeError, ValueError):
                worst = math.inf
    return {"entries": len(na), "differ": differ, "max_rel_diff": worst}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline-src", type=Path, default=None, help="src/ folder of the checkout to compare with")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="time compute(QUICK) instead of compute(FULL)")
    ap.add_argument("--out", default="", help="write both reports here (first repeat) and compare numbers.json")
    args = ap.parse_args()
    versions = {"new": NEW_SRC}
    if args.baseline_src is not None:
        versions["baseline"] = args.baseline_src.resolve()
    times: dict[str, list[float]] = {k: [] for k in versions}
    last: dict[str, dict] = {}
    for rep in range(args.repeats):
        for name, src in versions.items():
            out = str(Path(args.out) / name) if args.out and rep == 0 else ""
            r = run_once(src, args.quick, out)
            times[name].append(r["seconds"])
            last[name] = r
            print(f"repeat {rep + 1}: {name:8s} {r['seconds']:8.1f} s  nfev {r['nfev']}", flush=True)
    med = {k: float(np.median(v)) for k, v in times.items()}
    result: dict = {"settings": "QUICK" if args.quick else "FULL", "repeats": args.repeats, "times_s": times,
                    "median_s": med, "nfev": {k: v["nfev"] for k, v in last.items()},
                    "sources": {k: str(v) for k, v in versions.items()}}
    for k, v in med.items():
        print(f"{k:8s} median {v:8.1f} s over {len(times[k])} run(s) ({', '.join(f'{t:.1f}' for t in times[k])})")
    if "baseline" in med:
        result["ratio"] = med["baseline"] / med["new"]
        result["rows_equal"] = last["new"]["rows"] == last["baseline"]["rows"]
        print(f"ratio baseline/new {result['ratio']:.2f}x; mission rows identical: {result['rows_equal']}")
        if args.out:
            result["numbers"] = compare_numbers(Path(args.out) / "new" / "numbers.json",
                                                Path(args.out) / "baseline" / "numbers.json")
            print(f"numbers.json: {result['numbers']['entries']} entries, differing: "
                  f"{result['numbers']['differ'] or 'none'} (max rel diff {result['numbers']['max_rel_diff']:.3g})")
    res_dir = HERE / "results"
    res_dir.mkdir(exist_ok=True)
    (res_dir / "slocum_dive_cycle.json").write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
