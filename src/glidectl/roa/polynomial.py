"""Sparse multivariate polynomials with real coefficients, the only algebra the SOS layer needs.

A :class:`Poly` is a mapping ``exponent tuple -> coefficient`` in ``n`` variables. It supports ``+``, ``-``,
``*`` (by polynomials and scalars), powers, partial derivatives, the Lie derivative along a polynomial vector
field, vectorized evaluation (real or complex arguments, so complex-step derivatives of certificates are exact)
and substitution of polynomials for variables. Monomial bases come from :func:`monomials`.

Nothing here is specific to gliders; :mod:`glidectl.roa.sos` builds SOS programs on top of it.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import GlidectlError

__all__ = ["Poly", "monomial_matrix", "monomials"]

Exp = tuple[int, ...]


class Poly:
    """Polynomial ``sum_k c_k z^{e_k}`` in ``nvars`` variables (immutable by convention).

    Parameters
    ----------
    terms : mapping exponent tuple -> float
        Coefficients; zero coefficients are dropped.
    nvars : int
        Number of variables.
    """

    __slots__ = ("nvars", "terms")

    def __init__(self, terms: Mapping[Exp, float], nvars: int) -> None:
        self.nvars = int(nvars)
        clean: dict[Exp, float] = {}
        for e, c in terms.items():
            if len(e) != self.nvars:
                raise GlidectlError(f"exponent {e} has {len(e)} entries, the polynomial has {nvars} variables")
            if c != 0.0:
                clean[tuple(int(k) for k in e)] = float(c)
        self.terms = clean

    # ------------------------------------------------------------------ constructors
    @classmethod
    def const(cls, c: float, nvars: int) -> Poly:
        return cls({(0,) * nvars: float(c)}, nvars)

    @classmethod
    def var(cls, i: int, nvars: int) -> Poly:
        e = [0] * nvars
        e[i] = 1
        return cls({tuple(e): 1.0}, nvars)

    @classmethod
    def variables(cls, nvars: int) -> list[Poly]:
        return [cls.var(i, nvars) for i in range(nvars)]

    # ------------------------------------------------------------------ arithmetic
    def _coerce(self, other: Any) -> Poly:
        if isinstance(other, Poly):
            if other.nvars != self.nvars:
                raise GlidectlError(f"polynomials in {self.nvars} and {other.nvars} variables cannot be combined")
            return other
        return Poly.const(float(other), self.nvars)

    def __add__(self, other: Any) -> Poly:
        o = self._coerce(other)
        t = dict(self.terms)
        for e, c in o.terms.items():
            t[e] = t.get(e, 0.0) + c
        return Poly(t, self.nvars)

    __radd__ = __add__

    def __neg__(self) -> Poly:
        return Poly({e: -c for e, c in self.terms.items()}, self.nvars)

    def __sub__(self, other: Any) -> Poly:
        return self + (-self._coerce(other))

    def __rsub__(self, other: Any) -> Poly:
        return self._coerce(other) - self

    def __mul__(self, other: Any) -> Poly:
        if not isinstance(other, Poly):
            s = float(other)
            return Poly({e: s * c for e, c in self.terms.items()}, self.nvars)
        o = self._coerce(other)
        t: dict[Exp, float] = {}
        for e1, c1 in self.terms.items():
            for e2, c2 in o.terms.items():
                e = tuple(a + b for a, b in zip(e1, e2, strict=True))
                t[e] = t.get(e, 0.0) + c1 * c2
        return Poly(t, self.nvars)

    __rmul__ = __mul__

    def __truediv__(self, s: float) -> Poly:
        return self * (1.0 / float(s))

    def __pow__(self, k: int) -> Poly:
        if int(k) != k or k < 0:
            raise GlidectlError(f"polynomial powers must be non-negative integers, got {k}")
        out = Poly.const(1.0, self.nvars)
        for _ in range(int(k)):
            out = out * self
        return out

    # ------------------------------------------------------------------ queries
    @property
    def degree(self) -> int:
        return max((sum(e) for e in self.terms), default=0)

    @property
    def is_zero(self) -> bool:
        return not self.terms

    def max_abs_coefficient(self) -> float:
        return max((abs(c) for c in self.terms.values()), default=0.0)

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """``(exponents (m, n) int, coefficients (m,))``."""
        if not self.terms:
            return np.zeros((0, self.nvars), dtype=int), np.zeros(0)
        return np.array(list(self.terms.keys()), dtype=int), np.array(list(self.terms.values()))

    def __call__(self, Z: Any) -> Any:
        """Evaluate at ``Z`` of shape ``(..., nvars)`` (real or complex)."""
        Z = np.asarray(Z)
        if Z.shape[-1] != self.nvars:
            raise GlidectlError(f"polynomial in {self.nvars} variables evaluated at points of dimension "
                                f"{Z.shape[-1]}")
        exps, coef = self.arrays()
        if exps.shape[0] == 0:
            return np.zeros(Z.shape[:-1], dtype=Z.dtype if np.iscomplexobj(Z) else float)
        dmax = int(exps.max(initial=0))
        # powers table (..., nvars, dmax + 1)
        pw = np.ones((*Z.shape, dmax + 1), dtype=np.result_type(Z, float))
        for k in range(1, dmax + 1):
            pw[..., k] = pw[..., k - 1] * Z
        out = np.zeros(Z.shape[:-1], dtype=pw.dtype)
        for e, c in zip(exps, coef, strict=True):
            term = c
            for i in np.flatnonzero(e):
                term = term * pw[..., i, e[i]]
            out = out + term
        return out

    def diff(self, i: int) -> Poly:
        """``d/dz_i``."""
        t: dict[Exp, float] = {}
        for e, c in self.terms.items():
            if e[i] > 0:
                e2 = list(e)
                e2[i] -= 1
                t[tuple(e2)] = t.get(tuple(e2), 0.0) + c * e[i]
        return Poly(t, self.nvars)

    def lie(self, F: Sequence[Poly]) -> Poly:
        """Lie derivative ``grad(self) . F`` along the polynomial vector field ``F``."""
        out = Poly({}, self.nvars)
        for i, Fi in enumerate(F):
            d = self.diff(i)
            if not d.is_zero:
                out = out + d * Fi
        return out

    def substitute(self, polys: Sequence[Poly]) -> Poly:
        """``self(p_1(y), ..., p_n(y))`` for polynomials ``p_i`` in a common set of variables."""
        if len(polys) != self.nvars:
            raise GlidectlError(f"substitute needs {self.nvars} polynomials, got {len(polys)}")
        m = polys[0].nvars
        out = Poly({}, m)
        cache: dict[tuple[int, int], Poly] = {}
        for e, c in self.terms.items():
            term = Poly.const(c, m)
            for i, k in enumerate(e):
                if k:
                    if (i, k) not in cache:
                        cache[(i, k)] = polys[i] ** k
                    term = term * cache[(i, k)]
            out = out + term
        return out

    def __repr__(self) -> str:
        if not self.terms:
            return "Poly(0)"
        parts = []
        for e, c in sorted(self.terms.items(), key=lambda t: (sum(t[0]), t[0])):
            mono = "*".join(f"z{i}" + (f"^{k}" if k > 1 else "") for i, k in enumerate(e) if k)
            parts.append(f"{c:+.6g}" + (f"*{mono}" if mono else ""))
        return "Poly(" + " ".join(parts) + ")"


def monomials(nvars: int, max_degree: int, min_degree: int = 0,
              max_exponent: Mapping[int, int] | None = None) -> list[Exp]:
    """All exponents of total degree in ``[min_degree, max_degree]``, graded order.

    ``max_exponent`` caps single variables (e.g. ``{1: 1}`` keeps ``s`` of an angle pair ``(s, c)`` linear, a basis
    of polynomials modulo ``s^2 + c^2 - 2c``).
    """
    cap = dict(max_exponent or {})
    out: list[Exp] = []
    for d in range(min_degree, max_degree + 1):
        for combo in itertools.combinations_with_replacement(range(nvars), d):
            e = [0] * nvars
            for i in combo:
                e[i] += 1
            if all(e[i] <= k for i, k in cap.items()):
                out.append(tuple(e))
    return out


def monomial_matrix(Z: Any, basis: Sequence[Exp]) -> np.ndarray:
    """``M[k, j] = z_k^{basis_j}`` for points ``Z`` (N, nvars): the design matrix of a polynomial fit, or the linear
    map from coefficients on ``basis`` to values at ``Z``."""
    Z = np.asarray(Z, dtype=float)
    E = np.asarray(list(basis), dtype=int).reshape(len(basis), Z.shape[-1])
    return np.prod(Z[:, None, :] ** E[None, :, :], axis=2)
