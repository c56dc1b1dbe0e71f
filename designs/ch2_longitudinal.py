"""Chapter 2 design: ROGUE steady glides, linear analysis, r_bh root locus, LQR/placement, glide switch.

Run ``python designs/ch2_longitudinal.py [OUTDIR]`` (same as ``glidectl report ch2_longitudinal``); writes
``OUTDIR/ch2_longitudinal/`` (default ``reports/``).
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("ch2_longitudinal")
