"""Steady-state flight at measured pitch and buoyancy: the flight model the field calibrates on dive records.

Given the pitch angle ``theta`` and the net heaviness ``m0`` (kg; positive sinks) at each sample, the steady glide
balances weight, lift and drag (the force balance of (2.27)-(2.28), as in Merckelbach et al. 2019's steady-state
model):

    L(V^2, alpha) = m0 g cos(gamma),     D(V^2, alpha) = -m0 g sin(gamma),     gamma = theta - alpha.

Every law of :func:`glidectl.hydro.lift_drag` has lift linear in ``V^2`` (``L = V^2 l(alpha)``), so the lift
equation gives ``V^2(alpha)`` and the drag equation leaves one scalar root in ``alpha`` per sample. Its root on the
efficient branch (the one nearest zero lift, of the largest speed) is bracketed on a geometric grid of angles from
the zero-lift angle and refined by the Illinois method, for all samples at once: no Python loop over samples.

The net heaviness of a glider with a compressible hull and a pumped volume (:func:`excess_mass`) is
``m0 = mass - rho (volume (1 - epsilon p + alpha_T (T - T_ref)) + dV)`` at the gauge pressure ``p`` (a record's
own; else ``rho g depth`` with the in-situ density, whose difference from the profile's integral is far below the
compressibility's own uncertainty), the buoyancy of gliderflight's ``compute_FB_and_Fg`` with the thermal-expansion
term of the ``[hydrodynamics]`` table.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError
from ..hydro import lift_drag, zero_lift_angle
from ..params import Vehicle

__all__ = ["SEARCH_ANGLE_MAX", "SteadyFlight", "efficient_root", "steady_flight"]

#: Largest angle of attack searched from the zero-lift angle (rad): 30 degrees, far past any glider's stall.
SEARCH_ANGLE_MAX = np.pi / 6
_GRID = np.geomspace(1e-7, 1.0, 24)  # fractions of the search range: first sign change = efficient branch
_ITERATIONS = 50
_GOLDEN_ITERATIONS = 40


@dataclass(frozen=True)
class SteadyFlight:
    """Steady-state glide at each sample (:func:`steady_flight`).

    Attributes
    ----------
    theta, m0 : ndarray
        The pitch (rad) and net heaviness (kg) the flight was solved at.
    speed : ndarray
        Speed through the water (m/s); 0 where no steady glide exists.
    alpha : ndarray
        Angle of attack (rad); NaN where no steady glide exists.
    gamma : ndarray
        Flight-path angle ``theta - alpha`` (rad, positive climbing); NaN where no steady glide exists.
    vertical_speed, horizontal_speed : ndarray
        ``speed sin(gamma)`` (m/s, positive up) and ``speed cos(gamma)`` (m/s); 0 where no steady glide exists.
    feasible : ndarray of bool
        Where a steady glide exists: heaviness and pitch allow the force balance within
        :data:`SEARCH_ANGLE_MAX` of zero lift (neutral samples, ``m0 = 0``, are not).
    vehicle : Vehicle
        The vehicle (its law and coefficients).
    """

    theta: np.ndarray
    m0: np.ndarray
    speed: np.ndarray
    alpha: np.ndarray
    gamma: np.ndarray
    vertical_speed: np.ndarray
    horizontal_speed: np.ndarray
    feasible: np.ndarray
    vehicle: Vehicle = field(repr=False, compare=False)

    @property
    def provenance(self) -> str:
        """The vehicle's parameter hash."""
        return self.vehicle.provenance


def _rows(a: Any, rows: np.ndarray, ndim: int) -> Any:
    """Per-sample values ``a[rows]`` shaped to broadcast against an ``ndim``-dimensional array of angles."""
    if a is None or np.ndim(a) == 0:
        return a
    out = np.asarray(a)[rows]
    return out[:, None] if ndim == 2 else out


