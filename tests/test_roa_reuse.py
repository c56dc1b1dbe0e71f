"""Van der Pol speed work of issue 17 (part 5): programs re-solved with cvxpy Parameters give the optimum of a fresh
build, the one-matmul field evaluation and the cached segment points give what the per-term loops gave, the closed
form 2x2 inverse of the batch integrator, and the verification still rejects a wrong certificate."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.analysis.measure import unit_sobol
from glidectl.batch import _inverse
from glidectl.roa import Poly, alternation, certificate, polynomial_system, programs, routes, sector_system  # noqa: F401
from glidectl.roa.polynomial import field_evaluator


def _prepared(ps):
    k = programs.variable_scaling(ps)
    pss = programs.rescaled(ps, k)
    return pss, programs.scaled_field(pss), programs.to_scaled(programs.lyapunov_quadratic(ps), k)


def _perturbed(V: Poly, seed: int, size: float = 0.05) -> Poly:
    """``V`` with every coefficient scaled by ``1 + size * u``, ``u`` uniform in [-1, 1] (same support)."""
    rng = np.random.default_rng(seed)
    return Poly({e: c * (1 + size * rng.uniform(-1, 1)) for e, c in V.terms.items()}, V.nvars)


# ------------------------------------------------------------------------------------------- reused programs
def test_reused_level_program_matches_fresh_build():
    """The level program built once with V as Parameters, re-solved for a second V of the same support, gives the
    level of a program built from scratch for that V (and the first V's level again), to 1e-5: Clarabel's optimum
    of this level SDP at its default tolerances. The two canonicalizations (Parameters, constants) reach it 2.5e-6
    apart on an AMD EPYC with AVX-512 under cvxpy 1.8-1.9, Clarabel 0.9-0.11, numpy 2.3-2.4 and scipy 1.16-1.17
    alike (deterministic run to run), where the machine of earlier sessions agreed to 1e-6."""
    pss, F, V0 = _prepared(gc.benchmarks.van_der_pol())
    ex = programs.auto_extra(pss, None)
    V1 = _perturbed(V0, 1)
    cache: dict = {}
    reused = [programs.solve_level(pss, F, V, rho_cap=1e6, solver="CLARABEL", center=0.05, extra=ex, cache=cache)
              for V in (V0, V1, V0)]
    assert len(cache) == 2          # one level and one centering program, both re-solved
    fresh = [programs.solve_level(pss, F, V, rho_cap=1e6, solver="CLARABEL", center=0.05, extra=ex) for V in (V0, V1)]
    assert reused[1].rho != pytest.approx(reused[0].rho, rel=1e-4)      # the Parameters did change the program
    for r, f in zip(reused, fresh + fresh[:1], strict=False):
        assert r.rho == pytest.approx(f.rho, rel=1e-5)
        assert r.n_sdp == 2 and all(c.max_residual < 1e-7 for c in r.checks)
    assert reused[0].rho == pytest.approx(2.3045, rel=2e-4)          # Drake's level of x'Px


def _margin_with(pss, F, V, lam, rho, ex) -> float:
    """Largest ``t`` with every Gram matrix of the level conditions ``>= t I`` at level ``rho`` with the multiplier
    fixed to ``lam`` (the slack the V step gets from it)."""
    prog, out = programs.build_program(pss, F, 2, V=V, lam=None, rho=rho, eps=0.0, extra=ex, margin=True)
    u = out["lambda"]
    prog.constraints.append(u.var == np.array([lam.terms.get(e, 0.0) for e in u.basis]))
    return prog.solve(cp.Maximize(out["margin"]), solver="CLARABEL")


@pytest.mark.parametrize("reuse", [False, True])
def test_a_large_program_is_centred_by_its_level_program_under_a_cap(monkeypatch, reuse, moment_policy):
    """Where the largest Gram block reaches CENTER_BY_LEVEL_MIN_BLOCK (patched to 1 here: Van der Pol's blocks are
    small) on the moment route, the centering multiplier is the level program's, re-solved with ``rho <= (1 - c)
    rho*``: two SDPs, the uncapped level, and a multiplier with a positive Gram margin at ``(1 - c) rho*`` where the
    uncapped level program's multiplier has none at ``rho*``. Without the patch the feasibility program is used, as
    with Clarabel throughout."""
    pss, F, V0 = _prepared(gc.benchmarks.van_der_pol())
    ex = programs.auto_extra(pss, None)
    plain = programs.solve_level(pss, F, V0, rho_cap=1e6, solver="CLARABEL", center=0.0, extra=ex)
    kept = programs.solve_level(pss, F, V0, rho_cap=1e6, solver="CVXOPT_MOMENT", center=0.1, extra=ex,
                    cache={} if reuse else None)
    feas = programs.solve_level(pss, F, V0, rho_cap=1e6, solver="CLARABEL", center=0.1, extra=ex)
    assert (kept.lam - feas.lam).max_abs_coefficient() < 1e-6 * feas.lam.max_abs_coefficient()
    moment_policy(center_by_level_min_block=1)
    cache: dict = {}
    capped = programs.solve_level(pss, F, V0, rho_cap=1e6, solver="CVXOPT_MOMENT", center=0.1, extra=ex,
                      cache=cache if reuse else None)
    assert capped.n_sdp == 2 and capped.rho == pytest.approx(plain.rho, rel=1e-6)
    assert (capped.lam - feas.lam).max_abs_coefficient() > 1e-6 * feas.lam.max_abs_coefficient()
    assert len(cache) == (1 if reuse else 0)        # no separate centering program
    assert _margin_with(pss, F, V0, capped.lam, 0.9 * plain.rho, ex) > 1e-6
    assert _margin_with(pss, F, V0, plain.lam, plain.rho, ex) < 1e-7
    if reuse:                                       # re-solved at the full cap after the centering
        again = programs.solve_level(pss, F, V0, rho_cap=1e6, solver="CVXOPT_MOMENT", center=0.1, extra=ex, cache=cache)
        assert again.rho == pytest.approx(plain.rho, rel=1e-6)


def test_reused_v_step_matches_fresh_build():
    """The V step built once with the multiplier as Parameters and re-solved for a second multiplier of the same
    support reaches the optimum of a fresh build for that multiplier, to 1e-6."""
    ps = gc.benchmarks.van_der_pol()
    pss, F, V0 = _prepared(ps)
    ex = programs.auto_extra(pss, None)
    lv = programs.solve_level(pss, F, V0, rho_cap=1e6, solver="CLARABEL", center=0.05, extra=ex)
    lam1 = lv.lam
    lam2 = _perturbed(lam1, 2, 0.02)
    lo, hi = ps.box
    Zt = pss.lift(lo + (hi - lo) * unit_sobol(2, 5, 256))
    cache: dict = {}
    vals = []
    for lam in (lam1, lam2):
        prog, _out = programs.solve_v_step(pss, F, 4, lam, Zt, eps=1e-6, extra=ex, solver="CLARABEL", cache=cache)
        vals.append(prog.problem.value)
        assert all(c.max_residual < 1e-7 for c in prog.check())
    assert len(cache) == 1
    for lam, v in zip((lam1, lam2), vals, strict=True):
        fprog, _fout = programs.solve_v_step(pss, F, 4, lam, Zt, eps=1e-6, extra=ex, solver="CLARABEL", cache=None)
        assert v == pytest.approx(fprog.problem.value, rel=1e-6, abs=1e-9)
    assert vals[0] != pytest.approx(vals[1], rel=1e-6)


def test_reuse_option_gives_the_same_certificate_and_fewer_builds(monkeypatch):
    """certify_roa with reuse (default) and without it: the same SOS conditions, so the same first level (to 1e-6)
    and, along the alternation (whose V steps have non-unique minimizers), certificates of the same volume; with
    reuse the programs are built once per degree instead of once per SDP."""
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("odd", ("x1", "x2"), [-x1 + x2, -x1 - x2 + x1**3], box=((-2, -2), (2, 2)))
    kw = dict(degree=2, iterations=2, sampling=dict(n_truth=64, n_verify=2000, n_simulate=8))
    builds = []
    build = programs.build_program

    def counted(*a, **k):
        builds.append(1)
        return build(*a, **k)

    monkeypatch.setattr(programs, "build_program", counted)
    monkeypatch.setattr(alternation, "build_program", counted)
    certs = {}
    for reuse in (True, False):
        builds.clear()
        certs[reuse] = (gc.certify_roa(ps, **kw, solver=dict(reuse=reuse)), len(builds))
    (a, na), (b, nb) = certs[True], certs[False]
    assert a.certified and b.certified
    assert a.history[0].rho == pytest.approx(b.history[0].rho, rel=1e-6)
    assert a.volume(n=2**12) == pytest.approx(b.volume(n=2**12), rel=0.02)
    n_sdp = sum(1 for h in b.history if h.step == "V step + level")
    # (level + centering) + per step 3 (V step, level, centering; the last level is not centred) + final
    assert nb == 2 + 3 * n_sdp - 1 + 1 and na < nb
    with pytest.raises(gc.ArgumentTypeError):
        gc.certify_roa(ps, **kw, solver=dict(reuse="yes"))


# ------------------------------------------------------------------------------------------- evaluation
_coef = st.floats(-3, 3, allow_nan=False).filter(lambda c: c != 0.0)


@st.composite
def _fields(draw):
    n = draw(st.integers(1, 3))
    exps = st.tuples(*[st.integers(0, 3)] * n)
    F = [Poly(draw(st.dictionaries(exps, _coef, min_size=0, max_size=6)), n) for _ in range(draw(st.integers(1, 3)))]
    return n, F


@settings(max_examples=25, deadline=None)
@given(_fields(), st.integers(0, 2**16))
def testfield_evaluator_equals_the_per_term_loop(nF, seed):
    """One gather and one matmul give every component of ``Poly.__call__`` (to rounding), for real points and for
    complex steps (the imaginary part is the exact directional derivative)."""
    n, F = nF
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(17, n))
    D = rng.normal(size=(17, n))
    ev = field_evaluator(F)
    ref = np.stack([f(X) for f in F], axis=-1)
    scale = 1.0 + np.abs(ref)
    assert np.all(np.abs(ev(X) - ref) <= 1e-12 * scale * (1 + sum(len(f.terms) for f in F)))
    h = 1e-30
    dz = ev(X + 1j * h * D).imag / h
    dref = np.stack([sum((f.diff(i)(X) * D[:, i] for i in range(n)), np.zeros(17)) for f in F], axis=-1)
    assert np.allclose(dz, dref, rtol=1e-11, atol=1e-11)
    assert ev(X[0]).shape == (len(F),)


def _contains_reference(ps, V, rho, X, n_path=33):
    """The loop of c6c3172: every point evaluated at every segment point."""
    ok = np.all(np.isfinite(X), axis=-1)
    x0 = np.asarray(ps.equilibrium, dtype=float)
    for t in np.linspace(1.0, 0.0, n_path, endpoint=False):
        Y = np.where(ok[:, None], x0 + t * (X - x0), x0)
        ok &= (certificate.value_of(V, ps, Y) <= rho) & ps.in_cuts(Y)
    return ok


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**16), st.floats(0.05, 3.0), st.integers(1, 40))
def test_contains_and_cached_paths_equal_the_full_loop(seed, rho, n_path):
    """Evaluating only the points still inside (and the cached segment points of the sampled volumes) gives exactly
    the membership of the full loop, for random polynomials that are not star-shaped sublevel sets, NaN rows and a
    system with cuts and an angle lift."""
    rng = np.random.default_rng(seed)
    x1, x2 = Poly.variables(2)
    terms = {e: rng.normal() for e in [(2, 0), (0, 2), (1, 1), (3, 0), (1, 2), (4, 0), (2, 2), (0, 4)]}
    V = Poly(terms, 2) + x1**2 + x2**2
    ps = gc.benchmarks.van_der_pol()
    X = np.concatenate([rng.uniform(-3, 3, size=(300, 2)), [[np.nan, 0.0], [np.inf, 1.0]]])
    ref = _contains_reference(ps, V, rho, X, n_path)
    assert np.array_equal(certificate.path_contains(ps, V, rho, X, n_path), ref)
    assert np.array_equal(certificate.PathPoints(ps, X, n_path).contains(V, rho), ref)
    assert 0 < ref.sum() < len(X) or rho < 0.2


def test_contains_with_cuts_and_angles_equals_the_full_loop():
    """Same on a recast glider model (angle lift, denominator cut)."""
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5", K_M=-50.0))
    ps = gc.recast(sp.reduced_model())
    V = programs.lyapunov_quadratic(ps)
    lo, hi = ps.box
    X = lo + (hi - lo) * np.random.default_rng(3).random((400, ps.n))
    vals = certificate.value_of(V, ps, X)
    for rho in np.quantile(vals, [0.2, 0.6]):
        ref = _contains_reference(ps, V, rho, X)
        assert 0 < ref.sum() < len(X)
        assert np.array_equal(certificate.path_contains(ps, V, rho, X), ref)
        assert np.array_equal(certificate.PathPoints(ps, X).contains(V, rho), ref)


def _buoyancy_sector_points(seed: int, n: int):
    """The chapter-6 buoyancy loop's saturation system (surrogate plant; its lift computes the saturated input from
    ``K x``), its quadratic V and ``n`` random states in the fifth of its box about the equilibrium."""
    sph = gc.load_vehicle("sphere_ch5")
    sl = gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0)))
    ps = sector_system(sl, method="surrogate")
    lo, hi = ps.box
    x0 = np.asarray(ps.equilibrium, dtype=float)
    return ps, programs.lyapunov_quadratic(ps), x0 + 0.2 * (lo + (hi - lo) * np.random.default_rng(seed).random((n,
                                                                                                                 ps.n))
                                                     - x0)


def test_contains_on_a_saturated_surrogate_system_in_batches_equals_the_full_loop(monkeypatch):
    """Same on the chapter-6 buoyancy loop's saturation system (surrogate plant; the lift computes the saturated
    input from ``K x``), with the segment points evaluated in batches of several sizes (``_PATH_BATCH``)."""
    ps, V, X = _buoyancy_sector_points(4, 300)
    vals = certificate.value_of(V, ps, X)
    for rho in np.quantile(vals, [0.3, 0.7]):
        ref = _contains_reference(ps, V, rho, X)
        assert 0 < ref.sum() < len(X)
        for batch in (1, 97, 10**6):
            monkeypatch.setattr(certificate, "_PATH_BATCH", batch)
            assert np.array_equal(certificate.path_contains(ps, V, rho, X), ref), (rho, batch)


def test_contains_lifts_each_evaluated_point_once():
    """``_contains`` hands the lift it computed for ``V`` to ``in_cuts`` (``in_cuts(X, Z)``, the same answer as
    ``in_cuts(X)``): on a saturation system, whose lift computes the saturated input, every evaluation of the
    segment points lifts them once (it lifted them twice, once for ``V`` and once for the cuts)."""
    import dataclasses

    ps, V, X = _buoyancy_sector_points(5, 200)
    x0 = np.asarray(ps.equilibrium, dtype=float)
    assert np.array_equal(ps.in_cuts(X, ps.lift(X)), ps.in_cuts(X))
    rows = []

    def lift(Y):
        rows.append(np.asarray(Y).shape[0])
        return ps.lift(Y)

    counted = dataclasses.replace(ps, lift=lift)
    rho = float(np.quantile(certificate.value_of(V, ps, X), 0.5))
    ok = certificate.path_contains(counted, V, rho, X)
    assert np.array_equal(ok, _contains_reference(ps, V, rho, X)) and 0 < ok.sum() < len(X)
    # t = 1 for all 200 points, then the other 32 segment points of those still inside, in one batch: each once
    Y1 = x0 + 1.0 * (X - x0)
    first = (certificate.value_of(V, ps, Y1) <= rho) & ps.in_cuts(Y1)
    assert rows == [200, 32 * int(first.sum())]


# ------------------------------------------------------------------------------------------- integrator
@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**16))
def test_closed_form_2x2_inverse(seed):
    rng = np.random.default_rng(seed)
    W = rng.normal(size=(50, 2, 2)) + 3 * np.eye(2)
    Wi = _inverse(W)
    assert np.allclose(np.einsum("mij,mjk->mik", W, Wi), np.eye(2), atol=1e-9)
    W[7] = [[1.0, 2.0], [2.0, 4.0]]                   # singular: NaN, so that step is rejected and retried
    Wi = _inverse(W)
    assert np.all(np.isnan(Wi[7])) and np.all(np.isfinite(np.delete(Wi, 7, axis=0)))


# ------------------------------------------------------------------------------------------- soundness
def test_verification_rejects_a_level_beyond_the_region_of_attraction():
    """The a-posteriori checks (sampled true dV/dt, simulations from the outermost samples) pass for Drake's level
    of x'Px on Van der Pol and fail when the level is inflated past the limit cycle."""
    ps = gc.benchmarks.van_der_pol()
    V = programs.lyapunov_quadratic(ps)
    kw = dict(n_verify=4000, n_simulate=32, horizon=50.0, seed=0)
    good = certificate.verify_certificate(ps, V, 2.3, (), **kw)
    assert good.passed, good
    bad = certificate.verify_certificate(ps, V, 4.0 * 2.3, (), **kw)
    assert not bad.passed
    assert bad.max_Vdot > 0 and bad.n_converged < bad.n_simulated
