"""Chapter 4 design: phugoid-mode model, Lanchester's classes of motion (Fig 4.1), Hamiltonian formulations.

Run ``python designs/ch4_phugoid.py [OUTDIR]`` (same as ``glidectl report ch4_phugoid``); writes
``OUTDIR/ch4_phugoid/`` (default ``reports/``).
"""

import sys

from glidectl.studies import ch4_phugoid

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "reports"
    pdf = ch4_phugoid.build(out, progress=lambda msg: print("  ", msg, flush=True))
    print(pdf)
