"""Polynomial surrogates with a remainder bound, for closed loops that do not recast exactly (issue 17).

**What is certified.** For a closed loop ``x' = f(x)`` with equilibrium ``x_e`` and a box ``B`` containing it, the
scaled field ``g(y) = f(x_e + S y) / s`` (``S = diag(s)``, :mod:`glidectl.roa.scaling`) is replaced by a polynomial
``p`` of degree ``d`` with ``p(0) = 0`` and ``Dp(0) = Dg(0)`` exactly (the linearization by complex step; the
higher terms by least squares over the box), together with

    ``|g_i(y) - p_i(y)| <= r_i(y) = c_i |y|^2``  for every ``y`` in the scaled box,

so the SOS programs of :func:`glidectl.certify_roa` certify every field ``p + delta`` with ``|delta_i| <= r_i`` on
the box, the true ``g`` included (see ``_build`` in :mod:`glidectl.roa.certify`: ``dV/dt <= grad V . p + sum_i r_i
t_i`` with ``t_i >= |dV/dy_i|`` certified on the box by SOS).

**Why the bound holds.** With ``e = g - p``, ``e(0) = 0`` and ``De(0) = 0`` (to rounding; the equilibrium is first
refined by Newton steps so that ``g(0)`` is at rounding level), and the box is star-shaped about ``0``, so Taylor's
formula with integral remainder along the segment ``[0, y]`` gives ``|e_i(y)| <= 1/2 M_i |y|^2`` with
``M_i = sup_B ||Hess e_i||_2``. ``M_i`` is bounded on a tensor grid of the box with ``g`` nodes per axis (spacing
``D_j``): at every node the Hessian is computed (central differences, step ``1e-4``, of exact complex-step
Jacobians; error ``O(1e-8)``, covered by the added ``1e-6`` relative allowance) and, since every point of the box
is within the covering radius ``h = 1/2 sqrt(sum_j D_j^2)`` of a node,

    ``M_i <= max_nodes ||Hess e_i||_2 + L_i h``,  ``L_i = margin * sqrt(sum_j L_ij^2)``,

where ``L_ij`` is the largest difference quotient ``||H(a) - H(b)||_2 / D_j`` between neighbouring nodes along axis
``j``. **Assumption** (the one step that is not proved): the Lipschitz constant of ``Hess e_i`` along each axis is at
most ``margin`` (default 2) times the largest difference quotient seen on the grid; it holds when the third
derivatives of ``f`` vary by less than that factor within one grid cell. Everything else is exact or rounding. The
bound, its ingredients and this assumption are recorded in :class:`RemainderBound`, and
:func:`surrogate_error` checks it at any points (the tests check it on many more points than the fit used).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np
from scipy.stats import qmc

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, ModelError
from .polynomial import Poly, monomial_matrix, monomials
from .scaling import box_scale, resolve_box
from .sos import GramCheck, SOSProgram
from .systems import PolySystem

__all__ = ["RemainderBound", "surrogate_error", "surrogate_system"]

_H_FD = 1e-4            # step of the central differences of the Jacobians (scaled units)
_CS = 1e-30             # complex step


@dataclass(frozen=True)
class RemainderBound:
    """How the remainder ``|g_i(y) - p_i(y)| <= c_i |y|^2`` of a surrogate was bounded (module docstring).

    Attributes
    ----------
    coefficients : ndarray (n,)
        ``c_i = M_i / 2`` (per time unit of the model; ``y`` nondimensional).
    hessian_max : ndarray (n,)
        Largest ``||Hess e_i||_2`` at the grid nodes.
    hessian_lipschitz : ndarray (n,)
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

    coefficients: np.ndarray
    hessian_max: np.ndarray
    hessian_lipschitz: np.ndarray
    covering_radius: float
    grid: int
    margin: float
    fit_degree: int
    n_fit: int
    fit_residual: np.ndarray
    equilibrium_residual: float
    assumptions: str = field(repr=False, default="")

    def summary(self) -> str:
        """One line: degree, grid, covering radius and the largest coefficient."""
        return (f"surrogate degree {self.fit_degree}, remainder <= c |y|^2 with max c = "
                f"{float(np.max(self.coefficients)):.3g} (grid {self.grid}^n, covering radius "
                f"{self.covering_radius:.3g}, margin {self.margin:g})")


