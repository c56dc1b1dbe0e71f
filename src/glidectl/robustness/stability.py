"""Closed-loop robustness to uncertain coefficients: :func:`robust_stability`, :class:`RobustStability`,
:func:`with_vehicle`, :func:`loop_poles`.

A controller designed on the nominal vehicle keeps its law (gain, set point, the model it was built on) while the
plant takes a sampled vehicle's coefficients (:func:`with_vehicle`). The loop then has another equilibrium: it is
found by Newton's method from the nominal one (``scipy.optimize.root`` with the complex-step Jacobian), and the
loop is locally exponentially stable there iff every eigenvalue of its Jacobian has a negative real part. Two kinds
of states are held out of the analysis: those the loop never moves (rows of zeros in the nominal Jacobian, such as a
fixed actuator's) and those nothing depends on (columns of zeros, such as the horizontal position and, without a
density profile, the depth of a loop that does not feed them back: they drift along the glide and have no
equilibrium, and the rest of the loop is stable or not whatever they are). The
largest real part is the number studied: its distribution over the ``[uncertainty]`` table (probability of
stability), its maximum over the box of the table (worst case: sampled, then a bounded local search from the worst
samples and the box's corners), the largest scaling of that box about the nominal coefficients that keeps it
negative (margin, by bisection on the worst case), and its derivatives with respect to each coefficient
(sensitivities, by central differences).
"""

from __future__ import annotations

import dataclasses
import math
import time
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.optimize as so

from .. import checks
from ..analysis.continuation import chunk_bounds, run_chunks
from ..controllers.closed_loop import closed_loop
from ..controllers.output_feedback import PlantWithEstimator
from ..derivatives import jacobians
from ..errors import ArgumentError, ArgumentTypeError, GlidectlError, ModelError, VehicleFileError
from ..models.closed_loop import ClosedLoop
from ..params import Vehicle
from ..uncertainty import vertex_values

__all__ = ["LoopPoles", "RobustStability", "WorstCase", "loop_poles", "robust_stability", "with_vehicle"]

#: Largest scaling of the uncertainty box the margin search tries: a loop stable on 4 times the box is reported with
#: ``margin == MARGIN_MAX`` (and ``margin_bounded`` False).
MARGIN_MAX = 4.0


def with_vehicle(model: Any, veh: Vehicle) -> Any:
    """The same model with another vehicle's coefficients: every :class:`~glidectl.params.Vehicle` among its
    (nested, frozen dataclass) fields replaced by ``veh``.

    A :class:`~glidectl.models.closed_loop.ClosedLoop` keeps its law (a controller designed on the nominal vehicle
    keeps its gain and set point) and loses its equilibrium, which the new plant generally moves
    (:func:`loop_poles` finds it).

    Parameters
    ----------
    model : glidectl model or ClosedLoop
    veh : Vehicle

    Returns
    -------
    The model rebuilt (its checks rerun) on ``veh``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, or ``model`` holds no vehicle in its dataclass fields.
    """
    if not isinstance(veh, Vehicle):
        raise ArgumentTypeError(f"veh must be a Vehicle, got {type(veh).__name__}")
    if isinstance(model, ClosedLoop):
        return ClosedLoop(with_vehicle(model.plant, veh), model.law, None, model.description)
    out, found = _replace_vehicle(model, veh)
    if not found:
        raise ArgumentTypeError(f"{type(model).__name__} holds no Vehicle in its fields: it cannot be rebuilt on "
                                "another vehicle")
    return out


def _replace_vehicle(obj: Any, veh: Vehicle) -> tuple[Any, bool]:
    if isinstance(obj, Vehicle):
        return veh, True
    if not dataclasses.is_dataclass(obj) or isinstance(obj, type):
        return obj, False
    changes = {}
    for f in dataclasses.fields(obj):
        if not f.init:
            continue
        new, found = _replace_vehicle(getattr(obj, f.name), veh)
        if found:
            changes[f.name] = new
    return (dataclasses.replace(obj, **changes), True) if changes else (obj, False)


