"""Options of :func:`glidectl.certify_roa`, grouped by what they control: the sampling that steers and verifies the
certificate (:class:`SamplingOptions`), the time and memory budget (:class:`BudgetOptions`), how a model becomes a
polynomial system (:class:`SurrogateOptions`) and the SDPs of the alternation (:class:`SolverOptions`).

Each group is a frozen dataclass that checks its fields when it is made, so a bad value is refused before anything
is built. :func:`certify_roa` also takes a mapping (``sampling={"n_truth": 64}``) or, for the solver and the budget,
the one value most often changed (``solver="CLARABEL"``, ``budget=60.0`` seconds).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, TypeVar

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError
from .sdp_solvers import DEFAULT_SOLVER, check_solver
from .sos import GRAM_CONES

__all__ = ["MAX_DEGREE", "BudgetOptions", "SamplingOptions", "SolverOptions", "SurrogateOptions", "resolve_options"]

#: Default largest degree of ``V`` that :func:`glidectl.certify_roa` accepts (:attr:`BudgetOptions.max_degree`):
#: degree 8 in 2 variables takes ~20 s, degree 6 in 3 variables ~10 min, degree 4 in 5 variables about a minute (the
#: 4-state glider on the moment route; hours with Clarabel).
MAX_DEGREE = 8


@dataclass(frozen=True)
class SamplingOptions:
    """Sampling of :func:`glidectl.certify_roa`: the simulations that steer the V step and the a-posteriori checks.

    Parameters
    ----------
    n_truth : int
        Box points simulated once (>= 1); the V step minimizes ``mean(max(V - 1, 0))`` over those that converge
        (the simulated region of attraction guides the search, the certificate never depends on it).
    n_verify : int
        Points of the certified set at which the true ``dV/dt`` is checked (>= 1).
    n_simulate : int
        Simulations from the outermost of those points (>= 0).
    horizon : float, optional
        Length of those simulations (> 0, the model's time unit); default 25 slowest time constants.
    seed : int
        Seed of every sample (>= 0).
    """

    n_truth: int = 2048
    n_verify: int = 20_000
    n_simulate: int = 256
    horizon: float | None = None
    seed: int = 0

    def __post_init__(self) -> None:
        _set(self, "n_truth", checks.integer("n_truth", self.n_truth, lo=1, hi=2**22))
        _set(self, "n_verify", checks.integer("n_verify", self.n_verify, lo=1, hi=2**24))
        _set(self, "n_simulate", checks.integer("n_simulate", self.n_simulate, lo=0, hi=2**20))
        _set(self, "horizon", None if self.horizon is None else checks.positive("horizon", self.horizon))
        _set(self, "seed", checks.integer("seed", self.seed, lo=0))


@dataclass(frozen=True)
class BudgetOptions:
    """Time and memory budget of :func:`glidectl.certify_roa`.

    Parameters
    ----------
    time_limit : float, optional
        Wall-time budget (s), checked between SDPs (an SDP under way is not interrupted); default none. With
        ``on_budget="raise"`` it also bounds the ``n_truth`` simulations and every step of the final verification:
        :class:`~glidectl.BudgetError` names the step and what to lower; the verification is never shortened to
        fit. A budget message also gives the wall time of each stage so far and the time the requested run needs.
    memory_limit : float, optional
        Bytes the largest program may need (:func:`~glidectl.roa.estimate_sos_size`, checked before anything is
        built); default :data:`~glidectl.roa.programs.MEMORY_FRACTION` of the physical memory.
    max_degree : int
        Largest degree of ``V`` accepted (default :data:`MAX_DEGREE`): SDP time grows steeply with the degree.
    on_budget : {"raise", "stop"}
        What hitting ``time_limit`` does: raise :class:`~glidectl.BudgetError` (default), or end the alternation and
        certify the best ``V`` found so far (the final certification SDPs and checks still run, in full and past the
        limit), with ``stopped_by = "time_limit"``. ``max_degree`` and ``memory_limit`` always refuse up front.
    """

    time_limit: float | None = None
    memory_limit: float | None = None
    max_degree: int = MAX_DEGREE
    on_budget: str = "raise"

    def __post_init__(self) -> None:
        if self.time_limit is not None:
            _set(self, "time_limit", checks.positive("time_limit", self.time_limit))
        if self.memory_limit is not None:
            _set(self, "memory_limit", checks.positive("memory_limit", self.memory_limit))
        _set(self, "max_degree", checks.integer("max_degree", self.max_degree, lo=2))
        checks.choice("on_budget", self.on_budget, ("raise", "stop"))


@dataclass(frozen=True)
class SurrogateOptions:
    """How :func:`glidectl.certify_roa` turns a model into the polynomial system it certifies.

    Parameters
    ----------
    degree : int
        Degree of the polynomial surrogate, 2 to 5 (:func:`~glidectl.roa.surrogate.surrogate_system`).
    margin : float
        Safety factor (>= 1) of the surrogate's remainder bound.
    speed_floor : float
        ``delta`` of the denominator cut of an exact recast, in ``(0, 1)``.
    box_search : int
        Surrogate routes with a quadratic start: how many smaller boxes to try for the surrogate at most (0: the
        box only). The remainder bound holds on the whole box, so a region much smaller than the box pays for
        curvature far from it. Each round sets the box to three times the extents of the best set of the starting
        ``V0`` so far (clipped to the box), builds its surrogate and solves one level SDP; the alternation runs on
        the box with the largest level (each round a ``"remainder box r = ..."`` history row).
    box_rounds : int
        Surrogate routes: rounds of certification (1: one). After a certificate, the box is set to three times the
        extents of the certified set (clipped), the surrogate is built on it and the alternation runs again from
        the certificate's ``V``; the new certificate is kept if it is certified and larger. Without a time limit,
        the first round's sampled checks run only if it is the certificate returned.
    """

    degree: int = 3
    margin: float = 2.0
    speed_floor: float = 0.1
    box_search: int = 6
    box_rounds: int = 2

    def __post_init__(self) -> None:
        _set(self, "degree", checks.integer("surrogate degree", self.degree, lo=2, hi=5))
        _set(self, "margin", checks.real("margin", self.margin, lo=1.0))
        _set(self, "speed_floor", checks.real("speed_floor", self.speed_floor, lo=0.0, hi=1.0, lo_open=True,
                                              hi_open=True))
        _set(self, "box_search", checks.integer("box_search", self.box_search, lo=0, hi=30))
        _set(self, "box_rounds", checks.integer("box_rounds", self.box_rounds, lo=1, hi=10))


@dataclass(frozen=True)
class SolverOptions:
    """The SDPs of the alternation of :func:`glidectl.certify_roa`.

    Parameters
    ----------
    name : str
        An SDP solver of :func:`glidectl.roa.installed_sdp_solvers` (default the moment route
        ``"CVXOPT_MOMENT"``, chosen per program by :data:`~glidectl.roa.moment.MOMENT_POLICY`).
    backoff : float
        Certified level ``(1 - backoff) rho*``, in ``[0, 1)``; tripled (up to 3 times, at most 0.25; from 0.01 when
        it is 0) when the Gram margins at that level do not exceed the coefficient residuals. On the moment route,
        if no backoff passes, the same steps are taken again with Clarabel.
    eps : float
        ``V - eps |z|^2`` must be SOS in the V step (strict positivity), ``> 0``.
    center : float
        The multiplier of the V step comes from the level problem re-solved at ``(1 - center) rho*``, in
        ``[0, 1)``. A V step that fails is tried once more with the multiplier centred at ``(1 - RETRY_CENTER)
        rho*`` (:data:`~glidectl.roa.alternation.RETRY_CENTER`); a second failure stops the alternation at the best
        V so far (``stopped_by = "solver failure"``).
    extra : int, optional
        Extra multiplier degree (steps of 2, >= 0); default 2 for up to 3 polynomial variables, else 0.
    reuse : bool
        Exact route: build the V step, level and centering programs once per degree (and monomial support) with the
        fixed polynomials as cvxpy Parameters and re-solve them across alternations (same SOS conditions).
    inner : {"sos", "sdsos", "dsos"}
        Cone of the Gram matrices of the alternation's inner programs: ``"sos"`` (SDPs), or the inner
        approximations ``"sdsos"`` (SOCPs) and ``"dsos"`` (LPs) of Ahmadi and Majumdar (2019). The final
        certificate is always a full SOS one (the kept ``V`` first gets its full SOS level, a ``"final SOS level"``
        history row).
    """

    name: str = DEFAULT_SOLVER
    backoff: float = 0.01
    eps: float = 1e-6
    center: float = 0.05
    extra: int | None = None
    reuse: bool = True
    inner: str = "sos"

    def __post_init__(self) -> None:
        check_solver(self.name)
        _set(self, "backoff", checks.real("backoff", self.backoff, lo=0.0, hi=1.0, hi_open=True))
        _set(self, "eps", checks.positive("eps", self.eps))
        _set(self, "center", checks.real("center", self.center, lo=0.0, hi=1.0, hi_open=True))
        if self.extra is not None:
            _set(self, "extra", checks.integer("extra", self.extra, lo=0))
        _set(self, "reuse", checks.boolean("reuse", self.reuse))
        checks.choice("inner", self.inner, GRAM_CONES)


def _set(obj: Any, name: str, value: Any) -> None:
    object.__setattr__(obj, name, value)


_T = TypeVar("_T")


def resolve_options(kind: type[_T], value: Any, name: str, shorthand: str | None = None) -> _T:
    """``value`` as options of ``kind``: None gives the defaults, a mapping its fields, and a bare value the field
    ``shorthand`` (``solver="CLARABEL"``, ``budget=60.0``).

    Raises
    ------
    ArgumentError
        If a mapping names a field ``kind`` does not have.
    ArgumentTypeError
        If ``value`` is none of these.
    """
    if value is None:
        return kind()
    if isinstance(value, kind):
        return value
    if isinstance(value, Mapping):
        known = {f.name for f in dataclasses.fields(kind)}
        unknown = sorted(set(value) - known)
        if unknown:
            raise ArgumentError(f"{name} has no option(s) {unknown}; {kind.__name__} has {sorted(known)}")
        return kind(**value)
    if shorthand is not None and not isinstance(value, bool | list | tuple):
        return kind(**{shorthand: value})
    raise ArgumentTypeError(f"{name} must be a {kind.__name__}, a mapping of its fields"
                            + (f" or a value of {shorthand}" if shorthand else "") + f", got {type(value).__name__}")
