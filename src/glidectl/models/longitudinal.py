"""Longitudinal-plane underwater glider: (2.15)-(2.25), glide-path deviation z' (2.30), and the
force-to-acceleration transform (2.31)-(2.36).

There is one right-hand side, :meth:`LongitudinalGlider.rhs` (force inputs). The acceleration-controlled model
(:class:`AccelerationControlledGlider`) maps its state to the force form, computes the input of (2.33) and calls
that right-hand side; the glide-path form (:class:`GlidePathModel`) replaces (x, z) by z' and also calls it.

States and inputs are named; every array argument may carry leading batch dimensions (``x[..., n]``) and may be
complex (for exact complex-step Jacobians).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from ..errors import ModelError
from ..hydro import longitudinal_loads
from ..iosys import IOSysExport
from ..params import Vehicle
from ._validate import angle_arg, require_glider, require_instance, trailing_array

__all__ = [
    "ACCEL_INPUTS",
    "ACCEL_STATES",
    "FORCE_INPUTS",
    "FORCE_STATES",
    "STATE_UNITS",
    "AccelerationControlledGlider",
    "GlidePathModel",
    "LongitudinalGlider",
]

FORCE_STATES = ("x", "z", "theta", "Omega2", "v1", "v3", "r_P1", "r_P3", "P_P1", "P_P3", "m0")
FORCE_INPUTS = ("u1", "u3", "u4")
ACCEL_STATES = ("x", "z", "theta", "Omega2", "v1", "v3", "r_P1", "rdot_P1", "r_P3", "rdot_P3", "m0")
ACCEL_INPUTS = ("w1", "w3", "w4")

STATE_UNITS = {
    "x": "m", "z": "m", "z_prime": "m", "theta": "rad", "Omega2": "rad/s", "v1": "m/s", "v3": "m/s",
    "r_P1": "m", "r_P3": "m", "P_P1": "kg m/s", "P_P3": "kg m/s", "m0": "kg", "rdot_P1": "m/s",
    "rdot_P3": "m/s", "u1": "N", "u3": "N", "u4": "kg/s", "w1": "m/s^2", "w3": "m/s^2", "w4": "kg/s",
}


def _columns(a: np.ndarray, idx: Any) -> list[Any]:
    """Entries ``idx`` of the last axis of ``a``: numpy scalars for a single real vector (the calls of a simulation;
    real scalar arithmetic is the same IEEE arithmetic as the array loops, only cheaper), views ``a[..., i]``
    otherwise (a batch; complex steps, whose scalar division differs from the array loop in the last bit)."""
    if a.ndim == 1 and a.dtype.kind == "f":
        return [a[i] for i in idx]
    return [a[..., i] for i in idx]


def _momenta(mbar: float, Om: Any, v1: Any, v3: Any, rP1: Any, rdP1: Any, rP3: Any, rdP3: Any) -> tuple[Any, Any]:
    """``P_P1, P_P3`` (kg m/s) of the moving mass from its velocity ``rdot_P``: (2.31) inverted,
    ``P_P = mbar (rdot_P + v + Omega x r_P)``."""
    return mbar * (rdP1 + v1 + rP3 * Om), mbar * (rdP3 + v3 - rP1 * Om)


def _stack(*cols: Any) -> Any:
    """Stack equally shaped (or broadcastable) columns along a new last axis. Scalar columns (the single-state calls
    of a simulation) take a direct path with the same result: no broadcasting is needed."""
    if all(getattr(c, "ndim", 0) == 0 for c in cols):
        return np.array(cols)
    return np.stack(np.broadcast_arrays(*cols), axis=-1)


@dataclass(frozen=True)
class LongitudinalGlider(IOSysExport):
    """Force-controlled longitudinal glider (2.15)-(2.25).

    State ``x = (x, z, theta, Omega2, v1, v3, r_P1, r_P3, P_P1, P_P3, m0)`` in (m, m, rad, rad/s, m/s, m/s, m, m,
    kg m/s, kg m/s, kg); input ``u = (u1, u3, u4)``: total force on the moving mass along body 1 and 3 (N) and
    buoyancy rate (kg/s). Inertial z points down; theta is the pitch angle, theta = alpha + gamma.

    Parameters
    ----------
    vehicle : Vehicle
        An underwater glider with a moving mass ``mbar > 0`` (kg).
    state_names : tuple of str
        Names of the 11 states; default :data:`FORCE_STATES` (units in :data:`STATE_UNITS`).
    input_names : tuple of str
        Names of the 3 inputs; default :data:`FORCE_INPUTS` (N, N, kg/s).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If the vehicle is not an underwater glider or has ``mbar <= 0``.
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = FORCE_STATES
    input_names: tuple[str, ...] = FORCE_INPUTS

    def __post_init__(self) -> None:
        v = require_glider(self.vehicle)
        if v.mbar <= 0:
            raise ModelError(
                f"vehicle '{v.name}' has mbar = {v.mbar:g} kg: the longitudinal model (2.15)-(2.25) needs an "
                "internal moving mass mbar > 0 (use the reduced model of chapter 5 for r_P = 0 gliders)")

    def generalized_forces(self, x: Any) -> tuple[Any, Any, Any, dict[str, Any]]:
        """The input-free brackets of (2.18)-(2.20): ``X1, X3`` (N) and ``Y`` (N m).

        ``v1' = (X1 - u1)/m1``, ``v3' = (X3 - u3)/m3``, ``Omega2' = (Y + r_P1 u3 - r_P3 u1)/J2`` with
        ``X1 = -m3 v3 Om - P_P3 Om - m0 g sin(theta) + L sin(alpha) - D cos(alpha)``,
        ``X3 = m1 v1 Om + P_P1 Om + m0 g cos(theta) - L cos(alpha) - D sin(alpha)`` and
        ``Y = (m3 - m1) v1 v3 - mbar g (r_P1 cos(theta) + r_P3 sin(theta)) + M_DL2 - Om (r_P1 P_P1 + r_P3 P_P3)``.
        ``M_DL2`` is :func:`glidectl.hydro.longitudinal_loads`'s: (2.13) plus any chapter-8 pitch damping of the
        file, through :func:`glidectl.hydro.damping_moment` (the same damping as the 3-D models).
        Also returns the masses and hydrodynamic quantities used, for reuse. ``x`` has shape ``(..., 11)``.
        """
        x = trailing_array("x", x, 11, FORCE_STATES)
        return self._brackets(*_columns(x, range(2, 11)))[:4]

    def _brackets(self, th: Any, Om: Any, v1: Any, v3: Any, rP1: Any, rP3: Any, PP1: Any, PP3: Any,
                  m0: Any) -> tuple[Any, Any, Any, dict[str, Any], Any, Any]:
        """:meth:`generalized_forces` from the state columns, plus ``sin(theta)``, ``cos(theta)``."""
        veh = self.vehicle
        g, mbar = veh.g, veh.mbar
        m1, m3 = veh.mass(1, m0), veh.mass(3, m0)
        alpha, L, D, M = longitudinal_loads(veh, v1, v3, Om)
        s, c = np.sin(th), np.cos(th)
        sa, ca = np.sin(alpha), np.cos(alpha)
        X1 = -m3 * v3 * Om - PP3 * Om - m0 * g * s + L * sa - D * ca
        X3 = m1 * v1 * Om + PP1 * Om + m0 * g * c - L * ca - D * sa
        Y = (m3 - m1) * v1 * v3 - mbar * g * (rP1 * c + rP3 * s) + M - Om * (rP1 * PP1 + rP3 * PP3)
        return X1, X3, Y, {"m1": m1, "m3": m3, "alpha": alpha, "L": L, "D": D, "M": M}, s, c

    def rhs(self, x: Any, u: Any) -> Any:
        """Time derivative of the state, equations (2.15)-(2.25).

        Parameters
        ----------
        x : array_like, shape (..., 11)
        u : array_like, shape (..., 3)

        Returns
        -------
        ndarray, shape (..., 11)

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 11, self.state_names)
        u = trailing_array("u", u, 3, self.input_names)
        cols = _columns(x, range(2, 11))
        return _stack(*self._derivatives(*cols[:-1], *_columns(u, range(3)), self._brackets(*cols)))

    def _derivatives(self, th: Any, Om: Any, v1: Any, v3: Any, rP1: Any, rP3: Any, PP1: Any, PP3: Any, u1: Any,
                     u3: Any, u4: Any, brackets: tuple[Any, Any, Any, dict[str, Any], Any, Any]) -> tuple[Any, ...]:
        """The 11 columns of (2.15)-(2.25) from the state columns, the inputs and :meth:`_brackets` there."""
        veh = self.vehicle
        X1, X3, Y, aux, s, c = brackets
        mbar = veh.mbar
        return (
            v1 * c + v3 * s,                                  # (2.15)
            -v1 * s + v3 * c,                                 # (2.16)
            Om,                                               # (2.17)
            (Y + rP1 * u3 - rP3 * u1) / veh.J2,               # (2.20)
            (X1 - u1) / aux["m1"],                            # (2.18)
            (X3 - u3) / aux["m3"],                            # (2.19)
            PP1 / mbar - v1 - rP3 * Om,                       # (2.21)
            PP3 / mbar - v3 + rP1 * Om,                       # (2.22)
            u1,                                               # (2.23)
            u3,                                               # (2.24)
            u4,                                               # (2.25)
        )


@dataclass(frozen=True)
class AccelerationControlledGlider(IOSysExport):
    """Longitudinal glider under the force-to-acceleration feedback (2.31)-(2.34).

    State ``(x, z, theta, Omega2, v1, v3, r_P1, rdot_P1, r_P3, rdot_P3, m0)`` (eta, zeta of §2.3.2); input
    ``w = (w1, w3, w4)``: accelerations of the moving mass relative to the body (m/s^2) and buoyancy rate (kg/s).
    By construction ``rddot_P1 = w1``, ``rddot_P3 = w3``, ``m0' = w4``.

    Notes
    -----
    (2.32) as printed has the wrong sign on ``Z``. Differentiating (2.31) along (2.18)-(2.24) gives
    ``rddot_P = Z + F u`` with ``Z = -[X1/m1 + rdot_P3 Om + r_P3 Y/J2, X3/m3 - rdot_P1 Om - r_P1 Y/J2]``
    (the negative of the printed vector) and ``F`` as printed.

    Parameters
    ----------
    vehicle : Vehicle
        An underwater glider with a moving mass ``mbar > 0`` (kg).
    state_names : tuple of str
        Names of the 11 states; default :data:`ACCEL_STATES` (units in :data:`STATE_UNITS`).
    input_names : tuple of str
        Names of the 3 inputs; default :data:`ACCEL_INPUTS` (m/s^2, m/s^2, kg/s).

    Raises
    ------
    ModelError
        If the vehicle is not an underwater glider or has ``mbar <= 0`` (the checks of :class:`LongitudinalGlider`).
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = ACCEL_STATES
    input_names: tuple[str, ...] = ACCEL_INPUTS

    def __post_init__(self) -> None:
        LongitudinalGlider(self.vehicle)  # same validity conditions (underwater glider, mbar > 0)

    @cached_property
    def force_model(self) -> LongitudinalGlider:
        """The underlying force-controlled model (the one right-hand side); built once per model."""
        return LongitudinalGlider(self.vehicle)

    def to_force_state(self, xa: Any) -> Any:
        """Map ``(.., rdot_P1, .., rdot_P3, m0)`` to ``(.., r_P3, P_P1, P_P3, m0)`` by inverting (2.31)."""
        xa = trailing_array("xa", xa, 11, ACCEL_STATES)
        mbar = self.vehicle.mbar
        c = _columns(xa, range(11))
        Om, v1, v3 = c[3], c[4], c[5]
        rP1, rdP1, rP3, rdP3, m0 = c[6], c[7], c[8], c[9], c[10]
        return _stack(*c[:6], rP1, rP3, *_momenta(mbar, Om, v1, v3, rP1, rdP1, rP3, rdP3), m0)

    def from_force_state(self, xf: Any) -> Any:
        """Map a force-form state to the acceleration-form state with (2.31)."""
        xf = trailing_array("xf", xf, 11, FORCE_STATES)
        mbar = self.vehicle.mbar
        c = _columns(xf, range(11))
        Om, v1, v3 = c[3], c[4], c[5]
        rP1, rP3, PP1, PP3, m0 = c[6], c[7], c[8], c[9], c[10]
        return _stack(*c[:6], rP1, PP1 / mbar - v1 - rP3 * Om, rP3,
                      PP3 / mbar - v3 + rP1 * Om, m0)

    def transform(self, xa: Any) -> tuple[Any, Any]:
        """``Z`` (m/s^2, shape (..., 2)) and ``F`` (1/kg, shape (..., 2, 2)) of (2.32), sign of Z corrected."""
        xa = trailing_array("xa", xa, 11, ACCEL_STATES)
        Z0, Z1, F11, F13, F33 = self._zf(xa, self.force_model.generalized_forces(self.to_force_state(xa)))
        rows = (_stack(F11, F13), _stack(F13, F33))
        F = np.stack(rows if rows[0].shape == rows[1].shape else np.broadcast_arrays(*rows), axis=-2)
        return _stack(Z0, Z1), F

    def _zf(self, xa: np.ndarray, forces: tuple[Any, ...]) -> tuple[Any, Any, Any, Any, Any]:
        """Columns ``Z1, Z3, F11, F13, F33`` of :meth:`transform` from the brackets of
        :meth:`LongitudinalGlider.generalized_forces` at ``to_force_state(xa)``."""
        veh = self.vehicle
        X1, X3, Y, aux = forces[:4]
        Om, rP1, rdP1, rP3, rdP3 = _columns(xa, (3, 6, 7, 8, 9))
        J2, mbar = veh.J2, veh.mbar
        F11 = 1 / mbar + 1 / aux["m1"] + rP3 * rP3 / J2
        F33 = 1 / mbar + 1 / aux["m3"] + rP1 * rP1 / J2
        F13 = -rP1 * rP3 / J2
        return (-(X1 / aux["m1"] + rdP3 * Om + rP3 * Y / J2), -(X3 / aux["m3"] - rdP1 * Om - rP1 * Y / J2),
                F11, F13, F33)

    @staticmethod
    def _forces_u(w1: Any, w3: Any, zf: tuple[Any, Any, Any, Any, Any]) -> tuple[Any, Any]:
        """``u1, u3`` of (2.33)-(2.34): ``F u = w - Z`` solved by Cramer's rule."""
        Z0, Z1, F11, F13, F33 = zf
        r0, r1 = w1 - Z0, w3 - Z1
        det = F11 * F33 - F13 * F13
        return (F33 * r0 - F13 * r1) / det, (-F13 * r0 + F11 * r1) / det

    def force_input(self, xa: Any, w: Any) -> Any:
        """Force input ``(u1, u3, u4)`` of (2.33)-(2.34) realizing acceleration input ``w`` (shape ``(..., 3)``)."""
        w = trailing_array("w", w, 3, ACCEL_INPUTS)
        xa = trailing_array("xa", xa, 11, ACCEL_STATES)
        zf = self._zf(xa, self.force_model.generalized_forces(self.to_force_state(xa)))
        w1, w3, w4 = _columns(w, range(3))
        return _stack(*self._forces_u(w1, w3, zf), w4)

    def rhs(self, xa: Any, w: Any) -> Any:
        """Time derivative of the acceleration-form state (2.35)-(2.36), through the force right-hand side.

        The force state (2.31), the brackets (2.18)-(2.20) (computed once: they serve both the force input
        (2.33)-(2.34) and the force right-hand side (2.15)-(2.20)) and the force input are evaluated column by
        column, with the same operations as :meth:`to_force_state`, :meth:`force_input` and
        :meth:`LongitudinalGlider.rhs`.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``xa`` (shape ``(..., 11)``) or ``w`` (shape ``(..., 3)``) is not an array of numbers with that
            trailing dimension.
        """
        xa = trailing_array("xa", xa, 11, self.state_names)
        w = trailing_array("w", w, 3, self.input_names)
        mbar = self.vehicle.mbar
        th, Om, v1, v3, rP1, rdP1, rP3, rdP3, m0 = _columns(xa, range(2, 11))
        PP1, PP3 = _momenta(mbar, Om, v1, v3, rP1, rdP1, rP3, rdP3)
        fm = self.force_model
        br = fm._brackets(th, Om, v1, v3, rP1, rP3, PP1, PP3, m0)
        w1, w3, w4 = _columns(w, range(3))
        u1, u3 = self._forces_u(w1, w3, self._zf(xa, br))
        fdot = fm._derivatives(th, Om, v1, v3, rP1, rP3, PP1, PP3, u1, u3, w4, br)
        return _stack(*fdot[:6], rdP1, w1, rdP3, w3, w4)


@dataclass(frozen=True)
class GlidePathModel(IOSysExport):
    """A longitudinal model with (x, z) replaced by the glide-path deviation z' of (2.30).

    ``z'' = sin(gamma_e) x' + cos(gamma_e) z'`` is the rate of the distance (m, positive below-right of the path,
    i.e. along ``(sin gamma_e, cos gamma_e)`` in the (x, z-down) plane) from the desired straight path of flight-path
    angle ``gamma`` (``gamma_e``, rad). State: ``("z_prime",) + base.state_names[2:]``.

    Parameters
    ----------
    base : LongitudinalGlider or AccelerationControlledGlider
        The longitudinal model whose ``(x, z)`` are replaced; its vehicle and inputs are used unchanged.
    gamma : float
        Flight-path angle ``gamma_e`` of the desired straight path (rad; negative descending, as
        :attr:`~glidectl.trim.glide.SteadyGlide.gamma`), ``|gamma_e| <= pi/2``.

    Raises
    ------
    ArgumentTypeError
        If ``base`` is not one of the two longitudinal models or ``gamma`` is not a real number.
    ArgumentError
        If ``gamma`` is not finite or ``|gamma| > pi/2``.
    """

    base: LongitudinalGlider | AccelerationControlledGlider
    gamma: float

    def __post_init__(self) -> None:
        require_instance("base", self.base, (LongitudinalGlider, AccelerationControlledGlider))
        object.__setattr__(self, "gamma", angle_arg("gamma (path angle)", self.gamma, np.pi / 2))

    @property
    def state_names(self) -> tuple[str, ...]:
        return ("z_prime", *self.base.state_names[2:])

    @property
    def input_names(self) -> tuple[str, ...]:
        return self.base.input_names

    @property
    def vehicle(self) -> Vehicle:
        return self.base.vehicle

    def rhs(self, xr: Any, u: Any) -> Any:
        """Derivative of ``(z', theta, ...)`` (shape ``(..., 10)``): (2.30) and the base model's equations without
        (2.15)-(2.16).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``xr`` or ``u`` is not an array of numbers with the right trailing dimension.
        """
        xr = trailing_array("xr", xr, 10, self.state_names)
        full = np.concatenate([np.zeros_like(xr[..., :2]), xr[..., 1:]], axis=-1)
        d = self.base.rhs(full, u)
        zp = np.sin(self.gamma) * d[..., 0] + np.cos(self.gamma) * d[..., 1]
        return np.concatenate([zp[..., None], d[..., 2:]], axis=-1)
