"""Pure torque control of the chapter-5 glider, §6.1: control law (6.5) for the model (6.1)-(6.4), the closed-loop
equilibrium and small parameters, and a gain-selection routine built on the composite Lyapunov function of §5.2-§5.3
with the time-scale-ratio constraint (6.6).

One right-hand side
-------------------
:class:`~glidectl.models.torque_glider.TorqueControlledGlider` is
:class:`~glidectl.models.reduced.ReducedLongitudinalGlider` with the control torque ``u`` (N m) added to the pitch
equation, ``J2 Omega2' = ... + u`` (6.4). Under the law (6.5), ``u = (K_M0u + K_Mu alpha + K_qu Omega2) V^2``,
the closed loop *is* the open-loop glider with the moment coefficients ``K_M0 + K_M0u``, ``K_M + K_Mu``,
``K_q + K_qu`` (tested to 1e-12), so the closed-loop equilibrium, ``eps1``, ``eps2``, ``mu`` and ``mu_d`` are
those of :func:`~glidectl.stability.singular_perturbation.singular_perturbation` and
:func:`~glidectl.stability.composite.composite_lyapunov` applied to :meth:`TorqueLaw.closed_loop_vehicle` (one
source of truth; no closed-loop formula is coded twice).

Corrections to the text (checked by the tests)
----------------------------------------------
Write ``K_M' = K_M + K_Mu`` (kg/rad), ``K_q' = K_q + K_qu`` (kg s/rad), ``K_De`` (kg/m), ``J2`` (kg m^2),
``m1`` (kg), ``V_e`` (m/s), and ``tau_s = m1/(K_De V_e)`` (5.18).

1. ``eps2`` after (6.5) is printed as ``-K_De V_e^3 J2 / (m1 K_q')``; its dimension is
   ``(kg/m)(m/s)^3(kg m^2)/(kg * kg s) = m^4/s^4``, so it is not a small *parameter*. The chapter-5 definition
   (5.17), ``eps2 = -J2/(K_q' V_e^2 tau_s)``, gives ``eps2 = -K_De J2 / (m1 K_q' V_e)`` (dimensionless):
   ``V_e^-1``, not ``V_e^3`` (they agree only for ``V_e = 1 m/s``).
2. ``alpha_e = -(K_M0 + K_M0u)/(K_M + K_Mu)`` and ``eps1 = K_De V_e K_q' / (m1 K_M')`` are right (``eps1`` is
   dimensionless) for equal added masses; with ``m1 != m3`` ``alpha_e`` solves (5.90) with the closed-loop
   coefficients instead.
3. (6.6): from the corrected ``eps1, eps2``, ``eps1/eps2 = -K_q'^2 V_e^2 / (K_M' J2)`` (positive: ``K_M' < 0``).
   The printed ``J2 eps1/eps2 = (K_q')^2 V_e^2/K_M'`` has the wrong sign (the right side is negative); the
   constraint itself, ``K_q'^2 V_e^2 / K_M' = K_q^2 V_eol^2 / K_M``, is unaffected because both sides carry the same
   sign error. Its ``V_e^2`` is consistent with the corrected ``eps2`` only (the printed ``eps2`` would give
   ``V_e^-2``), which confirms correction 1. (Also ``r_1 = mu/eps2`` in the text means ``r_2``.)

Gain family
-----------
With ``alpha_e`` fixed by the target (through (5.8)-(5.9)), ``V_e``, ``gamma_e`` and ``K_De`` are fixed, and (6.6)
leaves one free parameter, the *scale* ``s > 0``: ``K_q' = s K_q,ref``, ``K_M' = s^2 K_M,ref`` with
``K_q,ref = K_q`` and ``K_M,ref = K_M (V_e/V_eol)^2`` (so ``s = 1`` is the open-loop damping). Then
``eps1, eps2, mu`` scale as ``1/s`` while ``r1, r2`` (hence ``mu_d``) are invariant; ``K_M0u`` places ``alpha_e``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, InfeasibleGlideError, ModelError, SolverError
from ..models._validate import angle_arg, require_glider, require_instance, speed_arg, trailing_array
from ..models.closed_loop import ClosedLoop
from ..models.reduced import ReducedLongitudinalGlider, require_v2_pitch_damping
from ..models.torque_glider import TorqueControlledGlider
from ..params import Vehicle
from ..stability.composite import CompositeCertificate, composite_lyapunov
from ..stability.singular_perturbation import SingularPerturbation, singular_perturbation
from ..trim.glide import alpha_for_gamma, permissible_gamma

__all__ = [
    "TorqueDesign",
    "TorqueGainFamily",
    "TorqueLaw",
    "alpha_for_target",
    "closed_loop_formulas",
    "design_torque_control",
    "peak_torque",
    "torque_gain_family",
]


# ------------------------------------------------------------------------------------------------ law (6.5)
@dataclass(frozen=True)
class TorqueLaw:
    """Torque feedback (6.5), ``u = (K_M0u + K_Mu alpha + K_qu Omega2) V^2`` (N m).

    Attributes
    ----------
    K_M0u : float
        Constant moment gain (kg).
    K_Mu : float
        Angle-of-attack gain (kg/rad).
    K_qu : float
        Pitch-rate gain (kg s/rad).

    ``law(t, x)`` returns shape ``x.shape[:-1] + (1,)`` for a state ``x = (V, gamma, alpha, Omega2)`` (batch-safe),
    so it plugs into :func:`glidectl.sim.simulate` with :class:`TorqueControlledGlider`.

    Raises
    ------
    ArgumentTypeError
        If a gain is not a real number.
    ArgumentError
        If a gain is not finite.
    """

    K_M0u: float
    K_Mu: float
    K_qu: float

    def __post_init__(self) -> None:
        for k, unit in (("K_M0u", "kg"), ("K_Mu", "kg/rad"), ("K_qu", "kg s/rad")):
            object.__setattr__(self, k, checks.real(f"torque gain {k}", getattr(self, k), unit=unit))

    def torque(self, x: Any) -> Any:
        """Control torque (N m), shape ``x.shape[:-1]``, at state ``x = (V, gamma, alpha, Omega2)`` (shape
        ``(..., 4)``)."""
        x = trailing_array("x", x, 4, ("V", "gamma", "alpha", "Omega2"))
        V, al, Om = x[..., 0], x[..., 2], x[..., 3]
        return (self.K_M0u + self.K_Mu * al + self.K_qu * Om) * V * V

    def u(self, x: Any) -> Any:
        """Input ``(torque,)`` (N m), shape ``x.shape[:-1] + (1,)``, at states ``x = (V, gamma, alpha, Omega2)``."""
        return self.torque(x)[..., None]

    def __call__(self, t: float, x: Any) -> Any:
        return self.u(x)

    def closed_loop_vehicle(self, veh: Vehicle) -> Vehicle:
        """The open-loop vehicle with ``K_M0 + K_M0u``, ``K_M + K_Mu``, ``K_q + K_qu``: the closed loop of (6.5).

        Raises
        ------
        ArgumentTypeError
            If ``veh`` is not a Vehicle.
        ModelError
            If it is not an underwater glider, or its pitch damping is not the ``K_q`` form that (6.5) adds to.
        """
        require_glider(veh, "veh")
        require_v2_pitch_damping(veh, "the torque feedback (6.5), which adds K_qu to K_q")
        return veh.with_overrides(K_M0=veh.K_M0 + self.K_M0u, K_M=veh.K_M + self.K_Mu, K_q=veh.K_q + self.K_qu)

    def closed_loop(self, veh: Vehicle, equilibrium: Any = None) -> ClosedLoop:
        """Input-free closed loop of (6.1)-(6.4) with (6.5): :class:`~glidectl.models.closed_loop.ClosedLoop` of
        ``TorqueControlledGlider(veh)`` and :meth:`u` (for :func:`glidectl.sim.simulate_many`).

        Parameters
        ----------
        veh : Vehicle
            Open-loop vehicle.
        equilibrium : array_like, optional
            Closed-loop steady glide ``(V_e, gamma_e, alpha_e, 0)`` (m/s, rad, rad, rad/s), if known (e.g.
            ``singular_perturbation(self.closed_loop_vehicle(veh)).equilibrium``).
        """
        return ClosedLoop(TorqueControlledGlider(veh), self.u, equilibrium, "torque law (6.5)")


def closed_loop_formulas(veh: Vehicle, law: TorqueLaw, *, printed: bool = False) -> dict[str, float]:
    """The closed-loop formulas printed after (6.5), evaluated at the closed-loop steady glide.

    Parameters
    ----------
    veh : Vehicle
        Open-loop vehicle (equal added masses, §6.1).
    law : TorqueLaw
    printed : bool
        ``True``: ``eps2`` as printed, ``-K_De V_e^3 J2/(m1 K_q')`` (dimension m^4/s^4, wrong); ``False``: the
        corrected ``-K_De J2/(m1 K_q' V_e)`` from (5.17).

    Returns
    -------
    dict
        ``alpha_e`` (rad), ``eps1``, ``eps2``, and ``V_e`` (m/s), ``K_De`` (kg/m) used; ``m1`` is the translational
        mass ``m3 + mbar`` of the reduced model (= ``m1 + mbar`` for equal added masses).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``law`` not a TorqueLaw, or ``printed`` not a bool.
    ModelError
        If ``veh`` is not an underwater glider, has unequal added masses (``m1 != m3``, the formulas assume
        (5.10)), or the closed-loop vehicle has no singularly perturbed chapter-5 glide (``m0 = 0``, closed-loop
        ``K_M' = 0``, ``K_q' >= 0`` or ``K_M' >= 0``; from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("sphere_ch5")
    >>> law = gc.design_torque_control(veh, speed=1.6).law
    >>> f = gc.closed_loop_formulas(veh, law)
    >>> print(f"alpha_e = {f['alpha_e']:.4f} rad, eps1 = {f['eps1']:.2e}, eps2 = {f['eps2']:.2e}")
    alpha_e = 0.0231 rad, eps1 = 2.52e-03, eps2 = 2.32e-04
    """
    require_glider(veh, "veh")
    require_instance("law", law, TorqueLaw)
    checks.boolean("printed", printed)
    if ReducedLongitudinalGlider(veh).delta_m != 0:
        raise ModelError(f"vehicle '{veh.name}' has unequal added masses (Delta m = "
                         f"{ReducedLongitudinalGlider(veh).delta_m:g} kg): the formulas after (6.5) assume "
                         "m1 = m3 (alpha_e = -K_M0'/K_M', (5.10))")
    KM, Kq, KM0 = veh.K_M + law.K_Mu, veh.K_q + law.K_qu, veh.K_M0 + law.K_M0u
    sp = singular_perturbation(law.closed_loop_vehicle(veh))
    _, m1 = sp.model.masses
    alpha_e = -KM0 / KM
    eps1 = sp.K_De * sp.speed * Kq / (m1 * KM)
    V3 = sp.speed**3 if printed else 1.0 / sp.speed
    eps2 = -sp.K_De * V3 * veh.J2 / (m1 * Kq)
    return {"alpha_e": alpha_e, "eps1": eps1, "eps2": eps2, "V_e": sp.speed, "K_De": sp.K_De}


# ------------------------------------------------------------------------------------------------ targets (5.8)-(5.9)
def alpha_for_target(veh: Vehicle, *, speed: float | None = None, gamma: float | None = None) -> float:
    """Equilibrium angle of attack (rad) giving a requested steady-glide speed or flight-path angle, (5.8)-(5.9).

    ``m0`` is fixed (the vehicle's), so (5.8) ``V_e^2 sqrt(K_De^2 + K_Le^2) = |m0| g`` with
    ``K_De = K_D0 + K_D a^2``, ``K_Le = K_L0 + K_L a`` is a quartic in ``a``; (5.9) ``tan(gamma_e) = -K_De/K_Le`` is
    solved by :func:`glidectl.trim.glide.alpha_for_gamma` (the quadratic of the permissible set (2.26)). Of several
    roots, the one of smallest ``|a|`` with lift of the sign of ``m0`` (a heavy glider glides down) and
    ``|a| < pi/4`` (the range of §5.4) is returned.

    Parameters
    ----------
    veh : Vehicle
        Underwater glider with ``m0 != 0`` (kg), ``g`` (m/s^2) and the lift/drag coefficients.
    speed : float, optional
        Target ``V_e`` (m/s).
    gamma : float, optional
        Target ``gamma_e`` (rad); exactly one of ``speed``, ``gamma``.

    Returns
    -------
    float
        ``alpha_e`` (rad), ``|alpha_e| < pi/4``.

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle or a target is not a real number.
    ArgumentError
        If both or neither target is given, ``speed`` is not in ``(0, 100]`` m/s, or ``gamma`` is not finite.
    ModelError
        If ``veh`` is not an underwater glider accepted by the chapter-5 model (``m0 != 0``).
    InfeasibleGlideError
        If no such angle of attack exists (speed above the fastest glide of this ``m0``, ``gamma`` outside the
        permissible set or of the wrong sign for the sign of ``m0``).
    """
    require_glider(veh, "veh")
    if (speed is None) == (gamma is None):
        raise ArgumentError("give exactly one target: speed= (m/s) or gamma= (rad)")
    if speed is not None:
        speed = speed_arg("target speed", speed)
    else:
        gamma = angle_arg("target gamma", gamma)
    ReducedLongitudinalGlider(veh)
    m0, g = veh.m0, veh.g
    KD0, KD, KL0, KL = veh.K_D0, veh.K_D, veh.K_L0, veh.K_L
    if speed is not None:
        c = abs(m0) * g / speed**2
        roots = np.roots([KD * KD, 0.0, 2 * KD0 * KD + KL * KL, 2 * KL0 * KL, KD0 * KD0 + KL0 * KL0 - c * c])
        ok = [float(r.real) for r in roots if abs(r.imag) < 1e-9 * max(1.0, abs(r))
              and m0 * (KL0 + KL * r.real) > 0 and abs(r.real) < math.pi / 4]
        if not ok:
            a = np.linspace(-math.pi / 4, math.pi / 4, 20001)
            a = a[m0 * (KL0 + KL * a) > 0]
            vmax = math.sqrt(abs(m0) * g / float(np.min(np.hypot(KD0 + KD * a * a, KL0 + KL * a)))) if a.size \
                else float("nan")
            raise InfeasibleGlideError(
                f"no steady glide of vehicle '{veh.name}' at V_e = {speed:g} m/s with m0 = {m0:g} kg: (5.8) needs "
                f"sqrt(K_De^2 + K_Le^2) = |m0| g / V_e^2 = {c:.4g} kg/m at some |alpha_e| < 45 deg with lift of the "
                f"sign of m0; reachable speeds are V_e < {vmax:.4g} m/s (change the target or m0 by buoyancy control)")
        return min(ok, key=abs)
    assert gamma is not None
    lo, hi = permissible_gamma(veh)
    down = m0 > 0
    text = (f"vehicle '{veh.name}' with m0 = {m0:g} kg glides {'down' if down else 'up'}: steady glides need "
            + (f"-90 deg < gamma < {math.degrees(lo):.4f} deg" if down else f"{math.degrees(hi):.4f} deg < gamma < "
               "90 deg") + " ((2.26), (5.9))")
    if not (abs(gamma) < math.pi / 2 and ((down and gamma < lo) or (not down and gamma > hi))):
        raise InfeasibleGlideError(f"no steady glide at gamma = {math.degrees(gamma):.4f} deg: {text}")
    try:
        a = alpha_for_gamma(veh, gamma)
    except ValueError:
        raise InfeasibleGlideError(f"no steady glide at gamma = {math.degrees(gamma):.4f} deg: {text}") from None
    if abs(a) >= math.pi / 4:
        raise InfeasibleGlideError(f"gamma = {math.degrees(gamma):.4f} deg needs alpha_e = {math.degrees(a):.2f} deg, "
                                   "outside |alpha| < 45 deg assumed by §5.4")
    return float(a)


# ------------------------------------------------------------------------------------------------ gain family (6.6)
@dataclass(frozen=True)
class TorqueGainFamily:
    """The one-parameter family of gains (6.5) with a fixed ``alpha_e`` and a fixed ``eps1/eps2`` (6.6).

    ``K_q' = s Kq_ref``, ``K_M' = s^2 KM_ref`` and ``K_M0'`` placing ``alpha_e`` ((5.10), or (5.90) for
    ``m1 != m3``); ``eps1, eps2, mu`` of the closed loop scale as ``1/s``.

    Attributes
    ----------
    vehicle : Vehicle
        Open-loop vehicle.
    alpha : float
        Closed-loop equilibrium angle of attack ``alpha_e`` (rad).
    speed : float
        Closed-loop equilibrium speed ``V_e`` (m/s), (5.8) at ``alpha_e``.
    Kq_ref : float
        ``K_q'`` at ``s = 1`` (kg s/rad): the open-loop ``K_q``.
    KM_ref : float
        ``K_M'`` at ``s = 1`` (kg/rad): ``K_M (V_e/V_eol)^2`` by (6.6), or ``-Kq_ref^2 V_e^2/(eps_ratio J2)``.
    eps_ratio : float
        ``eps1/eps2`` of every member.
    provenance : str
        The open-loop vehicle's parameter hash (:attr:`Vehicle.provenance`).
    """

    vehicle: Vehicle = field(repr=False, compare=False)
    alpha: float
    speed: float
    Kq_ref: float
    KM_ref: float
    eps_ratio: float
    provenance: str = ""

    def gains(self, s: Any) -> tuple[Any, Any, Any]:
        """``(K_M0u, K_Mu, K_qu)`` (kg, kg/rad, kg s/rad) at scale ``s`` (array-capable, positive finite)."""
        s = checks.array("s", s)
        if not np.all(s > 0):
            raise ArgumentError(f"gain scale s must be positive, got {s!r}")
        veh, a = self.vehicle, self.alpha
        KM, Kq = s * s * self.KM_ref, s * self.Kq_ref
        KM0 = -(KM * a + ReducedLongitudinalGlider(veh).delta_m * math.sin(a) * math.cos(a))
        return KM0 - veh.K_M0, KM - veh.K_M, Kq - veh.K_q

    def law(self, s: float) -> TorqueLaw:
        """The :class:`TorqueLaw` at scale ``s > 0``.

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``s`` is not a positive finite number.
        """
        s = checks.positive("gain scale s", s)
        return TorqueLaw(*(float(g) for g in self.gains(s)))


def torque_gain_family(veh: Vehicle, alpha_e: float, *, eps_ratio: float | None = None) -> TorqueGainFamily:
    """The gain family of (6.6) for a closed-loop ``alpha_e`` (rad); see :class:`TorqueGainFamily`.

    Parameters
    ----------
    veh : Vehicle
        Open-loop chapter-5 glider.
    alpha_e : float
        Target equilibrium angle of attack (rad), e.g. from :func:`alpha_for_target`.
    eps_ratio : float, optional
        ``eps1/eps2`` to keep; default the open-loop one (6.6), ``-K_q^2 V_eol^2/(K_M J2)``. Required when the open
        loop has no steady glide or no pitch damping/stiffness (``K_q >= 0`` or ``K_M >= 0``).

    Returns
    -------
    TorqueGainFamily
        The closed-loop ``alpha_e`` (rad) and ``V_e`` (m/s), the reference gains ``Kq_ref`` (kg s/rad) and
        ``KM_ref`` (kg/rad) at scale ``s = 1``, and the kept ``eps1/eps2`` (nondimensional).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, or ``alpha_e`` or ``eps_ratio`` is not a real number.
    ArgumentError
        If ``alpha_e`` is not finite with ``|alpha_e| < pi/4`` (§5.4), or ``eps_ratio`` is given and is not a
        positive finite number.
    ModelError
        If ``veh`` is not an underwater glider or has ``m0 = 0``; the target glide at ``alpha_e`` is not singularly
        perturbed (e.g. ``K_De <= 0``); or ``eps_ratio`` is omitted and the open loop has no singularly perturbed
        glide.

    Examples
    --------
    >>> import glidectl as gc
    >>> fam = gc.torque_gain_family(gc.load_vehicle("sphere_ch5"), alpha_e=0.0231)
    >>> print(f"V_e = {fam.speed:.3f} m/s, K_q,ref = {fam.Kq_ref:.1f} kg s/rad, eps1/eps2 = {fam.eps_ratio:.2f}")
    V_e = 1.600 m/s, K_q,ref = -2.0 kg s/rad, eps1/eps2 = 10.86
    """
    require_glider(veh, "veh")
    alpha_e = angle_arg("alpha_e", alpha_e, math.pi / 4, open_ends=True)
    if eps_ratio is not None:
        eps_ratio = checks.positive("eps_ratio", eps_ratio)
    ReducedLongitudinalGlider(veh)
    dm = ReducedLongitudinalGlider(veh).delta_m
    KM_t = veh.K_M if veh.K_M < 0 else -1.0
    # the target glide (V_e, K_De depend on alpha_e only), from the model with any K_M' < 0, K_q' < 0
    sp_t = singular_perturbation(veh.with_overrides(
        K_M0=-(KM_t * alpha_e + dm * math.sin(alpha_e) * math.cos(alpha_e)), K_M=KM_t,
        K_q=veh.K_q if veh.K_q < 0 else -1.0))
    V_e, J2 = sp_t.speed, veh.J2
    if eps_ratio is None:
        try:
            sp_ol: SingularPerturbation = singular_perturbation(veh)
        except ModelError as exc:
            raise ModelError(f"the constraint (6.6) uses the open-loop glide and K_q, K_M, but: {exc}; pass "
                             "eps_ratio= (eps1/eps2) explicitly") from None
        return TorqueGainFamily(veh, float(alpha_e), V_e, veh.K_q, veh.K_M * (V_e / sp_ol.speed) ** 2,
                                sp_ol.eps1 / sp_ol.eps2, veh.provenance)
    Kq_ref = veh.K_q if veh.K_q < 0 else -J2 / (V_e**2 * sp_t.tau_s)  # else eps2 = 1 at s = 1 (5.17)
    return TorqueGainFamily(veh, float(alpha_e), V_e, Kq_ref, -Kq_ref**2 * V_e**2 / (eps_ratio * J2), eps_ratio,
                            veh.provenance)


# ------------------------------------------------------------------------------------------------ design
@dataclass(frozen=True)
class TorqueDesign:
    """A torque-control design of §6.1 (immutable, with provenance).

    Attributes
    ----------
    law : TorqueLaw
        Gains ``K_M0u`` (kg), ``K_Mu`` (kg/rad), ``K_qu`` (kg s/rad) of (6.5).
    target : str
        ``"speed"`` or ``"gamma"``; ``target_value`` in m/s or rad.
    scale : float
        Gain scale ``s`` of the (6.6) family (module docstring); ``scale_boundary`` the smallest certifying scale
        (``mu = mu_d`` there), found by bisection on the certificate.
    speed, gamma, alpha : float
        Closed-loop steady glide ``V_e, gamma_e, alpha_e`` (m/s, rad, rad).
    eps1, eps2, mu, mu_d : float
        Closed-loop small parameters (5.16)-(5.17), ``mu`` (5.26) and ``mu_d`` of Theorem 2 on the domain.
    eps_ratio : float
        ``eps1/eps2``, kept fixed by (6.6).
    certified : bool
        ``mu < mu_d``.
    peak_torque : float
        ``max |u|`` (N m) of (6.5) over ``V = V_e (1 + Vbar)``, ``alpha = alpha_e + alphabar`` on the domain box and
        ``|Omegabar2| <= omegabar_reach``, the largest ``|Omegabar2|`` in ``{W <= w0}`` (which contains the region
        of attraction estimate ``L*`` (5.85); capped by a finite ``Omegabar`` bound of the domain). It bounds
        ``|u(t)|`` along every trajectory starting in ``L*``. Computed exactly: ``u/V^2`` is affine in
        ``(alpha, Omega2)``, so the maximum is at ``V_max`` and a corner.
    omegabar_reach : float
        See ``peak_torque`` (dimensionless, ``Omegabar2 = (K_q'/K_M') Omega2``).
    torque_max : float
        Torque bound requested (N m).
    certificate : CompositeCertificate
        Certificate of the closed-loop vehicle (``certificate.verify()`` samples every inequality).
    closed_loop_vehicle : Vehicle
        Open-loop vehicle with the closed-loop moment coefficients.
    vehicle : Vehicle
        The open-loop vehicle.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    plant_vehicle : Vehicle or None
        The open-loop vehicle the design is for (the plant of :func:`glidectl.closed_loop`).
    """

    law: TorqueLaw
    target: str
    target_value: float
    scale: float
    scale_boundary: float
    speed: float
    gamma: float
    alpha: float
    eps1: float
    eps2: float
    mu: float
    mu_d: float
    eps_ratio: float
    certified: bool
    peak_torque: float
    omegabar_reach: float
    torque_max: float
    certificate: CompositeCertificate = field(repr=False)
    closed_loop_vehicle: Vehicle = field(repr=False)
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str = ""
    plant_vehicle: Vehicle | None = field(default=None, repr=False, compare=False)

    @property
    def equilibrium(self) -> np.ndarray:
        """Closed-loop steady glide ``(speed, gamma, alpha, 0)`` (m/s, rad, rad, rad/s)."""
        return np.array([self.speed, self.gamma, self.alpha, 0.0])

    @property
    def K_M(self) -> float:
        """Closed-loop ``K_M + K_Mu`` (kg/rad)."""
        return float(self.closed_loop_vehicle.K_M)

    @property
    def K_q(self) -> float:
        """Closed-loop ``K_q + K_qu`` (kg s/rad)."""
        return float(self.closed_loop_vehicle.K_q)

    @property
    def K_M0(self) -> float:
        """Closed-loop ``K_M0 + K_M0u`` (kg)."""
        return float(self.closed_loop_vehicle.K_M0)

    def as_dict(self) -> dict[str, float | str | bool]:
        """Plain dict (SI units, rad) for tables and JSON."""
        return {"K_M0u": self.law.K_M0u, "K_Mu": self.law.K_Mu, "K_qu": self.law.K_qu, "target": self.target,
                "target_value": self.target_value, "scale": self.scale, "scale_boundary": self.scale_boundary,
                "speed": self.speed, "gamma": self.gamma, "alpha": self.alpha, "eps1": self.eps1,
                "eps2": self.eps2, "mu": self.mu, "mu_d": self.mu_d, "eps_ratio": self.eps_ratio,
                "certified": self.certified, "peak_torque": self.peak_torque, "omegabar_reach": self.omegabar_reach,
                "torque_max": self.torque_max, "vehicle": self.vehicle.name, "provenance": self.provenance}


def _omegabar_reach(cert: CompositeCertificate) -> float:
    """Largest ``|Omegabar2|`` in ``{W <= w0}`` over the ``Vbar`` range, capped by the domain's ``Omegabar``."""
    V = np.linspace(*cert.domain.Vbar, 2001)
    c1, c2, c3 = cert.cw_entries(V)
    reach = float(np.max(np.sqrt(2 * cert.w0 * c1 / (c1 * c2 - c3**2))))
    return min(reach, -cert.domain.Omegabar[0], cert.domain.Omegabar[1])


def _peak(K_M0u: Any, K_Mu: Any, K_qu: Any, omega_scale: Any, V_e: float, alpha_e: float,
          Vbar: tuple[float, float], alphabar: tuple[float, float], omegabar: float) -> Any:
    """Exact ``max |u|`` of (6.5) over the box (vectorized over gains); see :attr:`TorqueDesign.peak_torque`."""
    Vmax = V_e * (1 + Vbar[1])
    best = 0.0
    for ab in alphabar:
        for ob in (-omegabar, omegabar):
            best = np.maximum(best, np.abs(K_M0u + K_Mu * (alpha_e + ab) + K_qu * ob / omega_scale))
    return best * Vmax**2


def peak_torque(law: TorqueLaw, cert: CompositeCertificate) -> float:
    """``max |u|`` (N m) of ``law`` over a closed-loop certificate's domain, as defined in
    :attr:`TorqueDesign.peak_torque`.

    Parameters
    ----------
    law : TorqueLaw
    cert : CompositeCertificate
        Certificate of ``law.closed_loop_vehicle(veh)`` (supplies ``V_e``, ``alpha_e``, ``K_q'/K_M'`` and the box).

    Returns
    -------
    float
        The peak torque (N m).

    Raises
    ------
    ArgumentTypeError
        If ``law`` is not a TorqueLaw or ``cert`` not a CompositeCertificate.
    """
    require_instance("law", law, TorqueLaw)
    require_instance("cert", cert, CompositeCertificate, " (from gc.composite_lyapunov)")
    sp = cert.sp
    return float(_peak(law.K_M0u, law.K_Mu, law.K_qu, sp.omega_scale, sp.speed, sp.alpha, cert.domain.Vbar,
                       cert.domain.alphabar, _omegabar_reach(cert)))


def _interval(name: str, value: Any) -> tuple[float, float]:
    """A domain bound ``(lo, hi)`` with ``lo < 0 < hi`` (infinite ends allowed)."""
    if isinstance(value, str | bytes) or not isinstance(value, tuple | list | np.ndarray) or len(value) != 2:
        raise ArgumentError(f"{name} must be a pair (lo, hi) of nondimensional bounds, got {value!r}")
    lo = checks.real(f"{name}[0]", value[0], allow_inf=True)
    hi = checks.real(f"{name}[1]", value[1], allow_inf=True)
    if not lo < 0 < hi:
        raise ArgumentError(f"{name} = ({lo:g}, {hi:g}) must contain the equilibrium 0 strictly inside (lo < 0 < hi)")
    return lo, hi


def design_torque_control(veh: Vehicle, *, speed: float | None = None, gamma: float | None = None,
                          Vbar: tuple[float, float] = (-0.4, 0.4), alphabar: tuple[float, float] = (-0.2, 0.2),
                          gammabar: tuple[float, float] = (-math.pi, math.pi),
                          Omegabar: tuple[float, float] = (-math.inf, math.inf),
                          torque_max: float = math.inf, eps_ratio: float | None = None,
                          margin: float = 1e-3, s_max: float = 1e4) -> TorqueDesign:
    """Torque-control gains (6.5) for a target speed or flight-path angle that certify ``B_p x B_q``, §6.1-§6.1.1.

    Steps: ``alpha_e`` from the target by (5.8)-(5.9) (:func:`alpha_for_target`); the one-parameter gain family
    of (6.6) (module docstring), ``K_q' = s K_q,ref``, ``K_M' = s^2 K_M,ref``, ``K_M0'`` placing ``alpha_e``;
    bisection on the composite-Lyapunov certificate (``mu < mu_d``, Theorem 2 with the constants of
    :func:`composite_lyapunov`) for the smallest certifying scale ``s_b``; then the scale in
    ``[s_b (1 + margin), s_max]`` of smallest :attr:`TorqueDesign.peak_torque` (dense logarithmic scan and a local
    refinement; the peak torque is exact for every scale).

    Parameters
    ----------
    veh : Vehicle
        Open-loop chapter-5 glider (equal added masses; ``m0 != 0``).
    speed, gamma : float
        Target ``V_e`` (m/s) or ``gamma_e`` (rad); exactly one.
    Vbar, alphabar, gammabar, Omegabar : (lo, hi)
        Domain ``B_p x B_q`` (nondimensional, (5.12)-(5.15)); see :func:`composite_lyapunov`.
    torque_max : float
        Bound on :attr:`TorqueDesign.peak_torque` (N m); ``inf`` for none.
    eps_ratio : float, optional
        ``eps1/eps2`` to keep; default the open-loop ratio ``-K_q^2 V_eol^2/(K_M J2)`` (the constraint (6.6)).
        Required when the open loop has no steady glide or ``K_q >= 0`` / ``K_M >= 0``.
    margin : float
        Relative margin above the boundary scale (so ``mu <= mu_d / (1 + margin)``), ``0 < margin < 1``.
    s_max : float
        Largest gain scale searched (relative to the boundary scale), in ``(1, 1e12]``.

    Returns
    -------
    TorqueDesign

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, or a number or bound is not a real number.
    ArgumentError
        Both or neither target; a target out of range (:func:`alpha_for_target`); a domain bound that is not a
        pair ``(lo, hi)`` of real numbers with ``lo < 0 < hi``; ``torque_max`` not positive; ``margin`` not in
        ``(0, 1)``; ``s_max`` not in ``(1, 1e12]``.
    ModelError
        If ``veh`` is not an underwater glider accepted by the chapter-5 model, or the composite Lyapunov function
        does not apply (e.g. unequal added masses).
    InfeasibleGlideError
        Unreachable target, or no gain of the family within ``torque_max`` certifies the domain (the message
        gives the request, the best ``mu/mu_d`` within the bound and the torque needed).
    SolverError
        If the certification boundary cannot be bracketed within the documented scale range ``[1e-12, 1e12]``
        (the search is bounded: at most ~140 bracketing steps and 200 bisection steps).

    Examples
    --------
    >>> import glidectl as gc
    >>> d = gc.design_torque_control(gc.load_vehicle("sphere_ch5"), speed=1.6)
    >>> d.certified, f"gamma_e = {d.gamma:.3f} rad", f"peak torque {d.peak_torque:.0f} N m"
    (True, 'gamma_e = -0.867 rad', 'peak torque 384 N m')
    """
    require_glider(veh, "veh")
    torque_max = checks.positive("torque_max", torque_max, allow_inf=True, unit="N m")
    margin = checks.real("margin", margin, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    s_max = checks.real("s_max", s_max, lo=1.0, hi=1e12, lo_open=True)
    Vbar, alphabar, gammabar, Omegabar = (_interval(n, b) for n, b in
                                          (("Vbar", Vbar), ("alphabar", alphabar), ("gammabar", gammabar),
                                           ("Omegabar", Omegabar)))
    a_e = alpha_for_target(veh, speed=speed, gamma=gamma)
    target, tval = ("speed", float(speed)) if speed is not None else ("gamma", float(gamma))  # type: ignore[arg-type]
    fam = torque_gain_family(veh, a_e, eps_ratio=eps_ratio)
    V_e = fam.speed

    def cert_at(s: float) -> CompositeCertificate:
        return composite_lyapunov(fam.law(s).closed_loop_vehicle(veh), Vbar=Vbar, alphabar=alphabar,
                                  gammabar=gammabar, Omegabar=Omegabar)

    def law_at(s: Any) -> tuple[Any, Any, Any]:
        return fam.gains(s)

    c1 = cert_at(1.0)
    where = (f"vehicle '{veh.name}', target {target} = {tval:.6g} {'m/s' if target == 'speed' else 'rad'} "
             f"(alpha_e = {a_e:.6g} rad, V_e = {V_e:.6g} m/s), domain Vbar = {tuple(Vbar)}, alphabar = "
             f"{tuple(alphabar)}")
    if not c1.mu_d > 0:
        raise InfeasibleGlideError(f"{where}: mu_d = {c1.mu_d:.4g} <= 0, no gain certifies this domain (the "
                                   "boundary-layer bound of Proposition 1 fails); shrink the domain")
    # bracket and bisect the certification boundary in log(s)
    lo = hi = c1.mu / c1.mu_d
    while cert_at(hi).certified is False:
        hi *= 1.5
        if hi > 1e12:  # pragma: no cover - mu ~ 1/s with mu_d fixed
            raise SolverError(f"{where}: no certifying gain scale found up to 1e12")
    lo = hi / 1.5
    while cert_at(lo).certified:
        lo /= 1.5
        if lo < 1e-12:  # pragma: no cover
            raise SolverError(f"{where}: certification boundary not bracketed")
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if cert_at(mid).certified:
            hi = mid
        else:
            lo = mid
        if hi / lo - 1 < 1e-12:
            break
    s_b = hi
    # smallest peak torque over the certified scales
    omegabar = _omegabar_reach(c1)  # r1, r2 (hence w0) are invariant along (6.6)
    s_lo = s_b * (1 + margin)
    grid = np.geomspace(s_lo, s_lo * s_max, 4001)

    def peak_of(s: Any) -> Any:
        g0, g1, g2 = law_at(s)
        return _peak(g0, g1, g2, fam.Kq_ref / (s * fam.KM_ref), V_e, a_e, tuple(Vbar), tuple(alphabar), omegabar)

    P = peak_of(grid)
    i = int(np.argmin(P))
    s_opt = float(grid[i])
    if 0 < i < grid.size - 1:  # golden-section refinement inside the bracketing grid cell pair
        a, b = float(grid[i - 1]), float(grid[i + 1])
        gr = (math.sqrt(5) - 1) / 2
        for _ in range(100):
            c_, d_ = b - gr * (b - a), a + gr * (b - a)
            if peak_of(c_) < peak_of(d_):
                b = d_
            else:
                a = c_
        s_opt = min((a, b, s_opt), key=lambda s: float(peak_of(s)))
    P_opt = float(peak_of(s_opt))
    if P_opt > torque_max:
        # the largest scale (smallest mu) whose peak torque is within the bound: the best mu/mu_d reachable
        sg = np.geomspace(s_b * 1e-3, s_lo, 2001)
        ok = sg[peak_of(sg) <= torque_max]
        s_best = float(ok.max()) if ok.size else None
        best = (f"the best reachable within the bound is mu/mu_d = {cert_at(s_best).mu / c1.mu_d:.4g} "
                f"(gain scale {s_best:.4g})" if s_best is not None else
                "no gain of the (6.6) family has a peak torque within the bound")
        raise InfeasibleGlideError(
            f"{where}: no torque gain with peak |u| <= torque_max = {torque_max:.4g} N m certifies the domain "
            f"(mu < mu_d = {c1.mu_d:.4g} needs gain scale > {s_b:.4g} and a peak torque of at least {P_opt:.4g} N m); "
            f"{best}. Raise torque_max or shrink the domain.")
    cert = cert_at(s_opt)
    sp = cert.sp
    law = TorqueLaw(*(float(v) for v in law_at(s_opt)))
    if not (abs(sp.alpha - a_e) < 1e-9 and cert.certified):  # pragma: no cover - internal consistency
        raise SolverError(f"{where}: internal error, closed loop alpha_e = {sp.alpha}, certified = "
                          f"{cert.certified}")
    return TorqueDesign(law, target, tval, s_opt, s_b, sp.speed, sp.gamma, sp.alpha, sp.eps1, sp.eps2, sp.mu,
                        cert.mu_d, sp.eps1 / sp.eps2, cert.certified, peak_torque(law, cert), omegabar, torque_max,
                        cert, law.closed_loop_vehicle(veh), veh, veh.provenance, plant_vehicle=veh)
