"""Per-call cost of the right-hand sides that the long simulations of the reports call most, against a baseline
checkout in the same run.

- ``ctol_rhs``: :meth:`glidectl.models.ctol.CTOLAircraft.rhs` on one state (the calls of ch7's tracking runs);
- ``ctol_law``: :meth:`glidectl.controllers.ctol.SteadyGlideController.u` on one state;
- ``ctol_augmented``: the tracking's closed-loop right-hand side with its three quadrature states (one state);
- ``nondim_full_4096``: ``SingularPerturbation.full_rhs_nondimensional`` on 4096 states (the batch simulations of
  roa_certification's full-glider parts);
- ``ctol_printed_10s``: ``gc.track_with_steady_glides`` with the printed gains (k3 = 7e5, k4 = 250: the 1522 rad/s
  pitch loop) over 10 s, CPU time, plus a hash of its time, state and input arrays.

Usage::

    OMP_NUM_THREADS=1 python bench/bench_model_rhs.py --baseline-src /path/to/old/src --repeats 3

Each checkout runs in its own subprocess, alternating, ``--repeats`` times; the medians are reported with the ratio
new over baseline (lower is faster) and whether the tracking run's arrays are bitwise the same.

Measured 2026-12-03 20:50 (2-core machine, ``OMP_NUM_THREADS=1``, ``--repeats 1``), 665699d against 2274156:

=====================  ==========  ==========  =====
call                   665699d     2274156     ratio
=====================  ==========  ==========  =====
ctol_rhs               4.54 us     3.20 us     0.71
ctol_law               3.66 us     3.00 us     0.82
ctol_augmented         9.81 us     7.36 us     0.75
nondim_full_4096       0.873 ms    0.470 ms    0.54
ctol_printed_10s       10.40 s     9.09 s      0.87
=====================  ==========  ==========  =====

The printed-gains run hashes the same in both (``printed_bitwise_same: true``).
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


def worker() -> dict:
    import hashlib
    import timeit

    import numpy as np

    import glidectl as gc
    from glidectl.controllers.ctol import SteadyGlideController
    from glidectl.controllers.ctol_tracking import _augmented
    from glidectl.models.ctol import CTOLAircraft

    veh = gc.load_vehicle("dc8_ctol")
    glide = gc.ctol_glide(veh, 0.3, 0.05)
    model, ctrl = CTOLAircraft(veh), SteadyGlideController(veh, glide, 7e5, 250.0, 1.0)
    x = glide.full_state((0.0, 0.0)) + 1e-3
    u = ctrl.u(x)
    z = np.r_[x, 0.0, 0.0, 0.0]
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5", K_M=-50.0))
    Z = np.random.default_rng(0).uniform(-0.5, 0.5, (4096, 4))

    def per_call(f, n):
        return min(timeit.repeat(f, number=n, repeat=5)) / n

    out = {"ctol_rhs": per_call(lambda: model.rhs(x, u), 20000),
           "ctol_law": per_call(lambda: ctrl.u(x), 20000),
           "ctol_augmented": per_call(lambda: _augmented(model, ctrl, z), 20000),
           "nondim_full_4096": per_call(lambda: sp.full_rhs_nondimensional(Z), 200)}
    traj = gc.climb_trajectory(veh, 0.85)
    c0 = time.process_time()
    run = gc.track_with_steady_glides(veh, traj, t_final=10.0).run
    out["ctol_printed_10s"] = time.process_time() - c0
    h = hashlib.sha256(b"".join(np.ascontiguousarray(a).tobytes() for a in (run.t, run.x, run.u)))
    out["printed_hash"] = h.hexdigest()[:16]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline-src", default=None, help="src directory of the checkout to compare with")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        print(json.dumps(worker()))
        return
    here = Path(__file__).resolve().parent
    srcs = {"new": str(here.parent / "src")}
    if a.baseline_src:
        srcs["baseline"] = str(Path(a.baseline_src).resolve())
    runs: dict[str, list[dict]] = {k: [] for k in srcs}
    for _ in range(a.repeats):
        for tag, src in srcs.items():
            env = {**os.environ, "PYTHONPATH": src}
            p = subprocess.run([sys.executable, __file__, "--worker"], capture_output=True, text=True, env=env,
                               check=True)
            runs[tag].append(json.loads(p.stdout.strip().splitlines()[-1]))
    res: dict[str, dict] = {}
    for tag, rs in runs.items():
        res[tag] = {k: statistics.median(r[k] for r in rs) for k in rs[0] if k != "printed_hash"}
        res[tag]["printed_hash"] = sorted({r["printed_hash"] for r in rs})
    if "baseline" in res:
        res["ratio_new_over_baseline"] = {k: res["new"][k] / res["baseline"][k] for k in res["new"]
                                          if k != "printed_hash"}
        res["printed_bitwise_same"] = res["new"]["printed_hash"] == res["baseline"]["printed_hash"]
    (here / "results").mkdir(exist_ok=True)
    (here / "results" / "model_rhs.json").write_text(json.dumps(res, indent=1))
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
