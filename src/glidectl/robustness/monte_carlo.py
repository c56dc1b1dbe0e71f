"""Monte Carlo of any study over the uncertain coefficients of a vehicle: :func:`monte_carlo`, :class:`MonteCarlo`.

A *study* is a function of a vehicle that returns numbers: a mapping ``{name: number}``, a result with
``as_dict()``, or one number (named ``"value"``). :func:`monte_carlo` draws ``n`` vehicles from the vehicle's
``[uncertainty]`` table (:meth:`glidectl.Vehicle.sample`), runs the study on each (in this process, or in chunks on
a ``concurrent.futures`` executor or a dask cluster's executor) and tabulates the sampled coefficients with the
study's numbers. A sample the vehicle file's validation refuses, or on which the study raises a
:class:`~glidectl.errors.GlidectlError` (an infeasible glide, a failed solve), is a counted failure with its reason,
never the end of the run. The draws are made here, before anything is distributed, so the table is the same for a
seed whatever the executor and the number of chunks.
"""

from __future__ import annotations

import math
import numbers
import os
from collections import Counter
from collections.abc import Callable, Mapping
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..analysis.continuation import chunk_bounds, run_chunks
from ..errors import ArgumentError, ArgumentTypeError, GlidectlError
from ..params import Vehicle, VehicleSample

__all__ = ["MonteCarlo", "monte_carlo", "study_numbers"]


def study_numbers(out: Any) -> dict[str, float]:
    """The numbers of a study's return value: a mapping, a result's ``as_dict()`` or one number (``"value"``);
    entries that are not real numbers (text, arrays) are left out, booleans become 0/1.

    Raises
    ------
    ArgumentTypeError
        If the value is none of these, or has no number at all.
    """
    if hasattr(out, "as_dict") and callable(out.as_dict):
        out = out.as_dict()
    if isinstance(out, numbers.Real):
        return {"value": float(out)}
    if not isinstance(out, Mapping):
        raise ArgumentTypeError(f"a study must return numbers (a mapping, a result with as_dict() or one number), "
                                f"got {type(out).__name__}")
    nums = {str(k): float(v) for k, v in out.items() if isinstance(v, numbers.Real)}
    if not nums:
        raise ArgumentTypeError(f"the study returned no number (keys {sorted(map(str, out))})")
    return nums


def _run(study: Callable[[Vehicle], Any], vehicles: list[Vehicle | None]) -> list[tuple[dict[str, float] | None,
                                                                                      str | None]]:
    """The study on each vehicle: its numbers, or None and the reason of a GlidectlError (None: invalid sample).
    A study with ``batch`` runs the valid vehicles in one call."""
    out: list[tuple[dict[str, float] | None, str | None]] = []
    batch = getattr(study, "batch", None)
    if callable(batch):
        valid = [v for v in vehicles if v is not None]
        values = list(batch(valid)) if valid else []
        if len(values) != len(valid):
            raise ArgumentTypeError(f"the study's batch(vehicles) returned {len(values)} results for {len(valid)} "
                                    "vehicles; it must return one per vehicle")
        got = iter(values)
        for veh in vehicles:
            value = None if veh is None else next(got)
            if isinstance(value, GlidectlError):
                out.append((None, f"{type(value).__name__}: {value}"))
            else:
                out.append((None, None) if veh is None else (study_numbers(value), None))
        return out
    for veh in vehicles:
        if veh is None:
            out.append((None, None))
            continue
        try:
            value = study(veh)
        except GlidectlError as exc:
            out.append((None, f"{type(exc).__name__}: {exc}"))
            continue
        out.append((study_numbers(value), None))       # a study that returns no numbers is a mistake: raised
    return out


