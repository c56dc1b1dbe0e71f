"""Hamiltonian, Lagrangian and pendulum descriptions of the phugoid-mode model (thesis §4.1-§4.3).

Each formulation is coded from its *generating object* (a Hamiltonian, a 2-form, a Lagrangian with a vector
potential, a pendulum with a driven base) and returns the vector field it generates on the phugoid state
``(x, z, xdot, zdot)`` (m, m, m/s, m/s), so that tests and the ch4 study can compare it with the one right-hand
side :meth:`glidectl.models.phugoid.PhugoidModel.rhs`. Nothing here copies that right-hand side: gradients and
Jacobians of the generating functions are taken by the complex-step method (exact to rounding, see
:mod:`glidectl.derivatives`), and the mechanical structure (Hamilton's equations, ``i_X Omega = dH``, the
Euler-Lagrange equations of a magnetic-type Lagrangian) is solved generically.

(a) :func:`canonical_field` -- 2-D canonical Hamilton's equations (4.6)-(4.8), ``q = xdot``, ``p = zdot``.
(b) :func:`omega_B`, :func:`symplectic_field` -- noncanonical symplectic form (4.31)-(4.35) with the energy
    (4.32) as Hamiltonian, ``X^T Omega_B = dH`` solved by :func:`numpy.linalg.solve`; built from the 2-form with
    :func:`wedge` and cross-checked against the charged particle (4.11)-(4.18), :func:`charged_particle_field`.
(c) :func:`vector_potential`, :func:`lagrangian`, :func:`euler_lagrange_field`, :func:`zero_energy_shift` --
    the Lagrangian (4.37) and its Euler-Lagrange equations (4.39)-(4.42).
(d) :func:`to_canonical`, :func:`legendre_hamiltonian`, :func:`legendre_field`, :func:`legendre_vector_field` --
    the Legendre transform (4.38), (4.44)-(4.48).
(e) :class:`PendulumAnalogue` -- the simple pendulum (4.19)-(4.25) and the driven-base construction
    (4.49)-(4.58), with the dimensionally correct mapping ``l = m/K``, ``g_p = m0 g/m``.

Throughout ``m = m1 + mbar`` (kg), ``V = sqrt(xdot^2 + zdot^2)`` (m/s), z down.

Notes
-----
Thesis typos and imprecise statements found while coding chapter 4 (each is pinned by a test in
``tests/test_phugoid.py`` and listed in the ch4_phugoid report):

1. (4.10) reads ``dV/dt = (q/m) B x V``. The matrix (4.13) with ``i_X Omega_B = dH`` and (4.14)/(4.18) generates
   ``dV/dt = (q/m) V x B + g e_z`` (the usual Lorentz force, plus the gravity that the Hamiltonian (4.14)
   contains); only with ``V x B`` does ``B_y = -(K/q) V`` of §4.3.1 give the phugoid lift.
2. (4.11) ``Omega_B = m (dx ^ dp_x + ...)`` with ``p = m V`` counts m twice: the matrix (4.13) (entries m) and
   dH (4.18) (entries ``m xdot``) are in coordinates ``(r, V)``, i.e. ``Omega_B = m (dx ^ dV_x + ...)``
   ``= dx ^ dp_x + ...``.
3. The matrix printed under (4.31) has the wrong sign on its K entries: the 2-form (4.31)
   ``m (dx ^ dxdot + dz ^ dzdot) + K V dz ^ dx`` in the order ``(x, z, xdot, zdot)`` with footnote 2's
   convention (``a ^ b -> a^T b - b^T a``) is ``Omega[x, z] = -K V``, ``Omega[z, x] = +K V`` -- the same as the
   restriction of (4.13) with ``B_y = -(K/q) V``. The printed matrix (``+K V`` at ``[x, z]``) generates the
   phugoid with the lift reversed (``K -> -K``). ``omega_B(..., printed=True)`` returns it for comparison.
4. (4.34) drops factors of ``X_H``: ``X^T Omega_B = (K V X_H2 - m X_H3, -K V X_H1 - m X_H4, m X_H1, m X_H2)``
   (with the corrected matrix; the printed matrix gives ``(-K V X_H2 - m X_H3, K V X_H1 - m X_H4, ...)``).
5. (4.46) first line: ``pdot = -dH/dq = +(K/m) [dA/dq]^T (p - K A) + (0, m0 g)``, not
   ``-(1/m) [dA/dq]^T (p - K A) + ...`` (sign and the factor K); the second line lacks ``K/m``: it should read
   ``(0, -(K/m) sqrt(2 m0 g z / m) (p1 - K A1) + m0 g)``. (4.45), (4.47), (4.48) are right.
6. §4.3.2: the shift ``z -> z + E/(m0 g)`` maps every *phugoid* trajectory (any energy E) onto a zero-energy
   trajectory of the Lagrangian system (4.41)-(4.42). It does not map Lagrangian trajectories with ``E != 0``
   (they feel the lift ``K sqrt(V^2 - 2E/m)``, not ``K V``) onto solutions, and the E-L equations *do* depend on
   z. The correspondence is one-to-one only modulo the vertical-translation symmetry of the phugoid: the shifted
   depth is ``m V^2 / (2 m0 g)``, a function of the velocity alone.
7. (4.21)-(4.22) read ``dx/dt = -T cos(theta)``, ``dz/dt = mg - T sin(theta)``: the left sides are
   ``m dxdot/dt``, ``m dzdot/dt`` and sin/cos are swapped for ``sin(theta) = x/l``, ``cos(theta) = z/l``:
   ``m xddot = -T sin(theta)``, ``m zddot = m g - T cos(theta)``.
8. (4.24)-(4.25): with ``p_theta = m l thetadot`` and ``H = p_theta^2/(2m) - m g l cos(theta)``, Hamilton's
   equations give ``thetadot = l thetadot`` -- the pair is not canonical. Canonical: ``p_theta = m l^2 thetadot``,
   ``H = p_theta^2 / (2 m l^2) - m g l cos(theta)``, ``thetadot = p_theta/(m l^2)``,
   ``pdot_theta = -m g l sin(theta)``.
9. (4.51)-(4.58) are accelerations but carry a mass factor m on every right-hand term (``m V^2/l``,
   ``m g cos(theta)``, ``m V/l``, ``m g x z/l^2``...): divide by m. Corrected, ``(4.57)-(4.58)`` read
   ``xddot = (V/l) zdot``, ``zddot = g - (V/l) xdot`` and match (4.3)-(4.4) with
   ``l = m/K`` and the pendulum's gravity ``g_p = m0 g / m`` (then the centripetal part of the tension,
   ``m V^2/l``, *equals* the lift ``K V^2``). The identity holds at states of the pendulum (``|r| = l``,
   ``v`` perpendicular to ``r``) with ``thetadot > 0`` only (``V = l thetadot`` is signed in
   ``V cos(theta) = xdot``, ``V sin(theta) = -zdot``; ``thetadot < 0`` gives the reversed lift), and it is an
   identity of vector fields, not of motions: along the phugoid flow ``d^2(|r|^2/2)/dt^2 = g_p z != 0``, so the
   base-frame motion leaves the circle ``|r| = l`` at once -- it is not a pendulum with a rigid rod.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import checks
from ..derivatives import jacobian_batch
from ..errors import ArgumentError, ModelError
from ._validate import require_instance
from .phugoid import PhugoidModel

__all__ = [
    "PendulumAnalogue",
    "canonical_field",
    "canonical_vector_field",
    "charged_particle_field",
    "charged_particle_omega",
    "euler_lagrange_field",
    "from_canonical",
    "interior_product",
    "lagrangian",
    "legendre_field",
    "legendre_hamiltonian",
    "legendre_vector_field",
    "omega_B",
    "pdot_as_printed",
    "symplectic_field",
    "to_canonical",
    "vector_potential",
    "wedge",
    "zero_energy_shift",
]

_H = 1e-30  # complex step


def _grad(f: Callable[[Any], Any], x: Any) -> np.ndarray:
    """Gradient of a batch scalar function ``f(x[..., n]) -> [...]`` by complex step, shape (..., n)."""
    return jacobian_batch(f, np.asarray(x, dtype=float), _H)


def _jac(f: Callable[[Any], Any], x: Any) -> np.ndarray:
    """Jacobian ``J[..., i, j] = d f_i / d x_j`` of a batch map ``f(x[..., n]) -> [..., k]`` by complex step."""
    return jacobian_batch(f, np.asarray(x, dtype=float), _H)


def _stack(*cols: Any) -> Any:
    return np.stack(np.broadcast_arrays(*cols), axis=-1)


def _state(x: Any) -> np.ndarray:
    x = checks.array("phugoid state x", x)
    if x.shape[-1:] != (4,):
        raise ArgumentError(f"phugoid state must have last dimension 4 (x, z, xdot, zdot), got shape {x.shape}")
    return x


def _model(model: Any) -> PhugoidModel:
    return require_instance("model", model, PhugoidModel)


# ------------------------------------------------------------------------------------ (a) canonical 2-D form
def canonical_field(model: PhugoidModel, xdot: Any, zdot: Any) -> tuple[np.ndarray, np.ndarray]:
    """Hamilton's equations (4.7)-(4.8) of the Hamiltonian (4.6) with ``q = xdot``, ``p = zdot``.

    ``d xdot/dt = dH/dzdot``, ``d zdot/dt = -dH/dxdot`` with ``H = PhugoidModel.H_canonical`` (m^2/s^3),
    differentiated exactly (complex step).

    Parameters
    ----------
    model : PhugoidModel
    xdot, zdot : array_like
        Velocity components (m/s), broadcast together.

    Returns
    -------
    (ndarray, ndarray)
        ``(d xdot/dt, d zdot/dt)`` in m/s^2.
    """
    _model(model)
    w = _stack(np.asarray(xdot, dtype=float), np.asarray(zdot, dtype=float))
    dH = _grad(lambda v: model.H_canonical(v[..., 0], v[..., 1]), w)
    return dH[..., 1], -dH[..., 0]


def canonical_vector_field(model: PhugoidModel, x: Any) -> np.ndarray:
    """The field of (4.7)-(4.8) on the full state, positions reconstructed by (4.1)-(4.2), shape (..., 4)."""
    _model(model)
    x = _state(x)
    a, b = canonical_field(model, x[..., 2], x[..., 3])
    return _stack(x[..., 2], x[..., 3], a, b)


# ------------------------------------------------------------------- (b) noncanonical symplectic form
def wedge(a: Any, b: Any) -> np.ndarray:
    """Matrix of the wedge product of two 1-forms given as row vectors, ``a^T b - b^T a`` (footnote 2, ch. 4)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a[..., :, None] * b[..., None, :] - b[..., :, None] * a[..., None, :]


