"""Polynomial systems for region-of-attraction certification, and the exact recasting of glidectl models.

A :class:`PolySystem` is ``dz/dt = F(z) / den(z)`` on the variety ``{h_j(z) = 0}`` intersected with the cuts
``{g_k(z) >= 0}`` (where ``den > 0``), together with the lift ``z = lift(x)`` from the model's states ``x`` and the
model's own right-hand side (the truth every certificate is checked against).

**Exact recasting** (:func:`recast`): each angle state ``x_i`` becomes the pair ``s_i = sin x_i``,
``c_i = 1 - cos x_i`` (zero at the equilibrium) with ``s_i^2 + c_i^2 - 2 c_i = 0``; a model whose right-hand side
has a factor ``1 / (1 + x_j)`` (the glider's ``1/V``) is multiplied by the positive denominator ``1 + x_j`` and the
cut ``1 + x_j - delta >= 0`` keeps it positive. The polynomial ``F`` is not typed in a second time: each state's
derivative (times the denominator) is *recovered from the model's right-hand side* by least squares on the monomial
basis of the quotient ring (``s_i`` at most linear), at the smallest degree that recovers it, which is exact when the
model is polynomial in the lift; the recovery is checked at fresh random points (relative residual ``< 1e-9``, the
largest over the states recorded as ``recast_residual``). The derivatives of the lifted pairs then follow by the
chain rule, ``ds/dt = (1 - c) dx/dt`` and ``dc/dt = s dx/dt`` reduced modulo the equality, so the lift's structure
is exact rather than fitted (:func:`_chain_rule`); a model that is not polynomial in the lift
(e.g. ``sin(alpha)`` together with ``alpha`` for an ``alpha`` not declared a mixed angle, below) is refused with
:class:`~glidectl.errors.ModelError`.

**Taylor-with-remainder route** for an angle that enters both polynomially and through ``sin``/``cos`` (the CTOL
angle of attack: lift and drag polynomial in ``alpha``, forces rotated by ``alpha``): the state is kept *and* lifted,
``(x_i, s_i, c_i)``, and the graph of ``(sin, 1 - cos)`` is enclosed by the Taylor bounds with their remainders,
valid for every real ``x``: ``x (x - s) >= 0``, ``x (s - x + x^3/6) >= 0``, ``x^2/2 - c >= 0``,
``c - x^2/2 + x^4/24 >= 0`` (``valid`` inequalities: S-procedure terms of the decrease condition, nothing to
contain). A certificate then holds for every ``(s, c)`` in the enclosure, the true ``(sin x, 1 - cos x)`` included.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, ModelError
from ..models.saturated_loop import at_held_values
from .polynomial import Poly, field_evaluator, monomial_matrix, monomials, powers_table
from .quotient import AngleQuotient

__all__ = ["PolySystem", "polynomial_system", "recast", "taylor_system"]

#: Largest monomial basis :func:`recast` fits (the design matrix of a bigger least-squares fit takes gigabytes).
_MAX_RECAST_BASIS = 3000


@dataclass(frozen=True)
class PolySystem:
    """``dz/dt = F(z)/den(z)`` with equalities ``h(z) = 0`` and cuts ``g(z) >= 0``, lifted from states ``x``.

    Attributes
    ----------
    name : str
    state_names : tuple of str
        Names of the model's states ``x`` (the coordinates of :meth:`ROACertificate.contains`).
    z_names : tuple of str
        Names of the polynomial variables.
    F : tuple of Poly
        Numerators of the vector field in ``z``.
    den : Poly
        Positive denominator (``1`` for polynomial models).
    equalities, cuts : tuple of Poly
        ``h_j(z) = 0`` (angle pairs) and ``g_k(z) >= 0`` (denominator cut); the certified set lies in the cuts.
    valid : tuple of Poly
        ``v_k(z) >= 0`` on the whole lifted graph (Taylor enclosures of mixed angles); used by the S-procedure only.
    lift : callable
        ``x (N, n) -> z (N, nz)``, complex-safe.
    rhs : callable
        The model's right-hand side ``x (N, n) -> dx/dt (N, n)``.
    equilibrium : ndarray
        Equilibrium in ``x`` (mapped to ``z = 0``).
    angle_states : tuple of int
        Indices of angle states in ``x`` (lifted to ``(s, c)``).
    mixed_states : tuple of int
        Indices of mixed angle states (kept and lifted: ``(x, s, c)``).
    remainder : tuple of Poly
        Surrogate systems only (:func:`~glidectl.roa.surrogate.surrogate_system`): polynomials ``R_i(z) >= 0``
        with ``|dz_i/dt - F_i(z)/den(z)| <= r_i(z) = R_i(z) + b_i q(z)^(3/2)`` for every ``z`` in the cuts (the
        true right-hand side lies within ``r`` of ``F``; ``b = remainder_cubic``, ``q = remainder_norm``); empty
        for exact systems.
    remainder_cubic : tuple of float
        Surrogate systems: the ``b_i >= 0`` of the cubic part of the remainder bound (empty: none).
    remainder_norm : Poly or None
        Surrogate systems: the positive definite quadratic form ``q`` of the cubic part (``|y|^2``).
    method : str
        ``"exact recast"`` (``F`` is the model) or ``"surrogate+remainder"`` (``F`` is a polynomial surrogate and
        ``remainder`` bounds the difference).
    scale : ndarray or None
        Surrogate systems: the state scale ``s`` of ``z = (x - x_e) / s`` (state units); None otherwise.
    remainder_bound : object
        Surrogate systems: the :class:`~glidectl.roa.surrogate.RemainderBound` (how ``remainder`` was bounded).
    inputs : tuple of int
        Saturated loops (:func:`~glidectl.roa.sector.sector_system`): indices in ``z`` of the saturated-input
        variables ``v``; ``V`` and its positivity condition do not involve them. Empty otherwise.
    held : tuple of int
        States held at their equilibrium values (a certificate of :func:`glidectl.certify_roa` for a loop whose
        locked states never move): ``lift`` reads the other states only, ``slots`` are those of the other states,
        and :meth:`in_cuts` holds only with the held states at the equilibrium. Empty otherwise.
    slots : tuple of tuple of int
        For each state of ``x``, the indices of its variables in ``z``.
    s_caps : dict
        ``{index of s_i in z: 1}`` (basis of the quotient ring).
    box : (ndarray, ndarray)
        Region of interest in ``x`` (the enlargement objective and volumes use it).
    recast_residual : float
        Relative residual of the recovered ``F`` at fresh points (``0`` for polynomial systems).
    time_unit : str
    provenance : str
    """

    name: str
    state_names: tuple[str, ...]
    z_names: tuple[str, ...]
    F: tuple[Poly, ...] = field(repr=False)
    den: Poly = field(repr=False)
    equalities: tuple[Poly, ...] = field(repr=False)
    cuts: tuple[Poly, ...] = field(repr=False)
    lift: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    rhs: Callable[[np.ndarray], np.ndarray] = field(repr=False)
    equilibrium: np.ndarray = field(repr=False)
    angle_states: tuple[int, ...] = ()
    s_caps: dict[int, int] = field(default_factory=dict)
    box: tuple[np.ndarray, np.ndarray] = field(default=(np.zeros(0), np.zeros(0)), repr=False)
    recast_residual: float = 0.0
    time_unit: str = "s"
    provenance: str = ""
    valid: tuple[Poly, ...] = field(default=(), repr=False)
    mixed_states: tuple[int, ...] = ()
    slots: tuple[tuple[int, ...], ...] = ()
    # --- surrogate route: remainder polynomials, route, scale, how the remainder was bounded
    remainder: tuple[Poly, ...] = field(default=(), repr=False)
    method: str = "exact recast"
    scale: np.ndarray | None = field(default=None, repr=False)
    remainder_bound: Any = field(default=None, repr=False)
    remainder_cubic: tuple[float, ...] = field(default=(), repr=False)
    remainder_norm: Poly | None = field(default=None, repr=False)
    # --- SOS path with saturation: z-indices of the saturated-input variables (V does not use them)
    inputs: tuple[int, ...] = ()
    # --- held states: indices of states fixed at their equilibrium values (certificates of loops with
    # locked actuators: lift and cuts see the other states; in_cuts requires these at the equilibrium)
    held: tuple[int, ...] = ()

    @property
    def n(self) -> int:
        return len(self.state_names)

    @property
    def nz(self) -> int:
        return len(self.z_names)

    @property
    def degree(self) -> int:
        return max(f.degree for f in self.F)

    def zdot(self, Z: Any) -> np.ndarray:
        """``F(z)/den(z)`` at lifted points ``Z`` (N, nz)."""
        Z = np.asarray(Z)
        d = self.den(Z)
        return np.stack([f(Z) / d for f in self.F], axis=-1)

    def in_cuts(self, X: Any, Z: Any = None) -> np.ndarray:
        """Whether states ``X`` (N, n) satisfy every cut (and hold the held states at their values); ``Z``: their
        lift ``lift(X)`` when the caller has it already (the lift of a saturated loop costs as much as the rest)."""
        X = np.asarray(X, dtype=float)
        Z = self.lift(X) if Z is None else Z
        ok = np.ones(Z.shape[:-1], dtype=bool)
        if self.cuts:       # one powers table for every cut (bitwise each cut's own evaluation)
            dmax = max((max(e) for g in self.cuts for e in g.terms), default=0)
            pw = powers_table(np.asarray(Z), dmax)
            for g in self.cuts:
                ok &= g.on_powers(pw) >= 0
        if self.held:           # held states at their equilibrium values (as the LMI certificate)
            ok &= at_held_values(X, self.equilibrium, self.held)
        return ok


def polynomial_system(name: str, state_names: tuple[str, ...], F: list[Poly], *,
                      box: tuple[Any, Any], time_unit: str = "s", provenance: str = "") -> PolySystem:
    """A polynomial system ``dx/dt = F(x)`` with its equilibrium at ``x = 0`` (no lift, no cuts).

    Parameters
    ----------
    name : str
        Name of the system.
    state_names : sequence of str
        Names of the ``n`` states.
    F : sequence of Poly
        ``n`` polynomials in ``n`` variables, ``F(0) = 0``.
    box : (array_like, array_like)
        Region of interest ``(lo, hi)``, each of shape ``(n,)``, finite, ``lo < hi``.
    time_unit, provenance : str
        Time unit of the system and where it comes from.

    Returns
    -------
    PolySystem
        The system (``lift`` is the identity).

    Raises
    ------
    ArgumentTypeError
        If ``name``, a state name, ``time_unit`` or ``provenance`` is not a string, or ``F`` does not hold Polys.
    ArgumentError
        If the numbers of states and polynomials differ, the origin is not an equilibrium, or ``box`` is invalid.
    """
    for nm, val in (("name", name), ("time_unit", time_unit), ("provenance", provenance)):
        if not isinstance(val, str):
            raise ArgumentTypeError(f"{nm} must be a string, got {type(val).__name__} {val!r}")
    if isinstance(state_names, str) or not all(isinstance(x, str) for x in state_names):
        raise ArgumentTypeError(f"state_names must be a sequence of strings, got {state_names!r}")
    n = len(state_names)
    if n == 0:
        raise ArgumentError("a polynomial system needs at least one state")
    if not all(isinstance(f, Poly) for f in F):
        raise ArgumentTypeError("F must be a sequence of glidectl.roa.Poly")
    if len(F) != n or any(f.nvars != n for f in F):
        raise ArgumentError(f"a polynomial system with {n} states needs {n} polynomials in {n} variables")
    F0 = np.array([f(np.zeros(n)) for f in F])
    if np.max(np.abs(F0)) > 1e-12:
        raise ArgumentError(f"the origin is not an equilibrium of '{name}': F(0) = {F0}")
    Ft = tuple(F)
    field = field_evaluator(Ft)        # one gather and one matrix product per call (hot in the simulations)

    def rhs(X: np.ndarray) -> np.ndarray:
        return field(X)

    lo, hi = _box(box, n)
    return PolySystem(name=name, state_names=tuple(state_names), z_names=tuple(state_names), F=Ft,
                      den=Poly.const(1.0, n), equalities=(), cuts=(), lift=lambda X: np.asarray(X), rhs=rhs,
                      equilibrium=np.zeros(n), box=(lo, hi), time_unit=time_unit, provenance=provenance,
                      slots=tuple((i,) for i in range(n)))


def _box(box: Any, n: int) -> tuple[np.ndarray, np.ndarray]:
    if not isinstance(box, tuple | list) or len(box) != 2:
        raise ArgumentTypeError(f"box must be a pair (lo, hi) of arrays of shape ({n},), got {box!r}")
    lo, hi = checks.array("box lo", box[0], shape=(n,)), checks.array("box hi", box[1], shape=(n,))
    if np.any(lo >= hi):
        raise ArgumentError(f"box must have lo < hi in every state, got lo = {lo.tolist()}, hi = {hi.tolist()}")
    return lo, hi


def recast(model: Any, *, speed_floor: float = 0.1, max_degree: int = 8, seed: int = 0) -> PolySystem:
    """Exact polynomial form of a glidectl model at its equilibrium (see the module docstring).

    Parameters
    ----------
    model : object
        Needs ``state_names``, ``equilibrium`` (``x`` with the equilibrium at ``0``), ``rhs(X)`` (batch, complex
        safe), ``box`` (``(lo, hi)`` region of interest); optionally ``angle_states`` and ``mixed_angle_states``
        (indices), ``positive_state`` (index ``j`` of a state with a ``1/(1 + x_j)`` factor), ``name``,
        ``time_unit`` and ``provenance``.
    speed_floor : float
        ``delta`` of the cut ``1 + x_j - delta >= 0``, in ``(0, 1)``.
    max_degree : int
        Largest degree tried for ``F`` (1 to 12).
    seed : int
        Seed of the random fitting and test points.

    Returns
    -------
    PolySystem
        ``dz/dt = F(z)/den(z)`` in the lifted variables ``z`` with the angle equalities, the denominator cut and the
        Taylor enclosures of mixed angles; ``rhs`` and ``lift`` are the model's own (its states and time unit). A
        ``PolySystem`` argument is returned unchanged.

    Raises
    ------
    ArgumentTypeError
        If ``model`` lacks ``state_names``, ``equilibrium``, ``rhs`` or ``box`` (for example a model with inputs,
        such as ``LongitudinalGlider``: close the loop and use a model built for certification, e.g.
        ``sp.reduced_model()``), or an option has the wrong type.
    ArgumentError
        If ``speed_floor`` is not in ``(0, 1)``, ``max_degree`` or ``seed`` is out of range, or the model's box or
        state indices are invalid.
    ModelError
        If the model is not polynomial in the lift up to ``max_degree`` (relative residual above ``1e-9``).
        Also if the equilibrium is not the origin or a state is listed both as a pure and as a mixed angle.

    Examples
    --------
    >>> import glidectl as gc
    >>> sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    >>> ps = gc.recast(sp.reduced_model())
    >>> ps.state_names, ps.z_names, ps.method
    (('Vbar', 'gammabar'), ('Vbar', 'sin(gammabar)', '1-cos(gammabar)'), 'exact recast')
    """
    if isinstance(model, PolySystem):
        return model
    missing = [a for a in ("state_names", "equilibrium", "rhs", "box") if not hasattr(model, a)]
    if missing or not callable(getattr(model, "rhs", None)):
        raise ArgumentTypeError(f"expected a PolySystem or a model built for certification (state_names, equilibrium "
                                f"at 0, batch rhs(X), box), got {type(model).__name__} without "
                                f"{', '.join(missing) or 'a callable rhs'} (e.g. use sp.reduced_model() or "
                                "ClosedLoopCTOL.roa_model())")
    speed_floor = checks.real("speed_floor", speed_floor, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    max_degree = checks.integer("max_degree", max_degree, lo=1, hi=12)
    seed = checks.integer("seed", seed, lo=0)
    names = tuple(model.state_names)
    n = len(names)
    if n == 0 or not all(isinstance(x, str) for x in names):
        raise ArgumentError(f"the model's state_names must be a non-empty sequence of strings, got {names!r}")
    eq = checks.array("model.equilibrium", model.equilibrium, shape=(n,))
    if np.max(np.abs(eq)) != 0.0:
        raise ModelError(f"recast needs the model in coordinates with the equilibrium at 0; got {eq}")
    angles, mixed, pos = _recast_indices(model, n)
    lo, hi = _box(model.box, n)
    z_names, slot = _lift_layout(names, angles, mixed)
    nz = len(z_names)
    lift = _lift_function(n, angles, mixed)
    equalities, s_caps, valid, den, cuts = _lifted_constraints(nz, slot, angles, mixed, pos, speed_floor)
    rng = np.random.default_rng(seed)
    slo, shi = _sampling_box(lo, hi, angles + mixed, pos, speed_floor)
    sampler = _RecastSampler(model, lift, den, slo, shi, rng)
    # each state's derivative (times den) at the smallest degree that recovers it; every lifted variable's
    # derivative then follows by the chain rule (below), so the lift's structure is exact, not fitted
    G, last, tried = _recover_derivatives(sampler, n, nz, s_caps, max_degree)
    if not last < 1e-9:
        raise ModelError(_refusal(model, names, angles + mixed, pos, slo, shi, tried, last, seed))
    F = _chain_rule(G, slot, angles, mixed, nz)
    return PolySystem(name=getattr(model, "name", type(model).__name__), state_names=names,
                      z_names=tuple(z_names), F=tuple(F), den=den, equalities=equalities, cuts=cuts, lift=lift,
                      rhs=model.rhs, equilibrium=eq, angle_states=angles, s_caps=s_caps, box=(lo, hi),
                      recast_residual=last, time_unit=getattr(model, "time_unit", "s"),
                      provenance=getattr(model, "provenance", ""), valid=tuple(valid), mixed_states=mixed,
                      slots=tuple(slot))


def _recast_indices(model: Any, n: int) -> tuple[tuple[int, ...], tuple[int, ...], int | None]:
    """The model's angle states, mixed angle states and positive state (:func:`recast`), checked."""
    angles = tuple(checks.integer("angle state", i, lo=0, hi=n - 1) for i in getattr(model, "angle_states", ()))
    mixed = tuple(checks.integer("mixed angle state", i, lo=0, hi=n - 1)
                  for i in getattr(model, "mixed_angle_states", ()))
    if set(mixed) & set(angles):
        raise ModelError(f"states {set(mixed) & set(angles)} are listed both as pure and as mixed angles")
    pos = getattr(model, "positive_state", None)
    if pos is not None:
        pos = checks.integer("positive_state", pos, lo=0, hi=n - 1)
    return angles, mixed, pos


