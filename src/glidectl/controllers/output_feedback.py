"""Output feedback about a steady glide: an LQR gain on a Kalman-filter estimate (LQG), from named sensors.

:func:`lqg_glide` designs, on the linearization of :func:`~glidectl.analysis.linear.linearize_glide` with the
sensors as outputs, an LQR gain (:func:`control.lqr`, on the actuated inputs) and a stationary Kalman-filter gain
(:func:`control.lqe`) from the sensor noise levels. The result, :class:`LQGController`, is a dynamic controller with
an explicit estimator state:

* :meth:`LQGController.closed_loop` (and :func:`glidectl.closed_loop`) gives the input-free model whose state is the
  nonlinear plant's followed by the estimate (names ``<state>_hat``), for :func:`glidectl.simulate`;
* :meth:`LQGController.to_iosys` gives the controller alone as a :class:`control.NonlinearIOSystem` (sensors in,
  inputs out), for python-control interconnections;
* :meth:`LQGController.sampled` gives its sampled-data (digital) version, :class:`SampledLQG`: a discrete LQR and
  Kalman filter on the zero-order-hold discretization, for a flight computer that reads its sensors and updates
  its command every sample period (the dive cycle's ``"lqg"``).

A vehicle file that fixes an actuator (e.g. ``r_P3 = { fixed = 0.05 }``) has the design made on the model without
that actuator's states and input (``reduce_fixed=True``, :func:`~glidectl.analysis.linear.design_model`).

What can be estimated: ``z'`` (distance from the glide path, 2.30) needs the horizontal position, which a submerged
glider does not measure: it is a pure integrator that no other state sees, so it is estimated and regulated only
when a sensor measures it (then the regulator holds the path; otherwise it holds the glide: speed, attitude and
internal masses, and the path offset drifts with the disturbances). Likewise depth ``z`` is estimated when a sensor
measures it (it is never regulated: the nominal depth changes along a glide). The remaining states must be
detectable from the sensors, or the design is refused (e.g. depth, pitch and pitch rate cannot see the moving mass
moving along gravity when both mass axes move; fix one axis with ``actuate`` or measure the mass position).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import control
import numpy as np

from .. import checks
from ..analysis.linear import (
    FIXED_ACTUATOR_STATES,
    OutputMap,
    design_model,
    fixed_actuators,
    glide_model,
    linearize_glide,
    observability,
    output_map,
)
from ..errors import ArgumentError, ArgumentTypeError, SolverError
from ..models._validate import trailing_array
from ..models.closed_loop import ClosedLoop
from ..params import Vehicle
from ..trim.glide import SteadyGlide
from .linear import (
    DEFAULT_MAX_DEVIATION,
    actuated_subset,
    bryson_weights,
    check_glide_design,
    design_weight,
    lqr_subset,
)

__all__ = ["LQGController", "PlantWithEstimator", "SampledLQG", "lqg_glide"]

#: Default process-noise intensity of each estimated state: this fraction of its Bryson scale
#: (:data:`~glidectl.controllers.linear.DEFAULT_MAX_DEVIATION`), per square root of a second.
PROCESS_NOISE_FRACTION = 0.1


@dataclass(frozen=True, eq=False)
class LQGController:
    """LQG output feedback about a steady glide: ``u = -K (xhat - x_e)`` with the Kalman filter
    ``xhat' = d + A (xhat - x_e) + B u + L (y - y_e - C (xhat - x_e))``.

    Actuator limits: this law does not saturate its own commands. Run it through
    :class:`~glidectl.models.actuated.ActuatedGlider` (:func:`glidectl.sim.simulate_actuated`,
    :func:`glidectl.controllers.dive_cycle.dive_cycle`) to have the vehicle's ``[actuators]`` ranges and rates
    enforced; :func:`glidectl.sim.simulate` on the plain model applies no limits.

    Built by :func:`lqg_glide`. States are those of the glide-path model (plus depth ``z`` when a sensor measures
    it); the estimate covers :attr:`estimated_states` (the others are taken at their equilibrium values); ``d`` is
    the nominal sink rate in the ``z`` row (zero elsewhere); the equilibrium input of the glide-path form is zero.

    Attributes
    ----------
    K : ndarray, shape (m, n)
        Regulator gain of the plant's inputs on its states (zero rows for inputs not actuated, zero columns for states
        not regulated; ``m = 3`` without fixed actuators).
    L : ndarray, shape (len(estimated_states), len(sensors))
        Kalman-filter gain (state units per sensor unit).
    plant : control.StateSpace
        Linearization with the sensors as outputs (:func:`~glidectl.analysis.linear.linearize_glide`).
    glide : SteadyGlide
    inputs : {"force", "acceleration"}
    sensors : OutputMap
        The measured outputs (names, channels, coefficients).
    noise : ndarray
        Sensor noise standard deviations (sensor units), one per sensor; ``RN = diag(noise^2)``.
    process_noise : ndarray
        Process-noise covariance ``QN`` on the estimated states (state units^2 per s).
    Q, R : ndarray
        LQR weights on the regulated states and actuated inputs.
    regulator_poles, estimator_poles : ndarray
        Eigenvalues (1/s) of the regulated subsystem ``A - B K`` and of the estimator ``A - L C``.
    estimated_states, regulated_states : tuple of str
    actuate, locked_states : tuple of str
        As in :class:`~glidectl.controllers.linear.LinearGlideController`.
    vehicle : Vehicle
    provenance : str
        The vehicle's parameter hash.
    fixed_actuators : tuple of str
        Actuators the vehicle file fixes, removed from the plant model with their states and inputs
        (:class:`~glidectl.analysis.linear.FixedActuatorModel`); ``()`` for the full model.

    Raises
    ------
    ArgumentError
        If the gains do not match the plant and sensors.
    """

    K: np.ndarray
    L: np.ndarray
    plant: control.StateSpace
    glide: SteadyGlide
    inputs: str
    sensors: OutputMap
    noise: np.ndarray
    process_noise: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    regulator_poles: np.ndarray
    estimator_poles: np.ndarray
    estimated_states: tuple[str, ...]
    regulated_states: tuple[str, ...]
    actuate: tuple[str, ...]
    locked_states: tuple[str, ...]
    vehicle: Vehicle = field(repr=False, compare=False)
    method: str = "lqg"
    fixed_actuators: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        n, m = np.asarray(self.plant.B).shape
        checks.array("K", self.K, shape=(m, n))
        checks.array("L", self.L, shape=(len(self.estimated_states), len(self.sensors.names)))

    @property
    def provenance(self) -> str:
        return self.vehicle.provenance

    @property
    def state_names(self) -> tuple[str, ...]:
        """States of the plant model (glide-path states, then ``z`` when measured)."""
        return tuple(self.plant.state_labels)

    @property
    def estimator_state_names(self) -> tuple[str, ...]:
        """Names of the estimator's states, ``<state>_hat``."""
        return tuple(f"{s}_hat" for s in self.estimated_states)

    def plant_model(self) -> tuple[Any, np.ndarray]:
        """The nonlinear plant the controller was designed for and its equilibrium (``z = 0`` when depth is a state).

        Returns
        -------
        model : GlidePathModel, DepthGlidePathModel or FixedActuatorModel
            :func:`~glidectl.analysis.linear.design_model`.
        xe : ndarray, shape (n,)
        """
        return design_model(self.vehicle, self.glide, self.inputs,  # type: ignore[arg-type]
                            depth="z" in self.state_names, reduce_fixed=bool(self.fixed_actuators))

    def _data(self) -> tuple[Any, np.ndarray, list[int], np.ndarray, np.ndarray]:
        cache = self.__dict__.get("_cache")
        if cache is None:
            model, xe = self.plant_model()
            ei = [self.state_names.index(s) for s in self.estimated_states]
            drift = np.zeros(len(ei))
            if "z" in self.estimated_states:
                drift[self.estimated_states.index("z")] = np.real(model.rhs(xe, np.zeros(len(model.input_names))))[-1]
            ye = np.real(self.sensors(model, xe))
            cache = (model, xe, ei, drift, ye)
            object.__setattr__(self, "_cache", cache)
        return cache

    def measure(self, x: Any) -> np.ndarray:
        """Noise-free sensor values (sensor units) of plant states ``x`` (shape ``(..., n)``)."""
        model = self._data()[0]
        x = trailing_array("x", x, len(self.state_names), self.state_names)
        return self.sensors(model, x)

    def u_from_estimate(self, xhat: Any) -> np.ndarray:
        """Input ``u = -K (xhat - x_e)`` (shape ``(..., 3)``) for estimates ``xhat`` of :attr:`estimated_states`."""
        _, xe, ei, _, _ = self._data()
        xhat = np.asarray(xhat)
        return -(xhat - xe[ei]) @ np.asarray(self.K)[:, ei].T

    def estimator_rhs(self, xhat: Any, y: Any, u: Any) -> np.ndarray:
        """Kalman-filter derivative for estimates ``xhat`` (``(..., ne)``), sensor values ``y`` and inputs ``u``
        (batch-capable, complex-safe)."""
        _, xe, ei, drift, ye = self._data()
        A, B, C = (np.asarray(M) for M in (self.plant.A, self.plant.B, self.plant.C))
        A, B, C = A[np.ix_(ei, ei)], B[ei], C[:, ei]
        dx = np.asarray(xhat) - xe[ei]
        innov = np.asarray(y) - ye - dx @ C.T
        return drift + dx @ A.T + np.asarray(u) @ B.T + innov @ np.asarray(self.L).T

    def closed_loop(self) -> ClosedLoop:
        """The nonlinear plant with this controller: states plant then estimate (:class:`PlantWithEstimator`).

        Returns
        -------
        ClosedLoop
            Equilibrium ``(x_e, x_e)`` restricted to the estimated states, or None when depth is a state (the depth
            changes along the glide).
        """
        aug = PlantWithEstimator(self)
        xe, ei = self._data()[1], self._data()[2]
        eq = None if "z" in self.state_names else np.concatenate([xe, xe[ei]])
        return ClosedLoop(aug, aug.law, eq, f"LQG from {', '.join(self.sensors.names)} "
                          f"(gamma_e = {np.degrees(self.glide.gamma):.4g} deg)")

    def sampled(self, period: float) -> SampledLQG:
        """The sampled-data (digital) version of this design at the sample period ``period``.

        Parameters
        ----------
        period : float
            Sample period ``T`` (s), > 0: the sensors are read, the estimate corrected and the input updated every
            ``T`` seconds; the input is held in between (zero-order hold).

        Returns
        -------
        SampledLQG
            Discrete LQR gain and Kalman measurement-update gain of the zero-order-hold discretization of
            :attr:`plant`, with the same weights (see :class:`SampledLQG`).

        Raises
        ------
        ArgumentTypeError
            If ``period`` is not a real number.
        ArgumentError
            If ``period`` is not positive and finite.
        SolverError
            If a discrete Riccati equation has no stabilizing solution at this period.
        """
        return _sample_design(self, checks.positive("period", period, unit="s"))

    def to_iosys(self) -> control.NonlinearIOSystem:
        """The controller as a :class:`control.NonlinearIOSystem`: inputs the sensors, states the estimate
        (``<state>_hat``), outputs the plant inputs.

        Returns
        -------
        control.NonlinearIOSystem
        """
        ne = len(self.estimated_states)

        def update(t: float, xh: Any, y: Any, params: Any = None) -> np.ndarray:
            xh = np.asarray(xh, dtype=float).reshape(ne)
            return self.estimator_rhs(xh, np.asarray(y, dtype=float), self.u_from_estimate(xh))

        def output(t: float, xh: Any, y: Any, params: Any = None) -> np.ndarray:
            return self.u_from_estimate(np.asarray(xh, dtype=float).reshape(ne))

        return control.NonlinearIOSystem(update, output, states=list(self.estimator_state_names),
                                         inputs=list(self.sensors.names), outputs=list(self.plant.input_labels),
                                         name="lqg_controller")