@dataclass(frozen=True)
class LoopPoles:
    """The equilibrium of a closed loop near a guess and the eigenvalues of its Jacobian there (:func:`loop_poles`).

    Attributes
    ----------
    equilibrium : ndarray, shape (n,)
        States (the loop's units); the held states at the guess.
    poles : ndarray of complex
        Eigenvalues of the Jacobian on the states that are not held (1 / time unit of the loop).
    max_real : float
        Their largest real part (< 0: locally exponentially stable).
    residual : float
        ``max |x'|`` at the equilibrium.
    """

    equilibrium: np.ndarray = field(repr=False)
    poles: np.ndarray = field(repr=False)
    max_real: float
    residual: float

    @property
    def dominant(self) -> complex:
        """The pole with the largest real part (of a complex pair, the one with positive imaginary part)."""
        top = self.poles[self.poles.real >= self.max_real - 1e-9 * max(1.0, abs(self.max_real))]
        return complex(top[int(np.argmax(top.imag))])


def loop_poles(loop: Any, guess: Any, free: Any = None, *, tol: float = 1e-9) -> LoopPoles:
    """Equilibrium of an input-free loop near ``guess`` (Newton, complex-step Jacobian) and its poles.

    Parameters
    ----------
    loop : input-free model
        ``rhs(x)`` complex-safe (a :class:`~glidectl.models.closed_loop.ClosedLoop`).
    guess : array_like, shape (n,)
        Where Newton's method starts (e.g. the nominal loop's equilibrium).
    free : sequence of int, optional
        States solved for and in the Jacobian; the others are held at ``guess`` (default all).
    tol : float
        Largest ``max |x'|`` accepted, relative to ``max(1, max |x'(guess)|)``.

    Returns
    -------
    LoopPoles

    Raises
    ------
    ModelError
        If no equilibrium is found near ``guess`` (the message gives the residual).
    """
    x0 = np.asarray(guess, dtype=float)
    f = list(range(x0.size)) if free is None else list(free)

    def full(z: np.ndarray) -> np.ndarray:
        x = np.broadcast_to(x0, (*np.shape(z)[:-1], x0.size)).astype(np.result_type(z, float))
        x[..., f] = z
        return x

    def F(z: np.ndarray) -> np.ndarray:
        return np.asarray(loop.rhs(full(z)))[..., f].real

    def J(z: np.ndarray) -> np.ndarray:
        return jacobians(lambda x, u: np.asarray(loop.rhs(full(x)))[..., f], z, np.zeros(0))[0]

    scale = max(1.0, float(np.max(np.abs(F(x0[f])))))
    with np.errstate(all="ignore"):
        sol = so.root(F, x0[f], jac=J, method="hybr", options={"xtol": 1e-13})
    res = float(np.max(np.abs(F(sol.x)))) if np.all(np.isfinite(sol.x)) else math.inf
    if not res <= tol * scale:
        raise ModelError(f"no closed-loop equilibrium near the nominal one (Newton residual {res:.3g}: "
                         f"{sol.message})")
    poles = np.linalg.eigvals(J(sol.x))
    return LoopPoles(full(sol.x).real, poles, float(np.max(poles.real)), res)


@dataclass(frozen=True)
class WorstCase:
    """The coefficients in the uncertainty box with the largest closed-loop real part found.

    Attributes
    ----------
    coefficients : dict
        Coefficient name to value (its unit).
    max_real : float
        Largest real part of the closed-loop poles there (``inf``: no equilibrium near the nominal one).
    pole : complex
        The dominant pole (NaN without an equilibrium).
    evaluations : int
        Loops solved by the search.
    """

    coefficients: dict[str, float]
    max_real: float
    pole: complex
    evaluations: int