def _field(model: Any) -> Any:
    rhs = model.rhs

    def f(X: np.ndarray) -> np.ndarray:
        return np.asarray(rhs(X))
    return f


def _jac(g: Any, Y: np.ndarray) -> np.ndarray:
    """``J[k, j, i] = d g_i / d y_j`` at points ``Y`` (N, n), complex step."""
    N, n = Y.shape
    Yc = (Y[:, None, :] + 1j * _CS * np.eye(n)[None]).reshape(N * n, n)
    out = g(Yc)
    if not np.iscomplexobj(out):
        raise ModelError("the model's right-hand side is not complex-safe (it returned real values for complex "
                         "states), so its derivatives cannot be bounded: the surrogate route needs rhs written with "
                         "numpy operations that keep complex values")
    return (np.imag(out) / _CS).reshape(N, n, n)


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


def _poly_hessians(P: list[Poly], Y: np.ndarray) -> np.ndarray:
    """Exact Hessians of polynomials ``P`` at points ``Y`` (N, n): ``(N, len(P), n, n)``."""
    N, n = Y.shape
    H = np.zeros((N, len(P), n, n))
    for i, p in enumerate(P):
        for j in range(n):
            dj = p.diff(j)
            for k in range(j, n):
                djk = dj.diff(k)
                if djk.is_zero:
                    continue
                E, c = djk.arrays()
                v = monomial_matrix(Y, [tuple(e) for e in E]) @ c
                H[:, i, j, k] = v
                H[:, i, k, j] = v
    return H


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


