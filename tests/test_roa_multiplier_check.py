"""The Gram check covers the S-procedure multipliers: a certificate passes only if it holds with every multiplier
exactly SOS (its Gram matrix made positive semidefinite), not with the solver's approximately SOS one."""

from __future__ import annotations

import math

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from glidectl.roa.polynomial import Poly, monomials
from glidectl.roa.sos import LinPoly, SOSProgram


def _program(a: float = 2.0, solve: bool = True) -> tuple[SOSProgram, object, list]:
    """``a x^2 + 1 - sigma`` SOS with the multiplier ``sigma = s x^2`` SOS (``0 <= s <= a``); solved with ``solve``
    (only a feasible program: ``a >= 0``)."""
    x = Poly.variables(1)[0]
    prog = SOSProgram(1)
    u, sigma = prog.sos_poly("sigma", [(1,)])
    us = prog.add_sos("p", LinPoly(a * x**2 + 1.0) - sigma, monomials(1, 1))
    if solve:
        prog.solve(cp.Minimize(0))
    return prog, u, us


def _fake(u: object, us: list, s: float, a: float = 2.0) -> None:
    """Set the multiplier to ``s x^2`` and the constraint's Gram matrix to match ``(a - s) x^2 + 1`` exactly."""
    u.var.value = np.array([[s]])
    coef = {(0,): 1.0, (1,): a - s}         # Gram diagonal on the monomials 1 and x (one block each, or one block)
    for g in us:
        g.var.value = np.diag([coef[tuple(b)] for b in g.basis])


def test_a_solved_program_with_a_psd_multiplier_passes_unshifted():
    prog, u, us = _program()
    _fake(u, us, 0.5)
    (chk,) = prog.check()
    assert chk.passed and chk.multiplier_shift == 0.0 and chk.max_residual < 1e-15
    assert list(prog.multiplier_values()) == [u]


def test_a_negative_multiplier_fails_the_check_it_used_to_pass():
    """``sigma = -0.6 x^2`` is not SOS. With ``a = -0.5``, ``p = 0.1 x^2 + 1`` has an exact PSD Gram matrix (what
    the check saw before: residual 0, passed); made SOS (``sigma = 0``) the constraint is ``-0.5 x^2 + 1``, which is
    not SOS: residual 0.6 on x^2, and the projected Gram matrix ``diag(1, 0.1 - 0.6)`` is indefinite."""
    prog, u, us = _program(a=-0.5, solve=False)
    _fake(u, us, -0.6, a=-0.5)
    _, expr, grams = prog.sos_constraints[0]
    raw = expr.value() - sum((g.poly() for g in grams), Poly({}, 1))
    assert raw.max_abs_coefficient() < 1e-15          # the old check's residual: the certificate looked exact
    (chk,) = prog.check()
    assert chk.multiplier_shift == pytest.approx(0.6, rel=1e-12)
    assert chk.max_residual == pytest.approx(0.6, rel=1e-12)
    assert chk.projected_min_eig == pytest.approx(-0.5, rel=1e-12) and chk.projected_residual < 1e-15
    assert not chk.passed and chk.slack == pytest.approx(max(0.1 - 2 * 0.6, -0.5), rel=1e-12)


def test_the_projection_passes_a_residual_the_bound_could_not_absorb():
    """``sigma = -0.6 x^2`` against ``2 x^2 + 1``: made SOS, the constraint ``2 x^2 + 1`` is SOS, but the Gram matrix
    of ``2.6 x^2 + 1`` leaves a residual 0.6 that ``n_basis max|r| = 1.2`` cannot absorb (unprojected slack -0.2).
    Spread onto the Gram entry of ``x^2`` it gives ``diag(1, 2)``: passed, with the exact certificate."""
    prog, u, us = _program()
    _fake(u, us, -0.6)
    (chk,) = prog.check()
    assert chk.min_eig - chk.n_basis * chk.max_residual == pytest.approx(1.0 - 2 * 0.6, rel=1e-12)
    assert chk.projected_min_eig == pytest.approx(1.0, rel=1e-12) and chk.projected_residual < 1e-15
    assert chk.passed and chk.slack == pytest.approx(1.0, rel=1e-12)


