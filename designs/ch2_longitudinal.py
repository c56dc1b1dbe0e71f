"""Chapter 2 design: ROGUE steady glides, linear analysis, r_bh root locus, LQR/placement, glide switch.

Run ``python designs/ch2_longitudinal.py [OUTDIR]`` (same as ``glidectl report ch2_longitudinal``); writes
``OUTDIR/ch2_longitudinal/`` (default ``reports/``).
"""

import sys

from glidectl.studies import ch2_longitudinal

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "reports"
    pdf = ch2_longitudinal.build(out, progress=lambda msg: print("  ", msg, flush=True))
    print(pdf)
