"""Profile of the CTOL region-of-attraction certificate (issue 17 part 5, issue 18): what is built and why it is big.

The chapter-7 CTOL closed loop of ``bench/bench_roa.py`` case ``ctol`` (``ClosedLoopCTOL(dc8_ctol, level glide at
0.85 / sqrt(a_L), k3 = 10, k4 = 5).roa_model()``, ``certify_roa(degree=2, iterations=1)``). Printed:

1. the recast: its time, the lifted variables, and per component of ``F`` the number of terms, the degree and the
   largest exponents of the mixed angle ``alphabar`` and of ``1 - cos(alphabar)``;
2. the same recast restricted to the exponents the physics allows (``alphabar`` at most 2: lift and drag
   (7.1)-(7.2) are polynomials of degree 1 and 2 in it; ``1 - cos`` at most 3): its residual, terms and degrees
   (``--physical``);
3. the level program of the starting ``V`` as ``certify_roa`` builds it: build time, Gram block sizes before and
   after :func:`~glidectl.roa.sos.reduce_basis`, the support of the polynomial that must be SOS (by degree, against
   the number of monomials of that degree) and the unknowns; with ``--solve`` it is solved once (compile and
   solver times).

Measured 2026-12-01 (load 12-28 on the shared 2-core machine, so the times are inflated several-fold):

- recast 40 s (load ~2) to 167 s (load ~26), 83 % of it in ``numpy.linalg.lstsq`` (12 least-squares fits of up to
  ~2400 x 800, the degree search 1..5 and 7 sparse refits); F has 180-232 terms per component, every component of
  degree 5, with ``alphabar`` up to exponent 5 and O(1) coefficients on terms such as ``alphabar^3 sin(alphabar)``
  that cancel only on the graph of (sin, 1 - cos) (the fit's basis is nearly dependent there);
- with the physical exponent caps the fit is exact to 3e-14 (today's 1.5e-11) with 15-62 terms per component, and
  only ``Vbar'`` has degree 5 (``(1 + Vbar)^3 K_Dr(alpha)``), the others 3-4;
- the level program: decrease Gram 103 x 103 (degree 6 in 7 variables, half basis of degree 1-3 with the sines
  capped at 1), nothing removed: the support of the decrease polynomial has 1616 monomials, every monomial of
  degree <= 6 the equalities leave (the multipliers ``tau`` of the cut and the Taylor enclosures, degree 4, and
  ``psi`` of the two angle equalities, degree 4, are full, and ``N = (z . z)^2`` alone already spans the whole
  Newton polytope); no sign symmetry (F has every parity). Containment 7 + 1; tau blocks 36, 36, 8, 36, 8.
  Clarabel: 8120 variables, 1745 equalities, one 5356-entry PSD cone: ~5 s per interior-point iteration at load
  2, 3-4 min at load 28, 25-30 iterations.

Run ``python bench/bench_roa_ctol_sizes.py [--physical] [--solve]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--physical", action="store_true", help="also fit F with the physical exponent caps")
    ap.add_argument("--solve", action="store_true", help="solve the level program once (slow: minutes)")
    args = ap.parse_args()

    import cvxpy as cp

    import glidectl as gc
    from glidectl.roa import certify as C
    from glidectl.roa.polynomial import monomial_matrix, monomials
    from glidectl.roa.sos import linear_support as _support
    from glidectl.roa.sos import reduce_basis

    veh = gc.load_vehicle("dc8_ctol")
    gl = gc.ctol_glide(veh, speed=0.85 / math.sqrt(veh.a_L), gamma=0.0)
    model = gc.ClosedLoopCTOL(veh, gl, 10.0, 5.0).roa_model()
    t0 = time.perf_counter()
    ps = C.recast(model)
    print(f"recast {time.perf_counter() - t0:.1f} s, z = {ps.z_names}, residual {ps.recast_residual:.2e}")
    ia, ica = ps.slots[2][0], ps.slots[2][2]
    for name, f in zip(ps.z_names, ps.F, strict=True):
        E = np.array(list(f.terms))
        print(f"  F[{name}]: {len(f.terms)} terms, degree {f.degree}, max exponent alphabar {E[:, ia].max()}, "
              f"1-cos(alphabar) {E[:, ica].max()}")
    if args.physical:
        caps = dict(ps.s_caps)
        basis = [e for e in monomials(ps.nz, ps.degree, 0, caps) if e[ia] <= 2 and e[ica] <= 3
                 and e[ps.slots[1][1]] <= 3]
        lo, hi = (np.array(b, dtype=float) for b in ps.box)
        slo, shi = lo.copy(), hi.copy()
        slo[1:3], shi[1:3] = -np.pi, np.pi
        slo[0] = max(slo[0], -0.9)
        rng = np.random.default_rng(0)

        def targets(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            Fx = np.asarray(model.rhs(X))
            Zd = np.imag(ps.lift(X + 1j * 1e-30 * Fx)) / 1e-30
            Zx = ps.lift(X)
            return Zx, Zd * ps.den(Zx)[:, None]

        t0 = time.perf_counter()
        Zx, T = targets(slo + (shi - slo) * rng.random((4 * len(basis), ps.n)))
        M = monomial_matrix(Zx, basis)
        sc = np.max(np.abs(M), axis=0)
        coef = np.linalg.lstsq(M / sc, T, rcond=None)[0] / sc[:, None]
        Zt, Tt = targets(slo + (shi - slo) * rng.random((2000, ps.n)))
        res = np.max(np.abs(monomial_matrix(Zt, basis) @ coef - Tt)) / np.max(np.abs(Tt))
        keep = [np.flatnonzero(np.abs(c) > 1e-8 * np.max(np.abs(c))) for c in coef.T]
        print(f"physical caps (alphabar <= 2, 1-cos <= 3): basis {len(basis)}, residual {res:.2e}, "
              f"{time.perf_counter() - t0:.1f} s; terms {[len(k) for k in keep]}, degrees "
              f"{[max(sum(basis[i]) for i in k) for k in keep]}")
    ex = C.auto_extra(ps, None)
    k = C.variable_scaling(ps)
    pss = C.rescaled(ps, k)
    F = C.scaled_field(pss)
    V = C.to_scaled(C.lyapunov_quadratic(ps), k)
    print(f"degrees {C._degrees(2, ps.degree, ex)}; estimate: {C._size(ps, 2, ex).summary()}")
    t0 = time.perf_counter()
    prog, out = C.build_program(pss, F, 2, V=V, lam=None, rho=None, eps=0.0, extra=ex)
    print(f"level program built in {time.perf_counter() - t0:.1f} s; Gram blocks {prog.gram_sizes()}; symmetry "
          f"generators {out['symmetry'].tolist()}")
    for name, expr, _ in prog.sos_constraints:
        S = _support(expr)
        D = max(sum(e) for e in S)
        by = {d: sum(1 for e in S if sum(e) == d) for d in range(D + 1)}
        full = {d: len(monomials(pss.nz, d, d)) for d in range(D + 1)}
        kept = sum(len(b) for b in reduce_basis(S, prog.full_bases[name]))
        print(f"  {name}: support {len(S)} monomials, by degree {by} of {full}; half basis "
              f"{len(prog.full_bases[name])} -> {kept} after reduce_basis")
    print("  unknowns:", [(u.name, len(u.basis) if u.gram else u.size) for u in prog.unknowns])
    print("certify_roa(degree=2, iterations=1) solves: initial level + centring, V step, last level (not centred), "
          "final margin program: 5 programs of this size")
    if args.solve:
        prog.constraints.append(out["rho"].var <= 1e6)
        rho = prog.solve(cp.Maximize(out["rho"].var[0]))
        print(f"level {rho:.6g}: solve {prog.solve_time:.1f} s (compile {prog.compile_time:.1f} s, solver "
              f"{prog.solver_time:.1f} s)")


if __name__ == "__main__":
    main()
