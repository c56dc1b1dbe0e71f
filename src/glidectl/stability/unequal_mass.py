"""Unequal added masses, §5.4: the reduced-subsystem condition (5.110) and its trade-off (Fig 5.3), checked against
the model.

With ``Delta m = m3 - m1`` the reduced subsystem (5.103)-(5.104) keeps ``Phi`` (5.106) as a Lyapunov function if
``dPhi/dt_n = -psi^2 + R`` with ``R <= kappa_dm psi^2`` (5.109) and ``kappa_dm < 1`` (5.110), where
``kappa_dm = 2 |Delta m m0 g| / (m1 K_De V_e^2 (1 + Vbar_min)^2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import checks
from ..errors import ArgumentError
from ..params import Vehicle
from .composite import CompositeCertificate, Domain
from .singular_perturbation import singular_perturbation

__all__ = ["UnequalMassCheck", "allowable_delta_m_ratio", "unequal_mass_check"]


def allowable_delta_m_ratio(kappa: float, Vbar_min: np.ndarray | float) -> np.ndarray | float:
    """Largest ``|Delta m| / m1`` allowed by (5.110) for ``kappa = |m0 g| / (K_De V_e^2)`` (Fig 5.3).

    Parameters
    ----------
    kappa : float
        ``|m0 g| / (K_De V_e^2)`` (nondimensional), finite and ``> 0``.
    Vbar_min : float or array_like
        Lower end(s) of the ``Vbar`` range of the domain (nondimensional, ``-1 < Vbar_min <= 0``; 0 is the limit of
        a vanishing domain); broadcast.

    Returns
    -------
    float or numpy.ndarray
        ``(1 + Vbar_min)^2 / (2 kappa)`` (nondimensional), the bound on ``|m3 - m1| / m1``; a float for a scalar
        ``Vbar_min``, else an array of its shape.

    Raises
    ------
    ArgumentTypeError
        If ``kappa`` or ``Vbar_min`` is not real numbers.
    ArgumentError
        If ``kappa`` is not positive and finite, or a ``Vbar_min`` is not finite or not in (-1, 0].

    Examples
    --------
    >>> import numpy as np
    >>> import glidectl as gc
    >>> print(gc.allowable_delta_m_ratio(1.243, np.array([-0.4, -0.2, 0.0])).round(3))   # kappa of sphere_ch5
    [0.145 0.257 0.402]
    """
    kappa = checks.positive("kappa", kappa)
    scalar = not isinstance(Vbar_min, list | tuple | np.ndarray) or np.ndim(Vbar_min) == 0
    V = np.asarray(checks.real("Vbar_min", Vbar_min), dtype=float) if scalar else checks.array("Vbar_min", Vbar_min)
    if np.any(V <= -1) or np.any(V > 0):
        raise ArgumentError(f"Vbar_min must lie in (-1, 0], got {Vbar_min!r}")
    out = (1 + V) ** 2 / (2 * kappa)
    return float(out) if scalar else out


@dataclass(frozen=True)
class UnequalMassCheck:
    """(5.110) for one vehicle and domain, and what sampling of the model says.

    Attributes
    ----------
    delta_m, kappa : float
        ``m3 - m1`` (kg) and ``|m0 g| / (K_De V_e^2)``.
    condition_lhs : float
        Left side of (5.110) (the bound is claimed valid when < 1).
    bound_margin : float
        ``condition_lhs psi^2 / R`` at the worst sample: the bound (5.109) ``R <= kappa_dm psi^2`` holds when
        ``>= 1`` (``inf`` when ``R <= 0`` on every sample).
    max_dPhi : float
        Largest sampled ``dPhi/dt_n / psi^2`` along the reduced subsystem (``Phi`` decreases when < 0).
    n_samples : int
    vehicle : Vehicle
        The vehicle.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    certified : bool
        The analytic condition (5.110), ``condition_lhs < 1``.
    margins : dict[str, float]
        ``1 / condition_lhs`` for (5.110), :attr:`bound_margin` for (5.109) and ``inf``/``0.0`` for
        ``dPhi/dt_n < 0`` (``>= 1`` holds).
    passed : bool
        Every margin is ``>= 1`` (relative tolerance 1e-9).
    """

    delta_m: float
    kappa: float
    condition_lhs: float
    bound_margin: float
    max_dPhi: float
    n_samples: int
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str

    @property
    def certified(self) -> bool:
        return self.condition_lhs < 1

    @property
    def margins(self) -> dict[str, float]:
        return {"(5.110) kappa_dm < 1": math.inf if self.condition_lhs <= 0 else 1.0 / self.condition_lhs,
                "(5.109) R <= kappa_dm psi^2": self.bound_margin,
                "dPhi/dt_n < 0": math.inf if self.max_dPhi < 0 else 0.0}

    @property
    def passed(self) -> bool:
        return all(m >= 1 - 1e-9 for m in self.margins.values())

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1 (relative tolerance 1e-9)."""
        return {k: m for k, m in self.margins.items() if not m >= 1 - 1e-9}


