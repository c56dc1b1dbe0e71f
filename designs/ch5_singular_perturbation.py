"""Chapter 5 design: singular-perturbation reduction, composite Lyapunov certificate and region of attraction.

Run ``python designs/ch5_singular_perturbation.py [OUTDIR]`` (same as ``glidectl report ch5_singular_perturbation``);
writes ``OUTDIR/ch5_singular_perturbation/`` (default ``reports/``).
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("ch5_singular_perturbation")
