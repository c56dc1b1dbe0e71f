"""The dive cycle's "lqg": simulated sensor noise and the Kalman filter's weights are separate; the controller is
sampled-data (a discrete Kalman filter and a zero-order hold at the sensor period), as a glider's flight computer
runs it, and does not make the actuators chatter on the noise."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad_vec
from scipy.linalg import expm

import glidectl as gc
from glidectl.controllers.dive_cycle import (
    LQG_NOISE,
    LQG_PROCESS_NOISE,
    LQG_SENSORS,
    SampledGlideLQG,
    lqg_filter_noise,
)
from glidectl.controllers.output_feedback import SampledLQG, _van_loan

VEH = gc.load_vehicle("slocum_shallow")
GLIDE = gc.steady_glide(VEH, 0.35, -math.radians(25), r_p3=VEH.actuators["r_P3"].fixed)
SHORT = dict(depths=(5.0, 30.0), cycles=1)


@pytest.fixture(scope="module")
def design():
    return gc.lqg_glide(VEH, GLIDE, LQG_SENSORS, LQG_NOISE, inputs="acceleration")


# ------------------------------------------------------------------------------------------------ the sampled design
def test_van_loan_integral_matches_quadrature():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(4, 4)) - 2 * np.eye(4)
    W = rng.normal(size=(4, 4))
    W = W @ W.T
    ref, _ = quad_vec(lambda t: expm(A.T * t) @ W @ expm(A * t), 0.0, 0.7, epsabs=1e-13, epsrel=1e-12)
    np.testing.assert_allclose(_van_loan(A, W, 0.7), ref, rtol=1e-9, atol=1e-12)


def test_sampled_design_tends_to_the_continuous_one(design):
    # regulator: the continuous-time equivalents log(z)/T of the sampled poles converge to the continuous poles
    # (first-order bound T |lambda|^2); the Kalman filter with per-sample noise sigma is the continuous filter with
    # noise intensity sigma^2 T, so its poles converge to those of lqg_glide with noise sigma sqrt(T)
    errs = []
    for T in (1e-3, 1e-4):
        sd = design.sampled(T)
        assert isinstance(sd, SampledLQG) and sd.period == T
        assert np.max(np.abs(sd.regulator_poles)) < 1 and np.max(np.abs(sd.estimator_poles)) < 1
        lam = design.regulator_poles
        err = np.max(np.abs(np.sort_complex(sd.regulator_poles_s) - np.sort_complex(lam)))
        assert err <= T * np.max(np.abs(lam)) ** 2
        cont = gc.lqg_glide(VEH, GLIDE, LQG_SENSORS, {k: v * math.sqrt(T) for k, v in LQG_NOISE.items()},
                            inputs="acceleration")
        mu = cont.estimator_poles
        err_e = np.max(np.abs(np.sort_complex(sd.estimator_poles_s) - np.sort_complex(mu)))
        assert err_e <= T * np.max(np.abs(mu)) ** 2
        errs.append((err, err_e / np.max(np.abs(mu))))
    assert errs[1][0] < errs[0][0] / 5 and errs[1][1] < errs[0][1] / 5


def test_sampled_design_at_the_sensor_period_is_stable_and_refuses_bad_periods(design):
    sd = design.sampled(1.0)
    assert sd.K.shape == design.K.shape and sd.M.shape == design.L.shape
    assert np.max(np.abs(sd.regulator_poles)) < 1 and np.max(np.abs(sd.estimator_poles)) < 1
    # the continuous gain held over 1 s does not stabilize the discretized plant: the sampled design is needed
    ri = [design.state_names.index(s) for s in design.regulated_states]
    ui = [design.plant.input_labels.index(q) for q in design.actuate]
    A, B = np.asarray(design.plant.A)[np.ix_(ri, ri)], np.asarray(design.plant.B)[np.ix_(ri, ui)]
    n, m = len(ri), len(ui)
    E = expm(np.block([[A, B], [np.zeros((m, n + m))]]))
    held = np.linalg.eigvals(E[:n, :n] - E[:n, n:] @ np.asarray(design.K)[np.ix_(ui, ri)])
    assert np.max(np.abs(held)) > 1
    for bad, err in ((0.0, gc.ArgumentError), (-1.0, gc.ArgumentError), ("1", gc.ArgumentTypeError)):
        with pytest.raises(err):
            design.sampled(bad)


# ------------------------------------------------------------------------------------------------ filter weights
def test_filter_weights_are_separate_from_the_simulated_noise():
    meas, proc = lqg_filter_noise(LQG_SENSORS)
    assert meas == pytest.approx(LQG_NOISE) and proc == LQG_PROCESS_NOISE
    # never trusts a sensor more than the simulated noise deserves
    meas, _ = lqg_filter_noise(LQG_SENSORS, {"z": 0.3, "theta": 1e-4})
    assert meas["z"] == 0.3 and meas["theta"] == LQG_NOISE["theta"] and meas["Omega2"] == LQG_NOISE["Omega2"]
    meas, proc = lqg_filter_noise(LQG_SENSORS, {"z": 0.3}, measurement_noise={"z": 0.01}, process_noise={"m0": 1e-3})
    assert meas["z"] == 0.01 and proc["m0"] == 1e-3 and proc["v1"] == LQG_PROCESS_NOISE["v1"]
    with pytest.raises(gc.ArgumentError, match="not sensors"):
        lqg_filter_noise(LQG_SENSORS, measurement_noise={"m0": 0.1})
    with pytest.raises(gc.ArgumentError, match="not states"):
        lqg_filter_noise(LQG_SENSORS, process_noise={"depth": 0.1})
    with pytest.raises(gc.ArgumentError, match="must lie in"):
        lqg_filter_noise(LQG_SENSORS, process_noise={"m0": 0.0})
    with pytest.raises(gc.ArgumentTypeError, match="mapping"):
        lqg_filter_noise(LQG_SENSORS, measurement_noise=0.1)


def test_dive_cycle_flies_the_filter_weights_it_is_given():
    base = gc.dive_cycle(VEH, "lqg", seed=5, **SHORT)
    same = gc.dive_cycle(VEH, "lqg", seed=5, measurement_noise=dict(LQG_NOISE), process_noise=LQG_PROCESS_NOISE,
                         **SHORT)
    np.testing.assert_array_equal(base.x, same.x)  # the defaults are these
    # the same simulated noise (same seed) with the former filter (process noise a tenth of each state's Bryson
    # scale per root second, as if the model were that uncertain): the filter follows the noise, and the pump with it
    former = {"theta": 0.01, "Omega2": 0.02, "v1": 0.005, "v3": 0.005, "r_P1": 0.002, "rdot_P1": 0.002, "m0": 0.01,
              "z": 0.05}
    jumpy = gc.dive_cycle(VEH, "lqg", seed=5, process_noise=former, **SHORT)
    assert jumpy.as_dict()["energy_per_cycle"] > 2 * base.as_dict()["energy_per_cycle"]
    assert jumpy.as_dict()["saturated_time_per_cycle"] > 1.5 * base.as_dict()["saturated_time_per_cycle"]
    # without simulated noise the filter keeps its default weights and the run draws no noise
    quiet = gc.dive_cycle(VEH, "lqg", noise={}, **SHORT)
    assert quiet.seed is None and quiet.as_dict()["max_overshoot"] < 3.0
    with pytest.raises(gc.ArgumentError, match="not sensors"):
        gc.dive_cycle(VEH, "lqg", measurement_noise={"m0": 0.1}, **SHORT)
    with pytest.raises(gc.ArgumentError, match="not states"):
        gc.compare_missions(VEH, ("lqr", "lqg"), process_noise={"depth": 0.1}, **SHORT)


def test_default_lqg_does_not_chatter_on_the_sensor_noise():
    # same mission, noise-free "lqr" (every state measured) against the default "lqg" (noisy depth, pitch, rate):
    # the regulator is the same, so a filter that does not pass the noise to the actuators saturates them about as
    # long as the LQR (at the inflections) and spends about its pump energy; a filter weighted by the noise alone
    # (the former default) saturated them three times as long and spent three times the energy
    lqr = gc.dive_cycle(VEH, "lqr", **SHORT).as_dict()
    for seed in (0, 1):
        lqg = gc.dive_cycle(VEH, "lqg", seed=seed, **SHORT).as_dict()
        assert lqg["saturated_time_per_cycle"] <= 1.25 * lqr["saturated_time_per_cycle"]
        assert lqg["energy_per_cycle"] <= 1.5 * lqr["energy_per_cycle"]
        assert lqg["max_overshoot"] < 2 * lqr["max_overshoot"]


# ------------------------------------------------------------------------------------------------ sampled-data runs
def test_sampled_controller_is_sampled_every_period_and_holds_its_command(design):
    plant = gc.ActuatedGlider(VEH)

    class Counter:
        controller_states = ("samples", "held")
        command = "rate"

        def initial_state(self, t, y):
            return np.zeros(2)

        def derivative(self, t, xc, y):
            return np.zeros(2)

        def sample(self, t, xc, y):
            return np.array([xc[0] + 1.0, -1e-4 * (1 + (round(t) % 3))])

        def __call__(self, t, y, xc):
            return np.array([0.0, 0.0, xc[1]])

    te = np.linspace(0.0, 10.0, 41)
    run = gc.simulate_actuated(plant, GLIDE.accel_state(), 10.0, Counter(), sensor_period=2.0, t_eval=te)
    assert run.sensor_period == 2.0 and run.seed is None
    # samples at 0, 2, 4, 6, 8 (no noise needed); the command is constant between samples and jumps at them
    np.testing.assert_array_equal(run.xc[:, 0], np.minimum(np.floor(te / 2.0) + 1, 5))
    for k in range(5):
        inside = (te >= 2 * k) & (te < 2 * k + 2)
        assert np.ptp(run.u[inside, 2]) == 0.0 and run.u[inside, 2][0] == -1e-4 * (1 + (2 * k) % 3)


def test_sampled_lqg_estimate_converges_on_the_nonlinear_plant(design):
    # the estimate starts 0.02 kg, 2 mm and 2 deg off in pump mass, battery and pitch; noise-free sensors sampled
    # every second: the error decays at least as fast as the slowest sampled estimator pole allows
    plant = gc.ActuatedGlider(VEH)
    sd = design.sampled(1.0)
    x0 = GLIDE.accel_state(0.0, 20.0)
    xh0 = x0.copy()
    xh0[[2, 6, 10]] += (math.radians(2.0), 0.002, 0.02)
    ctrl = SampledGlideLQG(sd, plant, x0, x0, 0.0, 0.0, (0, 1, 2), xh0)
    te = np.arange(0.0, 301.0, 1.0)
    run = gc.simulate_actuated(plant, x0, 300.0, ctrl, sensors=LQG_SENSORS, sensor_period=1.0, t_eval=te,
                               rtol=1e-8, atol=1e-10)
    err = run.xc[:, :11] - run.x
    idx = [2, 3, 4, 5, 6, 7, 10]  # theta, Omega2, v1, v3, r_P1, rdot_P1, m0
    rho = np.max(np.abs(sd.estimator_poles))
    assert np.all(np.abs(err[-1, idx]) <= np.abs(err[0, idx]).max() * rho ** 300 * 5 + 1e-6)
    assert abs(err[-1, 10]) < 0.1 * abs(err[0, 10])
    assert run.x[-1, 10] == pytest.approx(GLIDE.m0, abs=0.01) and run.x[-1, 6] == pytest.approx(GLIDE.r_p1, abs=1e-3)
    with pytest.raises(gc.ArgumentError, match="14 controller states"):
        ctrl.with_estimate(np.zeros(5))
    with pytest.raises(gc.ArgumentTypeError, match="SampledLQG"):
        SampledGlideLQG(design, plant, x0, x0)


def test_analog_lqg_flies_like_the_sampled_one_without_noise():
    """sensor_period = 0 flies the continuous filter; on noise-free sensors its cycles match the 1-s sampled
    filter's to the effect of the sampling (a 1 s hold against minute-long legs)."""
    analog = gc.dive_cycle(VEH, "lqg", noise={}, sensor_period=0.0, cycles=1)
    sampled = gc.dive_cycle(VEH, "lqg", noise={}, sensor_period=1.0, cycles=1)
    a, s = analog.as_dict(), sampled.as_dict()
    assert a["distance_per_cycle"] == pytest.approx(s["distance_per_cycle"], rel=0.01)
    assert a["duration_per_cycle"] == pytest.approx(s["duration_per_cycle"], rel=0.01)
    with pytest.raises(gc.ArgumentError, match="cannot be noisy"):
        gc.dive_cycle(VEH, "lqg", sensor_period=0.0)