def _lift_layout(names: tuple[str, ...], angles: tuple[int, ...],
                 mixed: tuple[int, ...]) -> tuple[list[str], list[tuple[int, ...]]]:
    """The names of the lifted variables ``z`` and, per state, the indices of its variables in ``z``: ``(s, c)``
    for an angle, ``(x, s, c)`` for a mixed angle, ``(x,)`` otherwise."""
    z_names: list[str] = []
    slot: list[tuple[int, ...]] = []
    for i, nm in enumerate(names):
        if i in angles:
            slot.append((len(z_names), len(z_names) + 1))
            z_names += [f"sin({nm})", f"1-cos({nm})"]
        elif i in mixed:
            slot.append((len(z_names), len(z_names) + 1, len(z_names) + 2))
            z_names += [nm, f"sin({nm})", f"1-cos({nm})"]
        else:
            slot.append((len(z_names),))
            z_names.append(nm)
    return z_names, slot


def _lift_function(n: int, angles: tuple[int, ...], mixed: tuple[int, ...]) -> Callable[[Any], np.ndarray]:
    """The lift ``x (..., n) -> z (..., nz)`` of :func:`_lift_layout` (complex-safe)."""

    def lift(X: Any) -> np.ndarray:
        X = np.asarray(X)
        cols = []
        for i in range(n):
            if i in angles:
                cols += [np.sin(X[..., i]), 1.0 - np.cos(X[..., i])]
            elif i in mixed:
                cols += [X[..., i], np.sin(X[..., i]), 1.0 - np.cos(X[..., i])]
            else:
                cols.append(X[..., i])
        return np.stack(cols, axis=-1)

    return lift


