"""Region-of-attraction certificates by SOS programs: level maximization, V-lambda alternation, verification.

For ``dz/dt = F(z)/den(z)`` on ``{h = 0} ∩ {g >= 0}`` (:class:`~glidectl.roa.systems.PolySystem`) and a polynomial
``V`` with ``V(0) = 0``, the *level problem* (one SDP, linear in the level ``rho``; the form used by Drake's
``RegionOfAttraction``, extended by S-procedure terms for cuts and equality multipliers) is::

    maximize rho  s.t.  (V - rho) N + lambda * (grad V . F) - sum_k tau_k g_k + sum_j psi_j h_j  is SOS,
                        (V - rho) + sigma_k g_k + sum_j phi_kj h_j                             is SOS (each k),
                        tau_k, sigma_k SOS,  lambda, psi, phi free,   N = (z . z)^m.

The first line says: wherever ``dV/dt = 0`` inside the cuts, ``V >= rho``; with ``dV/dt < 0`` near the equilibrium
(checked from the linearization) the connected component of ``{V < rho}`` containing the equilibrium has
``dV/dt < 0`` except at the equilibrium. The second says: outside a cut, ``V >= rho``, so that component stays
where the denominator is positive. Its closure is compact (``V >= eps |z|^2``), hence positively invariant and in
the region of attraction (LaSalle).

The *V step* fixes ``lambda`` (taken from the level problem re-solved slightly below its optimum, so that it has
slack) and solves for ``V`` and every other multiplier at ``rho = 1`` with ``V - eps |z|^2`` SOS, minimizing
``mean(max(V - 1, 0))`` over box points whose simulations converge: the simulated region of attraction steers the
search, the certificate never depends on it. The previous ``V`` stays feasible, the best ``V`` by sampled volume is
kept, and the degree of ``V`` is raised 2 -> 4 -> 6 with the previous ``V`` as the starting point.

**Speed** (exact, no certificate is weakened): every SOS constraint's half basis is reduced by the Newton polytope,
diagonal consistency and sign symmetry (:func:`~glidectl.roa.sos.reduce_basis`), and when the system has sign
symmetries (odd Van der Pol: ``x -> -x``) every unknown is restricted to the matching monomials (``_symmetry``);
in the large programs, the angle equalities ``s^2 + c^2 - 2 c = 0`` of a recast are not multiplied by free ``psi_j``,
``phi_kj``: every coefficient is matched modulo them instead (:mod:`glidectl.roa.quotient`,
:attr:`~glidectl.roa.moment.MomentPolicy.quotient_min_block`; the same feasible set);
the level is a variable of one SDP (no bisection), the back-off re-solves reuse the compiled program through a cvxpy
``Parameter`` (the level), and the final level is not searched again (the kept ``V`` is normalized by its
own optimal level). Each history entry records ``sdp_time`` and, split, ``compile_time`` (cvxpy) and
``solver_time`` (the solver's own time).

Every certificate is stated at a backed-off level ``rho_c = (1 - backoff) rho*``, re-solved at that fixed level
with the largest Gram eigenvalue margin, and verified a posteriori (:class:`ROAVerification`): exact SOS by Gram
eigenvalue margins against coefficient residuals, the local conditions at the equilibrium, ``dV/dt < 0`` of the
*true model* at sampled points of the set, and convergence of simulations started in it.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, BudgetError, ModelError, SolverError
from .alternation import Alternation, Clock
from .blas_threads import pinned_blas
from .certificate import HistoryRow, ROACertificate
from .lmi import SaturatedLoop, certify_roa_lmi
from .options import (
    BudgetOptions,
    SamplingOptions,
    SolverOptions,
    SurrogateOptions,
    resolve_options,
)
from .polynomial import Poly
from .programs import (
    auto_extra,
    check_candidate,
    check_degree,
    check_iterations,
    check_memory,
    default_memory_limit,
    estimate_sos_size,
    linearization,
    lyapunov_quadratic,
    require_exponential_stability,
)
from .routes import HeldLoop, box_about, build_route, search_remainder_box, transport
from .scaling import resolve_box, scaled_lyapunov
from .systems import PolySystem

__all__ = ["AUTO_DEGREE_BYTES", "certify_roa"]

#: bytes: ``certify_roa(system)`` without a degree takes the largest even degree <= 6 whose estimated SOS program
#: (:func:`~glidectl.roa.programs.estimate_sos_size`) is within this (and the memory limit), else 2. On the roa
#: design's systems this is degree 6 for Van der Pol and the reduced chapter-5 glider (0.02-0.4 GB), 2 for the
#: 4-state chapter-5 glider (degree 4: 3.3 GB), the CTOL loop (degree 2 already 3.0 GB) and the 8-state slocum loop
#: (degree 4: 1.6 TB): the degrees the design uses.
AUTO_DEGREE_BYTES = 1.0e9


@pinned_blas
def certify_roa(system: Any, degree: int | None = None, *, iterations: int | Sequence[int] = 4,
                initial: Poly | np.ndarray | None = None, box: Any = None, method: str = "auto",
                sampling: SamplingOptions | dict | None = None, budget: BudgetOptions | dict | float | None = None,
                surrogate: SurrogateOptions | dict | None = None,
                solver: SolverOptions | dict | str | None = None) -> Any:
    """Certify a region of attraction of the equilibrium of ``system``: a polynomial Lyapunov function by SOS
    programs, or for a saturated loop with state-dependent actuator limits a quadratic one by LMIs.

    With ``method="auto"`` and no ``degree``, a saturated loop (:func:`glidectl.saturated_loop`) with state-dependent
    limits (:class:`~glidectl.models.saturated_loop.AffineLimit`) goes to the LMI path
    (:func:`~glidectl.roa.lmi.certify_roa_lmi`, whose generalized sector condition takes them; the SOS path models
    constant levels only), and every other system, saturated loops with constant levels included, to the SOS path at
    the degree of :data:`AUTO_DEGREE_BYTES` (on the saturated loops measured, its degree-2 set reaches 2-4 times
    further per axis than the LMI ellipsoid, in 10-12 times the time). The V-lambda alternation
    (:class:`~glidectl.roa.alternation.Alternation`) raises the degree of ``V`` through 2, 4, ..., ``degree``; surrogate
    routes first search a smaller remainder box and then run remainder-box rounds (:class:`SurrogateOptions`).

    Parameters
    ----------
    system : PolySystem or glidectl model
        A polynomial system (e.g. :func:`glidectl.benchmarks.van_der_pol`) or a model at an equilibrium with the
        attributes :func:`~glidectl.roa.systems.recast` needs (``sp.reduced_model()``, ``sp.full_model()``), or a
        closed loop (:func:`glidectl.closed_loop`). Its equilibrium must be exponentially stable. A saturated loop
        (:func:`glidectl.saturated_loop`) is certified with its saturation as S-procedure terms
        (:func:`~glidectl.roa.sector.sector_system`; the states are its free states): ``method = "sos-sector"``
        with a polynomial plant, ``"sos-sector+remainder"`` with a surrogate of one that is not. A closed loop
        whose locked states never move (the states its law locks, and states whose derivative is zero on the box
        once those are fixed; e.g. ``r_P3``, ``rdot_P3`` when the vehicle file fixes ``r_P3``) is certified on its
        other states with the locked ones held at their equilibrium values: ``cert.held`` names them, and the set
        is certified for them AT those values.
    degree : int, optional
        Final (even, >= 2) degree of ``V``; the search runs through 2, 4, ..., ``degree``. Default: the largest
        degree <= 6 whose program fits :data:`AUTO_DEGREE_BYTES` (2 when none does); none for a saturated loop with
        state-dependent limits and ``method="auto"`` (the LMI path). Given, it asks for the SOS path.
    iterations : int or sequence of int
        Alternations (V step + level problem) per degree, >= 1; the best ``V`` (largest sampled volume) is kept.
        One number for every degree, or one per degree 2, 4, ..., ``degree`` (the counts of degrees below that of
        the starting ``V`` go unused). The V steps of a low degree are much cheaper, and a ``V`` taken further
        there leaves less to do at the high degree (``iterations=(9, 1)`` against ``4``: ``bench/README.md``).
    initial : Poly or array_like (n, n), optional
        Starting ``V`` in the system's polynomial variables, ``V(0) = 0``; or a weight matrix ``W`` (state units,
        e.g. ``Q + K^T R K`` of an LQR law): the start is then the cost-to-go ``(x - x_e)^T P (x - x_e)`` with
        ``A^T P + P A = -W`` (:func:`~glidectl.roa.scaling.scaled_lyapunov`). Default: the Lyapunov equation with
        ``W = I`` of the scaled linearization for the surrogate route (states scaled to the box), else
        :func:`~glidectl.roa.programs.lyapunov_quadratic`.
    box : (array_like, array_like) or mapping, optional
        Region of interest in state units, ``(lo, hi)`` or ``{state name: (lo, hi)}``
        (:func:`~glidectl.roa.scaling.resolve_box`); default the model's own box, else the validity box of its
        states (:func:`~glidectl.roa.scaling.validity_box`, the same default as :func:`glidectl.saturated_loop`);
        a state none of these knows is refused with a message asking for ``box=``. ``cert.box`` is the box used.
    method : {"auto", "exact", "surrogate", "lmi"}
        Route: ``"lmi"`` (a saturated loop only) is the LMI path, whose sampling options are ``n_verify``,
        ``n_simulate``, ``horizon`` and ``seed`` and whose solver option is the name (the other options and
        ``iterations``, ``initial`` do not apply to it); ``"exact"`` recasts the model exactly
        (:func:`~glidectl.roa.systems.recast`; a closed loop is shifted to its equilibrium and sampled on the box
        widened 3x); ``"surrogate"`` certifies a polynomial surrogate with a remainder bound on the box
        (:func:`~glidectl.roa.surrogate.surrogate_system`), for every right-hand side within that bound, the true one
        included; ``"auto"`` (default) tries the exact recast (closed loops: small monomial bases only) and falls back
        to the surrogate. ``cert.method`` says which. A saturated loop takes the same choice for its plant.
    sampling : SamplingOptions or mapping, optional
        Simulations that steer the V step and the a-posteriori checks (``n_truth``, ``n_verify``, ``n_simulate``,
        ``horizon``, ``seed``).
    budget : BudgetOptions, mapping or float, optional
        Time and memory budget (``time_limit``, ``memory_limit``, ``max_degree``, ``on_budget``); a number is the
        time limit (s).
    surrogate : SurrogateOptions or mapping, optional
        Surrogate degree and margin, recast speed floor, remainder-box search and rounds.
    solver : SolverOptions, mapping or str, optional
        The SDPs: solver name (a string is the name), ``backoff``, ``eps``, ``center``, ``extra``, ``reuse``,
        ``inner``.

    The certificate is a function of the arguments only: the call runs with one BLAS thread
    (:data:`glidectl.roa.blas_threads.BLAS_THREADS`) and Clarabel with one thread
    (:data:`glidectl.roa.sdp_solvers.CLARABEL_THREADS`), whose parallel sums would otherwise change it between
    machines.

    Returns
    -------
    ROACertificate or EllipsoidCertificate
        Both implement :class:`~glidectl.roa.extent.Certificate`. An ROACertificate has ``stopped_by`` saying what ended
        the alternation at the final degree, ``method`` the route, ``box`` and ``scale`` what was used, ``held`` the
        states held at their equilibrium values, ``history`` one :class:`~glidectl.roa.certificate.HistoryRow` per step.

    Raises
    ------
    ArgumentTypeError
        If ``system`` is neither a PolySystem nor a model, or an argument has the wrong type (``degree=4.0``
        included: degrees are integers).
    ArgumentError
        If an argument is out of range (an odd or too small ``degree``, an option outside its range, an unknown
        option name, a bad ``initial``, an unknown ``method``, ``"lmi"`` for a system that is not a saturated loop, a
        count of
        ``iterations`` below 1 or a sequence without one per degree), or a box that is invalid, misses limits for
        some states or does not contain the equilibrium.
    ModelError
        If the equilibrium is not exponentially stable (for a closed loop, its linearization on the states that
        are not held, checked before it is recast or a surrogate is built), the model cannot be recast exactly
        with ``method="exact"`` (the message names the derivatives that are not polynomial in which states), the
        model has no equilibrium, or its right-hand side is not complex-safe or not finite on the box.
    BudgetError
        If ``degree > max_degree`` or the program would need more than ``memory_limit`` (the message gives the
        largest degree that fits), or ``time_limit`` is hit (unless ``on_budget="stop"``), the final verification
        included. For the surrogate route the size is checked before anything is sampled, fitted or built.
    SolverError
        If the first level problem fails (no certificate at all) or no simulated box point converges.

    Examples
    --------
    >>> import glidectl as gc
    >>> vdp = gc.benchmarks.van_der_pol()
    >>> cert = gc.certify_roa(vdp, degree=2, iterations=1)
    >>> cert.certified, cert.method, cert.stopped_by
    (True, 'exact recast', 'iterations')
    >>> bool(cert.volume() > 0.3 * gc.benchmarks.VAN_DER_POL_AREA)     # the true region: 13.72
    True
    """
    t_wall = time.perf_counter()
    method = checks.choice("method", method, ("auto", "exact", "surrogate", "lmi"))
    if method == "lmi" or (method == "auto" and degree is None and isinstance(system, SaturatedLoop)
                           and system.limits):
        return _certify_lmi(system, box, sampling, solver)
    degree = _auto_degree(system, budget) if degree is None else check_degree(degree)
    smp = resolve_options(SamplingOptions, sampling, "sampling")
    bud = resolve_options(BudgetOptions, budget, "budget", "time_limit")
    sur = resolve_options(SurrogateOptions, surrogate, "surrogate")
    sol = resolve_options(SolverOptions, solver, "solver", "name")
    its = check_iterations(iterations, degree)
    limit = default_memory_limit() if bud.memory_limit is None else bud.memory_limit
    clock = Clock(checks.Deadline(bud.time_limit, "certify_roa"), bud.on_budget, degree, its)
    history: list = []
    ps, full, rebuild, box0, V0, ex, t_route = _route(system, box, method, degree, initial, (smp, bud, sur, sol),
                                                      clock, limit, history)

    def alternation(ps: PolySystem, V0: Poly, full: HeldLoop | None, t_solve: float) -> Alternation:
        return Alternation(ps, V0, full, sol, smp, degree, its, ex, clock, history, t_route, t_solve)

    rounds = range(2, sur.box_rounds + 1 if rebuild is not None else 0)
    # the first round's sampling and simulations wait until it is known to be the certificate kept (a second
    # round, verified in full, replaces it when larger); not under a time limit, which they could then exceed
    pending = bool(rounds) and clock.deadline.limit is None
    searched = float(sum(h.sdp_time for h in history))     # the remainder-box search's level programs
    cert, verify_first = alternation(ps, V0, full, searched).certificate(t_wall, verify=not pending)
    cert, untaken, pending = _remainder_rounds(cert, ps, full, rebuild, box0, rounds, alternation, history,
                                               smp.seed, pending, t_wall)
    if pending:                                 # the first round is the certificate kept: its sampled checks
        cert = verify_first()
    # the rounds that were tried, kept or not, in the history, and in the times: a certificate made before a later
    # round was tried (under a time limit, or one kept before a round that was not) would otherwise report its own
    return dataclasses.replace(cert, history=tuple(history), solve_time=cert.solve_time + untaken,
                               wall_time=time.perf_counter() - t_wall)


def _route(system: Any, box: Any, method: str, degree: int, initial: Any, options: tuple[Any, Any, Any, Any],
           clock: Clock, limit: float, history: list) -> tuple[PolySystem, HeldLoop | None, Any,
                                                               tuple[np.ndarray, np.ndarray], Poly, int, float]:
    """The polynomial system certified (:func:`~glidectl.roa.routes.build_route`), checked (budget, exponential
    stability, memory), with its starting ``V``, and for a surrogate route the smaller remainder box searched first.
    Returns the system, the held-state loop, the rebuild function, the route's box (free states), ``V0``, the
    extra multiplier degree and the time the route took (s)."""
    smp, bud, sur, sol = options
    ps, full, rebuild = build_route(system, box=box, method=method, surrogate_degree=sur.degree, margin=sur.margin,
                                    speed_floor=sur.speed_floor, seed=smp.seed, degree=degree,
                                    max_degree=bud.max_degree, limit=limit, extra=sol.extra)
    t_route = clock.deadline.elapsed
    box0 = (np.array(ps.box[0], dtype=float), np.array(ps.box[1], dtype=float))     # the route's (free states)
    if bud.on_budget == "raise":
        clock.deadline.check(f"after building the {ps.method} system of {ps.n} states ({t_route:.1f} s)"
                             + ("" if full is None else f", {', '.join(full.names[i] for i in full.held)} held"))
    V0 = _starting_V(ps, initial)
    ex = auto_extra(ps, sol.extra)
    require_exponential_stability(ps, linearization(ps))
    check_memory(ps, degree, ex, bud.max_degree, limit, f"certify_roa(degree={degree})")
    if rebuild is not None and sur.box_search > 0 and V0.degree == 2:
        t_stage = time.perf_counter()
        ps, V0 = search_remainder_box(ps, rebuild, V0, n_boxes=sur.box_search, solver=sol.name, extra=sol.extra,
                                      history=history, out_of_time=clock.out_of_time)
        clock.spent["remainder-box search"] = time.perf_counter() - t_stage
        full = full.with_free_box(ps.box) if full is not None else None
    return ps, full, rebuild, box0, V0, ex, t_route


def _certify_lmi(system: Any, box: Any, sampling: Any, solver: Any) -> Any:
    """The LMI path for :func:`certify_roa` (``method="lmi"``, or ``"auto"`` on a saturated loop with state-dependent
    limits and no degree): :func:`~glidectl.roa.lmi.certify_roa_lmi` with the sampling options that apply to it and
    the solver's name."""
    if not isinstance(system, SaturatedLoop):
        raise ArgumentError(f"method='lmi' needs a saturated loop (gc.saturated_loop(loop)), got "
                            f"{type(system).__name__}: certify other systems by SOS (method 'auto')")
    if box is not None:
        system = dataclasses.replace(system, box=resolve_box(system, box, system.equilibrium))
    kw: dict[str, Any] = {}
    if sampling is not None:
        smp = resolve_options(SamplingOptions, sampling, "sampling")
        kw.update(n_verify=smp.n_verify, n_simulate=smp.n_simulate, horizon=smp.horizon, seed=smp.seed)
    if solver is not None:
        kw["solver"] = resolve_options(SolverOptions, solver, "solver", "name").name
    return certify_roa_lmi(system, **kw)


