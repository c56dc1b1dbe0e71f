"""CTOL aircraft of Hauser, Sastry and Meyer, thesis chapter 7: the longitudinal model (7.1)-(7.7), its reduced,
nondimensional form (7.8)-(7.15) about a steady glide, and the model with the thrust dynamically extended (the plant
of the approximate linearization of §7.3.1).

Units. The vehicle file carries ``rho_AW_half``, ``m``, ``g`` and ``J``; §7.1 sets all four to 1, which makes the
printed equations (7.12)-(7.15) exact (they are written with ``m = g = J = rho A_W / 2 = 1``). The right-hand sides
here keep the four parameters, so the normalized model is the special case, and (7.12)-(7.15) are implemented in the
general form::

    V' = (1/m) (-m g sin gamma - D + u1 cos alpha + eps u2 sin alpha)
    gamma' = (1/(m V)) (-m g cos gamma + L + u1 sin alpha - eps u2 cos alpha),   theta'' = u2 / J

The physical DC-8 values quoted in §7.3.3 (m = 85000 kg, J2 = 4e6 kg m^2) do **not** enter the normalized model:
in §7.1 the mass, inertia, rho A_W/2 and g are all 1, so the lift and drag coefficients a_L, a_D are per unit mass
(and per rho A_W/2) and the time unit is fixed by g = 1. Substituting the physical m and J into (7.5)-(7.7) while
keeping a_L = 30 and g = 1 would mix dimensional and normalized quantities; the only consistent use of them is the
ratio J/m = 47.1 m^2, which would rescale the pitch dynamics relative to the translational ones, and the thesis's
simulation sets J = 1. We keep them in the vehicle file for reference only (``m_physical``, ``J2_physical``).

States and inputs are named; arrays may carry leading batch dimensions and may be complex (complex-step Jacobians).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..params import Vehicle
from ._validate import angle_arg, require_ctol_vehicle, single_real_state, speed_arg, trailing_array

__all__ = ["CTOL_INPUTS", "CTOL_STATES", "REDUCED_STATES", "CTOLAircraft", "CTOLReduced", "ExtendedCTOL",
           "drag_coefficient", "lift_coefficient", "require_ctol"]

CTOL_STATES = ("x", "y", "xdot", "ydot", "theta", "Omega2")
CTOL_INPUTS = ("u1", "u2")
REDUCED_STATES = ("Vbar", "gammabar", "thetabar", "Omega2bar")


def require_ctol(veh: Vehicle) -> None:
    """Raise unless ``veh`` is a CTOL aircraft (``kind = "ctol"``).

    Parameters
    ----------
    veh : Vehicle
        The vehicle to check.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a :class:`~glidectl.Vehicle` (e.g. a preset name).
    ModelError
        If it is a vehicle of another kind.
    """
    require_ctol_vehicle(veh)


def lift_coefficient(veh: Vehicle, alpha: Any) -> Any:
    """``K_Li(alpha) = a_L (1 + c alpha)`` (7.1), times ``rho A_W / 2`` (kg/m; 1 when normalized).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.
    ModelError
        If it is not a CTOL aircraft.
    """
    require_ctol(veh)
    return _lift_from(veh.rho_AW_half * veh.a_L, veh.c, alpha)


def drag_coefficient(veh: Vehicle, alpha: Any) -> Any:
    """``K_Dr(alpha) = a_D (1 + b (1 + c alpha)^2)`` (7.2), times ``rho A_W / 2`` (kg/m).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.
    ModelError
        If it is not a CTOL aircraft.
    """
    require_ctol(veh)
    return _drag_from(veh.rho_AW_half * veh.a_D, veh.b, veh.c, alpha)


def _lift_from(lift0: Any, c: Any, alpha: Any) -> Any:
    """(7.1) from the constants ``lift0 = rho A_W / 2 a_L`` and ``c`` (the right-hand sides' hot path, constants read
    once per model: :func:`_constants`)."""
    return lift0 * (1 + c * alpha)


def _drag_from(drag0: Any, b: Any, c: Any, alpha: Any) -> Any:
    """(7.2) from the constants ``drag0 = rho A_W / 2 a_D``, ``b`` and ``c``."""
    return drag0 * (1 + b * (1 + c * alpha) ** 2)


def _float_arctan(v: float) -> float:
    """``np.arctan`` of a Python float, as a float (numpy's arctan, not libm's: they differ in the last bit for
    about one argument in 700, and the batch path uses numpy's)."""
    return float(np.arctan(v))


#: ``(sqrt, arctan, rint, cos, sin)`` for Python floats, giving the same bits as numpy's float64 functions on this
#: path: ``math.sqrt`` (IEEE), ``math.cos``/``math.sin`` (libm, which numpy's float64 loops call), numpy's own
#: ``arctan`` (:func:`_float_arctan`) and ``round`` (half to even, as ``np.rint``). Python float arithmetic is the
#: same IEEE double arithmetic as numpy scalars, at less cost: a single-state call of the CTOL right-hand side
#: takes 3.2 us against 4.5 us (bench/bench_model_rhs.py) and returns identical values (tests/test_ctol_fast.py
#: compares them to the batch row).
_FLOAT_MATH = (math.sqrt, _float_arctan, round, math.cos, math.sin)

#: The same functions for arrays and numpy scalars.
_NUMPY_MATH = (np.sqrt, np.arctan, np.rint, np.cos, np.sin)


def _constants(veh: Vehicle) -> tuple[Any, ...]:
    """``(rho A_W/2 a_L, rho A_W/2 a_D, b, c, epsilon, m, g, J)`` of a CTOL aircraft: the constants of (7.1)-(7.7)
    and (7.12)-(7.15), read once per model instance instead of by attribute look-ups on every call (the products
    are those :func:`lift_coefficient` and :func:`drag_coefficient` form first: the same values to the last bit).

    Raises
    ------
    ModelError
        If the vehicle does not define one of them.
    """
    return (veh.rho_AW_half * veh.a_L, veh.rho_AW_half * veh.a_D, veh.b, veh.c, veh.epsilon, veh.m, veh.g, veh.J)


@dataclass(frozen=True)
class CTOLAircraft:
    """The CTOL model (7.5)-(7.7).

    State ``(x, y, xdot, ydot, theta, Omega2)`` (m, m, m/s, m/s, rad, rad/s; y up), input ``(u1, u2)``: thrust
    along the body axis (N) and elevator moment (N m), which also produces the force ``eps u2`` perpendicular to
    the body axis. The flight-path angle is ``gamma = atan2(ydot, xdot)`` and ``alpha = theta - gamma``.

    Parameters
    ----------
    vehicle : Vehicle
        A ``kind = "ctol"`` vehicle (``dc8_ctol``: normalized units of §7.1, ``m = g = J = rho A_W / 2 = 1``).
    state_names : tuple of str
        Names of the 6 states; default :data:`CTOL_STATES` (m, m, m/s, m/s, rad, rad/s).
    input_names : tuple of str
        Names of the 2 inputs; default :data:`CTOL_INPUTS` (N, N m).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If the vehicle is not a CTOL aircraft (:func:`require_ctol`).
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = CTOL_STATES
    input_names: tuple[str, ...] = CTOL_INPUTS

    def __post_init__(self) -> None:
        require_ctol(self.vehicle)

    def rhs(self, x: Any, u: Any) -> Any:
        """(7.5)-(7.7) for states ``x`` of shape ``(..., 6)`` and inputs ``u`` of shape ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 6, self.state_names)
        u = trailing_array("u", u, 2, self.input_names)
        if single_real_state(x, u):  # one real state (the calls of a simulation): Python floats, see _FLOAT_MATH
            cols = (*x[2:].tolist(), *u.tolist())
            try:
                return np.array(self._columns(*cols, _FLOAT_MATH))
            except (ZeroDivisionError, ValueError, OverflowError):
                # V = 0, gamma = pi, or a state that is not finite: numpy scalars give the batch row's inf and NaN
                with np.errstate(all="ignore"):
                    return np.array(self._columns(*np.array(cols), _NUMPY_MATH))
        cols = (x[..., 2], x[..., 3], x[..., 4], x[..., 5], u[..., 0], u[..., 1])
        return np.stack(np.broadcast_arrays(*self._columns(*cols, _NUMPY_MATH)), axis=-1)

    def _columns(self, xd: Any, yd: Any, th: Any, Om: Any, u1: Any, u2: Any, fns: tuple[Any, ...]) -> tuple[Any, ...]:
        """The six columns of (7.5)-(7.7) from the state and input columns, with ``fns = (sqrt, arctan, rint, cos,
        sin)``: :data:`_FLOAT_MATH` for Python floats, :data:`_NUMPY_MATH` for arrays and numpy scalars."""
        sqrt, arctan, rint, cos, sin = fns
        lift0, drag0, b, c, eps, m, g, J = self._constants  # the vehicle was checked in __post_init__
        V2 = xd * xd + yd * yd
        V = sqrt(V2)
        cg, sg = xd / V, yd / V  # cos gamma, sin gamma
        # gamma by the half-angle formula (complex-step safe, exact except at gamma = pi); alpha wrapped to (-pi, pi]
        alpha = th - 2 * arctan(yd / (V + xd))
        alpha = alpha - 2 * np.pi * rint(alpha.real / (2 * np.pi))  # (np.round(np.real(.)), without dispatch)
        L = _lift_from(lift0, c, alpha) * V2
        D = _drag_from(drag0, b, c, alpha) * V2
        cth, sth = cos(th), sin(th)
        xdd = (-D * cg - L * sg + u1 * cth + eps * u2 * sth) / m
        ydd = (-D * sg + L * cg + u1 * sth - eps * u2 * cth) / m - g
        return xd, yd, xdd, ydd, Om, u2 / J

    @cached_property
    def _constants(self) -> tuple[Any, ...]:
        """:func:`_constants` of the vehicle, read once per model (the right-hand side's hot path)."""
        return _constants(self.vehicle)

    @staticmethod
    def speed_gamma_alpha(x: Any) -> tuple[Any, Any, Any]:
        """``(V, gamma, alpha)`` of full states ``(..., 6)`` (m/s, rad, rad; angles wrapped to (-pi, pi])."""
        x = checks.array("x", x)
        trailing_array("x", x, 6, CTOL_STATES)
        V = np.hypot(x[..., 2], x[..., 3])
        gam = np.arctan2(x[..., 3], x[..., 2])
        a = np.angle(np.exp(1j * (x[..., 4] - gam)))
        return V, gam, a


