"""Linearization about steady glides, modal analysis, controllability and observability (§2.3.1).

Linear models are returned as :class:`control.StateSpace` with named states, inputs and outputs (outputs = all
states). The actuators a vehicle file fixes are not in them (:func:`design_model`, :class:`FixedActuatorModel`;
``reduce_fixed=False`` keeps them). Ranks are reported with the tolerance used and the singular values behind
them, and checked by the PBH (Popov-Belevitch-Hautus) test at every eigenvalue, which does not suffer from the
conditioning of the Kalman matrix on badly scaled states; a failing mode is named by the states its failing
directions are made of (:class:`ModeStates`). Modes are labelled by their states' participation factors
(:func:`modes`), which do not depend on the states' units.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import control
import numpy as np

from .. import checks
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, SolverError
from ..models._validate import trailing_array
from ..models.longitudinal import (
    AccelerationControlledGlider,
    GlidePathModel,
    LongitudinalGlider,
)
from ..params import Vehicle
from ..trim.glide import SteadyGlide

__all__ = [
    "EXTRA_OUTPUTS",
    "FIXED_ACTUATOR_STATES",
    "DepthGlidePathModel",
    "FixedActuatorModel",
    "ModeStates",
    "Modes",
    "OutputMap",
    "RankTest",
    "controllability",
    "depth_rate",
    "design_model",
    "fixed_actuators",
    "glide_model",
    "linearize_glide",
    "modes",
    "observability",
    "output_map",
]

InputKind = Literal["force", "acceleration"]


def _check_glide(veh: Vehicle, glide: SteadyGlide) -> None:
    checks.vehicle("veh", veh, "underwater_glider")
    if not isinstance(glide, SteadyGlide):
        raise ArgumentTypeError(f"glide must be a SteadyGlide from gc.steady_glide(veh, speed, gamma, ...), got "
                                f"{type(glide).__name__}")
    checks.same_vehicle("glide", glide, veh)


def glide_model(veh: Vehicle, glide: SteadyGlide, inputs: InputKind = "force") -> tuple[GlidePathModel, np.ndarray]:
    """The glide-path model (z' instead of x, z) for ``inputs`` and its equilibrium state (z' = 0).

    Parameters
    ----------
    veh : Vehicle
        The underwater glider the glide was trimmed for (moving mass ``mbar > 0``).
    glide : SteadyGlide
        From :func:`~glidectl.trim.glide.steady_glide`; its flight-path angle (rad) defines the path of (2.30).
    inputs : {"force", "acceleration"}
        ``"force"``: :class:`~glidectl.models.longitudinal.LongitudinalGlider` base, inputs ``(u1, u3, u4)`` (N, N,
        kg/s). ``"acceleration"``: :class:`~glidectl.models.longitudinal.AccelerationControlledGlider` base, inputs
        ``(w1, w3, w4)`` (m/s^2, m/s^2, kg/s).

    Returns
    -------
    model : GlidePathModel
        The glide-path model (10 states, first ``z_prime`` in m).
    xe : numpy.ndarray, shape (10,)
        Its equilibrium state on the glide (``z_prime = 0``; other states in the units of
        :data:`glidectl.models.longitudinal.STATE_UNITS`).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``glide`` is not a :class:`~glidectl.trim.glide.SteadyGlide` (e.g. ``None``).
    ArgumentError
        If ``inputs`` is neither ``"force"`` nor ``"acceleration"``.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle (different provenance).
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> g = gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05)
    >>> model, xe = gc.glide_model(veh, g)
    >>> model.state_names[:3], model.input_names, xe.shape
    (('z_prime', 'theta', 'Omega2'), ('u1', 'u3', 'u4'), (10,))
    """
    _check_glide(veh, glide)
    checks.choice("inputs", inputs, ("force", "acceleration"))
    if inputs == "force":
        base: LongitudinalGlider | AccelerationControlledGlider = LongitudinalGlider(veh)
        xe = glide.force_state()
    else:
        base = AccelerationControlledGlider(veh)
        xe = glide.accel_state()
    model = GlidePathModel(base, glide.gamma)
    return model, np.concatenate([[0.0], xe[2:]])


#: Output channels :func:`linearize_glide` knows besides the glide-path states: depth ``z`` (m, positive down; a
#: kinematic state appended to the model when asked for) and its rate ``depth_rate`` (m/s, from (2.16)).
EXTRA_OUTPUTS: dict[str, str] = {"z": "m", "depth_rate": "m/s"}


@dataclass(frozen=True)
class DepthGlidePathModel:
    """The glide-path model of (2.30) with the depth ``z`` (m, positive down) appended as a last, kinematic state.

    States ``("z_prime", <body states>, "z")``: ``z'`` (2.30), the base model's body states and ``z`` with
    ``z' = -sin(theta) v1 + cos(theta) v3`` of (2.16) (the base model's own kinematics). No force depends on the
    position, so ``z`` is a pure integrator; together with ``z'`` it determines the horizontal position
    (``x = (z' - cos(gamma_e) z) / sin(gamma_e)``) on a non-level path.

    Parameters
    ----------
    path : GlidePathModel
        The glide-path model to extend (from :func:`glide_model`).

    Raises
    ------
    ArgumentTypeError
        If ``path`` is not a :class:`~glidectl.models.longitudinal.GlidePathModel`.
    """

    path: GlidePathModel

    def __post_init__(self) -> None:
        if not isinstance(self.path, GlidePathModel):
            raise ArgumentTypeError(f"path must be a GlidePathModel (from gc.glide_model), got "
                                    f"{type(self.path).__name__}")

    @property
    def state_names(self) -> tuple[str, ...]:
        return (*self.path.state_names, "z")

    @property
    def input_names(self) -> tuple[str, ...]:
        return self.path.input_names

    @property
    def vehicle(self) -> Vehicle:
        return self.path.vehicle

    @property
    def gamma(self) -> float:
        """Flight-path angle of the path (rad)."""
        return self.path.gamma

    def rhs(self, x: Any, u: Any) -> Any:
        """Derivative of ``(z', theta, ..., z)`` (shape ``(..., 11)``): the glide-path model's and (2.16).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with the right trailing dimension.
        """
        x = trailing_array("x", x, 11, self.state_names)
        xr = x[..., :10]
        full = np.concatenate([np.zeros_like(xr[..., :1]), x[..., 10:], xr[..., 1:]], axis=-1)
        d = self.path.base.rhs(full, u)
        zp = np.sin(self.path.gamma) * d[..., 0] + np.cos(self.path.gamma) * d[..., 1]
        return np.concatenate([zp[..., None], d[..., 2:], d[..., 1:2]], axis=-1)


#: States of each actuator in each input form, and the input that moves it (:func:`fixed_actuators`,
#: :class:`FixedActuatorModel`): a fixed actuator's states and input leave the design models.
FIXED_ACTUATOR_STATES: dict[str, dict[str, tuple[tuple[str, ...], str]]] = {
    "force": {"r_P1": (("r_P1", "P_P1"), "u1"), "r_P3": (("r_P3", "P_P3"), "u3"), "m0": (("m0",), "u4")},
    "acceleration": {"r_P1": (("r_P1", "rdot_P1"), "w1"), "r_P3": (("r_P3", "rdot_P3"), "w3"),
                     "m0": (("m0",), "w4")},
}


def fixed_actuators(veh: Vehicle) -> tuple[str, ...]:
    """The longitudinal actuators (``r_P1``, ``r_P3``, ``m0``, in that order) that the vehicle file fixes.

    Parameters
    ----------
    veh : Vehicle
        Its ``[actuators]`` table is read (``fixed = ...`` entries); a vehicle without one fixes none.

    Returns
    -------
    tuple of str

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle.

    Examples
    --------
    >>> import glidectl as gc
    >>> gc.fixed_actuators(gc.load_vehicle("slocum_shallow"))
    ('r_P3',)
    >>> gc.fixed_actuators(gc.load_vehicle("rogue"))  # no [actuators] table
    ()
    """
    acts = checks.vehicle("veh", veh).actuators
    return tuple(a for a in ("r_P1", "r_P3", "m0") if getattr(acts.get(a), "fixed", None) is not None)


@dataclass(frozen=True)
class FixedActuatorModel:
    """A glide-path model (:class:`~glidectl.models.longitudinal.GlidePathModel` or :class:`DepthGlidePathModel`)
    with some actuators held where they are: their states and inputs removed.

    A held moving-mass axis ``i`` keeps ``r_Pi`` at its value and ``rdot_Pi = 0``; a held pump keeps ``m0``. In the
    acceleration form its input (``w_i``, ``w4``) is zero, which keeps it there exactly. In the force form the mass is
    held by the force of the hull on it: ``P_Pi = mbar (v + Omega x r_P)_i`` (no sliding, (2.31) with
    ``rdot_Pi = 0``), and ``u_i`` is the constraint force that keeps ``rdot_Pi = 0`` (solved at each state from the
    model's own right-hand side, which is affine in ``u``); a held pump has ``u4 = 0``. The remaining states evolve
    exactly as in the model with the actuator held (the held states are constant along its solutions).

    Parameters
    ----------
    inner : GlidePathModel or DepthGlidePathModel
        The model with every state.
    actuators : tuple of str
        The held actuators, among ``("r_P1", "r_P3", "m0")``.
    values : tuple of float
        Where each is held (m, m, kg), e.g. the steady glide's values.

    Raises
    ------
    ArgumentTypeError
        If ``inner`` is not a glide-path model.
    ArgumentError
        If ``actuators`` names an unknown or repeated actuator, or ``values`` are not one finite number each.
    """

    inner: Any
    actuators: tuple[str, ...]
    values: tuple[float, ...]

    def __post_init__(self) -> None:
        path = self.inner.path if isinstance(self.inner, DepthGlidePathModel) else self.inner
        if not isinstance(path, GlidePathModel):
            raise ArgumentTypeError(f"inner must be a GlidePathModel or a DepthGlidePathModel, got "
                                    f"{type(self.inner).__name__}")
        acts = tuple(self.actuators)
        if any(a not in ("r_P1", "r_P3", "m0") for a in acts) or len(set(acts)) != len(acts):
            raise ArgumentError(f"actuators must be distinct names among ('r_P1', 'r_P3', 'm0'), got {acts!r}")
        vals = checks.array("values", self.values, shape=(len(acts),))
        object.__setattr__(self, "actuators", acts)
        object.__setattr__(self, "values", tuple(float(v) for v in vals))
        form = "force" if isinstance(path.base, LongitudinalGlider) else "acceleration"
        table = FIXED_ACTUATOR_STATES[form]
        dropped = {s for a in acts for s in table[a][0]}
        names = tuple(self.inner.state_names)
        inputs = tuple(self.inner.input_names)
        keep = [i for i, q in enumerate(names) if q not in dropped]
        ikeep = [i for i, q in enumerate(inputs) if q not in {table[a][1] for a in acts}]
        object.__setattr__(self, "_layout", (form, keep, ikeep, names, inputs))

    @property
    def form(self) -> str:
        """``"force"`` or ``"acceleration"``."""
        return self._layout[0]

    @property
    def path(self) -> GlidePathModel:
        """The glide-path model inside."""
        return self.inner.path if isinstance(self.inner, DepthGlidePathModel) else self.inner

    @property
    def state_names(self) -> tuple[str, ...]:
        names, keep = self._layout[3], self._layout[1]
        return tuple(names[i] for i in keep)

    @property
    def input_names(self) -> tuple[str, ...]:
        inputs, ikeep = self._layout[4], self._layout[2]
        return tuple(inputs[i] for i in ikeep)

    @property
    def removed_states(self) -> tuple[str, ...]:
        """The states of :attr:`inner` this model removes (held)."""
        keep = set(self.state_names)
        return tuple(q for q in self._layout[3] if q not in keep)

    @property
    def removed_inputs(self) -> tuple[str, ...]:
        """The inputs of :attr:`inner` this model removes."""
        keep = set(self.input_names)
        return tuple(q for q in self._layout[4] if q not in keep)

    @property
    def vehicle(self) -> Vehicle:
        return self.path.vehicle

    @property
    def gamma(self) -> float:
        """Flight-path angle of the path (rad)."""
        return self.path.gamma

    def reduce(self, x: Any) -> np.ndarray:
        """The states of this model from states ``x`` of :attr:`inner` (shape ``(..., n_inner)``)."""
        x = trailing_array("x", x, len(self._layout[3]), self._layout[3])
        return x[..., self._layout[1]]

    def full_state(self, x: Any) -> np.ndarray:
        """States of :attr:`inner` (shape ``(..., n_inner)``) for states ``x`` of this model: the held states at
        their values (and, in the force form, the momentum of a held mass from the no-sliding condition)."""
        form, keep, _, names, _ = self._layout
        x = trailing_array("x", x, len(keep), self.state_names)
        full = np.zeros((*x.shape[:-1], len(names)), dtype=np.result_type(x.dtype, float))
        full[..., keep] = x
        col = {q: full[..., i] for i, q in enumerate(names)}
        for a, v in zip(self.actuators, self.values, strict=True):
            full[..., names.index(a)] = v
            if form == "acceleration" and a != "m0":
                full[..., names.index("rdot_" + a[2:])] = 0.0
        if form == "force":
            mbar = self.vehicle.mbar
            Om, v1, v3, r1, r3 = (col[q] for q in ("Omega2", "v1", "v3", "r_P1", "r_P3"))
            if "r_P1" in self.actuators:
                full[..., names.index("P_P1")] = mbar * (v1 + r3 * Om)
            if "r_P3" in self.actuators:
                full[..., names.index("P_P3")] = mbar * (v3 - r1 * Om)
        return full

    def full_input(self, x: Any, u: Any) -> np.ndarray:
        """Inputs of :attr:`inner` for states ``x`` and inputs ``u`` of this model: zero for a held actuator, except
        the constraint force of a held mass in the force form."""
        form, _, ikeep, names, inputs = self._layout
        u = trailing_array("u", u, len(ikeep), self.input_names)
        full_x = self.full_state(x)
        shape = np.broadcast_shapes(full_x.shape[:-1], u.shape[:-1])
        U = np.zeros((*shape, len(inputs)), dtype=np.result_type(full_x.dtype, u.dtype, float))
        U[..., ikeep] = u
        held = [a for a in self.actuators if a != "m0"] if form == "force" else []
        if not held:
            return U
        # the derivative of rdot_Pi is affine in the constraint forces: one batched evaluation at U and U + e_j
        ui = [inputs.index(FIXED_ACTUATOR_STATES["force"][a][1]) for a in held]
        trial = np.repeat(U[None], len(held) + 1, axis=0)
        for j, k in enumerate(ui):
            trial[j + 1, ..., k] += 1.0
        d = self.inner.rhs(np.broadcast_to(full_x, (*shape, len(names))), trial)
        mbar = self.vehicle.mbar
        col = {q: full_x[..., i] for i, q in enumerate(names)}
        dcol = {q: d[..., i] for i, q in enumerate(names)}

        def slip_rate(a: str) -> Any:  # d/dt of rdot_Pi = P_Pi / mbar - v_i -+ (Omega x r_P)_i
            if a == "r_P1":
                return dcol["P_P1"] / mbar - dcol["v1"] - dcol["r_P3"] * col["Omega2"] - col["r_P3"] * dcol["Omega2"]
            return dcol["P_P3"] / mbar - dcol["v3"] + dcol["r_P1"] * col["Omega2"] + col["r_P1"] * dcol["Omega2"]

        g = np.stack([slip_rate(a) for a in held], axis=-1)  # (k + 1, ..., k)
        G = np.moveaxis(g[1:] - g[0], 0, -1)  # (..., k rows (constraints), k columns (forces))
        if len(held) == 1:
            c = -g[0] / G[..., 0]
        else:
            c = np.linalg.solve(G, -g[0][..., None])[..., 0]
        for j, k in enumerate(ui):
            U[..., k] = c[..., j]
        return U

    def rhs(self, x: Any, u: Any) -> Any:
        """Derivative of the remaining states: :attr:`inner`'s at the held actuators (batch, complex-safe).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` or ``u`` is not an array of numbers with the right trailing dimension.
        """
        full = self.full_state(x)
        d = self.inner.rhs(full, self.full_input(x, u))
        return np.asarray(d)[..., self._layout[1]]


def design_model(veh: Vehicle, glide: SteadyGlide, inputs: InputKind = "force", *, depth: bool = False,
                 reduce_fixed: bool = True) -> tuple[Any, np.ndarray]:
    """The model the linear designs are made on and its equilibrium: the glide-path model (:func:`glide_model`),
    with the depth ``z`` appended when asked for (:class:`DepthGlidePathModel`), without the states and inputs of
    the actuators the vehicle file fixes (:class:`FixedActuatorModel`, held at the glide's values).

    Parameters
    ----------
    veh, glide, inputs :
        As :func:`glide_model`.
    depth : bool
        Append the depth ``z`` (m) as a last state (its equilibrium value is 0).
    reduce_fixed : bool
        Remove the fixed actuators (default); False keeps every state and input. A vehicle without fixed actuators
        (every thesis preset) gets the same model either way.

    Returns
    -------
    model : GlidePathModel, DepthGlidePathModel or FixedActuatorModel
    xe : numpy.ndarray
        Its equilibrium state on the glide.

    Raises
    ------
    ArgumentTypeError, ArgumentError, VehicleMismatchError, ModelError
        As :func:`glide_model`, or if a flag is not a bool.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("slocum_shallow")  # its vehicle file fixes r_P3
    >>> g = gc.steady_glide(veh, speed=0.35, gamma=np.radians(-25.0), r_p3=0.05)
    >>> model, xe = gc.design_model(veh, g)
    >>> type(model).__name__, model.input_names, xe.shape
    ('FixedActuatorModel', ('u1', 'u4'), (8,))
    """
    checks.boolean("depth", depth)
    checks.boolean("reduce_fixed", reduce_fixed)
    model, xe = glide_model(veh, glide, inputs)
    plant: Any = model
    if depth:
        plant, xe = DepthGlidePathModel(model), np.concatenate([xe, [0.0]])
    fixed = fixed_actuators(veh) if reduce_fixed else ()
    if fixed:
        names = list(plant.state_names)
        plant = FixedActuatorModel(plant, fixed, tuple(float(xe[names.index(a)]) for a in fixed))
        xe = plant.reduce(xe)
    return plant, xe


def depth_rate(model: Any, x: Any) -> Any:
    """Depth rate ``-sin(theta) v1 + cos(theta) v3`` (m/s, (2.16)) of glide-path states ``x`` (batch,
    complex-safe), from the base model's own kinematics."""
    if isinstance(model, FixedActuatorModel):
        x, model = model.full_state(x), model.inner
    path = model.path if isinstance(model, DepthGlidePathModel) else model
    x = np.asarray(x)
    xr = x[..., :10]
    full = np.concatenate([np.zeros_like(xr[..., :2]), xr[..., 1:]], axis=-1)
    u = np.zeros((*x.shape[:-1], len(path.input_names)))
    return path.base.rhs(full, u)[..., 1]


@dataclass(frozen=True)
class OutputMap:
    """Named outputs ``y = M c(x)`` of a glide-path model: ``c`` are channels (states, ``z``, ``depth_rate``).

    Built by :func:`output_map`; evaluates the nonlinear outputs of a state batch (``__call__``) and is linearized
    by :func:`linearize_glide` (``C = M dc/dx``).

    Attributes
    ----------
    names : tuple of str
        Output names.
    channels : tuple of str
        The channels the outputs combine (states of the model, ``"z"``, ``"depth_rate"``).
    M : ndarray, shape (len(names), len(channels))
        Coefficients (output unit per channel unit).
    """

    names: tuple[str, ...]
    channels: tuple[str, ...]
    M: np.ndarray

    @property
    def needs_depth(self) -> bool:
        """True when an output uses the depth ``z`` (the model then carries ``z`` as a state)."""
        return "z" in self.channels

    def __call__(self, model: Any, x: Any) -> Any:
        """Outputs (shape ``(..., len(names))``) for states ``x`` of ``model`` (shape ``(..., n)``)."""
        x = np.asarray(x)
        names = list(model.state_names)
        cols = [depth_rate(model, x) if c == "depth_rate" else x[..., names.index(c)] for c in self.channels]
        return np.stack(cols, axis=-1) @ self.M.T


def output_map(outputs: Any, state_names: Sequence[str]) -> OutputMap:
    """Parse an output selection of :func:`linearize_glide` into an :class:`OutputMap`.

    Parameters
    ----------
    outputs : str, sequence of str or mapping
        A channel name, a sequence of channel names, or a mapping ``{output name: channel name or {channel:
        coefficient}}`` (a linear combination). Channels: the glide-path states ``state_names`` (without ``"z"``)
        and :data:`EXTRA_OUTPUTS` (``"z"``, ``"depth_rate"``).
    state_names : sequence of str
        States of the glide-path model.

    Returns
    -------
    OutputMap

    Raises
    ------
    ArgumentTypeError
        If ``outputs`` is not a name, a sequence of names or a mapping of names to names or coefficient mappings,
        or a coefficient is not a real number.
    ArgumentError
        If a channel is unknown, an output or channel is named twice, the selection is empty, a coefficient is not
        finite or a combination has no nonzero coefficient.
    """
    known = [*state_names, *(k for k in EXTRA_OUTPUTS if k not in state_names)]
    if isinstance(outputs, str):
        outputs = (outputs,)
    if isinstance(outputs, Mapping):
        spec = dict(outputs)
    elif isinstance(outputs, Sequence | np.ndarray) and not isinstance(outputs, bytes):
        outputs = list(outputs)
        if not all(isinstance(o, str) for o in outputs):
            raise ArgumentTypeError(f"outputs must be names (str) from {known} or a mapping {{name: channel or "
                                    f"{{channel: coefficient}}}}, got {outputs!r}")
        if len(set(outputs)) != len(outputs):
            raise ArgumentError(f"the output selection {outputs} names an output twice")
        spec = {o: o for o in outputs}
    else:
        raise ArgumentTypeError(f"outputs must be a name, a sequence of names from {known} or a mapping {{name: "
                                f"channel or {{channel: coefficient}}}}, got {type(outputs).__name__}")
    if not spec:
        raise ArgumentError(f"empty output selection; name at least one of {known} (or pass None for all states)")
    rows: list[dict[str, float]] = []
    for name, val in spec.items():
        if not isinstance(name, str):
            raise ArgumentTypeError(f"output names must be strings, got {name!r}")
        comb = {val: 1.0} if isinstance(val, str) else val
        if not isinstance(comb, Mapping):
            raise ArgumentTypeError(f"output {name!r} must be a channel name or a mapping {{channel: coefficient}} "
                                    f"over {known}, got {type(val).__name__}")
        row = {}
        for ch, coef in comb.items():
            if ch not in known:
                raise ArgumentError(f"unknown output channel {ch!r} in output {name!r}; known channels: {known}")
            row[ch] = checks.real(f"coefficient of {ch!r} in output {name!r}", coef)
        if not any(v != 0.0 for v in row.values()):
            raise ArgumentError(f"output {name!r} has no nonzero coefficient; give at least one channel")
        rows.append(row)
    channels = tuple(c for c in known if any(c in r for r in rows))
    M = np.array([[r.get(c, 0.0) for c in channels] for r in rows])
    return OutputMap(tuple(spec), channels, M)


def linearize_glide(veh: Vehicle, glide: SteadyGlide, inputs: InputKind = "force",
                    outputs: Any = None, *, reduce_fixed: bool = True) -> control.StateSpace:
    """Exact linearization of the longitudinal glider about a steady glide, with z' (2.30), and named outputs.

    Parameters
    ----------
    veh : Vehicle
        The vehicle the glide was trimmed for.
    glide : SteadyGlide
        From :func:`~glidectl.trim.glide.steady_glide`.
    inputs : {"force", "acceleration"}
        ``"force"``: states ``(z_prime, theta, Omega2, v1, v3, r_P1, r_P3, P_P1, P_P3, m0)``, inputs
        ``(u1, u3, u4)`` of (2.15)-(2.25). ``"acceleration"``: states ``(z_prime, theta, Omega2, v1, v3, r_P1,
        rdot_P1, r_P3, rdot_P3, m0)``, inputs ``(w1, w3, w4)`` of (2.33)-(2.34).
    outputs : str, sequence of str or mapping, optional
        Measured outputs ``y``; default all states (``C = I``). Channels: every state, ``"z"`` (depth, m, positive
        down) and ``"depth_rate"`` (m/s, ``-sin(theta) v1 + cos(theta) v3`` of (2.16)). A sequence names channels,
        e.g. ``("z", "theta", "Omega2")``; a mapping names outputs and gives each a channel or a linear
        combination ``{channel: coefficient}`` (output unit per channel unit), e.g. ``{"depth": "z",
        "pitch_lead": {"theta": 1.0, "Omega2": 0.5}}``.

        The glide-path state has no depth (z' replaces x and z; depth is not a function of it), so an output that
        uses ``"z"`` appends the kinematic state ``z`` of (2.16) as the last state (:class:`DepthGlidePathModel`).
        In the linearization ``z`` is the depth deviation from the nominal glide at the same time (the nominal depth
        grows at the sink rate and is no equilibrium; the constant sink rate drops out), a pure integrator: with
        ``z'`` it fixes the horizontal position, which is why ``z'`` stays unobservable from depth (it needs ``x``).
    reduce_fixed : bool
        Leave out the actuators the vehicle's ``[actuators]`` table fixes (default): their states
        (:data:`FIXED_ACTUATOR_STATES`: ``r_P3`` and ``rdot_P3`` or ``P_P3`` for a fixed ``r_P3``) and their input
        (:class:`FixedActuatorModel`: in the force form the mass is held by its constraint force). A part that never
        moves then adds no eigenvalue at 0 and no unobservable or uncontrollable mode. False: every state and input,
        the fixed actuator free to move under its input. A vehicle without fixed actuators (every thesis preset)
        gets the same model either way.

    Returns
    -------
    control.StateSpace
        ``A, B`` exact (complex step); ``C`` the (complex-step) linearization of the outputs, ``D = 0``; states,
        inputs and outputs named; units in :data:`glidectl.models.longitudinal.STATE_UNITS`.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` is not a :class:`~glidectl.trim.glide.SteadyGlide` (e.g. ``None``),
        or ``outputs`` is not a name, a sequence of names or a mapping.
    ArgumentError
        If ``inputs`` is not ``"force"`` or ``"acceleration"``, or ``outputs`` names an unknown channel (a state of
        a fixed actuator is none unless ``reduce_fixed=False``), names one twice, is empty or gives a combination
        without a nonzero finite coefficient.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle (different provenance).
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``, or the linearization is not finite at the glide.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> g = gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05)
    >>> sys = gc.linearize_glide(veh, g, inputs="force", outputs=("z", "theta"))
    >>> sys.nstates, sys.input_labels, sys.output_labels  # the depth z appended as an 11th state
    (11, ['u1', 'u3', 'u4'], ['z', 'theta'])
    """
    checks.boolean("reduce_fixed", reduce_fixed)
    model, _ = glide_model(veh, glide, inputs)
    omap = None
    if outputs is not None:
        dropped = {q for a in (fixed_actuators(veh) if reduce_fixed else ())
                   for q in FIXED_ACTUATOR_STATES[inputs][a][0]}
        omap = output_map(outputs, [q for q in model.state_names if q not in dropped])
    plant, xe = design_model(veh, glide, inputs, depth=omap is not None and omap.needs_depth,
                             reduce_fixed=reduce_fixed)
    m = len(plant.input_names)
    A, B = jacobians(plant.rhs, xe, np.zeros(m))
    n = A.shape[0]
    names = list(plant.state_names)
    if omap is None:
        C, onames = np.eye(n), names
    else:
        C, _ = jacobians(lambda x, u: omap(plant, x), xe, np.zeros(0))
        onames = list(omap.names)
    return control.ss(A, B, C, np.zeros((C.shape[0], m)), states=names, inputs=list(plant.input_names),
                      outputs=onames, name=f"{veh.name}_gamma{np.degrees(glide.gamma):+.0f}deg_{inputs}")


@dataclass(frozen=True)
class Modes:
    """Eigen-structure of a linear model.

    Attributes
    ----------
    eigenvalues : ndarray
        Sorted by decreasing real part (1/s).
    eigenvectors : ndarray
        Columns normalized to unit 2-norm.
    wn, zeta, time_constant : ndarray
        Natural frequency (rad/s), damping ratio, and ``-1/Re(lambda)`` (s; inf for Re = 0).
    dominant_states : tuple of str
        State with the largest participation in each mode (:attr:`participation`).
    participation : ndarray, shape (n_states, n_modes)
        Participation of each state in each mode (nondimensional, each column sums to 1): ``|P_ii|`` of the spectral
        projector ``P`` of the mode's eigenvalue (for a simple eigenvalue ``|v_i w_i|``, right and left eigenvectors
        with ``w v = 1``: the participation factors of Perez-Arriaga, Verghese & Schweppe 1982, independent of the
        states' units), shared equally by the modes of a repeated eigenvalue.
    labels : tuple of str
        Each mode named by the states that make up 80 % of its participation (at most three, or as many as the
        eigenvalue's multiplicity, and any tied with the last; with their percentages, e.g.
        ``"theta 61% + Omega2 35%"``). The two modes of a complex pair are marked ``(pair +i)`` and
        ``(pair -i)``, the modes of a repeated eigenvalue ``(k of m at lambda)``, and two distinct eigenvalues whose
        states would read the same carry their eigenvalue (``[-0.0728/s]``): no two labels are equal.
    """

    eigenvalues: np.ndarray
    eigenvectors: np.ndarray
    wn: np.ndarray
    zeta: np.ndarray
    time_constant: np.ndarray
    dominant_states: tuple[str, ...]
    participation: np.ndarray | None = None
    labels: tuple[str, ...] = ()

    @property
    def stable(self) -> bool:
        """All eigenvalues strictly in the open left half plane."""
        return bool(np.all(self.eigenvalues.real < 0))

    def __str__(self) -> str:
        names = self.labels or self.dominant_states
        head = f"{'eigenvalue [1/s]':>26} {'wn [rad/s]':>11} {'zeta':>8} {'tau [s]':>10}"
        lines = [f"{head}  dominant states (participation)"]
        for lam, wn, z, tc, d in zip(self.eigenvalues, self.wn, self.zeta, self.time_constant, names, strict=True):
            lines.append(f"{lam.real:12.5g} {lam.imag:+12.5g}i {wn:11.5g} {z:8.4g} {tc:10.4g}  {d}")
        return "\n".join(lines)


def _clusters(lam: np.ndarray, scale: float) -> list[list[int]]:
    """Indices of (numerically) equal eigenvalues, grouped: a defective or repeated eigenvalue is one group."""
    tol = 1e-6 * max(scale, 1.0)
    groups: list[list[int]] = []
    for k, l in enumerate(lam):
        for g in groups:
            if abs(lam[g[0]] - l) <= tol:
                g.append(k)
                break
        else:
            groups.append([k])
    return groups


def _projector_diagonal(A: np.ndarray, lam: complex, tol: float) -> np.ndarray:
    """``|diag(P)|`` of the spectral projector of ``A`` onto the eigenvalues within ``tol`` of ``lam`` (ordered
    complex Schur form and a Sylvester equation: well defined for defective eigenvalues)."""
    from scipy.linalg import schur, solve_sylvester

    T, Z, k = schur(A.astype(complex), output="complex", sort=lambda x: abs(x - lam) <= tol)
    n = A.shape[0]
    P = np.zeros((n, n), dtype=complex)
    P[:k, :k] = np.eye(k)
    if k < n:
        P[:k, k:] = solve_sylvester(T[:k, :k], -T[k:, k:], T[:k, k:])
    return np.abs(np.einsum("ij,jk,ik->i", Z, P, Z.conj()))


def _ranked(p: np.ndarray) -> np.ndarray:
    """State indices by decreasing participation ``p``; ties (a repeated eigenvalue) in state order."""
    return np.argsort(-np.round(p, 9), kind="stable")


def _mode_labels(lam: np.ndarray, part: np.ndarray, names: Sequence[str], groups: list[list[int]]) -> list[str]:
    labels = []
    size = {k: len(g) for g in groups for k in g}
    for k in range(lam.size):
        p = part[:, k]
        order = _ranked(p)
        chosen, total = [], 0.0
        for i in order[:max(3, size[k])]:  # a repeated eigenvalue spreads over at least as many states
            chosen.append(i)
            total += p[i]
            if total >= 0.8:
                break
        chosen += [i for i in order[len(chosen):] if p[i] >= p[chosen[-1]] - 5e-3]  # and states tied with the last
        labels.append(" + ".join(f"{names[i]} {100 * p[i]:.0f}%" for i in chosen))
    for g in groups:
        if len(g) > 1:
            mid = complex(np.round(np.mean(lam[g]), 9)) + 0.0  # + 0.0: no signed zeros
            for j, k in enumerate(g):
                labels[k] += f" ({j + 1} of {len(g)} at {mid.real:.3g}{mid.imag:+.3g}i)"
    for k in range(lam.size):
        if abs(lam[k].imag) > 0 and all(len(g) == 1 for g in groups if k in g):
            labels[k] += " (pair +i)" if lam[k].imag > 0 else " (pair -i)"
    for digits in (3, 6, 12):  # distinct eigenvalues whose states read the same: add the eigenvalue
        dup = {q for q in labels if labels.count(q) > 1}
        if not dup:
            break
        for k in range(lam.size):
            if labels[k] in dup:
                labels[k] += f" [{lam[k].real:.{digits}g}{lam[k].imag:+.{digits}g}i/s]"
    return labels


def _state_matrix(sys: Any) -> np.ndarray:
    if not isinstance(sys, control.StateSpace):
        raise ArgumentTypeError(f"sys must be a control.StateSpace (e.g. from gc.linearize_glide), got "
                                f"{type(sys).__name__}")
    A = np.asarray(sys.A)
    if A.shape[0] == 0:
        raise ArgumentError("sys has no states")
    if np.iscomplexobj(A) or not np.all(np.isfinite(A)):
        raise ArgumentError("sys.A must be a finite real matrix (no NaN or inf)")
    return A


def modes(sys: control.StateSpace) -> Modes:
    """Eigenvalues, eigenvectors, natural frequencies, damping ratios, state participations and labels of the modes
    of ``sys``.

    Parameters
    ----------
    sys : control.StateSpace
        Linear model with named states (time in s), e.g. from :func:`linearize_glide`.

    Returns
    -------
    Modes
        Eigenvalues (1/s) sorted by decreasing real part, unit-norm eigenvectors, natural frequencies (rad/s),
        damping ratios (nondimensional; NaN for a zero eigenvalue), time constants (s; inf for ``Re = 0``), the
        participation of each state in each mode (unit-free), the dominant state and a distinct label of each mode.

    Raises
    ------
    ArgumentTypeError
        If ``sys`` is not a :class:`control.StateSpace`.
    ArgumentError
        If ``sys`` has no states or ``sys.A`` is not finite.
    SolverError
        If the eigenvalue, Schur or Sylvester computation fails.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> sys = gc.linearize_glide(veh, gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05))
    >>> m = gc.modes(sys)
    >>> print(f"{m.eigenvalues[-1].real:.4f} 1/s: {m.labels[-1]}")  # the fastest mode
    -2.9181 1/s: v3 34% + r_P3 23% + theta 20%
    """
    A = _state_matrix(sys)
    try:
        lam, vec = np.linalg.eig(A)
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"eigenvalues of the {A.shape[0]}-state model did not converge: {exc}") from exc
    order = np.lexsort((-lam.imag, -lam.real))
    lam, vec = lam[order], vec[:, order]
    vec = vec / np.linalg.norm(vec, axis=0)
    wn = np.abs(lam)
    with np.errstate(divide="ignore", invalid="ignore"):
        zeta = np.where(wn > 0, -lam.real / wn, np.nan)
        tc = np.where(lam.real != 0, -1.0 / lam.real, np.inf)
    names = list(sys.state_labels)
    scale = float(np.linalg.norm(A, 2))
    groups = _clusters(lam, scale)
    part = np.zeros((A.shape[0], lam.size))
    try:
        for g in groups:
            d = _projector_diagonal(A, complex(np.mean(lam[g])), 1e-6 * max(scale, 1.0))
            part[:, g] = (d / np.sum(d))[:, None]
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise SolverError(f"participation factors of the {A.shape[0]}-state model failed: {exc}") from exc
    dom = tuple(names[int(_ranked(part[:, k])[0])] for k in range(lam.size))
    return Modes(lam, vec, wn, zeta, tc, dom, part, tuple(_mode_labels(lam, part, names, groups)))


@dataclass(frozen=True)
class ModeStates:
    """A mode that fails a rank test, in state terms.

    Attributes
    ----------
    eigenvalue : complex
        The mode's eigenvalue (1/s).
    states : tuple of str
        The states that make up 90 % of the failing direction (at most four), largest share first.
    shares : ndarray
        Their shares (nondimensional, of 1): the diagonal of the orthogonal projector onto the failing directions
        (the null space of ``[A - lambda I; C]`` for observability, of ``[A - lambda I, B]^T`` for controllability) in
        the test's balanced coordinates, divided by its dimension.
    dimension : int
        Number of independent failing directions at this eigenvalue.
    """

    eigenvalue: complex
    states: tuple[str, ...]
    shares: np.ndarray
    dimension: int

    def __str__(self) -> str:
        lam = self.eigenvalue
        what = " + ".join(f"{q} {100 * w:.0f}%" for q, w in zip(self.states, self.shares, strict=True))
        return f"{lam.real:.4g}{lam.imag:+.4g}i ({what}" + (f"; {self.dimension} directions)" if self.dimension > 1
                                                          else ")")


def _failing_states(As: np.ndarray, Bs: np.ndarray, bad: np.ndarray, names: Sequence[str], pbh_tol: float,
                    scale: float) -> tuple[ModeStates, ...]:
    """The states of the left null space of ``[As - lam I, Bs]`` at each distinct failing eigenvalue."""
    n = As.shape[0]
    out = []
    for g in _clusters(bad, scale):
        lam = complex(bad[g[0]])
        M = np.hstack([As - lam * np.eye(n), Bs])
        u, sv, _ = np.linalg.svd(M)
        dim = max(1, int(np.sum(sv / scale < pbh_tol)))
        c = np.sum(np.abs(u[:, n - dim:]) ** 2, axis=1) / dim
        order = np.argsort(-c, kind="stable")
        chosen, total = [], 0.0
        for i in order[:4]:
            chosen.append(int(i))
            total += c[i]
            if total >= 0.9:
                break
        out.append(ModeStates(lam, tuple(names[i] for i in chosen), c[chosen], dim))
    return tuple(out)


@dataclass(frozen=True)
class RankTest:
    """Result of a controllability or observability test.

    Attributes
    ----------
    kind : str
        ``"controllability"`` or ``"observability"``.
    rank, n : int
        Numerical rank of the Kalman matrix (with ``tol``) and state dimension.
    tol : float
        Rank tolerance on singular values of the Kalman matrix after state scaling.
    singular_values : ndarray
        Singular values of the (scaled) Kalman matrix, largest first.
    pbh_min : ndarray
        For each eigenvalue, the smallest singular value of ``[A - lam I, B]`` (or its dual) relative to
        ``||[A, B]||``; near zero means the mode is uncontrollable (unobservable).
    uncontrollable_modes : ndarray
        Eigenvalues whose PBH margin is below ``pbh_tol`` (unobservable ones for observability).
    pbh_tol : float
    channels : tuple of str
        Inputs (or outputs) the test used.
    mode_states : tuple of ModeStates
        Each distinct failing eigenvalue in state terms: the states its uncontrollable (unobservable) directions are
        made of, with their shares (:class:`ModeStates`); empty when the test passes.
    """

    kind: str
    rank: int
    n: int
    tol: float
    singular_values: np.ndarray
    pbh_min: np.ndarray
    eigenvalues: np.ndarray
    uncontrollable_modes: np.ndarray
    pbh_tol: float
    channels: tuple[str, ...]
    mode_states: tuple[ModeStates, ...] = ()

    @property
    def full(self) -> bool:
        """True when the Kalman rank is full and no mode fails the PBH test."""
        return self.rank == self.n and self.uncontrollable_modes.size == 0

    @property
    def pbh_rank_deficiency(self) -> int:
        """Number of eigenvalues (with multiplicity) failing the PBH test."""
        return int(self.uncontrollable_modes.size)

    def __str__(self) -> str:
        verdict = "full" if self.full else "NOT full"
        if self.mode_states:
            bad = ", ".join(str(m) for m in self.mode_states)
        else:
            bad = ", ".join(f"{z.real:.4g}{z.imag:+.4g}i" for z in np.unique(np.round(self.uncontrollable_modes, 9)))
        return (f"{self.kind} with {', '.join(self.channels)}: rank {self.rank}/{self.n} ({verdict}; "
                f"tol {self.tol:.2e}, min relative PBH singular value {np.min(self.pbh_min):.2e})"
                + (f"; failing PBH at {bad}" if bad else ""))


def _scaled_rank(K: np.ndarray, tol: float | None) -> tuple[int, float, np.ndarray]:
    s = np.linalg.svd(K, compute_uv=False)
    if tol is None:
        tol = max(K.shape) * np.finfo(float).eps * (s[0] if s.size else 0.0) * 1e3
    return int(np.sum(s > tol)), float(tol), s


def _pbh(A: np.ndarray, B: np.ndarray, pbh_tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = A.shape[0]
    lam = np.linalg.eigvals(A)
    scale = np.linalg.norm(np.hstack([A, B]), 2) or 1.0  # A = 0, B = 0: every margin is 0 (uncontrollable)
    mins = np.array([np.linalg.svd(np.hstack([A - l * np.eye(n), B]), compute_uv=False)[-1] / scale
                     for l in lam])
    return lam, mins, lam[mins < pbh_tol]


def _index(names: Any, labels: Sequence[str], what: str) -> list[int]:
    """Indices of the selected names (a single name is one channel, never split into characters)."""
    labels = list(labels)
    if isinstance(names, str):
        names = [names]
    elif isinstance(names, bytes) or not isinstance(names, Sequence | np.ndarray):
        raise ArgumentTypeError(f"the {what} selection must be a name or a sequence of names from {labels}, got "
                                f"{type(names).__name__} {names!r}")
    names = list(names)
    if not all(isinstance(q, str) for q in names):
        raise ArgumentTypeError(f"the {what} selection must hold names (str) from {labels}, got {names!r}")
    if len(names) == 0:
        raise ArgumentError(f"empty {what} selection; pass None for all of {labels}")
    bad = [q for q in names if q not in labels]
    if bad:
        raise ArgumentError(f"unknown {what} {bad}; this model has {labels}")
    if len(set(names)) != len(names):
        raise ArgumentError(f"the {what} selection {names} names a channel twice")
    return [labels.index(q) for q in names]


def _tolerances(tol: Any, pbh_tol: Any) -> tuple[float | None, float]:
    return (None if tol is None else checks.positive("tol", tol)), checks.positive("pbh_tol", pbh_tol)


def controllability(sys: control.StateSpace, inputs: Sequence[str] | None = None,
                    states: Sequence[str] | None = None, tol: float | None = None,
                    pbh_tol: float = 1e-8) -> RankTest:
    """Controllability of ``sys`` (optionally restricted to some inputs and a subset of states).

    Parameters
    ----------
    sys : control.StateSpace
    inputs : str or sequence of str, optional
        Input names to keep (default: all); a single name is one input.
    states : str or sequence of str, optional
        States to keep (the others are removed, e.g. to model a moving mass locked along one axis).
    tol : float, optional
        Rank tolerance for the Kalman matrix ``ctrb(A, B)`` computed by python-control on state-scaled
        ``(A, B)``; default ``1e3 * max(shape) * eps * sigma_max``.
    pbh_tol : float
        Threshold on the relative PBH singular value (nondimensional).

    Returns
    -------
    RankTest
        Kalman rank (with the tolerance and singular values behind it), the relative PBH margin at every eigenvalue
        of the (scaled) ``A`` and the modes failing it, and the inputs used.

    Raises
    ------
    ArgumentTypeError
        If ``sys`` is not a :class:`control.StateSpace`, a selection is not a name or a sequence of names, or a
        tolerance is not a real number.
    ArgumentError
        If ``inputs`` or ``states`` names an input or state ``sys`` does not have, names one twice or selects none;
        a tolerance is not positive and finite; ``sys`` has no states or non-finite matrices.
    SolverError
        If the balancing, SVD or eigenvalue computation fails.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> sys = gc.linearize_glide(veh, gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05))
    >>> c = gc.controllability(sys)
    >>> c.rank, c.n
    (10, 10)
    >>> gc.controllability(sys, inputs=("u1", "u3")).mode_states[0].states  # without the pump u4
    ('m0',)
    """
    A = _state_matrix(sys)
    B = np.asarray(sys.B)
    if np.iscomplexobj(B) or not np.all(np.isfinite(B)):
        raise ArgumentError("sys.B must be a finite real matrix (no NaN or inf)")
    if inputs is None and B.shape[1] == 0:
        raise ArgumentError("sys has no inputs: nothing can be controllable")
    si = _index(sys.state_labels if states is None else states, sys.state_labels, "state")
    ui = _index(sys.input_labels if inputs is None else inputs, sys.input_labels, "input")
    tol, pbh_tol = _tolerances(tol, pbh_tol)
    A, B = A[np.ix_(si, si)], B[np.ix_(si, ui)]
    # diagonal similarity scaling (balancing) to make the Kalman matrix well conditioned
    from scipy.linalg import matrix_balance
    try:
        _, T = matrix_balance(A, permute=False, separate=True)
        d = T[0]
        As, Bs = A * (1 / d)[:, None] * d[None, :], B / d[:, None]
        rank, tol_used, s = _scaled_rank(np.asarray(control.ctrb(As, Bs)), tol)
        lam, mins, bad = _pbh(As, Bs, pbh_tol)
        failing = _failing_states(As, Bs, bad, [sys.state_labels[i] for i in si], pbh_tol,
                                  float(np.linalg.norm(np.hstack([As, Bs]), 2)) or 1.0)
    except (np.linalg.LinAlgError, ValueError, FloatingPointError, ZeroDivisionError) as exc:
        raise SolverError(f"controllability test failed numerically ({type(exc).__name__}: {exc})") from exc
    return RankTest("controllability", rank, A.shape[0], tol_used, s, mins, lam, bad, pbh_tol,
                    tuple(sys.input_labels[i] for i in ui), failing)


def observability(sys: control.StateSpace, outputs: Sequence[str], states: Sequence[str] | None = None,
                  tol: float | None = None, pbh_tol: float = 1e-8) -> RankTest:
    """Observability of ``sys`` when only the named outputs (or states) are measured.

    Parameters
    ----------
    sys : control.StateSpace
        Linear model with named states and outputs, e.g. from :func:`linearize_glide` (with ``outputs=`` for depth
        and combinations).
    outputs : str or sequence of str
        Names of the measured signals: outputs of ``sys`` (their rows of ``sys.C``) or states (rows of I; an output
        name wins when a name is both); a single name is one signal (never split into characters).
    states : str or sequence of str, optional
        States to keep (the others are removed, as in :func:`controllability`); default all.
    tol : float, optional
        Rank tolerance of the (scaled) Kalman observability matrix; default as in :func:`controllability`.
    pbh_tol : float
        Threshold on the relative PBH singular value (nondimensional).

    Returns
    -------
    RankTest
        ``kind = "observability"``; ``uncontrollable_modes`` holds the unobservable modes (eigenvalues, 1/s),
        ``mode_states`` names each in state terms (the states its unobservable directions, the null space of
        ``[A - lambda I; C]``, are made of, with their shares) and ``channels`` the measured signals. Computed as the
        controllability of the dual ``(A^T, C^T)``.

    Raises
    ------
    ArgumentTypeError
        If ``sys`` is not a :class:`control.StateSpace`, ``outputs`` is not a name or a sequence of names, or a
        tolerance is not a real number.
    ArgumentError
        If ``outputs`` is empty, names a signal that is neither an output nor a state of ``sys``, or names one twice;
        ``states`` names an unknown state, one twice or none; a tolerance is not positive and finite; ``sys`` has no
        states or a non-finite ``A`` or ``C``.
    SolverError
        If the balancing, SVD or eigenvalue computation fails.

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("rogue")
    >>> g = gc.steady_glide(veh, speed=0.3, gamma=-np.pi / 4, r_p3=0.05)
    >>> o = gc.observability(gc.linearize_glide(veh, g, outputs=("z", "theta")), ["z", "theta"])
    >>> o.rank, o.n, o.mode_states[0].states
    (8, 11, ('z_prime', 'r_P3', 'r_P1'))
    """
    A = _state_matrix(sys)
    olabels = list(sys.output_labels)
    slabels = list(sys.state_labels)
    labels = olabels + [q for q in slabels if q not in olabels]
    oi = _index(outputs, labels, "output or state")
    Cs = np.asarray(sys.C)
    if np.iscomplexobj(Cs) or not np.all(np.isfinite(Cs)):
        raise ArgumentError("sys.C must be a finite real matrix (no NaN or inf)")
    eye = np.eye(A.shape[0])
    C = np.array([Cs[i] if i < len(olabels) else eye[slabels.index(labels[i])] for i in oi])
    si = _index(slabels if states is None else states, slabels, "state")
    tol, pbh_tol = _tolerances(tol, pbh_tol)
    A, C = A[np.ix_(si, si)], C[:, si]
    r = controllability(control.ss(A.T, C.T, np.eye(len(si)), 0, states=[slabels[i] for i in si]), tol=tol,
                        pbh_tol=pbh_tol)
    return RankTest("observability", r.rank, r.n, r.tol, r.singular_values, r.pbh_min, r.eigenvalues,
                    r.uncontrollable_modes, pbh_tol, tuple(labels[i] for i in oi), r.mode_states)