def _lifted_constraints(nz: int, slot: list[tuple[int, ...]], angles: tuple[int, ...], mixed: tuple[int, ...],
                        pos: int | None, speed_floor: float
                        ) -> tuple[tuple[Poly, ...], dict[int, int], list[Poly], Poly, tuple[Poly, ...]]:
    """``(equalities, s_caps, valid, den, cuts)`` of the lifted system: the angle equalities
    ``s^2 + c^2 - 2 c = 0``, the quotient basis (each ``s`` at most linear), the Taylor enclosures of the mixed
    angles, the denominator ``1 + x_pos`` (``1`` without a positive state) and its cut ``den - speed_floor >= 0``."""
    Z = Poly.variables(nz)
    pairs = [slot[i][:2] for i in angles] + [slot[i][1:] for i in mixed]
    equalities = tuple(Z[a] ** 2 + Z[b] ** 2 - 2.0 * Z[b] for a, b in pairs)
    s_caps = {a: 1 for a, _ in pairs}
    valid: list[Poly] = []
    for i in mixed:
        x, sn, c = (Z[k] for k in slot[i])
        valid += [x * (x - sn), x * (sn - x + x**3 / 6.0), x**2 / 2.0 - c, c - x**2 / 2.0 + x**4 / 24.0]
    den = Poly.const(1.0, nz) if pos is None else 1.0 + Z[slot[pos][0]]
    cuts = () if pos is None else (den - speed_floor,)
    return equalities, s_caps, valid, den, cuts


