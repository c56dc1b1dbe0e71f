"""Region of attraction of a saturated closed loop by LMIs: a quadratic ``V``, the generalized sector condition of the
saturation and a bounded nonlinear remainder (one quadratic bound per component), one small SDP per remainder box.

Loop form (:class:`SaturatedLoop`)
----------------------------------
``X' = F(X, sat(K (X - X_e)))``: the plant's own right-hand side ``F`` with the input deviation ``w`` (the channels
fed back) saturated to ``[u_lo, u_hi]`` (``u_lo < 0 < u_hi``, ``+-inf`` for none). :func:`glidectl.saturated_loop`
extracts ``F``, ``K``, the levels and the equilibrium from a glidectl closed loop and checks, on random points of
the box, that ``F(X, sat(K (X - X_e)))`` *is* the loop's right-hand side.

In the scaled deviation ``x = D^-1 (X - X_e)`` (``D`` the half-widths of the largest box centred on the equilibrium
inside the loop's box) and scaled inputs ``w = s v``::

    x' = A x + B w + delta(x),    w = sat(K x) = K x - psi(K x),    delta = F(x, w) - A x - B w,

with ``A, B`` the exact (complex-step) Jacobians of ``F`` at the equilibrium.

Certificate (Tarbouriech, Garcia, Gomes da Silva & Queinnec 2011, Prop. 3.1 / Hu & Lin 2001, with a remainder)
----------------------------------------------------------------------------------------------------------------
*Generalized sector condition* (Tarbouriech et al. 2011, Lemma 1.6): if ``-a_i <= (K_i - G_i) x <= b_i`` then
``psi_i (psi_i - G_i x) <= 0``; on an ellipsoid (symmetric) the condition is ``|(K_i - G_i) x| <= u0_i =
min(a_i, b_i)``. *Remainder*: ``delta_j(x)^2 <= x' Q_j x`` on a box ``|x_k| <= b_k`` (below). With ``W = P^-1``,
``S = T^-1`` (diagonal), ``Z = G W``, ``R_j' R_j = Q_j`` and multipliers ``nu_j > 0`` (``2 x'P delta <= sum_j nu_j
(Px)_j^2 + delta_j^2 / nu_j``), ``dV/dt < 0`` on ``E = {x' P x <= 1}`` minus the origin follows from::

    [ (A+BK) W + W (A+BK)' + N    -B_s S + Z'    (R_1 W)' ... (R_p W)'   ]
    [            *                   -2 S              0                 ]  <  0,     N = diag(nu_j),
    [            *                     *        -diag(nu_1 I, ..., nu_p I)]

    [ W                 (K_i W - Z_i)' ]
    [ K_i W - Z_i            u0_i^2    ]  >= 0  (each saturating channel: E inside the sector region),

    W_kk <= b_k^2 <= 1   (E inside the remainder box, itself inside the box),

(Schur complements of ``sum_j W Q_j W / nu_j``). *State-dependent limits*
(:class:`~glidectl.models.saturated_loop.AffineLimit`, the actuators' range and rate): with ``w_i = clip(K_i x,
max_l(a_l x + b_l), min_l(a_l x + b_l))`` and ``psi_i = K_i x - w_i``, ``psi_i (psi_i - G_i x) <= 0`` still holds
where ``|(K_i - a_l - G_i) x| <= |b_l|`` for every limit ``l`` of channel ``i`` (the constant levels are limits with
``a_l = 0``), so each limit adds a region block like the one above, with ``K_i - a_l`` and ``b_l^2``. ``E`` is then
contractive, hence invariant, inside the box and in
the region of attraction. For a fixed remainder box this is one SDP maximizing ``log det W`` (volume) or, with a
given shape ``P0``, the largest ``c`` with ``W = c P0^-1``. The box is ``b = min(1, rho beta)``: ``rho`` is searched
on a geometric grid refined by golden section, and ``beta`` (the box's shape) is the unit box in the first round
and the best ellipsoid's extents in the next ones (``rounds``). Each SDP is solved in ``W = rho^2 B Wt B``,
``B = diag(beta)``, so that its unknowns are of order one.

Remainder bound (what is and is not rigorous)
---------------------------------------------
``delta_j`` vanishes with its gradient at 0, so by Taylor's theorem (mean-value form) ``delta_j(xi) = (1/2) xi' H_j
xi`` with the Hessian ``H_j`` of ``F_j`` at a point of the segment from 0 to ``xi = (x, w)``. On the convex set
``C = {|x_k| <= b_k} x {w_i between its levels, |w_i| <= r_i}`` (``r_i`` of :func:`_input_reach`), which contains those
segments, ``|delta_j| <= sum_l c_jl |xi_l|`` with ``c_jl = (1/2) sum_k Hmax_jkl b_k`` (``Hmax`` the entrywise maximum of
``|H_j|`` over ``C``, ``b`` extended by the input bounds); Cauchy-Schwarz and ``w_i^2 <= (K_i x)^2 + sum_l (a_l x)^2``
(a clipped input is either ``K_i x`` in magnitude or at most ``|a_l x|``, ``b_l`` having the sign of the side it limits;
the sum runs over the limits whose level changes sign somewhere in the box, ``sum_k |a_lk| b_k > |b_l|``: the others
clip towards 0) then give ``delta_j^2 <= x' Q_j x`` with ``Q_j = |c_j|_1 (diag(c_j,x) + K' diag(c_j,w) K + sum_l
c_j,w(l) a_l a_l')``.

``Hmax`` is the maximum over dense samples of ``C`` (corners included; Hessians by central differences of
complex-step Jacobians) times ``hessian_margin`` (default 1.5): a sampled bound with a safety factor, **not** an
interval enclosure. The certificate is therefore sound up to that bound, and every certificate is also verified a
posteriori on the true saturated loop (:class:`EllipsoidVerification`): the assembled LMI's eigenvalues in floating
point, the region blocks, the remainder bound on dense samples of ``E``, sampled true ``dV/dt < 0`` in ``E`` and on
its boundary, and simulated convergence from boundary points. ``certified`` reports those checks.

Shared with the robust certificate
----------------------------------
The scaling with a given ``D`` (:func:`scale_loop`), the search over remainder boxes (:func:`ellipsoid_search`), the
back-off (:func:`back_off`) and the verification (:func:`verify_ellipsoid`) also serve
:func:`glidectl.roa.robust.certify_roa_family`, whose program has one decrease LMI per corner of a box of uncertain
coefficients, with common multipliers and one common slack for the remainder terms (:func:`_vertex_program`), and
a remainder bound with a term linear in ``(x, w)``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np
from scipy.special import gammaln

from .. import checks
from ..analysis.measure import MIN_SOBOL_HITS, unit_sobol
from ..batch import integrate_batch
from ..derivatives import COMPLEX_STEP, jacobians, partial_derivative
from ..errors import ArgumentError, ArgumentTypeError, ModelError, SolverError
from ..models.saturated_loop import (  # noqa: F401 (held_motion, held_points: re-exported, the loop's old home)
    SaturatedLoop,
    at_held_values,
    held_motion,
    held_points,
    saturate,
)
from .blas_threads import pinned_blas
from .extent import Extent
from .sdp_solvers import DEFAULT_SOLVER, MOMENT, check_solver, inaccuracy_checked, solver_argument, solver_options

__all__ = ["EllipsoidCertificate", "EllipsoidSearch", "EllipsoidSolution", "EllipsoidVerification", "Remainder",
           "SaturatedLoop", "ScaledLoop", "back_off", "certify_roa_lmi", "ellipsoid_search", "scale_loop",
           "search_options", "verify_ellipsoid"]


# --------------------------------------------------------------------------------------------- scaled problem
@dataclass(frozen=True)
class ScaledLoop:
    """A :class:`SaturatedLoop` in the scaled deviation ``x = D^-1 (X - X_e)_f`` and scaled inputs ``w = v / s``
    (module docstring), what the programs and the checks of this module work on (:func:`scale_loop`).

    Attributes
    ----------
    f : ndarray of int
        The free states' indices.
    d : ndarray, shape (nf,)
        Their half-widths ``D`` (state units).
    s : ndarray, shape (m,)
        Input scales (the fed-back channels' units).
    A, B : ndarray
        Exact Jacobians of the scaled ``F`` at the equilibrium, ``(nf, nf)`` and ``(nf, m)`` (per time unit).
    K : ndarray, shape (m, nf)
        The scaled gain.
    lo, hi : ndarray, shape (m,)
        The scaled constant levels.
    F : callable
        Scaled ``F(x, w)`` (free components), batch-capable and complex-safe.
    truth : callable
        The scaled true loop ``x -> x'``.
    feedback : callable
        The scaled saturated inputs ``w(x)``, every limit applied.
    lim_ch : ndarray of int, shape (L,)
        The channel of each state-dependent limit.
    lim_a : ndarray, shape (L, nf)
        Its scaled gain.
    lim_b : ndarray, shape (L,)
        Its scaled, signed value at the equilibrium.
    """

    f: np.ndarray
    d: np.ndarray
    s: np.ndarray
    A: np.ndarray
    B: np.ndarray
    K: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    F: Callable[[np.ndarray, np.ndarray], np.ndarray]
    truth: Callable[[np.ndarray], np.ndarray]
    feedback: Callable[[np.ndarray], np.ndarray]
    lim_ch: np.ndarray
    lim_a: np.ndarray
    lim_b: np.ndarray

    @property
    def sat(self) -> np.ndarray:
        """Channels with a finite constant level or a state-dependent limit (those with a sector condition)."""
        has = np.isfinite(self.lo) | np.isfinite(self.hi)
        has[self.lim_ch] = True
        return np.flatnonzero(has)

    def limits_of(self, i: int) -> list[tuple[np.ndarray, float]]:
        """``(a_l, |b_l|)`` of channel ``i``'s region blocks: its constant level (``a = 0``, ``min(-lo, hi)``) when
        finite, then its state-dependent limits."""
        nf = self.A.shape[0]
        out = []
        u0 = float(min(-self.lo[i], self.hi[i]))
        if math.isfinite(u0):
            out.append((np.zeros(nf), u0))
        out += [(self.lim_a[k], abs(float(self.lim_b[k]))) for k in np.flatnonzero(self.lim_ch == i)]
        return out


def scale_loop(sl: SaturatedLoop, d: Any = None) -> ScaledLoop:
    """The loop in the scaled deviation and inputs of the module docstring, with its exact linearization.

    Parameters
    ----------
    sl : SaturatedLoop
        The loop, at its equilibrium.
    d : array_like, shape (nf,), optional
        Half-widths ``D`` of the free states (state units, > 0, ``X_e +- D`` inside the loop's box). Default: those
        of the largest box centred on the equilibrium inside the loop's box. A family of loops scaled alike (the
        robust certificate, :mod:`glidectl.roa.robust`) gives one ``D`` to every member.

    Returns
    -------
    ScaledLoop

    Raises
    ------
    ArgumentError
        If ``d`` has the wrong shape, is not positive, or ``X_e +- D`` leaves the box.
    ModelError
        If the linearization is not finite, or the equilibrium is not one (``F(X_e, 0) != 0``).
    """
    f = np.array(sl.free)
    xe = sl.equilibrium
    lo, hi = sl.box
    if d is None:
        d = np.minimum(xe - lo, hi - xe)[f]
    else:
        d = checks.array("d", d, shape=(len(f),))
        if not (np.all(d > 0) and np.all(xe[f] - d >= lo[f]) and np.all(xe[f] + d <= hi[f])):
            raise ArgumentError(f"the half-widths d = {d.tolist()} must be positive with x_e +- d inside the box of "
                                f"'{sl.name}'")
    Kd = sl.K[:, f] * d
    u0 = np.minimum(-sl.u_lo, sl.u_hi)
    s = np.minimum(u0, np.sum(np.abs(Kd), axis=1))
    s = np.where(s > 0, s, 1.0)

    def X_of(x: np.ndarray) -> np.ndarray:
        X = np.broadcast_to(xe, (*x.shape[:-1], sl.n)).astype(x.dtype).copy()
        X[..., f] = xe[f] + d * x
        return X

    def F(x: np.ndarray, w: np.ndarray) -> np.ndarray:
        return np.asarray(sl.plant_rhs(X_of(x), w * s))[..., f] / d

    def truth(x: np.ndarray) -> np.ndarray:
        return np.asarray(sl.rhs(X_of(x)))[..., f] / d

    def feedback(x: np.ndarray) -> np.ndarray:
        return np.asarray(sl.feedback(X_of(x))) / s

    nf, m = len(f), sl.n_feedback
    with np.errstate(all="ignore"):
        F0 = F(np.zeros((1, nf)), np.zeros((1, m)))
    A, B = jacobians(lambda x, w: F(np.asarray(x)[None, :], np.asarray(w)[None, :])[0], np.zeros(nf), np.zeros(m))
    if not np.all(np.isfinite(A)) or not np.all(np.isfinite(B)):
        raise ModelError(f"the linearization of '{sl.name}' at its equilibrium is not finite")
    if np.max(np.abs(F0)) > 1e-8 * max(1.0, float(np.max(np.abs(A)))):
        raise ModelError(f"the equilibrium of '{sl.name}' is not one: scaled |x'| = {np.max(np.abs(F0)):.3g} there")
    ch = np.array([q.channel for q in sl.limits], dtype=int)
    la = np.array([q.a[f] * d / s[q.channel] for q in sl.limits]).reshape(len(ch), nf)
    lb = np.array([q.b / s[q.channel] for q in sl.limits])
    return ScaledLoop(f, d, s, A, B, Kd / s[:, None], sl.u_lo / s, sl.u_hi / s, F, truth, feedback, ch, la, lb)


def _hessians(sc: ScaledLoop, beta: np.ndarray, n_samples: int, rho_max: float, seed: int,
              step: float = 1e-4) -> tuple[np.ndarray, np.ndarray]:
    """Sorted levels ``t`` and the running entrywise maximum over samples of ``|Hessian of F_j|`` (shape
    ``(N, nf, q, q)``, ``q = nf + m``): row ``k`` bounds ``|H_j|`` on the samples of ``C(t_k)``, the box
    ``|x_i| <= min(1, t beta_i)`` times the inputs ``w_i`` within their levels and ``|w_i| <= t r_i``
    (:func:`_input_reach`)
    (``t`` half uniform in ``[0, rho_max]``, half log-uniform in ``[1e-3, 1] rho_max``; a quarter at corners)."""
    nf, m = sc.A.shape[0], sc.B.shape[1]
    rng = np.random.default_rng(seed)
    t = rho_max * rng.random(n_samples)
    t[::2] = rho_max * 10.0 ** (-3.0 * rng.random(t[::2].size))          # half log-uniform: small boxes too
    t = np.sort(t)
    u = rng.uniform(-1.0, 1.0, (n_samples, nf))
    u[: n_samples // 4] = np.sign(u[: n_samples // 4])                     # a quarter at corners
    x = np.clip(t[:, None] * beta * u, -1.0, 1.0)
    kb = _input_reach(sc, beta)
    wl = np.maximum(sc.lo, -kb * t[:, None]) * (1 - 1e-3)
    wh = np.minimum(sc.hi, kb * t[:, None]) * (1 - 1e-3)
    w = wl + (wh - wl) * rng.random((n_samples, m))
    xi = np.concatenate([x, w], axis=1)
    q = nf + m
    def jac(z: np.ndarray) -> np.ndarray:      # (N, nf, q), complex step
        out = np.empty((z.shape[0], nf, q))
        for k in range(q):
            out[:, :, k] = partial_derivative(lambda Z: sc.F(Z[:, :nf], Z[:, nf:]), z, k, COMPLEX_STEP)
        return out

    H = np.empty((n_samples, nf, q, q))
    with np.errstate(all="ignore"):
        for k in range(q):
            e = np.zeros(q)
            e[k] = step
            H[:, :, :, k] = (jac(xi + e) - jac(xi - e)) / (2 * step)
    if not np.all(np.isfinite(H)):
        raise ModelError("the Hessian of the loop's right-hand side is not finite on the box (the box reaches a "
                         "singularity of the model: shrink it)")
    Habs = 0.5 * np.abs(H + np.swapaxes(H, 2, 3))
    return t, np.maximum.accumulate(Habs, axis=0)


def _crossing_limits(sc: ScaledLoop, b: np.ndarray) -> np.ndarray:
    """Indices of the state-dependent limits whose level ``a_l x + b_l`` changes sign on the box ``|x_k| <= b_k``
    (``sum_k |a_lk| b_k > |b_l|``): only they can clip an input to a value larger in magnitude than ``K_i x``."""
    return np.flatnonzero(np.abs(sc.lim_a) @ b > np.abs(sc.lim_b)) if len(sc.lim_b) else np.zeros(0, dtype=int)


def _input_reach(sc: ScaledLoop, b: np.ndarray) -> np.ndarray:
    """``r_i = sum_k |K_ik| b_k`` plus, for a limit ``l`` of channel ``i`` that changes sign on the box
    (:func:`_crossing_limits`), up to ``sum_k |a_lk| b_k``: ``|w_i| <= r_i`` on the box ``|x_k| <= b_k``, however the
    inputs are clipped (module docstring)."""
    r = np.abs(sc.K) @ b
    for k in _crossing_limits(sc, b):
        i = sc.lim_ch[k]
        r[i] = max(r[i], float(np.abs(sc.K[i]) @ b + np.abs(sc.lim_a[k]) @ b))
    return r


@dataclass(frozen=True)
class Remainder:
    """Remainder bound on the box ``|x_k| <= b_k`` (scaled): ``delta_j^2 <= x' Q_j x``, ``R_j' R_j = Q_j``.

    Attributes
    ----------
    b : ndarray, shape (nf,)
        Half-widths of the box where it holds (scaled).
    Q, R : ndarray, shape (nf, nf, nf)
        The forms ``Q_j`` and their symmetric square roots ``R_j``.
    """

    b: np.ndarray
    Q: np.ndarray
    R: np.ndarray


def _remainder(t: np.ndarray, Hc: np.ndarray, sc: ScaledLoop, beta: np.ndarray, rho: float,
               margin: float, linear: np.ndarray | None = None) -> Remainder:
    """The bound of the module docstring on the box ``b = min(1, rho beta)``: ``|delta_j| <= sum_l c_jl |xi_l|``
    with ``c_jl = (1/2) sum_k Hmax_jkl b_k`` (``b`` extended by the input bounds) plus ``linear_jl`` when given (a
    term linear in ``xi = (x, w)``: the robust certificate's bound on how far ``[A B]`` is from the interpolation of
    its vertex values), then Cauchy-Schwarz ``delta_j^2 <= |c_j|_1 sum_l c_jl xi_l^2`` and ``w_i^2 <= (K_i x)^2 +
    sum_l (a_l x)^2``."""
    nf = sc.A.shape[0]
    k = int(np.searchsorted(t, rho, side="right")) - 1
    Hm = margin * (Hc[k] if k >= 0 else np.zeros(Hc.shape[1:]))
    b = np.minimum(1.0, rho * beta)
    ub = np.maximum(-sc.lo, sc.hi)
    bw = np.minimum(ub, _input_reach(sc, b))
    crossing = _crossing_limits(sc, b)
    bx = np.concatenate([b, bw])
    c = 0.5 * np.einsum("jkl,k->jl", Hm, bx)                      # (nf, q)
    if linear is not None:
        c = c + linear
    Q = np.empty((nf, nf, nf))
    R = np.empty((nf, nf, nf))
    for j in range(nf):
        Qw = sc.K.T @ np.diag(c[j, nf:]) @ sc.K
        for k in crossing:
            Qw = Qw + c[j, nf + sc.lim_ch[k]] * np.outer(sc.lim_a[k], sc.lim_a[k])
        Qj = np.sum(c[j]) * (np.diag(c[j, :nf]) + Qw)
        Qj = 0.5 * (Qj + Qj.T)
        lam, U = np.linalg.eigh(Qj)
        Q[j] = Qj
        R[j] = (U * np.sqrt(np.maximum(lam, 0.0))) @ U.T
    return Remainder(b, Q, R)


@dataclass
class _Program:
    prob: cp.Problem
    W: Any
    c: Any
    S: Any
    Z: Any
    nu: Any
    R: list[Any]
    bb: Any
    uu: Any
    p_idx: np.ndarray
    sat: np.ndarray


def _program(sc: ScaledLoop, p_idx: np.ndarray, shape_W0: np.ndarray | None, beta: np.ndarray) -> _Program:
    """The SDP of the module docstring for the remainder box ``b = min(1, rho beta)``, in ``Wt`` with
    ``W = rho^2 B Wt B``, ``B = diag(beta)`` (congruence by ``diag(B^-1, I, I) / rho``: the unknowns are of order 1
    whatever ``rho`` and however elongated the ellipsoid): ``A + BK``, ``B_s`` and ``K`` become ``B^-1 (A + BK) B``,
    ``B^-1 B_s``, ``K B``; the box is ``Wt_ii <= b_i^2 / (rho beta_i)^2`` and the region blocks (one per level or
    limit of a channel, :meth:`ScaledLoop.limits_of`) have ``u0^2 / rho^2``, written with their off-diagonal scaled by
    ``rho / u0`` (the parameter ``uu``) so that every block is of order one. Parameters: ``R_j B`` (remainder
    factors), ``bb``, ``uu``."""
    nf = sc.A.shape[0]
    sat = sc.sat
    ms, p = len(sat), len(p_idx)
    Bi = 1.0 / beta
    Acl = Bi[:, None] * (sc.A + sc.B @ sc.K) * beta[None, :]
    Bs = Bi[:, None] * sc.B[:, sat]
    Kt = sc.K * beta[None, :]
    if shape_W0 is None:
        W = cp.Variable((nf, nf), symmetric=True)
        c = None
    else:
        c = cp.Variable(nonneg=True)
        W = c * (Bi[:, None] * shape_W0 * Bi[None, :])
    s_var = cp.Variable(ms) if ms else None
    Z = cp.Variable((ms, nf)) if ms else None
    nu = cp.Variable(p) if p else None
    Rp = [cp.Parameter((nf, nf)) for _ in range(p)]
    bb = cp.Parameter(nf, nonneg=True)
    blocks = [(a, i, al * beta) for a, i in enumerate(sat) for al, _ in sc.limits_of(i)]
    uu = cp.Parameter(len(blocks), nonneg=True) if blocks else None
    eta = 1e-7 * max(1.0, float(np.linalg.norm(Acl, 2))) * cp.trace(W) / nf
    Nmat = 0
    if p:
        E = np.zeros((nf, p))
        E[p_idx, np.arange(p)] = Bi[p_idx]
        Nmat = E @ cp.diag(nu) @ E.T
    top = Acl @ W + W @ Acl.T + Nmat
    rows = [[top]]
    if ms:
        S = cp.diag(s_var)
        off = -Bs @ S + Z.T
        rows[0].append(off)
        rows.append([off.T, -2 * S])
    for j in range(p):
        rows[0].append((Rp[j] @ W).T)
    for r_i in range(1, len(rows)):
        rows[r_i] += [np.zeros((ms, nf))] * p
    for j in range(p):
        row = [Rp[j] @ W]
        if ms:
            row.append(np.zeros((nf, ms)))
        row += [(-nu[k] * np.eye(nf) if k == j else np.zeros((nf, nf))) for k in range(p)]
        rows.append(row)
    L = cp.bmat(rows)
    size = nf + ms + nf * p
    cons = [0.5 * (L + L.T) + eta * np.eye(size) << 0, cp.diag(W) <= bb]
    for r, (a, i, alt) in enumerate(blocks):      # [W, v'; v, u0^2] >= 0, as [W, v'/u0; v/u0, 1] >= 0
        v = uu[r] * ((Kt[i] - alt)[None, :] @ W - Z[a:a + 1, :])
        blk = cp.bmat([[W, v.T], [v, np.ones((1, 1))]])
        cons.append(0.5 * (blk + blk.T) >> 0)
    if shape_W0 is None:
        cons.append(W >> 0)
        obj = cp.Maximize(cp.log_det(W))
    else:
        obj = cp.Maximize(c)
    return _Program(cp.Problem(obj, cons), W, c, s_var, Z, nu, Rp, bb, uu, p_idx, sat)


def _vertex_program(sc: ScaledLoop, vertices: Sequence[ScaledLoop], p_idx: np.ndarray,
                    beta: np.ndarray) -> _Program:
    """The SDP of :func:`_program` (free shape) with one decrease LMI per vertex system ``(A_v, B_v)`` and the gain,
    levels, limits and remainder of ``sc``, in the slack form: one common ``Y >= sum_j W R_j' R_j W / nu_j``
    (``[Y, (R_j W)'; R_j W, nu_j I] >= 0``, a single block) and per vertex the small block ``[sym((A_v + B_v K) W) +
    N + Y, -B_v,s S + Z'; *, -2 S] < 0``. By Schur complements each vertex block with the slack implies the vertex's
    decrease LMI of :func:`_program`; the per-vertex remainder columns are not repeated (stacking them per vertex,
    even for one vertex listed twice, stops Clarabel with a numerical error). The same scaling ``W = rho^2 B Wt B``
    and parameters as :func:`_program`."""
    nf = sc.A.shape[0]
    sat = sc.sat
    ms, p = len(sat), len(p_idx)
    Bi = 1.0 / beta
    Kt = sc.K * beta[None, :]
    W = cp.Variable((nf, nf), symmetric=True)
    s_var = cp.Variable(ms) if ms else None
    Z = cp.Variable((ms, nf)) if ms else None
    nu = cp.Variable(p) if p else None
    Rp = [cp.Parameter((nf, nf)) for _ in range(p)]
    bb = cp.Parameter(nf, nonneg=True)
    blocks = [(a, i, al * beta) for a, i in enumerate(sat) for al, _ in sc.limits_of(i)]
    uu = cp.Parameter(len(blocks), nonneg=True) if blocks else None
    cons = [cp.diag(W) <= bb, W >> 0]
    common: Any = 0
    if p:
        E = np.zeros((nf, p))
        E[p_idx, np.arange(p)] = Bi[p_idx]
        Y = cp.Variable((nf, nf), symmetric=True)
        common = E @ cp.diag(nu) @ E.T + Y
        rows = [[Y] + [(Rp[j] @ W).T for j in range(p)]]
        rows += [[Rp[j] @ W] + [(nu[k] * np.eye(nf) if k == j else np.zeros((nf, nf))) for k in range(p)]
                 for j in range(p)]
        Ly = cp.bmat(rows)
        cons.append(0.5 * (Ly + Ly.T) >> 0)
    for v in vertices:
        Acl = Bi[:, None] * (v.A + v.B @ sc.K) * beta[None, :]
        eta = 1e-7 * max(1.0, float(np.linalg.norm(Acl, 2))) * cp.trace(W) / nf
        top = Acl @ W + W @ Acl.T + common
        if ms:
            off = -(Bi[:, None] * v.B[:, sat]) @ cp.diag(s_var) + Z.T
            top = cp.bmat([[top, off], [off.T, -2 * cp.diag(s_var)]])
        cons.append(0.5 * (top + top.T) + eta * np.eye(nf + ms) << 0)
    for r, (a, i, alt) in enumerate(blocks):
        v_r = uu[r] * ((Kt[i] - alt)[None, :] @ W - Z[a:a + 1, :])
        blk = cp.bmat([[W, v_r.T], [v_r, np.ones((1, 1))]])
        cons.append(0.5 * (blk + blk.T) >> 0)
    return _Program(cp.Problem(cp.Maximize(cp.log_det(W)), cons), W, None, s_var, Z, nu, Rp, bb, uu, p_idx, sat)


def _lmi_numeric(sc: ScaledLoop, W: np.ndarray, s: np.ndarray, Z: np.ndarray, nu: np.ndarray, R: np.ndarray,
                 p_idx: np.ndarray, vertices: Sequence[ScaledLoop] | None = None) -> tuple[float, float]:
    """Largest eigenvalue of the assembled decrease LMI (of each vertex system, with ``sc``'s gain, when
    ``vertices`` are given) and smallest of the region blocks, in floating point."""
    sat = sc.sat
    lmax = max(_decrease_max_eig(v.A, v.B, sc.K, sat, W, s, Z, nu, R, p_idx) for v in (vertices or [sc]))
    rmin = math.inf
    for a, i in enumerate(sat):
        for al, u0 in sc.limits_of(i):
            v = (sc.K[i] - al) @ W - Z[a]
            blk = np.block([[W, v[:, None]], [v[None, :], np.array([[u0**2]])]])
            rmin = min(rmin, float(np.min(np.linalg.eigvalsh(blk))) / max(1.0, u0**2))
    return lmax, rmin


def _decrease_max_eig(A: np.ndarray, B: np.ndarray, K: np.ndarray, sat: np.ndarray, W: np.ndarray, s: np.ndarray,
                      Z: np.ndarray, nu: np.ndarray, R: np.ndarray, p_idx: np.ndarray) -> float:
    """Largest eigenvalue of the decrease LMI of the module docstring for ``(A, B, K)``, assembled in floating
    point."""
    nf = W.shape[0]
    ms, p = len(sat), len(p_idx)
    Acl = A + B @ K
    size = nf + ms + nf * p
    L = np.zeros((size, size))
    N = np.zeros((nf, nf))
    N[p_idx, p_idx] = nu
    L[:nf, :nf] = Acl @ W + W @ Acl.T + N
    if ms:
        off = -B[:, sat] @ np.diag(s) + Z.T
        L[:nf, nf:nf + ms] = off
        L[nf:nf + ms, :nf] = off.T
        L[nf:nf + ms, nf:nf + ms] = -2 * np.diag(s)
    for k, j in enumerate(p_idx):
        a = nf + ms + k * nf
        L[a:a + nf, :nf] = R[j] @ W
        L[:nf, a:a + nf] = (R[j] @ W).T
        L[a:a + nf, a:a + nf] = -nu[k] * np.eye(nf)
    return float(np.max(np.linalg.eigvalsh(0.5 * (L + L.T))))


# --------------------------------------------------------------------------------------------- certificate
@dataclass(frozen=True)
class EllipsoidVerification:
    """A-posteriori checks of an :class:`EllipsoidCertificate` (all must pass for ``certified``).

    Attributes
    ----------
    lmi_max_eig : float
        Largest eigenvalue of the assembled decrease LMI at the certified (backed-off) solution, in floating point
        (must be < 0; scaled units).
    region_min_eig : float
        Smallest eigenvalue of the sector-region blocks, relative to ``max(1, u0^2)`` (must be >= 0; ``inf``
        without saturating channels).
    box_max : float
        Largest ``W_ii`` (must be <= 1: the ellipsoid is inside the box).
    remainder_ratio : float
        Largest ``|delta_j(x)| / (gamma_j |x|)`` over dense samples of the ellipsoid (must be <= 1: the remainder
        bound holds there; 0 when the loop has no remainder).
    n_sampled : int
        Points of the ellipsoid (inside and on the boundary) where ``dV/dt`` of the true loop was evaluated.
    max_Vdot : float
        Largest ``dV/dt / |x|^2`` there (scaled units, per time unit of the loop; must be < 0).
    n_simulated, n_converged : int
        Simulations of the true loop from boundary points, and those that converged to the equilibrium.
    horizon : float
        Their length (time unit of the loop).
    """

    lmi_max_eig: float
    region_min_eig: float
    box_max: float
    remainder_ratio: float
    n_sampled: int
    max_Vdot: float
    n_simulated: int
    n_converged: int
    horizon: float

    @property
    def passed(self) -> bool:
        return bool(self.lmi_max_eig < 0 and self.region_min_eig >= -1e-9 and self.box_max <= 1 + 1e-9
                    and self.remainder_ratio <= 1 and self.n_sampled > 0 and self.max_Vdot < 0
                    and self.n_converged == self.n_simulated)

    @property
    def margins(self) -> dict[str, float]:
        """One entry per check, ``>= 1`` when it holds (``inf``/``0`` for pass/fail checks)."""
        inf = math.inf
        return {"LMI negative definite": inf if self.lmi_max_eig < 0 else 0.0,
                "sector region": inf if self.region_min_eig >= -1e-9 else 0.0,
                "inside the box": inf if self.box_max <= 1 + 1e-9 else 0.0,
                "remainder bound on samples": (1.0 / self.remainder_ratio if self.remainder_ratio > 0 else inf),
                "sampled dV/dt < 0": inf if self.n_sampled > 0 and self.max_Vdot < 0 else 0.0,
                "simulations converged": self.n_converged / self.n_simulated if self.n_simulated else 1.0}

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1."""
        return {k: v for k, v in self.margins.items() if not v >= 1 - 1e-9}

    def summary(self) -> str:
        """One line with every check."""
        return (f"LMI max eig {self.lmi_max_eig:.3g}, region min eig {self.region_min_eig:.3g}, box max "
                f"{self.box_max:.4g}, remainder ratio {self.remainder_ratio:.3g}, max dV/dt/|x|^2 on "
                f"{self.n_sampled} samples {self.max_Vdot:.3g}, simulations {self.n_converged}/{self.n_simulated} "
                f"converged in {self.horizon:g}")


@dataclass(frozen=True)
class EllipsoidCertificate:
    """Certified region of attraction ``{X : (X - X_e)_f' P (X - X_e)_f <= 1, X_held = X_e,held}`` of a
    :class:`SaturatedLoop` (``f`` the free states), from :func:`certify_roa_lmi`.

    It has the attributes and methods every region-of-attraction certificate has
    (:class:`~glidectl.roa.extent.Certificate`).

    Attributes
    ----------
    system : SaturatedLoop
        The loop certified.
    P : ndarray, shape (nf, nf)
        The quadratic form in the free states' own units (``V = dX' P dX``, certified level 1).
    G : ndarray, shape (ms, nf)
        Gain of the generalized sector condition (per saturating channel, input units per state unit).
    remainder : ndarray, shape (nf, nf, nf)
        ``Q_j`` of the remainder bound ``delta_j^2 <= x' Q_j x`` used (scaled coordinates ``x``; zero where the loop is
        exactly linear-saturated).
    remainder_box : ndarray, shape (nf,)
        Half-widths (free states' units) of the box about the equilibrium on which that bound holds (the ellipsoid
        lies in it).
    scale : ndarray, shape (nf,)
        Half-widths ``D`` of the free states (scaled ``x = (X - X_e) / D``).
    box : (ndarray, ndarray)
        The loop's box (all states).
    verification : EllipsoidVerification
    history : tuple of dict
        Per SDP: search round, ``rho``, remainder box, status, objective (``log sqrt det W`` of the scaled ``W``, or
        the level of a fixed shape) and solver time.
    solve_time, hessian_time, wall_time : float
        Total SDP solver time, time of the Hessian sampling, and wall time (s).
    method : str
        ``"lmi"``.
    provenance : str
    """

    system: SaturatedLoop = field(repr=False)
    P: np.ndarray = field(repr=False)
    G: np.ndarray = field(repr=False)
    remainder: np.ndarray = field(repr=False)
    remainder_box: np.ndarray = field(repr=False)
    scale: np.ndarray = field(repr=False)
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    verification: EllipsoidVerification = field(repr=False)
    history: tuple[dict[str, Any], ...] = field(repr=False)
    solve_time: float
    hessian_time: float
    wall_time: float
    method: str = "lmi"
    provenance: str = ""

    @property
    def certified(self) -> bool:
        """True only if every a-posteriori check passed (:class:`EllipsoidVerification`), as
        :attr:`glidectl.roa.certificate.ROACertificate.certified`."""
        return self.verification.passed

    @property
    def rho(self) -> float:
        """The certified level of ``V`` (1)."""
        return 1.0

    @property
    def rigorous(self) -> bool:
        """Whether the set is proved a region of attraction: only when the loop is exactly linear with saturated
        inputs (no remainder) and every check passed. With a remainder, its bound comes from sampled Hessians times
        a safety factor (module docstring), not an enclosure: the certificate is then sampled-sound, not proved."""
        return self.certified and not np.any(self.remainder)

    @property
    def in_box(self) -> bool:
        """Whether the certified set lies in :attr:`box`: always (the ellipsoid lies in its remainder box, itself in
        the box)."""
        return True

    def extent(self) -> Extent:
        """The certified interval along each state axis through the equilibrium (state units): ``x_e +- 1 /
        sqrt(P_kk)`` for a free state, ``x_e`` for a held one.

        Returns
        -------
        Extent
        """
        xe = np.asarray(self.system.equilibrium, dtype=float)
        lo, hi = xe.copy(), xe.copy()
        f = list(self.system.free)
        r = 1.0 / np.sqrt(np.diag(self.P))
        lo[f], hi[f] = xe[f] - r, xe[f] + r
        return Extent(self.state_names, lo, hi, xe, self.box, f"certified ({self.method})", self.rigorous)

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.system.state_names

    def _states(self, X: Any) -> np.ndarray:
        n = self.system.n
        X = np.atleast_2d(checks.array("X", X, finite=False))
        if X.ndim != 2 or X.shape[-1] != n:
            raise ArgumentError(f"X must hold states of dimension {n} ({', '.join(self.system.state_names)}), shape "
                                f"(N, {n}) or ({n},); got shape {np.shape(X)}")
        return X

    def value(self, X: Any) -> np.ndarray:
        """``V = dX_f' P dX_f`` at states ``X``.

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States in the loop's units.

        Returns
        -------
        ndarray, shape (N,)

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not numeric.
        ArgumentError
            If ``X`` has the wrong shape.
        """
        X = self._states(X)
        dX = (X - self.system.equilibrium)[:, list(self.system.free)]
        return np.einsum("ni,ij,nj->n", dX, self.P, dX)

    def contains(self, X: Any) -> np.ndarray:
        """Membership of the certified ellipsoid (held states at their equilibrium value, relative 1e-12).

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States; NaN or inf are outside.

        Returns
        -------
        ndarray of bool, shape (N,)

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not numeric.
        ArgumentError
            If ``X`` has the wrong shape.
        """
        X = self._states(X)
        ok = np.all(np.isfinite(X), axis=1)
        ok &= at_held_values(X, self.system.equilibrium, self.system.held)
        with np.errstate(all="ignore"):
            return ok & (np.nan_to_num(self.value(np.where(np.isfinite(X), X, 0.0)), nan=np.inf) <= 1.0)

    def volume(self, box: tuple[Any, Any] | None = None, n: int = 2**16, seed: int = 0,
               method: str = "auto") -> float:
        """Volume of the ellipsoid in the free states (product of their units): exact by default (it lies in the
        loop's box), an estimate of its intersection with another ``box``.

        In another box, ``method="sobol"`` counts the scrambled Sobol points inside (0 when none falls in a thin
        ellipsoid); ``method="directed"`` averages over ``n`` directions ``u = z / |z|``, ``z ~ N(0, P^-1)`` (angular
        central Gaussian, density ``det(P)^(1/2) (u' P u)^(-nf/2)`` relative to the uniform law on the sphere) the
        exact ray integral of the ellipsoid cut by the box::

            vol = |B^nf| / sqrt(det P) E[min(1, t(u)^2 u' P u)^(nf/2)],

        ``t(u)`` the distance from the equilibrium to the box along ``u`` and ``|B^nf| = pi^(nf/2) / Gamma(nf/2 + 1)``
        (exact when the box does not cut the ellipsoid; relative standard error ``std / (mean sqrt(n))`` of the
        averaged term otherwise; the box must contain the equilibrium). ``method="auto"`` keeps the Sobol number
        when at least 100 of its points are inside and takes the directed one otherwise (or the Sobol one if the box
        does not contain the equilibrium), as :meth:`glidectl.roa.certificate.ROACertificate.volume`.

        Parameters
        ----------
        box : (array_like, array_like), optional
            ``(lo, hi)`` over all states (held states ignored); default the loop's box (exact formula, any method).
        n : int
            Sobol points, or directions, for another box (>= 1).
        seed : int
            Their seed (>= 0).
        method : {"auto", "sobol", "directed"}
            The estimate in another box, as above.

        Returns
        -------
        float

        Raises
        ------
        ArgumentTypeError, ArgumentError
            For a bad ``box``, ``n``, ``seed`` or ``method``, or ``method="directed"`` with a box that does not
            contain the equilibrium.
        """
        method = checks.choice("method", method, ("auto", "sobol", "directed"))
        nf = self.P.shape[0]
        log_ball = 0.5 * nf * math.log(math.pi) - gammaln(0.5 * nf + 1) - 0.5 * np.linalg.slogdet(self.P)[1]
        if box is None:
            return float(math.exp(log_ball))
        if not isinstance(box, tuple | list) or len(box) != 2:
            raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({self.system.n},)")
        lo = checks.array("box lo", box[0], shape=(self.system.n,))
        hi = checks.array("box hi", box[1], shape=(self.system.n,))
        if np.any(lo >= hi):
            raise ArgumentError(f"box must have lo < hi in every state, got lo = {lo.tolist()}, hi = {hi.tolist()}")
        n = checks.integer("n", n, lo=1, hi=2**24)
        seed = checks.integer("seed", seed, lo=0)
        f = list(self.system.free)
        if method != "directed":
            X = np.tile(self.system.equilibrium, (n, 1))
            X[:, f] = lo[f] + (hi[f] - lo[f]) * unit_sobol(len(f), seed, n)
            inside = self.contains(X)
            sobol = float(np.prod(hi[f] - lo[f]) * np.mean(inside))
            if method == "sobol" or int(np.count_nonzero(inside)) >= MIN_SOBOL_HITS:
                return sobol
        xe = np.asarray(self.system.equilibrium, dtype=float)[f]
        a, b = lo[f] - xe, hi[f] - xe
        if np.any(a > 0) or np.any(b < 0):
            if method == "auto":
                return sobol
            raise ArgumentError(f"volume(method='directed') integrates along rays from the equilibrium "
                                f"{self.system.equilibrium.tolist()}, which must lie in the box (lo {lo.tolist()}, hi "
                                f"{hi.tolist()}): enlarge the box or use method='sobol'")
        return float(math.exp(log_ball) * np.mean(_ellipsoid_box_weights(self.P, a, b, n, seed)))

    @property
    def volume_fraction(self) -> float:
        """:meth:`volume` over the volume of the loop's box in the free states."""
        f = list(self.system.free)
        lo, hi = self.box
        return self.volume() / float(np.prod(hi[f] - lo[f]))

    def sample(self, n: int, seed: int = 0, *, boundary: bool = False) -> np.ndarray:
        """``n`` random states of the ellipsoid (uniform in it, or on its boundary), held states at equilibrium.

        Parameters
        ----------
        n : int
            Number of points (>= 1).
        seed : int
            Seed (>= 0).
        boundary : bool
            On the boundary ``V = 1`` instead of inside.

        Returns
        -------
        ndarray, shape (n, n_states)

        Raises
        ------
        ArgumentTypeError, ArgumentError
            For a bad ``n``, ``seed`` or ``boundary``.
        """
        n = checks.integer("n", n, lo=1, hi=2**24)
        seed = checks.integer("seed", seed, lo=0)
        boundary = checks.boolean("boundary", boundary)
        dX = _ellipsoid_points(np.linalg.inv(self.P), n, np.random.default_rng(seed), boundary)
        X = np.tile(self.system.equilibrium, (n, 1))
        X[:, list(self.system.free)] += dX
        return X

    def plot(self, ax: Any = None, dims: Any = (0, 1), n: int = 200) -> Any:
        """Draw the ellipsoid's slice through the equilibrium in the plane of two free states, within the box.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        dims : two state names or indices
            The plane (free states).
        n : int
            Points of the drawn boundary (>= 8).

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn into (angles in degrees).

        Raises
        ------
        GlidectlError
            For ``dims`` that are not two distinct free states, or ``n < 8``.
        """
        from ..plotting import plot_ellipsoid_certificate, style

        with style():
            return plot_ellipsoid_certificate(self, ax, dims=dims, n=n)


def _ellipsoid_box_weights(P: np.ndarray, a: np.ndarray, b: np.ndarray, n: int, seed: int) -> np.ndarray:
    """``min(1, t(u)^2 u' P u)^(nf/2)`` for ``n`` directions ``u`` of the angular central Gaussian ``N(0, P^-1)``,
    ``t(u)`` the largest ``t`` with ``a <= t u <= b`` (``a <= 0 <= b``): the volume of ``{x' P x <= 1}`` cut by the
    box ``[a, b]`` is the ellipsoid's times their mean (:meth:`EllipsoidCertificate.volume`)."""
    nf = P.shape[0]
    lam, Q = np.linalg.eigh(0.5 * (P + P.T))
    Z = np.random.default_rng([seed, 23]).standard_normal((n, nf)) @ (Q / np.sqrt(lam)).T
    Z /= np.linalg.norm(Z, axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.min(np.where(Z > 0, b / Z, np.where(Z < 0, a / Z, np.inf)), axis=1)
    q = np.einsum("ij,jk,ik->i", Z, P, Z)
    return np.minimum(1.0, t * t * q) ** (0.5 * nf)


def _ellipsoid_points(Winv: np.ndarray, n: int, rng: np.random.Generator, boundary: bool) -> np.ndarray:
    """Points ``L y`` with ``L L' = W`` (``W`` the inverse of P) and ``y`` uniform in (or on) the unit ball."""
    L = np.linalg.cholesky(0.5 * (Winv + Winv.T))
    y = rng.standard_normal((n, L.shape[0]))
    y /= np.linalg.norm(y, axis=1, keepdims=True)
    if not boundary:
        y *= rng.random((n, 1)) ** (1.0 / L.shape[0])
    return y @ L.T


@dataclass
class _Round:
    """One round of the remainder-box search: solves the SDP for a ``rho`` (cached in ``sols``, logged in
    ``history``)."""

    prog: _Program
    sc: ScaledLoop
    t: np.ndarray
    Hc: np.ndarray
    beta: np.ndarray
    margin: float
    solver: str
    W0: np.ndarray | None
    rnd: int
    sols: dict[float, tuple[float, dict[str, Any]]]
    history: list[dict[str, Any]]
    backoff: float = 0.0
    t_solve: float = 0.0
    vertices: Sequence[ScaledLoop] | None = None
    linear: np.ndarray | None = None
    clarabel_settings: dict[str, Any] | None = None

    def _solve_program(self) -> str:
        """Solve the program (by Clarabel with :attr:`clarabel_settings` added to its options, when given and the
        solver is Clarabel or its moment route); the status, or the solver error."""
        prog = self.prog
        if self.clarabel_settings is not None and self.solver in ("CLARABEL", MOMENT):
            solver, opts = "CLARABEL", {**solver_options("CLARABEL"), **self.clarabel_settings}
        else:
            solver, opts = solver_argument(self.solver), solver_options(self.solver)
        try:
            with inaccuracy_checked():      # an inaccurate solution is kept only if its LMIs hold (below)
                prog.prob.solve(solver=solver, **opts)
            return str(prog.prob.status)
        except cp.SolverError as exc:
            return f"solver error: {str(exc)[:60]}"

    def solve(self, rho: float) -> float:
        if rho in self.sols:
            return self.sols[rho][0]
        prog, sc, beta = self.prog, self.sc, self.beta
        nf = sc.A.shape[0]
        rem = _remainder(self.t, self.Hc, sc, beta, rho, self.margin, self.linear)
        for k, j in enumerate(prog.p_idx):
            prog.R[k].value = rem.R[j] * beta[None, :]
        prog.bb.value = (rem.b / (rho * beta)) ** 2
        if prog.uu is not None:
            prog.uu.value = rho / np.array([u0 for i in prog.sat for _, u0 in sc.limits_of(i)])

        t0 = time.perf_counter()
        status = self._solve_program()
        dt = time.perf_counter() - t0
        self.t_solve += dt
        ok = status in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) and prog.prob.value is not None \
            and bool(np.isfinite(prog.prob.value))
        sol: dict[str, Any] = {}
        obj = -math.inf
        if ok:
            r2 = rho * rho
            W = r2 * beta[:, None] * np.asarray(prog.W.value, float) * beta[None, :]
            W = 0.5 * (W + W.T)
            if np.linalg.eigvalsh(W)[0] > 0:
                obj = (0.5 * float(np.linalg.slogdet(W)[1]) if self.W0 is None
                       else float(np.trace(W) / np.trace(self.W0)))
                sol = {"W": W, "rem": rem,
                       "s": r2 * np.asarray(prog.S.value, float) if prog.S is not None else np.zeros(0),
                       "Z": (r2 * np.asarray(prog.Z.value, float) * beta[None, :] if prog.Z is not None
                             else np.zeros((0, nf))),
                       "nu": r2 * np.asarray(prog.nu.value, float) if prog.nu is not None else np.zeros(0)}
                # keep only solutions whose LMIs hold in floating point after the backoff (an inaccurate solve
                # may not)
                q = 1.0 - self.backoff
                lmax, rmin = _lmi_numeric(sc, q * W, q * sol["s"], q * sol["Z"], q * sol["nu"], rem.R, prog.p_idx,
                                          self.vertices)
                if not (lmax < 0 and rmin >= -1e-9 and np.max(np.diag(q * W) - rem.b**2) <= 1e-9):
                    status, obj, sol = f"{status} (rejected: LMI fails in floating point)", -math.inf, {}
        self.history.append({"round": self.rnd, "rho": rho, "box": np.minimum(1.0, rho * beta) * sc.d,
                             "status": status, "objective": obj, "time": dt})
        self.sols[rho] = (obj, sol)
        return obj


@pinned_blas
def certify_roa_lmi(system: Any, *, shape: Any = None,
                    hessian_margin: float = 1.5, n_hessian: int = 1024, n_radii: int = 8, refine: int = 5,
                    rounds: int = 6, round_gain: float = 0.1,
                    backoff: float = 0.01, n_verify: int = 4000, n_simulate: int = 32, horizon: float | None = None,
                    solver: str = DEFAULT_SOLVER, seed: int = 0) -> EllipsoidCertificate:
    """Largest certified ellipsoid of a saturated closed loop: quadratic ``V``, generalized sector condition and a
    per-component norm-bounded remainder (Tarbouriech et al. 2011, Prop. 3.1, with the remainder; see the module
    docstring for the LMIs and what the remainder bound rests on).

    Parameters
    ----------
    system : SaturatedLoop
        The loop, e.g. :func:`glidectl.saturated_loop` of a closed loop of this package (chapter-6 buoyancy and
        elevator loops, linear glide regulators saturated at the vehicle's pump rate, saturated state feedbacks).
        The ellipsoid lies in the largest box centred on the equilibrium inside the loop's box.
    shape : array_like (nf, nf), optional
        A fixed shape ``P0`` (symmetric positive definite, free states' units): the largest level ``c`` with
        ``{dX' P0 dX <= c}`` certified (the LMI analogue of the SOS fixed-V level problem). Default: the shape is
        free and ``log det`` (volume) is maximized.
    hessian_margin : float
        Safety factor (>= 1) on the sampled Hessian bound of the remainder.
    n_hessian : int
        Sample points for the Hessian bound (>= 16).
    n_radii, refine : int
        Sizes ``rho`` of the remainder box on the geometric grid (>= 2) and golden-section refinements (>= 0) of the
        best one, per round (one SDP each; a loop without remainder needs a single SDP).
    rounds : int
        Largest number of rounds of the search (>= 1): the first with a box shaped like the loop's box, the next
        ones shaped like the best ellipsoid so far.
    round_gain : float
        The search stops after a round that raised ``log sqrt det W`` (the log of the volume) by less than this
        (>= 0; 0.1: a volume gain under 10 %).
    backoff : float
        The certified ellipsoid is ``W = (1 - backoff) W*``, in ``[0, 0.5]``.
    n_verify, n_simulate : int
        Points of the ellipsoid where the true ``dV/dt`` and the remainder bound are checked (>= 1; half on the
        boundary), and simulations from boundary points (>= 0).
    horizon : float, optional
        Length of those simulations (default 25 slowest time constants of the linearization).
    solver : str
        An SDP solver of :func:`glidectl.roa.installed_sdp_solvers` (default ``"CVXOPT_MOMENT"``: programs with
        a Gram block of order 40 or more whose moment form is the smaller side by CVXOPT on that form, 2-5 times
        faster per program, the others by Clarabel; see :mod:`glidectl.roa.sdp_solvers`).
    seed : int
        Seed of every sampling (>= 0).

    Returns
    -------
    EllipsoidCertificate
        ``method = "lmi"``; ``certified`` says whether every a-posteriori check passed.

    Raises
    ------
    ArgumentTypeError
        If ``system`` is not a SaturatedLoop (the message says to use :func:`glidectl.saturated_loop`), or an
        option has the wrong type.
    ArgumentError
        If an option is out of range, or ``shape`` is not symmetric positive definite of the free states' size.
    ModelError
        If the linearized loop ``A + B K`` is not Hurwitz (unstable or marginal), the equilibrium is not one, or the
        Hessian is not finite on the box.
    SolverError
        If no SDP is feasible (no ellipsoid of the given shape, or none at all, is certified).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5")
    >>> ctrl = gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0)
    >>> sl = gc.saturated_loop(gc.closed_loop(ctrl))        # the pump saturates at its rate limit
    >>> cert = gc.certify_roa_lmi(sl, rounds=1, n_radii=4, refine=1, n_hessian=128, n_verify=500, n_simulate=4)
    >>> cert.certified, cert.method
    (True, 'lmi')
    """
    t_wall = time.perf_counter()
    if not isinstance(system, SaturatedLoop):
        raise ArgumentTypeError(f"certify_roa_lmi() needs a SaturatedLoop, got {type(system).__name__}: for a glidectl "
                                "closed loop pass gc.saturated_loop(loop) (it extracts F, K and the saturation "
                                "levels, and refuses loops of another form); polynomial loops without saturation "
                                "also go to gc.certify_roa (SOS path)")
    sl = system
    opts = search_options(hessian_margin=hessian_margin, n_hessian=n_hessian, n_radii=n_radii, refine=refine,
                          rounds=rounds, round_gain=round_gain, backoff=backoff, solver=solver, seed=seed)
    backoff, seed = opts["backoff"], opts["seed"]
    n_verify = checks.integer("n_verify", n_verify, lo=1, hi=2**22)
    n_simulate = checks.integer("n_simulate", n_simulate, lo=0, hi=2**16)
    horizon = None if horizon is None else checks.positive("horizon", horizon)
    sc = scale_loop(sl)
    nf = len(sc.f)
    W0 = None
    if shape is not None:
        P0 = checks.array("shape", shape, shape=(nf, nf))
        if not np.allclose(P0, P0.T, rtol=1e-10, atol=0) or np.linalg.eigvalsh(0.5 * (P0 + P0.T))[0] <= 0:
            raise ArgumentError("shape must be a symmetric positive definite matrix (the free states' P0)")
        W0 = np.linalg.inv(np.diag(sc.d) @ (0.5 * (P0 + P0.T)) @ np.diag(sc.d))
        W0 = 0.5 * (W0 + W0.T)
    Acl = sc.A + sc.B @ sc.K
    lam = np.linalg.eigvals(Acl)
    if not np.max(lam.real) < -1e-9 * max(1.0, float(np.max(np.abs(lam)))):
        raise ModelError(f"the linearized loop A + BK of '{sl.name}' is not exponentially stable (eigenvalues "
                         f"{np.round(lam, 6).tolist()}, per {sl.time_unit} in scaled states): no region of "
                         "attraction to certify; change the gain")
    search = ellipsoid_search(sc, shape_W0=W0, **opts)
    if not search.found:
        what = "of the given shape " if W0 is not None else ""
        raise SolverError(f"no ellipsoid {what}is certified for '{sl.name}': every SDP was infeasible or failed "
                          f"(statuses {sorted({h['status'] for h in search.history})}). "
                          + ("The shape P0 may not be a Lyapunov matrix of the linearized loop A + BK"
                             if W0 is not None else "The remainder bound leaves no feasible ellipsoid"))
    sol = back_off(sc, search.solution, search.p_idx, backoff)
    ver = verify_ellipsoid(sl, sc, sol, n_verify=n_verify, n_simulate=n_simulate, horizon=horizon, seed=seed)
    return EllipsoidCertificate(sl, sol.P, sol.G, sol.Q, sol.remainder.b * sc.d, sc.d.copy(), sl.box, ver,
                                search.history, search.solve_time, search.hessian_time,
                                time.perf_counter() - t_wall, "lmi", sl.provenance)


# --------------------------------------------------------------------------------------------- search, back-off
def search_options(*, hessian_margin: Any, n_hessian: Any, n_radii: Any, refine: Any, rounds: Any, round_gain: Any,
                   backoff: Any, solver: Any, seed: Any) -> dict[str, Any]:
    """The options of :func:`ellipsoid_search`, validated (their meaning: :func:`certify_roa_lmi`).

    Parameters
    ----------
    hessian_margin, n_hessian, n_radii, refine, rounds, round_gain, backoff, solver, seed
        As :func:`certify_roa_lmi`.

    Returns
    -------
    dict
        The keyword arguments of :func:`ellipsoid_search` (numbers as Python ``int``/``float``).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If an option has the wrong type or is out of range, or the solver is not installed.
    """
    check_solver(solver)
    return {"hessian_margin": checks.real("hessian_margin", hessian_margin, lo=1.0),
            "n_hessian": checks.integer("n_hessian", n_hessian, lo=16, hi=2**20),
            "n_radii": checks.integer("n_radii", n_radii, lo=2, hi=200),
            "refine": checks.integer("refine", refine, lo=0, hi=50),
            "rounds": checks.integer("rounds", rounds, lo=1, hi=20),
            "round_gain": checks.real("round_gain", round_gain, lo=0.0),
            "backoff": checks.real("backoff", backoff, lo=0.0, hi=0.5),
            "solver": solver, "seed": checks.integer("seed", seed, lo=0)}


@dataclass(frozen=True)
class EllipsoidSearch:
    """The best solution of the remainder-box search of :func:`ellipsoid_search`.

    Attributes
    ----------
    objective : float
        Its objective (``log sqrt det W``, or the level of a fixed shape; ``-inf`` when no SDP was feasible).
    solution : dict
        ``W`` (scaled), the remainder bound used (``rem``, a :class:`Remainder`), and the multipliers ``s``, ``Z``,
        ``nu`` (empty when nothing was feasible).
    p_idx : ndarray of int
        The components with a remainder term.
    history : tuple of dict
        Per SDP: search round, ``rho``, remainder box (state units), status, objective and solver time (s).
    solve_time, hessian_time : float
        Total SDP solver time and Hessian sampling time (s).
    """

    objective: float
    solution: dict[str, Any] = field(repr=False)
    p_idx: np.ndarray = field(repr=False)
    history: tuple[dict[str, Any], ...] = field(repr=False)
    solve_time: float
    hessian_time: float

    @property
    def found(self) -> bool:
        """Whether some SDP gave an ellipsoid."""
        return bool(np.isfinite(self.objective))


def ellipsoid_search(sc: ScaledLoop, *, shape_W0: np.ndarray | None = None,
                     vertices: Sequence[ScaledLoop] | None = None,
                     hessian_systems: Sequence[ScaledLoop] | None = None, linear: np.ndarray | None = None,
                     clarabel_settings: dict[str, Any] | None = None, hessian_margin: float, n_hessian: int,
                     n_radii: int, refine: int, rounds: int, round_gain: float, backoff: float, solver: str,
                     seed: int) -> EllipsoidSearch:
    """The search of :func:`certify_roa_lmi` for the largest ellipsoid: per round, the Hessian bound sampled on
    remainder boxes shaped by ``beta``, one SDP per remainder-box size ``rho`` (a geometric grid refined by golden
    section), then the next round's boxes shaped like the best ellipsoid, until a round gains less than
    ``round_gain``.

    Parameters
    ----------
    sc : ScaledLoop
        The scaled loop: its gain, levels, limits and remainder geometry; its ``(A, B)`` is the decrease LMI's unless
        ``vertices`` are given.
    shape_W0 : ndarray (nf, nf), optional
        A fixed shape (scaled ``W``): the largest multiple is searched (only without ``vertices``).
    vertices : sequence of ScaledLoop, optional
        Vertex systems: one decrease LMI per vertex ``(A_v, B_v)`` with ``sc``'s gain, a common ``W`` and
        multipliers, in the slack form (:func:`_vertex_program`); they must be scaled like ``sc`` (the same ``d``
        and ``s``).
    hessian_systems : sequence of ScaledLoop, optional
        The systems whose sampled Hessians are bounded together (entrywise maximum; default ``[sc]``).
    linear : ndarray (nf, nf + m), optional
        A term of the remainder bound linear in ``(x, w)`` (scaled, >= 0): ``|delta_j| <= sum_l (c_jl + linear_jl)
        |xi_l|``.
    clarabel_settings : dict, optional
        Clarabel settings (e.g. ``static_regularization_constant``) with which every program is solved by Clarabel
        when the solver is Clarabel or its moment route (every solution's LMIs are checked in floating point
        whatever solved it); default the solver's own settings.
    hessian_margin, n_hessian, n_radii, refine, rounds, round_gain, backoff, solver, seed
        As :func:`certify_roa_lmi` (validated by :func:`search_options`).

    Returns
    -------
    EllipsoidSearch

    Raises
    ------
    ArgumentError
        If both ``shape_W0`` and ``vertices`` are given.
    ModelError
        If a sampled Hessian is not finite.
    """
    if shape_W0 is not None and vertices is not None:
        raise ArgumentError("a fixed shape and vertex systems cannot be combined in one search")
    nf = len(sc.f)
    systems = [sc] if hessian_systems is None else list(hessian_systems)
    t_hess = t_solve = 0.0
    history: list[dict[str, Any]] = []
    best: tuple[float, dict[str, Any]] = (-math.inf, {})
    beta, rho0 = np.ones(nf), 1.0
    p_idx: np.ndarray | None = None
    for rnd in range(rounds):
        th = time.perf_counter()
        rho_max = min(1.0 / float(np.min(beta)), 50.0)       # beyond 1/min(beta) the remainder box is the box
        t, Hc = _hessians(systems[0], beta, n_hessian, rho_max, seed + rnd)
        for other in systems[1:]:                            # the same levels t: the same seed and rho_max
            Hc = np.maximum(Hc, _hessians(other, beta, n_hessian, rho_max, seed + rnd)[1])
        t_hess += time.perf_counter() - th
        if p_idx is None:
            # components with a remainder (the Hessian is rounding noise for exactly linear components)
            tiny = 1e-7 * max(1.0, float(np.max(np.abs(np.concatenate([sc.A, sc.B], axis=1)))))
            has = np.max(Hc[-1], axis=(1, 2)) > tiny
            if linear is not None:
                has |= np.max(linear, axis=1) > 0
            p_idx = np.flatnonzero(has)
        prog = _program(sc, p_idx, shape_W0, beta) if vertices is None else _vertex_program(sc, vertices, p_idx, beta)
        sols: dict[float, tuple[float, dict[str, Any]]] = {}
        ctx = _Round(prog, sc, t, Hc, beta, hessian_margin, solver, shape_W0, rnd, sols, history, backoff,
                     vertices=vertices, linear=linear, clarabel_settings=clarabel_settings)

        def solve(rho: float, ctx: _Round = ctx) -> float:
            return ctx.solve(rho)

        if len(p_idx) == 0:
            radii = [rho_max]
        elif rnd == 0:
            radii = list(rho_max * np.geomspace(1.0, 1e-3, n_radii))
        else:
            radii = list(np.geomspace(min(rho_max, 4.0 * rho0), 0.5 * rho0, n_radii))
        _search_radius(solve, radii, refine)
        t_solve += ctx.t_solve
        r_best = max(sols, key=lambda r: sols[r][0])
        gain = sols[r_best][0] - best[0]
        if sols[r_best][0] > best[0]:
            best = sols[r_best]
        if not np.isfinite(best[0]) or len(p_idx) == 0 or gain < round_gain:
            break
        # next round: remainder boxes shaped like the best ellipsoid's extents (largest extent 1: rho is it)
        ext = np.sqrt(np.diag(best[1]["W"]))
        beta, rho0 = ext / np.max(ext), float(np.max(ext))
    return EllipsoidSearch(best[0], best[1], p_idx if p_idx is not None else np.zeros(0, dtype=int),
                           tuple(history), t_solve, t_hess)


def _search_radius(solve: Callable[[float], float], radii: list[float], refine: int) -> None:
    """Solve at every radius of ``radii``, then refine the best by ``refine`` golden-section steps in log radius
    between its neighbours (the solutions are kept by ``solve``)."""
    vals = [solve(r) for r in radii]
    k = int(np.argmax(vals))
    if not (np.isfinite(vals[k]) and len(radii) > 1 and refine):
        return
    a = math.log(radii[min(k + 1, len(radii) - 1)])
    b = math.log(radii[max(k - 1, 0)])
    gr = (math.sqrt(5) - 1) / 2
    c1, c2 = b - gr * (b - a), a + gr * (b - a)
    f1, f2 = solve(math.exp(c1)), solve(math.exp(c2))
    for _ in range(refine - 2):
        if f1 > f2:
            b, c2, f2 = c2, c1, f1
            c1 = b - gr * (b - a)
            f1 = solve(math.exp(c1))
        else:
            a, c1, f1 = c1, c2, f2
            c2 = a + gr * (b - a)
            f2 = solve(math.exp(c2))


@dataclass(frozen=True)
class EllipsoidSolution:
    """A solution of the search scaled by ``1 - backoff`` and its LMIs checked in floating point
    (:func:`back_off`).

    Attributes
    ----------
    W, s, Z, nu : ndarray
        The backed-off ``W`` (scaled, ``(nf, nf)``) and multipliers.
    remainder : Remainder
        The remainder bound the LMIs use.
    p_idx : ndarray of int
        Its components.
    Ps : ndarray, shape (nf, nf)
        ``W^-1`` (scaled ``P``).
    Q : ndarray, shape (nf, nf, nf)
        The remainder forms, zero outside ``p_idx``.
    P : ndarray, shape (nf, nf)
        ``P`` in the free states' units.
    G : ndarray, shape (ms, nf)
        The sector condition's gain (input units per state unit).
    lmi_max_eig, region_min_eig : float
        Largest eigenvalue of the decrease LMI (of every system checked) and smallest of the region blocks.
    """

    W: np.ndarray = field(repr=False)
    s: np.ndarray = field(repr=False)
    Z: np.ndarray = field(repr=False)
    nu: np.ndarray = field(repr=False)
    remainder: Remainder = field(repr=False)
    p_idx: np.ndarray = field(repr=False)
    Ps: np.ndarray = field(repr=False)
    Q: np.ndarray = field(repr=False)
    P: np.ndarray = field(repr=False)
    G: np.ndarray = field(repr=False)
    lmi_max_eig: float
    region_min_eig: float


def back_off(sc: ScaledLoop, sol: dict[str, Any], p_idx: np.ndarray, backoff: float,
             vertices: Sequence[ScaledLoop] | None = None) -> EllipsoidSolution:
    """A solution of :func:`ellipsoid_search` scaled by ``1 - backoff``, its LMIs (at ``sc``'s ``(A, B)``, or at
    every vertex system) checked in floating point, with ``P`` and ``G`` in state units.

    Parameters
    ----------
    sc : ScaledLoop
        The loop whose decrease LMI and region blocks are checked.
    sol : dict
        :attr:`EllipsoidSearch.solution`.
    p_idx : ndarray of int
        :attr:`EllipsoidSearch.p_idx`.
    backoff : float
        In ``[0, 0.5]``.
    vertices : sequence of ScaledLoop, optional
        Check the decrease LMI at each of these systems instead (largest eigenvalue over them).

    Returns
    -------
    EllipsoidSolution
    """
    nf = len(sc.f)
    q = 1.0 - backoff
    Wc, s_c, Zc, nuc = q * sol["W"], q * sol["s"], q * sol["Z"], q * sol["nu"]
    rem: Remainder = sol["rem"]
    lmax, rmin = _lmi_numeric(sc, Wc, s_c, Zc, nuc, rem.R, p_idx, vertices)
    Ps = np.linalg.inv(Wc)
    Ps = 0.5 * (Ps + Ps.T)
    Q = np.zeros((nf, nf, nf))
    Q[p_idx] = rem.Q[p_idx]
    Dinv = np.diag(1.0 / sc.d)
    P = Dinv @ Ps @ Dinv
    sat = sc.sat
    G = (sc.s[sat, None] * (Zc @ Ps)) @ Dinv if len(sat) else np.zeros((0, nf))
    return EllipsoidSolution(Wc, s_c, Zc, nuc, rem, p_idx, Ps, Q, 0.5 * (P + P.T), G, lmax, rmin)


def verify_ellipsoid(sl: SaturatedLoop, sc: ScaledLoop, sol: EllipsoidSolution, *, n_verify: int, n_simulate: int,
                     horizon: float | None, seed: int) -> EllipsoidVerification:
    """The a-posteriori checks of an ellipsoid on the true loop (:class:`EllipsoidVerification`): ``dV/dt`` and the
    remainder bound (against ``sc``'s ``(A, B)``) on points of the ellipsoid, simulations from its boundary.

    Parameters
    ----------
    sl : SaturatedLoop
        The loop, at its equilibrium.
    sc : ScaledLoop
        It scaled (:func:`scale_loop`).
    sol : EllipsoidSolution
        The ellipsoid and the LMI checks already made (:func:`back_off`).
    n_verify, n_simulate : int
        Points (half on the boundary) and simulations (at most ``n_verify // 2``).
    horizon : float or None
        Length of the simulations (default 25 slowest time constants of ``A + B K``).
    seed : int
        Seed of the points.

    Returns
    -------
    EllipsoidVerification
    """
    Ps, Wc, Q = sol.Ps, sol.W, sol.Q
    rng = np.random.default_rng(seed + 11)
    nb = n_verify // 2
    x = np.concatenate([_ellipsoid_points(Wc, n_verify - nb, rng, False), _ellipsoid_points(Wc, nb, rng, True)])
    with np.errstate(all="ignore"):
        w = sc.feedback(x)
        xdot = sc.truth(x)
        Fw = sc.F(x, w)
    r2 = np.sum(x * x, axis=1)
    vd = 2.0 * np.einsum("ni,ij,nj->n", x, Ps, xdot) / np.maximum(r2, 1e-300)
    delta = Fw - x @ sc.A.T - w @ sc.B.T
    bound2 = np.einsum("ni,jik,nk->nj", x, Q, x)
    tol = 1e-10 * (1.0 + np.abs(x) @ np.abs(sc.A).T) ** 2     # rounding of delta for exactly linear components
    with np.errstate(all="ignore"):
        ratio = np.sqrt(np.maximum(delta**2 - tol, 0.0) / np.where(bound2 > 0, bound2, 0.0))
    ratio = np.where(np.isnan(ratio), 0.0, ratio)
    ratio_max = float(np.max(ratio)) if ratio.size else 0.0
    Acl = sc.A + sc.B @ sc.K
    hz = horizon or 25.0 / float(np.min(np.abs(np.linalg.eigvals(Acl).real)))
    nsim = min(n_simulate, nb)
    conv = 0
    if nsim:
        f = list(sc.f)
        X0 = sl.equilibrium[f] + x[n_verify - nb:n_verify - nb + nsim] * sc.d
        res = integrate_batch(lambda Z: _free_rhs(sl, Z, f), X0, hz, rtol=1e-7, atol=1e-10 * sc.d,
                              max_steps=200_000)
        conv = int(np.sum(res.converged_to(sl.equilibrium[f], 1e-3 * float(np.linalg.norm(sc.d)))))
    return EllipsoidVerification(sol.lmi_max_eig, sol.region_min_eig, float(np.max(np.diag(Wc))), ratio_max,
                                 int(x.shape[0]), float(np.max(vd)), nsim, conv, float(hz))


def _free_rhs(sl: SaturatedLoop, Z: np.ndarray, f: list[int]) -> np.ndarray:
    X = np.broadcast_to(sl.equilibrium, (*Z.shape[:-1], sl.n)).astype(Z.dtype).copy()
    X[..., f] = Z
    return np.asarray(sl.rhs(X))[..., f]