@dataclass(frozen=True, eq=False)
class SampledLQG:
    """Sampled-data (digital) LQG of an :class:`LQGController`: what a glider's flight computer runs.

    Every ``period`` seconds the sensors are read (``y_k``), the predicted estimate is corrected,
    ``xhat_k = xhat_k^- + M (y_k - y_e - C (xhat_k^- - x_e))``, and the input ``u_k = -K (xhat_k - x_e)`` is
    computed and held until the next sample (zero-order hold); the estimate is then predicted to the next sample
    with the plant's model under the held input. Built by :meth:`LQGController.sampled`.

    Gains are those of the zero-order-hold discretization ``(A_d, B_d)`` of the design's linearization over one
    period, with the design's weights carried over exactly (Van Loan's integrals): the regulator minimizes the same
    continuous cost ``integral of (x' Q x + u' R u) dt`` over sampled inputs (:func:`control.dlqr` with the
    integrated state, cross and input weights); the Kalman filter assumes the design's process-noise intensity
    ``QN`` (integrated over a period) and, per sample, independent sensor errors of standard deviation
    :attr:`LQGController.noise` (``R_d = diag(noise^2)``: a sensor read once per period, whose error is held over
    it, as :func:`glidectl.sim.simulate_actuated` draws it).

    Attributes
    ----------
    design : LQGController
        The continuous design whose states, sensors and weights are sampled.
    period : float
        Sample period (s).
    K : ndarray, shape (m, n)
        Discrete regulator gain of the plant's inputs on its states (zero rows for inputs not actuated, zero
        columns for states not regulated; input units per state unit).
    M : ndarray, shape (len(design.estimated_states), len(design.sensors.names))
        Measurement-update (correction) gain of the estimated states (state units per sensor unit).
    Ad, Bd : ndarray
        Zero-order-hold discretization of ``(A, B)`` over one period on the estimated states (``Bd`` on every input
        of the plant).
    regulator_poles, estimator_poles : ndarray
        Eigenvalues (nondimensional, z-plane) of ``A_d - B_d K`` on the regulated states and of the estimation
        error ``A_d (I - M C)`` on the estimated states; inside the unit circle.
    """

    design: LQGController
    period: float
    K: np.ndarray
    M: np.ndarray
    Ad: np.ndarray
    Bd: np.ndarray
    regulator_poles: np.ndarray
    estimator_poles: np.ndarray

    @property
    def regulator_poles_s(self) -> np.ndarray:
        """Continuous-time equivalents ``log(z) / period`` (1/s) of :attr:`regulator_poles`."""
        return np.log(self.regulator_poles.astype(complex)) / self.period

    @property
    def estimator_poles_s(self) -> np.ndarray:
        """Continuous-time equivalents ``log(z) / period`` (1/s) of :attr:`estimator_poles`."""
        return np.log(self.estimator_poles.astype(complex)) / self.period


