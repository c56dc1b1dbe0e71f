"""
Root locus over bottom-heaviness (Fig 2.7)
==========================================

Under acceleration control of the moving mass (2.31)-(2.34) the glide's stability is decided by the 4x4 block
``dq_r/deta_r`` of the states ``(theta, Omega2, v1, v3)`` (2.35): the moving-mass and pump loop (2.37) only adds
the poles of ``A + BK``. :func:`glidectl.rbh_locus` re-solves the ROGUE -45 deg, 0.3 m/s glide for every
bottom-heaviness ``r_bh`` (the component of the moving-mass position along gravity, m) and tracks the four
eigenvalues, with the stability crossing and the break points marked.
"""

import matplotlib.pyplot as plt
import numpy as np

import glidectl as gc

rogue = gc.load_vehicle("rogue")
locus = gc.rbh_locus(rogue, 0.3, -np.pi / 4, np.linspace(-0.02, 0.10, 241))
for c in locus.crossings:
    print(f"stability boundary at r_bh = {c * 1000:.2f} mm (the thesis reads -6.8 mm off its plot)")
for b in locus.breakpoints:
    print(b)

# %%
# Top: the locus in the complex plane, coloured by ``r_bh``. Bottom: the real parts against ``r_bh``; the glide
# is stable to the right of the crossing, i.e. when the moving mass sits low enough.
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.5, 8), layout="constrained")
locus.plot(ax=ax1)
locus.plot(ax=ax2, kind="real")
plt.show()
