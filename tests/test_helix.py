"""Steady 3D motions, chapter 8: the §8.2.2 circular helix (residual, printed numbers, helix geometry against
(8.18)/(8.22), Omega parallel to gravity (8.31), the trajectory it generates), Theorem 7's classification, the
reduced linearization and the errors of helix_trim."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from glidectl import (
    ArgumentError,
    ArgumentTypeError,
    FixedMassGlider3D,
    GlidectlError,
    InfeasibleGlideError,
    ModelError,
    classify_motion,
    helix_trim,
    load_vehicle,
)
from glidectl.derivatives import central_difference_jacobians, jacobians
from glidectl.models.glider3d import R_to_ypr, quat_to_R, ypr_to_quat
from glidectl.sim import simulate
from glidectl.trim.helix import (
    RESIDUAL_TOL,
    Helix,
    helix_eigenvalues,
    helix_equations,
    helix_newton,
    reduced_rhs,
    zeta_of,
)

SLOCUM = load_vehicle("slocum_ch8")
R_P = (0.02, 0.02, 0.04)  # m, §8.2.2
M0 = 0.25  # kg, §8.2.2
K = np.array([0.0, 0.0, 1.0])


@pytest.fixture(scope="module")
def helix() -> Helix:
    return helix_trim(SLOCUM, R_P, M0)


def _reduced_state(h: Helix) -> np.ndarray:
    return np.r_[h.v, h.Omega, h.theta, h.phi]


def _gravity_in_body(h: Helix) -> np.ndarray:
    """R^T k from the helix attitude, through the quaternion (independent of zeta_of)."""
    return quat_to_R(ypr_to_quat(0.0, h.theta, h.phi)).T @ K


# ------------------------------------------------------------------------------- the §8.2.2 helix


def test_helix_is_a_relative_equilibrium(helix):
    """(v', Omega') = 0 of (8.23) to 1e-10, recomputed with a fresh model (not the one the trim carries)."""
    h = helix
    assert h.residual < 1e-10
    model = FixedMassGlider3D(SLOCUM, R_P, M0)
    vd, Od = model.accelerations(h.v, h.Omega, zeta_of(h.theta, h.phi))
    assert max(np.max(np.abs(vd)), np.max(np.abs(Od))) < 1e-10
    # the full 13-state field on the helix: only position and attitude move
    d = model.rhs(h.initial_state(psi=0.7, position=(3.0, -2.0, 10.0)))
    np.testing.assert_allclose(d[7:13], 0.0, atol=1e-10)
    np.testing.assert_allclose(reduced_rhs(model, _reduced_state(h)), 0.0, atol=1e-10)
    assert h.r_p == R_P and h.m0 == M0 and h.vehicle.name == "slocum_ch8" and h.provenance == SLOCUM.provenance


def test_helix_reproduces_822_numbers(helix):
    """§8.2.2: radius 66.60 m, speed 0.729 m/s, pitch 206.2 m, period 639.6 s, to the printed digits."""
    h = helix
    assert f"{h.radius:.2f}" == "66.60"
    assert f"{h.speed:.3f}" == "0.729"
    assert f"{h.pitch:.1f}" == "206.2"
    assert f"{h.period:.1f}" == "639.6"
    # a heavy glider (m0 > 0) descends, pitched nose down, with the stable equilibrium of Fig 8.2
    assert h.vertical_speed > 0 and h.gamma < 0 and h.theta < 0
    assert h.stable and np.max(h.eigenvalues.real) < 0
    # Omega is 1/period turns per second
    assert np.linalg.norm(h.Omega) == pytest.approx(2 * math.pi / h.period, rel=1e-12)


def test_helix_mirror_in_rP2_and_rbh_of_83(helix):
    """§8.2.2: 'for a given m0 the equilibrium solutions are symmetric about r_P2 = 0'; §8.3: the nominal
    r_P = (0.02, -0.02, 0.04) m has r_bh = 0.0481 m."""
    h = helix
    hm = helix_trim(SLOCUM, (0.02, -0.02, 0.04), M0)
    flip = np.array([1.0, -1.0, 1.0])
    np.testing.assert_allclose(hm.v, flip * h.v, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(hm.Omega, -flip * h.Omega, rtol=1e-9, atol=1e-12)
    assert hm.phi == pytest.approx(-h.phi, rel=1e-9)
    assert hm.theta == pytest.approx(h.theta, rel=1e-9)
    assert hm.radius == pytest.approx(h.radius, rel=1e-9)
    assert f"{hm.r_bh:.4f}" == "0.0481"
    # bottom-heaviness r_P . R^T k (§8.3)
    assert hm.r_bh == pytest.approx(float(np.dot((0.02, -0.02, 0.04), _gravity_in_body(hm))), rel=1e-14)


def test_warm_start_finds_the_same_helix(helix):
    h2 = helix_trim(SLOCUM, R_P, M0, guess=helix.unknowns * (1 + 1e-3))
    np.testing.assert_allclose(h2.unknowns, helix.unknowns, rtol=1e-10, atol=1e-13)


def test_helix_geometry_matches_818_822(helix):
    """Helix identities: curvature r/(r^2 + c^2), torsion c/(r^2 + c^2), c = pitch/(2 pi) (signed by the turn
    direction psidot, right-handed inertial frame) against classify_motion's (8.18) and (8.22)."""
    h = helix
    c = math.copysign(h.pitch / (2 * math.pi), h.psidot)
    r = h.radius
    cls = classify_motion(h.v, h.Omega)
    assert cls["kind"] == "helix"
    assert cls["curvature"] == pytest.approx(r / (r**2 + c**2), rel=1e-12)
    assert cls["torsion"] == pytest.approx(c / (r**2 + c**2), rel=1e-12)
    assert h.curvature == cls["curvature"] and h.torsion == cls["torsion"]
    # (8.22)'s two forms agree: (v . Omega)/V^2 = |Omega| cos(xi)/V
    assert cls["torsion"] == pytest.approx(np.dot(h.v, h.Omega) / h.speed**2, rel=1e-12)
    # and the inverse: r = kappa/(kappa^2 + tau^2), c = tau/(kappa^2 + tau^2)
    kap, tau = cls["curvature"], cls["torsion"]
    assert kap / (kap**2 + tau**2) == pytest.approx(66.60, abs=0.005)
    assert 2 * math.pi * tau / (kap**2 + tau**2) == pytest.approx(206.2, abs=0.05)


