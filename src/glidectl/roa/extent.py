"""Per-axis extents of regions of attraction: how far along each state axis through the equilibrium a certificate
reaches (:meth:`ROACertificate.extent`, :meth:`EllipsoidCertificate.extent`) and how far simulations of the true
loop converge (:func:`convergent_extent`), in state units, so that a certificate can be judged against what it
certifies (a volume fraction of an 8-dimensional box hides a set 10 times too small along every axis).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np

from .. import checks
from ..batch import integrate_batch
from ..derivatives import jacobians
from ..errors import ArgumentError, ModelError
from .scaling import resolve_box

__all__ = ["Certificate", "ConvergentSlice", "Extent", "axis_extent", "convergent_extent", "convergent_slice",
           "settling_horizon"]


@dataclass(frozen=True)
class Extent:
    """An interval per state axis through the equilibrium ``x_e``: the states ``x_e + t e_k`` with ``lo_k <= x_k
    <= hi_k`` (the others at their equilibrium values) belong to the region described by ``what``.

    Attributes
    ----------
    names : tuple of str
        State names.
    lo, hi : ndarray, shape (n,)
        Ends of each axis's interval, in state units (``lo <= x_e <= hi``; both ``x_e`` for a state the region
        does not extend along, such as a held actuator).
    equilibrium : ndarray, shape (n,)
        ``x_e``.
    box : (ndarray, ndarray)
        The box searched (the intervals lie in it).
    what : str
        What the intervals are (``"certified (sos, exact recast)"``, ``"convergent (simulation, horizon 300 s)"``).
    rigorous : bool or None
        For a certificate, whether it is proved (``cert.rigorous``); None for simulations.
    """

    names: tuple[str, ...]
    lo: np.ndarray = field(repr=False)
    hi: np.ndarray = field(repr=False)
    equilibrium: np.ndarray = field(repr=False)
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    what: str = ""
    rigorous: bool | None = None

    @property
    def below(self) -> np.ndarray:
        """``x_e - lo`` per axis (state units, >= 0)."""
        return self.equilibrium - self.lo

    @property
    def above(self) -> np.ndarray:
        """``hi - x_e`` per axis (state units, >= 0)."""
        return self.hi - self.equilibrium

    def ratio(self, other: Extent) -> tuple[np.ndarray, np.ndarray]:
        """This extent over ``other``'s, per axis and direction: ``(below / other.below, above / other.above)``
        (NaN where ``other`` has zero extent).

        Raises
        ------
        ArgumentError
            If the two extents are not of the same states.
        """
        if tuple(other.names) != tuple(self.names):
            raise ArgumentError(f"extents of different states: {self.names} and {other.names}")
        with np.errstate(divide="ignore", invalid="ignore"):
            lo = np.where(other.below > 0, self.below / other.below, np.nan)
            hi = np.where(other.above > 0, self.above / other.above, np.nan)
        return lo, hi

    def table(self, other: Extent | None = None) -> list[list[str]]:
        """Rows ``[state, lo, x_e, hi]`` (4 significant digits, state units), with the ratios to ``other`` per
        direction when given."""
        rows = []
        r = self.ratio(other) if other is not None else None
        for k, name in enumerate(self.names):
            row = [name, f"{self.lo[k]:.4g}", f"{self.equilibrium[k]:.4g}", f"{self.hi[k]:.4g}"]
            if r is not None:
                row += [f"{r[0][k]:.3g}", f"{r[1][k]:.3g}"]
            rows.append(row)
        return rows

    def plot(self, ax: Any = None, other: Extent | None = None) -> Any:
        """Bar chart of this extent (and ``other``'s, e.g. the convergent one under a certified one) per axis and
        direction, as a fraction of the box's half-width on that side.

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plotting import plot_extents, style

        with style():
            return plot_extents(self, other, ax)


@runtime_checkable
class Certificate(Protocol):
    """What every region-of-attraction certificate has (:class:`~glidectl.roa.certificate.ROACertificate` of the SOS
    path, :class:`~glidectl.roa.lmi.EllipsoidCertificate` of the LMI path), with the same names and units.

    Attributes
    ----------
    system
        The model certified (a PolySystem, or the saturated loop).
    rho : float
        Certified level of ``V``.
    box : (ndarray, ndarray)
        The region of interest it was computed in (state units).
    scale : ndarray or None
        Scale of the variables the programs see.
    method : str
        The route (``"exact recast"``, ``"surrogate+remainder"``, ``"sos-sector"``, ``"lmi"``, ...).
    certified : bool
        Every a-posteriori check passed.
    rigorous : bool
        The set is proved a region of attraction of the true model (not only sampled-sound).
    in_box : bool
        The set lies in ``box`` (its runs stay there): compare its extent with
        ``convergent_extent(loop, box=cert.box, within_box=cert.in_box)``.
    verification
        The a-posteriori checks, with ``passed`` and ``summary()``.
    """

    system: Any
    rho: float
    box: tuple[np.ndarray, np.ndarray]
    scale: Any
    method: str
    verification: Any

    @property
    def certified(self) -> bool: ...

    @property
    def rigorous(self) -> bool: ...

    @property
    def in_box(self) -> bool: ...

    def contains(self, X: Any) -> np.ndarray:
        """Whether each state (N, n) is in the certified set."""

    def sample(self, n: int, seed: int = 0, *, boundary: bool = False) -> np.ndarray:
        """``n`` states of the set (or of its boundary)."""

    def volume(self) -> float:
        """Volume of the set in the box (product of the free states' units)."""

    def extent(self) -> Extent:
        """The certified interval per state axis through the equilibrium."""

    def plot(self, ax: Any = None, dims: Any = (0, 1)) -> Any:
        """A slice of the set (angles in degrees); returns the Axes."""


def axis_extent(inside: Callable[[np.ndarray], np.ndarray], equilibrium: np.ndarray,
                box: tuple[np.ndarray, np.ndarray], axes: Any = None, steps: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Ends of the interval of each axis through ``equilibrium`` on which ``inside`` holds, by bisection between
    the equilibrium and the box's faces (all axes and both directions in one batch per step).

    Parameters
    ----------
    inside : callable
        States ``(N, n) -> bool (N,)``; the set must be star-shaped about the equilibrium along each axis (true for
        a certificate's set: its membership checks the segment from the equilibrium).
    equilibrium : ndarray, shape (n,)
    box : (ndarray, ndarray)
    axes : sequence of int, optional
        Axes searched (default all); the others get ``lo = hi = x_e``.
    steps : int
        Bisection steps (the ends are within ``2^-steps`` of the half-width).

    Returns
    -------
    (ndarray, ndarray)
        ``lo`` and ``hi`` (state units).
    """
    xe = np.asarray(equilibrium, dtype=float)
    n = xe.size
    axes = list(range(n)) if axes is None else list(axes)
    lo_b, hi_b = (np.asarray(b, dtype=float) for b in box)
    # directions: -e_k then +e_k for each searched axis, with the distance to the box's face
    k = np.array(axes * 2, dtype=int)
    sign = np.repeat([-1.0, 1.0], len(axes))
    reach = np.where(sign < 0, xe[k] - lo_b[k], hi_b[k] - xe[k])

    def points(t: np.ndarray) -> np.ndarray:
        X = np.tile(xe, (len(k), 1))
        X[np.arange(len(k)), k] += sign * t * reach
        return X

    full = np.asarray(inside(points(np.ones(len(k)))), dtype=bool)      # the set reaches the box's face
    t_in, t_out = np.where(full, 1.0, 0.0), np.ones(len(k))
    for _ in range(steps if not full.all() else 0):
        mid = 0.5 * (t_in + t_out)
        ok = np.asarray(inside(points(mid)), dtype=bool)
        t_in = np.where(~full & ok, mid, t_in)
        t_out = np.where(~full & ~ok, mid, t_out)
    lo, hi = xe.copy(), xe.copy()
    neg = sign < 0
    lo[k[neg]] = xe[k[neg]] - t_in[neg] * reach[neg]
    hi[k[~neg]] = xe[k[~neg]] + t_in[~neg] * reach[~neg]
    return lo, hi


def _loop_parts(loop: Any) -> tuple[Callable[[np.ndarray], np.ndarray], np.ndarray, tuple[str, ...]]:
    """The batch right-hand side ``X -> X'``, the equilibrium and the state names of an input-free model."""
    if len(getattr(loop, "input_names", ()) or ()) > 0:
        raise ArgumentError(f"'{getattr(loop, 'name', type(loop).__name__)}' has inputs {tuple(loop.input_names)}: "
                            "close the loop first (gc.closed_loop, gc.saturated_loop)")
    for attr in ("rhs", "equilibrium", "state_names"):
        if not hasattr(loop, attr):
            raise ArgumentError(f"convergent_extent needs an input-free model with '{attr}' (a gc.closed_loop, "
                                f"gc.saturated_loop or PolySystem), got {type(loop).__name__}")
    xe = checks.array("equilibrium", loop.equilibrium, ndim=1)
    return (lambda X: np.asarray(loop.rhs(X))), xe, tuple(loop.state_names)


def convergent_extent(loop: Any, box: Any = None, horizon: float | None = None, n: int = 16, *,
                      tol: float = 1e-3, steps: int = 12, within_box: bool = True) -> Extent:
    """The interval along each state axis through the equilibrium from which simulations of the true loop
    converge without leaving a box: what a region-of-attraction certificate of the loop in that box can at best
    reach per axis.

    A certificate's set lies in the box it was computed in (the model's domain of validity: actuator ranges and
    rates, the documented half-widths of the glider states) and is invariant, so the runs from it never leave the
    box. With ``within_box`` (the default) a run that leaves the box therefore counts as not converging: the
    reference a certificate in that box can reach. ``within_box=False`` asks only that the run start in the box
    and converge (a run of an unsaturated loop may then drive an actuator far beyond its range on the way).

    Along each axis and direction, ``n`` evenly spaced points from the equilibrium to the box's face are simulated;
    the interval ends before the first that does not converge, refined by ``steps`` bisections between it and the
    last that does (so a region that is not an interval along the axis is cut at its first gap, not bridged).

    Parameters
    ----------
    loop : input-free model
        A closed loop (:func:`glidectl.closed_loop`), a saturated loop (:func:`glidectl.saturated_loop`), a
        :class:`~glidectl.roa.systems.PolySystem` or any model with a batch ``rhs(X)``, ``equilibrium`` and
        ``state_names``.
    box : (array_like, array_like) or mapping, optional
        ``(lo, hi)`` or ``{state: (lo, hi)}`` in state units (:func:`~glidectl.roa.scaling.resolve_box`); default the
        loop's own ``box``, else its validity box (:func:`~glidectl.roa.scaling.validity_box`), the same default
        as :func:`glidectl.certify_roa`. It must contain the equilibrium strictly.
    horizon : float, optional
        Simulated time (the model's time unit); default 25 time constants of the slowest mode of the
        linearization.
    n : int
        Points per axis and direction (>= 2).
    tol : float
        A run converges when its distance to the equilibrium at the horizon, per state in units of the box's
        half-width, is at most ``tol`` (0 < tol < 1).
    steps : int
        Bisection steps after the grid (>= 0).
    within_box : bool
        Whether a run must stay in the box (to ``1e-9`` of each state's width) to count as converging.

    Returns
    -------
    Extent
        ``what = "convergent in the box (simulation, horizon ...)"`` (``"convergent (...)"`` without
        ``within_box``); an axis along which the loop does not move (a held
        actuator) has ``lo = hi = x_e``.

    Raises
    ------
    ArgumentError
        If ``loop`` is not an input-free model, the box does not contain the equilibrium strictly (or misses
        states), or an argument is out of range.
    ModelError
        If the equilibrium is not exponentially stable (the linearization has an eigenvalue with real part >= 0
        on the states that move), or the horizon is too short to tell: runs started at 1 % of the box from the
        equilibrium have not converged by the horizon.

    Examples
    --------
    >>> import glidectl as gc
    >>> ext = gc.convergent_extent(gc.benchmarks.van_der_pol(), n=8, steps=6)
    >>> print(ext.hi.round(1))              # where the limit cycle crosses the axes: |x1| = 2.01, |x2| = 2.17
    [2.  2.2]
    """
    n = checks.integer("n", n, lo=2, hi=1000)
    steps = checks.integer("steps", steps, lo=0, hi=60)
    test = _ConvergenceTest.of(loop, box, horizon, tol, within_box)
    xe, names, (lo_b, hi_b), moving, converges, T = (test.xe, test.names, test.box, test.moving, test.converges,
                                                     test.horizon)

    near = np.tile(xe, (2 * len(moving), 1))
    for r, k in enumerate(moving):
        near[2 * r, k] -= 0.01 * (xe[k] - lo_b[k])
        near[2 * r + 1, k] += 0.01 * (hi_b[k] - xe[k])
    if not np.all(converges(near, stay=False)):
        raise ModelError(f"convergent_extent: runs started at 1 % of the box from the equilibrium of "
                         f"'{getattr(loop, 'name', 'the loop')}' have not converged within the horizon {T:.4g} "
                         "(to tol of the box): the horizon is too short to tell; give a longer horizon")
    lo, hi = _grid_then_bisect(converges, xe, (lo_b, hi_b), moving, n, steps)
    what = "convergent in the box" if test.within_box else "convergent"
    return Extent(names, lo, hi, xe, (lo_b, hi_b), f"{what} (simulation, horizon {T:.4g})", None)


@dataclass(frozen=True)
class ConvergentSlice:
    """Which states of a 2-D slice through the equilibrium converge under the true loop (from simulations): drawn
    under a certificate's slice to show what it could certify.

    Attributes
    ----------
    names : (str, str)
        The slice's two states.
    x, y : ndarray, shape (n,)
        Grid values of the two states (state units).
    converged : ndarray of bool, shape (n, n)
        ``converged[j, i]``: the run from ``(x[i], y[j])`` (the other states at ``base``) converges (and stays in
        the box when ``within_box``).
    base : ndarray, shape (n_states,)
        The state the slice goes through.
    what : str
        As for :class:`Extent`.
    """

    names: tuple[str, str]
    x: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)
    converged: np.ndarray = field(repr=False)
    base: np.ndarray = field(repr=False)
    what: str = ""

    @property
    def fraction(self) -> float:
        """Fraction of the slice's grid that converges."""
        return float(np.mean(self.converged))

    def plot(self, ax: Any = None) -> Any:
        """The converging part of the slice, filled grey (angles in degrees); a certificate's ``plot(ax=ax, ...)``
        draws over it.

        Returns
        -------
        matplotlib.axes.Axes
        """
        from ..plotting import plot_convergent_slice, style

        with style():
            return plot_convergent_slice(self, ax)


def convergent_slice(loop: Any, dims: Any = (0, 1), box: Any = None, n: int = 41, horizon: float | None = None, *,
                     tol: float = 1e-3, within_box: bool = True, window: Any = None) -> ConvergentSlice:
    """Simulate the true loop from an ``n`` x ``n`` grid of a 2-D slice through the equilibrium (the other states
    there) and mark the runs that converge, as :func:`convergent_extent` decides it.

    Parameters
    ----------
    loop : input-free model
        As for :func:`convergent_extent`.
    dims : two state names or indices
        The slice's plane.
    box, horizon, tol, within_box :
        As for :func:`convergent_extent` (the grid spans the box).
    n : int
        Grid points per axis (2 to 401).
    window : ((float, float), (float, float)), optional
        The part of the slice gridded, ``((lo_x, hi_x), (lo_y, hi_y))`` in state units, inside the box (default the
        box's extent in the two states); the runs are still judged against the whole box.

    Returns
    -------
    ConvergentSlice

    Raises
    ------
    ArgumentError
        For ``dims`` that are not two distinct states, and as :func:`convergent_extent`.
    ModelError
        As :func:`convergent_extent` (an equilibrium that is not exponentially stable).

    Examples
    --------
    >>> import glidectl as gc
    >>> sl = gc.convergent_slice(gc.benchmarks.van_der_pol(), dims=("x1", "x2"), n=9)
    >>> sl.converged.shape, int(sl.converged.sum())          # the grid points inside the limit cycle
    ((9, 9), 21)
    """
    n = checks.integer("n", n, lo=2, hi=401)
    test = _ConvergenceTest.of(loop, box, horizon, tol, within_box)
    i, j = (_state_index(d, test.names) for d in dims)
    if i == j:
        raise ArgumentError(f"dims must be two different states, got {dims!r}")
    lo, hi = test.box
    if window is None:
        window = ((lo[i], hi[i]), (lo[j], hi[j]))
    w = checks.array("window", window, shape=(2, 2))
    if not (lo[i] <= w[0, 0] < w[0, 1] <= hi[i] and lo[j] <= w[1, 0] < w[1, 1] <= hi[j]):
        raise ArgumentError(f"window must be two increasing intervals inside the box's "
                            f"[{lo[i]:.4g}, {hi[i]:.4g}] x [{lo[j]:.4g}, {hi[j]:.4g}], got {w.tolist()}")
    x, y = np.linspace(w[0, 0], w[0, 1], n), np.linspace(w[1, 0], w[1, 1], n)
    A, B = np.meshgrid(x, y)
    X = np.tile(test.xe, (A.size, 1))
    X[:, i], X[:, j] = A.ravel(), B.ravel()
    ok = test.converges(X).reshape(A.shape)
    what = ("convergent in the box" if test.within_box else "convergent") + f" (simulation, horizon {test.horizon:.4g})"
    return ConvergentSlice((test.names[i], test.names[j]), x, y, ok, test.xe.copy(), what)


def _state_index(d: Any, names: tuple[str, ...]) -> int:
    if isinstance(d, str):
        if d not in names:
            raise ArgumentError(f"unknown state {d!r}; the states are {names}")
        return names.index(d)
    return checks.integer("dims index", d, lo=0, hi=len(names) - 1)


@dataclass(frozen=True)
class _ConvergenceTest:
    """Whether runs of an input-free loop from given states converge to its equilibrium by the horizon (to ``tol``
    of the box's half-widths per state), staying in the box when ``within_box``."""

    f: Callable[[np.ndarray], np.ndarray]
    xe: np.ndarray
    names: tuple[str, ...]
    box: tuple[np.ndarray, np.ndarray]
    moving: list[int]
    horizon: float
    tol: float
    within_box: bool

    @classmethod
    def of(cls, loop: Any, box: Any, horizon: float | None, tol: float, within_box: bool) -> _ConvergenceTest:
        f, xe, names = _loop_parts(loop)
        tol = checks.real("tol", tol, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
        within_box = checks.boolean("within_box", within_box)
        lo_b, hi_b = _box(loop, box)
        A = jacobians(lambda x, u: f(x[None, :])[0], xe, np.zeros(0))[0]
        moving = _moving_states(A, (lo_b, hi_b))
        T = _horizon(A, names, moving, horizon)
        return cls(f, xe, names, (lo_b, hi_b), moving, T, tol, within_box)

    def converges(self, X: np.ndarray, stay: bool = True) -> np.ndarray:
        """Per state (N, n): the run converges (and, with ``stay`` and ``within_box``, never leaves the box)."""
        lo_b, hi_b = self.box
        half = np.maximum(self.xe - lo_b, hi_b - self.xe)
        scale = np.where(half > 0, half, 1.0)
        slack = 1e-9 * (hi_b - lo_b)
        left = (lambda Y: np.any((Y < lo_b - slack) | (Y > hi_b + slack), axis=-1)) if self.within_box else None
        res = integrate_batch(self.f, X, self.horizon, rtol=1e-7, atol=1e-10 * scale, max_steps=200_000,
                              diverged=left if stay else None,
                              bound=1e3 * float(np.max(np.abs(np.concatenate([lo_b, hi_b])))))
        dev = np.abs(res.x_final - self.xe) / scale
        return ~res.diverged & np.all(np.isfinite(dev), axis=1) & (np.max(dev, axis=1) <= self.tol)


def _box(loop: Any, box: Any) -> tuple[np.ndarray, np.ndarray]:
    """The box searched: ``box``, the loop's own box, or its validity box (:func:`~glidectl.roa.scaling.resolve_box`,
    which refuses a box without the equilibrium strictly inside)."""
    lo, hi = resolve_box(loop, box)
    return np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)


def settling_horizon(A: np.ndarray) -> float:
    """25 time constants of the slowest mode of a stable linearization ``A`` (the model's time unit): how long the
    simulations of the certificates and of :func:`convergent_extent` run by default."""
    return 25.0 / float(np.min(np.abs(np.linalg.eigvals(A).real)))


def _moving_states(A: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> list[int]:
    """The states the loop moves: those with a nonzero row or column in the linearization ``A``, and a box
    interval."""
    lo, hi = box
    return [k for k in range(A.shape[0]) if hi[k] > lo[k] and (np.any(A[k] != 0.0) or np.any(A[:, k] != 0.0))]


def _horizon(A: np.ndarray, names: tuple[str, ...], moving: list[int], horizon: float | None) -> float:
    """The horizon: ``horizon``, or :func:`settling_horizon` on the states the loop moves; refuses a loop that is
    not exponentially stable there."""
    Am = A[np.ix_(moving, moving)]
    ev = np.linalg.eigvals(Am) if moving else np.zeros(0)
    if ev.size and np.max(ev.real) >= 0:
        raise ModelError(f"convergent_extent: the equilibrium is not exponentially stable (largest real part of the "
                         f"linearization on {[names[k] for k in moving]}: {np.max(ev.real):.4g}); no simulation "
                         "converges to it from an interval")
    if horizon is not None:
        return checks.positive("horizon", horizon)
    return settling_horizon(Am) if ev.size else 1.0


def _grid_then_bisect(converges: Callable[[np.ndarray], np.ndarray], xe: np.ndarray,
                      box: tuple[np.ndarray, np.ndarray], moving: list[int], n: int, steps: int
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Per moving axis and direction: the last of ``n`` grid points (from the equilibrium to the box's face) before
    the first that does not converge, refined by bisection towards that one."""
    lo_b, hi_b = box
    k = np.array(moving * 2, dtype=int)
    sign = np.repeat([-1.0, 1.0], len(moving))
    reach = np.where(sign < 0, xe[k] - lo_b[k], hi_b[k] - xe[k])

    def states(t: np.ndarray) -> np.ndarray:         # t (m, d) -> states (m * d, n)
        X = np.tile(xe, (t.size, 1))
        cols = np.tile(k, t.shape[0])
        X[np.arange(t.size), cols] += (t * (sign * reach)).ravel()
        return X

    grid = np.linspace(1.0 / n, 1.0, n)[:, None] * np.ones(len(k))
    ok = converges(states(grid)).reshape(grid.shape)
    first_bad = np.where(ok.all(axis=0), n, np.argmin(ok, axis=0))
    t_in = np.where(first_bad > 0, grid[np.maximum(first_bad - 1, 0), 0], 0.0)
    t_out = np.where(first_bad < n, grid[np.minimum(first_bad, n - 1), 0], math.inf)
    for _ in range(steps):
        open_ = np.isfinite(t_out)
        if not open_.any():
            break
        mid = 0.5 * (t_in + np.where(open_, t_out, t_in))
        good = converges(states(mid[None, :])).reshape(-1)
        t_in = np.where(open_ & good, mid, t_in)
        t_out = np.where(open_ & ~good, mid, t_out)
    lo, hi = xe.copy(), xe.copy()
    neg = sign < 0
    lo[k[neg]] = xe[k[neg]] - t_in[neg] * reach[neg]
    hi[k[~neg]] = xe[k[~neg]] + t_in[~neg] * reach[~neg]
    return lo, hi
