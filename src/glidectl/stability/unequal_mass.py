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

from ..errors import GlidectlError
from ..params import Vehicle
from .composite import CompositeCertificate
from .singular_perturbation import singular_perturbation

__all__ = ["UnequalMassCheck", "allowable_delta_m_ratio", "unequal_mass_check"]


def allowable_delta_m_ratio(kappa: float, Vbar_min: np.ndarray | float) -> np.ndarray | float:
    """Largest ``|Delta m| / m1`` allowed by (5.110) for ``kappa = |m0 g| / (K_De V_e^2)`` (Fig 5.3).

    Parameters
    ----------
    kappa : float
        ``|m0 g| / (K_De V_e^2)`` (nondimensional), ``> 0``.
    Vbar_min : float or ndarray
        Lower end of the ``Vbar`` range of the domain (nondimensional, ``-1 < Vbar_min < 0``); broadcast.

    Returns
    -------
    float or numpy.ndarray
        ``(1 + Vbar_min)^2 / (2 kappa)`` (nondimensional), the bound on ``|m3 - m1| / m1``; same shape as
        ``Vbar_min``.

    Raises
    ------
    TypeError
        If ``kappa`` or ``Vbar_min`` is not numeric. The arguments are not otherwise validated: ``kappa = 0`` gives
        ``inf`` (with a numpy ``RuntimeWarning``) rather than an error.
    """
    return (1 + np.asarray(Vbar_min)) ** 2 / (2 * kappa)


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
        Range of ``gammabar = gamma - gamma_e`` (rad).
    n : int
        Number of uniform samples of ``p = (Vbar, gammabar)`` in the box.
    seed : int
        Seed of the samples.

    Returns
    -------
    UnequalMassCheck
        ``Delta m`` (kg), ``kappa`` and the left side of (5.110) (nondimensional), the sampled margin of the bound
        (5.109) and the largest sampled ``dPhi/dt_n / psi^2`` (nondimensional).

    Raises
    ------
    GlidectlError
        If ``Vbar`` does not satisfy ``-1 < lo < 0 < hi``.
    ModelError
        If the vehicle has no singularly perturbed chapter-5 glide (from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`).
    ValueError
        If ``n`` is not positive (no samples).
    """
    if not (-1 < Vbar[0] < 0 < Vbar[1]):
        raise GlidectlError(f"Vbar range {Vbar} must satisfy -1 < lo < 0 < hi")
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
    ok = psi2 > 1e-14
    R = dPhi[ok] + psi2[ok]
    ratio = float(np.max(R / (lhs * psi2[ok]))) if lhs > 0 else float(np.max(np.abs(R)))
    margin = math.inf if ratio <= 0 else 1.0 / ratio
    return UnequalMassCheck(dm, kappa, lhs, margin, float(np.max(dPhi[ok] / psi2[ok])), n, veh, veh.provenance)
