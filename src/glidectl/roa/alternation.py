"""The V-lambda alternation of :func:`glidectl.certify_roa` as an object with named steps.

One :class:`Alternation` runs on one polynomial system (one remainder box of a surrogate route):

1. :meth:`Alternation.first_level`: the level problem of the starting ``V`` (``V`` is normalized to level 1);
2. :meth:`Alternation.guide`: the simulated box points that steer the V step;
3. per degree 2, 4, ..., :meth:`Alternation.v_step` (the V step, its level problem and, once, a retry with a
   multiplier centred deeper inside), keeping the ``V`` with the largest sampled volume;
4. :meth:`Alternation.final_margin`: the kept ``V`` re-solved at the backed-off level with the largest Gram margin;
5. :meth:`Alternation.certificate`: the certificate, verified on the true model now or later.

:class:`Clock` holds the time budget across alternations (a remainder-box round runs a second alternation on
another box); every step appends a :class:`HistoryRow`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np

from .. import checks
from ..analysis.measure import unit_sobol
from ..errors import SolverError
from .certificate import (
    HistoryRow,
    PathPoints,
    ROACertificate,
    ROAVerification,
    default_horizon,
    local_checks,
    simulated_truth,
    step_volume,
    verify_certificate,
)
from .options import SamplingOptions, SolverOptions
from .polynomial import Poly
from .programs import (
    LevelResult,
    build_program,
    coverage_objective,
    even_up,
    from_scaled,
    rescaled,
    scaled_field,
    solve_level,
    solve_v_step,
    to_scaled,
    variable_scaling,
)
from .routes import HeldLoop, embed_held, local_robust_checks
from .sdp_solvers import MOMENT
from .systems import PolySystem

__all__ = ["RETRY_CENTER", "Alternation", "Clock", "HistoryRow"]

#: A V step whose new V has no positive level (or whose SDP fails) is tried once more, with the multiplier of the
#: current V's level problem at ``(1 - RETRY_CENTER) rho*`` instead of ``(1 - center) rho*`` (a history row "V step
#: failed (...): retried ..."); if that fails too, the alternation stops at the best V so far. The multiplier
#: centred just inside the limit lets the V step push the new V's decrease condition to where rounding decides it;
#: one from a quarter of the way in does not. Not a tuned value (measurements: ``bench/README.md``).
RETRY_CENTER = 0.25


class Clock:
    """The time budget of one :func:`glidectl.certify_roa` call: the deadline, the stages' wall times and the V
    steps' durations, for the budget message (what took the time and what the requested run would need)."""

    def __init__(self, deadline: checks.Deadline, on_budget: str, degree: int, its: tuple[int, ...]) -> None:
        self.deadline, self.on_budget, self.degree, self.its = deadline, on_budget, degree, its
        self.spent: dict[str, float] = {}
        self.v_steps: list[float] = []

    @property
    def raising(self) -> checks.Deadline | None:
        """The deadline when hitting it raises (``on_budget="raise"``), else None."""
        return self.deadline if self.on_budget == "raise" else None

    def time_spent(self) -> str:
        """What took the time so far and what the requested run would need (what would fit)."""
        parts = [f"{k} {v:.1f} s" for k, v in self.spent.items()]
        its = self.its
        if self.v_steps:
            per = max(self.v_steps)
            parts.append(f"{len(self.v_steps)} V step(s) with their level problems, {per:.1f} s at most each")
            need = sum(self.spent.values()) + per * sum(its) + per
            shown = its if len(set(its)) > 1 else its[0]
            est = (f"degree {self.degree} with iterations = {shown} needs about {need:.0f} s before the final "
                   f"verification: raise time_limit to that, or lower iterations (or degree)")
        else:
            est = "no V step finished within the limit: raise time_limit, or lower degree or n_truth"
        return f"time spent: {', '.join(parts)}; {est}"

    def out_of_time(self, where: str) -> bool:
        """Whether the time limit has passed; raises :class:`~glidectl.BudgetError` instead with
        ``on_budget="raise"``."""
        d = self.deadline
        if d.limit is None or d.elapsed <= d.limit:
            return False
        if self.on_budget == "raise":
            d.check(f"{where}; {self.time_spent()}; or pass budget=gc.BudgetOptions(time_limit=..., "
                    "on_budget='stop') to certify the best V found so far")
        return True