def _auto_degree(system: Any, budget: Any) -> int:
    """The largest even degree <= 6 whose SOS program is within :data:`AUTO_DEGREE_BYTES` and the memory limit
    (estimated before anything is built), else 2."""
    bud = resolve_options(BudgetOptions, budget, "budget", "time_limit")
    limit = min(AUTO_DEGREE_BYTES, default_memory_limit() if bud.memory_limit is None else bud.memory_limit)
    best = 2
    for d in (4, 6):
        try:
            if estimate_sos_size(system, d).bytes > limit:
                break
        except (ArgumentError, ModelError):
            break
        best = d
    return best


def _starting_V(ps: PolySystem, initial: Any) -> Poly:
    """The starting ``V``: ``initial`` itself, the cost-to-go of a weight matrix, the scaled Lyapunov quadratic
    (surrogate routes) or :func:`~glidectl.roa.programs.lyapunov_quadratic`."""
    weight = None
    if initial is not None and not isinstance(initial, Poly):
        # a weight matrix: the starting V is the quadratic cost-to-go (x - x_e)^T P (x - x_e), A'P + PA = -weight
        weight = checks.array("initial (weight matrix)", initial, shape=(ps.n, ps.n))
        if ps.nz != ps.n:
            raise ArgumentError("initial as a weight matrix needs a system whose polynomial variables are its states "
                                f"(no angle lift); '{ps.name}' has z = {ps.z_names}: give initial as a Poly")
        initial = None
    if initial is not None:
        check_candidate(initial, ps, "initial")
        return initial
    if ps.scale is not None or weight is not None:
        V0 = scaled_lyapunov(linearization(ps), ps.scale[:ps.n] if ps.scale is not None else np.ones(ps.n), weight)
        if ps.nz != ps.n:       # (a saturated loop) the quadratic in the states' own variables of z
            Zv = Poly.variables(ps.nz)
            V0 = V0.substitute([Zv[sl[0]] for sl in ps.slots])
        return V0
    return lyapunov_quadratic(ps)


