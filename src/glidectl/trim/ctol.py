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

Plausibility limit: the speed must lie in ``(0, SPEED_MAX_REF * V_ref]`` with ``V_ref = sqrt(m g / (rho A_W / 2))``
the speed at which the aerodynamic force scale equals the weight (``V_ref = 1`` in the normalized units of
``dc8_ctol``, so the limit is 100 there); far beyond it the forces are meaningless and ``V^2`` overflows. The glide
is accepted only if the residual of (7.21)-(7.23) is below ``RESIDUAL_TOL`` (1e-9) relative to the largest force in
those equations.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .. import checks
from ..errors import ArgumentError, InfeasibleGlideError, SolverError
from ..models.ctol import drag_coefficient, lift_coefficient, require_ctol
from ..params import Vehicle

__all__ = ["ALPHA_MAX", "RESIDUAL_TOL", "SPEED_MAX_REF", "CTOLGlide", "angle_equation", "ctol_glide"]

#: Largest |alpha_e| (rad) accepted as physical by default (linear lift model).
ALPHA_MAX = 0.35
#: Plausibility limit on the speed, in units of ``V_ref = sqrt(m g / (rho A_W / 2))``.
SPEED_MAX_REF = 100.0
#: Largest residual of (7.21)-(7.23) relative to the largest force in them.
RESIDUAL_TOL = 1e-9


def _speed_gamma(veh: Vehicle, speed: Any, gamma: Any) -> tuple[float, float]:
    """Checked ``(speed, gamma)``: speed in (0, SPEED_MAX_REF V_ref], gamma in [-pi, pi]."""
    v_max = SPEED_MAX_REF * math.sqrt(veh.m * veh.g / veh.rho_AW_half)
    unit = "m/s (normalized units for a normalized vehicle)"
    speed = checks.real("speed (V_e)", speed, lo=0.0, lo_open=True, hi=v_max, unit=unit)
    gamma = checks.real("gamma (gamma_e, flight-path angle)", gamma, lo=-math.pi, hi=math.pi, unit="rad")
    if speed * speed < sys.float_info.min:
        raise ArgumentError(f"speed (V_e) = {speed:g} is so small that V_e^2 underflows and the aerodynamic forces "
                            "vanish; ask for a speed of at least 1e-150")
    return speed, gamma


def _F(veh: Vehicle, speed: float, gamma: float, a: Any) -> Any:
    return (veh.m * veh.g * np.cos(gamma + a)
            - (drag_coefficient(veh, a) * np.sin(a) + lift_coefficient(veh, a) * np.cos(a)) * speed**2)


def angle_equation(veh: Vehicle, speed: float, gamma: float, alpha: np.ndarray | float) -> np.ndarray | float:
    """``F(alpha)`` of (7.25) in the general units of :mod:`glidectl.models.ctol` (N).

    Parameters
    ----------
    veh : Vehicle
        A ``kind = "ctol"`` vehicle.
    speed : float
        ``V_e`` (m/s; normalized units for ``dc8_ctol``), in ``(0, SPEED_MAX_REF * V_ref]``.
    gamma : float
        ``gamma_e`` (rad), in ``[-pi, pi]``.
    alpha : float or array_like
        Angles of attack (rad), finite.

    Returns
    -------
    ndarray
        ``F(alpha)`` (N), shaped like ``alpha``.

    Raises
    ------
    ArgumentTypeError
        ``veh`` is not a Vehicle, ``speed`` or ``gamma`` not a real number, ``alpha`` not real numbers.
    ArgumentError
        A value is not finite or outside its range.
    ModelError
        ``veh`` is not a CTOL aircraft.
    """
    require_ctol(veh)
    speed, gamma = _speed_gamma(veh, speed, gamma)
    a = checks.array("alpha (angle of attack, rad)", alpha)
    return _F(veh, speed, gamma, a)


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
        max ``|(7.21), (7.22), (7.23)|`` at the solution (N).
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
        """State ``(x, y, xdot, ydot, theta, Omega2)`` of the CTOL model on this glide.

        Parameters
        ----------
        position : array_like, shape (2,)
            Inertial position ``(x, y)`` (m), finite.

        Returns
        -------
        ndarray, shape (6,)

        Raises
        ------
        ArgumentTypeError
            If ``position`` is not an array of real numbers.
        ArgumentError
            If it is not two finite numbers.
        """
        pos = checks.array("position (x, y)", position, shape=(2,))
        return np.r_[pos, self.velocity, self.theta, 0.0]


