"""Dive cycles: a supervisor flies sawtooth profiles between two depths on the actuated glider
(:class:`~glidectl.ActuatedGlider`), with a choice of controllers, and measures each cycle.

Supervisor
----------
The mission starts at the top limit in the steady up-glide (so ``t = 0`` is the first top inflection). Each leg
flies one glide of the glide family, :func:`~glidectl.steady_glide` at ``(speed, -gamma)`` down and
``(speed, +gamma)`` up, at the vehicle's fixed ``r_P3`` (its pump mass ``m0`` and battery position ``r_P1`` are the
leg's setpoints), and ends when the *measured* depth reaches the leg's limit: the inflection, where the supervisor
switches to the other leg and its controller (one design per leg: gain scheduling by leg). After the last cycle's
top inflection the run goes on until the climb stops, to measure the last overshoot.

At an inflection the leg's reference moves from the previous glide to the new one along a straight line in state
space in the time the slowest actuator needs at :data:`RAMP_RATE_FRACTION` (80 %) of its rate limit
(``ramp_time``); so the linear designs are not asked for steps they cannot follow, and keep some rate for feedback.

Controllers (``controller=``)
-----------------------------
Actuator limits: the named controllers do not saturate their own commands; they are run only through the
actuated model (:class:`~glidectl.ActuatedGlider` in :func:`~glidectl.sim.simulate_actuated`), whose servo loops
and rate/range limiter enforce the ``[actuators]`` table (``"pid"`` also clips its battery command to the travel
for its anti-windup, and setpoints are clipped to the ranges by the servo loops).

* ``"lqr"``: :class:`ScheduledGlideLQR`, LQR (python-control) on the acceleration-form linearization
  (:func:`~glidectl.linearize_glide`) of the leg's glide, restricted to the actuated inputs (the vehicle file's
  default, :func:`~glidectl.controllers.linear.default_actuate`: ``w1`` battery, ``w4`` pump; ``w3`` too if
  ``r_P3`` moves) and to the states other than the glide-path deviation ``z'`` (which needs the unmeasurable
  horizontal position); Bryson weights from :data:`~glidectl.controllers.linear.DEFAULT_MAX_DEVIATION`. This is the
  regulator of :func:`~glidectl.lqg_glide` (same weights, same :func:`~glidectl.controllers.linear.lqr_subset`);
  :func:`~glidectl.lqr_glide` differs in also regulating ``z'``. Needs every state measured.
* ``"lqg"``: :class:`SampledGlideLQG`, sampled-data output feedback from depth, pitch and pitch rate
  (:data:`LQG_SENSORS`; simulated noise :data:`LQG_NOISE` unless ``noise`` says otherwise), run as a glider's
  flight computer runs it: every ``sensor_period`` the sensors are read, a discrete Kalman filter corrects the
  estimate and a new command is held until the next sample. Gains: :func:`~glidectl.lqg_glide` at each leg's glide
  on the acceleration inputs the file actuates (with ``r_P3`` fixed: ``w1``, ``w4``; with all three inputs these
  sensors leave two modes of the moving mass unobservable and the design is refused), sampled at
  ``sensor_period`` (:meth:`~glidectl.LQGController.sampled`). The filter's weights are its own
  (``measurement_noise``, ``process_noise``; defaults :func:`lqg_filter_noise`), separate from the simulated noise.
  The estimate is predicted with the actuated model between samples, integrated with the plant, and carried over
  each inflection. (:class:`ScheduledGlideLQG` is the continuous-time version, for ``controller=`` objects.)
* ``"nonlinear"``: the chapter-6 steady-glide controller, the torque law (6.5) realized by the moving mass
  (:class:`~glidectl.controllers.moving_mass.MovingMassTorque`) plus the buoyancy law (6.9); applies only to vehicles
  that meet its chapter-5 assumptions (``K_q < 0``, ``K_M < 0``, equal added masses, a nominal ``m0``); refused
  otherwise, naming the assumption.
* ``"pid"``: the operational baseline of Slocum/Seaglider flight software: :class:`PitchPID`, PID on the pitch
  angle through the battery position ``r_P1`` (feedforward from the glide family), and the pump run to the end of
  its range at each inflection (``m0 = max`` down, ``min`` up), so the speed is whatever the full pump gives.
* a controller object: a pair ``(down, up)`` of controllers, an object with ``for_leg(glide, previous, t_start)``
  returning the leg's controller, or one controller flown on every leg; any controller
  :func:`~glidectl.sim.simulate_actuated` accepts.

Metrics (:class:`CycleMetrics`)
-------------------------------
Per cycle (top inflection to the next top inflection): horizontal ``distance`` (m), ``duration`` (s), the
``overshoot`` beyond the depth limit after the bottom and the closing top inflection (m), ``saturated_time`` (s
during which some actuator is at a limit: rate cut or within 1e-3 of its range width from an end) and pump
``energy`` (J, :func:`pump_energy`).

Pump energy
-----------
``E = (1 / eta) * integral of p(z) |dV/dt| dt`` over the times the pump pushes oil *out* (``dm0/dt < 0``: the
displaced volume grows, ``dV/dt = -(dm0/dt) / rho``), with the absolute pressure ``p(z) = p_atm + rho g z``
(``rho`` = :data:`RHO_SEAWATER` = 1025 kg/m^3, ``p_atm`` = :data:`P_ATM` = 101 325 Pa, ``g`` of the vehicle) and
``eta`` the vehicle file's ``pump_efficiency`` (1, i.e. hydraulic work, when the file gives none; the result says
which). Only pumping out is counted by default: that is the stroke that works against the sea pressure; the
return stroke is driven by it (Seaglider lets the oil back through a valve, Eriksen et al. 2001, IEEE J. Oceanic
Eng. 26(4):424-436; the Slocum buoyancy piston is pushed back by the ambient pressure, Webb, Simonetti & Jones
2001, same issue, 447-452), so counting it would charge the pump for work the sea does. ``pump_work="both"``
counts both directions (a motor that spends the same power either way).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..analysis.linear import linearize_glide
from ..derivatives import jacobians
from ..errors import (
    ArgumentError,
    ArgumentTypeError,
    BudgetError,
    GlidectlError,
    InfeasibleGlideError,
    ModelError,
    SolverError,
)
from ..models._validate import require_glider, require_instance
from ..models.actuated import ACTUATED_AXES, ActuatedGlider
from ..models.longitudinal import ACCEL_INPUTS, ACCEL_STATES
from ..params import Vehicle
from ..sim import ActuatedSimulation, actuator_trace, simulate_actuated
from ..trim.glide import SteadyGlide, steady_glide
from .linear import DEFAULT_MAX_DEVIATION, actuated_subset, bryson_weights, lqr_subset
from .output_feedback import LQGController, SampledLQG, lqg_glide

__all__ = [
    "CONTROLLER_NAMES",
    "P_ATM",
    "RHO_SEAWATER",
    "CycleMetrics",
    "DiveCycleRun",
    "MissionComparison",
    "PitchPID",
    "SampledGlideLQG",
    "ScheduledGlideLQG",
    "ScheduledGlideLQR",
    "compare_missions",
    "cycle_summary",
    "dive_cycle",
    "dive_cycles_batched",
    "lqg_filter_noise",
    "pump_energy",
    "pump_power",
    "tune_pitch_pid",
]

#: Seawater density used for the pump's volume flow and the hydrostatic pressure (kg/m^3).
RHO_SEAWATER = 1025.0
#: Atmospheric pressure at the surface (Pa).
P_ATM = 101_325.0
#: Controller names :func:`dive_cycle` knows.
CONTROLLER_NAMES = ("lqr", "lqg", "nonlinear", "pid")
#: Sensors of the ``"lqg"`` controller: depth (pressure sensor), pitch (attitude sensor), pitch rate (rate gyro).
LQG_SENSORS = ("z", "theta", "Omega2")
#: Default noise standard deviations of :data:`LQG_SENSORS` (m, rad, rad/s): assumed levels of this design, of the
#: order of a glider's pressure sensor (5 cm, about 0.05 % of a 100 dbar range), compass/attitude sensor (0.5 deg)
#: and rate gyro (0.2 deg/s); replace them with the datasheet values of the glider's sensors.
LQG_NOISE = {"z": 0.05, "theta": math.radians(0.5), "Omega2": math.radians(0.2)}
#: Default process-noise intensities of the ``"lqg"`` Kalman filter (state unit per square root of a second): the
#: uncertainty of the model the filter predicts with, as random walks. Speed ``v1``, ``v3`` and pitch rate ``Omega2``:
#: unmodelled hydrodynamic forces and moments (coefficients known to a few percent) drift them by about 5 mm/s and
#: 0.1 deg/s in 100 s; buoyancy ``m0``: pump delivery and hull compression, about 2 g in 100 s. The kinematic states
#: (``theta`` of ``Omega2``, depth ``z`` of the velocities) and the battery, driven by the flight computer's own
#: commands, get only a floor. These are assumptions of the design; replace them with the vehicle's identified
#: uncertainties (``process_noise=`` of :func:`dive_cycle`).
LQG_PROCESS_NOISE = {"theta": 1e-4, "Omega2": 2e-4, "v1": 5e-4, "v3": 5e-4, "r_P1": 1e-5, "rdot_P1": 1e-5,
                     "r_P3": 1e-5, "rdot_P3": 1e-5, "m0": 2e-4, "z": 1e-3}
_PUMP_WORK = ("out", "both")
_IZ = ACCEL_STATES.index("z")


# ------------------------------------------------------------------------------------------------ energy
def pump_power(depth: Any, m0_rate: Any, *, efficiency: float = 1.0, rho: float = RHO_SEAWATER, g: float = 9.81,
               p_atm: float = P_ATM, pump_work: str = "out") -> Any:
    """Power (W) the buoyancy pump draws: ``p(z) |dV/dt| / eta`` while it pushes oil out (``pump_work="out"``,
    ``dm0/dt < 0``; the return stroke is driven by the sea pressure) or always (``"both"``), with ``dV/dt =
    -(dm0/dt) / rho`` and ``p(z) = p_atm + rho g z``. No argument checks (right-hand sides and
    :func:`~glidectl.pump_energy` check theirs).

    Parameters
    ----------
    depth : array_like
        Depth ``z`` (m, positive down).
    m0_rate : array_like
        Pump rate ``dm0/dt`` (kg/s).
    efficiency, rho, g, p_atm : float
        Pump efficiency ``eta`` (0, 1], water density (kg/m^3), gravity (m/s^2), surface pressure (Pa).
    pump_work : {"out", "both"}
        Which strokes cost energy.
    """
    vdot = -np.asarray(m0_rate) / rho
    flow = np.maximum(vdot, 0.0) if pump_work == "out" else np.abs(vdot)
    return (p_atm + rho * g * np.asarray(depth)) * flow / efficiency


def pump_energy(t: Any, depth: Any, m0_rate: Any, *, efficiency: float = 1.0, rho: float = RHO_SEAWATER,
                p_atm: float = P_ATM, g: float = 9.81, pump_work: str = "out") -> float:
    """Pump energy, ``1/eta`` times the integral of ``p(z) abs(dV/dt)`` over time (J), of a sampled trajectory.

    ``dV/dt = -(dm0/dt) / rho`` (the pump changes the displaced volume, ``m0`` is the net heaviness) and
    ``p(z) = p_atm + rho g z``; trapezoidal rule on the samples.

    Parameters
    ----------
    t : array_like, shape (N,)
        Increasing times (s).
    depth : array_like, shape (N,)
        Depth ``z`` (m, positive down).
    m0_rate : array_like, shape (N,)
        Pump rate ``dm0/dt`` (kg/s); negative: pumping out (the vehicle gets lighter).
    efficiency : float
        Pump efficiency ``eta`` in ``(0, 1]``.
    rho : float
        Water density (kg/m^3), > 0.
    p_atm : float
        Surface pressure (Pa), >= 0.
    g : float
        Gravity (m/s^2), > 0.
    pump_work : {"out", "both"}
        Count only pumping out (against the pressure; default) or both directions.

    Returns
    -------
    float
        Energy (J).

    Raises
    ------
    ArgumentTypeError
        If an argument is not a number or an array of numbers.
    ArgumentError
        If the arrays differ in shape, are not finite, ``t`` is not increasing, or a constant is out of range.
    """
    t = checks.array("t", t, ndim=1, min_size=1)
    z = checks.array("depth", depth, shape=t.shape)
    r = checks.array("m0_rate", m0_rate, shape=t.shape)
    if np.any(np.diff(t) < 0):
        raise ArgumentError("t must be increasing")
    eta = checks.real("efficiency", efficiency, lo=0.0, hi=1.0, lo_open=True)
    rho = checks.positive("rho", rho, unit="kg/m^3")
    p_atm = checks.nonnegative("p_atm", p_atm, unit="Pa")
    g = checks.positive("g", g, unit="m/s^2")
    checks.choice("pump_work", pump_work, _PUMP_WORK)
    power = pump_power(z, r, efficiency=eta, rho=rho, g=g, p_atm=p_atm, pump_work=pump_work)
    if t.size < 2:
        return 0.0
    return float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))


# ------------------------------------------------------------------------------------------------ controllers
def _ramp(t: float, t_start: float, ramp_time: float) -> tuple[float, float]:
    """Fraction ``s`` of the transition done at ``t`` and its rate (1/s)."""
    if ramp_time <= 0:
        return 1.0, 0.0
    s = (t - t_start) / ramp_time
    if s <= 0:
        return 0.0, 0.0
    if s >= 1:
        return 1.0, 0.0
    return s, 1.0 / ramp_time


def _ramp_reference(t: float, x_from: np.ndarray, x_to: np.ndarray, t_start: float,
                    ramp_time: float) -> tuple[np.ndarray, np.ndarray]:
    """Reference state and feedforward ``(w1, w3, w4)`` of a transition from ``x_from`` to ``x_to``."""
    s, sd = _ramp(t, t_start, ramp_time)
    d = x_to - x_from
    x_ref = x_from + s * d
    x_ref[7], x_ref[9] = sd * d[6], sd * d[8]
    return x_ref, np.array([0.0, 0.0, sd * d[10]])


def _accel_gain(K: Any, states: Sequence[str], inputs: Sequence[str]) -> np.ndarray:
    """A design's gain (its inputs x its states) as the gain ``(w1, w3, w4) x ACCEL_STATES`` on the acceleration-form
    state (zero for ``x``, for the glide-path deviation ``z'`` and for the inputs and states the design has not)."""
    K = np.asarray(K, dtype=float)
    out = np.zeros((3, 11))
    for i, q in enumerate(inputs):
        for j, sname in enumerate(states):
            if sname != "z_prime":
                out[ACCEL_INPUTS.index(q), ACCEL_STATES.index(sname)] = K[i, j]
    return out


@dataclass(frozen=True)
class ScheduledGlideLQR:
    """LQR leg controller of a dive cycle: ``w = w_ff - K (x - x_ref(t))`` on the acceleration-form state, with the
    reference moving from ``x_from`` to the glide ``glide`` in ``ramp_time`` seconds from ``t_start``.

    Actuator limits: the law does not saturate its commands; it is run through the actuated model
    (:class:`~glidectl.ActuatedGlider` in :func:`~glidectl.sim.simulate_actuated`), whose servo and rate/range
    limiter keep the actuators inside the vehicle's ``[actuators]`` table.

    Attributes
    ----------
    K : ndarray, shape (3, 11)
        Gain (rows ``w1, w3, w4``; zero columns for ``x``, ``z`` and for the states of fixed actuators; zero rows
        for fixed actuators). SI units.
    x_from, x_to : ndarray, shape (11,)
        Reference at the start and at the end of the transition (acceleration-form states; ``x``, ``z`` unused).
    t_start, ramp_time : float
        Start (s) and duration (s) of the transition.
    glide : SteadyGlide
        The leg's glide.
    closed_loop_poles : ndarray
        Eigenvalues (1/s) of the restricted linear closed loop the gain was designed on.
    state_names, input_names : tuple of str
        States and inputs of that restricted design.
    command : str
        ``"acceleration"`` (read by :func:`~glidectl.sim.simulate_actuated`).

    Raises
    ------
    ArgumentError
        If the arrays do not have the shapes above or are not finite, or ``ramp_time < 0``.
    """

    K: np.ndarray
    x_from: np.ndarray
    x_to: np.ndarray
    t_start: float
    ramp_time: float
    glide: SteadyGlide = field(repr=False)
    closed_loop_poles: np.ndarray = field(repr=False)
    state_names: tuple[str, ...] = ()
    input_names: tuple[str, ...] = ()
    command: str = "acceleration"

    def __post_init__(self) -> None:
        object.__setattr__(self, "K", checks.array("K", self.K, shape=(3, 11)))
        object.__setattr__(self, "x_from", checks.array("x_from", self.x_from, shape=(11,)))
        object.__setattr__(self, "x_to", checks.array("x_to", self.x_to, shape=(11,)))
        object.__setattr__(self, "t_start", checks.real("t_start", self.t_start, unit="s"))
        object.__setattr__(self, "ramp_time", checks.nonnegative("ramp_time", self.ramp_time, unit="s"))

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Reference state (11,) and feedforward ``(w1, w3, w4)`` at time ``t`` (s): the ramp moves the positions
        at constant rates (velocity entries ``rdot_P1``, ``rdot_P3`` and pump rate ``w4`` follow)."""
        return _ramp_reference(t, self.x_from, self.x_to, self.t_start, self.ramp_time)

    def __call__(self, t: float, y: Any) -> np.ndarray:
        """``(w1, w3, w4)`` for the measured full state ``y`` (shape (11,)) at time ``t`` (s)."""
        x_ref, w_ff = self.reference(t)
        return w_ff - self.K @ (np.asarray(y, dtype=float) - x_ref)


def _check_lqg_leg(leg: Any, d: LQGController, K_design: Any, filter_gain: Any) -> None:
    """The checks and matrices the LQG leg controllers (:class:`ScheduledGlideLQG`, :class:`SampledGlideLQG`)
    share: a design on the acceleration inputs and on the plant's vehicle, the references and initial estimate,
    sensors that are states; sets ``leg._mats = (K, G, C, sensor positions)``: the gain on the 11 states, the filter
    gain ``filter_gain`` (continuous ``L`` or sampled ``M``) placed on the estimated states, the sensor matrix."""
    if d.inputs != "acceleration":
        raise ArgumentError("a dive-cycle LQG leg commands the thesis accelerations (w1, w3, w4): design it with "
                            "inputs='acceleration'")
    checks.same_vehicle("design", d, leg.plant.vehicle)
    object.__setattr__(leg, "x_from", checks.array("x_from", leg.x_from, shape=(11,)))
    object.__setattr__(leg, "x_to", checks.array("x_to", leg.x_to, shape=(11,)))
    object.__setattr__(leg, "t_start", checks.real("t_start", leg.t_start, unit="s"))
    object.__setattr__(leg, "ramp_time", checks.nonnegative("ramp_time", leg.ramp_time, unit="s"))
    if leg.xhat0 is not None:
        object.__setattr__(leg, "xhat0", checks.array("xhat0", leg.xhat0, shape=(11,)))
    smap = d.sensors
    bad = [c for c in smap.channels if c not in ACCEL_STATES]
    if bad:
        raise ArgumentError(f"the LQG sensors use channels {bad}, which are not states of the actuated glider: a "
                            "dive cycle measures states")
    if len(leg.sensor_index) != len(smap.names):
        raise ArgumentError(f"sensor_index must give the position of each of {list(smap.names)} among the "
                            "measurements")
    K = _accel_gain(K_design, d.state_names, d.plant.input_labels)
    G = np.zeros((11, len(smap.names)))
    for r, sname in enumerate(d.estimated_states):
        G[ACCEL_STATES.index(sname)] = np.asarray(filter_gain)[r]
    C = np.zeros((len(smap.names), 11))
    for k, ch in enumerate(smap.channels):
        C[:, ACCEL_STATES.index(ch)] += smap.M[:, k]
    object.__setattr__(leg, "_mats", (K, G, C, np.array(leg.sensor_index, dtype=int)))


@dataclass(frozen=True, eq=False)
class ScheduledGlideLQG:
    """Continuous-time LQG leg controller of a dive cycle: the regulator and Kalman gains of
    :func:`~glidectl.lqg_glide` at the leg's glide, on an estimate of the acceleration-form state, with the reference
    ramp of :class:`ScheduledGlideLQR`. (``controller="lqg"`` flies its sampled-data version,
    :class:`SampledGlideLQG`; this one is for controller objects and analog studies.)

    ``w = w_ff(t) - K (xhat - x_ref(t))`` (``K`` of the design on the regulated states, zero columns elsewhere) and
    ``xhat' = f(xhat, w) + L (y - C xhat)``: the prediction ``f`` is the right-hand side of the actuated glider
    (:meth:`~glidectl.ActuatedGlider.rhs`, with the same rate/range limiter as the plant, so the estimate follows
    the inflection transitions and saturations that the leg's linearization does not describe); the correction is
    the design's stationary Kalman gain ``L`` (:func:`control.lqe` on the linearization at the glide) on the
    estimated states (the others, horizontal position ``x`` and the held actuators, are predicted only). The
    controller sees only the measured sensors (noisy when noise is simulated); its state, the estimate
    (``<state>_hat``), is integrated with the plant by :func:`~glidectl.sim.simulate_actuated`. Commands are the
    thesis accelerations (``command = "acceleration"``); the actuated glider's servo and limiter realize them, so
    the actuator limits hold (the controller itself does not saturate).

    Attributes
    ----------
    design : LQGController
        The leg's design (gains, poles, sensors, noise).
    plant : ActuatedGlider
        The actuated model of the prediction.
    x_from, x_to : ndarray, shape (11,)
        Reference at the start and the end of the transition.
    t_start, ramp_time : float
        Start (s) and duration (s) of the transition.
    sensor_index : tuple of int
        Positions of the design's sensor channels among the measurements ``y`` the controller receives.
    xhat0 : ndarray, shape (11,), optional
        Initial estimate (default: ``x_from`` with the measured states replaced by their measurements).

    Raises
    ------
    ArgumentTypeError
        If ``design`` is not an :class:`~glidectl.LQGController` or ``plant`` not an ActuatedGlider.
    ArgumentError
        If the design is not on the acceleration inputs, a sensor is not a plain state, or an array has the wrong
        shape.
    VehicleMismatchError
        If the design is for another vehicle than the plant.
    """

    design: LQGController
    plant: ActuatedGlider = field(repr=False)
    x_from: np.ndarray = field(repr=False)
    x_to: np.ndarray = field(repr=False)
    t_start: float = 0.0
    ramp_time: float = 0.0
    sensor_index: tuple[int, ...] = ()
    xhat0: np.ndarray | None = field(default=None, repr=False)

    command = "acceleration"
    controller_states = tuple(f"{s}_hat" for s in ACCEL_STATES)

    def __post_init__(self) -> None:
        require_instance("design", self.design, LQGController, " (from gc.lqg_glide)")
        require_instance("plant", self.plant, ActuatedGlider)
        _check_lqg_leg(self, self.design, self.design.K, self.design.L)

    @property
    def glide(self) -> SteadyGlide:
        """The leg's glide."""
        return self.design.glide

    def with_estimate(self, xhat: Any) -> ScheduledGlideLQG:
        """The same leg controller starting from the estimate ``xhat`` (shape (11,); the previous leg's last).

        Returns
        -------
        ScheduledGlideLQG

        Raises
        ------
        ArgumentError
            If ``xhat`` is not 11 finite numbers.
        """
        return ScheduledGlideLQG(self.design, self.plant, self.x_from, self.x_to, self.t_start, self.ramp_time,
                                 self.sensor_index, checks.array("xhat", xhat, shape=(11,)))

    def initial_state(self, t: float, y: Any) -> np.ndarray:
        """Initial estimate (:attr:`xhat0`, or ``x_from`` corrected by the measurements)."""
        if self.xhat0 is not None:
            return self.xhat0.copy()
        _, _, C, idx = self._mats
        xh = self.x_from.copy()
        ym = np.asarray(y, dtype=float)[idx]
        for r in range(C.shape[0]):
            nz = np.flatnonzero(C[r])
            if nz.size == 1:  # a plain state sensor: start from its measurement
                xh[nz[0]] = ym[r] / C[r, nz[0]]
        return xh

    def _w(self, t: float, xhat: np.ndarray) -> np.ndarray:
        x_ref, w_ff = _ramp_reference(t, self.x_from, self.x_to, self.t_start, self.ramp_time)
        return w_ff - self._mats[0] @ (xhat - x_ref)

    def derivative(self, t: float, xc: Any, y: Any) -> np.ndarray:
        """Estimator: ``f(xhat, w) + L (y - C xhat)`` (per second)."""
        _, Lg, C, idx = self._mats
        xh = np.asarray(xc, dtype=float)
        w = self._w(t, xh)
        pred = self.plant.rhs(xh, self.plant.acceleration_rates(xh, w))
        return pred + Lg @ (np.asarray(y, dtype=float)[idx] - C @ xh)

    def __call__(self, t: float, y: Any, xc: Any) -> np.ndarray:
        """``(w1, w3, w4)`` from the estimate ``xc`` at time ``t`` (s)."""
        return self._w(t, np.asarray(xc, dtype=float))


@dataclass(frozen=True, eq=False)
class SampledGlideLQG:
    """Sampled-data LQG leg controller of a dive cycle (the ``"lqg"`` controller): the digital version
    (:class:`~glidectl.SampledLQG`) of :func:`~glidectl.lqg_glide` at the leg's glide, run every ``period`` seconds
    as a glider's flight computer runs it, with the reference ramp of :class:`ScheduledGlideLQR`.

    At each sample ``t_k`` (:func:`~glidectl.sim.simulate_actuated` calls :meth:`sample`) the sensors are read and
    the predicted estimate is corrected, ``xhat_k = xhat_k^- + M (y_k - C xhat_k^-)`` (``M`` the measurement-update
    gain of the estimated states); the command ``w_k = w_ff,k - K (xhat_k - x_ref(t_k))`` is computed and held until
    the next sample (zero-order hold; the controller does not saturate it: the actuated glider's limiter does, in
    the plant and in the prediction). ``w_ff,k`` is the
    reference's pump rate averaged over the period, so that the reference's actuator positions are met at the next
    sample. Between samples the estimate is predicted with the actuated glider under the held command,
    ``xhat' = f(xhat, w_k)`` (:meth:`~glidectl.ActuatedGlider.rhs`, with the plant's rate/range limiter): the
    inflection transitions, far from the leg's glide, are predicted by the model and not by the leg's linearization
    (a linear prediction about the new leg's glide, whose pitch and buoyancy have the other sign, makes the estimate
    diverge there); and the estimate is the prediction to any time, so an inflection between samples starts the next
    leg from the right estimate. The states that are not estimated (horizontal position ``x``, a fixed actuator) are
    predicted only. The command is the thesis acceleration ``(w1, w3, w4)`` (``command = "acceleration"``),
    realized by the actuated glider's servo and limiter.

    Attributes
    ----------
    design : SampledLQG
        The leg's sampled-data design (gains, period, the continuous design it samples).
    plant : ActuatedGlider
        The actuated glider of the prediction.
    x_from, x_to : ndarray, shape (11,)
        Reference at the start and the end of the transition.
    t_start, ramp_time : float
        Start (s) and duration (s) of the transition.
    sensor_index : tuple of int
        Positions of the design's sensor channels among the measurements ``y`` the controller receives.
    xhat0 : ndarray, shape (11,), optional
        Initial (predicted) estimate, corrected at the first sample (default: ``x_from`` with the measured states
        replaced by their measurements).

    Raises
    ------
    ArgumentTypeError
        If ``design`` is not a :class:`~glidectl.SampledLQG` or ``plant`` not an ActuatedGlider.
    ArgumentError
        If the design is not on the acceleration inputs, a sensor is not a plain state, or an array has the wrong
        shape.
    VehicleMismatchError
        If the design is for another vehicle than the plant.
    """

    design: SampledLQG
    plant: ActuatedGlider = field(repr=False)
    x_from: np.ndarray = field(repr=False)
    x_to: np.ndarray = field(repr=False)
    t_start: float = 0.0
    ramp_time: float = 0.0
    sensor_index: tuple[int, ...] = ()
    xhat0: np.ndarray | None = field(default=None, repr=False)

    command = "acceleration"
    #: The estimate (``<state>_hat``) and the held command (``<input>_held``).
    controller_states = (*(f"{s}_hat" for s in ACCEL_STATES), "w1_held", "w3_held", "w4_held")

    def __post_init__(self) -> None:
        require_instance("design", self.design, SampledLQG, " (from gc.lqg_glide(...).sampled(period))")
        require_instance("plant", self.plant, ActuatedGlider)
        _check_lqg_leg(self, self.design.design, self.design.K, self.design.M)

    @property
    def glide(self) -> SteadyGlide:
        """The leg's glide."""
        return self.design.design.glide

    @property
    def period(self) -> float:
        """Sample period (s)."""
        return self.design.period

    def with_estimate(self, xc: Any) -> SampledGlideLQG:
        """The same leg controller starting from the estimate of ``xc`` (the previous leg's last controller state,
        shape (14,), or an estimate, shape (11,)).

        Returns
        -------
        SampledGlideLQG

        Raises
        ------
        ArgumentError
            If ``xc`` is not 14 or 11 finite numbers.
        """
        xc = checks.array("xc", xc, ndim=1)
        if xc.size not in (11, 14):
            raise ArgumentError(f"xc must be the 14 controller states {self.controller_states} or the 11 estimated "
                                f"states, got {xc.size} numbers")
        return SampledGlideLQG(self.design, self.plant, self.x_from, self.x_to, self.t_start, self.ramp_time,
                               self.sensor_index, xc[:11])

    def initial_state(self, t: float, y: Any) -> np.ndarray:
        """Predicted estimate at the start (:attr:`xhat0`, or ``x_from`` with the measured states replaced by their
        measurements) and a zero held command (the first :meth:`sample` sets it)."""
        if self.xhat0 is not None:
            xh = self.xhat0.copy()
        else:
            C, idx = self._mats[2], self._mats[3]
            xh = self.x_from.copy()
            ym = np.asarray(y, dtype=float)[idx]
            for r in range(C.shape[0]):
                nz = np.flatnonzero(C[r])
                if nz.size == 1:  # a plain state sensor: start from its measurement
                    xh[nz[0]] = ym[r] / C[r, nz[0]]
        return np.concatenate([xh, np.zeros(3)])

    def command_at(self, t: float, xhat: Any) -> np.ndarray:
        """Command ``(w1, w3, w4)`` (m/s^2, m/s^2, kg/s) computed at a sample at time ``t`` (s) from the corrected
        estimate ``xhat``."""
        T = self.design.period
        x_ref, _ = _ramp_reference(t, self.x_from, self.x_to, self.t_start, self.ramp_time)
        s0, _ = _ramp(t, self.t_start, self.ramp_time)
        s1, _ = _ramp(t + T, self.t_start, self.ramp_time)
        w_ff = np.array([0.0, 0.0, (s1 - s0) / T * (self.x_to[10] - self.x_from[10])])
        return w_ff - self._mats[0] @ (np.asarray(xhat, dtype=float) - x_ref)

    def sample(self, t: float, xc: Any, y: Any) -> np.ndarray:
        """Sample at time ``t`` (s): the corrected estimate and the new held command (the controller state after
        the sample, shape (14,))."""
        Mg, C, idx = self._mats[1], self._mats[2], self._mats[3]
        xc = np.asarray(xc, dtype=float)
        xh = xc[:11] + Mg @ (np.asarray(y, dtype=float)[idx] - C @ xc[:11])
        return np.concatenate([xh, self.command_at(t, xh)])

    def derivative(self, t: float, xc: Any, y: Any) -> np.ndarray:
        """Between samples: the prediction ``f(xhat, w_held)`` of the actuated glider; the held command is constant
        (per second)."""
        xc = np.asarray(xc, dtype=float)
        xh, w = xc[:11], xc[11:]
        return np.concatenate([self.plant.rhs(xh, self.plant.acceleration_rates(xh, w)), np.zeros(3)])

    def __call__(self, t: float, y: Any, xc: Any) -> np.ndarray:
        """The held command ``(w1, w3, w4)``."""
        return np.asarray(xc, dtype=float)[11:14]


@dataclass(frozen=True)
class PitchPID:
    """Operational baseline: PID on the pitch angle through the battery position, pump to a fixed setpoint.

    ``r_P1c = r_ff(t) - kp e - ki I + kd Omega2_meas`` with ``e = theta_ref(t) - theta_meas`` and ``I' = e``
    (conditional integration: ``I`` is frozen while ``r_P1c`` is at an end of the battery travel and ``e`` would
    drive it further), and ``m0c = m0_setpoint``. With positive gains the battery goes forward (nose-down gravity
    torque ``-mbar g r_P1 cos(theta)`` of (2.20)) when the nose is too high: right for a bottom-heavy, statically
    stable hull; a hull whose pitch response to the battery reverses (Munk moment larger than the pendulum and
    hydrodynamic stiffness) needs negative gains, which :func:`tune_pitch_pid` finds. The pitch reference and the
    feedforward move from their previous values to the leg's in ``ramp_time`` seconds from ``t_start``.

    Actuator limits: the commands are position setpoints; the actuated model's servo loops clip them to the ranges
    and its limiter enforces the rates (:class:`~glidectl.ActuatedGlider`), and the integrator is frozen while the
    battery command is beyond its travel (``r_p1_bounds``).

    Attributes
    ----------
    theta_from, theta_to : float
        Pitch reference before and after the transition (rad).
    r_p1_from, r_p1_to : float
        Battery feedforward before and after the transition (m).
    m0_setpoint : float
        Pump setpoint (kg).
    t_start, ramp_time : float
        Transition start and duration (s).
    kp, ki, kd : float
        Gains (m/rad, m/(rad s), m s/rad), signed (see above).
    theta_index, omega_index : int
        Positions of ``theta`` and ``Omega2`` among the sensors.
    r_p1_bounds : (float, float)
        Battery travel (m), for the anti-windup.

    Raises
    ------
    ArgumentError
        If a number is not finite or ``ramp_time < 0``.
    """

    theta_from: float
    theta_to: float
    r_p1_from: float
    r_p1_to: float
    m0_setpoint: float
    t_start: float
    ramp_time: float
    kp: float = 0.1
    ki: float = 0.01
    kd: float = 0.2
    theta_index: int = 2
    omega_index: int = 3
    r_p1_bounds: tuple[float, float] = (-math.inf, math.inf)

    controller_states = ("pitch_error_integral",)
    command = "setpoint"

    def __post_init__(self) -> None:
        for k in ("theta_from", "theta_to", "r_p1_from", "r_p1_to", "m0_setpoint", "t_start"):
            object.__setattr__(self, k, checks.real(k, getattr(self, k)))
        object.__setattr__(self, "ramp_time", checks.nonnegative("ramp_time", self.ramp_time, unit="s"))
        for k in ("kp", "ki", "kd"):
            object.__setattr__(self, k, checks.real(k, getattr(self, k)))

    def _refs(self, t: float) -> tuple[float, float]:
        s, _ = _ramp(t, self.t_start, self.ramp_time)
        return (self.theta_from + s * (self.theta_to - self.theta_from),
                self.r_p1_from + s * (self.r_p1_to - self.r_p1_from))

    def _r_cmd(self, t: float, y: np.ndarray, integral: float) -> tuple[float, float]:
        th_ref, r_ff = self._refs(t)
        e = th_ref - float(y[self.theta_index])
        return r_ff - self.kp * e - self.ki * integral + self.kd * float(y[self.omega_index]), e

    def initial_state(self, t: float, y: Any) -> np.ndarray:
        """Integrator state at the start (0)."""
        return np.zeros(1)

    def derivative(self, t: float, xc: Any, y: Any) -> np.ndarray:
        """``I' = e``, frozen while the command is at an end of the travel and ``e`` pushes it further out."""
        r, e = self._r_cmd(t, np.asarray(y), float(xc[0]))
        lo, hi = self.r_p1_bounds
        if (r >= hi and -self.ki * e > 0) or (r <= lo and -self.ki * e < 0):
            return np.zeros(1)
        return np.array([e])

    def __call__(self, t: float, y: Any, xc: Any) -> dict[str, float]:
        """Setpoints ``{"r_P1": m, "m0": kg}`` at time ``t`` (s) for measurements ``y`` and integrator ``xc``."""
        r, _ = self._r_cmd(t, np.asarray(y), float(xc[0]))
        return {"r_P1": r, "m0": self.m0_setpoint}


@dataclass(frozen=True)
class _NonlinearLeg:
    """Chapter-6 leg: battery setpoint from the torque law (6.5) (MovingMassTorque), pump by (6.9)."""

    mass: Any
    m0e: float
    rate_gain: float
    pump_gain: float
    command = "setpoint"

    def __call__(self, t: float, y: Any) -> dict[str, float]:
        y = np.asarray(y, dtype=float)
        m0 = float(y[10])
        # (6.9): dm0/dt = -(K_b/tau_s)(m0 - m0e), as a setpoint of the pump servo of gain pump_gain
        c = m0 + (self.rate_gain / self.pump_gain) * (self.m0e - m0)
        return {"r_P1": float(self.mass.r_p1_command(y)), "m0": c}


#: Gains searched by :func:`tune_pitch_pid`: ``kp`` (m/rad, both signs), ``kd`` (m s/rad), integral time (s).
PID_KP_GRID = (0.005, 0.01, 0.02, 0.05, 0.1, 0.2)
PID_KD_GRID = (0.0, 0.02, 0.05, 0.1, 0.2, 0.5)
PID_INTEGRAL_TIME = 20.0


def tune_pitch_pid(plant: ActuatedGlider, glide: SteadyGlide) -> tuple[float, float, float, float]:
    """PID gains ``(kp, ki, kd)`` of :class:`PitchPID` for a glide: the pair ``(kp, kd)`` of
    :data:`PID_KP_GRID` (either sign) x :data:`PID_KD_GRID` (sign of ``kp``) with ``ki = kp / PID_INTEGRAL_TIME``
    whose linearized closed loop (exact Jacobians of :meth:`ActuatedGlider.rhs` at the glide, servo loops
    included, limits inactive) has the largest stability margin (most negative largest real part).

    Parameters
    ----------
    plant : ActuatedGlider
    glide : SteadyGlide
        Glide flown (its ``m0`` and ``r_p1`` are the pump setpoint and the battery feedforward).

    Returns
    -------
    (kp, ki, kd, max_real) : tuple of float
        Gains (m/rad, m/(rad s), m s/rad) and the largest real part of the closed-loop eigenvalues (1/s; negative:
        locally stable).

    Raises
    ------
    ArgumentTypeError
        If ``plant`` is not an ActuatedGlider or ``glide`` not a SteadyGlide.
    VehicleMismatchError
        If the glide was trimmed for another vehicle.
    ModelError
        If the right-hand side is not finite at the glide.

    Examples
    --------
    >>> import math
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("slocum_shallow")
    >>> glide = gc.steady_glide(veh, 0.35, math.radians(-25), r_p3=veh.actuators["r_P3"].fixed)
    >>> kp, ki, kd, max_real = gc.tune_pitch_pid(gc.ActuatedGlider(veh), glide)
    >>> print(kp, ki, kd, max_real < 0)
    0.2 0.01 0.5 True
    """
    require_instance("plant", plant, ActuatedGlider)
    require_instance("glide", glide, SteadyGlide, " (from gc.steady_glide)")
    checks.same_vehicle("glide", glide, plant.vehicle)
    xe = glide.accel_state()
    A, B = jacobians(plant.rhs, xe, np.zeros(3))
    k = plant.gain
    # u = k * (c - p): c_r1 = r_ff + kp theta - ki I + kd Omega2 (deviations; e = -theta), c_r3, c_m0 fixed
    G = np.zeros((3, 11))
    G[0, 6] -= k[0]
    G[1, 8] -= k[1]
    G[2, 10] -= k[2]
    keep = [*range(2, 11), 11]  # drop x, z (no feedback, zero eigenvalues)
    best = None
    for sign in (1.0, -1.0):
        for kp0 in PID_KP_GRID:
            for kd0 in PID_KD_GRID:
                kp, kd = sign * kp0, sign * kd0
                ki = kp / PID_INTEGRAL_TIME
                Acl = np.zeros((12, 12))
                Gk = G.copy()
                Gk[0, 2] += k[0] * kp
                Gk[0, 3] += k[0] * kd
                Acl[:11, :11] = A + B @ Gk
                Acl[:11, 11] = B[:, 0] * (-k[0] * ki)
                Acl[11, 2] = -1.0
                ev = np.linalg.eigvals(Acl[np.ix_(keep, keep)])
                margin = float(np.max(ev.real))
                if best is None or margin < best[3] - 1e-12:
                    best = (kp, ki, kd, margin)
    return best  # type: ignore[return-value]


# ------------------------------------------------------------------------------------------------ results
@dataclass(frozen=True)
class CycleMetrics:
    """One dive cycle: top inflection, down leg, bottom inflection, up leg, next top inflection.

    Attributes
    ----------
    index : int
        Cycle number (0-based).
    t_start, t_end : float
        Times of the opening and closing top inflections (s).
    distance : float
        Horizontal distance covered (m).
    duration : float
        ``t_end - t_start`` (s).
    overshoot : tuple of float
        Depth beyond the limit after the bottom inflection and after the closing top inflection (m, >= 0).
    saturated_time : float
        Time during which some actuator is at a limit (s).
    energy : float
        Pump energy (J), :func:`pump_energy`.
    """

    index: int
    t_start: float
    t_end: float
    distance: float
    duration: float
    overshoot: tuple[float, float]
    saturated_time: float
    energy: float

    @property
    def max_overshoot(self) -> float:
        """Largest of the two overshoots (m)."""
        return max(self.overshoot)


def _cycle_metrics(t: np.ndarray, xpos: np.ndarray, depth: np.ndarray, m0_rate: np.ndarray, saturated: np.ndarray,
                   switch_times: Sequence[float], depths: tuple[float, float], *, efficiency: float, rho: float,
                   p_atm: float, g: float, pump_work: str) -> tuple[CycleMetrics, ...]:
    """Metrics of each cycle from sampled arrays; ``switch_times = (top_0, bottom_0, top_1, bottom_1, ...)``."""
    top, bottom = depths
    out = []
    sw = list(switch_times)
    for k in range((len(sw) - 1) // 2):
        t0, tb, t1 = sw[2 * k], sw[2 * k + 1], sw[2 * k + 2]
        t_next = sw[2 * k + 3] if 2 * k + 3 < len(sw) else t[-1]
        cyc = (t >= t0) & (t <= t1)
        up = (t >= tb) & (t <= t1)
        after = (t >= t1) & (t <= t_next)
        ob = max(0.0, float(np.max(depth[up])) - bottom) if np.any(up) else 0.0
        ot = max(0.0, top - float(np.min(depth[after]))) if np.any(after) else 0.0
        tc = t[cyc]
        sat = float(np.sum(0.5 * (saturated[cyc][1:] + saturated[cyc][:-1]) * np.diff(tc))) if tc.size > 1 else 0.0
        e = pump_energy(tc, depth[cyc], m0_rate[cyc], efficiency=efficiency, rho=rho, p_atm=p_atm, g=g,
                        pump_work=pump_work) if tc.size else 0.0
        x0 = float(np.interp(t0, t, xpos))
        x1 = float(np.interp(t1, t, xpos))
        out.append(CycleMetrics(k, float(t0), float(t1), x1 - x0, float(t1 - t0), (ob, ot), sat, e))
    return tuple(out)


@dataclass(frozen=True)
class DiveCycleRun:
    """A simulated dive-cycle mission (:func:`dive_cycle`).

    Attributes
    ----------
    controller : str
        Controller name (``"lqr"``, ``"pid"``, ...) or the class name of a controller object.
    t : ndarray, shape (N,)
        Times (s).
    x : ndarray, shape (N, 11)
        States ``state_names`` (acceleration form, SI units).
    state_names : tuple of str
    u : ndarray, shape (N, 3)
        Requested actuator rates (m/s, m/s, kg/s).
    rates : ndarray, shape (N, 3)
        Limited rates the actuators were driven with.
    commanded : ndarray, shape (N, 3)
        Position commands (m, m, kg).
    saturated : ndarray of bool, shape (N,)
        Some actuator at a limit.
    actuator_names : tuple of str
    lower, upper, rate_limit : ndarray, shape (3,)
        Actuator limits.
    switch_times : tuple of float
        Inflections (s): top, bottom, top, ... (the first at ``t = 0``).
    switch_depths : tuple of float
        True depth at each inflection (m); the switch happens on the measured depth.
    cycles : tuple of CycleMetrics
    depths : (float, float)
        Depth limits (m).
    gamma, speed : float
        Glide-path angle magnitude (rad) and speed (m/s) of the legs.
    glides : tuple of SteadyGlide
        Down and up glides.
    pump_efficiency : float
    efficiency_source : str
        Where ``pump_efficiency`` comes from.
    rho, p_atm : float
        Density (kg/m^3) and surface pressure (Pa) of the energy.
    pump_work : str
        ``"out"`` or ``"both"``.
    sensors : tuple of str
    seed : int or None
        Noise seed (None without noise).
    nfev : int
        Right-hand-side evaluations.
    vehicle : Vehicle
    provenance : str
    """

    controller: str
    t: np.ndarray
    x: np.ndarray
    state_names: tuple[str, ...]
    u: np.ndarray
    rates: np.ndarray
    commanded: np.ndarray
    saturated: np.ndarray
    actuator_names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    rate_limit: np.ndarray
    switch_times: tuple[float, ...]
    switch_depths: tuple[float, ...]
    cycles: tuple[CycleMetrics, ...]
    depths: tuple[float, float]
    gamma: float
    speed: float
    glides: tuple[SteadyGlide, ...] = field(repr=False)
    pump_efficiency: float
    efficiency_source: str
    rho: float
    p_atm: float
    pump_work: str
    sensors: tuple[str, ...]
    seed: int | None
    nfev: int
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    @property
    def depth(self) -> np.ndarray:
        """Depth ``z`` (m, positive down), shape (N,)."""
        return self.x[:, _IZ]

    def state(self, name: str) -> np.ndarray:
        """Time history of a state.

        Parameters
        ----------
        name : str
            A name of ``state_names``.

        Returns
        -------
        ndarray, shape (N,)

        Raises
        ------
        ArgumentError
            If there is no such state.
        """
        if name not in self.state_names:
            raise ArgumentError(f"no state {name!r}; have {self.state_names}")
        return self.x[:, self.state_names.index(name)]

    def actuator(self, name: str, *, commanded: bool = False, rate: bool = False) -> np.ndarray:
        """Trajectory of one actuator (as :meth:`glidectl.sim.ActuatedSimulation.actuator`).

        Parameters
        ----------
        name : str
            ``"m0"`` (kg), ``"r_P1"`` or ``"r_P3"`` (m).
        commanded : bool
            Commanded instead of achieved.
        rate : bool
            Rates (unit/s) instead of positions.

        Returns
        -------
        ndarray, shape (N,)

        Raises
        ------
        ArgumentTypeError
            If ``name`` is not a string or a flag not a bool.
        ArgumentError
            If ``name`` is not an actuator.
        """
        return actuator_trace(self, name, commanded=commanded, rate=rate)

    def as_dict(self) -> dict[str, Any]:
        """Comparison row: per-cycle means of distance (m), duration (s), saturated time (s) and energy (J), and the
        largest overshoot (m) (:func:`cycle_summary`).

        Returns
        -------
        dict
        """
        return {"controller": self.controller, "cycles": len(self.cycles), **cycle_summary(self.cycles)}

    def summary(self) -> str:
        """A few lines: mission, controller and per-cycle metrics.

        Returns
        -------
        str
        """
        lines = [f"dive cycles of '{self.vehicle.name}' between {self.depths[0]:g} and {self.depths[1]:g} m, "
                 f"gamma = +-{math.degrees(self.gamma):.3g} deg, {self.speed:g} m/s, controller {self.controller}"]
        for k in self.cycles:
            lines.append(f"  cycle {k.index}: {k.distance:.1f} m in {k.duration:.0f} s, overshoot "
                         f"{k.overshoot[0]:.2f} / {k.overshoot[1]:.2f} m, saturated {k.saturated_time:.0f} s, "
                         f"pump {k.energy:.0f} J")
        return "\n".join(lines)

    def plot(self, ax: Any = None) -> Any:
        """Depth with the limits and inflections, pitch, and commanded versus achieved pump and battery.

        Parameters
        ----------
        ax : array of 4 axes, optional
            Default a new figure.

        Returns
        -------
        ndarray of 4 matplotlib.axes.Axes
            Depth, pitch, pump mass and battery position (``axes[0].figure`` is the figure).

        Raises
        ------
        GlidectlError
            If ``ax`` is not 4 axes.
        """
        from ..plotting import plot_dive_cycle, style

        with style():
            return plot_dive_cycle(self, ax)


@dataclass(frozen=True)
class MissionComparison:
    """Controllers flown on the same dive-cycle mission (:func:`compare_missions`).

    Attributes
    ----------
    rows : tuple of dict
        One :meth:`DiveCycleRun.as_dict` row per controller that flew; a controller that could not fly has a row
        with its ``error`` message and NaN metrics.
    runs : dict of str to DiveCycleRun
        The runs, by controller name.
    vehicle : Vehicle
    provenance : str
    """

    rows: tuple[dict[str, Any], ...]
    runs: dict[str, DiveCycleRun] = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    def table(self) -> str:
        """Markdown table: controller, distance/cycle (m), duration/cycle (s), max overshoot (m), saturated
        time/cycle (s), energy/cycle (J), note.

        Returns
        -------
        str
        """
        head = ("| controller | distance/cycle [m] | duration/cycle [s] | max overshoot [m] | saturated/cycle [s] "
                "| energy/cycle [J] | note |\n| --- | ---: | ---: | ---: | ---: | ---: | --- |")
        lines = [head]
        for r in self.rows:
            if r.get("error"):
                lines.append(f"| {r['controller']} | - | - | - | - | - | {r['error']} |")
            else:
                lines.append(f"| {r['controller']} | {r['distance_per_cycle']:.1f} | {r['duration_per_cycle']:.0f} "
                             f"| {r['max_overshoot']:.2f} | {r['saturated_time_per_cycle']:.0f} "
                             f"| {r['energy_per_cycle']:.1f} | |")
        return "\n".join(lines)

    def summary(self) -> str:
        """The table (:meth:`table`).

        Returns
        -------
        str
        """
        return self.table()


# ------------------------------------------------------------------------------------------------ designs per leg
def _lqr_gain(veh: Vehicle, plant: ActuatedGlider, glide: SteadyGlide,
              max_deviation: Mapping[str, float] | None) -> tuple[np.ndarray, np.ndarray, tuple, tuple]:
    """LQR on the glide's acceleration-form linearization restricted to the actuated inputs (the vehicle file's
    default, :func:`~glidectl.controllers.linear.default_actuate`) and to the states other than ``z'``: the
    regulator of :func:`~glidectl.lqg_glide` without sensors (the same weights, the same
    :func:`~glidectl.controllers.linear.lqr_subset`). Not :func:`~glidectl.lqr_glide`, which also regulates the
    glide-path deviation ``z'``: a dive cycle holds the glide, not a path through the origin."""
    sys = linearize_glide(veh, glide, "acceleration")
    A, B = np.asarray(sys.A), np.asarray(sys.B)
    snames, inames = list(sys.state_labels), list(sys.input_labels)
    act, ui, si, _ = actuated_subset(sys, veh, "acceleration", None)
    si = [i for i in si if snames[i] != "z_prime"]
    extra = dict(max_deviation or {})
    known = set(snames) | set(inames) | set(ACCEL_STATES[2:]) | set(ACCEL_INPUTS)
    unknown = sorted(str(k) for k in extra if k not in known)
    if unknown:
        raise ArgumentError(f"max_deviation names {unknown}, which are not states or inputs of the leg design; "
                            f"known: {sorted(known)}")
    dev = {**DEFAULT_MAX_DEVIATION, **{k: checks.positive(f"max_deviation[{k!r}]", v) for k, v in extra.items()}}
    K10, _ = lqr_subset(A, B, bryson_weights(snames, dev), bryson_weights(inames, dev), ui, si,
                        f"the {math.degrees(glide.gamma):+.1f} deg leg of vehicle '{veh.name}' with inputs "
                        f"{list(act)}")
    E = np.linalg.eigvals((A - B @ K10)[np.ix_(si, si)])
    return _accel_gain(K10, snames, inames), E, tuple(snames[i] for i in si), act


#: The reference of a transition moves the actuators at this fraction of their rate limits (headroom for feedback).
RAMP_RATE_FRACTION = 0.8


def _ramp_time(plant: ActuatedGlider, x_from: np.ndarray, x_to: np.ndarray) -> float:
    dp = np.abs(plant.positions(x_to) - plant.positions(x_from))
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(plant.rate_limit > 0, dp / (RAMP_RATE_FRACTION * plant.rate_limit), 0.0)
    return float(np.max(np.where(np.isfinite(t), t, 0.0)))


def _nonlinear_designs(veh: Vehicle, plant: ActuatedGlider, gamma: float, speed: float, r_p3: float) -> tuple:
    """(6.5) + (6.9) designs for the down and up legs, or ModelError naming why the chapter-6 controller does not
    apply."""
    from .buoyancy import buoyancy_equilibrium
    from .moving_mass import MovingMassTorque
    from .torque import design_torque_control

    legs = []
    try:
        for sign in (-1.0, 1.0):
            # the chapter-5 analysis is about the nominal m0: the leg's glide-family value (its sign sets the leg)
            vl = veh.with_overrides(m0=steady_glide(veh, speed, sign * gamma, r_p3=r_p3).m0)
            design = design_torque_control(vl, gamma=sign * gamma)
            eq = buoyancy_equilibrium(design.law.closed_loop_vehicle(veh), speed, descending=sign < 0)
            legs.append(_NonlinearLeg(MovingMassTorque(veh, design.law, r_p3=r_p3), eq.m0e,
                                      1.0 / eq.tau_s, plant.pump_gain))
    except GlidectlError as exc:
        raise ModelError(f"controller='nonlinear' (the chapter-6 steady-glide controller: torque law (6.5) through "
                         f"the moving mass and buoyancy law (6.9)) does not apply to vehicle '{veh.name}': {exc}") \
            from exc
    return tuple(legs)


# ------------------------------------------------------------------------------------------------ mission
def _check_depths(depths: Any) -> tuple[float, float]:
    if isinstance(depths, str) or not isinstance(depths, Sequence) or len(depths) != 2:
        raise ArgumentTypeError(f"depths must be a pair (top, bottom) of depths in m, got {depths!r}")
    top = checks.real("depths[0] (top)", depths[0], lo=0.0, unit="m")
    bottom = checks.real("depths[1] (bottom)", depths[1], lo=0.0, unit="m")
    if not top < bottom:
        raise ArgumentError(f"depths = ({top:g}, {bottom:g}) m: give (top, bottom) with top < bottom (depth is "
                            "positive down)")
    return top, bottom


def _mission_args(depths: Any, speed: Any, gamma: Any, cycles: Any, output_step: Any, pump_work: Any,
                  max_leg_time: Any) -> tuple[tuple[float, float], float, float, int, float, float]:
    """The checked mission arguments of :func:`dive_cycle` and :func:`dive_cycles_batched`, and the longest leg
    allowed (s): ``max_leg_time``, by default 4 times the nominal leg time plus 600 s."""
    top, bottom = _check_depths(depths)
    speed = checks.positive("speed", speed, unit="m/s")
    gamma = checks.real("gamma", gamma, lo=0.0, hi=math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    cycles = checks.integer("cycles", cycles, lo=1, hi=1000)
    step = checks.positive("output_step", output_step, unit="s")
    checks.choice("pump_work", pump_work, _PUMP_WORK)
    nominal = (bottom - top) / (speed * math.sin(gamma))
    leg_cap = 4.0 * nominal + 600.0 if max_leg_time is None else checks.positive("max_leg_time", max_leg_time)
    return (top, bottom), speed, gamma, cycles, step, leg_cap


def dive_cycle(veh: Vehicle, controller: Any = "lqr", *, depths: Sequence[float] = (5.0, 100.0),
               gamma: float = math.radians(25.0), speed: float = 0.35, cycles: int = 3,
               sensors: Sequence[str] | None = None, noise: dict[str, float] | None = None, seed: int | None = None,
               sensor_period: float = 1.0, measurement_noise: Mapping[str, float] | None = None,
               process_noise: Mapping[str, float] | None = None, output_step: float = 1.0,
               pid_gains: tuple[float, float, float] | None = None,
               max_deviation: Mapping[str, float] | None = None, pump_work: str = "out",
               rho: float = RHO_SEAWATER, p_atm: float = P_ATM, servo_time: float = 0.5, pump_gain: float = 0.5,
               method: str | None = None, rtol: float = 1e-5, atol: float = 1e-7,
               max_leg_time: float | None = None, design_vehicle: Vehicle | None = None) -> DiveCycleRun:
    """Fly ``cycles`` sawtooth dive cycles between two depths on the actuated glider (module docstring).

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with ``mbar > 0`` and ``[actuators]`` entries ``m0``, ``r_P1``, ``r_P3``.
    controller : str or controller object
        ``"lqr"``, ``"lqg"``, ``"nonlinear"``, ``"pid"`` (module docstring), or an object: a pair ``(down, up)``,
        an object with ``for_leg(glide, previous, t_start)``, or one controller for every leg.
    depths : (float, float)
        Top and bottom depth limits (m, positive down), ``0 <= top < bottom``.
    gamma : float
        Magnitude of the glide-path angle of both legs (rad), in ``(0, pi/2)``.
    speed : float
        Glide speed of the legs (m/s), > 0 (the ``"pid"`` baseline flies at the speed of the full pump).
    cycles : int
        Number of cycles, >= 1.
    sensors : sequence of str, optional
        Measured states (default all; ``"lqg"``: :data:`LQG_SENSORS`); must include ``z`` (the supervisor switches
        on the measured depth).
    noise, seed, sensor_period :
        Simulated sensor noise standard deviations (state units), seed and sample-and-hold period (s), as
        :func:`~glidectl.sim.simulate_actuated`; each leg draws from its own stream spawned from ``seed``.
        ``"lqg"`` defaults to :data:`LQG_NOISE` and samples its sensors, corrects its estimate and updates its
        command every ``sensor_period``; ``sensor_period = 0`` flies the analog LQG (continuous Kalman filter,
        :class:`ScheduledGlideLQG`) on noise-free sensors (``noise={}``).
    measurement_noise, process_noise : mapping of str to float, optional
        The Kalman filter of ``"lqg"`` (ignored by the other controllers, which have none), independent of the
        simulated ``noise``: the standard deviation the filter assumes for each sensor sample (sensor units) and
        the process-noise intensity it assumes on each state (state unit per square root of a second). Defaults
        (:func:`lqg_filter_noise`): per sensor the larger of the simulated noise and :data:`LQG_NOISE`; per state
        :data:`LQG_PROCESS_NOISE`, the model's uncertainty.
    output_step : float
        Spacing of the output samples (s), > 0.
    pid_gains : (kp, ki, kd), optional
        Gains of the ``"pid"`` baseline (m/rad, m/(rad s), m s/rad) on both legs; default tuned per leg by
        :func:`tune_pitch_pid` at the leg's full-pump glide.
    max_deviation : mapping, optional
        Bryson's-rule deviations overriding :data:`~glidectl.controllers.linear.DEFAULT_MAX_DEVIATION` (``"lqr"``).
    pump_work : {"out", "both"}
        Which pump strokes the energy counts (:func:`pump_energy`).
    rho, p_atm : float
        Water density (kg/m^3) and surface pressure (Pa) of the energy.
    servo_time, pump_gain : float
        Servo settings of :class:`~glidectl.ActuatedGlider` (s, 1/s).
    design_vehicle : Vehicle, optional
        The vehicle the named controller is designed on and whose glides are the legs' set points (default ``veh``):
        ``veh`` is then the vehicle that flies, which the controller does not know exactly (a vehicle drawn from
        the designer's ``[uncertainty]`` table, :func:`glidectl.dive_cycle_ensemble`). Its actuators must be
        ``veh``'s.
    method, rtol, atol : integrator settings of :func:`~glidectl.sim.simulate_actuated`.
        ``method=None``: ``"RK23"`` for the sampled ``"lqg"``, ``"LSODA"`` otherwise. The sampled-data ``"lqg"``
        restarts the integrator at every sample; there a one-step method that carries its step over the sample
        spends the fewest right-hand-side evaluations (LSODA restarts at order 1 each time), at the same accuracy
        (see ``bench/README.md``, ``bench_lqg_dive_cycle.py``).
    max_leg_time : float, optional
        Longest leg allowed (s); default 4 times the nominal leg time plus 600 s.

    Returns
    -------
    DiveCycleRun

    Raises
    ------
    ArgumentTypeError
        If an argument has the wrong type.
    ArgumentError
        Depths not ``(top, bottom)`` with ``top < bottom``, a non-positive speed, ``gamma`` outside ``(0, pi/2)``,
        an unknown controller name, sensors without ``z`` or without the states the controller needs, or
        ``"lqg"`` with sensors that cannot detect the estimated states.
    ModelError
        A vehicle without the actuators (the message shows how to add them), or ``"nonlinear"`` on a vehicle
        outside its assumptions.
    InfeasibleGlideError
        A leg's glide does not exist or needs an actuator setting outside its range.
    BudgetError
        A leg does not reach its depth limit within ``max_leg_time`` (the controller does not fly the glide).
    SolverError
        A design or the integration fails.
    """
    require_glider(veh, "veh")
    (top, bottom), speed, gamma, cycles, step, leg_cap = _mission_args(depths, speed, gamma, cycles, output_step,
                                                                       pump_work, max_leg_time)
    if isinstance(controller, str):
        checks.choice("controller", controller, CONTROLLER_NAMES)
    period = checks.nonnegative("sensor_period", sensor_period, unit="s")
    plant = ActuatedGlider(veh, servo_time=servo_time, pump_gain=pump_gain)
    dv, design_plant = _design_side(veh, design_vehicle, plant, servo_time, pump_gain)
    if controller == "lqg":
        sens = tuple(LQG_SENSORS if sensors is None else sensors)
        if noise is None:
            noise = dict(LQG_NOISE)
    else:
        sens = tuple(plant.state_names if sensors is None else sensors)
    if period == 0.0 and noise and any(float(v) > 0 for v in dict(noise).values()):
        raise ArgumentError("sensor_period = 0 asks for continuous (analog) sensors and filter, which cannot be "
                            "noisy: simulated noise is drawn once per sample; pass noise={} or a sensor_period > 0")
    if method is None:
        method = "RK23" if controller == "lqg" and period > 0 else "LSODA"
    if "z" not in sens:
        raise ArgumentError(f"sensors {sens} must include the depth 'z': the supervisor switches on the measured "
                            "depth")
    i3 = ACTUATED_AXES.index("r_P3")
    r_p3 = float(np.clip(dv.params.get("r_P3", 0.0), plant.lower[i3], plant.upper[i3]))
    g_down, g_up = _leg_glides(dv, plant, speed, gamma, r_p3)
    make = _leg_factory(controller, dv, design_plant, sens, g_down, g_up, gamma, speed, r_p3, pid_gains,
                        max_deviation, noise, measurement_noise, process_noise, period)
    name = controller if isinstance(controller, str) else type(controller).__name__
    n_legs = 2 * cycles + 1
    used_seed, leg_seeds = _leg_seeds(noise, seed, n_legs)
    runs, switch_t, switch_z, nfev = _fly_legs(
        plant, make, (g_down, g_up), leg_seeds, (top, bottom), leg_cap, name,
        dict(sensors=sens, noise=noise, sensor_period=period or 1.0, method=method, rtol=rtol, atol=atol), step)

    def cat(get: Any) -> np.ndarray:
        parts = [get(r) if k == 0 else get(r)[1:] for k, r in enumerate(runs)]
        return np.concatenate(parts)

    T = cat(lambda r: r.t)
    X = cat(lambda r: r.x)
    U = cat(lambda r: r.u)
    S = cat(lambda r: r.rates)
    C = cat(lambda r: r.commanded)
    SAT = cat(lambda r: r.saturated)
    eff = float(veh.params.get("pump_efficiency", 1.0))
    src = (f"vehicle file ({veh.sources.get('pump_efficiency', 'no source given')})" if "pump_efficiency" in
           veh.params else "not in the vehicle file: 1 (hydraulic work)")
    mets = _cycle_metrics(T, X[:, 0], X[:, _IZ], S[:, 2], SAT.astype(float), switch_t, (top, bottom),
                          efficiency=eff, rho=rho, p_atm=p_atm, g=veh.g, pump_work=pump_work)
    return DiveCycleRun(name, T, X, plant.state_names, U, S, C, SAT, ACTUATED_AXES, plant.lower.copy(),
                        plant.upper.copy(), plant.rate_limit.copy(), tuple(switch_t), tuple(switch_z), mets,
                        (top, bottom), gamma, speed, (g_down, g_up), eff, src, float(rho), float(p_atm), pump_work,
                        sens, used_seed, nfev, veh, veh.provenance)


def _leg_glides(veh: Vehicle, plant: ActuatedGlider, speed: float, gamma: float,
                r_p3: float) -> tuple[SteadyGlide, SteadyGlide]:
    """The down and up glides of the legs (``veh``'s, at ``-gamma`` and ``gamma``), checked inside ``plant``'s
    actuator ranges and rates."""
    glides = []
    for g in (-gamma, gamma):
        gl = steady_glide(veh, speed, g, r_p3=r_p3)
        try:
            plant.check_state(gl.accel_state(), f"the {'down' if g < 0 else 'up'} glide")
        except InfeasibleGlideError as exc:
            raise InfeasibleGlideError(f"{exc} (glide at {speed:g} m/s, gamma = {math.degrees(g):+.2f} deg)") \
                from None
        glides.append(gl)
    return glides[0], glides[1]


def _leg_seeds(noise: Any, seed: int | None, n_legs: int) -> tuple[int | None, list[int | None]]:
    """The seed used and one noise seed per leg, spawned from it (None without noise)."""
    if not (noise and any(float(v) > 0 for v in dict(noise).values())):
        return None, [None] * n_legs
    used = int(np.random.SeedSequence().entropy % (2**63)) if seed is None else checks.integer("seed", seed, lo=0)
    return used, [int(s.generate_state(1)[0]) for s in np.random.SeedSequence(used).spawn(n_legs)]


def _zdot(xx: np.ndarray) -> float:
    """Depth rate (m/s) of an actuated-glider state."""
    th, v1, v3 = xx[2], xx[4], xx[5]
    return float(-v1 * math.sin(th) + v3 * math.cos(th))


def _fly_legs(plant: ActuatedGlider, make: Any, glides: tuple[SteadyGlide, SteadyGlide], leg_seeds: list[Any],
              depths: tuple[float, float], leg_cap: float, name: str, sim: dict[str, Any],
              step: float) -> tuple[list[ActuatedSimulation], list[float], list[float], int]:
    """Fly the legs down, up, ..., down and the last climb's top overshoot, each until its depth limit (the
    supervisor), from the up glide's state at the top depth. Returns the leg runs, the switch times and depths
    (from 0 s at the top) and the right-hand-side evaluations."""
    g_down, g_up = glides
    top, bottom = depths
    iz = sim["sensors"].index("z")
    x, t, prev = g_up.accel_state(0.0, top), 0.0, g_up
    runs: list[ActuatedSimulation] = []
    switch_t, switch_z, nfev = [0.0], [top], 0
    for leg, seed in enumerate(leg_seeds):
        down = leg % 2 == 0
        glide = g_down if down else g_up
        ctrl = make(glide, prev, t, down)
        if runs and callable(getattr(ctrl, "with_estimate", None)) and \
                runs[-1].controller_states == tuple(getattr(ctrl, "controller_states", ())):
            ctrl = ctrl.with_estimate(runs[-1].xc[-1])  # the estimate carries over the inflection
        tail = leg == len(leg_seeds) - 1
        if tail:
            def stop(tt: float, xx: np.ndarray, yy: np.ndarray) -> float:
                return -_zdot(xx)  # climb has stopped: the top overshoot is over
            if stop(t, x, x) <= 0:
                break
        elif down:
            def stop(tt: float, xx: np.ndarray, yy: np.ndarray) -> float:
                return bottom - float(yy[iz])
        else:
            def stop(tt: float, xx: np.ndarray, yy: np.ndarray) -> float:
                return float(yy[iz]) - top
        te = np.append(np.arange(t, t + leg_cap, step), t + leg_cap)
        run = simulate_actuated(plant, x, leg_cap, ctrl, seed=seed, t0=t, t_eval=te, stop=stop, max_steps=200_000,
                                on_budget="stop", **sim)
        nfev += run.nfev
        if run.stopped_by not in ("stop",) and not tail:
            raise BudgetError(f"the {'down' if down else 'up'} leg {leg} of the mission did not reach "
                              f"{bottom if down else top:g} m within {leg_cap:g} s (it ended at depth "
                              f"{run.x[-1, _IZ]:.2f} m, by {run.stopped_by}): controller {name!r} does not fly the "
                              f"{math.degrees(glide.gamma):+.1f} deg glide of vehicle '{plant.vehicle.name}'; raise "
                              "max_leg_time or change the controller")
        runs.append(run)
        t, x = float(run.t[-1]), run.x[-1].copy()
        if not tail:
            switch_t.append(t)
            switch_z.append(float(x[_IZ]))
        prev = glide
    return runs, switch_t, switch_z, nfev


def _design_side(veh: Vehicle, design_vehicle: Vehicle | None, plant: ActuatedGlider, servo_time: float,
                 pump_gain: float) -> tuple[Vehicle, ActuatedGlider]:
    """The vehicle and actuated model the controller is designed on: ``veh``'s own, or ``design_vehicle``'s
    (checked: a glider with the same actuators)."""
    if design_vehicle is None:
        return veh, plant
    require_glider(design_vehicle, "design_vehicle")
    if dict(design_vehicle.actuators) != dict(veh.actuators):
        raise ArgumentError(f"design_vehicle '{design_vehicle.name}' has other actuators than the flying vehicle "
                            f"'{veh.name}': the controller must command the actuators the vehicle has")
    return design_vehicle, ActuatedGlider(design_vehicle, servo_time=servo_time, pump_gain=pump_gain)


def _leg_factory(controller: Any, veh: Vehicle, plant: ActuatedGlider, sens: tuple[str, ...], g_down: SteadyGlide,
                 g_up: SteadyGlide, gamma: float, speed: float, r_p3: float, pid_gains: Any,
                 max_deviation: Any, noise: Any = None, measurement_noise: Any = None, process_noise: Any = None,
                 period: float = 1.0) -> Any:
    """``make(glide, previous_glide, t_start, down) -> leg controller`` for the chosen controller."""
    full = sens == tuple(plant.state_names)
    if controller == "lqg":
        return _lqg_factory(veh, plant, sens, g_down, g_up, max_deviation, noise, measurement_noise, process_noise,
                            period)
    if controller == "lqr":
        if not full:
            raise ArgumentError("controller='lqr' is state feedback: it needs every state measured (sensors=None); "
                                "use an output-feedback controller for a subset of sensors")
        gains = {id(g): _lqr_gain(veh, plant, g, max_deviation) for g in (g_down, g_up)}

        def make_lqr(glide: SteadyGlide, prev: SteadyGlide, t0: float, down: bool) -> Any:
            K, E, sn, inn = gains[id(glide)]
            xf, xt = prev.accel_state(), glide.accel_state()
            return ScheduledGlideLQR(K, xf, xt, t0, _ramp_time(plant, xf, xt), glide, E, sn, inn)
        return make_lqr
    if controller == "nonlinear":
        if not full:
            raise ArgumentError("controller='nonlinear' needs every state measured (sensors=None)")
        down_leg, up_leg = _nonlinear_designs(veh, plant, gamma, speed, r_p3)
        return lambda glide, prev, t0, down: down_leg if down else up_leg
    if controller == "pid":
        missing = [s for s in ("theta", "Omega2") if s not in sens]
        if missing:
            raise ArgumentError(f"controller='pid' needs the sensors {missing}")
        if pid_gains is not None and not (isinstance(pid_gains, Sequence) and len(pid_gains) == 3):
            raise ArgumentTypeError(f"pid_gains must be (kp, ki, kd), got {pid_gains!r}")
        given = None if pid_gains is None else tuple(checks.real(n, v) for n, v in
                                                     zip(("kp", "ki", "kd"), pid_gains, strict=True))
        im = ACTUATED_AXES.index("m0")
        ir = ACTUATED_AXES.index("r_P1")
        lo, hi = plant.lower[im], plant.upper[im]
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ArgumentError("controller='pid' runs the pump to the ends of its range: the vehicle's m0 "
                                "actuator needs a finite min and max")
        full_glides = {}
        for g, m_end in ((g_down, hi), (g_up, lo)):
            if m_end * g.m0 <= 0:
                raise InfeasibleGlideError(f"the pump range [{lo:g}, {hi:g}] kg cannot make vehicle '{veh.name}' "
                                           f"{'heavy' if g.m0 > 0 else 'light'}")
            v_full = g.speed * math.sqrt(m_end / g.m0)  # m0 grows as V^2 at a fixed gamma
            gf = steady_glide(veh, v_full, g.gamma, r_p3=r_p3)
            gains = given if given is not None else tune_pitch_pid(plant, gf)[:3]
            full_glides[id(g)] = (gf, m_end, gains)
        it, io = sens.index("theta"), sens.index("Omega2")

        def make_pid(glide: SteadyGlide, prev: SteadyGlide, t0: float, down: bool) -> Any:
            gf, m_end, (kp, ki, kd) = full_glides[id(glide)]
            gp, m_prev, _ = full_glides[id(prev)]
            ramp = abs(m_end - m_prev) / plant.rate_limit[im] if plant.rate_limit[im] > 0 else 0.0
            ramp = ramp if math.isfinite(ramp) else 0.0
            return PitchPID(gp.theta, gf.theta, gp.r_p1, gf.r_p1, m_end, t0, ramp, kp, ki, kd, it, io,
                            (float(plant.lower[ir]), float(plant.upper[ir])))
        return make_pid
    # a controller object
    if isinstance(controller, tuple | list):
        if len(controller) != 2 or not all(callable(c) for c in controller):
            raise ArgumentTypeError("a controller pair must be (down, up), two controllers")
        down_c, up_c = controller
        return lambda glide, prev, t0, down: down_c if down else up_c
    if callable(getattr(controller, "for_leg", None)):
        return lambda glide, prev, t0, down: controller.for_leg(glide, prev, t0)
    if callable(controller):
        return lambda glide, prev, t0, down: controller
    raise ArgumentTypeError(f"controller must be one of {CONTROLLER_NAMES} or a controller object, got "
                            f"{type(controller).__name__} {controller!r}")


def _named_levels(name: str, value: Any, allowed: Sequence[str], what: str) -> dict[str, float]:
    """A mapping ``{name: positive level}`` over ``allowed`` names (empty for None)."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise ArgumentTypeError(f"{name} must be a mapping {{{what}: standard deviation}} over {list(allowed)}, "
                                f"got {type(value).__name__}")
    unknown = [k for k in value if k not in allowed]
    if unknown:
        raise ArgumentError(f"{name} names {unknown}, which are not {what}s of the 'lqg' design; {what}s: "
                            f"{list(allowed)}")
    return {k: checks.positive(f"{name}[{k!r}]", v) for k, v in value.items()}


def lqg_filter_noise(sensors: Sequence[str], noise: Mapping[str, float] | None = None,
                     measurement_noise: Mapping[str, float] | None = None,
                     process_noise: Mapping[str, float] | None = None) -> tuple[dict[str, float], dict[str, float]]:
    """The Kalman-filter weights of the ``"lqg"`` dive-cycle controller: measurement and process noise.

    Parameters
    ----------
    sensors : sequence of str
        The filter's sensors (states of the actuated glider).
    noise : mapping of str to float, optional
        The simulated sensor noise (standard deviation per sample, sensor units), as ``noise`` of
        :func:`dive_cycle`.
    measurement_noise : mapping of str to float, optional
        Standard deviation the filter assumes for each sensor sample (sensor units, > 0); overrides the default of a
        sensor: the larger of its simulated noise and its :data:`LQG_NOISE` level (1e-3 of its Bryson scale for a
        sensor without one), so that the filter never trusts a sensor more than it deserves.
    process_noise : mapping of str to float, optional
        Process-noise intensity the filter assumes (state unit per square root of a second, > 0); overrides entries
        of :data:`LQG_PROCESS_NOISE`.

    Returns
    -------
    measurement : dict of str to float
        Standard deviation per sensor.
    process : dict of str to float
        Intensity per state (every state of :data:`LQG_PROCESS_NOISE`, overridden).

    Raises
    ------
    ArgumentTypeError
        If a mapping is not a mapping of names to real numbers.
    ArgumentError
        If ``measurement_noise`` names a state that is not a sensor, ``process_noise`` a name that is not a state
        of the actuated glider, or a level is not positive and finite.

    Examples
    --------
    >>> import glidectl as gc
    >>> measurement, process = gc.lqg_filter_noise(("theta", "m0"), noise={"theta": 0.01})
    >>> measurement
    {'theta': 0.01, 'm0': 0.0001}
    >>> process["theta"], process["m0"]                       # intensities (state unit per sqrt(s))
    (0.0001, 0.0002)
    """
    sens = tuple(sensors)
    meas = _named_levels("measurement_noise", measurement_noise, sens, "sensor")
    proc = _named_levels("process_noise", process_noise, tuple(LQG_PROCESS_NOISE), "state")
    sim = dict(noise or {})
    levels = {}
    for q in sens:
        floor = LQG_NOISE.get(q, 1e-3 * DEFAULT_MAX_DEVIATION.get(q, 1.0))
        levels[q] = meas.get(q, max(float(sim.get(q, 0.0)), floor))
    return levels, {**LQG_PROCESS_NOISE, **proc}


def _lqg_factory(veh: Vehicle, plant: ActuatedGlider, sens: tuple[str, ...], g_down: SteadyGlide,
                 g_up: SteadyGlide, max_deviation: Any, noise: Any, measurement_noise: Any, process_noise: Any,
                 period: float) -> Any:
    """Leg controllers of ``controller="lqg"``: :func:`~glidectl.lqg_glide` at each leg's glide from the measured
    sensors with the filter weights of :func:`lqg_filter_noise`, sampled every ``period`` seconds
    (:class:`SampledGlideLQG`), or the continuous filter (:class:`ScheduledGlideLQG`) for ``period = 0``."""
    bad = [q for q in sens if q not in plant.state_names]
    if bad:
        raise ArgumentError(f"sensors {bad} are not states of the actuated glider")
    lqg_sens = tuple(q for q in sens if q != "x")  # horizontal position is not a sensor of a submerged glider
    levels, proc = lqg_filter_noise(lqg_sens, noise, measurement_noise, process_noise)
    designs = {}
    for g in (g_down, g_up):
        try:
            est = lqg_glide(veh, g, lqg_sens, levels, inputs="acceleration",
                            max_deviation=max_deviation).estimated_states
            d = lqg_glide(veh, g, lqg_sens, levels, inputs="acceleration", max_deviation=max_deviation,
                          process_noise={k: v for k, v in proc.items() if k in est})
        except ArgumentError as exc:
            raise ArgumentError(f"controller='lqg' cannot be designed for the {math.degrees(g.gamma):+.1f} deg leg "
                                f"of vehicle '{veh.name}': {exc}") from exc
        designs[id(g)] = d.sampled(period) if period > 0 else d
    idx = tuple(sens.index(q) for q in lqg_sens)

    def make_lqg(glide: SteadyGlide, prev: SteadyGlide, t0: float, down: bool) -> Any:
        xf, xt = prev.accel_state(), glide.accel_state()
        leg = SampledGlideLQG if period > 0 else ScheduledGlideLQG      # period 0: the analog filter
        return leg(designs[id(glide)], plant, xf, xt, t0, _ramp_time(plant, xf, xt), idx)
    return make_lqg


def compare_missions(veh: Vehicle, controllers: Sequence[Any] = CONTROLLER_NAMES, **mission: Any) -> MissionComparison:
    """Fly the same dive-cycle mission with several controllers and tabulate them.

    Parameters
    ----------
    veh : Vehicle
    controllers : sequence
        Names or controller objects for :func:`dive_cycle`.
    **mission
        Keyword arguments of :func:`dive_cycle` (``depths``, ``gamma``, ``speed``, ``cycles``, ``noise``, the
        ``"lqg"`` filter's ``measurement_noise`` and ``process_noise``, ...).

    Returns
    -------
    MissionComparison
        One row per controller; a controller that cannot fly the mission (a refused name, a leg that never
        reaches its limit) gets a row with its error message instead of metrics.

    Raises
    ------
    ArgumentTypeError
        If ``controllers`` is not a sequence or ``veh`` not a Vehicle.
    ArgumentError
        If ``controllers`` is empty, or ``"lqg"`` is among them and ``measurement_noise`` / ``process_noise`` name
        an unknown sensor / state or give a level that is not positive.
    ModelError
        If ``veh`` is not an underwater glider.
    """
    require_glider(veh, "veh")
    if isinstance(controllers, str) or not isinstance(controllers, Sequence):
        raise ArgumentTypeError(f"controllers must be a sequence of names or controller objects, got "
                                f"{type(controllers).__name__}")
    if not controllers:
        raise ArgumentError("controllers is empty")
    if "lqg" in controllers:  # a bad filter weight is the caller's error, not a row of a refused controller
        lqg_filter_noise(tuple(q for q in (mission.get("sensors") or LQG_SENSORS) if q != "x"), mission.get("noise"),
                         mission.get("measurement_noise"), mission.get("process_noise"))
    rows, runs = [], {}
    nan = float("nan")
    for c in controllers:
        name = c if isinstance(c, str) else type(c).__name__
        try:
            run = dive_cycle(veh, c, **mission)
        except (ArgumentError, ModelError, InfeasibleGlideError, BudgetError, SolverError) as exc:
            if isinstance(exc, ArgumentError) and not (isinstance(c, str) and c in ("lqg",)):
                raise
            rows.append({"controller": name, "cycles": 0, "distance_per_cycle": nan, "duration_per_cycle": nan,
                         "max_overshoot": nan, "saturated_time_per_cycle": nan, "energy_per_cycle": nan,
                         "error": f"{type(exc).__name__}: {str(exc).splitlines()[0][:400]}"})
            continue
        runs[name] = run
        rows.append({**run.as_dict(), "error": ""})
    return MissionComparison(tuple(rows), runs, veh, veh.provenance)


# ------------------------------------------------------------------------------------------------ batched
def cycle_summary(cycles: Sequence[CycleMetrics]) -> dict[str, float]:
    """Per-cycle means of distance (m), duration (s), saturated time (s) and energy (J), and the largest overshoot
    (m): the numbers of :meth:`DiveCycleRun.as_dict`."""
    return {"distance_per_cycle": float(np.mean([k.distance for k in cycles])),
            "duration_per_cycle": float(np.mean([k.duration for k in cycles])),
            "max_overshoot": float(max(k.max_overshoot for k in cycles)),
            "saturated_time_per_cycle": float(np.mean([k.saturated_time for k in cycles])),
            "energy_per_cycle": float(np.mean([k.energy for k in cycles]))}


def _ramp_rows(tau: np.ndarray, x_from: np.ndarray, x_to: np.ndarray,
               ramp_time: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_ramp_reference` at the times ``tau`` (shape (N,), from the transition's start) of N runs: reference
    states (N, 11) and feedforwards (N, 3), row by row the same numbers."""
    if ramp_time <= 0:
        s, sd = np.ones_like(tau), np.zeros_like(tau)
    else:
        q = tau / ramp_time
        inside = (q > 0) & (q < 1)
        s = np.where(q <= 0, 0.0, np.where(q >= 1, 1.0, q))
        sd = np.where(inside, 1.0 / ramp_time, 0.0)
    d = x_to - x_from
    x_ref = x_from + s[:, None] * d
    x_ref[:, 7], x_ref[:, 9] = sd * d[6], sd * d[8]
    w_ff = np.zeros((tau.size, 3))
    w_ff[:, 2] = sd * d[10]
    return x_ref, w_ff


@dataclass(frozen=True)
class _BatchLeg:
    """One leg of the batched LQR dive cycle: gain, transition and the depth event that ends it."""

    K: np.ndarray
    x_from: np.ndarray
    x_to: np.ndarray
    ramp_time: float
    kind: str                      # "down", "up" or "tail"
    depths: tuple[float, float]

    def command(self, tau: np.ndarray, X: np.ndarray) -> np.ndarray:
        """``(w1, w3, w4)`` of :class:`ScheduledGlideLQR` for N runs at their leg times ``tau``."""
        x_ref, w_ff = _ramp_rows(tau, self.x_from, self.x_to, self.ramp_time)
        return w_ff - (X - x_ref) @ self.K.T

    def event(self, tau: np.ndarray, X: np.ndarray) -> np.ndarray:
        """The supervisor's stop function of :func:`_fly_legs`, row by row."""
        if self.kind == "down":
            return self.depths[1] - X[:, _IZ]
        if self.kind == "up":
            return X[:, _IZ] - self.depths[0]
        th, v1, v3 = X[:, 2], X[:, 4], X[:, 5]
        return v1 * np.sin(th) - v3 * np.cos(th)            # -zdot: the climb has stopped


def _batch_legs(dv: Vehicle, plant: ActuatedGlider, depths: tuple[float, float], gamma: float, speed: float,
                cycles: int, max_deviation: Any) -> tuple[list[_BatchLeg], SteadyGlide]:
    """The legs of :func:`dive_cycle`'s ``"lqr"`` mission designed on ``dv`` (its gains, glides and ramps, the
    transition starting at each leg's own time 0), and the up glide whose state starts the mission."""
    i3 = ACTUATED_AXES.index("r_P3")
    r_p3 = float(np.clip(dv.params.get("r_P3", 0.0), plant.lower[i3], plant.upper[i3]))
    g_down, g_up = _leg_glides(dv, plant, speed, gamma, r_p3)
    gains = {id(g): _lqr_gain(dv, plant, g, max_deviation)[0] for g in (g_down, g_up)}
    legs = []
    for leg in range(2 * cycles + 1):
        glide, prev = (g_down, g_up) if leg % 2 == 0 else (g_up, g_down)
        xf, xt = prev.accel_state(), glide.accel_state()
        kind = "tail" if leg == 2 * cycles else "down" if leg % 2 == 0 else "up"
        legs.append(_BatchLeg(gains[id(glide)], xf, xt, _ramp_time(plant, xf, xt), kind, depths))
    return legs, g_up


def _leg_records(legs: list[_BatchLeg], members: list[Vehicle], plant0: ActuatedGlider, x0: np.ndarray,
                 leg_cap: float, step: float, rtol: float,
                 atol: float) -> tuple[list[list[tuple]], list[GlidectlError | None]]:
    """Fly every member through the legs together (:func:`~glidectl.batch_events.integrate_batch_events`, one leg
    at a time, each member from its own end of the previous leg). Returns per member its legs' samples
    ``(t, X, rates, saturated)`` on absolute times, and what stopped it (None if it flew every leg)."""
    from ..batch_events import integrate_batch_events
    from ..params import stack_vehicles
    from ..sim import saturated_mask

    N = len(members)
    records: list[list[tuple]] = [[] for _ in range(N)]
    errors: list[GlidectlError | None] = [None] * N
    X, t_abs = np.tile(x0, (N, 1)), np.zeros(N)
    for number, leg in enumerate(legs):
        alive = np.flatnonzero([e is None for e in errors])
        if leg.kind == "tail":
            alive = alive[leg.event(np.zeros(alive.size), X[alive]) > 0]
        if alive.size == 0:
            break
        plant = ActuatedGlider(stack_vehicles([members[i] for i in alive]), servo_time=plant0.servo_time,
                               pump_gain=plant0.pump_gain)

        def rhs(tau: np.ndarray, Z: np.ndarray, plant: ActuatedGlider = plant, leg: _BatchLeg = leg) -> np.ndarray:
            return plant.rhs(Z, plant.acceleration_rates(Z, leg.command(tau, Z)))

        res = integrate_batch_events(rhs, X[alive], leg_cap, event=leg.event, t_step=step, rtol=rtol, atol=atol,
                                     max_steps=200_000)
        for j, i in enumerate(alive):
            if leg.kind != "tail" and not res.stopped[j]:
                target = leg.depths[1] if leg.kind == "down" else leg.depths[0]
                errors[i] = BudgetError(f"the {leg.kind} leg {number} of the mission did not reach {target:g} m "
                                        f"within {leg_cap:g} s (it ended at depth {res.x[j, _IZ]:.2f} m, by "
                                        f"{res.reason(j)})")
                continue
            k = int(res.n_samples[j])
            tau = np.arange(k) * step
            Xs = res.samples[j, :k]
            if not tau.size or tau[-1] < res.t[j]:
                tau, Xs = np.append(tau, res.t[j]), np.vstack([Xs, res.x[j]])
            records[i].append((t_abs[i] + tau, Xs, tau))
            X[i], t_abs[i] = res.x[j], t_abs[i] + res.t[j]
        # rates and saturation at the samples, every member of the leg at once (the actuators are common)
        rows = [i for i in alive if errors[i] is None and len(records[i]) == number + 1]
        if rows:
            Xs = np.concatenate([records[i][-1][1] for i in rows])
            tau = np.concatenate([records[i][-1][2] for i in rows])
            U = plant0.acceleration_rates(Xs, leg.command(tau, Xs))
            S = plant0.limited_rates(Xs, U)
            sat = saturated_mask(U, S, plant0.positions(Xs), plant0.lower, plant0.upper, plant0.rate_limit)
            cut = np.cumsum([0] + [len(records[i][-1][2]) for i in rows])
            for r, i in enumerate(rows):
                t_i, X_i, _ = records[i][-1]
                records[i][-1] = (t_i, X_i, S[cut[r]:cut[r + 1]], sat[cut[r]:cut[r + 1]])
    return records, errors


def dive_cycles_batched(vehicles: Sequence[Vehicle], design_vehicle: Vehicle, *,
                        depths: Sequence[float] = (5.0, 100.0), gamma: float = math.radians(25.0),
                        speed: float = 0.35, cycles: int = 3, output_step: float = 1.0,
                        max_deviation: Mapping[str, float] | None = None, pump_work: str = "out",
                        rho: float = RHO_SEAWATER, p_atm: float = P_ATM, servo_time: float = 0.5,
                        pump_gain: float = 0.5, rtol: float = 1e-5, atol: float = 1e-7,
                        max_leg_time: float | None = None) -> list[tuple[CycleMetrics, ...] | GlidectlError]:
    """The ``"lqr"`` dive cycles of :func:`dive_cycle` flown by many vehicles at once, every one under the
    controller designed on ``design_vehicle``: the cycle metrics of each.

    Every vehicle flies the same two leg controllers (the gains, glides and ramps of ``design_vehicle``), and a
    leg is autonomous in its own time (the reference ramp starts at the leg's start), so the vehicles fly each leg
    together as one stacked state (:func:`~glidectl.params.stack_vehicles`, one right-hand-side call for all),
    each with its own step size and its own depth switch, located on the integrator's continuous extension as
    :func:`dive_cycle`'s supervisor locates it (:func:`~glidectl.batch_events.integrate_batch_events`,
    Dormand-Prince 5(4)). The metrics are :func:`dive_cycle`'s, from the same output grid; they agree with
    :func:`dive_cycle` ``(veh, "lqr", design_vehicle=design_vehicle)`` to the integration tolerance (the serial
    run uses LSODA).

    Parameters
    ----------
    vehicles : sequence of Vehicle
        The flying vehicles (e.g. :meth:`~glidectl.Vehicle.sample` of ``design_vehicle``).
    design_vehicle : Vehicle
        The vehicle the controller is designed on; the flying vehicles need its actuators.
    depths, gamma, speed, cycles, output_step, max_deviation, pump_work, rho, p_atm, servo_time, pump_gain, rtol, \
atol, max_leg_time :
        As :func:`dive_cycle`.

    Returns
    -------
    list
        Per vehicle, its :class:`CycleMetrics` (one per cycle), or the :class:`~glidectl.errors.GlidectlError` that
        stopped it (a vehicle the actuated model refuses, a leg that does not reach its depth).

    Raises
    ------
    ArgumentError, ArgumentTypeError
        Bad arguments, as :func:`dive_cycle`.
    InfeasibleGlideError, ModelError, SolverError
        The design on ``design_vehicle`` fails (common to every vehicle).
    """
    require_glider(design_vehicle, "design_vehicle")
    (top, bottom), speed, gamma, cycles, step, leg_cap = _mission_args(depths, speed, gamma, cycles, output_step,
                                                                       pump_work, max_leg_time)
    plant0 = ActuatedGlider(design_vehicle, servo_time=servo_time, pump_gain=pump_gain)
    legs, g_up = _batch_legs(design_vehicle, plant0, (top, bottom), gamma, speed, cycles, max_deviation)
    out: list[Any] = [None] * len(vehicles)
    members, where = [], []
    for i, v in enumerate(vehicles):
        try:
            require_instance(f"vehicles[{i}]", v, Vehicle)
            _design_side(v, design_vehicle, ActuatedGlider(v, servo_time=servo_time, pump_gain=pump_gain),
                         servo_time, pump_gain)
        except GlidectlError as exc:
            out[i] = exc
            continue
        members.append(v)
        where.append(i)
    if not members:
        return out
    records, errors = _leg_records(legs, members, plant0, g_up.accel_state(0.0, top), leg_cap, step, rtol, atol)
    for i, v, rec, why in zip(where, members, records, errors, strict=True):
        if why is not None:
            out[i] = why
            continue
        T = np.concatenate([r[0] if k == 0 else r[0][1:] for k, r in enumerate(rec)])
        X = np.concatenate([r[1] if k == 0 else r[1][1:] for k, r in enumerate(rec)])
        S = np.concatenate([r[2] if k == 0 else r[2][1:] for k, r in enumerate(rec)])
        SAT = np.concatenate([r[3] if k == 0 else r[3][1:] for k, r in enumerate(rec)])
        switch = [0.0] + [float(r[0][-1]) for r, leg in zip(rec, legs, strict=False) if leg.kind != "tail"]
        eff = float(v.params.get("pump_efficiency", 1.0))
        out[i] = _cycle_metrics(T, X[:, 0], X[:, _IZ], S[:, 2], SAT.astype(float), switch, (top, bottom),
                                efficiency=eff, rho=rho, p_atm=p_atm, g=v.g, pump_work=pump_work)
    return out
