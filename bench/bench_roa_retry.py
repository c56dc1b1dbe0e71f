"""Benchmark: the retried V step of ``certify_roa`` (``glidectl.roa.certify.RETRY_CENTER``) on a perturbed solver.

The saturated user glider's SOS certificate (designs/roa_certification.py, part ``user_sat``: the LQR dive-cycle loop
with its pump saturated, degree 2, two remainder-box rounds of four V steps) is run with Clarabel's default settings
and with its iterative refinement off, each with the retry (``RETRY_CENTER = 0.25``) and without it (0), one
subprocess per run, two at a time. Iterative refinement off makes every Clarabel solve 10-40 % cheaper and moves
the alternation's path: the question is whether a path that meets a V step whose new V has no positive level
still gets somewhere. Reported per run: certified, the SOS volume (``cert.volume()``), the LMI certificate's
volume, the history rows that failed or were retried, wall time.

Run from the project root (about 5 minutes on 2 cores)::

    python bench/bench_roa_retry.py

Writes ``bench/results/roa_retry.json``.

Measured 2026-12-04 11:07-11:12 (tenth session, 2 cores, two runs at a time):

==================  ======  ===========  ==========  =======  ==================================================
settings            retry   SOS volume   LMI volume  wall     what happened
==================  ======  ===========  ==========  =======  ==================================================
default             0.25    3.476e-12    1.766e-15   134.8 s  no V step fails: the retry never runs
default             0       3.476e-12    1.766e-15   133.3 s  (the same run)
refinement off      0.25    2.980e-12    1.285e-15   114.7 s  round 2's first V step: level -2.63e-09; retried
                                                              from the deeper multiplier, round 2 kept
refinement off      0       4.710e-15    1.285e-15   93.9 s   the same failure; round 2 dropped
==================  ======  ===========  ==========  =======  ==================================================

Also measured and not kept (same part, same day, by hand): Clarabel's iterative refinement at one step or at reltol
1e-10 (instead of 1e-13) for every program, without the retry: 4.71e-15, the same failure (level -2.78e-07 at one
step; the LMI certificate's volume moved too, 1.77e-15 to 4.5e-16
at one step); refinement off for the V steps only (``steering`` programs): the 4-state glider's (K_M = -100) V
steps then steered to sets whose sampled volume was 1e7 times smaller than the starting V's (no failure, a worse
path), so its certificate was the starting V's, volume 4.0e-6 against 0.169: the speed-up (V step 6.1 s -> 3.9 s
on the user glider) is not worth it; Clarabel's chordal decomposition off: bitwise the same solution,
no faster (the Gram blocks are dense). Routing the user glider's V steps to the moment route with their sample
equations counted out (the eliminated ones): every V step and its retry ended with levels of -1.5e-9 to -4.5e-8,
volume 5.3e-16 -- the moment route's optimal-face points are the wrong steering for these programs, retry or not.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RUNS = [("default", 0.25), ("default", 0.0), ("refinement off", 0.25), ("refinement off", 0.0)]


def _worker(settings: str, retry: float) -> dict:
    """Child process: the user_sat part with the given Clarabel settings and RETRY_CENTER."""
    import matplotlib

    matplotlib.use("Agg")
    from glidectl.roa import certify, lmi, sdp_solvers, sos

    if settings == "refinement off":
        base = sdp_solvers.solver_options

        def options(solver: str) -> dict:
            o = base(solver)
            return {**o, "iterative_refinement_enable": False} if solver == "CLARABEL" else o

        sdp_solvers.solver_options = sos.solver_options = lmi.solver_options = options
    certify.RETRY_CENTER = retry
    from glidectl.report import load_design

    mod = load_design("roa_certification", ROOT / "designs").module
    t0 = time.perf_counter()
    _, res, _ = mod._saturated_part(mod.FULL, "user_sat")
    wall = time.perf_counter() - t0
    case = res["user_sat"]
    cert = case["sos"].get("cert")
    rows = [h.step for h in cert.history if "failed" in h.step or "not kept" in h.step] if cert else []
    return {"settings": settings, "retry_center": retry, "certified": bool(cert is not None and cert.certified),
            "sos_volume": case["sos"].get("volume", 0.0), "lmi_volume": case["cert"].volume(),
            "error": case["sos"].get("error"), "failed_or_dropped": rows, "wall_s": wall}


def _run(settings: str, retry: float) -> dict:
    cmd = [sys.executable, __file__, "--worker", settings, str(retry)]
    env = {**os.environ, "OMP_NUM_THREADS": "1", "RAYON_NUM_THREADS": "1"}
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT, timeout=3600)
    if out.returncode != 0:
        return {"settings": settings, "retry_center": retry, "error": out.stderr[-2000:]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", nargs=2, default=None)
    ap.add_argument("--parallel", type=int, default=2, help="runs at a time")
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(_worker(args.worker[0], float(args.worker[1]))))
        return
    with ThreadPoolExecutor(args.parallel) as ex:
        results = list(ex.map(lambda r: _run(*r), RUNS))
    for r in results:
        print(f"{r['settings']:15s} retry {r['retry_center']:<5g} certified {r.get('certified')} "
              f"SOS volume {r.get('sos_volume', 0.0):.4g} LMI {r.get('lmi_volume', 0.0):.4g} "
              f"wall {r.get('wall_s', 0.0):.1f} s  {'; '.join(r.get('failed_or_dropped', []))[:200]}")
    out = ROOT / "bench" / "results" / "roa_retry.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