@dataclass(frozen=True)
class _Problem:
    """What every evaluation needs: the nominal loop and vehicle, the free states, the box (pickled to workers)."""

    loop: Any
    vehicle: Vehicle
    free: tuple[int, ...]
    keys: tuple[str, ...]
    nominal: np.ndarray
    lo: np.ndarray
    hi: np.ndarray

    def evaluate(self, values: np.ndarray) -> tuple[float, complex, str | None]:
        """Largest real part and dominant pole at coefficients ``values``, and why it failed: ``inf`` when the loop
        has no equilibrium near the nominal one (unstable for this study), NaN when the coefficients make no valid
        vehicle (no verdict)."""
        try:
            veh = self.vehicle.with_overrides(**dict(zip(self.keys, map(float, values), strict=True)))
        except VehicleFileError as exc:              # not a physical vehicle: no verdict
            return math.nan, complex(math.nan, math.nan), f"VehicleFileError: {exc}"
        try:
            lp = loop_poles(with_vehicle(self.loop, veh), self.loop.equilibrium, self.free)
            return lp.max_real, lp.dominant, None
        except GlidectlError as exc:                 # no equilibrium near the nominal one: counted unstable
            return math.inf, complex(math.nan, math.nan), f"{type(exc).__name__}: {exc}"

    def at(self, u: np.ndarray) -> np.ndarray:
        """Coefficients at box coordinates ``u`` in [-1, 1] (0: nominal; -1, 1: the box's ends, per side)."""
        return np.where(u < 0, self.nominal + u * (self.nominal - self.lo), self.nominal + u * (self.hi - self.nominal))

    def coordinates(self, values: np.ndarray) -> np.ndarray:
        """Box coordinates of coefficients ``values`` (the inverse of :meth:`at`)."""
        span = np.where(values < self.nominal, self.nominal - self.lo, self.hi - self.nominal)
        return (values - self.nominal) / np.where(span > 0, span, 1.0)


def _evaluate_chunk(problem: _Problem, values: np.ndarray) -> list[tuple[float, complex, str | None]]:
    return [problem.evaluate(v) for v in values]


def _evaluate_many(problem: _Problem, values: np.ndarray, executor: Executor | None,
                   chunks: int) -> list[tuple[float, complex, str | None]]:
    bounds = chunk_bounds(len(values), max(1, min(chunks, len(values))))
    parts = run_chunks(_evaluate_chunk, [(problem, values[a:b]) for a, b in bounds], executor)
    return [r for p in parts for r in p]


def _objective(u: np.ndarray, problem: _Problem, count: list[int]) -> float:
    """Minus the largest real part at box coordinates ``u`` (an invalid vehicle is never the worst case)."""
    count[0] += 1
    r = problem.evaluate(problem.at(u))[0]
    return -r if math.isfinite(r) else (-1e6 if r > 0 else 1e6)


def _search(problem: _Problem, starts: np.ndarray, scale: float, maxfev: int, count: list[int]) -> tuple[np.ndarray,
                                                                                                        float]:
    """Bounded local search (Powell) of the largest real part in the box scaled by ``scale`` from each start (box
    coordinates); the best point and its value."""
    best_u, best = starts[0], -math.inf
    bounds = [(-scale, scale)] * starts.shape[1]
    for u0 in starts:
        with np.errstate(all="ignore"):
            r = so.minimize(_objective, np.clip(u0, -scale, scale), args=(problem, count), method="Powell",
                            bounds=bounds, options={"maxfev": maxfev, "xtol": 1e-3, "ftol": 1e-6})
        val = -float(r.fun)
        if val > best:
            best_u, best = np.clip(r.x, -scale, scale), val
    return best_u, best


def _worst_in_box(problem: _Problem, scale: float, extra: np.ndarray, corner_limit: int, starts: int, maxfev: int,
                  seed: int, count: list[int]) -> tuple[np.ndarray, float]:
    """Worst case in the box scaled by ``scale``: its corners (those of :meth:`glidectl.Vehicle.vertices`: all when
    ``2^k <= corner_limit``, else the nominal point, the axis extremes and random corners) and ``extra`` points (box
    coordinates) evaluated, then the local search from the ``starts`` worst of them."""
    veh = problem.vehicle
    _, corners = vertex_values(veh.uncertainty, veh.params, max(corner_limit, 2 * len(problem.keys) + 1), seed)
    pts = np.concatenate([scale * problem.coordinates(corners), np.clip(extra, -scale, scale)])
    vals = np.array([-_objective(u, problem, count) for u in pts])
    order = np.argsort(-vals)[:starts]
    u, v = _search(problem, pts[order], scale, maxfev, count)
    if vals[order[0]] >= v:
        u, v = pts[order[0]], float(vals[order[0]])
    return u, v