def _van_loan(A: np.ndarray, W: np.ndarray, T: float) -> np.ndarray:
    """``integral_0^T exp(A' t) W exp(A t) dt`` (Van Loan 1978, IEEE TAC 23(3): one matrix exponential)."""
    from scipy.linalg import expm

    n = A.shape[0]
    E = expm(np.block([[-A.T, W], [np.zeros((n, n)), A]]) * T)
    G = E[n:, n:].T @ E[:n, n:]
    return 0.5 * (G + G.T)


def _sample_design(d: LQGController, T: float) -> SampledLQG:
    from scipy.linalg import expm, solve_discrete_are

    names = list(d.state_names)
    A, B, C = (np.asarray(M, dtype=float) for M in (d.plant.A, d.plant.B, d.plant.C))
    ui = [list(d.plant.input_labels).index(q) for q in d.actuate]
    ri = [names.index(s) for s in d.regulated_states]
    ei = [names.index(s) for s in d.estimated_states]
    # regulator: ZOH on the regulated states and actuated inputs, the continuous cost integrated over a period
    nr, m = len(ri), len(ui)
    F = np.zeros((nr + m, nr + m))
    F[:nr, :nr], F[:nr, nr:] = A[np.ix_(ri, ri)], B[np.ix_(ri, ui)]
    W = np.zeros_like(F)
    W[:nr, :nr], W[nr:, nr:] = d.Q, d.R
    Phi = expm(F * T)
    Ard, Brd = Phi[:nr, :nr], Phi[:nr, nr:]
    Wd = _van_loan(F, W, T)
    try:
        Kr, _, Er = control.dlqr(Ard, Brd, Wd[:nr, :nr], Wd[nr:, nr:], Wd[:nr, nr:])
    except Exception as exc:  # python-control raises several types
        raise SolverError(f"sampled LQR design (period {T:g} s) failed: {exc}") from exc
    Kr, Er = np.asarray(Kr, dtype=float), np.asarray(Er)
    if not (np.all(np.isfinite(Kr)) and np.max(np.abs(Er)) < 1.0):
        raise SolverError(f"the sampled LQR (period {T:g} s) does not stabilize the discretized linearization "
                          f"(poles {np.round(Er, 6)})")
    K = np.zeros_like(np.asarray(d.K, dtype=float))
    K[np.ix_(ui, ri)] = Kr
    # Kalman filter: ZOH on the estimated states, process noise integrated over a period, R_d per sample
    ne = len(ei)
    nu = B.shape[1]
    Fe = np.zeros((ne + nu, ne + nu))
    Fe[:ne, :ne], Fe[:ne, ne:] = A[np.ix_(ei, ei)], B[ei]
    Phe = expm(Fe * T)
    Ad, Bd = Phe[:ne, :ne], Phe[:ne, ne:]
    Qd = _van_loan(A[np.ix_(ei, ei)].T, np.asarray(d.process_noise, dtype=float), T)
    Ce = C[:, ei]
    Rd = np.diag(np.asarray(d.noise, dtype=float) ** 2)
    try:
        P = solve_discrete_are(Ad.T, Ce.T, Qd, Rd)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"sampled Kalman-filter design (period {T:g} s) failed for sensors "
                          f"{list(d.sensors.names)}: {exc}") from exc
    Mg = np.linalg.solve(Ce @ P @ Ce.T + Rd, Ce @ P).T
    Ee = np.linalg.eigvals(Ad @ (np.eye(ne) - Mg @ Ce))
    if not (np.all(np.isfinite(Mg)) and np.max(np.abs(Ee)) < 1.0):
        raise SolverError(f"the sampled Kalman filter (period {T:g} s) is not stable (poles {np.round(Ee, 6)})")
    return SampledLQG(d, T, K, Mg, Ad, Bd, np.asarray(Er), Ee)


