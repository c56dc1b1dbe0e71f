"""Exact derivatives of glidectl functions by the complex-step method: one module for every layer that differentiates.

For a function ``f`` that is analytic (real on real arguments, written with numpy operations that keep complex
values), ``f(x + i h v) = f(x) + i h Df(x)[v] - h^2 D^2f(x)[v, v] / 2 + O(h^3)``, so

    ``Df(x)[v] = Im f(x + i h v) / h + O(h^2)``.

No difference of two nearby values is taken, so there is no subtractive cancellation and ``h`` can be tiny: with
``h = 1e-30`` (:data:`COMPLEX_STEP`) the truncation error ``h^2`` is far below the rounding of ``f`` and the result is
exact to machine precision. The real part, ``f(x) + O(h^2)``, is the value itself. Every primitive here evaluates all
its perturbed points in one call of ``f`` (``f`` is batch-capable over leading dimensions), so a Jacobian of ``n``
columns costs one vectorized call, not ``n``.

The module sits at the foundation beside :mod:`glidectl.checks` and :mod:`glidectl.errors` (it imports nothing else of
glidectl), so models, hydrodynamics and trims can differentiate without importing :mod:`glidectl.analysis`.

Checked single-point Jacobians and Hessians:

- :func:`jacobians` -- ``A = df/dx``, ``B = df/du`` of a vector field at one point;
- :func:`hessian` -- Hessian of a scalar function (central differences of its exact gradient);
- :func:`central_difference_jacobians` -- the reference the complex-step Jacobians are tested against.

They refuse a function that is not complex-safe (it returns a real array for complex input, e.g. through ``float()``
or ``np.real``, which would make the derivative silently zero) and non-finite derivatives (the point is outside the
function's domain, or the derivative overflows), with :class:`~glidectl.ModelError`.

Batched primitives for code that differentiates many points at once (controllers, certificates, batch
integration):

- :func:`complex_step` -- directional derivatives ``Im f(X + i h D) / h`` at many points along given directions;
- :func:`partial_derivative` -- the derivative along one coordinate at many points;
- :func:`jacobian_batch` -- the Jacobian (or gradient) of ``f`` at each row of ``X``;
- :func:`jacobians_batch` -- ``A`` and ``B`` of ``f(x, u)`` at each point of a batch;
- :func:`second_directional_derivative` -- ``D^2 f(x)[v, v]`` by the ``e^{i pi/4}`` complex step.

They refuse a function that is not complex-safe too, but pass non-finite values through (a point outside ``f``'s
domain gives NaN in its own rows, the others are unaffected), so callers that sample many points decide what a
non-finite row means. Each builds its perturbed batch in one fixed memory layout (documented per function) and
divides by ``h`` last, so a caller that switches to it from the same hand-written arithmetic gets results equal to
the last bit.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .checks import array, function, integer, positive
from .errors import ArgumentError, ArgumentTypeError, ModelError

__all__ = [
    "COMPLEX_STEP",
    "central_difference_jacobians",
    "complex_step",
    "hessian",
    "jacobian_batch",
    "jacobians",
    "jacobians_batch",
    "partial_derivative",
    "second_directional_derivative",
]

#: Default complex step ``h``: the relative truncation error ``O(h^2)`` is far below double rounding, and the
#: imaginary part ``h * Df`` stays a normal double (no lost digits) for every derivative ``|Df|`` above about 1e-277.
COMPLEX_STEP = 1e-30

_H = COMPLEX_STEP
_E8 = cmath.exp(0.25j * math.pi)  # e^{i pi/4}: (e^{i pi/4})^2 = i puts the second derivative in the imaginary part
_ADVICE = "write it with numpy operations that keep complex values (a constant field: return 0 * x + c)"


# ------------------------------------------------------------------------------------------------ shared checks
def _point(name: str, value: Any, *, min_size: int = 0) -> np.ndarray:
    return array(name, value, ndim=1, min_size=min_size)


def _real(name: str, value: Any) -> np.ndarray:
    """``np.asarray(value)`` (the same object for an ndarray, so the caller's arithmetic is unchanged), refusing
    complex, boolean and non-numeric arrays: a complex base point would mix its own imaginary part into the
    derivative."""
    out = np.asarray(value)
    if out.dtype.kind not in "iuf":
        raise ArgumentTypeError(f"{name} must be a real array (the base point of a complex step), got dtype "
                                f"{out.dtype}")
    return out


def _complex_output(name: str, value: Any, advice: str) -> np.ndarray:
    """``np.asarray(value)``, refused (:class:`ModelError`) unless complex: a real result for complex input means
    ``f`` dropped the imaginary part, and its complex-step derivative would be zero without a word."""
    out = np.asarray(value)
    if out.dtype.kind != "c":
        raise ModelError(f"{name} returned a {out.dtype} array for complex input: it is not complex-safe (it drops "
                         f"the imaginary part), so the complex-step derivative would be zero; {advice}")
    return out


def _derivative(what: str, value: Any, rows: int, h: float) -> np.ndarray:
    """``Im(value) / h`` for the batch of ``rows`` perturbed evaluations, checked (complex-safe, shape, finite)."""
    out = _complex_output(what, value, _ADVICE)
    if out.ndim == 0 or out.shape[0] != rows:
        raise ArgumentError(f"{what} must return one row per point of the batch ({rows} rows), got shape {out.shape}")
    d = np.imag(out) / h
    if not np.all(np.isfinite(d)) or not np.all(np.isfinite(np.real(out))):
        raise ModelError(f"{what} is not finite (or its derivative overflows) at this point: the point is outside "
                         "the function's domain")
    return d


# ----------------------------------------------------------------------------------------- batched primitives
def complex_step(f: Callable[[np.ndarray], Any], X: Any, directions: Any, h: float = COMPLEX_STEP, *,
                 value: bool = False, name: str = "f",
                 advice: str = _ADVICE) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """Directional derivatives ``Df(X)[D] = Im f(X + i h D) / h`` at many points in one call of ``f``.

    The perturbed batch is ``X + 1j * h * directions`` (numpy broadcasting, a new C-ordered array), so one call
    gives the derivative at every point along its own direction, or, with ``X[..., None, :]`` and
    ``np.eye(n)``, every column of every Jacobian. The result is exact to rounding because no two values of ``f``
    are subtracted (see the module docstring).

    Parameters
    ----------
    f : callable
        ``f(Z) -> values``, batch-capable over the leading dimensions of ``Z`` and complex-safe (analytic).
    X : array_like
        Base points (real; units of ``f``'s argument), broadcast against ``directions``.
    directions : array_like
        Directions ``D`` (real; units of ``X``), broadcast against ``X``; a scalar ``1.0`` differentiates a scalar
        function of a scalar argument.
    h : float
        Complex step, ``> 0`` (default :data:`COMPLEX_STEP`, 1e-30). Any ``h`` below about ``1e-20 / |D|`` gives
        the derivative to rounding; a larger ``h`` adds a truncation error ``O(h^2)``.
    value : bool
        Also return ``Re f(X + i h D) = f(X) + O(h^2)`` (the value, to rounding for the default ``h``), e.g. for a
        Newton step, without a second call.
    name : str
        How the error message names ``f``.
    advice : str
        What the error message tells the user to do when ``f`` is not complex-safe.

    Returns
    -------
    numpy.ndarray
        ``Df(X)[D]``, the shape of ``f``'s output (units of ``f`` per unit of ``D``).
    tuple of numpy.ndarray
        ``(f(X), Df(X)[D])`` when ``value`` is true.

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, ``X`` or ``directions`` is not a real array, or ``h`` not a real number.
    ArgumentError
        If ``h <= 0`` or not finite.
    ModelError
        If ``f`` returns a real array for complex input (not complex-safe: the derivative would be zero).
    Exception
        Whatever ``f`` raises passes through unchanged (also a ``ValueError`` if ``X`` and ``directions`` do not
        broadcast).
    """
    function("f", f)
    h = positive("h", h)
    X = _real("X", X)
    D = _real("directions", directions)
    out = _complex_output(name, f(X + 1j * h * D), advice)
    d = np.imag(out) / h
    return (np.real(out), d) if value else d


def partial_derivative(f: Callable[[np.ndarray], Any], X: Any, j: int, h: float = COMPLEX_STEP, *,
                       value: bool = False, name: str = "f",
                       advice: str = _ADVICE) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """``df/dx_j`` at every point of a batch, in one call of ``f``: ``Im f(X + i h e_j) / h``.

    The perturbed batch is a complex copy of ``X`` (``X.astype(complex)``, same memory order) whose column ``j``
    gets ``+ 1j * h``; the other columns are ``X`` unchanged. Use it for one coordinate of many points (a column of
    a batched gradient); :func:`jacobian_batch` gives all of them.

    Parameters
    ----------
    f : callable
        ``f(Z) -> values`` for ``Z`` of the shape of ``X``, batch-capable and complex-safe (analytic).
    X : array_like, shape (..., n)
        Points (real; units of ``f``'s argument), one per row.
    j : int
        Coordinate to differentiate along, ``0 <= j < n``.
    h : float
        Complex step, ``> 0`` (default :data:`COMPLEX_STEP`; exact to rounding for any ``h`` below about 1e-20).
    value : bool
        Also return ``Re f(...) = f(X)`` (to rounding).
    name : str
        How the error message names ``f``.
    advice : str
        What the error message tells the user to do when ``f`` is not complex-safe.

    Returns
    -------
    numpy.ndarray
        ``df/dx_j`` at each point, the shape of ``f``'s output (units of ``f`` per unit of ``x_j``).
    tuple of numpy.ndarray
        ``(f(X), df/dx_j)`` when ``value`` is true.

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, ``X`` is not a real array, or ``j`` or ``h`` is not a number of the right type.
    ArgumentError
        If ``X`` has no trailing dimension, ``j`` is not in ``[0, n)``, or ``h <= 0``.
    ModelError
        If ``f`` returns a real array for complex input (not complex-safe).
    Exception
        Whatever ``f`` raises passes through unchanged.
    """
    function("f", f)
    h = positive("h", h)
    X = _real("X", X)
    if X.ndim == 0:
        raise ArgumentError("X must have a trailing dimension of coordinates (shape (..., n)), got a scalar")
    j = integer("j", j, lo=0, hi=X.shape[-1] - 1)
    Z = X.astype(complex)
    Z[..., j] += 1j * h
    out = _complex_output(name, f(Z), advice)
    d = np.imag(out) / h
    return (np.real(out), d) if value else d


def jacobian_batch(f: Callable[[np.ndarray], Any], X: Any, h: float = COMPLEX_STEP, *, name: str = "f",
                   advice: str = _ADVICE) -> np.ndarray:
    """Jacobian of ``f`` at each row of ``X`` (the gradient for a scalar ``f``), all columns in one call of ``f``.

    ``f`` is called once on ``Z = X[..., None, :] + 1j * h * np.eye(n)`` (shape ``(..., n, n)``, C order: row
    ``j`` of point ``k`` is ``x_k + i h e_j``), so it must accept one more leading dimension than ``X`` has.

    Parameters
    ----------
    f : callable
        ``f(Z[..., n]) -> [..., p]`` (a vector function) or ``-> [...]`` (a scalar function), batch-capable over
        leading dimensions and complex-safe (analytic).
    X : array_like, shape (..., n)
        Points (real; units of ``f``'s argument), ``n >= 1``.
    h : float
        Complex step, ``> 0`` (default :data:`COMPLEX_STEP`; exact to rounding for any ``h`` below about 1e-20).
    name : str
        How the error message names ``f``.
    advice : str
        What the error message tells the user to do when ``f`` is not complex-safe.

    Returns
    -------
    numpy.ndarray, shape (..., p, n) or (..., n)
        ``J[..., i, j] = d f_i / d x_j`` for a vector ``f`` (a transposed view of the ``(..., n, p)`` derivative
        rows), or the gradient ``d f / d x_j`` for a scalar ``f`` (units of ``f`` per unit of ``x_j``).

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, ``X`` is not a real array or ``h`` not a real number.
    ArgumentError
        If ``X`` has no trailing dimension or it is empty, ``h <= 0``, or ``f`` returns neither one vector nor one
        value per perturbed point.
    ModelError
        If ``f`` returns a real array for complex input (not complex-safe).
    Exception
        Whatever ``f`` raises passes through unchanged.
    """
    function("f", f)
    h = positive("h", h)
    X = _real("X", X)
    if X.ndim == 0 or X.shape[-1] == 0:
        raise ArgumentError(f"X must have a nonempty trailing dimension (shape (..., n), n >= 1), got {X.shape}")
    n = X.shape[-1]
    Z = X[..., None, :] + 1j * h * np.eye(n)
    out = _complex_output(name, f(Z), advice)
    d = np.imag(out) / h
    if out.shape == Z.shape[:-1]:
        return d
    if out.ndim != Z.ndim or out.shape[:-1] != Z.shape[:-1]:
        raise ArgumentError(f"{name} must return one value or one vector per point of the batch of shape {Z.shape} "
                            f"(shape {Z.shape[:-1]} or {(*Z.shape[:-1], 'p')}), got {out.shape}")
    return np.swapaxes(d, -1, -2)


def jacobians_batch(f: Callable[[np.ndarray, np.ndarray], Any], X: Any, U: Any, h: float = COMPLEX_STEP, *,
                    name: str = "f(x, u)", advice: str = _ADVICE) -> tuple[np.ndarray, np.ndarray]:
    """``A = df/dx`` and ``B = df/du`` at every point ``(x_k, u_k)`` of a batch, in one call of ``f``: the batched
    :func:`jacobians`, without its finiteness checks.

    ``f`` is called once on ``(Xc, Uc)`` of shapes ``(..., n + m, n)`` and ``(..., n + m, m)`` (C order): row
    ``j < n`` of point ``k`` is ``(x_k + i h e_j, u_k)``, row ``n + j`` is ``(x_k, u_k + i h e_j)``.

    Parameters
    ----------
    f : callable
        ``f(x, u) -> xdot``, batch-capable over leading dimensions and complex-safe (analytic); extra arguments
        (time) go in a closure.
    X : array_like, shape (..., n)
        States (real; model units), ``n >= 1``.
    U : array_like, shape (..., m)
        Inputs (real; model units), the same leading shape as ``X``; ``m`` may be 0.
    h : float
        Complex step, ``> 0`` (default :data:`COMPLEX_STEP`; exact to rounding for any ``h`` below about 1e-20).
    name : str
        How the error message names ``f``.
    advice : str
        What the error message tells the user to do when ``f`` is not complex-safe.

    Returns
    -------
    A : numpy.ndarray, shape (..., p, n)
        ``df/dx`` at each point (units of ``f`` per unit of ``x``).
    B : numpy.ndarray, shape (..., p, m)
        ``df/du`` at each point (units of ``f`` per unit of ``u``).

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, ``X`` or ``U`` is not a real array or ``h`` not a real number.
    ArgumentError
        If ``X`` or ``U`` has no trailing dimension, ``X``'s is empty, their leading shapes differ, ``h <= 0``, or
        ``f`` does not return one vector per perturbed point.
    ModelError
        If ``f`` returns a real array for complex input (not complex-safe).
    Exception
        Whatever ``f`` raises passes through unchanged.
    """
    function("f", f)
    h = positive("h", h)
    X = _real("X", X)
    U = _real("U", U)
    if X.ndim == 0 or U.ndim == 0 or X.shape[-1] == 0 or X.shape[:-1] != U.shape[:-1]:
        raise ArgumentError(f"X and U must have shapes (..., n) and (..., m) with the same leading shape and "
                            f"n >= 1, got {X.shape} and {U.shape}")
    n, m = X.shape[-1], U.shape[-1]
    Xc = np.repeat(X[..., None, :], n + m, axis=-2).astype(complex)
    Uc = np.repeat(U[..., None, :], n + m, axis=-2).astype(complex)
    Xc[..., np.arange(n), np.arange(n)] += 1j * h
    Uc[..., n + np.arange(m), np.arange(m)] += 1j * h
    out = _complex_output(name, f(Xc, Uc), advice)
    if out.ndim != Xc.ndim or out.shape[:-1] != Xc.shape[:-1]:
        raise ArgumentError(f"{name} must return one vector per point of the batch (shape {(*Xc.shape[:-1], 'p')}), "
                            f"got {out.shape}")
    J = np.swapaxes(np.imag(out) / h, -1, -2)
    return J[..., :n].copy(), J[..., n:].copy()


def second_directional_derivative(f: Callable[[np.ndarray], Any], X: Any, V: Any, h: float, *, name: str = "f",
                                  advice: str = _ADVICE) -> np.ndarray:
    """``D^2 f(X)[V, V]`` by the ``e^{i pi/4}`` complex step: ``Im(f(X + h w V) + f(X - h w V)) / h^2``,
    ``w = e^{i pi/4}``.

    With ``w^2 = i`` and ``w^4 = -1`` the Taylor series gives ``f(X + h w V) + f(X - h w V) = 2 f + i h^2 D^2f[V, V]
    - h^4 D^4f[V, V, V, V] / 12 + O(h^6)``: the imaginary part holds the second derivative with a truncation error
    ``O(h^4)``, and the value ``2 f`` (real) does not cancel against it. Unlike the first derivative the step is not
    free: the first-order terms ``+-h w Df[V]`` cancel in the sum, which costs a relative rounding error about
    ``eps |Df[V]| / (h |D^2f[V, V]|)``, so ``h |V|`` of about 1e-3 of the scale on which ``f`` varies balances the two.

    Parameters
    ----------
    f : callable
        ``f(Z) -> values``, batch-capable and complex-safe (analytic), called twice (``X + h w V``, ``X - h w V``).
    X : array_like
        Base point(s) (real; units of ``f``'s argument).
    V : array_like
        Direction(s) (real; units of ``X``), broadcast against ``X``.
    h : float
        Step, ``> 0``, no default: ``h |V|`` about 1e-3 of ``f``'s length scale (see above).
    name : str
        How the error message names ``f``.
    advice : str
        What the error message tells the user to do when ``f`` is not complex-safe.

    Returns
    -------
    numpy.ndarray
        ``D^2 f(X)[V, V]``, the shape of ``f``'s output (units of ``f`` per unit of ``V`` squared).

    Raises
    ------
    ArgumentTypeError
        If ``f`` is not callable, ``X`` or ``V`` is not a real array, or ``h`` not a real number.
    ArgumentError
        If ``h <= 0`` or not finite.
    ModelError
        If ``f`` returns a real array for complex input (not complex-safe).
    Exception
        Whatever ``f`` raises passes through unchanged.
    """
    function("f", f)
    h = positive("h", h)
    X = _real("X", X)
    V = _real("V", V)
    plus = _complex_output(name, f(X + h * _E8 * V), advice)
    minus = _complex_output(name, f(X - h * _E8 * V), advice)
    return np.imag(plus + minus) / h**2


# ---------------------------------------------------------------------------------- checked single-point tools
def jacobians(f: Callable[[Any, Any], Any], x: Any, u: Any) -> tuple[np.ndarray, np.ndarray]:
    """``A = df/dx`` and ``B = df/du`` at ``(x, u)`` by complex step (exact to rounding).

    All ``n + m`` perturbed points go to ``f`` in one batch (``h`` = :data:`COMPLEX_STEP`); the result is exact to
    rounding because no two values of ``f`` are subtracted.

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

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> def pendulum(x, u):  # batch-capable: x (..., 2), u (..., 1)
    ...     return np.stack([x[..., 1], -np.sin(x[..., 0]) - 0.5 * x[..., 1] + u[..., 0]], axis=-1)
    >>> A, B = gc.jacobians(pendulum, [0.0, 0.0], [0.0])
    >>> A.tolist(), B.tolist()
    ([[0.0, 1.0], [-1.0, -0.5]], [[0.0], [1.0]])
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

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> H = gc.hessian(lambda X: X[:, 0] ** 2 * X[:, 1], [1.0, 2.0])  # f = x0^2 x1, one point per row
    >>> np.round(H, 6).tolist()
    [[4.0, 2.0], [2.0, 0.0]]
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
