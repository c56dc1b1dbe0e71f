"""Exact output tracking of the CTOL aircraft (§7.3.1): the linearizing inputs (7.80)-(7.81), the outer loop
(7.82)-(7.83), the internal dynamics (7.84) and its zero dynamics in level flight. Shared by the three exact-tracking
baselines: :mod:`glidectl.controllers.ctol_feedback_linearization`,
:mod:`glidectl.controllers.ctol_stable_inversion` and :mod:`glidectl.controllers.ctol_approximate_linearization`.

Feedback linearization (7.80)-(7.83). With output ``p = (x, y)``, (7.5)-(7.6) read ``m p'' = F_aero + u1 b(theta)
+ eps u2 n(theta) - m g e_y`` with ``b = (cos theta, sin theta)`` and ``n = (sin theta, -cos theta)``; the 2x2
matrix ``[b, n]`` is orthogonal and symmetric (its own inverse), so ``p'' = w`` is obtained with::

    u1     = D cos(alpha) - L sin(alpha) + m g sin(theta) + m (w1 cos(theta) + w2 sin(theta))      (7.80)
    eps u2 = D sin(alpha) + L cos(alpha) - m g cos(theta) + m (w1 sin(theta) - w2 cos(theta))      (7.81)

For ``m = g = 1`` these are exactly the printed (7.80)-(7.81) (checked: no correction needed). The internal dynamics
(7.84) is ``theta'' = u2 / J`` with that ``u2``; the printed (7.84) writes ``theta'' = u2`` (``J = 1``) and keeps an
``m g`` that (7.81) drops (both consistent with ``m = g = J = 1``). ``L`` and ``D`` are evaluated from the model's
right-hand side (:meth:`glidectl.models.ctol.CTOLAircraft.rhs` with zero input), not re-implemented.

Zero dynamics. For level flight at constant speed ``V`` (``w = 0``) (7.84) is ``theta'' = f(theta)``; its equilibrium
``theta*`` is the level-flight pitch (the angle equation (7.25) with ``gamma_e = 0``) and ``f'(theta*) > 0`` makes it
a saddle, ``+-lambda``, ``lambda = sqrt(f'(theta*))`` ([36]; §7.3.1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .. import checks
from ..derivatives import jacobians
from ..errors import ModelError, SolverError
from ..models._validate import angle_arg, require_instance, speed_arg, trailing_array
from ..models.ctol import CTOLAircraft, require_ctol
from ..params import Vehicle
from .ctol_trajectory import ClimbTrajectory

__all__ = [
    "ZeroDynamics",
    "feedback_linearizing_inputs",
    "frozen_internal_dynamics",
    "internal_acceleration",
    "level_flight_state",
    "outer_loop_acceleration",
    "require_inversion_vehicle",
    "saddle_directions",
    "zero_dynamics",
]


def require_inversion_vehicle(veh: Vehicle, need_eps: bool = True) -> None:
    """Raise :class:`ModelError` unless ``veh`` is a CTOL aircraft on which (7.81) can be solved for ``u2``.

    Parameters
    ----------
    veh : Vehicle
        Must be a CTOL aircraft (``kind = "ctol"``).
    need_eps : bool
        Also require ``epsilon != 0`` (the elevator force ``eps u2``, which (7.81) divides by).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``need_eps`` not a bool.
    ModelError
        If ``veh`` is not a CTOL aircraft, or ``need_eps`` and ``epsilon = 0``.
    """
    require_ctol(veh)
    checks.boolean("need_eps", need_eps)
    if need_eps and veh.epsilon == 0:
        raise ModelError("epsilon = 0: u2 produces no force, so (7.81) cannot be solved for u2; use the approximate "
                         "linearization (ApproximateLinearizationController) for eps = 0")


def _aero_force(model: CTOLAircraft, v: Any, theta: Any) -> Any:
    """Aerodynamic force ``(-D cos g - L sin g, -D sin g + L cos g)`` (N) from the model's right-hand side at zero
    input (complex-safe; ``v`` shape ``(..., 2)``)."""
    veh = model.vehicle
    theta = np.asarray(theta)
    z = np.zeros_like(theta)
    x = np.stack(np.broadcast_arrays(z, z, v[..., 0], v[..., 1], theta, z), -1)
    acc = model.rhs(x, np.zeros((*x.shape[:-1], 2)))[..., 2:4]
    return veh.m * (acc + np.array([0.0, veh.g]))


def level_flight_state(speed: float, theta: float) -> np.ndarray:
    """Full CTOL state ``(0, 0, speed, 0, theta, 0)`` of level flight at the origin: ``speed`` in m/s, pitch
    ``theta`` in rad (the start of the §7.3.3 climb is ``theta = theta*`` of :func:`zero_dynamics`).

    Raises
    ------
    ArgumentTypeError
        If ``speed`` or ``theta`` is not a real number.
    ArgumentError
        If ``speed`` is not in ``(0, 100]`` or ``theta`` not finite.
    """
    speed = speed_arg("speed", speed)
    theta = angle_arg("theta", theta)
    return np.array([0.0, 0.0, speed, 0.0, theta, 0.0])


def feedback_linearizing_inputs(veh: Vehicle, x: Any, w: Any) -> np.ndarray:
    """Inputs that make ``(x'', y'') = w`` exactly: (7.80)-(7.81) in general units (see the module docstring).

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft with ``epsilon != 0``.
    x : array_like, shape (..., 6)
        States ``(x, y, xdot, ydot, theta, Omega2)`` (m, m, m/s, m/s, rad, rad/s); may be complex (complex step).
    w : array_like, shape (..., 2)
        Commanded accelerations ``(w1, w2)`` (m/s^2), (7.82)-(7.83).

    Returns
    -------
    ndarray, shape (..., 2)
        ``(u1, u2)`` (N, N m).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``x``, ``w`` are not arrays of numbers.
    ArgumentError
        If ``x`` does not have shape ``(..., 6)`` or ``w`` shape ``(..., 2)``.
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0``.
    """
    require_inversion_vehicle(veh)
    x = trailing_array("x", x, 6)
    w = trailing_array("w", w, 2)
    F = _aero_force(CTOLAircraft(veh), x[..., 2:4], x[..., 4])
    c, s = np.cos(x[..., 4]), np.sin(x[..., 4])
    a = veh.m * w[..., 0] - F[..., 0]  # = u1 cos + eps u2 sin
    b = veh.m * (w[..., 1] + veh.g) - F[..., 1]  # = u1 sin - eps u2 cos
    return np.stack(np.broadcast_arrays(a * c + b * s, (a * s - b * c) / veh.epsilon), -1)


def internal_acceleration(veh: Vehicle, x: Any, w: Any) -> Any:
    """Internal dynamics (7.84): ``theta'' = u2 / J`` (rad/s^2) under the linearizing ``u2`` of (7.81).

    Parameters
    ----------
    veh : Vehicle
    x : array_like, shape (..., 6)
        States (only ``xdot, ydot, theta`` enter).
    w : array_like, shape (..., 2)
        Output accelerations ``(x'', y'')`` (m/s^2).

    Raises
    ------
    ArgumentTypeError, ArgumentError, ModelError
        As :func:`feedback_linearizing_inputs`.
    """
    return feedback_linearizing_inputs(veh, x, w)[..., 1] / veh.J


def outer_loop_acceleration(trajectory: ClimbTrajectory, kp: float, kd: float, t: Any, x: Any) -> Any:
    """Outer loop (7.82)-(7.83): commanded output acceleration ``w = p_d'' + kd (p_d' - p') + kp (p_d - p)``.

    Parameters
    ----------
    trajectory : ClimbTrajectory
        Desired output ``p_d(t) = (x_d, y_d)`` (m).
    kp : float
        Position gain (1/s^2).
    kd : float
        Velocity gain (1/s).
    t : float or array_like
        Time (s); an array broadcasting with ``x[..., 0]``.
    x : array_like, shape (..., 6)
        States ``(x, y, xdot, ydot, theta, Omega2)``; may be complex (complex step).

    Returns
    -------
    ndarray, shape (..., 2)
        ``w`` (m/s^2).

    Raises
    ------
    ArgumentTypeError
        If ``trajectory`` is not a ClimbTrajectory or an argument is not numbers.
    ArgumentError
        If ``kp``, ``kd`` or ``t`` is not finite, or ``x`` does not have shape ``(..., 6)``.
    """
    require_instance("trajectory", trajectory, ClimbTrajectory)
    kp, kd = checks.real("kp", kp), checks.real("kd", kd)
    d = trajectory.derivatives(t, 2)
    x = trailing_array("x", x, 6)
    return d[..., 2, :] + kd * (d[..., 1, :] - x[..., 2:4]) + kp * (d[..., 0, :] - x[..., :2])


@dataclass(frozen=True)
class ZeroDynamics:
    """Zero dynamics (7.84) for level flight at constant speed (``w = 0``).

    Attributes
    ----------
    speed : float
        ``V`` (m/s).
    theta : float
        Equilibrium pitch ``theta*`` (rad); equals the level-glide angle of attack.
    thrust : float
        ``u1`` of (7.80) at the equilibrium (N).
    jacobian : ndarray (2, 2)
        Linearization of ``(theta, Omega2)' = (Omega2, theta'')`` at ``theta*`` (complex step).
    eigenvalues : ndarray (2,)
        Its eigenvalues, ascending (1/s): ``(-lambda, +lambda)`` for the saddle.
    unstable_vector, stable_vector : ndarray (2,)
        Unit eigenvectors of ``+lambda`` and ``-lambda`` in ``(theta, Omega2)`` (theta component > 0).
    residual : float
        ``|theta''(theta*)|`` (rad/s^2).
    vehicle : Vehicle
        The aircraft.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    """

    speed: float
    theta: float
    thrust: float
    jacobian: np.ndarray = field(repr=False)
    eigenvalues: np.ndarray
    unstable_vector: np.ndarray = field(repr=False)
    stable_vector: np.ndarray = field(repr=False)
    residual: float
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = field(default="", repr=False)

    @property
    def is_saddle(self) -> bool:
        ev = self.eigenvalues
        return bool(np.all(np.abs(np.imag(ev)) < 1e-12) and ev[0].real < 0 < ev[1].real)

    @property
    def rate(self) -> float:
        """Unstable eigenvalue ``lambda`` (1/s)."""
        return float(np.real(self.eigenvalues[-1]))


def frozen_internal_dynamics(veh: Vehicle, x: np.ndarray, w: np.ndarray, y: Any) -> Any:
    """Right-hand side ``(Omega2, theta'')`` (rad/s, rad/s^2) of the internal dynamics (7.84) with the output frozen.

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``epsilon != 0``).
    x : ndarray, shape (6,)
        Full state whose velocity ``(xdot, ydot)`` (m/s) is frozen (its pitch entries are replaced by ``y``).
    w : ndarray, shape (2,)
        Frozen output acceleration ``(x'', y'')`` (m/s^2).
    y : array_like, shape (..., 2)
        Internal state ``(theta, Omega2)`` (rad, rad/s), batched over its leading dimensions; may be complex.

    Returns
    -------
    ndarray, shape (..., 2)

    Raises
    ------
    ArgumentTypeError, ArgumentError, ModelError
        Bad vehicle or array shapes (as :func:`feedback_linearizing_inputs`).
    """
    y = trailing_array("y", y, 2)
    x = trailing_array("x", x, 6)
    X = np.broadcast_to(x, (*y.shape[:-1], 6)).astype(y.dtype, copy=True)
    X[..., 4], X[..., 5] = y[..., 0], y[..., 1]
    return np.stack([y[..., 1], internal_acceleration(veh, X, w)], -1)


def saddle_directions(J: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenvalues and the unstable and stable eigenvectors of a 2x2 linearization ``J`` (1/s).

    Returns
    -------
    eigenvalues : ndarray, shape (2,)
        Sorted by real part (real for a saddle).
    unstable_vector, stable_vector : ndarray, shape (2,)
        Eigenvectors of the larger and the smaller eigenvalue; for real eigenvalues normalized to unit length
        with a positive first (``theta``) component.

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``J`` is not a finite real 2x2 array.
    SolverError
        If the eigenvalue computation fails.
    """
    J = checks.array("J", J, shape=(2, 2))
    try:
        ev, V = np.linalg.eig(J)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigen-decomposition of the 2x2 linearization failed: {exc}") from exc
    order = np.argsort(ev.real)
    ev, V = ev[order], V[:, order]
    if np.any(np.abs(ev.imag) > 1e-12):
        return ev, V[:, 1], V[:, 0]
    V = np.real(V)
    V = V / np.where(V[0] < 0, -1.0, 1.0) / np.linalg.norm(V, axis=0)
    return np.real(ev), V[:, 1], V[:, 0]


