"""Coefficient matching modulo the angle equalities (the quotient ring of the lifted variety).

An exact recast lifts each angle ``x`` to ``s = sin x``, ``c = 1 - cos x`` on the variety
``h = s^2 + c^2 - 2 c = 0`` (:func:`~glidectl.roa.systems.recast`). An SOS condition on that variety,
``p + sum_j psi_j h_j = m' Q m`` with free multipliers ``psi_j`` of degree ``deg p - 2``, is equivalent to
``NF(p) = NF(m' Q m)``: equality of the *normal forms* modulo the ideal ``<h_j>``, where ``NF`` rewrites
``s^2 -> 2 c - c^2`` until every ``s`` is at most linear. The ``h_j`` of distinct angles have coprime leading
monomials ``s_j^2``, so they are a Groebner basis and the normal form is unique; the rewriting never raises the
degree, so the division algorithm gives multipliers ``psi_j`` of degree at most ``deg p - 2``: the two programs
have the same feasible set (Parrilo 2005, *Exploiting algebraic structure in sum of squares programs*).

The quotient form has no multiplier unknowns and one equation per *standard* monomial (each ``s`` at most linear)
instead of one per monomial. On the moment route (:mod:`glidectl.roa.moment`) the equations set the order of the
dense factorization and the multiplier coefficients make up most of the free unknowns (its equality block ``A``),
so each iteration of a program in the quotient form is cheaper, and it reaches the same level. Which programs use
it: :attr:`~glidectl.roa.moment.MomentPolicy.quotient_min_block`; measurements on the CTOL closed loop:
``bench/README.md``.

The Gram check (:class:`~glidectl.roa.sos.GramCheck`) takes the residual modulo the ideal too, and
:meth:`AngleQuotient.lift` moves a residual on a standard monomial that no Gram entry reaches (the monomial ``c``)
onto reached ones by a multiple of an equality, as the multipliers ``psi_j`` of the other form would.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .polynomial import Exp, Poly

__all__ = ["AngleQuotient", "angle_quotient"]


@dataclass(frozen=True)
class AngleQuotient:
    """Normal forms modulo ``s_k^2 + c_k^2 - 2 c_k`` for the pairs ``(s_k, c_k)`` (variable indices).

    Attributes
    ----------
    nvars : int
        Number of polynomial variables.
    pairs : tuple of (int, int, float, float)
        ``(s, c, beta, delta)``: variable indices of each angle pair and the rule ``s^2 -> beta c^2 + delta c``
        (``beta = -1``, ``delta = 2`` in the recast's units; other values once the variables are scaled).
    equalities : tuple of Poly
        The equalities ``s_k^2 + c_k^2 - 2 c_k`` the quotient replaces.
    """

    nvars: int
    pairs: tuple[tuple[int, int, float, float], ...]
    equalities: tuple[Poly, ...]
    _memo: dict[Exp, tuple[tuple[Exp, float], ...]] = field(default_factory=dict, repr=False, compare=False)

    def monomial(self, e: Exp) -> tuple[tuple[Exp, float], ...]:
        """Normal form of the monomial ``z^e`` as ``((exponent, coefficient), ...)`` (memoized)."""
        out = self._memo.get(e)
        if out is not None:
            return out
        terms: dict[Exp, float] = {tuple(e): 1.0}
        for s, c, beta, delta in self.pairs:
            k, r = divmod(e[s], 2)
            if k == 0:
                continue
            # s^(2k + r) rest = (beta c^2 + delta c)^k s^r rest = sum_i binom(k, i) beta^i delta^(k-i) c^(k+i) s^r rest
            new: dict[Exp, float] = {}
            binom = 1
            for i in range(k + 1):
                w = binom * delta ** (k - i) * beta ** i
                for ex, v in terms.items():
                    ee = list(ex)
                    ee[s] = r
                    ee[c] = ex[c] + k + i
                    t = tuple(ee)
                    new[t] = new.get(t, 0.0) + v * w
                binom = binom * (k - i) // (i + 1)
            terms = new
        out = tuple(terms.items())
        self._memo[e] = out
        return out

    def nf(self, p: Poly) -> Poly:
        """Normal form of ``p`` (every ``s_k`` at most linear)."""
        t: dict[Exp, float] = {}
        for e, v in p.terms.items():
            for ee, w in self.monomial(e):
                t[ee] = t.get(ee, 0.0) + v * w
        return Poly._make(t, p.nvars)

    def linpoly(self, L: Any) -> Any:
        """Normal form of a :class:`~glidectl.roa.sos.LinPoly` (constant part and every column)."""
        return type(L)(self.nf(L.const), {u: [self.nf(c) for c in cols] for u, cols in L.parts.items()})

    def lift(self, res: Poly, reach: set[Exp]) -> Poly:
        """``res + sum_k phi_k h_k`` with no coefficient on a monomial outside ``reach``, or ``res`` if no such
        multipliers exist (least squares, kept only if exact to rounding).

        A residual ``res = NF(p - m' Q m)`` of the quotient form can sit on a standard monomial that no pair of the
        half basis reaches (``c``, whose multiplier form ``p + psi h = m' Q m`` balances it by ``psi(0) h``); the
        equal polynomial modulo the ideal with that residual moved onto reached monomials (``c = (s^2 + c^2) / 2``
        on the variety) is what a Gram matrix can absorb. The identity is exact: the returned polynomial equals
        ``res`` on the variety."""
        out = [e for e, v in res.terms.items() if e not in reach]
        if not out or not reach:
            return res
        # multiples m h_k of degree at most the largest reached one: the monomials they bring in that are not
        # reached become rows too (their coefficient must stay zero), a closure of bounded degree, hence finite
        top = max(sum(e) for e in reach)
        rows: dict[Exp, int] = {}
        cols: list[Poly] = []
        seen: set[tuple[int, Exp]] = set()
        todo = list(out)
        while todo:
            a = todo.pop()
            rows.setdefault(a, len(rows))
            for k, h in enumerate(self.equalities):
                for t in h.terms:
                    m = tuple(x - y for x, y in zip(a, t, strict=True))
                    if min(m) < 0 or (k, m) in seen:
                        continue
                    seen.add((k, m))
                    col = h * Poly({m: 1.0}, self.nvars)
                    if col.degree > top:
                        continue
                    cols.append(col)
                    for e in col.terms:
                        if e not in reach and e not in rows:
                            rows[e] = len(rows)
                            todo.append(e)
        if not cols:
            return res
        A = np.zeros((len(rows), len(cols)))
        for j, col in enumerate(cols):
            for e, v in col.terms.items():
                if e in rows:
                    A[rows[e], j] = v
        r = np.zeros(len(rows))
        for e, i in rows.items():
            r[i] = res.terms.get(e, 0.0)
        phi, *_ = np.linalg.lstsq(A, -r, rcond=None)
        if np.max(np.abs(A @ phi + r)) > 1e-6 * max(np.max(np.abs(r)), 1e-300):
            return res
        t = dict(res.terms)
        for w, col in zip(phi, cols, strict=True):
            for e, v in col.terms.items():
                t[e] = t.get(e, 0.0) + w * v
        return Poly._make(t, res.nvars)

    def covers(self, h: Poly) -> bool:
        """Whether ``h`` is one of the equalities this quotient replaces."""
        return any(h.terms == q.terms for q in self.equalities)


def angle_quotient(nvars: int, equalities: tuple[Poly, ...]) -> AngleQuotient | None:
    """The quotient of the angle equalities among ``equalities``: those of the form ``a s^2 + b c^2 + d c`` (``a``,
    ``b``, ``d`` nonzero; ``s^2 + c^2 - 2 c`` for the recast, scaled variables otherwise) in two variables that no
    other such equality uses, or None if there is none."""
    pairs: list[tuple[int, int, float, float]] = []
    eqs: list[Poly] = []
    used: set[int] = set()
    for h in equalities:
        if len(h.terms) != 3 or any(sum(e) not in (1, 2) or max(e) != sum(e) for e in h.terms):
            continue        # three pure powers of degree 1 or 2
        sq = {next(i for i in range(nvars) if e[i]): v for e, v in h.terms.items() if sum(e) == 2}
        lin = {next(i for i in range(nvars) if e[i]): v for e, v in h.terms.items() if sum(e) == 1}
        if len(sq) != 2 or len(lin) != 1:
            continue
        (c, d), = lin.items()
        if c not in sq:
            continue
        s = next(i for i in sq if i != c)
        if s in used or c in used:
            continue
        pairs.append((s, c, -sq[c] / sq[s], -d / sq[s]))
        eqs.append(h)
        used |= {s, c}
    if not pairs:
        return None
    return AngleQuotient(nvars, tuple(pairs), tuple(eqs))