@dataclass
class _Step:
    """A solved V step: the new ``V`` (scaled), its level problem and the V step's program."""

    V: Poly
    level: LevelResult
    prog: Any


@dataclass
class Alternation:
    """The alternation on one polynomial system ``ps`` from ``V0`` (see the module docstring).

    Parameters
    ----------
    ps : PolySystem
        The system certified (free states, on its box).
    V0 : Poly
        Starting ``V`` in ``ps``'s polynomial variables.
    full : HeldLoop or None
        The full loop when states are held at their equilibrium values (the certificate is embedded in it).
    solver, sampling : SolverOptions, SamplingOptions
        The options of :func:`glidectl.certify_roa`.
    degree, its, extra : int, tuple of int, int
        Final degree of ``V``, alternations per degree, extra multiplier degree (resolved).
    clock : Clock
    history : list of HistoryRow
        Shared by every alternation of one call (appended to).
    t_route : float
        Wall time of building ``ps`` (s), reported by the budget message.
    """

    ps: PolySystem
    V0: Poly
    full: HeldLoop | None
    solver: SolverOptions
    sampling: SamplingOptions
    degree: int
    its: tuple[int, ...]
    extra: int
    clock: Clock
    history: list[HistoryRow]
    t_route: float
    t_solve: float = 0.0
    stopped_by: str = "iterations"
    _cache: dict | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        ps = self.ps
        self.k = variable_scaling(ps)
        self.pss = rescaled(ps, self.k)
        self.F = scaled_field(self.pss)
        self.horizon = self.sampling.horizon or default_horizon(ps)
        # programs re-solved with new Parameter values (per degree); the inner cones build their programs anew
        self._cache = {} if self.solver.reuse and self.solver.inner == "sos" else None
        lo, hi = ps.box
        self._volume_points = PathPoints(self.pss, lo + (hi - lo) * unit_sobol(ps.n, 2, 2**13))

    # ------------------------------------------------------------------------------------------- helpers
    def volume(self, V: Poly, rho: float = 1.0) -> float:
        """Sampled volume fraction of the box inside ``{V <= rho}`` (scaled ``V``), the alternation's measure."""
        lo, hi = self.ps.box
        return step_volume(self.pss, self._volume_points, V, lo, hi, self.sampling.seed, rho)

    def _level(self, V: Poly, center: float, *, cache: Any = "default", basis: Any = None) -> LevelResult:
        s = self.solver
        return solve_level(self.pss, self.F, V, rho_cap=1e6, solver=s.name, center=center, extra=self.extra,
                           cache=self._cache if cache == "default" else cache, basis=basis, cone=s.inner)

    def _row(self, degree: int, step: str, rho: float = math.nan, volume: float = math.nan, sdp_time: float = 0.0,
             timed: Any = None) -> None:
        """Append a history row; ``timed`` (LevelResult or program(s)) adds its compile and solver times."""
        ct = st = math.nan
        if timed is not None:
            items = timed if isinstance(timed, tuple) else (timed,)
            ct = sum(x.compile_time for x in items)
            st = sum(x.solver_time for x in items)
        self.history.append(HistoryRow(degree, step, rho, volume, sdp_time, ct, st))

    # ------------------------------------------------------------------------------------------- steps
    def first_level(self) -> tuple[Poly, Poly]:
        """Level problem of the starting ``V`` (scaled); returns ``V / rho*`` and the multiplier."""
        ps, inner = self.ps, self.solver.inner
        full = self.full
        held_note = "" if full is None else (f" (free states; {', '.join(full.names[i] for i in full.held)} held at "
                                             "their equilibrium values)")
        self.clock.spent[f"building the {ps.method} system of {ps.n} states{held_note}"] = self.t_route
        t_stage = time.perf_counter()
        V = to_scaled(self.V0, self.k)
        try:
            lvl = self._level(V, self.solver.center)
        except SolverError as exc:
            if inner == "sos":
                raise
            raise SolverError(f"the first level problem with inner='{inner}' failed ({exc}): the {inner.upper()} inner "
                              "approximation cannot certify the starting V; use inner='sos'") from exc
        if not (math.isfinite(lvl.rho) and lvl.rho > 0):
            if inner == "sos":
                raise SolverError(f"the first level problem gives level {lvl.rho:.3g}, not positive: the starting V "
                                  f"is not certified on any level set of '{ps.name}' (give another initial V, or a "
                                  "smaller box)")
            raise SolverError(f"the first level problem with inner='{inner}' gives level {lvl.rho:.3g} <= 0: the "
                              f"{inner.upper()} inner approximation cannot certify the starting V; use inner='sos'")
        self.t_solve += lvl.solve_time
        self.clock.spent["first level problem"] = time.perf_counter() - t_stage
        V = V / lvl.rho
        self._row(V.degree, "initial level", lvl.rho, self.volume(V), lvl.solve_time, lvl)
        return V, lvl.lam

    def guide(self) -> np.ndarray:
        """The lifted box points whose simulations converge (they steer the V step)."""
        ps, n_truth = self.ps, self.sampling.n_truth
        t_stage = time.perf_counter()
        Zt = self.pss.lift(simulated_truth(ps, n_truth, self.horizon, self.sampling.seed, self.clock.raising))
        self.clock.spent[f"simulating n_truth = {n_truth} box points"] = time.perf_counter() - t_stage
        if Zt.shape[0] == 0:
            raise SolverError(f"none of the {n_truth} simulated box points of '{ps.name}' converges within "
                              f"{self.horizon:g}: nothing to steer the V step towards (check the box and the horizon)")
        return Zt

    def _solve_v_step(self, degV: int, V: Poly, lam: Poly, Zt: np.ndarray) -> Any:
        s = self.solver
        if s.inner == "sos":
            return solve_v_step(self.pss, self.F, degV, lam, Zt, eps=s.eps, extra=self.extra, solver=s.name,
                                cache=self._cache, V0=V)
        prog, out = build_program(self.pss, self.F, degV, V=None, lam=lam, rho=1.0, eps=s.eps, extra=self.extra,
                                  cone=s.inner, V0=V)
        prog.solve(coverage_objective(prog, out["V"], Zt), solver=s.name)
        return prog, out

    def v_step(self, degV: int, V: Poly, lam: Poly, Zt: np.ndarray, last: bool) -> _Step | None:
        """The V step from ``V`` with multiplier ``lam`` and the level problem of its new ``V``; once more after a
        failure with a multiplier centred deeper inside (:data:`RETRY_CENTER`). None when it stops the alternation
        (:attr:`stopped_by` says why)."""
        step_sdp = 0.0      # SDP time of this step counted in t_solve (its history row shows the same)
        retried = False
        while True:
            try:
                prog, out = self._solve_v_step(degV, V, lam, Zt)
                self.t_solve += prog.solve_time
                step_sdp += prog.solve_time
                Vn = out["V"].poly()
                if self.clock.out_of_time(f"degree {degV}, after a V step"):
                    self._row(degV, "V step solved, not used: time limit before its level", sdp_time=step_sdp)
                    self.stopped_by = "time_limit"
                    return None
                # the centred multiplier only feeds a later V step: none follows the last one
                lv = self._level(Vn, 0.0 if last else self.solver.center, basis=out["V"].basis)
                self.t_solve += lv.solve_time
                step_sdp += lv.solve_time
                if not (math.isfinite(lv.rho) and lv.rho > 0):
                    # an inaccurate V step can return a V whose level is 0 (or a solver a NaN level): V / rho would
                    # be infinite and its multiplier would steer the next step from nothing
                    raise SolverError(f"the level of the new V is {lv.rho:.3g}, not positive")
                return _Step(Vn, lv, prog)
            except SolverError as exc:
                lvc = self._retry_multiplier(degV, V, exc, step_sdp, retried)
                if lvc is None:
                    return None
                self.t_solve += lvc.solve_time
                step_sdp += lvc.solve_time
                self._row(degV, f"V step failed ({exc}): retried with the multiplier centred at "
                          f"(1 - {RETRY_CENTER:g}) rho*", lvc.rho, sdp_time=step_sdp)
                step_sdp = 0.0
                lam, retried = lvc.lam, True

    def _retry_multiplier(self, degV: int, V: Poly, exc: Exception, step_sdp: float,
                          retried: bool) -> LevelResult | None:
        """After a failed V step: the multiplier of ``V``'s level problem at ``(1 - RETRY_CENTER) rho*`` (the V step
        took its multiplier from just inside the current V's limit and pushed the new V to where no level is
        certified); None, with a history row and :attr:`stopped_by`, when there is no retry (one was ``retried``
        already, or the time is up)."""
        why, lvc, stop = f"V step failed: {exc}", None, "solver failure"
        if not retried and RETRY_CENTER > self.solver.center:
            if self.clock.out_of_time(f"degree {degV}, before a retry"):
                why, stop = why + "; not retried: time limit", "time_limit"
            else:
                try:
                    lvc = self._level(V, RETRY_CENTER, cache=None)
                except SolverError as exc2:
                    why += f"; its retry's multiplier: {exc2}"
        if lvc is None:
            self._row(degV, why, sdp_time=step_sdp)
            self.stopped_by = stop
        return lvc

    def run_degree(self, degV: int, V: Poly, lam: Poly, Zt: np.ndarray, best: tuple[float, Poly]
                   ) -> tuple[Poly, Poly, tuple[float, Poly]]:
        """The alternations of one degree from ``V``, ``lam``; returns the last ``V``, its multiplier and the best
        ``(volume, V)`` so far. Stops after two steps without a larger volume (``stopped_by = "no improvement"``)."""
        worse = 0
        self.stopped_by = "iterations"
        if self._cache is not None:       # programs of a lower degree are not used again
            for old in [key for key in self._cache if key[1] < degV]:
                del self._cache[old]
        n_its = self.its[degV // 2 - 1]
        for it in range(n_its):
            if self.clock.out_of_time(f"degree {degV}, before a V step"):
                self.stopped_by = "time_limit"
                break
            t_stage = time.perf_counter()
            step = self.v_step(degV, V, lam, Zt, last=degV == self.degree and it == self.its[-1] - 1)
            if step is None:
                break
            V, lam = step.V / step.level.rho, step.level.lam
            self.clock.v_steps.append(time.perf_counter() - t_stage)
            cur_vol = self.volume(V)
            self._row(degV, "V step + level", step.level.rho, cur_vol, step.prog.solve_time + step.level.solve_time,
                      (step.prog, step.level))
            if cur_vol > best[0]:
                best, worse = (cur_vol, V), 0
            else:
                worse += 1
                if worse >= 2:
                    self.stopped_by = "no improvement"
                    break
        if self.stopped_by == "time_limit":
            self._row(degV, f"time limit of {self.clock.deadline.limit:g} s: alternation stopped")
        return V, lam, best

    def alternate(self) -> Poly:
        """Steps 1-3: the best ``V`` (scaled, level 1) over every degree."""
        V, lam = self.first_level()
        best = (self.history[-1].volume, V)
        Zt = self.guide()
        for degV in range(2, self.degree + 1, 2):
            if degV < even_up(V.degree):
                continue
            V, lam, best = self.run_degree(degV, V, lam, Zt, best)
            if self.stopped_by == "time_limit":
                break
        V = best[1]
        if self.ps.remainder:   # V(0) = 0 and V >= 0 leave no linear terms but rounding ones: they would make dV/dt
            # sign-indefinite at |z| ~ 1e-10, which the local check of the surrogate routes cannot pass; drop them
            V = Poly({e: c for e, c in V.terms.items() if sum(e) >= 2}, V.nvars)
        if self.stopped_by != "time_limit":
            self.clock.out_of_time("before the final certification")
        return V

    def full_sos_level(self, V: Poly) -> Poly:
        """With an inner cone, the kept ``V``'s full SOS level (>= its inner level 1): ``V`` normalized by it."""
        s = self.solver
        lvs = solve_level(self.pss, self.F, V, rho_cap=1e6, solver=s.name, center=0.0, extra=self.extra)
        self.t_solve += lvs.solve_time
        if lvs.rho > 1.0:
            V = V / lvs.rho
        self._row(V.degree, f"final SOS level ({s.inner} level 1)", lvs.rho, self.volume(V), lvs.solve_time, lvs)
        return V

    def final_margin(self, V: Poly) -> tuple[float, tuple]:
        """Step 4: the certified level ``rho_c = (1 - backoff)`` (``V`` has level 1) re-solved with the largest Gram
        eigenvalue margin, checked with the residual on monomials no Gram pair reaches cancelled by the free
        multipliers first; backed off further (x3, at most 3 times) while rounding leaves the margin below the
        coefficient residuals, re-solving the same compiled program (``rho_c`` a cvxpy Parameter). On the moment
        route, the same steps by Clarabel if none passes (the moment route stops at a singular Schur complement
        with residuals near 1e-6). Returns ``rho_c`` and the Gram checks."""
        s = self.solver
        prog, outf = build_program(self.pss, self.F, even_up(V.degree), V=V, lam=None, rho=None, eps=0.0,
                                   extra=self.extra, margin=True)
        rho_p = cp.Parameter(nonneg=True)
        prog.constraints.append(outf["rho"].var == rho_p)
        rho_c, gram, bo = self._margin_steps(V, prog, outf, rho_p, s.name)
        if s.name == MOMENT and not all(c.passed for c in gram):
            self._row(V.degree, f"Gram slack {min(c.slack for c in gram):.2g} at backoff {bo:g}: the same steps by "
                      f"Clarabel from backoff {s.backoff:g}", rho_c)
            rho_c, gram, _ = self._margin_steps(V, prog, outf, rho_p, "CLARABEL")
        return rho_c, gram

    def _margin_steps(self, V: Poly, prog: Any, outf: dict, rho_p: Any, fin_solver: str) -> tuple[float, tuple, float]:
        bo, tag = self.solver.backoff, "" if fin_solver == self.solver.name else f" ({fin_solver.capitalize()})"
        for i in range(4):
            rho_c = 1 - bo
            rho_p.value = rho_c
            if prog.problem is None:
                prog.solve(cp.Maximize(outf["margin"]), solver=fin_solver)
            else:
                prog.resolve(solver=fin_solver)
            self.t_solve += prog.solve_time
            outf["rho"].var.value = np.full(outf["rho"].var.shape, rho_c)    # the level checked: rho_c exactly
            checks_ = tuple(prog.check(polish=True))
            rad = max((c.radius for c in checks_ if c.name == "decrease"), default=0.0)
            gram = checks_ + local_robust_checks(outf.get("W"), self.pss, rad)
            self._row(V.degree, f"final margin at backoff {bo:g}{tag}", rho_c, self.volume(V, rho_c),
                      prog.solve_time, prog)
            if all(c.passed for c in gram) or bo >= 0.25 or i == 3:
                break
            self._row(V.degree, f"Gram slack {min(c.slack for c in gram):.2g} at backoff {bo:g}: backing off", rho_c)
            bo = min(3 * bo, 0.25) if bo > 0 else 0.01
        return rho_c, gram, bo

    def certificate(self, t_wall: float, verify: bool = True) -> tuple[ROACertificate, Callable[[], ROACertificate]]:
        """Steps 1-5 from ``V0``: the certificate and a function that returns it verified. With ``verify=False``
        the certificate carries only the checks that cost no sampling (Gram, Hessian, ``A'H + HA``;
        :attr:`ROACertificate.certified` is then False), and the sampling and simulations run when that function
        is called (the first of several remainder-box rounds is verified only if it is the one kept)."""
        V = self.alternate()
        if self.solver.inner != "sos":
            V = self.full_sos_level(V)
        rho_c, gram = self.final_margin(V)
        ps, full, k = self.ps, self.full, self.k
        Vz = from_scaled(V, k)
        scale = k * (ps.scale if ps.scale is not None else 1.0)
        smp = self.sampling

        def made(ver: ROAVerification) -> ROACertificate:
            return ROACertificate(ps if full is None else embed_held(ps, full), Vz, rho_c, 1.0, Vz.degree,
                                  tuple(self.history), ver, self.t_solve, time.perf_counter() - t_wall,
                                  ps.provenance, self.stopped_by, method=ps.method,
                                  scale=np.asarray(scale, dtype=float),
                                  held=() if full is None else tuple(full.names[i] for i in full.held))

        def verified() -> ROACertificate:
            return made(verify_certificate(ps, Vz, rho_c, gram, n_verify=smp.n_verify, n_simulate=smp.n_simulate,
                                           horizon=self.horizon, seed=smp.seed, deadline=self.clock.raising))

        if verify:
            cert = verified()
            return cert, lambda: cert
        hmin, lmax = local_checks(ps, Vz)
        return made(ROAVerification(gram, hmin, lmax, 0, math.nan, 0, 0, self.horizon)), verified