@dataclass(frozen=True, eq=False)
class PlantWithEstimator:
    """The plant of an :class:`LQGController` with its estimator: states plant then ``<state>_hat``; inputs the plant's.

    ``rhs(x, u)`` stacks the plant's right-hand side and the Kalman filter fed with the plant's sensor values and
    ``u``; :attr:`law` is the controller's ``u`` from the estimate (for
    :class:`~glidectl.models.closed_loop.ClosedLoop`).

    Parameters
    ----------
    controller : LQGController

    Raises
    ------
    ArgumentTypeError
        If ``controller`` is not an :class:`LQGController`.
    """

    controller: LQGController

    def __post_init__(self) -> None:
        if not isinstance(self.controller, LQGController):
            raise ArgumentTypeError(f"controller must be an LQGController (from gc.lqg_glide), got "
                                    f"{type(self.controller).__name__}")

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.controller.state_names + self.controller.estimator_state_names

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(self.controller.plant.input_labels)

    @property
    def vehicle(self) -> Vehicle:
        return self.controller.vehicle

    def law(self, x: Any) -> np.ndarray:
        """``u`` from the estimate part of ``x`` (shape ``(..., n + ne)``)."""
        return self.controller.u_from_estimate(np.asarray(x)[..., len(self.controller.state_names):])

    def rhs(self, x: Any, u: Any) -> np.ndarray:
        """Derivative of plant and estimate for states ``x`` (``(..., n + ne)``) and inputs ``u`` (``(..., 3)``)."""
        c = self.controller
        x = trailing_array("x", x, len(self.state_names), self.state_names)
        n = len(c.state_names)
        xp, xh = x[..., :n], x[..., n:]
        u = np.asarray(u)
        model = c._data()[0]
        dp = np.asarray(model.rhs(xp, u))
        dh = c.estimator_rhs(xh, c.sensors(model, xp), u)
        return np.concatenate([dp, np.broadcast_to(dh, dp.shape[:-1] + dh.shape[-1:])], axis=-1)