def test_omega_parallel_to_gravity(helix):
    """(8.31): Omega x R^T k = 0, Omega = psidot R^T k, i.e. omega = R Omega = psidot k (helix axis vertical)."""
    h = helix
    zeta = _gravity_in_body(h)
    np.testing.assert_allclose(np.cross(h.Omega, zeta), 0.0, atol=1e-16)
    np.testing.assert_allclose(h.Omega, h.psidot * zeta, rtol=1e-14, atol=1e-17)
    R = quat_to_R(h.initial_state(psi=1.3)[3:7])
    np.testing.assert_allclose(R @ h.Omega, h.psidot * K, atol=1e-16)
    assert not h.is_straight and h.psidot != 0.0


@pytest.fixture(scope="module")
def on_helix(helix):
    """660 s (> 600 s, and more than one period of 639.6 s) on the helix, glidectl's default integrator."""
    return simulate(helix.model, helix.initial_state(), 660.0, t_eval=np.linspace(0.0, 660.0, 661))


def test_simulation_from_helix_stays_on_it(helix, on_helix):
    """Started exactly on Helix.initial_state(), v and Omega stay constant to 1e-8 over > 600 s; theta, phi too."""
    h, s = helix, on_helix
    np.testing.assert_allclose(s.x[:, 7:10], np.broadcast_to(h.v, (s.t.size, 3)), atol=1e-8)
    np.testing.assert_allclose(s.x[:, 10:13], np.broadcast_to(h.Omega, (s.t.size, 3)), atol=1e-8)
    ypr = R_to_ypr(quat_to_R(s.x[:, 3:7]))
    np.testing.assert_allclose(ypr[:, 1], h.theta, atol=1e-8)
    np.testing.assert_allclose(ypr[:, 2], h.phi, atol=1e-8)
    # yaw advances at psidot (unwrapped)
    np.testing.assert_allclose(np.unwrap(ypr[:, 0]), h.psidot * s.t, atol=1e-7)


def test_helix_trajectory_is_a_vertical_circular_helix(helix, on_helix):
    """Projected on the horizontal plane the path is a circle of the helix radius, centred a radius to the side
    of the initial horizontal velocity (turning toward starboard for psidot > 0); z falls at the sink rate, one
    pitch per period."""
    h, s = helix, on_helix
    xy, z = s.x[:, :2], s.x[:, 2]
    A = np.c_[2 * xy, np.ones(len(xy))]
    cx, cy, c0 = np.linalg.lstsq(A, np.sum(xy**2, 1), rcond=None)[0]
    r_fit = math.sqrt(c0 + cx**2 + cy**2)
    assert r_fit == pytest.approx(h.radius, rel=1e-7)
    np.testing.assert_allclose(np.linalg.norm(xy - [cx, cy], axis=1), h.radius, atol=1e-5)
    vh = (quat_to_R(s.x[0, 3:7]) @ h.v)[:2]
    centre = h.radius * math.copysign(1.0, h.psidot) * np.array([-vh[1], vh[0]]) / np.linalg.norm(vh)
    np.testing.assert_allclose([cx, cy], centre, atol=1e-5)
    np.testing.assert_allclose(z, h.vertical_speed * s.t, atol=1e-8)
    assert np.interp(h.period, s.t, z) == pytest.approx(h.pitch, rel=1e-9)
    # after one period the horizontal position returns
    xT = np.interp(h.period, s.t, xy[:, 0]), np.interp(h.period, s.t, xy[:, 1])
    assert np.hypot(*xT) < 0.05  # linear interpolation on a 1 s grid


