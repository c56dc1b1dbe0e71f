"""Three-dimensional glider, §2.2 and §8.2.1: the force form (2.1)-(2.8) against the acceleration form
(8.23)-(8.25), the longitudinal-plane restriction against (2.15)-(2.25), the reading of (2.5), SO(3) kinematics
(quaternions, YPR (8.26)-(8.28)), the 3D hydrodynamics (2.9)-(2.14) and the §8.2.2 simulation (Fig 8.2-8.4)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl import LongitudinalGlider, ModelError, load_vehicle
from glidectl.derivatives import central_difference_jacobians, jacobians
from glidectl.hydro import loads_3d, longitudinal_loads
from glidectl.models.glider3d import (
    FIXED_STATES,
    FORCE3D_INPUTS,
    FORCE3D_STATES,
    FixedMassGlider3D,
    Glider3D,
    R_to_ypr,
    hat,
    quat_to_R,
    ypr_to_quat,
    ypr_to_R,
)
from glidectl.models.longitudinal import FORCE_STATES
from glidectl.sim import simulate
from glidectl.trim.helix import helix_trim, reduced_rhs, zeta_of

SLOCUM = load_vehicle("slocum_ch8")
# damping K_q V^2 only (no chapter-8 K_Omega1_2 Omega2): the pitch moment is exactly (2.13)
SLOCUM_KQ = load_vehicle("slocum_ch8", K_Omega1_2=0.0, K_q=-3.0)
# every term of (2.9)-(2.14) and of the chapter-8 damping switched on; the linear damping of each axis in one form
# only (a file giving both is refused, docs/conventions.md): V^2-scaled for roll and pitch, chapter 8 for yaw
SLOCUM_FULL = load_vehicle("slocum_ch8", K_q=-3.0, K_Omega1_2=0.0, K_q1=-1.0, K_Omega1_1=0.0, K_q3=0.0, K_L0=5.0,
                           K_M0=0.3, K_Omega2_1=-4.0, K_Omega2_2=-7.0, K_Omega2_3=-5.0)

F3 = {s: i for i, s in enumerate(FORCE3D_STATES)}
FL = {s: i for i, s in enumerate(FORCE_STATES)}
K = np.array([0.0, 0.0, 1.0])

FAST = settings(max_examples=40, deadline=None)

# §8.2.2 nominal control parameters and initial condition (Fig 8.2-8.4)
R_P = (0.02, 0.02, 0.04)  # m
M0 = 0.25  # kg
PSI0, THETA0, PHI0 = 0.0, np.radians(-26.654), np.radians(14.419)
V0 = np.array([0.802, 0.014, 0.025])  # m/s
OMEGA0 = np.array([0.0046, 0.0025, 0.0077])  # rad/s


def _u(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def _vec(lo: float, hi: float) -> st.SearchStrategy[np.ndarray]:
    return st.tuples(_u(lo, hi), _u(lo, hi), _u(lo, hi)).map(np.array)


def _away_from_zero(lo: float, hi: float) -> st.SearchStrategy[float]:
    """|x| in [lo, hi], either sign (keeps central differences away from the kink of |Omega_i|)."""
    return st.tuples(_u(lo, hi), st.booleans()).map(lambda t: t[0] if t[1] else -t[0])


@st.composite
def unit_quaternions(draw: st.DrawFn) -> np.ndarray:
    q = np.array([draw(_u(-1, 1)) for _ in range(4)])
    if np.linalg.norm(q) < 0.1:
        q = q + np.array([1.0, 0.0, 0.0, 0.0])
    return q / np.linalg.norm(q)


@st.composite
def velocities(draw: st.DrawFn) -> np.ndarray:
    """Forward flight v1 > 0.05 m/s with moderate incidence and sideslip."""
    return np.array([draw(_u(0.05, 1.5)), draw(_u(-0.3, 0.3)), draw(_u(-0.4, 0.4))])


@st.composite
def fixed_mass_cases(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple, float]:
    """(b, q, v, Omega, r_P, m0) with the moving mass anywhere within 10 cm of the CB."""
    b = draw(_vec(-50, 50))
    q = draw(unit_quaternions())
    v = draw(velocities())
    Om = draw(_vec(-0.5, 0.5))
    r = tuple(float(c) for c in draw(_vec(-0.1, 0.1)))
    m0 = draw(_u(-1.0, 1.0))
    return b, q, v, Om, r, m0


# ------------------------------------------------------------------------------------------- helpers


def _force_state(b: np.ndarray, q: np.ndarray, v: np.ndarray, Om: np.ndarray, r: tuple, m0: float,
                 mbar: float) -> np.ndarray:
    """Force-form state with r_P held (r_P' = 0): P_P = mbar (v + Omega x r_P), (2.6) definition of P_P."""
    P = mbar * (v + np.cross(Om, r))
    return np.r_[b, q, v, Om, r, P, m0]


def _holding_input(model: Glider3D, x: np.ndarray) -> np.ndarray:
    """The ubar that keeps rddot_P = 0: solve ubar = mbar (v' + Omega' x r_P), linear in ubar, for ubar.

    The right-hand side is affine in u; its exact u-Jacobian (complex step) gives the linear system."""
    mbar = model.vehicle.mbar
    r = x[13:16]
    u0 = np.zeros(4)
    f0 = model.rhs(x, u0)
    _, B = jacobians(model.rhs, x, u0)
    rh = hat(r)
    # ubar - mbar (v'(ubar) - r^ Omega'(ubar)) = 0 with v' = f0_v + B_v ubar, Omega' = f0_O + B_O ubar
    A = np.eye(3) - mbar * (B[7:10, :3] - rh @ B[10:13, :3])
    rhs = mbar * (f0[7:10] - rh @ f0[10:13])
    return np.r_[np.linalg.solve(A, rhs), 0.0]


def _literal_25_omega_dot(model: Glider3D, x: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Omega' with (2.5) read literally, Tbar = (J Omega + r_P^ P_P) x Omega + ..., computed by swapping only that
    term of the model's Tbar (J Omega x Omega + r_P x (P_P x Omega)) by hand."""
    veh = model.vehicle
    J = np.array([veh.J1, veh.J2, veh.J3])
    Om, r, P = x[10:13], x[13:16], x[16:19]
    literal = np.cross(J * Om + np.cross(r, P), Om)
    implemented = np.cross(J * Om, Om) + np.cross(r, np.cross(P, Om))
    return model.rhs(x, u)[10:13] + (literal - implemented) / J


def _assert_close(a: np.ndarray, b: np.ndarray, rel: float = 1e-12) -> None:
    scale = 1.0 + float(np.max(np.abs(b)))
    np.testing.assert_allclose(a, b, rtol=0, atol=rel * scale)


# ------------------------------------------------------------------ 1. force form == acceleration form


@FAST
@given(fixed_mass_cases())
def test_force_form_with_held_mass_equals_acceleration_form(case):
    """(2.1)-(2.8) with r_P held fixed by ubar has the (b', q', v', Omega') of (8.23)-(8.25)."""
    b, q, v, Om, r, m0 = case
    veh = SLOCUM
    force, fixed = Glider3D(veh), FixedMassGlider3D(veh, r, m0)
    x = _force_state(b, q, v, Om, r, m0, veh.mbar)
    u = _holding_input(force, x)
    d = force.rhs(x, u)
    e = fixed.rhs(np.r_[b, q, v, Om])
    _assert_close(d[0:3], e[0:3])    # b' = R v (2.1)
    _assert_close(d[3:7], e[3:7])    # quaternion form of R' = R Omega^ (2.2)
    _assert_close(d[7:10], e[7:10])  # v'
    _assert_close(d[10:13], e[10:13])  # Omega'
    # the held mass really is held: r_P' = 0, rddot_P = ubar/mbar - v' - Omega' x r_P = 0, m0' = 0
    _assert_close(d[13:16], np.zeros(3))
    _assert_close(u[:3] / veh.mbar - d[7:10] - np.cross(d[10:13], r), np.zeros(3))
    np.testing.assert_array_equal(d[16:19], u[:3])  # P_P' = ubar (2.6)
    assert d[19] == 0.0


def test_force_form_with_literal_25_disagrees_with_acceleration_form():
    """Pins the reading of (2.5): with the literal (J Omega + r_P^ P_P) x Omega the held-mass force form no longer
    reproduces (8.23)-(8.25); the difference is J^-1 P_P x (Omega x r_P) (non-zero here)."""
    veh = SLOCUM
    r = (0.05, -0.03, 0.04)
    b, q, v, Om = np.zeros(3), ypr_to_quat(0.3, -0.4, 0.2), np.array([0.7, 0.05, 0.04]), np.array([0.2, -0.3, 0.25])
    force, fixed = Glider3D(veh), FixedMassGlider3D(veh, r, M0)
    x = _force_state(b, q, v, Om, r, M0, veh.mbar)
    u = _holding_input(force, x)
    _assert_close(force.rhs(x, u)[10:13], fixed.rhs(np.r_[b, q, v, Om])[10:13])
    lit = _literal_25_omega_dot(force, x, u)
    J = np.array([veh.J1, veh.J2, veh.J3])
    P = x[16:19]
    np.testing.assert_allclose(lit - force.rhs(x, u)[10:13], np.cross(P, np.cross(Om, r)) / J, rtol=1e-12)
    assert np.max(np.abs(lit - fixed.rhs(np.r_[b, q, v, Om])[10:13])) > 1e-3


def test_fixed_mass_generalized_mass_is_823_inverse():
    """The 6x6 matrix of (8.23) (with M + mbar I, -mbar r^; mbar r^, J - mbar r^ r^) is what the model inverts."""
    r = np.array(R_P)
    fixed = FixedMassGlider3D(SLOCUM, R_P, M0)
    M = np.diag([SLOCUM.mass(i, M0) for i in (1, 2, 3)])
    J = np.diag([SLOCUM.J1, SLOCUM.J2, SLOCUM.J3])
    mb = SLOCUM.mbar
    rh = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])  # the ^ map of §2.2.1, typed out
    big = np.block([[M + mb * np.eye(3), -mb * rh], [mb * rh, J - mb * rh @ rh]])
    np.testing.assert_allclose(fixed.generalized_mass @ big, np.eye(6), atol=1e-13)
    # chapter-8 masses (docs/conventions.md): m_i = m + m0 - mbar + m_fi
    np.testing.assert_allclose(np.diag(M), [50 + 0.25 - 9 + 5, 50 + 0.25 - 9 + 60, 50 + 0.25 - 9 + 70])