def _noise(sensors: OutputMap, noise: Any) -> np.ndarray:
    if not isinstance(noise, Mapping):
        raise ArgumentTypeError(f"noise must be a mapping {{sensor: standard deviation}} over {list(sensors.names)}, "
                                f"got {type(noise).__name__}")
    unknown = [k for k in noise if k not in sensors.names]
    if unknown:
        raise ArgumentError(f"noise names {unknown}, which are not sensors; sensors: {list(sensors.names)}")
    missing = [k for k in sensors.names if k not in noise]
    if missing:
        raise ArgumentError(f"noise has no standard deviation for sensors {missing}; give one (> 0, sensor units) "
                            "for every sensor")
    return np.array([checks.positive(f"noise[{k!r}]", noise[k]) for k in sensors.names])


def _unobservable(A: np.ndarray, C: np.ndarray, names: Sequence[str]) -> list[str]:
    """Undetectable modes (Re >= 0) of ``(A, C)`` (PBH on the pair), each in state terms as
    :func:`~glidectl.analysis.linear.observability` names it."""
    n = A.shape[0]
    scale = max(np.linalg.norm(np.vstack([A, C]), 2), 1.0)
    bad = []
    for lam in np.linalg.eigvals(A):
        if lam.real < -1e-9 * scale:
            continue
        if np.linalg.svd(np.vstack([A - lam * np.eye(n), C]), compute_uv=False)[-1] / scale < 1e-8:
            bad.append(complex(np.round(lam, 9)))
    if not bad:
        return []
    outs = [f"y{i}" for i in range(C.shape[0])]
    named = observability(control.ss(A, np.zeros((n, 1)), C, 0, states=list(names), outputs=outs), outs).mode_states
    found = [str(m) for m in named if m.eigenvalue.real >= -1e-9 * scale]
    return found or [f"{lam.real:.4g}{lam.imag:+.4g}i" for lam in dict.fromkeys(bad)]


