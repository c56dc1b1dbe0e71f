"""Saturation in the SOS path: the polynomial system of a :class:`~glidectl.models.saturated_loop.SaturatedLoop`
with the exact graph of the saturation as S-procedure terms (:func:`sector_system`, used by
:func:`glidectl.certify_roa` when it is given a SaturatedLoop: ``cert.method == "sos-sector"``).

The loop is ``x' = F(x, v)`` with ``v = sat(u)``, ``u = K x`` (deviations from the equilibrium, the channels with a
finite level; unsaturated channels are substituted, ``v = u``). Each saturated input becomes an extra polynomial
variable ``v`` (``v = u - psi(u)``, ``psi`` the dead zone) that ``V`` does not depend on, and the pair ``(x, v)`` is
restricted to the graph of the saturation by

* ``g1 = (v - lo)(hi - v) >= 0``   (the saturated value is within its levels; ``hi - v`` or ``v - lo`` alone for a
  one-sided saturation),
* ``g2 = (u - v) v >= 0``          (the sector condition ``psi (psi - u) <= 0`` of the dead zone: ``psi = u - v``
  has the sign of ``v``),
* ``h = (u - v) g1 = 0``          (complementarity: either ``v = u`` or ``v`` is at a level).

These describe the graph exactly: with ``v`` strictly inside the levels ``h = 0`` forces ``v = u``; at ``v = hi > 0``
``g2`` forces ``u >= hi``; at ``v = lo < 0`` it forces ``u <= lo``. ``g1, g2`` enter the decrease condition of the
level problem (:mod:`glidectl.roa.programs`) with SOS multipliers and ``h`` with a free polynomial multiplier
(piecewise S-procedure), so ``dV/dt < 0`` is certified for the saturated loop itself, not for a sector bound of it;
the generalized sector condition of the LMI path (``psi (psi - G x) <= 0`` where ``|(K - G) x| <= u0``,
Tarbouriech et al. 2011, Lemma 1.6) is one consequence of these terms.

**Plants that are not polynomial** (the chapter-6 glider loops and the user glider: angles, masses that depend on the
ballast, a matrix inverse): when the plant does not recast exactly into a polynomial in ``(x, v)``
(:func:`~glidectl.roa.systems.recast`), it is replaced by a polynomial surrogate in ``(x, v)`` over the box of the
free states and the range of each saturated input (:func:`~glidectl.roa.surrogate.surrogate_system`: matched to
second order at the equilibrium, with the remainder bound ``a_i |y|^2 + b_i |y|^3`` on that box), and the decrease
condition is the robust one of the surrogate route (``cert.method == "sos-sector+remainder"``). The range of ``v``,
``[max(lo, -reach), min(hi, reach)]`` with ``reach`` the largest ``|K (x - x_e)|`` over the box, holds on the graph
of every point of the box, so it enters as a valid inequality; the box of the free states is a cut (the set lies in
it, where the remainder bound holds).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, ModelError
from ..models.saturated_loop import SaturatedLoop
from .blas_threads import pinned_blas
from .polynomial import Poly
from .surrogate import surrogate_system
from .systems import PolySystem, recast

__all__ = ["sector_system"]


class _Augmented:
    """The plant in ``(x_f - x_f,e, v)`` (free-state deviations, saturated input deviations) as an input-free model
    with ``v' = 0``, equilibrium at 0, for :func:`~glidectl.roa.systems.recast`."""

    def __init__(self, sl: SaturatedLoop, sat: np.ndarray, box_dev: tuple[np.ndarray, np.ndarray]) -> None:
        self._sl, self._sat = sl, sat
        self._f = np.array(sl.free)
        self._uns = np.array([i for i in range(sl.n_feedback) if i not in set(sat.tolist())], dtype=int)
        self.state_names = tuple(sl.state_names[i] for i in sl.free) + tuple(f"sat({sl.feedback_names[i]})"
                                                                           for i in sat)
        self.equilibrium = np.zeros(len(self.state_names))
        # sampled on the box widened 3x (as the exact route of certify_roa): a polynomial is polynomial everywhere
        self.box = (3.0 * box_dev[0], 3.0 * box_dev[1])
        self.name = f"{sl.name} (plant in x and the saturated inputs)"
        self.provenance = sl.provenance
        self.time_unit = sl.time_unit

    def rhs(self, Z: Any) -> np.ndarray:
        sl, f, nf = self._sl, self._f, len(self._f)
        Z = np.asarray(Z)
        X = np.broadcast_to(sl.equilibrium, (*Z.shape[:-1], sl.n)).astype(Z.dtype).copy()
        X[..., f] = sl.equilibrium[f] + Z[..., :nf]
        W = np.zeros((*Z.shape[:-1], sl.n_feedback), dtype=Z.dtype)
        if len(self._uns):
            W[..., self._uns] = (X - sl.equilibrium) @ sl.K[self._uns].T
        W[..., self._sat] = Z[..., nf:]
        out = np.zeros(Z.shape, dtype=np.result_type(Z.dtype, float))
        out[..., :nf] = np.asarray(sl.plant_rhs(X, W))[..., f]
        return out