# ------------------------------------------------------------------ 2. restriction to the longitudinal plane


@st.composite
def longitudinal_cases(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    x = np.array([
        draw(_u(-10, 10)), draw(_u(-10, 10)),      # x, z
        draw(_u(-1.2, 1.2)), draw(_away_from_zero(0.01, 0.8)),  # theta, Omega2
        draw(_u(0.05, 1.5)), draw(_u(-0.4, 0.4)),  # v1, v3
        draw(_u(-0.1, 0.1)), draw(_u(-0.1, 0.1)),  # r_P1, r_P3
        draw(_u(-3.0, 3.0)), draw(_u(-1.0, 1.0)),  # P_P1, P_P3
        draw(_u(-1.0, 1.0)),                       # m0
    ])
    u = np.array([draw(_u(-5, 5)), draw(_u(-5, 5)), draw(_u(-0.01, 0.01))])
    return x, u


def _embed(xl: np.ndarray, ul: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Longitudinal state/input -> 3D (v2 = Omega1 = Omega3 = r_P2 = P_P2 = 0, roll = yaw = 0, u2 = 0)."""
    L = {s: xl[i] for s, i in FL.items()}
    x3 = np.r_[L["x"], 0.0, L["z"], ypr_to_quat(0.0, L["theta"], 0.0), L["v1"], 0.0, L["v3"], 0.0, L["Omega2"], 0.0,
               L["r_P1"], 0.0, L["r_P3"], L["P_P1"], 0.0, L["P_P3"], L["m0"]]
    return x3, np.r_[ul[0], 0.0, ul[1], ul[2]]


def _project(x3: np.ndarray, d3: np.ndarray) -> np.ndarray:
    """3D derivative -> the 11 longitudinal derivatives; theta' from q' for q = (cos th/2, 0, sin th/2, 0)."""
    q, dq = x3[3:7], d3[3:7]
    theta_dot = 2.0 * (q[0] * dq[2] - q[2] * dq[0])
    n = F3
    return np.array([d3[n["x"]], d3[n["z"]], theta_dot, d3[n["Omega2"]], d3[n["v1"]], d3[n["v3"]], d3[n["r_P1"]],
                     d3[n["r_P3"]], d3[n["P_P1"]], d3[n["P_P3"]], d3[n["m0"]]])


OUT_OF_PLANE = [F3[s] for s in ("y", "q1", "q3", "v2", "Omega1", "Omega3", "r_P2", "P_P2")]


@FAST
@given(longitudinal_cases())
def test_plane_restriction_equals_longitudinal_model(case):
    """Glider3D restricted to the plane equals LongitudinalGlider (2.15)-(2.25) in all 11 derivatives, and the plane
    is invariant (§2.3: every out-of-plane derivative vanishes)."""
    xl, ul = case
    x3, u3 = _embed(xl, ul)
    d3 = Glider3D(SLOCUM_KQ).rhs(x3, u3)
    dl = LongitudinalGlider(SLOCUM_KQ).rhs(xl, ul)
    _assert_close(_project(x3, d3), dl)
    np.testing.assert_allclose(d3[OUT_OF_PLANE], 0.0, atol=1e-14)


@FAST
@given(longitudinal_cases(), st.sampled_from(["seaglider", "gliderflight"]))
def test_plane_restriction_equals_longitudinal_model_on_other_laws(case, law):
    """The same restriction with the Seaglider and gliderflight lift and drag laws (gc.law_start): both models read
    lift and drag through the one hydro.lift_drag, so the plane stays invariant and the two models agree."""
    xl, ul = case
    x3, u3 = _embed(xl, ul)
    veh = gc.law_start(SLOCUM_KQ, law)
    d3 = Glider3D(veh).rhs(x3, u3)
    dl = LongitudinalGlider(veh).rhs(xl, ul)
    _assert_close(_project(x3, d3), dl)
    np.testing.assert_allclose(d3[OUT_OF_PLANE], 0.0, atol=1e-14)


@FAST
@given(longitudinal_cases())
def test_plane_restriction_fails_with_literal_25(case):
    """With the literal (J Omega + r_P^ P_P) x Omega of (2.5), Omega2' misses -Omega2 (r_P1 P_P1 + r_P3 P_P3)/J2 of
    (2.20): by hand, (r_P x P_P) x Omega = 0 in the plane while r_P x (P_P x Omega) = (0, -Omega2 (r_P1 P_P1 + r_P3
    P_P3), 0)."""
    xl, ul = case
    L = {s: xl[i] for s, i in FL.items()}
    x3, u3 = _embed(xl, ul)
    model = Glider3D(SLOCUM_KQ)
    lit = _literal_25_omega_dot(model, x3, u3)
    dl = LongitudinalGlider(SLOCUM_KQ).rhs(xl, ul)
    hand = L["Omega2"] * (L["r_P1"] * L["P_P1"] + L["r_P3"] * L["P_P3"]) / SLOCUM_KQ.J2
    np.testing.assert_allclose(lit[1] - dl[FL["Omega2"]], hand, rtol=1e-9, atol=1e-13)
    if abs(hand) > 1e-6:
        assert abs(lit[1] - dl[FL["Omega2"]]) > 1e-7


def test_plane_restriction_keeps_ch8_damping():
    """One damping convention: with Table 8.1's K_Omega1_2 = -60 (no V^2) both the 3D and the longitudinal model
    carry K_Omega1_2 Omega2, so they agree; switching it off changes Omega2' by exactly K_Omega1_2 Omega2 / J2."""
    xl = np.array([0.0, 0.0, -0.4, 0.05, 0.7, 0.03, 0.02, 0.04, 6.3, 0.2, 0.25])
    ul = np.zeros(3)
    x3, u3 = _embed(xl, ul)
    d3 = Glider3D(SLOCUM).rhs(x3, u3)
    _assert_close(_project(x3, d3), LongitudinalGlider(SLOCUM).rhs(xl, ul))
    veh0 = load_vehicle("slocum_ch8", K_Omega1_2=0.0)
    dl = LongitudinalGlider(veh0).rhs(xl, ul)
    assert d3[F3["Omega2"]] - dl[FL["Omega2"]] == pytest.approx(-60.0 * 0.05 / 12.0, rel=1e-12)


# ------------------------------------------------------------------------------------- 3. kinematics


@st.composite
def angles(draw: st.DrawFn) -> tuple[float, float, float]:
    return draw(_u(-3.1, 3.1)), draw(_u(-1.5, 1.5)), draw(_u(-3.1, 3.1))


def _rx(a: float) -> np.ndarray:
    return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])


