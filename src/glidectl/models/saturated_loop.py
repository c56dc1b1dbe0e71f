"""A closed loop with a saturated linear state feedback, as an input-free model: :class:`SaturatedLoop`.

``X' = F(X, sat(K (X - X_e)))``: the plant's own right-hand side ``F`` with the deviations ``w`` of the fed-back
channels saturated to ``[u_lo, u_hi]`` (``u_lo < 0 < u_hi``, ``+-inf`` for none). Like a
:class:`~glidectl.models.closed_loop.ClosedLoop` it has no inputs (``input_names == ()``), an ``equilibrium``,
``state_names`` and a batch-capable, complex-safe ``rhs(x, u=None)``, so :func:`glidectl.simulate`,
:func:`glidectl.simulate_many`, :func:`glidectl.jacobians` (``jacobians(loop.rhs, loop.equilibrium, [])``),
:meth:`to_iosys` and the region-of-attraction tools (:func:`glidectl.certify_roa`, :func:`glidectl.certify_roa_lmi`)
take it. The fed-back channels are :attr:`SaturatedLoop.feedback_names` (they are inputs of the plant, not of the
loop). :func:`glidectl.saturated_loop` extracts ``F``, ``K``, the levels, the equilibrium and a box from a glidectl
closed loop.

Also here: :func:`saturate` (a clip that carries a complex step) and the held-state helpers :func:`held_points`,
:func:`at_held_values` and :func:`held_motion` (states a law never moves, used by :func:`glidectl.saturated_loop` and
:func:`glidectl.certify_roa`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError
from ..iosys import IOSysExport
from ..params import Vehicle
from ._validate import trailing_array

__all__ = ["SaturatedLoop", "at_held_values", "held_motion", "held_points", "saturate"]


def saturate(v: Any, lo: np.ndarray, hi: np.ndarray) -> Any:
    """``clip(v, lo, hi)`` carrying a complex step (derivative 1 inside, 0 outside).

    Parameters
    ----------
    v : array_like
        Values (real or complex; the real part is compared with the levels), shape ``(..., m)``.
    lo, hi : ndarray, shape (m,)
        Levels (``-inf``/``inf``: none).

    Returns
    -------
    ndarray
        ``v`` where ``lo <= Re v <= hi``, else the level (plus ``0 v``, so a complex step gives derivative 0).
    """
    re = np.real(v)
    return np.where(re > hi, hi + 0.0 * v, np.where(re < lo, lo + 0.0 * v, v))


# --------------------------------------------------------------------------------------------- the loop
@dataclass(frozen=True, eq=False)
class SaturatedLoop(IOSysExport):
    """Input-free closed loop ``X' = F(X, sat(K (X - X_e)))`` with saturated feedback deviations.

    Parameters
    ----------
    name : str
        What the loop is.
    state_names : tuple of str
        The ``n`` states.
    feedback_names : tuple of str
        The ``n_feedback`` fed-back channels (inputs of the plant, not of the loop).
    plant_rhs : callable
        ``F(X, w)``: states ``(N, n)`` and feedback deviations ``(N, n_feedback)`` (the plant's input units, already
        saturated) to ``X'`` ``(N, n)``; batch-capable and complex-safe (complex-step Jacobians).
    equilibrium : array_like, shape (n,)
        ``X_e`` with ``F(X_e, 0) = 0``.
    K : array_like, shape (n_feedback, n)
        Gain of the feedback deviation ``v = K (X - X_e)`` (input units per state unit), no zero row.
    u_lo, u_hi : array_like, shape (n_feedback,)
        Saturation of ``v``: ``u_lo < 0 < u_hi`` (``-inf``/``inf``: not saturated).
    box : (array_like, array_like)
        Region of interest and validity ``(lo, hi)`` of the states, containing ``X_e`` strictly (except in held
        states).
    held : tuple of int
        States held at their equilibrium value (actuators the law does not move: zero gain, zero rate); the
        certificate is on the others, with these fixed.
    truth : callable, optional
        The loop's own right-hand side ``X (N, n) -> X'`` (default ``F(X, sat(K (X - X_e)))``); :meth:`rhs` and
        verification use it.
    time_unit, provenance : str
        Unit of time of the right-hand side (default ``"s"``) and the vehicle's parameter hash.
    vehicle : Vehicle, optional
        The plant's vehicle (for names in tables and simulations), None when unknown.

    Attributes
    ----------
    input_names : tuple
        ``()`` (input-free).
    n, n_states : int
        Number of states.
    n_feedback : int
        Number of fed-back channels.
    free : tuple of int
        The states that are not held.
    saturating : ndarray of bool
        Channels with a finite saturation level.
    equilibrium : ndarray, shape (n,)
        Read-only.

    Raises
    ------
    ArgumentTypeError
        If a name is not a string or ``plant_rhs`` / ``truth`` is not callable.
    ArgumentError
        If shapes disagree, values are not finite, ``K`` has a zero row, the levels do not bracket 0, or the box
        does not contain the equilibrium strictly in the free states.
    """

    name: str
    state_names: tuple[str, ...]
    feedback_names: tuple[str, ...]
    plant_rhs: Callable[[np.ndarray, np.ndarray], Any] = field(repr=False)
    equilibrium: np.ndarray = field(repr=False)
    K: np.ndarray = field(repr=False)
    u_lo: np.ndarray = field(repr=False)
    u_hi: np.ndarray = field(repr=False)
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    held: tuple[int, ...] = ()
    truth: Callable[[np.ndarray], Any] | None = field(default=None, repr=False)
    time_unit: str = "s"
    provenance: str = ""
    vehicle: Vehicle | None = field(default=None, repr=False)
    input_names: tuple[str, ...] = field(default=(), init=False)

    def __post_init__(self) -> None:
        for nm in ("name", "time_unit", "provenance"):
            if not isinstance(getattr(self, nm), str):
                raise ArgumentTypeError(f"{nm} must be a string, got {type(getattr(self, nm)).__name__}")
        for nm in ("state_names", "feedback_names"):
            val = getattr(self, nm)
            if isinstance(val, str) or not all(isinstance(q, str) for q in val):
                raise ArgumentTypeError(f"{nm} must be a sequence of strings, got {val!r}")
            object.__setattr__(self, nm, tuple(val))
        checks.function("plant_rhs", self.plant_rhs)
        if self.truth is not None:
            checks.function("truth", self.truth)
        n, m = len(self.state_names), len(self.feedback_names)
        if n == 0 or m == 0:
            raise ArgumentError(f"a saturated loop needs states and fed-back channels, got {n} states, {m} fed-back "
                                "channels")
        xe = checks.array("equilibrium", self.equilibrium, shape=(n,)).copy()
        xe.setflags(write=False)
        K = checks.array("K", self.K, shape=(m, n))
        lo = checks.array("u_lo", self.u_lo, shape=(m,), finite=False)
        hi = checks.array("u_hi", self.u_hi, shape=(m,), finite=False)
        if np.any(np.isnan(lo)) or np.any(np.isnan(hi)) or not (np.all(lo < 0) and np.all(hi > 0)):
            raise ArgumentError(f"saturation levels must bracket 0 (u_lo < 0 < u_hi, +-inf for none), got u_lo = "
                                f"{lo.tolist()}, u_hi = {hi.tolist()}")
        held = tuple(checks.integer("held index", i, lo=0, hi=n - 1) for i in self.held)
        zero = [self.feedback_names[i] for i in range(m) if not np.any(K[i])]
        if zero:
            raise ArgumentError(f"channels {zero} have zero gain: a constant input belongs to plant_rhs, not to K")
        if not isinstance(self.box, tuple | list) or len(self.box) != 2:
            raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({n},)")
        blo = checks.array("box lo", self.box[0], shape=(n,))
        bhi = checks.array("box hi", self.box[1], shape=(n,))
        free = [i for i in range(n) if i not in held]
        bad = [self.state_names[i] for i in free if not blo[i] < xe[i] < bhi[i]]
        if bad:
            raise ArgumentError(f"the box must contain the equilibrium strictly; it does not in {bad}: lo = "
                                f"{blo.tolist()}, x_e = {xe.tolist()}, hi = {bhi.tolist()}")
        for nm, val in (("equilibrium", xe), ("K", K), ("u_lo", lo), ("u_hi", hi), ("box", (blo, bhi)),
                        ("held", held)):
            object.__setattr__(self, nm, val)

    @property
    def n(self) -> int:
        return len(self.state_names)

    @property
    def n_states(self) -> int:
        return len(self.state_names)

    @property
    def n_feedback(self) -> int:
        return len(self.feedback_names)

    @property
    def free(self) -> tuple[int, ...]:
        """Indices of the states the certificate is on (all but :attr:`held`)."""
        return tuple(i for i in range(self.n) if i not in self.held)

    @property
    def saturating(self) -> np.ndarray:
        """Channels with a finite saturation level."""
        return np.isfinite(self.u_lo) | np.isfinite(self.u_hi)

    def feedback(self, X: Any) -> Any:
        """The saturated feedback deviation ``sat(K (X - X_e))`` (the plant's input units) at states ``X``
        (..., n), complex-safe.

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not an array of numbers.
        ArgumentError
            If ``X`` does not have the trailing dimension ``n``.
        """
        X = trailing_array("state", X, self.n, self.state_names)
        return saturate((X - self.equilibrium) @ self.K.T, self.u_lo, self.u_hi)

    def rhs(self, X: Any, u: Any = None) -> np.ndarray:
        """The loop's ``X'`` at states ``X`` of shape ``(..., n)`` (``u`` is ignored: the loop is input-free): the
        :attr:`truth` when given, else ``F(X, sat(K (X - X_e)))``. ``X`` may be complex (complex-step Jacobians).

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not an array of numbers.
        ArgumentError
            If ``X`` does not have the trailing dimension ``n``.
        """
        X = trailing_array("state", X, self.n, self.state_names)
        if self.truth is not None:
            return np.asarray(self.truth(X))
        return np.asarray(self.plant_rhs(X, self.feedback(X)))


# --------------------------------------------------------------------------------------------- held states
def held_points(box: tuple[np.ndarray, np.ndarray], equilibrium: np.ndarray, held: Any, n: int = 64,
                seed: int = 7) -> np.ndarray:
    """``n`` random points of the box with the ``held`` states at their equilibrium values, and the equilibrium
    (``(n + 1, n_states)``): where a held state is checked not to move (:func:`held_motion`; used by
    :func:`glidectl.saturated_loop` and by :func:`glidectl.certify_roa` for the states it holds)."""
    lo, hi = (np.asarray(b, dtype=float) for b in box)
    xe = np.asarray(equilibrium, dtype=float)
    X = lo + (hi - lo) * np.random.default_rng(seed).random((n, len(xe)))
    X[:, list(held)] = xe[list(held)]
    return np.concatenate([X, xe[None, :]])


def at_held_values(X: np.ndarray, equilibrium: np.ndarray, held: Any) -> np.ndarray:
    """Per row of states ``X`` (..., n): whether the ``held`` states are at their equilibrium values (relative
    ``1e-12``; all rows when none is held). A certificate with held states holds only there."""
    X = np.asarray(X)
    h = list(held)
    if not h:
        return np.ones(X.shape[:-1], dtype=bool)
    xe = np.asarray(equilibrium, dtype=float)[h]
    return np.all(np.abs(X[..., h] - xe) <= 1e-12 * np.maximum(1.0, np.abs(xe)), axis=-1)


def held_motion(dX: np.ndarray, held: Any) -> float:
    """Largest ``|x_h'|`` of the ``held`` states over rates ``dX`` (:func:`held_points`), relative to
    ``max(1, max |x'|)``: a held state does not move when this is ``<= 1e-12``."""
    h = list(held)
    if not h:
        return 0.0
    dX = np.asarray(dX)
    return float(np.max(np.abs(dX[:, h])) / max(1.0, float(np.max(np.abs(dX)))))