@settings(max_examples=25, deadline=None)
@given(st.floats(min_value=1e-9, max_value=1.0),
       st.floats(min_value=-1.0, max_value=2.0).filter(lambda a: abs(a) > 1e-6))
def test_the_shift_is_the_multipliers_negative_eigenvalue(q: float, a: float):
    """Made SOS, the multiplier is 0 and the constraint ``a x^2 + 1``: it passes iff ``a > 0``, whatever the
    solver's Gram matrix ``diag(1, a + q)``; the unprojected bound ``min(1, a + q) - 2 q`` is never more lenient."""
    prog, u, us = _program(a=a, solve=False)
    _fake(u, us, -q, a=a)
    (chk,) = prog.check()
    (Qp,) = prog.multiplier_values().values()
    assert np.linalg.eigvalsh(Qp)[0] >= 0.0
    assert chk.multiplier_shift == pytest.approx(q, rel=1e-9)
    assert chk.max_residual == pytest.approx(q, rel=1e-9)
    assert chk.projected_min_eig == pytest.approx(min(1.0, a), rel=1e-9, abs=1e-12)
    assert chk.passed == (a > 0)
    assert chk.slack >= min(1.0, a + q) - 2 * q - 1e-12


@pytest.mark.parametrize("quotient", [False, True])
def test_real_level_program_multipliers_are_made_psd_and_counted(quotient, monkeypatch, moment_policy):
    """A solved level program of the chapter-5 reduced glider (a recast with a speed cut, so with multipliers):
    every multiplier Gram matrix given to the check is PSD, and the check's residual of each constraint is the
    residual at those matrices: matched modulo the angle equality (``glidectl.roa.quotient``), a polynomial equal to
    it at every point of the lifted variety."""
    import glidectl as gc
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401
    from glidectl.roa.sos import _gram_residual

    ps = gc.recast(gc.singular_perturbation(gc.load_vehicle("sphere_ch5")).reduced_model())
    assert ps.cuts
    moment_policy(quotient_min_block=0 if quotient else math.inf)
    F = programs.scaled_field(ps)
    V = programs.lyapunov_quadratic(ps)
    prog, out = programs.build_program(ps, F, 2, V=V, lam=None, rho=None, eps=0.0, extra=0, margin=False)
    prog.solve(cp.Maximize(out["rho"].var))
    mult = prog.multiplier_values()
    assert mult, "the level program has S-procedure multipliers"
    for Q in mult.values():
        assert np.linalg.eigvalsh(Q)[0] >= 0.0
    for chk, (_, expr, grams) in zip(prog.check(), prog.sos_constraints, strict=True):
        res = expr.value(mult)
        for g in grams:
            res = res - g.poly()
        if not quotient:
            assert prog.quotient is None
            assert chk.max_residual == pytest.approx(res.max_abs_coefficient(), rel=1e-12, abs=1e-300)
            continue
        assert prog.quotient is not None
        checked, _, _ = _gram_residual(expr, grams, mult, prog.quotient)
        assert chk.max_residual == pytest.approx(checked.max_abs_coefficient(), rel=1e-12, abs=1e-300)
        assert chk.max_residual < 1e-6 < res.max_abs_coefficient()      # the ideal's multiple is not a residual
        Z = ps.lift(np.random.default_rng(0).uniform(*ps.box, (200, ps.n)))
        assert np.max(np.abs(checked(Z) - res(Z))) <= 1e-9 * max(1.0, res.max_abs_coefficient())


def _low_program(c0: float, c1: float) -> SOSProgram:
    """``x^2 + y^2 - c0 - c1 x`` with a half basis without the constant (as the decrease condition's), its Gram
    matrix set to the identity: the residual ``-c0 - c1 x`` no basis pair reaches."""
    x, y = Poly.variables(2)
    prog = SOSProgram(2, reduce=False)
    (g,) = prog.add_sos("decrease", LinPoly(x**2 + y**2 - c0 - c1 * x), monomials(2, 1, 1))
    g.var.value = np.eye(2)
    return prog