def _ry(a: float) -> np.ndarray:
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def _rz(a: float) -> np.ndarray:
    return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])


@FAST
@given(st.tuples(_u(-2, 2), _u(-2, 2), _u(-2, 2), _u(-2, 2)).filter(lambda t: np.linalg.norm(t) > 0.05))
def test_quat_to_R_is_a_rotation(q):
    R = quat_to_R(np.array(q))
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)


@FAST
@given(angles())
def test_ypr_matches_826_and_quaternion(a):
    """(8.26) is yaw about 3, then pitch about 2, then roll about 1 (body to inertial: Rz Ry Rx); the quaternion of
    the same angles gives the same matrix and R_to_ypr inverts it; R^T k is (8.27)."""
    psi, th, ph = a
    R = ypr_to_R(psi, th, ph)
    np.testing.assert_allclose(R, _rz(psi) @ _ry(th) @ _rx(ph), atol=1e-14)
    np.testing.assert_allclose(quat_to_R(ypr_to_quat(psi, th, ph)), R, atol=1e-14)
    assert np.linalg.norm(ypr_to_quat(psi, th, ph)) == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(R_to_ypr(R), [psi, th, ph], atol=1e-12)
    np.testing.assert_allclose(R.T @ K, zeta_of(th, ph), atol=1e-15)


