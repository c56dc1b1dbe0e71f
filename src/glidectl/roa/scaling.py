"""Boxes, scales and starting Lyapunov functions for certifying any closed loop (issue 17).

A closed loop of this package (:func:`glidectl.closed_loop`) lives in the plant's state units with its equilibrium
``x_e`` somewhere in state space. Before any SOS program is built its states are mapped to ``y = (x - x_e) / s``
with ``s_i = max(x_e,i - lo_i, hi_i - x_e,i)``, so that the box is inside ``[-1, 1]^n`` and touches ``-1`` or ``1``
in every state (:func:`box_scale`). The box comes from the caller (``box=``), from the model's own ``box`` (models
built for certification) or from the actuator limits of the vehicle file (``Vehicle.actuators``: states named
``m0``, ``r_P1``, ``r_P3`` ... with a non-fixed actuator); when a state has none of these, :func:`resolve_box`
refuses and asks for ``box=``. The starting ``V`` is ``y^T P y`` with ``A_y^T P + P A_y = -I`` for the scaled
linearization ``A_y = S^-1 A S`` (:func:`scaled_lyapunov`), so its level sets are shaped by the box, not by the SI
units.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from scipy.linalg import solve_continuous_lyapunov

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, ModelError, SolverError
from .polynomial import Poly

__all__ = ["box_scale", "resolve_box", "scaled_lyapunov"]


def _actuator_box(model: Any) -> dict[str, tuple[float, float]]:
    """``{state name: (min, max)}`` of the non-fixed actuators of the model's vehicle that are states."""
    veh = getattr(model, "vehicle", None)
    acts = getattr(veh, "actuators", None) or {}
    names = set(getattr(model, "state_names", ()))
    out: dict[str, tuple[float, float]] = {}
    for key, a in dict(acts).items():
        if key in names and getattr(a, "fixed", None) is None and float(a.max) > float(a.min):
            out[key] = (float(a.min), float(a.max))
    return out


def resolve_box(model: Any, box: Any = None, equilibrium: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """The region of interest of a certification, in the model's state units.

    Parameters
    ----------
    model : glidectl model
        Needs ``state_names``; its ``box`` (models built for certification) and the actuator limits of its
        ``vehicle`` (``Vehicle.actuators``) are the defaults.
    box : (array_like, array_like) or mapping, optional
        ``(lo, hi)`` of shape ``(n,)`` each, or ``{state name: (lo, hi)}`` for some states (the others from the
        defaults).
    equilibrium : array_like (n,), optional
        Must lie strictly inside the box (default the model's ``equilibrium``).

    Returns
    -------
    (ndarray, ndarray)
        ``lo`` and ``hi`` (state units).

    Raises
    ------
    ArgumentTypeError
        If ``box`` is neither a pair nor a mapping.
    ArgumentError
        If a state has no limit (neither ``box=`` nor a model box nor a non-fixed actuator): the message lists the
        states and the limits found; an unknown state name; ``lo >= hi``; or the equilibrium outside the box.
    """
    names = tuple(getattr(model, "state_names", ()))
    n = len(names)
    lo = np.full(n, np.nan)
    hi = np.full(n, np.nan)
    own = getattr(model, "box", None)
    if own is not None and not callable(own):
        lo[:], hi[:] = (checks.array("model box", b, shape=(n,)) for b in own)
    else:
        for k, (a, b) in _actuator_box(model).items():
            i = names.index(k)
            lo[i], hi[i] = a, b
    if box is not None:
        if isinstance(box, Mapping):
            for k, v in box.items():
                if k not in names:
                    raise ArgumentError(f"box names state '{k}', which is not a state of {names}")
                pair = checks.array(f"box['{k}']", v, shape=(2,))
                i = names.index(k)
                lo[i], hi[i] = pair
        elif isinstance(box, tuple | list) and len(box) == 2:
            lo = checks.array("box lo", box[0], shape=(n,)).copy()
            hi = checks.array("box hi", box[1], shape=(n,)).copy()
        else:
            raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({n},) or a mapping "
                                    f"{{state name: (lo, hi)}}, got {type(box).__name__}")
    missing = [names[i] for i in range(n) if not (np.isfinite(lo[i]) and np.isfinite(hi[i]))]
    if missing:
        have = {names[i]: (float(lo[i]), float(hi[i])) for i in range(n) if names[i] not in missing}
        raise ArgumentError(f"no limits known for states {missing} of '{getattr(model, 'name', type(model).__name__)}'"
                            f" (the vehicle's non-fixed actuators give {have or 'none'}): pass box=(lo, hi) in state "
                            f"units for all {n} states {names}, or box={{name: (lo, hi)}} for the missing ones")
    if np.any(lo >= hi):
        raise ArgumentError(f"box must have lo < hi in every state, got lo = {lo.tolist()}, hi = {hi.tolist()}")
    xe = getattr(model, "equilibrium", None) if equilibrium is None else equilibrium
    if xe is not None:
        xe = checks.array("equilibrium", xe, shape=(n,))
        out = [names[i] for i in range(n) if not lo[i] < xe[i] < hi[i]]
        if out:
            raise ArgumentError(f"the equilibrium {xe.tolist()} is not strictly inside the box in states {out}: "
                                f"lo = {lo.tolist()}, hi = {hi.tolist()}")
    return lo, hi


