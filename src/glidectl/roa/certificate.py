"""The SOS region-of-attraction certificate (:class:`ROACertificate`): membership of the certified set, sampling,
volume, and its a-posteriori verification on the true model (:class:`ROAVerification`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .. import checks
from ..analysis.measure import MIN_SOBOL_HITS, box_measure, unit_sobol
from ..batch import integrate_batch
from ..derivatives import COMPLEX_STEP, complex_step, hessian
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, SolverError
from .extent import Extent, axis_extent, settling_horizon
from .polynomial import Poly
from .programs import linearization
from .sos import (
    GramCheck,
)
from .systems import PolySystem

__all__ = ["HistoryRow", "PathPoints", "ROACertificate", "ROAVerification", "dVdt", "default_horizon", "local_checks",
           "path_contains", "simulated_truth", "step_volume", "value_of", "verify_certificate"]


def value_of(V: Poly, ps: PolySystem, X: np.ndarray) -> np.ndarray:
    return V(ps.lift(X))


_PATH_BATCH = 32_000
"""Most segment points :func:`path_contains` evaluates in one call: below it the per-call cost of the polynomial
evaluation dominates and the whole segments go at once; above it the ``t``-by-``t`` loop, which drops the points that
leave, is faster (measurements: ``bench/README.md``)."""


def path_contains(ps: PolySystem, V: Poly, rho: float, X: np.ndarray, n_path: int = 33) -> np.ndarray:
    """``V(lift(x_e + t (x - x_e))) <= rho`` and the cuts for ``t`` on the grid ``1, 1 - 1/n_path, ...,
    1/n_path`` (the component of the equilibrium). The end points ``t = 1`` are evaluated first (most points outside
    the set fail there); then, for the points still inside, the rest of their segments in one evaluation if that is
    at most :data:`_PATH_BATCH` points, else ``t`` by ``t`` (a point that fails once is not evaluated again).
    Polynomial evaluation is elementwise, so both give bitwise the same answer."""
    X = np.asarray(X, dtype=float)
    ok = np.all(np.isfinite(X), axis=-1)
    x0 = np.asarray(ps.equilibrium, dtype=float)
    ts = np.linspace(1.0, 0.0, n_path, endpoint=False)
    for j, t in enumerate(ts):
        idx = np.flatnonzero(ok)
        if idx.size == 0:
            break
        rest = ts[j:]
        if j > 0 and idx.size * len(rest) <= _PATH_BATCH:       # small: the rest of the segments at once
            Y = (x0 + rest[:, None, None] * (X[idx] - x0)[None]).reshape(-1, X.shape[-1])
            Z = ps.lift(Y)
            good = (V(Z) <= rho) & ps.in_cuts(Y, Z)
            ok[idx] = np.all(good.reshape(len(rest), idx.size), axis=0)
            break
        Y = x0 + t * (X[idx] - x0)
        Z = ps.lift(Y)
        ok[idx] = (V(Z) <= rho) & ps.in_cuts(Y, Z)
    return ok


class PathPoints:
    """Fixed points ``X`` with the lifted segment points ``lift(x_e + t (x - x_e))`` and their cut masks cached for
    every ``t`` of :func:`path_contains` (they do not depend on ``V``): :meth:`contains` then evaluates only ``V``,
    on the points still inside, and gives exactly :func:`path_contains` ``(ps, V, rho, X, n_path)``."""

    def __init__(self, ps: PolySystem, X: np.ndarray, n_path: int = 33) -> None:
        X = np.asarray(X, dtype=float)
        self.finite = np.all(np.isfinite(X), axis=-1)
        x0 = np.asarray(ps.equilibrium, dtype=float)
        Xf = np.where(self.finite[:, None], X, x0)
        self.Z, self.cut = [], []
        for t in np.linspace(1.0, 0.0, n_path, endpoint=False):
            Y = x0 + t * (Xf - x0)
            self.Z.append(ps.lift(Y))
            self.cut.append(ps.in_cuts(Y, self.Z[-1]))

    def contains(self, V: Poly, rho: float) -> np.ndarray:
        ok = self.finite.copy()
        for Z, cut in zip(self.Z, self.cut, strict=True):
            idx = np.flatnonzero(ok)
            if idx.size == 0:
                break
            ok[idx] = (V(Z[idx]) <= rho) & cut[idx]
        return ok


def dVdt(V: Poly, lift: Any, rhs: Any, X: Any) -> np.ndarray:
    """``d/dt V(lift(x))`` along ``x' = rhs(x)`` at states ``X`` (N, n), by complex step through the lift (exact to
    rounding). With a certificate's ``system.lift`` and ``system.rhs`` this is the true model's derivative.

    Parameters
    ----------
    V : Poly
        Function of the polynomial variables ``z``.
    lift : callable
        ``x (N, n) -> z (N, nz)``, complex-safe (e.g. ``PolySystem.lift``).
    rhs : callable
        ``x (N, n) -> dx/dt (N, n)`` (e.g. ``PolySystem.rhs``).
    X : array_like, shape (N, n)
        States (the model's units).

    Returns
    -------
    numpy.ndarray, shape (N,)
        ``dV/dt`` at each state (units of ``V`` per the model's time unit: 1/s, or per ``t_n`` for nondimensional
        models).

    Raises
    ------
    ArgumentTypeError
        If ``V`` is not a Poly, ``lift`` or ``rhs`` is not callable, or ``X`` is not numeric.
    ArgumentError
        If ``X`` is not a finite (N, n) array, or the shapes of ``X``, ``rhs(X)`` and ``lift`` do not agree.

    Examples
    --------
    >>> import glidectl as gc
    >>> vdp = gc.benchmarks.van_der_pol()
    >>> V = gc.lyapunov_quadratic(vdp)
    >>> gc.dVdt(V, vdp.lift, vdp.rhs, [[0.1, 0.2], [0.5, -0.5]]).round(4)
    array([-0.0494, -0.3125])
    """
    if not isinstance(V, Poly):
        raise ArgumentTypeError(f"V must be a glidectl.roa.Poly, got {type(V).__name__}")
    checks.function("lift", lift)
    checks.function("rhs", rhs)
    X = checks.array("X", X, ndim=2)
    D = np.asarray(rhs(X))
    if D.shape != X.shape:
        raise ArgumentError(f"rhs returned shape {D.shape} for states of shape {X.shape}")
    return complex_step(lambda Z: V(lift(Z)), X, D, COMPLEX_STEP)



# --------------------------------------------------------------------------------------------- certificate
@dataclass(frozen=True)
class HistoryRow:
    """One step of the alternation (:attr:`ROACertificate.history`).

    Attributes
    ----------
    degree : int
        Degree of ``V`` at this step.
    step : str
        What was done (``"initial level"``, ``"V step + level"``, ``"final margin at backoff ..."``, ...).
    rho : float
        Level of the step's level problem (NaN: none solved).
    volume : float
        Sampled volume fraction of the box inside the step's set (NaN: not measured).
    sdp_time, compile_time, solver_time : float
        Wall time of the step's SDPs, of cvxpy's compilation and the solver's own time (s); the last two NaN when
        not recorded.
    """

    degree: int
    step: str
    rho: float = math.nan
    volume: float = math.nan
    sdp_time: float = 0.0
    compile_time: float = math.nan
    solver_time: float = math.nan



@dataclass(frozen=True)
class ROAVerification:
    """A-posteriori checks of a certificate (all must pass for :attr:`ROACertificate.certified`).

    ``margins`` has one entry per check (``>= 1`` holds): ``"Gram <name>"`` (:attr:`GramCheck.margin` of each SOS
    constraint), ``"Hessian of V positive definite"``, ``"A'H + HA negative definite"`` and ``"sampled dV/dt < 0"``
    (``inf`` when they hold, ``0.0`` when not) and ``"simulations converged"`` (``n_converged / n_simulated``).
    ``passed`` is every check passing (each Gram check exactly SOS, ``slack > 0``); ``failing()`` the margins
    below 1.

    Attributes
    ----------
    gram : tuple of GramCheck
        Exact-SOS check of every SOS constraint of the final program.
    hessian_V_min : float
        Smallest eigenvalue of the Hessian ``H`` of ``V(lift(x))`` at the equilibrium (must be > 0; units of ``V``
        per squared state unit).
    lyapunov_max : float
        Largest eigenvalue of ``A^T H + H A`` (must be < 0; per time unit of the model).
    n_sampled : int
        Sampled points of the certified set.
    max_Vdot : float
        Largest true ``dV/dt / |x - x_e|^2`` over them (must be < 0).
    n_simulated, n_converged : int
        Simulations started in the set and those that converged to the equilibrium.
    horizon : float
        Length of those simulations (model time unit: s, or ``t_n``).
    """

    gram: tuple[GramCheck, ...]
    hessian_V_min: float            # smallest eigenvalue of the Hessian of V(lift(x)) at the equilibrium
    lyapunov_max: float             # largest eigenvalue of A^T H + H A (must be < 0)
    n_sampled: int                  # sampled points of the certified set
    max_Vdot: float                 # largest true dV/dt / |x - x_e|^2 over them (must be < 0)
    n_simulated: int
    n_converged: int
    horizon: float

    @property
    def gram_passed(self) -> bool:
        """Every SOS constraint is exactly SOS (:attr:`GramCheck.passed`)."""
        return all(c.passed for c in self.gram)

    @property
    def unsampled_passed(self) -> bool:
        """The checks that need no sampling pass: every Gram check, the Hessian of V positive definite and
        ``A'H + HA`` negative definite (what gates a second remainder-box round of :func:`certify_roa`)."""
        return bool(self.gram_passed and self.hessian_V_min > 0 and self.lyapunov_max < 0)

    @property
    def passed(self) -> bool:
        return bool(self.unsampled_passed and self.n_sampled > 0 and self.max_Vdot < 0
                    and self.n_converged == self.n_simulated)

    @property
    def margins(self) -> dict[str, float]:
        inf = math.inf
        out: dict[str, float] = {}
        for c in self.gram:
            key = f"Gram {c.name}"
            out[key if key not in out else f"{key} #{len(out)}"] = c.margin
        out["Hessian of V positive definite"] = inf if self.hessian_V_min > 0 else 0.0
        out["A'H + HA negative definite"] = inf if self.lyapunov_max < 0 else 0.0
        out["sampled dV/dt < 0"] = inf if self.n_sampled > 0 and self.max_Vdot < 0 else 0.0
        out["simulations converged"] = self.n_converged / self.n_simulated if self.n_simulated else 1.0
        return out

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1 (relative tolerance 1e-9)."""
        return {k: m for k, m in self.margins.items() if not m >= 1 - 1e-9}

    def summary(self) -> str:
        """One line: the smallest Gram margin and slack, the local conditions, sampled dV/dt, simulations."""
        g = min((c.margin for c in self.gram), default=float("nan"))
        sl = min((c.slack for c in self.gram), default=float("nan"))
        shift = max((c.multiplier_shift for c in self.gram), default=0.0)
        made = f"; S-procedure multipliers shifted by <= {shift:.2g} to be SOS" if shift > 0 else ""
        return (f"Gram margin {g:.3g} (slack {sl:.3g}, {'exact' if self.gram_passed else 'NOT exact'}{made}), "
                f"Hessian min {self.hessian_V_min:.3g}, A'H+HA max {self.lyapunov_max:.3g}, max dV/dt/|x|^2 on "
                f"{self.n_sampled} samples {self.max_Vdot:.3g}, simulations {self.n_converged}/{self.n_simulated} "
                f"converged in {self.horizon:g}")


@dataclass(frozen=True)
class ROACertificate:
    """Certified region of attraction ``{x : V(lift(x)) <= rho}`` (component of the equilibrium).

    Attributes
    ----------
    system : PolySystem
    V : Poly
        Lyapunov function in the polynomial variables ``z = lift(x)``.
    rho : float
        Certified (backed-off) level.
    rho_star : float
        Optimal level of the last level problem (``rho = (1 - backoff) rho_star``).
    degree : int
        Degree of ``V``.
    history : tuple of HistoryRow
        Per iteration: degree, level, sampled volume in the box, SDP time.
    verification : ROAVerification
        A-posteriori checks; ``certified`` is ``verification.passed``.
    solve_time : float
        Total SDP solver time (s); ``wall_time`` includes building and verification. Both are those of the whole
        :func:`certify_roa` call, remainder-box rounds that were not kept included (the SDP time of a round stopped
        by an error is not counted).
    provenance : str
        The system's provenance (its vehicle's parameter hash for recast glidectl models).
    stopped_by : str
        What ended the V-lambda alternation at the final degree: ``"iterations"`` (all ran), ``"no improvement"``
        (two V steps without a larger sampled volume), ``"solver failure"`` (a V step or level problem failed; the
        best V so far is kept) or ``"time_limit"`` (``on_budget="stop"``).
    method : str
        The route: ``"exact recast"`` (the SOS programs see the model itself) or ``"surrogate+remainder"`` (a
        polynomial surrogate whose distance to the model is bounded on the box, :mod:`glidectl.roa.surrogate`;
        the decrease condition holds for every field within that bound) or ``"sos-sector"`` (a saturated loop:
        the saturated inputs are extra variables on the exact graph of the saturation,
        :mod:`glidectl.roa.sector`) or ``"sos-sector+remainder"`` (the same with a surrogate of a plant that is not
        polynomial).
    scale : ndarray or None
        Scale of each polynomial variable ``z`` in the programs (``z / scale`` is what the SDPs see): for the
        surrogate route the state scale ``s`` of ``(x - x_e) / s`` times the internal rescaling (state units).
    held : tuple of str
        States held at their equilibrium values (``system.equilibrium``): a closed loop's locked states, whose
        derivative is zero on the box with them there (e.g. ``r_P3``, ``rdot_P3`` of a glider whose vehicle file
        fixes ``r_P3``). The set is certified on the other states, for the held ones AT those values: every method
        takes full states, :meth:`contains` is false unless the held states are at their values (relative 1e-12),
        :meth:`sample` returns them there and :meth:`volume` is the volume in the other states. Empty if none.
    """

    system: PolySystem = field(repr=False)
    V: Poly = field(repr=False)
    rho: float
    rho_star: float
    degree: int
    history: tuple[HistoryRow, ...] = field(repr=False)
    verification: ROAVerification = field(repr=False)
    solve_time: float
    wall_time: float
    provenance: str = ""
    stopped_by: str = ""
    method: str = "exact recast"
    scale: np.ndarray | None = field(default=None, repr=False)
    held: tuple[str, ...] = ()

    @property
    def rigorous(self) -> bool:
        """Whether the set is proved a region of attraction of the true model: the SOS programs see the model itself
        (``method`` ``"exact recast"`` or ``"sos-sector"``) and every Gram matrix's eigenvalue margin exceeds its
        coefficient residual. The surrogate routes (``"...+remainder"``) bound the distance to the model from
        sampled derivatives times a safety factor, not an enclosure: sampled-sound, not proved."""
        return self.method in ("exact recast", "sos-sector") and self.verification.gram_passed

    @property
    def in_box(self) -> bool:
        """Whether the certified set lies in :attr:`box` (so that the runs from it stay there): true for the
        surrogate routes, whose remainder bound holds only on the box and whose cuts keep the set in it; an exact
        recast certifies the model itself, and its set may reach beyond the box."""
        return bool(self.system.remainder)

    def extent(self, steps: int = 40) -> Extent:
        """The certified interval along each state axis through the equilibrium (state units), within the box: the
        states ``x_e + t e_k`` of the set, found by bisection (``steps``) on :meth:`contains`; ``x_e`` for a held
        state.

        Returns
        -------
        Extent
        """
        steps = checks.integer("steps", steps, lo=1, hi=60)
        ps = self.system
        free = [k for k in range(ps.n) if ps.state_names[k] not in self.held]
        lo, hi = axis_extent(self.contains, np.asarray(ps.equilibrium, dtype=float), self.box, free, steps)
        return Extent(tuple(ps.state_names), lo, hi, np.asarray(ps.equilibrium, dtype=float), self.box,
                      f"certified ({self.method})", self.rigorous)

    @property
    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """``(lo, hi)``: the region of interest the certificate was computed in (state units); the certified set
        lies inside it for the surrogate route (its cuts)."""
        return self.system.box

    def sample(self, n: int, seed: int = 0, *, boundary: bool = False) -> np.ndarray:
        """Points of the certified set, in state units.

        The set is star-shaped about the equilibrium (:meth:`contains` checks the segment from it), so directions
        ``u`` are drawn uniformly in the box-scaled coordinates, the largest radius ``R(u)`` inside the set is found
        by bisection (40 steps) and the point is ``x_e + R(u) U^(1/n) u`` with ``U`` uniform, the direction kept
        with probability ``(R(u) / R_max)^n``: uniform in the set up to the largest radius seen. A set too thin
        for that (its expected acceptance projects to more than 20 rounds of ``max(2 n, 256)`` directions after 3
        rounds, or to more than the 200 allowed after one) is sampled instead with directions proposed along the
        Hessian of ``V`` at the equilibrium (angular central Gaussian) and kept with their importance weight
        ``R(u)^n / q(u)`` over the largest weight proposed: uniform in the set as long as that largest weight bounds
        the weights (exact for an ellipsoid), and the same points as before whenever the first way succeeds.

        Parameters
        ----------
        n : int
            Number of points, >= 1.
        seed : int
            Seed (>= 0).
        boundary : bool
            Return the outermost points ``x_e + R(u) (1 - 1e-9) u`` instead (uniform directions): starting points
            for convergence checks.

        Returns
        -------
        ndarray (n, n_states)
            Points with :meth:`contains` true (state units).

        Raises
        ------
        ArgumentTypeError
            If ``n`` or ``seed`` is not an integer, or ``boundary`` not a bool.
        ArgumentError
            If ``n < 1`` or ``seed < 0``.
        SolverError
            If the set is empty in every sampled direction (no certified set).
        """
        n = checks.integer("n", n, lo=1, hi=2**22)
        seed = checks.integer("seed", seed, lo=0)
        boundary = checks.boolean("boundary", boundary)
        return _sample_set(self.system, self.V, self.rho, n, seed, boundary)

    @property
    def certified(self) -> bool:
        """True only if every a-posteriori check passed."""
        return self.verification.passed

    def _states(self, X: Any, finite: bool) -> np.ndarray:
        n = self.system.n
        X = checks.array("X", X, finite=finite)
        X = np.atleast_2d(X)
        if X.ndim != 2 or X.shape[-1] != n:
            raise ArgumentError(f"X must hold states of dimension {n} ({', '.join(self.system.state_names)}), "
                                f"shape (N, {n}) or ({n},); got shape {np.shape(X)}")
        return X

    def value(self, X: Any) -> np.ndarray:
        """``V(lift(x))`` at states ``X``.

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States in the system's coordinates (finite).

        Returns
        -------
        ndarray, shape (N,)
            The Lyapunov function there.

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not numeric.
        ArgumentError
            If ``X`` has the wrong shape or is not finite.
        """
        return value_of(self.V, self.system, self._states(X, finite=True))

    def contains(self, X: Any, n_path: int = 33) -> np.ndarray:
        """Membership of the certified set for states ``X`` in the system's coordinates.

        A point belongs when it and the straight segment from the equilibrium to it satisfy ``V <= rho`` and the
        cuts (so it lies in the connected component of the equilibrium; ``n_path`` points on the segment, the
        point itself included).

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States; a state with NaN or inf is reported outside.
        n_path : int
            Points checked on each segment, >= 1.

        Returns
        -------
        ndarray of bool, shape (N,)
            Membership.

        Raises
        ------
        ArgumentTypeError
            If ``X`` is not numeric or ``n_path`` is not an integer.
        ArgumentError
            If ``X`` has the wrong shape or ``n_path < 1``.
        """
        X = self._states(X, finite=False)
        n_path = checks.integer("n_path", n_path, lo=1)
        return path_contains(self.system, self.V, self.rho, X, n_path)

    def volume(self, box: tuple[Any, Any] | None = None, n: int = 2**16, seed: int = 0,
               method: str = "auto") -> float:
        """Volume (area for 2 states) of the certified set inside ``box`` (default the system's); with :attr:`held`
        states, the volume in the other states (the held ones at their values).

        ``method="sobol"`` counts the scrambled Sobol points of the box that :meth:`contains` accepts
        (:func:`~glidectl.analysis.measure.box_measure`): ``prod(hi - lo) k / n`` for ``k`` points inside. A thin
        set in many states holds none of them (the 8 free states of a glider's LQR loop): that estimate is then 0.
        ``method="directed"`` integrates along rays from the equilibrium ``x_e`` instead (the set is star-shaped
        about it): in the box-scaled free states ``y = (x - x_e) / w`` (``w`` the largest distance from ``x_e`` to a
        face of the system's box), with ``R(u)`` the largest radius inside the set and the box along the unit
        direction ``u`` (40 bisection steps on :meth:`contains`) and ``H`` the Hessian of ``V(lift(x))`` at the
        equilibrium in those coordinates, ::

            vol = prod(w_free) |S^(nf-1)| / (nf sqrt(det H)) E[W(u)],   W(u) = (R(u)^2 u' H u)^(nf/2),

        the mean over ``m = ceil(n / 16)`` directions ``u = z / |z|``, ``z ~ N(0, H^-1)`` (angular central
        Gaussian, density ``det(H)^(1/2) (u' H u)^(-nf/2)`` relative to the uniform law on the sphere; ``nf`` free
        states; ``H``'s eigenvalues clipped at 1e-8 of the largest). It is exact for an ellipsoid (``W``
        constant) and has the relative standard error ``std(W) / (mean(W) sqrt(m))`` otherwise; the box must
        contain the equilibrium. ``method="auto"`` returns the Sobol estimate when at least 100 of its points are
        inside (relative counting error below about 1/10; the same number as ``"sobol"``, bit for bit) and the
        directed one otherwise (or the Sobol one if the box does not contain the equilibrium).

        Parameters
        ----------
        box : (array_like, array_like), optional
            ``(lo, hi)``, each of shape (n,), finite, ``lo < hi`` (in the free states); default the system's box.
        n : int
            Sobol points (>= 1; a power of 2 keeps the sequence balanced); the directed estimate draws
            ``ceil(n / 16)`` directions (each costs 41 membership tests of a point: the default, 4096 directions,
            takes about 2 s on an 8-free-state glider loop).
        seed : int
            Seed of the scrambled Sobol sequence and of the directions (>= 0).
        method : {"auto", "sobol", "directed"}
            The estimate, as above.

        Returns
        -------
        float
            The estimated volume (product of the state units of the free states).

        Raises
        ------
        ArgumentTypeError
            If an argument has the wrong type.
        ArgumentError
            If ``box`` has the wrong shape, is not finite or has ``lo >= hi``, ``n`` or ``seed`` is out of range,
            ``method`` is not one of the three, or ``method="directed"`` with a box that does not contain the
            equilibrium.
        """
        method = checks.choice("method", method, ("auto", "sobol", "directed"))
        ps = self.system
        if method != "directed":
            hits: list[int] = []
            vol = self._volume_sobol(box, n, seed, hits)
            if method == "sobol" or hits[0] >= MIN_SOBOL_HITS:
                return vol
        lo, hi = self._volume_box(box)
        n = checks.integer("n", n, lo=1, hi=2**24)
        seed = checks.integer("seed", seed, lo=0)
        free = [i for i in range(ps.n) if i not in ps.held]
        xe = np.asarray(ps.equilibrium, dtype=float)
        if np.any(xe[free] < lo[free]) or np.any(xe[free] > hi[free]):
            if method == "auto":
                return vol
            raise ArgumentError(f"volume(method='directed') integrates along rays from the equilibrium "
                                f"{xe.tolist()}, which must lie in the box (lo {lo.tolist()}, hi {hi.tolist()}): "
                                "enlarge the box or use method='sobol'")
        return _volume_directed(ps, self.V, self.rho, lo, hi, -(-n // _DIRECTED_PER_SOBOL), seed)[0]

    def _volume_box(self, box: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(lo, hi)`` of :meth:`volume` over all states, checked (``lo < hi`` in the free states)."""
        ps = self.system
        if box is None:
            box = ps.box
        if not isinstance(box, tuple | list) or len(box) != 2:
            raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({ps.n},)")
        lo = checks.array("box lo", box[0], shape=(ps.n,))
        hi = checks.array("box hi", box[1], shape=(ps.n,))
        free = [i for i in range(ps.n) if i not in ps.held]
        if np.any(lo[free] >= hi[free]):
            raise ArgumentError(f"box must have lo < hi in every coordinate, got lo {lo.tolist()}, hi {hi.tolist()}")
        return lo, hi

    def _volume_sobol(self, box: Any, n: int, seed: int, hits: list[int]) -> float:
        """The Sobol estimate of :meth:`volume`; appends the number of points inside to ``hits``."""
        ps = self.system

        def counted(inside: np.ndarray) -> np.ndarray:
            hits.append(int(np.count_nonzero(inside)))
            return inside

        if not ps.held:
            return box_measure(lambda X: counted(self.contains(X)), box if box is not None else ps.box, n, seed,
                               dim=ps.n)
        lo, hi = self._volume_box(box)
        free = [i for i in range(ps.n) if i not in ps.held]
        xe = np.asarray(ps.equilibrium, dtype=float)

        def inside(Y: np.ndarray) -> np.ndarray:      # the free states; the held ones at their values
            X = np.tile(xe, (len(Y), 1))
            X[:, free] = Y
            return counted(self.contains(X))

        return box_measure(inside, (lo[free], hi[free]), n, seed, dim=len(free))

    HISTORY_HEADER: ClassVar[tuple[str, ...]] = ("problem", "deg", "step", "rho", "measure", "SDP s")
    """Column names of :meth:`history_table`."""

    def history_table(self, label: str = "") -> list[list[str]]:
        """The alternation :attr:`history` as rows of text, one per iteration, as :data:`HISTORY_HEADER`.

        Parameters
        ----------
        label : str
            Text of the first column (the problem's name, so that the rows of several certificates can share one
            table).

        Returns
        -------
        list of list of str
            ``[label, degree, step (first 60 characters), level rho (6 significant digits), sampled area/volume in
            the box (4 digits, product of the state units), SDP time (s, 2 decimals)]`` per iteration.

        Raises
        ------
        ArgumentTypeError
            If ``label`` is not a string.
        """
        if not isinstance(label, str):
            raise ArgumentTypeError(f"label must be a string (the table's first column), got {type(label).__name__}")
        return [[label, str(h.degree), h.step[:60], f"{h.rho:.6g}", f"{h.volume:.4g}", f"{h.sdp_time:.2f}"]
                for h in self.history]

    def plot(self, ax: Any = None, dims: Any = (0, 1), fixed: Any = None, n: int = 201,
             samples: bool = True) -> Any:
        """Draw a 2-D slice of the certified set through the equilibrium, in the glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        dims : two state names or indices
            The plane of the slice (axes labelled with the system's state names).
        fixed : array_like (n,) or mapping, optional
            Values of the other states on the slice (a full state whose ``dims`` entries are ignored, or
            ``{name: value}``); default the equilibrium.
        n : int
            Grid points per axis over the system's box (:meth:`contains` on the grid), and the number of points of
            the set drawn when ``samples``.
        samples : bool
            Draw ``n`` random points of the slice that are in the set (the :attr:`verification` keeps counts, not
            its sampled points).

        Returns
        -------
        matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_roa_certificate`.

        Raises
        ------
        GlidectlError
            For ``dims`` or ``fixed`` that do not fit the system (see :func:`glidectl.plotting.plot_roa_certificate`).
        """
        from ..plotting import plot_roa_certificate, style

        with style():
            return plot_roa_certificate(self, ax, dims=dims, fixed=fixed, n=n, samples=samples)


_SWITCH_ROUNDS = 3       # rejection rounds of _sample_set before it may switch to the directed sampler
_SWITCH_PROJECTED = 20   # ... which it does if the rejection sampler projects to more rounds than this
_ROUNDS = 200            # rounds of directions at most (each sampler)
_DIRECTED_PER_SOBOL = 16  # volume(n=...): the directed estimate draws ceil(n / 16) directions (40 bisection steps each)


def _radii(ps: PolySystem, V: Poly, rho: float, x0: np.ndarray, D: np.ndarray, lo: np.ndarray, hi: np.ndarray,
           check: Any = None) -> np.ndarray:
    """Largest ``R`` with ``x0 + R D`` in the set (the box limits it), per row of ``D``: 40 bisection steps on
    :func:`path_contains`."""
    m = D.shape[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        tb = np.min(np.where(D > 0, (hi - x0) / D, np.where(D < 0, (lo - x0) / D, np.inf)), axis=1)
    a, b = np.zeros(m), tb * (1 - 1e-12)
    inside = path_contains(ps, V, rho, x0 + b[:, None] * D)
    a[inside] = b[inside]
    for _ in range(40):
        if check is not None:
            check()
        mid = 0.5 * (a + b)
        ok = path_contains(ps, V, rho, x0 + mid[:, None] * D) | inside
        a, b = np.where(ok, mid, a), np.where(ok, b, mid)
    return a


def _sample_set(ps: PolySystem, V: Poly, rho: float, n: int, seed: int, boundary: bool,
                check: Any = None) -> np.ndarray:
    """Points of the star-shaped set ``{V <= rho}`` (component of the equilibrium): see ROACertificate.sample.
    ``check()`` (optional) is called before every batch of directions and every bisection step (a time budget).

    Interior points come from rejection: uniform directions ``u`` (box-scaled, free states), kept with probability
    ``(R(u) / R_max)^nf`` (``R_max`` the largest radius of the batch), radius ``R(u) U^(1/nf)``. If after
    ``_SWITCH_ROUNDS`` rounds the expected acceptance (sum of those probabilities) projects to more than
    ``_SWITCH_PROJECTED`` rounds in all, or after any earlier round to more than ``_ROUNDS`` (the rounds allowed),
    the set is thin in many states: the points drawn so far are dropped and :func:`_sample_directed` draws all
    ``n`` (another random stream); otherwise the result is that of the rejection rounds alone, unchanged."""
    x0 = np.asarray(ps.equilibrium, dtype=float)
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    w = np.maximum(x0 - lo, hi - x0)
    free = [i for i in range(ps.n) if i not in ps.held]      # held states stay at their values
    nf = len(free)
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    got = 0
    expected = 0.0      # expected accepted count of the rounds so far (sum of the acceptance probabilities)

    for k in range(_ROUNDS):
        if check is not None:
            check()
        m = max(2 * n, 256)
        U = np.zeros((m, ps.n))
        U[:, free] = rng.standard_normal((m, nf))
        U /= np.linalg.norm(U, axis=1, keepdims=True)
        D = U * w                                   # directions in state units
        R = _radii(ps, V, rho, x0, D, lo, hi, check)
        if boundary:
            keep = R > 0
            pts = x0 + (R[keep] * (1 - 1e-9))[:, None] * D[keep]
        else:
            if not np.any(R > 0):
                continue
            acc = (R / np.max(R)) ** nf
            expected += float(np.sum(acc[R > 0]))
            keep = (rng.random(m) < acc) & (R > 0)
            rad = R[keep] * rng.random(int(keep.sum())) ** (1.0 / nf)
            pts = x0 + rad[:, None] * D[keep]
        out.append(pts)
        got += len(pts)
        if got >= n:
            break
        if not boundary and k + 1 <= _SWITCH_ROUNDS and expected > 0 and n * (k + 1) / expected > (
                _SWITCH_PROJECTED if k + 1 == _SWITCH_ROUNDS else _ROUNDS):
            return _sample_directed(ps, V, rho, n, seed, check)
    if got == 0:
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    return np.concatenate(out)[:n]


def _acg_proposal(ps: PolySystem, V: Poly) -> tuple[np.ndarray, np.ndarray, list[int], np.ndarray, np.ndarray,
                                                   np.ndarray]:
    """The angular central Gaussian proposal of :func:`_sample_directed` and :func:`_volume_directed`: ``(x0, w,
    free, Hs, L, lam)`` with ``x0`` the equilibrium, ``w`` the largest distance from it to a face of the system's
    box per state, ``free`` the states not held, ``Hs`` the Hessian of ``V(lift(x))`` at ``x0`` in the box-scaled
    free states ``(x - x0) / w`` (eigenvalues ``lam`` clipped at 1e-8 of the largest; the identity when it has no
    positive curvature) and ``L`` with ``L g ~ N(0, Hs^-1)`` for ``g ~ N(0, I)``."""
    x0 = np.asarray(ps.equilibrium, dtype=float)
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    w = np.maximum(x0 - lo, hi - x0)
    free = [i for i in range(ps.n) if i not in ps.held]
    nf = len(free)
    try:
        H = hessian(lambda X: value_of(V, ps, X), x0)[np.ix_(free, free)] * np.outer(w[free], w[free])
        lam, Q = np.linalg.eigh(0.5 * (H + H.T))
        ok = bool(np.all(np.isfinite(lam)) and lam[-1] > 0)
    except (np.linalg.LinAlgError, ValueError, FloatingPointError):
        ok = False
    if not ok:                          # no curvature to follow: uniform directions (still exact)
        lam, Q = np.ones(nf), np.eye(nf)
    lam = np.maximum(lam, 1e-8 * lam[-1])
    Hs = (Q * lam) @ Q.T
    L = Q / np.sqrt(lam)                # z = L g ~ N(0, Hs^-1)
    return x0, w, free, Hs, L, lam


def _directed_weights(ps: PolySystem, V: Poly, rho: float, G: np.ndarray, proposal: tuple, lo: np.ndarray,
                      hi: np.ndarray, check: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For standard normal draws ``G`` (m, nf) and the ``(x0, w, free, Hs, L)`` of :func:`_acg_proposal`: the
    directions ``u = L g / |L g|`` (angular central Gaussian), their log importance weights
    ``log W(u) = nf/2 log(R(u)^2 u' Hs u)`` (``-inf`` where ``R = 0``), the radii ``R(u)`` in the set and the box
    (:func:`_radii`) and the directions ``D`` in state units (rows ``x0 + R D`` are on the boundary)."""
    x0, w, free, Hs, L = proposal
    nf = len(free)
    Z = G @ L.T
    Z /= np.linalg.norm(Z, axis=1, keepdims=True)
    U = np.zeros((len(Z), ps.n))
    U[:, free] = Z
    D = U * w
    R = _radii(ps, V, rho, x0, D, lo, hi, check)
    with np.errstate(divide="ignore"):
        return 0.5 * nf * np.log(R ** 2 * np.einsum("ij,jk,ik->i", Z, Hs, Z)), R, D


def _sample_directed(ps: PolySystem, V: Poly, rho: float, n: int, seed: int, check: Any = None) -> np.ndarray:
    """``n`` points of the star-shaped set ``{V <= rho}`` (component of the equilibrium), uniform in its volume, for
    thin sets in many states where the rejection of :func:`_sample_set` accepts too few directions.

    A uniform point of a star-shaped set is a direction ``u`` with density proportional to ``R(u)^nf`` (``R(u)`` the
    boundary radius, ``nf`` the free states) times the radius ``R(u) U^(1/nf)``, ``U`` uniform. Directions are
    proposed from the angular central Gaussian: ``u = z / |z|``, ``z ~ N(0, H^-1)`` with ``H`` the Hessian of
    ``V(lift(x))`` at the equilibrium (box-scaled free states, eigenvalues clipped at 1e-8 of the largest), whose
    density on the sphere is proportional to ``(u' H u)^(-nf/2)``: exactly ``R(u)^nf`` for an ellipsoid. A proposal
    is kept with probability ``W(u) / W_max``, ``W(u) = (R(u)^2 u' H u)^(nf/2)`` the importance weight and
    ``W_max`` the largest weight among ALL the directions proposed (the acceptance of every proposal is re-decided
    with the final ``W_max``, its uniform number drawn once): the points are exactly uniform in the set whenever
    ``W_max`` bounds ``W``; directions whose weight exceeds every one seen (a part of the set rarer than one in the
    number proposed) are under-weighted, as the rejection of :func:`_sample_set` is with its batch's ``R_max``."""
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    x0, w, free, Hs, L, _ = _acg_proposal(ps, V)
    nf = len(free)
    rng = np.random.default_rng([seed, 17])
    logW, logU, Rs, Vs, Ds = [], [], [], [], []
    for _ in range(_ROUNDS):
        if check is not None:
            check()
        m = max(2 * n, 256)
        lw, R, D = _directed_weights(ps, V, rho, rng.standard_normal((m, nf)), (x0, w, free, Hs, L), lo, hi, check)
        logW.append(lw)
        logU.append(np.log(rng.random(m)))
        Vs.append(rng.random(m) ** (1.0 / nf))
        Rs.append(R)
        Ds.append(D)
        lw = np.concatenate(logW)
        top = float(np.max(lw))
        if not np.isfinite(top):
            continue
        keep = (np.concatenate(logU) < lw - top) & (np.concatenate(Rs) > 0)
        if int(keep.sum()) >= n:
            idx = np.flatnonzero(keep)[:n]
            rad = (np.concatenate(Rs) * np.concatenate(Vs))[idx]
            return x0 + rad[:, None] * np.concatenate(Ds)[idx]
    lw = np.concatenate(logW)
    if not np.any(np.isfinite(lw)):
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    keep = (np.concatenate(logU) < lw - np.max(lw)) & (np.concatenate(Rs) > 0)
    if not np.any(keep):
        raise SolverError("the certified set is empty in every sampled direction: nothing to sample")
    idx = np.flatnonzero(keep)          # fewer than n points after every round (as _sample_set)
    return x0 + (np.concatenate(Rs) * np.concatenate(Vs))[idx][:, None] * np.concatenate(Ds)[idx]


_VOLUME_CHUNK = 4096     # directions per batch of _volume_directed (bounds memory; the result does not depend on it)


def step_volume(ps: PolySystem, points: PathPoints, V: Poly, lo: np.ndarray, hi: np.ndarray, seed: int,
                 rho: float = 1.0) -> float:
    """Volume of ``{V <= rho}`` in the box ``[lo, hi]`` by which the alternation of :func:`certify_roa` judges a step
    (and its history records the final level), chosen as :meth:`ROACertificate.volume` ``(method="auto")`` chooses:
    ``prod(hi - lo)`` times the fraction of the fixed Sobol ``points`` inside when at least ``MIN_SOBOL_HITS`` of
    them are, else the directed estimate (:func:`_volume_directed`, ``ceil(N / 16)`` directions for ``N`` points,
    with the same seeded Gaussian draws at every step; the directions also depend on each V's Hessian).

    A thin set holds a handful of the points or none. The user glider's unsaturated LQR loop (8 free states) held
    none at every step, so no V step ever counted as an improvement and its certificate was the starting V's
    (1.55e-12); judged by the directed estimate, the alternation keeps its V steps (3.63e-11, certified).

    Parameters
    ----------
    ps : PolySystem
        The (scaled) system of the alternation, in its free states (it holds none); its box contains the
        equilibrium.
    points : PathPoints
        The fixed Sobol points of the box, with their segment points cached.
    V : Poly
        The candidate; the set is ``{V <= rho}``.
    lo, hi : ndarray, shape (n,)
        The box.
    seed : int
        Seed of the directions.
    rho : float
        The level (1 for the alternation's steps, whose V is normalized by its level).

    Returns
    -------
    float
        The volume, in the units of ``ps``'s states.
    """
    inside = points.contains(V, rho)
    if np.count_nonzero(inside) >= MIN_SOBOL_HITS:
        return float(np.prod(hi - lo) * np.mean(inside))
    return _volume_directed(ps, V, rho, lo, hi, -(-len(inside) // _DIRECTED_PER_SOBOL), seed)[0]


def _volume_directed(ps: PolySystem, V: Poly, rho: float, lo: np.ndarray, hi: np.ndarray, n: int, seed: int,
                     check: Any = None) -> tuple[float, float]:
    """Volume of the star-shaped set ``{V <= rho}`` (component of the equilibrium ``x_e``) inside the box
    ``[lo, hi]`` (which must contain ``x_e``), in the free states, and its standard error: ``n`` directions of the
    angular central Gaussian of :func:`_acg_proposal` (another random stream than the samplers).

    In the box-scaled free states ``y = (x - x_e) / w`` (``w`` the largest distance from ``x_e`` to a face of the
    system's box, per state) a star-shaped set with boundary radius ``R(u)`` (:func:`_radii`, which stops every ray
    at ``[lo, hi]``: the radius of the set intersected with the box) has volume
    ``(1 / nf) int_{S^(nf-1)} R(u)^nf du = |B^nf| E_unif[R(u)^nf]`` (``|B^nf| = pi^(nf/2) / Gamma(nf/2 + 1)``, the
    unit ball). The angular central Gaussian ``u = z / |z|``, ``z ~ N(0, H^-1)``, has density
    ``det(H)^(1/2) (u' H u)^(-nf/2)`` relative to the uniform law on the sphere, so

        vol_y = |B^nf| / sqrt(det H) E_ACG[W(u)],    W(u) = (R(u)^2 u' H u)^(nf/2),

    and the volume in state units is ``prod(w[free]) vol_y``. For an ellipsoid ``y' H y <= c`` (not cut by the box)
    ``W = c^(nf/2)`` in every direction: the estimate is exact. The standard error is the sample standard deviation
    of ``W`` over ``sqrt(n)`` times the same factor. ``check()`` (optional) is called before every batch of
    directions and every bisection step (a time budget). Returns ``(0.0, 0.0)`` if every radius is zero."""
    x0, w, free, Hs, L, lam = _acg_proposal(ps, V)
    nf = len(free)
    G = np.random.default_rng([seed, 23]).standard_normal((n, nf))
    lw = np.empty(n)                    # log W(u)
    for a in range(0, n, _VOLUME_CHUNK):
        if check is not None:
            check()
        g = G[a:a + _VOLUME_CHUNK]
        lw[a:a + len(g)] = _directed_weights(ps, V, rho, g, (x0, w, free, Hs, L), lo, hi, check)[0]
    top = float(np.max(lw))
    if not np.isfinite(top):
        return 0.0, 0.0
    e = np.exp(lw - top)
    log_c = (0.5 * nf * math.log(math.pi) - math.lgamma(0.5 * nf + 1) - 0.5 * float(np.sum(np.log(lam)))
             + float(np.sum(np.log(w[free]))) + top)
    c = math.exp(log_c)
    err = c * float(np.std(e, ddof=1)) / math.sqrt(n) if n > 1 else math.inf
    return c * float(np.mean(e)), err


_VERIFY_CHUNK = 4096     # points per membership / dV/dt batch of the verification (time checks between batches)


def verify_certificate(ps: PolySystem, V: Poly, rho: float, gram: tuple[GramCheck, ...], *, n_verify: int,
            n_simulate: int, horizon: float, seed: int, deadline: checks.Deadline | None = None) -> ROAVerification:
    """The a-posteriori checks. With a ``deadline`` (``time_limit`` of :func:`certify_roa`, ``on_budget="raise"``),
    every step is bounded by it: :class:`BudgetError` naming the step and what to lower, never fewer samples or
    simulations than asked for."""

    def remaining() -> float:
        return math.inf if deadline is None or deadline.limit is None else deadline.limit - deadline.elapsed

    def budget(step: str, lower: str) -> None:
        if remaining() < 0:
            raise BudgetError(f"certify_roa stopped at its time limit of {deadline.limit:g} s in the final "
                              f"verification, while {step} (the SOS certificate itself was found): raise time_limit, "
                              f"or lower {lower}; the verification is never shortened to fit")

    sampling = (f"sampling the certified set (n_verify = {n_verify} points) and checking the true dV/dt there",
                "n_verify")
    x0 = ps.equilibrium
    hmin, lmax = local_checks(ps, V)
    # sample the certified set (rejection from the system's box)
    lo, hi = ps.box
    rng = np.random.default_rng(seed)
    X = lo + (hi - lo) * rng.random((n_verify, ps.n))
    inside = np.zeros(n_verify, dtype=bool)
    for a in range(0, n_verify, _VERIFY_CHUNK):
        budget(*sampling)
        inside[a:a + _VERIFY_CHUNK] = path_contains(ps, V, rho, X[a:a + _VERIFY_CHUNK])
    Xs = X[inside]
    if ps.remainder or Xs.shape[0] < n_verify // 20:
        # a thin set in many states (or the surrogate route): add points drawn in the set and on its boundary
        try:
            Xs = np.concatenate([Xs, _sample_set(ps, V, rho, max(n_verify // 4, 1), seed, False,
                                                 lambda: budget(*sampling)),
                                 _sample_set(ps, V, rho, max(n_verify // 4, 1), seed + 1, True,
                                             lambda: budget(*sampling))])
        except SolverError:
            pass
    max_vd = float("nan")
    if Xs.shape[0]:
        vd = []
        for a in range(0, Xs.shape[0], _VERIFY_CHUNK):
            budget(*sampling)
            Xa = Xs[a:a + _VERIFY_CHUNK]
            vd.append(dVdt(V, ps.lift, ps.rhs, Xa) / np.maximum(np.sum((Xa - x0) ** 2, axis=1), 1e-300))
        max_vd = float(np.max(np.concatenate(vd)))
    # simulations from the outermost sampled points
    nsim = min(n_simulate, Xs.shape[0])
    conv = 0
    if nsim:
        sims = (f"simulating n_simulate = {nsim} runs of length horizon = {horizon:g} from the outermost samples",
                "n_simulate or horizon")
        budget(*sims)
        pick = Xs[np.argsort(value_of(V, ps, Xs))[::-1][:nsim]]
        left = remaining()
        try:
            res = integrate_batch(ps.rhs, pick, horizon, rtol=1e-7, atol=1e-10, max_steps=200_000,
                                  time_limit=None if math.isinf(left) else max(left, 1e-3))
        except BudgetError as exc:
            raise BudgetError(f"certify_roa's final verification ran out of its time limit while {sims[0]}: "
                              f"raise time_limit, or lower {sims[1]} ({exc})") from exc
        conv = int(np.sum(res.converged_to(x0, 1e-3 * max(1.0, float(np.max(hi - lo))))))
    return ROAVerification(gram, hmin, lmax, int(Xs.shape[0]), max_vd, nsim, conv, horizon)


def local_checks(ps: PolySystem, V: Poly) -> tuple[float, float]:
    """The checks of :class:`ROAVerification` at the equilibrium: the smallest eigenvalue of the Hessian ``H`` of
    ``V(lift(x))`` there and the largest of ``A'H + HA`` (``A`` the linearization)."""
    H = hessian(lambda X: value_of(V, ps, X), ps.equilibrium)
    A = linearization(ps)
    return float(np.linalg.eigvalsh(H)[0]), float(np.linalg.eigvalsh(A.T @ H + H @ A)[-1])


def default_horizon(ps: PolySystem) -> float:
    """25 time constants of the slowest mode of the linearization (:func:`~glidectl.roa.extent.settling_horizon`)."""
    return settling_horizon(linearization(ps))


def simulated_truth(ps: PolySystem, n: int, horizon: float, seed: int,
                  deadline: checks.Deadline | None = None) -> np.ndarray:
    """Sobol points of the box (inside the cuts) whose simulations converge to the equilibrium (bounded by the
    ``deadline``, if it has a limit: :class:`BudgetError` saying to lower ``n_truth`` or ``horizon``)."""
    lo, hi = ps.box
    X = lo + (hi - lo) * unit_sobol(ps.n, seed + 5, n)
    X = X[ps.in_cuts(X)]
    if X.shape[0] == 0:
        return X
    left = None if deadline is None or deadline.limit is None else deadline.limit - deadline.elapsed
    what = (f"certify_roa stopped at its time limit of {deadline.limit if left is not None else 0:g} s while "
            f"simulating n_truth = {n} box points over horizon = {horizon:g} (the points that steer the V step): "
            "raise time_limit, or lower n_truth or horizon")
    if left is not None and left <= 0:
        raise BudgetError(what)
    try:
        res = integrate_batch(ps.rhs, X, horizon, rtol=1e-6, atol=1e-9, max_steps=50_000,
                              bound=1e3 * float(np.max(np.abs(np.concatenate([lo, hi])))), time_limit=left)
    except BudgetError as exc:
        raise BudgetError(f"{what} ({exc})") from exc
    return X[res.converged_to(ps.equilibrium, 1e-3)]

