"""Benchmark: LMI certificates (quadratic V, generalized sector condition, bounded remainder) of the saturated
glidectl loops, issue 17 part 2.

Loops:

* chapter-6 buoyancy loop (6.9) of ``sphere_ch5`` at V_e = 1.5 m/s, K_b = 5 (the ch6 design's settings), pump rate
  limit 0.02 kg/s;
* chapter-6 elevator + buoyancy loop (6.21)-(6.22) of ``elevator_ch6`` at the Fig 6.2 glide (1 m/s, -45 deg),
  K = 1, pump rate limit 0.05 kg/s;
* LQR glide-path regulator of ``slocum_shallow`` (acceleration inputs, ``actuate=("w1", "w4")``, 0.35 m/s at
  -25 deg), pump rate ``w4`` saturated at the vehicle's 0.01 kg/s, battery range/rate and pump range in the box.

For each: median wall time and SDP solve time over repeats, the certified volume as a fraction of the box (free
states), each axis's extent over the box half-width, the smallest scale of the certified ellipsoid at which the
true loop's sampled dV/dt >= 0 on its boundary (or it leaves the box: how close the LMI level is to the best level of
that shape), the remainder box, and whether every a-posteriori check passed. Also the LMI with the saturation ignored
(levels at infinity), verified on the true saturated loop: what a certificate that forgets the saturation claims,
and which checks catch it.

Run ``python bench/bench_roa_lmi.py [--repeats N]``; writes ``bench/results/roa_lmi.json``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
import warnings
from pathlib import Path

import numpy as np

import glidectl as gc


def loops() -> dict[str, gc.SaturatedLoop]:
    sph = gc.load_vehicle("sphere_ch5")
    beq = gc.buoyancy_equilibrium(sph, 1.5)
    ev = gc.load_vehicle("elevator_ch6")
    eeq = gc.elevator_equilibrium(ev, 1.0, -np.pi / 4)
    sl = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(sl, 0.35, np.radians(-25.0), r_p3=0.05)
    lqr = gc.lqr_glide(sl, glide, inputs="acceleration", actuate=("w1", "w4"))
    return {
        "buoyancy (6.9), sphere_ch5": gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(beq, sph, 5.0))),
        "elevator (6.21)-(6.22), elevator_ch6": gc.saturated_loop(
            gc.closed_loop(gc.ElevatorBuoyancyController(eeq, ev, 1.0))),
        "LQR w1,w4, slocum_shallow": gc.saturated_loop(gc.closed_loop(lqr)),
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    out: dict[str, dict[str, object]] = {}
    for name, loop in loops().items():
        walls, solves, cert = [], [], None
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            cert = gc.certify_roa_lmi(loop)
            walls.append(time.perf_counter() - t0)
            solves.append(cert.solve_time)
        unsat = dataclasses.replace(loop, u_lo=np.full(loop.n_feedback, -np.inf), u_hi=np.full(loop.n_feedback, np.inf),
                                    truth=loop.rhs, name=loop.name + " (saturation ignored)")
        cu = gc.certify_roa_lmi(unsat)
        assert cert is not None
        free = [loop.state_names[i] for i in loop.free]
        # tightness: the smallest scale k of the certified ellipsoid where the true loop's sampled dV/dt >= 0 on its
        # boundary, or the ellipsoid leaves the box (how far the quadratic V of that shape could go at best)
        Xb = cert.sample(20000, seed=1, boundary=True)
        tight = None
        for k in (1.05, 1.1, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0):
            Y = loop.equilibrium + k * (Xb - loop.equilibrium)
            dY = Y - loop.equilibrium
            vd = 2 * np.einsum("ni,ij,nj->n", dY[:, list(loop.free)], cert.P, loop.rhs(Y)[:, list(loop.free)])
            if np.any(vd >= 0) or not np.all((Y >= loop.box[0]) & (Y <= loop.box[1])):
                tight = (k, "dV/dt >= 0 sampled" if np.any(vd >= 0) else "leaves the box")
                break
        out[name] = {
            "states": free, "wall_median_s": float(np.median(walls)), "sdp_median_s": float(np.median(solves)),
            "n_sdp": len(cert.history), "hessian_s": cert.hessian_time,
            "volume_fraction": cert.volume_fraction, "volume": cert.volume(),
            "extent_over_half_width": (np.sqrt(np.diag(np.linalg.inv(cert.P))) / cert.scale).tolist(),
            "first_failing_scale": tight,
            "remainder_box": cert.remainder_box.tolist(), "certified": cert.certified,
            "verification": cert.verification.summary(),
            "saturation_ignored_volume_fraction": cu.volume_fraction, "saturation_ignored_certified": cu.certified,
            "saturation_ignored_failing": list(cu.verification.failing()),
        }
    for k, v in out.items():
        print(f"\n{k}")
        for kk, vv in v.items():
            print(f"  {kk:30s} {vv}")
    res = Path(__file__).parent / "results"
    res.mkdir(exist_ok=True)
    (res / "roa_lmi.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
