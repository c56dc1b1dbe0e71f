"""Issue 17: the sampler of certified sets (``_sample_set``, ``ROACertificate.sample``) on thin sets in many states.

The rejection rounds are unchanged whenever they succeed quickly (same random stream, bitwise the same points, checked
against a verbatim copy of the sampler before the change); a thin set switches to the directed sampler, whose points
are inside the set and uniform in its volume (radial law against the volume ratio of a scaled copy, law of one
coordinate against its exact marginal)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

import glidectl as gc
import glidectl.roa.certify as cert_mod
from glidectl.errors import SolverError
from glidectl.roa import Poly, lyapunov_quadratic, polynomial_system
from glidectl.roa.certify import _contains, _sample_set


def _old_sample_set(ps, V, rho, n, seed, boundary, check=None):
    """Verbatim copy of ``_sample_set`` before issue 17's change (main at 66dbb45)."""
    x0 = np.asarray(ps.equilibrium, dtype=float)
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    w = np.maximum(x0 - lo, hi - x0)
    free = [i for i in range(ps.n) if i not in ps.held]      # held states stay at their values
    nf = len(free)
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    got = 0

    def contains(X: np.ndarray) -> np.ndarray:
        return _contains(ps, V, rho, X)

    for _ in range(200):
        if check is not None:
            check()
        m = max(2 * n, 256)
        U = np.zeros((m, ps.n))
        U[:, free] = rng.standard_normal((m, nf))
        U /= np.linalg.norm(U, axis=1, keepdims=True)
        D = U * w                                   # directions in state units
        with np.errstate(divide="ignore", invalid="ignore"):
            tb = np.min(np.where(D > 0, (hi - x0) / D, np.where(D < 0, (lo - x0) / D, np.inf)), axis=1)
        a, b = np.zeros(m), tb * (1 - 1e-12)
        inside = contains(x0 + b[:, None] * D)
        a[inside] = b[inside]
        for _ in range(40):
            if check is not None:
                check()
            mid = 0.5 * (a + b)
            ok = contains(x0 + mid[:, None] * D) | inside
            a, b = np.where(ok, mid, a), np.where(ok, b, mid)
        R = a
        if boundary:
            keep = R > 0
            pts = x0 + (R[keep] * (1 - 1e-9))[:, None] * D[keep]
        else:
            if not np.any(R > 0):
                continue
            keep = (rng.random(m) < (R / np.max(R)) ** nf) & (R > 0)
            rad = R[keep] * rng.random(int(keep.sum())) ** (1.0 / nf)
            pts = x0 + rad[:, None] * D[keep]
        out.append(pts)
        got += len(pts)
        if got >= n:
            break
    if got == 0:
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    return np.concatenate(out)[:n]


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
    monkeypatch.setattr(cert_mod, "_sample_directed", lambda *a, **k: calls.append(1))
    for n, seed in ((300, 1), (1000, 7)):
        new = _sample_set(ps, V, rho, n, seed, boundary)
        old = _old_sample_set(ps, V, rho, n, seed, boundary)
        assert new.shape == old.shape == (n, ps.n)
        assert np.array_equal(new, old)
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
    directed = cert_mod._sample_directed
    monkeypatch.setattr(cert_mod, "_sample_directed", lambda *a, **k: calls.append(1) or directed(*a, **k))
    n = 3000
    X = _sample_set(ps, V, rho, n, 0, False)
    assert calls == [1]                       # the rejection rounds alone would need far more rounds
    assert X.shape == (n, NF) and np.all(_contains(ps, V, rho, X))
    # radial law: the share in the copy scaled by 0.8 about the equilibrium is 0.8^NF (any star-shaped set)
    k_in = int(np.sum(_contains(ps, V, rho, X / 0.8)))
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
    assert X.shape == (n, NF) and np.all(_contains(ps, V, rho, X))
    for s in (0.9, 0.7):
        assert _binomial_ok(int(np.sum(_contains(ps, V, rho, X / s))), n, s ** NF)
    # both halves of the long axis (the set is symmetric)
    assert _binomial_ok(int(np.sum(X[:, 0] > 0)), n, 0.5)
    Xb = _sample_set(ps, V, rho, 500, 6, True)          # boundary points: one round, no switch
    assert Xb.shape == (500, NF) and np.all(_contains(ps, V, rho, Xb))
    assert not np.any(_contains(ps, V, rho, Xb * (1 + 1e-6)))


def test_directed_sampler_empty_set_raises():
    ps, V, _ = _thin()
    with pytest.raises(SolverError, match="empty"):
        cert_mod._sample_directed(ps, V, -1.0, 10, 0)


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