def _roots(veh: Vehicle, speed: float, gamma: float, n: int = 4001) -> list[float]:
    a = np.linspace(-math.pi, math.pi, n)
    f = _F(veh, speed, gamma, a)
    out = []
    # the grid intervals that hold a root, found at once (same order and test as a loop over i < n - 1)
    for i in np.flatnonzero((f[:-1] == 0) | (f[:-1] * f[1:] < 0)):
        if f[i] == 0:
            out.append(float(a[i]))
        else:
            out.append(float(brentq(lambda x: float(_F(veh, speed, gamma, x)), a[i], a[i + 1],
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
        ``V_e`` (m/s; normalized units for ``dc8_ctol``), in ``(0, SPEED_MAX_REF * V_ref]`` with ``V_ref = sqrt(m g /
        (rho A_W / 2))`` (a plausibility limit: 100 in normalized units).
    gamma : float
        ``gamma_e`` in [-pi, pi] (rad).
    alpha_max : float
        Largest ``|alpha_e|`` accepted as physical (rad), in ``(0, pi]``.

    Returns
    -------
    CTOLGlide

    Raises
    ------
    ArgumentTypeError
        ``veh`` is not a Vehicle, or ``speed``, ``gamma`` or ``alpha_max`` is not a real number (``str``, ``None``,
        ``bool``, arrays).
    ArgumentError
        A value is not finite or outside its range above (e.g. ``speed = 1e200``).
    ModelError
        ``veh`` is not a CTOL vehicle.
    InfeasibleGlideError
        No root of (7.25) with ``|alpha_e| <= alpha_max`` (the message lists the roots that exist).
    SolverError
        The root finder failed or the residual of (7.21)-(7.23) is not small relative to the forces.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> dc8 = gc.load_vehicle("dc8_ctol")  # normalized units of section 7.1
    >>> level = gc.ctol_glide(dc8, speed=0.155, gamma=0.0)
    >>> print(f"alpha_e = {np.degrees(level.alpha):.3f} deg, thrust = {level.thrust:.4f}")
    alpha_e = 3.658 deg, thrust = 0.0491
    """
    require_ctol(veh)
    speed, gamma = _speed_gamma(veh, speed, gamma)
    alpha_max = checks.real("alpha_max", alpha_max, lo=0.0, lo_open=True, hi=math.pi, unit="rad")
    try:
        with np.errstate(over="raise", invalid="raise"):
            roots = _roots(veh, speed, gamma)
    except (OverflowError, FloatingPointError, ZeroDivisionError, RuntimeError) as exc:
        raise SolverError(f"solving the angle equation (7.25) for V = {speed:g}, gamma = {gamma:g} rad failed: "
                          f"{exc}") from exc
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
    W = veh.m * veh.g
    scale = max(W, abs(drag_coefficient(veh, alpha)) * speed**2, abs(lift_coefficient(veh, alpha)) * speed**2,
                abs(k1 + W), abs(k1), abs(k2))
    if not (math.isfinite(res) and res <= RESIDUAL_TOL * scale):
        raise SolverError(f"the steady glide at V = {speed:g}, gamma = {gamma:g} rad has residual {res:.3e} N, "
                          f"{res / scale:.2e} of the largest force {scale:.3g} N (tolerance {RESIDUAL_TOL:g})")
    return CTOLGlide(speed, gamma, alpha, k1, k2, tuple(roots), res, veh, veh.provenance)
