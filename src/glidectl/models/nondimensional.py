"""Nondimensional chapter-5 glider of the singular-perturbation analysis, §5.1: the scalings (5.12)-(5.19), the
compact form (5.28)-(5.29), the boundary-layer (5.30) and reduced (5.33) subsystems, and the reduced (slow) model in
dimensional form (5.4)-(5.5) simulated in Fig 5.1.

Every vector field here is the dimensional right-hand side
:meth:`glidectl.models.reduced.ReducedLongitudinalGlider.rhs` seen through the change of variables, so there is one
model and no second copy of its equations:

``f(p, q) = tau_s (V'/V_e, gamma')`` and ``g(p, q, eps) = (eps1 tau_s alpha', eps2 tau_s (K_q/K_M) Omega2')``,
with ``p = (Vbar, gammabar)``, ``q = (alphabar, Omegabar2)``. Because ``alpha' = Omega2 - gamma'`` exactly,
``g1 = Omegabar2 - eps1 f2`` and the ``eps -> 0`` limit is ``g(p, q, 0) = (Omegabar2, g2)``.

The numbers the change of variables needs (steady glide, slow time scale, small parameters) are plain inputs of
:class:`NondimensionalScaling`; :func:`glidectl.stability.singular_perturbation.singular_perturbation` computes them
and its result builds the models (``reduced_model()``, ``full_model()``, ``slow_model()``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ModelError
from ..params import Vehicle
from ._validate import angle_arg, require_instance, trailing_array
from .reduced import ReducedLongitudinalGlider, require_v2_pitch_damping

__all__ = ["NondimensionalModel", "NondimensionalScaling", "SlowModel"]


@dataclass(frozen=True)
class NondimensionalScaling:
    """Change of variables (5.12)-(5.19) of the chapter-5 glider and its compact form (5.28)-(5.29).

    Holds the steady glide, the slow time scale and the small parameters; its vector fields evaluate
    :meth:`ReducedLongitudinalGlider.rhs` of ``vehicle`` at the dimensional state and rescale the rates.

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider accepted by :class:`ReducedLongitudinalGlider` (``m0 != 0``); supplies the dimensional
        model and ``K_q`` (kg m^2 s/rad), ``K_M`` (kg/rad) of the rate scale ``K_q/K_M`` (s).
    speed : float
        Equilibrium speed ``V_e`` (m/s), (5.8); ``> 0``.
    gamma : float
        Equilibrium flight-path angle ``gamma_e`` (rad), (5.9).
    alpha : float
        Equilibrium angle of attack ``alpha_e`` (rad), (5.10)/(5.90).
    tau_s : float
        Slow time scale (s), (5.18): nondimensional time is ``t_n = t / tau_s``; ``> 0``.
    eps1, eps2 : float
        Small parameters ``(K_q/K_M)/tau_s`` (5.16) and ``-J2/(K_q V_e^2 tau_s)`` (5.17), dimensionless; ``> 0``.

    Attributes
    ----------
    mu : float
        ``max(eps1, eps2)`` (5.26), dimensionless.
    r1, r2 : float
        ``mu/eps1``, ``mu/eps2`` (5.27), dimensionless.
    omega_scale : float
        ``K_q / K_M`` (s): ``Omegabar2 = (K_q/K_M) Omega2`` (5.15).
    equilibrium : ndarray, shape (4,)
        Dimensional steady glide ``(speed, gamma, alpha, 0)`` (m/s, rad, rad, rad/s).
    glider : ReducedLongitudinalGlider
        The dimensional model (the one right-hand side).

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle or a number is not a real number.
    ArgumentError
        If a number is not finite, or ``speed``, ``tau_s``, ``eps1`` or ``eps2`` is not positive.
    ModelError
        If the vehicle is not accepted by :class:`ReducedLongitudinalGlider`, or has ``K_M = 0`` (no rate scale).
    """

    vehicle: Vehicle = field(repr=False)
    speed: float
    gamma: float
    alpha: float
    tau_s: float
    eps1: float
    eps2: float

    def __post_init__(self) -> None:
        ReducedLongitudinalGlider(self.vehicle)  # same validity conditions
        require_v2_pitch_damping(self.vehicle, "the nondimensional scaling (5.12)-(5.19)")
        units = {"speed": "m/s", "gamma": "rad", "alpha": "rad", "tau_s": "s", "eps1": "", "eps2": ""}
        for k, unit in units.items():
            v = getattr(self, k)
            v = checks.real(k, v, unit=unit) if k in ("gamma", "alpha") else checks.positive(k, v, unit=unit)
            object.__setattr__(self, k, v)
        if self.vehicle.K_M == 0:
            raise ModelError(f"vehicle '{self.vehicle.name}' has K_M = 0: no rate scale K_q/K_M (5.15)")

    # ---------------------------------------------------------------- small parameters (5.26)-(5.27)
    @property
    def mu(self) -> float:
        """``max(eps1, eps2)`` (5.26)."""
        return max(self.eps1, self.eps2)

    @property
    def r1(self) -> float:
        """``mu / eps1`` (5.27)."""
        return self.mu / self.eps1

    @property
    def r2(self) -> float:
        """``mu / eps2`` (5.27)."""
        return self.mu / self.eps2

    @cached_property
    def glider(self) -> ReducedLongitudinalGlider:
        """The dimensional model whose right-hand side every field here rescales (built once per scaling: the
        vehicle is immutable)."""
        return ReducedLongitudinalGlider(self.vehicle)

    # ---------------------------------------------------------------- coordinates (5.12)-(5.15), (5.19)
    @property
    def omega_scale(self) -> float:
        """``K_q / K_M`` (s): ``Omegabar2 = (K_q/K_M) Omega2`` (5.15)."""
        v = self.vehicle
        return float(v.K_q / v.K_M)

    @property
    def equilibrium(self) -> np.ndarray:
        """Dimensional steady glide ``(speed, gamma, alpha, 0)``."""
        return np.array([self.speed, self.gamma, self.alpha, 0.0])

    def to_nondimensional(self, x: Any) -> np.ndarray:
        """``(V, gamma, alpha, Omega2) -> (Vbar, gammabar, alphabar, Omegabar2)``, (5.12)-(5.15); shape
        ``(..., 4)``."""
        x = trailing_array("x", x, 4)
        return np.stack([(x[..., 0] - self.speed) / self.speed, x[..., 1] - self.gamma, x[..., 2] - self.alpha,
                         self.omega_scale * x[..., 3]], axis=-1)

    def to_dimensional(self, z: Any) -> np.ndarray:
        """Inverse of :meth:`to_nondimensional`; shape ``(..., 4)``."""
        z = trailing_array("z", z, 4)
        return np.stack([self.speed * (1 + z[..., 0]), z[..., 1] + self.gamma, z[..., 2] + self.alpha,
                         z[..., 3] / self.omega_scale], axis=-1)

    # ---------------------------------------------------------------- compact form (5.28)-(5.29)
    def _rates(self, p: Any, q: Any) -> tuple[Any, Any, Any, Any]:
        p, q = trailing_array("p", p, 2), trailing_array("q", q, 2)
        z = np.concatenate(np.broadcast_arrays(p, q), axis=-1)
        d = self.glider.rhs(self.to_dimensional(z))
        return d[..., 0], d[..., 1], d[..., 2], d[..., 3]

    def _f_of(self, Vd: Any, gd: Any) -> np.ndarray:
        return np.stack([self.tau_s * Vd / self.speed, self.tau_s * gd], axis=-1)

    def _g_of(self, gd: Any, ad: Any, Od: Any, eps: bool) -> np.ndarray:
        g1 = self.eps1 * self.tau_s * ad
        if not eps:
            g1 = g1 + self.eps1 * self.tau_s * gd
        g2 = self.eps2 * self.tau_s * self.omega_scale * Od
        return np.stack([g1, g2], axis=-1)

    def f(self, p: Any, q: Any) -> np.ndarray:
        """Slow vector field ``dp/dt_n = f(p, q)`` of (5.28), ``p = (Vbar, gammabar)``."""
        Vd, gd, _, _ = self._rates(p, q)
        return self._f_of(Vd, gd)

    def f_and_g(self, p: Any, q: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(f(p, q), g(p, q), g(p, q, 0))`` of (5.28)-(5.29) from one evaluation of the right-hand side (equal to
        the three separate calls of :meth:`f` and :meth:`g`, which each evaluate it); ``p``, ``q`` of shape
        ``(..., 2)``."""
        Vd, gd, ad, Od = self._rates(p, q)
        return self._f_of(Vd, gd), self._g_of(gd, ad, Od, True), self._g_of(gd, ad, Od, False)

    def g(self, p: Any, q: Any, eps: bool = True) -> np.ndarray:
        """Fast vector field ``g(p, q, eps)`` of (5.29) (``mu dq/dt_n = A g``); ``eps=False`` gives ``g(p, q, 0)``.

        ``g1 = eps1 dalphabar/dt_n = Omegabar2 - eps1 f2`` and ``g2 = eps2 dOmegabar2/dt_n``; with ``eps=False``
        the ``eps1 f2`` term is dropped (the only place the small parameters enter once ``p, q`` are fixed).
        """
        _, gd, ad, Od = self._rates(p, q)
        return self._g_of(gd, ad, Od, eps)

    def A(self) -> np.ndarray:
        """``diag(r1, r2)`` of (5.29)."""
        return np.diag([self.r1, self.r2])

    def full_rhs_nondimensional(self, z: Any) -> np.ndarray:
        """``dz/dt_n`` for ``z = (p, q)`` (shape ``(..., 4)``): ``(f, A g / mu)``."""
        z = trailing_array("z", z, 4)
        f, g, _ = self.f_and_g(z[..., :2], z[..., 2:])     # one evaluation of the right-hand side for f and g
        return np.concatenate([f, g * np.array([self.r1, self.r2]) / self.mu], axis=-1)

    def reduced_rhs(self, p: Any) -> np.ndarray:
        """Reduced subsystem (5.33): ``dp/dt_n = f(p, 0)``, ``p`` of shape ``(..., 2)``."""
        p = trailing_array("p", p, 2)
        return self.f(p, np.zeros_like(p))

    def boundary_layer_rhs(self, p: Any, q: Any) -> np.ndarray:
        """Boundary-layer subsystem (5.30): ``dq/dtau = A g(p, q, 0)``, ``tau = t_n / mu``."""
        return self.g(p, q, eps=False) * np.array([self.r1, self.r2])