@FAST
@given(angles(), _vec(-0.5, 0.5))
def test_euler_rates_828_and_reduced_kinematics(a, rates):
    """Omega^ = R^T R' along a YPR path equals (8.28) applied to (phi', theta', psi'); reduced_rhs inverts it."""
    psi, th, ph = a
    dph, dth, dpsi = rates
    h = 1e-6
    Rp = ypr_to_R(psi + h * dpsi, th + h * dth, ph + h * dph)
    Rm = ypr_to_R(psi - h * dpsi, th - h * dth, ph - h * dph)
    W = ypr_to_R(psi, th, ph).T @ (Rp - Rm) / (2 * h)
    Om_fd = np.array([W[2, 1], W[0, 2], W[1, 0]])
    E = np.array([[1, 0, -np.sin(th)], [0, np.cos(ph), np.cos(th) * np.sin(ph)],
                  [0, -np.sin(ph), np.cos(th) * np.cos(ph)]])  # (8.28)
    Om = E @ np.array([dph, dth, dpsi])
    np.testing.assert_allclose(Om_fd, Om, atol=1e-8)
    s = np.r_[0.7, 0.0, 0.03, Om, th, ph]
    d = reduced_rhs(FixedMassGlider3D(SLOCUM, R_P, M0), s)
    np.testing.assert_allclose(d[6:8], [dth, dph], atol=1e-12 * (1 + 1 / np.cos(th)))