def lqg_glide(veh: Vehicle, glide: SteadyGlide, sensors: Any, noise: Mapping[str, float], *,
              inputs: Literal["force", "acceleration"] = "force", process_noise: Mapping[str, float] | None = None,
              actuate: Sequence[str] | None = None, Q: Any = None, R: Any = None,
              max_deviation: Mapping[str, float] | None = None, reduce_fixed: bool = True) -> LQGController:
    """LQG output feedback to a steady glide from named sensors: :func:`control.lqr` gain on a :func:`control.lqe`
    (stationary Kalman filter) estimate.

    Parameters
    ----------
    veh : Vehicle
        The underwater glider the glide was trimmed for.
    glide : SteadyGlide
        From :func:`~glidectl.trim.glide.steady_glide`.
    sensors : str, sequence of str or mapping
        Measured outputs, as ``outputs`` of :func:`~glidectl.analysis.linear.linearize_glide`: states, ``"z"``
        (depth, m), ``"depth_rate"`` (m/s) or named linear combinations, e.g. ``("z", "theta", "Omega2")``.
    noise : mapping of str to float
        Standard deviation of each sensor's white noise (sensor units, > 0): ``RN = diag(noise^2)``.
    inputs : {"force", "acceleration"}
        Input form of the model (see :func:`~glidectl.controllers.linear.lqr_glide`).
    process_noise : mapping of str to float, optional
        Intensity (state units per square root of a second) of the white process noise on each estimated state:
        ``QN = diag(process_noise^2)``; default :data:`PROCESS_NOISE_FRACTION` times the state's Bryson scale.
    actuate : sequence of str, optional
        Inputs to design on (as :func:`~glidectl.controllers.linear.lqr_glide`; default all but those moving a
        ``fixed`` actuator of the vehicle file).
    Q, R : array_like, optional
        LQR weights on the design model's glide-path states and inputs (or in full, 10x10 and 3x3, restricted to
        the design model's), restricted to the regulated states and actuated inputs; default Bryson's rule.
    max_deviation : mapping of str to float, optional
        Overrides of :data:`~glidectl.controllers.linear.DEFAULT_MAX_DEVIATION` for Bryson's rule and the default
        process noise.
    reduce_fixed : bool
        Design on the model without the states and inputs of the actuators the vehicle file fixes (default; as
        :func:`~glidectl.controllers.linear.lqr_glide`): the estimator and the closed loop have no pole at 0 for a
        part that never moves. False: the full model (a fixed actuator's states are locked, not estimated).

    Returns
    -------
    LQGController
        Gains, poles of regulator and estimator, the sensors and noise used; usable through
        :meth:`LQGController.closed_loop` / :func:`glidectl.closed_loop` (plant plus estimator, for
        :func:`glidectl.simulate`) and :meth:`LQGController.to_iosys`.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a SteadyGlide, ``sensors`` not names or a mapping, ``noise`` or
        ``process_noise`` not a mapping of names to real numbers, or ``Q``/``R`` not real arrays.
    ArgumentError
        If ``sensors`` is empty or names an unknown channel; ``noise`` misses a sensor, names an unknown one or gives
        a value that is not positive and finite; ``process_noise`` names a state that is not estimated or gives a
        value that is not positive; ``actuate``, ``Q``, ``R`` or ``max_deviation`` are invalid (as
        :func:`~glidectl.controllers.linear.lqr_glide`); or the estimated states are not detectable from the
        sensors (the message names the unobservable modes and their dominant states).
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.
    SolverError
        If the LQR or Kalman-filter design fails or returns gains that do not stabilize.

    Examples
    --------
    >>> import math
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> glide = gc.steady_glide(veh, 0.3, math.radians(-45), r_p3=0.05)
    >>> sensors = ("z", "theta", "r_P1", "r_P3", "m0")
    >>> ctrl = gc.lqg_glide(veh, glide, sensors, noise=dict.fromkeys(sensors, 1e-3))
    >>> ctrl.L.shape, bool(ctrl.estimator_poles.real.max() < 0)
    ((10, 5), True)
    """
    check_glide_design(veh, glide, inputs)
    checks.boolean("reduce_fixed", reduce_fixed)
    fixed = fixed_actuators(veh) if reduce_fixed else ()
    full_states = glide_model(veh, glide, inputs)[0].state_names
    dropped = {q for a in fixed for q in FIXED_ACTUATOR_STATES[inputs][a][0]}
    path_states = tuple(q for q in full_states if q not in dropped)
    smap = output_map(sensors, path_states)
    sig = _noise(smap, noise)
    sys = linearize_glide(veh, glide, inputs, outputs={k: dict(zip(smap.channels, row, strict=True))
                                                      for k, row in zip(smap.names, smap.M, strict=True)},
                          reduce_fixed=reduce_fixed)
    if max_deviation is not None and not isinstance(max_deviation, Mapping):
        raise ArgumentTypeError(f"max_deviation must be a mapping of state/input names to deviations, got "
                                f"{type(max_deviation).__name__}")
    known = set(sys.state_labels) | set(sys.input_labels) | set(full_states) | set(
        glide_model(veh, glide, inputs)[0].input_names)
    extra = dict(max_deviation or {})
    unknown = sorted(str(k) for k in extra if k not in known)
    if unknown:
        raise ArgumentError(f"max_deviation names {unknown}, which are not states or inputs of this design; known: "
                            f"{sorted(known)}")
    dev = {**DEFAULT_MAX_DEVIATION, **{k: checks.positive(f"max_deviation[{k!r}]", v) for k, v in extra.items()}}
    names = list(sys.state_labels)
    act, ui, _, locked = actuated_subset(sys, veh, inputs, actuate)
    measured = set(smap.channels)
    est = [s for s in names if s not in locked and (s not in ("z_prime", "z") or s in measured)]
    reg = [s for s in est if s != "z"]
    # regulator
    A, B, C = np.asarray(sys.A), np.asarray(sys.B), np.asarray(sys.C)
    n10 = len(path_states)
    Qp = bryson_weights(path_states, dev) if Q is None else design_weight("Q", Q, path_states, full_states,
                                                                          definite=False)
    Qm = np.zeros((len(names), len(names)))
    Qm[:n10, :n10] = Qp
    full_inputs = glide_model(veh, glide, inputs)[0].input_names
    Rm = bryson_weights(sys.input_labels, dev) if R is None else design_weight("R", R, sys.input_labels, full_inputs,
                                                                               definite=True)
    ri = [names.index(s) for s in reg]
    K, Ereg = lqr_subset(A, B, Qm, Rm, ui, ri, f"glide gamma = {np.degrees(glide.gamma):.2f} deg with inputs "
                         f"{list(act)} on states {reg}")
    Ereg = np.linalg.eigvals((A - B @ K)[np.ix_(ri, ri)])
    # estimator
    ei = [names.index(s) for s in est]
    Ae, Ce = A[np.ix_(ei, ei)], C[:, ei]
    bad = _unobservable(Ae, Ce, est)
    if bad:
        modes = ", ".join(bad)
        raise ArgumentError(f"the sensors {list(smap.names)} cannot detect the estimated states {est}: modes {modes} "
                            "are unobservable and not stable; add a sensor that sees them (e.g. the moving-mass "
                            "position r_P1 or r_P3, or m0) or leave an input out with actuate= (its actuator is then "
                            "held)")
    if process_noise is None:
        qn = np.array([PROCESS_NOISE_FRACTION * dev[s] for s in est])
    else:
        if not isinstance(process_noise, Mapping):
            raise ArgumentTypeError(f"process_noise must be a mapping {{state: intensity}} over {est}, got "
                                    f"{type(process_noise).__name__}")
        unknown = [k for k in process_noise if k not in est]
        if unknown:
            raise ArgumentError(f"process_noise names {unknown}, which are not estimated states; estimated: {est}")
        qn = np.array([checks.positive(f"process_noise[{s!r}]", process_noise[s]) if s in process_noise
                       else PROCESS_NOISE_FRACTION * dev[s] for s in est])
    QN, RN = np.diag(qn**2), np.diag(sig**2)
    try:
        L, _, Eest = control.lqe(Ae, np.eye(len(ei)), Ce, QN, RN)
    except Exception as exc:  # python-control raises several types
        raise SolverError(f"Kalman-filter design failed for sensors {list(smap.names)}: {exc}") from exc
    L, Eest = np.asarray(L, dtype=float), np.asarray(Eest)
    if not (np.all(np.isfinite(L)) and np.max(Eest.real) < 0):
        raise SolverError(f"the Kalman filter from {list(smap.names)} is not stable (poles {np.round(Eest, 6)})")
    return LQGController(K, L, sys, glide, inputs, smap, sig, QN, Qm[np.ix_(ri, ri)], Rm[np.ix_(ui, ui)],
                         Ereg, Eest, tuple(est), tuple(reg), act, locked, vehicle=veh, fixed_actuators=fixed)