def box_scale(box: tuple[Any, Any], equilibrium: Any) -> np.ndarray:
    """``s_i = max(x_e,i - lo_i, hi_i - x_e,i)``: ``y = (x - x_e) / s`` maps the box into ``[-1, 1]^n``.

    Parameters
    ----------
    box : (array_like, array_like)
        ``(lo, hi)`` in state units, ``lo < x_e < hi``.
    equilibrium : array_like
        ``x_e`` (state units).

    Returns
    -------
    ndarray
        The positive scale of each state (state units).

    Raises
    ------
    ArgumentError
        If the shapes differ or the equilibrium is not strictly inside the box.
    """
    xe = checks.array("equilibrium", equilibrium, ndim=1)
    lo = checks.array("box lo", box[0], shape=xe.shape)
    hi = checks.array("box hi", box[1], shape=xe.shape)
    if np.any(lo >= xe) or np.any(xe >= hi):
        raise ArgumentError("the equilibrium must be strictly inside the box")
    return np.maximum(xe - lo, hi - xe)


def scaled_lyapunov(A: Any, scale: Any, weight: Any = None) -> Poly:
    """Starting ``V(y) = y^T P y`` with ``A_y^T P + P A_y = -W_y``, ``A_y = S^-1 A S`` (``S = diag(scale)``).

    ``W_y = I`` by default; with ``weight = Q + K^T R K`` (state units) of an LQR law ``u = -K (x - x_e)``,
    ``W_y = S weight S`` and ``V`` is the closed loop's quadratic cost-to-go ``(x - x_e)^T P_x (x - x_e)`` (the
    Riccati solution when ``K`` is the LQR gain of ``A``), written in ``y``.

    Parameters
    ----------
    A : array_like (n, n)
        Linearization in state units (per the model's time unit).
    scale : array_like (n,)
        State scale ``s`` of ``y = (x - x_e) / s``.
    weight : array_like (n, n), optional
        Symmetric positive definite weight in state units (default: ``W_y = I``).

    Returns
    -------
    Poly
        The quadratic in the ``n`` scaled variables, normalized to largest coefficient 1 (nondimensional).

    Raises
    ------
    ArgumentError
        If ``weight`` has the wrong shape or is not positive definite.
    ModelError
        If ``A`` is not Hurwitz (the equation has no positive definite solution).
    SolverError
        If the Lyapunov equation fails.
    """
    A = checks.array("A", A, ndim=2)
    s = checks.array("scale", scale, shape=(A.shape[0],))
    Ay = A * s[None, :] / s[:, None]
    Wy = np.eye(len(s))
    if weight is not None:
        Wx = checks.array("weight", weight, shape=(len(s), len(s)))
        Wy = 0.5 * (Wx + Wx.T) * s[:, None] * s[None, :]
        if np.linalg.eigvalsh(Wy)[0] <= 0:
            raise ArgumentError("weight must be symmetric positive definite (e.g. Q + K^T R K of an LQR law)")
    if np.max(np.linalg.eigvals(Ay).real) >= 0:
        raise ModelError(f"the linearization is not Hurwitz (eigenvalues {np.round(np.linalg.eigvals(A), 6)}): no "
                         "quadratic Lyapunov function to start from")
    try:
        P = solve_continuous_lyapunov(Ay.T, -Wy)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"the scaled Lyapunov equation failed: {exc}") from exc
    P = 0.5 * (P + P.T)
    P = P / np.max(np.abs(P))
    n = len(s)
    Y = Poly.variables(n)
    V = Poly({}, n)
    for i in range(n):
        for j in range(n):
            V = V + float(P[i, j]) * Y[i] * Y[j]
    return V