def _sobol(d: int, seed: int, n: int) -> np.ndarray:
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return qmc.Sobol(d, seed=seed).random(n)


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
        Degree of the surrogate, 2 to 5.
    margin : float
        Safety factor (>= 1) on the sampled Lipschitz quotients of the Hessians (module docstring).
    n_hessian : int, optional
        Largest number of grid nodes (>= 2^n; default ``max(4096, 2^n)``): ``grid = floor(n_hessian^(1/n))`` per
        axis. Each node costs ``2 n^2`` evaluations of the right-hand side.
    n_fit : int, optional
        Least-squares points (default ``max(8 x basis size, 512)``).
    seed : int
        Seed of the fit points.

    Returns
    -------
    PolySystem
        In ``z = y = (x - x_e) / s``: ``F = p``, the box as cuts ``(y_j - ylo_j)(yhi_j - y_j) >= 0``, ``remainder
        = (c_i |y|^2)``, ``rhs`` the model's own (state units), ``equilibrium`` the refined ``x_e``, ``box`` in state
        units, ``scale = s``, ``method = "surrogate+remainder"``, ``remainder_bound`` a :class:`RemainderBound`.

    Raises
    ------
    ArgumentTypeError
        If ``model`` has no ``state_names``, ``equilibrium`` or callable ``rhs``, or an option has the wrong type.
    ArgumentError
        If an option is out of range or the box is invalid (see :func:`~glidectl.roa.scaling.resolve_box`).
    ModelError
        If the model has no equilibrium (``None``), ``f(x_e)`` is not zero to rounding after Newton refinement, the
        right-hand side is not complex-safe, or it is not finite on the box.
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
    basis = monomials(n, degree, 2)
    nf = max(8 * len(basis), 512) if n_fit is None else checks.integer("n_fit", n_fit, lo=len(basis) + 1)
    Y = ylo + (yhi - ylo) * _sobol(n, seed + 1, nf)
    G = np.real(g(Y))
    if not np.all(np.isfinite(G)):
        raise ModelError("the right-hand side is not finite everywhere in the box: shrink the box")
    T = G - Y @ A.T
    M = monomial_matrix(Y, basis)
    colscale = np.maximum(np.max(np.abs(M), axis=0), 1e-300)
    coef, *_ = np.linalg.lstsq(M / colscale, T, rcond=None)
    coef = coef / colscale[:, None]
    Z = Poly.variables(n)
    P: list[Poly] = []
    for i in range(n):
        p = Poly(dict(zip(basis, coef[:, i], strict=True)), n)
        for j in range(n):
            p = p + float(A[i, j]) * Z[j]
        P.append(p)
    fit_res = np.max(np.abs(T - M @ coef), axis=0)

    # Hessian bound on the grid
    gn = 2
    while (gn + 1) ** n <= n_hessian:
        gn += 1
    axes = [np.linspace(ylo[j], yhi[j], gn) for j in range(n)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, n)

    H = _hessians(g, nodes) - _poly_hessians(P, nodes)            # Hess e = Hess g - Hess p, (N, n_out, n, n)
    if not np.all(np.isfinite(H)):
        raise ModelError("the Hessian of the right-hand side is not finite on the box: shrink the box")
    norms = np.max(np.abs(np.linalg.eigvalsh(H)), axis=-1)          # (N, n_out) spectral norms
    Hg = H.reshape(*(gn,) * n, n, n, n)
    D = (yhi - ylo) / (gn - 1)
    Lij = np.zeros((n, n))
    for j in range(n):
        diff = np.diff(Hg, axis=j).reshape(-1, n, n, n)
        Lij[:, j] = np.max(np.max(np.abs(np.linalg.eigvalsh(diff)), axis=-1), axis=0) / D[j]
    L = margin * np.sqrt(np.sum(Lij**2, axis=1))
    h = 0.5 * float(np.sqrt(np.sum(D**2)))
    hmax = np.max(norms, axis=0)
    Mb = hmax * (1 + 1e-6) + 1e-12 + L * h
    c = 0.5 * Mb
    q = sum((Z[j] ** 2 for j in range(n)), Poly({}, n))
    remainder = tuple(float(c[i]) * q for i in range(n))
    cuts = tuple((Z[j] - float(ylo[j])) * (float(yhi[j]) - Z[j]) for j in range(n))
    assumptions = (f"|g_i(y) - p_i(y)| <= c_i |y|^2 on the scaled box holds if: the box is star-shaped about the "
                   f"equilibrium (a box containing it is); g(0) = 0 and Dp(0) = Dg(0) to rounding (max |f(x_e)| = "
                   f"{f0:.2g}); and the Lipschitz constant of Hess(g - p) along each axis is at most {margin:g} times "
                   f"the largest difference quotient between neighbouring nodes of the {gn}^{n} grid (the one "
                   "assumption that is not proved)")
    bound = RemainderBound(c, hmax, L, h, gn, margin, degree, nf, fit_res, f0, assumptions)
    Pt = tuple(P)
    return PolySystem(name=getattr(model, "name", type(model).__name__), state_names=names, z_names=names, F=Pt,
                      den=Poly.const(1.0, n), equalities=(), cuts=cuts,
                      lift=lambda X: (np.asarray(X) - xe) / s, rhs=f, equilibrium=xe, box=(lo, hi),
                      recast_residual=float(np.max(fit_res)), time_unit=getattr(model, "time_unit", "s"),
                      provenance=str(getattr(model, "provenance", "")), slots=tuple((i,) for i in range(n)),
                      remainder=remainder, method="surrogate+remainder", scale=s, remainder_bound=bound)


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
    R = np.stack([r(Z) for r in ps.remainder], axis=-1)
    return np.abs(true - F), R


