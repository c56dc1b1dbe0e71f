"""Independent parts of one design, run on the build's workers: :func:`map_parts`.

A design whose study splits into independent computations (the certificates of several systems, the runs of
several controllers) writes them as ``map_parts(fn, items)``. Outside ``glidectl report`` (a plain ``design()`` call,
``python designs/NAME.py``) and in a build with ``--jobs 1`` this is ``[fn(x) for x in items]``. Inside a build with
``--jobs N`` (N > 1) the parts run on a spawned process pool of ``min(N, len(items))`` workers (in a build of
several designs, at most N of the designs and their parts compute at once: :mod:`glidectl.report.slots`); inside a
``--scheduler`` build, on the dask cluster (``distributed.worker_client``). Each part runs under its own recording,
so the data files a part reads (vehicle files) become dependencies of the design's cache entry and
:func:`~glidectl.report.cached` works inside parts, exactly as in a serial run; the results come back in the order of
``items``. So the three ways give the same results (tested in ``tests/test_report_parts.py``).

``fn`` must be a module-level function of the design file (or of an importable module) and ``items`` picklable: a
worker loads the design file the build is running (the same bytes), then calls ``fn(item)``. Items and results go
through ``cloudpickle``, so results may hold closures (certificates, models with lambdas), as with
:func:`~glidectl.report.cached`.
"""

from __future__ import annotations

import contextvars
import importlib
import multiprocessing
import pickle
import sys
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import cloudpickle

from ..errors import ArgumentError, ArgumentTypeError
from . import slots
from .cache import holds_lock, merge_run, recording
from .threads import worker_threads

__all__ = ["map_parts", "parts_context"]

T = TypeVar("T")
R = TypeVar("R")


@dataclass(frozen=True)
class _Context:
    """What a worker needs to run a part of the design being built."""

    name: str
    path: str
    source: bytes
    jobs: int
    cache_root: str | None
    refresh: bool
    dask: bool
    start_method: str
    build: str | None = None


_CONTEXT: contextvars.ContextVar[_Context | None] = contextvars.ContextVar("glidectl_report_parts", default=None)


@contextmanager
def parts_context(name: str, path: str, source: bytes, jobs: int, cache_root: str | None = None,
                  refresh: bool = False, dask: bool = False, start_method: str = "spawn",
                  build: str | None = None) -> Iterator[None]:
    """Let :func:`map_parts` calls inside the block use ``jobs`` workers (the build machinery sets this).

    Parameters
    ----------
    name, path, source : str, str, bytes
        The design being built: its name, file and file content (what a worker loads).
    jobs : int
        Worker processes the parts may use (1: serial).
    cache_root : str, optional
        The build's cache folder (for :func:`~glidectl.report.cached` inside parts).
    refresh : bool
        ``--no-cache``: parts compute cached values again.
    dask : bool
        The design runs on a dask worker: parts are submitted to the same cluster.
    start_method : str
        How the parts' pool starts its workers (``"spawn"``, safe everywhere; ``"fork"`` where available).
    build : str, optional
        Id of the build (parts reuse what other designs of the same build cached, as the design does).

    Yields
    ------
    None

    Raises
    ------
    ArgumentError
        If ``jobs`` is not a positive integer or ``start_method`` is not available here.
    """
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ArgumentError(f"jobs must be a positive integer (worker processes), got {jobs!r}")
    if start_method not in multiprocessing.get_all_start_methods():
        raise ArgumentError(f"start_method must be one of {multiprocessing.get_all_start_methods()}, got "
                            f"{start_method!r}")
    token = _CONTEXT.set(_Context(name, str(path), bytes(source), jobs, cache_root, bool(refresh), bool(dask),
                                  start_method, build))
    try:
        yield
    finally:
        _CONTEXT.reset(token)


def _resolve(module: str, qualname: str, ctx: tuple[str, str, bytes]) -> Callable[[Any], Any]:
    """The part function in a worker: from the design file being built, or from an importable module."""
    if module not in sys.modules:
        from .designs import load_design_source

        name, path, source = ctx
        design = load_design_source(name, path, source)
        if design.module.__name__ != module:
            importlib.import_module(module)
    obj: Any = sys.modules[module]
    for attr in qualname.split("."):
        obj = getattr(obj, attr)
    return obj