@dataclass(frozen=True)
class NondimensionalModel:
    """A nondimensional chapter-5 model at its steady glide (equilibrium at 0), time ``t_n``.

    ``rhs`` is :meth:`NondimensionalScaling.reduced_rhs` (``kind="reduced"``) or
    :meth:`NondimensionalScaling.full_rhs_nondimensional` (the dimensional model seen through (5.12)-(5.19)).
    ``angle_states`` and ``positive_state`` tell :func:`glidectl.roa.recast` how to make it polynomial: ``gammabar``
    is an angle and the right-hand side has the factor ``1/(1 + Vbar)`` (``1/V``). ``box`` is the region of interest
    ``(lo, hi)``.

    Built by :meth:`glidectl.stability.singular_perturbation.SingularPerturbation.reduced_model` and
    :meth:`~glidectl.stability.singular_perturbation.SingularPerturbation.full_model`.

    Parameters
    ----------
    scaling : NondimensionalScaling
        Steady glide (m/s, rad), slow time scale ``tau_s`` (s) and small parameters of the glider.
    kind : {"reduced", "full"}
        ``"reduced"``: states ``(Vbar, gammabar)`` (5.33); ``"full"``: the full model (5.28)-(5.29), states
        ``(Vbar, gammabar, alphabar, Omegabar2)``.
    state_names : tuple of str
        Names of the nondimensional states (must match ``kind``); all are dimensionless.
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

    Attributes
    ----------
    name : str
        Vehicle, kind and ``K_M`` (kg/rad), for tables and plots.
    provenance : str
        The vehicle's parameter hash.
    equilibrium : ndarray
        Zeros (the steady glide in nondimensional states).

    Raises
    ------
    ArgumentTypeError
        If ``scaling`` is not a :class:`NondimensionalScaling`.
    ArgumentError
        If ``kind`` is not ``"reduced"`` or ``"full"``, ``state_names`` does not have its 2 or 4 names, or ``box``
        is not ``(lo, hi)`` with ``lo < hi``.
    """

    scaling: NondimensionalScaling = field(repr=False)
    kind: str
    state_names: tuple[str, ...]
    box: tuple[np.ndarray, np.ndarray] = field(repr=False)
    angle_states: tuple[int, ...] = (1,)
    positive_state: int = 0
    time_unit: str = "t_n"
    input_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        require_instance("scaling", self.scaling, NondimensionalScaling)
        checks.choice("kind", self.kind, ("reduced", "full"))
        n = 2 if self.kind == "reduced" else 4
        if len(self.state_names) != n:
            raise ArgumentError(f"a {self.kind} model has {n} states, got state_names {tuple(self.state_names)}")
        b = checks.array("box", self.box, shape=(2, n))
        if not np.all(b[0] < b[1]):
            raise ArgumentError(f"box must be (lo, hi) with lo < hi in every state, got {self.box!r}")

    @property
    def name(self) -> str:
        v = self.scaling.vehicle
        return f"{v.name} {self.kind} (K_M = {v.K_M:g})"

    @property
    def provenance(self) -> str:
        return self.scaling.vehicle.provenance

    @property
    def equilibrium(self) -> np.ndarray:
        return np.zeros(len(self.state_names))

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        """``dx/dt_n`` for ``x`` of shape ``(..., 2)`` (reduced) or ``(..., 4)`` (full); ``u`` is ignored (the model
        has no inputs).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` is not an array of numbers with that trailing dimension.
        """
        if self.kind == "reduced":
            return self.scaling.reduced_rhs(x)
        return self.scaling.full_rhs_nondimensional(x)