def omega_B(model: PhugoidModel, x: Any, *, printed: bool = False) -> np.ndarray:
    """Noncanonical symplectic form (4.31) as a 4x4 matrix in the coordinate order ``(x, z, xdot, zdot)``.

    Built from the 2-form as written, ``Omega_B = m (dx ^ dxdot + dz ^ dzdot) + K V dz ^ dx`` (kg/s and kg),
    with :func:`wedge`. This gives ``Omega[x, z] = -K V``, ``Omega[z, x] = +K V``, the restriction of the charged
    particle's (4.13) with ``B_y = -(K/q) V``.

    Parameters
    ----------
    model : PhugoidModel
    x : array_like, shape (..., 4)
        State (m, m, m/s, m/s); only the speed enters.
    printed : bool
        Return the matrix as printed under (4.31) instead (``+K V`` at ``[x, z]``, sign typo, Notes item 3).

    Returns
    -------
    ndarray, shape (..., 4, 4)
    """
    _model(model)
    x = _state(x)
    V = np.sqrt(x[..., 2] ** 2 + x[..., 3] ** 2)
    dx, dz, dxd, dzd = np.eye(4)
    kv = (-1.0 if printed else 1.0) * model.K * V[..., None, None]
    return model.mass * (wedge(dx, dxd) + wedge(dz, dzd)) + kv * wedge(dz, dx)