def zero_dynamics(veh: Vehicle, speed: float) -> ZeroDynamics:
    """Zero dynamics of the CTOL aircraft for level flight at constant ``speed`` (§7.3.1, (7.84) with ``w = 0``).

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``epsilon != 0``).
    speed : float
        Level-flight speed ``V > 0`` (m/s); §7.3.3 uses ``0.85 / sqrt(a_L)``.

    Returns
    -------
    ZeroDynamics
        The equilibrium of smallest ``|theta|`` on ``(-pi/2, pi/2)`` and its linearization.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``speed`` not a real number.
    ArgumentError
        If ``speed`` is not in ``(0, 100]``.
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0``.
    SolverError
        No equilibrium on ``(-pi/2, pi/2)``, or the root finder fails.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> zd = gc.zero_dynamics(veh, gc.climb_trajectory(veh).speed)
    >>> zd.is_saddle, f"theta* = {zd.theta:.4f} rad", f"rate {zd.rate:.2f} 1/s"
    (True, 'theta* = 0.0633 rad', 'rate 3.82 1/s')
    """
    require_inversion_vehicle(veh)
    V = speed_arg("speed", speed)
    x = level_flight_state(V, 0.0)
    w = np.zeros(2)

    def f(th: Any) -> Any:
        return frozen_internal_dynamics(veh, x, w, np.stack(np.broadcast_arrays(th, 0.0 * np.asarray(th)), -1))[..., 1]

    grid = np.linspace(-0.5 * math.pi, 0.5 * math.pi, 4001)[1:-1]
    fg = f(grid)
    if not np.all(np.isfinite(fg)):
        raise SolverError(f"the internal dynamics at V = {V:g} is not finite on (-pi/2, pi/2)")
    idx = np.nonzero(np.sign(fg[:-1]) * np.sign(fg[1:]) <= 0)[0]
    if idx.size == 0:
        raise SolverError(f"no level-flight equilibrium of the zero dynamics at V = {V:g} on (-pi/2, pi/2)")
    try:
        roots = [brentq(lambda s: float(f(s)), grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15) for i in idx]
    except (ValueError, RuntimeError) as exc:
        raise SolverError(f"root finding of the level-flight zero dynamics at V = {V:g} failed: {exc}") from exc
    th = float(min(roots, key=abs))
    y = np.array([th, 0.0])
    Jac, _ = jacobians(lambda Y, U: frozen_internal_dynamics(veh, x, w, Y), y, np.zeros(0))
    ev, vu, vs = saddle_directions(Jac)
    X = level_flight_state(V, th)
    u = feedback_linearizing_inputs(veh, X, w)
    return ZeroDynamics(V, th, float(u[0]), Jac, ev, vu, vs, float(abs(f(th))), veh, veh.provenance)
