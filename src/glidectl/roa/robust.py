"""Robust region-of-attraction certificates: one ellipsoid shape that holds for every uncertain coefficient of a
vehicle in the box of its ``[uncertainty]`` table, for a saturated loop whose controller keeps its nominal design.

The family
----------
When the coefficients ``p`` move, the controller keeps its gain and set point and the loop's equilibrium moves to
``X_e(p)``. The certified set is therefore a family with a common shape::

    E(p) = X_e(p) + {dX : dX_f' P dX_f <= 1},

each member invariant and in the region of attraction of ``X_e(p)`` for the loop at ``p``. The loop at ``p`` is a
:class:`~glidectl.models.saturated_loop.SaturatedLoop` about its own equilibrium (its fed-back deviation vanishes
there) with the same gain, levels and limit gains; its state-dependent limits have other values at the equilibrium
(the worst, smallest of them over the box is used).

The LMIs (:mod:`glidectl.roa.lmi`)
----------------------------------
Every member is scaled with one half-width vector ``D`` (the largest with ``X_e(p) +- D`` inside the loop's box for
every member computed), so ``x = D^-1 (X - X_e(p))_f`` and the scaled ``W = P^-1`` are common. With ``W``, the sector
multipliers ``S``, ``Z``, the remainder multipliers ``nu`` and the remainder factors common, the decrease LMI is
affine in ``(A, B)``: the LMIs at the ``2^k`` corners of the box (``k`` uncertain coefficients) hold on the convex hull
of the corners' ``[A B]``. ``[A B](p)`` at the moving equilibrium is not affine in ``p``; it is written as the
multilinear interpolation of the corner values, ``sum_v lambda_v(p) [A B]_v`` (``lambda_v >= 0``, summing to 1), plus a
residual. The residual's entrywise maximum over the nominal point and ``n_samples`` points drawn uniformly in the
box, times ``interpolation_margin`` (1.5), enters the remainder bound as a term linear in ``(x, w)``; the Hessian
bound is the entrywise maximum over the same loops. The program has one common slack ``Y >= sum_j W R_j' R_j W /
nu_j`` and small per-corner blocks (the vertex program of :mod:`glidectl.roa.lmi`), solved by Clarabel with
:data:`CLARABEL_SETTINGS`.
Corners whose ``[A B]`` agree to :data:`MERGE_TOLERANCE` share one LMI (their difference joins the linear term): a
box whose corners all merge is the nominal program of :func:`~glidectl.roa.lmi.certify_roa_lmi`.

What it rests on
----------------
The certificate is sampled-sound (``rigorous`` is False): the Hessian bound and the interpolation residual are
sampled maxima with a safety factor, not enclosures. It is verified a posteriori at every corner, at the nominal
coefficients and at every sampled point (:class:`RobustVerification`): the corner LMIs and the region blocks in
floating point, and for each member the interpolated LMI, the remainder bound against the interpolated ``[A B]``,
the true ``dV/dt < 0`` on points of ``E(p)`` and simulations from its boundary converging to ``X_e(p)``.
:meth:`RobustEllipsoidCertificate.verify_by_simulation` repeats the member checks with more simulations at other
vehicles.

Layers: this module takes the loops of the family from a ``member`` function (a vehicle to its saturated loop), so it
does not build controllers' loops itself (the ``roa`` layer does not import ``controllers``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, GlidectlError, ModelError, SolverError, VehicleFileError
from ..models.saturated_loop import SaturatedLoop
from ..params import Vehicle
from .blas_threads import pinned_blas
from .extent import Extent
from .lmi import (
    EllipsoidCertificate,
    EllipsoidSearch,
    EllipsoidVerification,
    ScaledLoop,
    back_off,
    ellipsoid_search,
    scale_loop,
    search_options,
    verify_ellipsoid,
)
from .sdp_solvers import DEFAULT_SOLVER

__all__ = ["BOX_TOLERANCE", "CLARABEL_SETTINGS", "MERGE_TOLERANCE", "RobustEllipsoidCertificate", "RobustVerification",
           "certify_roa_family"]

#: Relative tolerance of a coefficient on the box's faces (:meth:`RobustEllipsoidCertificate.at`).
BOX_TOLERANCE = 1e-12

#: Clarabel's settings for the corner program (solved by Clarabel when the solver is Clarabel or its moment route):
#: ten times Clarabel's default static regularization of its KKT systems. With the default, the program over the
#: slocum loop's 8 corners at +-30 % stops with a numerical error at every remainder box for some samplings (a
#: change of 1e-4 in the box size turns a solved program into a failed one); with this one each solved program is
#: ``optimal`` and the best ellipsoid is as large or larger (slocum +-10 % and +-30 %, buoyancy loop +-10 %).
CLARABEL_SETTINGS: dict[str, Any] = {"static_regularization_constant": 1e-7}

#: Corners whose scaled ``[A B]`` differ by at most this, relative to its largest entry, share one LMI; the
#: difference goes into the linear remainder term (:func:`certify_roa_family`).
MERGE_TOLERANCE = 1e-5


# --------------------------------------------------------------------------------------------- verification
@dataclass(frozen=True)
class RobustVerification:
    """A-posteriori checks of a :class:`RobustEllipsoidCertificate`: the corner LMIs of the program, and one
    :class:`~glidectl.roa.lmi.EllipsoidVerification` per member checked (corners, nominal coefficients, points of the
    box).

    Attributes
    ----------
    keys : tuple of str
        The uncertain coefficients.
    values : ndarray, shape (N, k)
        The coefficients of each member checked (their units).
    kinds : tuple of str
        ``"vertex"``, ``"nominal"`` or ``"sample"`` per member.
    members : tuple of EllipsoidVerification
        Per member: its interpolated decrease LMI (``lmi_max_eig``) and region blocks at the backed-off solution,
        ``W_ii <= 1``, the remainder bound against the interpolated ``[A B]`` on samples of ``E(p)``, the true
        ``dV/dt`` there and simulations from its boundary to ``X_e(p)``.
    lmi_max_eig : float
        Largest eigenvalue of the corners' decrease LMIs at the backed-off solution, in floating point (must be
        < 0; scaled units).
    region_min_eig : float
        Smallest eigenvalue of the region blocks at the worst limit levels (relative to ``max(1, u0^2)``; must be
        >= 0).
    n_invalid : int
        Points drawn in the box that are not valid vehicles (left out).
    """

    keys: tuple[str, ...]
    values: np.ndarray = field(repr=False)
    kinds: tuple[str, ...] = field(repr=False)
    members: tuple[EllipsoidVerification, ...] = field(repr=False)
    lmi_max_eig: float
    region_min_eig: float
    n_invalid: int = 0

    @property
    def n_simulated(self) -> int:
        """Simulations over every member."""
        return sum(m.n_simulated for m in self.members)

    @property
    def n_converged(self) -> int:
        """Those that converged to their member's own equilibrium."""
        return sum(m.n_converged for m in self.members)

    @property
    def max_Vdot(self) -> float:
        """Largest sampled ``dV/dt / |x|^2`` over every member (scaled, per time unit; must be < 0)."""
        return max(m.max_Vdot for m in self.members)

    @property
    def margins(self) -> dict[str, float]:
        """One entry per check, ``>= 1`` when it holds (``inf``/``0`` for pass/fail checks)."""
        inf = math.inf
        ok = sum(m.passed for m in self.members)
        return {"corner LMIs negative definite": inf if self.lmi_max_eig < 0 else 0.0,
                "sector region at the worst levels": inf if self.region_min_eig >= -1e-9 else 0.0,
                "members verified": ok / len(self.members) if self.members else 0.0,
                "simulations converged": self.n_converged / self.n_simulated if self.n_simulated else 1.0}

    @property
    def passed(self) -> bool:
        """Every margin >= 1: the corner LMIs, the region blocks and every member's checks."""
        return not self.failing()

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1."""
        return {k: v for k, v in self.margins.items() if not v >= 1 - 1e-9}

    def summary(self) -> str:
        """A line with the corner checks and the members' totals, and a line per member that fails."""
        ok = sum(m.passed for m in self.members)
        rows = [f"corner LMIs max eig {self.lmi_max_eig:.3g}, region min eig {self.region_min_eig:.3g}; "
                f"{ok}/{len(self.members)} members verified ({self.kinds.count('vertex')} corners), max dV/dt/|x|^2 "
                f"{self.max_Vdot:.3g}, simulations {self.n_converged}/{self.n_simulated} converged"
                + (f"; {self.n_invalid} points of the box are not valid vehicles" if self.n_invalid else "")]
        for kind, vals, m in zip(self.kinds, self.values, self.members, strict=True):
            if not m.passed:
                at = ", ".join(f"{k} = {v:.5g}" for k, v in zip(self.keys, vals, strict=True))
                rows.append(f"  {kind} ({at}) fails {sorted(m.failing())}: {m.summary()}")
        return "\n".join(rows)