def interior_product(omega: Any, X: Any) -> np.ndarray:
    """``i_X Omega = X^T Omega`` (row vector), as in (4.16) and (4.34); shapes (..., n, n), (..., n) -> (..., n)."""
    return np.einsum("...i,...ij->...j", np.asarray(X), np.asarray(omega))


def symplectic_field(model: PhugoidModel, x: Any, *, printed: bool = False) -> np.ndarray:
    """Hamiltonian vector field of the energy (4.32) on ``(T*R^2, Omega_B)``: solve ``X^T Omega_B = dH`` (4.33).

    ``dH`` is the exact gradient of :meth:`PhugoidModel.energy` (it equals (4.35),
    ``(0, -m0 g, m xdot, m zdot)``); the linear system ``Omega_B^T X = dH^T`` is solved with
    :func:`numpy.linalg.solve` (``det Omega_B = m^4 != 0``).

    Parameters
    ----------
    model : PhugoidModel
    x : array_like, shape (..., 4)
    printed : bool
        Use the matrix as printed under (4.31) (it generates the phugoid with ``K -> -K``).

    Returns
    -------
    ndarray, shape (..., 4)
        ``(xdot, zdot, xddot, zddot)`` in (m/s, m/s, m/s^2, m/s^2).
    """
    _model(model)
    x = _state(x)
    dH = _grad(model.energy, x)
    om = omega_B(model, x, printed=printed)
    return np.linalg.solve(np.swapaxes(om, -1, -2), dH[..., None])[..., 0]


