"""Routes from a model to the polynomial system that is certified: exact recast, or a polynomial surrogate with a
remainder bound; states held at their equilibrium values; the remainder-box search."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import COMPLEX_STEP, jacobian_batch, jacobians
from ..errors import ArgumentTypeError, ModelError, SolverError
from .certificate import HistoryRow
from .lmi import SaturatedLoop, held_motion, held_points
from .polynomial import Poly
from .programs import (
    LevelResult,
    auto_extra,
    check_memory,
    is_certification_model,
    require_exponential_stability,
    rescaled,
    scaled_field,
    solve_level,
    to_scaled,
    variable_scaling,
)
from .scaling import resolve_box
from .sector import sector_system
from .sos import (
    GramCheck,
)
from .surrogate import (
    refine_equilibrium,
    skeleton,
    surrogate_system,
)
from .systems import PolySystem, recast

__all__ = ["HeldLoop", "ShiftedModel", "box_about", "build_route", "embed_held", "held_states", "local_robust_checks",
           "search_remainder_box", "transport"]

#: Largest monomial basis the automatic route tries to recast a closed loop with before using a surrogate (the
#: least-squares recovery costs seconds per thousand monomials; ``method="exact"`` tries up to degree 4).
_AUTO_RECAST_BASIS = 500



# --------------------------------------------------------------------------------------------- routes
def local_robust_checks(W: Poly | None, ps: PolySystem, radius: float = 0.0) -> tuple[GramCheck, ...]:
    """Surrogate routes: the robust upper bound ``W`` of ``dV/dt`` must be negative on ``0 < |z| <= radius``, the
    ball where the decrease certificate does not speak (its unreachable low-degree residual,
    :attr:`~glidectl.roa.sos.GramCheck.radius`), and negative definite at the equilibrium, else ``{W != 0}`` could
    be ``W > 0`` near it. With ``W = W_2 + W_3 + ...`` (by degree) and ``|z^e| <= |z|^|e|``:
    ``W(z) <= (-mu + sum_{|e| >= 3} |w_e| radius^(|e| - 2)) |z|^2`` there, ``mu`` the smallest eigenvalue of
    ``-W_2``; the entry of the Gram checks has ``min_eig = mu`` and ``max_residual`` the sum. With saturated-input
    variables (``ps.inputs``), ``W`` is taken on the loop's own graph near the equilibrium, where no input saturates:
    ``z = T z_x`` with ``T`` the derivative of ``lift`` there (``v = K x``)."""
    if W is None or not ps.remainder:
        return ()
    P = W
    if ps.inputs:
        xe = np.asarray(ps.equilibrium, dtype=float)
        J = jacobian_batch(ps.lift, xe, COMPLEX_STEP)                          # J[z, x] = d z / d x
        xz = [i for i in range(ps.nz) if i not in set(ps.inputs)]
        T = J @ np.linalg.inv(J[xz])
        Zx = Poly.variables(len(xz))
        P = W.substitute([sum((Zx[j] * float(T[i, j]) for j in range(len(xz)) if T[i, j] != 0.0), Poly({}, len(xz)))
                          for i in range(ps.nz)])
    mu = float(np.linalg.eigvalsh(-P.quadratic_part())[0])
    if not math.isfinite(radius):
        tail = math.inf
    else:
        tail = sum((abs(c) * radius ** (sum(e) - 2) for e, c in P.terms.items() if sum(e) >= 3), 0.0)
        tail += math.inf if any(sum(e) < 2 and c != 0.0 for e, c in P.terms.items()) else 0.0
    return (GramCheck(f"local robust decrease (-quadratic part of the dV/dt bound, within |z| <= {radius:.2g})", 1,
                      mu, tail),)


class ShiftedModel:
    """A closed loop in deviations ``x - x_e`` with its box, for :func:`recast` (equilibrium at 0)."""

    def __init__(self, model: Any, xe: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> None:
        self._f, self._xe = model.rhs, xe
        self.state_names = tuple(model.state_names)
        self.equilibrium = np.zeros(len(xe))
        # the recast is sampled on the box widened 3x about the equilibrium: a smooth non-polynomial field is
        # within 1e-9 of a low-degree polynomial on a small enough box, a polynomial one is polynomial everywhere
        self.box = (3.0 * (box[0] - xe), 3.0 * (box[1] - xe))
        self.name = getattr(model, "name", type(model).__name__)
        self.provenance = str(getattr(model, "provenance", ""))
        self.time_unit = getattr(model, "time_unit", "s")
        for a in ("angle_states", "mixed_angle_states", "positive_state"):
            if hasattr(model, a):
                setattr(self, a, getattr(model, a))

    def rhs(self, X: Any) -> np.ndarray:
        return np.asarray(self._f(np.asarray(X) + self._xe))




def held_states(model: Any, xe: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> tuple[int, ...]:
    """States of a closed loop that never move: the states its law locks (``locked_states`` of its controller, as
    :func:`glidectl.saturated_loop` holds them) and those whose row of the linearization vanishes once the states
    already held are fixed (repeated: ``r_P3' = rdot_P3`` is held once ``rdot_P3`` is), kept only if their derivative
    is zero on box points with them at the equilibrium (:func:`~glidectl.roa.lmi.held_points`,
    :func:`~glidectl.roa.lmi.held_motion`, the check of :func:`glidectl.saturated_loop`): then ``{x_h = x_e,h}`` is
    invariant on the box. Empty if none, or if every state would be held."""
    names = tuple(model.state_names)
    n = len(names)

    def f(X: np.ndarray) -> np.ndarray:
        return np.asarray(model.rhs(X))

    with np.errstate(all="ignore"):
        A = jacobians(lambda x, u: f(x[None, :])[0], xe, np.zeros(0))[0]
    if not np.all(np.isfinite(A)):
        return ()
    ctrl = getattr(getattr(model, "law", None), "__self__", None)
    held = {names.index(q) for q in getattr(ctrl, "locked_states", ()) if q in names}
    tol = 1e-12 * max(1.0, float(np.max(np.abs(A))))
    while True:
        free = [j for j in range(n) if j not in held]
        new = {i for i in free if np.all(np.abs(A[i, free]) <= tol)}
        if not new:
            break
        held |= new
    if not held or len(held) == n:
        return ()
    h = tuple(sorted(held))
    with np.errstate(all="ignore"):
        dX = np.real(f(held_points(box, xe, h)))
    if not np.all(np.isfinite(dX)) or held_motion(dX, h) > 1e-12:
        return ()
    return h


class _Held:
    """A closed loop on its free states, the held ones fixed at their equilibrium values (an input-free model for
    the exact and surrogate routes); angle indices are renumbered."""

    def __init__(self, model: Any, held: tuple[int, ...], xe: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> None:
        names = tuple(model.state_names)
        self._f, self._xe, self._n = model.rhs, np.asarray(xe, dtype=float).copy(), len(names)
        self.free = [i for i in range(len(names)) if i not in held]
        self.state_names = tuple(names[i] for i in self.free)
        self.equilibrium = self._xe[self.free]
        self.box = (box[0][self.free], box[1][self.free])
        self.name = getattr(model, "name", type(model).__name__)
        self.provenance = str(getattr(model, "provenance", ""))
        self.time_unit = getattr(model, "time_unit", "s")
        new = {i: k for k, i in enumerate(self.free)}
        for a in ("angle_states", "mixed_angle_states"):
            if hasattr(model, a):
                setattr(self, a, tuple(new[i] for i in getattr(model, a) if i in new))
        if getattr(model, "positive_state", None) in new:
            self.positive_state = new[model.positive_state]

    def rhs(self, Y: Any) -> np.ndarray:
        Y = np.asarray(Y)
        X = np.broadcast_to(self._xe, (*Y.shape[:-1], self._n)).astype(Y.dtype).copy()
        X[..., self.free] = Y
        return np.asarray(self._f(X))[..., self.free]


@dataclass(frozen=True)
class HeldLoop:
    """The full states of a loop certified on its free states (:class:`_Held`)."""

    names: tuple[str, ...]
    held: tuple[int, ...]
    free: tuple[int, ...]
    equilibrium: np.ndarray
    box: tuple[np.ndarray, np.ndarray]
    rhs: Any

    def with_free_box(self, box: tuple[Any, Any]) -> HeldLoop:
        """The same states with the free states' part of the box replaced by ``box`` (free states' units)."""
        lo, hi = self.box[0].copy(), self.box[1].copy()
        lo[list(self.free)], hi[list(self.free)] = box
        return dataclasses.replace(self, box=(lo, hi))


def embed_held(ps: PolySystem, full: HeldLoop) -> PolySystem:
    """The certified free-state system as a system of all the states (held ones at their equilibrium values): what
    the certificate's contains, value, sample, volume and plot take."""
    free = list(full.free)
    xe = full.equilibrium.copy()
    xe[free] = ps.equilibrium
    lift0 = ps.lift
    return dataclasses.replace(
        ps, state_names=full.names, lift=lambda X: lift0(np.asarray(X)[..., free]), rhs=full.rhs, equilibrium=xe,
        box=(full.box[0].copy(), full.box[1].copy()), held=full.held,
        angle_states=tuple(free[i] for i in ps.angle_states), mixed_states=tuple(free[i] for i in ps.mixed_states))