@dataclass(frozen=True)
class RobustStability:
    """Stability of a closed loop over a vehicle's uncertain coefficients (:func:`robust_stability`).

    Attributes
    ----------
    loop : str
        The nominal closed loop.
    keys : tuple of str
        The uncertain coefficients.
    values : ndarray, shape (n, len(keys))
        The sampled coefficients (their units).
    max_real : ndarray, shape (n,)
        Largest real part of each sample's closed-loop poles (1 / time unit of the loop); ``inf``: no equilibrium
        near the nominal one; NaN: an invalid vehicle.
    dominant : ndarray of complex, shape (n,)
        Each sample's dominant pole.
    errors : tuple of (str or None)
        Why a sample has no poles.
    nominal_max_real : float
        The nominal loop's.
    probability : float
        Fraction of the valid samples whose loop is stable (``max_real < 0``).
    worst_case : WorstCase or None
        Largest real part found in the box (None when not searched).
    margin : float or None
        Largest scaling of the box about the nominal coefficients that keeps every point found stable (each side
        scaled; 1: the box itself; None when not searched).
    margin_bounded : bool
        Whether an unstable point was found (else ``margin`` is :data:`MARGIN_MAX`, a lower bound).
    sensitivities : dict
        Coefficient to the change of the dominant pole (complex, 1 / time unit) when the coefficient moves by its
        half-range in the box (central differences at the nominal coefficients).
    box : (ndarray, ndarray)
        The box of the uncertainty table (:meth:`glidectl.uncertainty.Uncertainty.box`).
    seed : int
    executor : str
    times : dict
        Wall time of each stage (s).
    vehicle : Vehicle
        The vehicle with the uncertainty table.
    provenance : str
    """

    loop: str
    keys: tuple[str, ...]
    values: np.ndarray = field(repr=False)
    max_real: np.ndarray = field(repr=False)
    dominant: np.ndarray = field(repr=False)
    errors: tuple[str | None, ...] = field(repr=False)
    nominal_max_real: float
    probability: float
    worst_case: WorstCase | None
    margin: float | None
    margin_bounded: bool
    sensitivities: dict[str, complex]
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    seed: int
    executor: str
    times: dict[str, float]
    vehicle: Vehicle = field(repr=False)
    provenance: str

    @property
    def valid(self) -> np.ndarray:
        """Samples that are valid vehicles (a verdict: stable or not)."""
        return ~np.isnan(self.max_real)

    @property
    def stable(self) -> np.ndarray:
        """Samples whose loop is stable."""
        return self.valid & (self.max_real < 0)

    def summary(self) -> str:
        """The probability, worst case, margin and the largest sensitivities, in words."""
        rows = [f"{self.loop}: stable in {self.probability:.1%} of {int(self.valid.sum())} valid samples (of "
                f"{self.max_real.size}); nominal largest real part {self.nominal_max_real:.4g}"]
        if self.worst_case is not None:
            wc = self.worst_case
            rows.append(f"  worst case {wc.max_real:.4g} at " + ", ".join(f"{k} = {v:.5g}"
                                                                       for k, v in wc.coefficients.items()))
        if self.margin is not None:
            rows.append(f"  margin: {'' if self.margin_bounded else '>= '}{self.margin:.3g} x the box")
        top = sorted(self.sensitivities.items(), key=lambda kv: -abs(kv[1].real))[:5]
        rows.append("  dominant-pole real part per half-range: " + ", ".join(f"{k} {v.real:+.3g}" for k, v in top))
        return "\n".join(rows)

    def plot(self, ax: Any = None) -> Any:
        """Histogram of the largest real part (the stability boundary and the worst case marked), the
        sensitivities of the dominant pole, and the largest real part against the most sensitive coefficient
        (:func:`glidectl.plotting.plot_robust_stability`). Returns the 3 Axes."""
        from ..plotting import plot_robust_stability

        return plot_robust_stability(self, ax)