@FAST
@given(unit_quaternions(), _vec(-0.5, 0.5))
def test_quaternion_rate_is_R_Omega_hat(q, Om):
    """The quaternion rate of the models realizes (2.2), R' = R Omega^ (checked by a central difference of R(q))."""
    model = FixedMassGlider3D(SLOCUM, R_P, M0)
    x = np.r_[np.zeros(3), q, 0.7, 0.0, 0.03, Om]
    dq = model.rhs(x)[3:7]
    assert float(np.dot(q, dq)) == pytest.approx(0.0, abs=1e-15)  # tangent to |q| = 1
    h = 1e-6
    Rdot = (quat_to_R(q + h * dq) - quat_to_R(q - h * dq)) / (2 * h)
    np.testing.assert_allclose(Rdot, quat_to_R(q) @ hat(Om), atol=1e-9)
    np.testing.assert_allclose(hat(Om) @ np.array([0.3, -0.2, 0.9]), np.cross(Om, [0.3, -0.2, 0.9]), atol=1e-16)


def test_baumgarte_term_pulls_norm_back():
    """Off the unit sphere the quaternion rate has a radial component that restores |q| = 1."""
    model = FixedMassGlider3D(SLOCUM, R_P, M0)
    q = 1.01 * ypr_to_quat(0.1, -0.2, 0.3)
    dq = model.rhs(np.r_[np.zeros(3), q, 0.7, 0.0, 0.03, 0.01, 0.02, -0.01])[3:7]
    assert np.dot(q, dq) < 0


