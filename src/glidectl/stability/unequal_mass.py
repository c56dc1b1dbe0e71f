"""Unequal added masses, §5.4: the reduced-subsystem condition (5.110) and its trade-off (Fig 5.3), checked against
the model.

With ``Delta m = m3 - m1`` the reduced subsystem (5.103)-(5.104) keeps ``Phi`` (5.106) as a Lyapunov function if
``dPhi/dt_n = -psi^2 + R`` with ``R <= kappa_dm psi^2`` (5.109) and ``kappa_dm < 1`` (5.110), where
``kappa_dm = 2 |Delta m m0 g| / (m1 K_De V_e^2 (1 + Vbar_min)^2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import GlidectlError
from ..params import Vehicle
from .composite import CompositeCertificate
from .singular_perturbation import singular_perturbation

__all__ = ["UnequalMassCheck", "allowable_delta_m_ratio", "unequal_mass_check"]


def allowable_delta_m_ratio(kappa: float, Vbar_min: np.ndarray | float) -> np.ndarray | float:
    """Largest ``|Delta m| / m1`` allowed by (5.110) for ``kappa = |m0 g| / (K_De V_e^2)`` (Fig 5.3)."""
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
    bound_ratio : float
        Worst sampled ``R / (condition_lhs psi^2)`` (the bound (5.109) holds when <= 1).
    max_dPhi : float
        Largest sampled ``dPhi/dt_n / psi^2`` along the reduced subsystem (``Phi`` decreases when < 0).
    """

    delta_m: float
    kappa: float
    condition_lhs: float
    bound_ratio: float
    max_dPhi: float
    n_samples: int
    vehicle: str
    provenance: str

    @property
    def condition_holds(self) -> bool:
        return self.condition_lhs < 1


def unequal_mass_check(veh: Vehicle, Vbar: tuple[float, float] = (-0.4, 0.4),
                       gammabar: tuple[float, float] = (-math.pi, math.pi), n: int = 50_000,
                       seed: int = 0) -> UnequalMassCheck:
    """Evaluate (5.110) and sample (5.107)-(5.109) on ``B_p`` for a glider with ``m1 != m3``."""
    if not (-1 < Vbar[0] < 0 < Vbar[1]):
        raise GlidectlError(f"Vbar range {Vbar} must satisfy -1 < lo < 0 < hi")
    sp = singular_perturbation(veh)
    M1, M3 = sp.model.masses
    dm = M3 - M1
    kappa = abs(veh.m0) * veh.g / (sp.K_De * sp.V_e**2)
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
    return UnequalMassCheck(dm, kappa, lhs, ratio, float(np.max(dPhi[ok] / psi2[ok])), n, veh.name, veh.provenance)
