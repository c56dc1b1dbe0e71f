"""Threads of the worker processes of a build: one pool of ``jobs`` processes shares the machine's cores.

numpy's OpenBLAS, CVXOPT's BLAS and Clarabel's supernodal solver (faer, on a rayon thread pool) each start one
thread per core in every process. On a pool of one worker per core that oversubscribes the machine, and the idle
threads spin: a Clarabel solve then costs about half again as much CPU as its wall time, for no gain (measured in
``bench/README.md``). :func:`worker_threads` gives the workers of a pool ``cores // jobs`` threads each (at least
one) by the environment variables these libraries read when they load, which spawned workers inherit. (The ROA
layer holds BLAS and Clarabel to one thread while it certifies, whatever these variables say: their thread counts
change its results; see ``glidectl.roa.blas_threads``.)
"""
from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Iterator

from .. import checks

__all__ = ["THREAD_VARIABLES", "worker_threads"]

THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "RAYON_NUM_THREADS")
"""The environment variables :func:`worker_threads` sets: OpenMP, OpenBLAS, MKL and rayon (Clarabel's faer)."""


@contextlib.contextmanager
def worker_threads(jobs: int, cores: int | None = None) -> Iterator[dict[str, str]]:
    """Within the block, processes started by this one use ``max(1, cores // jobs)`` threads per library.

    Parameters
    ----------
    jobs : int
        Worker processes of the pool started within the block (>= 1).
    cores : int, optional
        Cores of the machine (default ``os.cpu_count()``).

    Yields
    ------
    dict of str to str
        The variables of :data:`THREAD_VARIABLES` set for the block. A variable the environment already has (set by
        the user, or inherited from the build's own pool by a design that starts a pool for its parts) is left as
        it is. On leaving the block the environment is what it was.

    Notes
    -----
    The libraries read these variables when they are loaded, so they apply to workers that start a fresh
    interpreter (the ``spawn`` start method, the build's default), not to this process or forked workers. Blocks
    that overlap in several threads of one process share the values of the first: the variables stay set until the
    last of them ends.

    Raises
    ------
    ArgumentError
        If ``jobs`` or ``cores`` is not a positive integer.
    """
    jobs = checks.integer("jobs", jobs, lo=1)
    cores = checks.integer("cores", os.cpu_count() or 1 if cores is None else cores, lo=1)
    per = str(max(1, cores // jobs))
    with _STATE_LOCK:
        if _STATE["blocks"] == 0:
            _STATE["set"] = {k: per for k in THREAD_VARIABLES if k not in os.environ}
            os.environ.update(_STATE["set"])
        _STATE["blocks"] += 1
        new = dict(_STATE["set"])
    try:
        yield new
    finally:
        with _STATE_LOCK:
            _STATE["blocks"] -= 1
            if _STATE["blocks"] == 0:
                for k in _STATE["set"]:
                    os.environ.pop(k, None)
                _STATE["set"] = {}


# the blocks open in this process and the variables the first of them set (threads may overlap their blocks)
_STATE_LOCK = threading.Lock()
_STATE: dict = {"blocks": 0, "set": {}}