@settings(max_examples=40, deadline=None)
@given(st.floats(1e-12, 1e-2), st.floats(0.0, 1e-2))
def test_an_unreachable_low_degree_residual_bounds_a_radius(c0: float, c1: float):
    """The check used to count the constant and linear residual as absorbable: slack ~1, passed, although the
    polynomial is negative near 0. The radius marks where it stops speaking: the polynomial is >= 0 for
    ``|z| >= radius`` and negative somewhere inside."""
    (chk,) = _low_program(c0, c1).check()
    assert chk.passed and chk.low == pytest.approx((c0, c1), rel=1e-12) and chk.full_linear
    r = chk.radius
    assert 0 < r < 1
    t = np.linspace(0, 2 * np.pi, 721)
    for rr in (r, 1.5 * r, 0.9):
        P = rr * np.stack([np.cos(t), np.sin(t)], axis=1)
        assert np.all(P[:, 0] ** 2 + P[:, 1] ** 2 - c0 - c1 * P[:, 0] >= -1e-15)
    x, y = Poly.variables(2)
    p = x**2 + y**2 - c0 - c1 * x
    assert p(np.zeros((1, 2)))[0] < 0                  # negative at 0, inside the radius: the old pass was unsound
    (clean,) = _low_program(0.0, 0.0).check()
    assert clean.radius == 0.0 and clean.low == (0.0, 0.0)


def test_local_robust_check_covers_the_radius():
    """``W = -x^2 - y^2 + 10 x^3``: negative definite at 0, positive beyond x = 0.1. The local check passes on a
    radius of 0.05 (tail 10 * 0.05 < 1) and fails on 0.2; an infinite radius fails."""
    from glidectl.roa.routes import local_robust_checks
    from glidectl.roa.surrogate import skeleton

    ps = skeleton(2, 3)
    x, y = Poly.variables(2)
    W = -(x**2) - y**2 + 10.0 * x**3
    (ok,) = local_robust_checks(W, ps, 0.05)
    (bad,) = local_robust_checks(W, ps, 0.2)
    (inf_,) = local_robust_checks(W, ps, float("inf"))
    assert ok.passed and ok.min_eig == pytest.approx(1.0) and ok.max_residual == pytest.approx(0.5)
    assert not bad.passed and not inf_.passed


def _psi_program(c1: float, shared: bool):
    """``x^2 + y^2 + c1 x + a (x^2 - 2 x)``: the free ``a`` (an equality multiplier's constant) must cancel the
    linear term, ``a = c1 / 2``; left at 0 (a solver's residual) the linear term is unreachable by the Gram matrix on
    (x, y). With ``shared``, ``a`` also enters a second constraint."""
    prog = SOSProgram(2)
    x, y = Poly.variables(2)
    a, al = prog.free_poly("a", [(0, 0)])
    expr = LinPoly(x**2 + y**2 + c1 * x) + al * (x**2 - 2.0 * x)
    blocks = prog.add_sos("decrease", expr, [(1, 0), (0, 1)])
    if shared:
        blocks += prog.add_sos("other", LinPoly(x**2) + al * x**2, [(1, 0)])
    for g in blocks:
        g.var.value = np.eye(len(g.basis))
    a.var.value = np.zeros(1)
    return prog, a


@settings(max_examples=30, deadline=None)
@given(st.floats(1e-10, 1e-3))
def test_unreached_low_residual_is_cancelled_by_the_constraints_own_free_unknowns(c1: float):
    """The check cancels the unreachable linear residual exactly with a free unknown only this constraint uses
    (radius 0, the identity holds to rounding), and leaves an unknown shared with another constraint alone (the
    radius stays: changing it would change the other constraint)."""
    prog, a = _psi_program(c1, shared=False)
    (chk,) = prog.check()
    assert a.value()[0] == pytest.approx(c1 / 2, rel=1e-12)
    assert chk.low[1] <= 1e-15 * max(c1, 1.0) and chk.radius < 1e-12 and chk.passed
    prog, a = _psi_program(c1, shared=True)
    chk, _ = prog.check()
    assert a.value()[0] == 0.0 and chk.low[1] == pytest.approx(c1, rel=1e-12) and chk.radius > 0


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 3), st.integers(0, 2), st.floats(-3.0, 3.0)),
                min_size=1, max_size=6))