@pytest.fixture(scope="module")
def sim_822():
    """2000 s of the §8.2.2 simulation (Fig 8.2-8.4), glidectl defaults (LSODA, rtol 1e-8, atol 1e-10)."""
    model = FixedMassGlider3D(SLOCUM, R_P, M0)
    x0 = np.r_[0.0, 0.0, 0.0, ypr_to_quat(PSI0, THETA0, PHI0), V0, OMEGA0]
    return simulate(model, x0, 2000.0, t_eval=np.linspace(0.0, 2000.0, 801))


def test_simulation_stays_on_SO3(sim_822):
    assert sim_822.state_names == FIXED_STATES
    q = sim_822.x[:, 3:7]
    assert np.max(np.abs(np.linalg.norm(q, axis=1) - 1.0)) < 1e-8
    R = quat_to_R(q)
    np.testing.assert_allclose(np.einsum("nij,nkj->nik", R, R), np.broadcast_to(np.eye(3), R.shape), atol=1e-8)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-8)
    np.testing.assert_allclose(R_to_ypr(R[0]), [PSI0, THETA0, PHI0], atol=1e-14)


def test_simulation_converges_to_the_helix(sim_822):
    """Fig 8.2-8.4: from the §8.2.2 initial condition the glider converges to helix_trim's circular helix."""
    h = helix_trim(SLOCUM, R_P, M0)
    xf = sim_822.x[-1]
    np.testing.assert_allclose(xf[7:10], h.v, atol=1e-8)
    np.testing.assert_allclose(xf[10:13], h.Omega, atol=1e-8)
    _, th, ph = R_to_ypr(quat_to_R(xf[3:7]))
    assert th == pytest.approx(h.theta, abs=1e-8)
    assert ph == pytest.approx(h.phi, abs=1e-8)
    # not trivially: the initial state is far from the helix (theta0 differs by 2.4 deg)
    assert abs(THETA0 - h.theta) > 0.04
    # and the glider sinks: z grows (z down) at the helix sink rate at the end
    dz = np.gradient(sim_822.state("z"), sim_822.t)
    assert dz[-1] == pytest.approx(h.vertical_speed, rel=1e-6)


# ------------------------------------------------------------------------------------- 4. hydrodynamics


@FAST
@given(st.tuples(_u(0.05, 1.5), _u(-0.5, 0.5), _u(-0.5, 0.5)))
def test_loads_3d_without_sideslip_equal_longitudinal_loads(c):
    """beta = 0: body force = (L sin a - D cos a, 0, -L cos a - D sin a) as in (2.18)-(2.19), moment (0, M_DL2, 0)."""
    v1, v3, Om2 = c
    for veh in (SLOCUM_KQ, load_vehicle("slocum_ch8", K_Omega1_2=0.0, K_q=-3.0, K_L0=5.0, K_M0=0.3)):
        F, T, alpha, beta, V = loads_3d(veh, np.array([v1, 0.0, v3]), np.array([0.0, Om2, 0.0]))
        a, L, D, M = longitudinal_loads(veh, v1, v3, Om2)
        assert beta == 0.0
        assert alpha == pytest.approx(float(a), abs=1e-15)
        assert V == pytest.approx(np.hypot(v1, v3), rel=1e-15)
        sa, ca = np.sin(a), np.cos(a)
        np.testing.assert_allclose(F, [L * sa - D * ca, 0.0, -L * ca - D * sa], rtol=1e-13, atol=1e-14)
        np.testing.assert_allclose(T, [0.0, M, 0.0], rtol=1e-13, atol=1e-14)
    # Table 8.1: both carry the chapter-8 damping K_Omega1_2 Omega2 (no V^2), one convention
    T8 = loads_3d(SLOCUM, np.array([v1, 0.0, v3]), np.array([0.0, Om2, 0.0]))[1]
    a, _, _, M8 = longitudinal_loads(SLOCUM, v1, v3, Om2)
    assert T8[1] == pytest.approx(M8, rel=1e-13, abs=1e-14)
    assert M8 == pytest.approx(SLOCUM.K_M * a * (v1**2 + v3**2) + SLOCUM.K_Omega1_2 * Om2, rel=1e-12, abs=1e-14)