def charged_particle_omega(mass: float, charge: float, B: Any) -> np.ndarray:
    """Symplectic form (4.13) of a charged particle, coordinates ``(x, y, z, V_x, V_y, V_z)``.

    Parameters
    ----------
    mass : float
        Particle mass m (kg).
    charge : float
        Charge q (C).
    B : array_like, shape (..., 3)
        Magnetic field (T).

    Returns
    -------
    ndarray, shape (..., 6, 6)
        ``[[-q B^, m I], [-m I, 0]]`` with ``B^`` the skew matrix of B, as printed in (4.13).

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``mass`` is not a positive finite number, ``charge`` not a finite number, or ``B`` not finite of shape
        ``(..., 3)``.
    """
    mass, charge = checks.positive("mass", mass, unit="kg"), checks.real("charge", charge, unit="C")
    B = checks.array("B", B)
    if B.shape[-1:] != (3,):
        raise ArgumentError(f"B must have shape (..., 3), got {B.shape}")
    bx, by, bz = B[..., 0], B[..., 1], B[..., 2]
    out = np.zeros((*B.shape[:-1], 6, 6))
    out[..., 0, 1], out[..., 0, 2], out[..., 1, 2] = -charge * bz, charge * by, -charge * bx
    out[..., 1, 0], out[..., 2, 0], out[..., 2, 1] = charge * bz, -charge * by, charge * bx
    out[..., :3, 3:] = mass * np.eye(3)
    out[..., 3:, :3] = -mass * np.eye(3)
    return out


