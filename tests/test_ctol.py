"""CTOL aircraft of chapter 7: model reductions, Theorem 4, the steady-glide controller, the climb trajectory,
tracking by steady gliding (Theorem 6) and the exact-tracking baselines."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.controllers.ctol import SteadyGlideController, closed_loop_eigenvalues
from glidectl.controllers.ctol_feedback_linearization import feedback_linearization_blowup
from glidectl.controllers.ctol_runs import TrackingRun
from glidectl.controllers.ctol_stable_inversion import stable_inversion, track_stable_inversion
from glidectl.controllers.ctol_tracking import pareto_front, track_with_steady_glides
from glidectl.controllers.ctol_trajectory import ClimbTrajectory, climb_trajectory
from glidectl.controllers.ctol_zero_dynamics import feedback_linearizing_inputs, zero_dynamics
from glidectl.models.ctol import CTOLAircraft, CTOLReduced
from glidectl.models.ctol_closed_loop import ClosedLoopCTOL
from glidectl.trim.ctol import angle_equation, residuals

VEH = gc.load_vehicle("dc8_ctol")
V_LEVEL = 0.85 / math.sqrt(30.0)
TRAJ = climb_trajectory(VEH)


def _random_full(rng: np.random.Generator, n: int) -> np.ndarray:
    V = rng.uniform(0.08, 0.5, n)
    g = rng.uniform(-1.0, 1.0, n)
    return np.column_stack([rng.normal(size=n), rng.normal(size=n), V * np.cos(g), V * np.sin(g),
                            g + rng.uniform(-0.3, 0.3, n), rng.normal(scale=0.5, size=n)])


# ---------------------------------------------------------------------------------------------- model
def test_reduced_model_is_the_full_model_in_reduced_coordinates():
    rng = np.random.default_rng(0)
    model = CTOLAircraft(VEH)
    red = CTOLReduced(VEH, 0.2, 0.1, 0.15, T=0.7)
    X = _random_full(rng, 50)
    U = rng.normal(size=(50, 2))
    h = 1e-6
    f = model.rhs(X, U)
    d_num = (red.from_full(X + h * f) - red.from_full(X - h * f)) / (2 * h)  # d/dt of the reduced state
    np.testing.assert_allclose(red.rhs(red.from_full(X), U), d_num, rtol=1e-7, atol=1e-8)


def test_normalized_parameters_and_physical_constants_do_not_enter():
    # m_physical and J2_physical are reference values only: changing them changes nothing
    x = _random_full(np.random.default_rng(1), 5)
    u = np.ones((5, 2))
    other = VEH.with_overrides(m_physical=1.0, J2_physical=1.0)
    np.testing.assert_array_equal(CTOLAircraft(VEH).rhs(x, u), CTOLAircraft(other).rhs(x, u))
    assert (VEH.m, VEH.g, VEH.J, VEH.rho_AW_half) == (1.0, 1.0, 1.0, 1.0)


def test_model_rejects_non_ctol_vehicle():
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        CTOLAircraft(gc.load_vehicle("rogue"))
    with pytest.raises(gc.ArgumentError, match="reference time"):
        CTOLReduced(VEH, 0.2, 0.0, 0.0, T=0.0)


# ---------------------------------------------------------------------------------------------- Theorem 4
def test_level_glide_values():
    gl = gc.ctol_glide(VEH, speed=V_LEVEL, gamma=0.0)
    assert gl.alpha == pytest.approx(0.0632962, abs=1e-7)
    assert gl.k1 == pytest.approx(-0.00311096, abs=1e-8)
    assert gl.k2 == pytest.approx(-0.0490837, abs=1e-7)
    assert gl.thrust > 0
    assert len(gl.alpha_roots) >= 3 and min(gl.alpha_roots, key=abs) == gl.alpha
    # level flight: lift = weight + k1 (vertical control force -k1), drag balanced by -k2
    lift = VEH.a_L * (1 + VEH.c * gl.alpha) * V_LEVEL**2
    drag = VEH.a_D * (1 + VEH.b * (1 + VEH.c * gl.alpha) ** 2) * V_LEVEL**2
    assert lift == pytest.approx(1 + gl.k1, rel=1e-12)
    assert drag == pytest.approx(-gl.k2, rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(V=st.floats(0.13, 0.6), gamma=st.floats(-1.3, 1.3))
def test_theorem4_residuals_and_closed_loop_equilibrium(V, gamma):
    gl = gc.ctol_glide(VEH, speed=V, gamma=gamma)
    assert abs(gl.alpha) <= 0.35
    assert np.max(np.abs(residuals(VEH, V, gamma, gl.alpha, gl.k1, gl.k2))) < 1e-12
    assert abs(angle_equation(VEH, V, gamma, gl.alpha)) < 1e-12
    # the full closed loop is at rest in (velocity, theta, Omega2) on the glide
    ctrl = SteadyGlideController(VEH, gl, k3=10.0, k4=5.0)
    x = gl.full_state((3.0, -2.0))
    xd = CTOLAircraft(VEH).rhs(x, ctrl(0.0, x))
    np.testing.assert_allclose(xd[2:], 0.0, atol=1e-12)
    np.testing.assert_allclose(xd[:2], gl.velocity, atol=1e-15)


def test_thrust_changes_sign_on_steep_descents():
    assert gc.ctol_glide(VEH, 0.4, math.radians(-60)).thrust < 0
    assert gc.ctol_glide(VEH, 0.4, math.radians(20)).thrust > 0


@pytest.mark.parametrize("kw, err, match", [
    ({"speed": 0.05, "gamma": 0.0}, gc.InfeasibleGlideError, "no steady glide"),
    ({"speed": -0.1, "gamma": 0.0}, gc.ArgumentError, "speed"),
    ({"speed": 0.0, "gamma": 0.0}, gc.ArgumentError, "speed"),
    ({"speed": float("nan"), "gamma": 0.0}, gc.ArgumentError, "speed"),
    ({"speed": 0.2, "gamma": float("inf")}, gc.ArgumentError, "gamma"),
    ({"speed": 0.2, "gamma": 1e300}, gc.ArgumentError, "gamma"),
    ({"speed": 0.2, "gamma": 3.2}, gc.ArgumentError, "gamma"),
    ({"speed": "fast", "gamma": 0.0}, gc.ArgumentTypeError, "speed"),
    ({"speed": None, "gamma": 0.0}, gc.ArgumentTypeError, "speed"),
    ({"speed": np.array([0.2]), "gamma": 0.0}, gc.ArgumentTypeError, "speed"),
    ({"speed": 0.2, "gamma": True}, gc.ArgumentTypeError, "gamma"),
    ({"speed": 0.2, "gamma": 0.0, "alpha_max": "a"}, gc.ArgumentTypeError, "alpha_max"),
    ({"speed": 0.2, "gamma": 0.0, "alpha_max": float("nan")}, gc.ArgumentError, "alpha_max"),
    ({"speed": 0.2, "gamma": 0.0, "alpha_max": 0.0}, gc.ArgumentError, "alpha_max"),
    ({"speed": 1e-200, "gamma": 0.1}, gc.ArgumentError, "underflow"),
])
def test_ctol_glide_bad_inputs(kw, err, match):
    with pytest.raises(err, match=match):
        gc.ctol_glide(VEH, **kw)


@pytest.mark.parametrize("speed", [1e200, 100.0001, 1e3])
def test_ctol_glide_speed_beyond_the_plausibility_limit(speed):
    """Issue 15: ctol_glide(dc8, 1e200, .1) raised OverflowError; speeds beyond SPEED_MAX_REF V_ref are refused."""
    from glidectl.trim.ctol import SPEED_MAX_REF

    assert SPEED_MAX_REF == 100.0 and VEH.m * VEH.g / VEH.rho_AW_half == 1.0  # V_ref = 1: limit 100 here
    with pytest.raises(gc.ArgumentError, match="speed"):
        gc.ctol_glide(VEH, speed, 0.1)
    with pytest.raises(ValueError):
        gc.ctol_glide(VEH, speed, 0.1)


def test_ctol_glide_accepts_numpy_scalars_and_the_limits():
    gl = gc.ctol_glide(VEH, np.float32(0.2), np.float64(0.1))
    assert gl.speed == pytest.approx(0.2) and isinstance(gl.speed, float)
    assert gc.ctol_glide(VEH, 0.2, math.pi).gamma == math.pi  # gamma in [-pi, pi]
    with pytest.raises(gc.ArgumentTypeError):
        gl.full_state("origin")
    with pytest.raises(gc.ArgumentError):
        gl.full_state((0.0, math.nan))


def test_ctol_glide_rejects_glider():
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        gc.ctol_glide(gc.load_vehicle("rogue"), 0.2, 0.0)
    with pytest.raises(gc.ArgumentTypeError, match="Vehicle"):
        gc.ctol_glide("dc8_ctol", 0.2, 0.0)


def test_angle_equation_checks_its_arguments():
    assert abs(angle_equation(VEH, 0.2, 0.1, 0.0)) > 0
    with pytest.raises(gc.ArgumentTypeError):
        angle_equation(VEH, "a", 0.1, 0.1)
    with pytest.raises(gc.ArgumentError):
        angle_equation(VEH, 0.2, 0.1, [0.1, math.nan])
    with pytest.raises(gc.ModelError):
        angle_equation(gc.load_vehicle("rogue"), 0.2, 0.1, 0.1)


# ---------------------------------------------------------------------------------------------- controller
def test_closed_loop_jacobian_is_exact():
    gl = gc.ctol_glide(VEH, 0.25, 0.2)
    cl = ClosedLoopCTOL(VEH, gl, 50.0, 8.0, T=0.5)
    J = cl.jacobian()
    h = 1e-6
    Jn = np.column_stack([(cl.rhs(h * e) - cl.rhs(-h * e)) / (2 * h) for e in np.eye(4)])
    np.testing.assert_allclose(J, Jn, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(cl.rhs(np.zeros(4)), 0.0, atol=1e-13)


@settings(max_examples=25, deadline=None)
@given(V=st.floats(0.12, 0.5), gamma=st.floats(-0.8, 0.8), k3=st.floats(0.5, 1e5), k4=st.floats(0.1, 300.0),
       T=st.floats(0.2, 3.0))
def test_closed_loop_eigenvalues_split(V, gamma, k3, k4, T):
    gl = gc.ctol_glide(VEH, V, gamma)
    ev = closed_loop_eigenvalues(VEH, gl, k3, k4, T)
    # rotational pair: s^2 + k4 T s + (k3 + k'') / eps with k'' = -thrust
    def rest(ev, k3_, k4_, T_):
        out = list(ev)
        for z in np.roots([1.0, k4_ * T_, (k3_ - gl.thrust) / VEH.epsilon]):
            i = int(np.argmin(np.abs(np.array(out) - z)))
            assert abs(out[i] - z) < 1e-6 * (1 + abs(z))
            out.pop(i)
        return np.sort_complex(np.array(out))

    # translational pair: the same for other pitch gains (the control force is constant in inertial axes)
    other = closed_loop_eigenvalues(VEH, gl, 2 * k3 + 1.0, 0.5 * k4, 1.3 * T)
    np.testing.assert_allclose(rest(ev, k3, k4, T), rest(other, 2 * k3 + 1.0, 0.5 * k4, 1.3 * T), rtol=1e-6,
                               atol=1e-8)
    if k3 > gl.thrust:
        assert np.max(ev.real) < 0


def test_rotational_loop_unstable_below_the_thrust_condition():
    gl = gc.ctol_glide(VEH, V_LEVEL, 0.0)
    ev = closed_loop_eigenvalues(VEH, gl, 0.5 * gl.thrust, 1.0)  # k3 + k'' < 0: a saddle
    assert np.max(ev.real) > 0
    with pytest.raises(gc.ArgumentError, match="k3"):
        SteadyGlideController(VEH, gl, k3=-1.0, k4=1.0)


# ---------------------------------------------------------------------------------------------- trajectory
def test_climb_trajectory_solves_7_91():
    t = np.linspace(0.01, 40.0, 400)
    d = TRAJ.derivatives(t, 5)[..., 1]
    c = np.array([1.0, 3.5, 4.9, 3.4, 1.2, 0.17])
    lhs = d[:, 5] * c[0] + d[:, 4] * c[1] + d[:, 3] * c[2] + d[:, 2] * c[3] + d[:, 1] * c[4] + d[:, 0] * c[5] - 1.7
    np.testing.assert_allclose(lhs, 0.0, atol=1e-10)
    h = 1e-5
    for k in range(4):  # each derivative is the time derivative of the previous one
        num = (TRAJ.derivatives(t + h, 4)[:, k, 1] - TRAJ.derivatives(t - h, 4)[:, k, 1]) / (2 * h)
        np.testing.assert_allclose(num, d[:, k + 1], atol=1e-7)
    assert TRAJ.derivatives(60.0, 0)[0, 1] == pytest.approx(10.0, abs=1e-6)
    np.testing.assert_array_equal(TRAJ.derivatives(np.array([-1.0, 0.0]), 5)[:, :, 1], 0.0)
    assert TRAJ.speed == pytest.approx(V_LEVEL)
    with pytest.raises(gc.ArgumentError, match="order"):
        TRAJ.derivatives(1.0, 6)


# ---------------------------------------------------------------------------------------------- tracking
def test_theorem6_constant_velocity_tracking_error_bounded_and_decaying():
    level = ClimbTrajectory(V_LEVEL, forcing=0.0)
    x0 = gc.ctol_glide(VEH, V_LEVEL, 0.0).full_state((0.0, 0.05))
    r = track_with_steady_glides(VEH, level, dt=4.0, k3=10.0, k4=10.0, t_final=40.0, x0=x0)
    e = np.hypot(*r.error.T)
    assert r.completed
    assert r.max_error < 0.06
    assert e[-1] < 1e-3
    # each replanned glide is a Theorem-4 glide of the chord
    assert all(abs(g.alpha) <= 0.35 for g in r.glides)


def test_tracking_from_the_trajectory_stays_on_it():
    level = ClimbTrajectory(V_LEVEL, forcing=0.0)
    r = track_with_steady_glides(VEH, level, dt=1.0, k3=10.0, k4=10.0, t_final=10.0)
    assert r.max_error < 1e-6


def test_tracking_reports_a_step_without_a_steady_glide():
    level = ClimbTrajectory(V_LEVEL, forcing=0.0)
    x0 = gc.ctol_glide(VEH, V_LEVEL, 0.0).full_state((0.0, 1e-3))
    r = track_with_steady_glides(VEH, level, dt=0.5, k3=1.0, k4=2.0, t_final=40.0, x0=x0)
    assert not r.completed
    assert r.stopped_at is not None and r.stopped_at < 40.0
    assert "no steady glide" in r.note


@pytest.mark.parametrize("kw, match", [({"dt": 0.0}, "dt"), ({"k3": float("nan")}, "k3"),
                                       ({"x0": [0.0, 1.0]}, "x0")])
def test_tracking_bad_inputs(kw, match):
    with pytest.raises(gc.ArgumentError, match=match):
        track_with_steady_glides(VEH, TRAJ, **kw)


def test_tracking_run_metrics():
    t = np.linspace(0.0, 2 * np.pi, 20001)
    u = np.column_stack([np.sin(t), 2 * np.cos(t)])
    r = TrackingRun.from_arrays("test", t, np.zeros((t.size, 6)), u, np.column_stack([t, 0 * t]))
    assert r.rms_u1 == pytest.approx(1 / math.sqrt(2), rel=1e-6)
    assert r.rms_u2 == pytest.approx(math.sqrt(2), rel=1e-6)
    assert r.effort == pytest.approx(math.sqrt(2.5), rel=1e-6)
    assert r.peak_u2 == pytest.approx(2.0)
    assert r.max_error == pytest.approx(2 * np.pi)
    with pytest.raises(gc.ArgumentError, match="inconsistent"):
        TrackingRun.from_arrays("bad", t, np.zeros((t.size, 6)), u[:-1], np.zeros((t.size, 2)))


def test_pareto_front():
    pts = [(1.0, 5.0), (2.0, 2.0), (3.0, 3.0), (0.5, 9.0), (2.0, 2.0), (4.0, 1.0)]
    assert pareto_front(pts) == [5, 1, 4, 0, 3]


# ---------------------------------------------------------------------------------------------- baselines
def test_zero_dynamics_is_a_saddle():
    zd = zero_dynamics(VEH, V_LEVEL)
    assert zd.is_saddle
    assert zd.theta == pytest.approx(gc.ctol_glide(VEH, V_LEVEL, 0.0).alpha, abs=1e-10)
    assert zd.eigenvalues[1] == pytest.approx(-zd.eigenvalues[0], rel=1e-9)
    # small-angle estimate sqrt(a_L c V^2 / eps)
    assert zd.rate == pytest.approx(math.sqrt(VEH.a_L * VEH.c * V_LEVEL**2 / VEH.epsilon), rel=0.01)


def test_feedback_linearizing_inputs_give_the_commanded_acceleration():
    rng = np.random.default_rng(3)
    X = _random_full(rng, 40)
    w = rng.normal(size=(40, 2))
    acc = CTOLAircraft(VEH).rhs(X, feedback_linearizing_inputs(VEH, X, w))[:, 2:4]
    np.testing.assert_allclose(acc, w, atol=1e-12)


@pytest.fixture(scope="module")
def inversion():
    return stable_inversion(VEH, TRAJ, t1=25.0)


def test_stable_inversion_tracks_exactly_and_feedback_linearization_blows_up(inversion):
    assert inversion.max_residual < 1e-5
    # bounded before the climb starts, and it moves before t = 0 (pre-action)
    th = inversion.pitch(np.array([inversion.t0, -1.0]))[:, 0]
    assert abs(th[0] - zero_dynamics(VEH, V_LEVEL).theta) < 1e-8
    assert abs(th[1] - th[0]) > 1e-4
    run = track_stable_inversion(VEH, TRAJ, inversion=inversion, t_final=20.0)
    assert run.completed and run.max_error < 1e-5
    blow = feedback_linearization_blowup(VEH, TRAJ, inversion=inversion, t_final=20.0)
    assert blow.blowup_time is not None and blow.blowup_time < 20.0
    assert blow.growth_rate == pytest.approx(blow.frozen_rate, rel=0.1)


def test_approximate_linearization_exact_on_design_model_unstable_on_aircraft():
    from glidectl.controllers.ctol_approximate_linearization import (
        approximate_linearization_eigenvalues,
        track_approximate_linearization,
    )

    design = VEH.with_overrides(epsilon=0.0)
    ok = track_approximate_linearization(design, TRAJ, t_final=8.0)
    assert ok.completed and ok.max_error < 1e-4
    ev0 = approximate_linearization_eigenvalues(design, V_LEVEL)
    np.testing.assert_allclose(ev0, -1.0, atol=0.1)  # fourfold root -1 per axis (ill-conditioned)
    ev = approximate_linearization_eigenvalues(VEH, V_LEVEL)
    assert np.max(ev.real) > 0.01
    bad = track_approximate_linearization(VEH, TRAJ, t_final=8.0)
    assert not bad.completed and bad.stopped_at < 3.0
    assert "stopped" in bad.note


# ---------------------------------------------------------------------------------------------- bad inputs (issue 15)
GLIDE = gc.ctol_glide(VEH, V_LEVEL, 0.0)


def test_closed_loop_eigenvalues_refuse_a_glider_and_eps_zero():
    # a glider has no epsilon: a ModelError naming the kind, not AttributeError('epsilon')
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        gc.ctol_closed_loop_eigenvalues(gc.load_vehicle("rogue"), GLIDE, 10.0, 5.0)
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        gc.SteadyGlideController(gc.load_vehicle("sphere_ch5"), GLIDE, 10.0, 5.0)
    # epsilon = 0: the law divides by eps -> ModelError, not ZeroDivisionError
    flat = VEH.with_overrides(epsilon=0.0)
    gl0 = gc.ctol_glide(flat, V_LEVEL, 0.0)
    for call in (lambda: gc.ctol_closed_loop_eigenvalues(flat, gl0, 10.0, 5.0),
                 lambda: gc.SteadyGlideController(flat, gl0, 10.0, 5.0),
                 lambda: ClosedLoopCTOL(flat, gl0, 10.0, 5.0)):
        with pytest.raises(gc.ModelError, match="epsilon"):
            call()


@pytest.mark.parametrize("k3, k4, T, err", [
    (-1.0, 5.0, 1.0, gc.ArgumentError), (0.0, 5.0, 1.0, gc.ArgumentError), (10.0, -5.0, 1.0, gc.ArgumentError),
    (10.0, 0.0, 1.0, gc.ArgumentError), (10.0, 5.0, 0.0, gc.ArgumentError), (math.nan, 5.0, 1.0, gc.ArgumentError),
    (10.0, math.inf, 1.0, gc.ArgumentError), ("10", 5.0, 1.0, gc.ArgumentTypeError),
    (10.0, None, 1.0, gc.ArgumentTypeError), (True, 5.0, 1.0, gc.ArgumentTypeError),
])
def test_steady_glide_law_gains_are_checked(k3, k4, T, err):
    with pytest.raises(err):
        gc.ctol_closed_loop_eigenvalues(VEH, GLIDE, k3, k4, T)
    with pytest.raises(err):
        gc.SteadyGlideController(VEH, GLIDE, k3, k4, T)
    with pytest.raises(ValueError if issubclass(err, ValueError) else TypeError):
        ClosedLoopCTOL(VEH, GLIDE, k3, k4, T)


def test_glide_provenance_and_type_are_checked():
    other = VEH.with_overrides(a_L=31.0)
    with pytest.raises(gc.VehicleMismatchError):
        gc.ctol_closed_loop_eigenvalues(other, GLIDE, 10.0, 5.0)
    with pytest.raises(gc.VehicleMismatchError):
        gc.SteadyGlideController(other, GLIDE, 10.0, 5.0)
    with pytest.raises(gc.ArgumentTypeError, match="CTOLGlide"):
        gc.ctol_closed_loop_eigenvalues(VEH, None, 10.0, 5.0)
    with pytest.raises(gc.ArgumentTypeError, match="Vehicle"):
        gc.ctol_closed_loop_eigenvalues("dc8_ctol", GLIDE, 10.0, 5.0)
    ctrl = gc.SteadyGlideController(VEH, GLIDE, 10.0, 5.0)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 6"):
        ctrl(0.0, np.zeros(4))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 4"):
        ctrl.reduced_input(np.zeros(6))


def test_models_check_vehicle_and_array_shapes():
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        gc.ExtendedCTOL(gc.load_vehicle("rogue"))  # refused at construction, not at the first rhs call
    with pytest.raises(gc.ArgumentTypeError):
        CTOLAircraft("dc8_ctol")
    m = CTOLAircraft(VEH)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 6"):
        m.rhs(np.zeros(5), np.zeros(2))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 2"):
        m.rhs(GLIDE.full_state((0.0, 0.0)), np.zeros(3))
    with pytest.raises(gc.ArgumentTypeError):
        m.rhs(GLIDE.full_state((0.0, 0.0)), None)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 8"):
        gc.ExtendedCTOL(VEH).rhs(np.zeros(6), np.zeros(2))
    with pytest.raises(gc.ArgumentError, match="V_e"):
        CTOLReduced(VEH, -0.2, 0.0, 0.0)
    with pytest.raises(gc.ArgumentTypeError):
        CTOLReduced(VEH, 0.2, "0", 0.0)
    with pytest.raises(gc.ArgumentError, match="trailing dimension"):
        feedback_linearizing_inputs(VEH, np.zeros(6), np.zeros(3))


def test_climb_trajectory_inputs():
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        climb_trajectory(gc.load_vehicle("rogue"))
    with pytest.raises(gc.ArgumentTypeError, match="load_vehicle"):
        climb_trajectory("dc8_ctol")
    with pytest.raises(gc.ArgumentError):
        climb_trajectory(VEH, mach_like=-0.85)
    with pytest.raises(gc.ArgumentTypeError):
        climb_trajectory(VEH, mach_like="0.85")
    with pytest.raises(gc.ArgumentError):
        ClimbTrajectory(math.nan)
    with pytest.raises(gc.ArgumentError, match="coeffs"):
        ClimbTrajectory(V_LEVEL, coeffs=(1.0, 2.0))
    with pytest.raises(gc.ModelError, match="settle"):
        ClimbTrajectory(V_LEVEL, coeffs=(1.0, -3.5, 4.9, -3.4, 1.2, -0.17))  # mirrored roots: unstable
    with pytest.raises(gc.ArgumentError, match="finite"):
        TRAJ.derivatives(np.array([0.0, math.nan]))
    with pytest.raises(gc.ArgumentTypeError, match="order"):
        TRAJ.derivatives(1.0, 2.0)


def test_approximate_linearization_dt_zero_is_an_argument_error():
    from glidectl.controllers.ctol_approximate_linearization import track_approximate_linearization

    for dt in (0.0, -0.01, math.nan, 50.0):  # dt = 0 used to be a ZeroDivisionError; dt > t_final is refused
        with pytest.raises(gc.ArgumentError, match="dt"):
            track_approximate_linearization(VEH, TRAJ, t_final=8.0, dt=dt)
    with pytest.raises(ValueError):  # the builtin still catches it
        track_approximate_linearization(VEH, TRAJ, t_final=8.0, dt=0.0)
    with pytest.raises(gc.ArgumentTypeError, match="ClimbTrajectory"):
        track_approximate_linearization(VEH, "climb")
    with pytest.raises(gc.ArgumentError, match="speed"):
        gc.approximate_linearization_eigenvalues(VEH, 0.0)
    with pytest.raises(gc.ArgumentError, match="pole"):
        gc.approximate_linearization_eigenvalues(VEH, V_LEVEL, pole=-1.0)


def test_track_stable_inversion_checks_arguments_before_the_expensive_solve(monkeypatch):
    import glidectl.controllers.ctol_stable_inversion as si

    def no_solve(*args, **kw):
        raise AssertionError("stable_inversion must not run before the arguments are checked")

    monkeypatch.setattr(si, "stable_inversion", no_solve)
    for kw, err in [({"t_final": -1.0}, gc.ArgumentError), ({"t_final": math.nan}, gc.ArgumentError),
                    ({"t_final": "40"}, gc.ArgumentTypeError), ({"start": "middle"}, gc.ArgumentError),
                    ({"dt": 0.0}, gc.ArgumentError), ({"q": (1.0, 1.0)}, gc.ArgumentError),
                    ({"r": -1.0}, gc.ArgumentError), ({"kp": math.inf}, gc.ArgumentError),
                    ({"inversion": "inv"}, gc.ArgumentTypeError)]:
        with pytest.raises(err):
            si.track_stable_inversion(VEH, TRAJ, **kw)
    with pytest.raises(gc.ModelError, match="epsilon"):
        si.track_stable_inversion(VEH.with_overrides(epsilon=0.0), TRAJ)
    with pytest.raises(gc.ArgumentError, match="t0 < 0 < t1"):
        stable_inversion(VEH, TRAJ, t0=1.0)


def test_inversion_window_and_vehicle_are_checked(inversion):
    with pytest.raises(gc.ArgumentError, match="past the end"):
        track_stable_inversion(VEH, TRAJ, inversion=inversion, t_final=30.0)
    with pytest.raises(gc.VehicleMismatchError):
        track_stable_inversion(VEH.with_overrides(epsilon=0.31), TRAJ, inversion=inversion, t_final=20.0)
    with pytest.raises(gc.ArgumentError, match="another trajectory"):
        track_stable_inversion(VEH, ClimbTrajectory(0.2), inversion=inversion, t_final=20.0)
    with pytest.raises(gc.ArgumentError, match="reference exists"):
        inversion.pitch(100.0)
    with pytest.raises(gc.ArgumentError, match="ends at"):
        feedback_linearization_blowup(VEH, TRAJ, inversion=inversion, t_final=30.0)
    with pytest.raises(gc.ArgumentError, match="dt"):
        feedback_linearization_blowup(VEH, TRAJ, inversion=inversion, t_final=20.0, dt=0.0)


def test_steady_glide_tracking_inputs_and_budget():
    for kw, err in [({"dt": 50.0}, gc.ArgumentError), ({"t_final": -1.0}, gc.ArgumentError),
                    ({"k4": -1.0}, gc.ArgumentError), ({"x0": [0.0, 0.0, 0.2, 0.0, 0.0, math.nan]}, gc.ArgumentError),
                    ({"method": "Euler"}, gc.ArgumentError), ({"dt": 1e-9, "t_final": 40.0}, gc.ArgumentError),
                    ({"k3": "7e5"}, gc.ArgumentTypeError)]:
        with pytest.raises(err):
            track_with_steady_glides(VEH, TRAJ, **kw)
    with pytest.raises(gc.ArgumentTypeError, match="ClimbTrajectory"):
        track_with_steady_glides(VEH, None)
    with pytest.raises(gc.ModelError, match="not a CTOL"):
        track_with_steady_glides(gc.load_vehicle("rogue"), TRAJ)
    with pytest.raises(gc.BudgetError, match="max_nfev"):
        track_with_steady_glides(VEH, TRAJ, t_final=1.0, max_nfev=50)


def test_pareto_and_grid_inputs():
    assert pareto_front([]) == []
    with pytest.raises(gc.ArgumentError, match="pairs"):
        pareto_front([1.0, 2.0, 3.0])
    with pytest.raises(gc.ArgumentError, match="finite"):
        pareto_front([(1.0, math.nan)])
    with pytest.raises(gc.ArgumentTypeError):
        pareto_front([("a", "b")])
    from glidectl.controllers.ctol_tracking import tracking_grid

    with pytest.raises(gc.ArgumentError, match="at least one"):
        tracking_grid(VEH, TRAJ, [], [(1.0, 1.0)])
    with pytest.raises(gc.ArgumentError, match="pairs"):
        tracking_grid(VEH, TRAJ, [0.1], [1.0, 2.0, 3.0])
    with pytest.raises(gc.ArgumentError, match="positive"):
        tracking_grid(VEH, TRAJ, [-0.1], [(1.0, 1.0)])
    with pytest.raises(gc.ArgumentError, match="at most"):
        tracking_grid(VEH, TRAJ, np.linspace(0.1, 1.0, 200), [(1.0, k) for k in np.linspace(1, 2, 100)])
    with pytest.raises(gc.ArgumentTypeError, match="map"):
        tracking_grid(VEH, TRAJ, [0.1], [(1.0, 1.0)], executor=object())


def test_zero_dynamics_inputs():
    with pytest.raises(gc.ArgumentError, match="speed"):
        zero_dynamics(VEH, -V_LEVEL)
    with pytest.raises(gc.ArgumentTypeError):
        zero_dynamics(VEH, None)
    with pytest.raises(gc.ModelError, match="epsilon"):
        zero_dynamics(VEH.with_overrides(epsilon=0.0), V_LEVEL)
    with pytest.raises(gc.ArgumentTypeError, match="ClimbTrajectory"):
        gc.FeedbackLinearizingController(VEH, None)
    with pytest.raises(gc.ArgumentError, match="kp"):
        gc.FeedbackLinearizingController(VEH, TRAJ, kp=0.0)
