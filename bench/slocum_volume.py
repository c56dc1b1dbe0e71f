"""Issue 17: ``ROACertificate.volume`` on the slocum LQR loop (degree-2 certificate, 8 free states): the Sobol estimate
(0: no point of the box falls in the thin set), the directed one (``method="directed"``, its standard error) and
``"auto"``, with median wall times over repeats; cross-check: Sobol and plain Monte Carlo in a box just around the set
(1.05 x the extents of the quadratic approximation), where they have points inside.

Run: PYTHONPATH=src OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python bench/slocum_volume.py
(about 60 s of certification, then about 30 s of volumes)."""

from __future__ import annotations

import math
import statistics
import time

import numpy as np

import glidectl as gc
from glidectl.derivatives import hessian
from glidectl.roa.certify import _volume_directed, value_of


def _timed(f, repeats: int = 3):
    ts, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t)
    return out, statistics.median(ts)


def main() -> None:
    veh = gc.load_vehicle("slocum_shallow")
    trim = gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=veh.actuators["r_P3"].fixed)
    loop = gc.closed_loop(gc.lqr_glide(veh, trim, inputs="acceleration"))
    t = time.perf_counter()
    cert = gc.certify_roa(loop, degree=2, budget=dict(time_limit=120))
    print(f"certify_roa {time.perf_counter() - t:.1f} s: {cert}, certified {cert.certified}")
    ps = cert.system
    lo, hi = ps.box
    free = [i for i in range(ps.n) if i not in ps.held]
    xe = np.asarray(ps.equilibrium, dtype=float)
    box = float(np.prod((hi - lo)[free]))
    print(f"box volume (free states) {box:.6g}")
    for method in ("sobol", "directed", "auto"):
        v, dt = _timed(lambda m=method: cert.volume(method=m))
        print(f"volume(method={method!r}) = {v:.8g} (fraction of box {v / box:.4g}), median {dt:.3f} s")
    v, se = _volume_directed(ps, cert.V, cert.rho, lo, hi, 4096, 0)
    print(f"directed, 4096 directions: {v:.8g} +- {se:.3g}")
    H = hessian(lambda X: value_of(cert.V, ps, X), xe)[np.ix_(free, free)]
    ext = 1.05 * np.sqrt(2 * cert.rho * np.diag(np.linalg.inv(H)))
    blo, bhi = lo.copy(), hi.copy()
    blo[free], bhi[free] = xe[free] - ext, xe[free] + ext
    bv = float(np.prod((bhi - blo)[free]))
    sob = [cert.volume((blo, bhi), n=2**20, seed=s, method="sobol") for s in range(4)]
    print(f"tight box: Sobol 2**20, 4 seeds: {np.mean(sob):.5g} +- {np.std(sob, ddof=1) / 2:.2g}; "
          f"directed {cert.volume((blo, bhi), method='directed'):.8g}")
    rng = np.random.default_rng(0)
    N = 2**21
    X = np.tile(xe, (N, 1))
    X[:, free] = blo[free] + (bhi - blo)[free] * rng.random((N, len(free)))
    p = float(np.mean(cert.contains(X)))
    print(f"tight box: plain Monte Carlo 2**21: {bv * p:.5g} +- {bv * math.sqrt(p * (1 - p) / N):.2g}")


if __name__ == "__main__":
    main()
