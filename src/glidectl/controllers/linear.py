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
from ..analysis.linear import linearize_glide
from ..errors import ArgumentError, ArgumentTypeError, SolverError, VehicleMismatchError
from ..models._validate import numeric_array, require_glider, require_instance, trailing_array
from ..params import Vehicle
from ..trim.glide import SteadyGlide

__all__ = [
    "DEFAULT_MAX_DEVIATION",
    "DecoupledAccelerationFeedback",
    "LinearGlideController",
    "decoupled_gain_matrix",
    "lqr_glide",
    "place_glide",
]

#: Bryson's-rule scales: acceptable deviation of each state / input (SI units) for the default LQR weights.
DEFAULT_MAX_DEVIATION: Mapping[str, float] = {
    "z_prime": 0.5, "theta": 0.1, "Omega2": 0.2, "v1": 0.05, "v3": 0.05, "r_P1": 0.02, "r_P3": 0.02,
    "P_P1": 0.1, "P_P3": 0.1, "m0": 0.1, "rdot_P1": 0.02, "rdot_P3": 0.02,
    "u1": 1.0, "u3": 1.0, "u4": 0.05, "w1": 0.1, "w3": 0.1, "w4": 0.05,
}


@dataclass(frozen=True)
class LinearGlideController:
    """State feedback ``u = u_e - K (x_r - x_r,e)`` about a steady glide, on the glide-path state ``x_r``.

    Attributes
    ----------
    K : ndarray, shape (3, 10)
        Gain on ``(z_prime, theta, ...)`` (SI units).
    method : str
        ``"lqr"`` or ``"place"``.
    plant : control.StateSpace
        Open-loop linearization the gain was designed on.
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

    Raises
    ------
    ArgumentTypeError
        If ``glide`` is not a SteadyGlide, ``plant`` not a state-space model, or a number has the wrong type.
    ArgumentError
        If ``method`` or ``inputs`` is unknown, ``K`` is not a finite (inputs x states) array, or ``path_offset``
        is not finite.
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
        if self.vehicle is not None:
            require_glider(self.vehicle)
            checks.same_vehicle("glide", self.glide, self.vehicle)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(self.plant.state_labels)

    def reduced_state(self, x: Any) -> np.ndarray:
        """Full state (x, z, ...) (shape ``(..., 11)``) -> glide-path state (z', ...) with
        ``z' = sin(g_e) x + cos(g_e) z - offset``."""
        x = checks.array("x", x)
        trailing_array("x", x, len(self.state_names) + 1)
        zp = np.sin(self.glide.gamma) * x[..., 0] + np.cos(self.glide.gamma) * x[..., 1] - self.path_offset
        return np.concatenate([zp[..., None], x[..., 2:]], axis=-1)

    def equilibrium(self) -> np.ndarray:
        """Glide-path equilibrium state (z' = 0)."""
        xe = self.glide.force_state() if self.inputs == "force" else self.glide.accel_state()
        return np.concatenate([[0.0], xe[2:]])

    def u(self, x: Any) -> np.ndarray:
        """Input (u1, u3, u4) or (w1, w3, w4) for full states ``x`` (shape ``(..., 11)``)."""
        return -(self.reduced_state(x) - self.equilibrium()) @ self.K.T

    def path_input(self, xr: Any) -> np.ndarray:
        """Input for glide-path states ``xr = (z', theta, ...)`` of
        :class:`~glidectl.models.longitudinal.GlidePathModel` (shape ``(..., 10)``; ``z'`` in m from the path through
        the origin, so the law regulates ``z' = path_offset``)."""
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


def _bryson(names: Sequence[str], max_dev: Mapping[str, float]) -> np.ndarray:
    return np.diag([1.0 / max_dev[n] ** 2 for n in names])


def _glide_for(veh: Any, glide: Any, inputs: Any) -> None:
    """Checks shared by :func:`lqr_glide` and :func:`place_glide`, before anything is computed."""
    require_glider(veh, "veh")
    require_instance("glide", glide, SteadyGlide, " (from gc.steady_glide)")
    checks.same_vehicle("glide", glide, veh)
    checks.choice("inputs", inputs, ("force", "acceleration"))


def _weight(name: str, value: Any, n: int, *, definite: bool) -> np.ndarray:
    """A symmetric ``n x n`` weight, positive semidefinite (``definite``: positive definite)."""
    W = checks.array(name, value, shape=(n, n))
    if not np.allclose(W, W.T, rtol=1e-12, atol=1e-12 * max(1.0, float(np.max(np.abs(W))))):
        raise ArgumentError(f"{name} must be symmetric")
    ev = np.linalg.eigvalsh(0.5 * (W + W.T))
    scale = max(1.0, float(np.max(np.abs(ev))))
    if (definite and not ev[0] > 1e-12 * scale) or ev[0] < -1e-12 * scale:
        raise ArgumentError(f"{name} must be positive {'definite' if definite else 'semidefinite'}; its smallest "
                            f"eigenvalue is {ev[0]:.3g}")
    return W


def lqr_glide(veh: Vehicle, glide: SteadyGlide, *, inputs: Literal["force", "acceleration"] = "force",
              Q: Any = None, R: Any = None, max_deviation: Mapping[str, float] | None = None
              ) -> LinearGlideController:
    """LQR regulator to the glide path of ``glide`` (z' included), designed with :func:`control.lqr`.

    Parameters
    ----------
    veh, glide : Vehicle, SteadyGlide
    inputs : {"force", "acceleration"}
    Q, R : array_like, optional
        Weights on the glide-path state and the input; default Bryson's rule with ``max_deviation``
        (default :data:`DEFAULT_MAX_DEVIATION`).
    max_deviation : mapping of str to float, optional
        Acceptable deviation of named states and inputs (SI units of each: m, rad, rad/s, m/s, kg m/s, kg, N,
        m/s^2, kg/s), overriding entries of :data:`DEFAULT_MAX_DEVIATION` for Bryson's rule
        (``Q_ii = 1 / max_i^2``).

    Returns
    -------
    LinearGlideController
        ``method = "lqr"``, gain ``K`` of shape (3, 10) (input units per glide-path-state unit), the linearization
        it was designed on, the closed-loop poles (1/s) and the weights used.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a SteadyGlide, ``max_deviation`` not a mapping of names to
        real numbers, or ``Q``/``R`` not real arrays.
    ArgumentError
        If ``inputs`` is not ``"force"`` or ``"acceleration"``; ``Q`` is not a finite symmetric positive
        semidefinite 10x10 matrix or ``R`` a finite symmetric positive definite 3x3 matrix; or ``max_deviation``
        names an unknown state or input or gives a value that is not a positive finite number.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.
    SolverError
        If the LQR design fails (python-control's message is included; e.g. no stabilizing solution) or returns a
        gain that is not finite or does not stabilize the linearization.
    """
    _glide_for(veh, glide, inputs)
    if max_deviation is not None and not isinstance(max_deviation, Mapping):
        raise ArgumentTypeError(f"max_deviation must be a mapping of state/input names to deviations, got "
                                f"{type(max_deviation).__name__}")
    sys = linearize_glide(veh, glide, inputs)
    extra = dict(max_deviation or {})
    known = set(sys.state_labels) | set(sys.input_labels)
    unknown = sorted(str(k) for k in extra if k not in known)
    if unknown:
        raise ArgumentError(f"max_deviation names {unknown}, which are not states or inputs of this design; known: "
                            f"{sorted(known)}")
    for k, v in extra.items():
        extra[k] = checks.positive(f"max_deviation[{k!r}]", v)
    dev = {**DEFAULT_MAX_DEVIATION, **extra}
    n, m = sys.nstates, sys.ninputs
    Qm = _bryson(sys.state_labels, dev) if Q is None else _weight("Q", Q, n, definite=False)
    Rm = _bryson(sys.input_labels, dev) if R is None else _weight("R", R, m, definite=True)
    try:
        K, _, E = control.lqr(sys, Qm, Rm)
    except Exception as exc:  # python-control raises several types (ControlArgument, LinAlgError, ValueError)
        raise SolverError(f"LQR design failed for glide gamma = {np.degrees(glide.gamma):.2f} deg: {exc}") from exc
    K, E = np.asarray(K, dtype=float), np.asarray(E)
    if not (np.all(np.isfinite(K)) and np.all(np.isfinite(E)) and np.max(E.real) < 0):
        raise SolverError(f"LQR design for glide gamma = {np.degrees(glide.gamma):.2f} deg returned a gain that does "
                          f"not stabilize the linearization (closed-loop poles {np.round(E, 6)}); check Q (the "
                          "unstable modes must be weighted)")
    return LinearGlideController(K, "lqr", sys, E, glide, inputs, Qm, Rm, vehicle=veh)


def place_glide(veh: Vehicle, glide: SteadyGlide, poles: Sequence[complex], *,
                inputs: Literal["force", "acceleration"] = "force") -> LinearGlideController:
    """Pole placement to the glide path of ``glide`` with :func:`control.place` (1/s poles, conjugate-closed).

    Parameters
    ----------
    veh : Vehicle
        The underwater glider the glide was trimmed for.
    glide : SteadyGlide
        From :func:`~glidectl.trim.glide.steady_glide`.
    poles : sequence of complex
        The 10 requested closed-loop poles (1/s), finite and closed under conjugation (a pole may be repeated at
        most as often as there are inputs, 3).
    inputs : {"force", "acceleration"}
        Input form of the linearization (see :func:`~glidectl.analysis.linear.linearize_glide`).

    Returns
    -------
    LinearGlideController
        ``method = "place"``, gain ``K`` of shape (3, 10), the linearization and the achieved closed-loop poles
        (1/s); ``Q`` and ``R`` are None.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` not a SteadyGlide, or ``poles`` not numbers.
    ArgumentError
        If the number of poles differs from the number of states, a pole is not finite, the set is not closed under
        conjugation or repeats a pole more often than there are inputs, or ``inputs`` is not ``"force"`` or
        ``"acceleration"``.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle.
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``.
    SolverError
        If :func:`control.place` fails or the achieved poles differ from the requested ones by more than 1e-6
        (relative).
    """
    _glide_for(veh, glide, inputs)
    p = numeric_array("poles", poles).astype(complex).ravel()
    if not np.all(np.isfinite(p)):
        raise ArgumentError(f"poles must be finite, got {poles!r}")
    sys = linearize_glide(veh, glide, inputs)
    if p.size != sys.nstates:
        raise ArgumentError(f"need {sys.nstates} poles for states {list(sys.state_labels)}, got {p.size}")
    scale = np.maximum(1.0, np.abs(p))
    if np.max(np.min(np.abs(p[:, None] - np.conj(p)[None, :]) / scale[:, None], axis=1)) > 1e-9:
        raise ArgumentError(f"poles must be closed under complex conjugation (real gains), got {np.round(p, 6)}")
    mult = np.sum(np.abs(p[:, None] - p[None, :]) <= 1e-12 * scale[:, None], axis=1)
    if np.max(mult) > sys.ninputs:
        raise ArgumentError(f"a pole is repeated {int(np.max(mult))} times; with {sys.ninputs} inputs place_glide "
                            f"can repeat a pole at most {sys.ninputs} times (spread them slightly)")
    try:
        with warnings.catch_warnings():
            # scipy's YT robustness iteration may stop before its tolerance; the placement itself is checked below
            warnings.filterwarnings("ignore", message="Convergence was not reached", category=UserWarning)
            K = np.asarray(control.place(np.asarray(sys.A), np.asarray(sys.B), p))
    except Exception as exc:  # python-control / scipy raise several types
        raise SolverError(f"pole placement failed: {exc}") from exc
    if not np.all(np.isfinite(K)):
        raise SolverError("pole placement returned a gain that is not finite")
    E = np.linalg.eigvals(np.asarray(sys.A) - np.asarray(sys.B) @ K)
    r, c = linear_sum_assignment(np.abs(E[:, None] - p[None, :]))
    err = float(np.max(np.abs(E[r] - p[c]) / np.maximum(1.0, np.abs(p[c]))))
    if err > 1e-6:
        raise SolverError(f"pole placement inaccurate: closed-loop poles {np.round(E, 6)} differ from the "
                            f"requested {np.round(p, 6)} (relative error {err:.1e}); the requested set may be "
                            "ill-conditioned for this plant")
    return LinearGlideController(K, "place", sys, E, glide, inputs, vehicle=veh)


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
    """
    kp1, kd1, kp3, kd3, k4 = (checks.real(n, v) for n, v in
                              (("kp1", kp1), ("kd1", kd1), ("kp3", kp3), ("kd3", kd3), ("k4", k4)))
    K = np.zeros((3, 5))
    K[0, 0], K[0, 1], K[1, 2], K[1, 3], K[2, 4] = kp1, kd1, kp3, kd3, k4
    return K


@dataclass(frozen=True)
class DecoupledAccelerationFeedback:
    """Decoupled feedback (2.37) on the moving mass and buoyancy of the acceleration-controlled glider.

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
