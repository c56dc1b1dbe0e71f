"""The three-dimensional glider with its actuators as part of the model: buoyancy pump, battery translation along
the hull, battery roll by rotation about the hull axis and rudder, each with the range and rate of the vehicle
file's ``[actuators]`` table; currents enter the kinematics.

Model
-----
State (SI units, :data:`ACTUATED3D_STATES`)::

    (x, y, z, q0, q1, q2, q3, v1, v2, v3, Omega1, Omega2, Omega3,
     r_P1, rdot_P1, roll, rdot_roll, m0, rudder)

``(x, y, z)`` is the position in the inertial frame (x north, y east, z down, m), ``q`` the attitude quaternion of
:mod:`~glidectl.models.glider3d`, ``v`` the body velocity *relative to the water* (m/s), ``Omega`` the body angular
velocity (rad/s); then the battery position along body-1 and its rate, the battery roll angle ``phi_b`` and its rate,
the net buoyancy ``m0`` set by the pump (kg) and the rudder angle ``delta_r`` (rad).

The battery is the moving point mass ``mbar`` of (2.1)-(2.8). Rolling it about body-1 puts it at

    r_P = (r_P1, rho sin(phi_b), rho cos(phi_b)),

``rho`` the vehicle's ``r_P3`` setting (the battery offset below the axis), so its body-frame velocity and
acceleration follow from ``(r_P1, rdot_P1, phi_b, rdot_roll)`` and the servo accelerations. Given the mass motion, the
force form (2.1)-(2.8) with ``P_P = mbar (v + Omega x r_P + rdot_P)`` and ``P_P' = u`` eliminates the internal
force ``u``:

    [[M + mbar I, -mbar r_P^], [mbar r_P^, J - mbar r_P^ r_P^]] (v', Omega')
        = (A - a, B - r_P x a),   a = mbar (Omega x rdot_P + rddot_P),

with ``A = (M v + P_P) x Omega + m0 g zeta + F`` and ``B = J Omega x Omega + r_P x (P_P x Omega) + M v x v +
mbar g r_P x zeta + T`` the remaining terms of (2.4)-(2.5) (the form of :class:`~glidectl.models.glider3d.Glider3D`).
The matrix is the generalized mass matrix of (8.23): with the mass at rest the model reduces to
:class:`~glidectl.models.glider3d.FixedMassGlider3D` (tested), and in the vertical plane to the acceleration form of
the longitudinal model (tested). Loads are :func:`~glidectl.hydro.loads_3d` with the vehicle's lift and drag law
and the rudder.

Actuators
---------
The input is a vector of **requested rates** ``(r_P1_rate, roll_rate, m0_rate, rudder_rate)`` (m/s, rad/s, kg/s,
rad/s), limited exactly as :class:`~glidectl.models.actuated.ActuatedGlider` limits its own: the rate limit and a
linear taper of slope ``k_i`` onto each end of the range. The pump and the rudder follow the limited rate; the
battery translation and roll are velocity servos of time constant ``servo_time`` (taper slope ``1/(4 tau)``), so
their positions never leave the range and their rates never exceed the limit. An actuator the file lists as
``fixed`` (or does not list: ``roll`` and ``rudder`` are then fixed at 0) has rate limit 0.

Buoyancy at depth
-----------------
``m0`` is the net buoyancy at the surface (what the pump sets); at depth ``z`` the vehicle carries
``m0 + dm(z)`` with ``dm(z) = excess_mass(veh, z, 0) - excess_mass(veh, 0, 0)``
(:func:`~glidectl.excess_mass`: the hull's compressibility and the vehicle file's density profile). For a file
without compressibility or density profile ``dm = 0`` and the model is the thesis's.

Currents
--------
``x' = R v + c(t, x)``: the water moves with the current ``c`` (:class:`~glidectl.environment.Current`) and the
dynamics are those of the glider in the water (Galilean invariance for a uniform current). A sheared or
time-varying current also accelerates the water around the glider; that term, of order ``(m + m_f) dc/dt``
(``dc/dt = w dc/dz`` for a glider sinking at ``w`` through shear), is left out: through a shear of 0.1 m/s per 100 m
at 0.2 m/s it is about 2e-4 m/s^2 on the vehicle, below the resolution of any glider's flight model.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..environment import as_current
from ..errors import ModelError
from ..hydro import excess_mass, loads_3d
from ..params import Vehicle
from ._validate import require_glider, trailing_array
from .actuated import RateLimitedActuators, check_actuator_state, rate_interval
from .glider3d import body_masses, cross, quaternion_rate, require_glider3d, rotation

__all__ = ["ACTUATED3D_AXES", "ACTUATED3D_INPUTS", "ACTUATED3D_STATES", "ACTUATED3D_UNITS", "BUOYANCY_TABLE_DEPTHS",
           "ActuatedGlider3D"]

#: State names of :class:`ActuatedGlider3D`.
ACTUATED3D_STATES = ("x", "y", "z", "q0", "q1", "q2", "q3", "v1", "v2", "v3", "Omega1", "Omega2", "Omega3",
                     "r_P1", "rdot_P1", "roll", "rdot_roll", "m0", "rudder")
#: The actuators of the 3-D model, in input order.
ACTUATED3D_AXES = ("r_P1", "roll", "m0", "rudder")
#: Input names of :class:`ActuatedGlider3D`: requested actuator rates (m/s, rad/s, kg/s, rad/s).
ACTUATED3D_INPUTS = ("r_P1_rate", "roll_rate", "m0_rate", "rudder_rate")
#: Units of the actuator positions and of the inputs.
ACTUATED3D_UNITS = {"r_P1": "m", "roll": "rad", "m0": "kg", "rudder": "rad", "r_P1_rate": "m/s",
                    "roll_rate": "rad/s", "m0_rate": "kg/s", "rudder_rate": "rad/s"}

_POS = np.array([13, 15, 17, 18])  # columns of the actuator positions in ACTUATED3D_STATES


def _fixed_setting(veh: Vehicle, axis: str) -> float:
    """Setting of a moving-mass axis that does not move: its fixed actuator value or its nominal parameter."""
    act = veh.actuators.get(axis)
    if act is not None:
        if act.fixed is None:
            raise ModelError(
                f"vehicle '{veh.name}' translates the battery along {axis} ([actuators] {axis} has a range): the "
                "3-D actuated model moves the battery along body-1 and rolls it about body-1 ([actuators] roll); "
                f"make {axis} fixed")
        return float(act.fixed)
    return float(veh.params.get(axis, 0.0))


@dataclass(frozen=True)
class ActuatedGlider3D(RateLimitedActuators):
    """Three-dimensional glider whose pump, battery (translation and roll) and rudder obey the vehicle's
    ``[actuators]`` limits, flying in a current (module docstring).

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider with the 3D parameters (``J1``, ``J3``, ``K_beta``, ``K_MR``, ``K_MY``), a battery
        ``mbar > 0`` and ``[actuators]`` entries ``m0`` and ``r_P1`` (actuated or fixed). ``roll`` and ``rudder`` are
        optional (fixed at 0 when absent); ``r_P2`` and ``r_P3`` must not translate.
    current : Current, tuple or callable, optional
        Water velocity (m/s, inertial north, east, down components): anything :func:`~glidectl.environment.as_current`
        takes. Default: still water.
    servo_time : float
        Time constant ``tau`` (s) of the battery translation and roll servos, > 0 (default 0.5 s).
    pump_gain, rudder_gain : float
        Setpoint gain and range taper (1/s) of the pump (default 0.5) and of the rudder (default 2), > 0.

    Attributes
    ----------
    lower, upper, rate_limit, gain : ndarray, shape (4,)
        Range ends, rate limits (0 for a fixed axis) and taper/setpoint gains (1/s) of :data:`ACTUATED3D_AXES`.
    rho : float
        Battery offset below the body-1 axis (m), the radius of the roll circle.
    r_P2 : float
        Fixed lateral battery offset (m) of a vehicle without a roll actuator (0 with one).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle or a number is not real.
    ArgumentError
        If a time constant or gain is not a positive finite number, or ``current`` is not a current.
    ModelError
        If the vehicle is not an underwater glider with the 3D parameters and ``mbar > 0``, lacks an ``[actuators]``
        entry for ``m0`` or ``r_P1``, or translates the battery along ``r_P2`` or ``r_P3``.
    """

    vehicle: Vehicle = field(repr=False)
    current: Any = None
    servo_time: float = 0.5
    pump_gain: float = 0.5
    rudder_gain: float = 2.0
    lower: np.ndarray = field(init=False, repr=False, compare=False)
    upper: np.ndarray = field(init=False, repr=False, compare=False)
    rate_limit: np.ndarray = field(init=False, repr=False, compare=False)
    gain: np.ndarray = field(init=False, repr=False, compare=False)
    rho: float = field(init=False, repr=False, compare=False)
    r_P2: float = field(init=False, repr=False, compare=False)
    _consts: tuple[Any, ...] = field(init=False, repr=False, compare=False)
    _buoyancy_table: tuple[np.ndarray, np.ndarray] | None = field(init=False, repr=False, compare=False)

    state_names = ACTUATED3D_STATES
    input_names = ACTUATED3D_INPUTS
    actuator_names = ACTUATED3D_AXES

    def __post_init__(self) -> None:
        veh = require_glider(self.vehicle)
        require_glider3d(veh)
        if not veh.mbar > 0:
            raise ModelError(f"vehicle '{veh.name}' has mbar = 0: the actuated 3-D model moves a battery (mbar > 0)")
        object.__setattr__(self, "current", as_current(self.current))
        tau = checks.positive("servo_time", self.servo_time, unit="s")
        object.__setattr__(self, "servo_time", tau)
        kp = checks.positive("pump_gain", self.pump_gain, unit="1/s")
        object.__setattr__(self, "pump_gain", kp)
        kr = checks.positive("rudder_gain", self.rudder_gain, unit="1/s")
        object.__setattr__(self, "rudder_gain", kr)
        missing = [a for a in ("m0", "r_P1") if a not in veh.actuators]
        if missing:
            raise ModelError(
                f"vehicle '{veh.name}' has no [actuators] entr{'y' if len(missing) == 1 else 'ies'} for "
                f"{', '.join(missing)}: the actuated 3-D model needs the range and rate of the pump (m0) and of the "
                "battery along the hull (r_P1; 'fixed' if it does not move). Add them to the vehicle file, or e.g. "
                "veh.with_actuators(m0={'min': -0.25, 'max': 0.25, 'rate': 0.01}, r_P1={'min': -0.025, 'max': "
                "0.025, 'rate': 0.005})")
        rho = _fixed_setting(veh, "r_P3")
        r2 = 0.0 if "roll" in veh.actuators else _fixed_setting(veh, "r_P2")
        object.__setattr__(self, "rho", rho)
        object.__setattr__(self, "r_P2", r2)
        lo, hi, rate = [], [], []
        for axis in ACTUATED3D_AXES:
            act = veh.actuators.get(axis)
            if act is None:
                lo.append(0.0), hi.append(0.0), rate.append(0.0)
            else:
                lo.append(act.bounds[0]), hi.append(act.bounds[1])
                rate.append(0.0 if act.fixed is not None else act.rate)
        object.__setattr__(self, "lower", np.array(lo))
        object.__setattr__(self, "upper", np.array(hi))
        object.__setattr__(self, "rate_limit", np.array(rate))
        object.__setattr__(self, "gain", np.array([0.25 / tau, 0.25 / tau, kp, kr]))
        object.__setattr__(self, "_buoyancy_table", _depth_buoyancy(veh))
        base = body_masses(veh, np.array(0.0))
        object.__setattr__(self, "_consts", (np.array([veh.J1, veh.J2, veh.J3]), veh.g, veh.mbar, base,
                                             body_masses(veh, np.array(1.0)) - base))

    @property
    def time_varying(self) -> bool:
        """Whether the right-hand side depends on time (a current that changes in time)."""
        return self.current.time_varying

    def positions(self, x: Any) -> np.ndarray:
        """Actuator positions ``(r_P1, roll, m0, rudder)`` (m, rad, kg, rad) of states ``x`` (shape ``(..., 19)``)."""
        return trailing_array("x", x, 19, self.state_names)[..., _POS]

    def moving_mass(self, x: Any) -> np.ndarray:
        """Battery position ``r_P = (r_P1, r_P2 + rho sin(phi_b), rho cos(phi_b))`` (m, body axes) of states ``x``."""
        x = trailing_array("x", x, 19, self.state_names)
        return np.stack([x[..., 13], self.r_P2 + self.rho * np.sin(x[..., 15]), self.rho * np.cos(x[..., 15])], -1)

    def buoyancy_change(self, depth: Any) -> Any:
        """``dm(z)`` (kg): the net buoyancy at ``depth`` (m) minus the surface's at the same pump setting (module
        docstring); 0 for a hull that neither compresses nor meets a density profile."""
        if self._buoyancy_table is None:
            return np.zeros(np.shape(depth))
        return np.interp(depth, *self._buoyancy_table)

    def rhs(self, x: Any, u: Any, t: float = 0.0) -> Any:
        """Time derivative of the state (module docstring).

        Parameters
        ----------
        x : array_like, shape (..., 19)
            States (:data:`ACTUATED3D_STATES`).
        u : array_like, shape (..., 4)
            Requested actuator rates (m/s, rad/s, kg/s, rad/s).
        t : float
            Time (s): read only by a time-varying current.

        Returns
        -------
        ndarray, shape (..., 19)

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with that trailing dimension.
        """
        x = trailing_array("x", x, 19, self.state_names)
        u = trailing_array("u", u, 4, self.input_names)
        shape = np.broadcast_shapes(x.shape[:-1], u.shape[:-1])
        x, u = np.broadcast_to(x, (*shape, 19)), np.broadcast_to(u, (*shape, 4))
        lo, hi = rate_interval(x[..., _POS], self.lower, self.upper, self.rate_limit, self.gain)
        s = np.minimum(np.maximum(u, lo), hi)
        tau = self.servo_time
        w1 = (s[..., 0] - x[..., 14]) / tau       # battery acceleration along body-1
        wr = (s[..., 1] - x[..., 16]) / tau       # battery roll acceleration
        R = rotation(x[..., 3:7])
        vdot, Odot = self._accelerations(x, w1, wr, R[..., 2, :])
        out = np.empty(x.shape, dtype=np.result_type(x, u, vdot))
        out[..., 0:3] = np.einsum("...ij,...j->...i", R, x[..., 7:10]) + self.current.velocity(t, x[..., 0:3])
        out[..., 3:7] = quaternion_rate(x[..., 3:7], x[..., 10:13])
        out[..., 7:10] = vdot
        out[..., 10:13] = Odot
        out[..., 13] = x[..., 14]
        out[..., 14] = w1
        out[..., 15] = x[..., 16]
        out[..., 16] = wr
        out[..., 17:19] = s[..., 2:4]
        return out

    def _accelerations(self, x: Any, w1: Any, wr: Any, zeta: Any) -> tuple[Any, Any]:
        """``(v', Omega')`` of the force form with the battery's motion prescribed (module docstring); ``zeta =
        R^T k``."""
        J, g, mbar, m_base, m_slope = self._consts
        rho = self.rho
        v, Om = x[..., 7:10], x[..., 10:13]
        phi, phid, m0 = x[..., 15], x[..., 16], x[..., 17]
        if self._buoyancy_table is not None:
            m0 = m0 + np.interp(np.real(x[..., 2]), *self._buoyancy_table)
        c, s_ = np.cos(phi), np.sin(phi)
        dtype = np.result_type(x, w1, wr)
        rP, rPd, rPdd = (np.empty((*x.shape[:-1], 3), dtype=dtype) for _ in range(3))
        rP[..., 0], rP[..., 1], rP[..., 2] = x[..., 13], self.r_P2 + rho * s_, rho * c
        rPd[..., 0], rPd[..., 1], rPd[..., 2] = x[..., 14], rho * c * phid, -rho * s_ * phid
        rPdd[..., 0] = w1
        rPdd[..., 1] = rho * (c * wr - s_ * phid * phid)
        rPdd[..., 2] = -rho * (s_ * wr + c * phid * phid)
        M = m_base + m_slope * m0[..., None]      # body masses, linear in m0 (body_masses)
        Mv = M * v
        PP = mbar * (v + cross(Om, rP) + rPd)
        F, T, _, _, _ = loads_3d(self.vehicle, v, Om, x[..., 18])
        a = mbar * (cross(Om, rPd) + rPdd)
        rhs = np.empty((*x.shape[:-1], 6, 1), dtype=np.result_type(dtype, F))
        rhs[..., 0:3, 0] = cross(Mv + PP, Om) + (m0 * g)[..., None] * zeta + F - a
        rhs[..., 3:6, 0] = (cross(J * Om, Om) + cross(rP, cross(PP, Om) + mbar * g * zeta - a) + cross(Mv, v) + T)
        sol = np.linalg.solve(_generalized_mass(M, J, mbar, rP), rhs)[..., 0]
        return sol[..., :3], sol[..., 3:]

    def check_state(self, x: Any, what: str = "x0") -> np.ndarray:
        """``x`` (shape (19,)) if its actuators are inside their ranges and the battery's rates inside the invariant
        set of its servos.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If ``x`` is not 19 finite numbers.
        InfeasibleGlideError
            If an actuator is outside its range or moves faster than its rate limit allows there.
        """
        x = checks.array(what, x, shape=(19,))
        check_actuator_state(self, x, what, {0: 14, 1: 16}, ACTUATED3D_UNITS)
        return x


#: Depths (m) at which :class:`ActuatedGlider3D` tabulates the buoyancy change with depth (linear in between; the
#: density profile's own depths are added so that its breakpoints are exact).
BUOYANCY_TABLE_DEPTHS = np.linspace(0.0, 6000.0, 601)


def _depth_buoyancy(veh: Vehicle) -> tuple[np.ndarray, np.ndarray] | None:
    """Depths and buoyancy change ``dm(z)`` (kg) of a compressible hull or a stratified sea, None when both are
    absent (or the hull's mass and volume are unknown: a ``fixed`` mass model without them)."""
    if not (veh.params.get("compressibility", 0.0) or veh.params.get("thermal_expansion", 0.0)
            or veh.density_profile):
        return None
    depths = np.unique(np.r_[BUOYANCY_TABLE_DEPTHS, np.asarray(veh.density_profile[0]) if veh.density_profile
                             else []])
    try:
        dm = excess_mass(veh, depths, 0.0) - excess_mass(veh, 0.0, 0.0)
    except ModelError:
        return None
    return depths, np.asarray(dm, dtype=float)


def _generalized_mass(M: Any, J: np.ndarray, mbar: float, rP: Any) -> Any:
    """The 6 x 6 matrix of (8.23), ``[[M + mbar I, -mbar r^], [mbar r^, J - mbar r^ r^]]``, for body masses ``M``
    (shape ``(..., 3)``) and battery positions ``rP`` (shape ``(..., 3)``)."""
    r1, r2, r3 = rP[..., 0], rP[..., 1], rP[..., 2]
    out = np.zeros((*rP.shape[:-1], 6, 6), dtype=np.result_type(M, rP))
    for i in range(3):
        out[..., i, i] = M[..., i] + mbar
    rh = ((None, -r3, r2), (r3, None, -r1), (-r2, r1, None))
    for i in range(3):
        for j in range(3):
            if rh[i][j] is not None:
                out[..., i, 3 + j] = -mbar * rh[i][j]
                out[..., 3 + i, j] = mbar * rh[i][j]
    # J - mbar r^ r^ = J + mbar (|r|^2 I - r r^T)
    r = (r1, r2, r3)
    n2 = r1 * r1 + r2 * r2 + r3 * r3
    for i in range(3):
        for j in range(3):
            out[..., 3 + i, 3 + j] = mbar * ((n2 if i == j else 0.0) - r[i] * r[j]) + (J[i] if i == j else 0.0)
    return out
