"""Benchmark: region-of-attraction certification, against Drake and against another glidectl checkout (today's).

(A) glidectl ``max_level`` (Drake's fixed-V problem, one SDP through cvxpy/Clarabel) and (B) Drake's
``RegionOfAttraction`` (when ``pip install -e ".[drake]"``), timed alternately in one process, medians over
repeats. Without pydrake, Drake's stored numbers are reported instead: level 2.3045 of ``V = x'Px`` on Van der Pol
(``test_van_der_pol_level_equals_drake``), i.e. 47 % of the true area; no stored Drake time.

(C) The issue-17 speed targets, each run in a subprocess (one per case and code version, so the timings do not
share caches), for this checkout and, with ``--baseline-src DIR``, for another checkout's ``src`` (e.g. the base
of the speed branch) in the same run:

- ``vdp``: ``certify_roa(van_der_pol(), degree=6, iterations=6, backoff=0.003)``: >= 96 % of the true area
  (13.7222) in under 3 s;
- ``glider2`` / ``glider4``: the 4-state chapter-5 glider (``sphere_ch5``, ``K_M = -50``, its ``full_model()``
  box, as in designs/roa_certification.py) at degree 2 (8 iterations, the design's settings: the reference
  volume) and degree 4 (target: under 60 s with volume >= the degree-2 one);
- ``glider4_staged``: the same glider at degree 4 with ``iterations=(9, 1)`` (nine quadratic V steps, then one
  quartic): the V is taken far at degree 2, where a V step costs 3-7 s, before the one quartic step (45-60 s). It
  needs a checkout whose ``certify_roa`` takes a count per degree;
- ``ctol``: the CTOL closed loop of designs/roa_certification.py ``_ctol`` (``ClosedLoopCTOL(veh, gl, 10, 5)``,
  degree 2, 1 iteration): under 60 s with volume >= 0.00441.

Every case reports wall time, total SDP time, the certified volume (``cert.volume(n=2**16)``), ``certified``,
every step of ``cert.history`` (``history``: step, level, sampled volume, SDP time) and, where the code records
them, cvxpy compile and solver times summed over the history. ``--time-limit`` is passed to
``certify_roa`` with ``on_budget="stop"`` (the best V so far is certified; 0 = none).
``cpu_s``: CPU time of the certification (less sensitive to the load than the wall time); the versions alternate
run by run.

(D) ``--cases glider4_sdp``: one degree-4 level SDP of that glider with and without the exact basis reduction (the
unreduced program is today's), sizes and times (printed only).

Measured 2026-12-01 on the shared 2-core machine (load 4-10, so absolute times are inflated; ratios are from the
same run), this branch against its base (``--baseline-src`` of a checkout of 5cf147f):

- vdp: 4.46 s vs 11.54 s (ratio 0.39), SDP time 1.96 s vs 8.46 s (0.23), 96.5 % vs 96.4 % of the true area,
  certified; the rest of the wall time is the simulated guidance (2048 simulations), the verification
  (20000 samples, 256 simulations) and the sampled volumes, not SDPs. Target (< 3 s) not met.
- vdp, issue 17 part 5 against c6c3172 (``--cert-repeats 3``, versions alternated, load average 29-34 on the 2
  cores, so wall times are ~5x inflated): median wall 22.2 s vs 28.6 s (paired ratios 0.69, 0.78, 0.62), CPU
  3.74 s vs 5.89 s (0.64); cvxpy compile 2.49 s vs 3.89 s (10 programs built instead of 42: reused with
  Parameters), Clarabel iterations the same (606 vs 619); 96.49 % of the true area both, certified, same 15
  steps. An earlier run (load 35): wall 25.7 s vs 42.3 s, CPU 3.82 s vs 5.13 s (0.74). Scaled to the 4.46 s
  above, ~2.9-3.3 s idle: the < 3 s target is not shown on this machine.
- vdp, main after the merges (2026-12-02 00:11, nearly idle: load 0.8), ``--cases vdp --cert-repeats 3 --repeats 1
  --baseline-src <checkout of c6c3172>/src``: median wall **2.96 s** (2.96, 2.63, 3.01) vs 4.98 s (ratio 0.595),
  CPU 2.97 s vs 5.00 s, Clarabel 1.03 s vs 1.23 s, cvxpy compile 0.27 s vs 0.69 s, 96.49 % of the true area both,
  certified, 15 steps: the target (>= 96 % in < 3 s) is met, narrowly (one of three runs took 3.01 s).
- glider2 (degree 2, 8 iterations): 124.6 s vs 134.2 s (separate runs), same volume 0.1585 (same V path; no basis
  reduction applies at degree 2). Re-measured 2026-12-01 23:00-23:31 (branch s-g4 against c6c3172, load 19-35):
  1402.5 s vs 730.0 s wall, SDP 1142.7 s vs 596.5 s (cvxpy compile 12.9 s vs 7.6 s), both certified, volume 0.15853
  in both: the same programs (the default ``inner="sos"`` is today's path), so the ratio 1.92 is the load (the new
  run overlapped other jobs); one degree-2 level SDP alternated 3 times: 14.9 s vs 11.9 s (medians), 24 Clarabel
  iterations each, identical level. Compile is ~1 % of the SDP time: Parameter reuse cannot help, the time is
  Clarabel's factorization of the dense 1225-entry PSD block (49 x 49 Gram matrix).
- glider4 / ctol: not reached: the degree-4 glider level program has a dense support (no reduction: 104 x 104), one
  such SDP took 546 s of Clarabel time under load; the CTOL degree-2 program (103 x 103) is unreduced too.
  Re-measured (one level SDP, V = V2 + 0.1 V2^2, load 25-35): 7772 variables, 8701 constraints, PSD blocks of
  5460/1596/210/21 entries, build 3.7 s, compile 0.5 s, Clarabel (faer) 2341 s in 37 iterations. The inner
  approximations of the same program (``SOSProgram(cone=...)``): SDSOS 22.8 s (61 iterations) but level -0.0036
  (cannot certify the V), DSOS infeasible; at degree 2 SDSOS gives level -0.58 against SOS 2.0e-5. So
  ``certify_roa(inner="sdsos")`` does not apply to this glider, and with the final certificate a full SOS program
  the degree-4 target (< 60 s) is out of reach while the decrease Gram matrix stays 104 x 104.
- ctol (2026-12-01 evening, load 12-36): not timed end to end (one 103 x 103 level SDP took 3-4 min per
  interior-point iteration at load 28; the baseline run did not finish). The run now solves 5 programs of that size
  instead of 6 (the last level problem is not centred; same certificate); ``bench/bench_roa_ctol_sizes.py`` prints
  what is built and why nothing reduces (full support of degree 6 in 7 lifted variables; a recast of 40-136 s).
- ctol (2026-12-02, third session, inside two FULL ``glidectl report all --no-cache --jobs 2`` builds): 1488.7 s and
  1338.1 s (SDP 1466 s and 1315 s), volume 0.004193 (0.95 of the target 0.00441), certified with the Gram check that
  makes the S-procedure multipliers exactly SOS (largest shift 3.7e-8, slack 4.8e-5): 22-25x the 60 s target. A
  capped recast (22-57 terms per component instead of 180-232) leaves the 103 x 103 block; the surrogate route fails
  the local robust decrease (quadratic remainder); ``inner="sdsos"`` fails its first level problem.
- vdp and ctol, 2026-12-02 13:16-13:46 (fifth session, nearly idle), ``--cases vdp,ctol --repeats 1
  --baseline-src <checkout of c459f0e>/src``, this checkout 224d84c: vdp 2.93 s vs 3.04 s (ratio 0.97), 96.5 % of
  the true area both, certified (target met). ctol **567.7 s vs 1108.0 s** (ratio 0.51; CPU 818 s vs 1669 s, 0.49),
  SDP 549 s vs 1091 s, both certified, volume **0.000815 vs 0.00385** (ratio 0.21): 9.5x the 60 s target. The volume
  is smaller on purpose: the recast now lifts angles by the chain rule and the multipliers of cuts have no constant
  monomial (an exact facial reduction), and the old certificates rested on a solver residual of ~4e-8 on the
  constant monomial of the decrease condition (tau(0) ~ 4e-8 with linear terms ~3e-3, which no exact certificate
  can have), so they proved dV/dt < 0 only outside a small ball. The exact program's level for the starting V is
  0.0012-0.0014 against 0.0025-0.0044 before, so the volume target 0.00441 was set by that residual.
- ctol and glider4, 2026-12-02 16:30-17:40 (seventh session, 99f604b; the ``ctol`` and ``glider4`` cases of this
  file run with every SDP timed, ``OMP_NUM_THREADS=1``): ctol alone **215.3 s**, volume **0.00207**, certified
  (backoff 0.027), against 369-396 s and 0.000982 at 7059cd5: the V step, with its hinge at one equation per
  sample, takes the moment route (57 s against 226 s in Clarabel); the centering feasibility program (Clarabel,
  65-95 s) is now the largest step; 3.6x the 60 s target. glider4 (beside CI, not timed end to end): volume 0.15527
  (>= the degree-2 0.154291: volume target met), about 116 s per degree-4 alternation alone (V step 62-74 s on the
  moment route, centering 45-60 s in Clarabel, level 8-15 s): about 8x the 60 s target.
- ctol, glider2 and glider4, 2026-12-02 20:45-21:10 (eighth session, a fresh machine; ``OMP_NUM_THREADS=1``, two
  single-threaded runs side by side): with the large programs centred by their capped level program
  (``certify.CENTER_BY_LEVEL_MIN_BLOCK``) and the projected Gram check, ctol **175.5 s** (CPU 168.1 s), certified at
  backoff 0.003, volume **0.002161**, against b8bdaf6's 330.0 s (CPU 320.3 s), volume 0.001941 on this machine (its
  final margin failed at backoffs 0.003, 0.009 and 0.027 and passed at 0.081; the previous machine passed at 0.027
  with 0.002069): ratio 0.53 in time, 1.11 in volume; 2.9x the 60 s target. glider2 unchanged: 0.1542909 (its
  blocks are 49 x 49: Clarabel's centering stays). glider4: 520.3 s, volume 0.154598 (>= 0.154291); one degree-4
  alternation is a V step of 66 s (moment route, 29 iterations), a level program of 13 s and its capped re-solve of
  12 s: about 9x the 60 s target.
- ctol and glider4, 2026-12-03 06:11-06:25 (ninth session, another machine, about 1.6x faster than the eighth's;
  the same two runs side by side, abe1ee5 against a1b820c, the moment route's Schur complement from the rows of
  each moment column): ctol CPU **134.0 s vs 165.3 s** (ratio 0.81; wall 292 s vs 324 s: two stray runs shared the
  cores), the same path and volume **0.002124** (backoff 0.003 fails by rounding on this machine, 0.009 passes):
  2.2x the 60 s target in CPU time. glider4 **336.7 s vs 393.6 s** (0.86; CPU 318.9 s vs 376.5 s), the same path,
  volume 0.154601 (>= 0.154291); a degree-4 alternation (V step + level) 73 s against 86-96 s: 5.6x the target.
- ctol and glider4, 2026-12-03 08:16-08:38 (tenth session, the ninth's machine; ``hist.py``: this module's
  ``_model(case)`` through ``gc.certify_roa``, two single-threaded runs side by side, 4582c9b against 1bfa43c, the
  final margin check with its unreached residual polished by the free multipliers): ctol **111.5 s vs 125.4 s**
  (0.89; CPU 109.9 s vs 123.7 s), certified at backoff **0.003** (it failed there by a slack of -0.00049 and passed
  at 0.009 before), volume **0.00216064** against 0.00212402; one margin SDP fewer, the rest the same path: 1.86x
  the 60 s target. glider4 316.8 s vs 315.1 s, the same path and volume 0.154601 (its margin passed at 0.003
  before): 5.3x the target.
- 2026-12-03 12:21-12:55 (eleventh session, main at 1f82e01 and its successor, each case alone, single-threaded,
  ``--repeats 1``): vdp **2.44 s**, 96.50 % of the true area, certified (target met: 0.81 of the time). ctol
  **89.9 s**, volume 0.00216064, certified: 1.50x the 60 s target (the same path as 111.5 s above, measured side by
  side there). ``--cases glider4_staged,glider4`` in one run: glider4_staged (``iterations=(9, 1)``) **109.2 s**
  (CPU 110.8 s, SDP 96.5 s), volume **0.197150**, certified, against glider4 (``iterations=4``) 321.5 s (CPU 320.8 s),
  volume 0.154601: ratio **0.34** in time, **1.275** in volume. The staged run is 1.82x the 60 s target, with a
  volume 1.28 times the degree-2 reference 0.154291. Its one quartic V step is 49 s of it (the moment route: 3581
  moment variables, 2048 of them the samples' equations, one 104 x 104 Gram block); nine quadratic steps take
  2.7-6.7 s each, and each still enlarges the set (0.0086 -> 0.171).
- ctol and glider4_staged, 2026-12-03 14:40-14:50 (twelfth session; two single-threaded runs side by side, 40abd49
  against this session's ``_SparseKKT.schur``, which keeps ``Ylow`` column-major so that the sparse product does
  not copy it and symmetrizes in place: bitwise the same Schur complement): ctol **106.9 s vs 111.4 s** (0.96; CPU
  104.8 s vs 110.3 s), the same volume 0.00216064, certified: 1.78x the 60 s target in this loaded pair (1.50x
  alone, above). glider4_staged **106.2 s vs 106.6 s** (1.00), the same volume 0.197150: its quartic V step's time
  is not in the Schur complement's copies. Both targets stay unmet.
- 2026-12-03 17:52-18:03 (thirteenth session, main at ee44935, nothing else running; ``--cases
  vdp,ctol,glider4_staged --repeats 3``, first with ``OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1``, what a worker of
  ``glidectl report all`` now gets on 2 cores, then with the libraries' defaults, one thread per core): vdp **2.27
  s** (1.92 s), 96.50 % of the true area, certified: 0.76 of the 3 s target. ctol **84.6 s**, CPU 84.5 s (defaults:
  81.2 s, CPU 137.5 s), volume 0.00216064, certified: **1.41x** the 60 s target. glider4_staged **80.3 s**, CPU
  80.3 s (defaults: 82.5 s, CPU 143.5 s), volume **0.197147** (defaults: 0.197141; 0.197150 in the eleventh
  session), certified: **1.34x** the 60 s target, 1.28 times the degree-2 volume. The second thread of OpenBLAS
  and faer buys no wall time on these programs and costs 1.6-1.8x the CPU; the volumes differ by the rounding of
  the thread count (as the report builds' numbers do: ``bench/bench_report_all.py``).
- 2026-12-04 04:20-04:27 (eighth session, 2742e85: Clarabel and BLAS held to one thread inside the ROA layer, so
  the results no longer depend on the thread count; ``--cases vdp,ctol,glider4_staged --repeats 1``, alone, with
  ``OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1``, not paired with a base run): vdp **2.59 s**, 96.49 % of the true area,
  certified (target met). ctol **91.0 s**, volume 0.00216064 (unchanged), certified: 1.52x the 60 s target.
  glider4_staged **85.8 s**, volume **0.197132** (0.197147 before: Clarabel's ``max_threads=1`` rounds differently
  from its default with one rayon thread), certified: 1.43x the target, 1.28 times the degree-2 volume. The times
  are within this machine's drift of the thirteenth session's (no solver path got slower: the same steps).
- 2026-12-04 06:12-06:17 (ninth session, 73dce59 against 1574fa3 in the same run: ``OMP_NUM_THREADS=1
  RAYON_NUM_THREADS=1 python bench/bench_roa.py --cases vdp,ctol,glider4_staged --repeats 1 --baseline-src
  <checkout of 1574fa3>/src``, nothing else running). The large programs match their coefficients modulo the angle
  equalities (``roa/quotient.py``: no multiplier unknowns, 1113 equations instead of 1739 on the CTOL), the V step on
  the moment route stops at ``STEERING_TOLERANCES`` and eliminates its sample equations first
  (``ELIMINATE_DIAGONAL``): vdp **1.86 s** vs 2.23 s (0.84), 96.50 % of the true area both, certified (target met:
  0.62 of 3 s). ctol **36.0 s** vs 81.5 s (ratio **0.44**; SDP 24.2 s vs 69.7 s), certified, volume 0.00216064 both
  (the same Sobol count): **0.60 of the 60 s target**, met in time; the volume target 0.00441 stays the residual
  artifact explained above. glider4_staged **46.6 s** vs 78.5 s (**0.59**; SDP 39.9 s vs 71.6 s), certified, volume
  0.197132 both (1.28 times the degree-2 reference 0.154291): **0.78 of the 60 s target**, met. The degree-2 steps
  of glider4_staged are the same programs as before (their Gram order 49 is under ``QUOTIENT_MIN_BLOCK``); its
  quartic V step took 38 iterations (was 49 s, now about 25 s).
- Drake: pydrake not installed; stored level 2.3045 (47.2 % of the true area), no stored time.

Run ``python bench/bench_roa.py [--repeats N] [--cases vdp,glider2,glider4,glider4_staged,ctol]
[--baseline-src DIR]``; writes ``bench/results/roa.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

VDP_TARGET_S = 3.0
VDP_TARGET_FRACTION = 0.96
GLIDER_TARGET_S = 60.0
CTOL_TARGET_S = 60.0
CTOL_TODAY_VOLUME = 0.00441
GLIDER2_TODAY_VOLUME = 0.154291     # the glider2 case's certified volume (degree 2, 8 iterations; unchanged since)
DRAKE_VDP_RHO = 2.3045          # Drake's RegionOfAttraction level of V = x'Px on Van der Pol (stored)


def _model(case: str):
    import glidectl as gc

    if case == "vdp":
        return gc.benchmarks.van_der_pol(), {"degree": 6, "iterations": 6, "backoff": 0.003}
    if case in ("glider2", "glider4", "glider4_staged"):
        fm = gc.singular_perturbation(gc.load_vehicle("sphere_ch5", K_M=-50.0)).full_model()
        it = {"glider2": 8, "glider4": 4, "glider4_staged": (9, 1)}[case]
        return fm, {"degree": 2 if case == "glider2" else 4, "iterations": it, "backoff": 0.003, "n_truth": 2048}
    if case == "ctol":
        veh = gc.load_vehicle("dc8_ctol")
        gl = gc.ctol_glide(veh, speed=0.85 / math.sqrt(veh.a_L), gamma=0.0)
        return (gc.ClosedLoopCTOL(veh, gl, 10.0, 5.0).roa_model(),
                {"degree": 2, "iterations": 1, "backoff": 0.003, "n_truth": 1024})
    raise SystemExit(f"unknown case {case}")


_GROUPS = {"n_truth": "sampling", "n_verify": "sampling", "n_simulate": "sampling", "horizon": "sampling",
           "seed": "sampling", "time_limit": "budget", "memory_limit": "budget", "max_degree": "budget",
           "on_budget": "budget", "backoff": "solver", "eps": "solver", "center": "solver", "extra": "solver",
           "reuse": "solver", "inner": "solver", "solver": "solver"}


def certify(gc, model, **kw):
    """``gc.certify_roa(model, **kw)`` with flat keyword arguments, on this tree or on an older one: where
    certify_roa groups its options (``sampling=``, ``budget=``, ``solver=``), the flat ones are grouped."""
    if not hasattr(gc, "SamplingOptions"):
        return gc.certify_roa(model, **kw)
    grouped: dict = {}
    for k in [k for k in kw if k in _GROUPS]:
        v = kw.pop(k)
        grouped.setdefault(_GROUPS[k], {})["name" if k == "solver" else k] = v
    return gc.certify_roa(model, **kw, **grouped)


def worker(case: str, time_limit: float) -> dict:
    """One certification in this process (imports whatever glidectl PYTHONPATH gives)."""
    import glidectl as gc

    model, kw = _model(case)
    if time_limit > 0:
        kw.update(time_limit=time_limit, on_budget="stop")
    t0, c0 = time.perf_counter(), time.process_time()
    cert = certify(gc, model, **kw)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    hist = list(cert.history)
    out = {"case": case, "wall_s": wall, "solve_s": float(cert.solve_time), "certified": bool(cert.certified),
           "degree": int(cert.degree), "volume": float(cert.volume(n=2**16)), "steps": len(hist),
           "stopped_by": getattr(cert, "stopped_by", ""), "glidectl": os.path.dirname(gc.__file__)}
    out["cpu_s"] = cpu
    rows = [h if isinstance(h, dict) else vars(h) for h in hist]      # dicts on older trees, HistoryRow now

    def total(key: str) -> float:       # (NaN: not recorded)
        return float(sum(v for h in rows if (v := h.get(key, 0.0)) == v))

    if rows and "compile_time" in rows[0]:
        out["compile_s"], out["solver_s"] = total("compile_time"), total("solver_time")
    if case == "vdp":
        out["fraction_of_true"] = out["volume"] / gc.benchmarks.VAN_DER_POL_AREA
    # the path: every step of the history (which backoff the final margin passed at, the rounds tried)
    out["history"] = [{"degree": int(h["degree"]), "step": str(h["step"]), "rho": float(h["rho"]),
                       "volume": float(h["volume"]), "sdp_s": float(h["sdp_time"])} for h in rows]
    return out


def glider4_sdp() -> dict:
    """One degree-4 level SDP of the 4-state glider (the issue's "104 x 104 Gram matrix, 98 s"), with the exact basis
    reduction and without it (today's program), in this process: sizes, compile and solver times, and levels."""
    import glidectl as gc
    from glidectl.roa import certify as C

    fm = gc.singular_perturbation(gc.load_vehicle("sphere_ch5", K_M=-50.0)).full_model()
    ps = C.recast(fm)
    k = C.variable_scaling(ps)
    pss = C.rescaled(ps, k)
    F = C.scaled_field(pss)
    V2 = C.to_scaled(C.lyapunov_quadratic(ps), k)
    V = V2 + V2 * V2 * 0.1
    ex = C.auto_extra(ps, None)
    out = {}
    for tag, sym in (("reduced", True), ("today_program", False)):
        t0 = time.perf_counter()
        prog, o = C.build_program(pss, F, 4, V=V, lam=None, rho=None, eps=0.0, extra=ex, symmetry=sym)
        prog.constraints.append(o["rho"].var <= 1e6)
        build = time.perf_counter() - t0
        import cvxpy as cp

        rho = prog.solve(cp.Maximize(o["rho"].var[0]))
        out[tag] = {"gram": prog.gram_sizes(), "build_s": build, "compile_s": prog.compile_time,
                    "solver_s": prog.solver_time, "solve_s": prog.solve_time, "rho": rho, "status": prog.status}
        print(json.dumps({tag: out[tag]}), flush=True)
    out["solve_ratio_reduced_over_today"] = out["reduced"]["solve_s"] / out["today_program"]["solve_s"]
    return out


def run_case(case: str, src: str, time_limit: float, timeout: float) -> dict:
    env = dict(os.environ, PYTHONPATH=src)
    cmd = [sys.executable, __file__, "--worker", case, "--time-limit", str(time_limit)]
    try:
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"case": case, "error": f"timed out after {timeout:g} s", "glidectl": src}
    lines = [ln for ln in r.stdout.splitlines() if ln.startswith("{")]
    if r.returncode or not lines:
        return {"case": case, "error": (r.stderr or r.stdout)[-600:], "glidectl": src}
    return json.loads(lines[-1])


def drake_part(repeats: int) -> dict:
    import glidectl as gc
    from glidectl.roa import lyapunov_matrix, lyapunov_quadratic, max_level

    vdp = gc.benchmarks.van_der_pol()
    V = lyapunov_quadratic(vdp)
    ours, theirs, rho_ours, rho_drake = [], [], np.nan, np.nan
    max_level(vdp, V)
    have_drake = gc.benchmarks.drake_van_der_pol(1) is not None
    for _ in range(repeats):
        t0 = time.perf_counter()
        rho_ours = max_level(vdp, V).rho
        ours.append(time.perf_counter() - t0)
        if have_drake:
            d = gc.benchmarks.drake_van_der_pol(1)
            rho_drake = d["rho"]
            theirs.append(d["time"])
    if not have_drake:
        rho_drake = DRAKE_VDP_RHO
    return {
        "max_level_median_s": float(np.median(ours)), "max_level_rho": rho_ours,
        "drake_installed": have_drake, "drake_median_s": float(np.median(theirs)) if theirs else None,
        "drake_rho": rho_drake, "drake_rho_source": "measured" if have_drake else "stored (pydrake not installed)",
        "ratio_time_ours_over_drake": float(np.median(ours) / np.median(theirs)) if theirs else None,
        "drake_fraction_of_true": float(np.pi * rho_drake / np.sqrt(np.linalg.det(lyapunov_matrix(vdp)))
                                        / gc.benchmarks.VAN_DER_POL_AREA),
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--cert-repeats", type=int, default=1, help="repeats of each case (median wall time)")
    ap.add_argument("--cases", default="vdp", help="comma-separated: vdp, glider2, glider4, glider4_staged, ctol")
    ap.add_argument("--baseline-src", default="", help="src directory of the checkout to compare with")
    ap.add_argument("--time-limit", type=float, default=0.0)
    ap.add_argument("--timeout", type=float, default=3600.0, help="per subprocess (s)")
    ap.add_argument("--worker", default="")
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(worker(args.worker, args.time_limit)))
        return
    if args.cases == "glider4_sdp":
        print(json.dumps(glider4_sdp(), indent=1))
        return
    here = str(Path(__file__).resolve().parents[1] / "src")
    out: dict = {"drake": drake_part(args.repeats), "cases": {}}
    for case in [c for c in args.cases.split(",") if c]:
        row: dict = {}
        versions = [("new", here)] + ([("today", args.baseline_src)] if args.baseline_src else [])
        by_tag: dict = {tag: [] for tag, _ in versions}
        for _ in range(max(1, args.cert_repeats)):      # the versions alternate: same load for both
            for tag, src in versions:
                by_tag[tag].append(run_case(case, src, args.time_limit, args.timeout))
        for tag, _src in versions:
            runs = by_tag[tag]
            ok = [r for r in runs if "error" not in r]
            best = ok[int(np.argsort([r["wall_s"] for r in ok])[len(ok) // 2])] if ok else runs[-1]
            if ok:
                best["wall_s_median"] = float(np.median([r["wall_s"] for r in ok]))
                best["cpu_s_median"] = float(np.median([r.get("cpu_s", np.nan) for r in ok]))
                best["wall_s_all"] = [round(r["wall_s"], 3) for r in ok]
            row[tag] = best
        if "today" in row and "error" not in row["today"] and "error" not in row["new"]:
            row["time_ratio_new_over_today"] = row["new"]["wall_s_median"] / row["today"]["wall_s_median"]
            row["cpu_ratio_new_over_today"] = row["new"]["cpu_s_median"] / row["today"]["cpu_s_median"]
            row["volume_ratio_new_over_today"] = row["new"]["volume"] / max(row["today"]["volume"], 1e-300)
        n = row["new"]
        if "error" not in n:
            if case == "vdp":
                row["target_met"] = bool(n["wall_s_median"] < VDP_TARGET_S
                                         and n["fraction_of_true"] >= VDP_TARGET_FRACTION and n["certified"])
            elif case == "ctol":
                row["target_met"] = bool(n["wall_s_median"] < CTOL_TARGET_S and n["volume"] >= CTOL_TODAY_VOLUME
                                         and n["certified"])
            elif case in ("glider4", "glider4_staged"):
                ref = out["cases"].get("glider2", {}).get("today", {}).get("volume", GLIDER2_TODAY_VOLUME)
                row["target_met"] = bool(n["wall_s_median"] < GLIDER_TARGET_S and n["certified"]
                                         and n["volume"] >= ref)
        out["cases"][case] = row
        print(json.dumps({case: row}, indent=1), flush=True)
    print(json.dumps(out["drake"], indent=1))
    res = Path(__file__).parent / "results"
    res.mkdir(exist_ok=True)
    (res / "roa.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