@pinned_blas
def sector_system(system: Any, *, box_cuts: bool = True, max_degree: int = 4, seed: int = 0, method: str = "auto",
                  surrogate_degree: int = 3, margin: float = 2.0, box: Any = None) -> PolySystem:
    """The polynomial system of a saturated loop in ``z = (lift of x_f - x_f,e, v)`` with the graph of the
    saturation as valid inequalities and equalities (module docstring), for :func:`glidectl.certify_roa`.

    Parameters
    ----------
    system : SaturatedLoop
        The loop (:func:`glidectl.saturated_loop`, or built directly), with a plant ``F(X, w)`` that is polynomial
        in the free states and the saturated inputs (exact) or complex-safe (surrogate). Held states stay at their
        equilibrium values.
    box_cuts : bool
        Restrict the certified set to the loop's box (one cut ``(x_i - lo_i)(hi_i - x_i) >= 0`` per free state), as
        the LMI path does (default); without them only the equilibrium's level set of ``V`` counts. The surrogate
        route always has them (its remainder bound holds on the box only).
    max_degree : int
        Largest degree of the recast polynomial (1 to 8).
    seed : int
        Seed of the recast's and the surrogate's sample points (>= 0).
    method : {"auto", "exact", "surrogate"}
        ``"exact"``: the plant must recast into a polynomial; ``"surrogate"``: a polynomial surrogate with a
        remainder bound (module docstring); ``"auto"`` (default): the exact recast, else the surrogate.
    surrogate_degree : int
        Degree of the surrogate, 2 to 5 (default 3).
    margin : float
        Safety factor (>= 1) of the surrogate's remainder bound.
    box : (array_like, array_like), optional
        Box of the free states (state units) inside the loop's box, containing the equilibrium strictly (default
        the loop's box): a smaller one for a surrogate with a smaller remainder (``certify_roa``'s ``box_search``).

    Returns
    -------
    PolySystem
        States: the free states (``state_names``, ``box``, ``equilibrium``, ``rhs`` the saturated loop
        ``F(X, sat(K (X - X_e)))`` on them, complex-safe); ``inputs`` the indices in ``z`` of the saturated-input
        variables; ``method = "sos-sector"`` (exact plant) or ``"sos-sector+remainder"`` (surrogate plant:
        ``remainder`` and ``remainder_bound`` as for :func:`~glidectl.roa.surrogate.surrogate_system`, ``scale``
        the scale of the free states).

    Raises
    ------
    ArgumentTypeError
        If ``system`` is not a SaturatedLoop, or an option has the wrong type.
    ArgumentError
        If an option is out of range.
    ModelError
        With ``method="exact"``, if the plant is not polynomial in ``(x, v)`` up to ``max_degree`` (the message of
        :func:`~glidectl.roa.systems.recast` names the derivatives that are not); with a surrogate, as
        :func:`~glidectl.roa.surrogate.surrogate_system`; if the loop has no saturating channel (certify the
        closed loop itself with :func:`glidectl.certify_roa`); or if it has state-dependent limits (the graph of a
        clip between state-dependent levels is not modelled here: the LMI path takes them).
    """
    if not isinstance(system, SaturatedLoop):
        raise ArgumentTypeError(f"sector_system() needs a SaturatedLoop (gc.saturated_loop(loop)), got "
                                f"{type(system).__name__}")
    sl = system
    box_cuts = checks.boolean("box_cuts", box_cuts)
    max_degree = checks.integer("max_degree", max_degree, lo=1, hi=8)
    seed = checks.integer("seed", seed, lo=0)
    method = checks.choice("method", method, ("auto", "exact", "surrogate"))
    if sl.limits:
        raise ModelError(f"'{sl.name}' has state-dependent actuator limits ({', '.join(q.label for q in sl.limits)})"
                         ", which the SOS path does not model: certify it with gc.certify_roa(loop) (the LMI path) "
                         "or build the loop with gc.saturated_loop(..., actuator_limits=False)")
    sat = np.flatnonzero(sl.saturating)
    if len(sat) == 0:
        raise ModelError(f"'{sl.name}' has no saturating channel: certify the closed loop itself with "
                         "gc.certify_roa (exact or surrogate route)")
    f = np.array(sl.free)
    nf, ms = len(f), len(sat)
    xe = sl.equilibrium
    lo, hi = (np.array(b, dtype=float) for b in sl.box)
    if box is not None:
        blo = checks.array("box[0]", box[0], shape=(nf,))
        bhi = checks.array("box[1]", box[1], shape=(nf,))
        if np.any(blo < lo[f]) or np.any(bhi > hi[f]) or np.any(blo >= xe[f]) or np.any(bhi <= xe[f]):
            raise ArgumentError(f"box must lie in the loop's box and contain the equilibrium strictly in every free "
                                f"state; got {blo.tolist()} to {bhi.tolist()}")
        lo[f], hi[f] = blo, bhi
    dlo, dhi = lo[f] - xe[f], hi[f] - xe[f]
    # range of each saturated input over the box: its levels, or |K (x - x_e)| where that is smaller
    reach = np.abs(sl.K[sat][:, f]) @ np.maximum(-dlo, dhi)
    vlo = np.maximum(sl.u_lo[sat], -reach)
    vhi = np.minimum(sl.u_hi[sat], reach)
    zbox = (np.concatenate([dlo, vlo]), np.concatenate([dhi, vhi]))
    aug = _Augmented(sl, sat, zbox)
    ps = None
    if method != "surrogate":
        try:
            ps = recast(aug, max_degree=max_degree, seed=seed)
        except ModelError as exc:
            if method == "exact":
                raise ModelError(f"the SOS path with saturation and method 'exact' needs a plant that is polynomial "
                                 f"in the states and the saturated inputs; for '{sl.name}': {exc}. Use method "
                                 "'auto' or 'surrogate' (a polynomial surrogate with a remainder bound), or "
                                 "gc.certify_roa_lmi") from exc
    route = "sos-sector"
    if ps is None:      # a surrogate of the plant in (x, v) on the box and the input ranges (module docstring)
        if np.any(vhi <= vlo):
            raise ModelError(f"'{sl.name}': a saturated input has an empty range over the box ({vlo} to {vhi}): its "
                             "gain is zero on the free states")
        sur = surrogate_system(aug, zbox, degree=surrogate_degree, margin=margin, seed=seed)
        # the cuts of the v variables become valid inequalities (V does not see v; the range holds on the graph)
        ps = dataclasses.replace(sur, cuts=sur.cuts[:nf], valid=sur.cuts[nf:])
        route, box_cuts = "sos-sector+remainder", False     # the x cuts are there already
    nz = ps.nz
    Z = Poly.variables(nz)
    sc = np.ones(nf + ms) if ps.scale is None else np.asarray(ps.scale, dtype=float)
    xs = [Z[ps.slots[k][0]] * float(sc[k]) for k in range(nf)]      # deviations of the free states (state units)
    vi = tuple(ps.slots[nf + a][0] for a in range(ms))
    valid, eqs = list(ps.valid), list(ps.equalities)
    for a, i in enumerate(sat):
        v = Z[vi[a]] * float(sc[nf + a])
        u = sum((float(sl.K[i, f[k]]) * xs[k] for k in range(nf) if sl.K[i, f[k]] != 0.0), Poly({}, nz))
        one = Poly.const(1.0, nz)
        g1 = one
        if np.isfinite(sl.u_hi[i]):
            g1 = g1 * (float(sl.u_hi[i]) * one - v)
        if np.isfinite(sl.u_lo[i]):
            g1 = g1 * (v - float(sl.u_lo[i]) * one)
        valid += [g1, (u - v) * v]
        eqs.append((u - v) * g1)
    cuts = list(ps.cuts)
    if box_cuts:
        cuts += [(xs[k] - float(dlo[k])) * (float(dhi[k]) - xs[k]) for k in range(nf)]
    lift0 = ps.lift

    def X_of(Y: np.ndarray) -> np.ndarray:
        X = np.broadcast_to(xe, (*Y.shape[:-1], sl.n)).astype(Y.dtype).copy()
        X[..., f] = Y
        return X

    def lift(Y: Any) -> np.ndarray:
        Y = np.asarray(Y)
        W = sl.feedback(X_of(Y))[..., sat]            # sat(K (X - X_e)), complex-safe
        return lift0(np.concatenate([Y - xe[f], W], axis=-1))

    def rhs(Y: Any) -> np.ndarray:
        X = X_of(np.asarray(Y))
        return np.asarray(sl.plant_rhs(X, sl.feedback(X)))[..., f]

    return dataclasses.replace(
        ps, name=sl.name, state_names=tuple(sl.state_names[i] for i in f), valid=tuple(valid),
        equalities=tuple(eqs), cuts=tuple(cuts), lift=lift, rhs=rhs, equilibrium=xe[f].copy(),
        box=(lo[f].copy(), hi[f].copy()), slots=tuple(ps.slots[:nf]), inputs=vi, method=route,
        provenance=sl.provenance, time_unit=sl.time_unit)
