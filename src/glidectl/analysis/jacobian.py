"""Exact Jacobians of glidectl vector fields by the complex-step method.

For an analytic ``f``, ``df/dx_j = Im f(x + i h e_j) / h + O(h^2)`` with no subtractive cancellation, so with
``h = 1e-30`` the result is exact to machine precision. All perturbations are evaluated in one batched call.

A function that is not complex-safe (it drops the imaginary part, e.g. through ``float()`` or ``np.real``) would give
a zero derivative without a word; :func:`jacobians` and :func:`hessian` refuse it (:class:`~glidectl.ModelError`) when
it returns a real array for complex input, and refuse non-finite derivatives (the point is outside the function's
domain, or the derivative overflows). Exceptions raised by ``f`` itself pass through unchanged.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..checks import array, function, positive
from ..errors import ArgumentError, ModelError

__all__ = ["central_difference_jacobians", "hessian", "jacobians"]

_H = 1e-30


def _point(name: str, value: Any, *, min_size: int = 0) -> np.ndarray:
    return array(name, value, ndim=1, min_size=min_size)


def _derivative(what: str, value: Any, rows: int, h: float) -> np.ndarray:
    """``Im(value) / h`` for the batch of ``rows`` perturbed evaluations, checked (complex-safe, shape, finite)."""
    out = np.asarray(value)
    if out.dtype.kind != "c":
        raise ModelError(f"{what} returned a {out.dtype} array for complex input: it is not complex-safe (it drops "
                         "the imaginary part), so the complex-step derivative would be zero; write it with numpy "
                         "operations that keep complex values (a constant field: return 0 * x + c)")
    if out.ndim == 0 or out.shape[0] != rows:
        raise ArgumentError(f"{what} must return one row per point of the batch ({rows} rows), got shape {out.shape}")
    d = np.imag(out) / h
    if not np.all(np.isfinite(d)) or not np.all(np.isfinite(np.real(out))):
        raise ModelError(f"{what} is not finite (or its derivative overflows) at this point: the point is outside "
                         "the function's domain")
    return d


def jacobians(f: Callable[[Any, Any], Any], x: Any, u: Any) -> tuple[np.ndarray, np.ndarray]:
    """``A = df/dx`` and ``B = df/du`` at ``(x, u)`` by complex step (exact to rounding).

    Parameters
    ----------
    f : callable
        ``f(x, u) -> xdot``, batch-capable over leading dimensions and analytic (complex-safe).
    x : array_like, shape (n,)
        State at which to differentiate (units of the model's states), finite, ``n >= 1``.
    u : array_like, shape (m,)
        Input at which to differentiate (units of the model's inputs; ``m = 0`` for input-free models), finite.

    Returns
    -------
    A : ndarray, shape (p, n)
        ``df/dx`` (units of ``xdot`` per unit of ``x``; 1/s for states and rates in consistent units); ``p = n`` for
        a vector field.
    B : ndarray, shape (p, m)
        ``df/du`` (units of ``xdot`` per unit of ``u``).

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, or ``x``/``u`` are not arrays of real numbers.
    ArgumentError
        If ``x`` or ``u`` is not one-dimensional or not finite, ``x`` is empty, or ``f`` does not return one row per
        point of the batch.
    ModelError
        If ``f`` is not complex-safe (returns a real array for complex input, which would make the derivative
        silently zero), or its value or derivative is not finite at ``(x, u)``.
    Exception
        Whatever ``f`` raises on the complex batch passes through unchanged.
    """
    function("f", f)
    x = _point("x", x, min_size=1)
    u = _point("u", u)
    n, m = x.size, u.size
    X = np.broadcast_to(x, (n + m, n)).astype(complex)
    U = np.broadcast_to(u, (n + m, m)).astype(complex)
    X[np.arange(n), np.arange(n)] += 1j * _H
    U[n + np.arange(m), np.arange(m)] += 1j * _H
    d = _derivative("f(x, u)", f(X, U), n + m, _H)
    if d.ndim != 2:
        raise ArgumentError(f"f(x, u) must return a vector per point (shape ({n + m}, p) for the batch), got shape "
                            f"{d.shape}")
    return d[:n].T.copy(), d[n:].T.copy()


def central_difference_jacobians(f: Callable[[Any, Any], Any], x: Any, u: Any,
                                 h: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """Central-difference Jacobians (for checking :func:`jacobians`; error O(h^2), cancellation O(eps/h)).

    Parameters
    ----------
    f : callable
        ``f(x, u) -> xdot`` for one point (real arithmetic suffices).
    x : array_like, shape (n,)
        State (model units), finite, ``n >= 1``.
    u : array_like, shape (m,)
        Input (model units), finite; may be empty.
    h : float
        Relative step, ``> 0``: component ``j`` is perturbed by ``h max(1, |x_j|)``.

    Returns
    -------
    A : ndarray, shape (n, n)
        ``df/dx``.
    B : ndarray, shape (n, m)
        ``df/du``.

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, ``x``/``u`` are not real arrays or ``h`` is not a real number.
    ArgumentError
        If ``x`` or ``u`` is not one-dimensional or not finite, ``h <= 0``, or ``f`` returns a value of the wrong
        shape.
    ModelError
        If a difference quotient is not finite (``f`` not finite near ``(x, u)``).
    Exception
        Whatever ``f`` raises passes through unchanged.
    """
    function("f", f)
    x = _point("x", x, min_size=1)
    u = _point("u", u)
    h = positive("h", h)
    n, m = x.size, u.size
    A = np.empty((n, n))
    B = np.empty((n, m))

    def val(xx: np.ndarray, uu: np.ndarray) -> np.ndarray:
        out = np.asarray(f(xx, uu), dtype=float)
        if out.shape != (n,):
            raise ArgumentError(f"f(x, u) must return shape ({n},) for one point, got {out.shape}")
        return out

    for j in range(n):
        e = np.zeros(n)
        e[j] = h * max(1.0, abs(x[j]))
        A[:, j] = (val(x + e, u) - val(x - e, u)) / (2 * e[j])
    for j in range(m):
        e = np.zeros(m)
        e[j] = h * max(1.0, abs(u[j]))
        B[:, j] = (val(x, u + e) - val(x, u - e)) / (2 * e[j])
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B))):
        raise ModelError("central differences of f are not finite near this point (outside f's domain)")
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
        Point at which the Hessian is taken (units of ``fun``'s argument), finite, ``n >= 1``.
    h : float
        Central-difference step of the gradient (same units as ``x``), ``> 0``.

    Returns
    -------
    numpy.ndarray, shape (n, n)
        The symmetrized Hessian ``d^2 fun / dx_i dx_j`` (units of ``fun`` per unit of ``x_i x_j``).

    Raises
    ------
    ArgumentTypeError
        If ``fun`` is not callable, ``x`` is not a real array or ``h`` not a real number.
    ArgumentError
        If ``x`` is not one-dimensional or not finite, ``h <= 0``, or ``fun`` does not return one value per row of
        the batch.
    ModelError
        If ``fun`` is not complex-safe or its value or gradient is not finite near ``x``.
    Exception
        Whatever ``fun`` raises passes through unchanged.
    """
    function("fun", fun)
    x = _point("x", x, min_size=1)
    h = positive("h", h)
    n = x.size

    def grad(y: np.ndarray) -> np.ndarray:
        Y = np.broadcast_to(y, (n, n)).astype(complex)
        Y[np.arange(n), np.arange(n)] += 1j * _H
        g = _derivative("fun(X)", fun(Y), n, _H)
        if g.shape != (n,):
            raise ArgumentError(f"fun(X) must return one value per row of the batch, shape ({n},), got {g.shape}")
        return g

    H = np.stack([(grad(x + h * e) - grad(x - h * e)) / (2 * h) for e in np.eye(n)], axis=1)
    if not np.all(np.isfinite(H)):
        raise ModelError("the Hessian is not finite at this point (the gradient overflows)")
    return 0.5 * (H + H.T)