# ----------------------------------------------------------------------------------------- Theorem 7


@pytest.mark.parametrize(("v", "Om", "kind", "kappa", "tau"), [
    ((0.5, 0.1, 0.0), (0.0, 0.0, 0.0), "straight line", 0.0, 0.0),
    ((0.0, 0.0, 0.0), (0.1, -0.2, 0.3), "pure rotation", math.nan, math.nan),
    ((0.6, 0.0, 0.8), (0.03, 0.0, 0.04), "screw", 0.0, 0.05),       # Omega = 0.05 v/V: kappa 0, tau |Omega|/V
    ((0.6, 0.0, 0.8), (-0.03, 0.0, -0.04), "screw", 0.0, -0.05),    # antiparallel: negative torsion
    ((1.0, 0.0, 0.0), (0.1, 0.0, 0.1), "helix", 0.1, 0.1),          # xi = 45 deg
    ((2.0, 0.0, 0.0), (0.0, 0.0, 0.4), "helix", 0.2, 0.0),          # xi = 90 deg: circle of radius V/|Omega|
])
def test_classify_motion_theorem_7(v, Om, kind, kappa, tau):
    c = classify_motion(np.array(v), np.array(Om))
    assert c["kind"] == kind
    for key, exp in (("curvature", kappa), ("torsion", tau)):
        if math.isnan(exp):
            assert math.isnan(c[key])
        else:
            assert c[key] == pytest.approx(exp, abs=1e-15)


def test_classify_motion_angle_xi():
    c = classify_motion(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.1, 0.1]))
    assert c["xi"] == pytest.approx(math.pi / 2, abs=1e-15)
    c = classify_motion(np.array([1.0, 0.0, 0.0]), np.array([0.1, 0.1, 0.0]))
    assert c["xi"] == pytest.approx(math.pi / 4, abs=1e-15)


# ---------------------------------------------------------------------------- reduced linearization


def test_reduced_linearization_eigenvalues(helix):
    """Helix.eigenvalues (complex-step Jacobian of reduced_rhs) equal those of a central-difference Jacobian."""
    h = helix
    s0 = _reduced_state(h)

    def f(s, u):
        return reduced_rhs(h.model, s)

    A, _ = jacobians(f, s0, np.zeros(0))
    Acd, _ = central_difference_jacobians(f, s0, np.zeros(0), h=1e-6)
    np.testing.assert_allclose(A, Acd, rtol=1e-6, atol=1e-7)
    lam, lam_cd = h.eigenvalues, np.linalg.eigvals(Acd)
    assert lam.shape == (8,)
    cost = np.abs(lam[:, None] - lam_cd[None, :])
    i, j = linear_sum_assignment(cost)
    assert cost[i, j].max() < 1e-6 * np.max(np.abs(lam))
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(A)), np.sort_complex(lam), rtol=1e-10)
    # sorted by real part
    assert np.all(np.diff(lam.real) >= 0)


def test_reduced_rhs_matches_full_model(helix):
    """reduced_rhs's (v', Omega', theta', phi') equal the 13-state model's (v', Omega') and the YPR rates of its
    quaternion rate (central difference of R_to_ypr along q'), at a point off the helix."""
    model = helix.model
    th, ph = -0.3, 0.5
    v, Om = np.array([0.6, 0.04, 0.05]), np.array([0.02, -0.03, 0.04])
    x = np.r_[0.0, 0.0, 0.0, ypr_to_quat(0.4, th, ph), v, Om]
    d = model.rhs(x)
    r = reduced_rhs(model, np.r_[v, Om, th, ph])
    np.testing.assert_allclose(r[:6], d[7:13], rtol=1e-14)
    hstep = 1e-6
    yp = R_to_ypr(quat_to_R(x[3:7] + hstep * d[3:7]))
    ym = R_to_ypr(quat_to_R(x[3:7] - hstep * d[3:7]))
    np.testing.assert_allclose(r[6:8], ((yp - ym) / (2 * hstep))[1:], atol=1e-9)


