"""Theorem 5 of the thesis for the CTOL closed loop (§7.2.2-§7.2.5, Appendix "Theorem 5 Calculations"): the split
into interconnected subsystems, the Lyapunov functions ``Q1`` (7.69) and ``Q2`` (7.48), every constant of
(7.40)-(7.43), the coupling conditions (7.44)-(7.45), the composite function ``Q = d1 Q1 + d2 Q2`` (7.79) with
(7.46), and the certified ball ``||x|| <= r_a``; every printed inequality checkable by sampling.

States ``x = (x1, x2)``, ``x1 = (Vbar, gammabar)``, ``x2 = (thetabar, Omega2bar)`` (nondimensional, (7.8)-(7.11));
the domain is the ball ``||x|| <= r`` with ``r < 1`` (so ``|thetabar| <= r``, as in §7.2.3). The closed loop is
:class:`glidectl.models.ctol_closed_loop.ClosedLoopCTOL` and is the only right-hand side used here:

- ``f1(x1) = rhs_1(x1, 0)`` (7.29)-(7.30), ``g1(x) = rhs_1(x) - f1(x1)`` (7.31)-(7.32);
- ``f2(x2) = rhs_2(0, x2)`` (7.33)-(7.34), ``g2(x) = rhs_2(x) - f2(x2)``. ``g2 = 0`` (7.35) holds exactly (bit for
  bit): the pitch equations (7.14)-(7.15) under (7.17)-(7.20) do not involve ``x1`` at all. What (7.23) adds is the
  form of ``f2``: ``k1 cos theta - k2 sin theta = -k'' sin thetabar`` with ``k'' = k1 sin theta_e + k2 cos theta_e``,
  so ``f22 = -(T/(eps J)) (k3 + k'') sin thetabar - (T k4/J) Omega2bar``.

Constants (``J`` is the vehicle's inertia; with the normalized ``J = 1`` of §7.1 the formulas are the printed ones,
otherwise ``k3 + k''`` and ``k4`` enter as ``(k3 + k'')/J`` and ``k4/J``):

- ``c11, c12``: ``k1, k2`` of §5.1.2, (5.38) and (5.41), with ``Vbar_min = -r``, ``Vbar_max = r`` and the printed
  ``pi`` of (5.38) (§7.2.4 says they are "equal to k1 and k2 of §5.1.2");
- ``c21`` (7.59), ``c22`` (7.53), ``lambda2`` (7.63) (with ``sin(1)``: a valid lower bound of ``sin(r)/r`` for
  ``r <= 1``), ``beta2`` (7.67), ``lambda1 = min(s1, s2)`` (7.70)-(7.72), ``beta1 = sqrt(2)(2 + r)`` (7.74);
- ``gamma11 = gamma21 = gamma22 = 0`` and ``gamma12`` (7.77), which the thesis leaves as ``max(p1 + p2, p3)^(1/2)``
  with unspecified ``p_i``: computed here as the sup over the ball of ``||g1(x)|| / ||x2||`` (sampled, refined by
  Nelder-Mead from the worst samples, then raised by ``margin``).

Corrections to the text, found by :meth:`CTOLLyapunovCertificate.verify` and derived here:

1. ``lambda1`` (7.70) is too large by the factor ``V_e/m`` (``V_e = 0.155`` for the level glide: printed 3.675,
   true min of ``-Q1'/||x1||^2`` on the ball 0.712). The Appendix computes ``Q1' = V_e[...]`` and then drops the
   ``V_e`` when it reads off ``s1, s2``. Exactly (any glide, any ``k1, k2, m, g``): the controller force is the
   constant ``(-k2, -k1)`` and the equilibrium equations (7.21)-(7.22) turn the weight-plus-controller terms of
   (7.29)-(7.30) into ``K_De cos gammabar - K_Le sin gammabar`` and ``-K_Le cos gammabar - K_De sin gammabar``
   (times ``V_e^2``), so

       Q1' = -(V_e/m) { K_De [(Vbar^2 + 2 Vbar)^2 + 4 (1 + Vbar)^2 sin^2(gammabar/2)]
                        + dK_D (1 + Vbar)^2 ((1 + Vbar)^2 - cos gammabar) - dK_L (1 + Vbar)^2 sin gammabar },

   ``dK_D = K_Dr(alpha_e - gammabar) - K_De``, ``dK_L = K_Li(alpha_e - gammabar) - K_Le = -a_L c gammabar``
   (:meth:`CTOLLyapunovCertificate.Q1dot_closed_form`). Hence the suspicion that ``Q1`` (the Lanchester integral
   normalized for ``g = 1``, ``K_L V_e^2 = 1``) is not a Lyapunov function of ``f1`` for a general glide is
   unfounded: ``k1 + m g``, ``k2`` and ``g`` drop out, and ``Q1`` decreases for every glide sampled; only the
   printed rate is wrong. ``(V_e/m) min(s1, s2)`` is kept as :attr:`CTOLLyapunovCertificate.lambda1_formula` and
   checked too (it holds at every glide tested).
2. ``gamma12`` has no printed value; it is computed (above).
3. Not errors, but worth knowing: ``c12`` (5.41) is attained (``Vbar = r, gammabar = 0``) and ``c22``, ``beta2`` are
   tight to ``1e-7`` for large ``k3``; ``c11`` (with ``pi``) and ``c21`` (with ``1/pi^2``) are loose on the ball by
   factors 10 and 2; (7.63) is only sufficient (``k4 = 0.6``, ``k' = 0.5``: printed ``lambda2 < 0``, true
   ``lambda2 = 0.099 > 0``); with ``k4 T^2 = k'`` the true ``lambda2`` is negative and nothing is certified.
4. The certified region is tiny: ``gamma12 ~ k3 / (V_e (1 - r))`` (the pitch stiffness acts on the flight path
   through ``eps u2``), so ``d2 ~ (beta1 gamma12)^2 / (lambda1 lambda2)`` is huge and ``r_a ~ r sqrt(c11 / (d2
   c22))``: ``1.05e-4`` for ``(k3, k4) = (10, 5)`` and ``4.8e-11`` for ``(7e5, 250)`` at the level glide. Theorem
   5 proves exponential stability, not a useful region of attraction.

Where a printed constant fails, the certificate uses the sampled extreme (refined by local optimization) backed off
by ``margin`` (relative): lower bounds times ``1 - margin``, upper bounds times ``1 + margin``. Printed constants
that hold are kept (``c11`` with ``pi`` and ``c21`` with ``1/pi^2`` are valid but loose on the ball).

Composite function (§7.2.5). With ``gamma11 = gamma2j = 0``,
``Q' <= -d1 lambda1 |x1|^2 - d2 lambda2 |x2|^2 + d1 beta1 gamma12 |x1| |x2| = -(|x1|, |x2|) M (|x1|, |x2|)^T``,
``M = [[d1 lambda1, -d1 beta1 gamma12/2], [-d1 beta1 gamma12/2, d2 lambda2]]`` (the M-matrix argument of Khalil's
Theorem 9.2). ``d1 = 1`` and ``d2 > d2* = (beta1 gamma12)^2 / (4 lambda1 lambda2)`` makes ``M`` positive definite;
``d2`` is chosen to maximize the certified exponential rate ``sigma = lambda_min(M) / max(c12, d2 c22)`` of ``Q``
(``Q' <= -sigma Q``). Then (7.46) holds with ``lambda = 2 lambda_min(M)``. The certified region: the level
``level = min(c11, d2 c21) r^2`` lies below ``Q`` on the sphere ``||x|| = r``, so ``{Q <= level}`` is invariant
and inside the ball; it contains the ball of radius ``r_a = sqrt(level / max(c12, d2 c22))`` (§7.2.5).

The ``margins`` reported by :meth:`CTOLLyapunovCertificate.verify` are ``>= 1`` when the bound holds on the
samples, ``< 1`` when it fails (lower bounds: sampled min / constant; upper bounds: constant / sampled max).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError, ModelError, SolverError
from ..models.ctol import drag_coefficient, lift_coefficient, require_ctol
from ..models.ctol_closed_loop import ClosedLoopCTOL
from ..params import Vehicle
from ..trim.ctol import CTOLGlide

__all__ = ["CTOLLyapunovCertificate", "CTOLVerification", "Theorem5Constants", "ctol_lyapunov"]

TOL = 1e-9  # relative tolerance of a ratio test (a tight bound evaluated in floating point)
CONSTANTS = ("c11", "c12", "lambda1", "beta1", "gamma1", "c21", "c22", "lambda2", "beta2", "gamma2")
_SHELLS = (1e-1, 1e-2, 1e-3, 1e-4)  # radii (times r) of the thin shells sampled near the origin
MAX_SAMPLES = 5_000_000  # largest n of the construction and of verify (each set adds shells: memory ~ 2 kB x n)


def _pts(name: str, value: Any, k: int) -> np.ndarray:
    """A finite array with trailing dimension ``k``: real, or complex for complex-step derivatives
    (``gc.hessian``, ``gc.jacobians``)."""
    a = checks.array(name, value, allow_complex=True)
    if a.ndim == 0 or a.shape[-1] != k:
        raise ArgumentError(f"{name} must have a trailing dimension {k}, got shape {a.shape}")
    return a


@dataclass(frozen=True)
class Theorem5Constants:
    """The constants of Theorem 5, (7.40)-(7.43), for ``i = 1, 2`` (all nondimensional; ``lambda_i`` in 1/s).

    ``c_i1 |x_i|^2 <= Q_i <= c_i2 |x_i|^2``, ``dQ_i/dx_i f_i <= -lambda_i |x_i|^2``, ``|dQ_i/dx_i| <= beta_i |x_i|``,
    ``|g_i| <= gamma_i1 |x1| + gamma_i2 |x2|`` on ``||x|| <= r``.
    """

    c11: float
    c12: float
    c21: float
    c22: float
    lambda1: float
    lambda2: float
    beta1: float
    beta2: float
    gamma11: float
    gamma12: float
    gamma21: float
    gamma22: float

    @property
    def coupling(self) -> tuple[float, float]:
        """Left sides of the coupling conditions (7.44) and (7.45) (both must be > 0)."""
        l1, l2, b1, b2 = self.lambda1, self.lambda2, self.beta1, self.beta2
        g11, g12, g21, g22 = self.gamma11, self.gamma12, self.gamma21, self.gamma22
        return (l1 - b1 * g11,
                l1 * l2 + b1 * b2 * (g11 * g22 - g12 * g21) - l1 * b2 * g22 - l2 * b1 * g11)

    @property
    def certified(self) -> bool:
        """(7.44)-(7.45) hold and every ``c_ij, lambda_i, beta_i`` is positive (the hypotheses of Theorem 5)."""
        pos = min(self.c11, self.c12, self.c21, self.c22, self.lambda1, self.lambda2, self.beta1, self.beta2) > 0
        return bool(pos and min(self.coupling) > 0)

    def as_dict(self) -> dict[str, float]:
        return {k: float(getattr(self, k)) for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class CTOLVerification:
    """Result of :meth:`CTOLLyapunovCertificate.verify` (independent samples of the ball ``||x|| <= r``).

    Attributes
    ----------
    margins, margins_printed : Mapping[str, float]
        Margin of each bound (read-only) with the certificate's / the printed constants: ``>= 1`` holds, ``< 1``
        fails. Keys ``c11, c12, lambda1, beta1, gamma1`` ((7.43) for ``i = 1``), ``c21, c22, lambda2, beta2,
        gamma2``;
        ``margins`` adds ``"composite (7.46)"`` (``-Q' / (lambda/2 |x|^2)``), ``"level on sphere"``
        (``Q / level`` on ``||x|| = r``) and ``"r_a ball in level set"`` (``level / Q`` on ``||x|| <= r_a``) when
        the certificate is certified. ``gamma2`` is ``inf`` when ``g2`` is exactly zero on every sample, else 0.
    lambda1_formula_margin : float
        Margin of the corrected analytic ``lambda1 = (V_e/m) min(s1, s2)``
        (:attr:`CTOLLyapunovCertificate.lambda1_formula`).
    sampled : Theorem5Constants
        Sampled extremes (``c11`` = min of ``Q1/|x1|^2``, ``c12`` = max, ``lambda1`` = min of ``-Q1'/|x1|^2``,
        ``beta1`` = max of ``|grad Q1|/|x1|``, ``gamma12`` = max of ``|g1|/|x2|``, same for ``i = 2``; ``gamma11 = 0``,
        ``gamma21 = gamma22 = max |g2| / |x|``).
    g2_max : float
        ``max |g2|`` over the samples (exactly 0).
    n_samples, seed : int
    elapsed : float
        Wall time of the verification (s).
    passed : bool
        Every margin is ``>= 1`` (relative tolerance 1e-9): every bound with the certificate's constants holds on
        the samples.
    """

    margins_printed: Mapping[str, float]
    margins: Mapping[str, float]
    lambda1_formula_margin: float
    sampled: Theorem5Constants
    g2_max: float
    n_samples: int
    seed: int
    elapsed: float

    @property
    def passed(self) -> bool:
        """Every bound with the certificate's constants holds on the samples (``gamma2`` included: ``g2 = 0``)."""
        return all(v >= 1 - TOL for v in self.margins.values())

    def failing(self) -> dict[str, float]:
        """Bounds with the certificate's constants that fail on the samples, with their margins (< 1)."""
        return {k: v for k, v in self.margins.items() if not v >= 1 - TOL}

    def failing_printed(self) -> dict[str, float]:
        """Printed constants that fail on the samples, with their margins (< 1)."""
        return {k: v for k, v in self.margins_printed.items() if not v >= 1 - TOL}


@dataclass(frozen=True)
class CTOLLyapunovCertificate:
    """Theorem 5 for the CTOL closed loop about one steady glide: constants, composite function and region.

    Attributes
    ----------
    vehicle : Vehicle
    glide : CTOLGlide
    k3, k4, T, k_prime : float
        Gains of (7.20) (``k3`` N, ``k4`` N m s), reference time of (7.11) (s) and ``k'`` of (7.48).
    r : float
        Radius of the domain ``||x|| <= r`` (nondimensional).
    k_pp : float
        ``k'' = k1 sin theta_e + k2 cos theta_e`` (N).
    printed : Theorem5Constants
        The constants as printed ((5.38), (5.41), (7.53), (7.59), (7.63), (7.67), (7.70), (7.74); ``gamma12``
        computed, see the module notes).
    valid : Theorem5Constants
        The constants this certificate uses: printed where they hold, otherwise the sampled extreme backed off by
        ``margin``.
    sampled : Theorem5Constants
        Refined sampled extremes from the construction samples.
    lambda1_formula : float
        Corrected analytic ``lambda1 = (V_e/m) min(s1, s2)`` (1/s).
    d1, d2 : float
        Weights of ``Q = d1 Q1 + d2 Q2`` (7.79) (0 when not certified).
    lam : float
        ``lambda`` of (7.46): ``Q' <= -(lam/2) ||x||^2`` on the ball (1/s; 0 when not certified).
    level, r_a : float
        Certified invariant level ``{Q <= level}`` inside the ball and the radius of the ball it contains.
    margin : float
        Relative back-off applied to sampled constants.
    corrections : tuple of str
        One line per printed constant replaced, with the reason.
    n_build, seed_build : int
        Samples used for the construction.
    provenance : str
    """

    vehicle: Vehicle = field(repr=False)
    glide: CTOLGlide
    k3: float
    k4: float
    T: float
    k_prime: float
    r: float
    k_pp: float
    printed: Theorem5Constants
    valid: Theorem5Constants
    sampled: Theorem5Constants = field(repr=False)
    lambda1_formula: float
    d1: float
    d2: float
    lam: float
    level: float
    r_a: float
    margin: float
    corrections: tuple[str, ...]
    n_build: int
    seed_build: int
    provenance: str = field(repr=False)

    # ------------------------------------------------------------------------------------------------- system
    @property
    def closed_loop(self) -> ClosedLoopCTOL:
        """The closed loop (7.12)-(7.20) in reduced states (the single right-hand side used)."""
        return ClosedLoopCTOL(self.vehicle, self.glide, self.k3, self.k4, self.T)

    @property
    def certified(self) -> bool:
        """The certificate's constants satisfy the hypotheses and coupling conditions (7.44)-(7.45) of Theorem 5."""
        return self.valid.certified and self.lam > 0

    def rhs(self, x: Any) -> np.ndarray:
        """Closed-loop ``x' = (f1 + g1, f2 + g2)`` (7.28) at ``x = (Vbar, gammabar, thetabar, Omega2bar)`` (1/s),
        ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        return np.asarray(self.closed_loop.rhs(_pts("x", x, 4)))

    def f1(self, x1: Any) -> np.ndarray:
        """Translational subsystem (7.29)-(7.30): the closed loop's first two rows at ``x2 = 0`` (1/s), ``x1`` of
        shape ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x1`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x1 = _pts("x1", x1, 2)
        return self.rhs(np.concatenate([x1, np.zeros_like(x1)], axis=-1))[..., :2]

    def g1(self, x: Any) -> np.ndarray:
        """Coupling (7.31)-(7.32): ``rhs_1(x) - f1(x1)`` (1/s), ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        x = _pts("x", x, 4)
        return self.rhs(x)[..., :2] - self.f1(x[..., :2])

    def f2(self, x2: Any) -> np.ndarray:
        """Rotational subsystem (7.33)-(7.34): the closed loop's last two rows at ``x1 = 0`` (1/s), ``x2`` of shape
        ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x2`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x2 = _pts("x2", x2, 2)
        return self.rhs(np.concatenate([np.zeros_like(x2), x2], axis=-1))[..., 2:]

    def g2(self, x: Any) -> np.ndarray:
        """``rhs_2(x) - f2(x2)``, identically zero (7.35) (1/s), ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        x = _pts("x", x, 4)
        return self.rhs(x)[..., 2:] - self.f2(x[..., 2:])

    # ------------------------------------------------------------------------------------------------- functions
    @staticmethod
    def Q1(x1: Any) -> Any:
        """(7.69) ``(1 + Vbar)^3/3 - (1 + Vbar) cos gammabar + 2/3``, evaluated in the cancellation-free form
        ``Vbar^2 (1 + Vbar/3) + 2 (1 + Vbar) sin^2(gammabar/2)`` (identical algebraically); ``x1`` of shape
        ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x1`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x1 = _pts("x1", x1, 2)
        V, g = x1[..., 0], x1[..., 1]
        return V * V * (1 + V / 3) + 2 * (1 + V) * np.sin(g / 2) ** 2

    @staticmethod
    def grad_Q1(x1: Any) -> np.ndarray:
        """``dQ1/dx1 = ((1 + Vbar)^2 - cos gammabar, (1 + Vbar) sin gammabar)`` (7.73); ``x1`` of shape
        ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x1`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x1 = _pts("x1", x1, 2)
        V, g = x1[..., 0], x1[..., 1]
        return np.stack([V * (2 + V) + 2 * np.sin(g / 2) ** 2, (1 + V) * np.sin(g)], axis=-1)

    @property
    def _kappa(self) -> float:
        """``(k3 + k'') T^2 / (eps J)``: the pitch stiffness of ``Q2`` (7.48)."""
        veh = self.vehicle
        return (self.k3 + self.k_pp) * self.T**2 / (veh.epsilon * veh.J)

    def Q2(self, x2: Any) -> Any:
        """(7.48) ``(k3 + k'') (2 T^2/eps) sin^2(thetabar/2) + Omega2bar^2/2 + k' thetabar Omega2bar`` (``/J``);
        ``x2`` of shape ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x2`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x2 = _pts("x2", x2, 2)
        th, Om = x2[..., 0], x2[..., 1]
        return 2 * self._kappa * np.sin(th / 2) ** 2 + 0.5 * Om * Om + self.k_prime * th * Om

    def grad_Q2(self, x2: Any) -> np.ndarray:
        """``dQ2/dx2 = ((k3 + k'') T^2/eps sin thetabar + k' Omega2bar, Omega2bar + k' thetabar)`` (7.64); ``x2``
        of shape ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x2`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x2 = _pts("x2", x2, 2)
        th, Om = x2[..., 0], x2[..., 1]
        return np.stack([self._kappa * np.sin(th) + self.k_prime * Om, Om + self.k_prime * th], axis=-1)

    def Q(self, x: Any) -> Any:
        """Composite ``Q = d1 Q1 + d2 Q2`` (7.79); ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        x = _pts("x", x, 4)
        return self.d1 * self.Q1(x[..., :2]) + self.d2 * self.Q2(x[..., 2:])

    def grad(self, x: Any) -> np.ndarray:
        """``dQ/dx`` (4-vector per state); ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        x = _pts("x", x, 4)
        return np.concatenate([self.d1 * self.grad_Q1(x[..., :2]), self.d2 * self.grad_Q2(x[..., 2:])], axis=-1)

    def Qdot(self, x: Any) -> Any:
        """``dQ/dt`` along the true closed loop (1/s); ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        x = _pts("x", x, 4)
        return np.sum(self.grad(x) * self.rhs(x), axis=-1)

    def Q1dot_closed_form(self, x1: Any) -> Any:
        """``dQ1/dt`` along ``f1`` in closed form (module note 1; the Appendix's expression with ``V_e/m``); ``x1``
        of shape ``(..., 2)``.

        Raises
        ------
        ArgumentTypeError
            If ``x1`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        x1 = _pts("x1", x1, 2)
        veh, gl = self.vehicle, self.glide
        V, g = x1[..., 0], x1[..., 1]
        a = gl.alpha - g
        KDe, KLe = drag_coefficient(veh, gl.alpha), lift_coefficient(veh, gl.alpha)
        dKD, dKL = drag_coefficient(veh, a) - KDe, lift_coefficient(veh, a) - KLe
        s2 = (1 + V) ** 2
        return -(gl.speed / veh.m) * (KDe * ((V * V + 2 * V) ** 2 + 4 * s2 * np.sin(g / 2) ** 2)
                                      + dKD * s2 * (s2 - np.cos(g)) - dKL * s2 * np.sin(g))

    def in_region(self, x: Any) -> Any:
        """Membership of the certified invariant set ``{||x|| <= r, Q(x) <= level}``; ``x`` of shape ``(..., 4)``.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        x = _pts("x", x, 4)
        return (np.linalg.norm(x, axis=-1) <= self.r) & (self.Q(x) <= self.level)

    # ------------------------------------------------------------------------------------------------- ratios
    def _ratios(self) -> dict[str, Callable[[np.ndarray], np.ndarray]]:
        """Pointwise ratio functions on ``x`` in the ball (``(N, 4)``); subsystem ones use only ``x_i``."""
        def n1(x: np.ndarray) -> np.ndarray:
            return np.sum(x[:, :2] ** 2, axis=1)

        def n2(x: np.ndarray) -> np.ndarray:
            return np.sum(x[:, 2:] ** 2, axis=1)

        def lie1(x: np.ndarray) -> np.ndarray:
            return np.sum(self.grad_Q1(x[:, :2]) * self.f1(x[:, :2]), axis=1)

        def lie2(x: np.ndarray) -> np.ndarray:
            return np.sum(self.grad_Q2(x[:, 2:]) * self.f2(x[:, 2:]), axis=1)

        return {
            "Q1": lambda x: self.Q1(x[:, :2]) / n1(x),
            "dQ1": lambda x: -lie1(x) / n1(x),
            "gradQ1": lambda x: np.linalg.norm(self.grad_Q1(x[:, :2]), axis=1) / np.sqrt(n1(x)),
            "Q2": lambda x: self.Q2(x[:, 2:]) / n2(x),
            "dQ2": lambda x: -lie2(x) / n2(x),
            "gradQ2": lambda x: np.linalg.norm(self.grad_Q2(x[:, 2:]), axis=1) / np.sqrt(n2(x)),
            "g1": lambda x: np.linalg.norm(self.g1(x), axis=1) / np.sqrt(n2(x)),
        }

    # ------------------------------------------------------------------------------------------------- checks
    def verify(self, n: int = 200_000, seed: int = 1) -> CTOLVerification:
        """Sample the ball ``||x|| <= r`` (uniformly, on its sphere, on thin shells ``||x|| = r 10^-k`` and on sets
        with ``||x2|| << ||x1||``) and measure every bound (7.40)-(7.43), (7.46) and the region.

        Left sides use the closed loop's own right-hand side (:meth:`rhs`), not the thesis's algebra.

        Parameters
        ----------
        n : int
            Uniform samples of each set (the shells add ``n/10`` each).
        seed : int
            Random seed; use one different from the construction's ``seed_build`` for an independent check.

        Returns
        -------
        CTOLVerification

        Raises
        ------
        ArgumentTypeError
            If ``n`` or ``seed`` is not an integer.
        ArgumentError
            If ``n`` is outside ``[100, 5_000_000]`` or ``seed < 0``.
        """
        n = checks.integer("n", n, lo=100, hi=MAX_SAMPLES)
        seed = checks.integer("seed", seed, lo=0)
        t0 = time.perf_counter()
        rng = np.random.default_rng(seed)
        x1s = _disk_samples(n, 2, self.r, rng)   # subsystem i: x_i in the disk |x_i| <= r
        sub = np.concatenate([x1s, _disk_samples(n, 2, self.r, rng)], axis=1)
        full = _ball_samples(n, self.r, rng)
        fr = self._ratios()
        q1, d1_, b1 = fr["Q1"](sub), fr["dQ1"](sub), fr["gradQ1"](sub)
        q2, d2_, b2 = fr["Q2"](sub), fr["dQ2"](sub), fr["gradQ2"](sub)
        g1r = fr["g1"](full)
        g2 = np.abs(self.g2(full))
        g2_max = float(np.max(g2))
        nf = np.linalg.norm(full, axis=1)
        sampled = Theorem5Constants(
            c11=float(q1.min()), c12=float(q1.max()), c21=float(q2.min()), c22=float(q2.max()),
            lambda1=float(d1_.min()), lambda2=float(d2_.min()), beta1=float(b1.max()), beta2=float(b2.max()),
            gamma11=0.0, gamma12=float(g1r.max()), gamma21=float(np.max(g2.max(axis=1) / nf)),
            gamma22=float(np.max(g2.max(axis=1) / nf)))

        def margins(c: Theorem5Constants) -> dict[str, float]:
            return {"c11": _lower(sampled.c11, c.c11), "c12": _upper(sampled.c12, c.c12),
                    "lambda1": _lower(sampled.lambda1, c.lambda1), "beta1": _upper(sampled.beta1, c.beta1),
                    "gamma1": _upper(sampled.gamma12, c.gamma12),
                    "c21": _lower(sampled.c21, c.c21), "c22": _upper(sampled.c22, c.c22),
                    "lambda2": _lower(sampled.lambda2, c.lambda2), "beta2": _upper(sampled.beta2, c.beta2),
                    "gamma2": math.inf if g2_max == 0.0 else 0.0}

        rp, rv = margins(self.printed), margins(self.valid)
        if self.certified:
            qd = self.Qdot(full)
            rv["composite (7.46)"] = float(np.min(-qd / (0.5 * self.lam * nf**2)))
            sph = _sphere_samples(n // 2, 4, self.r, rng)
            rv["level on sphere"] = float(np.min(self.Q(sph)) / self.level)
            inner = _ball_samples(n // 2, self.r_a, rng)
            rv["r_a ball in level set"] = float(self.level / np.max(self.Q(inner)))
        return CTOLVerification(MappingProxyType(rp), MappingProxyType(rv),
                                _lower(sampled.lambda1, self.lambda1_formula), sampled, g2_max, int(n), int(seed),
                                time.perf_counter() - t0)


# ----------------------------------------------------------------------------------------------------- sampling
def _unit(n: int, dim: int, rng: np.random.Generator) -> np.ndarray:
    u = rng.normal(size=(n, dim))
    return u / np.linalg.norm(u, axis=1, keepdims=True)


def _sphere_samples(n: int, dim: int, radius: float, rng: np.random.Generator) -> np.ndarray:
    return radius * _unit(n, dim, rng)


def _disk_samples(n: int, dim: int, r: float, rng: np.random.Generator) -> np.ndarray:
    """Uniform in the ``dim``-ball of radius ``r``, plus ``n/10`` on its sphere and on each thin shell."""
    parts = [_unit(n, dim, rng) * (r * rng.random(n) ** (1 / dim))[:, None], _sphere_samples(n // 10, dim, r, rng)]
    parts += [_sphere_samples(n // 10, dim, r * s, rng) for s in _SHELLS]
    return np.concatenate(parts)


def _ball_samples(n: int, r: float, rng: np.random.Generator) -> np.ndarray:
    """4-ball samples as :func:`_disk_samples`, plus ``n/10`` points for each ``k = 2, 4, 6`` with
    ``||x2|| = r 10^-k`` and ``x1`` in the remaining disk, half of them on its edge (``||g1|| / ||x2||`` is largest
    as ``x2 -> 0`` with ``||x1|| = r``)."""
    base = _disk_samples(n, 4, r, rng)
    thin = []
    for s in (1e-2, 1e-4, 1e-6):
        m = n // 10
        x2 = _sphere_samples(m, 2, r * s, rng)
        rad1 = r * math.sqrt(1 - s * s) * np.sqrt(rng.random(m))
        rad1[: m // 2] = r * math.sqrt(1 - s * s)  # half of them on the outer edge
        thin.append(np.concatenate([_unit(m, 2, rng) * rad1[:, None], x2], axis=1))
    return np.concatenate([base, *thin])


def _lower(sampled_min: float, constant: float) -> float:
    """Margin of a lower bound ``constant <= sampled``: ``sampled_min / constant``; ``-inf`` for a non-positive
    constant (Theorem 5 needs ``c_i1, lambda_i > 0``, so such a constant never holds)."""
    if constant <= 0:
        return -math.inf
    return sampled_min / constant


def _upper(sampled_max: float, constant: float) -> float:
    """Margin of an upper bound ``sampled <= constant``: ``constant / sampled_max`` (``inf`` if both are 0)."""
    if sampled_max <= 0:
        return math.inf
    return constant / sampled_max


# ----------------------------------------------------------------------------------------------------- extremes
def _project(z: np.ndarray, r: float, which: str) -> np.ndarray:
    """Map ``z`` into the closed ball of radius ``r`` keeping the relevant sub-vector off zero."""
    x = np.array(z, dtype=float)
    floor = 1e-7 * r
    sl = slice(0, 2) if which == "x1" else slice(2, 4)
    nz = np.linalg.norm(x[sl])
    if nz < floor:
        x[sl] = floor * (x[sl] / nz if nz > 0 else np.array([1.0, 0.0]))
    nx = np.linalg.norm(x)
    if nx > r:
        if which == "x2" and np.linalg.norm(x[2:]) < r:  # shrink x1 first so that small x2 stays small
            k = math.sqrt(max(r * r - float(x[2:] @ x[2:]), 0.0)) / max(np.linalg.norm(x[:2]), 1e-300)
            x[:2] *= min(k, 1.0)
        else:
            x *= r / nx
    return x


def _refine(fun: Callable[[np.ndarray], np.ndarray], x: np.ndarray, values: np.ndarray, sign: float, r: float,
            which: str, starts: int = 3) -> float:
    """Extreme of ``fun`` over the ball: the best sample, improved by Nelder-Mead from the ``starts`` best samples
    (``sign = +1`` for a minimum, ``-1`` for a maximum)."""
    order = np.argsort(sign * values)[:starts]
    best = float(np.min(sign * values))

    def obj(z: np.ndarray) -> float:
        v = float(fun(_project(z, r, which)[None])[0])
        return sign * v if math.isfinite(v) else math.inf

    for i in order:
        res = minimize(obj, x[i], method="Nelder-Mead",
                       options={"xatol": 1e-10 * r, "fatol": 1e-13, "maxiter": 600, "maxfev": 1200})
        if math.isfinite(res.fun):
            best = min(best, float(res.fun))
    return sign * best


# ----------------------------------------------------------------------------------------------------- builder
def _printed(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float, kp: float, r: float,
             k_pp: float) -> tuple[Theorem5Constants, float]:
    """Constants as printed (gamma12 filled in later) and ``min(s1, s2)`` of (7.70)-(7.72)."""
    eps, J = veh.epsilon, veh.J
    K = (k3 + k_pp) / J  # (k3 + k'') (/J)
    k4j = k4 / J
    c11 = min(1 - r / 3, (1 - r) / 2 * (1 - math.pi**2 / 12))                       # (5.38), Vbar_min = -r
    c12 = max(1 + r / 3, (1 + r) / 2)                                                # (5.41), Vbar_max = r
    c21 = 0.5 * min(4 * K * T**2 / (eps * math.pi**2) - kp, 1 - kp)                  # (7.59)
    c22 = 0.5 * max(abs(K) * T**2 / eps + kp, 1 + kp)                                # (7.53)
    lam2 = kp * T * min(K * math.sin(1.0) / eps - k4j / 2, k4j * (1 / kp - 0.5) - 1 / T**2)  # (7.63)
    A = K * T**2 / eps
    beta2 = math.sqrt(kp * A + kp + max(A * A + kp * kp, 1 + kp * kp))               # (7.67)
    rho = veh.rho_AW_half
    aD, aL, b, c = rho * veh.a_D, rho * veh.a_L, veh.b, veh.c
    ae = glide.alpha
    KDe = float(drag_coefficient(veh, ae))
    s1 = KDe * (2 - r) ** 2 - 2 * aD * b * c * abs(c * ae + 1) * (1 + 3 * r + r * r)                   # (7.71)
    s2 = (KDe * (1 - r) ** 2 * math.sin(r / 2) ** 2 / (r / 2) ** 2 + aL * c * math.sin(r) / r * (1 - r) ** 2
          + aD * b * c * c * (r * r - 2 * r) - aD * b * c * abs(c * ae + 1) * ((1 + r) ** 2 * r + 2))  # (7.72)
    lam1 = min(s1, s2)                                                                # (7.70)
    beta1 = math.sqrt(2) * (2 + r)                                                    # (7.74)
    return Theorem5Constants(c11, c12, c21, c22, lam1, lam2, beta1, beta2, 0.0, 0.0, 0.0, 0.0), lam1


def _composite(c: Theorem5Constants) -> tuple[float, float, float]:
    """``(d1, d2, lambda)`` for ``gamma11 = gamma2j = 0``: ``d1 = 1``, ``d2`` maximizing ``lambda_min(M) /
    max(c12, d2 c22)``; zeros if Theorem 5 does not apply."""
    if not c.certified:
        return 0.0, 0.0, 0.0
    a, b, cc = c.lambda1, 0.5 * c.beta1 * c.gamma12, c.lambda2

    def lmin(d2: float) -> float:  # det / lambda_max: no cancellation when d2 lambda2 >> lambda1
        return (a * d2 * cc - b * b) / (0.5 * (a + d2 * cc) + math.hypot(0.5 * (a - d2 * cc), b))

    if b == 0.0:  # uncoupled (k3 = k4 = 0 is excluded, but keep the algebra total)
        d2 = c.c12 / c.c22
    else:
        dstar = b * b / (a * cc)
        res = minimize_scalar(lambda t: -lmin(dstar * (1 + math.exp(t))) / max(c.c12, dstar * (1 + math.exp(t))
                                                                               * c.c22),
                              bounds=(-20.0, 20.0), method="bounded", options={"xatol": 1e-10})
        d2 = dstar * (1 + math.exp(float(res.x)))
    return 1.0, d2, 2 * lmin(d2)


def ctol_lyapunov(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float = 1.0, k_prime: float = 0.5,
                  r: float = 0.5, *, margin: float = 0.02, n: int = 20_000,
                  seed: int = 0) -> CTOLLyapunovCertificate:
    """Theorem 5 (§7.2.2-§7.2.5) for the CTOL closed loop (7.12)-(7.20) about ``glide``: every constant of
    (7.40)-(7.45), printed and checked, the composite Lyapunov function (7.79) and the certified region.

    Parameters
    ----------
    veh : Vehicle
        A ``kind = "ctol"`` vehicle (``dc8_ctol``: normalized units of §7.1).
    glide : CTOLGlide
        The steady glide (:func:`glidectl.trim.ctol.ctol_glide`), with ``k1, k2`` (N) of Theorem 4.
    k3 : float
        Pitch stiffness gain of (7.20) (N), > 0 and ``k3 + k'' > 0`` (``Q2`` positive definite).
    k4 : float
        Pitch damping gain of (7.20) (N m s), > 0.
    T : float
        Reference time of (7.11) (s), > 0.
    k_prime : float
        ``k'`` of (7.48), in (0, 1).
    r : float
        Radius of the domain ``||x|| <= r`` in the nondimensional states, in (0, 1) (Appendix D assumes r < 1).
    margin : float
        Relative back-off of sampled constants (the certificate's constant is the sampled extreme times
        ``1 -+ margin``), in [0, 0.5).
    n, seed : int
        Construction samples per set and their seed (verify with another seed).

    Returns
    -------
    CTOLLyapunovCertificate

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, ``glide`` is not a :class:`~glidectl.trim.ctol.CTOLGlide`, a number is not a
        real number or ``n``/``seed`` not an integer.
    ArgumentError
        Non-positive or non-finite gains or ``T``; ``k'`` or ``r`` outside (0, 1); ``margin`` outside [0, 0.5);
        ``n`` outside ``[100, 5_000_000]`` or ``seed < 0``; ``k3 + k'' <= 0`` (``Q2`` (7.48) not positive
        definite); gains so large that the constants overflow.
    VehicleMismatchError
        If ``glide`` was trimmed for another vehicle.
    ModelError
        Not a CTOL vehicle, or ``epsilon <= 0``.
    SolverError
        If a constant of the certificate is not finite (it lost its meaning).

    Examples
    --------
    >>> import glidectl as gc
    >>> veh = gc.load_vehicle("dc8_ctol")
    >>> glide = gc.ctol_glide(veh, 0.155, 0.0)              # level flight
    >>> cert = gc.ctol_lyapunov(veh, glide, k3=10.0, k4=5.0, n=2000)
    >>> cert.certified, len(cert.corrections)               # two printed constants corrected
    (True, 2)
    """
    checks.vehicle("veh", veh, "ctol")
    if not isinstance(glide, CTOLGlide):
        raise ArgumentTypeError(f"glide must be a CTOLGlide from gc.ctol_glide(veh, speed, gamma), got "
                                f"{type(glide).__name__}")
    checks.same_vehicle("glide", glide, veh)
    require_ctol(veh)
    if veh.epsilon <= 0:
        raise ModelError("the steady-glide controller (7.19)-(7.20) divides by eps: it needs epsilon > 0")
    k3, k4 = checks.positive("k3", k3, unit="N"), checks.positive("k4", k4, unit="N m s")
    T = checks.positive("T", T, unit="s")
    kp = checks.real("k_prime", k_prime, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    r = checks.real("r", r, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    margin = checks.real("margin", margin, lo=0.0, hi=0.5, hi_open=True)
    n = checks.integer("n", n, lo=100, hi=MAX_SAMPLES)
    seed = checks.integer("seed", seed, lo=0)
    k_pp = glide.k1 * math.sin(glide.theta) + glide.k2 * math.cos(glide.theta)
    if k3 + k_pp <= 0:
        raise ArgumentError(f"k3 + k'' = {k3 + k_pp:g} <= 0 (k'' = {k_pp:g}): Q2 (7.48) is not positive definite; "
                            f"choose k3 > {-k_pp:g} (§7.2.3 asks for k3 > |k''|)")
    try:
        return _build(veh, glide, k3, k4, T, kp, r, k_pp, margin, n, seed)
    except (OverflowError, ZeroDivisionError) as exc:
        raise ArgumentError(f"the Theorem-5 constants overflow for k3 = {k3:g}, k4 = {k4:g}, T = {T:g} "
                            f"({type(exc).__name__}: {exc}); use gains and T of moderate size") from exc


def _build(veh: Vehicle, glide: CTOLGlide, k3: float, k4: float, T: float, kp: float, r: float, k_pp: float,
           margin: float, n: int, seed: int) -> CTOLLyapunovCertificate:
    printed0, lam1_printed = _printed(veh, glide, k3, k4, T, kp, r, k_pp)
    lam1_formula = glide.speed / veh.m * lam1_printed

    # sampled extremes on the construction samples, refined
    base = CTOLLyapunovCertificate(veh, glide, k3, k4, T, kp, r, k_pp, printed0, printed0, printed0, lam1_formula,
                                   0.0, 0.0, 0.0, 0.0, 0.0, margin, (), n, seed, "")
    fr = base._ratios()
    rng = np.random.default_rng(seed)
    sub = np.concatenate([_disk_samples(n, 2, r, rng), _disk_samples(n, 2, r, rng)], axis=1)
    full = _ball_samples(n, r, rng)

    def ext(key: str, pts: np.ndarray, sign: float, which: str) -> float:
        return _refine(fr[key], pts, fr[key](pts), sign, r, which)

    sampled = Theorem5Constants(
        c11=ext("Q1", sub, 1, "x1"), c12=ext("Q1", sub, -1, "x1"), c21=ext("Q2", sub, 1, "x2"),
        c22=ext("Q2", sub, -1, "x2"), lambda1=ext("dQ1", sub, 1, "x1"), lambda2=ext("dQ2", sub, 1, "x2"),
        beta1=ext("gradQ1", sub, -1, "x1"), beta2=ext("gradQ2", sub, -1, "x2"), gamma11=0.0,
        gamma12=ext("g1", full, -1, "x2"), gamma21=0.0, gamma22=0.0)
    gamma12 = sampled.gamma12 * (1 + margin)
    printed = Theorem5Constants(**{**printed0.as_dict(), "gamma12": gamma12})

    lower = ("c11", "c21", "lambda1", "lambda2")
    upper = ("c12", "c22", "beta1", "beta2")
    valid = printed.as_dict()
    corrections: list[str] = []
    for k in (*lower, *upper):
        p, s = getattr(printed, k), getattr(sampled, k)
        ok = (p > 0 and s >= p * (1 - TOL)) if k in lower else (s <= p * (1 + TOL))
        if not ok:
            v = s - margin * abs(s) if k in lower else s * (1 + margin)
            valid[k] = v
            corrections.append(f"{k}: printed {p:.6g} fails (sampled {'min' if k in lower else 'max'} {s:.6g}); "
                               f"using {v:.6g} (margin {margin:g})")
    corrections.append(f"gamma12: not printed (7.77); sampled sup of |g1|/|x2| {sampled.gamma12:.6g}, "
                       f"using {gamma12:.6g} (margin {margin:g})")
    valid_c = Theorem5Constants(**valid)
    values = {**{f"printed {k}": v for k, v in printed.as_dict().items()},
              **{f"sampled {k}": v for k, v in sampled.as_dict().items()}}
    bad = sorted(k for k, v in values.items() if not math.isfinite(v))
    if bad:
        raise SolverError(f"Theorem 5 constants are not finite for k3 = {k3:g}, k4 = {k4:g}, T = {T:g} ({bad}): they "
                          "overflow or the closed loop is not finite on the ball; use gains of moderate size")
    d1, d2, lam = _composite(valid_c)
    if lam > 0:
        level = min(d1 * valid_c.c11, d2 * valid_c.c21) * r * r
        r_a = math.sqrt(level / max(d1 * valid_c.c12, d2 * valid_c.c22))
    else:
        level = r_a = 0.0
    prov = (f"glidectl.stability.ctol_lyapunov: Bhatta 2006 Theorem 5 (§7.2.2-§7.2.5, App. 'Theorem 5 "
            f"Calculations'); vehicle {veh.name} [{veh.provenance}]; glide V_e={glide.speed:.10g}, "
            f"gamma_e={glide.gamma:.10g}, alpha_e={glide.alpha:.10g}, k1={glide.k1:.10g}, k2={glide.k2:.10g}; "
            f"k3={k3:g}, k4={k4:g}, T={T:g}, k'={kp:g}, r={r:g}; margin={margin:g}, n={n}, seed={seed}")
    return CTOLLyapunovCertificate(veh, glide, k3, k4, T, kp, r, k_pp, printed, valid_c, sampled, lam1_formula,
                                   d1, d2, lam, level, r_a, margin, tuple(corrections), n, seed, prov)