def box_about(xe: np.ndarray, half: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The box ``xe +- half`` clipped to ``box`` (the remainder-box search and rounds)."""
    return np.maximum(box[0], xe - half), np.minimum(box[1], xe + half)


def transport(V: Poly, ps_from: PolySystem, ps_to: PolySystem) -> Poly:
    """``V`` in the variables of one surrogate system as the same function of the states in another's (both
    ``z = (x - x_e) / s``: only the scales differ)."""
    r = np.asarray(ps_to.scale, dtype=float) / np.asarray(ps_from.scale, dtype=float)
    Z = Poly.variables(ps_to.nz)
    return V.substitute([Z[i] * float(r[i]) for i in range(ps_to.nz)])


def _level_on(ps: PolySystem, V: Poly, *, solver: str, extra: int | None) -> LevelResult:
    """The level problem of ``V`` (in ``ps``'s variables) on ``ps``, built as :func:`certify_roa` builds it."""
    k = variable_scaling(ps)
    pss = rescaled(ps, k)
    return solve_level(pss, scaled_field(pss), to_scaled(V, k), rho_cap=1e6, solver=solver, center=0.0,
                  extra=auto_extra(ps, extra))


def search_remainder_box(ps: PolySystem, rebuild: Callable[[tuple[np.ndarray, np.ndarray]], PolySystem], V0: Poly, *,
                n_boxes: int, solver: str, extra: int | None, history: list[HistoryRow],
                out_of_time: Callable[[str], bool]) -> tuple[PolySystem, Poly]:
    """The remainder-box search of the surrogate routes: the remainder bound holds on the whole box, so a set much
    smaller than the box pays for curvature far away from it. Starting from the box, each round takes the box
    ``x_e +- 3 sqrt(rho) e`` (``e`` the extents of ``{V0 <= 1}``, ``rho`` the best level so far: three times the
    extents of the best set, clipped to the box), builds its surrogate and finds the level of the same ``V0`` (the
    same function of the states) on it (one SDP; the set must lie in that box). Stops when a round does not raise
    the level or the box changes by less than 10 %, after ``n_boxes`` rounds at most (while the level program
    fails, as it can on the whole box, each round takes an 8 times smaller box). Returns the system and ``V0`` (in
    its variables) of the largest level (the box when none was found); the levels are logged in ``history``."""
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    xe = np.asarray(ps.equilibrium, dtype=float)
    idx = [sl[0] for sl in ps.slots]
    Pz = V0.quadratic_part()[np.ix_(idx, idx)]
    sc = np.asarray(ps.scale, dtype=float)[idx]
    ext = np.sqrt(np.diag(np.linalg.inv(Pz / np.outer(sc, sc))))      # extents of {V0 <= 1}, state units
    r = r_box = float(np.max(np.maximum(xe - lo, hi - xe) / ext))       # the box is the search's first one

    def log(step: str, lv: LevelResult | None) -> None:
        history.append(HistoryRow(V0.degree, step, lv.rho if lv else math.nan, math.nan,
                                  lv.solve_time if lv else 0.0, lv.compile_time if lv else 0.0,
                                  lv.solver_time if lv else 0.0))

    best: tuple[float, PolySystem, Poly] = (-math.inf, ps, V0)
    try:
        lv = _level_on(ps, V0, solver=solver, extra=extra)
        log(f"remainder box r = {r:.3g} (the box)", lv)
        best = (lv.rho, ps, V0)
    except SolverError as exc:              # (an ill-conditioned program on the whole box: try smaller ones)
        log(f"remainder box r = {r:.3g} (the box): {exc}", None)
    for _ in range(n_boxes):
        # three times the extents of the best set so far; while no level is known, an 8 times smaller box
        r_new = min(3.0 * math.sqrt(best[0]) if best[0] > 0 else r / 8.0, r_box)
        if abs(math.log(max(r_new, 1e-300) / r)) < 0.1 or out_of_time(f"remainder-box search at r = {r_new:.3g}"):
            break
        r = r_new
        b = box_about(xe, r * ext, (lo, hi))
        try:
            psk = rebuild(b)
            Vk = transport(V0, ps, psk)
            lv = _level_on(psk, Vk, solver=solver, extra=extra)
        except (SolverError, ModelError) as exc:
            log(f"remainder box r = {r:.3g}: {exc}", None)
            if best[0] > 0:
                break
            continue
        log(f"remainder box r = {r:.3g}", lv)
        if not lv.rho > best[0]:
            break
        best = (lv.rho, psk, Vk)
    return best[1], best[2]


def build_route(system: Any, *, box: Any, method: str, surrogate_degree: int, margin: float, speed_floor: float,
                seed: int, degree: int, max_degree: int, limit: float, extra: int | None,
                ) -> tuple[PolySystem, HeldLoop | None, Callable[[tuple[np.ndarray, np.ndarray]], PolySystem] | None]:
    """The PolySystem certified: the system itself, its exact recast, or a surrogate with remainder; when the loop
    has held states (:func:`held_states`), the full states it is embedded in (else None); and, for a surrogate,
    how to build it again on a smaller box of the free states (else None; :func:`search_remainder_box`). Budgets of the
    surrogate route are checked before anything is sampled; a closed loop's linearization on its free states is
    checked for exponential stability before it is recast or a surrogate is built."""
    if isinstance(system, PolySystem):
        return system, None, None
    if isinstance(system, SaturatedLoop):            # saturation in the SOS path: graph of sat as S-procedure terms
        ps = sector_system(system, seed=seed, method=method, surrogate_degree=surrogate_degree, margin=margin)
        if not ps.remainder:
            return ps, None, None
        return ps, None, lambda b: sector_system(system, seed=seed, method="surrogate",
                                                 surrogate_degree=surrogate_degree, margin=margin, box=b)
    names = getattr(system, "state_names", None)
    if names is None or not callable(getattr(system, "rhs", None)):
        raise ArgumentTypeError(f"certify_roa needs a PolySystem or an input-free glidectl model (state_names, rhs, "
                                f"equilibrium), e.g. gc.closed_loop(controller); got {type(system).__name__}")
    if tuple(getattr(system, "input_names", ())):
        raise ArgumentTypeError(f"{type(system).__name__} has inputs {tuple(system.input_names)}: certify_roa needs "
                                "an input-free model with an equilibrium; close the loop first "
                                "(gc.closed_loop(controller) or gc.closed_loop(plant, law))")
    def surrogate_fits(n: int, note: str = "") -> None:
        if method != "exact":
            sk = skeleton(n, surrogate_degree)
            check_memory(sk, degree, auto_extra(sk, extra), max_degree, limit,
                          f"certify_roa(degree={degree}) of a {n}-state surrogate of degree {surrogate_degree}{note}")

    if is_certification_model(system) and box is None:       # a model built for certification: its own box, x_e = 0
        surrogate_fits(len(tuple(names)))
        try:
            if method in ("auto", "exact"):
                return recast(system, speed_floor=speed_floor), None, None
        except ModelError:
            if method == "exact":
                raise

        def build_own(b: Any) -> PolySystem:
            return surrogate_system(system, b, degree=surrogate_degree, margin=margin, seed=seed)
        return build_own(box), None, build_own
    xe0 = getattr(system, "equilibrium", None)
    if xe0 is None:
        raise ModelError(f"'{getattr(system, 'name', type(system).__name__)}' has no equilibrium (None): a region of "
                         "attraction needs one (e.g. closed_loop(plant, law, equilibrium=...))")
    xe0 = checks.array("equilibrium", xe0, shape=(len(tuple(names)),))
    lo, hi = resolve_box(system, box, xe0)
    held = held_states(system, xe0, (lo, hi))
    # the size of the surrogate route counts the free states only (the held ones are not variables of the program)
    surrogate_fits(len(tuple(names)) - len(held),
                   f" ({', '.join(tuple(names)[i] for i in held)} held)" if held else "")
    full = None
    model: Any = system
    if held:
        model = _Held(system, held, xe0, (lo, hi))
        full = HeldLoop(tuple(names), held, tuple(model.free), xe0.copy(), (lo, hi), system.rhs)
        lo, hi = model.box
    xe = refine_equilibrium(lambda X: np.asarray(model.rhs(X)), np.asarray(model.equilibrium, dtype=float))
    # fast refusal: the linearization on the free states, before anything is recast or fitted
    require_exponential_stability(model, jacobians(lambda x, u: np.asarray(model.rhs(x[None, :]))[0], xe,
                                                    np.zeros(0))[0])
    if method in ("auto", "exact"):
        try:
            n = len(xe)
            dmax = max((d for d in range(1, 5) if math.comb(n + d, d) <= _AUTO_RECAST_BASIS), default=1)
            ps = recast(ShiftedModel(model, xe, (lo, hi)), speed_floor=speed_floor,
                        max_degree=4 if method == "exact" else dmax, seed=seed)
            lift0 = ps.lift
            return dataclasses.replace(ps, lift=lambda X: lift0(np.asarray(X) - xe), rhs=model.rhs, equilibrium=xe,
                                       box=(lo, hi)), full, None
        except ModelError:
            if method == "exact":
                raise

    def build(b: Any) -> PolySystem:
        return surrogate_system(model, b, degree=surrogate_degree, margin=margin, seed=seed)
    return build((lo, hi)), full, build
