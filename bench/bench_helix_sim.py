"""Benchmark: the 2000 s §8.2.2 helix simulation, glidectl's default integrator vs scipy RK45.

(A) ``glidectl.sim.simulate(model, x0, 2000.0)`` with its defaults (LSODA, rtol 1e-8, atol 1e-10, 2001 output
    points from the dense output) for ``model = FixedMassGlider3D(slocum_ch8, r_p=(0.02, 0.02, 0.04), m0=0.25)``
    from the initial condition of §8.2.2 (Fig 8.2-8.4). The whole call is timed.
(B) ``scipy.integrate.solve_ivp(lambda t, y: model.rhs(y), (0, 2000), x0, method="RK45", rtol=1e-6)`` directly
    on the same right-hand side (scipy's default atol 1e-6, no dense output, final state only).

Both are compared with each other and with the steady helix of ``glidectl.trim.helix.helix_trim`` (the state the
simulation converges to: radius 66.60 m, speed 0.729 m/s in the thesis).

Usage::

    python bench/bench_helix_sim.py [--repeats N]

Prints a table and writes ``bench/results/helix_sim.json`` (the folder is created at run time).
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import scipy
from scipy.integrate import solve_ivp

import glidectl
from glidectl.models.glider3d import FixedMassGlider3D, R_to_ypr, quat_to_R, ypr_to_quat
from glidectl.sim import simulate
from glidectl.trim.helix import helix_trim

VEHICLE = "slocum_ch8"
R_P = (0.02, 0.02, 0.04)  # m
M0 = 0.25  # kg
T_FINAL = 2000.0  # s
# §8.2.2 initial condition: x = y = z = 0, psi = 0, theta = -26.654 deg, phi = 14.419 deg
X0 = np.r_[0.0, 0.0, 0.0, ypr_to_quat(0.0, np.radians(-26.654), np.radians(14.419)),
           0.802, 0.014, 0.025, 0.0046, 0.0025, 0.0077]
RK45_RTOL = 1e-6
RK45_ATOL = 1e-6  # scipy's default
RESULTS = Path(__file__).resolve().parent / "results" / "helix_sim.json"


def time_call(fn, repeats: int) -> list[float]:
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def helix_error(x: np.ndarray, target: np.ndarray) -> float:
    """max |(v, Omega, theta, phi) - helix| (SI units, mixed)."""
    _, th, ph = R_to_ypr(quat_to_R(x[3:7]))
    return float(np.max(np.abs(np.r_[x[7:13], th, ph] - target)))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="timed repeats per method (median reported)")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")

    veh = glidectl.load_vehicle(VEHICLE)
    model = FixedMassGlider3D(veh, R_P, M0)
    h = helix_trim(veh, R_P, M0)
    target = np.r_[h.v, h.Omega, h.theta, h.phi]

    def run_a():
        return simulate(model, X0, T_FINAL)

    def run_b():
        return solve_ivp(lambda t, y: model.rhs(y), (0.0, T_FINAL), X0, method="RK45", rtol=RK45_RTOL,
                         atol=RK45_ATOL)

    # untimed warm-up; these results are the ones compared (the computation is deterministic)
    sim_a, sol_b = run_a(), run_b()
    if not sol_b.success:
        raise SystemExit(f"RK45 failed: {sol_b.message}")

    # alternate A and B so drift in machine load affects both alike
    t_a: list[float] = []
    t_b: list[float] = []
    for _ in range(args.repeats):
        t_a += time_call(run_a, 1)
        t_b += time_call(run_b, 1)
    med_a, med_b = statistics.median(t_a), statistics.median(t_b)

    xa, xb = sim_a.x[-1], sol_b.y[:, -1]
    diff = np.abs(xa - xb)
    names = model.state_names
    worst = int(np.argmax(diff))
    pos_diff = float(np.linalg.norm(xa[:3] - xb[:3]))
    dyn_diff = float(np.max(diff[7:13]))
    q_norm_err = float(np.max(np.abs(np.linalg.norm(sim_a.x[:, 3:7], axis=1) - 1.0)))
    q_norm_err_b = float(np.max(np.abs(np.linalg.norm(sol_b.y[3:7].T, axis=1) - 1.0)))
    err_a, err_b = helix_error(xa, target), helix_error(xb, target)

    rows = [
        ("glidectl simulate (LSODA 1e-8/1e-10)", f"{med_a:.4f} s", sim_a.nfev, ", ".join(f"{t:.4f}" for t in t_a)),
        (f"scipy solve_ivp RK45 ({RK45_RTOL:g}/{RK45_ATOL:g})", f"{med_b:.4f} s", sol_b.nfev,
         ", ".join(f"{t:.4f}" for t in t_b)),
    ]
    w0 = max(len(r[0]) for r in rows)
    print(f"§8.2.2 helix simulation: vehicle={VEHICLE}, r_P={R_P} m, m0={M0} kg, t_final={T_FINAL:g} s, "
          f"repeats={args.repeats}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}")
    print()
    print(f"{'method':<{w0}}  {'median':>9}  {'nfev':>6}  all runs (s)")
    print(f"{'-' * w0}  {'-' * 9}  {'-' * 6}  {'-' * 30}")
    for name, med, nfev, allt in rows:
        print(f"{name:<{w0}}  {med:>9}  {nfev:>6}  {allt}")
    print()
    print(f"ratio RK45 / glidectl (median)            : {med_b / med_a:.2f}x")
    print(f"final-state max |diff| (all 13 states)    : {diff[worst]:.3e} (in {names[worst]})")
    print(f"final position |diff|                     : {pos_diff:.3e} m")
    print(f"final (v, Omega) max |diff|               : {dyn_diff:.3e}")
    print(f"final distance to the helix, glidectl     : {err_a:.3e} (max over v, Omega, theta, phi)")
    print(f"final distance to the helix, RK45         : {err_b:.3e}")
    print(f"max ||q| - 1| glidectl (2001 outputs)     : {q_norm_err:.3e}")
    print(f"max ||q| - 1| RK45 (at its steps)         : {q_norm_err_b:.3e}")
    print(f"RK45 accepted steps, mean step            : {sol_b.t.size - 1}, {T_FINAL / (sol_b.t.size - 1):.3f} s "
          f"(explicit stability limit ~3.3/|lambda_max| = {3.3 / np.max(np.abs(h.eigenvalues)):.3f} s)")
    print(f"helix: radius {h.radius:.2f} m, speed {h.speed:.3f} m/s, pitch {h.pitch:.1f} m, period "
          f"{h.period:.1f} s; reduced eigenvalues {np.min(h.eigenvalues.real):.3f} .. "
          f"{np.max(h.eigenvalues.real):.4f} 1/s")

    result = {
        "benchmark": "helix_sim",
        "config": {"vehicle": VEHICLE, "provenance": veh.provenance, "r_p": list(R_P), "m0": M0,
                   "t_final": T_FINAL, "x0": X0.tolist(), "state_names": list(names), "repeats": args.repeats,
                   "glidectl": {"method": sim_a.method, "rtol": sim_a.rtol, "atol": sim_a.atol,
                                "n_output": int(sim_a.t.size)},
                   "rk45": {"rtol": RK45_RTOL, "atol": RK45_ATOL}},
        "environment": {"python": platform.python_version(), "platform": platform.platform(),
                        "numpy": np.__version__, "scipy": scipy.__version__, "executable": sys.executable},
        "glidectl": {"times_s": t_a, "median_s": med_a, "nfev": sim_a.nfev, "x_final": xa.tolist(),
                     "helix_error": err_a, "max_q_norm_error": q_norm_err},
        "rk45": {"times_s": t_b, "median_s": med_b, "nfev": int(sol_b.nfev), "n_steps": int(sol_b.t.size - 1),
                 "x_final": xb.tolist(), "helix_error": err_b, "max_q_norm_error": q_norm_err_b},
        "ratio_rk45_over_glidectl": med_b / med_a,
        "final_state_abs_diff": dict(zip(names, diff.tolist(), strict=True)),
        "final_position_diff_m": pos_diff,
        "final_v_omega_max_abs_diff": dyn_diff,
        "helix": {"radius": h.radius, "speed": h.speed, "pitch": h.pitch, "period": h.period,
                  "v": h.v.tolist(), "Omega": h.Omega.tolist(), "theta": h.theta, "phi": h.phi},
    }
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    RESULTS.write_text(json.dumps(result, indent=2) + "\n")
    print(f"\nwrote {RESULTS}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