def _problem(controller: Any, vehicle: Vehicle | None) -> _Problem:
    """The nominal loop, its vehicle with the uncertainty table, the held states and the box."""
    loop = controller if isinstance(controller, ClosedLoop) else closed_loop(controller)
    if isinstance(loop.plant, PlantWithEstimator):
        raise ArgumentTypeError("robust_stability takes state-feedback loops: in an output-feedback loop the "
                                "estimator must keep the nominal vehicle while the plant changes, which "
                                "with_vehicle does not separate yet")
    if loop.equilibrium is None:
        raise ArgumentError(f"{loop.name} has no equilibrium: give a closed loop with one (gc.closed_loop(controller) "
                            "or gc.closed_loop(plant, law, equilibrium=...))")
    veh = loop.vehicle if vehicle is None else vehicle
    if not isinstance(veh, Vehicle):
        raise ArgumentTypeError(f"vehicle must be a Vehicle, got {type(veh).__name__}")
    if dict(veh.params) != dict(loop.vehicle.params):
        raise ArgumentError(f"vehicle '{veh.name}' does not have the coefficients of the loop's nominal vehicle "
                            f"'{loop.vehicle.name}': give the loop's vehicle with its [uncertainty] table "
                            "(veh.with_uncertainty(...))")
    if not veh.uncertainty:
        raise ArgumentError(f"vehicle '{veh.name}' has no [uncertainty] table: add one to its file, or pass "
                            "vehicle=veh.with_uncertainty({...})")
    A = jacobians(lambda x, u: np.asarray(loop.rhs(x)), np.asarray(loop.equilibrium, float), np.zeros(0))[0]
    free = tuple(int(i) for i in np.flatnonzero(np.any(A != 0, axis=1) & np.any(A != 0, axis=0)))
    keys = tuple(veh.uncertainty)
    nominal = np.array([veh.params[k] for k in keys], dtype=float)
    box = np.array([veh.uncertainty[k].box(veh.params[k]) for k in keys], dtype=float)
    return _Problem(loop, veh, free, keys, nominal, box[:, 0], box[:, 1])


def _margin(problem: _Problem, worst_u: np.ndarray, corner_limit: int, maxfev: int, seed: int,
            count: list[int], steps: int = 8) -> tuple[float, bool]:
    """Largest box scaling (<= MARGIN_MAX) whose worst case found is stable, by bisection; and whether bounded."""
    def unstable(scale: float) -> bool:
        return _worst_in_box(problem, scale, worst_u[None, :] * scale, corner_limit, 1, maxfev, seed, count)[1] >= 0

    if problem.evaluate(problem.nominal)[0] >= 0:
        return 0.0, True
    lo, hi = 0.0, 1.0
    while not unstable(hi):
        lo, hi = hi, 2.0 * hi
        if lo >= MARGIN_MAX:
            return MARGIN_MAX, False
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if unstable(mid) else (mid, hi)
    return lo, True


def _sensitivities(problem: _Problem, h: float = 1e-3) -> dict[str, complex]:
    """Central differences of the dominant pole in box coordinates (per half-range of each coefficient)."""
    out = {}
    for j, k in enumerate(problem.keys):
        e = np.zeros(len(problem.keys))
        e[j] = h
        up, dn = problem.evaluate(problem.at(e))[1], problem.evaluate(problem.at(-e))[1]
        out[k] = (up - dn) / (2 * h)
    return out