@dataclass(frozen=True)
class MonteCarlo:
    """A study over ``n`` vehicles drawn from a vehicle's ``[uncertainty]`` table (:func:`monte_carlo`).

    Attributes
    ----------
    keys : tuple of str
        The sampled coefficients (columns of :attr:`values`).
    values : ndarray, shape (n, len(keys))
        Their values per sample (the coefficients' units).
    names : tuple of str
        The study's numbers (columns of :attr:`results`), in the order first met.
    results : ndarray, shape (n, len(names))
        The study's numbers per sample, NaN where the sample failed (or the study did not return that number).
    ok : ndarray of bool, shape (n,)
        Samples whose study ran.
    errors : tuple of (str or None)
        Per sample: why it failed (the vehicle file's validation or the study's GlidectlError), None if it ran.
    study : str
        The study's name.
    seed : int
    executor : str
        ``"none"`` or the executor's type.
    vehicle : Vehicle
        The nominal vehicle.
    provenance : str
        The nominal vehicle's parameter hash.
    units : dict
        Unit of each of the study's numbers it names (its ``units`` attribute, when it has one).
    """

    keys: tuple[str, ...]
    values: np.ndarray = field(repr=False)
    names: tuple[str, ...]
    results: np.ndarray = field(repr=False)
    ok: np.ndarray = field(repr=False)
    errors: tuple[str | None, ...] = field(repr=False)
    study: str
    seed: int
    executor: str
    vehicle: Vehicle = field(repr=False)
    provenance: str
    units: dict[str, str] = field(default_factory=dict, repr=False)

    def unit(self, name: str) -> str:
        """The unit of a study's number or of a sampled coefficient ("" when unknown)."""
        if name in self.units:
            return self.units[name]
        return str(getattr(self.vehicle, "units", {}).get(name, ""))

    @property
    def n(self) -> int:
        """Number of samples drawn."""
        return int(self.values.shape[0])

    @property
    def table(self) -> np.ndarray:
        """One row per sample (structured array): ``sample``, ``ok``, the sampled coefficients and the study's
        numbers, by name (``mc.table["K_M"]``, ``mc.table[3]``)."""
        dt = [("sample", int), ("ok", bool)] + [(k, float) for k in self.keys] + [(m, float) for m in self.names
                                                                                   if m not in self.keys]
        t = np.zeros(self.n, dtype=dt)
        t["sample"], t["ok"] = np.arange(self.n), self.ok
        for j, k in enumerate(self.keys):
            t[k] = self.values[:, j]
        for j, m in enumerate(self.names):
            if m not in self.keys:
                t[m] = self.results[:, j]
        return t

    @property
    def failures(self) -> dict[str, int]:
        """Each failure reason with its count (most frequent first)."""
        return dict(Counter(e for e in self.errors if e is not None).most_common())

    def column(self, name: str) -> np.ndarray:
        """The study's number ``name`` (or a sampled coefficient) over the samples that ran.

        Raises
        ------
        ArgumentError
            If ``name`` is neither a result nor a sampled coefficient.
        """
        if name in self.names:
            return self.results[self.ok, self.names.index(name)]
        if name in self.keys:
            return self.values[self.ok, self.keys.index(name)]
        raise ArgumentError(f"unknown column {name!r}; the study's numbers are {list(self.names)}, the sampled "
                            f"coefficients {list(self.keys)}")

    def quantiles(self, name: str, q: Any = (0.05, 0.5, 0.95)) -> np.ndarray:
        """Quantiles ``q`` (in [0, 1]) of a number over the samples that ran (NaN where it was not returned are
        left out).

        Raises
        ------
        ArgumentError
            For an unknown ``name``, ``q`` outside [0, 1], or no sample with that number.
        """
        qq = checks.array("q", q, ndim=None)
        if np.any((qq < 0) | (qq > 1)):
            raise ArgumentError(f"quantiles must be in [0, 1], got {np.atleast_1d(qq).tolist()}")
        col = self.column(name)
        col = col[np.isfinite(col)]
        if col.size == 0:
            raise ArgumentError(f"no sample returned {name!r} (failures: {self.failures})")
        return np.quantile(col, qq)

    def influence(self, name: str) -> dict[str, float]:
        """Spearman rank correlation of ``name`` with each sampled coefficient over the samples that ran, largest
        magnitude first (the coefficients that drive it)."""
        y = self.column(name)
        good = np.isfinite(y)
        out = {}
        for j, k in enumerate(self.keys):
            x = self.values[self.ok, j][good]
            out[k] = _spearman(x, y[good])
        return dict(sorted(out.items(), key=lambda kv: -abs(kv[1]) if math.isfinite(kv[1]) else 0.0))

    def summary(self) -> str:
        """Counts and the 5/50/95 % quantiles of every number."""
        rows = [f"{self.study}: {int(self.ok.sum())} of {self.n} samples ran (seed {self.seed}, coefficients "
                f"{', '.join(self.keys)})"]
        for m in self.names:
            try:
                lo, med, hi = self.quantiles(m)
                rows.append(f"  {m}: median {med:.5g}, 5-95 % [{lo:.5g}, {hi:.5g}]")
            except ArgumentError:
                rows.append(f"  {m}: no sample")
        rows += [f"  failed x{c}: {why}" for why, c in self.failures.items()]
        return "\n".join(rows)

    def plot(self, names: Any = None, ax: Any = None) -> Any:
        """Per number: its histogram, and a scatter against its most influential coefficient
        (:func:`glidectl.plotting.plot_monte_carlo`). Returns the Axes grid (``(len(names), 2)``)."""
        from ..plotting import plot_monte_carlo

        return plot_monte_carlo(self, names, ax)


