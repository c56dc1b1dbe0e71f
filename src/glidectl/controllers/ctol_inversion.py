"""Exact-tracking baselines for the CTOL climb of §7.3.3: feedback linearization (§7.3.1, (7.80)-(7.84)), its zero
dynamics, stable (non-causal) inversion, and an approximate (minimum-phase) linearization.

These are the methods §7.3.1 reviews and §7.3.3 compares the steady-gliding tracker against ([36], [60], [63]).

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

Stable inversion (Devasia, Chen and Paden). The internal dynamics driven by the desired output,
``theta'' = f(t, theta, theta')``, has a unique bounded solution on the whole line; it is non-causal (it starts to
move before ``t = 0``, the *pre-action*). It is computed on ``[t0, t1]`` with :func:`scipy.integrate.solve_bvp`
and the boundary conditions: at ``t0 < 0`` (level flight) the state lies on the unstable eigenvector of the
linearized internal dynamics about the level-flight equilibrium (no stable component), at ``t1`` on the stable
eigenvector about the frozen-time equilibrium of the end of the climb (level flight at ``y = 10`` up to the
exponentially small tail of (7.91)). The feedforward ``(u1_ff, u2_ff)`` is (7.80)-(7.81) with ``w = p_d''`` along
that reference, so the plant started on the reference state reproduces ``p_d`` exactly. The inverse is unstable to
perturbations (the saddle), so it is flown with feedback: (7.80)-(7.81) at the measured state with the outer loop
on ``(x, y)``, plus a pitch correction ``delta u2 = -K(t) (x - x_ref(t))`` from a finite-horizon, time-varying LQR
designed on the exact (complex-step) linearization of that feedback-linearized loop along the reference.

Approximate linearization ([63], as applied to the CTOL aircraft in [36]). The design model neglects the coupling
(``eps = 0``): then ``u2`` drops out of ``p''``, the thrust is dynamically extended (``u1, u1'`` become states, ``u1''``
a new input) and ``u2`` appears, through ``theta''``, in ``p''''``. The relative degree is (4, 4) = 8 = the extended
state dimension, so the ``eps = 0`` model is fully linearizable (no zero dynamics, minimum phase). The time
derivatives of ``L`` and ``D`` come from the design model's right-hand side by complex step: first derivatives
exactly, and the one second directional derivative by the ``e^{i pi/4}`` complex step (truncation ``O(h^4)``, no
subtractive cancellation of O(1) terms). The law is applied to the true ``eps = 0.3`` plant.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np
from scipy.integrate import solve_bvp, solve_ivp
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from .._checks import positive_number
from ..analysis.jacobian import central_difference_jacobians, jacobians
from ..errors import ModelError, SolverError
from ..models.ctol import CTOL_STATES, CTOLAircraft, require_ctol
from ..params import Vehicle
from ..sim import simulate
from .ctol_runs import TrackingRun
from .ctol_trajectory import ClimbTrajectory, climb_trajectory

__all__ = [
    "ApproximateLinearizationController",
    "BlowUp",
    "ExtendedCTOL",
    "FeedbackLinearizingController",
    "InternalEquilibrium",
    "InversionTracker",
    "StableInversion",
    "ZeroDynamics",
    "approximate_linearization_eigenvalues",
    "feedback_linearization_blowup",
    "feedback_linearizing_inputs",
    "internal_acceleration",
    "stable_inversion",
    "track_approximate_linearization",
    "track_stable_inversion",
    "zero_dynamics",
]

_H = 1e-30  # complex step


# ---------------------------------------------------------------------------------------------------------------
# helpers


def _check_vehicle(veh: Vehicle, need_eps: bool = True) -> None:
    require_ctol(veh)
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


def _level_state(speed: float, theta: float) -> np.ndarray:
    return np.array([0.0, 0.0, speed, 0.0, theta, 0.0])


# ---------------------------------------------------------------------------------------------------------------
# feedback linearization (7.80)-(7.84)


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
    """
    _check_vehicle(veh)
    x, w = np.asarray(x), np.asarray(w)
    if x.shape[-1:] != (6,) or w.shape[-1:] != (2,):
        raise ModelError(f"x must have shape (..., 6) and w (..., 2), got {x.shape} and {w.shape}")
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
    """
    return feedback_linearizing_inputs(veh, x, w)[..., 1] / veh.J


@dataclass(frozen=True)
class FeedbackLinearizingController:
    """(7.80)-(7.81) with the outer loop ``w = p_d'' + kd (p_d' - p') + kp (p_d - p)`` (7.82)-(7.83).

    The default ``kp = 1, kd = 2`` place both error poles of each axis at ``-1 1/s`` (``(s + 1)^2``).

    Parameters
    ----------
    vehicle : Vehicle
    trajectory : ClimbTrajectory
        Desired ``p_d(t)``.
    kp : float
        Position gain (1/s^2).
    kd : float
        Velocity gain (1/s).
    """

    vehicle: Vehicle
    trajectory: ClimbTrajectory
    kp: float = 1.0
    kd: float = 2.0
    _desired: ClimbTrajectory = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _check_vehicle(self.vehicle)
        positive_number("kp", self.kp)
        positive_number("kd", self.kd)
        object.__setattr__(self, "_desired", self.trajectory)

    def outer(self, t: Any, x: Any) -> Any:
        """``w(t, x)`` (m/s^2), shape ``(..., 2)``; ``x`` may be complex, ``t`` an array broadcasting with
        ``x[..., 0]``."""
        d = self._desired.derivatives(t, 2)
        x = np.asarray(x)
        return d[..., 2, :] + self.kd * (d[..., 1, :] - x[..., 2:4]) + self.kp * (d[..., 0, :] - x[..., :2])

    def __call__(self, t: float, x: Any) -> np.ndarray:
        return feedback_linearizing_inputs(self.vehicle, x, self.outer(t, x))


# ---------------------------------------------------------------------------------------------------------------
# zero dynamics


@dataclass(frozen=True)
class ZeroDynamics:
    """Zero dynamics (7.84) for level flight at constant speed (``w = 0``).

    Attributes
    ----------
    speed : float
        ``V`` (m/s).
    theta_star : float
        Equilibrium pitch (rad); equals the level-glide angle of attack.
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
    vehicle : str
    """

    speed: float
    theta_star: float
    thrust: float
    jacobian: np.ndarray = field(repr=False)
    eigenvalues: np.ndarray
    unstable_vector: np.ndarray = field(repr=False)
    stable_vector: np.ndarray = field(repr=False)
    residual: float
    vehicle: str = ""

    @property
    def is_saddle(self) -> bool:
        ev = self.eigenvalues
        return bool(np.all(np.abs(np.imag(ev)) < 1e-12) and ev[0].real < 0 < ev[1].real)

    @property
    def rate(self) -> float:
        """Unstable eigenvalue ``lambda`` (1/s)."""
        return float(np.real(self.eigenvalues[-1]))


def _frozen_internal(veh: Vehicle, x: np.ndarray, w: np.ndarray, y: Any) -> Any:
    """``(Omega2, theta'')`` of (7.84) at the frozen output state ``x`` (velocity), ``w``, for ``y = (theta, Omega2)``
    (batch over the leading dimensions of ``y``)."""
    y = np.asarray(y)
    X = np.broadcast_to(x, (*y.shape[:-1], 6)).astype(y.dtype, copy=True)
    X[..., 4], X[..., 5] = y[..., 0], y[..., 1]
    return np.stack([y[..., 1], internal_acceleration(veh, X, w)], -1)


def _saddle(J: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ev, V = np.linalg.eig(J)
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
    ModelError
        Bad vehicle or speed.
    SolverError
        No equilibrium on ``(-pi/2, pi/2)``.
    """
    _check_vehicle(veh)
    V = positive_number("speed", speed)
    x = _level_state(V, 0.0)
    w = np.zeros(2)

    def f(th: Any) -> Any:
        return _frozen_internal(veh, x, w, np.stack(np.broadcast_arrays(th, 0.0 * np.asarray(th)), -1))[..., 1]

    grid = np.linspace(-0.5 * math.pi, 0.5 * math.pi, 4001)[1:-1]
    fg = f(grid)
    idx = np.nonzero(np.sign(fg[:-1]) * np.sign(fg[1:]) <= 0)[0]
    if idx.size == 0:
        raise SolverError(f"no level-flight equilibrium of the zero dynamics at V = {V:g} on (-pi/2, pi/2)")
    roots = [brentq(lambda s: float(f(s)), grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15) for i in idx]
    th = float(min(roots, key=abs))
    y = np.array([th, 0.0])
    Jac, _ = jacobians(lambda Y, U: _frozen_internal(veh, x, w, Y), y, np.zeros(0))
    ev, vu, vs = _saddle(Jac)
    X = _level_state(V, th)
    u = feedback_linearizing_inputs(veh, X, w)
    return ZeroDynamics(V, th, float(u[0]), Jac, ev, vu, vs, float(abs(f(th))), veh.name)


