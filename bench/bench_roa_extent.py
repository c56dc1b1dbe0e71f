"""Certified against convergent extent, per state axis, on the loops of the region-of-attraction issue.

For each loop: the certificate of ``gc.certify_roa(loop)`` with its default arguments (it chooses the method: the
LMI path for a saturated loop, SOS at the degree its size allows otherwise), its per-axis extent (``cert.extent()``),
the extent from which simulations of the true loop converge (``gc.convergent_extent`` in the loop's default box, the box
certify_roa is asked for) and their ratio per axis and direction; with the certificate's wall time and whether it is
rigorous.

    python bench/bench_roa_extent.py [--cases a,b,...] [--out bench/results/roa_extent.json]

Cases: slocum (LQR dive-cycle loop of slocum_shallow, unsaturated), slocum_sat (the same, ``gc.saturated_loop``: pump
rate saturated, pump range, battery range and rate as state-dependent limits),
buoyancy, elevator (chapter-6 loops, pump rate saturated), glider4 (chapter-5 4-state glider, K_M = -50), ctol
(chapter-7 closed loop at the level glide). Each case runs in its own process, one after the other.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import time
from pathlib import Path

import numpy as np

CASES = ("slocum", "slocum_sat", "buoyancy", "elevator", "glider4", "ctol")


def _loop(case: str):
    """The loop of ``case``: what ``gc.certify_roa`` is given, with its default arguments."""
    import glidectl as gc

    if case in ("slocum", "slocum_sat"):
        veh = gc.load_vehicle("slocum_shallow")
        glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
        loop = gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration"))
        return loop if case == "slocum" else gc.saturated_loop(loop)
    if case == "buoyancy":
        sph = gc.load_vehicle("sphere_ch5")
        return gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0)))
    if case == "elevator":
        ev = gc.load_vehicle("elevator_ch6")
        eq = gc.elevator_equilibrium(ev, 1.0, -math.pi / 4)
        return gc.saturated_loop(gc.closed_loop(gc.ElevatorBuoyancyController(eq, ev, 1.0)))
    if case == "glider4":
        return gc.singular_perturbation(gc.load_vehicle("sphere_ch5", K_M=-50.0)).full_model()
    if case == "ctol":
        veh = gc.load_vehicle("dc8_ctol")
        gl = gc.ctol_glide(veh, speed=0.85 / math.sqrt(veh.a_L), gamma=0.0)
        return gc.ClosedLoopCTOL(veh, gl, 10.0, 5.0).roa_model()
    raise SystemExit(f"unknown case {case}")


def worker(case: str) -> dict:
    """One case in this process: the certificate, both extents and their ratios."""
    import glidectl as gc

    loop = _loop(case)
    t0 = time.perf_counter()
    cert = gc.certify_roa(loop)
    t_cert = time.perf_counter() - t0
    cert_ext = cert.extent()
    t0 = time.perf_counter()
    box = cert.box if case in ("glider4", "ctol") else None
    conv = gc.convergent_extent(cert.system if case in ("glider4", "ctol") else loop, box=box, within_box=cert.in_box)
    t_conv = time.perf_counter() - t0
    below, above = cert_ext.ratio(conv)
    return {"case": case, "method": cert.method, "certified": bool(cert.certified), "rigorous": bool(cert.rigorous),
            "cert_s": t_cert, "convergent_s": t_conv, "names": list(cert_ext.names),
            "cert_lo": cert_ext.lo.tolist(), "cert_hi": cert_ext.hi.tolist(), "conv_lo": conv.lo.tolist(),
            "conv_hi": conv.hi.tolist(), "equilibrium": conv.equilibrium.tolist(),
            "ratio_below": [None if not np.isfinite(r) else float(r) for r in below],
            "ratio_above": [None if not np.isfinite(r) else float(r) for r in above]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "roa_extent.json")
    args = ap.parse_args()
    rows = []
    ctx = mp.get_context("spawn")
    for case in args.cases.split(","):
        with ctx.Pool(1) as pool:
            r = pool.apply(worker, (case,))
        rows.append(r)
        print(f"\n{case}: {r['method']}, certified {r['certified']}, rigorous {r['rigorous']}, certificate "
              f"{r['cert_s']:.1f} s, convergent extent {r['convergent_s']:.1f} s")
        print(f"  {'state':>10} {'certified lo':>13} {'hi':>11} {'convergent lo':>14} {'hi':>11} {'ratio lo':>9} "
              f"{'hi':>6}")
        for k, name in enumerate(r["names"]):
            rb, ra = r["ratio_below"][k], r["ratio_above"][k]
            print(f"  {name:>10} {r['cert_lo'][k]:13.5g} {r['cert_hi'][k]:11.5g} {r['conv_lo'][k]:14.5g} "
                  f"{r['conv_hi'][k]:11.5g} {'-' if rb is None else f'{rb:.3f}':>9} "
                  f"{'-' if ra is None else f'{ra:.3f}':>6}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(rows, indent=1))
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
