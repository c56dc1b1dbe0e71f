"""Linear glide-path controllers: LQR and pole placement (python-control) and the decoupled acceleration
feedback (2.37) of §2.3.2.

Controllers are frozen objects; ``controller(t, x)`` returns the input for a state of the *full* longitudinal model
(force form ``(x, z, theta, ...)`` or acceleration form), so they plug into :func:`glidectl.sim.simulate`.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import control
import numpy as np
from scipy.optimize import linear_sum_assignment

from .. import checks
from ..analysis.linear import FIXED_ACTUATOR_STATES, fixed_actuators, linearize_glide
from ..errors import ArgumentError, ArgumentTypeError, SolverError, VehicleMismatchError
from ..models._validate import numeric_array, require_glider, require_instance, trailing_array
from ..models.longitudinal import ACCEL_INPUTS, ACCEL_STATES, FORCE_INPUTS, FORCE_STATES
from ..params import Vehicle
from ..trim.glide import SteadyGlide

__all__ = [
    "ACTUATOR_OF_INPUT",
    "DEFAULT_MAX_DEVIATION",
    "LOCKED_STATES",
    "DecoupledAccelerationFeedback",
    "LinearGlideController",
    "decoupled_gain_matrix",
    "default_actuate",
    "design_weight",
    "lqr_glide",
    "lqr_subset",
    "place_glide",
]

#: Bryson's-rule scales: acceptable deviation of each state / input (SI units) for the default LQR weights.
DEFAULT_MAX_DEVIATION: Mapping[str, float] = {
    "z_prime": 0.5, "theta": 0.1, "Omega2": 0.2, "v1": 0.05, "v3": 0.05, "r_P1": 0.02, "r_P3": 0.02,
    "P_P1": 0.1, "P_P3": 0.1, "m0": 0.1, "rdot_P1": 0.02, "rdot_P3": 0.02,
    "u1": 1.0, "u3": 1.0, "u4": 0.05, "w1": 0.1, "w3": 0.1, "w4": 0.05, "z": 0.5,
}

#: States an input holds when it is left out of a design (``actuate``): the buoyancy rate ``u4``/``w4`` integrates to
#: ``m0``; the mass accelerations ``w1``/``w3`` to ``(r_P, rdot_P)``; the mass forces ``u1``/``u3`` to the momenta
#: ``P_P`` (in the force form the mass itself still moves with the hull: to hold a mass axis, design in the
#: acceleration form). These states are uncontrollable (poles at 0) without their input and are left out of the design.
LOCKED_STATES: Mapping[str, tuple[str, ...]] = {
    "u1": ("P_P1",), "u3": ("P_P3",), "u4": ("m0",),
    "w1": ("r_P1", "rdot_P1"), "w3": ("r_P3", "rdot_P3"), "w4": ("m0",),
}

#: Actuator of the vehicle file moved by each input (a ``fixed`` actuator removes it from the default ``actuate``).
ACTUATOR_OF_INPUT: Mapping[str, str] = {"u1": "r_P1", "u3": "r_P3", "u4": "m0", "w1": "r_P1", "w3": "r_P3",
                                        "w4": "m0"}


@dataclass(frozen=True)
class LinearGlideController:
    """State feedback ``u = u_e - K (x_r - x_r,e)`` about a steady glide, on the glide-path state ``x_r``.

    Actuator limits: this law does not saturate its own commands. Run it through
    :class:`~glidectl.models.actuated.ActuatedGlider` (:func:`glidectl.sim.simulate_actuated`,
    :func:`glidectl.controllers.dive_cycle.dive_cycle`) to have the vehicle's ``[actuators]`` ranges and rates
    enforced; :func:`glidectl.sim.simulate` on the plain model applies no limits.

    Attributes
    ----------
    K : ndarray, shape (m, n)
        Gain of the design model's inputs on its states ``(z_prime, theta, ...)`` (SI units): ``3 x 10`` for a
        vehicle without fixed actuators; the states and input of a fixed actuator are not in it
        (:attr:`fixed_actuators`).
    method : str
        ``"lqr"`` or ``"place"``.
    plant : control.StateSpace
        Open-loop linearization the gain was designed on (:func:`~glidectl.analysis.linear.linearize_glide`).
    closed_loop_poles : ndarray
        Eigenvalues of ``A - B K`` (1/s).
    glide : SteadyGlide
        The glide (and path, through ``glide.gamma``) regulated to.
    inputs : {"force", "acceleration"}
    Q, R : ndarray or None
        LQR weights (None for placement).
    path_offset : float
        Distance (m) of the regulated path from the glide path through the origin (``z'`` of the law is
        ``z' - path_offset``).
    vehicle : Vehicle or None
        The vehicle the gain was designed for (set by :func:`lqr_glide` and :func:`place_glide`; the plant of
        :func:`glidectl.closed_loop`).
    actuate : tuple of str
        The inputs the gain drives (``()``: all); the rows of ``K`` of the other inputs are exactly zero.
    locked_states : tuple of str
        States held by the inputs left out (:data:`LOCKED_STATES`), left out of the design: their columns of ``K``
        are zero and each adds a closed-loop pole at 0 (the actuator stays where it is).
    fixed_actuators : tuple of str
        Actuators the vehicle file fixes, removed from the design model with their states and inputs
        (:class:`~glidectl.analysis.linear.FixedActuatorModel`); ``()`` for the full model (``reduce_fixed=False``,
        or a vehicle without fixed actuators).

    Raises
    ------
    ArgumentTypeError
        If ``glide`` is not a SteadyGlide, ``plant`` not a state-space model, or a number has the wrong type.
    ArgumentError
        If ``method`` or ``inputs`` is unknown, ``K`` is not a finite (inputs x states) array, ``path_offset``
        is not finite, ``actuate`` / ``locked_states`` name an unknown input / state, or ``fixed_actuators`` does
        not match the plant's states.
    ModelError
        If ``vehicle`` is not an underwater glider.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle than ``vehicle``.
    """

    K: np.ndarray
    method: str
    plant: control.StateSpace
    closed_loop_poles: np.ndarray
    glide: SteadyGlide
    inputs: str
    Q: np.ndarray | None = None
    R: np.ndarray | None = None
    path_offset: float = 0.0
    vehicle: Vehicle | None = field(default=None, repr=False, compare=False)
    actuate: tuple[str, ...] = ()
    locked_states: tuple[str, ...] = ()
    fixed_actuators: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        checks.choice("method", self.method, ("lqr", "place"))
        checks.choice("inputs", self.inputs, ("force", "acceleration"))
        require_instance("glide", self.glide, SteadyGlide, " (from gc.steady_glide)")
        if not (hasattr(self.plant, "A") and hasattr(self.plant, "B") and hasattr(self.plant, "state_labels")):
            raise ArgumentTypeError(f"plant must be a control.StateSpace (from gc.linearize_glide), got "
                                    f"{type(self.plant).__name__}")
        n, m = np.asarray(self.plant.B).shape
        K = checks.array("K", self.K, shape=(m, n))
        object.__setattr__(self, "K", K)
        object.__setattr__(self, "path_offset", checks.real("path_offset", self.path_offset, unit="m"))
        for attr, labels in (("actuate", self.plant.input_labels), ("locked_states", self.plant.state_labels)):
            val = getattr(self, attr)
            if isinstance(val, str) or not isinstance(val, Sequence) or any(q not in labels for q in val):
                raise ArgumentError(f"{attr} must be a sequence of names from {list(labels)}, got {val!r}")
            object.__setattr__(self, attr, tuple(val))
        fixed = self.fixed_actuators
        if isinstance(fixed, str) or not isinstance(fixed, Sequence) or \
                any(a not in FIXED_ACTUATOR_STATES[self.inputs] for a in fixed):
            raise ArgumentError(f"fixed_actuators must be a sequence of names from ('r_P1', 'r_P3', 'm0'), got "
                                f"{fixed!r}")
        object.__setattr__(self, "fixed_actuators", tuple(fixed))
        path_names = ("z_prime", *(FORCE_STATES if self.inputs == "force" else ACCEL_STATES)[2:])
        removed = {q for a in self.fixed_actuators for q in FIXED_ACTUATOR_STATES[self.inputs][a][0]}
        kept = tuple(q for q in path_names if q not in removed)
        if kept != tuple(self.plant.state_labels):
            raise ArgumentError(f"the plant's states {list(self.plant.state_labels)} are not the glide-path states "
                                f"without the fixed actuators {list(self.fixed_actuators)}: {list(kept)}")
        object.__setattr__(self, "_keep", [path_names.index(q) for q in kept] if removed else None)
        if self.vehicle is not None:
            require_glider(self.vehicle)
            checks.same_vehicle("glide", self.glide, self.vehicle)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(self.plant.state_labels)

    def reduced_state(self, x: Any) -> np.ndarray:
        """Full state (x, z, ...) (shape ``(..., 11)``) -> design-model state (z', ...) with
        ``z' = sin(g_e) x + cos(g_e) z - offset`` (without the states of :attr:`fixed_actuators`)."""
        x = checks.array("x", x)
        trailing_array("x", x, 11)
        zp = np.sin(self.glide.gamma) * x[..., 0] + np.cos(self.glide.gamma) * x[..., 1] - self.path_offset
        xr = np.concatenate([zp[..., None], x[..., 2:]], axis=-1)
        return xr if self._keep is None else xr[..., self._keep]

    def equilibrium(self) -> np.ndarray:
        """Design-model equilibrium state (z' = 0)."""
        xe = self.glide.force_state() if self.inputs == "force" else self.glide.accel_state()
        xr = np.concatenate([[0.0], xe[2:]])
        return xr if self._keep is None else xr[self._keep]

    def u(self, x: Any) -> np.ndarray:
        """Input (u1, u3, u4) or (w1, w3, w4) for full states ``x`` (shape ``(..., 11)``); the input of a fixed
        actuator is zero (in the acceleration form it holds the actuator; in the force form simulate
        :func:`glidectl.closed_loop`, whose model holds the mass by its constraint force)."""
        v = -(self.reduced_state(x) - self.equilibrium()) @ self.K.T
        if self._keep is None:
            return v
        names = FORCE_INPUTS if self.inputs == "force" else ACCEL_INPUTS
        out = np.zeros((*v.shape[:-1], 3))
        out[..., [names.index(q) for q in self.plant.input_labels]] = v
        return out

    def path_input(self, xr: Any) -> np.ndarray:
        """Input of the design model (:attr:`plant`'s inputs) for its states ``xr = (z', theta, ...)``
        (:func:`~glidectl.analysis.linear.design_model`: the glide-path model, shape ``(..., 10)``, without the states
        of :attr:`fixed_actuators`; ``z'`` in m from the path through the origin, so the law regulates
        ``z' = path_offset``)."""
        xr = trailing_array("xr", xr, len(self.state_names), self.state_names)
        zp = xr[..., :1] - self.path_offset
        return -(np.concatenate([zp, xr[..., 1:]], axis=-1) - self.equilibrium()) @ self.K.T

    def __call__(self, t: float, x: Any) -> np.ndarray:
        """Input (u1, u3, u4) or (w1, w3, w4) for full state ``x`` at time ``t`` (s)."""
        return self.u(x)

    def closed_loop(self) -> control.StateSpace:
        """Linear closed loop ``A - B K`` with the plant's state names."""
        A, B = np.asarray(self.plant.A), np.asarray(self.plant.B)
        n = A.shape[0]
        return control.ss(A - B @ self.K, np.zeros((n, 1)), np.eye(n), 0, states=list(self.state_names),
                          outputs=list(self.state_names), name=f"{self.method}_closed_loop")


def bryson_weights(names: Sequence[str], max_dev: Mapping[str, float]) -> np.ndarray:
    """Bryson's-rule weight ``diag(1 / max_dev[name]^2)`` for ``names`` (inverse squared units of each)."""
    return np.diag([1.0 / max_dev[n] ** 2 for n in names])


def check_glide_design(veh: Any, glide: Any, inputs: Any) -> None:
    """Checks shared by :func:`lqr_glide`, :func:`place_glide` and
    :func:`~glidectl.controllers.output_feedback.lqg_glide`, before anything is computed.

    Raises
    ------
    ArgumentTypeError, ArgumentError, VehicleMismatchError, ModelError
        As those functions.
    """
    require_glider(veh, "veh")
    require_instance("glide", glide, SteadyGlide, " (from gc.steady_glide)")
    checks.same_vehicle("glide", glide, veh)
    checks.choice("inputs", inputs, ("force", "acceleration"))


def default_actuate(veh: Vehicle, inputs: Literal["force", "acceleration"] = "force") -> tuple[str, ...]:
    """Inputs a design drives by default: all of them, except those moving an actuator the vehicle file fixes.

    Parameters
    ----------
    veh : Vehicle
        The underwater glider; its ``[actuators]`` table (``fixed = ...`` entries) is read.
    inputs : {"force", "acceleration"}
        Input form: ``(u1, u3, u4)`` or ``(w1, w3, w4)``.

    Returns
    -------
    tuple of str
        The inputs whose actuator (:data:`ACTUATOR_OF_INPUT`: ``r_P1``, ``r_P3``, ``m0``) is not fixed; all three
        for a vehicle without an ``[actuators]`` table.

    Raises
    ------
    ArgumentError
        If ``inputs`` is not ``"force"`` or ``"acceleration"``.

    Examples
    --------
    >>> import glidectl as gc
    >>> gc.default_actuate(gc.load_vehicle("rogue"))
    ('u1', 'u3', 'u4')
    >>> gc.default_actuate(gc.load_vehicle("slocum_shallow"), "acceleration")   # its file fixes r_P3
    ('w1', 'w4')
    """
    checks.choice("inputs", inputs, ("force", "acceleration"))
    names = ("u1", "u3", "u4") if inputs == "force" else ("w1", "w3", "w4")
    acts = getattr(veh, "actuators", {}) or {}
    return tuple(q for q in names if getattr(acts.get(ACTUATOR_OF_INPUT[q]), "fixed", None) is None)


def actuated_subset(sys: control.StateSpace, veh: Vehicle, inputs: str, actuate: Any
              ) -> tuple[tuple[str, ...], list[int], list[int], tuple[str, ...]]:
    """Selected inputs, their indices, the indices of the design states and the locked states
    (:data:`LOCKED_STATES` of the inputs left out).

    Raises
    ------
    ArgumentTypeError
        If ``actuate`` is not a sequence of names.
    ArgumentError
        If ``actuate`` is empty, names an unknown input or one twice, or (default) the file fixes every actuator.
    """
    labels = list(sys.input_labels)
    if actuate is None:
        act = default_actuate(veh, inputs)  # type: ignore[arg-type]
        if not act:
            fixed = ", ".join(ACTUATOR_OF_INPUT[q] for q in labels)
            raise ArgumentError(f"the vehicle file fixes every actuator ({fixed}"
                                "): nothing to design on; remove a 'fixed' entry or pass actuate=")
    else:
        if isinstance(actuate, str):
            actuate = (actuate,)
        if not isinstance(actuate, Sequence) or not all(isinstance(q, str) for q in actuate):
            raise ArgumentTypeError(f"actuate must be a sequence of input names from {labels}, got {actuate!r}")
        act = tuple(actuate)
        if not act:
            raise ArgumentError(f"actuate is empty; name at least one input of {labels} (or None for the default)")
        bad = [q for q in act if q not in labels]
        held = [q for q in bad if q in ACTUATOR_OF_INPUT and q[0] == ("u" if inputs == "force" else "w")]
        if held:
            raise ArgumentError(f"actuate names {held}, which move{'s' if len(held) == 1 else ''} "
                                f"{[ACTUATOR_OF_INPUT[q] for q in held]}, fixed by the vehicle file and removed from "
                                f"the design model (inputs: {labels}); pass reduce_fixed=False to design on the "
                                "full model")
        if bad:
            raise ArgumentError(f"actuate names {bad}, which are not inputs of the {inputs} form; inputs: {labels}")
        if len(set(act)) != len(act):
            raise ArgumentError(f"actuate {list(act)} names an input twice")
    ui = [labels.index(q) for q in labels if q in act]
    locked = tuple(s for q in labels if q not in act for s in LOCKED_STATES[q])
    si = [i for i, s in enumerate(sys.state_labels) if s not in locked]
    return tuple(labels[i] for i in ui), ui, si, locked


def symmetric_weight(name: str, value: Any, n: int, *, definite: bool) -> np.ndarray:
    """A symmetric ``n x n`` weight, positive semidefinite (``definite``: positive definite).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``value`` is not a finite real ``n x n`` array, not symmetric or not (semi)definite.
    """
    W = checks.array(name, value, shape=(n, n))
    if not np.allclose(W, W.T, rtol=1e-12, atol=1e-12 * max(1.0, float(np.max(np.abs(W))))):
        raise ArgumentError(f"{name} must be symmetric")
    ev = np.linalg.eigvalsh(0.5 * (W + W.T))
    scale = max(1.0, float(np.max(np.abs(ev))))
    if (definite and not ev[0] > 1e-12 * scale) or ev[0] < -1e-12 * scale:
        raise ArgumentError(f"{name} must be positive {'definite' if definite else 'semidefinite'}; its smallest "
                            f"eigenvalue is {ev[0]:.3g}")
    return W


def design_weight(name: str, value: Any, names: Sequence[str], full_names: Sequence[str], *,
                  definite: bool) -> np.ndarray:
    """A weight given on the design model's channels ``names``, or on every channel ``full_names`` of the full model
    (then restricted to ``names``: the channels of fixed actuators are dropped), as :func:`symmetric_weight`.

    Raises
    ------
    ArgumentTypeError, ArgumentError
        As :func:`symmetric_weight`, for the size of either model.
    """
    names, full_names = list(names), list(full_names)
    if names != full_names and np.shape(value) == (len(full_names), len(full_names)):
        W = symmetric_weight(name, value, len(full_names), definite=definite)
        idx = [full_names.index(q) for q in names]
        return W[np.ix_(idx, idx)]
    return symmetric_weight(name, value, len(names), definite=definite)


def _full_names(sys: control.StateSpace, inputs: str, fixed: Sequence[str]) -> tuple[list[str], list[str]]:
    """States and inputs of the full glide-path model of ``sys`` (``sys`` without the fixed actuators)."""
    if not fixed:
        return list(sys.state_labels), list(sys.input_labels)
    states = ["z_prime", *(FORCE_STATES if inputs == "force" else ACCEL_STATES)[2:]]
    if "z" in sys.state_labels:
        states.append("z")
    return states, list(FORCE_INPUTS if inputs == "force" else ACCEL_INPUTS)


def lqr_glide(veh: Vehicle, glide: SteadyGlide, *, inputs: Literal["force", "acceleration"] = "force",
              Q: Any = None, R: Any = None, max_deviation: Mapping[str, float] | None = None,
              actuate: Sequence[str] | None = None, reduce_fixed: bool = True) -> LinearGlideController:
    """LQR regulator to the glide path of ``glide`` (z' included), designed with :func:`control.lqr`.

    Parameters
    ----------
    veh, glide : Vehicle, SteadyGlide
    inputs : {"force", "acceleration"}
    Q, R : array_like, optional
        Weights on the design model's state and input (or on the full model's 10 states and 3 inputs, restricted to
        the design model's); default Bryson's rule with ``max_deviation`` (default :data:`DEFAULT_MAX_DEVIATION`).
    max_deviation : mapping of str to float, optional
        Acceptable deviation of named states and inputs (SI units of each: m, rad, rad/s, m/s, kg m/s, kg, N,
        m/s^2, kg/s), overriding entries of :data:`DEFAULT_MAX_DEVIATION` for Bryson's rule
        (``Q_ii = 1 / max_i^2``).
    actuate : sequence of str, optional
        The inputs to design on (e.g. ``("w1", "w4")``); the others get exactly zero gain, and the states they
        hold (:data:`LOCKED_STATES`) are left out of the design (zero gain columns; ``Q``, ``R`` given in full are
        restricted to the rest). Default :func:`default_actuate`: every input, except those moving an actuator the
        vehicle's ``[actuators]`` table marks ``fixed`` (e.g. a fixed ``r_P3`` removes ``u3``/``w3``); a vehicle
        without the table keeps all three (the gains of the presets are unchanged).
    reduce_fixed : bool
        Design on the model without the fixed actuators' states and inputs (default;
        :func:`~glidectl.analysis.linear.linearize_glide`): the closed-loop poles are those of the states that move.
        False: the full model, where a fixed actuator's states are locked (a pole at 0 each).

    Returns
    -------
    LinearGlideController
        ``method = "lqr"``, gain ``K`` of shape (m, n) (the design model's inputs and states, 3 x 10 without fixed
        actuators; input units per glide-path-state unit; zero rows for inputs not actuated), the linearization it
        was designed on, the closed-loop poles (1/s, of ``A - B K``: the designed ones plus a 0 per locked state) and
        the weights used.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a SteadyGlide, ``max_deviation`` not a mapping of names to
        real numbers, or ``Q``/``R`` not real arrays.
    ArgumentError
        If ``inputs`` is not ``"force"`` or ``"acceleration"``; ``Q`` is not a finite symmetric positive
        semidefinite matrix or ``R`` a finite symmetric positive definite matrix of the design model's (or the full
        model's) size; ``max_deviation``
        names an unknown state or input or gives a value that is not a positive finite number; or ``actuate`` is
        empty, names an unknown input or one twice (or the vehicle file fixes every actuator).
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.
    SolverError
        If the LQR design fails (python-control's message is included; e.g. no stabilizing solution) or returns a
        gain that is not finite or does not stabilize the linearization.

    Examples
    --------
    >>> import math
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> glide = gc.steady_glide(veh, 0.3, math.radians(-45), r_p3=0.05)
    >>> ctrl = gc.lqr_glide(veh, glide)
    >>> ctrl.K.shape, ctrl.state_names[:3], bool(ctrl.closed_loop_poles.real.max() < 0)
    ((3, 10), ('z_prime', 'theta', 'Omega2'), True)
    """
    check_glide_design(veh, glide, inputs)
    if max_deviation is not None and not isinstance(max_deviation, Mapping):
        raise ArgumentTypeError(f"max_deviation must be a mapping of state/input names to deviations, got "
                                f"{type(max_deviation).__name__}")
    sys = linearize_glide(veh, glide, inputs, reduce_fixed=reduce_fixed)
    fixed = fixed_actuators(veh) if reduce_fixed else ()
    full_states, full_inputs = _full_names(sys, inputs, fixed)
    extra = dict(max_deviation or {})
    known = set(full_states) | set(full_inputs)
    unknown = sorted(str(k) for k in extra if k not in known)
    if unknown:
        raise ArgumentError(f"max_deviation names {unknown}, which are not states or inputs of this design; known: "
                            f"{sorted(known)}")
    for k, v in extra.items():
        extra[k] = checks.positive(f"max_deviation[{k!r}]", v)
    dev = {**DEFAULT_MAX_DEVIATION, **extra}
    Qm = bryson_weights(sys.state_labels, dev) if Q is None else design_weight("Q", Q, sys.state_labels, full_states,
                                                                               definite=False)
    Rm = bryson_weights(sys.input_labels, dev) if R is None else design_weight("R", R, sys.input_labels, full_inputs,
                                                                               definite=True)
    act, ui, si, locked = actuated_subset(sys, veh, inputs, actuate)
    K, E = lqr_subset(np.asarray(sys.A), np.asarray(sys.B), Qm, Rm, ui, si,
                      f"glide gamma = {np.degrees(glide.gamma):.2f} deg with inputs {list(act)}")
    return LinearGlideController(K, "lqr", sys, E, glide, inputs, Qm, Rm, vehicle=veh, actuate=act,
                                 locked_states=locked, fixed_actuators=fixed)


def lqr_subset(A: np.ndarray, B: np.ndarray, Q: np.ndarray, R: np.ndarray, ui: Sequence[int], si: Sequence[int],
               what: str) -> tuple[np.ndarray, np.ndarray]:
    """LQR gain (shape of ``B.T``) designed on inputs ``ui`` and states ``si`` only (zero elsewhere), and the poles
    of the full ``A - B K`` (1/s).

    Parameters
    ----------
    A, B : ndarray
        Linearization (n x n, n x m).
    Q, R : ndarray
        Full weights (n x n, m x m); restricted to ``si`` and ``ui``.
    ui, si : sequence of int
        Indices of the inputs and states designed on.
    what : str
        What is designed (for error messages).

    Returns
    -------
    K : ndarray, shape (m, n)
    poles : ndarray, shape (n,)

    Raises
    ------
    SolverError
        If :func:`control.lqr` fails or its gain does not stabilize the designed subsystem.
    """
    ix = np.ix_(si, si)
    try:
        Kr, _, Er = control.lqr(A[ix], B[np.ix_(si, ui)], Q[ix], R[np.ix_(ui, ui)])
    except Exception as exc:  # python-control raises several types (ControlArgument, LinAlgError, ValueError)
        raise SolverError(f"LQR design failed for {what}: {exc} (an unstable or marginal mode these inputs cannot "
                          "move makes it impossible; actuate more inputs)") from exc
    Kr, Er = np.asarray(Kr, dtype=float), np.asarray(Er)
    if not (np.all(np.isfinite(Kr)) and np.all(np.isfinite(Er)) and np.max(Er.real) < 0):
        raise SolverError(f"LQR design for {what} returned a gain that does not stabilize the linearization "
                          f"(closed-loop poles {np.round(Er, 6)}); check Q (the unstable modes must be weighted)")
    K = np.zeros((B.shape[1], A.shape[0]))
    K[np.ix_(ui, si)] = Kr
    if len(si) == A.shape[0]:
        return K, Er
    return K, np.linalg.eigvals(A - B @ K)


def place_glide(veh: Vehicle, glide: SteadyGlide, poles: Sequence[complex], *,
                inputs: Literal["force", "acceleration"] = "force",
                actuate: Sequence[str] | None = None, reduce_fixed: bool = True) -> LinearGlideController:
    """Pole placement to the glide path of ``glide`` with :func:`control.place` (1/s poles, conjugate-closed).

    Parameters
    ----------
    veh : Vehicle
        The underwater glider the glide was trimmed for.
    glide : SteadyGlide
        From :func:`~glidectl.trim.glide.steady_glide`.
    poles : sequence of complex
        The requested closed-loop poles (1/s) of the designed states (the design model's: 10 without fixed
        actuators, less the states locked by inputs left out of ``actuate``), finite and closed under conjugation (a
        pole may be repeated at most as often as there are actuated inputs).
    inputs : {"force", "acceleration"}
        Input form of the linearization (see :func:`~glidectl.analysis.linear.linearize_glide`).
    actuate : sequence of str, optional
        Inputs to design on; the others get exactly zero gain and the states they hold
        (:data:`LOCKED_STATES`) zero gain columns and a pole at 0. Default :func:`default_actuate` (as
        :func:`lqr_glide`).
    reduce_fixed : bool
        Design on the model without the fixed actuators (default), as :func:`lqr_glide`.

    Returns
    -------
    LinearGlideController
        ``method = "place"``, gain ``K`` of the design model's shape (3, 10 without fixed actuators), the
        linearization and the achieved closed-loop poles (1/s; the requested ones plus a 0 per locked state);
        ``Q`` and ``R`` are None.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a SteadyGlide, or ``poles`` not numbers.
    ArgumentError
        If the number of poles differs from the number of states, a pole is not finite, the set is not closed under
        conjugation or repeats a pole more often than there are inputs, ``inputs`` is not ``"force"`` or
        ``"acceleration"``, or ``actuate`` is empty or names an unknown input or one twice.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.
    SolverError
        If :func:`control.place` fails or the achieved poles differ from the requested ones by more than 1e-6
        (relative).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> glide = gc.steady_glide(veh, 0.3, math.radians(-45), r_p3=0.05)
    >>> poles = -0.1 * np.arange(1, 11)                      # 1/s, one per state
    >>> ctrl = gc.place_glide(veh, glide, poles)
    >>> ctrl.K.shape, bool(np.allclose(np.sort(ctrl.closed_loop_poles.real), np.sort(poles)))
    ((3, 10), True)
    """
    check_glide_design(veh, glide, inputs)
    p = numeric_array("poles", poles).astype(complex).ravel()
    if not np.all(np.isfinite(p)):
        raise ArgumentError(f"poles must be finite, got {poles!r}")
    sys = linearize_glide(veh, glide, inputs, reduce_fixed=reduce_fixed)
    fixed = fixed_actuators(veh) if reduce_fixed else ()
    act, ui, si, locked = actuated_subset(sys, veh, inputs, actuate)
    names = [sys.state_labels[i] for i in si]
    if p.size != len(si):
        raise ArgumentError(f"need {len(si)} poles for states {names}" + (f" (locked by the inputs left out: "
                            f"{list(locked)})" if locked else "") + f", got {p.size}")
    scale = np.maximum(1.0, np.abs(p))
    if np.max(np.min(np.abs(p[:, None] - np.conj(p)[None, :]) / scale[:, None], axis=1)) > 1e-9:
        raise ArgumentError(f"poles must be closed under complex conjugation (real gains), got {np.round(p, 6)}")
    mult = np.sum(np.abs(p[:, None] - p[None, :]) <= 1e-12 * scale[:, None], axis=1)
    if np.max(mult) > len(ui):
        raise ArgumentError(f"a pole is repeated {int(np.max(mult))} times; with {len(ui)} inputs place_glide "
                            f"can repeat a pole at most {len(ui)} times (spread them slightly)")
    A, B = np.asarray(sys.A), np.asarray(sys.B)
    Ar, Br = A[np.ix_(si, si)], B[np.ix_(si, ui)]
    try:
        with warnings.catch_warnings():
            # scipy's YT robustness iteration may stop before its tolerance; the placement itself is checked below
            warnings.filterwarnings("ignore", message="Convergence was not reached", category=UserWarning)
            Kr = np.asarray(control.place(Ar, Br, p))
    except Exception as exc:  # python-control / scipy raise several types
        raise SolverError(f"pole placement failed with inputs {list(act)}: {exc}") from exc
    if not np.all(np.isfinite(Kr)):
        raise SolverError("pole placement returned a gain that is not finite")
    K = np.zeros((B.shape[1], A.shape[0]))
    K[np.ix_(ui, si)] = Kr
    E = np.linalg.eigvals(Ar - Br @ Kr)
    r, c = linear_sum_assignment(np.abs(E[:, None] - p[None, :]))
    err = float(np.max(np.abs(E[r] - p[c]) / np.maximum(1.0, np.abs(p[c]))))
    if err > 1e-6:
        raise SolverError(f"pole placement inaccurate: closed-loop poles {np.round(E, 6)} differ from the "
                            f"requested {np.round(p, 6)} (relative error {err:.1e}); the requested set may be "
                            "ill-conditioned for this plant")
    if locked:
        E = np.linalg.eigvals(A - B @ K)
    return LinearGlideController(K, "place", sys, E, glide, inputs, vehicle=veh, actuate=act, locked_states=locked,
                                 fixed_actuators=fixed)


ZETA = ("r_P1", "rdot_P1", "r_P3", "rdot_P3", "m0")


def decoupled_gain_matrix(kp1: float, kd1: float, kp3: float, kd3: float, k4: float) -> np.ndarray:
    """Gain of ``w = -K (zeta - zeta_e)`` for (2.37): PD on each mass axis and P on buoyancy, shape (3, 5).

    ``zeta = (r_P1, rdot_P1, r_P3, rdot_P3, m0)``; ``A + BK`` of the thesis becomes ``A - BK`` here with
    characteristic polynomials ``s^2 + kd s + kp`` (mass axes) and ``s + k4`` (buoyancy).

    Parameters
    ----------
    kp1, kd1 : float
        Proportional (1/s^2) and derivative (1/s) gains of the moving mass along body 1.
    kp3, kd3 : float
        Proportional (1/s^2) and derivative (1/s) gains of the moving mass along body 3.
    k4 : float
        Proportional gain of the buoyancy (1/s).

    Returns
    -------
    numpy.ndarray, shape (3, 5)
        ``K`` with rows ``(w1, w3, w4)`` and columns ``(r_P1, rdot_P1, r_P3, rdot_P3, m0)``.

    Raises
    ------
    ArgumentTypeError
        If a gain is not a real number (a string, None, a bool, complex).
    ArgumentError
        If a gain is not finite. The sign is not checked (the thesis's printed gains, with the sign error, are a
        case of interest): non-positive gains give an unstable ``zeta`` subsystem.

    Examples
    --------
    >>> import glidectl as gc
    >>> gc.decoupled_gain_matrix(kp1=1.0, kd1=2.0, kp3=1.0, kd3=2.0, k4=0.5)
    array([[1. , 2. , 0. , 0. , 0. ],
           [0. , 0. , 1. , 2. , 0. ],
           [0. , 0. , 0. , 0. , 0.5]])
    """
    kp1, kd1, kp3, kd3, k4 = (checks.real(n, v) for n, v in
                              (("kp1", kp1), ("kd1", kd1), ("kp3", kp3), ("kd3", kd3), ("k4", k4)))
    K = np.zeros((3, 5))
    K[0, 0], K[0, 1], K[1, 2], K[1, 3], K[2, 4] = kp1, kd1, kp3, kd3, k4
    return K


@dataclass(frozen=True)
class DecoupledAccelerationFeedback:
    """Decoupled feedback (2.37) on the moving mass and buoyancy of the acceleration-controlled glider.

    Actuator limits: this law does not saturate its own commands. Run it through
    :class:`~glidectl.models.actuated.ActuatedGlider` (:func:`glidectl.sim.simulate_actuated`,
    :func:`glidectl.controllers.dive_cycle.dive_cycle`) to have the vehicle's ``[actuators]`` ranges and rates
    enforced; :func:`glidectl.sim.simulate` on the plain model applies no limits.

    ``w = -K (zeta - zeta_e(t))`` with ``zeta_e`` switching between steady glides at given times. Pass to
    :func:`glidectl.sim.simulate` with :class:`~glidectl.models.longitudinal.AccelerationControlledGlider`.

    Attributes
    ----------
    K : ndarray, shape (3, 5)
    glides : tuple of SteadyGlide
        Glide ``i`` is commanded from ``switch_times[i]`` (s) on.
    switch_times : tuple of float
        Finite, nondecreasing switch times (s), one per glide.

    Raises
    ------
    ArgumentTypeError
        If ``K`` or ``switch_times`` is not real numbers, or a glide is not a SteadyGlide.
    ArgumentError
        If ``K`` is not a finite (3, 5) array, there is no glide, or the switch times are not one finite,
        nondecreasing time per glide.
    VehicleMismatchError
        If the glides were trimmed for different vehicles.
    """

    K: np.ndarray
    glides: tuple[SteadyGlide, ...]
    switch_times: tuple[float, ...] = field(default=(0.0,))

    def __post_init__(self) -> None:
        K = checks.array("K", self.K)
        if K.shape != (3, 5):
            raise ArgumentError("K must have shape (3, 5): rows (w1, w3, w4), columns (r_P1, rdot_P1, r_P3, "
                                f"rdot_P3, m0); got {K.shape}")
        if isinstance(self.glides, SteadyGlide) or not isinstance(self.glides, Sequence):
            raise ArgumentTypeError(f"glides must be a sequence of SteadyGlide, got {type(self.glides).__name__}")
        if not self.glides:
            raise ArgumentError("glides must hold at least one SteadyGlide")
        for i, g in enumerate(self.glides):
            require_instance(f"glides[{i}]", g, SteadyGlide, " (from gc.steady_glide)")
        if len({g.provenance for g in self.glides}) > 1:
            raise VehicleMismatchError("the glides were trimmed for different vehicles: "
                                       f"{sorted({g.vehicle.name + ' ' + g.provenance for g in self.glides})}")
        ts = checks.array("switch_times", self.switch_times, ndim=1)
        if ts.size != len(self.glides) or np.any(np.diff(ts) < 0):
            raise ArgumentError("need one increasing switch time per glide")
        object.__setattr__(self, "K", K.copy())
        object.__setattr__(self, "glides", tuple(self.glides))
        object.__setattr__(self, "switch_times", tuple(float(t) for t in ts))

    def zeta_e(self, t: float) -> np.ndarray:
        """Commanded (r_P1, rdot_P1, r_P3, rdot_P3, m0) at time t (s)."""
        t = checks.real("t", t, unit="s")
        i = int(np.searchsorted(self.switch_times, t, side="right")) - 1
        g = self.glides[max(i, 0)]
        return np.array([g.r_p1, 0.0, g.r_p3, 0.0, g.m0])

    @property
    def zeta_closed_loop_poles(self) -> np.ndarray:
        """Eigenvalues of the zeta subsystem ``A - B K`` (1/s)."""
        A = np.zeros((5, 5))
        A[0, 1] = A[2, 3] = 1.0
        B = np.zeros((5, 3))
        B[1, 0] = B[3, 1] = B[4, 2] = 1.0
        return np.linalg.eigvals(A - B @ self.K)

    def __call__(self, t: float, x: Any) -> np.ndarray:
        """Input ``w = (w1, w3, w4)`` at time ``t`` (s) for acceleration-form states ``x`` (shape ``(..., 11)``)."""
        x = checks.array("x", x)
        trailing_array("x", x, 11)
        zeta = x[..., 6:11]
        return -(zeta - self.zeta_e(t)) @ np.asarray(self.K).T