# ---------------------------------------------------------------------------------------------------------------
# stable inversion


@dataclass(frozen=True)
class InternalEquilibrium:
    """Frozen-time equilibrium of the internal dynamics at a window end (boundary conditions of the inversion).

    Attributes
    ----------
    t : float
        Time (s).
    theta : float
        Equilibrium pitch (rad) of ``theta'' = f(t, theta, 0)`` with the trajectory frozen at ``t``.
    eigenvalues : ndarray (2,)
        Of the frozen linearization (1/s), ascending.
    unstable_vector, stable_vector : ndarray (2,)
        Eigenvectors in ``(theta, Omega2)``.
    """

    t: float
    theta: float
    eigenvalues: np.ndarray
    unstable_vector: np.ndarray = field(repr=False)
    stable_vector: np.ndarray = field(repr=False)


@dataclass(frozen=True, eq=False)
class StableInversion:
    """Bounded, non-causal solution ``theta_ref(t)`` of the internal dynamics (7.84) driven by ``p_d`` on
    ``[t0, t1]`` and the exact feedforward (7.80)-(7.81) with ``w = p_d''``.

    Attributes
    ----------
    vehicle : Vehicle
    trajectory : ClimbTrajectory
    t0, t1 : float
        Window (s).
    mesh : ndarray (M,)
        Final collocation mesh of :func:`scipy.integrate.solve_bvp` (s).
    theta, Omega2 : ndarray (M,)
        Solution at the mesh (rad, rad/s).
    rms_residual : float
        Largest relative collocation residual reported by ``solve_bvp``.
    max_residual : float
        ``max |Omega2_ref' - theta''(t, theta_ref)|`` on a grid of 20 points per mesh interval (rad/s^2):
        the reference satisfies (7.84) to this accuracy.
    bc_residual : float
        Largest boundary-condition residual (rad/s).
    start, end : InternalEquilibrium
        Frozen internal equilibria at ``t0`` (level flight: the zero dynamics) and ``t1``.
    """

    vehicle: Vehicle = field(repr=False)
    trajectory: ClimbTrajectory = field(repr=False)
    t0: float
    t1: float
    mesh: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    Omega2: np.ndarray = field(repr=False)
    rms_residual: float
    max_residual: float
    bc_residual: float
    start: InternalEquilibrium
    end: InternalEquilibrium
    _sol: Any = field(repr=False)
    _desired: ClimbTrajectory = field(repr=False)

    def _check_t(self, t: Any) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if np.any(t < self.t0 - 1e-9) or np.any(t > self.t1 + 1e-9):
            raise ModelError(f"the reference exists on [{self.t0:g}, {self.t1:g}] s only")
        return np.clip(t, self.t0, self.t1)

    def pitch(self, t: Any) -> np.ndarray:
        """``(theta_ref, Omega2_ref)`` at ``t`` (rad, rad/s), shape ``(..., 2)``."""
        t = self._check_t(t)
        return np.moveaxis(self._sol(t), 0, -1)

    def reference_state(self, t: Any) -> np.ndarray:
        """Reference state ``(x_d, y_d, x_d', y_d', theta_ref, Omega2_ref)``, shape ``(..., 6)``."""
        t = self._check_t(t)
        d = self._desired.derivatives(t, 1)
        return np.concatenate([d[..., 0, :], d[..., 1, :], self.pitch(t)], -1)

    def feedforward(self, t: Any) -> np.ndarray:
        """``(u1_ff, u2_ff)`` (N, N m): (7.80)-(7.81) with ``w = p_d''`` on the reference, shape ``(..., 2)``."""
        t = self._check_t(t)
        return feedback_linearizing_inputs(self.vehicle, self.reference_state(t), self._desired.derivatives(t, 2)[
            ..., 2, :])


