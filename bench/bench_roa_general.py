"""Issue 17: certify_roa on closed loops that do not recast exactly (polynomial surrogate with remainder bound).

Measures, for each loop: the route taken, the surrogate's remainder bound, the certified volume as a fraction of the
box (quasi-MC with 2^14 points, and from the set's radii along 4000 random directions, which resolves the small
fractions of a 10-state box; ``reach_min``/``reach_max``: the smallest/largest fraction of the way to the box face
the set reaches), whether every a-posteriori check passed, and the wall / SDP time, at degree 2 (and 4 where the
budget estimate says it fits):

* ``rogue-lqr``: the LQR glide-path regulator of the rogue glider (``gc.lqr_glide``, 10 states, force form) at
  V = 0.3 m/s, gamma = -25 deg, in the box ``x_e +- frac * dev`` (``dev`` below, SI units), started from the
  Lyapunov equation of the scaled linearization; ``rogue-lqr-ctg``: the same, started from the LQR cost-to-go;
* ``sphere-torque``: the torque law (6.5) of the sphere glider of chapter 5 (``gc.design_torque_control``, 4 states);
* ``pendulum``: a damped pendulum at theta_e = 0.3 rad (the toy loop of tests/test_roa_general.py).

Usage::

    python bench/bench_roa_general.py [--loops rogue-lqr,sphere-torque,pendulum] [--frac 0.2]
        [--degrees 2,4] [--repeats 1]

Writes ``bench/results/roa_general.json``. One repeat by default (a certification is minutes for the 10-state loop;
the medians are over ``--repeats``).
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time
from pathlib import Path

import numpy as np

import glidectl as gc
from glidectl.errors import BudgetError, GlidectlError

DEV = {"z_prime": 0.5, "theta": 0.1, "Omega2": 0.05, "v1": 0.05, "v3": 0.02, "r_P1": 0.01, "r_P3": 0.005,
       "P_P1": 0.2, "P_P3": 0.05, "m0": 0.05}


class Pendulum:
    state_names = ("theta", "omega")
    input_names = ()
    name = "pendulum"
    equilibrium = np.array([0.3, 0.0])

    def rhs(self, X, u=None):
        X = np.asarray(X)
        return np.stack([X[..., 1], -np.sin(X[..., 0]) + math.sin(0.3) - X[..., 1]], axis=-1)


def loops(frac: float) -> dict[str, tuple[object, tuple[np.ndarray, np.ndarray], object]]:
    out = {}
    veh = gc.load_vehicle("rogue")
    ctrl = gc.lqr_glide(veh, gc.steady_glide(veh, 0.3, math.radians(-25), r_p3=0.005))
    loop = gc.closed_loop(ctrl)
    d = frac * np.array([DEV[k] for k in loop.state_names])
    out["rogue-lqr"] = (loop, (loop.equilibrium - d, loop.equilibrium + d), None)
    # the same loop started from its LQR cost-to-go (weight Q + K^T R K)
    out["rogue-lqr-ctg"] = (loop, (loop.equilibrium - d, loop.equilibrium + d), ctrl.Q + ctrl.K.T @ ctrl.R @ ctrl.K)
    sph = gc.load_vehicle("sphere_ch5")
    tl = gc.closed_loop(gc.design_torque_control(sph, speed=1.5))
    hw = np.array([0.1, 0.1, 0.03, 0.1])
    out["sphere-torque"] = (tl, (tl.equilibrium - hw, tl.equilibrium + hw), None)
    out["pendulum"] = (Pendulum(), (np.array([-0.7, -1.2]), np.array([1.3, 1.2])), None)
    return out


def radial_fraction(cert, n_dir: int = 4000, seed: int = 0) -> tuple[float, float, float]:
    """Volume fraction of the (star-shaped) certified set in its box from radii along random directions:
    ``E[R(u)^n] / E[T(u)^n]`` (``R`` the set's radius, ``T`` the box's, directions uniform in the box-scaled
    coordinates), and the smallest and largest ``R / T`` (how far the set reaches towards the box faces)."""
    ps = cert.system
    x0 = np.asarray(ps.equilibrium, dtype=float)
    lo, hi = (np.asarray(b, dtype=float) for b in cert.box)
    w = np.maximum(x0 - lo, hi - x0)
    rng = np.random.default_rng(seed)
    U = rng.standard_normal((n_dir, ps.n))
    U /= np.linalg.norm(U, axis=1, keepdims=True)
    D = U * w
    with np.errstate(divide="ignore", invalid="ignore"):
        T = np.min(np.where(D > 0, (hi - x0) / D, np.where(D < 0, (lo - x0) / D, np.inf)), axis=1)
    a, b = np.zeros(n_dir), T.copy()
    for _ in range(40):
        mid = 0.5 * (a + b)
        ok = cert.contains(x0 + mid[:, None] * D)
        a, b = np.where(ok, mid, a), np.where(ok, b, mid)
    r = a / T
    return float(np.mean(a**ps.n) / np.mean(T**ps.n)), float(np.min(r)), float(np.max(r))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--loops", default="pendulum,sphere-torque,rogue-lqr,rogue-lqr-ctg")
    ap.add_argument("--frac", type=float, default=0.2)
    ap.add_argument("--degrees", default="2,4")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--time-limit", type=float, default=1800.0)
    args = ap.parse_args()
    rows = []
    all_loops = loops(args.frac)
    for name in args.loops.split(","):
        model, box, weight = all_loops[name]
        for deg in (int(d) for d in args.degrees.split(",")):
            opts = {"iterations": 2, "sampling": gc.SamplingOptions(n_truth=256, n_verify=4000, n_simulate=32)}
            times, res = [], None
            for _ in range(args.repeats):
                t0 = time.perf_counter()
                try:
                    cert = gc.certify_roa(model, degree=deg, box=box, initial=weight, **opts,
                                          budget=gc.BudgetOptions(time_limit=args.time_limit, on_budget="stop"))
                except BudgetError as exc:
                    res = {"loop": name, "degree": deg, "refused": str(exc)[:400]}
                    break
                except GlidectlError as exc:
                    res = {"loop": name, "degree": deg, "error": f"{type(exc).__name__}: {str(exc)[:400]}"}
                    break
                times.append(time.perf_counter() - t0)
                lo, hi = cert.box
                rb = cert.system.remainder_bound
                frac, rmin, rmax = radial_fraction(cert)
                res = {"loop": name, "degree": deg, "n_states": cert.system.n, "method": cert.method,
                       "volume_fraction_radial": frac, "reach_min": rmin, "reach_max": rmax,
                       "certified": cert.certified, "volume_fraction": cert.volume(n=2**14) / float(np.prod(hi - lo)),
                       "rho": cert.rho, "sdp_time_s": cert.solve_time, "stopped_by": cert.stopped_by,
                       "remainder": rb.summary() if rb is not None else "", "verification":
                       cert.verification.summary(), "n_sdp_steps": len(cert.history)}
            if times:
                res["wall_time_s_median"] = statistics.median(times)
            rows.append(res)
            print(json.dumps(res), flush=True)
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "roa_general.json").write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