# ------------------------------------------------------------------------------------------- errors


def test_neutral_buoyancy_is_infeasible():
    with pytest.raises(InfeasibleGlideError, match="m0 = 0"):
        helix_trim(SLOCUM, R_P, 0.0)
    assert issubclass(InfeasibleGlideError, GlidectlError) and issubclass(InfeasibleGlideError, ValueError)


@pytest.mark.parametrize("r_p", [(0.02, float("nan"), 0.04), (float("inf"), 0.02, 0.04), (0.02, 0.04)])
def test_bad_r_p_raises_glidectl_error(r_p):
    with pytest.raises(GlidectlError, match="r_p"):
        helix_trim(SLOCUM, r_p, M0)


@pytest.mark.parametrize(("bad", "err"), [((0.02, float("nan"), 0.04), ArgumentError), ((0.02, 0.04), ArgumentError),
                                          (("a", 0, 0), ArgumentTypeError), (((1, 2), 0, 0), ArgumentTypeError),
                                          ("abc", ArgumentTypeError), (None, ModelError)])
def test_bad_r_p_raises_argument_errors(bad, err):
    veh = SLOCUM if bad is not None else load_vehicle("rogue")  # None: no nominal r_P in the ROGUE file
    with pytest.raises(err, match=r"r_p|r_P1"):
        helix_trim(veh, bad, M0)


@pytest.mark.parametrize(("m0", "err"), [(float("nan"), ArgumentError), (float("inf"), ArgumentError),
                                         ("heavy", ArgumentTypeError), (True, ArgumentTypeError),
                                         (np.array([0.25]), ArgumentTypeError)])
def test_bad_m0_raises_argument_errors(m0, err):
    with pytest.raises(err, match="m0"):
        helix_trim(SLOCUM, R_P, m0)


def test_numpy_scalars_are_accepted():
    h = helix_trim(SLOCUM, np.array(R_P), np.float32(M0))
    assert h.m0 == pytest.approx(M0) and isinstance(h.m0, float)


def test_m0_that_makes_a_mass_negative_is_refused():
    with pytest.raises(ModelError, match="solid mass"):
        helix_trim(SLOCUM, R_P, -1e4)


@pytest.mark.parametrize("m0", [-41.0, -41.5])
def test_m0_that_leaves_no_solid_mass_is_refused(m0):
    """Issue 15: m0 = -41 kg (m_s = m + m0 - mbar = 0) returned a helix of a vehicle with no solid mass."""
    with pytest.raises(ModelError, match="solid mass"):
        helix_trim(SLOCUM, R_P, m0)


def test_huge_mass_offset_is_a_clear_error_not_a_singular_matrix():
    """Issue 15: r_p = (1e9, 1e9, 1e9), m0 = 1e6 raised numpy's LinAlgError."""
    with pytest.raises(ArgumentError, match="R_P_MAX"):
        helix_trim(SLOCUM, r_p=(1e9, 1e9, 1e9), m0=1e6)


def test_tiny_buoyancy_is_not_accepted_on_an_absolute_residual():
    """Issue 15: m0 = 1e-300 returned a 'glide' at 5.7e-8 m/s whose residual was small only in absolute terms; the
    drag there is ~1e-14 N against a net weight of 1e-299 N. The residual is now judged against the forces."""
    with pytest.raises(InfeasibleGlideError):
        helix_trim(SLOCUM, R_P, 1e-300)
    model = FixedMassGlider3D(SLOCUM, R_P, 1e-300)
    # a fake like the old answer: creeping at 5.9e-8 m/s with the moving mass hanging straight down (r_P || zeta)
    zeta = np.array(R_P) / np.linalg.norm(R_P)
    y_fake = np.array([5.9e-8, 0.0, 0.0, 0.0, -math.asin(zeta[0]), math.atan2(zeta[1], zeta[2])])
    assert np.max(np.abs(helix_equations(model, y_fake))) < 1e-10  # it passes an absolute test
    y, _, ok = helix_newton(model, y_fake)
    assert not ok or np.linalg.norm(y[:3]) < 1e-100  # only a true equilibrium (V ~ sqrt(m0)) would be accepted


def test_relative_residual_of_a_helix(helix):
    assert 0.0 <= helix.relative_residual < RESIDUAL_TOL