def _internal_along(veh: Vehicle, desired: ClimbTrajectory, t: Any, theta: Any, Omega: Any) -> Any:
    d = desired.derivatives(t, 2)
    X = np.stack(np.broadcast_arrays(d[..., 0, 0], d[..., 0, 1], d[..., 1, 0], d[..., 1, 1], theta, Omega), -1)
    return internal_acceleration(veh, X, d[..., 2, :])


def _quasi_static(veh: Vehicle, desired: ClimbTrajectory, t: np.ndarray, theta0: float) -> np.ndarray:
    """Pitch of zero internal acceleration at each frozen time (vectorized Newton from the level-flight alpha)."""
    d = desired.derivatives(t, 1)
    th = np.arctan2(d[:, 1, 1], d[:, 1, 0]) + theta0
    z = np.zeros_like(th)
    for _ in range(50):
        f = _internal_along(veh, desired, t, th + 1j * _H, z)
        step = np.real(f) / (np.imag(f) / _H)
        th = th - np.clip(step, -0.2, 0.2)
        if np.max(np.abs(step)) < 1e-13:
            break
    return th


def _window_equilibrium(veh: Vehicle, desired: ClimbTrajectory, t: float, theta0: float) -> InternalEquilibrium:
    th = float(_quasi_static(veh, desired, np.array([t]), theta0)[0])
    d = desired.derivatives(t, 2)
    x = np.r_[d[0], d[1], 0.0, 0.0]
    Jac, _ = jacobians(lambda Y, U: _frozen_internal(veh, x, d[2], Y), np.array([th, 0.0]), np.zeros(0))
    ev, vu, vs = _saddle(Jac)
    if not (np.all(np.isreal(ev)) and ev[0] < 0 < ev[1]):
        raise SolverError(f"the frozen internal dynamics at t = {t:g} s is not a saddle (eigenvalues {ev}); the "
                          "stable-inversion boundary conditions need one stable and one unstable direction")
    return InternalEquilibrium(float(t), th, ev, vu, vs)


