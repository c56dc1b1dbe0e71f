"""Linearization about steady glides, modal analysis, controllability and observability (§2.3.1).

Linear models are returned as :class:`control.StateSpace` with named states, inputs and outputs (outputs = all
states). Ranks are reported with the tolerance used and the singular values behind them, and checked by the
PBH (Popov-Belevitch-Hautus) test at every eigenvalue, which does not suffer from the conditioning of the Kalman
matrix on badly scaled states.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import control
import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, SolverError
from ..models.longitudinal import (
    AccelerationControlledGlider,
    GlidePathModel,
    LongitudinalGlider,
)
from ..params import Vehicle
from ..trim.glide import SteadyGlide
from .jacobian import jacobians

__all__ = ["Modes", "RankTest", "controllability", "glide_model", "linearize_glide", "modes", "observability"]

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


def linearize_glide(veh: Vehicle, glide: SteadyGlide, inputs: InputKind = "force") -> control.StateSpace:
    """Exact linearization of the longitudinal glider about a steady glide, with z' (2.30).

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

    Returns
    -------
    control.StateSpace
        ``A, B`` exact (complex step); ``C = I``, ``D = 0``; states/inputs/outputs named; units in
        :data:`glidectl.models.longitudinal.STATE_UNITS`.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or ``glide`` is not a :class:`~glidectl.trim.glide.SteadyGlide` (e.g. ``None``).
    ArgumentError
        If ``inputs`` is not ``"force"`` or ``"acceleration"``.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle (different provenance).
    ModelError
        If ``veh`` is not an underwater glider or has ``mbar <= 0``, or the linearization is not finite at the glide.
    """
    model, xe = glide_model(veh, glide, inputs)
    A, B = jacobians(model.rhs, xe, np.zeros(3))
    n = A.shape[0]
    names = list(model.state_names)
    return control.ss(A, B, np.eye(n), np.zeros((n, 3)), states=names, inputs=list(model.input_names),
                      outputs=names, name=f"{veh.name}_gamma{np.degrees(glide.gamma):+.0f}deg_{inputs}")


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
    """Observability of ``sys`` when only the named states are measured (``y = C x`` with those rows of I).

    Parameters
    ----------
    sys : control.StateSpace
        Linear model with named states.
    outputs : str or sequence of str
        Names of the measured states; a single name is one output (never split into characters).
    tol : float, optional
        Rank tolerance of the (scaled) Kalman observability matrix; default as in :func:`controllability`.
    pbh_tol : float
        Threshold on the relative PBH singular value (nondimensional).

    Returns
    -------
    RankTest
        ``kind = "observability"``; ``uncontrollable_modes`` holds the unobservable modes (eigenvalues, 1/s) and
        ``channels`` the measured states. Computed as the controllability of the dual ``(A^T, C^T)``.

    Raises
    ------
    ArgumentTypeError
        If ``sys`` is not a :class:`control.StateSpace`, ``outputs`` is not a name or a sequence of names, or a
        tolerance is not a real number.
    ArgumentError
        If ``outputs`` is empty, names a state ``sys`` does not have or names one twice; a tolerance is not positive
        and finite; ``sys`` has no states or a non-finite ``A``.
    SolverError
        If the balancing, SVD or eigenvalue computation fails.
    """
    A = _state_matrix(sys)
    oi = _index(outputs, sys.state_labels, "output state")
    tol, pbh_tol = _tolerances(tol, pbh_tol)
    C = np.eye(A.shape[0])[oi]
    r = controllability(control.ss(A.T, C.T, np.eye(A.shape[0]), 0, states=list(sys.state_labels)),
                        tol=tol, pbh_tol=pbh_tol)
    return RankTest("observability", r.rank, r.n, r.tol, r.singular_values, r.pbh_min, r.eigenvalues,
                    r.uncontrollable_modes, pbh_tol, tuple(sys.state_labels[i] for i in oi))
