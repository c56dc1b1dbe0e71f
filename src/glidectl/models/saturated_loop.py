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

A fed-back channel may also have *state-dependent* limits, each affine in the state (:class:`AffineLimit`): the
battery's acceleration is limited so that its velocity stays within the rate limit and tapers onto the range ends,
the pump's rate tapers onto the ends of its range (the :class:`~glidectl.models.actuated.ActuatedGlider` law). The
loop is then ``X' = F(X, clip(K (X - X_e), lo(X), hi(X)))`` with ``lo``/``hi`` the tightest of the constant levels
and the affine limits; the LMI path takes each affine limit into its generalized sector condition.

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

__all__ = ["AffineLimit", "SaturatedLoop", "at_held_values", "held_motion", "held_points", "saturate"]


def saturate(v: Any, lo: np.ndarray, hi: np.ndarray) -> Any:
    """``clip(v, lo, hi)`` carrying a complex step (derivative 1 inside, 0 outside).

    Parameters
    ----------
    v : array_like
        Values (real or complex; the real part is compared with the levels), shape ``(..., m)``.
    lo, hi : array_like, shape (m,) or broadcasting with ``v``
        Levels (``-inf``/``inf``: none); state-dependent levels may be complex (their complex step is carried
        where they act).

    Returns
    -------
    ndarray
        ``v`` where ``Re lo <= Re v <= Re hi``, else the level (plus ``0 v``, so a complex step of a constant level
        gives derivative 0).
    """
    re = np.real(v)
    return np.where(re > np.real(hi), hi + 0.0 * v, np.where(re < np.real(lo), lo + 0.0 * v, v))


@dataclass(frozen=True)
class AffineLimit:
    """A state-dependent limit of one fed-back channel, affine in the state deviation: ``w_i <= a . (X - X_e) + b``
    (``upper``) or ``w_i >= a . (X - X_e) + b`` (lower).

    Parameters
    ----------
    channel : int
        Index of the fed-back channel (in ``feedback_names``).
    upper : bool
        An upper (True) or lower (False) limit.
    a : array_like, shape (n,)
        Gain on the state deviation (input units per state unit).
    b : float
        Value at the equilibrium (input units): > 0 for an upper limit, < 0 for a lower one (the equilibrium is
        strictly inside every limit).
    label : str
        What the limit is (e.g. ``"r_P1 rate limit"``), for messages and reports.
    """

    channel: int
    upper: bool
    a: np.ndarray = field(repr=False)
    b: float
    label: str = ""

    def level(self, dX: Any) -> Any:
        """The limit's value ``a . dX + b`` at state deviations ``dX`` (..., n), complex-safe."""
        return dX @ self.a + self.b


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
        The loop's own right-hand side ``X (N, n) -> X'`` (default ``F(X, feedback(X))``); :meth:`rhs` and
        verification use it.
    limits : tuple of AffineLimit
        State-dependent limits of the fed-back channels (module docstring), on top of ``u_lo``/``u_hi``.
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
        If shapes disagree, values are not finite, ``K`` has a zero row, the levels do not bracket 0, an affine
        limit does not hold strictly at the equilibrium or names no channel, or the box does not contain the
        equilibrium strictly in the free states.
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
    limits: tuple[AffineLimit, ...] = ()
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
        limits = tuple(self._checked_limit(q, n, m) for q in self.limits)
        for nm, val in (("equilibrium", xe), ("K", K), ("u_lo", lo), ("u_hi", hi), ("box", (blo, bhi)),
                        ("held", held), ("limits", limits)):
            object.__setattr__(self, nm, val)

    def _checked_limit(self, q: Any, n: int, m: int) -> AffineLimit:
        if not isinstance(q, AffineLimit):
            raise ArgumentTypeError(f"limits must be AffineLimit objects, got {type(q).__name__}")
        ch = checks.integer("limit channel", q.channel, lo=0, hi=m - 1)
        a = checks.array(f"limit '{q.label}' a", q.a, shape=(n,)).copy()
        a.setflags(write=False)
        b = checks.real(f"limit '{q.label}' b", q.b)
        if (b <= 0) if q.upper else (b >= 0):
            raise ArgumentError(f"the {'upper' if q.upper else 'lower'} limit '{q.label}' of "
                                f"{self.feedback_names[ch]} must hold strictly at the equilibrium (b "
                                f"{'> 0' if q.upper else '< 0'}), got b = {b:g}")
        return AffineLimit(ch, bool(q.upper), a, b, str(q.label))

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
        """The saturated feedback deviation ``clip(K (X - X_e), lo(X), hi(X))`` (the plant's input units) at
        states ``X`` (..., n), complex-safe: the constant levels and the affine :attr:`limits`.

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not an array of numbers.
        ArgumentError
            If ``X`` does not have the trailing dimension ``n``.
        """
        X = trailing_array("state", X, self.n, self.state_names)
        dX = X - self.equilibrium
        v = dX @ self.K.T
        if not self.limits:
            return saturate(v, self.u_lo, self.u_hi)
        lo = np.broadcast_to(self.u_lo, v.shape).astype(v.dtype)
        hi = np.broadcast_to(self.u_hi, v.shape).astype(v.dtype)
        for q in self.limits:
            lev = q.level(dX)
            side = hi if q.upper else lo
            tighter = (np.real(lev) < np.real(side[..., q.channel])) if q.upper else \
                (np.real(lev) > np.real(side[..., q.channel]))
            side[..., q.channel] = np.where(tighter, lev, side[..., q.channel])
        return saturate(v, lo, hi)

    def rhs(self, X: Any, u: Any = None) -> np.ndarray:
        """The loop's ``X'`` at states ``X`` of shape ``(..., n)`` (``u`` is ignored: the loop is input-free): the
        :attr:`truth` when given, else ``F(X, feedback(X))``. ``X`` may be complex (complex-step Jacobians).

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
