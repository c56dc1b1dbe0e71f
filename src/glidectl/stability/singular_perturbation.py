"""Singular-perturbation form of the chapter-5 glider, §5.1: equilibrium (5.8)-(5.11), scalings (5.12)-(5.19),
small parameters (5.16)-(5.18), (5.26)-(5.27), the compact form (5.28)-(5.29), the boundary-layer (5.30) and reduced
(5.33) subsystems and their eigenvalues.

Every nondimensional vector field here is the dimensional right-hand side
:meth:`glidectl.models.reduced.ReducedLongitudinalGlider.rhs` seen through the change of variables, so there is one
model and no second copy of its equations:

``f(p, q) = tau_s (V'/V_e, gamma')`` and ``g(p, q, eps) = (eps1 tau_s alpha', eps2 tau_s (K_q/K_M) Omega2')``,
with ``p = (Vbar, gammabar)``, ``q = (alphabar, Omegabar2)``. Because ``alpha' = Omega2 - gamma'`` exactly,
``g1 = Omegabar2 - eps1 f2`` and the ``eps -> 0`` limit is ``g(p, q, 0) = (Omegabar2, g2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..analysis.jacobian import jacobians
from ..errors import ModelError
from ..models.reduced import ReducedLongitudinalGlider
from ..params import Vehicle

__all__ = ["NondimensionalModel", "SingularPerturbation", "SlowModel", "singular_perturbation"]


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
    @property
    def omega_scale(self) -> float:
        """``K_q / K_M`` (s): ``Omegabar2 = (K_q/K_M) Omega2`` (5.15)."""
        v = self.model.vehicle
        return float(v.K_q / v.K_M)

    @property
    def equilibrium(self) -> np.ndarray:
        """Dimensional steady glide ``(speed, gamma, alpha, 0)``."""
        return np.array([self.speed, self.gamma, self.alpha, 0.0])

    def to_nondimensional(self, x: Any) -> np.ndarray:
        """``(V, gamma, alpha, Omega2) -> (Vbar, gammabar, alphabar, Omegabar2)``, (5.12)-(5.15)."""
        x = np.asarray(x)
        return np.stack([(x[..., 0] - self.speed) / self.speed, x[..., 1] - self.gamma, x[..., 2] - self.alpha,
                         self.omega_scale * x[..., 3]], axis=-1)

    def to_dimensional(self, z: Any) -> np.ndarray:
        """Inverse of :meth:`to_nondimensional`."""
        z = np.asarray(z)
        return np.stack([self.speed * (1 + z[..., 0]), z[..., 1] + self.gamma, z[..., 2] + self.alpha,
                         z[..., 3] / self.omega_scale], axis=-1)

    # ---------------------------------------------------------------- compact form (5.28)-(5.29)
    def _rates(self, p: Any, q: Any) -> tuple[Any, Any, Any, Any]:
        z = np.concatenate([np.asarray(p), np.asarray(q)], axis=-1)
        d = self.model.rhs(self.to_dimensional(z))
        return d[..., 0], d[..., 1], d[..., 2], d[..., 3]

    def f(self, p: Any, q: Any) -> np.ndarray:
        """Slow vector field ``dp/dt_n = f(p, q)`` of (5.28), ``p = (Vbar, gammabar)``."""
        Vd, gd, _, _ = self._rates(p, q)
        return np.stack([self.tau_s * Vd / self.speed, self.tau_s * gd], axis=-1)

    def g(self, p: Any, q: Any, eps: bool = True) -> np.ndarray:
        """Fast vector field ``g(p, q, eps)`` of (5.29) (``mu dq/dt_n = A g``); ``eps=False`` gives ``g(p, q, 0)``.

        ``g1 = eps1 dalphabar/dt_n = Omegabar2 - eps1 f2`` and ``g2 = eps2 dOmegabar2/dt_n``; with ``eps=False``
        the ``eps1 f2`` term is dropped (the only place the small parameters enter once ``p, q`` are fixed).
        """
        _, gd, ad, Od = self._rates(p, q)
        g1 = self.eps1 * self.tau_s * ad
        if not eps:
            g1 = g1 + self.eps1 * self.tau_s * gd
        g2 = self.eps2 * self.tau_s * self.omega_scale * Od
        return np.stack([g1, g2], axis=-1)

    def A(self) -> np.ndarray:
        """``diag(r1, r2)`` of (5.29)."""
        return np.diag([self.r1, self.r2])

    def full_rhs_nondimensional(self, z: Any) -> np.ndarray:
        """``dz/dt_n`` for ``z = (p, q)``: ``(f, A g / mu)``."""
        z = np.asarray(z)
        p, q = z[..., :2], z[..., 2:]
        gg = self.g(p, q)
        return np.concatenate([self.f(p, q), gg * np.array([self.r1, self.r2]) / self.mu], axis=-1)

    def reduced_rhs(self, p: Any) -> np.ndarray:
        """Reduced subsystem (5.33): ``dp/dt_n = f(p, 0)``."""
        p = np.asarray(p)
        return self.f(p, np.zeros_like(p))

    def boundary_layer_rhs(self, p: Any, q: Any) -> np.ndarray:
        """Boundary-layer subsystem (5.30): ``dq/dtau = A g(p, q, 0)``, ``tau = t_n / mu``."""
        return self.g(p, q, eps=False) * np.array([self.r1, self.r2])

    def reduced_dimensional_rhs(self, x: Any) -> np.ndarray:
        """The reduced subsystem in dimensional form, ``(V, gamma)' `` of (5.4)-(5.5) at ``alpha = alpha_e``,
        ``Omega2 = 0`` (the slow model simulated in Fig 5.1)."""
        x = np.asarray(x)
        full = np.stack([x[..., 0], x[..., 1], np.full_like(x[..., 0], self.alpha),
                         np.zeros_like(x[..., 0])], axis=-1)
        return self.model.rhs(full)[..., :2]

    # ---------------------------------------------------------------- models for region-of-attraction work
    def reduced_model(self) -> NondimensionalModel:
        """The reduced subsystem (5.33) as a model: states ``(Vbar, gammabar)``, time ``t_n``, equilibrium 0."""
        return NondimensionalModel(self, "reduced", ("Vbar", "gammabar"),
                                   (np.array([-0.9, -math.pi]), np.array([1.5, math.pi])))

    def full_model(self) -> NondimensionalModel:
        """The full model (5.28)-(5.29): states ``(Vbar, gammabar, alphabar, Omegabar2)``, time ``t_n``.

        Its region of interest is the box of the ROA study, ``|Vbar| <= 0.4``, ``|gammabar| <= pi/2``,
        ``|alphabar| <= 0.2``, ``|Omegabar2| <= 0.1``."""
        return NondimensionalModel(self, "full", ("Vbar", "gammabar", "alphabar", "Omegabar2"),
                                   (np.array([-0.4, -math.pi / 2, -0.2, -0.1]),
                                    np.array([0.4, math.pi / 2, 0.2, 0.1])))


@dataclass(frozen=True)
class NondimensionalModel:
    """A nondimensional chapter-5 model at its steady glide (equilibrium at 0), time ``t_n``.

    ``rhs`` is :meth:`SingularPerturbation.reduced_rhs` or :meth:`SingularPerturbation.full_rhs_nondimensional`
    (the dimensional model seen through (5.12)-(5.19)). ``angle_states`` and ``positive_state`` tell
    :func:`glidectl.roa.recast` how to make it polynomial: ``gammabar`` is an angle and the right-hand side has the
    factor ``1/(1 + Vbar)`` (``1/V``). ``box`` is the region of interest ``(lo, hi)``.

    Built by :meth:`SingularPerturbation.reduced_model` and :meth:`SingularPerturbation.full_model`.

    Parameters
    ----------
    sp : SingularPerturbation
        The analysed glider and its scalings.
    kind : {"reduced", "full"}
        ``"reduced"``: states ``(Vbar, gammabar)`` (5.33); any other value: the full model (5.28)-(5.29), states
        ``(Vbar, gammabar, alphabar, Omegabar2)``. Not validated.
    state_names : tuple of str
        Names of the nondimensional states (must match ``kind``).
    box : tuple of ndarray
        Region of interest ``(lo, hi)`` in the nondimensional states.
    angle_states : tuple of int
        Indices of the states that enter only through ``sin``/``cos`` (``gammabar``).
    positive_state : int
        Index of the state ``Vbar`` with ``1 + Vbar > 0`` (the ``1/V`` factor).
    time_unit : str
        ``"t_n"``: time is nondimensional, ``t_n = t / tau_s``.
    input_names : tuple of str
        Empty: the model has no inputs.
    """

    sp: SingularPerturbation = field(repr=False)
    kind: str
    state_names: tuple[str, ...]
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    angle_states: tuple[int, ...] = (1,)
    positive_state: int = 0
    time_unit: str = "t_n"
    input_names: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return f"{self.sp.vehicle.name} {self.kind} (K_M = {self.sp.model.vehicle.K_M:g})"

    @property
    def provenance(self) -> str:
        return self.sp.provenance

    @property
    def equilibrium(self) -> np.ndarray:
        return np.zeros(len(self.state_names))

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        """``dx/dt_n``."""
        if self.kind == "reduced":
            return self.sp.reduced_rhs(x)
        return self.sp.full_rhs_nondimensional(x)


def singular_perturbation(veh: Vehicle) -> SingularPerturbation:
    """Steady glide, time scales, small parameters and subsystem eigenvalues of §5.1 for ``veh``.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider (``r_P = 0`` is assumed; ``m0 != 0``). ``K_q < 0`` and ``K_M < 0`` are needed for
        positive ``eps1, eps2`` (pitch damping and pitch stiffness).

    Returns
    -------
    SingularPerturbation
        The steady glide ``V_e`` (m/s), ``gamma_e``, ``alpha_e`` (rad), ``K_De``, ``K_Le`` (kg/m), the slow time
        scale ``tau_s`` (s), the small parameters ``eps1, eps2, mu`` and ratios ``r1, r2`` (nondimensional), and the
        eigenvalues of the reduced, boundary-layer and full linearizations on the nondimensional time ``t_n =
        t / tau_s`` (nondimensional).

    Raises
    ------
    ModelError
        If the vehicle has no steady glide in this model or is not singularly perturbed (``eps_i <= 0``): not an
        underwater glider, ``m0 = 0``, ``K_M = 0``, no equilibrium angle of attack from (5.90), ``K_De <= 0``,
        ``K_q >= 0`` or ``K_M >= 0``.
    """
    model = ReducedLongitudinalGlider(veh)
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
    mu = max(eps1, eps2)
    sp = SingularPerturbation(model, V_e, gamma_e, a_e, K_De, K_Le, tau_s, eps1, eps2, mu, mu / eps1, mu / eps2,
                              np.empty(0), np.empty(0), np.empty(0), veh, veh.provenance)
    z0 = np.zeros(2)
    Ar, _ = jacobians(lambda p, u: sp.reduced_rhs(p), z0, np.zeros(0))
    Ab, _ = jacobians(lambda q, u: sp.g(np.zeros_like(q), q, eps=False) / np.array([eps1, eps2]), z0, np.zeros(0))
    Af, _ = jacobians(lambda z, u: sp.full_rhs_nondimensional(z), np.zeros(4), np.zeros(0))
    residual = np.max(np.abs(model.rhs(sp.equilibrium)))
    if residual > 1e-9 * max(1.0, V_e):
        raise ModelError(f"equilibrium residual {residual:.2e} for vehicle '{veh.name}' (internal error)")
    srt = lambda lam: lam[np.lexsort((lam.imag, lam.real))]  # noqa: E731
    return SingularPerturbation(model, V_e, gamma_e, a_e, K_De, K_Le, tau_s, eps1, eps2, mu, mu / eps1, mu / eps2,
                                srt(np.linalg.eigvals(Ar)), srt(np.linalg.eigvals(Ab)), srt(np.linalg.eigvals(Af)),
                                veh, veh.provenance)


@dataclass(frozen=True)
class SlowModel:
    """The reduced (slow) subsystem in dimensional form, state ``(V, gamma)`` (m/s, rad), for simulation.

    Its right-hand side is :meth:`SingularPerturbation.reduced_dimensional_rhs` (the full model at
    ``alpha = alpha_e``, ``Omega2 = 0``), equations (5.4)-(5.5) / (5.33).

    Parameters
    ----------
    sp : SingularPerturbation
        From :func:`singular_perturbation`; gives the vehicle and ``alpha_e`` (rad).
    state_names : tuple of str
        ``("V", "gamma")`` (m/s, rad).
    input_names : tuple of str
        Empty: the model has no inputs.
    """

    sp: SingularPerturbation
    state_names: tuple[str, ...] = ("V", "gamma")
    input_names: tuple[str, ...] = ()

    @property
    def vehicle(self) -> Vehicle:
        return self.sp.model.vehicle

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        return self.sp.reduced_dimensional_rhs(x)
