"""Region-of-attraction certification by SOS programs (glidectl.roa): Van der Pol against Drake, the reduced
2-state glider against the thesis's Phi < 2/3 set, the full 4-state glider (K_M = -50, -100) against L* (5.85),
and all of them against the true regions from batch simulation.

Run ``python designs/roa_certification.py [OUTDIR]`` (same as ``glidectl report roa_certification``); writes
``OUTDIR/roa_certification/`` (default ``reports/``) with report.pdf, the figures and numbers.json.
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("roa_certification")