def _sampling_box(lo: np.ndarray, hi: np.ndarray, angles: tuple[int, ...], pos: int | None,
                  speed_floor: float) -> tuple[np.ndarray, np.ndarray]:
    """The box :func:`recast` samples its fitting points in: the region of interest, the angles (pure and mixed)
    over a full turn, the positive state above the floor."""
    slo, shi = lo.copy(), hi.copy()
    for i in angles:   # a full turn: (x, sin x, cos x) well separated, so the fit is well conditioned
        slo[i], shi[i] = -np.pi, np.pi
    if pos is not None:
        slo[pos] = max(slo[pos], -1 + speed_floor)
    return slo, shi


@dataclass(frozen=True)
class _RecastSampler:
    """The fitting data of :func:`recast`: states drawn uniformly in the sampling box ``[lo, hi]`` from one random
    stream ``rng`` (shared by the fits and their checks, in the order they run), their lift and the targets
    ``den(z) dx/dt``."""

    model: Any
    lift: Callable[[Any], np.ndarray]
    den: Poly
    lo: np.ndarray
    hi: np.ndarray
    rng: np.random.Generator

    def points(self, count: int) -> np.ndarray:
        """``count`` random states in the sampling box."""
        return self.lo + (self.hi - self.lo) * self.rng.random((count, len(self.lo)))

    def targets(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The lift ``Z`` of ``X`` and the states' derivatives times the denominator, ``den(Z) dx/dt``."""
        Zx = self.lift(X)
        return Zx, np.asarray(self.model.rhs(X)) * self.den(Zx)[:, None]

    def residual(self, G: Poly, i: int) -> float:
        """Relative residual of ``G`` as ``den dx_i/dt`` at 2000 fresh points."""
        Zt, Tt = self.targets(self.points(2000))
        return float(np.max(np.abs(G(Zt) - Tt[:, i])) / max(np.max(np.abs(Tt[:, i])), 1e-300))


def _lstsq_fit(Zx: np.ndarray, T: np.ndarray, basis: list[tuple[int, ...]]) -> np.ndarray:
    """Least-squares coefficients of the monomials ``basis`` fitting ``T`` at ``Zx`` (columns scaled to unit size)."""
    M = monomial_matrix(Zx, basis)
    scale = np.max(np.abs(M), axis=0)
    coef, *_ = np.linalg.lstsq(M / scale, T, rcond=None)
    return coef / scale[:, None]


def _recover_derivatives(sampler: _RecastSampler, n: int, nz: int, s_caps: dict[int, int],
                         max_degree: int) -> tuple[list[Poly], float, int]:
    """``G_i = den dx_i/dt`` of every state as polynomials in ``z`` (:func:`recast`), state by state until one is
    not recovered; also the largest residual and the largest degree tried (for the refusal)."""
    G: list[Poly] = []
    last, tried = 0.0, 0
    for i in range(n):
        best, gi, deg_i = _recover_derivative(sampler, i, nz, s_caps, max_degree)
        tried = max(tried, deg_i)
        last = max(last, best)
        if not best < 1e-9:
            break
        G.append(gi)
    return G, last, tried


def _recover_derivative(sampler: _RecastSampler, i: int, nz: int, s_caps: dict[int, int],
                        max_degree: int) -> tuple[float, Poly | None, int]:
    """``den dx_i/dt`` at the smallest degree whose fit has a relative residual below ``1e-9``: ``(residual, G_i,
    largest degree tried)``, the best fit found if none does (``G_i`` None if no degree fits in memory)."""
    best, gi, tried = np.inf, None, 0
    for deg in range(1, max_degree + 1):
        if math.comb(nz + deg, deg) > _MAX_RECAST_BASIS:    # the fit would not fit in memory: stop trying
            break
        tried = deg
        basis = monomials(nz, deg, 0, s_caps)
        X = sampler.points(max(4 * len(basis), 200))
        Zx, T = sampler.targets(X)
        ck = _lstsq_fit(Zx, T[:, [i]], basis)[:, 0]
        g = Poly(dict(zip(basis, ck, strict=True)), nz)
        res = sampler.residual(g, i)
        if res < 1e-6:
            # exact up to conditioning: keep the support that matters and refit on it (sparse, exact polynomials)
            keep = [e for e, c in zip(basis, ck, strict=True) if abs(c) > 1e-8 * max(np.max(np.abs(ck)), 1e-300)]
            gs = Poly(dict(zip(keep, _lstsq_fit(Zx, T[:, [i]], keep)[:, 0], strict=True)), nz) if keep else Poly({}, nz)
            res_s = sampler.residual(gs, i)
            if res_s < max(res, 1e-12):     # the sparse fit unless it is worse than rounding
                g, res = gs, res_s
        if res < best:
            best, gi = res, g
        if res < 1e-9:
            break
    return best, gi, tried


def _chain_rule(G: list[Poly], slot: list[tuple[int, ...]], angles: tuple[int, ...], mixed: tuple[int, ...],
                nz: int) -> list[Poly]:
    """``den dz/dt`` of every lifted variable from ``G_i = den dx_i/dt`` (:func:`recast`).

    ``d sin x / dt = (1 - c) dx/dt`` and ``d (1 - cos x) / dt = s dx/dt``, reduced modulo ``s^2 + c^2 - 2 c`` (``s``
    at most linear). The structure is exact: ``d(1 - cos x)/dt`` is a multiple of ``s``, so its terms of degree 1
    are in ``c`` alone and the equality multipliers of an SOS program can cancel them. (A least-squares fit of
    ``d(1 - cos x)/dt`` itself picks up small multiples of terms such as ``alpha - sin alpha``, which vanish to third
    order on the graph but not on the lifted variety: linear terms of ``dV/dt`` that no SOS certificate can absorb.)
    """
    Z = Poly.variables(nz)
    F: list[Poly] = [Poly({}, nz)] * nz
    for i, sl in enumerate(slot):
        if i in angles or i in mixed:
            sn, c = sl[-2], sl[-1]
            if i in mixed:
                F[sl[0]] = G[i]
            F[sn] = _reduce_angle((1.0 - Z[c]) * G[i], sn, c)
            F[c] = _reduce_angle(Z[sn] * G[i], sn, c)
        else:
            F[sl[0]] = G[i]
    return F


def _reduce_angle(p: Poly, sn: int, c: int) -> Poly:
    """``p`` modulo ``s^2 + c^2 - 2 c`` with ``s`` at most linear: ``s^(2k + r) = (2c - c^2)^k s^r`` (the normal
    form of :class:`~glidectl.roa.quotient.AngleQuotient`, for one pair in the recast's units)."""
    return AngleQuotient(p.nvars, ((sn, c, -1.0, 2.0),), ()).nf(p)


def taylor_system(system: Any, order: int = 3) -> PolySystem:
    """The Taylor polynomial of a recast model in its own states ``x`` (no lift, no cuts), truncated at ``order``.

    This is what a tool restricted to polynomial dynamics would certify: ``sin``, ``1 - cos`` and ``1/(1 + x_j)``
    replaced by their series. A certificate of it is a certificate of the Taylor model only: the returned system's
    ``rhs`` *is* the Taylor polynomial, so check such a certificate against the model's own ``rhs`` (the
    ``roa_certification`` study counts the certified points where the true ``dV/dt`` is positive).

    Parameters
    ----------
    system : PolySystem or glidectl model
        Recast first with :func:`recast` (default options) if it is not a :class:`PolySystem`.
    order : int
        Total degree at which the series and the products are truncated, in ``[1, 12]``.

    Returns
    -------
    PolySystem
        A polynomial system in the model's states ``x`` (same names, box, time unit and provenance), named
        ``"<name> (Taylor order <order>)"``.

    Raises
    ------
    ArgumentTypeError
        If ``order`` is not an integer, or ``system`` is neither a PolySystem nor a model.
    ArgumentError
        If ``order`` is not in ``[1, 12]``.
    ModelError
        If ``system`` is a model that cannot be recast exactly.

    Examples
    --------
    >>> import glidectl as gc
    >>> sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    >>> ts = gc.taylor_system(sp.reduced_model(), order=3)
    >>> ts.name, ts.z_names                         # polynomial in the states themselves (no sin, cos)
    ('sphere_ch5 reduced (K_M = -50) (Taylor order 3)', ('Vbar', 'gammabar'))
    """
    order = checks.integer("order", order, lo=1, hi=12)
    ps = recast(system)
    n = ps.n
    X = Poly.variables(n)
    subs: list[Poly] = []
    for i in range(n):
        if i in ps.angle_states or i in ps.mixed_states:
            s = Poly({}, n)
            c = Poly({}, n)
            for k in range(1, order + 1):
                term = X[i] ** k / float(np.prod(np.arange(1, k + 1)))
                if k % 2 == 1:
                    s = s + term * (-1.0) ** ((k - 1) // 2)
                else:
                    c = c + term * -((-1.0) ** (k // 2))
            subs += [s, c] if i in ps.angle_states else [X[i], s, c]
        else:
            subs.append(X[i])
    # 1/den as a geometric series in (den - 1)
    d1 = ps.den.substitute(subs) - 1.0
    inv = Poly.const(1.0, n)
    for k in range(1, order + 1):
        inv = inv + (d1 * (-1.0)) ** k

    def trunc(p: Poly) -> Poly:
        return Poly({e: c for e, c in p.terms.items() if sum(e) <= order}, n)

    Fx: list[Poly] = []
    for i, sl in enumerate(ps.slots):
        if i in ps.angle_states:
            s, c = Poly.var(sl[0], ps.nz), Poly.var(sl[1], ps.nz)
            num = (1.0 - c) * ps.F[sl[0]] + s * ps.F[sl[1]]        # gamma' den = (1 - c) s' den + s c' den
        else:
            num = ps.F[sl[0]]                                      # plain or mixed: x itself is a variable
        Fx.append(trunc(trunc(num.substitute(subs)) * trunc(inv)))
    return polynomial_system(f"{ps.name} (Taylor order {order})", ps.state_names, Fx, box=ps.box,
                             time_unit=ps.time_unit, provenance=ps.provenance)


# -------------------------------------------------------------------------------------------------------------- refusal
def _refusal(model: Any, names: tuple[str, ...], angles: tuple[int, ...], pos: int | None, lo: np.ndarray,
             hi: np.ndarray, degree: int, residual: float, seed: int) -> str:
    """The refusal message of :func:`recast`, naming which derivatives depend non-polynomially on which states.

    Probe: along lines through random points of the box, each derivative ``dx_i/dt`` (times the declared positive
    denominator) is fitted by a polynomial of degree ``degree`` in each non-angle state ``x_j`` alone; a relative
    residual above ``1e-9`` (the threshold of the recast itself) marks ``dx_i/dt`` as non-polynomial in ``x_j``
    (an ``atan2``, a state-dependent mass or a matrix inverse shows up this way).
    """
    what = getattr(model, "name", type(model).__name__)
    n = len(names)
    rng = np.random.default_rng(seed + 11)
    t = np.cos(np.pi * (np.arange(24) + 0.5) / 24)            # Chebyshev nodes in [-1, 1]
    deg = max(degree, 1)
    bad: dict[int, list[str]] = {}
    try:
        base = lo + (hi - lo) * rng.random((3, n))
        for j in range(n):
            if j in angles:
                continue
            X = np.repeat(base, t.size, axis=0)
            X[:, j] = np.tile(0.5 * (lo[j] + hi[j]) + 0.5 * (hi[j] - lo[j]) * t, base.shape[0])
            D = np.real(np.asarray(model.rhs(X), dtype=complex))
            if pos is not None:
                D = D * (1.0 + X[:, [pos]])
            V = np.vander(np.tile(t, base.shape[0]), deg + 1)
            for i in range(n):
                for b in range(base.shape[0]):
                    y = D[b * t.size:(b + 1) * t.size, i]
                    c, *_ = np.linalg.lstsq(V[:t.size], y, rcond=None)
                    r = np.max(np.abs(V[:t.size] @ c - y)) / max(np.max(np.abs(y)), 1e-300)
                    if r > 1e-9:
                        bad.setdefault(i, []).append(names[j])
                        break
    except Exception:  # the probe only improves the message; the refusal stands without it
        bad = {}
    if bad:
        terms = "; ".join(f"d({names[i]})/dt in {', '.join(v)}" for i, v in sorted(bad.items()))
        why = (f"these derivatives are not polynomial in these states (e.g. an atan2 angle of attack, masses that "
               f"depend on a state, a matrix inverse): {terms}")
    else:
        why = ("no single non-angle state makes it non-polynomial, so an angle state enters both polynomially and "
               "through sin/cos: declare it in mixed_angle_states (Taylor enclosure)")
    return (f"model '{what}' is not polynomial in the lift (angles {angles} -> (sin, 1 - cos), denominator "
            f"1 + x_{pos}) up to degree {degree}: relative residual {residual:.2e}; {why}. certify_roa(loop, box=...) "
            "certifies such a model through a polynomial surrogate with a remainder bound "
            "(method='surrogate+remainder', glidectl.roa.surrogate)")