def robust_stability(controller: Any, n: int = 1000, seed: int = 0, executor: Executor | None = None, *,
                     vehicle: Vehicle | None = None, chunks: int | None = None, worst_case: bool = True,
                     margin: bool = True, corner_limit: int = 64, starts: int = 3,
                     maxfev: int = 300) -> RobustStability:
    """Probability of stability, worst case, margin and sensitivities of a closed loop whose controller keeps its
    nominal design while the vehicle's coefficients vary over its ``[uncertainty]`` table (module docstring).

    Parameters
    ----------
    controller : controller of this package or ClosedLoop
        Designed on the nominal vehicle (:func:`glidectl.closed_loop` makes its loop), or a closed loop with an
        equilibrium.
    n : int
        Samples of the table (>= 1; :meth:`glidectl.Vehicle.sample`).
    seed : int
        Seed of the samples and of the random corners (>= 0): the same result whatever the executor.
    executor : concurrent.futures.Executor, optional
        Runs the samples in chunks (a process pool, a dask client's executor); None: in this process.
    vehicle : Vehicle, optional
        The loop's vehicle with an ``[uncertainty]`` table (default the loop's own vehicle, which must have one).
    chunks : int, optional
        Pieces of the samples (default 1 without an executor, else 8).
    worst_case, margin : bool
        Search the worst case in the box (corners, then a bounded Powell search from the worst ``starts`` points
        among the corners and the samples, ``maxfev`` evaluations each), and the margin (bisection on the box
        scaling, :data:`MARGIN_MAX` at most).
    corner_limit : int
        Most corners evaluated per box (all ``2^k`` when fewer; else the nominal point, the axis extremes and random
        corners, at least ``2k + 1``).
    starts, maxfev : int
        Local searches and their evaluation budget.

    Returns
    -------
    RobustStability

    Raises
    ------
    ArgumentTypeError
        If ``controller`` is neither a controller of this package nor a ClosedLoop, or ``vehicle`` not a Vehicle.
    ArgumentError
        If the loop has no equilibrium, the vehicle has no ``[uncertainty]`` table or other coefficients than the
        loop's, or an option is out of range.
    ModelError
        If the nominal loop has no equilibrium where it says (Newton does not converge there).
    """
    t0 = time.perf_counter()
    n = checks.integer("n", n, lo=1, hi=10**7)
    seed = checks.integer("seed", seed, lo=0)
    corner_limit = checks.integer("corner_limit", corner_limit, lo=1, hi=2**16)
    starts = checks.integer("starts", starts, lo=1, hi=100)
    maxfev = checks.integer("maxfev", maxfev, lo=1, hi=10**6)
    chunks = checks.integer("chunks", 1 if executor is None else 8, lo=1) if chunks is None else \
        checks.integer("chunks", chunks, lo=1)
    problem = _problem(controller, vehicle)
    nominal = loop_poles(problem.loop, problem.loop.equilibrium, problem.free)
    sample = problem.vehicle.sample(n, seed)
    vals = np.array(sample.values, dtype=float)
    res = _evaluate_many(problem, vals, executor, chunks)
    times = {"samples": time.perf_counter() - t0}
    mr = np.array([r[0] for r in res])
    dom = np.array([r[1] for r in res])
    valid = ~np.isnan(mr)
    wc, marg, bounded, count = None, None, False, [0]
    if worst_case or margin:
        t1 = time.perf_counter()
        # the worst samples, in box coordinates, start the local search beside the corners
        U = np.clip(problem.coordinates(vals), -1.0, 1.0)
        worst = U[np.argsort(-np.where(valid, mr, -np.inf))[:starts]]
        u, v = _worst_in_box(problem, 1.0, worst, corner_limit, starts, maxfev, seed, count)
        r = problem.evaluate(problem.at(u))
        # the loop's own number there: inf when it has no equilibrium (the search ranks that case as 1e6)
        wc = WorstCase(dict(zip(problem.keys, map(float, problem.at(u)), strict=True)),
                       float(r[0]) if not math.isnan(r[0]) else float(v), r[1], count[0])
        times["worst case"] = time.perf_counter() - t1
        if margin:
            t2 = time.perf_counter()
            marg, bounded = _margin(problem, u, corner_limit, maxfev, seed, count)
            times["margin"] = time.perf_counter() - t2
    t3 = time.perf_counter()
    sens = _sensitivities(problem)
    times["sensitivities"] = time.perf_counter() - t3
    times["total"] = time.perf_counter() - t0
    for a in (vals, mr, dom):
        a.setflags(write=False)
    ex = "none" if executor is None else type(executor).__module__ + "." + type(executor).__qualname__
    prob = float(np.mean(mr[valid] < 0)) if valid.any() else math.nan
    return RobustStability(problem.loop.name, problem.keys, vals, mr, dom, tuple(r[2] for r in res),
                           nominal.max_real, prob, wc if worst_case else None, marg, bounded, sens,
                           (problem.lo.copy(), problem.hi.copy()), seed, ex, times, problem.vehicle,
                           problem.vehicle.provenance)
