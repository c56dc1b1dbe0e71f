"""Maps of steady circular helices versus one control parameter, §8.2.2 (Fig 8.5-8.12), and the existence scan of
§8.2.2's claim about the sign of ``r_P1`` against the sign of ``m0``.

:func:`helix_sweep` solves the helix trim (:func:`glidectl.trim.helix.helix_trim`, equations (8.23)-(8.31)) at each
value of one control parameter (``r_P1``, ``r_P2``, ``r_P3`` in m or ``m0`` in kg) with the others held fixed, and
returns a frozen :class:`HelixSweep` with one row of helix quantities per value (NaN and ``exists = False`` where no
steady motion was found) and a note per point saying how it was found or why not.

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
independently by the module-level function :func:`_walk_chunk` (seeded by a cold solve at its first point; only the
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
import math
import os
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from ..errors import InfeasibleGlideError, ModelError
from ..models.glider3d import FixedMassGlider3D
from ..params import Vehicle
from ..trim.helix import Helix, _newton, helix_trim

__all__ = [
    "COLUMNS",
    "PARAMETERS",
    "ExistenceScan",
    "HelixSweep",
    "existence_scan",
    "helix_sweep",
    "straight_glides",
]

#: control parameters that can be swept: name -> (unit, index in r_P or None for m0)
PARAMETERS: dict[str, tuple[str, int | None]] = {"r_P1": ("m", 0), "r_P2": ("m", 1), "r_P3": ("m", 2),
                                                 "m0": ("kg", None)}
#: columns of :attr:`HelixSweep.data`, with units
COLUMNS: tuple[str, ...] = ("radius", "speed", "pitch", "period", "alpha", "beta", "theta", "phi", "gamma", "psidot",
                            "Omega_norm", "max_re_eig", "residual", "r_bh", "v1", "v2", "v3")
COLUMN_UNITS: dict[str, str] = {"radius": "m", "speed": "m/s", "pitch": "m", "period": "s", "alpha": "rad",
                                "beta": "rad", "theta": "rad", "phi": "rad", "gamma": "rad", "psidot": "rad/s",
                                "Omega_norm": "rad/s", "max_re_eig": "1/s", "residual": "m/s^2, rad/s^2",
                                "r_bh": "m", "v1": "m/s", "v2": "m/s", "v3": "m/s"}
AGREE_TOL = 1e-7  # max |difference of trim unknowns| for two solves to be the same motion (chunk reconciliation)
_NAN_ROW = np.full(len(COLUMNS), np.nan)
_NAN_Y = np.full(6, np.nan)


# ---------------------------------------------------------------------------------------------- plain records
class _Options(NamedTuple):
    """Cold-solve settings forwarded to :func:`helix_trim` (picklable)."""

    continuation_steps: int
    n_random: int
    seed: int


class _Point(NamedTuple):
    """One solved (or failed) point, plain data only so that it pickles cheaply."""

    exists: bool
    unknowns: np.ndarray  # (6,) trim unknowns, NaN when missing
    row: np.ndarray  # (len(COLUMNS),), NaN when missing
    how: str  # "cold", "warm", "cold (warm failed)" or "none"
    note: str


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _controls(parameter: str, x: float, r_p: tuple[float, float, float], m0: float
              ) -> tuple[tuple[float, float, float], float]:
    idx = PARAMETERS[parameter][1]
    if idx is None:
        return r_p, float(x)
    r = list(r_p)
    r[idx] = float(x)
    return (r[0], r[1], r[2]), m0


def _row(h: Helix) -> np.ndarray:
    d = h.as_dict()
    return np.array([*(d[c] for c in COLUMNS[:14]), *h.v], dtype=float)


def _cold(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float, opts: _Options
          ) -> tuple[Helix | None, str]:
    rp, m = _controls(parameter, x, r_p, m0)
    try:
        return helix_trim(veh, rp, m, continuation_steps=opts.continuation_steps, n_random=opts.n_random,
                          seed=opts.seed), ""
    except InfeasibleGlideError as exc:
        return None, str(exc)


def _warm(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float,
          prev: np.ndarray, opts: _Options) -> Helix | None:
    """Newton from ``prev`` (the warm start of ``helix_trim(..., guess=prev)``); the Helix is then built by
    ``helix_trim`` from the converged root (one more Newton step), so its quantities are computed in one place."""
    rp, m = _controls(parameter, x, r_p, m0)
    if m == 0:
        return None
    y, _, ok = _newton(FixedMassGlider3D(veh, rp, m), np.asarray(prev, float))
    if not ok:
        return None
    h = helix_trim(veh, rp, m, guess=y, n_random=0)
    return h if float(np.max(np.abs(h.unknowns - y))) <= AGREE_TOL else None


def _found(h: Helix, how: str, note: str) -> _Point:
    return _Point(True, h.unknowns.astype(float), _row(h), how, note)


def _missing(note: str) -> _Point:
    return _Point(False, _NAN_Y.copy(), _NAN_ROW.copy(), "none", note)


def _cold_point(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float,
                opts: _Options, note_ok: str) -> _Point:
    h, msg = _cold(veh, parameter, x, r_p, m0, opts)
    if h is None:
        return _missing(f"cold start failed: {msg}")
    return _found(h, "cold", note_ok)


def _up_step(veh: Vehicle, parameter: str, x: float, r_p: tuple[float, float, float], m0: float, opts: _Options,
             prev: tuple[np.ndarray, float] | None, cold_known: _Point | None) -> tuple[_Point, _Point | None]:
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
               opts: _Options, prev: tuple[np.ndarray, float], failed: Sequence[_Point]) -> list[_Point]:
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


def _walk_chunk(veh: Vehicle, parameter: str, values: Sequence[float], r_p: tuple[float, float, float], m0: float,
                opts: _Options, continuation: bool) -> tuple[list[_Point], int | None, dict[int, _Point]]:
    """Walk one contiguous chunk of values (module level so that executors can pickle it).

    Returns the points, the seed index (first point where the cold solve succeeded; None if none did) and every
    cold solve made, by index (reused by the parent's reconciliation).
    """
    vals = [float(v) for v in values]
    n = len(vals)
    if not continuation:
        pts = [_cold_point(veh, parameter, x, r_p, m0, opts, "cold start") for x in vals]
        return pts, next((i for i, p in enumerate(pts) if p.exists), None), dict(enumerate(pts))
    pts = []
    cold: dict[int, _Point] = {}
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


def _agree(a: _Point, b: _Point) -> bool:
    return a.exists and b.exists and float(np.max(np.abs(a.unknowns - b.unknowns))) <= AGREE_TOL


def _reconcile(veh: Vehicle, parameter: str, values: np.ndarray, r_p: tuple[float, float, float], m0: float,
               opts: _Options, continuation: bool, bounds: list[tuple[int, int]],
               results: list[tuple[list[_Point], int | None, dict[int, _Point]]]) -> tuple[list[_Point], list[str]]:
    """Assemble independently walked chunks into the serial walk (module docstring). Returns the points and a log."""
    if not continuation:
        return [p for pts, _, _ in results for p in pts], []
    n = values.size
    out: list[_Point] = [_missing("")] * n
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


# ---------------------------------------------------------------------------------------------- result
def _column_property(name: str) -> property:
    return property(lambda self: self.column(name), doc=f"``{name}`` column ({COLUMN_UNITS[name]}); NaN where no "
                                                        "motion was found.")


@dataclass(frozen=True, eq=False)
class HelixSweep:
    """Steady helices (or straight glides) along a sweep of one control parameter, §8.2.2 (Fig 8.5-8.12).

    Attributes
    ----------
    parameter : str
        ``"r_P1"``, ``"r_P2"``, ``"r_P3"`` (moving-mass position, m) or ``"m0"`` (buoyancy, kg); ``unit`` its unit.
    values : ndarray, shape (n,)
        Swept values, in the order walked.
    columns : tuple of str
        Names of the columns of ``data`` (:data:`COLUMNS`; units in :data:`COLUMN_UNITS`): helix radius, speed,
        pitch (drop per turn, positive down) and period (``inf`` for a straight glide), angle of attack, sideslip,
        pitch and roll angles, flight-path angle, yaw rate, ``|Omega|``, max real part of the eigenvalues of the
        8-state reduced linearization, trim residual, bottom-heaviness ``r_bh`` and the body velocity.
    data : ndarray, shape (n, len(columns))
        One row per value; NaN where no steady motion was found.
    exists : ndarray of bool, shape (n,)
    unknowns : ndarray, shape (n, 6)
        Trim unknowns ``(v1, v2, v3, psidot, theta, phi)`` (warm starts for :func:`helix_trim`); NaN where missing.
    how : tuple of str
        Per point: ``"cold"``, ``"warm"`` (continuation), ``"cold (warm failed)"`` or ``"none"``.
    notes : tuple of str
        Per point: how the motion was found, or why not (the solver's message).
    r_p : tuple of float
        Moving-mass position (m) held fixed (the swept component is the base value it replaces).
    m0 : float
        Buoyancy (kg) held fixed (unless swept).
    provenance : dict
        Vehicle name and provenance hash, solver settings, chunking and reconciliation log.

    All arrays are read-only.
    """

    parameter: str
    unit: str
    values: np.ndarray
    columns: tuple[str, ...]
    data: np.ndarray
    exists: np.ndarray
    unknowns: np.ndarray
    how: tuple[str, ...]
    notes: tuple[str, ...]
    r_p: tuple[float, float, float]
    m0: float
    provenance: dict[str, Any] = field(repr=False)

    radius = _column_property("radius")
    speed = _column_property("speed")
    pitch = _column_property("pitch")
    period = _column_property("period")
    alpha = _column_property("alpha")
    beta = _column_property("beta")
    theta = _column_property("theta")
    phi = _column_property("phi")
    gamma = _column_property("gamma")
    psidot = _column_property("psidot")
    Omega_norm = _column_property("Omega_norm")
    max_re_eig = _column_property("max_re_eig")
    residual = _column_property("residual")
    r_bh = _column_property("r_bh")

    def column(self, name: str) -> np.ndarray:
        """One column of :attr:`data` by name (read-only view)."""
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise ModelError(f"unknown column {name!r}; available: {', '.join(self.columns)}") from None

    @property
    def stable(self) -> np.ndarray:
        """Existing points whose reduced linearization has all eigenvalues in the open left half plane."""
        with np.errstate(invalid="ignore"):
            return self.exists & (np.nan_to_num(self.max_re_eig, nan=1.0) < 0)

    def controls(self, i: int) -> tuple[tuple[float, float, float], float]:
        """``(r_p (m), m0 (kg))`` at point ``i``."""
        return _controls(self.parameter, float(self.values[i]), self.r_p, self.m0)

    def records(self) -> list[dict[str, Any]]:
        """One dict per point: the swept value, ``exists``, every column, ``how`` and ``note``."""
        return [{self.parameter: float(x), "exists": bool(e), **dict(zip(self.columns, map(float, row), strict=True)),
                 "how": h, "note": t}
                for x, e, row, h, t in zip(self.values, self.exists, self.data, self.how, self.notes, strict=True)]

    @property
    def branch_jumps(self) -> np.ndarray:
        """Values (left end of the interval) where consecutive existing solutions jump: a step in the trim unknowns
        more than 10x the median of its ten neighbouring steps. The continuation then left its branch (a fold, or
        coexisting motions); empty for a smooth map."""
        idx = np.flatnonzero(self.exists)
        if idx.size < 3:
            return np.empty(0)
        y = self.unknowns[idx]
        d = np.linalg.norm(np.diff(y, axis=0), axis=1)
        loc = np.array([np.median(np.r_[d[max(i - 5, 0):i], d[i + 1:i + 6]]) for i in range(d.size)])
        return self.values[idx[:-1]][d > 10 * np.maximum(loc, 1e-12)]

    def plot(self, ax: Any = None, column: str = "radius", **kw: Any) -> Any:
        """Plot one column against the swept value; unstable points are marked with an ``x``. Returns the axes."""
        from ..report.figures import label, new_figure

        if ax is None:
            _, ax = new_figure()
        y = self.column(column)
        ax.plot(self.values, y, **kw)
        uns = self.exists & ~self.stable
        if np.any(uns):
            ax.plot(self.values[uns], y[uns], "x", color="C3", label="unstable")
        ax.set_xlabel(label(self.parameter, self.unit))
        ax.set_ylabel(f"{column} [{COLUMN_UNITS[column]}]")
        return ax


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a


def _check_inputs(veh: Vehicle, parameter: str, values: Any, r_p: Any, m0: Any
                  ) -> tuple[np.ndarray, tuple[float, float, float], float]:
    if parameter not in PARAMETERS:
        raise ModelError(f"unknown sweep parameter {parameter!r}; choose one of {', '.join(PARAMETERS)}")
    try:
        vals = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"values must be a 1-D sequence of numbers, got {values!r}") from None
    if vals.ndim != 1 or vals.size == 0:
        raise ModelError(f"values must be a non-empty 1-D sequence of {parameter} values "
                            f"({PARAMETERS[parameter][0]}), got shape {vals.shape}")
    if not np.all(np.isfinite(vals)):
        raise ModelError(f"values of {parameter} must be finite, got {vals[~np.isfinite(vals)][:3]}")
    FixedMassGlider3D(veh, (0.0, 0.0, 0.0), 1.0)  # raises ModelError for a vehicle without the 3D parameters
    r_p = (veh.r_P1, veh.r_P2, veh.r_P3) if r_p is None else r_p  # ModelError naming the key if not in the file
    m0 = veh.m0 if m0 is None else m0
    try:
        r = np.asarray(r_p, dtype=float)
        m = float(m0)
    except (TypeError, ValueError):
        raise ModelError(f"r_p must be three numbers (m) and m0 a number (kg), got {r_p!r}, {m0!r}") from None
    if r.shape != (3,) or not np.all(np.isfinite(r)) or not math.isfinite(m):
        raise ModelError(f"r_p must be three finite numbers (m) and m0 finite (kg), got {r_p!r}, {m0!r}")
    return vals, (float(r[0]), float(r[1]), float(r[2])), m


def _chunk_bounds(n: int, chunks: int) -> list[tuple[int, int]]:
    edges = np.linspace(0, n, chunks + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in itertools.pairwise(edges) if b > a]


def helix_sweep(veh: Vehicle, parameter: str, values: Sequence[float] | np.ndarray, *,
                r_p: Sequence[float] | None = None, m0: float | None = None, executor: Executor | None = None,
                chunks: int | None = None, continuation: bool = True, continuation_steps: int = 12,
                n_random: int = 40, seed: int = 0) -> HelixSweep:
    """Steady helices of ``veh`` along a sweep of one control parameter, §8.2.2 (maps of Fig 8.5-8.12).

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider (``slocum_ch8``).
    parameter : {"r_P1", "r_P2", "r_P3", "m0"}
        Swept control parameter: a component of the moving-mass position ``r_P`` (m, body frame) or the buoyancy
        ``m0`` (kg, positive = heavy).
    values : sequence of float
        Values of ``parameter`` (m or kg), walked in the order given (sorted order gives the smoothest
        continuation). Non-empty, finite.
    r_p : 3 floats, optional
        Moving-mass position (m) for the components not swept; default the vehicle's nominal ``(r_P1, r_P2, r_P3)``.
    m0 : float, optional
        Buoyancy (kg) when not swept; default the vehicle's nominal ``m0``.
    executor : concurrent.futures.Executor, optional
        Runs the chunks (``executor.submit``); e.g. ``ProcessPoolExecutor(4)`` or
        ``dask.distributed.Client(...).get_executor()``. ``None``: in this process.
    chunks : int, optional
        Number of contiguous chunks; default 1 without an executor, ``min(n, os.cpu_count())`` with one. The result
        does not depend on it (module docstring).
    continuation : bool
        Warm-start each point from the previous solution (True) or cold-solve every point independently (False).
    continuation_steps, n_random, seed
        Cold-solve settings of :func:`glidectl.trim.helix.helix_trim` (steps of the ``r_P2`` continuation from the
        longitudinal straight glide; number of random starts; their seed).

    Returns
    -------
    HelixSweep
        Frozen; ``exists`` is False (and the row NaN) where no steady motion was found, with the reason in
        ``notes``. No exception is raised for missing points.

    Raises
    ------
    ModelError
        Unknown parameter, empty or non-finite values, invalid ``r_p``/``m0``/``chunks``; ``ModelError`` for a
        vehicle without the 3D parameters.
    """
    vals, rp, m = _check_inputs(veh, parameter, values, r_p, m0)
    n = vals.size
    if chunks is None:
        chunks = 1 if executor is None else min(n, os.cpu_count() or 1)
    if isinstance(chunks, bool) or not isinstance(chunks, int | np.integer) or chunks < 1:
        raise ModelError(f"chunks must be a positive integer, got {chunks!r}")
    if continuation_steps < 1 or n_random < 0:
        raise ModelError(f"continuation_steps must be >= 1 and n_random >= 0, got {continuation_steps}, "
                            f"{n_random}")
    opts = _Options(int(continuation_steps), int(n_random), int(seed))
    bounds = _chunk_bounds(n, min(int(chunks), n))
    args = [(veh, parameter, [float(x) for x in vals[a:b]], rp, m, opts, bool(continuation)) for a, b in bounds]
    if executor is None:
        results = [_walk_chunk(*a) for a in args]
    else:
        futures = [executor.submit(_walk_chunk, *a) for a in args]
        results = [f.result() for f in futures]
    pts, log = _reconcile(veh, parameter, vals, rp, m, opts, bool(continuation), bounds, results)
    prov = {"vehicle": veh.name, "vehicle_provenance": veh.provenance, "parameter": parameter,
            "fixed_r_p": rp, "fixed_m0": m, "continuation": bool(continuation), "chunks": len(bounds),
            "chunk_bounds": bounds, "chunk_seeds": [s for _, s, _ in results],
            "executor": None if executor is None else type(executor).__module__ + "." + type(executor).__qualname__,
            "helix_trim": opts._asdict(), "reconciliation": log, "thesis": "Bhatta 2006 §8.2.2, Fig 8.5-8.12"}
    return HelixSweep(parameter, PARAMETERS[parameter][0], _readonly(vals), COLUMNS,
                      _readonly(np.array([p.row for p in pts])), _readonly(np.array([p.exists for p in pts])),
                      _readonly(np.array([p.unknowns for p in pts])), tuple(p.how for p in pts),
                      tuple(p.note for p in pts), rp, m, prov)


def straight_glides(veh: Vehicle, sweep: HelixSweep, *, xtol: float = 1e-10) -> tuple[Helix, ...]:
    """Steady straight glides on the branch of a sweep: the values where the yaw rate ``psidot`` changes sign
    between two neighbouring points found by continuation, refined by Brent's method on ``psidot`` (each trim
    warm-started from the left neighbour).

    There ``Omega = 0`` and the helix degenerates to a straight line (Theorem 7); with ``r_P2 != 0`` it is not in
    the longitudinal plane (``beta != 0``), as §8.2.2 says of Fig 8.9. Intervals across a branch jump
    (:attr:`HelixSweep.branch_jumps`) are skipped.

    Parameters
    ----------
    veh : Vehicle
        The vehicle the sweep was computed for.
    sweep : HelixSweep
    xtol : float
        Absolute tolerance on the swept value (m or kg).

    Returns
    -------
    tuple of Helix
        One per sign change, with ``psidot`` zero to the trim tolerance (``|psidot| < 1e-9`` rad/s).
    """
    from scipy.optimize import brentq

    jumps = set(np.round(sweep.branch_jumps, 12))
    out = []
    idx = np.flatnonzero(sweep.exists)
    for i, j in itertools.pairwise(idx):
        if j != i + 1 or round(float(sweep.values[i]), 12) in jumps:
            continue
        a, b = float(sweep.values[i]), float(sweep.values[j])
        if not sweep.psidot[i] * sweep.psidot[j] < 0:
            continue
        guess = sweep.unknowns[i]

        def trim(x: float, guess: np.ndarray = guess) -> Helix:
            r_p, m0 = _controls(sweep.parameter, x, sweep.r_p, sweep.m0)
            return helix_trim(veh, r_p, m0, guess=guess, n_random=0)

        x0 = brentq(lambda x: trim(x).psidot, a, b, xtol=xtol)
        out.append(trim(x0))
    return tuple(out)


# ---------------------------------------------------------------------------------------------- existence scan
_SOLUTION_KEYS = ("speed", "radius", "pitch", "period", "alpha", "beta", "theta", "phi", "gamma", "psidot",
                  "Omega_norm", "r_bh", "residual", "max_re_eig")


def _wrap_phi(y: np.ndarray) -> np.ndarray:
    y = np.array(y, dtype=float)
    y[5] = math.remainder(y[5], 2 * math.pi)
    return y


def _solution_record(h: Helix, found_by: str) -> dict[str, Any]:
    d = h.as_dict()
    rec: dict[str, Any] = {k: float(d[k]) for k in _SOLUTION_KEYS}
    rec["phi"] = math.remainder(rec["phi"], 2 * math.pi)
    rec.update(stable=h.stable, upright=abs(rec["phi"]) < math.pi / 2, found_by=found_by,
               unknowns=tuple(float(u) for u in _wrap_phi(h.unknowns)))
    return rec


def _add_solution(sols: list[dict[str, Any]], rec: dict[str, Any], tol: float) -> None:
    y = np.asarray(rec["unknowns"])
    for s in sols:
        if float(np.max(np.abs(np.asarray(s["unknowns"]) - y))) <= tol:
            if rec["found_by"] not in s["found_by"].split(", "):
                s["found_by"] += ", " + rec["found_by"]
            return
    sols.append(rec)


def _random_start(rng: np.random.Generator) -> np.ndarray:
    """A random trim start over a wide box: V in [0.05, 1.5] m/s, |alpha| < 1.2 rad, |beta| < 0.8 rad,
    |psidot| < 0.3 rad/s, |theta| < 1.5 rad, any roll (inverted flight included)."""
    V, a, b = rng.uniform(0.05, 1.5), rng.uniform(-1.2, 1.2), rng.uniform(-0.8, 0.8)
    return np.array([V * math.cos(a) * math.cos(b), V * math.sin(b), V * math.sin(a) * math.cos(b),
                     rng.uniform(-0.3, 0.3), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi)])


def _scan_point(veh: Vehicle, r_p: tuple[float, float, float], m0: float, n_starts: int, seed: int,
                opts: _Options, tol: float) -> list[dict[str, Any]]:
    """Every distinct steady motion found at one ``(r_P, m0)``: the cold solve of ``helix_trim`` and ``n_starts``
    Newton solves from random starts (module level, for executors)."""
    sols: list[dict[str, Any]] = []
    try:
        h = helix_trim(veh, r_p, m0, continuation_steps=opts.continuation_steps, n_random=opts.n_random,
                       seed=opts.seed)
        _add_solution(sols, _solution_record(h, "cold start"), tol)
    except InfeasibleGlideError:
        pass
    model = FixedMassGlider3D(veh, r_p, m0)
    rng = np.random.default_rng(seed)
    for _ in range(n_starts):
        y, _, ok = _newton(model, _random_start(rng))
        if not ok:
            continue
        y = _wrap_phi(y)
        if any(float(np.max(np.abs(np.asarray(s["unknowns"]) - y))) <= tol for s in sols):
            continue
        h = helix_trim(veh, r_p, m0, guess=y, n_random=0)
        if float(np.max(np.abs(_wrap_phi(h.unknowns) - y))) <= tol:
            _add_solution(sols, _solution_record(h, "multi-start"), tol)
    return sols


def _scan_row(veh: Vehicle, r_P1_values: list[float], r_p: tuple[float, float, float], m0: float, opts: _Options
              ) -> list[list[dict[str, Any]]]:
    """Continuation along ``r_P1`` at fixed ``m0``, walked upwards and downwards (module level, for executors)."""
    out: list[list[dict[str, Any]]] = [[] for _ in r_P1_values]
    for order in (1, -1):
        vals = r_P1_values[::order]
        sw = helix_sweep(veh, "r_P1", vals, r_p=r_p, m0=m0, continuation_steps=opts.continuation_steps,
                         n_random=opts.n_random, seed=opts.seed)
        for i in np.flatnonzero(sw.exists):
            rec: dict[str, Any] = {k: float(sw.column(k)[i]) for k in _SOLUTION_KEYS}
            rec["phi"] = math.remainder(rec["phi"], 2 * math.pi)
            rec.update(stable=bool(sw.stable[i]), upright=abs(rec["phi"]) < math.pi / 2,
                       found_by="continuation in r_P1", unknowns=tuple(float(u) for u in _wrap_phi(sw.unknowns[i])))
            out[i if order == 1 else len(vals) - 1 - i].append(rec)
    return out


@dataclass(frozen=True, eq=False)
class ExistenceScan:
    """Where steady motions exist on a grid of ``(m0, r_P1)`` at fixed ``r_P2``, ``r_P3`` (§8.2.2's claim).

    Attributes
    ----------
    r_P1 : ndarray, shape (n1,)
        Moving-mass positions along body-1 (m).
    m0 : ndarray, shape (n0,)
        Buoyancies (kg); grid arrays are indexed ``[i_m0, j_rP1]``.
    r_P2, r_P3 : float
        Fixed moving-mass components (m).
    solutions : tuple (n0) of tuple (n1) of tuple of dict
        Distinct steady motions found at each grid point (trim unknowns within ``tol``; roll wrapped to
        (-pi, pi]): the quantities of :meth:`Helix.as_dict` (SI, rad) plus ``stable``, ``upright``
        (``|phi| < pi/2``), ``found_by`` and ``unknowns``.
    n_solutions, n_stable, n_upright, n_stable_upright : ndarray of int, shape (n0, n1)
    provenance : dict
        Vehicle, methods and their settings.
    """

    r_P1: np.ndarray
    m0: np.ndarray
    r_P2: float
    r_P3: float
    solutions: tuple[tuple[tuple[dict[str, Any], ...], ...], ...] = field(repr=False)
    n_solutions: np.ndarray
    n_stable: np.ndarray
    n_upright: np.ndarray
    n_stable_upright: np.ndarray
    provenance: dict[str, Any] = field(repr=False)

    @property
    def exists(self) -> np.ndarray:
        """True where at least one steady motion was found."""
        return self.n_solutions > 0

    @property
    def claim_region(self) -> np.ndarray:
        """Grid points of §8.2.2's claim: ``m0 > 0`` with ``r_P1 < 0``, or ``m0 < 0`` with ``r_P1 > 0``."""
        m, r = self.m0[:, None], self.r_P1[None, :]
        return ((m > 0) & (r < 0)) | ((m < 0) & (r > 0))

    @property
    def claim_holds(self) -> bool:
        """True when no steady motion was found anywhere in :attr:`claim_region`."""
        return not bool(np.any(self.exists & self.claim_region))

    def counterexamples(self, *, stable_only: bool = False, upright_only: bool = False) -> list[dict[str, Any]]:
        """Motions found inside :attr:`claim_region`, each with its ``r_P1`` (m) and ``m0`` (kg)."""
        out = []
        for i, j in zip(*np.nonzero(self.claim_region), strict=True):
            for s in self.solutions[i][j]:
                if (stable_only and not s["stable"]) or (upright_only and not s["upright"]):
                    continue
                out.append({"r_P1": float(self.r_P1[j]), "m0": float(self.m0[i]), **s})
        return out

    def summary(self) -> str:
        """A few lines of text: counts inside and outside the claim region."""
        cr, ex = self.claim_region, self.exists
        lines = [f"existence scan: {self.m0.size} m0 x {self.r_P1.size} r_P1 points, r_P2 = {self.r_P2:g} m, "
                 f"r_P3 = {self.r_P3:g} m",
                 f"  outside the claim region: motions at {int(np.sum(ex & ~cr))} of {int(np.sum(~cr))} points",
                 f"  inside the claim region (m0 r_P1 < 0): motions at {int(np.sum(ex & cr))} of {int(np.sum(cr))} "
                 f"points; at {int(np.sum((self.n_stable_upright > 0) & cr))} of them a stable upright one",
                 f"  claim {'holds' if self.claim_holds else 'does not hold'} on this grid"]
        return "\n".join(lines)


def existence_scan(veh: Vehicle, r_P1_values: Sequence[float], m0_values: Sequence[float], *,
                   r_P2: float | None = None, r_P3: float | None = None, n_starts: int = 100, seed: int = 0,
                   continuation: bool = True, tol: float = 1e-6, executor: Executor | None = None,
                   continuation_steps: int = 12, n_random: int = 40) -> ExistenceScan:
    """Search hard for steady motions on a ``(m0, r_P1)`` grid to test §8.2.2's claim: "We could not find any
    equilibrium solutions for a combination of negative buoyancy (m0 > 0) and aft center of gravity (r_P1 < 0) or
    for a combination of positive buoyancy (m0 < 0) and fore center of gravity (r_P1 > 0)".

    At every grid point three searches run and their distinct solutions are merged: the cold solve of
    :func:`helix_trim` (straight longitudinal glide continued in ``r_P2``, then ``n_random`` random starts);
    ``n_starts`` Newton solves of (8.23) = 0 from random starts over a wide box (any roll angle, so inverted motions
    are found too); and, with ``continuation``, :func:`helix_sweep` along ``r_P1`` at each ``m0``, walked both ways.

    Parameters
    ----------
    veh : Vehicle
        3D underwater glider (``slocum_ch8``).
    r_P1_values : sequence of float
        Moving-mass positions along body-1 (m), preferably sorted (for the continuation).
    m0_values : sequence of float
        Buoyancies (kg); ``m0 = 0`` has no steady glide and is recorded as empty.
    r_P2, r_P3 : float, optional
        Fixed moving-mass components (m); default the vehicle's nominal values (2 cm, 4 cm for ``slocum_ch8``, those
        of Fig 8.5-8.6).
    n_starts : int
        Random Newton starts per grid point; ``seed`` seeds them (grid point ``k`` uses ``seed + k``).
    tol : float
        Two solutions are the same motion when their trim unknowns differ by at most ``tol``.
    executor : concurrent.futures.Executor, optional
        Runs the grid points and the continuation rows in parallel.

    Returns
    -------
    ExistenceScan
        With :attr:`ExistenceScan.claim_holds`, :meth:`ExistenceScan.counterexamples` and
        :meth:`ExistenceScan.summary`.
    """
    r1 = np.asarray(r_P1_values, dtype=float)
    m0s = np.asarray(m0_values, dtype=float)
    if r1.ndim != 1 or m0s.ndim != 1 or r1.size == 0 or m0s.size == 0:
        raise ModelError("r_P1_values and m0_values must be non-empty 1-D sequences (m, kg)")
    if not (np.all(np.isfinite(r1)) and np.all(np.isfinite(m0s))):
        raise ModelError("r_P1_values and m0_values must be finite")
    if n_starts < 0 or continuation_steps < 1 or n_random < 0 or not tol > 0:
        raise ModelError("n_starts and n_random must be >= 0, continuation_steps >= 1 and tol > 0")
    p2 = float(veh.r_P2 if r_P2 is None else r_P2)
    p3 = float(veh.r_P3 if r_P3 is None else r_P3)
    _check_inputs(veh, "r_P1", r1, (0.0, p2, p3), 1.0)
    opts = _Options(int(continuation_steps), int(n_random), int(seed))
    grid = [(i, j) for i in range(m0s.size) for j in range(r1.size)]
    point_args = [(veh, (float(r1[j]), p2, p3), float(m0s[i]), int(n_starts), int(seed) + k, opts, float(tol))
                  for k, (i, j) in enumerate(grid) if m0s[i] != 0]
    row_args = [(veh, [float(x) for x in r1], (0.0, p2, p3), float(m0s[i]), opts)
                for i in range(m0s.size) if continuation and m0s[i] != 0]
    if executor is None:
        point_res = [_scan_point(*a) for a in point_args]
        row_res = [_scan_row(*a) for a in row_args]
    else:
        pf = [executor.submit(_scan_point, *a) for a in point_args]
        rf = [executor.submit(_scan_row, *a) for a in row_args]
        point_res, row_res = [f.result() for f in pf], [f.result() for f in rf]
    sols: list[list[list[dict[str, Any]]]] = [[[] for _ in r1] for _ in m0s]
    it = iter(point_res)
    for i, j in grid:
        if m0s[i] != 0:
            sols[i][j] = next(it)
    rows = iter(row_res)
    for i in range(m0s.size):
        if continuation and m0s[i] != 0:
            for j, recs in enumerate(next(rows)):
                for rec in recs:
                    _add_solution(sols[i][j], rec, tol)

    def count(pred: Any) -> np.ndarray:
        return _readonly(np.array([[sum(1 for s in sols[i][j] if pred(s)) for j in range(r1.size)]
                                   for i in range(m0s.size)], dtype=int))

    frozen = tuple(tuple(tuple(s) for s in row) for row in sols)
    prov = {"vehicle": veh.name, "vehicle_provenance": veh.provenance, "n_starts": int(n_starts), "seed": int(seed),
            "continuation": bool(continuation), "tol": float(tol), "helix_trim": opts._asdict(),
            "random_box": _random_start.__doc__, "thesis": "Bhatta 2006 §8.2.2"}
    return ExistenceScan(_readonly(r1), _readonly(m0s), p2, p3, frozen, count(lambda s: True),
                         count(lambda s: s["stable"]), count(lambda s: s["upright"]),
                         count(lambda s: s["stable"] and s["upright"]), prov)
