"""Chapter 7 design: the CTOL aircraft (DC-8, normalized) — steady glides under the controller (7.16)-(7.20)
(Theorem 4), closed-loop eigenvalues, tracking of the §7.3.3 climb by steady gliding (printed settings and a Pareto
study over dt, k3, k4), and the exact-tracking baselines (feedback linearization, stable inversion, approximate
linearization) on the same trajectory.

Run ``python designs/ch7_ctol.py [OUTDIR]`` (same as ``glidectl report ch7_ctol``); writes ``OUTDIR/ch7_ctol/``
(default ``reports/``). Takes about 5 minutes on 2 cores (the printed gains are very stiff).
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("ch7_ctol")