@FAST
@given(velocities().filter(lambda v: abs(v[1]) > 1e-3), _vec(-0.5, 0.5))
def test_side_force_opposes_sideslip(v, Om):
    """K_beta > 0 (Table 8.1): the side force, the e_2 component of the body force, has the sign opposite to v2
    (docs/conventions.md: -SF); with drag off the whole body y-force does."""
    F, _, alpha, beta, V = loads_3d(SLOCUM, v, Om)
    e2 = np.array([-np.cos(alpha) * np.sin(beta), np.cos(beta), -np.sin(alpha) * np.sin(beta)])
    assert np.sign(F @ e2) == -np.sign(v[1])
    assert F @ e2 == pytest.approx(-SLOCUM.K_beta * beta * V**2, rel=1e-12)
    assert np.sign(F[1]) == -np.sign(v[1])
    F0 = loads_3d(load_vehicle("slocum_ch8", K_D0=0.0, K_D=0.0), v, Om)[0]
    assert np.sign(F0[1]) == -np.sign(v[1])
    # drag is along -v, lift along -e_3 (perpendicular to v): the force does negative work against v
    assert F @ v < 0


@FAST
@given(velocities(), _vec(-0.5, 0.5))
def test_loads_3d_wind_frame(v, Om):
    """The wind frame is orthonormal, right-handed, e_V = v/V; the force is -D e_V - SF e_2 - L e_3."""
    veh = SLOCUM_FULL
    F, _, alpha, beta, V = loads_3d(veh, v, Om)
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    C = np.array([[ca * cb, -ca * sb, -sa], [sb, cb, 0.0], [sa * cb, -sa * sb, ca]])
    np.testing.assert_allclose(C.T @ C, np.eye(3), atol=1e-14)
    assert np.linalg.det(C) == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(C[:, 0], v / np.linalg.norm(v), atol=1e-14)
    D = (veh.K_D0 + veh.K_D * alpha**2) * V**2
    L = (veh.K_L0 + veh.K_L * alpha) * V**2
    SF = veh.K_beta * beta * V**2
    np.testing.assert_allclose(C.T @ F, [-D, -SF, -L], rtol=1e-12, atol=1e-13)


@FAST
@given(velocities(), st.tuples(*[_away_from_zero(1e-3, 0.5)] * 3).map(np.array))
def test_loads_3d_complex_step_equals_central_differences(v, Om):
    """Complex-step Jacobian of (F, T) in (v, Omega) equals a central-difference one (all terms switched on)."""
    veh = SLOCUM_FULL

    def f(x, u):
        F, T, _, _, _ = loads_3d(veh, x[..., 0:3], x[..., 3:6])
        return np.concatenate([F, T], -1)

    x0 = np.r_[v, Om]
    A, _ = jacobians(f, x0, np.zeros(0))
    Acd, _ = central_difference_jacobians(f, x0, np.zeros(0), h=1e-6)
    np.testing.assert_allclose(A, Acd, rtol=1e-6, atol=1e-6 * (1 + np.max(np.abs(A))))
    # batch evaluation agrees with single evaluation
    xb = np.stack([x0, 1.1 * x0])
    np.testing.assert_allclose(f(xb, None)[1], f(1.1 * x0, None), rtol=1e-15)


def test_loads_3d_damping_terms():
    """Moments: K_MR beta V^2 + K_q1 Omega1 V^2 + K_Omega1_1 Omega1 + K_Omega2_1 Omega1 |Omega1| (and axes 2, 3)."""
    veh = SLOCUM_FULL
    v, Om = np.array([0.6, 0.05, 0.04]), np.array([0.1, -0.2, -0.3])
    _, T, alpha, beta, V = loads_3d(veh, v, Om)
    V2 = V**2
    p = veh.params
    exp = np.array([
        p["K_MR"] * beta * V2 + p["K_q1"] * Om[0] * V2 + p["K_Omega1_1"] * Om[0] + p["K_Omega2_1"] * Om[0] * abs(Om[0]),
        (p["K_M0"] + p["K_M"] * alpha + p["K_q"] * Om[1]) * V2 + p["K_Omega1_2"] * Om[1]
        + p["K_Omega2_2"] * Om[1] * abs(Om[1]),
        p["K_MY"] * beta * V2 + p["K_q3"] * Om[2] * V2 + p["K_Omega1_3"] * Om[2] + p["K_Omega2_3"] * Om[2] * abs(Om[2]),
    ])
    np.testing.assert_allclose(T, exp, rtol=1e-13)
    # every damping term opposes its rotation
    damping = T - loads_3d(veh, v, np.zeros(3))[1]
    np.testing.assert_array_equal(np.sign(damping), -np.sign(Om))


