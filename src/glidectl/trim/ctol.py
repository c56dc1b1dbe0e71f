"""Steady glides of the CTOL aircraft under the controller (7.16)-(7.20): Theorem 4, equations (7.21)-(7.27).

For a desired speed ``V_e`` and flight-path angle ``gamma_e`` the unknowns are the angle of attack ``alpha_e`` and
the gains ``k1, k2``. Eliminating the gains gives the angle equation (7.25),

    F(alpha) = m g cos(gamma_e + alpha) - (K_Dr(alpha) sin alpha + K_Li(alpha) cos alpha) V_e^2 = 0,

(the force balance across the body axis, where the controller's forces have no component: see below), after which
(7.21)-(7.22) are linear in ``(k1, k2)`` with determinant -1, so the gains are unique.

Which root. F has several roots on (-pi, pi]: besides the root near zero there are roots near +-pi/2 and beyond
(flight at a large angle of attack or backwards), where the linear lift model (7.1) means nothing. The physical
root is the one of smallest ``|alpha|``; we return it when ``|alpha_e| <= alpha_max`` (default 0.35 rad, 20 deg, a
generous bound on the validity of (7.1)-(7.2)) and raise :class:`InfeasibleGlideError` otherwise. All roots are kept
in :attr:`CTOLGlide.alpha_roots`.

Why the controller's forces drop out: (7.18)-(7.19) make ``u1 (cos theta, sin theta) + eps u2 (sin theta,
-cos theta) = (-k2, -k1)`` in inertial axes: a constant force, so ``k1`` acts as extra weight and ``k2`` as a
constant horizontal force; only ``w22`` of (7.20) depends on the pitch error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..errors import InfeasibleGlideError, ModelError
from ..models.ctol import drag_coefficient, lift_coefficient, require_ctol
from ..params import Vehicle

__all__ = ["CTOLGlide", "angle_equation", "ctol_glide"]

ALPHA_MAX = 0.35  # rad: largest |alpha_e| accepted as physical (linear lift model)


def angle_equation(veh: Vehicle, speed: float, gamma: float, alpha: np.ndarray | float) -> np.ndarray | float:
    """``F(alpha)`` of (7.25) in the general units of :mod:`glidectl.models.ctol` (N)."""
    a = np.asarray(alpha, dtype=float)
    return (veh.m * veh.g * np.cos(gamma + a)
            - (drag_coefficient(veh, a) * np.sin(a) + lift_coefficient(veh, a) * np.cos(a)) * speed**2)


@dataclass(frozen=True)
class CTOLGlide:
    """A steady glide of the closed-loop CTOL aircraft (Theorem 4).

    Attributes
    ----------
    speed, gamma : float
        ``V_e`` (m/s) and ``gamma_e`` (rad, positive climbing).
    alpha, theta : float
        Angle of attack ``alpha_e`` and pitch angle ``theta_e`` (rad), ``theta = gamma + alpha`` (a property).
    k1, k2 : float
        Gains of (7.18)-(7.19) (N), from (7.21)-(7.22).
    thrust : float
        Equilibrium thrust ``u1 = -k1 sin theta_e - k2 cos theta_e`` (N); negative thrust (a brake) is needed for
        steep, fast descents.
    alpha_roots : tuple of float
        Every root of (7.25) on (-pi, pi] (rad), sorted; ``alpha`` is the one of smallest magnitude.
    residual : float
        max |(7.21), (7.22), (7.23)| at the solution (N).
    vehicle : Vehicle
        The aircraft.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    """

    speed: float
    gamma: float
    alpha: float
    k1: float
    k2: float
    alpha_roots: tuple[float, ...]
    residual: float
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = field(default="", repr=False)

    @property
    def theta(self) -> float:
        """Pitch angle ``theta_e = gamma_e + alpha_e`` (rad)."""
        return self.gamma + self.alpha

    @property
    def thrust(self) -> float:
        return float(-self.k1 * math.sin(self.theta) - self.k2 * math.cos(self.theta))

    @property
    def velocity(self) -> np.ndarray:
        """Inertial velocity ``(xdot, ydot)`` (m/s)."""
        return self.speed * np.array([math.cos(self.gamma), math.sin(self.gamma)])

    def full_state(self, position: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
        """State ``(x, y, xdot, ydot, theta, Omega2)`` of the CTOL model on this glide."""
        return np.r_[position, self.velocity, self.theta, 0.0]


def _roots(veh: Vehicle, speed: float, gamma: float, n: int = 4001) -> list[float]:
    a = np.linspace(-math.pi, math.pi, n)
    f = angle_equation(veh, speed, gamma, a)
    out = []
    for i in range(n - 1):
        if f[i] == 0:
            out.append(float(a[i]))
        elif f[i] * f[i + 1] < 0:
            out.append(float(brentq(lambda x: float(angle_equation(veh, speed, gamma, x)), a[i], a[i + 1],
                                    xtol=1e-15, rtol=1e-15)))
    return out


def gains(veh: Vehicle, speed: float, gamma: float, alpha: float) -> tuple[float, float]:
    """``(k1, k2)`` from the linear equations (7.21)-(7.22) for a given ``alpha_e`` (N)."""
    W = veh.m * veh.g
    A = np.array([[-math.sin(gamma), -math.cos(gamma)], [-math.cos(gamma), math.sin(gamma)]])
    rhs = np.array([drag_coefficient(veh, alpha) * speed**2, -lift_coefficient(veh, alpha) * speed**2])
    k1w, k2 = np.linalg.solve(A, rhs)  # unknowns (k1 + m g, k2)
    return float(k1w - W), float(k2)


def residuals(veh: Vehicle, speed: float, gamma: float, alpha: float, k1: float, k2: float) -> np.ndarray:
    """Left-hand sides of (7.21)-(7.23) in the general units (N)."""
    W = veh.m * veh.g
    KD, KL = drag_coefficient(veh, alpha) * speed**2, lift_coefficient(veh, alpha) * speed**2
    return np.array([-(k1 + W) * math.sin(gamma) - k2 * math.cos(gamma) - KD,
                     -(k1 + W) * math.cos(gamma) + k2 * math.sin(gamma) + KL,
                     k1 * math.cos(gamma + alpha) - k2 * math.sin(gamma + alpha)])


def ctol_glide(veh: Vehicle, speed: float, gamma: float, *, alpha_max: float = ALPHA_MAX) -> CTOLGlide:
    """Steady glide of speed ``speed`` (m/s) and flight-path angle ``gamma`` (rad) of the CTOL aircraft ``veh``
    under (7.16)-(7.20): Theorem 4.

    Parameters
    ----------
    veh : Vehicle
        A ``kind = "ctol"`` vehicle (``dc8_ctol``: normalized units of §7.1).
    speed : float
        ``V_e > 0``.
    gamma : float
        ``gamma_e`` in (-pi, pi] (rad).
    alpha_max : float
        Largest ``|alpha_e|`` accepted as physical (rad).

    Returns
    -------
    CTOLGlide

    Raises
    ------
    ModelError
        Not a CTOL vehicle, non-positive or non-finite speed, non-finite gamma.
    InfeasibleGlideError
        No root of (7.25) with ``|alpha_e| <= alpha_max`` (the message lists the roots that exist).
    """
    require_ctol(veh)
    try:
        speed, gamma = float(speed), float(gamma)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"speed and gamma must be numbers, got {speed!r}, {gamma!r}") from exc
    if not (math.isfinite(speed) and speed > 0):
        raise ModelError(f"speed must be a positive number (m/s), got {speed!r}")
    if not math.isfinite(gamma):
        raise ModelError(f"gamma must be finite (rad), got {gamma!r}")
    roots = _roots(veh, speed, gamma)
    phys = [a for a in roots if abs(a) <= alpha_max]
    if not phys:
        raise InfeasibleGlideError(
            f"no steady glide of the CTOL aircraft '{veh.name}' at V = {speed:g}, gamma = {math.degrees(gamma):.3f} "
            f"deg with |alpha_e| <= {alpha_max:g} rad: the angle equation (7.25) has roots "
            f"{[round(a, 4) for a in roots]} rad (Theorem 4 guarantees a root, not a small one); change the speed "
            "or raise alpha_max if the lift model still holds there")
    alpha = min(phys, key=abs)
    k1, k2 = gains(veh, speed, gamma, alpha)
    res = float(np.max(np.abs(residuals(veh, speed, gamma, alpha, k1, k2))))
    return CTOLGlide(speed, gamma, alpha, k1, k2, tuple(roots), res, veh, veh.provenance)
