"""Issue 17: the sampler of certified sets (``_sample_set``, ``ROACertificate.sample``) on thin sets in many states.

The rejection rounds are unchanged whenever they succeed quickly (same random stream, bitwise the same points, checked
against fingerprints of the points before the change); a thin set switches to the directed sampler, whose points
are inside the set and uniform in its volume (radial law against the volume ratio of a scaled copy, law of one
coordinate against its exact marginal)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

import glidectl as gc
from glidectl.errors import SolverError
from glidectl.roa import Poly, alternation, certificate, lyapunov_quadratic, polynomial_system, programs, routes  # noqa: F401
from glidectl.roa.certificate import _sample_set, path_contains

#: fingerprints of the rejection sampler's points before issue 17's change (main at 66dbb45; recorded with that
#: code's sampler, which the rejection rounds still are): (case, boundary, n, seed) -> (float.hex of the sum of all
#: coordinates, float.hex of rows 0, n // 2 and n - 1). Bitwise: any change of the random stream or the arithmetic
#: changes them.
OLD_POINTS = {(0, False, 300, 1): ('-0x1.ec605f98892f9p+4',
                      (('0x1.54ee21ce83226p-3', '0x1.40e6bc6f7b9e2p-3'),
                       ('0x1.6beb22e5e7277p-6', '-0x1.50be35ad0013cp-2'),
                       ('0x1.09dfab29b160ap-1', '-0x1.8e53c157b475bp-1'))),
 (0, False, 1000, 7): ('-0x1.6279d8f8cf3f0p+6',
                       (('0x1.4f8a00e4ce274p-9', '0x1.735b7f812cbf6p-1'),
                        ('-0x1.63176846f8a35p-4', '-0x1.56c1222bef57ap-1'),
                        ('-0x1.04f2196c76915p+0', '-0x1.b78025e4b2edfp-1'))),
 (0, True, 300, 1): ('-0x1.58e6d034e1d46p+3',
                     (('0x1.eef9f09416e24p-2', '0x1.573b50162c5b4p+0'),
                      ('-0x1.147f184e31451p+0', '-0x1.5791d675d6f7ep-2'),
                      ('0x1.c53cfd672af8ap-3', '-0x1.16be0761761d4p+0'))),
 (0, True, 1000, 7): ('-0x1.88c057af775d9p+6',
                      (('0x1.1bcac706e16bdp-8', '0x1.3a1626134f28fp+0'),
                       ('0x1.cd48ce0c3993ep-1', '0x1.25ac28b3146cdp+0'),
                       ('-0x1.0e8404a370fb7p+0', '-0x1.b3cf6ccaa4c73p-1'))),
 (1, False, 300, 1): ('-0x1.05ad5947491c6p+5',
                      (('-0x1.6ed8f84e944d8p-3', '0x1.08ae43169b019p-2', '0x1.f2273820fb2a0p-4'),
                       ('-0x1.a05b213572de4p-1', '-0x1.1090fe1320eb1p-6', '0x1.bafe9793f8948p-2'),
                       ('-0x1.d8407bf2d0185p-2', '-0x1.04ac63e39fd1bp-2', '-0x1.94e695969ecadp-3'))),
 (1, False, 1000, 7): ('0x1.09240a5d0dc1dp+5',
                       (('0x1.d28f8e56758a6p-10', '0x1.2710e502f074bp-1', '-0x1.9624604feb73ap-2'),
                        ('0x1.dbb0be540e696p-2', '-0x1.2a4584530cf91p-1', '0x1.9bffcc9078e2ap-2'),
                        ('0x1.692ee3bb4c3edp-3', '-0x1.8d2147d697516p-2', '0x1.d6fc38664a5bep-1'))),
 (1, True, 300, 1): ('-0x1.98599dac84d2cp+4',
                     (('0x1.0e038aa6d9bffp-2', '0x1.abf7b5d3780dfp-1', '0x1.022dd31ad1c75p-2'),
                      ('0x1.a79ff5ea8ab9dp-1', '-0x1.5afee8f5aed97p-2', '0x1.1a53169d9161cp-5'),
                      ('-0x1.8e7c5fd9f4cdfp-1', '0x1.62ff55e0ac39bp-2', '-0x1.8a243e3a3811ep-2'))),
 (1, True, 1000, 7): ('-0x1.2f3806a497f9cp+6',
                      (('0x1.458ce528ff009p-9', '0x1.9bc6324b93acdp-1', '-0x1.1b646b28e5042p-1'),
                       ('-0x1.b857b3020df07p-2', '0x1.8c491ca5ba43bp-1', '0x1.6e7f92e7e6980p-3'),
                       ('0x1.51e6dbe10b457p-1', '-0x1.d7620923001eep-2', '-0x1.1acc103bdd399p-1')))}


def _linear(nf: int, lo, hi):
    Z = Poly.variables(nf)
    return polynomial_system(f"linear{nf}", tuple(f"x{i}" for i in range(nf)), [-z for z in Z], box=(lo, hi))


def _vdp_cases():
    vdp = gc.benchmarks.van_der_pol()
    V = lyapunov_quadratic(vdp)
    Z = Poly.variables(3)
    F3 = [-Z[0] + Z[1] ** 2, -Z[1] - Z[0] * Z[2], -2.0 * Z[2] + Z[0] ** 3]
    ps3 = polynomial_system("cubic3", ("a", "b", "c"), F3,
                            box=([-1.0, -2.0, -1.5], [1.5, 1.0, 1.5]))
    return [(vdp, V, 1.5), (ps3, lyapunov_quadratic(ps3), 0.4)]


@pytest.mark.parametrize("case", [0, 1])
@pytest.mark.parametrize("boundary", [False, True])
def test_rejection_path_is_bitwise_unchanged(case, boundary, monkeypatch):
    ps, V, rho = _vdp_cases()[case]
    calls = []
    monkeypatch.setattr(certificate, "_sample_directed", lambda *a, **k: calls.append(1))
    for n, seed in ((300, 1), (1000, 7)):
        new = _sample_set(ps, V, rho, n, seed, boundary)
        total, rows = OLD_POINTS[(case, boundary, n, seed)]
        assert new.shape == (n, ps.n)
        assert float(new.sum()).hex() == total
        assert [[float(v).hex() for v in r] for r in new[[0, n // 2, n - 1]]] == [list(r) for r in rows]
    assert not calls


# a thin set in 6 states: an ellipsoid with semi-axes 1 (x0) and 0.05 (the others), cut by the box at |x0| = 0.7
NF = 6
AX = np.array([1.0] + [0.05] * (NF - 1))
LO, HI = [-0.7] + [-1.0] * (NF - 1), [0.7] + [1.0] * (NF - 1)


def _thin(quartic: float = 0.0):
    ps = _linear(NF, LO, HI)
    Z = Poly.variables(NF)
    V = Poly({}, NF)
    for i in range(NF):
        V = V + (1.0 / AX[i] ** 2) * Z[i] ** 2
    if quartic:
        V = V + quartic * Z[0] ** 4           # still star-shaped (convex), no longer an ellipsoid
    return ps, V, 1.0


def _marginal_fraction(c: float, clip: float) -> float:
    """P(|x0| > c) for x uniform in the unit-x0-semi-axis ellipsoid of NF states cut at |x0| <= clip: the x0
    marginal is proportional to (1 - x0^2)^((NF - 1) / 2)."""
    f = lambda t: (1.0 - t * t) ** ((NF - 1) / 2)   # noqa: E731
    return quad(f, c, clip)[0] / quad(f, 0.0, clip)[0]


def _binomial_ok(k: int, n: int, p: float, z: float = 4.5) -> bool:
    return abs(k - n * p) <= z * np.sqrt(n * p * (1 - p))


def test_thin_set_switches_and_is_uniform(monkeypatch):
    ps, V, rho = _thin()
    calls = []
    directed = certificate._sample_directed
    monkeypatch.setattr(certificate, "_sample_directed", lambda *a, **k: calls.append(1) or directed(*a, **k))
    n = 3000
    X = _sample_set(ps, V, rho, n, 0, False)
    assert calls == [1]                       # the rejection rounds alone would need far more rounds
    assert X.shape == (n, NF) and np.all(path_contains(ps, V, rho, X))
    # radial law: the share in the copy scaled by 0.8 about the equilibrium is 0.8^NF (any star-shaped set)
    k_in = int(np.sum(path_contains(ps, V, rho, X / 0.8)))
    assert _binomial_ok(k_in, n, 0.8 ** NF)
    # direction law: the share with |x0| > 0.35 is that of the exact x0 marginal (the box cut makes R(u) non-
    # ellipsoidal); uniform directions without the R^nf weight would put almost every point at small |x0|
    p = _marginal_fraction(0.35, 0.7)
    assert _binomial_ok(int(np.sum(np.abs(X[:, 0]) > 0.35)), n, p)
    assert np.array_equal(X, _sample_set(ps, V, rho, n, 0, False))          # reproducible


def test_thin_non_ellipsoidal_set_radial_law_and_boundary():
    ps, V, rho = _thin(quartic=3.0)
    n = 2000
    X = _sample_set(ps, V, rho, n, 5, False)
    assert X.shape == (n, NF) and np.all(path_contains(ps, V, rho, X))
    for s in (0.9, 0.7):
        assert _binomial_ok(int(np.sum(path_contains(ps, V, rho, X / s))), n, s ** NF)
    # both halves of the long axis (the set is symmetric)
    assert _binomial_ok(int(np.sum(X[:, 0] > 0)), n, 0.5)
    Xb = _sample_set(ps, V, rho, 500, 6, True)          # boundary points: one round, no switch
    assert Xb.shape == (500, NF) and np.all(path_contains(ps, V, rho, Xb))
    assert not np.any(path_contains(ps, V, rho, Xb * (1 + 1e-6)))


def test_directed_sampler_empty_set_raises():
    ps, V, _ = _thin()
    with pytest.raises(SolverError, match="empty"):
        certificate._sample_directed(ps, V, -1.0, 10, 0)


def test_in_cuts_shared_powers_table_is_bitwise_each_cut():
    import dataclasses

    ps = _linear(3, [-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])
    a, b, c = Poly.variables(3)
    cuts = (1.0 - a ** 2 - 0.3 * b ** 3, 0.5 + a * b * c - c ** 4, Poly({}, 3) + 1.0, 0.2 - b)
    ps = dataclasses.replace(ps, cuts=cuts)
    X = np.random.default_rng(2).uniform(-1.2, 1.2, (4000, 3))
    want = np.ones(len(X), dtype=bool)
    for g in cuts:
        want &= g(X) >= 0
    assert 0.05 < want.mean() < 0.95 and np.array_equal(ps.in_cuts(X), want)
    from glidectl.roa.polynomial import powers_table

    pw = powers_table(X, 4)
    for g in cuts:
        assert np.array_equal(g.on_powers(pw), g(X))