# ------------------------------------------------------------------------------------- validation


def test_models_refuse_vehicles_without_3d_parameters():
    with pytest.raises(ModelError, match="K_beta"):
        Glider3D(load_vehicle("rogue"))
    with pytest.raises(ModelError, match="K_beta"):
        FixedMassGlider3D(load_vehicle("rogue"), R_P, M0)
    with pytest.raises(ModelError, match="not an underwater glider"):
        Glider3D(load_vehicle("dc8_ctol"))
    with pytest.raises(ModelError, match="mbar"):
        Glider3D(load_vehicle("slocum_ch8", mbar=0.0))
    with pytest.raises(gc.ArgumentError, match="finite"):
        FixedMassGlider3D(SLOCUM, (0.02, float("nan"), 0.04), M0)
    assert Glider3D(SLOCUM).input_names == FORCE3D_INPUTS


# ------------------------------------------------------------------------------------- bad inputs (issue 15)
def test_fixed_mass_model_refuses_implausible_mass_positions_and_ballast():
    # r_p = 1e9 m made the generalized mass matrix singular (LinAlgError); now a clear refusal up front
    with pytest.raises(gc.ArgumentError, match="R_P_MAX"):
        FixedMassGlider3D(SLOCUM, (1e9, 1e9, 1e9), 1e6)
    with pytest.raises(gc.ArgumentError, match="shape"):
        FixedMassGlider3D(SLOCUM, (0.02, 0.04), M0)
    with pytest.raises(gc.ArgumentTypeError):
        FixedMassGlider3D(SLOCUM, R_P, "0.25")
    with pytest.raises(gc.ArgumentTypeError):
        FixedMassGlider3D(SLOCUM, None, M0)
    # m0 = -41 kg leaves slocum (m = 50, mbar = 9) without solid mass: refused, not a 'helix' of a massless hull
    with pytest.raises(ModelError, match="solid mass"):
        FixedMassGlider3D(SLOCUM, R_P, -41.0)
    model = FixedMassGlider3D(SLOCUM, [0.02, 0.02, 0.04], np.float64(0.25))
    assert model.r_p == (0.02, 0.02, 0.04) and isinstance(model.m0, float)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 13"):
        model.rhs(np.zeros(12))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 3"):
        model.accelerations(np.zeros(2), np.zeros(3), np.zeros(3))


def test_rotation_helpers_check_their_inputs():
    with pytest.raises(gc.ArgumentError, match="nonzero"):
        quat_to_R(np.zeros(4))
    with pytest.raises(gc.ArgumentError, match="finite"):
        quat_to_R([1.0, 0.0, np.nan, 0.0])
    with pytest.raises(gc.ArgumentError, match="trailing dimension 4"):
        quat_to_R([1.0, 0.0, 0.0])
    with pytest.raises(gc.ArgumentTypeError):
        quat_to_R("1 0 0 0")
    with pytest.raises(gc.ArgumentError, match="finite"):
        ypr_to_R(0.0, np.nan, 0.0)
    with pytest.raises(gc.ArgumentTypeError):
        ypr_to_quat(0.0, None, 0.0)
    with pytest.raises(gc.ArgumentError, match="broadcast"):
        ypr_to_R(np.zeros(2), np.zeros(3), 0.0)
    with pytest.raises(gc.ArgumentError, match="rotation"):
        R_to_ypr(2 * np.eye(3))
    with pytest.raises(gc.ArgumentError, match="rotation"):
        R_to_ypr(-np.eye(3))
    with pytest.raises(gc.ArgumentError, match="3, 3"):
        R_to_ypr(np.eye(2))
    R = ypr_to_R(0.3, -0.2, 0.1)
    np.testing.assert_allclose(R_to_ypr(R), [0.3, -0.2, 0.1], atol=1e-14)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 20"):
        Glider3D(SLOCUM).rhs(np.zeros(13), np.zeros(4))