def charged_particle_field(state: Any, mass: float, charge: float, B: Callable[[np.ndarray], Any],
                           g: float) -> np.ndarray:
    """Charged particle in a magnetic field and gravity: solve ``X^T Omega_B = dH`` with (4.13)-(4.15).

    ``H = m |V|^2 / 2 - m g z`` (4.14), differentiated exactly. The result is ``(V, (q/m) V x B + g e_z)``
    (Notes item 1: (4.10) prints ``B x V`` and leaves out gravity).

    Parameters
    ----------
    state : array_like, shape (..., 6)
        ``(x, y, z, V_x, V_y, V_z)`` (m, m/s), z down.
    mass, charge : float
        m (kg), q (C).
    B : callable
        ``B(state) -> (..., 3)``, the magnetic field (T) at the state (may depend on the velocity, §4.3.1).
    g : float
        Gravity (m/s^2) in the potential ``-m g z``.

    Returns
    -------
    ndarray, shape (..., 6)

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``state`` is not finite of shape ``(..., 6)``, ``B`` is not callable, or ``mass``, ``charge``, ``g`` are
        not valid numbers (see :func:`charged_particle_omega`).
    """
    s = checks.array("state", state)
    if s.shape[-1:] != (6,):
        raise ArgumentError(f"state must have shape (..., 6), got {s.shape}")
    checks.function("B", B)
    g = checks.real("g", g, unit="m/s^2")
    dH = _grad(lambda w: 0.5 * mass * (w[..., 3] ** 2 + w[..., 4] ** 2 + w[..., 5] ** 2) - mass * g * w[..., 2], s)
    om = charged_particle_omega(mass, charge, B(s))
    return np.linalg.solve(np.swapaxes(om, -1, -2), dH[..., None])[..., 0]


# ------------------------------------------------------------------------------ (c) Lagrangian, vector potential
def vector_potential(model: PhugoidModel, q: Any) -> Any:
    """Vector potential of §4.3.2, ``A = (-(2 m0 g z)^(3/2) / (3 m0 g sqrt(m)), 0)`` (m^2/s).

    Parameters
    ----------
    model : PhugoidModel
    q : array_like, shape (..., 2)
        ``(x, z)`` (m); ``z >= 0`` (A is real only there; zero-energy states have ``z = m V^2/(2 m0 g) >= 0``).
        May be complex (complex step).

    Raises
    ------
    ModelError
        Some ``z < 0``.
    """
    _model(model)
    q = np.asarray(q)
    z = q[..., 1]
    if np.any(np.real(z) < 0):
        raise ModelError("the vector potential A of (4.37) is real only for z >= 0 (depth below the zero-energy "
                         "reference); shift the state with zero_energy_shift() first")
    m0g = model.m0 * model.g
    a1 = -((2.0 * m0g * z) ** 1.5) / (3.0 * m0g * math.sqrt(model.mass))
    return _stack(a1, np.zeros_like(a1))


def lagrangian(model: PhugoidModel, q: Any, qdot: Any) -> Any:
    """Lagrangian (4.37), ``L = m |qdot|^2/2 + K A(q) . qdot + m0 g z`` (J).

    Parameters
    ----------
    model : PhugoidModel
    q : array_like, shape (..., 2)
        ``(x, z)`` (m), ``z >= 0``.
    qdot : array_like, shape (..., 2)
        ``(xdot, zdot)`` (m/s).
    """
    _model(model)
    q, qdot = np.asarray(q), np.asarray(qdot)
    A = vector_potential(model, q)
    return (0.5 * model.mass * np.sum(qdot * qdot, axis=-1) + model.K * np.sum(A * qdot, axis=-1)
            + model.m0 * model.g * q[..., 1])


def euler_lagrange_field(model: PhugoidModel, x: Any) -> np.ndarray:
    """Euler-Lagrange equations (4.36) of the Lagrangian (4.37), solved for the accelerations, (4.41)-(4.42).

    For a magnetic-type Lagrangian ``L = m |qdot|^2/2 + K A(q) . qdot - U(q)`` (here ``U = -m0 g z``), (4.36) is
    ``m qddot + K J_A qdot = K J_A^T qdot - grad U`` with ``J_A = dA/dq``, so
    ``qddot = (K (J_A^T - J_A) qdot + (0, m0 g)) / m``: a Lorentz-like force of field ``K (dA_1/dz)``.
    ``J_A`` is the exact (complex-step) Jacobian of :func:`vector_potential`. On the zero-energy set ``E = 0``
    this is the phugoid field; elsewhere the lift is ``K sqrt(2 m0 g z/m)`` instead of ``K V``.

    Parameters
    ----------
    model : PhugoidModel
    x : array_like, shape (..., 4)
        ``(x, z, xdot, zdot)`` (m, m, m/s, m/s) with ``z >= 0``.

    Returns
    -------
    ndarray, shape (..., 4)
    """
    _model(model)
    x = _state(x)
    q, qd = x[..., :2], x[..., 2:]
    J = _jac(lambda w: vector_potential(model, w), q)
    force = model.K * np.einsum("...ij,...j->...i", np.swapaxes(J, -1, -2) - J, qd)
    force[..., 1] += model.m0 * model.g
    return np.concatenate([qd, force / model.mass], axis=-1)


