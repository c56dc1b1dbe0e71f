"""Chapter 6 design: nonlinear steady-glide controllers of the underwater glider — pure torque (with gain selection
certified by the composite Lyapunov function), buoyancy, elevator + buoyancy (Fig 6.2, Theorem 3), the torque law
realized by the moving mass, and a comparison with LQR on the same models.

Run ``python designs/ch6_controllers.py [OUTDIR]`` (same as ``glidectl report ch6_controllers``); writes
``OUTDIR/ch6_controllers/`` (default ``reports/``).
"""

from glidectl.studies import run_design

if __name__ == "__main__":
    run_design("ch6_controllers")
