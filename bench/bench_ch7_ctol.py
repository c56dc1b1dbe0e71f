"""Wall and CPU time of the chapter-7 design's FULL build (``glidectl report ch7_ctol --no-cache``) with two source
trees, alternated in the same session, and a comparison of their ``numbers.json`` entry by entry.

    python bench/bench_ch7_ctol.py BASE_ROOT NEW_ROOT [REPEATS] [OUTDIR]

Each root is a checkout (its ``src`` on ``PYTHONPATH``, its ``designs/ch7_ctol.py`` built from it); the command runs
with the build's default ``--jobs`` (all cores) and ``OMP_NUM_THREADS = OPENBLAS_NUM_THREADS = 1``. CPU time is that
of the command and every process it started (``RUSAGE_CHILDREN``). Outputs go to ``OUTDIR/{base,new}_<i>/``.
"""

from __future__ import annotations

import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def build(root: Path, out: Path) -> tuple[float, float]:
    env = dict(os.environ, PYTHONPATH=str(root / "src"), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "glidectl", "report", "ch7_ctol", "--out", str(out), "--no-cache"],
                   cwd=root, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def compare(a: Path, b: Path) -> list[str]:
    na = {e["name"]: e for e in json.loads((a / "ch7_ctol" / "numbers.json").read_text())}
    nb = {e["name"]: e for e in json.loads((b / "ch7_ctol" / "numbers.json").read_text())}
    diffs = [f"only in one: {sorted(set(na) ^ set(nb))}"] if set(na) != set(nb) else []
    for k in na.keys() & nb.keys():
        for f in ("value", "published", "reproduced", "note"):
            if na[k].get(f) != nb[k].get(f):
                diffs.append(f"{k}.{f}: {na[k].get(f)!r} -> {nb[k].get(f)!r}")
    return diffs


def main(argv: list[str]) -> None:
    base, new = Path(argv[0]).resolve(), Path(argv[1]).resolve()
    reps = int(argv[2]) if len(argv) > 2 else 1
    outdir = Path(argv[3]) if len(argv) > 3 else Path(tempfile.mkdtemp(prefix="bench_ch7_"))
    times: dict[str, list[tuple[float, float]]] = {"base": [], "new": []}
    for i in range(reps):
        for name, root in (("base", base), ("new", new)):
            w, c = build(root, outdir / f"{name}_{i}")
            times[name].append((w, c))
            print(f"{name} run {i}: wall {w:.1f} s, cpu {c:.1f} s", flush=True)
    mw = {k: statistics.median(w for w, _ in v) for k, v in times.items()}
    mc = {k: statistics.median(c for _, c in v) for k, v in times.items()}
    print(f"median wall: base {mw['base']:.1f} s, new {mw['new']:.1f} s, ratio {mw['base'] / mw['new']:.2f}")
    print(f"median cpu: base {mc['base']:.1f} s, new {mc['new']:.1f} s, ratio {mc['base'] / mc['new']:.2f}")
    diffs = compare(outdir / "base_0", outdir / "new_0")
    print(f"numbers.json: {len(diffs)} differing fields" + "".join(f"\n  {d}" for d in diffs))


if __name__ == "__main__":
    main(sys.argv[1:])
