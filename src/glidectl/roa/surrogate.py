"""Polynomial surrogates with a remainder bound, for closed loops that do not recast exactly.

**What is certified.** For a closed loop ``x' = f(x)`` with equilibrium ``x_e`` and a box ``B`` containing it, the
scaled field ``g(y) = f(x_e + S y) / s`` (``S = diag(s)``, :mod:`glidectl.roa.scaling`) is replaced by a polynomial
``p`` of degree ``d`` that matches ``g`` to second order at the equilibrium: ``p(0) = 0``, ``Dp(0) = Dg(0)`` (the
linearization, by complex step) and ``D^2 p(0) = D^2 g(0)`` (central differences of complex-step Jacobians); the
terms of degree 3 to ``d`` are a least-squares fit over the box. With it,

    ``|g_i(y) - p_i(y)| <= r_i(y) = a_i |y|^2 + b_i |y|^3``  for every ``y`` in the scaled box,

where ``a_i`` covers the finite-difference error of ``D^2 g(0)`` (a relative allowance of ``1e-6``) and ``b_i``
is the third-order Taylor bound below. The SOS programs of :func:`glidectl.certify_roa` then certify every field
``p + delta`` with ``|delta_i| <= r_i`` on the box, the true ``g`` included: for a fixed ``V``, ::

    dV/dt <= grad V . p + sum_i r_i |dV/dy_i|
          <= grad V . p + sum_i |y|^2 [a_i (k_i + (dV/dy_i)^2 / k_i) + b_i (k_i |y|^2 + (dV/dy_i)^2 / k_i)] / 2

for any ``k_i > 0`` (Young's inequality, ``|y| |dV/dy_i| <= (k_i |y|^2 + (dV/dy_i)^2 / k_i) / 2``, and
``|dV/dy_i| <= (k_i + (dV/dy_i)^2 / k_i) / 2``): a polynomial bound (:func:`robust_decrease_bound`). Its quadratic
part is ``sum_i a_i k_i |y|^2 / 2`` (rounding level), so near the equilibrium the bound decreases as the
linearization does: the remainder costs only quartic terms. (A remainder ``c_i |y|^2``, a surrogate matched to first
order only, would add ``c_i t_i(0) |y|^2`` with ``t_i(0) > 0`` for any polynomial ``t_i >= |dV/dy_i|``, which
defeats the linear decrease whenever ``c_i`` is not small: the LQR loop of the user glider is refused that way.)

**Why the bound holds.** With ``e = g - p``: ``e(0) = 0`` and ``De(0) = 0`` to rounding (the equilibrium is first
refined by Newton steps, so that ``g(0)`` is at rounding level), ``|D^2 e(0)| <= 2 a_i`` (the allowance), and the
box is star-shaped about ``0``, so Taylor's formula with integral remainder along ``[0, y]`` gives
``|e_i(y)| <= a_i |y|^2 + M_i |y|^3 / 6`` with ``M_i = sup_B ||D^3 e_i||``, the norm of the symmetric 3-tensor
bounded by the spectral norm of its ``n x n^2`` unfolding. ``M_i`` is bounded on a tensor grid of the box with
``g`` nodes per axis (spacing ``D_j``): at every node the third derivatives are computed (second central
differences, step ``1e-3``, of exact complex-step Jacobians; error ``O(1e-7)``, covered by the relative allowance;
the nodes are moved ``2e-3`` inside the box so that the differences never leave it) and, since every point of the
box is within the covering radius ``h = 1/2 sqrt(sum_j D_j^2) + 2e-3 sqrt(n)`` of a node,

    ``M_i <= max_nodes ||D^3 e_i|| + L_i h``,  ``L_i = margin * sqrt(sum_j L_ij^2)``,

where ``L_ij`` is the largest difference quotient ``||T(a) - T(b)|| / D_j`` between neighbouring nodes along axis
``j``. **Assumption** (the one step that is not proved): the Lipschitz constant of ``D^3 e_i`` along each axis is
at most ``margin`` (default 2) times the largest difference quotient seen on the grid; it holds when the fourth
derivatives of ``f`` vary by less than that factor within one grid cell. Everything else is exact or rounding. The
bound, its ingredients and this assumption are recorded in :class:`RemainderBound`, and :func:`surrogate_error`
checks it at any points (the tests check it on many more points than the fit used).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..analysis.measure import unit_sobol
from ..derivatives import complex_step
from ..errors import ArgumentError, ArgumentTypeError, ModelError
from .blas_threads import pinned_blas
from .polynomial import Poly, monomial_matrix, monomials
from .scaling import box_scale, resolve_box
from .systems import PolySystem

__all__ = ["RemainderBound", "remainder_values", "robust_decrease_bound", "surrogate_error", "surrogate_system",
           "young_weights"]

_H_FD = 1e-4            # step of the central differences of the Jacobians (scaled units): D^2 g(0)
_T_FD = 1e-3            # step of the second differences of the Jacobians: D^3 g at the grid nodes
_REL = 1e-6             # relative allowance for the finite-difference errors
_CS = 1e-30             # complex step


@dataclass(frozen=True)
class RemainderBound:
    """How the remainder ``|g_i(y) - p_i(y)| <= a_i |y|^2 + b_i |y|^3`` of a surrogate was bounded (module
    docstring).

    Attributes
    ----------
    quadratic : ndarray (n,)
        ``a_i``: the allowance for the finite-difference error of ``D^2 g_i(0)`` (per time unit of the model; ``y``
        nondimensional).
    cubic : ndarray (n,)
        ``b_i = M_i / 6``, ``M_i`` the bound of ``||D^3 e_i||`` on the box.
    third_max : ndarray (n,)
        Largest ``||D^3 e_i||`` at the grid nodes (spectral norm of the ``n x n^2`` unfolding).
    third_lipschitz : ndarray (n,)
        ``L_i`` (margin included).
    covering_radius : float
        ``h``: every point of the scaled box is within ``h`` of a node.
    grid : int
        Nodes per axis (``grid ** n`` nodes).
    margin : float
        Safety factor on the sampled Lipschitz quotients (the assumption of the module docstring).
    fit_degree : int
        Degree ``d`` of the surrogate.
    n_fit : int
        Least-squares points.
    fit_residual : ndarray (n,)
        Largest ``|e_i|`` at the fit points.
    equilibrium_residual : float
        ``max |f(x_e)|`` after the Newton refinement (state units per time unit).
    assumptions : str
        The assumptions the bound rests on, in words.
    """

    quadratic: np.ndarray
    cubic: np.ndarray
    third_max: np.ndarray
    third_lipschitz: np.ndarray
    covering_radius: float
    grid: int
    margin: float
    fit_degree: int
    n_fit: int
    fit_residual: np.ndarray
    equilibrium_residual: float
    assumptions: str = field(repr=False, default="")

    def __call__(self, Y: Any) -> np.ndarray:
        """The bound ``a_i |y|^2 + b_i |y|^3`` at scaled states ``Y`` (N, n): (N, n)."""
        r = np.linalg.norm(np.asarray(Y, dtype=float), axis=-1)[..., None]
        return self.quadratic * r**2 + self.cubic * r**3

    def summary(self) -> str:
        """One line: degree, grid, covering radius and the largest coefficients."""
        return (f"surrogate degree {self.fit_degree} matched to second order, remainder <= a |y|^2 + b |y|^3 with "
                f"max a = {float(np.max(self.quadratic)):.3g}, max b = {float(np.max(self.cubic)):.3g} (grid "
                f"{self.grid}^n, covering radius {self.covering_radius:.3g}, margin {self.margin:g})")


def _field(model: Any) -> Any:
    rhs = model.rhs

    def f(X: np.ndarray) -> np.ndarray:
        return np.asarray(rhs(X))
    return f


def _jac(g: Any, Y: np.ndarray) -> np.ndarray:
    """``J[k, j, i] = d g_i / d y_j`` at points ``Y`` (N, n), complex step."""
    N, n = Y.shape
    d = complex_step(lambda Z: g(Z.reshape(N * n, n)), Y[:, None, :], np.eye(n)[None], _CS,
                     name="the model's right-hand side",
                     advice="its derivatives cannot be bounded: the surrogate route needs rhs written with numpy "
                            "operations that keep complex values")
    return d.reshape(N, n, n)


def _hessians(g: Any, Y: np.ndarray, chunk: int = 4096) -> np.ndarray:
    """``H[k, i] = Hess g_i (y_k)`` (N, n, n, n... as (N, n_out, n, n)), central differences of exact Jacobians."""
    N, n = Y.shape
    H = np.empty((N, n, n, n))
    for a in range(0, N, chunk):
        Yb = Y[a:a + chunk]
        for k in range(n):
            d = np.zeros(n)
            d[k] = _H_FD
            Jp, Jm = _jac(g, Yb + d), _jac(g, Yb - d)
            H[a:a + chunk, :, :, k] = np.transpose((Jp - Jm) / (2 * _H_FD), (0, 2, 1))   # [k, i, j, k]
    return 0.5 * (H + np.swapaxes(H, -1, -2))


def _thirds(g: Any, Y: np.ndarray, chunk: int = 1024) -> np.ndarray:
    """``T[k, i, j, a, b] = d^3 g_i / dy_j dy_a dy_b (y_k)``, (N, n_out, n, n, n): second central differences (step
    ``_T_FD``) of exact complex-step Jacobians."""
    N, n = Y.shape
    h = _T_FD
    T = np.empty((N, n, n, n, n))
    E = np.eye(n) * h
    for s0 in range(0, N, chunk):
        Yb = Y[s0:s0 + chunk]
        J0 = _jac(g, Yb)
        for a in range(n):
            for b in range(a, n):
                if a == b:
                    D = (_jac(g, Yb + 2 * E[a]) - 2 * J0 + _jac(g, Yb - 2 * E[a])) / (4 * h * h)
                else:
                    D = (_jac(g, Yb + E[a] + E[b]) - _jac(g, Yb + E[a] - E[b]) - _jac(g, Yb - E[a] + E[b])
                         + _jac(g, Yb - E[a] - E[b])) / (4 * h * h)
                D = np.transpose(D, (0, 2, 1))                               # [k, i, j]
                T[s0:s0 + chunk, :, :, a, b] = D
                T[s0:s0 + chunk, :, :, b, a] = D
    # symmetrize over the three derivative slots (the differences are symmetric in (a, b) only)
    return (T + np.transpose(T, (0, 1, 3, 2, 4)) + np.transpose(T, (0, 1, 4, 3, 2))) / 3.0


def _poly_derivs(P: list[Poly], Y: np.ndarray, order: int) -> np.ndarray:
    """Exact derivative tensors of order 2 or 3 of polynomials ``P`` at points ``Y`` (N, n):
    ``(N, len(P), n, ..., n)``."""
    import itertools

    N, n = Y.shape
    out = np.zeros((N, len(P)) + (n,) * order)
    for i, p in enumerate(P):
        for idx in itertools.combinations_with_replacement(range(n), order):
            d = p
            for j in idx:
                d = d.diff(j)
            if d.is_zero:
                continue
            E, c = d.arrays()
            v = monomial_matrix(Y, [tuple(e) for e in E]) @ c
            for perm in set(itertools.permutations(idx)):
                out[(slice(None), i, *perm)] = v
    return out


def _unfolded_norms(T: np.ndarray) -> np.ndarray:
    """Spectral norms of the ``n x n^2`` unfoldings of 3-tensors ``T (..., n, n, n)``: upper bounds of the tensor
    norm ``max |T[u, v, w]|`` over unit vectors."""
    n = T.shape[-1]
    M = T.reshape(*T.shape[:-3], n, n * n)
    G = M @ np.swapaxes(M, -1, -2)
    return np.sqrt(np.maximum(np.linalg.eigvalsh(G)[..., -1], 0.0))


def refine_equilibrium(f: Any, xe: np.ndarray) -> np.ndarray:
    """Newton steps on ``f(x) = 0`` from ``x_e`` (the trim's tolerance would leave ``e(0) != 0``); steps larger than
    ``1e-3 (1 + |x_e|)`` are not taken (then ``x_e`` is returned as it is and the caller's residual check decides)."""
    x = xe.astype(float).copy()
    for _ in range(4):
        r = np.real(f(x[None, :]))[0]
        if not np.all(np.isfinite(r)):
            break
        A = _jac(lambda X: f(X), x[None, :])[0].T
        try:
            step = np.linalg.solve(A, r)
        except np.linalg.LinAlgError:
            break
        if np.linalg.norm(step) > 1e-3 * (1 + np.linalg.norm(x)):
            break
        x = x - step
    return x


@pinned_blas
def surrogate_system(model: Any, box: Any = None, *, degree: int = 3, margin: float = 2.0,
                     n_hessian: int | None = None, n_fit: int | None = None, seed: int = 0) -> PolySystem:
    """A polynomial surrogate of a closed loop with a remainder bound, as a :class:`PolySystem` for
    :func:`glidectl.certify_roa` (``method = "surrogate+remainder"``).

    Parameters
    ----------
    model : glidectl model without inputs
        ``state_names``, ``equilibrium`` (state units, not None) and a batch, complex-safe ``rhs(X)``: e.g.
        ``gc.closed_loop(controller)``.
    box : pair or mapping, optional
        Region of interest (state units), see :func:`glidectl.roa.scaling.resolve_box` (default the model's box or
        the validity box of its states, :func:`~glidectl.roa.scaling.validity_box`).
    degree : int
        Degree of the surrogate, 2 to 5 (2: the second-order Taylor polynomial alone; higher: its terms of degree 3
        to ``degree`` fitted over the box).
    margin : float
        Safety factor (>= 1) on the sampled Lipschitz quotients of the third derivatives (module docstring).
    n_hessian : int, optional
        Largest number of grid nodes (>= 2^n; default ``max(4096, 2^n)``): ``grid = floor(n_hessian^(1/n))`` per
        axis. Each node costs ``2 n^3 + n`` evaluations of the right-hand side (its third derivatives).
    n_fit : int, optional
        Least-squares points (default ``max(8 x basis size, 512)``).
    seed : int
        Seed of the fit points.

    Returns
    -------
    PolySystem
        In ``z = y = (x - x_e) / s``: ``F = p``, the box as cuts ``(y_j - ylo_j)(yhi_j - y_j) >= 0``, the
        remainder bound ``a_i |y|^2 + b_i |y|^3`` as ``remainder = (a_i |y|^2)``, ``remainder_cubic = (b_i)`` and
        ``remainder_norm = |y|^2``, ``rhs`` the model's own (state units), ``equilibrium`` the refined ``x_e``,
        ``box`` in state units, ``scale = s``, ``method = "surrogate+remainder"``, ``remainder_bound`` a
        :class:`RemainderBound`.

    Raises
    ------
    ArgumentTypeError
        If ``model`` has no ``state_names``, ``equilibrium`` or callable ``rhs``, or an option has the wrong type.
    ArgumentError
        If an option is out of range or the box is invalid (see :func:`~glidectl.roa.scaling.resolve_box`).
    ModelError
        If the model has no equilibrium (``None``), ``f(x_e)`` is not zero to rounding after Newton refinement, the
        right-hand side is not complex-safe, or it is not finite on the box.

    Examples
    --------
    >>> import glidectl as gc
    >>> loop = gc.closed_loop(gc.design_torque_control(gc.load_vehicle("sphere_ch5"), speed=1.6))
    >>> ps = gc.surrogate_system(loop, degree=3)
    >>> ps.method, ps.state_names
    ('surrogate+remainder', ('V', 'gamma', 'alpha', 'Omega2'))
    """
    if not hasattr(model, "state_names") or not callable(getattr(model, "rhs", None)):
        raise ArgumentTypeError(f"expected an input-free glidectl model (state_names, rhs(x), equilibrium), e.g. "
                                f"gc.closed_loop(controller); got {type(model).__name__}")
    if tuple(getattr(model, "input_names", ())):
        raise ArgumentTypeError(f"{type(model).__name__} has inputs {tuple(model.input_names)}: close the loop first "
                                "(gc.closed_loop(controller) or gc.closed_loop(plant, law))")
    degree = checks.integer("degree", degree, lo=2, hi=5)
    margin = checks.real("margin", margin, lo=1.0)
    seed = checks.integer("seed", seed, lo=0)
    names = tuple(model.state_names)
    n = len(names)
    n_hessian = max(4096, 2**n) if n_hessian is None else checks.integer("n_hessian", n_hessian, lo=2**n)
    xe0 = getattr(model, "equilibrium", None)
    if xe0 is None:
        raise ModelError(f"'{getattr(model, 'name', type(model).__name__)}' has no equilibrium (None): a region of "
                         "attraction needs one (e.g. closed_loop(plant, law, equilibrium=...))")
    xe0 = checks.array("equilibrium", xe0, shape=(n,))
    lo, hi = resolve_box(model, box, xe0)
    f = _field(model)
    xe = refine_equilibrium(f, xe0)
    if np.any(xe <= lo) or np.any(xe >= hi):
        raise ModelError(f"the refined equilibrium {xe.tolist()} left the box")
    f0 = float(np.max(np.abs(np.real(f(xe[None, :]))[0])))
    s = box_scale((lo, hi), xe)
    ylo, yhi = (lo - xe) / s, (hi - xe) / s

    def g(Y: np.ndarray) -> np.ndarray:
        return f(xe + np.asarray(Y) * s) / s

    if f0 / max(float(np.max(np.abs(_jac(g, np.zeros((1, n)))))), 1e-300) > 1e-10:
        raise ModelError(f"x_e is not an equilibrium: max |f(x_e)| = {f0:.3g} after Newton refinement")
    A = _jac(g, np.zeros((1, n)))[0].T                          # A[i, j] = d g_i / d y_j
    H0 = _hessians(g, np.zeros((1, n)))[0]                         # H0[i] = D^2 g_i(0)
    Z = Poly.variables(n)
    P: list[Poly] = []
    for i in range(n):
        p = Poly({}, n)
        for j in range(n):
            p = p + float(A[i, j]) * Z[j]
            for k in range(j, n):
                p = p + float(H0[i, j, k] * (0.5 if j == k else 1.0)) * Z[j] * Z[k]
        P.append(p)
    basis = monomials(n, degree, 3)
    nf = max(8 * len(basis), 512) if n_fit is None else checks.integer("n_fit", n_fit, lo=len(basis) + 1)
    Y = ylo + (yhi - ylo) * unit_sobol(n, seed + 1, nf)
    G = np.real(g(Y))
    if not np.all(np.isfinite(G)):
        raise ModelError("the right-hand side is not finite everywhere in the box: shrink the box")
    T = G - np.stack([p(Y) for p in P], axis=-1)                 # what the terms of degree 3..d are fitted to
    if basis:
        M = monomial_matrix(Y, basis)
        colscale = np.maximum(np.max(np.abs(M), axis=0), 1e-300)
        coef, *_ = np.linalg.lstsq(M / colscale, T, rcond=None)
        coef = coef / colscale[:, None]
        P = [P[i] + Poly(dict(zip(basis, coef[:, i], strict=True)), n) for i in range(n)]
        T = T - M @ coef
    fit_res = np.max(np.abs(T), axis=0)

    # third-derivative bound on the grid
    gn = 2
    while (gn + 1) ** n <= n_hessian:
        gn += 1
    axes = [np.linspace(ylo[j], yhi[j], gn) for j in range(n)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, n)
    # the difference stencil reaches 2 _T_FD along each axis: its centres are kept that far inside the box (the
    # model may not be smooth past it, e.g. an actuator range), which moves a node by at most 2 _T_FD sqrt(n)
    nodes = np.clip(nodes, ylo + 2 * _T_FD, yhi - 2 * _T_FD)
    D3 = _thirds(g, nodes) - _poly_derivs(P, nodes, 3)              # D^3 e at the nodes, (N, n_out, n, n, n)
    if not np.all(np.isfinite(D3)):
        raise ModelError("the third derivatives of the right-hand side are not finite on the box: shrink the box")
    norms = _unfolded_norms(D3)                                     # (N, n_out)
    Tg = D3.reshape(*(gn,) * n, n, n, n, n)
    D = (yhi - ylo) / (gn - 1)
    Lij = np.zeros((n, n))
    for j in range(n):
        step = np.diff(np.clip(axes[j], ylo[j] + 2 * _T_FD, yhi[j] - 2 * _T_FD))   # the moved nodes' spacing
        shape = [1] * Tg.ndim
        shape[j] = gn - 1
        diff = (np.diff(Tg, axis=j) / step.reshape(shape)).reshape(-1, n, n, n, n)
        Lij[:, j] = np.max(_unfolded_norms(diff), axis=0)
    L = margin * np.sqrt(np.sum(Lij**2, axis=1))
    h = 0.5 * float(np.sqrt(np.sum(D**2))) + 2 * _T_FD * math.sqrt(n)
    tmax = np.max(norms, axis=0)
    Mb = tmax * (1 + _REL) + 1e-12 + L * h
    b3 = Mb / 6.0
    h0 = np.max(np.abs(np.linalg.eigvalsh(H0)), axis=-1)               # ||D^2 g_i(0)||
    a2 = 0.5 * (_REL * (h0 + Mb) + 1e-12)                            # |D^2 e_i(0)| <= 2 a_i
    q = sum((Z[j] ** 2 for j in range(n)), Poly({}, n))
    cuts = tuple((Z[j] - float(ylo[j])) * (float(yhi[j]) - Z[j]) for j in range(n))
    assumptions = (f"|g_i(y) - p_i(y)| <= a_i |y|^2 + b_i |y|^3 on the scaled box holds if: the box is star-shaped "
                   f"about the equilibrium (a box containing it is); g(0) = 0 and Dp(0) = Dg(0) to rounding (max "
                   f"|f(x_e)| = {f0:.2g}); the finite-difference errors of D^2 g(0) and of D^3 g at the nodes are "
                   f"within the relative allowance {_REL:g}; and the Lipschitz constant of D^3(g - p) along each "
                   f"axis is at most {margin:g} times the largest difference quotient between neighbouring nodes of "
                   f"the {gn}^{n} grid (the one assumption that is not proved)")
    bound = RemainderBound(a2, b3, tmax, L, h, gn, margin, degree, nf, fit_res, f0, assumptions)
    return PolySystem(name=getattr(model, "name", type(model).__name__), state_names=names, z_names=names,
                      F=tuple(P), den=Poly.const(1.0, n), equalities=(), cuts=cuts,
                      lift=lambda X: (np.asarray(X) - xe) / s, rhs=f, equilibrium=xe, box=(lo, hi),
                      recast_residual=float(np.max(fit_res)), time_unit=getattr(model, "time_unit", "s"),
                      provenance=str(getattr(model, "provenance", "")), slots=tuple((i,) for i in range(n)),
                      remainder=tuple(float(a2[i]) * q for i in range(n)),
                      remainder_cubic=tuple(float(x) for x in b3), remainder_norm=q,
                      method="surrogate+remainder", scale=s, remainder_bound=bound)


def surrogate_error(ps: PolySystem, X: Any) -> tuple[np.ndarray, np.ndarray]:
    """The surrogate's actual error and its bound at states ``X``: ``|dz/dt - F(z)|`` and ``r(z)``, ``z = lift(x)``.

    Parameters
    ----------
    ps : PolySystem
        A surrogate (:func:`surrogate_system`).
    X : array_like (N, n)
        States (state units), inside the box for the bound to apply.

    Returns
    -------
    (ndarray, ndarray), each (N, n)
        The error and the bound (per time unit, scaled states); the bound holds where ``error <= bound``.

    Raises
    ------
    ArgumentTypeError
        If ``ps`` is not a PolySystem.
    ArgumentError
        If ``ps`` has no remainder (not a surrogate) or ``X`` has the wrong shape.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> loop = gc.closed_loop(gc.design_torque_control(gc.load_vehicle("sphere_ch5"), speed=1.6))
    >>> ps = gc.surrogate_system(loop)
    >>> _, X = gc.box_points(ps.box, n=256)
    >>> error, bound = gc.surrogate_error(ps, X)
    >>> error.shape, bool(np.all(error <= bound))
    ((256, 4), True)
    """
    if not isinstance(ps, PolySystem):
        raise ArgumentTypeError(f"ps must be a PolySystem, got {type(ps).__name__}")
    if not ps.remainder or ps.scale is None:
        raise ArgumentError(f"'{ps.name}' is not a surrogate system (no remainder)")
    X = checks.array("X", X, ndim=2)
    if X.shape[1] != ps.n:
        raise ArgumentError(f"X must have shape (N, {ps.n}), got {X.shape}")
    Z = ps.lift(X)
    true = np.real(ps.rhs(X)) / ps.scale
    F = np.stack([p(Z) for p in ps.F], axis=-1)
    return np.abs(true - F), remainder_values(ps, Z)


def remainder_values(ps: PolySystem, Z: Any) -> np.ndarray:
    """The remainder bound ``r_i(z) = remainder_i(z) + b_i remainder_norm(z)^(3/2)`` of a surrogate system at
    ``Z`` (N, nz): (N, nz)."""
    Z = np.asarray(Z)
    R = np.stack([r(Z) for r in ps.remainder], axis=-1)
    if ps.remainder_cubic:
        R = R + np.asarray(ps.remainder_cubic) * np.maximum(ps.remainder_norm(Z), 0.0)[:, None] ** 1.5
    return R


def skeleton(n: int, degree: int) -> PolySystem:
    """A placeholder surrogate PolySystem of the right sizes (for budgets, before anything is sampled)."""
    Z = Poly.variables(n)
    q = sum((Z[j] ** 2 for j in range(n)), Poly({}, n))
    F = tuple(Z[i] ** degree + Z[i] for i in range(n))
    cuts = tuple((Z[j] + 1.0) * (1.0 - Z[j]) for j in range(n))
    return PolySystem(name="skeleton", state_names=tuple(f"x{i}" for i in range(n)),
                      z_names=tuple(f"x{i}" for i in range(n)), F=F, den=Poly.const(1.0, n), equalities=(),
                      cuts=cuts, lift=lambda X: X, rhs=lambda X: X, equilibrium=np.zeros(n),
                      box=(-np.ones(n), np.ones(n)), slots=tuple((i,) for i in range(n)),
                      remainder=tuple(q for _ in range(n)), remainder_cubic=(1.0,) * n, remainder_norm=q,
                      method="surrogate+remainder", scale=np.ones(n))


def robust_degree(degV: int, degF: int) -> int:
    """The degree of ``F`` to budget for when ``dV/dt`` carries the robust bound of :func:`robust_decrease_bound`
    (degree ``2 degV`` for a ``V`` of degree ``degV >= 2``): ``max(degF, degV + 1)``."""
    return max(degF, degV + 1)


def young_weights(ps: PolySystem, V: Poly, R: list[Poly], B: Any, n_points: int = 512) -> np.ndarray:
    """The ``k_i > 0`` of :func:`robust_decrease_bound` for ``V``: each minimizes the sum of its bound over points
    of the box, ``k_i^2 = sum w_i (dV/dz_i)^2 / sum (R_i + B_i q^2)`` with ``w_i = R_i + B_i q`` (any ``k_i > 0``
    is sound; this one is tight on average)."""
    lo, hi = ps.box
    Zp = ps.lift(lo + (hi - lo) * unit_sobol(ps.n, 7, n_points))
    q = ps.remainder_norm(Zp) if ps.remainder_norm is not None else np.zeros(len(Zp))
    B = np.asarray(B, dtype=float) if len(B) else np.zeros(ps.nz)
    k = np.ones(ps.nz)
    for i in range(ps.nz):
        r = R[i](Zp)
        num = float(np.sum((r + B[i] * q) * V.diff(i)(Zp) ** 2))
        den = float(np.sum(r + B[i] * q**2))
        if num > 0 and den > 0:
            k[i] = float(np.sqrt(num / den))
    return k


def robust_decrease_bound(ps: PolySystem, grads: list[Any], R: list[Poly], B: Any, k: np.ndarray) -> Any:
    """``sum_i [R_i (k_i + g_i^2 / k_i) + B_i q (k_i q + g_i^2 / k_i)] / 2`` (``q = remainder_norm``, ``g_i``
    the ``dV/dz_i`` of a fixed ``V``): the polynomial bound of ``sum_i r_i |g_i|`` of the module docstring, with
    ``r_i = R_i + B_i q^(3/2)`` (Young's inequality; sound for any ``k_i > 0``)."""
    nz = ps.nz
    zero = Poly({}, nz)
    q = ps.remainder_norm if ps.remainder_norm is not None else zero
    B = list(B) if len(B) else [0.0] * nz
    out = zero
    for i, g in enumerate(grads):
        w = R[i] + q * float(B[i])
        if w.is_zero:
            continue
        ki = float(k[i])
        out = out + (R[i] * ki + q * q * float(B[i] * ki)) * 0.5 + w * (g * g) * (0.5 / ki)
    return out