def test_angle_reduction_keeps_the_function_on_the_circle_and_s_linear(terms):
    """``_reduce_angle`` (modulo s^2 + c^2 - 2c, the recast's chain rule) leaves s at most linear and the value on
    the lifted circle (s, c) = (sin t, 1 - cos t) unchanged; the degree does not grow."""
    from glidectl.roa.systems import _reduce_angle

    t: dict = {}
    for a, b, x, v in terms:        # variables (x0, s, c): exponents of x0, s, c
        t[(x, a, b)] = t.get((x, a, b), 0.0) + v
    p = Poly(t, 3)
    q = _reduce_angle(p, 1, 2)
    assert all(e[1] <= 1 for e in q.terms) and q.degree <= max(p.degree, 0)
    th = np.linspace(-3.0, 3.0, 61)
    Z = np.stack([0.7 * np.ones_like(th), np.sin(th), 1.0 - np.cos(th)], axis=1)
    scale = 1.0 + sum(abs(v) for v in t.values()) * 4.0**p.degree
    assert np.max(np.abs(q(Z) - p(Z))) <= 1e-12 * scale


def test_cut_multipliers_lose_the_constant_only_where_it_is_forced():
    """``tau_k(0) = 0`` is forced for a cut positive at the equilibrium (CTOL: the speed cut, 0.9 at the glide), not
    for the Taylor enclosures (0 there); a cut negative at the equilibrium, which a positive one could balance, turns
    the reduction off for all."""
    import dataclasses
    import math

    import glidectl as gc
    from glidectl.roa.programs import _tau_low_degrees

    veh = gc.load_vehicle("dc8_ctol")
    gl = gc.ctol_glide(veh, speed=0.85 / math.sqrt(veh.a_L), gamma=0.0)
    ps = gc.recast(gc.ClosedLoopCTOL(veh, gl, 10.0, 5.0).roa_model())
    assert len(ps.cuts) == 1 and len(ps.valid) == 4
    assert _tau_low_degrees(ps) == [1, 0, 0, 0, 0]
    bad = dataclasses.replace(ps, cuts=(ps.cuts[0], ps.cuts[0] - 1.0))      # 0.9 and -0.1 at the glide
    assert _tau_low_degrees(bad) == [0] * 6


def _gram_poly(Q: np.ndarray, basis: list) -> Poly:
    """``m^T Q m`` as a polynomial."""
    t: dict = {}
    for i, bi in enumerate(basis):
        for j, bj in enumerate(basis):
            e = tuple(a + b for a, b in zip(bi, bj, strict=True))
            t[e] = t.get(e, 0.0) + Q[i, j]
    return Poly(t, len(basis[0]))


def _checked(Q0: np.ndarray, E: np.ndarray, basis: list) -> object:
    """The Gram check of ``p = m^T Q0 m`` against the solver's Gram matrix ``Q0 + E``."""
    prog = SOSProgram(2, reduce=False)
    (g,) = prog.add_sos("p", LinPoly(_gram_poly(Q0, basis)), basis)
    g.var.value = Q0 + 0.5 * (E + E.T)
    (chk,) = prog.check()
    return chk


def test_the_projected_check_is_never_weaker_and_never_passes_a_negative_polynomial():
    """``p = m^T Q0 m`` on the 10 monomials of degree <= 3 in two variables, ``Q0`` random with its spectrum shifted
    to ``lambda_min = shift``, checked against ``Q0 + E`` (a solver's error of size ``err``), over 60 seeds: the
    projection leaves only rounding and its slack is never below the unprojected bound's; every ``p`` negative at a
    sampled point fails (at least 10 such cases occur); every ``Q0`` with ``lambda_min >= 0.2`` and errors
    of 1e-2 passes (the unprojected bound fails at least 10 of those: the projection is what proves them)."""
    basis = monomials(2, 3)
    n = len(basis)
    negative = proved_only_by_projection = 0
    for seed in range(60):
        rng = np.random.default_rng(seed)
        L = rng.normal(size=(n, n))
        Q0 = L @ L.T / n
        shift = rng.uniform(-0.5, 0.5)
        Q0 = Q0 - (np.linalg.eigvalsh(Q0)[0] - shift) * np.eye(n)
        err = 10.0 ** rng.uniform(-8, -1)
        chk = _checked(Q0, rng.normal(size=(n, n)) * err, basis)
        assert chk.projected_residual < 1e-12 * (1.0 + np.max(np.abs(Q0)))
        assert chk.slack >= chk.min_eig - n * chk.max_residual - 1e-12
        Z = rng.uniform(-3.0, 3.0, (4000, 2))
        if np.min(_gram_poly(Q0, basis)(Z)) < -1e-9:
            negative += 1
            assert not chk.passed
        if shift >= 0.2:
            good = _checked(Q0, rng.normal(size=(n, n)) * 1e-2, basis)
            assert good.passed
            proved_only_by_projection += good.min_eig - n * good.max_residual <= 0
    assert negative >= 10 and proved_only_by_projection >= 10, (negative, proved_only_by_projection)