def _run_part(module: str, qualname: str, ctx: tuple[str, str, bytes], item: bytes, cache_root: str | None,
              refresh: bool, build: str | None = None, lock: bool = True) -> bytes:
    """Worker side of one part: load the design, call the function under a recording, return everything pickled.
    ``lock`` is False when the design started the parts inside a :func:`~glidectl.report.cached` computation that
    holds its key's lock (the parts then never wait for a lock: no cycle of waits)."""
    fn = _resolve(module, qualname, ctx)
    with slots.holding(), recording(None if cache_root is None else Path(cache_root), refresh, build, lock) as rec:
        value = fn(pickle.loads(item))
    return cloudpickle.dumps((value, sorted(rec.run.reads), rec.run.hits, rec.run.misses))


def _merge(blob: bytes) -> Any:
    value, reads, hits, misses = pickle.loads(blob)
    merge_run(reads, hits, misses)
    return value


def map_parts(fn: Callable[[T], R], items: Sequence[T]) -> list[R]:
    """``[fn(x) for x in items]``, run on the build's workers when ``glidectl report --jobs N`` gives more than one.

    Parameters
    ----------
    fn : callable
        A module-level function of one argument (defined in the design file or in an importable module; not a
        lambda or a nested function, which a worker cannot find).
    items : sequence
        The parts' arguments (picklable: numbers, tuples, the design's settings dataclass, vehicles, ...).

    Returns
    -------
    list
        ``fn(item)`` for every item, in order.

    Raises
    ------
    ArgumentTypeError
        If ``fn`` is not a module-level function or ``items`` is not a sequence.
    Exception
        The first exception a part raised, unchanged (as in a serial run).

    Examples
    --------
    >>> def _certify(case):                 # doctest: +SKIP
    ...     return gc.certify_roa(case.model(), degree=case.degree)
    >>> certs = map_parts(_certify, cases)  # doctest: +SKIP
    """
    if not callable(fn):
        raise ArgumentTypeError(f"fn must be a function of one argument, got {type(fn).__name__}")
    qualname = getattr(fn, "__qualname__", "")
    module = getattr(fn, "__module__", None)
    if not qualname or "<" in qualname or not module:
        raise ArgumentTypeError(f"fn must be a module-level function (a worker looks it up by name), got "
                                f"{qualname or type(fn).__name__!r}; define it with def at the top of the design")
    if not isinstance(items, Sequence) or isinstance(items, str | bytes):
        raise ArgumentTypeError(f"items must be a sequence (list or tuple), got {type(items).__name__}")
    ctx = _CONTEXT.get()
    if ctx is None or ctx.jobs <= 1 or len(items) <= 1:
        return [fn(x) for x in items]
    where = (ctx.name, ctx.path, ctx.source)
    lock = not holds_lock()
    args = [(module, qualname, where, cloudpickle.dumps(x), ctx.cache_root, ctx.refresh, ctx.build, lock)
            for x in items]
    if ctx.dask:
        from distributed import worker_client

        with worker_client() as client:
            futures = [client.submit(_run_part, *a, pure=False) for a in args]
            blobs = client.gather(futures)
    else:
        mp = multiprocessing.get_context(ctx.start_method)
        # the design's slot is lent until the pool is shut down: every part has finished then (a part that raised
        # leaves the others running to the end, and they need slots)
        with slots.lent(), worker_threads(ctx.jobs), ProcessPoolExecutor(
                max_workers=min(ctx.jobs, len(items)), mp_context=mp, initializer=slots.install,
                initargs=(slots.current(),)) as ex:
            try:
                blobs = list(ex.map(_run_part, *zip(*args, strict=True)))
            except BrokenProcessPool:
                slots.repay()       # a part's worker died, perhaps holding a slot: never leave the build waiting
                raise
    return [_merge(b) for b in blobs]
