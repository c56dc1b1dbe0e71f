"""BLAS threads while the ROA layer computes: one, so that a certificate does not depend on the machine.

numpy's and SciPy's OpenBLAS start one thread per core (or ``OPENBLAS_NUM_THREADS``), and with more than one some
of their routines add in another order. The SOS alternation carries that rounding along its path, so that the
certified volume of the same program changes with the thread count (in its second digit for the saturated user
glider's SOS certificate of designs/roa_certification.py; measurements: ``bench/README.md``). The certifying entry
points of :mod:`glidectl.roa` (:func:`~glidectl.roa.certify_roa`, :func:`~glidectl.certify_roa_lmi`,
:func:`~glidectl.roa.max_level`, the surrogate and sector systems, :meth:`~glidectl.roa.SOSProgram.resolve`)
therefore run with :data:`BLAS_THREADS` BLAS threads (``threadpoolctl``), and Clarabel with
:data:`glidectl.roa.sdp_solvers.CLARABEL_THREADS`. Together they make a certificate a function of its arguments:
the same on a laptop, in a ``glidectl report --jobs N`` build for any ``N`` and on a dask cluster.

On two cores a second BLAS thread saves no wall time on these programs and costs CPU time (``bench/README.md``).
On machines with many cores the largest programs may lose some speed: their dense Cholesky factorizations (the
Schur complements of the CTOL programs, of order a few thousand) run on one core. Set
``glidectl.roa.blas_threads.BLAS_THREADS = None`` to leave the libraries' thread counts alone (the results may then
differ in their last digits, or more, between machines).
"""
from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["BLAS_THREADS", "pinned_blas"]

BLAS_THREADS: int | None = 1
"""BLAS threads while a certifying function runs (None: the libraries' own count)."""

F = TypeVar("F", bound=Callable[..., Any])

_LOCK = threading.Lock()
_STATE: dict[str, Any] = {"depth": 0, "limiter": None}


def _enter() -> None:
    with _LOCK:
        if _STATE["depth"] == 0 and BLAS_THREADS is not None:
            from threadpoolctl import threadpool_limits

            _STATE["limiter"] = threadpool_limits(limits=BLAS_THREADS, user_api="blas")
        _STATE["depth"] += 1


def _leave() -> None:
    with _LOCK:
        _STATE["depth"] -= 1
        if _STATE["depth"] == 0 and _STATE["limiter"] is not None:
            _STATE["limiter"].restore_original_limits()
            _STATE["limiter"] = None


def pinned_blas(fn: F) -> F:
    """Decorator: ``fn`` runs with :data:`BLAS_THREADS` BLAS threads. The limit is set by the outermost call in
    the process and restored when the last one returns (nested calls and threads of one process share it).

    Parameters
    ----------
    fn : callable

    Returns
    -------
    callable
        ``fn`` with the limit around it.

    Raises
    ------
    Whatever ``fn`` raises.
    """
    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        _enter()
        try:
            return fn(*args, **kwargs)
        finally:
            _leave()
    return wrapper  # type: ignore[return-value]
