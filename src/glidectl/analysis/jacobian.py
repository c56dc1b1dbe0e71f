"""Exact Jacobians of glidectl vector fields by the complex-step method.

For an analytic ``f``, ``df/dx_j = Im f(x + i h e_j) / h + O(h^2)`` with no subtractive cancellation, so with
``h = 1e-30`` the result is exact to machine precision. All perturbations are evaluated in one batched call.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["central_difference_jacobians", "hessian", "jacobians"]

_H = 1e-30


def jacobians(f: Callable[[Any, Any], Any], x: Any, u: Any) -> tuple[np.ndarray, np.ndarray]:
    """``A = df/dx`` and ``B = df/du`` at ``(x, u)`` by complex step (exact to rounding).

    Parameters
    ----------
    f : callable
        ``f(x, u) -> xdot``, batch-capable over leading dimensions and analytic (complex-safe).
    x : array_like, shape (n,)
        State at which to differentiate (units of the model's states).
    u : array_like, shape (m,)
        Input at which to differentiate (units of the model's inputs; ``m = 0`` for input-free models).

    Returns
    -------
    A : ndarray, shape (n, n)
        ``df/dx`` (units of ``xdot`` per unit of ``x``; 1/s for states and rates in consistent units).
    B : ndarray, shape (n, m)
        ``df/du`` (units of ``xdot`` per unit of ``u``).

    Raises
    ------
    ValueError
        If ``x`` or ``u`` is not one-dimensional (the perturbation batch cannot be formed) or is not numeric.
    Exception
        Whatever ``f`` raises on the complex batch; a ``f`` that is not complex-safe may instead return a wrong
        (zero) derivative, which is not detected.
    """
    x = np.asarray(x, dtype=float)
    u = np.asarray(u, dtype=float)
    n, m = x.size, u.size
    X = np.broadcast_to(x, (n + m, n)).astype(complex)
    U = np.broadcast_to(u, (n + m, m)).astype(complex)
    X[np.arange(n), np.arange(n)] += 1j * _H
    U[n + np.arange(m), np.arange(m)] += 1j * _H
    d = np.imag(np.asarray(f(X, U))) / _H
    return d[:n].T.copy(), d[n:].T.copy()


def central_difference_jacobians(f: Callable[[Any, Any], Any], x: Any, u: Any,
                                 h: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Central-difference Jacobians (for checking :func:`jacobians`; error O(h^2))."""
    x = np.asarray(x, dtype=float)
    u = np.asarray(u, dtype=float)
    n, m = x.size, u.size
    A = np.empty((n, n))
    B = np.empty((n, m))
    for j in range(n):
        e = np.zeros(n)
        e[j] = h * max(1.0, abs(x[j]))
        A[:, j] = (np.asarray(f(x + e, u)) - np.asarray(f(x - e, u))) / (2 * e[j])
    for j in range(m):
        e = np.zeros(m)
        e[j] = h * max(1.0, abs(u[j]))
        B[:, j] = (np.asarray(f(x, u + e)) - np.asarray(f(x, u - e))) / (2 * e[j])
    return A, B


def hessian(fun: Callable[[Any], Any], x: Any, h: float = 1e-5) -> np.ndarray:
    """Hessian of a scalar, batch-capable, complex-safe ``fun`` at ``x``: central differences (step ``h``) of the
    exact complex-step gradient, so the error is ``O(h^2)`` with no ``eps/h^2`` cancellation.

    Parameters
    ----------
    fun : callable
        ``fun(X) -> values``: a scalar function evaluated on a batch ``X`` of shape ``(n, n)`` (one point per row),
        returning shape ``(n,)``; must be analytic (complex-safe).
    x : array_like, shape (n,)
        Point at which the Hessian is taken (units of ``fun``'s argument).
    h : float
        Central-difference step of the gradient (same units as ``x``).

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetrized Hessian ``d^2 fun / dx_i dx_j`` (units of ``fun`` per unit of ``x_i x_j``).

    Raises
    ------
    ValueError
        If ``x`` is not one-dimensional or ``fun`` does not return one value per row of the batch.
    """
    x = np.asarray(x, dtype=float)
    n = x.size

    def grad(y: np.ndarray) -> np.ndarray:
        Y = np.broadcast_to(y, (n, n)).astype(complex)
        Y[np.arange(n), np.arange(n)] += 1j * _H
        return np.imag(np.asarray(fun(Y))) / _H

    H = np.stack([(grad(x + h * e) - grad(x - h * e)) / (2 * h) for e in np.eye(n)], axis=1)
    return 0.5 * (H + H.T)
