"""SOS conditions matched modulo the angle equalities (``glidectl.roa.quotient``): normal forms, the lift of a
residual that no Gram entry reaches, and the quotient form's equivalence with the multiplier form it replaces."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.roa import dVdt, max_level, programs, recast
from glidectl.roa.polynomial import Poly
from glidectl.roa.programs import build_program, lyapunov_quadratic
from glidectl.roa.quotient import angle_quotient
from glidectl.roa.sos import _pair_sums

N = 3      # variables of the hand-made cases: (s, c, y)


def _h(ks: float = 1.0, kc: float = 1.0) -> Poly:
    """The angle equality in the scaled variables s = sin(x) / ks, c = (1 - cos(x)) / kc."""
    Z = Poly.variables(N)
    return (ks * ks) * Z[0] ** 2 + (kc * kc) * Z[1] ** 2 - 2.0 * kc * Z[1]


def _on_variety(ks: float, kc: float, n: int = 64, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.uniform(-np.pi, np.pi, n)
    return np.stack([np.sin(x) / ks, (1.0 - np.cos(x)) / kc, rng.uniform(-1.0, 1.0, n)], axis=1)


@pytest.fixture(scope="module")
def reduced():
    return recast(gc.singular_perturbation(gc.load_vehicle("sphere_ch5")).reduced_model())


_terms = st.dictionaries(st.tuples(*[st.integers(0, 5)] * N), st.floats(-10, 10, allow_nan=False).filter(
    lambda v: abs(v) > 1e-3), min_size=1, max_size=8)


@settings(max_examples=40, deadline=None)
@given(terms=_terms, ks=st.floats(0.2, 5.0), kc=st.floats(0.2, 5.0))
def test_normal_form_equals_the_polynomial_on_the_variety(terms, ks, kc):
    """NF(p) = p at points of the variety, every s at most linear, NF idempotent, NF(h) = 0 (scaled variables)."""
    q = angle_quotient(N, (_h(ks, kc),))
    assert q is not None and q.pairs[0][:2] == (0, 1)
    p = Poly(terms, N)
    f = q.nf(p)
    Z = _on_variety(ks, kc)
    # rounding bound: a few ulps of the sums of the absolute values of the terms (of p, and of its normal form,
    # whose rewriting can make large terms that cancel on the variety)
    size = Poly({e: abs(v) for e, v in p.terms.items()}, N)(np.abs(Z)) + Poly(
        {e: abs(v) for e, v in f.terms.items()}, N)(np.abs(Z))
    assert np.all(np.abs(f(Z) - p(Z)) <= 1e-13 * size + 1e-300)
    assert all(e[0] <= 1 for e in f.terms)
    assert q.nf(f).terms == pytest.approx(f.terms)
    assert q.nf(_h(ks, kc)).max_abs_coefficient() <= 1e-14 * max(ks, kc) ** 2     # (rounding of the rule)


def test_quotient_found_only_for_angle_equalities(reduced):
    Z = Poly.variables(N)
    assert angle_quotient(N, (Z[0] ** 3 - Z[2], Z[0] * Z[1] - Z[2])) is None   # (graph equalities of a saturation)
    assert angle_quotient(N, (Z[0] ** 2 + Z[1] ** 2 - 2.0 * Z[2],)) is None    # linear term not in the squared pair
    q = angle_quotient(N, (_h(), Z[0] ** 3 - Z[2]))
    assert q.pairs == ((0, 1, -1.0, 2.0),) and q.covers(_h()) and not q.covers(Z[0] ** 3 - Z[2])
    qr = angle_quotient(reduced.nz, reduced.equalities)
    assert qr is not None and all(qr.covers(h) for h in reduced.equalities)
    assert {s for s, *_ in qr.pairs} == set(reduced.s_caps)


def test_lift_moves_an_unreached_residual_onto_reached_monomials():
    """A residual on ``c`` (no pair of a degree-1 basis reaches it) becomes a residual on ``s^2`` and ``c^2``, the
    same polynomial on the variety."""
    q = angle_quotient(N, (_h(0.7, 1.3),))
    basis = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    reach = _pair_sums(basis, distinct=False)
    res = Poly({(0, 1, 0): 3e-8, (0, 0, 2): -1e-9, (1, 1, 0): 2e-9}, N)
    lifted = q.lift(res, reach)
    assert all(e in reach or abs(v) <= 1e-20 for e, v in lifted.terms.items())
    Z = _on_variety(0.7, 1.3)
    assert np.max(np.abs(lifted(Z) - res(Z))) <= 1e-20
    # a residual the equalities cannot move (a constant) is returned as it was
    res0 = Poly({(0, 0, 0): 1e-9}, N)
    assert q.lift(res0, reach).terms == res0.terms


def test_quotient_program_equals_the_multiplier_program(reduced, monkeypatch, moment_policy):
    """The same level of a fixed V (one SDP each), with fewer equations and no multiplier unknowns."""
    V = lyapunov_quadratic(reduced)
    out, sizes = {}, {}
    for flag in (False, True):
        moment_policy(quotient_min_block=0 if flag else math.inf)
        out[flag] = max_level(reduced, V)
        prog, _ = build_program(reduced, list(reduced.F), 2, V=V, lam=None, rho=None, eps=1e-6)
        sizes[flag] = (sum(u.size for u in prog.unknowns if u.name.startswith("psi")),
                       sum(c.shape[0] if c.shape else 1 for c in prog.constraints if id(c) in prog.coefficient_rows))
    assert out[True].rho == pytest.approx(out[False].rho, rel=1e-5)
    assert out[True].rho > 0
    assert sizes[False][0] > 0 and sizes[True][0] == 0
    assert sizes[True][1] < sizes[False][1]


def test_size_estimate_counts_the_quotient_form(reduced, monkeypatch, moment_policy):
    """estimate_sos_size: no multiplier unknowns and the standard monomials' equations with the quotient."""
    moment_policy(quotient_min_block=0)
    with_q = gc.estimate_sos_size(reduced, 4)
    moment_policy(quotient_min_block=math.inf)
    without = gc.estimate_sos_size(reduced, 4)
    assert with_q.gram == without.gram and with_q.bytes == without.bytes
    assert with_q.n_free < without.n_free and with_q.n_constraints < without.n_constraints


