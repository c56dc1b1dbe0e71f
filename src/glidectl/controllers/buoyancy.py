"""Buoyancy control of the chapter-5 glider, §6.2: equilibrium buoyancy (6.7), pump model (6.8) with rate limit and
range saturation, the proportional law (6.9), and a sampled check of the Lyapunov argument (6.10)-(6.13).

Model
-----
The plant is :class:`glidectl.models.buoyancy_glider.BuoyancyGlider`: state ``(V, gamma, alpha, Omega2, m0)`` (m/s,
rad, rad, rad/s, kg), input ``u1 = dm0/dt`` (kg/s), with the pump's rate limit ``u4_max`` and range ``m0_max``
(:class:`~glidectl.models.buoyancy_glider.ActuatorLimits`).

Law (6.8)-(6.9)
---------------
``mbar0 = (m0 - m0e) / m_e`` and ``dmbar0/dt_n = u = -K_b mbar0`` with ``t_n = t / tau_s``. In seconds this is
``dm0/dt = (m_e / tau_s) u = -(K_b / tau_s)(m0 - m0e)`` kg/s (``m_e`` cancels); :class:`BuoyancyController`
returns that rate after the pump limits.

What (6.10)-(6.12) do and do not prove (checked by :func:`buoyancy_lyapunov_check`)
------------------------------------------------------------------------------------
The text says that ``nu`` (5.83) does not depend on ``mbar0``, so ``dnu/dt_n`` is still bounded by (5.55). The
function ``nu`` indeed does not depend on ``mbar0``, but its derivative does: ``dnu/dt_n = grad nu(z) . zdot(z,
mbar0)`` and the vector field ``zdot`` depends on ``m0 = m0e + m_e mbar0`` (weight ``m0 g`` and, for the added-mass
model, the masses). The cross term ``C(z, mbar0) = grad nu(z) . [zdot(z, mbar0) - zdot(z, 0)]`` is not zero; it
vanishes at ``z = 0`` (``grad nu(0) = 0``) and is ``O(|z| |mbar0|)``. Hence

* (6.12) is false as stated for an arbitrary ``K_b > 0``: ``dnu_b/dt_n <= -c|z|^2 + b|z||mbar0| - K_b mbar0^2``
  is negative definite only if ``K_b > b^2 / (4 c)``; the check reports the sampled threshold ``K_b_required``
  on the whole box and on a small ball;
* local asymptotic stability is still true for every ``K_b > 0`` by a cascade argument: the closed-loop ``m0``
  equation does not depend on the glide state and converges exponentially, and the glide is exponentially stable
  at ``m0 = m0e`` (Theorem 2 / Proposition 2);
* the region estimate (6.13) is not implied by (6.10)-(6.12); it holds only where the sampled ``dnu_b/dt_n < 0``
  (e.g. for ``K_b >= K_b_required`` on the sampled set).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import jacobian_batch, partial_derivative
from ..errors import ArgumentError, InfeasibleGlideError, SolverError
from ..models._validate import require_glider, require_instance, speed_arg, trailing_array
from ..models.buoyancy_glider import ActuatorLimits, BuoyancyGlider, actuator_limits, loaded_rates
from ..models.reduced import ReducedLongitudinalGlider
from ..params import Vehicle
from ..stability.composite import CompositeCertificate, composite_lyapunov
from ..stability.singular_perturbation import SingularPerturbation, singular_perturbation

__all__ = [
    "BuoyancyController",
    "BuoyancyEquilibrium",
    "BuoyancyLyapunovCheck",
    "buoyancy_equilibrium",
    "buoyancy_lyapunov_check",
    "nu_b_derivative",
]


# ------------------------------------------------------------------------------------------------ equilibrium
@dataclass(frozen=True)
class BuoyancyEquilibrium:
    """Steady glide reached by buoyancy control at a requested speed, (6.7).

    Attributes
    ----------
    speed, gamma, alpha : float
        ``V_e`` (m/s), flight-path angle ``gamma_e`` (5.9) and angle of attack ``alpha_e`` (5.10) (rad); ``alpha``
        does not depend on the buoyancy (§6.2), so ``gamma`` is fixed up to its sign.
    m0e : float
        Equilibrium buoyancy (kg), (6.7): positive for a descent.
    m_e : float
        ``M1 = m1 + mbar`` at ``m0e`` (kg), the mass scaling ``mbar0 = (m0 - m0e)/m_e`` of (6.8).
    K_De, K_Le : float
        Drag and lift coefficients at ``alpha_e`` (kg/m).
    tau_s, eps1, eps2 : float
        Time scale (s) and small parameters of the closed-loop glide (5.16)-(5.18).
    residual : float
        ``max |x'|`` of :class:`BuoyancyGlider` at the equilibrium with ``u1 = 0``.
    sp : SingularPerturbation
        Chapter-5 analysis of the vehicle at ``m0 = m0e`` (nondimensional coordinates of (5.12)-(5.15)).
    vehicle : Vehicle
        The vehicle (any nominal ``m0``).
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    """

    speed: float
    gamma: float
    alpha: float
    m0e: float
    m_e: float
    K_De: float
    K_Le: float
    tau_s: float
    eps1: float
    eps2: float
    residual: float
    sp: SingularPerturbation = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = field(default="", repr=False)

    @property
    def state(self) -> np.ndarray:
        """``(speed, gamma, alpha, 0, m0e)``."""
        return np.array([self.speed, self.gamma, self.alpha, 0.0, self.m0e])


def buoyancy_equilibrium(veh: Vehicle, speed: float, *, descending: bool = True) -> BuoyancyEquilibrium:
    """Equilibrium buoyancy ``m0e = +-(1/g) sqrt(K_De^2 + K_Le^2) V_e^2`` (6.7) for the speed ``V_e``.

    Parameters
    ----------
    veh : Vehicle
        Chapter-5 glider (``K_q < 0``, ``K_M < 0``); ``m0_max`` (kg) is enforced when defined.
    speed : float
        Requested steady speed ``V_e`` (m/s), in ``(0, 100]``.
    descending : bool
        Sign of (6.7): ``m0e > 0`` (descent, ``gamma_e < 0``) or ``m0e < 0`` (climb). Only the sign of ``K_Le``
        (fixed by ``alpha_e``) gives an upright glide; the other raises.

    Returns
    -------
    BuoyancyEquilibrium
        ``V_e`` (m/s), ``gamma_e``, ``alpha_e`` (rad), ``m0e`` and ``m_e`` (kg), ``K_De``, ``K_Le`` (kg/m), ``tau_s``
        (s), ``eps1, eps2`` (nondimensional), the equilibrium residual and the chapter-5 analysis at ``m0e``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``speed`` not a real number or ``descending`` not a bool.
    ArgumentError
        If ``speed`` is not in ``(0, 100]`` m/s.
    InfeasibleGlideError
        ``|m0e| > m0_max``, or a direction that would need an inverted glide.
    ModelError
        If ``veh`` is not an underwater glider, its nominal ``m0`` is 0, ``K_M = 0``, or it has no singularly
        perturbed chapter-5 glide at ``m0e`` (``K_q >= 0``, ``K_M >= 0``, ``K_De <= 0``; from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`).
    SolverError
        If the equilibrium residual is not small relative to the forces at the glide (a loss of accuracy).

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> sph = gc.load_vehicle("sphere_ch5")
    >>> eq = gc.buoyancy_equilibrium(sph, 1.5)  # the m0 that glides at 1.5 m/s
    >>> print(f"m0e = {eq.m0e:.4f} kg, gamma_e = {np.degrees(eq.gamma):.2f} deg")
    m0e = 0.5799 kg, gamma_e = -53.57 deg
    """
    require_glider(veh, "veh")
    speed = speed_arg("speed", speed)
    descending = checks.boolean("descending", descending)
    a_e = ReducedLongitudinalGlider(veh).trim_alpha()
    K_De = veh.K_D0 + veh.K_D * a_e**2
    K_Le = veh.K_L0 + veh.K_L * a_e
    m0e = (1.0 if descending else -1.0) * math.hypot(K_De, K_Le) * speed**2 / veh.g          # (6.7)
    lim = actuator_limits(veh)
    if not (math.isfinite(m0e) and m0e != 0):
        raise InfeasibleGlideError(f"speed {speed:g} m/s needs buoyancy m0e = {m0e:g} kg (6.7) for vehicle "
                                   f"'{veh.name}' (K_De = {K_De:g}, K_Le = {K_Le:g} kg/m): no steady glide")
    if not lim.m0_in_range(m0e):
        bound = lim.m0_max if m0e > 0 else -lim.m0_min
        vmax = math.sqrt(bound * veh.g / math.hypot(K_De, K_Le))
        raise InfeasibleGlideError(
            f"speed {speed:g} m/s needs buoyancy m0e = {m0e:.4g} kg (6.7), outside the range [{lim.m0_min:g}, "
            f"{lim.m0_max:g}] kg of vehicle '{veh.name}' ([actuators] m0); the fastest steady "
            f"{'descent' if descending else 'climb'} is {vmax:.4g} m/s")
    if K_Le * m0e < 0:
        raise InfeasibleGlideError(
            f"buoyancy alone cannot make vehicle '{veh.name}' {'descend' if descending else 'climb'} upright: its "
            f"angle of attack alpha_e = {a_e:.4g} rad is fixed by the pitching moment (§6.2) and gives lift "
            f"coefficient K_Le = {K_Le:.4g} kg/m, so m0e must have the sign of K_Le (m0 g cos(gamma_e) = K_Le V_e^2); "
            "the other sign is an inverted glide. Change alpha_e (moving mass, elevator) to reverse the glide")
    veh_e = veh.with_overrides(m0=m0e)
    sp = singular_perturbation(veh_e)
    M1, _ = sp.model.masses
    x_e = np.array([sp.speed, sp.gamma, sp.alpha, 0.0, m0e])
    res = float(np.max(np.abs(BuoyancyGlider(veh).rhs(x_e, np.zeros(1)))))
    # relative to the accelerations involved: weight over mass, V_e / tau_s
    scale = max(abs(m0e) * veh.g / M1, sp.speed / sp.tau_s)
    if not res <= 1e-8 * scale:
        raise SolverError(f"the buoyancy equilibrium at V_e = {speed:g} m/s has a residual {res:.3g} (relative "
                          f"{res / scale:.3g}): not an equilibrium to working accuracy")
    return BuoyancyEquilibrium(float(sp.speed), float(sp.gamma), float(sp.alpha), float(m0e), float(M1),
                               float(K_De), float(K_Le), float(sp.tau_s), float(sp.eps1), float(sp.eps2), res, sp,
                               veh, veh.provenance)


# ------------------------------------------------------------------------------------------------ controller
@dataclass(frozen=True)
class BuoyancyController:
    """Proportional buoyancy law (6.9), ``controller(t, x) -> (u1,)`` in kg/s, pump limits applied.

    ``u1 = (m_e / tau_s) (-K_b mbar0) = -(K_b / tau_s)(m0 - m0e)``, then the vehicle's rate limit and range
    (:meth:`ActuatorLimits.pump`).

    Parameters
    ----------
    eq : BuoyancyEquilibrium
        Target (``m0e`` in kg, ``tau_s`` in s).
    vehicle : Vehicle
        The controlled vehicle (its ``u4_max``, ``m0_max``).
    K_b : float
        Nondimensional gain of (6.9), > 0 (the closed-loop buoyancy time constant is ``tau_s / K_b`` seconds when
        the pump is not rate limited).

    Raises
    ------
    ArgumentTypeError
        If ``eq`` is not a BuoyancyEquilibrium, ``vehicle`` not a Vehicle or ``K_b`` not a real number.
    ArgumentError
        If ``K_b`` is not a positive finite number.
    ModelError
        If ``vehicle`` is not an underwater glider.
    VehicleMismatchError
        If ``eq`` was computed for another vehicle.
    """

    eq: BuoyancyEquilibrium
    vehicle: Vehicle
    K_b: float = 1.0

    def __post_init__(self) -> None:
        require_instance("eq", self.eq, BuoyancyEquilibrium, " (from gc.buoyancy_equilibrium)")
        require_glider(self.vehicle)
        checks.same_vehicle("eq", self.eq, self.vehicle)
        object.__setattr__(self, "K_b", checks.positive("the buoyancy gain K_b of (6.9)", self.K_b))

    @cached_property
    def _limits(self) -> ActuatorLimits:
        """Pump and elevator limits of the vehicle (built once: the law is called many times)."""
        return actuator_limits(self.vehicle)

    @property
    def rate_gain(self) -> float:
        """``K_b / tau_s`` (1/s)."""
        return self.K_b / self.eq.tau_s

    def u(self, x: Any) -> np.ndarray:
        """Input ``(u1,)`` (kg/s), shape ``x.shape[:-1] + (1,)``, at states ``x = (V, gamma, alpha, Omega2, m0)``
        (shape ``(..., 5)``)."""
        m0 = trailing_array("x", x, 5)[..., 4]
        u = -self.rate_gain * (m0 - self.eq.m0e)
        return np.asarray(self._limits.pump(m0, u))[..., None]

    def __call__(self, t: float, x: Any) -> np.ndarray:
        return self.u(x)


# ------------------------------------------------------------------------------------------------ (6.10)-(6.12)
@dataclass(frozen=True)
class BuoyancyLyapunovCheck:
    """Sampled check of ``dnu_b/dt_n`` (6.11) along the true closed loop of (5.20)-(5.23), (6.8)-(6.9).

    Samples ``z = (Vbar, gammabar, alphabar, Omegabar2)`` uniformly in the certificate's box ``B_p x B_q`` and
    ``mbar0`` on a grid in ``[-mbar0_max, mbar0_max]``.

    Attributes
    ----------
    K_b, mbar0_max : float
        Gain of (6.9) and the sampled ``|mbar0|`` range.
    nu_certified : bool
        Whether ``nu`` is itself a certificate for the glide at ``m0e`` (``mu < mu_d``, Theorem 2).
    dnu_max_at_m0e : float
        ``max dnu/dt_n`` at ``mbar0 = 0`` (Theorem 2 says <= 0 when certified).
    cross_term_max : float
        ``max |C(z, mbar0)|`` with ``C = grad nu . [zdot(z, mbar0) - zdot(z, 0)]``: the term (6.11) omits. Zero
        would confirm the text; it is not.
    cross_coefficient : float
        ``max |C| / (|z| |mbar0|)`` over the samples (the ``b`` of ``|C| <= b |z| |mbar0|``).
    n_samples, n_positive : int
        Samples and samples with ``dnu_b/dt_n > 0`` for the gain ``K_b`` (unsaturated law, as in (6.11)).
    max_dnu_b : float
        ``max dnu_b/dt_n / (|z|^2 + mbar0^2)``, the largest normalized derivative (must be < 0 for (6.12)).
    max_dnu_b_at : ndarray
        ``(Vbar, gammabar, alphabar, Omegabar2, mbar0)`` of ``max_dnu_b``.
    K_b_required : float
        ``max over samples with mbar0 != 0 of (dnu/dt_n) / mbar0^2``: the smallest gain for which
        ``dnu_b/dt_n <= 0`` on every sample (``inf``-free lower bound of the true threshold on the box).
    K_b_required_local : float
        The same on the ball ``|z| <= local_radius``, ``0 < |mbar0| <= local_radius``.
    n_positive_local : int
        Samples in that ball with ``dnu_b/dt_n > 0`` for the gain ``K_b``.
    K_b_star : float
        Exact local threshold from the quadratic parts at the origin: with ``H`` the Hessian of ``nu``,
        ``A = d zdot/dz``, ``B = d zdot/d mbar0`` and ``S = sym(H A)`` (negative definite when ``nu`` is a local
        Lyapunov function), ``dnu_b/dt_n = z^T S z + z^T H B mbar0 - K_b mbar0^2 + O(3)`` is negative definite
        iff ``K_b > K_b_star = (H B)^T (-S)^-1 (H B) / 4``. For ``K_b < K_b_star`` there are points arbitrarily
        close to the origin where ``dnu_b/dt_n > 0``: (6.12) fails for small gains.
    z_star : ndarray
        ``-S^-1 H B / 2``: along ``z = z_star mbar0`` the quadratic part of ``dnu/dt_n`` equals ``K_b_star
        mbar0^2`` (the worst direction).
    local_radius : float
    vehicle : Vehicle
        The vehicle (keyword-only).
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    margins : dict[str, float]
        One entry per condition (``>= 1`` holds): ``K_b / K_b_required`` on the box and near 0, ``K_b / K_b_star``
        (each ``inf`` when the threshold is ``<= 0``), and ``inf``/``0.0`` for ``dnu/dt_n <= 0`` at ``m0e``.
    passed : bool
        (6.12) with this ``K_b``: no positive sample (box and ball) and ``K_b > K_b_star``.
    """

    K_b: float
    mbar0_max: float
    nu_certified: bool
    mu: float
    mu_d: float
    dnu_max_at_m0e: float
    cross_term_max: float
    cross_coefficient: float
    n_samples: int
    n_positive: int
    max_dnu_b: float
    max_dnu_b_at: np.ndarray = field(repr=False)
    K_b_required: float = math.nan
    K_b_required_local: float = math.nan
    n_positive_local: int = 0
    K_b_star: float = math.nan
    z_star: np.ndarray = field(default_factory=lambda: np.full(4, np.nan), repr=False)
    local_radius: float = 0.0
    seed: int = 0
    provenance: str = field(default="", repr=False)
    vehicle: Vehicle = field(repr=False, compare=False, kw_only=True)

    @property
    def passed(self) -> bool:
        """(6.12) with this ``K_b``: no positive sample (box and ball) and ``K_b > K_b_star``."""
        return self.n_positive == 0 and self.n_positive_local == 0 and self.K_b > self.K_b_star

    @property
    def margins(self) -> dict[str, float]:
        """One margin per condition (``>= 1`` holds); see the class docstring."""
        def over(threshold: float) -> float:
            return math.inf if threshold <= 0 else self.K_b / threshold

        return {"K_b >= K_b_required (box)": over(self.K_b_required),
                "K_b >= K_b_required (near 0)": over(self.K_b_required_local),
                "K_b > K_b_star": over(self.K_b_star),
                "dnu/dt_n <= 0 at m0e": math.inf if self.dnu_max_at_m0e <= 0 else 0.0}

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1 (relative tolerance 1e-9)."""
        return {k: m for k, m in self.margins.items() if not m >= 1 - 1e-9}


def _nd_rates(veh: Vehicle, sp: SingularPerturbation, z: np.ndarray, m0: np.ndarray,
              f3: Any = 0.0, M2: Any = 0.0) -> np.ndarray:
    """``dz/dt_n`` of (5.20)-(5.23) (with extra load) at nondimensional ``z`` and dimensional buoyancy ``m0``."""
    x = sp.to_dimensional(z)
    r = loaded_rates(veh, np.concatenate([x, m0[..., None]], axis=-1), f3, M2)
    return sp.tau_s * np.stack([r[..., 0] / sp.speed, r[..., 1], r[..., 2], sp.omega_scale * r[..., 3]], axis=-1)


def _grad_nu(cert: CompositeCertificate, z: np.ndarray) -> np.ndarray:
    h = 1e-30
    g = np.empty_like(z)
    for j in range(4):
        g[:, j] = partial_derivative(cert.nu, z, j, h)
    return g


def _check_lyapunov_args(eq: Any, veh: Any, cert: Any) -> None:
    require_instance("eq", eq, BuoyancyEquilibrium, " (from gc.buoyancy_equilibrium)")
    require_glider(veh, "veh")
    checks.same_vehicle("eq", eq, veh)
    if cert is not None:
        require_instance("cert", cert, CompositeCertificate, " (from gc.composite_lyapunov)")


def nu_b_derivative(eq: BuoyancyEquilibrium, veh: Vehicle, cert: CompositeCertificate, z: Any, mbar0: Any,
                    K_b: float) -> tuple[np.ndarray, np.ndarray]:
    """``dnu_b/dt_n`` (6.11) along the true closed loop, and the cross term the text omits.

    Parameters
    ----------
    eq : BuoyancyEquilibrium
        Target glide (coordinates (5.12)-(5.15), ``tau_s``, ``m0e``, ``m_e``).
    veh : Vehicle
    cert : CompositeCertificate
        ``nu`` (5.83) of the vehicle at ``m0e``.
    z : array_like, shape (N, 4)
        ``(Vbar, gammabar, alphabar, Omegabar2)``.
    mbar0 : array_like, shape (N,)
        ``(m0 - m0e)/m_e``.
    K_b : float
        Gain of (6.9) (unsaturated law, as in (6.11)).

    Returns
    -------
    dnu_b : ``grad nu(z) . zdot(z, mbar0) - K_b mbar0^2``
    cross : ``grad nu(z) . [zdot(z, mbar0) - zdot(z, 0)]`` (zero according to the text)

    Raises
    ------
    ArgumentTypeError
        If an argument has the wrong type.
    ArgumentError
        If ``z`` is not finite of shape ``(N, 4)``, ``mbar0`` not finite and broadcastable to ``(N,)``, or ``K_b``
        not finite.
    VehicleMismatchError
        If ``eq`` was computed for another vehicle.
    """
    _check_lyapunov_args(eq, veh, cert)
    K_b = checks.real("K_b", K_b)
    z = np.atleast_2d(checks.array("z", z))
    if z.ndim != 2 or z.shape[1] != 4:
        raise ArgumentError(f"z must have shape (N, 4), got {z.shape}")
    mbar0 = checks.array("mbar0", mbar0)
    try:
        mb = np.broadcast_to(mbar0, z.shape[:1])
    except ValueError as exc:
        raise ArgumentError(f"mbar0 of shape {mbar0.shape} does not broadcast to ({z.shape[0]},)") from exc
    gn = _grad_nu(cert, z)
    dnu_m = np.sum(gn * _nd_rates(veh, eq.sp, z, eq.m0e + eq.m_e * mb), axis=1)
    dnu_0 = np.sum(gn * _nd_rates(veh, eq.sp, z, np.full(len(z), eq.m0e)), axis=1)
    return dnu_m - K_b * mb**2, dnu_m - dnu_0


def _local_threshold(cert: CompositeCertificate, veh: Vehicle,
                     eq: BuoyancyEquilibrium) -> tuple[float, np.ndarray]:
    """``K_b_star`` of :class:`BuoyancyLyapunovCheck` (Hessian of ``nu`` by central differences of its exact
    complex-step gradient; ``A`` by complex step; ``B`` by a central difference in ``m0``)."""
    sp = eq.sp
    h = 1e-6
    E = np.eye(4)
    H = (_grad_nu(cert, h * E) - _grad_nu(cert, -h * E)) / (2 * h)
    H = 0.5 * (H + H.T)
    hc = 1e-30
    A = jacobian_batch(lambda Z: _nd_rates(veh, sp, Z, np.full(4, eq.m0e)), np.zeros(4), hc)
    dm = 1e-6
    z0 = np.zeros((1, 4))
    B = ((_nd_rates(veh, sp, z0, np.array([eq.m0e + eq.m_e * dm]))
          - _nd_rates(veh, sp, z0, np.array([eq.m0e - eq.m_e * dm]))) / (2 * dm))[0]
    S = 0.5 * (H @ A + (H @ A).T)
    if np.max(np.linalg.eigvalsh(S)) >= 0:
        return math.inf, np.full(4, np.nan)  # nu is not a strict local Lyapunov function: no gain helps
    b = H @ B
    return float(b @ np.linalg.solve(-S, b) / 4), -0.5 * np.linalg.solve(S, b)


def buoyancy_lyapunov_check(eq: BuoyancyEquilibrium, veh: Vehicle, *, K_b: float = 1.0, mbar0_max: float = 0.01,
                            n: int = 20_000, n_m0: int = 21, local_radius: float = 0.02, seed: int = 0,
                            cert: CompositeCertificate | None = None) -> BuoyancyLyapunovCheck:
    """Sample ``dnu_b/dt_n`` of (6.11) along the true closed loop and measure the cross term the text omits.

    Parameters
    ----------
    eq : BuoyancyEquilibrium
        Target glide (its ``sp`` defines the nondimensional coordinates (5.12)-(5.15) and ``tau_s``).
    veh : Vehicle
        The vehicle (any nominal ``m0``; the dynamics use ``m0 = m0e + m_e mbar0``).
    K_b : float
        Gain of (6.9).
    mbar0_max : float
        Half-width of the sampled ``mbar0`` interval (nondimensional; ``|m0 - m0e| <= m_e mbar0_max`` kg).
    n, n_m0 : int
        Number of samples of ``z`` (``1 <= n <= 10^6``, the budget of the check) and of grid values of ``mbar0``
        (odd, ``3 <= n_m0 <= 10001``, so that 0 is on the grid).
    local_radius : float
        Radius of the small ball on which ``K_b_required_local`` is measured, in ``(0, 1]``.
    seed : int
        Seed of the random sampler (``>= 0``).
    cert : CompositeCertificate, optional
        ``composite_lyapunov`` of the vehicle at ``m0e`` (default: its default domain ``|Vbar| <= 0.4``,
        ``|alphabar| <= 0.2``).

    Returns
    -------
    BuoyancyLyapunovCheck
        Sample counts, the largest normalized ``dnu_b/dt_n`` and where it occurs, the size of the omitted cross
        term, the gains required on the box and near the origin and the exact local threshold ``K_b_star``
        (all nondimensional, time ``t_n = t / tau_s``), with ``passed`` and ``margins``.

    Raises
    ------
    ArgumentTypeError
        If ``eq`` is not a BuoyancyEquilibrium, ``veh`` not a Vehicle, ``cert`` not a CompositeCertificate, or a
        number has the wrong type (``n``, ``n_m0``, ``seed`` must be integers).
    ArgumentError
        If ``K_b``, ``mbar0_max`` or ``local_radius`` is not a positive finite number (``local_radius <= 1``),
        ``n`` is not in ``[1, 10^6]``, ``n_m0`` is not an odd number in ``[3, 10001]`` or ``seed`` is negative.
    VehicleMismatchError
        If ``eq`` was computed for another vehicle.
    ModelError
        If ``veh`` is not an underwater glider, or (default ``cert``) the vehicle at ``m0e`` has no singularly
        perturbed chapter-5 glide or has unequal added masses (from
        :func:`~glidectl.stability.composite.composite_lyapunov`).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5", K_M=-100.0)      # the certified variant of section 5.3.1
    >>> eq = gc.buoyancy_equilibrium(veh, 1.79)
    >>> chk = gc.buoyancy_lyapunov_check(eq, veh, K_b=1.0, n=2000)
    >>> chk.passed, f"K_b* = {chk.K_b_star:.0f}"
    (False, 'K_b* = 191')
    >>> gc.buoyancy_lyapunov_check(eq, veh, K_b=400.0, n=2000).passed
    True
    """
    _check_lyapunov_args(eq, veh, cert)
    K_b = checks.positive("K_b", K_b)
    mbar0_max = checks.positive("mbar0_max", mbar0_max)
    n = checks.integer("n", n, lo=1, hi=1_000_000)
    n_m0 = checks.integer("n_m0", n_m0, lo=3, hi=10_001)
    if n_m0 % 2 == 0:
        raise ArgumentError(f"n_m0 must be odd (so that mbar0 = 0 is on the grid), got {n_m0}")
    local_radius = checks.real("local_radius", local_radius, lo=0.0, hi=1.0, lo_open=True)
    seed = checks.integer("seed", seed, lo=0)
    if cert is None:
        cert = composite_lyapunov(veh.with_overrides(m0=eq.m0e))
    rng = np.random.default_rng(seed)
    grid = np.linspace(-mbar0_max, mbar0_max, n_m0)

    def evaluate(z: np.ndarray, mb: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        dnu_m, C = nu_b_derivative(eq, veh, cert, z, mb, 0.0)
        return dnu_m, dnu_m - C, C

    z = cert.domain.sample(n, rng, omega_extent=cert.omega_extent)
    mb = rng.choice(grid, n)
    dnu_m, dnu_0, C = evaluate(z, mb)
    zn = np.linalg.norm(z, axis=1)
    dnub = dnu_m - K_b * mb**2
    r2 = zn**2 + mb**2
    ok = r2 > 1e-14
    ratio = np.where(ok, dnub / np.where(ok, r2, 1.0), -np.inf)
    i = int(np.argmax(ratio))
    nz = (np.abs(mb) > 0) & (zn > 0)
    coef = float(np.max(np.abs(C[nz]) / (zn[nz] * np.abs(mb[nz])))) if np.any(nz) else 0.0
    mnz = np.abs(mb) > 0
    Kreq = float(np.max(dnu_m[mnz] / mb[mnz] ** 2))
    # small ball around the origin: z uniform in the 4-ball of radius local_radius, mbar0 on a nonzero grid
    d = rng.standard_normal((n, 4))
    d *= (local_radius * rng.random(n) ** 0.25 / np.linalg.norm(d, axis=1))[:, None]
    lgrid = np.linspace(-local_radius, local_radius, n_m0 + 1)
    mb_l = rng.choice(lgrid, n)
    dm_l, _, _ = evaluate(d, mb_l)
    npos_l = int(np.sum(dm_l - K_b * mb_l**2 > 0))
    kstar, zstar = _local_threshold(cert, veh, eq)
    Kreq_l = float(np.max(dm_l / mb_l**2))
    return BuoyancyLyapunovCheck(float(K_b), float(mbar0_max), cert.certified, float(cert.mu), float(cert.mu_d),
                                 float(np.max(dnu_0)), float(np.max(np.abs(C))), coef, int(n),
                                 int(np.sum(dnub[ok] > 0)), float(ratio[i]),
                                 np.concatenate([z[i], [mb[i]]]), Kreq, Kreq_l, npos_l, kstar, zstar,
                                 float(local_radius), int(seed), veh.provenance, vehicle=veh)
