"""Closed loop of the CTOL aircraft under the steady-glide law (7.16)-(7.20), in the reduced nondimensional states
of (7.8)-(7.11) about the glide (the interconnected system (7.28)-(7.39)); its equilibrium is the origin.

    u1 = w11 = -k1 sin theta - k2 cos theta                                   (7.16), (7.18)
    u2 = w21 + w22,  w21 = (k1 cos theta - k2 sin theta) / eps                (7.17), (7.19)
                     w22 = -(k3 / eps) sin(theta - theta_e) - k4 T Omega2     (7.20)

``T Omega2`` is the nondimensional pitch rate ``Omega2bar`` of (7.11); ``k1, k2`` place the equilibrium (Theorem 4,
:func:`glidectl.trim.ctol.ctol_glide`) and ``k3, k4 > 0`` stabilize the pitch. The law is
:func:`steady_glide_inputs` (the controller object for the full model is
:class:`glidectl.controllers.ctol.SteadyGlideController`); :class:`ClosedLoopCTOL` is the one closed-loop right-hand
side used by the Theorem-5 certificate (:mod:`glidectl.stability.ctol_lyapunov`) and the region-of-attraction
certification (:class:`ClosedLoopCTOLAlpha`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, ModelError, SolverError
from ..params import Vehicle
from ..trim.ctol import CTOLGlide
from ._validate import require_ctol_vehicle, require_instance, single_real_state, trailing_array
from .ctol import REDUCED_STATES, CTOLReduced

__all__ = ["ClosedLoopCTOL", "ClosedLoopCTOLAlpha", "check_steady_glide_law", "steady_glide_inputs"]


def check_steady_glide_law(veh: Any, glide: Any, k3: Any, k4: Any, T: Any) -> tuple[float, float, float]:
    """Check the data of the steady-glide law (7.16)-(7.20) and return ``(k3, k4, T)`` as floats.

    Parameters
    ----------
    veh : Vehicle
        Must be a CTOL aircraft with ``epsilon > 0`` (the law divides by it).
    glide : CTOLGlide
        Must come from :func:`glidectl.ctol_glide` for ``veh``.
    k3, k4, T : float
        Pitch gains (N, N m s) and reference time (s): positive finite numbers.

    Returns
    -------
    tuple of float
        ``(k3, k4, T)``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a CTOLGlide, or a gain not a real number.
    ArgumentError
        If ``k3``, ``k4`` or ``T`` is not a positive finite number (``k3, k4 > 0`` stabilize the pitch).
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0`` (no elevator force: the law divides by eps).
    VehicleMismatchError
        If ``glide`` was computed for another vehicle.
    """
    require_ctol_vehicle(veh)
    if not veh.epsilon > 0:
        raise ModelError(f"vehicle '{veh.name}' has epsilon = {veh.epsilon:g}: the steady-glide law (7.17)-(7.20) "
                         "divides by eps (the elevator force coupling), so it needs epsilon > 0")
    require_instance("glide", glide, CTOLGlide, " (from gc.ctol_glide)")
    checks.same_vehicle("glide", glide, veh)
    return (checks.positive("k3 (pitch stiffness gain of (7.20))", k3, unit="N"),
            checks.positive("k4 (pitch damping gain of (7.20))", k4, unit="N m s"),
            checks.positive("T (reference time of (7.11))", T, unit="s"))


def steady_glide_inputs(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float, theta: Any,
                        Omega2: Any) -> Any:
    """Inputs ``(u1, u2)`` of the steady-glide law (7.16)-(7.20) at pitch ``theta`` and pitch rate ``Omega2``.

    Parameters
    ----------
    veh : Vehicle
        CTOL aircraft (``epsilon > 0``: the law divides by it).
    glide : CTOLGlide
        The steady glide (gains ``k1``, ``k2`` in N and ``theta_e`` in rad).
    k3 : float
        Pitch stiffness gain (N; enters as ``k3 / eps``).
    k4 : float
        Pitch damping gain on ``Omega2bar = T Omega2`` (N m s).
    T : float
        Reference time of (7.11) (s).
    theta, Omega2 : array_like
        Pitch angle (rad) and pitch rate (rad/s), broadcasting together (may be complex: complex-step Jacobians).

    Returns
    -------
    ndarray, shape (..., 2)
        Thrust ``u1`` (N) and elevator moment ``u2`` (N m).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.
    ModelError
        If ``veh`` is not a CTOL aircraft or has ``epsilon = 0``.
    """
    if not (type(veh) is Vehicle and veh.kind == "ctol" and veh.epsilon > 0):  # (a CTOL aircraft passes at once)
        require_ctol_vehicle(veh)
        if not veh.epsilon > 0:
            raise ModelError(f"vehicle '{veh.name}' has epsilon = {veh.epsilon:g}: the steady-glide law divides by "
                             "eps")
    return _steady_glide_inputs(veh, glide, k3, k4, T, theta, Omega2)


def _steady_glide_inputs(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float, theta: Any,
                         Omega2: Any) -> Any:
    """:func:`steady_glide_inputs` for data already checked (:func:`check_steady_glide_law`): the hot path of the
    closed-loop right-hand sides."""
    if type(theta) is float:  # one state in Python floats (SteadyGlideController.u): libm's sin and cos, which
        try:                  # numpy's float64 loops call too; an infinite theta falls back to numpy (NaN)
            return np.array(_law(veh.epsilon, glide, k3, k4, T, theta, Omega2, math.sin, math.cos))
        except ValueError:
            theta = np.float64(theta)
    u1, u2 = _law(veh.epsilon, glide, k3, k4, T, theta, Omega2, np.sin, np.cos)
    if getattr(u1, "ndim", 0) == 0 and getattr(u2, "ndim", 0) == 0:  # one state (scalars): no broadcasting
        return np.array((u1, u2))
    return np.stack(np.broadcast_arrays(u1, u2), -1)


def _law(eps: float, glide: CTOLGlide, k3: float, k4: float, T: float, theta: Any, Omega2: Any, sin: Any,
         cos: Any) -> tuple[Any, Any]:
    """``(u1, u2)`` of (7.16)-(7.20) with the given ``sin`` and ``cos`` (``math``'s for floats, numpy's else)."""
    k1, k2 = glide.k1, glide.k2
    s, c = sin(theta), cos(theta)
    u1 = -k1 * s - k2 * c
    u2 = (k1 * c - k2 * s) / eps - (k3 / eps) * sin(theta - glide.theta) - k4 * T * Omega2
    return u1, u2


@dataclass(frozen=True)
class ClosedLoopCTOL:
    """Input-free closed loop (7.12)-(7.20) in the reduced states ``(Vbar, gammabar, thetabar, Omega2bar)``; the
    equilibrium is the origin (the interconnected system (7.28)-(7.39)).

    Parameters
    ----------
    vehicle : Vehicle
        A ``kind = "ctol"`` vehicle with ``epsilon > 0`` (the law divides by it).
    glide : CTOLGlide
        The steady glide flown (:func:`glidectl.trim.ctol.ctol_glide`): ``V_e`` (m/s), ``gamma_e``, ``theta_e``
        (rad) and the gains ``k1, k2`` (N).
    k3 : float
        Pitch stiffness gain of (7.20) (N; enters as ``k3 / eps``).
    k4 : float
        Pitch damping gain of (7.20) on the nondimensional rate ``Omega2bar = T Omega2`` (N m, since ``u2`` is a
        moment).
    T : float
        Reference time of (7.11) (s); default 1.
    state_names : tuple of str
        Names of the 4 nondimensional states; default ``("Vbar", "gammabar", "thetabar", "Omega2bar")``.
    input_names : tuple of str
        Empty: the loop is closed.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle, ``glide`` not a CTOLGlide, or a gain not a real number.
    ArgumentError
        If ``k3``, ``k4`` or ``T`` is not a positive finite number.
    ModelError
        If the vehicle is not a CTOL aircraft or has ``epsilon = 0``.
    VehicleMismatchError
        If ``glide`` was computed for another vehicle.
    """

    vehicle: Vehicle
    glide: CTOLGlide
    k3: float
    k4: float
    T: float = 1.0
    state_names: tuple[str, ...] = REDUCED_STATES
    input_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        k3, k4, T = check_steady_glide_law(self.vehicle, self.glide, self.k3, self.k4, self.T)
        object.__setattr__(self, "k3", k3)
        object.__setattr__(self, "k4", k4)
        object.__setattr__(self, "T", T)

    @cached_property
    def reduced(self) -> CTOLReduced:
        """The open-loop :class:`~glidectl.models.ctol.CTOLReduced` about :attr:`glide` (built once)."""
        return CTOLReduced(self.vehicle, self.glide.speed, self.glide.gamma, self.glide.theta, self.T)

    def rhs(self, s: Any, u: Any = None) -> Any:
        """Closed-loop derivative of the reduced states ``s`` (shape ``(..., 4)``; ``u`` is ignored).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``s`` is not an array of numbers with a trailing dimension 4.
        """
        s = trailing_array("s", s, 4, self.state_names)
        tb, Ob = (s[2], s[3]) if single_real_state(s) else (s[..., 2], s[..., 3])  # numpy scalars for one real state
        th = tb + self.glide.theta
        uu = _steady_glide_inputs(self.vehicle, self.glide, self.k3, self.k4, self.T, th, Ob / self.T)
        return self.reduced.rhs(s, uu)

    def jacobian(self) -> np.ndarray:
        """Exact (complex-step) Jacobian at the origin.

        Raises
        ------
        SolverError
            If it is not finite (the glide is outside the range where the model's arithmetic holds).
        """
        J = jacobians(lambda s, u: self.rhs(s), np.zeros(4), np.zeros(0))[0]
        if not np.all(np.isfinite(J)):
            raise SolverError(f"the closed-loop Jacobian at the glide V_e = {self.glide.speed:g}, gamma_e = "
                              f"{self.glide.gamma:g} is not finite")
        return J

    def roa_model(self, box: tuple[Any, Any] | None = None) -> ClosedLoopCTOLAlpha:
        """This closed loop in ``(Vbar, gammabar, alphabar, Omega2bar)``, ``alphabar = thetabar - gammabar``, for
        region-of-attraction certification (:func:`glidectl.certify_roa`); ``box`` is the region of interest
        (default ``|Vbar| <= 0.5``, ``|gammabar| <= 0.5``, ``|alphabar| <= 0.3``, ``|Omega2bar| <= 1``).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``box`` is not ``(lo, hi)``, two finite 4-vectors with ``lo < hi``.
        """
        if box is None:
            box = (np.array([-0.5, -0.5, -0.3, -1.0]), np.array([0.5, 0.5, 0.3, 1.0]))
        b = checks.array("box", box, shape=(2, 4))
        if not np.all(b[0] < b[1]):
            raise ArgumentError(f"box must be (lo, hi) with lo < hi in every state, got {box!r}")
        return ClosedLoopCTOLAlpha(self, (b[0].copy(), b[1].copy()))


@dataclass(frozen=True)
class ClosedLoopCTOLAlpha:
    """:class:`ClosedLoopCTOL` with ``thetabar`` replaced by ``alphabar = thetabar - gammabar`` (a shear, volume
    preserving). The right-hand side is the closed loop's own, ``alphabar' = thetabar' - gammabar'``.

    In these states ``gammabar`` enters only through ``sin``/``cos`` and ``alphabar`` both polynomially (lift and
    drag (7.1)-(7.2)) and through ``sin``/``cos`` (``angle_states``, ``mixed_angle_states`` for
    :func:`glidectl.roa.recast`); the ``1/V`` of (7.13) is the ``positive_state``.
    """

    closed_loop: ClosedLoopCTOL
    box: tuple[np.ndarray, np.ndarray]
    state_names: tuple[str, ...] = ("Vbar", "gammabar", "alphabar", "Omega2bar")
    input_names: tuple[str, ...] = ()
    angle_states: tuple[int, ...] = (1,)
    mixed_angle_states: tuple[int, ...] = (2,)
    positive_state: int = 0
    time_unit: str = "s"

    @property
    def name(self) -> str:
        cl = self.closed_loop
        return (f"{cl.vehicle.name} closed loop (7.16)-(7.20), V_e = {cl.glide.speed:.4g}, "
                f"gamma_e = {cl.glide.gamma:.4g}, k3 = {cl.k3:g}, k4 = {cl.k4:g}")

    @property
    def provenance(self) -> str:
        return self.closed_loop.vehicle.provenance

    @property
    def equilibrium(self) -> np.ndarray:
        return np.zeros(4)

    def to_theta(self, x: Any) -> np.ndarray:
        """``(Vbar, gammabar, alphabar, Omega2bar) -> (Vbar, gammabar, thetabar, Omega2bar)``."""
        x = trailing_array("x", x, 4, self.state_names)
        return np.stack([x[..., 0], x[..., 1], x[..., 2] + x[..., 1], x[..., 3]], axis=-1)

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        d = self.closed_loop.rhs(self.to_theta(x))
        return np.stack([d[..., 0], d[..., 1], d[..., 2] - d[..., 1], d[..., 3]], axis=-1)