@dataclass(frozen=True)
class SlowModel:
    """The reduced (slow) subsystem in dimensional form, state ``(V, gamma)`` (m/s, rad), for simulation.

    Its right-hand side is the ``(V', gamma')`` of :meth:`ReducedLongitudinalGlider.rhs` at ``alpha = alpha_e``,
    ``Omega2 = 0``, equations (5.4)-(5.5) / (5.33) (the slow model simulated in Fig 5.1). Built by
    :meth:`glidectl.stability.singular_perturbation.SingularPerturbation.slow_model`.

    Parameters
    ----------
    vehicle : Vehicle
        Underwater glider accepted by :class:`ReducedLongitudinalGlider` (``m0 != 0``).
    alpha : float
        Angle of attack the fast states are frozen at (rad): the steady-glide ``alpha_e`` of (5.10)/(5.90).
    state_names : tuple of str
        ``("V", "gamma")`` (m/s, rad).
    input_names : tuple of str
        Empty: the model has no inputs.

    Raises
    ------
    ArgumentTypeError
        If ``vehicle`` is not a Vehicle or ``alpha`` is not a real number.
    ArgumentError
        If ``alpha`` is not finite.
    ModelError
        If the vehicle is not accepted by :class:`ReducedLongitudinalGlider`.
    """

    vehicle: Vehicle
    alpha: float
    state_names: tuple[str, ...] = ("V", "gamma")
    input_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        ReducedLongitudinalGlider(self.vehicle)  # same validity conditions
        require_v2_pitch_damping(self.vehicle, "the nondimensional scaling (5.12)-(5.19)")
        object.__setattr__(self, "alpha", angle_arg("alpha", self.alpha))

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        """``(V', gamma')`` (m/s^2, rad/s) at ``(V, gamma)`` (m/s, rad), ``x`` of shape ``(..., 2)`` (``u`` is
        ignored: the model has no inputs).

        Raises
        ------
        ArgumentTypeError, ArgumentError
            If ``x`` is not an array of numbers with a trailing dimension 2.
        """
        x = trailing_array("x", x, 2, self.state_names)
        full = np.stack([x[..., 0], x[..., 1], np.full_like(x[..., 0], self.alpha),
                         np.zeros_like(x[..., 0])], axis=-1)
        return ReducedLongitudinalGlider(self.vehicle).rhs(full)[..., :2]
