"""Evaluation of ``Poly`` at many points: bitwise the naive sum of terms in the order of ``Poly.terms`` (real and
complex points, any batch shape), through ``__call__`` and through a shared powers table (``on_powers``). It pins the
order of operations: a faster evaluation must give the same bits (the sampled volumes and verifications of the ROA
reports depend on them), which a contiguous complex product did not (numpy's FMA, 1 ulp)."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from glidectl.roa import Poly
from glidectl.roa.polynomial import monomials, powers_table


def _naive(p: Poly, Z: np.ndarray) -> np.ndarray:
    """The definition, term by term in the order of ``p.terms``: ``c * z_i^e_i * ...`` summed from zero."""
    out = np.zeros(Z.shape[:-1], dtype=np.result_type(Z, float))
    for e, c in p.terms.items():
        term = c
        for i, k in enumerate(e):
            if k:
                pw = np.ones(Z.shape[:-1], dtype=out.dtype)
                for _ in range(k):
                    pw = pw * Z[..., i]
                term = term * pw
        out = out + term
    return out


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), nv=st.integers(1, 6), deg=st.integers(0, 5),
       shape=st.sampled_from([(1,), (7,), (300,), (4, 25), (2, 3, 5)]), cplx=st.booleans())
def test_evaluation_at_many_points_is_bitwise_the_sum_of_terms(seed: int, nv: int, deg: int, shape: tuple,
                                                               cplx: bool) -> None:
    rng = np.random.default_rng(seed)
    mons = monomials(nv, deg)
    keep = rng.random(len(mons)) < 0.7
    p = Poly({e: float(rng.standard_normal()) for e, k in zip(mons, keep, strict=True) if k}, nv)
    Z = rng.uniform(-2.0, 2.0, (*shape, nv))
    if cplx:
        Z = Z + 1j * rng.uniform(-1e-3, 1e-3, Z.shape)
    want = _naive(p, Z)
    got = p(Z)
    assert got.shape == shape and got.dtype == want.dtype
    assert np.array_equal(got, want)
    if p.terms:
        assert np.array_equal(p.on_powers(powers_table(Z, max(max(e) for e in p.terms))), want)


def test_one_point_gives_a_scalar() -> None:
    x, y = Poly.variables(2)
    p = 1.5 * x ** 2 - x * y + 0.25
    v = p(np.array([2.0, 3.0]))
    assert np.ndim(v) == 0 and v == 1.5 * 4.0 - 6.0 + 0.25
