"""Time the chapter-7 design's printed-gains part alone (``designs/ch7_ctol.py`` ``_part(("tracking", FULL,
FULL.printed))``: steady gliding with dt 0.1, k3 7e5, k4 250 over 40 s, about 2 million single-state right-hand-side
calls) with two source trees, alternated in the same session, and compare the runs' histories to the last bit.

    python bench/bench_ch7_printed.py BASE_ROOT NEW_ROOT [REPEATS] [T_FINAL]

Each run is a fresh interpreter with ``PYTHONPATH = ROOT/src`` and ``OMP_NUM_THREADS = OPENBLAS_NUM_THREADS = 1``;
its wall and CPU time are those of the part (``time.perf_counter``, ``time.process_time`` inside the process).
``T_FINAL`` (default: the FULL 40 s) shortens the horizon for a quick look. Prints the medians and whether ``t``,
``x``, ``u``, the error and every interval's glide are bit-for-bit equal between the trees.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

CHILD = r"""
import dataclasses, importlib.util, json, sys, time
import numpy as np
root, t_final, out = sys.argv[1], sys.argv[2], sys.argv[3]
spec = importlib.util.spec_from_file_location("ch7_ctol_bench", f"{root}/designs/ch7_ctol.py")
mod = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = mod
spec.loader.exec_module(mod)
s = mod.FULL if t_final == "full" else dataclasses.replace(mod.FULL, t_final=float(t_final))
t0, c0 = time.perf_counter(), time.process_time()
r = mod._part(("tracking", s, s.printed))
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
glides = np.array([(g.speed, g.gamma, g.theta, g.k1, g.k2) for g in r.glides])
np.savez(out, t=r.t, x=r.x, u=r.u, error=r.error, glides=glides)
print(json.dumps({"wall": wall, "cpu": cpu, "max_error": r.max_error, "n": int(len(r.t))}))
"""


def run(root: Path, t_final: str, out: Path) -> dict[str, float]:
    env = dict(os.environ, PYTHONPATH=str(root / "src"), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    res = subprocess.run([sys.executable, "-c", CHILD, str(root), t_final, str(out)], env=env, check=True,
                         capture_output=True, text=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv: list[str]) -> None:
    import numpy as np

    base, new = Path(argv[0]).resolve(), Path(argv[1]).resolve()
    reps = int(argv[2]) if len(argv) > 2 else 1
    t_final = argv[3] if len(argv) > 3 else "full"
    outdir = Path(tempfile.mkdtemp(prefix="bench_ch7_printed_"))
    times: dict[str, list[dict[str, float]]] = {"base": [], "new": []}
    for i in range(reps):
        for name, root in (("base", base), ("new", new)):
            r = run(root, t_final, outdir / f"{name}_{i}.npz")
            times[name].append(r)
            print(f"{name} run {i}: wall {r['wall']:.1f} s, cpu {r['cpu']:.1f} s, {r['n']} points", flush=True)
    for what in ("wall", "cpu"):
        mb, mn = (statistics.median(r[what] for r in times[k]) for k in ("base", "new"))
        print(f"median {what}: base {mb:.1f} s, new {mn:.1f} s, ratio {mb / mn:.2f}")
    a, b = np.load(outdir / "base_0.npz"), np.load(outdir / "new_0.npz")
    same = {k: a[k].shape == b[k].shape and a[k].tobytes() == b[k].tobytes() for k in a.files}
    print("bit-for-bit equal: " + ", ".join(f"{k} {v}" for k, v in same.items()))


if __name__ == "__main__":
    main(sys.argv[1:])