def skeleton(n: int, degree: int) -> PolySystem:
    """A placeholder surrogate PolySystem of the right sizes (for budgets, before anything is sampled)."""
    Z = Poly.variables(n)
    q = sum((Z[j] ** 2 for j in range(n)), Poly({}, n))
    F = tuple(Z[i] ** degree + Z[i] for i in range(n))
    cuts = tuple((Z[j] + 1.0) * (1.0 - Z[j]) for j in range(n))
    return PolySystem(name="skeleton", state_names=tuple(f"x{i}" for i in range(n)),
                      z_names=tuple(f"x{i}" for i in range(n)), F=F, den=Poly.const(1.0, n), equalities=(),
                      cuts=cuts, lift=lambda X: X, rhs=lambda X: X, equilibrium=np.zeros(n),
                      box=(-np.ones(n), np.ones(n)), slots=tuple((i,) for i in range(n)), remainder=tuple(q for _ in
                      range(n)), method="surrogate+remainder", scale=np.ones(n))


def t_degree(degV: int) -> int:
    """Degree of the bounds ``t_i >= |dV/dz_i|``: the even degree >= ``degV - 1`` (at least 2)."""
    d = max(degV - 1, 2)
    return d + (d % 2)


def abs_gradient_constraints(prog: SOSProgram, ps: PolySystem, grad: list[Any], degT: int) -> list[Any]:
    """Add ``t_i -+ dV/dz_i - sum_j s_j g_j`` SOS (``s_j`` SOS, ``g_j`` the cuts) to ``prog``: ``t_i >= |dV/dz_i|``
    on the cuts. ``grad`` holds the ``dV/dz_i`` (LinPoly or Poly); returns the ``t_i`` as LinPolys."""
    from .sos import LinPoly

    nz = ps.nz
    ts = []
    for i, d in enumerate(grad):
        _, t = prog.free_poly(f"t{i}", monomials(nz, degT))
        dl = d if isinstance(d, LinPoly) else LinPoly(d)
        for sgn, tag in ((1.0, "+"), (-1.0, "-")):
            expr = t - dl * sgn
            for k, gk in enumerate(ps.cuts):
                _, sk = prog.sos_poly(f"s{i}{tag}{k}", monomials(nz, (degT - gk.degree) // 2))
                expr = expr - sk * gk
            prog.add_sos(f"|dV/dz{i}|{tag}", expr, monomials(nz, degT // 2))
        ts.append(t)
    return ts


def abs_gradient_bounds(ps: PolySystem, V: Poly, R: list[Poly], *, solver: str = "CLARABEL",
                        n_points: int = 512) -> tuple[list[Poly], list[Any]]:
    """For a fixed ``V``: polynomials ``t_i >= |dV/dz_i|`` on the cuts (SOS certificates), minimizing the mean of
    ``sum_i R_i t_i`` over points of the box (one small SDP); returns the ``t_i`` and the Gram checks of their SOS
    certificates (part of the certificate's exactness checks)."""
    nz = ps.nz
    degT = t_degree(max(V.degree, 2))
    prog = SOSProgram(nz)
    ts = abs_gradient_constraints(prog, ps, [V.diff(i) for i in range(nz)], degT)
    lo, hi = ps.box
    Zp = ps.lift(lo + (hi - lo) * _sobol(ps.n, 7, n_points))
    M = monomial_matrix(Zp, monomials(nz, degT))
    obj = 0
    for i, t in enumerate(ts):
        u = next(iter(t.parts))
        w = R[i](Zp)
        obj = obj + (w @ M) @ u.var / len(Zp)
    prog.solve(cp.Minimize(obj), solver=solver)
    # interior-point Gram matrices sit on the boundary of the cone: add delta m^T m to every t_i (delta I to every
    # Gram matrix of the |dV/dz_i| certificates), with delta above what the exactness check needs
    checks_ = prog.check()
    delta = 2.0 * max((c.n_basis * c.max_residual - c.min_eig for c in checks_), default=0.0)
    delta = max(delta, 0.0) + 1e-9 * max((t.value().max_abs_coefficient() for t in ts), default=1.0)
    mm = sum((Poly({tuple(2 * k for k in e): 1.0}, nz) for e in monomials(nz, degT // 2)), Poly({}, nz))
    out = [t.value() + mm * delta for t in ts]
    return out, [GramCheck(c.name, c.n_basis, c.min_eig + delta, c.max_residual, c.multiplier_shift) for c in checks_]
