"""Integrator convergence of the ch7 steady-glide tracking run with the printed gains (dt 0.1, k3 7e5, k4 250: the
pitch loop rings at 1522 rad/s): every method / tolerance on the same window, its metrics, end state and time.

    PYTHONPATH=src python bench/bench_ch7_integrators.py [T_FINAL] [METHOD:RTOL:ATOL ...]

Default: a 1 s window (the violent start, where the 3.30 m max error and the 2029 N peak thrust arise) with LSODA,
BDF and Radau at the library tolerances (rtol 1e-8, atol 1e-10; the implicit ones with the exact closed-loop Jacobian),
LSODA at 1e-9/1e-11 and 1e-10/1e-12 (tolerance halving), and DOP853 at 1e-10/1e-12 (an independent explicit method).
A converged answer is the one that stops changing under tighter tolerances and agrees across methods.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import glidectl as gc

DEFAULT = ("LSODA:1e-8:1e-10", "BDF:1e-8:1e-10", "Radau:1e-8:1e-10", "LSODA:1e-9:1e-11", "LSODA:1e-10:1e-12",
           "DOP853:1e-10:1e-12")


def main(argv: list[str]) -> None:
    t_final = float(argv[0]) if argv else 1.0
    specs = argv[1:] or DEFAULT
    veh = gc.load_vehicle("dc8_ctol")
    traj = gc.climb_trajectory(veh, 0.85)
    print(f"printed gains (dt 0.1, k3 7e5, k4 250) on [0, {t_final:g}] s")
    print(f"{'method':8s} {'rtol':>7s} {'atol':>7s} {'time s':>8s} {'max |e|':>14s} {'peak u1':>14s} {'rms u1':>14s} "
          f"{'rms u2':>14s}  end state (x, y, xdot, ydot, theta, Omega2)")
    for spec in specs:
        method, rtol, atol = spec.split(":")
        t0 = time.perf_counter()
        r = gc.track_with_steady_glides(veh, traj, dt=0.1, k3=7e5, k4=250.0, t_final=t_final, method=method,
                                        rtol=float(rtol), atol=float(atol), max_nfev=10**9)
        el = time.perf_counter() - t0
        print(f"{method:8s} {rtol:>7s} {atol:>7s} {el:8.1f} {r.max_error:14.9g} {r.peak_u1:14.9g} {r.rms_u1:14.9g} "
              f"{r.rms_u2:14.9g}  {np.array2string(r.x[-1], precision=9, max_line_width=200)} {r.note}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
