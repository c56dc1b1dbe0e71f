"""Chapter 5 design: singular-perturbation reduction, composite Lyapunov certificate and region of attraction.

Run ``python designs/ch5_singular_perturbation.py [OUTDIR]`` (same as ``glidectl report ch5_singular_perturbation``);
writes ``OUTDIR/ch5_singular_perturbation/`` (default ``reports/``).
"""

import sys

from glidectl.studies import ch5_singular_perturbation

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "reports"
    pdf = ch5_singular_perturbation.build(out, progress=lambda msg: print("  ", msg, flush=True))
    print(pdf)
