"""Compute slots of a pool build: at most ``jobs`` processes of one ``glidectl report all --jobs N`` compute at once.

A pool build nests two pools: the designs run on ``N`` worker processes, and a design's
:func:`~glidectl.report.map_parts` runs its parts on up to ``N`` more. Without a limit, ``N`` designs that all map
parts compute in ``N * N`` processes at once (each with ``cores // N`` threads: ``N`` times the machine's cores), and
a design that waits for another design's shared value (:func:`~glidectl.report.cached`) keeps its core idle.

The build's pool therefore shares one semaphore of ``N`` slots with every process it starts, directly or through a
design's parts pool (a jobserver, as in GNU make):

- a design process holds a slot while it runs (:func:`holding`), and lends it (:func:`lent`) while it waits for its
  parts or for another process's lock on a shared value;
- a part holds a slot while it runs.

Processes that wait hold no slot, so the waits cannot exhaust the slots, and the number of processes that compute
at once never exceeds ``N``. Processes are still started as before (a waiting part worker costs memory, not CPU).
Outside a pool build (a serial build, one design, a dask cluster, a plain script) no semaphore is installed and
every function here does nothing: dask schedules its own workers' threads.
"""
from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from typing import Any

__all__ = ["current", "holding", "install", "lent", "repay"]

_SLOTS: Any = None              # this process's share of the build's semaphore (None: no limit)
_LOCAL = threading.local()      # .held: slots this thread holds (0 or 1; lent() gives one back for a while)


def install(slots: Any) -> None:
    """Use ``slots`` (a ``multiprocessing`` semaphore of the build's pool, or None) in this process; the initializer
    of every worker the build starts.

    Parameters
    ----------
    slots : multiprocessing.synchronize.Semaphore or None
        The build's semaphore of ``jobs`` slots; None removes the limit.

    Raises
    ------
    None
    """
    global _SLOTS
    _SLOTS = slots


def current() -> Any:
    """The semaphore this process uses, to pass on to the workers it starts (None: no limit).

    Returns
    -------
    multiprocessing.synchronize.Semaphore or None

    Raises
    ------
    None
    """
    return _SLOTS


def _held() -> int:
    return int(getattr(_LOCAL, "held", 0))


@contextlib.contextmanager
def holding() -> Iterator[None]:
    """Hold one slot within the block (waiting for a free one first); nothing when no semaphore is installed or this
    thread already holds one.

    Raises
    ------
    None
    """
    slots = _SLOTS
    if slots is None or _held():
        yield
        return
    slots.acquire()
    _LOCAL.held = 1
    try:
        yield
    finally:
        _LOCAL.held = 0
        slots.release()


@contextlib.contextmanager
def lent() -> Iterator[None]:
    """Give this thread's slot back within the block (it waits for parts or for a lock) and take one again after;
    nothing when it holds none.

    Raises
    ------
    None
    """
    slots = _SLOTS
    if slots is None or not _held():
        yield
        return
    _LOCAL.held = 0
    slots.release()
    try:
        yield
    finally:
        slots.acquire()
        _LOCAL.held = 1


def repay() -> None:
    """Give back the slot of a worker that died while it held one (its pool is broken: a killed part), so that the
    build's other processes do not wait for it forever. A semaphore that is already full is left as it is; if the
    worker died before it took a slot, the rest of the build may compute in one process more than ``jobs`` (never
    a hang).

    Raises
    ------
    None
    """
    slots = _SLOTS
    if slots is None:
        return
    with contextlib.suppress(ValueError):       # a BoundedSemaphore refuses a release beyond its size
        slots.release()
