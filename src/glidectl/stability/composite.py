"""Composite Lyapunov function of §5.2 and the region-of-attraction estimate of §5.3, with every constant computed
and every inequality checkable by sampling.

Functions (nondimensional variables of §5.1, ``p = (Vbar, gammabar)``, ``q = (alphabar, Omegabar2)``):

- ``Phi(p) = 2/3 - (1 + Vbar) cos(gammabar) + (1 + Vbar)^3 / 3`` (5.35), from Lanchester's C (4.5)/(5.34);
- ``W(p, q) = q^T C_W(a) q / 2`` (5.31) with ``a = (1 + Vbar)^2``;
- ``nu = (1 - d) Phi + d W`` (5.53)/(5.83); ``psi`` (5.50) and ``sigma`` (5.32) the comparison functions.

Corrections to the text, each derived here and checked by :meth:`CompositeCertificate.verify`:

1. ``C_W`` of (5.31): with ``c3 = 1`` and ``c2 = 1 + r1/(r2 a)``, the cross term of ``dW/dtau`` vanishes only for
   ``c1 = 1 + 2 r2 a / r1``; the printed ``c1 = r1 + r1 a + r2 a`` leaves ``(r1^2 + r1^2 a + r1 r2 a - 2 r2 a - r1)
   alphabar Omegabar2`` (zero only when ``r1 = r2 = 1``) and Proposition 1 fails with it. ``cw="thesis"`` keeps the
   printed matrix so that its failure can be measured.
2. ``k3, k4``: ``W = q^T C_W q / 2``, so the bounds are half the eigenvalues of ``C_W`` (minimized/maximized over
   the ``Vbar`` range), not the eigenvalues as printed.
3. ``beta2'`` (5.77) is re-derived for the corrected ``c1`` (``|c1 alphabar + Omegabar2| <= sqrt(1 + c1^2) |q|``).
4. ``gamma2''`` (5.81) is ambiguous as printed (it is named ``C_3`` and its two terms do not follow from (5.79)).
   The provably valid reading used here: ``dW/dVbar = (c1'(Vbar) alphabar^2 + c2'(Vbar) Omegabar2^2)/2`` is a
   difference of two nonnegative terms, so ``|dW/dp f| <= F1 max(X, Y) sigma^2`` with ``F1 >= sup |f1|`` and
   ``X = c1'/(2(1+Vbar)^2)``, ``Y = -c2'/(2(1+Vbar)^2)`` at ``Vmin``; ``beta2'' = 0``.
5. ``beta1`` (5.62) uses ``Vbar_max`` where ``max |Vbar|`` is meant (they agree for symmetric ranges); ``k1`` and
   ``e`` (5.38), (5.46) are written with the domain's ``|gammabar|_max`` (``pi`` in the thesis).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from scipy.optimize import minimize_scalar

from ..errors import GlidectlError
from ..params import Vehicle
from .singular_perturbation import SingularPerturbation, singular_perturbation

__all__ = ["CompositeCertificate", "CompositeVerification", "Domain", "composite_lyapunov"]


@dataclass(frozen=True)
class Domain:
    """The box ``B_p x B_q`` (nondimensional): ``Vbar, gammabar, alphabar, Omegabar2`` ranges ``(lo, hi)``.

    Parameters
    ----------
    Vbar : (float, float)
        Range of ``Vbar = (V - V_e)/V_e`` (nondimensional), ``-1 < lo < 0 < hi``.
    gammabar : (float, float)
        Range of ``gammabar = gamma - gamma_e`` (rad), ``lo < 0 < hi``, ``|gammabar| <= pi``.
    alphabar : (float, float)
        Range of ``alphabar = alpha - alpha_e`` (rad), ``lo < 0 < hi``, ``|alphabar| <= 2 pi``.
    Omegabar : (float, float)
        Range of ``Omegabar2 = (K_q/K_M) Omega2`` (nondimensional), ``lo < 0 < hi``; may be infinite.

    Raises
    ------
    GlidectlError
        If a range does not contain 0 in its interior, is NaN or (except ``Omegabar``) infinite, ``Vbar_min <= -1``,
        ``|gammabar| > pi`` or ``|alphabar| > 2 pi``.
    """

    Vbar: tuple[float, float] = (-0.4, 0.4)
    gammabar: tuple[float, float] = (-math.pi, math.pi)
    alphabar: tuple[float, float] = (-0.2, 0.2)
    Omegabar: tuple[float, float] = (-math.inf, math.inf)

    def __post_init__(self) -> None:
        for name in ("Vbar", "gammabar", "alphabar", "Omegabar"):
            lo, hi = getattr(self, name)
            finite = name == "Omegabar" or (math.isfinite(lo) and math.isfinite(hi))
            if not (finite and not math.isnan(lo) and not math.isnan(hi) and lo < 0 < hi):
                raise GlidectlError(f"domain bound {name} = ({lo}, {hi}) must satisfy lo < 0 < hi (finite except "
                                    "for Omegabar, which may be unbounded): a neighbourhood of the steady glide")
        if self.Vbar[0] <= -1:
            raise GlidectlError(f"Vbar_min = {self.Vbar[0]} must be > -1 (V > 0), §5.1")
        if max(-self.gammabar[0], self.gammabar[1]) > math.pi:
            raise GlidectlError("|gammabar| must not exceed pi (the bounds of §5.1.2 assume -pi <= gammabar < pi)")
        if max(-self.alphabar[0], self.alphabar[1]) > 2 * math.pi:
            raise GlidectlError("|alphabar| must not exceed 2 pi (§5.1)")

    def sample(self, n: int, rng: np.random.Generator, omega_extent: float = 1.0) -> np.ndarray:
        """``n`` uniform samples ``(Vbar, gammabar, alphabar, Omegabar2)``; a tenth of them on the faces.

        An unbounded ``Omegabar`` side is sampled up to ``omega_extent``."""
        lo = np.array([self.Vbar[0], self.gammabar[0], self.alphabar[0], max(self.Omegabar[0], -omega_extent)])
        hi = np.array([self.Vbar[1], self.gammabar[1], self.alphabar[1], min(self.Omegabar[1], omega_extent)])
        z = lo + (hi - lo) * rng.random((n, 4))
        k = n // 10
        face = rng.integers(0, 4, k)
        side = rng.integers(0, 2, k)
        z[np.arange(k), face] = np.where(side == 1, hi[face], lo[face])
        return z


@dataclass(frozen=True)
class CompositeVerification:
    """Sampled margin of every inequality of §5.1-§5.3 (result of :meth:`CompositeCertificate.verify`).

    Attributes
    ----------
    margins : dict[str, float]
        ``right side / left side`` at the worst sample of each inequality: ``>= 1`` holds, ``< 1`` fails. ``inf``
        when the left side never reaches a positive value on the samples (or no sample qualifies), ``0.0`` when a
        derivative that must be negative is not negative everywhere.
    n_samples, seed : int
    passed : bool
        Every margin is ``>= 1`` (relative tolerance 1e-9).
    """

    margins: dict[str, float]
    n_samples: int
    seed: int

    @property
    def passed(self) -> bool:
        return all(m >= 1.0 - 1e-9 for m in self.margins.values())

    def failing(self) -> dict[str, float]:
        """The entries of :attr:`margins` below 1 (relative tolerance 1e-9)."""
        return {k: m for k, m in self.margins.items() if not m >= 1.0 - 1e-9}


def _margin(ratio: float) -> float:
    """Margin ``1 / ratio`` of a worst sampled ratio ``left / right`` (``inf`` for a ratio ``<= 0``, ``0`` for
    ``inf``)."""
    return math.inf if ratio <= 0 else 1.0 / ratio


@dataclass(frozen=True)
class CompositeCertificate:
    """All constants of Propositions 1-2 and Theorem 2 for one glider and domain, and the verdict.

    ``certified`` is True exactly when ``mu < mu_d`` (the composite function ``nu`` with the ``d`` of (5.84)
    proves asymptotic stability on ``B_p x B_q`` and ``L*`` (5.85) is a region-of-attraction estimate).

    All constants are nondimensional (variables and time ``t_n`` of §5.1).

    Attributes
    ----------
    sp : SingularPerturbation
        Chapter-5 analysis of the vehicle (``eps1``, ``eps2``, ``mu``, ``r1``, ``r2``).
    domain : Domain
        The box ``B_p x B_q``.
    cw : str
        ``"corrected"`` or ``"thesis"``: which ``C_W`` of (5.31) is used.
    k1, k2, e, a1, b1 : float
        Constants of Proposition 2 ((5.37)-(5.49)) for ``Phi`` on ``B_p``.
    k3, k4 : float
        Half the smallest and largest eigenvalues of ``C_W`` over the ``Vbar`` range (Proposition 1, corrected):
        ``k3 |q|^2 <= W <= k4 |q|^2``.
    a2, b2 : float
        Decrease rate of ``W`` along the boundary layer, ``dW/dtau <= -a2 sigma^2``, and ``b2 = a2 (1 +
        Vbar_min)^2``; ``a2 <= 0`` means Proposition 1 fails.
    beta1, gamma1 : float
        Interconnection constants of Theorem 2, condition 1 ((5.57)-(5.63)).
    beta2p, gamma2p : float
        ``beta2'``, ``gamma2'`` of condition 2 ((5.64)-(5.78), re-derived for the general ``c1``).
    beta2pp, gamma2pp : float
        ``beta2''``, ``gamma2''`` of condition 3 ((5.79)-(5.81), the valid reading of the module docstring).
    beta2, gamma2 : float
        ``beta2' + beta2''`` and ``gamma2' + gamma2''``.
    F1 : float
        Upper bound of ``|f1|`` on the domain, used in ``gamma2''``.
    mu_star : float
        ``a1 a2 / (a1 gamma2 + a2 gamma1 + beta1 beta2)`` (0 when ``a2 <= 0``).
    v0, w0 : float
        Smallest ``Phi`` on the faces of ``B_p`` and largest level of ``W`` inside ``B_q``.
    d : float
        Weight of (5.84), ``v0 / (v0 + w0)``.
    mu_d : float
        Bound ``mu_d(d)`` of (5.54) at that ``d``.
    level : float
        ``L* = v0 w0 / (v0 + w0)``, the level of ``nu`` bounding the region-of-attraction estimate (5.85).
    d_best, mu_d_best : float
        The ``d`` in ``(0, 1)`` maximizing ``mu_d`` and that maximum.
    mu : float
        ``max(eps1, eps2)`` of the vehicle (5.26).
    certified : bool
        ``mu < mu_d``.
    vehicle : Vehicle
        The vehicle.
    provenance : str
        Its parameter hash (:attr:`Vehicle.provenance`).
    """

    sp: SingularPerturbation = field(repr=False)
    domain: Domain
    cw: str
    k1: float
    k2: float
    k3: float
    k4: float
    a1: float
    b1: float
    a2: float
    b2: float
    e: float
    beta1: float
    gamma1: float
    beta2p: float
    gamma2p: float
    beta2pp: float
    gamma2pp: float
    F1: float
    mu_star: float
    v0: float
    w0: float
    d: float
    mu_d: float
    level: float
    d_best: float
    mu_d_best: float
    vehicle: Vehicle = field(repr=False, compare=False)
    provenance: str

    @property
    def mu(self) -> float:
        """``max(eps1, eps2)`` of the vehicle (5.26)."""
        return self.sp.mu

    @property
    def certified(self) -> bool:
        return bool(self.mu < self.mu_d)

    @property
    def omega_extent(self) -> float:
        """Largest ``|Omegabar2|`` in ``{W <= w0}`` (over the ``Vbar`` range), or the domain bound if smaller."""
        V = np.linspace(*self.domain.Vbar, 401)
        c1, c2, c3 = self.cw_entries(V)
        ext = float(np.max(np.sqrt(2 * self.w0 * c1 / (c1 * c2 - c3**2))))
        return min(1.05 * ext, max(-self.domain.Omegabar[0], self.domain.Omegabar[1]))

    @property
    def beta2(self) -> float:
        return self.beta2p + self.beta2pp

    @property
    def gamma2(self) -> float:
        return self.gamma2p + self.gamma2pp

    def mu_d_of(self, d: Any) -> Any:
        """``mu_d(d)`` of (5.54) for ``0 < d < 1``."""
        d = np.asarray(d, dtype=float)
        return _mu_d(d, self.a1, self.a2, self.beta1, self.beta2, self.gamma1, self.gamma2)

    # --------------------------------------------------------------------------------------------- functions
    def cw_entries(self, Vbar: Any) -> tuple[Any, Any, Any]:
        """``(c1, c2, c3)`` of ``C_W`` at ``Vbar``."""
        return _cw(self.cw, self.sp.r1, self.sp.r2, (1 + np.asarray(Vbar)) ** 2)

    @staticmethod
    def Phi(p: Any) -> Any:
        """Reduced-subsystem Lyapunov function (5.35)."""
        p = np.asarray(p)
        V, g = p[..., 0], p[..., 1]
        return 2.0 / 3.0 - (1 + V) * np.cos(g) + (1 + V) ** 3 / 3.0

    def W(self, p: Any, q: Any) -> Any:
        """Boundary-layer Lyapunov function (5.31)."""
        p, q = np.asarray(p), np.asarray(q)
        c1, c2, c3 = self.cw_entries(p[..., 0])
        a, O = q[..., 0], q[..., 1]
        return 0.5 * (c1 * a * a + 2 * c3 * a * O + c2 * O * O)

    def nu(self, z: Any, d: float | None = None) -> Any:
        """Composite Lyapunov function (5.53)/(5.83) at ``z = (Vbar, gammabar, alphabar, Omegabar2)``."""
        z = np.asarray(z)
        d = self.d if d is None else d
        return (1 - d) * self.Phi(z[..., :2]) + d * self.W(z[..., :2], z[..., 2:])

    @staticmethod
    def psi(p: Any) -> Any:
        """(5.50)."""
        p = np.asarray(p)
        V, g = p[..., 0], p[..., 1]
        return np.sqrt((V * V + 2 * V) ** 2 + 4 * (1 + V) ** 2 * np.sin(g / 2) ** 2)

    @staticmethod
    def sigma(z: Any) -> Any:
        """(5.32) at ``z = (Vbar, ., alphabar, Omegabar2)``."""
        z = np.asarray(z)
        return (1 + z[..., 0]) * np.hypot(z[..., 2], z[..., 3])

    def in_estimate(self, z: Any) -> Any:
        """Membership of ``L*`` (5.85): inside the box and ``nu <= v0 w0 / (v0 + w0)``."""
        z = np.asarray(z)
        box = np.ones(z.shape[:-1], dtype=bool)
        for i, (lo, hi) in enumerate(_bounds(self.domain)):
            box &= (z[..., i] >= lo) & (z[..., i] <= hi)
        return box & (self.nu(z) <= self.level)

    def plot(self, ax: Any = None, *, n: int = 201) -> Any:
        """Draw ``L*`` (5.85) in the ``(Vbar, gammabar)`` plane at ``alphabar = Omegabar2 = 0``, with the level set
        ``{Phi <= v0}`` (5.35) and the box ``B_p``, in the glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        n : int
            Grid points per axis.

        Returns
        -------
        matplotlib.axes.Axes
            The title says whether ``L*`` is certified (``mu < mu_d``); see
            :func:`glidectl.plotting.plot_composite_certificate`.
        """
        from ..plotting import plot_composite_certificate, style

        with style():
            return plot_composite_certificate(self, ax, n=n)

    def _grad_W(self, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(dW/dVbar, dW/dalphabar, dW/dOmegabar2) by complex step (exact)."""
        h = 1e-30
        V = p[..., 0]
        dV = np.imag(self.W(np.stack([V + 1j * h, p[..., 1]], axis=-1), q)) / h
        c1, c2, c3 = self.cw_entries(V)
        a, O = q[..., 0], q[..., 1]
        return dV, c1 * a + c3 * O, c3 * a + c2 * O

    # --------------------------------------------------------------------------------------------- checks
    def verify(self, n: int = 200_000, seed: int = 0) -> CompositeVerification:
        """Sample ``B_p x B_q`` and return the margin (right / left at the worst sample) of every bound of
        §5.1-§5.3.

        Left sides are evaluated with the model's own vector fields (:meth:`SingularPerturbation.f`, ``g``), not
        with the thesis's algebra, so a wrong derivation shows up as a margin below 1.
        """
        sp = self.sp
        rng = np.random.default_rng(seed)
        z = self.domain.sample(n, rng, omega_extent=self.omega_extent)
        p, q = z[:, :2], z[:, 2:]
        V = p[:, 0]
        P2 = np.sum(p * p, axis=1)
        Q2 = np.sum(q * q, axis=1)
        Phi, W = self.Phi(p), self.W(p, q)
        psi, sig = self.psi(p), self.sigma(z)
        q0 = np.zeros_like(q)
        f_pq, f_p0 = sp.f(p, q), sp.f(p, q0)
        dPhi = np.stack([-np.cos(p[:, 1]) + (1 + V) ** 2, (1 + V) * np.sin(p[:, 1])], axis=1)
        dWV, dWa, dWO = self._grad_W(p, q)
        Ar = np.array([sp.r1, sp.r2])
        g_eps, g_0 = sp.g(p, q), sp.g(p, q, eps=False)
        tiny = 1e-300

        def worst(lhs: np.ndarray, rhs: np.ndarray, mask: np.ndarray | None = None) -> float:
            ok = rhs > 1e-14 if mask is None else mask & (rhs > 1e-14)
            return float(np.max(lhs[ok] / rhs[ok])) if np.any(ok) else 0.0

        r: dict[str, float] = {}
        r["Prop2.1 lower: k1|p|^2 <= Phi"] = worst(self.k1 * P2, Phi)
        r["Prop2.1 upper: Phi <= k2|p|^2"] = worst(Phi, self.k2 * P2)
        dPhidt = np.sum(dPhi * f_p0, axis=1)
        r["Prop2.2: dPhi/dt_n <= -a1 psi^2"] = worst(self.a1 * psi**2, -dPhidt, dPhidt < 0) \
            if np.all(dPhidt < 0) else float("inf")
        r["Prop2.2: a1 psi^2 >= b1 |p|^2"] = worst(self.b1 * P2, self.a1 * psi**2)
        r["Prop1.1 lower: k3|q|^2 <= W"] = worst(self.k3 * Q2, W)
        r["Prop1.1 upper: W <= k4|q|^2"] = worst(W, self.k4 * Q2)
        bl = sp.boundary_layer_rhs(p, q)
        dWdtau = dWa * bl[:, 0] + dWO * bl[:, 1]
        r["Prop1.2: dW/dtau <= -a2 sigma^2"] = worst(self.a2 * sig**2, -dWdtau, dWdtau < 0) \
            if self.a2 > 0 and np.all(dWdtau < 0) else float("inf")
        r["Prop1.2: a2 sigma^2 >= b2 |q|^2"] = worst(self.b2 * Q2, self.a2 * sig**2)
        C1 = np.sum(dPhi * (f_pq - f_p0), axis=1)
        r["Thm2.1: C1 <= beta1 psi sigma + mu gamma1 psi^2"] = worst(C1, self.beta1 * psi * sig
                                                                     + sp.mu * self.gamma1 * psi**2)
        C2 = (dWa * Ar[0] * (g_eps[:, 0] - g_0[:, 0]) + dWO * Ar[1] * (g_eps[:, 1] - g_0[:, 1]))
        r["Thm2.2: C2 <= mu (gamma2' sigma^2 + beta2' psi sigma)"] = worst(
            C2, sp.mu * (self.gamma2p * sig**2 + self.beta2p * psi * sig))
        C3 = np.abs(dWV * f_pq[:, 0])
        r["Thm2.3: |dW/dp f| <= gamma2'' sigma^2 + beta2'' psi sigma"] = worst(
            C3, self.gamma2pp * sig**2 + self.beta2pp * psi * sig)
        r["F1 >= |f1|"] = worst(np.abs(f_pq[:, 0]), np.full(n, self.F1))
        inside_p = (self.Phi(p) <= self.v0)
        r["{Phi <= v0} inside B_p (sampled on the faces)"] = 0.0
        r["{W <= w0} inside B_q (sampled on the faces)"] = 0.0
        # on the faces of B_p, Phi >= v0; on the faces of B_q, W >= w0 (so the sublevel sets lie inside)
        lo, hi = np.array([b[0] for b in _bounds(self.domain)]), np.array([b[1] for b in _bounds(self.domain)])
        on = np.isclose(z, lo) | np.isclose(z, hi)
        fp = on[:, 0] | on[:, 1]
        fq = on[:, 2] | on[:, 3]
        if np.any(fp):
            r["{Phi <= v0} inside B_p (sampled on the faces)"] = float(np.max(self.v0 / Phi[fp]))
        if np.any(fq):
            r["{W <= w0} inside B_q (sampled on the faces)"] = float(np.max(self.w0 / np.maximum(W[fq], tiny)))
        del inside_p
        if self.certified:
            dnu = ((1 - self.d) * np.sum(dPhi * f_pq, axis=1)
                   + self.d * (dWV * f_pq[:, 0] + (dWa * Ar[0] * g_eps[:, 0] + dWO * Ar[1] * g_eps[:, 1]) / sp.mu))
            r["Thm2: dnu/dt_n <= 0 on B_p x B_q"] = float(np.max(dnu / (P2 + Q2 + tiny))) + 1.0 \
                if np.max(dnu) > 0 else 0.0
        return CompositeVerification({k: _margin(v) for k, v in r.items()}, n, seed)