def stable_inversion(veh: Vehicle, traj: ClimbTrajectory | None = None, *, t0: float = -15.0, t1: float = 45.0,
                     tol: float = 1e-8, nodes: int = 1501) -> StableInversion:
    """Bounded non-causal solution of the internal dynamics (7.84) along the desired climb (stable inversion).

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``dc8_ctol``).
    traj : ClimbTrajectory, optional
        Desired trajectory; default :func:`climb_trajectory` (§7.3.3).
    t0 : float
        Window start (s), < 0: the pre-action starts in the level flight before the climb. The neglected stable
        component decays like ``exp(-lambda |t0|)`` (``lambda ~ 3.8 1/s``), far below the solver tolerance for
        ``t0 = -15``.
    t1 : float
        Window end (s), > 0; the climb (7.91) has settled to ~1e-8 m by 45 s. Simulations must end by ``t1``.
    tol : float
        ``solve_bvp`` tolerance (relative collocation residual).
    nodes : int
        Initial mesh size (uniform).

    Returns
    -------
    StableInversion

    Raises
    ------
    ModelError
        Bad window or vehicle.
    SolverError
        ``solve_bvp`` did not converge, or the residual check failed.
    """
    _check_vehicle(veh)
    traj = climb_trajectory(veh) if traj is None else traj
    if not isinstance(traj, ClimbTrajectory):
        raise ModelError(f"traj must be a ClimbTrajectory, got {type(traj).__name__}")
    if not (math.isfinite(t0) and math.isfinite(t1) and t0 < 0 < t1):
        raise ModelError(f"need t0 < 0 < t1 (the window must contain the level flight before t = 0), got "
                         f"[{t0!r}, {t1!r}]")
    positive_number("tol", tol)
    if nodes < 10:
        raise ModelError(f"nodes must be >= 10, got {nodes}")
    desired = traj
    zd = zero_dynamics(veh, traj.speed)
    start = _window_equilibrium(veh, desired, t0, zd.theta_star)
    end = _window_equilibrium(veh, desired, t1, zd.theta_star)
    # the boundary conditions: the left eigenvector of the unwanted eigenvalue annihilates the deviation
    wl0 = np.linalg.inv(np.column_stack([start.stable_vector, start.unstable_vector]))[0]  # stable coordinate
    wl1 = np.linalg.inv(np.column_stack([end.stable_vector, end.unstable_vector]))[1]  # unstable coordinate
    y0, y1 = np.array([start.theta, 0.0]), np.array([end.theta, 0.0])

    def fun(t: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.vstack([y[1], _internal_along(veh, desired, t, y[0], y[1])])

    def bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
        return np.array([wl0 @ (ya - y0), wl1 @ (yb - y1)])

    mesh = np.linspace(t0, t1, nodes)
    guess = _quasi_static(veh, desired, mesh, zd.theta_star)
    sol = solve_bvp(fun, bc, mesh, np.vstack([guess, np.gradient(guess, mesh)]), tol=tol, max_nodes=100000,
                    bc_tol=tol)
    if sol.status != 0:
        raise SolverError(f"solve_bvp did not converge for the stable inversion: {sol.message}")
    # residual of (7.84) on a fine grid
    tf = np.linspace(t0, t1, 20 * (sol.x.size - 1) + 1)
    yf, dyf = sol.sol(tf), sol.sol(tf, 1)
    res = np.max(np.abs(dyf - fun(tf, yf)))
    bcr = float(np.max(np.abs(bc(sol.y[:, 0], sol.y[:, -1]))))
    if not np.isfinite(res) or res > 1e3 * tol * (1 + np.max(np.abs(fun(tf, yf)))):
        raise SolverError(f"stable-inversion reference fails the residual check: max |residual| = {res:.3g}")
    return StableInversion(veh, traj, float(t0), float(t1), sol.x, sol.y[0], sol.y[1],
                           float(np.max(sol.rms_residuals)), float(res), bcr, start, end, sol.sol, desired)


# ---------------------------------------------------------------------------------------------------------------
# tracking runs


def _run(model: Any, x0: np.ndarray, t_start: float, t_final: float, controller: Callable[[float, Any], Any],
         dt: float, stop: Callable[[float, np.ndarray], float] | None = None, method: str = "LSODA",
         rtol: float = 1e-9, atol: float = 1e-11) -> tuple[np.ndarray, np.ndarray, np.ndarray, float | None]:
    """:func:`glidectl.sim.simulate` on ``[t_start, t_final]`` (time shifted to start at 0)."""
    span = t_final - t_start
    n = round(span / dt)
    te = np.linspace(0.0, span, n + 1)

    def ctrl(s: float, x: Any) -> Any:
        return controller(s + t_start, x)

    st = None if stop is None else (lambda s, x: stop(s + t_start, x))
    sim = simulate(model, x0, span, ctrl, t_eval=te, method=method, rtol=rtol, atol=atol, stop=st)
    stopped = None if sim.stopped_at is None else sim.stopped_at + t_start
    return sim.t + t_start, sim.x, sim.u, stopped


@dataclass(frozen=True)
class BlowUp:
    """Feedback linearization on the climb from the §7.3.3 level-flight start: divergence of the internal dynamics.

    Attributes
    ----------
    run : TrackingRun
        The run until it was stopped.
    blowup_time : float or None
        When ``|theta - theta_ref|`` or ``|u|`` crossed its limit (s); None if it never did.
    growth_rate : float
        Least-squares slope of ``ln |theta - theta_ref|`` over ``fit_window`` (1/s).
    fit_window : tuple of float
        (s).
    frozen_rate : float
        Mean over ``fit_window`` of the unstable eigenvalue of the frozen internal dynamics along the reference
        (1/s): the growth rate the linearization predicts along the (accelerating) climb.
    zero_dynamics : ZeroDynamics
        Level-flight zero dynamics (``zero_dynamics.rate`` is the unstable eigenvalue at ``t <= 0``).
    """

    run: TrackingRun
    blowup_time: float | None
    growth_rate: float
    fit_window: tuple[float, float]
    frozen_rate: float
    zero_dynamics: ZeroDynamics


def _frozen_rate(inv: StableInversion, t: np.ndarray) -> np.ndarray:
    d = inv._desired.derivatives(t, 2)
    xr = inv.reference_state(t)
    out = np.empty(t.size)
    for i in range(t.size):
        Jac, _ = jacobians(lambda Y, U, i=i: _frozen_internal(inv.vehicle, xr[i], d[i, 2], Y), xr[i, 4:6],
                           np.zeros(0))
        out[i] = np.max(np.linalg.eigvals(Jac).real)
    return out


def feedback_linearization_blowup(veh: Vehicle, traj: ClimbTrajectory | None = None, *, kp: float = 1.0,
                                  kd: float = 2.0, t_final: float = 40.0, theta_max: float = 1.0,
                                  u_max: float = 50.0, inversion: StableInversion | None = None,
                                  dt: float = 0.005) -> BlowUp:
    """Feedback linearization (7.80)-(7.83) on the climb from the level-flight state at ``(0, 0)`` (§7.3.3 start,
    ``theta = theta*`` of the zero dynamics, ``Omega2 = 0``), stopped when it blows up.

    Parameters
    ----------
    veh : Vehicle
    traj : ClimbTrajectory, optional
        Default :func:`climb_trajectory`.
    kp, kd : float
        Outer-loop gains (1/s^2, 1/s); default poles ``-1, -1`` per axis.
    t_final : float
        Longest run (s).
    theta_max : float
        Stop when ``|theta - theta_ref(t)| >= theta_max`` (rad); ``theta_ref`` is the bounded solution.
    u_max : float
        Stop when ``max(|u1|, |u2|) >= u_max`` (N, N m); default 10x the peak exact-tracking thrust.
    inversion : StableInversion, optional
        Bounded reference (computed if omitted); must cover ``[0, t_final]``.
    dt : float
        Output spacing (s).

    Returns
    -------
    BlowUp
        The growth rate is fitted on the samples with ``0.02 theta_max <= |theta - theta_ref| <= 0.3 theta_max``.
    """
    _check_vehicle(veh)
    traj = climb_trajectory(veh) if traj is None else traj
    positive_number("t_final", t_final)
    positive_number("theta_max", theta_max)
    positive_number("u_max", u_max)
    inv = stable_inversion(veh, traj, t1=max(45.0, t_final + 5.0)) if inversion is None else inversion
    if inv.t1 < t_final:
        raise ModelError(f"the inversion ends at {inv.t1:g} s < t_final = {t_final:g} s")
    zd = zero_dynamics(veh, traj.speed)
    ctrl = FeedbackLinearizingController(veh, traj, kp, kd)

    def stop(t: float, x: np.ndarray) -> float:
        dth = abs(x[4] - float(inv.pitch(t)[0]))
        return min(theta_max - dth, u_max - float(np.max(np.abs(ctrl(t, x)))))

    x0 = _level_state(traj.speed, zd.theta_star)
    t, X, U, stopped = _run(CTOLAircraft(veh), x0, 0.0, t_final, ctrl, dt, stop=stop, method="RK45")
    err = X[:, :2] - traj.position(t)
    dth = np.abs(X[:, 4] - inv.pitch(t)[:, 0])
    sel = (dth >= 0.02 * theta_max) & (dth <= 0.3 * theta_max)
    # first contiguous stretch after which the deviation keeps growing
    if np.count_nonzero(sel) < 3:
        raise SolverError("the pitch deviation never grew through the fit band; no growth rate")
    ts = t[sel]
    rate = float(np.polyfit(ts, np.log(dth[sel]), 1)[0])
    window = (float(ts[0]), float(ts[-1]))
    frozen = float(np.mean(_frozen_rate(inv, np.linspace(*window, 21))))
    why = "" if stopped is None else (f"; stopped at t = {stopped:.3f} s (|theta - theta_ref| >= {theta_max:g} rad "
                                      f"or |u| >= {u_max:g})")
    run = TrackingRun.from_arrays(f"feedback linearization (kp = {kp:g}, kd = {kd:g})", t, X, U, err,
                                  note=f"level-flight start at (0, 0), theta = theta* = {zd.theta_star:.5f} rad{why}",
                                  stopped_at=stopped)
    return BlowUp(run, stopped, rate, window, frozen, zd)


@dataclass(frozen=True, eq=False)
class InversionTracker:
    """Stable-inversion tracking controller: (7.80)-(7.81) at the measured state with
    ``w = p_d'' + kd (p_d' - p') + kp (p_d - p)``, plus ``delta u2 = -K(t) (x - x_ref(t))``.

    On the reference the law returns the feedforward exactly. ``K(t)`` is the finite-horizon LQR gain of the
    exact (complex-step) linearization ``z' = A(t) z + B(t) delta u2`` of that feedback-linearized loop along the
    reference, cost ``int z' Q z + r delta_u2^2 dt``, with the terminal weight the algebraic-Riccati solution at
    ``t1`` (python-control ``lqr``); the Riccati equation is integrated backwards over ``[t0, t1]``.

    Why not a fixed PD on ``theta - theta_ref``: the internal dynamics is a saddle whose unstable eigenvalue grows
    from 3.8 1/s in level flight to ~25 1/s at the climb's peak speed, so a fixed pitch stiffness that stabilizes
    the climb is far too stiff in level flight, and the added ``u2`` pushes on the position through ``eps u2``,
    which the outer loop feeds back into ``u2`` through (7.81) with gain ``1 / eps``; the LQR on the coupled
    6-state linearization accounts for both.

    Parameters
    ----------
    inversion : StableInversion
    kp, kd : float
        Outer-loop gains (1/s^2, 1/s).
    q : sequence of 6 floats
        Diagonal state weights on ``x - x_ref`` (1/m^2, 1/m^2, s^2/m^2, s^2/m^2, 1/rad^2, s^2/rad^2).
    r : float
        Weight on ``delta u2`` (1/(N m)^2).
    dt_gain : float
        Grid (s) on which ``A, B`` are evaluated (linearly interpolated in the Riccati equation) and ``K`` stored.
    """

    inversion: StableInversion
    kp: float = 1.0
    kd: float = 2.0
    q: tuple[float, ...] = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    r: float = 1.0
    dt_gain: float = 0.01
    _outer: FeedbackLinearizingController = field(init=False, repr=False)
    _grid: np.ndarray = field(init=False, repr=False)
    _K: CubicSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        inv = self.inversion
        q = np.asarray(self.q, dtype=float)
        if q.shape != (6,) or not np.all(np.isfinite(q)) or np.any(q < 0):
            raise ModelError(f"q must be 6 nonnegative weights, got {self.q!r}")
        positive_number("r", self.r)
        positive_number("dt_gain", self.dt_gain)
        object.__setattr__(self, "_outer", FeedbackLinearizingController(inv.vehicle, inv.trajectory, self.kp,
                                                                         self.kd))
        tg = np.linspace(inv.t0, inv.t1, math.ceil((inv.t1 - inv.t0) / self.dt_gain) + 1)
        Ag, Bg = self.linearization(tg)
        Q, Rinv = np.diag(q), 1.0 / float(self.r)
        try:
            _, P1, _ = control.lqr(Ag[-1], Bg[-1], Q, np.array([[float(self.r)]]))
        except Exception as exc:  # python-control raises several types
            raise SolverError(f"no stabilizing LQR at the end of the window t1 = {inv.t1:g} s: {exc}") from exc
        sg = inv.t1 - tg[::-1]  # reversed time s = t1 - t, increasing
        Ar, Br = Ag[::-1], Bg[::-1]

        def riccati(s: float, p: np.ndarray) -> np.ndarray:
            k = min(max(int(np.searchsorted(sg, s)) - 1, 0), sg.size - 2)
            f = (s - sg[k]) / (sg[k + 1] - sg[k])
            A, B = (1 - f) * Ar[k] + f * Ar[k + 1], (1 - f) * Br[k] + f * Br[k + 1]
            P = p.reshape(6, 6)
            PB = P @ B
            dP = A.T @ P + P @ A - Rinv * (PB @ PB.T) + Q
            return (0.5 * (dP + dP.T)).ravel()

        sol = solve_ivp(riccati, (0.0, sg[-1]), np.asarray(P1, dtype=float).ravel(), method="LSODA", rtol=1e-6,
                        atol=1e-8, t_eval=sg)
        if not sol.success or not np.all(np.isfinite(sol.y)):
            raise SolverError(f"the time-varying Riccati equation failed: {sol.message}")
        P = sol.y.T.reshape(-1, 6, 6)[::-1]
        object.__setattr__(self, "_grid", tg)
        object.__setattr__(self, "_K", CubicSpline(tg, Rinv * np.einsum("nij,nik->nk", Bg, P)))

    def closed_loop(self, t: Any, x: Any, du2: Any) -> Any:
        """Plant right-hand side under the law with an extra pitch input ``du2`` (shape ``(..., 1)``; complex-safe,
        ``t`` broadcasting with ``x[..., 0]``)."""
        x = np.asarray(x)
        du2 = np.asarray(du2)[..., 0]
        u = feedback_linearizing_inputs(self.inversion.vehicle, x, self._outer.outer(t, x))
        u = u + np.stack(np.broadcast_arrays(0.0 * du2, du2), -1)
        return CTOLAircraft(self.inversion.vehicle).rhs(x, u)

    def linearization(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(A(t), B(t))`` of the feedback-linearized loop along the reference (complex step, batched over ``t``):
        shapes ``(..., 6, 6)`` and ``(..., 6, 1)``."""
        t = np.asarray(t, dtype=float)
        xr = self.inversion.reference_state(t)
        X = np.repeat(xr[..., None, :], 7, axis=-2).astype(complex)
        U = np.zeros((*X.shape[:-1], 1), dtype=complex)
        X[..., np.arange(6), np.arange(6)] += 1j * _H
        U[..., 6, 0] += 1j * _H
        d = np.imag(self.closed_loop(t[..., None], X, U)) / _H  # (..., 7, 6)
        J = np.swapaxes(d, -1, -2)
        return J[..., :6].copy(), J[..., 6:].copy()

    def gain(self, t: float) -> np.ndarray:
        """``K(t)`` (6,) (N m per unit state error): cubic spline through the ``dt_gain`` grid (smooth in ``t``, so
        the closed loop stays smooth for the integrator)."""
        tg = self._grid
        return self._K(min(max(float(t), tg[0]), tg[-1]))

    def __call__(self, t: float, x: Any) -> np.ndarray:
        inv = self.inversion
        tc = min(max(t, inv.t0), inv.t1)
        x = np.asarray(x, dtype=float)
        du2 = -float(self.gain(tc) @ (x - inv.reference_state(tc)))
        u = feedback_linearizing_inputs(inv.vehicle, x, self._outer.outer(t, x))
        return u + np.array([0.0, du2])


def track_stable_inversion(veh: Vehicle, traj: ClimbTrajectory | None = None, *,
                           inversion: StableInversion | None = None, start: str = "reference",
                           t_final: float = 40.0, kp: float = 1.0, kd: float = 2.0,
                           q: Sequence[float] = (1.0, 1.0, 1.0, 1.0, 1.0, 1.0), r: float = 1.0,
                           dt: float = 0.01) -> TrackingRun:
    """Exact tracking of the climb by stable inversion with feedback (:class:`InversionTracker`).

    Parameters
    ----------
    veh : Vehicle
    traj : ClimbTrajectory, optional
        Default :func:`climb_trajectory`.
    inversion : StableInversion, optional
        Computed with :func:`stable_inversion` if omitted.
    start : {"reference", "level"}
        ``"reference"``: start at ``t0 < 0`` on the reference state (the aircraft flies level and performs the
        pre-action before ``t = 0``). ``"level"``: start at ``t = 0`` in the §7.3.3 level-flight state
        (``theta = theta*``, no pre-action); the feedback absorbs the pitch mismatch.
    t_final : float
        End (s), ``<= inversion.t1``.
    kp, kd, q, r
        Gains and LQR weights, see :class:`InversionTracker`.
    dt : float
        Output spacing (s).

    Returns
    -------
    TrackingRun
        Metrics on ``[0, t_final]``.
    """
    _check_vehicle(veh)
    traj = climb_trajectory(veh) if traj is None else traj
    inv = stable_inversion(veh, traj, t1=max(45.0, t_final + 5.0)) if inversion is None else inversion
    positive_number("t_final", t_final)
    if t_final > inv.t1:
        raise ModelError(f"t_final = {t_final:g} s is past the end of the inversion window ({inv.t1:g} s)")
    if start not in ("reference", "level"):
        raise ModelError(f"start must be 'reference' or 'level', got {start!r}")
    tracker = InversionTracker(inv, kp, kd, tuple(float(v) for v in q), r)
    if start == "reference":
        t_start, x0 = inv.t0, inv.reference_state(inv.t0)
        note = f"started on the reference at t0 = {inv.t0:g} s (pre-action before t = 0)"
    else:
        zd = zero_dynamics(veh, traj.speed)
        t_start, x0 = 0.0, _level_state(traj.speed, zd.theta_star)
        note = "started at t = 0 in level flight (theta = theta*), no pre-action"
    t, X, U, _ = _run(CTOLAircraft(veh), x0, t_start, t_final, tracker, dt)
    keep = t >= -1e-12
    t, X, U = t[keep], X[keep], U[keep]
    err = X[:, :2] - traj.position(t)
    return TrackingRun.from_arrays(f"stable inversion + FL + TV-LQR (kp = {kp:g}, kd = {kd:g}, r = {r:g})", t, X, U,
                                   err, note=note)


# ---------------------------------------------------------------------------------------------------------------
# approximate linearization [63]


@dataclass(frozen=True)
class ExtendedCTOL:
    """The CTOL model (7.5)-(7.7) with the thrust dynamically extended.

    State ``(x, y, xdot, ydot, theta, Omega2, u1, u1dot)``, input ``(u1ddot, u2)`` (N/s^2, N m); the plant part is
    :meth:`CTOLAircraft.rhs` with input ``(u1, u2)``.
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = (*CTOL_STATES, "u1", "u1dot")
    input_names: tuple[str, ...] = ("u1ddot", "u2")

    def rhs(self, X: Any, U: Any) -> Any:
        X, U = np.asarray(X), np.asarray(U)
        u = np.stack(np.broadcast_arrays(X[..., 6], U[..., 1]), -1)
        xp = CTOLAircraft(self.vehicle).rhs(X[..., :6], u)
        return np.concatenate([xp, X[..., 7:8], U[..., 0:1]], -1)


_W8 = cmath.exp(0.25j * math.pi)


@dataclass(frozen=True)
class ApproximateLinearizationController:
    """Approximate input-output linearization of [63] for the CTOL aircraft: exact linearization of the design model
    with ``eps = 0`` by dynamic extension of ``u1``, applied to the true plant (state of :class:`ExtendedCTOL`).

    With ``a0(X)`` the design model's acceleration (:meth:`CTOLAircraft.rhs` of the vehicle with ``epsilon = 0``,
    input ``(u1, 0)``), the coordinates are ``xi = (p, p', a0, j0)``, ``j0 = Da0 . (a0, Omega2, u1dot)``, and

        ``d j0 / dt = D^2 a0 [d1, d1] + (da0/dv) j0 + (da0/du1) u1ddot + (da0/dtheta) u2 / J``,
        ``d1 = (v' = a0, theta' = Omega2, u1' = u1dot)``,

    which is set to ``v = p_d'''' + k3 (p_d''' - j0) + k2 (p_d'' - a0) + k1 (p_d' - p') + k0 (p_d - p)``. The
    2x2 decoupling matrix ``[da0/du1, da0/dtheta / J]`` has determinant ``(u1 + L_alpha cos(alpha) + D_alpha
    sin(alpha)) / (m^2 J)`` (nonzero in flight). The gains put all four poles of each axis at ``-pole``.

    Parameters
    ----------
    vehicle : Vehicle
        The true aircraft; the design model is ``vehicle.with_overrides(epsilon=0)``.
    trajectory : ClimbTrajectory
    pole : float
        Error-dynamics pole magnitude (1/s): ``(s + pole)^4`` per axis.
    """

    vehicle: Vehicle
    trajectory: ClimbTrajectory
    pole: float = 1.0
    _design: CTOLAircraft = field(init=False, repr=False)
    _desired: ClimbTrajectory = field(init=False, repr=False)

    def __post_init__(self) -> None:
        _check_vehicle(self.vehicle, need_eps=False)
        positive_number("pole", self.pole)
        object.__setattr__(self, "_design", CTOLAircraft(self.vehicle.with_overrides(epsilon=0.0)))
        object.__setattr__(self, "_desired", self.trajectory)

    @property
    def gains(self) -> tuple[float, float, float, float]:
        """``(k0, k1, k2, k3)`` of ``(s + pole)^4`` (1/s^4, 1/s^3, 1/s^2, 1/s)."""
        p = float(self.pole)
        return p**4, 4 * p**3, 6 * p**2, 4 * p

    def _a0(self, X: Any) -> Any:
        X = np.asarray(X)
        u = np.stack(np.broadcast_arrays(X[..., 6], 0.0 * X[..., 6]), -1)
        return self._design.rhs(X[..., :6], u)[..., 2:4]

    def coordinates(self, X: Any) -> dict[str, Any]:
        """Design-model output derivatives and the affine map ``p'''' = r0 + M (u1ddot, u2)`` at one state ``X``.

        Returns
        -------
        dict
            ``a0, j0`` (m/s^2, m/s^3), ``r0`` (m/s^4), ``M`` (2x2).
        """
        X = np.asarray(X, dtype=float)
        if X.shape != (8,):
            raise ModelError(f"X must be the 8 states (x, y, xdot, ydot, theta, Omega2, u1, u1dot) of "
                             f"ExtendedCTOL, got shape {X.shape}")
        a0 = self._a0(X)
        # first derivatives of a0 w.r.t. the 8 states (complex step, one batch)
        P = np.broadcast_to(X, (8, 8)).astype(complex)
        P[np.arange(8), np.arange(8)] += 1j * _H
        Da = (np.imag(self._a0(P)) / _H).T  # (2, 8)
        d1 = np.zeros(8)
        d1[2:4], d1[4], d1[6] = a0, X[5], X[7]
        j0 = Da @ d1
        nd = float(np.linalg.norm(d1))
        if nd > 0:
            h = 1e-3 / nd
            s2 = np.imag(self._a0(X + h * _W8 * d1) + self._a0(X - h * _W8 * d1)) / h**2
        else:
            s2 = np.zeros(2)
        r0 = s2 + Da[:, 2:4] @ j0
        M = np.column_stack([Da[:, 6], Da[:, 4] / self.vehicle.J])
        return {"a0": a0, "j0": j0, "r0": r0, "M": M}

    def __call__(self, t: float, X: Any) -> np.ndarray:
        X = np.asarray(X, dtype=float)
        c = self.coordinates(X)
        d = self._desired.derivatives(t, 4)
        k0, k1, k2, k3 = self.gains
        v = d[4] + k3 * (d[3] - c["j0"]) + k2 * (d[2] - c["a0"]) + k1 * (d[1] - X[2:4]) + k0 * (d[0] - X[:2])
        M = c["M"]
        det = np.linalg.det(M)
        if not np.isfinite(det) or abs(det) < 1e-12:
            raise SolverError(f"singular decoupling matrix at t = {t:.4g} s (det = {det:.3g})")
        return np.linalg.solve(M, v - c["r0"])


def track_approximate_linearization(veh: Vehicle, traj: ClimbTrajectory | None = None, *, pole: float = 1.0,
                                    t_final: float = 40.0, dt: float = 0.01, max_error: float = 50.0,
                                    u_max: float = 50.0) -> TrackingRun:
    """Track the climb with the approximate linearization of [63] (eps = 0 design model) on the true plant.

    Parameters
    ----------
    veh : Vehicle
        True aircraft (``epsilon = 0.3`` for ``dc8_ctol``).
    traj : ClimbTrajectory, optional
        Default :func:`climb_trajectory`.
    pole : float
        Error pole magnitude (1/s), see :class:`ApproximateLinearizationController`.
    t_final : float
        (s).
    dt : float
        Output spacing (s).
    max_error : float
        Stop if the position error exceeds this (m).
    u_max : float
        Stop if ``|u1|`` or ``|u2|`` exceeds this (N, N m): the closed loop on the ``eps = 0.3`` aircraft diverges
        violently (and the integrator would grind) long before the position error grows.

    Returns
    -------
    TrackingRun
        From the §7.3.3 start: level flight at ``(0, 0)``, ``theta = theta*``, ``u1 = u1*``, ``u1dot = 0``.
    """
    _check_vehicle(veh, need_eps=False)
    traj = climb_trajectory(veh) if traj is None else traj
    positive_number("t_final", t_final)
    positive_number("max_error", max_error)
    positive_number("u_max", u_max)
    ctrl = ApproximateLinearizationController(veh, traj, pole)
    if veh.epsilon != 0:
        zd = zero_dynamics(veh, traj.speed)
        th, u1 = zd.theta_star, zd.thrust
    else:
        zd = zero_dynamics(veh.with_overrides(epsilon=1.0), traj.speed)  # same equilibrium: u2 = 0 there
        th, u1 = zd.theta_star, zd.thrust
    X0 = np.r_[_level_state(traj.speed, th), u1, 0.0]
    desired = ctrl._desired

    def stop(t: float, X: np.ndarray) -> float:
        try:
            u2 = abs(float(ctrl(t, X)[1]))
        except SolverError:
            return -1.0
        return min(max_error - float(np.linalg.norm(X[:2] - desired.derivatives(t, 0)[0])), u_max - max(abs(X[6]), u2))

    t, X, V, stopped = _run(ExtendedCTOL(veh), X0, 0.0, t_final, ctrl, dt, stop=stop)
    U = np.column_stack([X[:, 6], V[:, 1]])
    err = X[:, :2] - traj.position(t)
    note = "level-flight start at (0, 0); design model eps = 0, dynamic extension of u1"
    if stopped is not None:
        note += f"; stopped at t = {stopped:.3f} s (error >= {max_error:g} m or |u| >= {u_max:g})"
    return TrackingRun.from_arrays(f"approximate linearization [63] (pole = {pole:g})", t, X[:, :6], U, err,
                                   note=note, stopped_at=stopped)


def approximate_linearization_eigenvalues(veh: Vehicle, speed: float, *, pole: float = 1.0) -> np.ndarray:
    """Eigenvalues (1/s) of the true aircraft (state of :class:`ExtendedCTOL`) under
    :class:`ApproximateLinearizationController`, linearized in level flight at ``speed`` (constant-velocity
    trajectory, start on it), ascending real part.

    With ``eps = 0`` the design is exact and all eight eigenvalues sit at ``-pole`` (a repeated root, computed to
    about 1e-2 because a fourfold root is ill-conditioned). For ``eps > 0`` the neglected force ``eps u2`` splits
    the fourfold roots like ``eps^(1/4)``: for the DC-8 a pair crosses into the right half-plane already at
    ``eps = 0.01`` (central differences: the controller itself uses complex steps).
    """
    _check_vehicle(veh, need_eps=False)
    V = positive_number("speed", speed)
    level = ClimbTrajectory(V, forcing=0.0)
    ctrl = ApproximateLinearizationController(veh, level, pole)
    zd = zero_dynamics(veh if veh.epsilon != 0 else veh.with_overrides(epsilon=1.0), V)
    X0 = np.r_[_level_state(V, zd.theta_star), zd.thrust, 0.0]
    model = ExtendedCTOL(veh)
    A, _ = central_difference_jacobians(lambda X, U: model.rhs(X, ctrl(0.0, X)), X0, np.zeros(0))
    ev = np.linalg.eigvals(A)
    return ev[np.lexsort((ev.imag, ev.real))]