def efficient_root(residual: Callable[[np.ndarray, np.ndarray], np.ndarray], a0: float,
                   sign: np.ndarray, span: Any = SEARCH_ANGLE_MAX) -> tuple[np.ndarray, np.ndarray]:
    """The root of a force-balance residual on the efficient branch, for many samples at once.

    ``residual(alpha, rows)`` evaluates the residual of samples ``rows`` (an index array) at angles of attack
    ``alpha`` of shape ``(len(rows),)`` or ``(len(rows), k)``; it is positive just off the zero-lift angle ``a0`` on
    the side ``sign`` (the lift's sign; 0: no root) and falls through zero at the root. The first sign change on a
    geometric grid of angles up to ``span`` from ``a0`` (its last point exactly there) brackets the root of the
    largest speed; a root hidden in a dip between two grid points before it (near the edge of the feasible set) is
    found by a golden-section search at each local minimum of the gridded residual. The Illinois variant of regula
    falsi refines the bracket to a few ulps. No Python loop over samples.

    Parameters
    ----------
    residual : callable
        ``residual(alpha, rows) -> ndarray`` as above (non-finite values count as positive).
    a0 : float
        Zero-lift angle of attack (rad).
    sign : ndarray
        Sign of the lift at each sample (+1, -1, or 0 for no root).
    span : float or ndarray, optional
        How far from ``a0`` to search (rad), per sample or for all: :data:`SEARCH_ANGLE_MAX` by default; the angle
        of the best glide ratio where the residual is a drag-to-lift ratio (the first root lies before it).

    Returns
    -------
    alpha : ndarray
        The root (rad), NaN where none was bracketed.
    found : ndarray of bool
        Where a root was bracketed.
    """
    sign = np.asarray(sign, dtype=float)
    rows = np.arange(sign.size)
    extent = np.broadcast_to(np.minimum(np.asarray(span, dtype=float), SEARCH_ANGLE_MAX), sign.shape)
    alphas = a0 + (sign * extent)[:, None] * _GRID[None, :]
    r = np.nan_to_num(residual(alphas, rows), nan=np.inf)
    neg = r <= 0
    found = neg.any(axis=1) & (sign != 0)
    k = np.where(found, np.argmax(neg, axis=1), alphas.shape[1])
    hi = alphas[rows, np.minimum(k, alphas.shape[1] - 1)]
    lo = np.where(k > 0, alphas[rows, np.maximum(k - 1, 0)], a0)
    dip = _dips(residual, alphas, r, k, sign)
    if dip is not None:  # a root in a dip between grid points, before the first negative grid value
        drows, dlo, dhi = dip
        lo[drows], hi[drows], found[drows] = dlo, dhi, True
    alpha = np.full(sign.shape, np.nan)
    idx = np.flatnonzero(found)
    if idx.size:
        alpha[idx] = _illinois(lambda a, sel: np.nan_to_num(residual(a, idx[sel]), nan=np.inf, posinf=1e300),
                               lo[idx].copy(), hi[idx].copy())
    return alpha, found


