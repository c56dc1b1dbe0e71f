"""Chapter 8 design: 3D steady motions (circular helices) of the Slocum-like glider, the 2000 s simulation converging
to the helix of §8.2.2, helix maps versus r_P and m0 (with the existence claim tested), stability versus
bottom-heaviness (frozen and re-solved equilibria) and inverse helix design.

Run ``python designs/ch8_helix.py [OUTDIR]`` (same as ``glidectl report ch8_helix``); writes ``OUTDIR/ch8_helix/``
(default ``reports/``).
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("ch8_helix")
