"""Benchmark: region-of-attraction certification on the time-reversed Van der Pol oscillator, against Drake.

(A) glidectl ``max_level`` (Drake's fixed-V problem, one SDP through cvxpy/Clarabel) and (B) Drake's
``RegionOfAttraction`` (when ``pip install -e ".[drake]"``), timed alternately in one process, medians over
repeats; (C) ``certify_roa(van_der_pol(), degree=6)`` wall time (median over ``--cert-repeats`` runs, against the
target of 60 s that used to be asserted in tests/test_roa.py) and certified fraction of the true area.

Run ``python bench/bench_roa.py [--repeats N] [--cert-repeats M]``; writes ``bench/results/roa.json``.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import glidectl as gc
from glidectl.roa import lyapunov_matrix, lyapunov_quadratic, max_level

CERTIFY_TARGET_S = 60.0  # wall-time target of the degree-6 Van der Pol certificate (issue 7)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--cert-repeats", type=int, default=3)
    args = ap.parse_args()
    vdp = gc.benchmarks.van_der_pol()
    V = lyapunov_quadratic(vdp)
    ours, theirs, rho_ours, rho_drake = [], [], np.nan, np.nan
    max_level(vdp, V)
    have_drake = gc.benchmarks.drake_van_der_pol(1) is not None
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        rho_ours = max_level(vdp, V).rho
        ours.append(time.perf_counter() - t0)
        if have_drake:
            d = gc.benchmarks.drake_van_der_pol(1)
            rho_drake = d["rho"]
            theirs.append(d["time"])
    t_certs, cert = [], None
    for _ in range(max(1, args.cert_repeats)):
        t0 = time.perf_counter()
        cert = gc.certify_roa(vdp, degree=6, iterations=6, backoff=0.003)
        t_certs.append(time.perf_counter() - t0)
    t_cert = float(np.median(t_certs))
    area = cert.volume()
    out = {
        "max_level_median_s": float(np.median(ours)), "max_level_rho": rho_ours,
        "drake_median_s": float(np.median(theirs)) if theirs else None, "drake_rho": rho_drake,
        "ratio_time_ours_over_drake": float(np.median(ours) / np.median(theirs)) if theirs else None,
        "certify_roa_degree6_s": t_cert, "certify_roa_degree6_wall_time_s": float(cert.wall_time),
        "certify_roa_target_60s_met": t_cert < CERTIFY_TARGET_S, "certified_area": area,
        "fraction_of_true": area / gc.benchmarks.VAN_DER_POL_AREA, "verified": cert.certified,
        "drake_fraction_of_true": float(np.pi * 2.3045 / np.sqrt(np.linalg.det(lyapunov_matrix(vdp)))
                                        / gc.benchmarks.VAN_DER_POL_AREA),
    }
    for k, v in out.items():
        print(f"{k:32s} {v}")
    res = Path(__file__).parent / "results"
    res.mkdir(exist_ok=True)
    (res / "roa.json").write_text(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