def zero_energy_shift(model: PhugoidModel, x: Any) -> np.ndarray:
    """The change of coordinates of §4.3.2, ``z -> z + E/(m0 g)``: the result has ``E = 0``.

    The new depth is ``m V^2 / (2 m0 g)`` (m), a function of the velocity only (Notes item 6).

    Parameters
    ----------
    model : PhugoidModel
    x : array_like, shape (..., 4)
    """
    _model(model)
    x = _state(x).copy()
    x[..., 1] += model.energy(x) / (model.m0 * model.g)
    return x


# ------------------------------------------------------------------------ (d) Legendre transform, canonical
def to_canonical(model: PhugoidModel, x: Any) -> Any:
    """Legendre transform (4.38): ``(q, p) = (x, z, m xdot + K A_1, m zdot + K A_2)`` in (m, m, kg m/s, kg m/s).

    Parameters
    ----------
    model : PhugoidModel
    x : array_like, shape (..., 4)
        State with ``z >= 0``; may be complex.
    """
    _model(model)
    x = np.asarray(x)
    A = vector_potential(model, x[..., :2])
    return np.concatenate([x[..., :2], model.mass * x[..., 2:] + model.K * A], axis=-1)


def from_canonical(model: PhugoidModel, y: Any) -> Any:
    """Inverse of :func:`to_canonical`, ``qdot = (p - K A(q)) / m`` (4.45); ``y = (q, p)``, shape (..., 4)."""
    _model(model)
    y = np.asarray(y)
    A = vector_potential(model, y[..., :2])
    return np.concatenate([y[..., :2], (y[..., 2:] - model.K * A) / model.mass], axis=-1)


def legendre_hamiltonian(model: PhugoidModel, y: Any) -> Any:
    """Canonical Hamiltonian (4.44), ``H(q, p) = |p - K A(q)|^2 / (2 m) - m0 g z`` (J); ``y = (x, z, p1, p2)``."""
    _model(model)
    y = np.asarray(y)
    r = y[..., 2:] - model.K * vector_potential(model, y[..., :2])
    return np.sum(r * r, axis=-1) / (2.0 * model.mass) - model.m0 * model.g * y[..., 1]


def legendre_field(model: PhugoidModel, y: Any) -> np.ndarray:
    """Hamilton's equations (4.45)-(4.46) of (4.44) in canonical coordinates, exact derivatives.

    ``qdot = dH/dp``, ``pdot = -dH/dq`` (the latter is ``+(K/m) J_A^T (p - K A) + (0, m0 g)``; Notes item 5).

    Parameters
    ----------
    model : PhugoidModel
    y : array_like, shape (..., 4)
        ``(x, z, p1, p2)`` (m, m, kg m/s, kg m/s), ``z >= 0``.

    Returns
    -------
    ndarray, shape (..., 4)
        ``(xdot, zdot, p1dot, p2dot)``.
    """
    _model(model)
    y = np.asarray(y, dtype=float)
    dH = _grad(lambda w: legendre_hamiltonian(model, w), y)
    return np.concatenate([dH[..., 2:], -dH[..., :2]], axis=-1)