def _dips(residual: Callable[[np.ndarray, np.ndarray], np.ndarray], alphas: np.ndarray, r: np.ndarray, k: np.ndarray,
          sign: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Roots hidden between grid points: at each interior local minimum of the gridded residual before a row's
    first non-positive value, the minimum over the two neighbouring cells (golden section); where it is <= 0, the
    bracket from the cell's left end to it (rows, lo, hi), the first such dip of each row. None when there is none.
    """
    K = alphas.shape[1]
    j = np.arange(1, K - 1)
    local = (r[:, 1:-1] <= r[:, :-2]) & (r[:, 1:-1] <= r[:, 2:]) & np.isfinite(r[:, 1:-1])
    local &= (j[None, :] < k[:, None]) & (sign != 0)[:, None]
    prow, pj = np.nonzero(local)
    if prow.size == 0:
        return None
    pj = pj + 1
    a, b = alphas[prow, pj - 1], alphas[prow, pj + 1]
    invphi = (np.sqrt(5.0) - 1.0) / 2.0
    c, d = b - invphi * (b - a), a + invphi * (b - a)
    fc, fd = residual(c, prow), residual(d, prow)
    for _ in range(_GOLDEN_ITERATIONS):
        left = np.nan_to_num(fc, nan=np.inf) < np.nan_to_num(fd, nan=np.inf)  # the minimum lies in [a, d]
        b, a = np.where(left, d, b), np.where(left, a, c)
        c, d = b - invphi * (b - a), a + invphi * (b - a)
        fc, fd = residual(c, prow), residual(d, prow)
    m = 0.5 * (a + b)
    fm = np.nan_to_num(residual(m, prow), nan=np.inf)
    ok = fm <= 0
    if not ok.any():
        return None
    prow, pj, m = prow[ok], pj[ok], m[ok]
    first = np.unique(prow, return_index=True)[1]  # the first (smallest-angle) dip of each row
    rows = prow[first]
    return rows, alphas[rows, pj[first] - 1], m[first]


def _illinois(f: Callable[[np.ndarray, np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Refine bracketed roots (``f(lo) > 0 >= f(hi)``) by the Illinois variant of regula falsi; ``f(alpha, sel)``
    evaluates the samples ``sel`` (indices into ``lo``). A sample stops iterating once its bracket is a few ulps wide
    (or its residual is 0), so its root does not depend on the other samples solved with it."""
    every = np.arange(lo.size)
    f_lo, f_hi = np.minimum(f(lo, every), 1e300), f(hi, every)
    side = np.zeros(lo.shape, dtype=int)
    x = hi.copy()
    act = every
    for _ in range(_ITERATIONS):
        a, b, fa, fb, sd = lo[act], hi[act], f_lo[act], f_hi[act], side[act]
        with np.errstate(divide="ignore", invalid="ignore"):
            xa = np.where(fa >= 1e300, 0.5 * (a + b), (a * fb - b * fa) / (fb - fa))
        xa = np.where(np.isfinite(xa) & ((xa - a) * (xa - b) <= 0), xa, 0.5 * (a + b))
        fx = np.minimum(f(xa, act), 1e300)
        left = fx > 0  # the root lies between x and hi
        a, b = np.where(left, xa, a), np.where(left, b, xa)
        fa, fb = np.where(left, fx, fa), np.where(left, fb, fx)
        # Illinois: halve the retained end's value when the same end is kept twice
        fb = np.where(left & (sd == 1), 0.5 * fb, fb)
        fa = np.where(~left & (sd == -1), 0.5 * fa, fa)
        lo[act], hi[act], f_lo[act], f_hi[act], side[act], x[act] = a, b, fa, fb, np.where(left, 1, -1), xa
        act = act[~((np.abs(b - a) <= 2e-15 * np.abs(xa)) | (fx == 0))]
        if act.size == 0:
            break
    return x


def _speed_squared(veh: Vehicle, theta: Any, weight: Any, alpha: np.ndarray, rho: Any) -> np.ndarray:
    """``V^2`` from the lift balance ``V^2 l(alpha) = W cos(theta - alpha)`` (lift is linear in ``V^2``)."""
    lift_unit, _ = lift_drag(veh, 1.0, alpha, rho)
    with np.errstate(divide="ignore", invalid="ignore"):
        return weight * np.cos(theta - alpha) / lift_unit


def steady_flight(veh: Vehicle, theta: Any, m0: Any, *, density: Any = None) -> SteadyFlight:
    """Steady glide at given pitch and net heaviness, at every sample (vectorized).

    Solves ``L = m0 g cos(gamma)``, ``D = -m0 g sin(gamma)``, ``gamma = theta - alpha`` ((2.27)-(2.28) with the
    vehicle's lift and drag law, :func:`glidectl.hydro.lift_drag`) for ``alpha`` and the speed, taking the root of
    the efficient branch (nearest zero lift). Relative accuracy of ``alpha`` about 1e-14.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (any law).
    theta : array_like
        Pitch angle (rad, nose up positive).
    m0 : array_like
        Net heaviness (kg, positive sinks), e.g. from :func:`excess_mass`.
    density : array_like, optional
        In-situ density (kg/m^3) for the laws written with ``q = rho V^2 / 2``; default the vehicle's.

    Returns
    -------
    SteadyFlight

    Raises
    ------
    ArgumentTypeError
        If an array argument is not numeric.
    ArgumentError
        If an array argument is not finite or the shapes do not broadcast.
    """
    veh = checks.vehicle("veh", veh, kind="underwater_glider")
    theta_in = np.asarray(checks.numeric("theta", theta), dtype=float)
    m0_in = np.asarray(checks.numeric("m0", m0), dtype=float)
    arrays = [theta_in, m0_in] + ([] if density is None else [np.asarray(checks.numeric("density", density),
                                                                         dtype=float)])
    for name, a in zip(("theta", "m0", "density"), arrays, strict=False):
        if not np.all(np.isfinite(a)):
            raise ArgumentError(f"{name} must be finite at every sample ({int(np.sum(~np.isfinite(a)))} are not)")
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError as exc:
        raise ArgumentError(f"theta, m0 and density must broadcast together: {exc}") from None
    th = np.broadcast_to(theta_in, shape).ravel()
    mm = np.broadcast_to(m0_in, shape).ravel()
    rho = None if density is None else np.broadcast_to(arrays[2], shape).ravel()
    weight = mm * veh.g

    def residual(alpha: np.ndarray, rows: np.ndarray) -> np.ndarray:
        # drag balance (D + W sin(theta - alpha)) / |W| at the speed of the lift balance
        t, w, r = (_rows(a, rows, alpha.ndim) for a in (th, weight, rho))
        V2 = _speed_squared(veh, t, w, alpha, r)
        _, D = lift_drag(veh, np.maximum(V2, 0.0), alpha, r)
        with np.errstate(invalid="ignore"):
            return np.where(V2 > 0, (D + w * np.sin(t - alpha)) / np.abs(w), np.inf)

    alpha, found = efficient_root(residual, zero_lift_angle(veh), np.sign(weight))
    speed = np.zeros(th.shape)
    speed[found] = np.sqrt(np.maximum(_speed_squared(veh, th[found], weight[found], alpha[found],
                                                     None if rho is None else rho[found]), 0.0))
    gamma = th - alpha
    with np.errstate(invalid="ignore"):
        w = np.where(found, speed * np.sin(gamma), 0.0)
        u = np.where(found, speed * np.cos(gamma), 0.0)
    out = [x.reshape(shape) for x in (np.broadcast_to(theta_in, shape).copy(), np.broadcast_to(m0_in, shape).copy(),
                                      speed, alpha, gamma, w, u, found)]
    return SteadyFlight(*out, vehicle=veh)
