"""Approximate (minimum-phase) linearization of the CTOL aircraft for the §7.3.3 climb (§7.3.1, [63]).

Approximate linearization ([63], as applied to the CTOL aircraft in [36]). The design model neglects the coupling
(``eps = 0``): then ``u2`` drops out of ``p''``, the thrust is dynamically extended (``u1, u1'`` become states, ``u1''``
a new input) and ``u2`` appears, through ``theta''``, in ``p''''``. The relative degree is (4, 4) = 8 = the extended
state dimension, so the ``eps = 0`` model is fully linearizable (no zero dynamics, minimum phase). The time
derivatives of ``L`` and ``D`` come from the design model's right-hand side by complex step: first derivatives
exactly, and the one second directional derivative by the ``e^{i pi/4}`` complex step (truncation ``O(h^4)``, no
subtractive cancellation of O(1) terms). The law is applied to the true ``eps = 0.3`` plant.

The plant with the thrust extended is :class:`glidectl.models.ctol.ExtendedCTOL`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import central_difference_jacobians, jacobian_batch, second_directional_derivative
from ..errors import SolverError
from ..models._validate import require_instance, speed_arg
from ..models.ctol import CTOLAircraft, ExtendedCTOL
from ..params import Vehicle
from .ctol_runs import TrackingRun, simulate_window
from .ctol_trajectory import ClimbTrajectory, climb_trajectory
from .ctol_zero_dynamics import level_flight_state, require_inversion_vehicle, zero_dynamics

__all__ = ["ApproximateLinearizationController", "approximate_linearization_eigenvalues",
           "track_approximate_linearization"]

_H = 1e-30  # complex step


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
        Error-dynamics pole magnitude (1/s): ``(s + pole)^4`` per axis, in ``(0, 100]``.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle, ``trajectory`` not a ClimbTrajectory or ``pole`` not a real number.
    ArgumentError
        If ``pole`` is not in ``(0, 100]`` 1/s.
    ModelError
        If ``vehicle`` is not a CTOL aircraft.
    """

    vehicle: Vehicle
    trajectory: ClimbTrajectory
    pole: float = 1.0
    _design: CTOLAircraft = field(init=False, repr=False)
    _desired: ClimbTrajectory = field(init=False, repr=False)

    def __post_init__(self) -> None:
        require_inversion_vehicle(self.vehicle, need_eps=False)
        require_instance("trajectory", self.trajectory, ClimbTrajectory, " (from gc.climb_trajectory)")
        object.__setattr__(self, "pole", checks.real("pole", self.pole, lo=0.0, hi=100.0, lo_open=True, unit="1/s"))
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

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``X`` is not 8 finite real numbers (the states of :class:`ExtendedCTOL`).
        """
        X = checks.array("X (the 8 states x, y, xdot, ydot, theta, Omega2, u1, u1dot of ExtendedCTOL)", X,
                         shape=(8,))
        a0 = self._a0(X)
        # first derivatives of a0 w.r.t. the 8 states (complex step, one batch)
        Da = jacobian_batch(self._a0, X, _H)  # (2, 8)
        d1 = np.zeros(8)
        d1[2:4], d1[4], d1[6] = a0, X[5], X[7]
        j0 = Da @ d1
        nd = float(np.linalg.norm(d1))
        if nd > 0:
            h = 1e-3 / nd
            s2 = second_directional_derivative(self._a0, X, d1, h)
        else:
            s2 = np.zeros(2)
        r0 = s2 + Da[:, 2:4] @ j0
        M = np.column_stack([Da[:, 6], Da[:, 4] / self.vehicle.J])
        return {"a0": a0, "j0": j0, "r0": r0, "M": M}

    def __call__(self, t: float, X: Any) -> np.ndarray:
        """Inputs ``(u1ddot, u2)`` at time ``t`` (s) and the 8 states ``X`` of :class:`ExtendedCTOL`.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``X`` is not 8 finite real numbers or ``t`` not a finite real number.
        SolverError
            If the decoupling matrix is singular at this state.
        """
        c = self.coordinates(X)
        X = np.asarray(X, dtype=float)
        d = self._desired.derivatives(t, 4)
        k0, k1, k2, k3 = self.gains
        v = d[4] + k3 * (d[3] - c["j0"]) + k2 * (d[2] - c["a0"]) + k1 * (d[1] - X[2:4]) + k0 * (d[0] - X[:2])
        M = c["M"]
        cond = float(np.linalg.cond(M)) if np.all(np.isfinite(M)) else np.inf
        if not cond < 1e12:  # relative test: the matrix's own scale, not an absolute determinant
            raise SolverError(f"singular decoupling matrix at t = {t:.4g} s (condition number {cond:.3g})")
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
        (s), in ``(0, 10^4]``.
    dt : float
        Output spacing (s), ``0 < dt <= t_final``.
    max_error : float
        Stop if the position error exceeds this (m).
    u_max : float
        Stop if ``|u1|`` or ``|u2|`` exceeds this (N, N m): the closed loop on the ``eps = 0.3`` aircraft diverges
        violently (and the integrator would grind) long before the position error grows.

    Returns
    -------
    TrackingRun
        From the §7.3.3 start: level flight at ``(0, 0)``, ``theta = theta*``, ``u1 = u1*``, ``u1dot = 0``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``traj`` not a ClimbTrajectory or a number not a real number.
    ArgumentError
        If ``pole`` is not in ``(0, 100]``, ``t_final`` not in ``(0, 10^4]``, ``dt`` not in ``(0, t_final]``, or
        ``max_error`` or ``u_max`` is not a positive finite number; or the stop condition already holds at the
        start (from :func:`glidectl.sim.simulate`).
    ModelError
        If ``veh`` is not a CTOL aircraft.
    BudgetError
        If the integration hits its step budget (:func:`glidectl.sim.simulate`).
    SolverError
        If the zero dynamics have no level-flight equilibrium at the trajectory speed (the start), the decoupling
        matrix becomes singular during the run, or the integration fails.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> bad = gc.track_approximate_linearization(veh, t_final=2.0)          # epsilon = 0.3: diverges
    >>> bad.completed, f"stopped at {bad.stopped_at:.2f} s"
    (False, 'stopped at 1.58 s')
    >>> ok = gc.track_approximate_linearization(veh.with_overrides(epsilon=0.0), t_final=2.0)
    >>> ok.completed, bool(ok.max_error < 1e-6)
    (True, True)
    """
    require_inversion_vehicle(veh, need_eps=False)
    traj = climb_trajectory(veh) if traj is None else require_instance("traj", traj, ClimbTrajectory,
                                                                          " (from gc.climb_trajectory)")
    t_final = checks.real("t_final", t_final, lo=0.0, hi=1e4, lo_open=True, unit="s")
    dt = checks.real("dt", dt, lo=0.0, hi=t_final, lo_open=True, unit="s")
    max_error = checks.positive("max_error", max_error, unit="m")
    u_max = checks.positive("u_max", u_max)
    ctrl = ApproximateLinearizationController(veh, traj, pole)
    if veh.epsilon != 0:
        zd = zero_dynamics(veh, traj.speed)
        th, u1 = zd.theta, zd.thrust
    else:
        zd = zero_dynamics(veh.with_overrides(epsilon=1.0), traj.speed)  # same equilibrium: u2 = 0 there
        th, u1 = zd.theta, zd.thrust
    X0 = np.r_[level_flight_state(traj.speed, th), u1, 0.0]
    desired = ctrl._desired

    def stop(t: float, X: np.ndarray) -> float:
        try:
            u2 = abs(float(ctrl(t, X)[1]))
        except SolverError:
            return -1.0
        return min(max_error - float(np.linalg.norm(X[:2] - desired.derivatives(t, 0)[0])), u_max - max(abs(X[6]), u2))

    t, X, V, stopped = simulate_window(ExtendedCTOL(veh), X0, 0.0, t_final, ctrl, dt, stop=stop)
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

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (any ``epsilon >= 0``).
    speed : float
        Level-flight speed ``V > 0`` (m/s; normalized units for ``dc8_ctol``).
    pole : float
        Error-dynamics pole magnitude of the design (1/s), ``> 0``.

    Returns
    -------
    numpy.ndarray, shape (8,)
        Eigenvalues (1/s) of the central-difference Jacobian of the closed loop in the 8 states of
        :class:`ExtendedCTOL`, sorted by real part, then imaginary part.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or a number not a real number.
    ArgumentError
        If ``speed`` is not in ``(0, 100]`` or ``pole`` not in ``(0, 100]``.
    ModelError
        If ``veh`` is not a CTOL aircraft.
    SolverError
        If the zero dynamics have no level-flight equilibrium at ``speed``, the decoupling matrix is singular
        there, or the Jacobian is not finite.

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")                    # epsilon = 0.3
    >>> speed = gc.climb_trajectory(veh).speed
    >>> ev = gc.approximate_linearization_eigenvalues(veh, speed)
    >>> ev.shape, bool(ev.real.max() > 0)                    # the eps = 0 design destabilizes the true aircraft
    ((8,), True)
    >>> ev0 = gc.approximate_linearization_eigenvalues(veh.with_overrides(epsilon=0.0), speed)
    >>> print(f"{ev0.real.min():.1f} {ev0.real.max():.1f}")  # exact design: every eigenvalue at -pole
    -1.0 -1.0
    """
    require_inversion_vehicle(veh, need_eps=False)
    V = speed_arg("speed", speed)
    level = ClimbTrajectory(V, forcing=0.0)
    ctrl = ApproximateLinearizationController(veh, level, pole)
    zd = zero_dynamics(veh if veh.epsilon != 0 else veh.with_overrides(epsilon=1.0), V)
    X0 = np.r_[level_flight_state(V, zd.theta), zd.thrust, 0.0]
    model = ExtendedCTOL(veh)
    A, _ = central_difference_jacobians(lambda X, U: model.rhs(X, ctrl(0.0, X)), X0, np.zeros(0))
    if not np.all(np.isfinite(A)):
        raise SolverError(f"the closed-loop Jacobian in level flight at V = {V:g} is not finite")
    try:
        ev = np.linalg.eigvals(A)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigenvalues of the approximate-linearization closed loop did not converge: {exc}") from exc
    return ev[np.lexsort((ev.imag, ev.real))]
