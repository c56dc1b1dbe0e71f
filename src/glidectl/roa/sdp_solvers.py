"""SDP solvers of the ROA programs: the accepted names, their options (Clarabel's thread count, the V step's
steering tolerances) and the silencing of cvxpy's inaccuracy warning. The default, ``CVXOPT_MOMENT``, is CVXOPT on
the moment form of a program (:mod:`glidectl.roa.moment`), for the programs :data:`~glidectl.roa.moment.MOMENT_POLICY`
gives it; Clarabel for the others.

Clarabel always runs with :data:`CLARABEL_THREADS` (one) thread, whatever the machine's cores or
``RAYON_NUM_THREADS`` (:func:`solver_options`): its parallel factorization would make a certificate depend on the
thread count.
"""
from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import cvxpy as cp

from .. import checks
from ..errors import ArgumentTypeError

__all__ = ["CLARABEL_THREADS", "DEFAULT_SOLVER", "INACCURATE_MESSAGE", "MOMENT", "SDP_SOLVERS", "STEERING_TOLERANCES",
           "check_solver", "inaccuracy_checked", "installed_sdp_solvers", "solver_argument", "solver_options",
           "steering_options"]

DEFAULT_SOLVER = "CVXOPT_MOMENT"
"""The default SDP solver of the ROA layer; programs it does not take go to Clarabel (module docstring). On the
programs it takes, the moment route is faster than Clarabel and certifies the same set or a larger one (the
chapter-5 glider, the CTOL closed loop). The centering feasibility programs go to Clarabel: solved on the moment
route for their largest common margin, they move the alternation onto another path that ends at a much smaller
set; the large programs centre by the capped level program instead
(:attr:`~glidectl.roa.moment.MomentPolicy.center_by_level_min_block`). Measurements: ``bench/README.md``."""

MOMENT = "CVXOPT_MOMENT"
"""Name of the moment-form CVXOPT route (:class:`~glidectl.roa.moment.CvxoptMoment`)."""

SDP_SOLVERS = ("CLARABEL", MOMENT, "SCS", "MOSEK", "CVXOPT", "COPT", "SDPA")
"""SDP solvers the ROA layer accepts (those installed: :func:`installed_sdp_solvers`)."""


def installed_sdp_solvers() -> list[str]:
    """The names of :data:`SDP_SOLVERS` that can run here (``CVXOPT_MOMENT`` needs the ``cvxopt`` package).

    Returns
    -------
    list of str
        Solver names, in the order of :data:`SDP_SOLVERS`.

    Raises
    ------
    None

    Examples
    --------
    >>> import glidectl as gc
    >>> "CLARABEL" in gc.installed_sdp_solvers()
    True
    """
    have = set(cp.installed_solvers())
    out = []
    for s in SDP_SOLVERS:
        if s == MOMENT:
            if "CVXOPT" in have and "CLARABEL" in have:
                out.append(s)
        elif s in have:
            out.append(s)
    return out


def check_solver(solver: Any) -> str:
    """Validate an SDP solver name.

    Parameters
    ----------
    solver : str
        One of :func:`installed_sdp_solvers`.

    Returns
    -------
    str
        The name.

    Raises
    ------
    ArgumentTypeError
        If ``solver`` is not a string.
    ArgumentError
        If it is not an installed SDP solver (the message lists those that are).
    """
    if not isinstance(solver, str):
        raise ArgumentTypeError(f"solver must be a solver name (str), got {type(solver).__name__} {solver!r}")
    return checks.choice("solver", solver, installed_sdp_solvers())


CLARABEL_THREADS = 1
"""Threads of Clarabel's factorization (its ``max_threads`` setting) in every program glidectl solves with it.
Clarabel's default is one thread per core (or ``RAYON_NUM_THREADS``), and its parallel factorization adds in an
order that depends on the thread count, which the SOS alternation carries along its path: with the default the
same certificate differs (in its certified area) between machines and between ``glidectl report all --jobs``
values. One thread makes a certificate a function of its program only (with one BLAS thread:
:mod:`glidectl.roa.blas_threads`). Measurements: ``bench/README.md``."""


def solver_options(solver: str) -> dict[str, Any]:
    """The options glidectl passes with ``solver`` to :meth:`cvxpy.Problem.solve`: Clarabel's thread count
    (:data:`CLARABEL_THREADS`) for ``"CLARABEL"``, nothing for the others (``CVXOPT_MOMENT`` passes it to the
    programs it hands to Clarabel).

    Parameters
    ----------
    solver : str
        A name of :data:`SDP_SOLVERS`.

    Returns
    -------
    dict
        Keyword arguments for :meth:`cvxpy.Problem.solve`.
    """
    return {"max_threads": CLARABEL_THREADS} if solver == "CLARABEL" else {}


STEERING_TOLERANCES = {"reltol": 1e-3, "feastol": 1e-5}
"""CVXOPT tolerances of the V step on the moment route (:func:`steering_options`): a relative gap of 1e-3 and
residuals of 1e-5, against CVXOPT's defaults 1e-6 and 1e-7. The V step only steers the alternation: the level
program that follows certifies whatever ``V`` it returns. Solved to the defaults, its moment form ends on the singular
part of the central path (the optimal face of the hinge objective is not a point): CVXOPT stops at a singular Schur
complement after a last step that raises the dual residual above what the route accepts in the original data, and
Clarabel solves the program again from scratch. At these tolerances the V step stops as ``optimal`` before that end,
in fewer iterations and a fraction of the time (measurements on the CTOL closed loop: ``bench/README.md``)."""


def steering_options(solver: str) -> dict[str, Any]:
    """Solver options of a program that only steers the search (the V step): :data:`STEERING_TOLERANCES` on the
    moment route (CVXOPT's option names), nothing for the other solvers (their defaults).

    Parameters
    ----------
    solver : str
        A name of :data:`SDP_SOLVERS`.

    Returns
    -------
    dict
        Keyword arguments for :meth:`~glidectl.roa.sos.SOSProgram.solve`.
    """
    return dict(STEERING_TOLERANCES) if solver == MOMENT else {}


INACCURATE_MESSAGE = "Solution may be inaccurate"
"""Start of the ``UserWarning`` cvxpy emits when a solver returns ``optimal_inaccurate`` (silenced by
:func:`inaccuracy_checked`)."""


@contextmanager
def inaccuracy_checked() -> Iterator[None]:
    """Silence cvxpy's "Solution may be inaccurate" ``UserWarning`` inside the block, and only that warning.

    For the ROA layer's solves, which check the status and the solution themselves: an ``optimal_inaccurate``
    SOS program is accepted or refused by its Gram check (:meth:`~glidectl.roa.sos.SOSProgram.check`), an
    inaccurate LMI solution by its LMIs in floating point (:func:`~glidectl.roa.lmi.certify_roa_lmi`), and the
    status is recorded in the certificate's history. Without it the warning, with cvxpy's advice to try another
    solver, reaches the terminal of ``glidectl report all`` when nothing is wrong. Any other warning passes.
    """
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=INACCURATE_MESSAGE, category=UserWarning)
        yield


def solver_argument(solver: str) -> Any:
    """What to pass as ``solver=`` to :meth:`cvxpy.Problem.solve` for a name of :data:`SDP_SOLVERS`: the name
    itself, or a :class:`~glidectl.roa.moment.CvxoptMoment` instance for ``CVXOPT_MOMENT``."""
    if solver != MOMENT:
        return solver
    from .moment import moment_solver  # (the moment route builds on this module)

    return moment_solver()
