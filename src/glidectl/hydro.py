"""Hydrodynamic forces and moments of the underwater glider, (2.9)-(2.14).

All functions are written with numpy ufuncs only, broadcast over leading dimensions and accept complex input,
so they serve simulation (batched real states) and exact complex-step linearization alike.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .params import Vehicle

__all__ = ["angle_of_attack", "atan2_cs", "loads_at", "longitudinal_loads"]


def atan2_cs(y: Any, x: Any) -> Any:
    """``arctan2(y, x)`` that is analytic in a complex-step perturbation.

    For real input this is :func:`numpy.arctan2`. For complex input the branch is chosen from the real parts and
    the analytic continuation ``2 arctan(y / (sqrt(x^2 + y^2) + x))`` (for ``Re x >= 0``) or
    ``arctan(y/x) +- pi`` (for ``Re x < 0``) is used, so the imaginary part carries the exact derivative.
    """
    y = np.asarray(y)
    x = np.asarray(x)
    if not (np.iscomplexobj(x) or np.iscomplexobj(y)):
        return np.arctan2(y, x)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.sqrt(x * x + y * y)
        right = 2.0 * np.arctan(y / (r + x))
        left = np.arctan(y / x) + np.where(np.real(y) >= 0, np.pi, -np.pi)
    return np.where(np.real(x) >= 0, right, left)


def angle_of_attack(v1: Any, v3: Any) -> Any:
    """Angle of attack ``alpha = atan2(v3, v1)`` (rad), §2.2.4; body 3-axis points down."""
    return atan2_cs(v3, v1)


def longitudinal_loads(veh: Vehicle, v1: Any, v3: Any, Omega2: Any) -> tuple[Any, Any, Any, Any]:
    """Lift, drag and pitching moment in the longitudinal plane, (2.9), (2.11), (2.13).

    Parameters
    ----------
    veh : Vehicle
        Uses ``K_L0 [kg/m], K_L [kg/m/rad], K_D0 [kg/m], K_D [kg/m/rad^2], K_M0 [kg], K_M [kg/rad],
        K_q [kg s/rad]``.
    v1, v3 : array_like
        Body-frame velocity components (m/s).
    Omega2 : array_like
        Pitch rate (rad/s).

    Returns
    -------
    alpha : angle of attack (rad)
    L, D : lift and drag (N), ``L = (K_L0 + K_L alpha) V^2``, ``D = (K_D0 + K_D alpha^2) V^2``
    M_DL2 : pitching moment (N m), ``(K_M0 + K_M alpha + K_q Omega2) V^2``
    """
    alpha = angle_of_attack(v1, v3)
    L, D, M = loads_at(veh, v1 * v1 + v3 * v3, alpha, Omega2)
    return alpha, L, D, M


def loads_at(veh: Vehicle, V2: Any, alpha: Any, Omega2: Any) -> tuple[Any, Any, Any]:
    """Lift, drag and pitching moment (N, N, N m) for squared speed ``V2`` (m^2/s^2), angle of attack ``alpha``
    (rad, not wrapped: models with alpha as a state, chapter 5, use it directly) and pitch rate (rad/s).

    ``L = (K_L0 + K_L alpha) V^2`` (2.11), ``D = (K_D0 + K_D alpha^2) V^2`` (2.9),
    ``M_DL2 = (K_M0 + K_M alpha + K_q Omega2) V^2`` (2.13); equivalently (5.24)-(5.25).
    """
    p = veh.params
    L = (p["K_L0"] + p["K_L"] * alpha) * V2
    D = (p["K_D0"] + p["K_D"] * alpha * alpha) * V2
    M = (p["K_M0"] + p["K_M"] * alpha + p["K_q"] * Omega2) * V2
    return L, D, M