def pdot_as_printed(model: PhugoidModel, y: Any, line: int = 1) -> np.ndarray:
    """``pdot`` exactly as printed in (4.46), for comparison with :func:`legendre_field` (Notes item 5).

    ``line=1``: ``-(1/m) J_A^T (p - K A) + (0, m0 g)``; ``line=2``:
    ``(0, -sqrt(2 m0 g z)/sqrt(m) (p1 - K A1) + m0 g)``. Both are wrong (kg m/s^2).
    """
    _model(model)
    y = np.asarray(y, dtype=float)
    q, p = y[..., :2], y[..., 2:]
    r = p - model.K * vector_potential(model, q)
    mg = _stack(np.zeros(y.shape[:-1]), np.full(y.shape[:-1], model.m0 * model.g))
    checks.choice("line", line, (1, 2))
    if line == 1:
        J = _jac(lambda w: vector_potential(model, w), q)
        return -np.einsum("...ji,...j->...i", J, r) / model.mass + mg
    if line == 2:
        z = q[..., 1]
        second = -np.sqrt(2.0 * model.m0 * model.g * z) / math.sqrt(model.mass) * r[..., 0]
        return mg + _stack(np.zeros_like(second), second)
    raise AssertionError("unreachable")  # pragma: no cover


def legendre_vector_field(model: PhugoidModel, x: Any) -> np.ndarray:
    """The field of (4.45)-(4.46) pulled back to ``(x, z, xdot, zdot)`` through the Legendre transform.

    ``X_state = D(from_canonical)(y) X_canonical(y)`` with ``y = to_canonical(x)``; the Jacobian is exact
    (complex step). On ``E = 0`` this is the phugoid field, (4.47)-(4.48) substituted into (4.46).

    Parameters
    ----------
    model : PhugoidModel
    x : array_like, shape (..., 4)
        State with ``z >= 0``.

    Returns
    -------
    ndarray, shape (..., 4)
    """
    _model(model)
    x = _state(x)
    y = to_canonical(model, x)
    Y = legendre_field(model, y)
    J = _jac(lambda w: from_canonical(model, w), y)
    return np.einsum("...ij,...j->...i", J, Y)


