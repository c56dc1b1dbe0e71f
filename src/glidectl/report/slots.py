"""Compute slots of a pool build: at most ``jobs`` processes of one ``glidectl report all --jobs N`` compute at once.

A pool build nests two pools: the designs run on worker processes, and a design's
:func:`~glidectl.report.map_parts` runs its parts on up to ``N`` more. Without a limit, ``N`` designs that all map
parts compute in ``N * N`` processes at once (each with ``cores // N`` threads: ``N`` times the machine's cores), and
a design that waits for another design's shared value (:func:`~glidectl.report.cached`) keeps its core idle.

The build's pool therefore shares one first-come-first-served semaphore of ``N`` slots (:class:`Slots`) with every
process it starts, directly or through a design's parts pool (a jobserver, as in GNU make):

- a design process holds a slot while it runs (:func:`holding`), and lends it (:func:`lent`) while it waits for its
  parts or for another process's lock on a shared value;
- a part holds a slot while it runs.

Processes that wait hold no slot, so the waits cannot exhaust the slots, and the number of processes that compute
at once never exceeds ``N``. The designs' pool has ``2 N`` workers, so a design that waits for its parts does not
hold back the next design. The slots are handed out in the order they were asked for (with a plain semaphore, a
part worker that gives its slot back and asks again for its next part won it again before the woken waiter ran, 18
of 20 tries). Processes are still started as before (a waiting part worker costs memory, not CPU).

What it changes (measured in ``bench/README.md``, report-all builds): the numbers stay the same to the last digit;
a build spends less CPU (single-threaded processes time-sliced on the same cores evict each other's caches), and a
design's own time now includes its waits for slots, which does not lengthen the build.

Outside a pool build (a serial build, one design, a dask cluster, a plain script) no semaphore is installed and
every function here does nothing: dask schedules its own workers' threads.
"""
from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from typing import Any

__all__ = ["Slots", "current", "holding", "install", "lent", "repay"]


class Slots:
    """A counting semaphore of ``n`` slots shared by processes, first come first served (a ticket queue).

    Ticket ``t`` (the ``t``-th request, from 0) is admitted once ``t < n + releases``: requests are served in the
    order they were made, whichever process gives a slot back. Picklable into the processes a pool starts (a
    ``multiprocessing`` condition and two shared counters), and usable from threads.

    Parameters
    ----------
    n : int
        Slots (>= 1).
    ctx : multiprocessing context
        The context of the processes that share it (its start method).
    """

    def __init__(self, n: int, ctx: Any) -> None:
        self.n = int(n)
        self._cond = ctx.Condition(ctx.Lock())
        self._issued = ctx.RawValue("q", 0)       # tickets handed out
        self._released = ctx.RawValue("q", 0)     # slots given back

    def acquire(self) -> None:
        """Take a slot, waiting for the requests made before this one to be served first."""
        with self._cond:
            ticket = self._issued.value
            self._issued.value = ticket + 1
            while ticket >= self.n + self._released.value:
                self._cond.wait()

    def release(self) -> None:
        """Give a slot back."""
        with self._cond:
            self._released.value += 1
            self._cond.notify_all()

    def _held(self) -> int:     # with self._cond held
        return min(self._issued.value, self.n + self._released.value) - self._released.value

    def held(self) -> int:
        """Slots held now: admitted tickets that were not given back."""
        with self._cond:
            return self._held()

    def repay(self) -> None:
        """Give back a slot that a dead process held, if any slot is held at all."""
        with self._cond:
            if self._held() > 0:
                self._released.value += 1
                self._cond.notify_all()


_SLOTS: Slots | None = None     # this process's handle on the build's slots (None: no limit)
_LOCAL = threading.local()      # .held: slots this thread holds (0 or 1; lent() gives one back for a while)


def install(slots: Slots | None) -> None:
    """Use ``slots`` (the build pool's :class:`Slots`, or None) in this process; the initializer of every worker the
    build starts.

    Parameters
    ----------
    slots : Slots or None
        The build's ``jobs`` slots; None removes the limit.

    Raises
    ------
    None
    """
    global _SLOTS
    _SLOTS = slots


def current() -> Slots | None:
    """The slots this process uses, to pass on to the workers it starts (None: no limit).

    Returns
    -------
    Slots or None

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
    build's other processes do not wait for it forever. Nothing happens when no slot is held; if the worker died
    before it took a slot, the rest of the build may compute in one process more than ``jobs`` (never a hang).

    Raises
    ------
    None
    """
    slots = _SLOTS
    if slots is None:
        return
    slots.repay()
