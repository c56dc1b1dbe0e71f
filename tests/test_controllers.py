"""Linear glide-path controllers (LQR, pole placement), the decoupled feedback (2.37) and nonlinear simulation."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.controllers.linear import DEFAULT_MAX_DEVIATION

ROGUE = gc.load_vehicle("rogue")
DOWN = gc.steady_glide(ROGUE, 0.3, math.radians(-45), r_p3=0.05)
UP = gc.steady_glide(ROGUE, 0.3, math.radians(45), r_p3=0.05)
THESIS_DIAG = 100.0 * np.array([1.0, 3.0, 1.0, 3.0, 0.5])


@pytest.fixture(scope="module")
def lqr() -> gc.LinearGlideController:
    return gc.lqr_glide(ROGUE, DOWN)


def test_lqr_closed_loop_is_stable_and_matches_riccati(lqr):
    A, B = np.asarray(lqr.plant.A), np.asarray(lqr.plant.B)
    lam = np.linalg.eigvals(A - B @ lqr.K)
    assert np.max(lam.real) < 0
    np.testing.assert_allclose(np.sort_complex(lam), np.sort_complex(lqr.closed_loop_poles), atol=1e-8)
    # Riccati optimality: K = R^-1 B^T P with P solving A^T P + P A - P B R^-1 B^T P + Q = 0
    from scipy.linalg import solve_continuous_are

    P = solve_continuous_are(A, B, lqr.Q, lqr.R)
    np.testing.assert_allclose(lqr.K, np.linalg.solve(lqr.R, B.T @ P), rtol=1e-6, atol=1e-9)
    # Bryson weights from the documented table
    assert lqr.Q[0, 0] == pytest.approx(1 / DEFAULT_MAX_DEVIATION["z_prime"] ** 2)


def test_lqr_regulates_the_glide_path_state(lqr):
    assert lqr.state_names[0] == "z_prime"
    assert lqr.K.shape == (3, 10)
    # the controller returns zero input exactly on the steady glide and on the path
    x = DOWN.force_state()
    np.testing.assert_allclose(lqr(0.0, x), 0.0, atol=1e-12)
    # moving along the path (z' = 0) does not change the input; moving across it does
    xs = x.copy()
    xs[0] += 3.0 * math.cos(DOWN.gamma)
    xs[1] -= 3.0 * math.sin(DOWN.gamma)
    np.testing.assert_allclose(lqr(0.0, xs), 0.0, atol=1e-10)
    xs[1] += 0.1
    assert np.linalg.norm(lqr(0.0, xs)) > 1e-3


def test_lqr_nonlinear_recovery_converges_to_path(lqr):
    x0 = DOWN.force_state()
    x0[1] = 0.5 / math.cos(DOWN.gamma)  # z' = 0.5 m
    sim = gc.simulate(gc.LongitudinalGlider(ROGUE), x0, 120.0, lqr)
    zp = lqr.reduced_state(sim.x)[:, 0]
    assert zp[0] == pytest.approx(0.5)
    assert abs(zp[-1]) < 0.02
    np.testing.assert_allclose(sim.state("m0")[-1], DOWN.m0, atol=1e-3)


def test_place_glide_places_requested_poles():
    poles = [-0.4, -0.5, -0.6, -0.7, -0.8, -0.9, -1.0, -1.1, -1.2, -1.3]
    c = gc.place_glide(ROGUE, DOWN, poles)
    np.testing.assert_allclose(np.sort(c.closed_loop_poles.real), np.sort(poles), rtol=1e-6)
    assert np.max(np.abs(c.closed_loop_poles.imag)) < 1e-8


def test_place_glide_rejects_wrong_pole_count():
    with pytest.raises(gc.GlidectlError, match="10"):
        gc.place_glide(ROGUE, DOWN, [-1.0, -2.0])


def test_acceleration_lqr_is_stable():
    c = gc.lqr_glide(ROGUE, DOWN, inputs="acceleration")
    assert c.plant.input_labels == ["w1", "w3", "w4"]
    assert np.max(c.closed_loop_poles.real) < 0


def test_printed_decoupled_gain_is_unstable_and_corrected_is_stable():
    printed = gc.DecoupledAccelerationFeedback(-gc.decoupled_gain_matrix(*THESIS_DIAG), (DOWN,))
    fixed = gc.DecoupledAccelerationFeedback(gc.decoupled_gain_matrix(*THESIS_DIAG), (DOWN,))
    assert np.max(printed.zeta_closed_loop_poles.real) > 10.0
    assert np.max(fixed.zeta_closed_loop_poles.real) < 0
    # characteristic polynomials s^2 + 300 s + 100 (twice) and s + 50
    expected = np.concatenate([np.roots([1, 300, 100]), np.roots([1, 300, 100]), [-50.0]])
    np.testing.assert_allclose(np.sort(fixed.zeta_closed_loop_poles.real), np.sort(expected.real), rtol=1e-9)


def test_decoupled_switch_reaches_the_up_glide():
    fb = gc.DecoupledAccelerationFeedback(gc.decoupled_gain_matrix(*THESIS_DIAG), (DOWN, UP), (0.0, 5.0))
    np.testing.assert_allclose(fb.zeta_e(4.999), [DOWN.r_p1, 0, DOWN.r_p3, 0, DOWN.m0])
    np.testing.assert_allclose(fb.zeta_e(5.0), [UP.r_p1, 0, UP.r_p3, 0, UP.m0])
    sim = gc.simulate(gc.AccelerationControlledGlider(ROGUE), DOWN.accel_state(), 60.0, fb)
    xf = sim.x[-1]
    up = UP.accel_state()
    np.testing.assert_allclose(xf[2:], up[2:], atol=1e-5)  # theta, Omega, v, mass state, m0
    # before the switch the vehicle stays on the down glide
    i = np.searchsorted(sim.t, 4.9)
    np.testing.assert_allclose(sim.x[i, 2:], DOWN.accel_state()[2:], atol=1e-8)


def test_decoupled_feedback_validates_inputs():
    with pytest.raises(gc.GlidectlError, match="shape"):
        gc.DecoupledAccelerationFeedback(np.eye(3), (DOWN,))
    with pytest.raises(gc.GlidectlError, match="switch"):
        gc.DecoupledAccelerationFeedback(gc.decoupled_gain_matrix(*THESIS_DIAG), (DOWN, UP), (5.0, 0.0))


def test_open_loop_steady_glide_stays_steady():
    sim = gc.simulate(gc.LongitudinalGlider(ROGUE), DOWN.force_state(), 20.0)
    np.testing.assert_allclose(sim.x[-1, 2:], DOWN.force_state()[2:], atol=1e-8)
    # position advances along the glide path at the glide speed
    dx = sim.x[-1, :2] - sim.x[0, :2]
    assert np.hypot(*dx) == pytest.approx(0.3 * 20.0, rel=1e-7)
    assert math.atan2(-dx[1], dx[0]) == pytest.approx(DOWN.gamma, abs=1e-8)


def test_simulate_rejects_bad_inputs():
    model = gc.LongitudinalGlider(ROGUE)
    with pytest.raises(gc.GlidectlError, match="shape"):
        gc.simulate(model, np.zeros(3), 1.0)
    with pytest.raises(gc.GlidectlError, match="t_final"):
        gc.simulate(model, DOWN.force_state(), -1.0)
    with pytest.raises(gc.GlidectlError, match="t_final"):
        gc.simulate(model, DOWN.force_state(), float("nan"))
    sim = gc.simulate(model, DOWN.force_state(), 1.0)
    with pytest.raises(gc.GlidectlError, match="no state"):
        sim.state("nope")


def test_simulate_stop_condition_ends_the_run():
    sim = gc.simulate(gc.LongitudinalGlider(ROGUE), DOWN.force_state(), 20.0,
                      stop=lambda t, x: 5.0 - t)  # stop at t = 5 s
    assert sim.stopped_at == pytest.approx(5.0, abs=1e-6)
    assert sim.t[-1] <= 5.0 + 1e-9
    full = gc.simulate(gc.LongitudinalGlider(ROGUE), DOWN.force_state(), 20.0)
    assert full.stopped_at is None and full.t[-1] == pytest.approx(20.0)
    with pytest.raises(gc.GlidectlError, match="already met"):
        gc.simulate(gc.LongitudinalGlider(ROGUE), DOWN.force_state(), 20.0, stop=lambda t, x: -1.0)


def test_modes_and_rank_tests_print_readably():
    sys = gc.linearize_glide(ROGUE, DOWN)
    text = str(gc.modes(sys))
    assert "dominant state" in text and len(text.splitlines()) == 11
    assert "rank 10/10 (full" in str(gc.controllability(sys))
    with pytest.raises(gc.GlidectlError, match="empty"):
        gc.controllability(sys, inputs=[])


# ---------------------------------------------------------------------------------------------- bad inputs (issue 15)
@pytest.mark.parametrize("kw, err, match", [
    ({"glide": None}, gc.ArgumentTypeError, "SteadyGlide"),
    ({"veh": "rogue"}, gc.ArgumentTypeError, "load_vehicle"),
    ({"veh": gc.load_vehicle("dc8_ctol")}, gc.ModelError, "not an underwater glider"),
    ({"veh": gc.load_vehicle("rogue", K_D=4.0)}, gc.VehicleMismatchError, "recompute"),
    ({"inputs": "forces"}, gc.ArgumentError, "inputs"),
    ({"Q": np.eye(3)}, gc.ArgumentError, "Q"),
    ({"Q": -np.eye(10)}, gc.ArgumentError, "semidefinite"),
    ({"Q": np.full((10, 10), np.nan)}, gc.ArgumentError, "finite"),
    ({"R": np.zeros((3, 3))}, gc.ArgumentError, "definite"),
    ({"R": np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])}, gc.ArgumentError, "symmetric"),
    ({"R": "eye"}, gc.ArgumentTypeError, "R"),
    ({"max_deviation": {"nope": 1.0}}, gc.ArgumentError, "nope"),
    ({"max_deviation": {"theta": -0.1}}, gc.ArgumentError, "theta"),
    ({"max_deviation": {"theta": "0.1"}}, gc.ArgumentTypeError, "theta"),
    ({"max_deviation": [("theta", 0.1)]}, gc.ArgumentTypeError, "mapping"),
])
def test_lqr_glide_bad_inputs(kw, err, match):
    args = {"veh": ROGUE, "glide": DOWN, **kw}
    with pytest.raises(err, match=match):
        gc.lqr_glide(args.pop("veh"), args.pop("glide"), **args)


def test_place_glide_bad_inputs():
    poles = [-0.4, -0.5, -0.6, -0.7, -0.8, -0.9, -1.0, -1.1, -1.2, -1.3]
    with pytest.raises(gc.ArgumentError, match="10"):
        gc.place_glide(ROGUE, DOWN, poles[:2])
    with pytest.raises(gc.ArgumentError, match="finite"):
        gc.place_glide(ROGUE, DOWN, [np.nan, *poles[1:]])
    with pytest.raises(gc.ArgumentError, match="conjugation"):
        gc.place_glide(ROGUE, DOWN, [-1 + 1j, *poles[1:]])
    with pytest.raises(gc.ArgumentError, match="repeated"):
        gc.place_glide(ROGUE, DOWN, [-1.0] * 10)
    with pytest.raises(gc.ArgumentTypeError):
        gc.place_glide(ROGUE, DOWN, None)
    with pytest.raises(gc.ArgumentTypeError):
        gc.place_glide(ROGUE, DOWN, ["a"] * 10)
    with pytest.raises(gc.VehicleMismatchError):
        gc.place_glide(gc.load_vehicle("rogue", K_D=4.0), DOWN, poles)
    with pytest.raises(ValueError):  # the builtin still catches it
        gc.place_glide(ROGUE, DOWN, poles[:2])


def test_decoupled_feedback_bad_inputs():
    with pytest.raises(gc.ArgumentTypeError):
        gc.decoupled_gain_matrix("100", 300.0, 100.0, 300.0, 50.0)
    with pytest.raises(gc.ArgumentError):
        gc.decoupled_gain_matrix(100.0, np.nan, 100.0, 300.0, 50.0)
    K = gc.decoupled_gain_matrix(*THESIS_DIAG)
    with pytest.raises(gc.ArgumentTypeError, match="SteadyGlide"):
        gc.DecoupledAccelerationFeedback(K, (None,))
    with pytest.raises(gc.ArgumentError, match="at least one"):
        gc.DecoupledAccelerationFeedback(K, ())
    with pytest.raises(gc.ArgumentError, match="finite"):
        gc.DecoupledAccelerationFeedback(np.full((3, 5), np.inf), (DOWN,))
    other = gc.steady_glide(gc.load_vehicle("rogue", K_D=4.0), 0.3, math.radians(45), r_p3=0.05)
    with pytest.raises(gc.VehicleMismatchError):
        gc.DecoupledAccelerationFeedback(K, (DOWN, other), (0.0, 5.0))
    fb = gc.DecoupledAccelerationFeedback(K, (DOWN,))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 11"):
        fb(0.0, np.zeros(10))


def test_linear_controller_checks_state_shapes(lqr):
    with pytest.raises(gc.ArgumentError, match="trailing dimension 11"):
        lqr(0.0, np.zeros(10))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 10"):
        lqr.path_input(np.zeros(11))