def _bounds(dom: Domain) -> list[tuple[float, float]]:
    return [dom.Vbar, dom.gammabar, dom.alphabar, dom.Omegabar]


def _cw(kind: str, r1: float, r2: float, a: Any) -> tuple[Any, Any, Any]:
    c2 = 1 + r1 / (r2 * a)
    c1 = 1 + 2 * r2 * a / r1 if kind == "corrected" else r1 + r1 * a + r2 * a
    return c1, c2, np.ones_like(a)


def _mu_d(d: Any, a1: float, a2: float, b1: float, b2: float, g1: float, g2: float) -> Any:
    return a1 * a2 / (a1 * g2 + a2 * g1 + ((1 - d) * b1 + d * b2) ** 2 / (4 * (1 - d) * d))


def _phi_min_on_faces(dom: Domain) -> float:
    """Smallest Phi on the boundary of B_p (closed form; Phi is even and increasing in |gammabar|)."""
    Vlo, Vhi = dom.Vbar
    gm = min(-dom.gammabar[0], dom.gammabar[1])

    def phi(V: float, g: float) -> float:
        return 2 / 3 - (1 + V) * math.cos(g) + (1 + V) ** 3 / 3

    cands = [phi(Vlo, 0.0), phi(Vhi, 0.0), phi(Vlo, gm), phi(Vhi, gm)]
    if math.cos(gm) > 0:  # stationary point in Vbar on the gammabar = gm face
        Vs = math.sqrt(math.cos(gm)) - 1
        if Vlo < Vs < Vhi:
            cands.append(phi(Vs, gm))
    return min(cands)


