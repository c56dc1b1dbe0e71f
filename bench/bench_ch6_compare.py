"""Benchmark: the three LQR comparisons of designs/ch6_controllers.py (pure torque, elevator + buoyancy, buoyancy)
with ``compare_controllers(method="batch")`` (integrate_batch, per-run steps, the default) against
``method="BDF"`` (one stacked solve_ivp ODE, the default before issue 18).

Same models, laws, initial states and horizons as the design's settings (``--quick`` for its QUICK preset, ``--n``
to change the number of initial states). Prints per comparison the wall times (median of ``--repeats``, the two
methods alternated), the right-hand-side calls and whether the converged fractions and table rows agree.

Usage::

    python bench/bench_ch6_compare.py --n 30          # a few minutes
    python bench/bench_ch6_compare.py --only e        # the elevator comparison only (BDF needs ~2.6e5 calls)
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import glidectl as gc

ROOT = Path(__file__).resolve().parents[1]


def _design():
    spec = importlib.util.spec_from_file_location("ch6_design", ROOT / "designs" / "ch6_controllers.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["ch6_design"] = mod
    spec.loader.exec_module(mod)
    return mod


def problems(s, fig62):
    """The three comparisons of the design as ``{tag: (model, controllers, X0, x_e, u_e, t_final, kwargs)}``."""
    sph = gc.load_vehicle("sphere_ch5")
    d = gc.design_torque_control(sph, speed=s.torque_speed, **s.torque_domain)
    beq = gc.buoyancy_equilibrium(sph, s.buoy_speed)
    ev = gc.load_vehicle("elevator_ch6")
    eq = gc.elevator_equilibrium(ev, fig62["speed"], fig62["gamma"])
    rng = np.random.default_rng(s.box_seed)
    tb, eb, bb = np.array(s.torque_box), np.array(s.elev_box), np.array(s.buoy_box)
    tm = gc.TorqueControlledGlider(sph)
    xt = np.array([d.speed, d.gamma, d.alpha, 0.0])
    ut = np.atleast_1d(np.asarray(d.law.torque(xt), dtype=float))
    sp = d.certificate.sp
    sc = np.abs(sp.to_dimensional(tb) - sp.to_dimensional(np.zeros(4)))
    tl = gc.lqr_state_feedback(tm, xt, ut, Q=1 / sc**2, R=[1 / d.peak_torque**2])
    X0t = sp.to_dimensional(rng.uniform(-1.0, 1.0, (s.n_box, 4)) * tb)
    em = gc.ElevatorBuoyancyGlider(ev)
    lim = em.limits
    ue = np.array([0.0, eq.u2e])
    el = gc.lqr_state_feedback(em, eq.state, ue, Q=1 / eb**2, R=1 / np.array([lim.u4_max, lim.u2_max])**2,
                               u_min=[-lim.u4_max, -lim.u2_max], u_max=[lim.u4_max, lim.u2_max])
    X0e = eq.state + rng.uniform(-1.0, 1.0, (s.n_box, 5)) * eb
    bm = gc.BuoyancyGlider(sph)
    bl = gc.lqr_state_feedback(bm, beq.state, [0.0], Q=1 / bb**2, R=[1 / bm.limits.u4_max**2],
                               u_min=[-bm.limits.u4_max], u_max=[bm.limits.u4_max])
    X0b = beq.state + rng.uniform(-1.0, 1.0, (s.n_box, 5)) * bb
    return {
        "t": (tm, {"nonlinear": d.law, "LQR": tl}, X0t, xt, ut, s.t_torque,
              {"scale": sc, "diverged": lambda X: X[:, 0] < 0.05 * d.speed}),
        "e": (em, {"nonlinear": gc.ElevatorBuoyancyController(eq, ev, s.elev_K), "LQR": el}, X0e, eq.state, ue,
              s.t_elev, {"scale": eb, "diverged": lambda X: X[:, 0] < 0.1}),
        "b": (bm, {"nonlinear": gc.BuoyancyController(beq, sph, s.buoy_kb), "LQR": bl}, X0b, beq.state,
              np.zeros(1), s.t_buoy, {"scale": bb, "diverged": lambda X: X[:, 0] < 0.1}),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=None, help="initial states per comparison (default: the preset's)")
    ap.add_argument("--quick", action="store_true", help="the design's QUICK preset")
    ap.add_argument("--only", default="teb", help="comparisons to run: t (torque), e (elevator), b (buoyancy)")
    ap.add_argument("--repeats", type=int, default=1)
    args = ap.parse_args()
    mod = _design()
    s = mod.QUICK if args.quick else mod.FULL
    if args.n is not None:
        s = dataclasses.replace(s, n_box=args.n)
    for tag, (model, ctrls, X0, xe, ue, T, kw) in problems(s, mod.FIG62).items():
        if tag not in args.only:
            continue
        times: dict[str, list[float]] = {"batch": [], "BDF": []}
        out = {}
        for _ in range(args.repeats):
            for method in times:
                t0 = time.perf_counter()
                out[method] = gc.compare_controllers(model, ctrls, X0, xe, ue, T, method=method, **kw)
                times[method].append(time.perf_counter() - t0)
        tb, tf = statistics.median(times["batch"]), statistics.median(times["BDF"])
        calls = {m: {k: r.evaluations for k, r in c.records.items()} for m, c in out.items()}
        same_rows = out["batch"].table_rows() == out["BDF"].table_rows()
        print(f"{tag}: {len(X0)} runs, {T:g} s: batch {tb:.1f} s, BDF {tf:.1f} s (x{tf / tb:.1f}); rhs calls "
              f"{calls}; table rows equal: {same_rows}")
        if not same_rows:
            for a, b in zip(out["batch"].table_rows(), out["BDF"].table_rows(), strict=True):
                print("   batch", a, "\n   BDF  ", b)


if __name__ == "__main__":
    main()