def _spearman(x: np.ndarray, y: np.ndarray) -> float:
    if x.size < 3 or np.ptp(x) == 0 or np.ptp(y) == 0:
        return float("nan")
    rx, ry = np.argsort(np.argsort(x)), np.argsort(np.argsort(y))
    return float(np.corrcoef(rx, ry)[0, 1])


def monte_carlo(study: Callable[[Vehicle], Any], veh: Vehicle | VehicleSample, n: int = 1000, seed: int = 0, *,
                executor: Executor | None = None, chunks: int | None = None) -> MonteCarlo:
    """Run ``study`` on ``n`` vehicles drawn from ``veh``'s ``[uncertainty]`` table.

    Parameters
    ----------
    study : callable
        ``study(vehicle)`` returning numbers (module docstring). With a process pool or dask, a module-level
        function or a picklable object (it is pickled); its ``name`` attribute, when it has one, names the study.
        A study that can run many vehicles at once has ``batch(vehicles)``, returning per vehicle its numbers or
        the :class:`~glidectl.errors.GlidectlError` that stopped it; each chunk is then one call.
    veh : Vehicle or VehicleSample
        A vehicle with an ``[uncertainty]`` table (:meth:`~glidectl.Vehicle.with_uncertainty` adds one), or an
        already drawn sample (:meth:`~glidectl.Vehicle.sample`, :meth:`~glidectl.Vehicle.vertices`; ``n`` and
        ``seed`` are then its own).
    n : int
        Samples (>= 1).
    seed : int
        Seed of the draws (>= 0): the same samples, hence the same table, whatever ``executor`` and ``chunks``.
    executor : concurrent.futures.Executor, optional
        Runs the chunks (``ProcessPoolExecutor(2)``, ``dask.distributed.Client(...).get_executor()``); None: here.
    chunks : int, optional
        Contiguous pieces of the samples, one task each; default 1 without an executor, else ``4 x cpu_count``
        (``cpu_count`` for a study with ``batch``: fewer, larger batches).

    Returns
    -------
    MonteCarlo

    Raises
    ------
    ArgumentTypeError
        If ``study`` is not callable, ``veh`` is neither a Vehicle nor a VehicleSample, a study returns something
        that is not numbers, or ``executor`` has no ``submit``.
    ArgumentError
        If ``n``, ``seed`` or ``chunks`` is out of range, or the vehicle has no ``[uncertainty]`` entry.
    """
    checks.function("study", study)
    if isinstance(veh, VehicleSample):
        sample = veh
    elif isinstance(veh, Vehicle):
        n = checks.integer("n", n, lo=1, hi=10**7)
        seed = checks.integer("seed", seed, lo=0)
        sample = veh.sample(n, seed)
    else:
        raise ArgumentTypeError(f"veh must be a Vehicle with an [uncertainty] table or a VehicleSample, got "
                                f"{type(veh).__name__}")
    vehicles = list(sample.vehicles)
    m = len(vehicles)
    if chunks is None:
        per_cpu = 1 if callable(getattr(study, "batch", None)) else 4
        chunks = 1 if executor is None else per_cpu * (os.cpu_count() or 1)
    chunks = checks.integer("chunks", chunks, lo=1)
    bounds = chunk_bounds(m, min(chunks, m))
    parts = run_chunks(_run, [(study, vehicles[a:b]) for a, b in bounds], executor)
    outs = [o for part in parts for o in part]
    names: list[str] = []
    for nums, _ in outs:
        for k in nums or {}:
            if k not in names:
                names.append(k)
    res = np.full((m, len(names)), np.nan)
    errors: list[str | None] = []
    for i, (nums, why) in enumerate(outs):
        for k, v in (nums or {}).items():
            res[i, names.index(k)] = v
        errors.append(why if nums is None and why is not None else sample.errors[i] if nums is None else None)
    ok = np.array([e is None for e in errors])
    res.setflags(write=False)
    ok.setflags(write=False)
    vals = np.array(sample.values, dtype=float)
    vals.setflags(write=False)
    ex = "none" if executor is None else type(executor).__module__ + "." + type(executor).__qualname__
    return MonteCarlo(tuple(sample.keys), vals, tuple(names), res, ok, tuple(errors),
                      str(getattr(study, "name", getattr(study, "__qualname__", type(study).__name__))),
                      int(sample.seed), ex, sample.vehicle,
                      sample.vehicle.provenance, dict(getattr(study, "units", {}) or {}))
