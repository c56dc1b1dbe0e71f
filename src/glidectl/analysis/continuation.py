"""Continuation engine for the maps of steady helices (§8.2.2): walking the helix trim along one control
parameter, optionally in chunks on an executor, and reconciling the chunks with the serial walk.

Used by :func:`glidectl.analysis.helix_sweeps.helix_sweep` (the public entry point, which returns a
:class:`~glidectl.analysis.helix_sweeps.HelixSweep`) and :func:`glidectl.analysis.helix_existence.existence_scan`.

Continuation (``continuation=True``)
------------------------------------
The values are walked in the order given. The walk starts at the first value where a cold solve (straight
longitudinal glide continued in ``r_P2``, then random starts: ``helix_trim(..., guess=None)``) succeeds; from there
it walks up to the last value and down to the first, warm-starting each solve from the last solution found (Newton
from the previous trim unknowns ``(v1, v2, v3, psidot, theta, phi)``) and falling back to a cold solve when the warm
start does not converge. Points below the seed already failed the cold solve during the seed search, so there the
walk tries the warm start only. A sweep that begins in a region without solutions thus still finds the branch, and
points the cold start cannot reach are found by continuation from a neighbour.

Executors
---------
With ``executor`` (any :class:`concurrent.futures.Executor`: a ``ProcessPoolExecutor``, a
``dask.distributed.Client.get_executor()``...) the values are split into ``chunks`` contiguous pieces, each walked
independently by the module-level function :func:`walk_chunk` (seeded by a cold solve at its first point; only the
vehicle and plain data are submitted, so everything pickles). The parent then reconciles the chunks with the serial
walk: at each chunk boundary it repeats the serial warm step from the previous chunk's last solution and accepts the
chunk from the first point (at or after the chunk's seed) where both agree (trim unknowns within 1e-7); before that
point, and for whole chunks that never agree (another branch, or no solution), it continues the serial walk itself,
reusing the chunks' cold solves (which are deterministic). If the first chunks have no cold solution at all, the
parent also repeats the serial downward walk from the first seed. The result is therefore the serial sweep, equal to
it to Newton precision (1e-9 or better in every column) whatever the executor and chunking; the work done in the
parent is one warm Newton step per chunk boundary when the chunks agree.

Determinism: cold solves use ``seed``; nothing depends on timing or on which worker ran a chunk.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from .. import checks
from ..errors import ArgumentTypeError, BudgetError, InfeasibleGlideError
from ..models.glider3d import FixedMassGlider3D
from ..params import Vehicle
from ..trim.helix import Helix, helix_newton, helix_trim

__all__ = [
    "AGREE_TOL",
    "COLUMNS",
    "COLUMN_UNITS",
    "MAX_CONTINUATION_STEPS",
    "MAX_NEWTON_SOLVES",
    "MAX_RANDOM_STARTS",
    "PARAMETERS",
    "ContinuationOptions",
    "ContinuationPoint",
    "check_executor",
    "check_options",
    "check_solve_budget",
    "check_sweep_inputs",
    "chunk_bounds",
    "readonly_array",
    "reconcile_chunks",
    "run_chunks",
    "sweep_controls",
    "walk_chunk",
]

#: control parameters that can be swept: name -> (unit, index in r_P or None for m0)
PARAMETERS: dict[str, tuple[str, int | None]] = {"r_P1": ("m", 0), "r_P2": ("m", 1), "r_P3": ("m", 2),
                                                 "m0": ("kg", None)}
#: columns of :attr:`glidectl.analysis.helix_sweeps.HelixSweep.data`, with units
COLUMNS: tuple[str, ...] = ("radius", "speed", "pitch", "period", "alpha", "beta", "theta", "phi", "gamma", "psidot",
                            "Omega_norm", "max_re_eig", "residual", "r_bh", "v1", "v2", "v3")
COLUMN_UNITS: dict[str, str] = {"radius": "m", "speed": "m/s", "pitch": "m", "period": "s", "alpha": "rad",
                                "beta": "rad", "theta": "rad", "phi": "rad", "gamma": "rad", "psidot": "rad/s",
                                "Omega_norm": "rad/s", "max_re_eig": "1/s", "residual": "m/s^2, rad/s^2",
                                "r_bh": "m", "v1": "m/s", "v2": "m/s", "v3": "m/s"}
AGREE_TOL = 1e-7  # max |difference of trim unknowns| for two solves to be the same motion (chunk reconciliation)
#: bounds of the multistart searches: r_P2 continuation steps and random starts of one cold solve, and the largest
#: number of Newton solves a sweep or scan may plan (checked before anything is solved)
MAX_CONTINUATION_STEPS = 1_000
MAX_RANDOM_STARTS = 10_000
MAX_NEWTON_SOLVES = 5_000_000
_NAN_ROW = np.full(len(COLUMNS), np.nan)
_NAN_Y = np.full(6, np.nan)


# ---------------------------------------------------------------------------------------------- plain records
class ContinuationOptions(NamedTuple):
    """Cold-solve settings forwarded to :func:`glidectl.trim.helix.helix_trim` (picklable): the number of ``r_P2``
    continuation steps from the longitudinal straight glide, of random starts, and their seed."""

    continuation_steps: int
    n_random: int
    seed: int


class ContinuationPoint(NamedTuple):
    """One solved (or failed) point of a walk, plain data only so that it pickles cheaply.

    ``unknowns`` are the trim unknowns ``(v1, v2, v3, psidot, theta, phi)`` (m/s, rad/s, rad) and ``row`` the
    helix quantities in the order of :data:`COLUMNS` (units :data:`COLUMN_UNITS`); both NaN when missing."""

    exists: bool
    unknowns: np.ndarray  # (6,) trim unknowns, NaN when missing
    row: np.ndarray  # (len(COLUMNS),), NaN when missing
    how: str  # "cold", "warm", "cold (warm failed)" or "none"
    note: str


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def sweep_controls(parameter: str, x: float, r_p: tuple[float, float, float], m0: float
                   ) -> tuple[tuple[float, float, float], float]:
    """Controls ``(r_P (m), m0 (kg))`` at the value ``x`` of the swept ``parameter`` (:data:`PARAMETERS`): the swept
    component replaces its entry of ``r_p`` (m), or ``m0`` (kg) itself.

    Parameters
    ----------
    parameter : str
        A key of :data:`PARAMETERS`.
    x : float
        Its value (m or kg).
    r_p : tuple of 3 floats
        Moving-mass position held fixed (m).
    m0 : float
        Buoyancy held fixed (kg).

    Returns
    -------
    tuple
        ``((r_P1, r_P2, r_P3), m0)``.

    Raises
    ------
    ArgumentError
        If ``parameter`` is not a key of :data:`PARAMETERS`.
    """
    idx = PARAMETERS[checks.choice("parameter", parameter, PARAMETERS)][1]
    if idx is None:
        return r_p, float(x)
    r = list(r_p)
    r[idx] = float(x)
    return (r[0], r[1], r[2]), m0


def _row(h: Helix) -> np.ndarray:
    d = h.as_dict()
    return np.array([*(d[c] for c in COLUMNS[:14]), *h.v], dtype=float)


def _cold(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float,
          opts: ContinuationOptions) -> tuple[Helix | None, str]:
    rp, m = sweep_controls(parameter, x, r_p, m0)
    try:
        return helix_trim(veh, rp, m, continuation_steps=opts.continuation_steps, n_random=opts.n_random,
                          seed=opts.seed), ""
    except InfeasibleGlideError as exc:
        return None, str(exc)


def _warm(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float,
          prev: np.ndarray, opts: ContinuationOptions) -> Helix | None:
    """Newton from ``prev`` (the warm start of ``helix_trim(..., guess=prev)``); the Helix is then built by
    ``helix_trim`` from the converged root (one more Newton step), so its quantities are computed in one place."""
    rp, m = sweep_controls(parameter, x, r_p, m0)
    if m == 0:
        return None
    y, _, ok = helix_newton(FixedMassGlider3D(veh, rp, m), np.asarray(prev, float))
    if not ok:
        return None
    h = helix_trim(veh, rp, m, guess=y, n_random=0)
    return h if float(np.max(np.abs(h.unknowns - y))) <= AGREE_TOL else None


def _found(h: Helix, how: str, note: str) -> ContinuationPoint:
    return ContinuationPoint(True, h.unknowns.astype(float), _row(h), how, note)


def _missing(note: str) -> ContinuationPoint:
    return ContinuationPoint(False, _NAN_Y.copy(), _NAN_ROW.copy(), "none", note)


def _cold_point(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float,
                opts: ContinuationOptions, note_ok: str) -> ContinuationPoint:
    h, msg = _cold(veh, parameter, x, r_p, m0, opts)
    if h is None:
        return _missing(f"cold start failed: {msg}")
    return _found(h, "cold", note_ok)


def _up_step(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float,
             opts: ContinuationOptions, prev: tuple[np.ndarray, float] | None, cold_known: ContinuationPoint | None
             ) -> tuple[ContinuationPoint, ContinuationPoint | None]:
    """One step of the serial upward walk: warm start from ``prev = (unknowns, value)``, else a cold solve
    (``cold_known``: a cold solve already made at this point, reused because cold solves are deterministic).

    Returns the point and the cold solve made or reused (None when the warm start succeeded)."""
    src = ""
    if prev is not None:
        src = f"{parameter} = {_fmt(prev[1])}"
        h = _warm(veh, parameter, x, r_p, m0, prev[0], opts)
        if h is not None:
            return _found(h, "warm", f"continued from {src}"), None
    cp = cold_known if cold_known is not None else _cold_point(veh, parameter, x, r_p, m0, opts, "cold start")
    if prev is None:
        return cp, cp
    if cp.exists:
        return cp._replace(how="cold (warm failed)", note=f"cold start (warm start from {src} failed)"), cp
    return cp._replace(note=f"no motion found: warm start from {src} failed; {cp.note}"), cp


def _down_walk(veh: Vehicle, parameter: str, values: Sequence[float], r_p: tuple[float, float, float], m0: float,
               opts: ContinuationOptions, prev: tuple[np.ndarray, float], failed: Sequence[ContinuationPoint]
               ) -> list[ContinuationPoint]:
    """Serial downward walk below the seed: ``values`` and ``failed`` (their failed cold solves) in walking order;
    warm starts only."""
    out = []
    for x, cp in zip(values, failed, strict=True):
        h = _warm(veh, parameter, x, r_p, m0, prev[0], opts)
        src = f"{parameter} = {_fmt(prev[1])}"
        if h is None:
            out.append(cp._replace(note=f"no motion found: {cp.note}; warm start from {src} failed"))
        else:
            out.append(_found(h, "warm", f"continued from {src} (walking down from the seed; cold start failed here)"))
            prev = (out[-1].unknowns, float(x))
    return out


def walk_chunk(veh: Vehicle, parameter: str, values: Sequence[float], r_p: tuple[float, float, float], m0: float,
               opts: ContinuationOptions, continuation: bool
               ) -> tuple[list[ContinuationPoint], int | None, dict[int, ContinuationPoint]]:
    """Walk one contiguous chunk of values (module level so that executors can pickle it).

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider.
    parameter : str
        Swept parameter (:data:`PARAMETERS`).
    values : sequence of float
        The chunk's values, in walking order.
    r_p, m0
        Controls held fixed (m, kg).
    opts : ContinuationOptions
        Cold-solve settings.
    continuation : bool
        Warm-start from the previous solution (True) or cold-solve every point.

    Returns
    -------
    tuple
        The points, the seed index (first point where the cold solve succeeded; None if none did) and every cold
        solve made, by index (reused by the parent's reconciliation).

    Raises
    ------
    ArgumentError
        If a point's controls are implausible (from the model; :func:`check_sweep_inputs` checks them first).
    ModelError
        If a point's ``m0`` makes a mass non-positive (idem). A point without a steady motion is recorded, not
        raised.
    """
    vals = [float(v) for v in values]
    n = len(vals)
    if not continuation:
        pts = [_cold_point(veh, parameter, x, r_p, m0, opts, "cold start") for x in vals]
        return pts, next((i for i, p in enumerate(pts) if p.exists), None), dict(enumerate(pts))
    pts = []
    cold: dict[int, ContinuationPoint] = {}
    seed = None
    for i, x in enumerate(vals):  # seed search
        p = _cold_point(veh, parameter, x, r_p, m0, opts, "cold start")
        cold[i] = p
        pts.append(p._replace(note="cold start (seed of the walk)") if p.exists else p)
        if p.exists:
            seed = i
            break
    if seed is None:
        return pts, None, cold
    prev = (pts[seed].unknowns, vals[seed])
    for i in range(seed + 1, n):
        p, cp = _up_step(veh, parameter, vals[i], r_p, m0, opts, prev, None)
        pts.append(p)
        if cp is not None:
            cold[i] = cp
        if p.exists:
            prev = (p.unknowns, vals[i])
    if seed > 0:
        pts[:seed] = _down_walk(veh, parameter, vals[seed - 1::-1], r_p, m0, opts, (pts[seed].unknowns, vals[seed]),
                                pts[seed - 1::-1])[::-1]
    return pts, seed, cold


def _agree(a: ContinuationPoint, b: ContinuationPoint) -> bool:
    return a.exists and b.exists and float(np.max(np.abs(a.unknowns - b.unknowns))) <= AGREE_TOL


def reconcile_chunks(veh: Vehicle, parameter: str, values: np.ndarray, r_p: tuple[float, float, float], m0: float,
                     opts: ContinuationOptions, continuation: bool, bounds: list[tuple[int, int]],
                     results: list[tuple[list[ContinuationPoint], int | None, dict[int, ContinuationPoint]]]
                     ) -> tuple[list[ContinuationPoint], list[str]]:
    """Assemble independently walked chunks into the serial walk (module docstring).

    Parameters
    ----------
    veh, parameter, values, r_p, m0, opts, continuation
        As given to :func:`walk_chunk` (``values`` all of the sweep's values).
    bounds : list of (int, int)
        The chunks' index ranges (:func:`chunk_bounds`).
    results : list
        :func:`walk_chunk`'s results, one per chunk.

    Returns
    -------
    tuple
        The points of the serial walk and a log of the reconciliation.

    Raises
    ------
    ArgumentError
        As in :func:`walk_chunk`, for the serial steps repeated here.
    ModelError
        As in :func:`walk_chunk`.
    """
    if not continuation:
        return [p for pts, _, _ in results for p in pts], []
    n = values.size
    out: list[ContinuationPoint] = [_missing("")] * n
    log: list[str] = []
    prev: tuple[np.ndarray, float] | None = None  # last solution of the serial upward walk
    seeded = False
    for k, ((a, b), (pts, seed, cold)) in enumerate(zip(bounds, results, strict=True)):
        if not seeded:
            # the serial walk is still searching for its seed: it makes the same cold solves as this chunk
            out[a:b] = pts
            if seed is None:
                continue
            seeded = True
            if a > 0:  # the serial downward walk continues into the earlier chunks (whose cold solves all failed)
                low = next(i for i in range(a, a + seed + 1) if out[i].exists)
                out[:a] = _down_walk(veh, parameter, values[a - 1::-1], r_p, m0, opts,
                                     (out[low].unknowns, float(values[low])), out[a - 1::-1])[::-1]
                log.append(f"chunk {k}: first seed; serial downward walk repeated over indices 0..{a - 1}")
        else:
            j = a
            while j < b:
                p, _ = _up_step(veh, parameter, float(values[j]), r_p, m0, opts, prev, cold.get(j - a))
                out[j] = p
                if seed is not None and j - a >= seed and _agree(p, pts[j - a]):
                    out[j + 1:b] = pts[j - a + 1:]
                    if j > a:
                        log.append(f"chunk {k}: re-walked indices {a}..{j - 1} serially, then agreed at index {j}")
                    break
                if p.exists:
                    prev = (p.unknowns, float(values[j]))
                j += 1
            else:
                log.append(f"chunk {k}: never agreed with the serial walk; re-walked all of it serially")
        last = next((i for i in range(b - 1, -1, -1) if out[i].exists), None)
        if last is not None:
            prev = (out[last].unknowns, float(values[last]))
    return out, log


def readonly_array(a: np.ndarray) -> np.ndarray:
    """A read-only copy of ``a`` (results are frozen).

    Parameters
    ----------
    a : array_like
        Anything :func:`numpy.array` accepts.

    Returns
    -------
    ndarray
        A copy with ``writeable = False``.

    Raises
    ------
    ValueError
        If ``a`` does not convert to an array (numpy's own error).
    """
    a = np.array(a)
    a.setflags(write=False)
    return a


def check_options(continuation_steps: Any, n_random: Any, seed: Any) -> ContinuationOptions:
    """Validated cold-solve settings: ``continuation_steps`` in ``[1, MAX_CONTINUATION_STEPS]``, ``n_random`` in
    ``[0, MAX_RANDOM_STARTS]``, ``seed`` an integer ``>= 0``.

    Parameters
    ----------
    continuation_steps, n_random, seed : int
        As in :func:`glidectl.trim.helix.helix_trim`.

    Returns
    -------
    ContinuationOptions

    Raises
    ------
    ArgumentTypeError
        If a value is not an integer.
    ArgumentError
        If a value is outside its range.
    """
    return ContinuationOptions(checks.integer("continuation_steps", continuation_steps, lo=1,
                                              hi=MAX_CONTINUATION_STEPS),
                               checks.integer("n_random", n_random, lo=0, hi=MAX_RANDOM_STARTS),
                               checks.integer("seed", seed, lo=0))


def check_solve_budget(what: str, solves: int) -> None:
    """Refuse a sweep or scan that plans more than :data:`MAX_NEWTON_SOLVES` Newton solves (worst case).

    Parameters
    ----------
    what : str
        The computation, for the message.
    solves : int
        Worst-case number of Newton solves it would make.

    Raises
    ------
    BudgetError
        If ``solves > MAX_NEWTON_SOLVES``.
    """
    if solves > MAX_NEWTON_SOLVES:
        raise BudgetError(f"{what} would make up to {solves:,} Newton solves, above the limit of "
                          f"{MAX_NEWTON_SOLVES:,}; use fewer values, random starts (n_random, n_starts) or "
                          "continuation steps")


def check_sweep_inputs(veh: Vehicle, parameter: str, values: Any, r_p: Any, m0: Any
                       ) -> tuple[np.ndarray, tuple[float, float, float], float]:
    """Validate a sweep request; returns the values as an array, ``r_P`` as three floats (m) and ``m0`` (kg).

    ``r_p`` and ``m0`` default to the vehicle's nominal ``(r_P1, r_P2, r_P3)`` and ``m0``. The swept points'
    controls are checked by building the models (:class:`~glidectl.models.glider3d.FixedMassGlider3D`) at the
    smallest and largest value: the moving mass within ``R_P_MAX`` of the centre and positive masses then hold at
    every point (masses are affine in ``m0``, ``|r_P|`` convex in a swept component).

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider.
    parameter : str
        A key of :data:`PARAMETERS`.
    values : array_like
        Non-empty 1-D sequence of finite values of ``parameter`` (m or kg).
    r_p : array_like of 3 floats or None
        Fixed moving-mass position (m).
    m0 : float or None
        Fixed buoyancy (kg).

    Returns
    -------
    tuple
        ``(values, r_p, m0)``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, or ``values``, ``r_p``, ``m0`` are not real numbers.
    ArgumentError
        Unknown parameter, empty, multi-dimensional or non-finite values, ``r_p`` not three finite numbers, ``m0``
        not finite, or a point whose moving mass is farther than ``R_P_MAX`` from the centre.
    ModelError
        A vehicle that is not an underwater glider or lacks the 3D parameters, or a point whose ``m0`` makes a mass
        non-positive (or the mass matrix singular).
    """
    checks.vehicle("veh", veh, "underwater_glider")
    checks.choice("parameter", parameter, PARAMETERS)
    vals = checks.array(f"values of {parameter}" if isinstance(parameter, str) else "values", values, ndim=1,
                        min_size=1)
    FixedMassGlider3D(veh, (0.0, 0.0, 0.0), 1.0)  # raises ModelError for a vehicle without the 3D parameters
    r_p = (veh.r_P1, veh.r_P2, veh.r_P3) if r_p is None else r_p  # ModelError naming the key if not in the file
    m0 = veh.m0 if m0 is None else m0
    r = checks.array("r_p (m)", r_p, shape=(3,))
    m = checks.real("m0", m0, unit="kg")
    rp = (float(r[0]), float(r[1]), float(r[2]))
    # every point is a valid model: the masses are affine in m0 and |r_P| is convex in a swept component, so the
    # extreme values decide (two models, whatever the number of values)
    for x in {float(np.min(vals)), float(np.max(vals))}:
        FixedMassGlider3D(veh, *sweep_controls(parameter, x, rp, m))
    return vals, rp, m


def check_executor(executor: Any) -> Any:
    """``executor`` if it is None or has ``submit`` (a ``concurrent.futures.Executor``, a dask client's
    ``get_executor()``).

    Raises
    ------
    ArgumentTypeError
        If it has no ``submit``.
    """
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise ArgumentTypeError(f"executor must be a concurrent.futures.Executor (with submit), e.g. "
                                f"ProcessPoolExecutor(2) or a dask Client's get_executor(), got "
                                f"{type(executor).__name__}")
    return executor


def run_chunks(fn: Callable[..., Any], args: list[tuple[Any, ...]], executor: Any) -> list[Any]:
    """``[fn(*a) for a in args]``, in this process or as futures of ``executor`` (results in the order of ``args``).

    Parameters
    ----------
    fn : callable
        A module-level function (a process pool pickles it).
    args : list of tuple
        One argument tuple per call.
    executor : concurrent.futures.Executor, optional
        ``ProcessPoolExecutor(k)``, ``dask.distributed.Client(...).get_executor()``, ...; None: in this process.

    Returns
    -------
    list

    Raises
    ------
    ArgumentTypeError
        If ``executor`` has no ``submit``.
    """
    if check_executor(executor) is None:
        return [fn(*a) for a in args]
    futures = [executor.submit(fn, *a) for a in args]
    return [f.result() for f in futures]


def chunk_bounds(n: int, chunks: int) -> list[tuple[int, int]]:
    """Index ranges ``[(a, b), ...]`` of ``chunks`` contiguous, nearly equal, non-empty pieces of ``range(n)``.

    Parameters
    ----------
    n : int
        Number of items, ``>= 0``.
    chunks : int
        Number of pieces, ``>= 1``.

    Returns
    -------
    list of (int, int)
        Half-open index ranges (at most ``chunks`` of them, empty ones dropped).

    Raises
    ------
    ArgumentTypeError
        If ``n`` or ``chunks`` is not an integer.
    ArgumentError
        If ``n < 0`` or ``chunks < 1``.
    """
    n = checks.integer("n", n, lo=0)
    chunks = checks.integer("chunks", chunks, lo=1)
    edges = np.linspace(0, n, chunks + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in itertools.pairwise(edges) if b > a]