def composite_lyapunov(veh: Vehicle, *, Vbar: tuple[float, float] = (-0.4, 0.4),
                       alphabar: tuple[float, float] = (-0.2, 0.2),
                       gammabar: tuple[float, float] = (-math.pi, math.pi),
                       Omegabar: tuple[float, float] = (-math.inf, math.inf),
                       cw: Literal["corrected", "thesis"] = "corrected") -> CompositeCertificate:
    """Constants of Propositions 1-2 and Theorem 2, ``mu_d`` and the optimal ``d`` (5.84) on ``B_p x B_q``.

    Parameters
    ----------
    veh : Vehicle
        Chapter-5 glider (equal added masses; ``r_P = 0``). Uses the vehicle's own ``K_M, J2, ...``.
    Vbar, alphabar, gammabar, Omegabar : (lo, hi)
        The domain (nondimensional, (5.12)-(5.15)). §5.3.1 bounds only ``|Vbar| <= 0.4`` and ``|alphabar| <= 0.2``;
        by default ``gammabar`` spans ``[-pi, pi]`` (§5.1) and ``Omegabar`` is unbounded (only ``w0`` depends on
        it; with a finite bound the level ``w0`` is limited by it too).
    cw : {"corrected", "thesis"}
        ``C_W`` with the derived ``c1 = 1 + 2 r2 a / r1`` (default) or as printed (for comparison; Proposition 1
        does not hold with it, see :meth:`CompositeCertificate.verify`).

    Returns
    -------
    CompositeCertificate
        ``certified`` is True exactly when ``mu < mu_d``.

    Raises
    ------
    ModelError
        If the vehicle has no singularly perturbed chapter-5 glide (from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`).
    GlidectlError
        If the added masses are unequal (``m1 + mbar != m3 + mbar``; see
        :func:`~glidectl.stability.unequal_mass.unequal_mass_check`), ``cw`` is not ``"corrected"`` or
        ``"thesis"``, or the domain is invalid (:class:`Domain`).
    """
    sp = singular_perturbation(veh)
    M1, M3 = sp.model.masses
    if M1 != M3:
        raise GlidectlError(f"composite_lyapunov implements §5.2-§5.3 for equal added masses; vehicle '{veh.name}' "
                            f"has m1 + mbar = {M1:g} kg, m3 + mbar = {M3:g} kg (see unequal_mass_check for (5.110))")
    if cw not in ("corrected", "thesis"):
        raise GlidectlError(f"cw must be 'corrected' or 'thesis', got {cw!r}")
    dom = Domain(tuple(Vbar), tuple(gammabar), tuple(alphabar), tuple(Omegabar))
    Vlo, Vhi = dom.Vbar
    Vabs = max(-Vlo, Vhi)
    gmax = max(-dom.gammabar[0], dom.gammabar[1])
    amax = max(-dom.alphabar[0], dom.alphabar[1])
    r1, r2 = sp.r1, sp.r2
    # Proposition 2 (5.37)-(5.49)
    k1 = min(1 + Vlo / 3, (1 + Vlo) / 2 * (1 - gmax**2 / 12))
    k2 = max(1 + Vhi / 3, (1 + Vhi) / 2)
    e = 1 - gmax**2 / 24
    a1, b1 = 1.0, e**2 * (1 + Vlo) ** 2
    # Proposition 1: eigenvalues of C_W / 2 over the Vbar range
    Vg = np.linspace(Vlo, Vhi, 2001)
    c1, c2, c3 = _cw(cw, r1, r2, (1 + Vg) ** 2)
    tr, det = c1 + c2, c1 * c2 - c3**2
    if np.any(det <= 0) or np.any(c1 <= 0):  # pragma: no cover - both C_W choices are positive definite
        raise GlidectlError(f"C_W ({cw}) is not positive definite on the Vbar range {dom.Vbar}")
    disc = np.sqrt((c1 - c2) ** 2 + 4 * c3**2)
    lmin, lmax = (tr - disc) / 2, (tr + disc) / 2

    def refine(fun: Any, sign: float) -> float:
        i = int(np.argmin(sign * fun(Vg)))
        a, b = Vg[max(i - 1, 0)], Vg[min(i + 1, Vg.size - 1)]
        if a == b:
            return float(fun(np.array([a]))[0])
        res = minimize_scalar(lambda v: sign * float(fun(np.array([v]))[0]), bounds=(a, b), method="bounded",
                              options={"xatol": 1e-12})
        return float(min(sign * fun(np.array([a, b, res.x]))) * sign)

    def lam(which: str) -> Any:
        def fn(V: np.ndarray) -> np.ndarray:
            c1_, c2_, c3_ = _cw(cw, r1, r2, (1 + V) ** 2)
            dd = np.sqrt((c1_ - c2_) ** 2 + 4 * c3_**2)
            return (c1_ + c2_ - dd) / 2 if which == "min" else (c1_ + c2_ + dd) / 2
        return fn

    k3 = 0.5 * min(float(np.min(lmin)), refine(lam("min"), 1.0))
    k4 = 0.5 * max(float(np.max(lmax)), refine(lam("max"), -1.0))
    # a2: dW/dtau = q^T S(a) q with S = sym(C_W A_bl), A_bl = [[0, r1], [-r2 a, -r2 a]] and sigma^2 = a |q|^2,
    # so a2 = min over a of -lambda_max(S(a)) / a (= r2 exactly for the corrected C_W)
    def a2_of(V: np.ndarray) -> np.ndarray:
        aa = (1 + V) ** 2
        c1_, c2_, c3_ = _cw(cw, r1, r2, aa)
        s11 = -c3_ * r2 * aa
        s22 = c3_ * r1 - c2_ * r2 * aa
        s12 = 0.5 * (c1_ * r1 - c3_ * r2 * aa - c2_ * r2 * aa)
        lmax_ = 0.5 * (s11 + s22) + np.sqrt(0.25 * (s11 - s22) ** 2 + s12**2)
        return -lmax_ / aa

    a2 = min(float(np.min(a2_of(Vg))), refine(a2_of, 1.0))
    if cw == "corrected":
        a2 = min(a2, r2)
    b2 = a2 * (1 + Vlo) ** 2
    # Theorem 2, condition 1 (5.57)-(5.63)
    KL, KD, KDe, KLe = sp.model.vehicle.K_L, sp.model.vehicle.K_D, sp.K_De, sp.K_Le
    beta1 = (abs(KL) + KD * (amax + 2 * abs(sp.alpha)) * (math.sqrt(2) * (1 + max(Vhi, 0.0)) + Vabs)) / KDe
    gamma1 = 0.0
    # condition 2 (5.64)-(5.78), re-derived for general c1
    c1_all, _, _ = _cw(cw, r1, r2, (1 + Vg) ** 2)
    c1max = float(np.max(c1_all))
    gamma2p = abs(KL) * (0.5 + (c1max if KL < 0 else 0.0)) / (KDe * (1 + Vlo))
    if cw == "corrected":
        shape = float(np.max(np.sqrt(1 + c1_all**2) / (1 + Vg) ** 2))
    else:
        shape = (1 + r1) / (1 + Vlo) ** 2 + r1 + r2  # (5.77) as printed
    beta2p = abs(KLe) / (KDe * abs(math.cos(sp.gamma))) * (math.sqrt(2) + Vabs / (1 + Vlo)) * shape
    # condition 3: |dW/dVbar f1| <= F1 max(X, Y) sigma^2
    veh_ = sp.model.vehicle
    F1 = (abs(veh_.m0) * veh_.g + (veh_.K_D0 + KD * (abs(sp.alpha) + amax) ** 2) * sp.speed**2 * (1 + Vhi) ** 2) \
        / (KDe * sp.speed**2)
    if cw == "corrected":
        X = 2 * (r2 / r1) / (1 + Vlo)  # c1' = 4 (r2/r1)(1 + V)
    else:
        X = (r1 + r2) / (1 + Vlo)      # c1' = 2 (r1 + r2)(1 + V)
    Y = (r1 / r2) / (1 + Vlo) ** 5     # c2' = -2 (r1/r2)(1 + V)^-3
    gamma2pp = F1 * max(X, Y)
    beta2pp = 0.0
    beta2, gamma2 = beta2p + beta2pp, gamma2p + gamma2pp
    # a2 <= 0: Proposition 1 fails (W is not a Lyapunov function of the boundary layer), nothing is certified
    mu_star = a1 * a2 / (a1 * gamma2 + a2 * gamma1 + beta1 * beta2) if a2 > 0 else 0.0
    # region of attraction (5.84)-(5.85)
    v0 = _phi_min_on_faces(dom)
    Olo, Ohi = dom.Omegabar
    alo, ahi = dom.alphabar

    def wlim(V: np.ndarray) -> np.ndarray:
        c1_, c2_, c3_ = _cw(cw, r1, r2, (1 + V) ** 2)
        det_ = c1_ * c2_ - c3_**2
        ia, iO = c2_ / det_, c1_ / det_  # diagonal of C_W^-1
        return np.minimum(min(-alo, ahi) ** 2 / (2 * ia), min(-Olo, Ohi) ** 2 / (2 * iO))

    w0 = min(float(np.min(wlim(Vg))), refine(wlim, 1.0))
    d = v0 / (v0 + w0)
    a2p = max(a2, 0.0)
    mu_d = float(_mu_d(d, a1, a2p, beta1, beta2, gamma1, gamma2))
    level = v0 * w0 / (v0 + w0)
    res = minimize_scalar(lambda x: -float(_mu_d(x, a1, a2p, beta1, beta2, gamma1, gamma2)),
                          bounds=(1e-9, 1 - 1e-9), method="bounded", options={"xatol": 1e-12})
    return CompositeCertificate(sp, dom, cw, k1, k2, k3, k4, a1, b1, a2, b2, e, beta1, gamma1, beta2p, gamma2p,
                                beta2pp, gamma2pp, F1, mu_star, v0, w0, d, mu_d, level, float(res.x),
                                float(-res.fun), veh, veh.provenance)
