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
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from scipy.optimize import minimize_scalar

from .. import checks
from ..analysis.measure import box_measure
from ..derivatives import partial_derivative
from ..errors import ArgumentError, ArgumentTypeError, ModelError, SolverError
from ..params import Vehicle
from .singular_perturbation import SingularPerturbation, singular_perturbation

__all__ = ["VERIFY_MIN_WIDTH", "CompositeCertificate", "CompositeVerification", "Domain", "composite_lyapunov"]

#: narrowest domain half-width :meth:`CompositeCertificate.verify` accepts (rounding of the dimensional round trip)
VERIFY_MIN_WIDTH = 1e-6


def _pair(name: str, value: Any, *, allow_inf: bool = False) -> tuple[float, float]:
    """A range ``(lo, hi)`` of two real numbers (infinite ends only with ``allow_inf``)."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence | np.ndarray):
        raise ArgumentTypeError(f"{name} must be a pair (lo, hi) of real numbers, got {type(value).__name__} "
                                f"{value!r}")
    if len(value) != 2:
        raise ArgumentError(f"{name} must be a pair (lo, hi), got {len(value)} entries {tuple(value)!r}")
    return (checks.real(f"{name}[0]", value[0], allow_inf=allow_inf),
            checks.real(f"{name}[1]", value[1], allow_inf=allow_inf))


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
    ArgumentTypeError
        If a range is not a pair of real numbers (a single number, a string, ``None`` inside).
    ArgumentError
        If a range does not have exactly two entries or does not contain 0 in its interior, is NaN or (except
        ``Omegabar``) infinite, ``Vbar_min <= -1``, ``|gammabar| > pi`` or ``|alphabar| > 2 pi``.
    """

    Vbar: tuple[float, float] = (-0.4, 0.4)
    gammabar: tuple[float, float] = (-math.pi, math.pi)
    alphabar: tuple[float, float] = (-0.2, 0.2)
    Omegabar: tuple[float, float] = (-math.inf, math.inf)

    def __post_init__(self) -> None:
        for name in ("Vbar", "gammabar", "alphabar", "Omegabar"):
            lo, hi = _pair(name, getattr(self, name), allow_inf=name == "Omegabar")
            if not lo < 0 < hi:
                raise ArgumentError(f"domain bound {name} = ({lo}, {hi}) must satisfy lo < 0 < hi (finite except "
                                    "for Omegabar, which may be unbounded): a neighbourhood of the steady glide")
            object.__setattr__(self, name, (lo, hi))
        if self.Vbar[0] <= -1:
            raise ArgumentError(f"Vbar_min = {self.Vbar[0]} must be > -1 (V > 0), §5.1")
        if max(-self.gammabar[0], self.gammabar[1]) > math.pi:
            raise ArgumentError("|gammabar| must not exceed pi (the bounds of §5.1.2 assume -pi <= gammabar < pi)")
        if max(-self.alphabar[0], self.alphabar[1]) > 2 * math.pi:
            raise ArgumentError("|alphabar| must not exceed 2 pi (§5.1)")

    def sample(self, n: int, rng: np.random.Generator, omega_extent: float = 1.0) -> np.ndarray:
        """``n`` uniform samples ``(Vbar, gammabar, alphabar, Omegabar2)``; a tenth of them on the faces.

        Parameters
        ----------
        n : int
            Number of samples, ``>= 0``.
        rng : numpy.random.Generator
            Source of the samples.
        omega_extent : float
            An unbounded ``Omegabar`` side is sampled up to this value (> 0).

        Returns
        -------
        ndarray, shape (n, 4)

        Raises
        ------
        ArgumentTypeError
            If ``n`` is not an integer, ``rng`` not a Generator or ``omega_extent`` not a real number.
        ArgumentError
            If ``n < 0`` or ``omega_extent`` is not positive and finite.
        """
        n = checks.integer("n", n, lo=0)
        if not isinstance(rng, np.random.Generator):
            raise ArgumentTypeError(f"rng must be a numpy.random.Generator (np.random.default_rng(seed)), got "
                                    f"{type(rng).__name__}")
        omega_extent = checks.positive("omega_extent", omega_extent)
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
        """``mu_d(d)`` of (5.54) for ``0 < d < 1``.

        Parameters
        ----------
        d : float or array_like
            Weight(s) of (5.53), each in the open interval (0, 1).

        Returns
        -------
        float or ndarray
            ``mu_d(d)`` (nondimensional), the shape of ``d``.

        Raises
        ------
        ArgumentTypeError
            If ``d`` is not real numbers.
        ArgumentError
            If a weight is not finite or not in (0, 1).
        """
        d = checks.array("d", d)
        if np.any(d <= 0) or np.any(d >= 1):
            raise ArgumentError(f"d must lie in the open interval (0, 1), got {d!r}")
        return _mu_d(d, self.a1, self.a2, self.beta1, self.beta2, self.gamma1, self.gamma2)

    # --------------------------------------------------------------------------------------------- functions
    def cw_entries(self, Vbar: Any) -> tuple[Any, Any, Any]:
        """``(c1, c2, c3)`` of ``C_W`` at ``Vbar``.

        Parameters
        ----------
        Vbar : float or array_like
            ``Vbar > -1`` (nondimensional), real or complex (complex step), finite.

        Returns
        -------
        tuple of three arrays
            The entries, broadcast to the shape of ``Vbar``.

        Raises
        ------
        ArgumentTypeError
            If ``Vbar`` is not numbers.
        ArgumentError
            If it is not finite, or a real value is ``<= -1`` (``V = 0``: ``C_W`` is singular).
        """
        V = _points("Vbar", Vbar, None)
        if np.any(np.real(V) <= -1):
            raise ArgumentError("Vbar must be > -1 (V > 0) for C_W")
        return _cw(self.cw, self.sp.r1, self.sp.r2, (1 + V) ** 2)

    @staticmethod
    def Phi(p: Any) -> Any:
        """Reduced-subsystem Lyapunov function (5.35) at ``p = (Vbar, gammabar)`` (trailing dimension 2).

        Evaluated in the cancellation-free form ``Vbar^2 (1 + Vbar/3) + 2 (1 + Vbar) sin^2(gammabar/2)``
        (algebraically equal to ``2/3 - (1 + Vbar) cos(gammabar) + (1 + Vbar)^3 / 3``), so tiny domains keep their
        meaning.

        Parameters
        ----------
        p : array_like, shape (..., 2)
            Real or complex, finite.

        Returns
        -------
        ndarray, shape (...)

        Raises
        ------
        ArgumentTypeError
            If ``p`` is not numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        p = _points("p", p, 2)
        return _phi(p[..., 0], p[..., 1])

    def W(self, p: Any, q: Any) -> Any:
        """Boundary-layer Lyapunov function (5.31).

        Parameters
        ----------
        p, q : array_like, shape (..., 2)
            ``(Vbar, gammabar)`` (``Vbar > -1``) and ``(alphabar, Omegabar2)``, real or complex, finite.

        Returns
        -------
        ndarray, shape (...)

        Raises
        ------
        ArgumentTypeError
            If ``p`` or ``q`` is not numbers.
        ArgumentError
            If a trailing dimension is not 2, a value is not finite or ``Vbar <= -1``.
        """
        p, q = _points("p", p, 2), _points("q", q, 2)
        if np.any(np.real(p[..., 0]) <= -1):
            raise ArgumentError("Vbar must be > -1 (V > 0)")
        return self._W(p, q)

    def _W(self, p: np.ndarray, q: np.ndarray) -> Any:
        c1, c2, c3 = _cw(self.cw, self.sp.r1, self.sp.r2, (1 + p[..., 0]) ** 2)
        a, O = q[..., 0], q[..., 1]
        return 0.5 * (c1 * a * a + 2 * c3 * a * O + c2 * O * O)

    def nu(self, z: Any, d: float | None = None) -> Any:
        """Composite Lyapunov function (5.53)/(5.83) at ``z = (Vbar, gammabar, alphabar, Omegabar2)``.

        Parameters
        ----------
        z : array_like, shape (..., 4)
            Real or complex (complex step), finite, ``Vbar > -1``.
        d : float, optional
            Weight in (0, 1); default the certificate's :attr:`d`.

        Returns
        -------
        ndarray, shape (...)

        Raises
        ------
        ArgumentTypeError
            If ``z`` is not numbers or ``d`` not a real number.
        ArgumentError
            If the trailing dimension is not 4, a value is not finite, ``Vbar <= -1`` or ``d`` is not in (0, 1).
        """
        z = _points("z", z, 4)
        d = self.d if d is None else checks.real("d", d, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
        if np.any(np.real(z[..., 0]) <= -1):
            raise ArgumentError("Vbar must be > -1 (V > 0)")
        return (1 - d) * _phi(z[..., 0], z[..., 1]) + d * self._W(z[..., :2], z[..., 2:])

    @staticmethod
    def psi(p: Any) -> Any:
        """(5.50) at ``p = (Vbar, gammabar)``.

        Parameters
        ----------
        p : array_like, shape (..., 2)
            Real, finite.

        Returns
        -------
        ndarray, shape (...)

        Raises
        ------
        ArgumentTypeError
            If ``p`` is not numbers.
        ArgumentError
            If its trailing dimension is not 2 or it is not finite.
        """
        p = _points("p", p, 2)
        V, g = p[..., 0], p[..., 1]
        return np.sqrt((V * V + 2 * V) ** 2 + 4 * (1 + V) ** 2 * np.sin(g / 2) ** 2)

    @staticmethod
    def sigma(z: Any) -> Any:
        """(5.32) at ``z = (Vbar, ., alphabar, Omegabar2)``.

        Parameters
        ----------
        z : array_like, shape (..., 4)
            Real, finite.

        Returns
        -------
        ndarray, shape (...)

        Raises
        ------
        ArgumentTypeError
            If ``z`` is not numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        z = _points("z", z, 4)
        return (1 + z[..., 0]) * np.hypot(z[..., 2], z[..., 3])

    def in_estimate(self, z: Any) -> Any:
        """Membership of ``L*`` (5.85): inside the box and ``nu <= v0 w0 / (v0 + w0)``.

        Parameters
        ----------
        z : array_like, shape (..., 4)
            Points ``(Vbar, gammabar, alphabar, Omegabar2)``, real and finite (any, inside the box or not).

        Returns
        -------
        ndarray of bool, shape (...)

        Raises
        ------
        ArgumentTypeError
            If ``z`` is not real numbers.
        ArgumentError
            If its trailing dimension is not 4 or it is not finite.
        """
        z = _points("z", z, 4, real=True)
        box = np.ones(z.shape[:-1], dtype=bool)
        for i, (lo, hi) in enumerate(_bounds(self.domain)):
            box &= (z[..., i] >= lo) & (z[..., i] <= hi)
        inside = np.zeros(z.shape[:-1], dtype=bool)
        if np.any(box):  # nu is evaluated in the box only (where Vbar > -1)
            inside[box] = self.nu(z[box]) <= self.level
        return inside

    @staticmethod
    def phi_area(box: Any = None, *, level: float = 2 / 3, n: int = 2**16, seed: int = 0) -> float:
        """Area of the reduced-subsystem set ``{Phi < level}`` of (5.35) in the ``(Vbar, gammabar)`` plane.

        Without ``box``, the whole set ``{Phi < 2/3}`` (the thesis's region-of-attraction estimate of the reduced
        glider: ``-1 < Vbar < sqrt(3 cos gammabar) - 1``, ``|gammabar| < pi/2``) in closed form, ``sqrt(3)
        int_{-pi/2}^{pi/2} sqrt(cos g) dg``; with ``box``, the part inside it by quasi-Monte Carlo.

        Parameters
        ----------
        box : (array_like, array_like), optional
            ``(lo, hi)`` of ``(Vbar, gammabar)`` (nondimensional, rad), finite, ``lo < hi``.
        level : float
            The level (default 2/3; without ``box`` only 2/3 has the closed form).
        n, seed : int
            Sobol points in the box and the sequence's seed, as in :func:`glidectl.box_measure`.

        Returns
        -------
        float
            The area (nondimensional speed x rad).

        Raises
        ------
        ArgumentTypeError
            If an argument has the wrong type.
        ArgumentError
            If ``box`` has the wrong shape, is not finite or has ``lo >= hi``, ``level`` is not positive, ``level``
            is not 2/3 without a box, or ``n`` or ``seed`` is out of range.
        """
        from scipy.integrate import quad

        level = checks.real("level", level, lo=0.0, lo_open=True)
        if box is None:
            if level != 2 / 3:
                raise ArgumentError(f"the closed form is for level 2/3 only (got {level:g}); pass a box for other "
                                    "levels")
            return math.sqrt(3.0) * quad(lambda g: math.sqrt(math.cos(g)), -math.pi / 2, math.pi / 2)[0]
        return box_measure(lambda P: CompositeCertificate.Phi(P) < level, box, n, seed, dim=2)

    def estimate_volume(self, box: Any = None, *, n: int = 2**16, seed: int = 0) -> float:
        """Volume of the region-of-attraction estimate ``L*`` (5.85) inside ``box``, by quasi-Monte Carlo over
        :meth:`in_estimate`.

        Parameters
        ----------
        box : (array_like, array_like), optional
            ``(lo, hi)`` of ``(Vbar, gammabar, alphabar, Omegabar2)`` (nondimensional), finite, ``lo < hi``; default
            the domain ``B_p x B_q``.
        n, seed : int
            Sobol points in the box and the sequence's seed, as in :func:`glidectl.box_measure`.

        Returns
        -------
        float
            The volume (nondimensional); 0 when ``L*`` misses every sample.

        Raises
        ------
        ArgumentTypeError
            If an argument has the wrong type.
        ArgumentError
            If ``box`` has the wrong shape, is not finite or has ``lo >= hi`` (or no box is given and the domain's
            ``Omegabar`` range is infinite), or ``n`` or ``seed`` is out of range.
        """
        if box is None:
            b = np.array(_bounds(self.domain), dtype=float)
            if not np.all(np.isfinite(b)):
                raise ArgumentError("the domain's Omegabar range is infinite: pass a finite box (lo, hi)")
            box = (b[:, 0], b[:, 1])
        return box_measure(self.in_estimate, box, n, seed, dim=4)

    def plot(self, ax: Any = None, *, n: int = 201) -> Any:
        """Draw ``L*`` (5.85) in the ``(Vbar, gammabar)`` plane at ``alphabar = Omegabar2 = 0``, with the level set
        ``{Phi <= v0}`` (5.35) and the box ``B_p``, in the glidectl style.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw into; default a new figure.
        n : int
            Grid points per axis, in ``[2, 2000]``.

        Returns
        -------
        matplotlib.axes.Axes
            The title says whether ``L*`` is certified (``mu < mu_d``); see
            :func:`glidectl.plotting.plot_composite_certificate`.

        Raises
        ------
        ArgumentTypeError
            If ``n`` is not an integer.
        ArgumentError
            If ``n`` is outside ``[2, 2000]``.
        """
        from ..plotting import plot_composite_certificate, style

        n = checks.integer("n", n, lo=2, hi=2000)
        with style():
            return plot_composite_certificate(self, ax, n=n)

    def _grad_W(self, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(dW/dVbar, dW/dalphabar, dW/dOmegabar2) by complex step (exact)."""
        h = 1e-30
        V = p[..., 0]
        dV = partial_derivative(lambda P: self._W(P, q), p, 0, h)
        c1, c2, c3 = _cw(self.cw, self.sp.r1, self.sp.r2, (1 + V) ** 2)
        a, O = q[..., 0], q[..., 1]
        return dV, c1 * a + c3 * O, c3 * a + c2 * O

    # --------------------------------------------------------------------------------------------- checks
    def verify(self, n: int = 200_000, seed: int = 0) -> CompositeVerification:
        """Sample ``B_p x B_q`` and return the margin (right / left at the worst sample) of every bound of
        §5.1-§5.3.

        Left sides are evaluated with the model's own vector fields (:meth:`SingularPerturbation.f`, ``g``), not
        with the thesis's algebra, so a wrong derivation shows up as a margin below 1. Samples where a right side
        is below ``1e-14`` times its largest sampled value (both sides vanish there) are skipped.

        Parameters
        ----------
        n : int
            Number of samples, in ``[10, 10_000_000]`` (a tenth of them on the faces).
        seed : int
            Seed of the samples, ``>= 0``.

        Returns
        -------
        CompositeVerification

        Raises
        ------
        ArgumentTypeError
            If ``n`` or ``seed`` is not an integer.
        ArgumentError
            If ``n`` or ``seed`` is out of range, or a half-width of the domain is below :data:`VERIFY_MIN_WIDTH`
            (the sampled left sides would be dominated by rounding).
        """
        n = checks.integer("n", n, lo=10, hi=10_000_000)
        seed = checks.integer("seed", seed, lo=0)
        width = min(min(-lo, hi) for lo, hi in _bounds(self.domain))
        if width < VERIFY_MIN_WIDTH:
            raise ArgumentError(f"the domain is too small to verify by sampling: its narrowest half-width {width:.3g} "
                                f"is below {VERIFY_MIN_WIDTH:g}, and the model's vector fields (evaluated in "
                                "dimensional variables about the steady glide) lose about eps / width of relative "
                                "precision, more than the 1e-9 the margins are judged with")
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
        sc = sp.scaling
        f_pq, g_eps, g_0 = sc.f_and_g(p, q)  # one right-hand-side evaluation for f, g and g(eps = 0) at (p, q)
        f_p0 = sp.f(p, q0)
        dPhi = np.stack([-np.cos(p[:, 1]) + (1 + V) ** 2, (1 + V) * np.sin(p[:, 1])], axis=1)
        dWV, dWa, dWO = self._grad_W(p, q)
        Ar = np.array([sp.r1, sp.r2])
        tiny = 1e-300

        def worst(lhs: np.ndarray, rhs: np.ndarray, mask: np.ndarray | None = None) -> float:
            floor = 1e-14 * max(float(np.max(rhs)), tiny)  # relative: tiny domains keep their samples
            ok = rhs > floor if mask is None else mask & (rhs > floor)
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
        bl = g_0 * np.array([sc.r1, sc.r2])  # sp.boundary_layer_rhs(p, q), from the evaluation above
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
        on = (z == lo) | (z == hi)  # Domain.sample puts the face samples exactly on the faces
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


def _points(name: str, value: Any, k: int | None, *, real: bool = False) -> np.ndarray:
    """A finite numeric array (real, or complex for complex-step use unless ``real``) with trailing dimension ``k``
    (any shape when ``k`` is None)."""
    if value is None or isinstance(value, str | bytes):
        raise ArgumentTypeError(f"{name} must be an array of numbers, got {type(value).__name__} {value!r}")
    try:
        a = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nesting
        raise ArgumentTypeError(f"{name} must be an array of numbers: {exc}") from exc
    if a.dtype.kind not in ("iuf" if real else "iufc"):
        raise ArgumentTypeError(f"{name} must be an array of {'real ' if real else ''}numbers, got dtype {a.dtype}")
    if a.dtype.kind in "iu":
        a = a.astype(float)
    if k is not None and (a.ndim == 0 or a.shape[-1] != k):
        raise ArgumentError(f"{name} must have a trailing dimension {k}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ArgumentError(f"{name} must be finite (no NaN or inf)")
    return a


def _phi(V: Any, g: Any) -> Any:
    """Phi (5.35) without cancellation: ``V^2 (1 + V/3) + 2 (1 + V) sin^2(g/2)``."""
    return V * V * (1 + V / 3) + 2 * (1 + V) * np.sin(g / 2) ** 2


def _bounds(dom: Domain) -> list[tuple[float, float]]:
    return [dom.Vbar, dom.gammabar, dom.alphabar, dom.Omegabar]


def _cw(kind: str, r1: float, r2: float, a: Any) -> tuple[Any, Any, Any]:
    c2 = 1 + r1 / (r2 * a)
    c1 = 1 + 2 * r2 * a / r1 if kind == "corrected" else r1 + r1 * a + r2 * a
    return c1, c2, np.ones_like(a)


def _mu_d(d: Any, a1: float, a2: float, b1: float, b2: float, g1: float, g2: float) -> Any:
    return a1 * a2 / (a1 * g2 + a2 * g1 + ((1 - d) * b1 + d * b2) ** 2 / (4 * (1 - d) * d))


def _phi_min_on_faces(dom: Domain) -> float:
    """Smallest Phi on the boundary of B_p (closed form; Phi is even and increasing in |gammabar|), evaluated
    without cancellation (tiny domains keep their meaning)."""
    Vlo, Vhi = dom.Vbar
    gm = min(-dom.gammabar[0], dom.gammabar[1])

    def phi(V: float, g: float) -> float:
        return float(_phi(V, g))

    cands = [phi(Vlo, 0.0), phi(Vhi, 0.0), phi(Vlo, gm), phi(Vhi, gm)]
    if math.cos(gm) > 0:  # stationary point in Vbar on the gammabar = gm face: (1 + V)^2 = cos(gm)
        Vs = math.expm1(0.5 * math.log1p(-2 * math.sin(gm / 2) ** 2))  # sqrt(cos gm) - 1 without cancellation
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
    ArgumentTypeError
        If ``veh`` is not a Vehicle, or a range is not a pair of real numbers (e.g. ``Vbar=0.4``).
    ArgumentError
        If ``cw`` is not ``"corrected"`` or ``"thesis"``, a range is invalid (:class:`Domain`: not two entries,
        not ``lo < 0 < hi``, NaN...), or the domain is so small that its levels ``v0``, ``w0`` underflow (the
        certificate would lose its meaning).
    ModelError
        If the vehicle has no singularly perturbed chapter-5 glide (from
        :func:`~glidectl.stability.singular_perturbation.singular_perturbation`), or the added masses are unequal
        (``m1 + mbar != m3 + mbar``; see :func:`~glidectl.stability.unequal_mass.unequal_mass_check`).
    SolverError
        If a computed constant is not finite or ``C_W`` is not positive definite (an internal inconsistency).

    Examples
    --------
    >>> import glidectl as gc
    >>> cert = gc.composite_lyapunov(gc.load_vehicle("sphere_ch5", K_M=-100.0))
    >>> cert.certified, f"mu = {cert.mu:.5f} < mu_d = {cert.mu_d:.5f}"
    (True, 'mu = 0.00257 < mu_d = 0.00287')
    >>> gc.composite_lyapunov(gc.load_vehicle("sphere_ch5")).certified     # K_M = -50: mu > mu_d
    False
    """
    checks.vehicle("veh", veh, "underwater_glider")
    checks.choice("cw", cw, ("corrected", "thesis"))
    dom = Domain(Vbar, gammabar, alphabar, Omegabar)
    sp = singular_perturbation(veh)
    M1, M3 = sp.model.masses
    if M1 != M3:
        raise ModelError(f"composite_lyapunov needs chapter 5 assumption 3 (§5.1): equal added masses m1 = m3 "
                         f"(§5.2-§5.3 are proved for them); vehicle '{veh.name}' "
                         f"has m1 + mbar = {M1:g} kg, m3 + mbar = {M3:g} kg (see unequal_mass_check for (5.110))")
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
        raise SolverError(f"C_W ({cw}) is not positive definite on the Vbar range {dom.Vbar}")
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
    level = v0 * w0 / (v0 + w0) if v0 > 0 and w0 > 0 else 0.0
    tiny = float(np.finfo(float).tiny)  # below it numbers are subnormal: precision is already lost
    if not (math.isfinite(v0) and v0 >= tiny and math.isfinite(w0) and w0 >= tiny and level >= tiny):
        raise ArgumentError(f"the domain is too small to certify anything in floating point: the levels v0 = {v0:.3g} "
                            f"(Phi on the faces of B_p), w0 = {w0:.3g} (W inside B_q) and L* = {level:.3g} must be "
                            "positive normal numbers; widen "
                            f"Vbar = {dom.Vbar}, gammabar = {dom.gammabar}, alphabar = {dom.alphabar}, Omegabar = "
                            f"{dom.Omegabar}")
    d = v0 / (v0 + w0)
    a2p = max(a2, 0.0)
    mu_d = float(_mu_d(d, a1, a2p, beta1, beta2, gamma1, gamma2))
    res = minimize_scalar(lambda x: -float(_mu_d(x, a1, a2p, beta1, beta2, gamma1, gamma2)),
                          bounds=(1e-9, 1 - 1e-9), method="bounded", options={"xatol": 1e-12})
    consts = {"k1": k1, "k2": k2, "k3": k3, "k4": k4, "a2": a2, "beta1": beta1, "beta2": beta2, "gamma2": gamma2,
              "F1": F1, "mu_star": mu_star, "d": d, "mu_d": mu_d, "level": level, "mu_d_best": -float(res.fun)}
    bad = {k: v for k, v in consts.items() if not math.isfinite(v)}
    if bad or not (0 < d < 1 and mu_d >= 0 and level > 0 and min(k1, k2, k3, k4) > 0):
        raise SolverError(f"composite_lyapunov for vehicle '{veh.name}' produced constants that lost their meaning "
                          f"(non-finite {sorted(bad)}; d = {d:.3g}, mu_d = {mu_d:.3g}, level = {level:.3g}, k1..k4 = "
                          f"{k1:.3g}, {k2:.3g}, {k3:.3g}, {k4:.3g}); the domain or vehicle is outside what this "
                          "analysis can represent")
    return CompositeCertificate(sp, dom, cw, k1, k2, k3, k4, a1, b1, a2, b2, e, beta1, gamma1, beta2p, gamma2p,
                                beta2pp, gamma2pp, F1, mu_star, v0, w0, d, mu_d, level, float(res.x),
                                float(-res.fun), veh, veh.provenance)