def _unreached_program(shared: bool = False) -> tuple[SOSProgram, object, object]:
    """``1e-7 (1 + x^2) + psi x^3`` SOS on the half basis ``(1, x)`` (pairs reach 1, x, x^2, not x^3), ``psi`` a
    free constant (an equality multiplier): exactly SOS only with ``psi = 0``. The values are set as a solver would
    leave them: the exact Gram matrix ``1e-7 I`` and ``psi = 1e-6``, a residual on the unreached ``x^3`` that the
    check counts whole. With ``shared``, ``psi`` also enters a second constraint."""
    x = Poly.variables(1)[0]
    prog = SOSProgram(1)
    psi_u, psi = prog.free_poly("psi", [(0,)])
    (g,) = prog.add_sos("p", LinPoly(1e-7 * (1.0 + x**2)) + psi * x**3, monomials(1, 1))
    if shared:
        for g2 in prog.add_sos("q", LinPoly(1.0 + x**2) + psi * x**2, monomials(1, 1)):    # exact Gram blocks
            g2.var.value = np.diag([{(0,): 1.0, (1,): 1.0 + 1e-6}[tuple(b)] for b in g2.basis])
    g.var.value = 1e-7 * np.eye(2)
    psi_u.var.value = np.array([1e-6])
    return prog, psi_u, g


def test_polish_cancels_a_residual_no_gram_entry_reaches():
    """A final check's polish (``check(polish=True)``) moves the free multiplier to cancel the residual on the
    monomial no Gram pair reaches: the check that failed (slack ``1e-7 - 2e-6 < 0``) passes, with the residual left
    at rounding; the plain check leaves the solver's values as they were."""
    prog, psi_u, _ = _unreached_program()
    (plain,) = prog.check()
    assert not plain.passed and plain.projected_residual == pytest.approx(1e-6, rel=1e-12)
    assert psi_u.var.value[0] == 1e-6                      # untouched
    (pol,) = prog.check(polish=True)
    assert pol.passed and pol.projected_residual < 1e-20 and pol.min_eig == pytest.approx(1e-7, rel=1e-12)
    assert abs(psi_u.var.value[0]) < 1e-20
    _, expr, grams = prog.sos_constraints[0]
    left = expr.value() - sum((g.poly() for g in grams), Poly({}, 1))
    assert left.max_abs_coefficient() < 1e-20              # the identity holds with the polished values


def test_polish_leaves_a_multiplier_that_another_constraint_uses():
    """``psi`` enters a second constraint: changing it would change that one too, so the polish does not touch it
    and the failing check stays failed (nothing is assumed)."""
    prog, psi_u, _ = _unreached_program(shared=True)
    chk = prog.check(polish=True)
    assert not chk[0].passed and psi_u.var.value[0] == 1e-6


def test_polish_leaves_an_unknown_a_constraint_of_the_caller_holds():
    """A scalar ``rho`` that also reaches ``x^3`` but is held by a constraint of the caller (``rho == 0``: the fixed
    level of a final margin program) is not moved: the whole correction goes to the free ``psi``. (Least squares
    over both would split it, and the check would then prove the identity at another ``rho`` than the one held.)"""
    x = Poly.variables(1)[0]
    prog = SOSProgram(1)
    psi_u, psi = prog.free_poly("psi", [(0,)])
    rho_u, rho = prog.scalar("rho")
    (g,) = prog.add_sos("p", LinPoly(1e-7 * (1.0 + x**2)) + psi * x**3 + rho * x**3, monomials(1, 1))
    prog.constraints.append(rho_u.var == 0.0)
    g.var.value = 1e-7 * np.eye(2)
    psi_u.var.value, rho_u.var.value = np.array([1e-6]), np.array([0.0])
    (chk,) = prog.check(polish=True)
    assert chk.passed and rho_u.var.value[0] == 0.0 and abs(psi_u.var.value[0]) < 1e-20
