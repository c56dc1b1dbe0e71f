"""Phugoid-mode model of an underwater glider (thesis chapter 4, §4.1): equations (4.1)-(4.8).

The one right-hand side is :meth:`PhugoidModel.rhs`, equations (4.1)-(4.4)::

    x'  = xdot,                        z'  = zdot,
    xdot' = K V zdot / m,              zdot' = (m0 g - K V xdot) / m,     V = sqrt(xdot^2 + zdot^2),

with ``m = m1 + mbar`` (kg), net weight ``m0 g`` (N), constant lift coefficient ``K = K_L0 + K_L alpha`` (kg/m)
and inertial ``z`` pointing down. Drag, added-mass anisotropy and the moving-mass dynamics are left out (§4.1
assumptions 1-4), so the model conserves the energy ``E`` (4.32)/(4.43) and Lanchester's quantity ``C`` (4.5).
The alternative (Hamiltonian, Lagrangian, pendulum) formulations of §4.1/§4.3 live in
:mod:`glidectl.models.phugoid_hamiltonian`; they are checked against this right-hand side, never copied from it.

States ``(x, z, xdot, zdot)`` in (m, m, m/s, m/s); no inputs. Arrays may carry leading batch dimensions and may
be complex (complex-step Jacobians): the speed is written ``sqrt(xdot^2 + zdot^2)``, not ``abs``.

Classes of motion (Fig 4.1, Lanchester)
---------------------------------------
``C = 2/3``: steady level flight at ``xdot_e = sqrt(m0 g / K)`` (the only relative equilibrium);
``0 < C < 2/3``: wavy (phugoid oscillation); ``C = 0``: a periodic train of cusps, the glider momentarily
stopping at each cusp; ``C < 0``: loops. ``C > 2/3`` is not attained by any state.

Notes
-----
The thesis calls ``C = 0`` "a single flight with the flight path angle varying between -90 deg and +90 deg over
an infinite time interval". Along ``C = 0`` the speed obeys ``dV/dt = -(m0 g / m) sin(gamma)`` and reaches zero
at a finite rate (gravity alone acts at ``V = 0``), so the time between cusps is finite:
``T = 2 sqrt(3) B(1/4, 1/2)/4 * m xdot_e / (m0 g)`` (:func:`orbit_period`; about 2.03 s for Fig 4.1's vehicle).
Every ``C <= 2/3`` orbit, the cusp train included, is periodic in the velocity plane.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any, Literal

import numpy as np

from .. import checks
from ..errors import InfeasibleGlideError, ModelError, SolverError
from ..params import Vehicle
from ._validate import angle_arg, numeric_array, require_instance, trailing_array
from .reduced import require_centred_mass

__all__ = [
    "C_STEADY",
    "PHUGOID_STATES",
    "PhugoidClass",
    "PhugoidModel",
    "classify_C",
    "initial_state_for_C",
    "orbit_period",
]

PHUGOID_STATES = ("x", "z", "xdot", "zdot")
C_STEADY = 2.0 / 3.0  #: Lanchester's C of steady level flight, the largest value C takes (4.5)


@dataclass(frozen=True)
class PhugoidModel:
    """Phugoid-mode model (4.1)-(4.4) of an underwater glider in the longitudinal plane.

    Parameters
    ----------
    mass : float
        ``m = m1 + mbar`` (kg): vehicle mass including added mass along body-1 (= body-3, assumption 3) plus the
        moving mass fixed at the centre of buoyancy (assumption 4).
    m0 : float
        Net buoyancy (heaviness) ``m0`` (kg), > 0: the glider sinks, as needed for the steady level flight
        ``xdot_e = sqrt(m0 g / K)`` to exist.
    K : float
        Lift coefficient ``K = K_L0 + K_L alpha`` (kg/m) at the frozen angle of attack (assumption 1), > 0.
    g : float, optional
        Gravitational acceleration (m/s^2), default 9.81 (chapter 4 does not state its g).
    vehicle : Vehicle, optional
        The vehicle the parameters came from (provenance only; set by :meth:`from_vehicle`).

    Raises
    ------
    ArgumentTypeError
        A parameter is not a real number, or ``vehicle`` is not a Vehicle.
    ArgumentError
        A parameter is not a positive finite number.
    """

    mass: float
    m0: float
    K: float
    g: float = 9.81
    vehicle: Vehicle | None = field(default=None, compare=False, repr=False)
    state_names: tuple[str, ...] = field(default=PHUGOID_STATES, init=False, repr=False)
    input_names: tuple[str, ...] = field(default=(), init=False, repr=False)

    def __post_init__(self) -> None:
        for name, what in (("mass", "m1 + mbar in kg"), ("m0", "net buoyancy in kg; m0 > 0 means heavy"),
                           ("K", "lift coefficient K_L0 + K_L alpha in kg/m"), ("g", "gravity in m/s^2")):
            object.__setattr__(self, name, checks.positive(f"phugoid model: {name} ({what})", getattr(self, name)))
        if self.vehicle is not None:
            checks.vehicle("vehicle", self.vehicle)

    @classmethod
    def from_vehicle(cls, veh: Vehicle, alpha: float, m0: float | None = None) -> PhugoidModel:
        """The phugoid model of a vehicle file at a fixed angle of attack (§4.1).

        Parameters
        ----------
        veh : Vehicle
            An underwater glider (:func:`glidectl.load_vehicle`) satisfying assumption 3, ``m1 = m3``.
        alpha : float
            Frozen angle of attack (rad); ``K = K_L0 + K_L alpha`` (kg/m) must come out positive.
        m0 : float, optional
            Net buoyancy (kg); default: the vehicle's nominal ``m0``.

        Returns
        -------
        PhugoidModel
            With ``mass = m1 + mbar`` (for the ``added`` mass model ``m1`` is evaluated at ``m0``) and the
            vehicle's ``g``.

        Raises
        ------
        ArgumentTypeError
            ``veh`` is not a Vehicle, or ``alpha`` or ``m0`` is not a real number.
        ArgumentError
            ``alpha`` is not finite (``|alpha| <= pi/2``), or ``m0`` is not a positive finite number.
        ModelError
            Not an underwater glider, the moving mass off the centre of buoyancy (``mbar > 0`` with a nonzero
            nominal ``r_P``, assumption 4), ``m1 != m3`` (assumption 3), no ``m0`` available, or ``K <= 0``.

        Notes
        -----
        Assumption 2 (no drag) and the frozen angle of attack of assumption 1 define the model: drag and the
        pitch dynamics (with its damping) are left out by construction, whatever the file gives.
        """
        checks.vehicle("veh", veh)
        if veh.kind != "underwater_glider":
            raise ModelError(f"vehicle '{veh.name}' is a {veh.kind}; the phugoid model of §4.1 is built from an "
                             "underwater glider (for an aircraft use PhugoidModel(mass=m, m0=m, K=...) directly)")
        alpha = angle_arg("angle of attack alpha", alpha, math.pi / 2)
        if m0 is not None:
            m0 = checks.positive("m0 (net buoyancy, heavy)", m0, unit="kg")
        if m0 is None:
            if not veh.has("m0"):
                raise ModelError(f"vehicle '{veh.name}' has no nominal m0: pass m0=... (kg) to "
                                 "PhugoidModel.from_vehicle")
            m0 = veh.m0
        require_centred_mass(veh, "PhugoidModel.from_vehicle", "§4.1 assumption 4 (= chapter 5 assumption 1)")
        m1, m3 = veh.mass(1, m0), veh.mass(3, m0)
        if not math.isclose(m1, m3, rel_tol=1e-12):
            raise ModelError(
                f"vehicle '{veh.name}' has m1 = {m1:g} kg != m3 = {m3:g} kg: the phugoid model (4.1)-(4.4) needs "
                "equal added masses (§4.1 assumption 3, a spherical glider); build PhugoidModel(mass=..., m0=..., "
                "K=...) directly if you accept the approximation")
        K = veh.K_L0 + veh.K_L * alpha
        if not K > 0:
            raise ModelError(f"lift coefficient K = K_L0 + K_L alpha = {K:g} kg/m at alpha = {alpha:g} rad is not "
                             "positive: the phugoid model needs positive lift")
        return cls(mass=m1 + veh.mbar, m0=float(m0), K=K, g=veh.g, vehicle=veh)

    # ------------------------------------------------------------------------------------------ dynamics
    def rhs(self, x: Any, u: Any = None) -> Any:
        """Time derivative of the state, equations (4.1)-(4.4).

        Parameters
        ----------
        x : array_like, shape (..., 4)
            ``(x, z, xdot, zdot)`` in (m, m, m/s, m/s); z down.
        u : ignored
            The model has no inputs (``input_names == ()``).

        Returns
        -------
        ndarray, shape (..., 4)
            ``(xdot, zdot, xddot, zddot)`` in (m/s, m/s, m/s^2, m/s^2).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` is not an array of numbers with a trailing dimension 4.
        """
        x = trailing_array("x", x, 4, self.state_names)
        xd, zd = x[..., 2], x[..., 3]
        V = np.sqrt(xd * xd + zd * zd)
        return np.stack(np.broadcast_arrays(
            xd,                                                   # (4.1)
            zd,                                                   # (4.2)
            self.K * V * zd / self.mass,                          # (4.3)
            (self.m0 * self.g - self.K * V * xd) / self.mass,     # (4.4)
        ), axis=-1)

    @property
    def xdot_e(self) -> float:
        """Speed of the relative equilibrium (steady level flight), ``sqrt(m0 g / K)`` (m/s), §4.1."""
        return math.sqrt(self.m0 * self.g / self.K)

    @property
    def time_scale(self) -> float:
        """``m xdot_e / (m0 g)`` (s): the phugoid time unit; periods are multiples of it (:func:`orbit_period`)."""
        return self.mass * self.xdot_e / (self.m0 * self.g)

    @property
    def linear_period(self) -> float:
        """Period of small oscillations about steady level flight, ``pi sqrt(2) m xdot_e / (m0 g)`` (s).

        The linearization of (4.3)-(4.4) at ``(xdot_e, 0)`` has eigenvalues ``+-i sqrt(2) K xdot_e / m``; with
        ``m = m0`` this is Lanchester's aircraft phugoid period ``pi sqrt(2) V / g``.
        """
        return math.pi * math.sqrt(2.0) * self.time_scale

    def energy(self, x: Any) -> Any:
        """Total energy ``E = m (xdot^2 + zdot^2)/2 - m0 g z`` (J), (4.32)/(4.43); conserved by (4.1)-(4.4).

        Parameters
        ----------
        x : array_like, shape (..., 4)
            State ``(x, z, xdot, zdot)`` (m, m, m/s, m/s).
        """
        x = trailing_array("x", x, 4, self.state_names)
        return 0.5 * self.mass * (x[..., 2] ** 2 + x[..., 3] ** 2) - self.m0 * self.g * x[..., 1]

    def lanchester_C(self, x: Any) -> Any:
        """Lanchester's second conserved quantity (4.5), dimensionless.

        ``C = xdot/|xdot_e| - (1/3) ((xdot^2 + zdot^2)/xdot_e^2)^(3/2)``; ``C = 2/3`` at steady level flight.

        Parameters
        ----------
        x : array_like, shape (..., 4)
            State ``(x, z, xdot, zdot)`` (m, m, m/s, m/s).
        """
        x = trailing_array("x", x, 4, self.state_names)
        xe = self.xdot_e
        v2 = (x[..., 2] ** 2 + x[..., 3] ** 2) / xe**2
        return x[..., 2] / xe - v2 * np.sqrt(v2) / 3.0

    def H_canonical(self, xdot: Any, zdot: Any) -> Any:
        """Hamiltonian (4.6) of the canonical 2-D formulation, ``q = xdot``, ``p = zdot`` (m^2/s^3).

        ``H = K (xdot^2 + zdot^2)^(3/2) / (3 m) - m0 g xdot / m = -(m0 g / m) |xdot_e| C``.

        Parameters
        ----------
        xdot, zdot : array_like
            Velocity components (m/s); broadcast together.
        """
        xdot, zdot = numeric_array("xdot", xdot), numeric_array("zdot", zdot)
        v2 = xdot * xdot + zdot * zdot
        return self.K * v2 * np.sqrt(v2) / (3.0 * self.mass) - self.m0 * self.g * xdot / self.mass


# ---------------------------------------------------------------------------------------------- classes of C
class PhugoidClass(StrEnum):
    """The four classes of phugoid trajectories of Fig 4.1, by Lanchester's C (4.5).

    A string enumeration (the value is the label used in figures); :func:`classify_C` maps a value of ``C``
    (nondimensional) to its class.

    Attributes
    ----------
    STEADY_LEVEL : str
        ``C = 2/3`` (:data:`C_STEADY`): steady level flight.
    WAVY : str
        ``0 < C < 2/3``: wavy flight path.
    CUSP : str
        ``C = 0``: the singular path with cusps (the speed vanishes at the cusps).
    LOOPS : str
        ``C < 0``: looping flight path.
    """

    STEADY_LEVEL = "steady level flight"
    WAVY = "wavy"
    CUSP = "cusps (singular)"
    LOOPS = "loops"


def _check_C(C: Any) -> float:
    return checks.real("Lanchester's C", C)


def _check_model(model: Any) -> PhugoidModel:
    return require_instance("model", model, PhugoidModel, " (gc.PhugoidModel(...) or PhugoidModel.from_vehicle)")


def classify_C(C: float, tol: float = 1e-9) -> PhugoidClass:
    """Class of the phugoid trajectory with Lanchester constant ``C`` (Fig 4.1, §4.1).

    Parameters
    ----------
    C : float
        Lanchester's C (4.5), dimensionless.
    tol : float, optional
        Absolute tolerance for the two singular values ``C = 2/3`` and ``C = 0``.

    Returns
    -------
    PhugoidClass
        ``STEADY_LEVEL`` for ``|C - 2/3| <= tol``, ``CUSP`` for ``|C| <= tol``, ``WAVY`` in between, ``LOOPS``
        for ``C < -tol``.

    Raises
    ------
    ArgumentTypeError
        ``C`` or ``tol`` is not a real number.
    ArgumentError
        ``C`` is not finite, or ``tol`` is not in ``[0, 1/3)``.
    InfeasibleGlideError
        ``C > 2/3 + tol`` (no state has it).
    """
    C = _check_C(C)
    tol = checks.real("tol", tol, lo=0.0, hi=C_STEADY / 2, hi_open=True)
    if C > C_STEADY + tol:
        raise InfeasibleGlideError(f"C = {C:.6g} > 2/3: no phugoid state has it (C <= 2/3, with equality only at "
                                   "steady level flight)")
    if C >= C_STEADY - tol:
        return PhugoidClass.STEADY_LEVEL
    if abs(C) <= tol:
        return PhugoidClass.CUSP
    return PhugoidClass.WAVY if C > 0 else PhugoidClass.LOOPS


def _fast_root(C: float) -> float:
    """Largest root s >= 1 of s - s^3/3 = C (C <= 2/3): the fastest, lowest point of the orbit, flying forward."""
    c = min(C, C_STEADY)
    if c == C_STEADY:
        return 1.0  # exact steady level flight (the trigonometric form rounds to 1 + 2e-16)
    if c >= -C_STEADY:
        return 2.0 * math.cos(math.acos(max(-1.0, -1.5 * c)) / 3.0)
    return 2.0 * math.cosh(math.acosh(-1.5 * c) / 3.0)


def _slow_root(C: float) -> float:
    """Root of s - |s|^3/3 = C with the slowest horizontal flight: s in [0, 1] for C >= 0, s < 0 for C < 0."""
    c = min(C, C_STEADY)
    if c == C_STEADY:
        return 1.0
    if c >= 0:
        return max(0.0, 2.0 * math.cos((math.acos(max(-1.0, -1.5 * c)) + 4.0 * math.pi) / 3.0))
    return 2.0 * math.sinh(math.asinh(1.5 * c) / 3.0)


def initial_state_for_C(model: PhugoidModel, C: float, *, x0: float = 0.0, z0: float = 0.0,
                        branch: Literal["fast", "slow"] = "fast", tol: float = 1e-12) -> np.ndarray:
    """Initial state with horizontal velocity (``zdot0 = 0``) giving a requested Lanchester constant ``C`` (4.5).

    With ``zdot = 0`` and ``s = xdot0 / xdot_e``, (4.5) reads ``C = s - |s|^3 / 3``. For ``C < 2/3`` the orbit
    passes through horizontal flight twice, so there are two roots, both on the same trajectory (half a period
    apart):

    * ``branch="fast"`` (default): the root ``s >= 1``, ``s - s^3/3 = C``. This is the bottom of the wave or loop:
      the fastest and deepest point of the orbit, flying forward. It is one smooth, strictly decreasing branch
      for all ``C <= 2/3`` (``s = 1`` at 2/3, ``sqrt(3)`` at 0, ``2`` at -2/3), never passes through zero speed
      and is the physically sensible choice: a glider launched level and fast.
    * ``branch="slow"``: the top of the orbit: ``0 <= s <= 1`` for ``C >= 0`` (``s = 0``, i.e. at rest, for the
      cusp ``C = 0``) and ``s < 0`` for ``C < 0`` (inverted, flying backwards at the top of a loop).

    Parameters
    ----------
    model : PhugoidModel
    C : float
        Requested Lanchester constant (dimensionless), ``C <= 2/3``.
    x0, z0 : float, optional
        Initial position (m), z down.
    branch : {"fast", "slow"}
    tol : float, optional
        ``C`` up to ``2/3 + tol`` is accepted as steady level flight.

    Returns
    -------
    ndarray, shape (4,)
        ``(x0, z0, s xdot_e, 0)`` in (m, m, m/s, m/s).

    Raises
    ------
    ArgumentTypeError
        ``model`` is not a PhugoidModel, or ``C``, ``x0``, ``z0``, ``tol`` not real numbers.
    ArgumentError
        ``C``, ``x0`` or ``z0`` is not finite, ``tol`` is not in ``[0, 1/3)``, or ``branch`` is unknown.
    InfeasibleGlideError
        ``C > 2/3`` (no trajectory has it).
    """
    _check_model(model)
    C = _check_C(C)
    x0, z0 = checks.real("x0", x0, unit="m"), checks.real("z0", z0, unit="m")
    tol = checks.real("tol", tol, lo=0.0, hi=C_STEADY / 2, hi_open=True)
    checks.choice("branch", branch, ("fast", "slow"))
    if C > C_STEADY + tol:
        raise InfeasibleGlideError(f"no phugoid trajectory has C = {C:.6g}: C <= 2/3 for every state (C = 2/3 is "
                                   "steady level flight); request C <= 2/3")
    s = _fast_root(C) if branch == "fast" else _slow_root(C)
    return np.array([x0, z0, s * model.xdot_e, 0.0])


def orbit_period(model: PhugoidModel, C: float, tol: float = 1e-12) -> float:
    """Period (s) of the phugoid orbit with Lanchester constant ``C`` in the velocity plane (§4.1, Fig 4.1).

    With ``v = V / xdot_e`` and ``cos(gamma) = (C + v^3/3)/v`` on the orbit, (4.3)-(4.4) give
    ``dv/dt = -sin(gamma) / T0``, ``T0 = m xdot_e / (m0 g)``; the speed sweeps ``[v_lo, v_hi]`` and back, so
    ``T = 2 T0 int_{v_lo}^{v_hi} dv / sqrt(1 - cos(gamma)^2)``. The endpoint singularities are removed by
    ``v = v_lo + (v_hi - v_lo)(1 - cos(phi))/2`` and the cubic factorization of ``1 -+ cos(gamma)``, leaving a
    smooth integrand on ``[0, pi]`` (scipy ``quad``). ``C = 2/3`` gives the linear period
    ``pi sqrt(2) T0``; ``C = 0`` gives the finite time between cusps ``2 sqrt(3) B(1/4, 1/2)/4 T0``; for
    ``C < 0`` it is the time per loop.

    Parameters
    ----------
    model : PhugoidModel
    C : float
        Lanchester's C, ``<= 2/3``.
    tol : float
        ``C`` up to ``2/3 + tol`` is treated as 2/3.

    Returns
    -------
    float
        Period in seconds.

    Raises
    ------
    ArgumentTypeError
        ``model`` is not a PhugoidModel, or ``C`` or ``tol`` not a real number.
    ArgumentError
        ``C`` is not finite, or ``tol`` is not in ``[0, 1/3)``.
    InfeasibleGlideError
        ``C > 2/3 + tol``.
    SolverError
        The quadrature does not reach its tolerance (it always does for finite ``C``; a safeguard).
    """
    import warnings

    from scipy.integrate import IntegrationWarning, quad

    _check_model(model)
    C = _check_C(C)
    tol = checks.real("tol", tol, lo=0.0, hi=C_STEADY / 2, hi_open=True)
    if C > C_STEADY + tol:
        raise InfeasibleGlideError(f"no phugoid orbit has C = {C:.6g} > 2/3")
    C = min(C, C_STEADY)
    v_hi = _fast_root(C)
    v_lo = abs(_slow_root(C))
    if C >= 0:
        r_min = -(v_hi + v_lo)  # third root of v^3 - 3v + 3C

        def g(v: float) -> float:
            return 3.0 * v / math.sqrt((v - r_min) * (v**3 + 3.0 * v + 3.0 * C))
    else:
        def g(v: float) -> float:
            q1 = v * v + v_hi * v + v_hi * v_hi - 3.0  # (v^3 - 3v + 3C) / (v - v_hi)
            q2 = v * v + v_lo * v + v_lo * v_lo + 3.0  # (v^3 + 3v + 3C) / (v - v_lo)
            return 3.0 * v / math.sqrt(q1 * q2)

    with warnings.catch_warnings():
        warnings.simplefilter("error", IntegrationWarning)
        try:
            val, _ = quad(lambda phi: g(v_lo + 0.5 * (v_hi - v_lo) * (1.0 - math.cos(phi))), 0.0, math.pi,
                          epsabs=1e-13, epsrel=1e-12, limit=200)
        except (IntegrationWarning, ValueError, ZeroDivisionError, OverflowError) as exc:
            raise SolverError(f"the period integral of the phugoid orbit C = {C:.6g} did not converge: {exc}") from exc
    if not math.isfinite(val):
        raise SolverError(f"the period integral of the phugoid orbit C = {C:.6g} is not finite")
    return 2.0 * model.time_scale * val