@pytest.mark.parametrize(("kw", "err"), [({"continuation_steps": 0}, ArgumentError),
                                         ({"continuation_steps": 2.5}, ArgumentTypeError),
                                         ({"continuation_steps": 10**9}, ArgumentError),
                                         ({"n_random": -1}, ArgumentError), ({"n_random": 10**9}, ArgumentError),
                                         ({"seed": "a"}, ArgumentTypeError), ({"seed": -1}, ArgumentError),
                                         ({"guess": (1.0, 0.0)}, ArgumentError), ({"guess": "x"}, ArgumentTypeError),
                                         ({"guess": (math.nan,) * 6}, ArgumentError)])
def test_bad_solver_options_raise_argument_errors(kw, err):
    with pytest.raises(err):
        helix_trim(SLOCUM, R_P, M0, **kw)


@pytest.mark.parametrize("veh", [load_vehicle("dc8_ctol")])
def test_wrong_kind_of_vehicle_is_a_model_error(veh):
    with pytest.raises(ModelError, match="not an underwater glider"):
        helix_trim(veh, R_P, M0)
    with pytest.raises(ArgumentTypeError, match="Vehicle"):
        helix_trim("slocum_ch8", R_P, M0)


def test_helpers_check_their_arguments(helix):
    model = helix.model
    with pytest.raises(ArgumentTypeError, match="FixedMassGlider3D"):
        helix_newton(SLOCUM, helix.unknowns)
    with pytest.raises(ArgumentError):
        helix_newton(model, helix.unknowns[:5])
    with pytest.raises(ArgumentError):
        helix_eigenvalues(model, np.full(6, math.nan))
    with pytest.raises(ArgumentError, match="trailing dimension 6"):
        helix_equations(model, np.zeros(5))
    with pytest.raises(ArgumentTypeError):
        helix_equations(model, "y")
    with pytest.raises(ArgumentError, match="trailing dimension 8"):
        reduced_rhs(model, np.zeros(6))
    with pytest.raises(ArgumentTypeError):
        zeta_of("a", 0.0)
    with pytest.raises(ArgumentError):
        zeta_of(np.zeros(2), np.zeros(3))
    assert zeta_of(0.1, np.zeros(4)).shape == (4, 3)
    for bad, err in (("a", ArgumentTypeError), (math.nan, ArgumentError), (-1.0, ArgumentError)):
        with pytest.raises(err, match="tol"):
            classify_motion([1.0, 0.0, 0.0], [0.0, 0.0, 0.1], tol=bad)
    with pytest.raises(ArgumentError):
        classify_motion([1.0, 0.0], [0.0, 0.0, 0.1])
    with pytest.raises(ArgumentTypeError):
        helix.initial_state("0")
    with pytest.raises(ArgumentError):
        helix.initial_state(0.0, (0.0, 0.0))


def test_loads_3d_at_rest_is_finite_and_checks_shapes():
    from glidectl import hydro

    F, T, _, beta, V = hydro.loads_3d(SLOCUM, [0.0, 0.0, 0.0], [0.0, 0.0, 0.1])
    assert np.all(np.isfinite(F)) and np.all(np.isfinite(T)) and beta == 0.0 and V == 0.0
    with pytest.raises(ArgumentError, match="trailing dimension 3"):
        hydro.loads_3d(SLOCUM, [1.0, 2.0], [0.0, 0.0, 0.0])
    with pytest.raises(ArgumentError, match="broadcast"):
        hydro.loads_3d(SLOCUM, np.ones((4, 3)), np.zeros((5, 3)))
    with pytest.raises(ModelError):
        hydro.loads_3d(load_vehicle("dc8_ctol"), [1.0, 0.0, 0.0], [0.0, 0.0, 0.0])


def test_helix_arrays_are_read_only():
    h = helix_trim(SLOCUM, R_P, M0)
    for a in (h.v, h.Omega, h.eigenvalues):
        with pytest.raises(ValueError):
            a[0] = 0.0


def test_vehicle_without_3d_parameters_raises_model_error():
    """ROGUE (§2.3.1) has only longitudinal parameters: no K_beta, K_MR, K_MY, J1, J3, m2."""
    rogue = load_vehicle("rogue")
    with pytest.raises(ModelError, match="K_beta") as exc:
        helix_trim(rogue, R_P, M0)
    for key in ("J1", "J3", "K_MR", "K_MY", "m2"):
        assert key in str(exc.value)
    with pytest.raises(ModelError, match="r_P1"):  # no nominal r_P to default to
        helix_trim(rogue)


def test_helix_trim_defaults_to_the_vehicle_file(helix):
    h = helix_trim(SLOCUM)
    assert h.r_p == R_P and h.m0 == M0
    np.testing.assert_allclose(h.unknowns, helix.unknowns, rtol=1e-12, atol=1e-15)
