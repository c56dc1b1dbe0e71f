"""Singular-perturbation form of the chapter-5 glider, §5.1: equilibrium (5.8)-(5.11), scalings (5.12)-(5.19),
small parameters (5.16)-(5.18), (5.26)-(5.27), the compact form (5.28)-(5.29), the boundary-layer (5.30) and reduced
(5.33) subsystems and their eigenvalues.

The nondimensional vector fields live in :mod:`glidectl.models.nondimensional` (one model, no second copy of its
equations): the dimensional right-hand side :meth:`glidectl.models.reduced.ReducedLongitudinalGlider.rhs` seen through
the change of variables :class:`~glidectl.models.nondimensional.NondimensionalScaling`. This module computes the
numbers of that change of variables and the subsystem eigenvalues. The vector-field methods of
:class:`SingularPerturbation` evaluate its ``scaling``; its ``reduced_model()``, ``full_model()`` and
``slow_model()`` build :class:`~glidectl.models.nondimensional.NondimensionalModel` and
:class:`~glidectl.models.nondimensional.SlowModel`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import jacobians
from ..errors import ModelError, SolverError
from ..models.nondimensional import NondimensionalModel, NondimensionalScaling, SlowModel
from ..models.reduced import ReducedLongitudinalGlider, require_centred_mass, require_v2_pitch_damping
from ..params import Vehicle

__all__ = ["SPEED_RANGE", "SingularPerturbation", "singular_perturbation"]

#: plausible steady-glide speeds V_e (m/s) of the chapter-5 analysis
SPEED_RANGE = (1e-6, 100.0)


@dataclass(frozen=True)
class SingularPerturbation:
    """Steady glide, time scales and small parameters of the chapter-5 glider (immutable, with provenance).

    Attributes
    ----------
    speed : float
        Equilibrium speed ``V_e`` (m/s), (5.8).
    gamma, alpha : float
        Equilibrium flight-path angle ``gamma_e`` (5.9) and angle of attack ``alpha_e`` (5.10)/(5.90) (rad).
    K_De, K_Le : float
        Drag and lift coefficients at ``alpha_e`` (kg/m).
    tau_s : float
        Reference (slow) time scale ``M3 / (K_De V_e)`` (s), (5.18) (``M3 = m3 + mbar``; ``m1 = m3`` in §5.1).
    eps1, eps2 : float
        ``(K_q/K_M)/tau_s`` (5.16) and ``-J2/(K_q V_e^2 tau_s)`` (5.17), dimensionless.
    mu, r1, r2 : float
        ``max(eps1, eps2)`` (5.26) and ``mu/eps1``, ``mu/eps2`` (5.27).
    reduced_eigenvalues : ndarray
        Eigenvalues of ``df/dp (0, 0)`` of the reduced subsystem (5.33), on the ``t_n`` time scale.
    boundary_layer_eigenvalues : ndarray
        Eigenvalues of the boundary-layer subsystem (5.30) at ``p = 0`` rescaled to ``t_n`` (i.e. of
        ``d/dq [g1/eps1, g2/eps2]``), as printed in §5.1.3.
    full_eigenvalues : ndarray
        Eigenvalues of the full nondimensional linearization (5.28)-(5.29) on ``t_n`` (for comparison).
    vehicle : Vehicle
        The analysed vehicle.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    scaling : NondimensionalScaling
        The change of variables (5.12)-(5.19) with these numbers (computed on first use): the models-layer object
        whose vector fields :meth:`f`, :meth:`g`, :meth:`full_rhs_nondimensional`, :meth:`reduced_rhs` and
        :meth:`boundary_layer_rhs` evaluate.
    """

    model: ReducedLongitudinalGlider = field(repr=False)
    speed: float
    gamma: float
    alpha: float
    K_De: float
    K_Le: float
    tau_s: float
    eps1: float
    eps2: float
    mu: float
    r1: float
    r2: float
    reduced_eigenvalues: np.ndarray = field(repr=False)
    boundary_layer_eigenvalues: np.ndarray = field(repr=False)
    full_eigenvalues: np.ndarray = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""

    # ---------------------------------------------------------------- coordinates (5.12)-(5.15), (5.19)
    @cached_property
    def scaling(self) -> NondimensionalScaling:
        """The change of variables (5.12)-(5.19) with this glide's numbers: the models-layer object every vector
        field below (and the models of :meth:`reduced_model`, :meth:`full_model`) evaluates."""
        return NondimensionalScaling(self.model.vehicle, self.speed, self.gamma, self.alpha, self.tau_s, self.eps1,
                                     self.eps2)

    @property
    def omega_scale(self) -> float:
        """``K_q / K_M`` (s): ``Omegabar2 = (K_q/K_M) Omega2`` (5.15)."""
        return self.scaling.omega_scale

    @property
    def equilibrium(self) -> np.ndarray:
        """Dimensional steady glide ``(speed, gamma, alpha, 0)``."""
        return self.scaling.equilibrium

    def to_nondimensional(self, x: Any) -> np.ndarray:
        """``(V, gamma, alpha, Omega2) -> (Vbar, gammabar, alphabar, Omegabar2)``, (5.12)-(5.15); ``x`` of trailing
        dimension 4.

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If an argument does not have the trailing dimension named above.
        """
        return self.scaling.to_nondimensional(x)

    def to_dimensional(self, z: Any) -> np.ndarray:
        """Inverse of :meth:`to_nondimensional`; ``z`` of trailing dimension 4.

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If an argument does not have the trailing dimension named above.
        """
        return self.scaling.to_dimensional(z)

    # ---------------------------------------------------------------- compact form (5.28)-(5.29)
    def f(self, p: Any, q: Any) -> np.ndarray:
        """Slow vector field ``dp/dt_n = f(p, q)`` of (5.28), ``p = (Vbar, gammabar)``
        (:meth:`NondimensionalScaling.f <glidectl.models.nondimensional.NondimensionalScaling.f>`); ``p`` and ``q``
        of trailing dimension 2.

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If an argument does not have the trailing dimension named above.
        """
        return self.scaling.f(p, q)

    def g(self, p: Any, q: Any, eps: bool = True) -> np.ndarray:
        """Fast vector field ``g(p, q, eps)`` of (5.29) (``mu dq/dt_n = A g``); ``eps=False`` gives ``g(p, q, 0)``.

        ``g1 = eps1 dalphabar/dt_n = Omegabar2 - eps1 f2`` and ``g2 = eps2 dOmegabar2/dt_n``; with ``eps=False``
        the ``eps1 f2`` term is dropped (:meth:`NondimensionalScaling.g
        <glidectl.models.nondimensional.NondimensionalScaling.g>`). ``p`` and ``q`` of trailing dimension 2.

        Raises
        ------
        ArgumentTypeError
            If ``p`` or ``q`` is not an array of numbers, or ``eps`` is not a bool.
        ArgumentError
            If ``p`` or ``q`` does not have the trailing dimension 2.
        """
        return self.scaling.g(p, q, checks.boolean("eps", eps))

    def A(self) -> np.ndarray:
        """``diag(r1, r2)`` of (5.29)."""
        return np.diag([self.r1, self.r2])

    def full_rhs_nondimensional(self, z: Any) -> np.ndarray:
        """``dz/dt_n`` for ``z = (p, q)``: ``(f, A g / mu)``; ``z`` of trailing dimension 4.

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If an argument does not have the trailing dimension named above.
        """
        return self.scaling.full_rhs_nondimensional(z)

    def reduced_rhs(self, p: Any) -> np.ndarray:
        """Reduced subsystem (5.33): ``dp/dt_n = f(p, 0)``; ``p`` of trailing dimension 2.

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If an argument does not have the trailing dimension named above.
        """
        return self.scaling.reduced_rhs(p)

    def boundary_layer_rhs(self, p: Any, q: Any) -> np.ndarray:
        """Boundary-layer subsystem (5.30): ``dq/dtau = A g(p, q, 0)``, ``tau = t_n / mu``; ``p`` and ``q`` of
        trailing dimension 2.

        Raises
        ------
        ArgumentTypeError
            If an argument is not an array of numbers.
        ArgumentError
            If an argument does not have the trailing dimension named above.
        """
        return self.scaling.boundary_layer_rhs(p, q)

    def reduced_dimensional_rhs(self, x: Any) -> np.ndarray:
        """The reduced subsystem in dimensional form, ``(V, gamma)' `` of (5.4)-(5.5) at ``alpha = alpha_e``,
        ``Omega2 = 0`` (the slow model simulated in Fig 5.1): ``self.slow_model().rhs(x)``."""
        return self.slow_model().rhs(x)

    # ---------------------------------------------------------------- models (simulation, region-of-attraction work)
    def slow_model(self) -> SlowModel:
        """The reduced subsystem in dimensional form (5.4)-(5.5) as a model: states ``(V, gamma)`` (m/s, rad), time
        in s, the fast states frozen at ``alpha = alpha_e``, ``Omega2 = 0``."""
        return SlowModel(self.model.vehicle, self.alpha)

    def reduced_model(self) -> NondimensionalModel:
        """The reduced subsystem (5.33) as a model: states ``(Vbar, gammabar)``, time ``t_n``, equilibrium 0."""
        return NondimensionalModel(self.scaling, "reduced", ("Vbar", "gammabar"),
                                   (np.array([-0.9, -math.pi]), np.array([1.5, math.pi])))

    def full_model(self) -> NondimensionalModel:
        """The full model (5.28)-(5.29): states ``(Vbar, gammabar, alphabar, Omegabar2)``, time ``t_n``.

        Its region of interest is the box of the ROA study, ``|Vbar| <= 0.4``, ``|gammabar| <= pi/2``,
        ``|alphabar| <= 0.2``, ``|Omegabar2| <= 0.1``."""
        return NondimensionalModel(self.scaling, "full", ("Vbar", "gammabar", "alphabar", "Omegabar2"),
                                   (np.array([-0.4, -math.pi / 2, -0.2, -0.1]),
                                    np.array([0.4, math.pi / 2, 0.2, 0.1])))


def singular_perturbation(veh: Vehicle) -> SingularPerturbation:
    """Steady glide, time scales, small parameters and subsystem eigenvalues of §5.1 for ``veh``.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider satisfying the assumptions of §5.1: 1. moving mass at the centre of buoyancy (``mbar = 0``
        or ``r_P = 0``; a file with a nonzero ``r_P1, r_P2, r_P3`` is refused, never reduced by dropping the
        offset), 2. constant ``m0 != 0``; assumption 3 (``m1 = m3``) is relaxed to (5.86)-(5.89) of §5.4. Pitch
        damping must be the ``V^2``-scaled ``K_q`` of (2.13) (the scalings (5.15)-(5.17) use it): ``K_q < 0``,
        no chapter-8 ``K_Omega1_2``, ``K_Omega2_2``; ``K_M < 0`` (pitch stiffness).

    Returns
    -------
    SingularPerturbation
        The steady glide ``V_e`` (m/s), ``gamma_e``, ``alpha_e`` (rad), ``K_De``, ``K_Le`` (kg/m), the slow time
        scale ``tau_s`` (s), the small parameters ``eps1, eps2, mu`` and ratios ``r1, r2`` (nondimensional), and the
        eigenvalues of the reduced, boundary-layer and full linearizations on the nondimensional time ``t_n =
        t / tau_s`` (nondimensional).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle (e.g. a preset name: load it first).
    ModelError
        If the vehicle breaks an assumption of §5.1 (the message names it: ``mbar > 0`` with ``r_P != 0``,
        ``m0 = 0``, chapter-8 pitch damping), has no steady glide in this model or is not singularly perturbed
        (``eps_i <= 0``): not an underwater glider, ``K_M = 0``, no equilibrium angle of attack from (5.90),
        ``K_De <= 0``, ``K_q >= 0`` or ``K_M >= 0``; or its numbers overflow or underflow (a time scale or small
        parameter that is not a finite positive number, a glide speed outside :data:`SPEED_RANGE`, a linearization
        that underflows to zero).
    SolverError
        If an eigenvalue computation fails.

    Examples
    --------
    >>> import glidectl as gc
    >>> sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    >>> print(f"V_e = {sp.speed:.3f} m/s, tau_s = {sp.tau_s:.2f} s, eps1 = {sp.eps1:.2e}, eps2 = {sp.eps2:.2e}")
    V_e = 1.648 m/s, tau_s = 8.36 s, eps1 = 4.78e-03, eps2 = 4.40e-04
    """
    checks.vehicle("veh", veh, "underwater_glider")
    try:
        with np.errstate(over="raise", invalid="raise", divide="raise"):
            return _singular_perturbation(veh)
    except (OverflowError, ZeroDivisionError, FloatingPointError) as exc:
        raise ModelError(f"vehicle '{veh.name}': the chapter-5 numbers overflow or divide by zero "
                         f"({type(exc).__name__}: {exc}); its parameters are outside the range this analysis can "
                         "represent") from exc


def _singular_perturbation(veh: Vehicle) -> SingularPerturbation:
    require_centred_mass(veh, "singular_perturbation (§5.1)")
    model = ReducedLongitudinalGlider(veh)  # refuses m0 = 0 (assumption 2)
    require_v2_pitch_damping(veh, "singular_perturbation (§5.1)")
    _, M3 = model.masses
    a_e = model.trim_alpha()
    K_De = veh.K_D0 + veh.K_D * a_e**2
    K_Le = veh.K_L0 + veh.K_L * a_e
    if K_De <= 0:
        raise ModelError(f"vehicle '{veh.name}': drag coefficient K_D0 + K_D alpha_e^2 = {K_De:g} kg/m must be > 0 "
                         "(drag is what makes the reduction of chapter 5 work)")
    m0 = veh.m0
    V_e = math.sqrt(abs(m0) * veh.g / math.hypot(K_De, K_Le))                      # (5.8)
    gamma_e = math.atan2(-K_De / m0, K_Le / m0)                                     # (5.9), quadrant from signs
    if not (veh.K_q < 0 and veh.K_M < 0):
        raise ModelError(f"vehicle '{veh.name}' has K_q = {veh.K_q:g} kg s/rad, K_M = {veh.K_M:g} kg/rad: the "
                         "singular perturbation form (5.15)-(5.17) (eps1, eps2 > 0) needs pitch damping K_q < 0 and "
                         "stiffness K_M < 0")
    tau_s = M3 / (K_De * V_e)  # (5.18); m3 (= m1 there) makes (5.103)-(5.107) hold as printed when m1 != m3
    eps1 = (veh.K_q / veh.K_M) / tau_s                                              # (5.16)
    eps2 = -(veh.J2 / (veh.K_q * V_e**2)) / tau_s                                   # (5.17)
    if not (eps1 > 0 and eps2 > 0):
        raise ModelError(f"vehicle '{veh.name}' gives eps1 = {eps1:.4g}, eps2 = {eps2:.4g}: the singular "
                         "perturbation form (5.16)-(5.17) needs K_q < 0 and K_M < 0 (pitch damping and stiffness)")
    numbers = {"V_e": V_e, "tau_s": tau_s, "eps1": eps1, "eps2": eps2, "K_De": K_De}
    bad = {k: v for k, v in numbers.items() if not (math.isfinite(v) and v > 0)}
    if bad:
        raise ModelError(f"vehicle '{veh.name}': {bad} must be finite and positive (the parameters overflow or "
                         "underflow in (5.8)-(5.18))")
    if not SPEED_RANGE[0] <= V_e <= SPEED_RANGE[1]:
        raise ModelError(f"vehicle '{veh.name}' glides at V_e = {V_e:.3g} m/s (5.8), outside the plausible range "
                         f"[{SPEED_RANGE[0]:g}, {SPEED_RANGE[1]:g}] m/s of this analysis (forces of that size "
                         f"underflow or overflow in the exact derivatives); check m0 = {m0:g} kg and the drag and "
                         "lift coefficients")
    mu = max(eps1, eps2)
    sp = SingularPerturbation(model, V_e, gamma_e, a_e, K_De, K_Le, tau_s, eps1, eps2, mu, mu / eps1, mu / eps2,
                              np.empty(0), np.empty(0), np.empty(0), veh, veh.provenance)
    z0 = np.zeros(2)
    Ar, _ = jacobians(lambda p, u: sp.reduced_rhs(p), z0, np.zeros(0))
    Ab, _ = jacobians(lambda q, u: sp.g(np.zeros_like(q), q, eps=False) / np.array([eps1, eps2]), z0, np.zeros(0))
    Af, _ = jacobians(lambda z, u: sp.full_rhs_nondimensional(z), np.zeros(4), np.zeros(0))
    # residual relative to the size of the terms of each equation (forces / mass, moments / inertia), not absolute
    M1, _ = model.masses
    acc = (abs(m0) * veh.g + (K_De + abs(K_Le)) * V_e**2) / min(M1, M3)
    mom = (abs(veh.K_M0) + abs(veh.K_M) * max(abs(a_e), 1.0) + abs(M3 - M1)) * V_e**2 / veh.J2  # K_M != 0 here
    scale = np.array([acc, acc / V_e, acc / V_e, mom])
    residual = float(np.max(np.abs(np.asarray(model.rhs(sp.equilibrium), dtype=float)) / scale))
    if not residual <= 1e-9:
        raise ModelError(f"equilibrium residual {residual:.2e} (relative to the forces and moments) for vehicle "
                         f"'{veh.name}': the steady glide (5.8)-(5.10) is not an equilibrium of the model to working "
                         "precision")
    def eig(M: np.ndarray, what: str) -> np.ndarray:
        if not np.any(M):
            raise ModelError(f"the {what} linearization of vehicle '{veh.name}' is identically zero: its exact "
                             "derivatives underflow (the forces are too small for double precision)")
        try:
            lam = np.linalg.eigvals(M)
        except np.linalg.LinAlgError as exc:
            raise SolverError(f"eigenvalues of the {what} linearization of vehicle '{veh.name}' did not converge: "
                              f"{exc}") from exc
        return lam[np.lexsort((lam.imag, lam.real))]

    return SingularPerturbation(model, V_e, gamma_e, a_e, K_De, K_Le, tau_s, eps1, eps2, mu, mu / eps1, mu / eps2,
                                eig(Ar, "reduced"), eig(Ab, "boundary-layer"), eig(Af, "full"), veh, veh.provenance)
