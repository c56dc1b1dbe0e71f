"""Three-dimensional underwater glider, §2.2 and §8.2.1.

Two models share the hydrodynamics (:func:`glidectl.hydro.loads_3d`) and the kinematics on SO(3) (unit quaternion
``q = (q0, q1, q2, q3)``, scalar first, ``R(q)`` maps body to inertial coordinates, ``qdot = q (x) (0, Omega) / 2``
with a Baumgarte term that keeps ``|q| = 1`` against integration drift):

- :class:`Glider3D`, the force form (2.1)-(2.8): state ``(x, y, z, q, v, Omega, r_P, P_P, m0)``, inputs
  ``(u1, u2, u3)`` = total force on the moving mass (the ``ubar`` of (2.6)) and ``u4 = m0'`` (2.8).
- :class:`FixedMassGlider3D`, the acceleration form (8.23)-(8.25) with ``r_P`` and ``m0`` fixed: state
  ``(x, y, z, q, v, Omega)``, no inputs. Its accelerations depend on the attitude only through the body-frame
  gravity direction ``zeta = R^T k`` (8.27), which is what steady-motion (helix) analysis uses.

Masses: ``M = diag(m_i(m0))`` (fixed or added-mass model of the vehicle file, docs/conventions.md) and
``J = diag(J1, J2, J3)`` (total inertia). The inertial ``z`` axis points down, ``k = (0, 0, 1)``.

Notes
-----
(2.5) prints ``Tbar = (J Omega + r_P^ P_P) x Omega + ...``. Read literally it differs from the moment balance of the
hull (Kirchhoff's ``h' = h x Omega + p x v + T`` with the reaction ``-r_P x f_int`` of the moving mass) by
``P_P x (Omega x r_P)``; in the longitudinal plane the literal form drops the ``-Omega2 (r_P1 P_P1 + r_P3 P_P3)`` of
(2.20), and with fixed ``r_P`` it disagrees with (8.25). The form implemented, ``J Omega x Omega + r_P x (P_P x
Omega)``, agrees with (2.20) and (8.23)-(8.25) (tests check both).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ModelError
from ..hydro import loads_3d
from ..params import Vehicle
from ._validate import numeric_array, require_glider, trailing_array

__all__ = [
    "FIXED_STATES",
    "FORCE3D_INPUTS",
    "FORCE3D_STATES",
    "R_P_MAX",
    "FixedMassGlider3D",
    "Glider3D",
    "R_to_ypr",
    "body_masses",
    "cross",
    "hat",
    "quat_to_R",
    "quaternion_rate",
    "require_glider3d",
    "rotation",
    "ypr_to_R",
    "ypr_to_quat",
]

FORCE3D_STATES = ("x", "y", "z", "q0", "q1", "q2", "q3", "v1", "v2", "v3", "Omega1", "Omega2", "Omega3",
                  "r_P1", "r_P2", "r_P3", "P_P1", "P_P2", "P_P3", "m0")
FORCE3D_INPUTS = ("u1", "u2", "u3", "u4")
FIXED_STATES = ("x", "y", "z", "q0", "q1", "q2", "q3", "v1", "v2", "v3", "Omega1", "Omega2", "Omega3")
_BAUMGARTE = 1.0  # 1/s, pulls |q| back to 1 (no effect on the manifold |q| = 1)
_REQUIRED_3D = ("J1", "J3", "K_beta", "K_MR", "K_MY")
#: Largest distance (m) of the fixed moving mass from the centre of buoyancy accepted by :class:`FixedMassGlider3D`
#: (a plausibility limit: gliders are a few metres long).
R_P_MAX = 10.0
_COND_MAX = 1e12  # largest condition number of the generalized mass matrix of (8.23)


def _finite(name: str, value: Any, n: int) -> np.ndarray:
    """A (batch of) finite vector(s) of length ``n``, real or complex."""
    a = trailing_array(name, value, n)
    if not np.all(np.isfinite(a)):
        raise ArgumentError(f"{name} must be finite (no NaN or inf), got {value!r}")
    return a


def hat(x: Any) -> np.ndarray:
    """The ``^`` map of §2.2.1: ``hat(x) @ y = x x y`` (batched over leading dimensions, ``x`` of shape
    ``(..., 3)``).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``x`` is not an array of numbers with a trailing dimension 3.
    """
    x = trailing_array("x", x, 3)
    z = np.zeros_like(x[..., 0])
    return np.stack([np.stack([z, -x[..., 2], x[..., 1]], -1),
                     np.stack([x[..., 2], z, -x[..., 0]], -1),
                     np.stack([-x[..., 1], x[..., 0], z], -1)], -2)


def quat_to_R(q: Any) -> np.ndarray:
    """Rotation matrix (body -> inertial) of a quaternion (normalized first).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternion ``(q0, q1, q2, q3)``, scalar first (nondimensional); need not be of unit norm (it is divided by
        its norm). Leading batch dimensions are allowed; complex values pass through (complex-step Jacobians).

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)
        Rotation matrix ``R(q)`` (nondimensional) mapping body to inertial coordinates.

    Raises
    ------
    ArgumentTypeError
        If ``q`` is not an array of numbers.
    ArgumentError
        If the last axis of ``q`` does not have 4 entries, ``q`` is not finite, or a quaternion is zero (its
        rotation is undefined).
    """
    q = _finite("q", q, 4)
    if not np.all(np.abs(np.real(np.sum(q * q, axis=-1))) > 1e-300):
        raise ArgumentError("quaternion q must be nonzero (a zero quaternion has no rotation matrix)")
    return rotation(q)


def rotation(q: Any) -> np.ndarray:
    """:func:`quat_to_R` without the argument checks (right-hand sides: the integrator watches finiteness)."""
    w, a, b, c = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    k = 2.0 / (w * w + a * a + b * b + c * c)   # normalizes q
    out = np.empty((*q.shape[:-1], 3, 3), dtype=np.result_type(q, 1.0))
    out[..., 0, 0] = 1 - k * (b * b + c * c)
    out[..., 0, 1] = k * (a * b - w * c)
    out[..., 0, 2] = k * (a * c + w * b)
    out[..., 1, 0] = k * (a * b + w * c)
    out[..., 1, 1] = 1 - k * (a * a + c * c)
    out[..., 1, 2] = k * (b * c - w * a)
    out[..., 2, 0] = k * (a * c - w * b)
    out[..., 2, 1] = k * (b * c + w * a)
    out[..., 2, 2] = 1 - k * (a * a + b * b)
    return out


def _angles(*angles: Any) -> tuple[np.ndarray, ...]:
    names = ("psi", "theta", "phi")
    out = []
    for name, a in zip(names, angles, strict=True):
        a = numeric_array(name, a)
        if not np.all(np.isfinite(a)):
            raise ArgumentError(f"{name} must be finite (rad), got {a!r}")
        out.append(a)
    try:
        np.broadcast_shapes(*(a.shape for a in out))
    except ValueError as exc:
        raise ArgumentError(f"psi, theta, phi must broadcast together: {exc}") from exc
    return tuple(out)


def ypr_to_R(psi: Any, theta: Any, phi: Any) -> np.ndarray:
    """Yaw-pitch-roll rotation matrix (8.26).

    Parameters
    ----------
    psi, theta, phi : float or array_like
        Yaw, pitch and roll angles (rad); broadcast against each other.

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)
        Rotation matrix (nondimensional) mapping body to inertial coordinates, ``R = R_z(psi) R_y(theta)
        R_x(phi)``.

    Raises
    ------
    ArgumentTypeError
        If an angle is not a number or array of numbers.
    ArgumentError
        If an angle is not finite or the three cannot be broadcast to a common shape.
    """
    psi, theta, phi = _angles(psi, theta, phi)
    cps, sps, cth, sth, cph, sph = (np.cos(psi), np.sin(psi), np.cos(theta), np.sin(theta), np.cos(phi),
                                    np.sin(phi))
    return np.stack([
        np.stack([cps * cth, -sps * cph + cps * sth * sph, sps * sph + cps * sth * cph], -1),
        np.stack([sps * cth, cps * cph + sps * sth * sph, -cps * sph + sps * sth * cph], -1),
        np.stack([-sth, cth * sph, cth * cph], -1)], -2)


def ypr_to_quat(psi: float, theta: float, phi: float) -> np.ndarray:
    """Quaternion of the YPR angles (rad) of (8.26).

    Parameters
    ----------
    psi, theta, phi : float or array_like
        Yaw, pitch and roll angles (rad); broadcast against each other.

    Returns
    -------
    numpy.ndarray, shape (4, ...)
        Unit quaternion ``(q0, q1, q2, q3)`` (nondimensional, scalar first) with ``quat_to_R(q) == ypr_to_R(psi,
        theta, phi)``. For array angles the quaternion components are along the *first* axis (unlike the
        ``(..., 4)`` layout that :func:`quat_to_R` expects).

    Raises
    ------
    ArgumentTypeError
        If an angle is not a number or array of numbers.
    ArgumentError
        If an angle is not finite or the three cannot be broadcast to a common shape.
    """
    psi, theta, phi = _angles(psi, theta, phi)
    cy, sy, cp, sp, cr, sr = (np.cos(psi / 2), np.sin(psi / 2), np.cos(theta / 2), np.sin(theta / 2),
                              np.cos(phi / 2), np.sin(phi / 2))
    return np.array([cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy])


def R_to_ypr(R: Any) -> np.ndarray:
    """``(psi, theta, phi)`` (rad) of a rotation matrix, inverse of (8.26) (``|theta| < pi/2``).

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Rotation matrix (nondimensional), body to inertial.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Yaw ``psi`` in (-pi, pi], pitch ``theta`` in [-pi/2, pi/2] and roll ``phi`` in (-pi, pi] (rad). At
        ``|theta| = pi/2`` (gimbal lock) yaw and roll are not unique.

    Raises
    ------
    ArgumentTypeError
        If ``R`` is not an array of real numbers.
    ArgumentError
        If the last two axes of ``R`` are not 3 x 3, ``R`` is not finite, or it is not a rotation matrix
        (``|R^T R - I| > 1e-6`` or ``det R < 0``).
    """
    R = checks.array("R", R)
    if R.ndim < 2 or R.shape[-2:] != (3, 3):
        raise ArgumentError(f"R must have shape (..., 3, 3), got {R.shape}")
    err = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3))
    if np.any(err > 1e-6) or np.any(np.linalg.det(R) < 0):
        raise ArgumentError(f"R is not a rotation matrix (max |R^T R - I| = {float(np.max(err)):.3g}); yaw, pitch "
                            "and roll exist only for rotations")
    return np.stack([np.arctan2(R[..., 1, 0], R[..., 0, 0]), -np.arcsin(np.clip(R[..., 2, 0], -1, 1)),
                     np.arctan2(R[..., 2, 1], R[..., 2, 2])], -1)


def quaternion_rate(q: Any, Om: Any) -> Any:
    """``q' = q (x) (0, Omega) / 2`` plus the Baumgarte term ``(1 - |q|^2) q`` (1/s) that keeps ``|q| = 1`` against
    integration drift; ``q`` of shape ``(..., 4)`` (scalar first), ``Om`` the body angular velocity (rad/s, shape
    ``(..., 3)``). No argument checks (right-hand sides)."""
    w, a, b, c = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    p, r, s = Om[..., 0], Om[..., 1], Om[..., 2]
    k = _BAUMGARTE * (1 - (w * w + a * a + b * b + c * c))
    out = np.empty(np.broadcast_shapes(q.shape, (*Om.shape[:-1], 4)), dtype=np.result_type(q, Om))
    out[..., 0] = 0.5 * (-a * p - b * r - c * s) + k * w
    out[..., 1] = 0.5 * (w * p + b * s - c * r) + k * a
    out[..., 2] = 0.5 * (w * r + c * p - a * s) + k * b
    out[..., 3] = 0.5 * (w * s + a * r - b * p) + k * c
    return out


def cross(a: Any, b: Any) -> Any:
    """Cross product ``a x b`` over the last axis (length 3), batched and complex-safe; no argument checks."""
    # the components written into one output array (no np.stack): the same products, less overhead
    c0 = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out = np.empty((*np.shape(c0), 3), dtype=np.result_type(c0))
    out[..., 0] = c0
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def require_glider3d(veh: Vehicle) -> None:
    """Refuse a vehicle that is not an underwater glider with the 3D parameters of (2.1)-(2.14).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.
    ModelError
        If it is not an underwater glider or lacks ``J1, J3, K_beta, K_MR, K_MY`` (and ``m2`` for the fixed mass
        model); the message names the missing parameters.
    """
    require_glider(veh)
    missing = [k for k in _REQUIRED_3D if k not in veh.params]
    if veh.mass_model == "fixed" and "m2" not in veh.params:
        missing.append("m2")
    if missing:
        raise ModelError(f"vehicle '{veh.name}' lacks the 3D parameters {missing} needed by the 3D model "
                         f"(2.1)-(2.14); add them to {veh.path} or pass them as overrides")


def body_masses(veh: Vehicle, m0: Any) -> Any:
    """Body masses ``(m_1, m_2, m_3)`` (kg, shape ``(..., 3)``) at net buoyancy ``m0`` (kg, any shape), by the
    vehicle's mass model (docs/conventions.md)."""
    return np.stack([np.broadcast_to(np.asarray(veh.mass(i, m0)), np.shape(m0)) for i in (1, 2, 3)], -1)


@dataclass(frozen=True)
class Glider3D:
    """Force form (2.1)-(2.8). ``rhs(x, u)`` with ``u = (u1, u2, u3, u4)`` (N, N, N, kg/s).

    Parameters
    ----------
    vehicle : Vehicle
        An underwater glider with the 3D parameters ``J1, J3, K_beta, K_MR, K_MY`` (and ``m2`` for the fixed mass
        model) and a moving mass ``mbar > 0`` (kg).
    state_names : tuple of str
        Names of the 20 states ``(x, y, z, q0..q3, v1..v3, Omega1..Omega3, r_P1..r_P3, P_P1..P_P3, m0)`` (m,
        nondimensional quaternion, m/s, rad/s, m, kg m/s, kg); default :data:`FORCE3D_STATES`.
    input_names : tuple of str
        Names of the inputs ``(u1, u2, u3, u4)`` (N, N, N, kg/s); default :data:`FORCE3D_INPUTS`.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle.
    ModelError
        If the vehicle is not an underwater glider, lacks a 3D parameter, or has ``mbar = 0``.
    """

    vehicle: Vehicle
    state_names: tuple[str, ...] = FORCE3D_STATES
    input_names: tuple[str, ...] = FORCE3D_INPUTS

    def __post_init__(self) -> None:
        require_glider3d(self.vehicle)
        if self.vehicle.mbar <= 0:
            raise ModelError(f"vehicle '{self.vehicle.name}' has mbar = 0: the force form needs a moving mass; use "
                             "FixedMassGlider3D")

    def rhs(self, x: Any, u: Any) -> Any:
        """(2.1)-(2.8): ``b' = R v``, ``R' = R Omega^``, ``r_P' = P_P/mbar - v - Omega x r_P``,
        ``v' = M^-1 Fbar``, ``Omega' = J^-1 Tbar``, ``P_P' = ubar``, ``m0' = u4``; ``x`` of shape ``(..., 20)``,
        ``u`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 20, self.state_names)
        u = trailing_array("u", u, 4, self.input_names)
        shape = np.broadcast_shapes(x.shape[:-1], u.shape[:-1])
        x, u = np.broadcast_to(x, shape + x.shape[-1:]), np.broadcast_to(u, shape + u.shape[-1:])
        veh = self.vehicle
        g, mbar = veh.g, veh.mbar
        q, v, Om = x[..., 3:7], x[..., 7:10], x[..., 10:13]
        rP, PP, m0 = x[..., 13:16], x[..., 16:19], x[..., 19]
        ub, u4 = u[..., 0:3], u[..., 3]
        R = rotation(q)
        zeta = R[..., 2, :]  # R^T k = third row of R
        Mv = body_masses(veh, m0) * v
        F, T, _, _, _ = loads_3d(veh, v, Om)
        J = np.array([veh.J1, veh.J2, veh.J3])
        Fbar = cross(Mv + PP, Om) + (m0 * g)[..., None] * zeta + F - ub
        # (2.5) read as J Om x Om + r_P x (P_P x Om): the literal (J Om + r_P x P_P) x Om differs by
        # P_P x (Om x r_P), disagrees with (2.20) in the plane and with (8.25); see the module notes
        Tbar = (cross(J * Om, Om) + cross(rP, cross(PP, Om)) + cross(Mv, v) + mbar * g * cross(rP, zeta) + T
                - cross(rP, ub))
        bdot = np.einsum("...ij,...j->...i", R, v)
        return np.concatenate([bdot, quaternion_rate(q, Om), Fbar / body_masses(veh, m0), Tbar / J,
                               PP / mbar - v - cross(Om, rP), ub, u4[..., None]], -1)


@dataclass(frozen=True)
class FixedMassGlider3D:
    """Acceleration form (8.23)-(8.25): moving mass fixed at ``r_p`` (m), constant buoyancy ``m0`` (kg).

    ``rhs(x)`` for ``x = (x, y, z, q, v, Omega)``; :meth:`accelerations` gives ``(v', Omega')`` from ``(v, Omega,
    zeta)`` with ``zeta = R^T k``.

    Parameters
    ----------
    vehicle : Vehicle
        An underwater glider with the 3D parameters ``J1, J3, K_beta, K_MR, K_MY`` (and ``m2`` for the fixed mass
        model).
    r_p : tuple of float
        Fixed moving-mass position ``(r_P1, r_P2, r_P3)`` in body axes (m), ``|r_p| <=`` :data:`R_P_MAX` (10 m).
    m0 : float
        Constant net buoyancy (kg, positive heavy); for the ``added`` mass model the solid mass
        ``m_s = m + m0 - mbar`` must stay positive.
    rudder : float
        Constant rudder angle ``delta_r`` (rad, ``|delta_r| <= pi/2``; default 0): side force and yaw moment of
        :func:`~glidectl.hydro.loads_3d`.
    state_names : tuple of str
        Names of the 13 states ``(x, y, z, q0..q3, v1..v3, Omega1..Omega3)`` (m, nondimensional, m/s, rad/s);
        default :data:`FIXED_STATES`.
    input_names : tuple of str
        Empty: the model has no inputs.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle, ``r_p`` is not three real numbers or ``m0`` not a real number.
    ArgumentError
        If ``r_p`` or ``m0`` is not finite, or ``|r_p| > R_P_MAX``.
    ModelError
        If the vehicle is not an underwater glider or lacks a 3D parameter, ``m0`` makes the solid mass
        ``m + m0 - mbar`` or a body mass ``m_i`` non-positive, or the generalized mass matrix of (8.23) is singular
        to working precision (condition number above 1e12).
    """

    vehicle: Vehicle
    r_p: tuple[float, float, float]
    m0: float
    rudder: float = 0.0
    state_names: tuple[str, ...] = FIXED_STATES
    input_names: tuple[str, ...] = ()
    _Minv: np.ndarray = field(init=False, repr=False, compare=False)
    _consts: tuple[np.ndarray, np.ndarray, np.ndarray] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        require_glider3d(self.vehicle)
        veh = self.vehicle
        r = checks.array("r_p (moving-mass position, m)", self.r_p, shape=(3,))
        m0 = checks.real("m0 (net buoyancy)", self.m0, unit="kg")
        if float(np.linalg.norm(r)) > R_P_MAX:
            raise ArgumentError(f"r_p = {tuple(r)} m puts the moving mass {np.linalg.norm(r):.4g} m from the centre "
                                f"of buoyancy; at most R_P_MAX = {R_P_MAX:g} m is plausible")
        object.__setattr__(self, "r_p", (float(r[0]), float(r[1]), float(r[2])))
        object.__setattr__(self, "m0", m0)
        object.__setattr__(self, "rudder", checks.real("rudder (angle)", self.rudder, lo=-math.pi / 2,
                                                       hi=math.pi / 2, unit="rad"))
        mbar = veh.mbar
        if veh.mass_model == "added" and not veh.m + m0 - mbar > 0:
            raise ModelError(f"m0 = {m0:g} kg makes the solid mass m + m0 - mbar = {veh.m + m0 - mbar:g} kg of "
                             f"vehicle '{veh.name}' non-positive (m = {veh.m:g} kg, mbar = {mbar:g} kg); the ballast "
                             "cannot be that light")
        masses = [float(veh.mass(i, m0)) for i in (1, 2, 3)]
        if min(masses) <= 0:
            raise ModelError(f"m0 = {m0} kg makes a body mass non-positive on vehicle '{veh.name}' "
                             f"(m_1, m_2, m_3 = {masses} kg); the ballast cannot be that light")
        M = np.diag(masses)
        J = np.diag([veh.J1, veh.J2, veh.J3])
        rh = hat(r)
        big = np.block([[M + mbar * np.eye(3), -mbar * rh], [mbar * rh, J - mbar * rh @ rh]])
        cond = float(np.linalg.cond(big))
        if not cond < _COND_MAX:
            raise ModelError(f"the generalized mass matrix of (8.23) is singular to working precision (condition "
                             f"number {cond:.3g}) for r_p = {self.r_p} m, m0 = {m0:g} kg on vehicle '{veh.name}'")
        object.__setattr__(self, "_Minv", np.linalg.inv(big))
        # (M, J, r_P) as arrays, built once: forces() is called thousands of times per trim sweep
        object.__setattr__(self, "_consts", (np.array(masses, dtype=float), np.array([veh.J1, veh.J2, veh.J3]),
                                             np.asarray(self.r_p, dtype=float)))

    @property
    def generalized_mass(self) -> np.ndarray:
        """Inverse of the 6x6 matrix of (8.23)."""
        return self._Minv.copy()

    def forces(self, v: Any, Om: Any, zeta: Any) -> tuple[Any, Any]:
        """``(Fbar', Tbar')`` of (8.24)-(8.25) for ``v``, ``Om``, ``zeta`` of shape ``(..., 3)``.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If an argument is not an array of numbers with a trailing dimension 3.
        """
        v, Om = trailing_array("v", v, 3), trailing_array("Om", Om, 3)
        zeta = trailing_array("zeta", zeta, 3)
        veh = self.vehicle
        g, mbar = veh.g, veh.mbar
        M, J, rP = self._consts
        F, T, _, _, _ = loads_3d(veh, v, Om, self.rudder)
        w = v + cross(Om, np.broadcast_to(rP, np.shape(v)))
        rPb = np.broadcast_to(rP, np.shape(v))
        Fp = cross(M * v + mbar * w, Om) + self.m0 * g * zeta + F
        Tp = (cross(J * Om + mbar * cross(rPb, w), Om) - cross(v, M * v)
              - mbar * cross(v, cross(Om, rPb)) + mbar * g * cross(rPb, zeta) + T)
        return Fp, Tp

    def accelerations(self, v: Any, Om: Any, zeta: Any) -> tuple[Any, Any]:
        """``(v', Omega')`` of (8.23)."""
        Fp, Tp = self.forces(v, Om, zeta)
        a = np.einsum("ij,...j->...i", self._Minv, np.concatenate([Fp, Tp], -1))
        return a[..., :3], a[..., 3:]

    def rhs(self, x: Any, u: Any = None) -> Any:
        """Derivative of the 13 states ``x`` (shape ``(..., 13)``; ``u`` is ignored, the model has no inputs).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` is not an array of numbers with a trailing dimension 13.
        """
        x = trailing_array("x", x, 13, self.state_names)
        q, v, Om = x[..., 3:7], x[..., 7:10], x[..., 10:13]
        R = rotation(q)
        vd, Od = self.accelerations(v, Om, R[..., 2, :])
        return np.concatenate([np.einsum("...ij,...j->...i", R, v), quaternion_rate(q, Om), vd, Od], -1)
