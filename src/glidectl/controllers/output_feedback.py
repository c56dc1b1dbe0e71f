"""Output feedback about a steady glide: an LQR gain on a Kalman-filter estimate (LQG), from named sensors.

:func:`lqg_glide` designs, on the linearization of :func:`~glidectl.analysis.linear.linearize_glide` with the
sensors as outputs, an LQR gain (:func:`control.lqr`, on the actuated inputs) and a stationary Kalman-filter gain
(:func:`control.lqe`) from the sensor noise levels. The result, :class:`LQGController`, is a dynamic controller with
an explicit estimator state:

* :meth:`LQGController.closed_loop` (and :func:`glidectl.closed_loop`) gives the input-free model whose state is the
  nonlinear plant's followed by the estimate (names ``<state>_hat``), for :func:`glidectl.simulate`;
* :meth:`LQGController.to_iosys` gives the controller alone as a :class:`control.NonlinearIOSystem` (sensors in,
  inputs out), for python-control interconnections.

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
from ..analysis.linear import DepthGlidePathModel, OutputMap, glide_model, linearize_glide, output_map
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
    lqr_subset,
    symmetric_weight,
)

__all__ = ["LQGController", "PlantWithEstimator", "lqg_glide"]

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
    K : ndarray, shape (3, n)
        Regulator gain on the plant state (zero rows for inputs not actuated, zero columns for states not regulated).
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
        model : GlidePathModel or DepthGlidePathModel
        xe : ndarray, shape (n,)
        """
        model, xe = glide_model(self.vehicle, self.glide, self.inputs)  # type: ignore[arg-type]
        if "z" in self.state_names:
            return DepthGlidePathModel(model), np.concatenate([xe, [0.0]])
        return model, xe

    def _data(self) -> tuple[Any, np.ndarray, list[int], np.ndarray, np.ndarray]:
        cache = self.__dict__.get("_cache")
        if cache is None:
            model, xe = self.plant_model()
            ei = [self.state_names.index(s) for s in self.estimated_states]
            drift = np.zeros(len(ei))
            if "z" in self.estimated_states:
                drift[self.estimated_states.index("z")] = np.real(model.rhs(xe, np.zeros(3)))[-1]
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


def _unobservable(A: np.ndarray, C: np.ndarray, names: Sequence[str]) -> list[tuple[complex, str]]:
    """Undetectable modes (Re >= 0) and the dominant state of each (PBH on the state-scaled pair)."""
    n = A.shape[0]
    scale = max(np.linalg.norm(np.vstack([A, C]), 2), 1.0)
    out: list[tuple[complex, str]] = []
    for lam in np.linalg.eigvals(A):
        if lam.real < -1e-9 * scale:
            continue
        M = np.vstack([A - lam * np.eye(n), C])
        _, s, vh = np.linalg.svd(M)
        if s[-1] / scale < 1e-8:
            item = (complex(np.round(lam, 9)), names[int(np.argmax(np.abs(vh[-1])))])
            if item not in out:
                out.append(item)
    return out


def lqg_glide(veh: Vehicle, glide: SteadyGlide, sensors: Any, noise: Mapping[str, float], *,
              inputs: Literal["force", "acceleration"] = "force", process_noise: Mapping[str, float] | None = None,
              actuate: Sequence[str] | None = None, Q: Any = None, R: Any = None,
              max_deviation: Mapping[str, float] | None = None) -> LQGController:
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
        LQR weights, given in full (10x10 on the glide-path states, 3x3) and restricted to the regulated states and
        actuated inputs; default Bryson's rule.
    max_deviation : mapping of str to float, optional
        Overrides of :data:`~glidectl.controllers.linear.DEFAULT_MAX_DEVIATION` for Bryson's rule and the default
        process noise.

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
    """
    check_glide_design(veh, glide, inputs)
    path_states = glide_model(veh, glide, inputs)[0].state_names
    smap = output_map(sensors, path_states)
    sig = _noise(smap, noise)
    sys = linearize_glide(veh, glide, inputs, outputs={k: dict(zip(smap.channels, row, strict=True))
                                                      for k, row in zip(smap.names, smap.M, strict=True)})
    if max_deviation is not None and not isinstance(max_deviation, Mapping):
        raise ArgumentTypeError(f"max_deviation must be a mapping of state/input names to deviations, got "
                                f"{type(max_deviation).__name__}")
    known = set(sys.state_labels) | set(sys.input_labels)
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
    Qp = bryson_weights(path_states, dev) if Q is None else symmetric_weight("Q", Q, n10, definite=False)
    Qm = np.zeros((len(names), len(names)))
    Qm[:n10, :n10] = Qp
    Rm = bryson_weights(sys.input_labels, dev) if R is None else symmetric_weight("R", R, 3, definite=True)
    ri = [names.index(s) for s in reg]
    K, Ereg = lqr_subset(A, B, Qm, Rm, ui, ri, f"glide gamma = {np.degrees(glide.gamma):.2f} deg with inputs "
                         f"{list(act)} on states {reg}")
    Ereg = np.linalg.eigvals((A - B @ K)[np.ix_(ri, ri)])
    # estimator
    ei = [names.index(s) for s in est]
    Ae, Ce = A[np.ix_(ei, ei)], C[:, ei]
    bad = _unobservable(Ae, Ce, est)
    if bad:
        modes = ", ".join(f"{lam.real:.3g}{lam.imag:+.3g}i (mostly {s})" for lam, s in bad)
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
                         Ereg, Eest, tuple(est), tuple(reg), act, locked, vehicle=veh)
