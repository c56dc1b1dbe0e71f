"""Speed layer of the SOS path (issue 17 part 5): exact basis reduction (Newton polytope, diagonal consistency,
sign symmetry), the level problem without bisection, problem reuse and timing records."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.roa import Poly, alternation, certificate, monomials, polynomial_system, programs, routes  # noqa: F401
from glidectl.roa.sos import LinPoly, SOSProgram, parity_generators, reduce_basis, sign_classes


# ------------------------------------------------------------------------------------------- parity / symmetry
def test_parity_generators_exact():
    """Even polynomials in (x, y) are invariant under (x, y) -> (-x, -y); x^2 y also under x -> -x only."""
    G = parity_generators([(2, 0), (1, 1), (0, 4)], 2)
    assert G.tolist() == [[1, 1]]
    G = parity_generators([(2, 1), (0, 2)], 2)
    assert G.tolist() == [[1, 0]]
    assert parity_generators([(1, 0), (0, 1)], 2).shape == (0, 2)
    assert parity_generators([(2, 0), (0, 2)], 2).shape == (2, 2)    # every sign flip
    # every generator leaves every monomial of the support even
    supp = [(2, 1, 1), (0, 2, 0), (1, 1, 0), (0, 0, 2)]
    G = parity_generators(supp, 3)
    assert G.shape[0] == 1 and np.all((G @ np.array(supp).T) % 2 == 0)


def test_sign_classes_partition():
    basis = monomials(2, 3)
    blocks = sign_classes(basis, np.array([[1, 1]]))
    assert sorted(map(len, blocks)) == [4, 6]
    assert sorted(b for blk in blocks for b in blk) == sorted(basis)
    assert all(sum(b) % 2 == sum(blk[0]) % 2 for blk in blocks for b in blk)


# ------------------------------------------------------------------------------------------- reduce_basis
def _sos_of(qs: list[Poly]) -> Poly:
    return sum((q * q for q in qs), Poly({}, qs[0].nvars))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**31 - 1), st.integers(1, 3), st.integers(1, 3))
def test_reduced_basis_keeps_every_monomial_of_a_decomposition(seed, nvars, nq):
    """For p = sum q_k^2 with random sparse q_k, the reduced half basis contains the support of every q_k (those
    monomials carry positive Gram diagonal entries, which no exact reduction may drop)."""
    rng = np.random.default_rng(seed)
    full = monomials(nvars, 3)
    qs = []
    for _ in range(nq):
        pick = rng.choice(len(full), size=min(len(full), int(rng.integers(1, 5))), replace=False)
        qs.append(Poly({full[i]: float(rng.normal()) or 1.0 for i in pick}, nvars))
    p = _sos_of(qs)
    blocks = reduce_basis(list(p.terms), full)
    kept = {b for blk in blocks for b in blk}
    need = {e for q in qs for e in q.terms}
    assert need <= kept
    assert len(kept) == sum(len(b) for b in blocks)          # blocks are disjoint


def test_reduced_basis_drops_outside_half_newton_polytope():
    """x^4 y^2 + x^2 y^4 + 1: half basis candidates of degree <= 3; the Newton polytope keeps 1, xy, x^2y, xy^2
    (plus nothing else that a decomposition could use) and the sign symmetries split them."""
    blocks = reduce_basis([(4, 2), (2, 4), (0, 0)], monomials(2, 3))
    kept = {b for blk in blocks for b in blk}
    assert kept <= {(0, 0), (1, 1), (2, 1), (1, 2)}
    assert {(0, 0), (2, 1), (1, 2)} <= kept
    assert max(len(b) for b in blocks) <= 2


def _min_sos_bound(p: Poly, half: list, reduce: bool) -> tuple[float, int, str]:
    """Largest gamma with p - gamma SOS (full or reduced basis), the largest Gram block, the solver status."""
    prog = SOSProgram(p.nvars, reduce=reduce)
    _, g = prog.scalar("gamma")
    prog.add_sos("p", LinPoly(p) - g, half)
    val = prog.solve(cp.Maximize(prog.unknowns[0].var[0]))
    (chk,) = prog.check()
    assert chk.max_residual < 1e-6
    return val, max(max(v) for v in prog.gram_sizes().values()), prog.status


@pytest.mark.parametrize("which", ["even", "odd", "sparse"])
def test_reduced_basis_same_optimum_as_full(which):
    """max gamma s.t. p - gamma SOS: the reduced program has the same optimum as the full one, with smaller
    Gram blocks. Known answers: 'even' has minimum -1 at x = +-1, y = 0 (and p + 1 is SOS); for 'sparse' the
    half Newton polytope is {1, xy, x^2 y, x y^2}, x^3 y^3 is absent so the Gram matrix is
    diag([[3 - gamma, -1], [-1, 2]], I_2) and the bound is exactly 2.5. There the full 10 x 10 program is
    ill-posed (no interior: the solver reports 'optimal_inaccurate' and a wrong 2.53), which the reduction cures."""
    x, y = Poly.variables(2)
    p = {"even": x**4 - 2.0 * x**2 + y**4 + x**2 * y**2 + y**2,
         "odd": x**4 + y**4 + x**3 * y + x + 0.5 * y**2,
         "sparse": x**4 * y**2 + x**2 * y**4 + 2.0 * x**2 * y**2 - 2.0 * x * y + 3.0}[which]
    half = monomials(2, 3)
    full, nf, status_full = _min_sos_bound(p, half, reduce=False)
    red, nr, status_red = _min_sos_bound(p, half, reduce=True)
    assert status_red == cp.OPTIMAL
    assert nr < nf
    if status_full == cp.OPTIMAL:
        assert red == pytest.approx(full, abs=1e-5 * max(1.0, abs(full)))
    else:
        assert which == "sparse"
    if which in ("even", "sparse"):
        assert red == pytest.approx({"even": -1.0, "sparse": 2.5}[which], abs=1e-5)


def test_reduced_infeasible_stays_infeasible():
    """-x^2 - y^2 is not SOS on any basis: the reduced program is infeasible as the full one."""
    x, y = Poly.variables(2)
    prog = SOSProgram(2)
    prog.add_sos("q", LinPoly(-(x**2) - y**2), monomials(2, 2))
    with pytest.raises(gc.SolverError):
        prog.solve(cp.Minimize(0))


# ------------------------------------------------------------------------------------------- program symmetry
def _prepared(ps):
    k = programs.variable_scaling(ps)
    pss = programs.rescaled(ps, k)
    return pss, programs.scaled_field(pss), programs.to_scaled(programs.lyapunov_quadratic(ps), k)


def test_van_der_pol_symmetry_found_and_exact():
    """Van der Pol is odd (x -> -x): the level problem finds that symmetry, splits its Gram matrix and gives the
    same level as without any reduction (Drake's 2.3045 for V = x'Px)."""
    ps = gc.benchmarks.van_der_pol()
    pss, F, V = _prepared(ps)
    G = programs._symmetry(pss, F, (V,))
    assert G.tolist() == [[1, 1]]
    ex = programs.auto_extra(pss, None)
    red = programs.solve_level(pss, F, V, rho_cap=1e6, solver="CLARABEL", center=0.0, extra=ex)
    prog, _ = programs.build_program(pss, F, 2, V=V, lam=None, rho=None, eps=0.0, extra=ex, symmetry=False)
    prog.constraints.append(_["rho"].var <= 1e6)
    full = prog.solve(cp.Maximize(_["rho"].var[0]))
    assert red.rho == pytest.approx(full, rel=1e-5)
    assert red.rho == pytest.approx(2.3045, rel=1e-3)
    progr, _ = programs.build_program(pss, F, 2, V=V, lam=None, rho=None, eps=0.0, extra=ex)
    assert len(progr.gram_sizes()["decrease"]) == 2 and sum(progr.gram_sizes()["decrease"]) <= 14


def test_asymmetric_system_has_no_symmetry():
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("asym", ("x1", "x2"), [-x1 + x1**2, -x2 + x1 * x2], box=((-1, -1), (1, 1)))
    pss, F, V = _prepared(ps)
    # x2 -> -x2 is a symmetry of F (x1' even in x2, x2' odd); V = x'Px is diagonal here, so it stays
    G = programs._symmetry(pss, F, (V,))
    assert G.tolist() == [[0, 1]]
    G2 = programs._symmetry(pss, F, (V + x1 * x2,))           # a V that is not invariant removes it
    assert G2.shape[0] == 0


# ------------------------------------------------------------------------------------------- level search
def _bisect(pss, F, V, ex, lo, hi, tol):
    """Largest feasible level by bisection on fixed-level feasibility SDPs (the reference)."""
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        prog, _ = programs.build_program(pss, F, programs.even_up(V.degree), V=V, lam=None, rho=mid, eps=0.0, extra=ex)
        try:
            prog.solve(cp.Minimize(0))
            lo = mid
        except gc.SolverError:
            hi = mid
    return lo, hi


@pytest.mark.parametrize("case", ["cubic", "vdp"])
def test_level_without_bisection_matches_bisection(case):
    """The level is a variable of one SDP: same value as bisection over fixed-level SDPs (cubic: rho = 1 known
    exactly; Van der Pol with x'Px: Drake's 2.3045)."""
    if case == "cubic":
        x = Poly.variables(1)[0]
        ps = polynomial_system("cubic", ("x",), [-x + x**3], box=((-2.0,), (2.0,)))
        pss, F, _ = _prepared(ps)
        V = programs.to_scaled(x**2, programs.variable_scaling(ps))
    else:
        ps = gc.benchmarks.van_der_pol()
        pss, F, V = _prepared(ps)
    ex = programs.auto_extra(pss, None)
    lv = programs.solve_level(pss, F, V, rho_cap=1e6, solver="CLARABEL", center=0.0, extra=ex)
    assert lv.n_sdp == 1
    lo, hi = _bisect(pss, F, V, ex, 0.5 * lv.rho, 2.0 * lv.rho, 1e-4)
    assert lo * (1 - 1e-4) <= lv.rho <= hi * (1 + 1e-4)
    known = {"cubic": 1.0, "vdp": 2.3045}[case]        # V values are unchanged by the internal scaling
    assert lv.rho == pytest.approx(known, rel=2e-4)


def test_level_center_step_records_times():
    """With center > 0 a second SDP finds lambda at (1 - center) rho*, with slack for the V step; compile and
    solver times are recorded."""
    ps = gc.benchmarks.van_der_pol()
    pss, F, V = _prepared(ps)
    ex = programs.auto_extra(pss, None)
    lv = programs.solve_level(pss, F, V, rho_cap=1e6, solver="CLARABEL", center=0.1, extra=ex)
    assert lv.n_sdp == 2 and lv.compile_time > 0 and lv.solver_time > 0
    assert lv.compile_time + lv.solver_time <= lv.solve_time * 1.5 + 1e-3
    # that lambda has slack: the V step with it at the level (1 - center) rho* is feasible
    prog, _out = programs.build_program(pss, F, 2, V=None, lam=lv.lam, rho=0.9 * lv.rho, eps=1e-9, extra=ex)
    prog.solve(cp.Minimize(0))
    assert all(c.max_residual < 1e-6 for c in prog.check())


def test_gram_check_refuses_residual_the_reduction_made_unreachable():
    """A residual on a monomial that only the dropped basis monomials could produce cannot be absorbed: the check
    reports an infinite residual (the reduction never lets a certificate pass that the full program would fail)."""
    x, y = Poly.variables(2)
    prog = SOSProgram(2)
    prog.add_sos("p", LinPoly(x**2 + y**2), monomials(2, 2))
    prog.solve(cp.Minimize(0))
    (ok,) = prog.check()
    assert ok.passed and ok.max_residual < 1e-8
    # fake a residual on x^4: only x^2 (dropped: outside the half Newton polytope) reaches it
    name, expr, us = prog.sos_constraints[0]
    assert (2, 0) not in {b for u in us for b in u.basis}
    prog.sos_constraints[0] = (name, expr + Poly({(4, 0): 1e-12}, 2), us)
    (bad,) = prog.check()
    assert bad.max_residual == float("inf") and not bad.passed


def test_certificate_history_records_compile_and_solver_times():
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("odd", ("x1", "x2"), [-x1 + x2, -x1 - x2 + x1**3], box=((-2, -2), (2, 2)))
    c = gc.certify_roa(ps, degree=2, iterations=1, sampling=dict(n_truth=64, n_verify=2000, n_simulate=8))
    assert c.certified, c.verification.summary()
    timed = [h for h in c.history if h.compile_time == h.compile_time]     # (NaN: a row without an SDP)
    assert timed and all(h.compile_time >= 0 and h.solver_time > 0 for h in timed)
    assert timed[-1].step.startswith("final margin")
    assert sum(h.sdp_time for h in c.history) == pytest.approx(c.solve_time, rel=1e-6)