# ---------------------------------------------------------------------------------- (e) pendulum analogue
@dataclass(frozen=True)
class PendulumAnalogue:
    """Simple pendulum (4.19)-(4.25) whose driven-base motion (4.55)-(4.58) reproduces the phugoid field.

    Pivot at the origin, ``x = l sin(theta)``, ``z = l cos(theta)`` (z down, theta from the downward vertical),
    bob velocity ``l thetadot (cos(theta), -sin(theta))``. The mapping from the phugoid model is
    ``l = m / K`` (m) and ``g_p = m0 g / m`` (m/s^2) (Notes item 9); the bob mass ``m`` only scales the tension.

    Attributes
    ----------
    length : float
        Rod length l (m).
    gravity : float
        Gravity g_p (m/s^2) of the equivalent pendulum.
    mass : float
        Bob mass (kg).
    """

    length: float
    gravity: float
    mass: float

    def __post_init__(self) -> None:
        for k, unit in (("length", "m"), ("gravity", "m/s^2"), ("mass", "kg")):
            object.__setattr__(self, k, checks.positive(k, getattr(self, k), unit=unit))

    @classmethod
    def from_model(cls, model: PhugoidModel) -> PendulumAnalogue:
        """The pendulum of §4.3.4 for a phugoid model: ``l = m/K``, ``g_p = m0 g/m``, bob mass ``m``."""
        _model(model)
        return cls(model.mass / model.K, model.m0 * model.g / model.mass, model.mass)

    def state(self, theta: Any, theta_dot: Any) -> np.ndarray:
        """Bob state ``(x, z, xdot, zdot)`` (m, m/s) at angle ``theta`` (rad) and rate ``theta_dot`` (rad/s)."""
        th, w = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(theta_dot, dtype=float))
        l = self.length
        return _stack(l * np.sin(th), l * np.cos(th), l * w * np.cos(th), -l * w * np.sin(th))

    def tension(self, x: Any) -> Any:
        """Rod tension (4.49), ``T = m V^2 / l + m g_p cos(theta)`` (N), ``cos(theta) = z / l``."""
        x = _state(x)
        return self.mass * ((x[..., 2] ** 2 + x[..., 3] ** 2) / self.length + self.gravity * x[..., 1] / self.length)

    def fixed_base_acceleration(self, x: Any) -> np.ndarray:
        """Bob acceleration, fixed pivot, (4.21)-(4.22) corrected (Notes item 7), shape (..., 2) (m/s^2).

        ``xddot = -(T/m) sin(theta)``, ``zddot = g_p - (T/m) cos(theta)`` with ``sin(theta) = x/l``,
        ``cos(theta) = z/l``; the same as (4.51)-(4.52) without their spurious factor m.
        """
        x = _state(x)
        t = self.tension(x) / self.mass
        return _stack(-t * x[..., 0] / self.length, self.gravity - t * x[..., 1] / self.length)

    def fixed_base_acceleration_velocity_form(self, x: Any) -> np.ndarray:
        """(4.53)-(4.54) corrected: ``((V/l) zdot - g_p x z/l^2, g_p - (V/l) xdot - g_p z^2/l^2)`` (m/s^2).

        Here ``V = sqrt(xdot^2 + zdot^2)``; this equals :meth:`fixed_base_acceleration` at pendulum states with
        ``thetadot > 0`` (where ``V cos(theta) = xdot``, ``V sin(theta) = -zdot`` hold with V the speed).
        """
        x = _state(x)
        V = np.sqrt(x[..., 2] ** 2 + x[..., 3] ** 2)
        l, g = self.length, self.gravity
        return _stack(V / l * x[..., 3] - g * x[..., 0] * x[..., 1] / l**2,
                      g - V / l * x[..., 2] - g * x[..., 1] ** 2 / l**2)

    def base_acceleration(self, x: Any) -> np.ndarray:
        """Prescribed pivot acceleration (4.55)-(4.56) corrected: ``-g_p (x z, z^2) / l^2`` (m/s^2)."""
        x = _state(x)
        f = -self.gravity * x[..., 1] / self.length**2
        return _stack(f * x[..., 0], f * x[..., 1])

    def relative_field(self, x: Any) -> np.ndarray:
        """Field of the bob relative to the driven pivot, ``(v, a_fixed - a_base)``, (4.57)-(4.58), shape (..., 4).

        Uses the tension form :meth:`fixed_base_acceleration` (the physical pendulum); equals the phugoid field
        at pendulum states with ``thetadot > 0``.
        """
        x = _state(x)
        return np.concatenate([x[..., 2:], self.fixed_base_acceleration(x) - self.base_acceleration(x)], axis=-1)

    def theta_ddot(self, theta: Any) -> Any:
        """Pendulum equation (4.23), ``thetaddot = -(g_p / l) sin(theta)`` (rad/s^2)."""
        return -self.gravity / self.length * np.sin(theta)

    def hamiltonian(self, theta: Any, p_theta: Any) -> Any:
        """Canonical pendulum Hamiltonian ``p^2 / (2 m l^2) - m g_p l cos(theta)`` (J); ``p = m l^2 thetadot``.

        Corrects (4.24)-(4.25) (Notes item 8).
        """
        return (np.asarray(p_theta) ** 2 / (2.0 * self.mass * self.length**2)
                - self.mass * self.gravity * self.length * np.cos(theta))

    def hamilton_field(self, theta: Any, p_theta: Any) -> tuple[np.ndarray, np.ndarray]:
        """Hamilton's equations of :meth:`hamiltonian` (exact derivatives): ``(thetadot, pdot_theta)``."""
        w = _stack(np.asarray(theta, dtype=float), np.asarray(p_theta, dtype=float))
        dH = _grad(lambda v: self.hamiltonian(v[..., 0], v[..., 1]), w)
        return dH[..., 1], -dH[..., 0]
