"""Linearization about steady glides, modal analysis, controllability and observability (§2.3.1).

Linear models are returned as :class:`control.StateSpace` with named states, inputs and outputs (outputs = all
states). Ranks are reported with the tolerance used and the singular values behind them, and checked by the
PBH (Popov-Belevitch-Hautus) test at every eigenvalue, which does not suffer from the conditioning of the Kalman
matrix on badly scaled states.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import control
import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, SolverError
from ..models._validate import trailing_array
from ..models.longitudinal import (
    AccelerationControlledGlider,
    GlidePathModel,
    LongitudinalGlider,
)
from ..params import Vehicle
from ..trim.glide import SteadyGlide
from .jacobian import jacobians

__all__ = ["EXTRA_OUTPUTS", "DepthGlidePathModel", "Modes", "OutputMap", "RankTest", "controllability", "depth_rate",
           "glide_model", "linearize_glide", "modes", "observability", "output_map"]

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


def depth_rate(model: Any, x: Any) -> Any:
    """Depth rate ``-sin(theta) v1 + cos(theta) v3`` (m/s, (2.16)) of glide-path states ``x`` (batch,
    complex-safe), from the base model's own kinematics."""
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
                    outputs: Any = None) -> control.StateSpace:
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
        If ``inputs`` is not ``"force"`` or ``"acceleration"``, or ``outputs`` names an unknown channel, names one
        twice, is empty or gives a combination without a nonzero finite coefficient.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle (different provenance).
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``, or the linearization is not finite at the glide.
    """
    model, xe = glide_model(veh, glide, inputs)
    omap = None if outputs is None else output_map(outputs, model.state_names)
    plant: Any = model
    if omap is not None and omap.needs_depth:
        plant, xe = DepthGlidePathModel(model), np.concatenate([xe, [0.0]])
    A, B = jacobians(plant.rhs, xe, np.zeros(3))
    n = A.shape[0]
    names = list(plant.state_names)
    if omap is None:
        C, onames = np.eye(n), names
    else:
        C, _ = jacobians(lambda x, u: omap(plant, x), xe, np.zeros(0))
        onames = list(omap.names)
    return control.ss(A, B, C, np.zeros((C.shape[0], 3)), states=names, inputs=list(model.input_names),
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
        State with the largest magnitude in each (unit-normalized) eigenvector.
    """

    eigenvalues: np.ndarray
    eigenvectors: np.ndarray
    wn: np.ndarray
    zeta: np.ndarray
    time_constant: np.ndarray
    dominant_states: tuple[str, ...]

    @property
    def stable(self) -> bool:
        """All eigenvalues strictly in the open left half plane."""
        return bool(np.all(self.eigenvalues.real < 0))

    def __str__(self) -> str:
        lines = [f"{'eigenvalue [1/s]':>26} {'wn [rad/s]':>11} {'zeta':>8} {'tau [s]':>10}  dominant state"]
        for lam, wn, z, tc, d in zip(self.eigenvalues, self.wn, self.zeta, self.time_constant,
                                     self.dominant_states, strict=True):
            lines.append(f"{lam.real:12.5g} {lam.imag:+12.5g}i {wn:11.5g} {z:8.4g} {tc:10.4g}  {d}")
        return "\n".join(lines)


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
    """Eigenvalues, eigenvectors, natural frequencies, damping ratios and dominant states of ``sys``.

    Parameters
    ----------
    sys : control.StateSpace
        Linear model with named states (time in s), e.g. from :func:`linearize_glide`.

    Returns
    -------
    Modes
        Eigenvalues (1/s) sorted by decreasing real part, unit-norm eigenvectors, natural frequencies (rad/s),
        damping ratios (nondimensional; NaN for a zero eigenvalue), time constants (s; inf for ``Re = 0``) and
        the dominant state of each mode.

    Raises
    ------
    ArgumentTypeError
        If ``sys`` is not a :class:`control.StateSpace`.
    ArgumentError
        If ``sys`` has no states or ``sys.A`` is not finite.
    SolverError
        If the eigenvalue computation does not converge.
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
    names = sys.state_labels
    dom = tuple(names[int(np.argmax(np.abs(vec[:, k])))] for k in range(lam.size))
    return Modes(lam, vec, wn, zeta, tc, dom)


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
    except (np.linalg.LinAlgError, ValueError, FloatingPointError, ZeroDivisionError) as exc:
        raise SolverError(f"controllability test failed numerically ({type(exc).__name__}: {exc})") from exc
    return RankTest("controllability", rank, A.shape[0], tol_used, s, mins, lam, bad, pbh_tol,
                    tuple(sys.input_labels[i] for i in ui))


def observability(sys: control.StateSpace, outputs: Sequence[str], tol: float | None = None,
                  pbh_tol: float = 1e-8) -> RankTest:
    """Observability of ``sys`` when only the named outputs (or states) are measured.

    Parameters
    ----------
    sys : control.StateSpace
        Linear model with named states and outputs, e.g. from :func:`linearize_glide` (with ``outputs=`` for depth
        and combinations).
    outputs : str or sequence of str
        Names of the measured signals: outputs of ``sys`` (their rows of ``sys.C``) or states (rows of I; an output
        name wins when a name is both); a single name is one signal (never split into characters).
    tol : float, optional
        Rank tolerance of the (scaled) Kalman observability matrix; default as in :func:`controllability`.
    pbh_tol : float
        Threshold on the relative PBH singular value (nondimensional).

    Returns
    -------
    RankTest
        ``kind = "observability"``; ``uncontrollable_modes`` holds the unobservable modes (eigenvalues, 1/s) and
        ``channels`` the measured signals. Computed as the controllability of the dual ``(A^T, C^T)``.

    Raises
    ------
    ArgumentTypeError
        If ``sys`` is not a :class:`control.StateSpace`, ``outputs`` is not a name or a sequence of names, or a
        tolerance is not a real number.
    ArgumentError
        If ``outputs`` is empty, names a signal that is neither an output nor a state of ``sys``, or names one twice;
        a tolerance is not positive and finite; ``sys`` has no states or a non-finite ``A`` or ``C``.
    SolverError
        If the balancing, SVD or eigenvalue computation fails.
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
    tol, pbh_tol = _tolerances(tol, pbh_tol)
    r = controllability(control.ss(A.T, C.T, np.eye(A.shape[0]), 0, states=slabels), tol=tol, pbh_tol=pbh_tol)
    return RankTest("observability", r.rank, r.n, r.tol, r.singular_values, r.pbh_min, r.eigenvalues,
                    r.uncontrollable_modes, pbh_tol, tuple(labels[i] for i in oi))