# --------------------------------------------------------------------------------------------- certificate
@dataclass(frozen=True)
class RobustEllipsoidCertificate:
    """A family of certified regions of attraction with a common shape over the box of a vehicle's uncertain
    coefficients (:func:`certify_roa_family`): ``E(p) = {X : (X - X_e(p))_f' P (X - X_e(p))_f <= 1, X_held =
    X_e,held}`` for every coefficient vector ``p`` in the box.

    It has the attributes and methods of the certificate protocol (:class:`~glidectl.roa.extent.Certificate`); the
    set they describe (:meth:`contains`, :meth:`sample`, :meth:`volume`, :meth:`extent`) is the member at the nominal
    coefficients, and :meth:`at` gives the member of another vehicle of the box.

    Attributes
    ----------
    system : SaturatedLoop
        The nominal loop.
    member : callable
        Vehicle to its saturated loop at its own equilibrium (the ``member`` of :func:`certify_roa_family`).
    vehicle : Vehicle
        The nominal vehicle with its ``[uncertainty]`` table.
    keys : tuple of str
        The uncertain coefficients.
    coefficient_box : (ndarray, ndarray)
        Their box ``(lo, hi)`` (their units).
    vertex_values : ndarray, shape (2^k, k)
        The corners (binary order, the first key varying slowest).
    vertex_equilibria : ndarray, shape (2^k, n)
        The loop's equilibrium at each corner (state units).
    sample_values : ndarray, shape (N, k)
        The points of the box the interpolation residual and the Hessian bound were sampled at (the nominal
        coefficients first).
    sample_equilibria : ndarray, shape (N, n)
        The equilibria there.
    P : ndarray, shape (nf, nf)
        The common quadratic form in the free states' units (level 1).
    G : ndarray, shape (ms, nf)
        Gain of the generalized sector condition (input units per state unit).
    remainder : ndarray, shape (nf, nf, nf)
        ``Q_j`` of the common remainder bound (scaled), the interpolation residual included.
    remainder_box : ndarray, shape (nf,)
        Half-widths (free states' units) of the box about each member's equilibrium where that bound holds.
    scale : ndarray, shape (nf,)
        The common half-widths ``D`` (scaled ``x = (X - X_e(p))_f / D``).
    vertex_jacobians : ndarray, shape (2^k, nf, nf + m)
        Scaled ``[A B]`` at each corner's equilibrium.
    interpolation_bound : ndarray, shape (nf, nf + m)
        The linear remainder term: the sampled residual of the multilinear interpolation of ``[A B]`` times
        ``interpolation_margin`` (scaled).
    box : (ndarray, ndarray)
        The nominal loop's box (every member lies in it).
    nominal_member : EllipsoidCertificate
        The member at the nominal coefficients, verified (``method = "lmi-robust"``).
    verification : RobustVerification
    search : EllipsoidSearch
        The program's best solution (scaled), its remainder components and history.
    backoff : float
        The certified ``W`` is ``(1 - backoff)`` times the optimum.
    history : tuple of dict
        Per SDP: round, ``rho``, remainder box, status, objective and solver time.
    solve_time, hessian_time, wall_time : float
        SDP solver time, Hessian sampling time and wall time (s).
    method : str
        ``"lmi-robust"``.
    provenance : str
        The vehicle's parameter hash (its uncertainty table included).
    """

    system: SaturatedLoop = field(repr=False)
    member: Callable[[Vehicle], SaturatedLoop] = field(repr=False, compare=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    keys: tuple[str, ...]
    coefficient_box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    vertex_values: np.ndarray = field(repr=False)
    vertex_equilibria: np.ndarray = field(repr=False)
    sample_values: np.ndarray = field(repr=False)
    sample_equilibria: np.ndarray = field(repr=False)
    P: np.ndarray = field(repr=False)
    G: np.ndarray = field(repr=False)
    remainder: np.ndarray = field(repr=False)
    remainder_box: np.ndarray = field(repr=False)
    scale: np.ndarray = field(repr=False)
    vertex_jacobians: np.ndarray = field(repr=False)
    interpolation_bound: np.ndarray = field(repr=False)
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    nominal_member: EllipsoidCertificate = field(repr=False)
    verification: RobustVerification = field(repr=False)
    search: EllipsoidSearch = field(repr=False)
    backoff: float
    history: tuple[dict[str, Any], ...] = field(repr=False)
    solve_time: float
    hessian_time: float
    wall_time: float
    method: str = "lmi-robust"
    provenance: str = ""

    @property
    def certified(self) -> bool:
        """True only if every a-posteriori check passed (:class:`RobustVerification`)."""
        return self.verification.passed

    @property
    def rho(self) -> float:
        """The certified level of ``V`` (1)."""
        return 1.0

    @property
    def rigorous(self) -> bool:
        """False: the Hessian bound and the interpolation residual are sampled over the box (module docstring)."""
        return False

    @property
    def in_box(self) -> bool:
        """Whether every member lies in :attr:`box`: always (the common half-widths keep them in it)."""
        return True

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.system.state_names

    # ---- the set at the nominal coefficients (the protocol)
    def extent(self) -> Extent:
        """The certified interval along each state axis through the nominal equilibrium (state units): ``x_e +- 1 /
        sqrt(P_kk)`` for a free state (the same half-widths about every member's equilibrium), ``x_e`` for a held
        one; comparable with the nominal certificate's :meth:`~glidectl.roa.lmi.EllipsoidCertificate.extent`.

        Returns
        -------
        Extent
        """
        e = self.nominal_member.extent()
        return dataclasses.replace(e, box=self.box, what=f"certified ({self.method}, every coefficient in the box "
                                   f"of {', '.join(self.keys)})", rigorous=self.rigorous)

    def contains(self, X: Any) -> np.ndarray:
        """Membership of the member at the nominal coefficients (:meth:`EllipsoidCertificate.contains`).

        Parameters
        ----------
        X : array_like, shape (N, n) or (n,)
            States; NaN or inf are outside.

        Returns
        -------
        ndarray of bool, shape (N,)

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``X`` is not numeric or has the wrong shape.
        """
        return self.nominal_member.contains(X)

    def sample(self, n: int, seed: int = 0, *, boundary: bool = False) -> np.ndarray:
        """``n`` states of the member at the nominal coefficients (uniform in it, or on its boundary).

        Parameters
        ----------
        n : int
            Number of points (>= 1).
        seed : int
            Seed (>= 0).
        boundary : bool
            On the boundary ``V = 1``.

        Returns
        -------
        ndarray, shape (n, n_states)

        Raises
        ------
        ArgumentTypeError, ArgumentError
            For a bad ``n``, ``seed`` or ``boundary``.
        """
        return self.nominal_member.sample(n, seed, boundary=boundary)

    def volume(self) -> float:
        """Volume of every member in the free states (product of their units; they share ``P``).

        Returns
        -------
        float
        """
        return self.nominal_member.volume()

    # ---- the family
    def at(self, vehicle: Vehicle, *, n_verify: int = 1000, n_simulate: int = 4, seed: int = 0
           ) -> EllipsoidCertificate:
        """The member of a vehicle of the box: the ellipsoid of shape :attr:`P` about its loop's equilibrium, as a
        certificate of that loop, verified on it (its interpolated decrease LMI, the remainder bound, sampled
        ``dV/dt``, simulations).

        Parameters
        ----------
        vehicle : Vehicle
            The nominal vehicle with other values of :attr:`keys` inside :attr:`coefficient_box` (e.g. from
            ``vehicle.sample`` or ``vehicle.with_overrides``).
        n_verify, n_simulate : int
            Points of the ellipsoid checked (>= 2, half on the boundary) and simulations from its boundary (>= 0,
            at most ``n_verify // 2``).
        seed : int
            Seed of the points (>= 0).

        Returns
        -------
        EllipsoidCertificate
            ``method = "lmi-robust"``; its ``system`` is the vehicle's loop in the box ``X_e(p) +- scale``.

        Raises
        ------
        ArgumentTypeError
            If ``vehicle`` is not a Vehicle.
        ArgumentError
            If its coefficients other than :attr:`keys` differ from the nominal vehicle's, or one of :attr:`keys` is
            outside the box.
        ModelError
            If its loop has no equilibrium near the nominal one, or its equilibrium lies closer to the loop's box
            than :attr:`scale` (the sampled family did not reach that far).
        """
        n_verify = checks.integer("n_verify", n_verify, lo=2, hi=2**22)
        n_simulate = checks.integer("n_simulate", n_simulate, lo=0, hi=n_verify // 2)
        seed = checks.integer("seed", seed, lo=0)
        values = self._coefficients(vehicle)
        sl = _member_loop(self.member, vehicle, values, self.keys, "vehicle")
        _check_form(self.system, sl, values, self.keys)
        room = _room(self.system, sl)
        if np.any(room < self.scale * (1 - 1e-12)):
            raise ModelError(f"the equilibrium of this vehicle's loop lies closer to the box than the family's "
                             f"half-widths (room {room.tolist()} < {self.scale.tolist()}): it is outside what was "
                             "sampled; certify again with more samples (n_samples)")
        sc = _interpolated(scale_loop(_reboxed(sl, self.scale), self.scale), self._weights(values[None, :])[0],
                           self.vertex_jacobians)
        return self._member_certificate(sl, sc, n_verify=n_verify, n_simulate=n_simulate, seed=seed)

    def verify_by_simulation(self, n_vehicles: int = 20, n_points: int = 16, seed: int = 1) -> RobustVerification:
        """The member checks of :meth:`at` at every corner of the box and at ``n_vehicles`` vehicles drawn uniformly
        in it, with ``n_points`` simulations from each member's boundary: the fraction converging to their own
        equilibria is ``n_converged / n_simulated``.

        Parameters
        ----------
        n_vehicles : int
            Vehicles drawn in the box (>= 0; those that are not valid vehicles are counted in ``n_invalid``).
        n_points : int
            Simulations per member (>= 1).
        seed : int
            Seed of the vehicles and the points (>= 0).

        Returns
        -------
        RobustVerification

        Raises
        ------
        ArgumentTypeError, ArgumentError
            For bad arguments.
        ModelError
            As :meth:`at`, for a drawn vehicle.
        """
        n_vehicles = checks.integer("n_vehicles", n_vehicles, lo=0, hi=10**5)
        n_points = checks.integer("n_points", n_points, lo=1, hi=2**14)
        seed = checks.integer("seed", seed, lo=0)
        vals, vehicles, n_invalid = _box_vehicles(self.vehicle, self.keys, self.coefficient_box, n_vehicles, seed)
        rows = [(v, veh, "vertex") for v, veh in zip(self.vertex_values, self._vertex_vehicles(), strict=True)]
        rows += [(v, veh, "sample") for v, veh in zip(vals, vehicles, strict=True)]
        n_verify = max(400, 2 * n_points)
        ver = [self.at(veh, n_verify=n_verify, n_simulate=n_points, seed=seed + i).verification
               for i, (_, veh, _) in enumerate(rows)]
        return RobustVerification(self.keys, np.array([r[0] for r in rows]).reshape(len(rows), len(self.keys)),
                                  tuple(r[2] for r in rows), tuple(ver), self.verification.lmi_max_eig,
                                  self.verification.region_min_eig, n_invalid)

    def extent_ratio(self, other: Any) -> np.ndarray:
        """This certificate's extent over another's per state axis (e.g. the nominal
        :func:`~glidectl.roa.lmi.certify_roa_lmi` certificate's): the smaller of the two directions' ratios, NaN where
        ``other`` has no extent (held states).

        Parameters
        ----------
        other : Certificate or Extent

        Returns
        -------
        ndarray, shape (n,)

        Raises
        ------
        ArgumentError
            If the two are not of the same states.
        """
        ext = other if isinstance(other, Extent) else other.extent()
        below, above = self.extent().ratio(ext)
        return np.fmin(below, above)

    def summary(self) -> str:
        """The box, the common half-widths per free state, the verification and the times."""
        lo, hi = self.coefficient_box
        f = list(self.system.free)
        half = 1.0 / np.sqrt(np.diag(self.P))
        status = "verified" if self.certified else "NOT verified"
        rows = [f"{self.system.name}: robust LMI region of attraction ({status}, sampled-sound)",
                "  box: " + ", ".join(f"{k} in [{a:.5g}, {b:.5g}]" for k, a, b in zip(self.keys, lo, hi, strict=True))
                + f" ({len(self.vertex_values)} corners, {len(self.sample_values)} interior points)",
                "  half-widths about every X_e(p): " + ", ".join(f"{self.state_names[i]} {h:.4g}"
                                                               for i, h in zip(f, half, strict=True)),
                f"  interpolation residual bound max {np.max(self.interpolation_bound, initial=0.0):.3g} (scaled); "
                f"{len(self.history)} SDPs, solver {self.solve_time:.1f} s, Hessians {self.hessian_time:.1f} s, "
                f"wall {self.wall_time:.1f} s",
                "  " + self.verification.summary().replace("\n", "\n  ")]
        return "\n".join(rows)

    def plot(self, ax: Any = None, dims: Any = (0, 1), n: int = 200, vertices: int = 4) -> Any:
        """Slices through their equilibria of the member at the nominal coefficients and of ``vertices`` corner
        members (those farthest from the nominal equilibrium in the metric of ``P``), in the plane of two free
        states, with every corner's equilibrium (the loop's box, usually far larger, is not drawn).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        dims : two state names or indices
            The plane (free states).
        n : int
            Points of each boundary (>= 8).
        vertices : int
            Corner members drawn (>= 0).

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn into (angles in degrees).

        Raises
        ------
        GlidectlError
            For ``dims`` that are not two distinct free states, ``n < 8`` or ``vertices < 0``.
        """
        from ..plotting import style

        with style():
            return _draw(self, ax, dims, n, vertices)

    # ---- helpers
    def _coefficients(self, vehicle: Vehicle) -> np.ndarray:
        """The values of :attr:`keys` of ``vehicle``, checked to be the nominal vehicle's elsewhere and in the box."""
        if not isinstance(vehicle, Vehicle):
            raise ArgumentTypeError(f"vehicle must be a Vehicle, got {type(vehicle).__name__}")
        nom, got = dict(self.vehicle.params), dict(vehicle.params)
        other = sorted(k for k in set(nom) | set(got) if k not in self.keys and nom.get(k) != got.get(k))
        if other:
            raise ArgumentError(f"vehicle '{vehicle.name}' differs from the nominal vehicle in {other}, which are not "
                                f"uncertain coefficients of the certificate ({', '.join(self.keys)})")
        values = np.array([float(got[k]) for k in self.keys])
        lo, hi = self.coefficient_box
        tol = BOX_TOLERANCE * np.maximum(1.0, np.abs(values))
        out = [f"{k} = {v:.6g} not in [{a:.6g}, {b:.6g}]" for k, v, a, b, t in
               zip(self.keys, values, lo, hi, tol, strict=True) if not a - t <= v <= b + t]
        if out:
            raise ArgumentError(f"vehicle '{vehicle.name}' is outside the certified box: {'; '.join(out)}")
        return np.clip(values, lo, hi)

    def _weights(self, values: np.ndarray) -> np.ndarray:
        return _multilinear_weights(values, self.coefficient_box, self.vertex_values)

    def _vertex_vehicles(self) -> list[Vehicle]:
        return [self.vehicle.with_overrides(**dict(zip(self.keys, map(float, v), strict=True)))
                for v in self.vertex_values]

    def _member_certificate(self, sl: SaturatedLoop, sc: ScaledLoop, *, n_verify: int, n_simulate: int,
                            seed: int) -> EllipsoidCertificate:
        return _member_certificate(sl, sc, self.search, self.backoff, self.history, self.provenance,
                                   n_verify=n_verify, n_simulate=n_simulate, seed=seed)


# --------------------------------------------------------------------------------------------- the driver
@pinned_blas
def certify_roa_family(system: Any, member: Callable[[Vehicle], SaturatedLoop], vehicle: Vehicle | None = None, *,
                       max_vertices: int = 64, n_samples: int = 16, seed: int = 0,
                       interpolation_margin: float = 1.5, hessian_margin: float = 1.5, n_hessian: int = 512,
                       n_radii: int = 8, refine: int = 5, rounds: int = 4, round_gain: float = 0.1,
                       backoff: float = 0.01, n_verify: int = 1000, n_simulate: int = 4,
                       horizon: float | None = None, solver: str = DEFAULT_SOLVER) -> RobustEllipsoidCertificate:
    """Largest ellipsoid shape certified about the moving equilibrium for every uncertain coefficient in the box of a
    vehicle's ``[uncertainty]`` table (module docstring): corner LMIs with a common ``W``, sector multipliers and
    remainder factors, the worst limit levels, and the sampled multilinear-interpolation residual of ``[A B]`` as a
    linear remainder term.

    Parameters
    ----------
    system : SaturatedLoop
        The nominal loop (:func:`glidectl.saturated_loop` of a closed loop; state feedback, as the LMI path of
        :func:`~glidectl.roa.lmi.certify_roa_lmi` takes it).
    member : callable
        ``member(vehicle) -> SaturatedLoop``: the same controller's loop on another vehicle of the box, at that
        loop's own equilibrium, extracted as ``system`` was (the same states, fed-back channels, gain, levels, limit
        gains). For a glidectl closed loop ``loop``::

            def member(v):
                lv = gc.with_vehicle(loop, v)                                   # the nominal law kept
                xe = gc.loop_poles(lv, loop.equilibrium, system.free).equilibrium
                return gc.saturated_loop(gc.ClosedLoop(lv.plant, lv.law, xe, lv.description))

    vehicle : Vehicle, optional
        The nominal vehicle with an ``[uncertainty]`` table (default ``system.vehicle``, which must then have one).
    max_vertices : int
        Most corners accepted (>= 2): all ``2^k`` corners are needed.
    n_samples : int
        Points drawn uniformly in the box (>= 0) where the interpolation residual and the Hessians are sampled and
        the certificate verified, beside the corners and the nominal coefficients.
    seed : int
        Seed of those points and of every sampling (>= 0).
    interpolation_margin : float
        Safety factor (>= 1) on the sampled interpolation residual.
    hessian_margin, n_hessian, n_radii, refine, rounds, round_gain, backoff, n_verify, n_simulate, horizon, solver
        As :func:`~glidectl.roa.lmi.certify_roa_lmi` (``n_hessian`` samples per loop, ``n_verify`` points and
        ``n_simulate`` simulations per member verified).

    Returns
    -------
    RobustEllipsoidCertificate
        ``rigorous`` is False; ``certified`` says whether every check at every member passed.

    Raises
    ------
    ArgumentTypeError
        If ``system`` is not a SaturatedLoop (a closed loop, an output-feedback loop: the message says what to
        give), ``member`` is not callable, ``vehicle`` is not a Vehicle, or an option has the wrong type.
    ArgumentError
        If the vehicle has no ``[uncertainty]`` table or other coefficients than the loop's vehicle, ``2^k >
        max_vertices``, ``member`` returns a loop of another form, or an option is out of range.
    ModelError
        If the box is too wide for a common certificate before any program: a corner is not a valid vehicle, a loop
        of the box has no equilibrium near the nominal one or leaves the loop's box, or a corner's linearized loop
        is not exponentially stable (the message says to try a smaller box).
    SolverError
        If no common ellipsoid is certified (the box is too wide for one shape: try a smaller box).

    Examples
    --------
    >>> import glidectl as gc
    >>> from glidectl.robustness.certificates import ControllerMember
    >>> veh = gc.load_vehicle("sphere_ch5").with_uncertainty({"K_D0": {"rel": 0.05}})
    >>> loop = gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0))
    >>> sl = gc.saturated_loop(loop)
    >>> cert = gc.certify_roa_family(sl, ControllerMember(loop, sl.free), rounds=1, n_radii=4, refine=1,
    ...                              n_samples=2, n_hessian=128, n_verify=200, n_simulate=2)
    >>> cert.certified, cert.keys
    (True, ('K_D0',))
    """
    t_wall = time.perf_counter()
    opts = search_options(hessian_margin=hessian_margin, n_hessian=n_hessian, n_radii=n_radii, refine=refine,
                          rounds=rounds, round_gain=round_gain, backoff=backoff, solver=solver, seed=seed)
    backoff, seed = opts["backoff"], opts["seed"]
    max_vertices, n_samples, interpolation_margin, n_verify, n_simulate = _options(
        system, member, max_vertices, n_samples, interpolation_margin, n_verify, n_simulate, horizon)
    veh = _vehicle(system, vehicle)
    fam = _family(system, member, veh, max_vertices, n_samples, seed)
    nv, keys, box = fam.nv, fam.keys, fam.box
    corners = _corner_systems(fam.scaled, fam.values, box, nv, interpolation_margin)
    search = ellipsoid_search(corners.common, vertices=corners.vertices, hessian_systems=fam.scaled,
                              linear=corners.linear,
                              clarabel_settings=CLARABEL_SETTINGS if corners.vertices is not None else None, **opts)
    if not search.found:
        raise SolverError(f"no common ellipsoid is certified for '{system.name}' over the box of {', '.join(keys)} "
                          f"({', '.join(f'[{a:.4g}, {b:.4g}]' for a, b in zip(*box, strict=True))}): every SDP "
                          f"was infeasible or failed (statuses {sorted({h['status'] for h in search.history})}). The "
                          "box is too wide for one shape at every corner; try a smaller box (a smaller 'rel' in the "
                          "[uncertainty] table) or fewer uncertain coefficients")
    sol = back_off(corners.common, search.solution, search.p_idx, backoff, vertices=corners.vertices)
    lam = _multilinear_weights(fam.values, box, fam.values[:nv])
    members = [_member_certificate(sl, _interpolated(sc, w, corners.jacobians), search, backoff, search.history,
                                   veh.provenance, n_verify=n_verify, n_simulate=n_simulate, horizon=horizon,
                                   seed=seed + i)
               for i, (sl, sc, w) in enumerate(zip(fam.loops, fam.scaled, lam, strict=True))]
    kinds = ("vertex",) * nv + ("nominal",) + ("sample",) * (len(fam.loops) - nv - 1)
    ver = RobustVerification(keys, fam.values, kinds, tuple(m.verification for m in members), sol.lmi_max_eig,
                             sol.region_min_eig, fam.n_invalid)
    eq = np.array([sl.equilibrium for sl in fam.loops])
    return RobustEllipsoidCertificate(
        system, member, veh, keys, box, fam.values[:nv], eq[:nv], fam.values[nv:], eq[nv:], sol.P, sol.G, sol.Q,
        sol.remainder.b * fam.d, fam.d, corners.jacobians, corners.linear, system.box, members[nv], ver, search,
        backoff, search.history, search.solve_time, search.hessian_time, time.perf_counter() - t_wall, "lmi-robust",
        veh.provenance)


@dataclass(frozen=True)
class _Family:
    """The loops of the family: the corners (binary order), the nominal loop, the points drawn in the box; their
    coefficients, the common half-widths ``d`` and the loops scaled with them."""

    keys: tuple[str, ...]
    box: tuple[np.ndarray, np.ndarray]
    values: np.ndarray
    nv: int
    loops: list[SaturatedLoop]
    scaled: list[ScaledLoop]
    d: np.ndarray
    n_invalid: int


def _family(system: SaturatedLoop, member: Callable[[Vehicle], SaturatedLoop], veh: Vehicle, max_vertices: int,
            n_samples: int, seed: int) -> _Family:
    """Every loop of the family, checked to be of the nominal loop's form, its equilibrium inside the box, its
    corners' linearizations stable (ModelError: the box is too wide), all scaled with the common ``d``."""
    keys, box, corner_veh, vals, samples, n_invalid = _box(veh, max_vertices, n_samples, seed)
    loops = [_member_loop(member, v, c, keys, "corner") for v, c in zip(corner_veh, vals, strict=True)]
    loops.append(system)
    loops += [_member_loop(member, v, c, keys, "point") for v, c in zip(samples[1], samples[0], strict=True)]
    values = np.concatenate([vals, _nominal_values(veh, keys)[None, :], samples[0]])
    for sl, c in zip(loops, values, strict=True):
        _check_form(system, sl, c, keys)
    d = np.min([_room(system, sl) for sl in loops], axis=0)
    if not np.all(d > 0):
        raise ModelError(f"the box of {', '.join(keys)} is too wide: an equilibrium of the family leaves the box of "
                         f"'{system.name}' in {[system.state_names[i] for i in np.array(system.free)[d <= 0]]}; try "
                         "a smaller box")
    scaled = [scale_loop(_reboxed(sl, d), d) for sl in loops]
    nv = len(vals)
    _check_corners(scaled[:nv], values[:nv], keys)
    return _Family(keys, box, values, nv, loops, scaled, d, n_invalid)


# --------------------------------------------------------------------------------------------- helpers
def _options(system: Any, member: Any, max_vertices: Any, n_samples: Any, interpolation_margin: Any, n_verify: Any,
             n_simulate: Any, horizon: Any) -> tuple[int, int, float, int, int]:
    """Refuse what is not a saturated loop and bad options of the robust driver (the search's are
    :func:`~glidectl.roa.lmi.search_options`'): ``max_vertices``, ``n_samples``, ``interpolation_margin``,
    ``n_verify``, ``n_simulate`` validated."""
    if not isinstance(system, SaturatedLoop):
        raise ArgumentTypeError(f"certify_roa_family() needs the saturated loop of a state-feedback controller, got "
                                f"{type(system).__name__}: pass gc.saturated_loop(loop) (it refuses loops of another "
                                "form, e.g. output feedback, whose estimator keeps the nominal vehicle) and a member "
                                "function giving that loop on another vehicle")
    checks.function("member", member)
    if horizon is not None:
        checks.positive("horizon", horizon)
    return (checks.integer("max_vertices", max_vertices, lo=2, hi=2**20),
            checks.integer("n_samples", n_samples, lo=0, hi=10**5),
            checks.real("interpolation_margin", interpolation_margin, lo=1.0),
            checks.integer("n_verify", n_verify, lo=2, hi=2**22),
            checks.integer("n_simulate", n_simulate, lo=0, hi=2**16))


def _vehicle(system: SaturatedLoop, vehicle: Vehicle | None) -> Vehicle:
    """The nominal vehicle with its uncertainty table, checked against the loop's."""
    veh = system.vehicle if vehicle is None else vehicle
    if veh is None:
        raise ArgumentError(f"'{system.name}' has no vehicle: give vehicle= (with an [uncertainty] table)")
    if not isinstance(veh, Vehicle):
        raise ArgumentTypeError(f"vehicle must be a Vehicle, got {type(veh).__name__}")
    if system.vehicle is not None and dict(veh.params) != dict(system.vehicle.params):
        raise ArgumentError(f"vehicle '{veh.name}' does not have the coefficients of the loop's vehicle "
                            f"'{system.vehicle.name}': give the loop's vehicle with its [uncertainty] table "
                            "(veh.with_uncertainty(...))")
    if not veh.uncertainty:
        raise ArgumentError(f"vehicle '{veh.name}' has no [uncertainty] table, so there is no box of coefficients "
                            "to certify over: add one to its file, or pass vehicle=veh.with_uncertainty({...}) "
                            "(gc.certify_roa_lmi certifies the nominal loop alone)")
    return veh


def _nominal_values(veh: Vehicle, keys: tuple[str, ...]) -> np.ndarray:
    return np.array([float(veh.params[k]) for k in keys])


def _box(veh: Vehicle, max_vertices: int, n_samples: int, seed: int
         ) -> tuple[tuple[str, ...], tuple[np.ndarray, np.ndarray], list[Vehicle], np.ndarray,
                    tuple[np.ndarray, list[Vehicle]], int]:
    """The keys, the box, the corner vehicles and values, the points drawn in the box (values, vehicles) and how
    many drawn points were not valid vehicles."""
    k = len(veh.uncertainty)
    if 2**k > max_vertices:
        raise ArgumentError(f"{k} uncertain coefficients have 2^{k} = {2**k} corners, more than max_vertices = "
                            f"{max_vertices}: the certificate needs an LMI at every corner (raise max_vertices, or "
                            "keep fewer coefficients in the [uncertainty] table)")
    corners = veh.vertices(max_vertices, seed)
    bad = [(row, err) for row, err in zip(corners.values, corners.errors, strict=True) if err is not None]
    if bad:
        row, err = bad[0]
        at = ", ".join(f"{key} = {v:.5g}" for key, v in zip(corners.keys, row, strict=True))
        raise ModelError(f"the box of {', '.join(corners.keys)} is too wide: its corner ({at}) is not a valid vehicle "
                         f"({err}); try a smaller box")
    vals = np.array(corners.values, dtype=float)
    box = (vals.min(axis=0), vals.max(axis=0))
    s_vals, s_veh, n_invalid = _box_vehicles(veh, corners.keys, box, n_samples, seed)
    return corners.keys, box, list(corners.vehicles), vals, (s_vals, s_veh), n_invalid


def _box_vehicles(veh: Vehicle, keys: tuple[str, ...], box: tuple[np.ndarray, np.ndarray], n: int,
                  seed: int) -> tuple[np.ndarray, list[Vehicle], int]:
    """``n`` points drawn uniformly in the box (``default_rng([seed, 7])``): the values and vehicles of the valid
    ones, and how many were not valid vehicles."""
    lo, hi = box
    U = np.random.default_rng([seed, 7]).random((n, len(keys)))
    vals, vehicles = [], []
    for row in lo + (hi - lo) * U:
        try:
            vehicles.append(veh.with_overrides(**dict(zip(keys, map(float, row), strict=True))))
            vals.append(row)
        except VehicleFileError:
            continue
    return np.array(vals, dtype=float).reshape(len(vals), len(keys)), vehicles, n - len(vals)


def _member_loop(member: Callable[[Vehicle], SaturatedLoop], veh: Vehicle, values: np.ndarray,
                 keys: tuple[str, ...], what: str) -> SaturatedLoop:
    """``member(veh)``, its failures said as the box being too wide (a loop of another form passes unchanged)."""
    try:
        sl = member(veh)
    except (ArgumentTypeError, ArgumentError):
        raise
    except GlidectlError as exc:
        at = ", ".join(f"{k} = {v:.5g}" for k, v in zip(keys, values, strict=True))
        raise ModelError(f"the loop at the {what} ({at}) of the box has no certificate: {type(exc).__name__}: {exc}. "
                         "The box is too wide for a common certificate; try a smaller box") from exc
    if not isinstance(sl, SaturatedLoop):
        raise ArgumentTypeError(f"member(vehicle) must return a SaturatedLoop, got {type(sl).__name__}")
    return sl


def _check_form(nominal: SaturatedLoop, sl: SaturatedLoop, values: np.ndarray, keys: tuple[str, ...]) -> None:
    """ArgumentError unless ``sl`` is a loop of the same form as ``nominal``: states, channels, held states, gain,
    constant levels, and limits of the same channels, sides and gains (their values at the equilibrium may
    differ)."""
    same = (sl.state_names == nominal.state_names and sl.feedback_names == nominal.feedback_names
            and sl.held == nominal.held and np.allclose(sl.K, nominal.K, rtol=1e-12, atol=0)
            and np.array_equal(sl.u_lo, nominal.u_lo) and np.array_equal(sl.u_hi, nominal.u_hi)
            and len(sl.limits) == len(nominal.limits)
            and all(a.channel == b.channel and a.upper == b.upper and np.allclose(a.a, b.a, rtol=1e-12, atol=0)
                    for a, b in zip(sl.limits, nominal.limits, strict=True)))
    if not same:
        at = ", ".join(f"{k} = {v:.5g}" for k, v in zip(keys, values, strict=True))
        raise ArgumentError(f"member(vehicle) at ({at}) returned a loop of another form than '{nominal.name}' (its "
                            "states, fed-back channels, gain, levels and limit gains must be the nominal loop's): "
                            "build it as the nominal loop was, with the nominal controller")


def _room(nominal: SaturatedLoop, sl: SaturatedLoop) -> np.ndarray:
    """Largest half-widths about ``sl``'s equilibrium inside both the nominal loop's box and its own (free states)."""
    f = list(nominal.free)
    xe = sl.equilibrium[f]
    return np.min([xe - nominal.box[0][f], nominal.box[1][f] - xe, xe - sl.box[0][f], sl.box[1][f] - xe], axis=0)


def _reboxed(sl: SaturatedLoop, d: np.ndarray) -> SaturatedLoop:
    """``sl`` with the box ``X_e +- d`` in its free states (its own box in the held ones)."""
    f = list(sl.free)
    lo, hi = np.array(sl.box[0], dtype=float), np.array(sl.box[1], dtype=float)
    lo[f], hi[f] = sl.equilibrium[f] - d, sl.equilibrium[f] + d
    return dataclasses.replace(sl, box=(lo, hi))


def _check_corners(corners: Sequence[ScaledLoop], values: np.ndarray, keys: tuple[str, ...]) -> None:
    """ModelError unless every corner's linearized loop ``A + B K`` is exponentially stable."""
    for sc, row in zip(corners, values, strict=True):
        lam = np.linalg.eigvals(sc.A + sc.B @ sc.K)
        if not np.max(lam.real) < -1e-9 * max(1.0, float(np.max(np.abs(lam)))):
            at = ", ".join(f"{k} = {v:.5g}" for k, v in zip(keys, row, strict=True))
            raise ModelError(f"at the corner ({at}) the linearized loop is not exponentially stable (largest real "
                             f"part {np.max(lam.real):.3g}, scaled): no common certificate over this box, which is "
                             "too wide; try a smaller box")


@dataclass(frozen=True)
class _Corners:
    """What the program needs from the corners: ``common`` (the gain, the worst limit levels; the ``(A, B)`` of the
    only distinct corner when all merge), the distinct corners' systems (None when one), the ``[A B]`` each corner
    stands for in the interpolation, and the linear remainder term."""

    common: ScaledLoop
    vertices: list[ScaledLoop] | None
    jacobians: np.ndarray
    linear: np.ndarray


def _corner_systems(scaled: list[ScaledLoop], values: np.ndarray, box: tuple[np.ndarray, np.ndarray], nv: int,
                    margin: float) -> _Corners:
    """The corners' LMI data and the linear remainder term: ``margin`` times the largest residual of the
    multilinear interpolation of ``[A B]`` over the members after the corners, plus the distance of each corner's
    ``[A B]`` to the one it is merged with. Corners within :data:`MERGE_TOLERANCE` of each other (relative to the
    largest entry) are merged: near-duplicate LMIs make the program degenerate, and a single corner left is the
    nominal program itself."""
    nf = scaled[0].A.shape[0]
    AB = np.array([np.concatenate([s.A, s.B], axis=1) for s in scaled])
    lam = _multilinear_weights(values, box, values[:nv])
    resid = AB[nv:] - np.einsum("nv,vjl->njl", lam[nv:], AB[:nv])
    eps = margin * np.max(np.abs(resid), axis=0, initial=0.0)
    tol = MERGE_TOLERANCE * max(1.0, float(np.max(np.abs(AB))))
    reps: list[int] = []
    for v in range(nv):
        if not any(np.max(np.abs(AB[v] - AB[r])) <= tol for r in reps):
            reps.append(v)
    used = np.array([AB[next(r for r in reps if np.max(np.abs(AB[v] - AB[r])) <= tol)] if v not in reps else AB[v]
                     for v in range(nv)])
    eps = eps + np.max(np.abs(AB[:nv] - used), axis=0)
    eps[eps <= 1e-9 * max(1.0, float(np.max(np.abs(AB))))] = 0.0
    lim_b = np.array([s.lim_b for s in scaled])
    worst = np.sign(scaled[nv].lim_b) * np.min(np.abs(lim_b), axis=0) if lim_b.size else scaled[nv].lim_b
    vertices = [dataclasses.replace(scaled[r], A=used[r][:, :nf], B=used[r][:, nf:]) for r in reps]
    if len(reps) == 1:
        return _Corners(dataclasses.replace(vertices[0], lim_b=worst), None, used, eps)
    return _Corners(dataclasses.replace(scaled[nv], lim_b=worst), vertices, used, eps)


def _multilinear_weights(values: np.ndarray, box: tuple[np.ndarray, np.ndarray], corners: np.ndarray) -> np.ndarray:
    """Weights ``lambda_v(p) = prod_i (u_i if corner v is high in i else 1 - u_i)``, ``u = (p - lo) / (hi - lo)``,
    of the multilinear interpolation over the corners: ``(N, 2^k)``, >= 0, each row summing to 1."""
    lo, hi = box
    u = np.clip((np.asarray(values, dtype=float) - lo) / (hi - lo), 0.0, 1.0)
    high = corners > 0.5 * (lo + hi)
    return np.prod(np.where(high[None, :, :], u[:, None, :], 1.0 - u[:, None, :]), axis=2)


def _interpolated(sc: ScaledLoop, weights: np.ndarray, AB: np.ndarray) -> ScaledLoop:
    """``sc`` with ``(A, B)`` replaced by the interpolation ``sum_v weights_v [A B]_v`` of the corners' values: what
    the corner LMIs certify for this member, the rest of its ``[A B]`` being in the remainder bound."""
    nf = sc.A.shape[0]
    ab = np.einsum("v,vjl->jl", weights, AB)
    return dataclasses.replace(sc, A=ab[:, :nf], B=ab[:, nf:])


def _member_certificate(sl: SaturatedLoop, sc: ScaledLoop, search: EllipsoidSearch, backoff: float,
                        history: tuple[dict[str, Any], ...], provenance: str, *, n_verify: int, n_simulate: int,
                        seed: int, horizon: float | None = None) -> EllipsoidCertificate:
    """The member of loop ``sl`` (scaled and interpolated: ``sc``) as an :class:`EllipsoidCertificate`, its LMIs
    checked at its interpolated ``[A B]`` and verified on the loop (its times: the family's search, and its own
    verification as the wall time)."""
    t0 = time.perf_counter()
    box_sl = _reboxed(sl, sc.d)
    sol = back_off(sc, search.solution, search.p_idx, backoff)
    ver = verify_ellipsoid(box_sl, sc, sol, n_verify=n_verify, n_simulate=n_simulate, horizon=horizon, seed=seed)
    return EllipsoidCertificate(box_sl, sol.P, sol.G, sol.Q, sol.remainder.b * sc.d, sc.d.copy(), box_sl.box, ver,
                                history, search.solve_time, search.hessian_time, time.perf_counter() - t0,
                                "lmi-robust", provenance)


def _draw(cert: RobustEllipsoidCertificate, ax: Any, dims: Any, n: int, vertices: int) -> Any:
    """The drawing of :meth:`RobustEllipsoidCertificate.plot`."""
    from ..plotting import new_figure, state_axis

    loop = cert.system
    names = loop.state_names
    idx = []
    for key in (dims if not isinstance(dims, str) else [dims]):
        if isinstance(key, str) and key not in names:
            raise GlidectlError(f"no state {key!r}; have {names}")
        idx.append(names.index(key) if isinstance(key, str) else int(key) % loop.n)
    free = list(loop.free)
    if len(idx) != 2 or idx[0] == idx[1] or not set(idx) <= set(free):
        raise GlidectlError(f"choose two distinct free states of the certificate, got {dims!r}")
    if n < 8 or vertices < 0:
        raise GlidectlError(f"n must be at least 8 and vertices at least 0, got n = {n}, vertices = {vertices}")
    i, j = idx
    a, b = free.index(i), free.index(j)
    P2 = cert.P[np.ix_([a, b], [a, b])]
    L = np.linalg.cholesky(np.linalg.inv(0.5 * (P2 + P2.T)))
    th = np.linspace(0.0, 2 * math.pi, n)
    ring = (L @ np.vstack([np.cos(th), np.sin(th)])).T
    (xlabel, fx), (ylabel, fy) = state_axis(names, i), state_axis(names, j)
    if ax is None:
        _, ax = new_figure(width=6.5, height=5.2)
    xe = loop.equilibrium
    far = np.argsort(-np.einsum("vi,ij,vj->v", (cert.vertex_equilibria - xe)[:, free], cert.P,
                                (cert.vertex_equilibria - xe)[:, free]))[:vertices]
    for r, v in enumerate(far):
        E = (ring + cert.vertex_equilibria[v, [i, j]]) * [fx, fy]
        ax.plot(E[:, 0], E[:, 1], color="C1", lw=0.9, alpha=0.8, label="corner members" if r == 0 else None)
    E = (ring + xe[[i, j]]) * [fx, fy]
    ax.fill(E[:, 0], E[:, 1], color="C0", alpha=0.35, label="member at the nominal coefficients")
    ax.plot(E[:, 0], E[:, 1], color="C0", lw=1.2)
    ax.plot(fx * cert.vertex_equilibria[:, i], fy * cert.vertex_equilibria[:, j], "x", color="C1", ms=5,
            label="corner equilibria")
    ax.plot(fx * xe[i], fy * xe[j], "k+", ms=12, mew=2, label="nominal equilibrium")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    status = "verified" if cert.certified else "NOT verified"
    ax.set_title(f"robust LMI region of attraction ({status}, sampled-sound) over {', '.join(cert.keys)}",
                 fontsize=8)
    ax.legend(loc="lower right", fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax
