"""Chapter 4 design: phugoid-mode model, Lanchester's classes of motion (Fig 4.1), Hamiltonian formulations.

Run ``python designs/ch4_phugoid.py [OUTDIR]`` (same as ``glidectl report ch4_phugoid``); writes
``OUTDIR/ch4_phugoid/`` (default ``reports/``).
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("ch4_phugoid")