def _remainder_rounds(cert: ROACertificate, ps: PolySystem, full: HeldLoop | None, rebuild: Any,
                      box0: tuple[np.ndarray, np.ndarray], rounds: range,
                      alternation: Any, history: list, seed: int, pending: bool, t_wall: float
                      ) -> tuple[ROACertificate, float, bool]:
    """Remainder-box rounds: the box three times the extents of the certified set (clipped to the route's box), a
    surrogate on it, and the alternation again from the certificate's ``V``; kept if certified and larger (``box0``:
    the route's box, before the remainder-box search). Returns
    the certificate kept, the SDP time of the rounds not kept, and whether the first round's verification is still
    pending."""
    untaken = 0.0           # SDP time of rounds not kept (a round starts its count from the certificate's)

    def note(degree: int, step: str) -> None:
        history.append(HistoryRow(degree, step))

    for rnd in rounds:
        if not cert.verification.unsampled_passed or cert.stopped_by == "time_limit":
            break
        cur = cert.system if full is None else ps
        free = list(range(cur.n)) if full is None else list(full.free)
        Xb = cert.sample(2000, seed=seed, boundary=True)[:, free]
        xe = np.asarray(cur.equilibrium, dtype=float)
        blo, bhi = box_about(xe, 3.0 * np.max(np.abs(Xb - xe), axis=0), box0)
        if np.all(np.abs(np.log((bhi - blo) / (np.asarray(cur.box[1]) - np.asarray(cur.box[0])))) < 0.1):
            note(cert.degree, f"remainder-box round {rnd} skipped: the box would change by less than 10 %")
            break
        note(cert.degree, f"remainder-box round {rnd}: the box three times the extents of the certified set")
        try:
            ps2 = rebuild((blo, bhi))
            full2 = full.with_free_box((blo, bhi)) if full is not None else None
            cert2, _ = alternation(ps2, transport(cert.V, cur, ps2), full2, cert.solve_time).certificate(t_wall)
        except (BudgetError, SolverError, ModelError) as exc:
            note(cert.degree, f"remainder-box round {rnd} stopped: {exc}")
            break
        if not (cert2.certified and cert2.volume() > cert.volume()):
            note(cert.degree, f"remainder-box round {rnd} not kept (not certified or not larger)")
            untaken += cert2.solve_time - cert.solve_time
            break
        cert, ps, full, pending = cert2, ps2, full2, False
    return cert, untaken, pending
