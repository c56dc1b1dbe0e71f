"""Issue 17: the SOS path (``gc.certify_roa``, degree 2) on the glider loops, against the LMI path
(``gc.certify_roa_lmi``) in the same run: the user glider's LQR loop (slocum_shallow, unsaturated: the closed loop
itself, surrogate route; saturated at the pump rate: ``gc.saturated_loop``, the saturation graph with a surrogate of
the plant) and the chapter-6 buoyancy and elevator loops (pump rate saturated). Per loop: wall time, certified,
volume of the certified set in the free states' own units, and the SOS/LMI volume ratio.

Run: ``PYTHONPATH=src OMP_NUM_THREADS=1 python bench/bench_roa_sos_glider_loops.py [--cases ...] [--lmi-rounds N]``
(about 4 minutes); the same script on another checkout's ``src`` gives that code's answers (a code without the
surrogate sector route refuses the saturated loops: reported as errors). Writes ``bench/results/roa_sos_glider.json``.

Measured 2026-12-02 (idle 2-core machine, ``OMP_NUM_THREADS=1``), this script on this code and, run the same way,
on main at fe6ce9e (the first-order surrogate with the quadratic remainder ``c |y|^2``, no box search, no surrogate
in the sector path); LMI path with 2 rounds of its remainder-box search, same run:

====================  ==========================================  ===========================  ====================
loop                  SOS path, this code                         SOS path at fe6ce9e          LMI path
====================  ==========================================  ===========================  ====================
user glider, unsat.   29.9 s, certified, 1.553e-12 (854 x LMI)    27.0 s, NOT certified        5.0 s, 1.818e-15
user glider, sat.     130.0 s, certified, 8.45e-16 (0.48 x LMI)   refused (plant not polyn.)   5.4 s, 1.766e-15
ch6 buoyancy          26.5 s, certified, 1.929e-6 (1184 x LMI)    refused (plant not polyn.)   1.1 s, 1.630e-9
ch6 elevator          19.2 s, certified, 4.44e-8 (0.11 x LMI)     refused (plant not polyn.)   1.1 s, 4.025e-7
====================  ==========================================  ===========================  ====================

The SOS path takes 5 to 25 times the LMI path's time. Where the box search lands the starting V in a good box it
certifies sets three orders of magnitude larger than the ellipsoid; on the saturated user loop and the elevator loop
it certifies 2 and 9 times smaller ones: the two paths are complementary, and the design roa_certification reports
both.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import glidectl as gc


def _loops(cases: list[str]) -> dict[str, tuple[object, object]]:
    out = {}
    if {"user_unsat", "user_sat"} & set(cases):
        veh = gc.load_vehicle("slocum_shallow")
        glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
        loop = gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration"))
        inf = [math.inf] * len(loop.plant.input_names)
        out["user_unsat"] = (loop, gc.saturated_loop(loop, u_min=[-x for x in inf], u_max=inf))
        sl = gc.saturated_loop(loop)
        out["user_sat"] = (sl, sl)
    if "buoyancy" in cases:
        sph = gc.load_vehicle("sphere_ch5")
        sl = gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0)))
        out["buoyancy"] = (sl, sl)
    if "elevator" in cases:
        ev = gc.load_vehicle("elevator_ch6")
        eq = gc.elevator_equilibrium(ev, 1.0, -math.pi / 4)
        sl = gc.saturated_loop(gc.closed_loop(gc.ElevatorBuoyancyController(eq, ev, 1.0)))
        out["elevator"] = (sl, sl)
    return {k: v for k, v in out.items() if k in cases}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="user_unsat,user_sat,buoyancy,elevator")
    ap.add_argument("--lmi-rounds", type=int, default=2)
    args = ap.parse_args()
    rows = []
    for key, (sos_sys, lmi_sys) in _loops(args.cases.split(",")).items():
        t = time.perf_counter()
        lmi = gc.certify_roa_lmi(lmi_sys, rounds=args.lmi_rounds)
        t_lmi = time.perf_counter() - t
        row = {"loop": key, "lmi_wall_s": t_lmi, "lmi_certified": lmi.certified, "lmi_volume": lmi.volume()}
        t = time.perf_counter()
        try:
            cert = gc.certify_roa(sos_sys, degree=2)
            row.update(sos_wall_s=time.perf_counter() - t, sos_method=cert.method, sos_certified=cert.certified,
                       sos_volume=cert.volume() if cert.certified else 0.0)
            row["ratio"] = row["sos_volume"] / row["lmi_volume"]
        except gc.GlidectlError as exc:
            row.update(sos_wall_s=time.perf_counter() - t, sos_error=f"{type(exc).__name__}: {str(exc)[:300]}")
        rows.append(row)
        print(json.dumps(row), flush=True)
    out = Path(__file__).parent / "results" / "roa_sos_glider.json"
    out.parent.mkdir(exist_ok=True)
    out.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