def test_quotient_certificate_is_sound_and_matches_the_multiplier_form(reduced, monkeypatch, moment_policy):
    """The reduced glider's certificate by both forms: both certified, the quotient one with its Gram checks
    passed and the true dV/dt < 0 at sampled points of its set, and the same set to the solvers' accuracy."""
    cert = {}
    for flag in (False, True):
        moment_policy(quotient_min_block=0 if flag else math.inf)
        cert[flag] = gc.certify_roa(reduced, degree=2, iterations=1, sampling=dict(n_verify=2000, n_simulate=32))
    c = cert[True]
    assert c.certified and c.verification.gram_passed, c.verification.summary()
    assert cert[False].certified
    X = c.sample(400, seed=3)
    assert np.all(c.contains(X))
    dV = dVdt(c.V, c.system.lift, c.system.rhs, X)
    far = np.linalg.norm(X, axis=1) > 1e-3
    assert far.sum() > 300 and np.all(dV[far] < 0.0)
    assert c.volume() == pytest.approx(cert[False].volume(), rel=0.02)


def test_quotient_only_for_programs_of_the_moment_route(reduced):
    """By default only programs with a decrease Gram matrix of order QUOTIENT_MIN_BLOCK or more take the quotient
    form: the reduced glider at degree 2 (order 24) and the full glider at degree 2 (49) keep their multipliers;
    the full glider at degree 4 (104) does not."""
    V = lyapunov_quadratic(reduced)
    prog, _ = build_program(reduced, list(reduced.F), 2, V=V, lam=None, rho=None, eps=1e-6)
    assert prog.quotient is None and any(u.name.startswith("psi") for u in prog.unknowns)
    full = recast(gc.singular_perturbation(gc.load_vehicle("sphere_ch5")).full_model())
    k = gc.roa.MOMENT_POLICY.quotient_min_block
    assert programs._quotient(full, k - 1) is None and programs._quotient(full, k) is not None
    assert gc.estimate_sos_size(full, 2).gram[0] == ("decrease", 49) and 49 < k
    assert gc.estimate_sos_size(full, 4).gram[0] == ("decrease", 104) and 104 >= k
