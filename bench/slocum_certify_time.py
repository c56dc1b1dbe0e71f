"""Issue 17: wall time of certify_roa on the slocum LQR loop (degree 2) with time_limit=120 s (one run).

Run: PYTHONPATH=src OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python bench/slocum_certify_time.py"""

from __future__ import annotations

import math
import time

import numpy as np

import glidectl as gc
import glidectl.roa.certify as certify_module

VERIFY: list[float] = []
_verify = certify_module._verify


def _timed_verify(*args, **kwargs):            # wall time of the final verification (sampling, dV/dt, simulations)
    t = time.perf_counter()
    try:
        return _verify(*args, **kwargs)
    finally:
        VERIFY.append(time.perf_counter() - t)


certify_module._verify = _timed_verify


def main() -> None:
    veh = gc.load_vehicle("slocum_shallow")
    trim = gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=veh.actuators["r_P3"].fixed)
    loop = gc.closed_loop(gc.lqr_glide(veh, trim, inputs="acceleration"))
    t = time.perf_counter()
    try:
        cert = gc.certify_roa(loop, degree=2, budget=dict(time_limit=120))
    except gc.errors.GlidectlError as exc:
        print(f"{type(exc).__name__} after {time.perf_counter() - t:.1f} s (final verification {VERIFY} s): {exc}")
        return
    wall = time.perf_counter() - t
    print(f"final verification {VERIFY} s")
    print(f"wall {wall:.1f} s, certified {cert.certified}, stopped_by {cert.stopped_by!r}, rho {cert.rho:.4g}")
    print(cert.verification.summary())
    lo, hi = cert.box
    free = [i for i, nm in enumerate(cert.system.state_names) if nm not in cert.held]
    vol = cert.volume()
    print(f"volume {vol:.4g}, box volume (free states) {float(np.prod((hi - lo)[free])):.4g}, "
          f"fraction {vol / float(np.prod((hi - lo)[free])):.4g}")


if __name__ == "__main__":
    main()
