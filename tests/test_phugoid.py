"""Phugoid-mode model of chapter 4 (4.1)-(4.8) and its Hamiltonian/Lagrangian/pendulum formulations (§4.3).

Oracles: conservation of E and C (exact Lie derivatives and long simulations); each formulation's vector field
against the one right-hand side ``PhugoidModel.rhs``; the Euler-Lagrange equations against central differences of
the Lagrangian itself; Hamilton's equations against central differences of H; the pendulum against the kinematics
of (4.23); the cusp period against its closed form. Thesis typos are pinned by tests named after the equation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import beta

import glidectl as gc
from glidectl import GlidectlError, ModelError, load_vehicle
from glidectl.derivatives import jacobians
from glidectl.errors import InfeasibleGlideError
from glidectl.models import phugoid_hamiltonian as ph
from glidectl.models.phugoid import (
    C_STEADY,
    PhugoidClass,
    PhugoidModel,
    classify_C,
    initial_state_for_C,
    orbit_period,
)
from glidectl.sim import simulate

FIG41 = PhugoidModel(mass=14.0, m0=1.0, K=100.0, g=9.81)
FAST = settings(max_examples=40, deadline=None)
R = np.array([-1.0, 1.0, -1.0, 1.0])  # mirror x -> -x: the phugoid with K -> -K is R f(R x)


def _u(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


models = st.builds(PhugoidModel, mass=_u(0.5, 200.0), m0=_u(0.01, 20.0), K=_u(0.5, 500.0), g=_u(1.0, 20.0))


@st.composite
def model_and_states(draw: st.DrawFn, n: int = 64) -> tuple[PhugoidModel, np.ndarray]:
    """A random model and n random states with positions in [-10, 10] m and velocities in [-3, 3] xdot_e."""
    model = draw(models)
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    xe = model.xdot_e
    X = np.column_stack([rng.uniform(-10, 10, n), rng.uniform(-10, 10, n),
                         rng.uniform(-3, 3, n) * xe, rng.uniform(-3, 3, n) * xe])
    return model, X


def _scale(model: PhugoidModel, X: np.ndarray) -> np.ndarray:
    """Per-state size of the phugoid field: speed and acceleration magnitudes (SI), shape (n, 1)."""
    V = np.hypot(X[..., 2], X[..., 3])
    return (V + (model.K * V * V + model.m0 * model.g) / model.mass)[..., None]


def _assert_field(got: np.ndarray, ref: np.ndarray, model: PhugoidModel, X: np.ndarray, rel: float = 1e-10) -> None:
    err = np.abs(np.asarray(got) - ref) / _scale(model, X)
    assert np.max(err) < rel, f"max relative mismatch {np.max(err):.3e}"


# -------------------------------------------------------------------------------------------- the model
def test_model_layout_and_batch():
    m = FIG41
    assert m.state_names == ("x", "z", "xdot", "zdot") and m.input_names == ()
    rng = np.random.default_rng(1)
    X = rng.normal(size=(5, 3, 4))
    F = m.rhs(X)
    assert F.shape == (5, 3, 4)
    for idx in np.ndindex(5, 3):
        np.testing.assert_array_equal(F[idx], m.rhs(X[idx], np.zeros(0)))
    # hand-checked value of (4.3)-(4.4) at xdot = 3, zdot = 4 (V = 5)
    np.testing.assert_allclose(m.rhs([1.0, 2.0, 3.0, 4.0]), [3.0, 4.0, 100 * 5 * 4 / 14, (9.81 - 100 * 5 * 3) / 14],
                               rtol=1e-15)


def test_equilibrium_and_linear_period():
    m = FIG41
    assert m.xdot_e == pytest.approx(math.sqrt(9.81 / 100), rel=1e-15)
    xeq = initial_state_for_C(m, C_STEADY)
    np.testing.assert_allclose(xeq, [0.0, 0.0, m.xdot_e, 0.0], rtol=1e-15)
    f = m.rhs(xeq)
    assert f[0] == m.xdot_e and f[1] == 0.0
    np.testing.assert_allclose(f[2:], 0.0, atol=1e-15)  # a relative equilibrium: constant velocity
    assert float(m.lanchester_C(xeq)) == pytest.approx(2 / 3, abs=1e-15)
    assert classify_C(float(m.lanchester_C(xeq))) is PhugoidClass.STEADY_LEVEL
    A, _ = jacobians(m.rhs, xeq, np.zeros(0))
    lam = np.linalg.eigvals(A)
    omega = np.max(lam.imag)
    np.testing.assert_allclose(lam.real, 0.0, atol=1e-12)
    assert 2 * math.pi / omega == pytest.approx(m.linear_period, rel=1e-12)
    assert m.linear_period == pytest.approx(orbit_period(m, C_STEADY), rel=1e-10)


@given(ms=model_and_states())
@FAST
def test_E_and_C_have_zero_lie_derivative(ms):
    """dE/dt = grad E . f and dC/dt = grad C . f vanish identically (exact complex-step gradients)."""
    model, X = ms
    f = model.rhs(X)
    for fun, scale in ((model.energy, model.mass * model.xdot_e * _scale(model, X)[:, 0]),
                       (model.lanchester_C, _scale(model, X)[:, 0] / model.xdot_e)):
        grad = ph._grad(fun, X)
        rate = np.sum(grad * f, axis=1)
        assert np.max(np.abs(rate) / (scale * (1 + np.hypot(X[:, 2], X[:, 3]) / model.xdot_e) ** 2)) < 1e-12


@pytest.mark.parametrize("C", [C_STEADY, 0.4, 0.05, 0.0, -0.5, -1.5])
def test_E_and_C_conserved_along_simulations(C):
    m = FIG41
    sim = simulate(m, initial_state_for_C(m, C, z0=0.3), 6.0, t_eval=np.linspace(0, 6, 601), rtol=1e-11,
                   atol=1e-13)
    E, Cs = m.energy(sim.x), m.lanchester_C(sim.x)
    assert np.max(np.abs(E - E[0])) / (0.5 * m.mass * sim.x[0, 2] ** 2) < 1e-8
    assert np.max(np.abs(Cs - C)) < 1e-8


def test_H_canonical_is_a_multiple_of_C():
    """(4.6): H = -(m0 g / m) |xdot_e| C."""
    m = FIG41
    rng = np.random.default_rng(3)
    X = np.column_stack([np.zeros(50), np.zeros(50), rng.normal(size=(50, 2))])
    np.testing.assert_allclose(m.H_canonical(X[:, 2], X[:, 3]),
                               -m.m0 * m.g / m.mass * m.xdot_e * m.lanchester_C(X), rtol=1e-12, atol=1e-15)


# -------------------------------------------------------------------------------------- classes and C
def test_classify_C():
    assert classify_C(2 / 3) is PhugoidClass.STEADY_LEVEL
    assert classify_C(2 / 3 - 1e-12) is PhugoidClass.STEADY_LEVEL
    assert classify_C(0.4) is PhugoidClass.WAVY
    assert classify_C(0.0) is PhugoidClass.CUSP
    assert classify_C(-1e-10) is PhugoidClass.CUSP
    assert classify_C(-1e-10, tol=1e-11) is PhugoidClass.LOOPS
    assert classify_C(-0.5) is PhugoidClass.LOOPS
    assert classify_C(1e-3, tol=1e-2) is PhugoidClass.CUSP
    with pytest.raises(InfeasibleGlideError):
        classify_C(0.7)  # no state has C > 2/3
    for bad in (math.nan, math.inf):
        with pytest.raises(gc.ArgumentError):
            classify_C(bad)
    with pytest.raises(gc.ArgumentTypeError):
        classify_C("0.1")  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentError):
        classify_C(0.1, tol=-1.0)
    with pytest.raises(gc.ArgumentTypeError):
        classify_C(0.1, tol="small")  # type: ignore[arg-type]


@given(model=models, C=_u(-2.0, 2 / 3))
@FAST
def test_initial_state_for_C_round_trip(model, C):
    xe = model.xdot_e
    fast = initial_state_for_C(model, C, x0=1.0, z0=-2.0)
    slow = initial_state_for_C(model, C, branch="slow")
    assert fast[0] == 1.0 and fast[1] == -2.0 and fast[3] == 0.0 and slow[3] == 0.0
    for x in (fast, slow):
        assert float(model.lanchester_C(x)) == pytest.approx(C, abs=1e-12)
    assert fast[2] >= xe * (1 - 1e-7) and slow[2] <= xe * (1 + 1e-7)  # the two roots straddle xdot_e
    assert (slow[2] < 0) == (C < 0) or abs(C) < 1e-15  # loops: the slowest level point is flying backwards


def test_initial_state_branches_and_errors():
    m = FIG41
    xe = m.xdot_e
    assert initial_state_for_C(m, 0.0)[2] == pytest.approx(math.sqrt(3) * xe, rel=1e-14)
    assert initial_state_for_C(m, 0.0, branch="slow")[2] == 0.0  # the cusp: at rest
    assert initial_state_for_C(m, -2 / 3)[2] == pytest.approx(2 * xe, rel=1e-14)
    assert initial_state_for_C(m, 2 / 3 + 1e-13)[2] == pytest.approx(xe, rel=1e-6)
    fast = [initial_state_for_C(m, c)[2] for c in np.linspace(-3, 2 / 3, 50)]
    assert np.all(np.diff(fast) < 0)  # one smooth decreasing branch
    with pytest.raises(InfeasibleGlideError, match="2/3"):
        initial_state_for_C(m, 0.7)
    with pytest.raises(gc.ArgumentError):
        initial_state_for_C(m, math.nan)
    with pytest.raises(gc.ArgumentError, match="branch"):
        initial_state_for_C(m, 0.1, branch="middle")  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentError, match="x0"):
        initial_state_for_C(m, 0.1, x0=math.inf)
    with pytest.raises(gc.ArgumentTypeError, match="PhugoidModel"):
        initial_state_for_C(None, 0.1)  # type: ignore[arg-type]


def test_orbit_period_against_simulation_and_closed_form():
    m = FIG41
    cusp = 2 * math.sqrt(3) * beta(0.25, 0.5) / 4 * m.time_scale
    assert orbit_period(m, 0.0) == pytest.approx(cusp, rel=1e-10)  # finite: 'infinite time interval' is wrong
    assert orbit_period(m, 1e-9) == pytest.approx(cusp, rel=1e-6)
    assert orbit_period(m, -1e-9) == pytest.approx(cusp, rel=1e-6)
    for C in (0.4, 0.0, -0.5):
        T = orbit_period(m, C)
        # starting at the lowest point, the fast branch returns to it after one period: zdot = 0 again, same state
        sim = simulate(m, initial_state_for_C(m, C), T, t_eval=[0.0, 0.5 * T, T], rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(sim.x[-1, 2:], sim.x[0, 2:], atol=1e-8 * m.xdot_e)
        # half a period later it is at the top: the slow branch of the same orbit
        np.testing.assert_allclose(sim.x[1, 2:], initial_state_for_C(m, C, branch="slow")[2:], atol=1e-7 * m.xdot_e)
    with pytest.raises(InfeasibleGlideError):
        orbit_period(m, 0.8)


# ----------------------------------------------------------------------------------- (a) canonical 2-D
@given(ms=model_and_states())
@FAST
def test_canonical_2d_hamiltonian_generates_the_phugoid(ms):
    model, X = ms
    _assert_field(ph.canonical_vector_field(model, X), model.rhs(X), model, X)


# ------------------------------------------------------------------------- (b) symplectic form (4.31)
@given(ms=model_and_states())
@FAST
def test_noncanonical_symplectic_form_generates_the_phugoid(ms):
    model, X = ms
    _assert_field(ph.symplectic_field(model, X), model.rhs(X), model, X)


@given(ms=model_and_states(n=16))
@FAST
def test_4_31_printed_matrix_reverses_the_lift(ms):
    """Typo: the matrix printed under (4.31) generates the mirror image (K -> -K), not the phugoid."""
    model, X = ms
    printed = ph.symplectic_field(model, X, printed=True)
    _assert_field(printed, R * model.rhs(R * X), model, X)
    assert np.max(np.abs(printed - model.rhs(X)) / _scale(model, X)) > 1e-3


def test_4_31_matrix_from_the_2_form_and_from_4_13():
    m = FIG41
    x = np.array([0.3, -0.2, 0.5, -0.7])
    V = math.hypot(0.5, -0.7)
    om = ph.omega_B(m, x)
    KV, M = m.K * V, m.mass
    np.testing.assert_allclose(om, [[0, -KV, M, 0], [KV, 0, 0, M], [-M, 0, 0, 0], [0, -M, 0, 0]], rtol=1e-15)
    np.testing.assert_allclose(ph.omega_B(m, x, printed=True),
                               [[0, KV, M, 0], [-KV, 0, 0, M], [-M, 0, 0, 0], [0, -M, 0, 0]], rtol=1e-15)
    assert np.linalg.det(om) == pytest.approx(M**4, rel=1e-12)  # nondegenerate
    q = 2.5  # the restriction of the charged particle's (4.13) with B_y = -(K/q) V is the corrected matrix
    full = ph.charged_particle_omega(M, q, np.array([0.0, -m.K / q * V, 0.0]))
    np.testing.assert_allclose(full[np.ix_([0, 2, 3, 5], [0, 2, 3, 5])], om, rtol=1e-15)
    # (4.34) corrected: X^T Omega = (KV X2 - m X3, -KV X1 - m X4, m X1, m X2); and dH of (4.35)
    X = np.array([1.0, 2.0, 3.0, 4.0])
    np.testing.assert_allclose(ph.interior_product(om, X), [KV * 2 - M * 3, -KV * 1 - M * 4, M * 1, M * 2])
    np.testing.assert_allclose(ph._grad(m.energy, x), [0, -m.m0 * m.g, M * 0.5, M * -0.7], rtol=1e-14)


def test_4_10_charged_particle_is_v_cross_b_plus_gravity():
    """Typo: (4.13)-(4.15) generate dV/dt = (q/m) V x B + g e_z, not (q/m) B x V (and gravity is missing)."""
    rng = np.random.default_rng(7)
    S = rng.normal(size=(40, 6))
    Bc = rng.normal(size=3)
    mass, q, g = 3.0, -1.7, 9.81
    F = ph.charged_particle_field(S, mass, q, lambda s: np.broadcast_to(Bc, (*s.shape[:-1], 3)), g)
    lorentz = q / mass * np.cross(S[:, 3:], Bc) + np.array([0.0, 0.0, g])
    np.testing.assert_allclose(F[:, :3], S[:, 3:], rtol=1e-14)
    np.testing.assert_allclose(F[:, 3:], lorentz, rtol=1e-12, atol=1e-13)
    assert np.max(np.abs(F[:, 3:] - q / mass * np.cross(Bc, S[:, 3:]))) > 1.0


@given(ms=model_and_states(n=32))
@FAST
def test_charged_particle_with_speed_dependent_field_is_the_phugoid(ms):
    """§4.3.1: B_y = -(K/q) V, planar motion, m = m1 + mbar, weight m0 g (g -> m0 g/m in (4.14))."""
    model, X = ms
    q = 0.8

    def B(s: np.ndarray) -> np.ndarray:
        V = np.sqrt(s[..., 3] ** 2 + s[..., 4] ** 2 + s[..., 5] ** 2)
        return np.stack([0 * V, -model.K / q * V, 0 * V], axis=-1)

    n = X.shape[0]
    S = np.column_stack([X[:, 0], np.zeros(n), X[:, 1], X[:, 2], np.zeros(n), X[:, 3]])
    F = ph.charged_particle_field(S, model.mass, q, B, model.m0 * model.g / model.mass)
    np.testing.assert_allclose(F[:, [1, 4]], 0.0, atol=1e-12 * np.max(_scale(model, X)))
    _assert_field(F[:, [0, 2, 3, 5]], model.rhs(X), model, X)


# ------------------------------------------------------------------------ (c) Lagrangian (4.37)-(4.43)
def _el_by_finite_differences(model: PhugoidModel, x: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """qddot from (4.36) with every derivative of L = lagrangian(...) taken by central differences."""
    def L(w: np.ndarray) -> float:
        return float(ph.lagrangian(model, w[:2], w[2:]))

    def d(w: np.ndarray, i: int) -> float:
        e = np.zeros(4)
        e[i] = h
        return (L(w + e) - L(w - e)) / (2 * h)

    def dd(w: np.ndarray, i: int, j: int) -> float:
        e = np.zeros(4)
        e[j] = h
        return (d(w + e, i) - d(w - e, i)) / (2 * h)

    Mq = np.array([[dd(x, 2 + i, 2 + j) for j in range(2)] for i in range(2)])       # d2L/dqdot2
    Cq = np.array([[dd(x, 2 + i, j) for j in range(2)] for i in range(2)])           # d2L/dqdot dq
    rhs = np.array([d(x, 0), d(x, 1)]) - Cq @ x[2:]
    return np.concatenate([x[2:], np.linalg.solve(Mq, rhs)])


def test_euler_lagrange_equations_match_finite_differences_of_L():
    m = FIG41
    rng = np.random.default_rng(11)
    for _ in range(8):
        x = np.array([rng.uniform(-1, 1), rng.uniform(0.05, 0.3), rng.uniform(-1, 1), rng.uniform(-1, 1)])
        np.testing.assert_allclose(ph.euler_lagrange_field(m, x), _el_by_finite_differences(m, x), rtol=1e-5,
                                   atol=1e-5)
    # (4.41)-(4.42) as printed
    x = np.array([0.0, 0.2, 0.4, -0.3])
    s = math.sqrt(2 * m.m0 * m.g * 0.2 / m.mass)
    np.testing.assert_allclose(ph.euler_lagrange_field(m, x)[2:],
                               [m.K * s * -0.3 / m.mass, (m.m0 * m.g - m.K * s * 0.4) / m.mass], rtol=1e-14)


@given(ms=model_and_states())
@FAST
def test_euler_lagrange_on_zero_energy_is_the_phugoid(ms):
    model, X = ms
    Z = ph.zero_energy_shift(model, X)
    np.testing.assert_allclose(model.energy(Z), 0.0, atol=1e-12 * model.mass * np.max(_scale(model, X)) ** 2)
    np.testing.assert_allclose(Z[:, 1], model.mass * np.hypot(X[:, 2], X[:, 3]) ** 2 / (2 * model.m0 * model.g),
                               rtol=1e-12, atol=1e-14 * np.max(np.abs(X[:, 1])))  # z + E/(m0 g) cancels
    _assert_field(ph.euler_lagrange_field(model, Z), model.rhs(Z), model, X)
    # off the zero-energy set the lift is K sqrt(2 m0 g z/m), not K V
    off = Z.copy()
    off[:, 1] = 2.0 * Z[:, 1] + 0.1
    assert np.max(np.abs(ph.euler_lagrange_field(model, off) - model.rhs(off)) / _scale(model, X)) > 1e-6


class _EulerLagrangeSystem:
    """Adapter so that ``simulate`` can integrate the field of (4.41)-(4.42) (it is not a second phugoid rhs)."""

    state_names = ("x", "z", "xdot", "zdot")
    input_names = ()

    def __init__(self, model: PhugoidModel) -> None:
        self.model = model

    def rhs(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return ph.euler_lagrange_field(self.model, x)


def test_zero_energy_shift_maps_phugoid_trajectories_to_lagrangian_ones():
    """§4.3.2 (as corrected): shifting a phugoid trajectory of any energy gives an E = 0 Lagrangian trajectory;
    shifting a Lagrangian trajectory with E != 0 does not give a Lagrangian trajectory."""
    m = FIG41
    t = np.linspace(0, 3, 31)
    x0 = initial_state_for_C(m, 0.3, z0=-0.4)  # E != 0
    assert abs(m.energy(x0)) > 0.1
    phug = simulate(m, x0, 3.0, t_eval=t, rtol=1e-12, atol=1e-14)
    lag = simulate(_EulerLagrangeSystem(m), ph.zero_energy_shift(m, x0), 3.0, t_eval=t, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(lag.x, ph.zero_energy_shift(m, phug.x), atol=1e-8)
    np.testing.assert_allclose(ph.zero_energy_shift(m, phug.x)[:, 0], phug.x[:, 0])
    # a Lagrangian trajectory with E = -0.5 J (deeper than the zero-energy set) ...
    y0 = ph.zero_energy_shift(m, x0) + np.array([0.0, 0.5 / (m.m0 * m.g), 0.0, 0.0])
    lagE = simulate(_EulerLagrangeSystem(m), y0, 3.0, t_eval=t, rtol=1e-12, atol=1e-14)
    assert np.ptp(m.energy(lagE.x)) < 1e-9  # (4.43): E is conserved by the Lagrangian system
    shifted = simulate(_EulerLagrangeSystem(m), ph.zero_energy_shift(m, y0), 3.0, t_eval=t, rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(ph.zero_energy_shift(m, lagE.x) - shifted.x)) > 1e-3  # ... is not mapped onto one


# -------------------------------------------------------------------------- (d) Legendre (4.44)-(4.48)
@given(ms=model_and_states())
@FAST
def test_legendre_hamiltonian_on_zero_energy_is_the_phugoid(ms):
    model, X = ms
    Z = ph.zero_energy_shift(model, X)
    _assert_field(ph.legendre_vector_field(model, Z), model.rhs(Z), model, X, rel=1e-9)
    # the same system as (c) everywhere on z >= 0
    off = Z.copy()
    off[:, 1] = 3.0 * Z[:, 1] + 0.2
    _assert_field(ph.legendre_vector_field(model, off), ph.euler_lagrange_field(model, off), model, X, rel=1e-9)


def test_legendre_transform_and_hamilton_equations():
    m = FIG41
    rng = np.random.default_rng(5)
    X = np.column_stack([rng.normal(size=20), rng.uniform(0, 0.5, 20), rng.normal(size=(20, 2))])
    y = ph.to_canonical(m, X)
    np.testing.assert_allclose(ph.from_canonical(m, y), X, rtol=1e-13, atol=1e-15)
    # (4.44): H(q, p) equals the energy of the velocity state
    np.testing.assert_allclose(ph.legendre_hamiltonian(m, y), m.energy(X), rtol=1e-12, atol=1e-12)
    Y = ph.legendre_field(m, y)
    np.testing.assert_allclose(Y[:, :2], X[:, 2:], rtol=1e-12, atol=1e-14)  # (4.45)
    h = 1e-6  # Hamilton's equations against central differences of H
    for i, yi in enumerate(y[:5]):
        g = np.array([(ph.legendre_hamiltonian(m, yi + h * e) - ph.legendre_hamiltonian(m, yi - h * e)) / (2 * h)
                      for e in np.eye(4)])
        np.testing.assert_allclose(Y[i], [g[2], g[3], -g[0], -g[1]], rtol=1e-6, atol=1e-6)
    # (4.47): p1dot = m xddot - K sqrt(2 m0 g z / m) zdot along the field
    a = ph.euler_lagrange_field(m, X)
    s = np.sqrt(2 * m.m0 * m.g * X[:, 1] / m.mass)
    np.testing.assert_allclose(Y[:, 2], m.mass * a[:, 2] - m.K * s * X[:, 3], rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(Y[:, 3], m.mass * a[:, 3], rtol=1e-10, atol=1e-10)  # (4.48)


def test_4_46_printed_pdot_is_wrong():
    """Typo: (4.46) line 1 has the wrong sign and lacks K; line 2 lacks K/m."""
    m = FIG41
    X = ph.zero_energy_shift(m, np.array([[0.0, 0.0, 0.4, 0.3], [1.0, 0.0, -0.2, 0.5]]))
    y = ph.to_canonical(m, X)
    exact = ph.legendre_field(m, y)[:, 2:]
    r = ph.pdot_as_printed(m, y, 1) - np.array([0.0, m.m0 * m.g])
    np.testing.assert_allclose(-(m.K / m.mass) * r * m.mass, exact - np.array([0.0, m.m0 * m.g]), rtol=1e-12)
    r2 = ph.pdot_as_printed(m, y, 2) - np.array([0.0, m.m0 * m.g])
    np.testing.assert_allclose(m.K / m.mass * r2, exact - np.array([0.0, m.m0 * m.g]), rtol=1e-12)
    with pytest.raises(gc.ArgumentError, match="line"):
        ph.pdot_as_printed(m, y, 3)


# ----------------------------------------------------------------------------- (e) pendulum (4.49)-(4.58)
@given(model=models, th=_u(-math.pi, math.pi), w=_u(1e-3, 50.0))
@FAST
def test_driven_pendulum_is_the_phugoid_field(model, th, w):
    pend = ph.PendulumAnalogue.from_model(model)
    assert pend.length == pytest.approx(model.mass / model.K) and pend.gravity == pytest.approx(
        model.m0 * model.g / model.mass)
    x = pend.state(th, w)
    l = pend.length
    # the tension form (4.21)-(4.22) corrected is the pendulum (4.23): a = l thdd t - l thd^2 n
    thdd = pend.theta_ddot(th)
    kin = np.array([l * thdd * math.cos(th) - l * w * w * math.sin(th),
                    -l * thdd * math.sin(th) - l * w * w * math.cos(th)])
    size = l * w * w + pend.gravity
    np.testing.assert_allclose(pend.fixed_base_acceleration(x), kin, atol=1e-12 * size)
    np.testing.assert_allclose(pend.fixed_base_acceleration_velocity_form(x), kin, atol=1e-12 * size)  # (4.53)
    f = model.rhs(x)
    np.testing.assert_allclose(pend.relative_field(x), f, atol=1e-12 * (size + l * w))  # (4.57)-(4.58)
    # thetadot < 0: the mirror image (lift reversed)
    xn = pend.state(th, -w)
    np.testing.assert_allclose(pend.relative_field(xn), R * model.rhs(R * xn), atol=1e-12 * (size + l * w))
    # an identity of vector fields only: the phugoid flow leaves the circle, d2(|r|^2/2)/dt^2 = g_p z
    assert float(np.dot(x[2:], x[2:]) + np.dot(x[:2], f[2:])) == pytest.approx(pend.gravity * x[1], abs=1e-12 * size
                                                                               * l)


def test_4_24_pendulum_hamiltonian_corrected():
    pend = ph.PendulumAnalogue(length=0.14, gravity=0.7, mass=14.0)
    th = np.linspace(-3, 3, 13)
    thd = np.linspace(-2, 2, 13)
    p = pend.mass * pend.length**2 * thd
    a, b = pend.hamilton_field(th, p)
    np.testing.assert_allclose(a, thd, rtol=1e-14)
    np.testing.assert_allclose(b / (pend.mass * pend.length**2), pend.theta_ddot(th), rtol=1e-13)
    # as printed: p = m l thd, H = p^2/(2m) - m g l cos(theta): dH/dp = l thd, not thd (not canonical)
    m, l, g = pend.mass, pend.length, pend.gravity
    w = np.column_stack([th, m * l * thd])
    dH = ph._grad(lambda v: v[..., 1] ** 2 / (2 * m) - m * g * l * np.cos(v[..., 0]), w)
    np.testing.assert_allclose(dH[:, 1], l * thd, rtol=1e-14)
    assert np.max(np.abs(dH[:, 1] - thd)) > 0.5


# ---------------------------------------------------------------------------------------- bad inputs
@pytest.mark.parametrize("kw", [{"mass": 0.0}, {"mass": -1.0}, {"mass": math.nan}, {"mass": math.inf},
                                {"m0": 0.0}, {"m0": -0.5}, {"K": 0.0}, {"K": -3.0}, {"g": 0.0},
                                {"mass": "14"}, {"K": True}])
def test_bad_parameters_raise(kw):
    args = {"mass": 14.0, "m0": 1.0, "K": 100.0, "g": 9.81, **kw}
    value = next(iter(kw.values()))
    err = gc.ArgumentTypeError if isinstance(value, str | bool) else gc.ArgumentError
    with pytest.raises(err) as exc:
        PhugoidModel(**args)
    assert isinstance(exc.value, GlidectlError)
    assert isinstance(exc.value, TypeError if err is gc.ArgumentTypeError else ValueError)
    assert next(iter(kw)) in str(exc.value)


def test_from_vehicle():
    sphere = load_vehicle("sphere_ch5")
    m = PhugoidModel.from_vehicle(sphere, alpha=0.02)
    assert (m.mass, m.m0, m.K, m.g) == (28.0, 0.7, pytest.approx(1.5), sphere.g)
    assert m.vehicle is sphere
    assert PhugoidModel.from_vehicle(sphere, 0.02, m0=0.3).m0 == 0.3
    ev = PhugoidModel.from_vehicle(load_vehicle("elevator_ch6"), 0.05)  # 'added' mass model: m1 = m + m0
    assert ev.mass == pytest.approx(28.0 + 2.657)
    with pytest.raises(ModelError, match="m1"):
        PhugoidModel.from_vehicle(load_vehicle("rogue"), 0.05, m0=0.5)  # m1 != m3: assumption 3
    with pytest.raises(ModelError, match="positive"):
        PhugoidModel.from_vehicle(sphere, -0.01)  # K <= 0
    with pytest.raises(ModelError):
        PhugoidModel.from_vehicle(load_vehicle("dc8_ctol"), 0.05)
    with pytest.raises(gc.ArgumentError):
        PhugoidModel.from_vehicle(sphere, math.nan)
    with pytest.raises(gc.ArgumentTypeError, match="load_vehicle"):
        PhugoidModel.from_vehicle("sphere_ch5", 0.02)  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentError, match="m0"):
        PhugoidModel.from_vehicle(sphere, 0.02, m0=-0.3)


def test_formulation_domain_errors():
    m = FIG41
    with pytest.raises(ModelError, match="z >= 0"):
        ph.euler_lagrange_field(m, np.array([0.0, -0.1, 0.2, 0.0]))
    with pytest.raises(gc.ArgumentError, match="last dimension 4"):
        ph.symplectic_field(m, np.zeros(3))
    with pytest.raises(gc.ArgumentTypeError, match="PhugoidModel"):
        ph.symplectic_field(None, np.zeros(4))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 4"):
        m.rhs(np.zeros(3))
    with pytest.raises(gc.ArgumentTypeError):
        m.rhs(None)


def test_orbit_period_inputs():
    m = FIG41
    with pytest.raises(gc.ArgumentError):
        orbit_period(m, math.nan)
    with pytest.raises(gc.ArgumentTypeError):
        orbit_period(m, "0.1")  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentTypeError, match="PhugoidModel"):
        orbit_period("model", 0.1)  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentError, match="tol"):
        orbit_period(m, 0.1, tol=-1e-3)
    with pytest.raises(gc.ArgumentTypeError):
        PhugoidModel(14.0, 1.0, 100.0, vehicle="sphere_ch5")  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentError):
        ph.PendulumAnalogue(length=0.0, gravity=1.0, mass=1.0)