def unequal_mass_check(veh: Vehicle, Vbar: tuple[float, float] = (-0.4, 0.4),
                       gammabar: tuple[float, float] = (-math.pi, math.pi), n: int = 50_000,
                       seed: int = 0) -> UnequalMassCheck:
    """Evaluate (5.110) and sample (5.107)-(5.109) on ``B_p`` for a glider with ``m1 != m3``.

    Parameters
    ----------
    veh : Vehicle
        Chapter-5 glider (``m0 != 0``, ``K_q < 0``, ``K_M < 0``); its masses give ``Delta m = M3 - M1`` (kg).
    Vbar : (float, float)
        Range of ``Vbar = (V - V_e)/V_e`` (nondimensional), ``-1 < lo < 0 < hi``.
    gammabar : (float, float)
        Range of ``gammabar = gamma - gamma_e`` (rad), ``lo < 0 < hi``, ``|gammabar| <= pi``.
    n : int
        Number of uniform samples of ``p = (Vbar, gammabar)`` in the box, in ``[1, 10_000_000]``.
    seed : int
        Seed of the samples, ``>= 0``.

    Returns
    -------
    UnequalMassCheck
        ``Delta m`` (kg), ``kappa`` and the left side of (5.110) (nondimensional), the sampled margin of the bound
        (5.109) and the largest sampled ``dPhi/dt_n / psi^2`` (nondimensional). ``R = dPhi/dt_n + psi^2`` within
        rounding of the terms it is computed from (``1e-12`` relative) counts as 0; any larger positive ``R``
        fails (5.109) when ``Delta m = 0`` (the bound is then ``R <= 0``).

    Raises
    ------
    ArgumentTypeError
        If ``veh`` is not a Vehicle, a range is not a pair of real numbers, or ``n``/``seed`` is not an integer.
    ArgumentError
        If ``Vbar`` does not satisfy ``-1 < lo < 0 < hi``, ``gammabar`` not ``lo < 0 < hi`` within ``[-pi, pi]``,
        or ``n``/``seed`` is out of range.
    ModelError
        If the vehicle has no singularly perturbed chapter-5 glide (from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`).

    Examples
    --------
    >>> import glidectl as gc
    >>> chk = gc.unequal_mass_check(gc.load_vehicle("sphere_ch5", m3=29.4), n=2000)    # m3 5 % above m1
    >>> print(f"Delta m = {chk.delta_m:.1f} kg, (5.110) left side {chk.condition_lhs:.3f}", chk.certified)
    Delta m = 1.4 kg, (5.110) left side 0.349 True
    """
    checks.vehicle("veh", veh, "underwater_glider")
    dom = Domain(Vbar=Vbar, gammabar=gammabar)
    Vbar, gammabar = dom.Vbar, dom.gammabar
    n = checks.integer("n", n, lo=1, hi=10_000_000)
    seed = checks.integer("seed", seed, lo=0)
    sp = singular_perturbation(veh)
    M1, M3 = sp.model.masses
    dm = M3 - M1
    kappa = abs(veh.m0) * veh.g / (sp.K_De * sp.speed**2)
    lhs = 2 * abs(dm) * kappa / (M1 * (1 + Vbar[0]) ** 2)
    rng = np.random.default_rng(seed)
    p = np.column_stack([rng.uniform(*Vbar, n), rng.uniform(*gammabar, n)])
    psi2 = CompositeCertificate.psi(p) ** 2
    f = sp.reduced_rhs(p)
    V, g = p[:, 0], p[:, 1]
    dPhi = (-np.cos(g) + (1 + V) ** 2) * f[:, 0] + (1 + V) * np.sin(g) * f[:, 1]
    ok = psi2 > 1e-14 * max(float(np.max(psi2)), np.finfo(float).tiny)  # both sides vanish at p = 0
    if not np.any(ok):
        raise ArgumentError(f"no sample of Vbar = {Vbar}, gammabar = {gammabar} is away from the steady glide "
                            "(psi = 0 on all of them); widen the ranges or take more samples")
    R = dPhi[ok] + psi2[ok]
    # rounding of R = dPhi + psi^2: relative to the terms it is computed from (each f_i times its gradient entry)
    terms = (np.abs(-np.cos(g) + (1 + V) ** 2) * np.abs(f[:, 0]) + np.abs((1 + V) * np.sin(g) * f[:, 1]))[ok]
    R = np.where(np.abs(R) <= 1e-12 * (terms + psi2[ok]), 0.0, R)
    if lhs > 0:
        ratio = float(np.max(R / (lhs * psi2[ok])))
        margin = math.inf if ratio <= 0 else 1.0 / ratio
    else:  # Delta m = 0: (5.109) reads R <= 0
        margin = math.inf if float(np.max(R)) <= 0 else 0.0
    return UnequalMassCheck(dm, kappa, lhs, margin, float(np.max(dPhi[ok] / psi2[ok])), n, veh, veh.provenance)