@dataclass(frozen=True)
class CTOLReduced:
    """Reduced nondimensional CTOL dynamics (7.12)-(7.15) about the steady glide ``(V_e, gamma_e, theta_e)``.

    State ``(Vbar, gammabar, thetabar, Omega2bar)`` = ``((V - V_e)/V_e, gamma - gamma_e, theta - theta_e, T Omega2)``
    (7.8)-(7.11), input ``(u1, u2)``; ``T`` (s) is the reference time of (7.11). Time is not rescaled: (7.14) reads
    ``thetabar' = Omega2bar / T``. The steady glide is stored as ``speed`` (``V_e``, m/s), ``gamma`` (``gamma_e``,
    rad) and ``theta`` (``theta_e``, rad).

    Parameters
    ----------
    vehicle : Vehicle
        A ``kind = "ctol"`` vehicle.
    speed : float
        Steady-glide speed ``V_e > 0`` (m/s).
    gamma : float
        Steady-glide flight-path angle ``gamma_e`` (rad, positive climbing), ``|gamma_e| <= pi``.
    theta : float
        Steady-glide pitch angle ``theta_e = gamma_e + alpha_e`` (rad), finite.
    T : float
        Reference time of (7.11) (s), ``T > 0``; default 1.
    state_names : tuple of str
        Names of the 4 nondimensional states; default ``("Vbar", "gammabar", "thetabar", "Omega2bar")``.
    input_names : tuple of str
        Names of the 2 inputs; default :data:`CTOL_INPUTS` (N, N m).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle or a number is not a real number.
    ArgumentError
        If ``speed`` is not in ``(0, 100]`` (normalized units), ``T`` is not a positive finite number, or an angle
        is not finite (``|gamma| <= pi``).
    ModelError
        If the vehicle is not a CTOL aircraft.
    """

    vehicle: Vehicle
    speed: float
    gamma: float
    theta: float
    T: float = 1.0
    state_names: tuple[str, ...] = REDUCED_STATES
    input_names: tuple[str, ...] = CTOL_INPUTS

    def __post_init__(self) -> None:
        require_ctol(self.vehicle)
        object.__setattr__(self, "speed", speed_arg("steady-glide speed V_e (speed)", self.speed))
        object.__setattr__(self, "gamma", angle_arg("steady-glide gamma_e (gamma)", self.gamma, np.pi))
        object.__setattr__(self, "theta", angle_arg("steady-glide theta_e (theta)", self.theta))
        object.__setattr__(self, "T", checks.positive("reference time T", self.T, unit="s"))

    def rhs(self, s: Any, u: Any) -> Any:
        """(7.12)-(7.15) with ``alpha = thetabar + theta_e - (gammabar + gamma_e)``; ``s`` of shape ``(..., 4)``,
        ``u`` of shape ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``s`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        s = trailing_array("s", s, 4, self.state_names)
        u = trailing_array("u", u, 2, self.input_names)
        one = single_real_state(s, u)
        if one:  # numpy scalars for one real state
            Vb, gb, tb, Ob, u1, u2 = s[0], s[1], s[2], s[3], u[0], u[1]
        else:
            Vb, gb, tb, Ob, u1, u2 = s[..., 0], s[..., 1], s[..., 2], s[..., 3], u[..., 0], u[..., 1]
        lift0, drag0, b, c, eps, m, g, J = self._constants  # the vehicle was checked in __post_init__
        gam = gb + self.gamma
        alpha = tb + self.theta - gam
        V = self.speed * (1 + Vb)
        Vbd = (-m * g * np.sin(gam) - _drag_from(drag0, b, c, alpha) * V * V + u1 * np.cos(alpha)
               + eps * u2 * np.sin(alpha)) / (m * self.speed)
        gbd = (-m * g * np.cos(gam) + _lift_from(lift0, c, alpha) * V * V + u1 * np.sin(alpha)
               - eps * u2 * np.cos(alpha)) / (m * V)
        if one:
            return np.array((Vbd, gbd, Ob / self.T, self.T * u2 / J))
        return np.stack(np.broadcast_arrays(Vbd, gbd, Ob / self.T, self.T * u2 / J), axis=-1)

    @cached_property
    def _constants(self) -> tuple[Any, ...]:
        """:func:`_constants` of the vehicle, read once per model (the right-hand side's hot path)."""
        return _constants(self.vehicle)

    def from_full(self, x: Any) -> np.ndarray:
        """Reduced state of full states ``(x, y, xdot, ydot, theta, Omega2)`` (the map (7.8)-(7.11)), shape
        ``(..., 6) -> (..., 4)``."""
        x = checks.array("x", x)
        V, gam, _ = CTOLAircraft.speed_gamma_alpha(x)
        return np.stack([V / self.speed - 1, np.angle(np.exp(1j * (gam - self.gamma))),
                         np.angle(np.exp(1j * (x[..., 4] - self.theta))), self.T * x[..., 5]], -1)


@dataclass(frozen=True)
class ExtendedCTOL:
    """The CTOL model (7.5)-(7.7) with the thrust dynamically extended.

    State ``(x, y, xdot, ydot, theta, Omega2, u1, u1dot)``, input ``(u1ddot, u2)`` (N/s^2, N m); the plant part is
    :meth:`CTOLAircraft.rhs` with input ``(u1, u2)``.

    Parameters
    ----------
    vehicle : Vehicle
        A ``kind = "ctol"`` vehicle.
    state_names : tuple of str
        Names of the 8 states (m, m, m/s, m/s, rad, rad/s, N, N/s).
    input_names : tuple of str
        Names of the 2 inputs ``(u1ddot, u2)`` (N/s^2, N m).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If the vehicle is not a CTOL aircraft (:func:`require_ctol`).
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = (*CTOL_STATES, "u1", "u1dot")
    input_names: tuple[str, ...] = ("u1ddot", "u2")

    def __post_init__(self) -> None:
        require_ctol(self.vehicle)

    def rhs(self, X: Any, U: Any) -> Any:
        """Derivative of the 8 states ``X`` (shape ``(..., 8)``) under the inputs ``U = (u1ddot, u2)`` (shape
        ``(..., 2)``).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``X`` or ``U`` is not an array of numbers with that trailing dimension.
        """
        X = trailing_array("X", X, 8, self.state_names)
        U = trailing_array("U", U, 2, self.input_names)
        u = np.stack(np.broadcast_arrays(X[..., 6], U[..., 1]), -1)
        xp = self._plant.rhs(X[..., :6], u)
        return np.concatenate([xp, X[..., 7:8], U[..., 0:1]], -1)

    @cached_property
    def _plant(self) -> CTOLAircraft:
        """The plant :class:`CTOLAircraft`, built once per model."""
        return CTOLAircraft(self.vehicle)
