"""Dive cycles: exact mission metrics on synthetic cases, inflections at the depth limits, the controllers, and bad
inputs."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import glidectl as gc
from glidectl.controllers.dive_cycle import P_ATM, RHO_SEAWATER, _cycle_metrics

ACTS = {"m0": {"min": -0.8, "max": 0.8, "rate": 0.02}, "r_P1": {"min": -0.04, "max": 0.04, "rate": 0.005},
        "r_P3": {"fixed": 0.02}}
DEPTHS = (5.0, 15.0)


@pytest.fixture(scope="module")
def veh():
    return gc.load_vehicle("rogue").with_actuators(**ACTS)


@pytest.fixture(scope="module")
def lqr_run(veh):
    return gc.dive_cycle(veh, "lqr", depths=DEPTHS, gamma=math.radians(25), speed=0.35, cycles=1)


# ------------------------------------------------------------------------------------------------ energy
@pytest.mark.parametrize("eta", [1.0, 0.5])
def test_pump_energy_constant_rate_at_constant_depth_is_exact(eta):
    t = np.linspace(0.0, 20.0, 7)
    z = np.full_like(t, 50.0)
    rate = np.full_like(t, -0.01)  # pumping out 0.01 kg/s: the displaced volume grows 0.01/rho m^3/s
    g = 9.81
    exact = (P_ATM + RHO_SEAWATER * g * 50.0) * (0.01 / RHO_SEAWATER) * 20.0 / eta
    assert gc.pump_energy(t, z, rate, efficiency=eta, g=g) == pytest.approx(exact, rel=1e-13)
    # letting oil back in is driven by the sea pressure: not counted by default, counted with pump_work="both"
    assert gc.pump_energy(t, z, -rate, efficiency=eta, g=g) == 0.0
    assert gc.pump_energy(t, z, -rate, efficiency=eta, g=g, pump_work="both") == pytest.approx(exact, rel=1e-13)


def test_pump_energy_linear_depth_is_exact():
    # constant rate while descending at constant speed: p(z) linear in t, the trapezoid rule is exact
    t = np.linspace(0.0, 100.0, 11)
    z = 0.2 * t
    rate = np.full_like(t, -0.005)
    exact = (P_ATM * 100.0 + RHO_SEAWATER * 9.8 * 0.2 * 100.0**2 / 2) * 0.005 / RHO_SEAWATER
    assert gc.pump_energy(t, z, rate, g=9.8) == pytest.approx(exact, rel=1e-13)


def test_pump_energy_bad_inputs():
    t = np.arange(3.0)
    with pytest.raises(gc.ArgumentError):
        gc.pump_energy(t, t[:2], t)
    with pytest.raises(gc.ArgumentError):
        gc.pump_energy(t, t, t, efficiency=1.5)
    with pytest.raises(gc.ArgumentError):
        gc.pump_energy(t[::-1], t, t)
    with pytest.raises(gc.ArgumentError):
        gc.pump_energy(t, t, t, pump_work="in")


# ------------------------------------------------------------------------------------------------ metrics
def test_cycle_metrics_on_a_constructed_sawtooth():
    # two cycles, each: down 0 -> 100 s (5 -> 105 m), bottom overshoot 2 m, up 100 -> 200 s, top overshoot 1 m
    top, bottom = 5.0, 100.0
    t = np.linspace(0.0, 450.0, 4501)
    z = np.empty_like(t)
    for k, tk in enumerate(t):
        s = tk % 200.0
        z[k] = 5.0 + 97.0 * math.sin(math.pi * s / 200.0) if tk < 400 else 5.0 - 1.0 * math.sin(
            math.pi * (tk - 400) / 100.0)
    sw = [0.0, 0.0, 200.0, 200.0, 400.0]  # placeholder, replaced below by the crossing times
    # crossings of the limits: z = 100 at sin = 95/97
    a = math.asin(95.0 / 97.0) * 200.0 / math.pi
    sw = [0.0, a, 200.0, 200.0 + a, 400.0]
    x = 0.3 * t  # constant horizontal speed
    rate = np.where((t % 200.0) < 50.0, -0.01, 0.0)  # pumping out during the first 50 s of each cycle
    sat = ((t % 200.0) >= 10.0) & ((t % 200.0) < 30.0)  # 20 s saturated per cycle
    mets = _cycle_metrics(t, x, z, rate, sat.astype(float), sw, (top, bottom), efficiency=1.0, rho=RHO_SEAWATER,
                          p_atm=P_ATM, g=9.81, pump_work="out")
    assert len(mets) == 2
    for k, m in enumerate(mets):
        assert m.t_start == 200.0 * k and m.t_end == 200.0 * (k + 1)
        assert m.duration == 200.0
        assert m.distance == pytest.approx(60.0, rel=1e-12)
        assert m.overshoot[0] == pytest.approx(2.0, abs=1e-6)  # peak 102 m
        assert m.saturated_time == pytest.approx(20.0, abs=0.11)  # sampled every 0.1 s
        sel = (t >= 200.0 * k) & (t <= 200.0 * (k + 1))
        assert m.energy == pytest.approx(gc.pump_energy(t[sel], z[sel], rate[sel]), rel=1e-12)
    assert mets[0].overshoot[1] == pytest.approx(0.0, abs=1e-6)  # the second cycle starts at 5 m going down
    assert mets[1].overshoot[1] == pytest.approx(1.0, abs=1e-6)  # the tail climbs to 4 m


# ------------------------------------------------------------------------------------------------ missions
def test_lqr_mission_switches_at_the_depth_limits(lqr_run):
    run = lqr_run
    top, bottom = DEPTHS
    assert run.switch_times[0] == 0.0 and np.all(np.diff(run.switch_times) > 0)
    assert len(run.switch_times) == 3 and len(run.cycles) == 1
    # no noise: the measured depth is the depth, and the switch happens where it reaches the limit
    np.testing.assert_allclose(run.switch_depths, (top, bottom, top), atol=1e-6)
    i = np.searchsorted(run.t, run.switch_times[1])
    assert np.all(run.depth[: i - 1] < bottom)
    c = run.cycles[0]
    assert c.duration == pytest.approx(run.switch_times[2] - run.switch_times[0])
    assert c.distance == pytest.approx(np.interp(run.switch_times[2], run.t, run.x[:, 0]))
    # before the bottom inflection the glider flies the requested down glide: path angle gamma, speed 0.35 m/s
    tb = run.switch_times[1]
    k0, k1 = np.searchsorted(run.t, tb - 30.0), np.searchsorted(run.t, tb - 10.0)
    dx, dz = run.x[k1, 0] - run.x[k0, 0], run.depth[k1] - run.depth[k0]
    assert math.atan2(dz, dx) == pytest.approx(run.gamma, abs=math.radians(0.5))
    assert math.hypot(dx, dz) / (run.t[k1] - run.t[k0]) == pytest.approx(0.35, rel=0.02)
    assert c.distance > 2 * (bottom - top) / math.tan(run.gamma)  # the inflections glide flatter
    assert 0.0 <= c.overshoot[0] < 5.0 and 0.0 <= c.overshoot[1] < 5.0
    assert c.energy > 0 and c.saturated_time >= 0
    assert run.pump_efficiency == 1.0 and "not in the vehicle file" in run.efficiency_source
    for k, name in enumerate(run.actuator_names):
        p = run.actuator(name)
        assert np.all(p >= run.lower[k] - 1e-8) and np.all(p <= run.upper[k] + 1e-8)
    # one design per leg: the down leg regulates to the down glide, the up leg to the up glide
    g_down, g_up = run.glides
    assert g_down.gamma < 0 < g_up.gamma
    assert run.actuator("m0")[k1] == pytest.approx(g_down.m0, rel=0.02)
    assert run.actuator("r_P1")[k1] == pytest.approx(g_down.r_p1, rel=0.02)
    assert run.actuator("m0", commanded=True).shape == run.t.shape


def test_mission_plot_and_summary(lqr_run):
    import matplotlib.pyplot as plt

    axes = lqr_run.plot()
    fig = axes[0].figure
    assert len(axes) == 4 and len(fig.axes) == 4 and axes[1].get_ylabel().endswith("[deg]")
    plt.close(fig)
    assert "cycle 0" in lqr_run.summary()
    row = lqr_run.as_dict()
    assert row["controller"] == "lqr" and row["cycles"] == 1


def test_comparison_table_gives_a_refused_controller_a_row(veh, lqr_run):
    cmp = gc.compare_missions(veh, ("nonlinear",), depths=DEPTHS)
    assert [r["controller"] for r in cmp.rows] == ["nonlinear"]
    assert "chapter-6" in cmp.rows[0]["error"] and math.isnan(cmp.rows[0]["energy_per_cycle"])
    assert "| nonlinear |" in cmp.table()


def test_bad_inputs(veh):
    with pytest.raises(gc.ArgumentError, match="top < bottom"):
        gc.dive_cycle(veh, depths=(100.0, 5.0))
    with pytest.raises(gc.ArgumentError):
        gc.dive_cycle(veh, speed=-0.35)
    with pytest.raises(gc.ArgumentError):
        gc.dive_cycle(veh, gamma=0.0)
    with pytest.raises(gc.ArgumentError, match="lqr"):
        gc.dive_cycle(veh, "mpc")
    with pytest.raises(gc.ArgumentError, match="unobservable"):
        gc.dive_cycle(veh.with_actuators(r_P3={"min": 0.0, "max": 0.04, "rate": 0.005}), "lqg")  # w3 moves too
    with pytest.raises(gc.ModelError, match="actuators"):
        gc.dive_cycle(gc.load_vehicle("rogue"))
    with pytest.raises(gc.ModelError, match="chapter-6"):
        gc.dive_cycle(veh, "nonlinear")
    with pytest.raises(gc.ArgumentError, match="'z'"):
        gc.dive_cycle(veh, "pid", sensors=("theta", "Omega2"))
    with pytest.raises(gc.ArgumentError, match="every state"):
        gc.dive_cycle(veh, "lqr", sensors=("z", "theta"))
    with pytest.raises(gc.InfeasibleGlideError, match="range"):
        gc.dive_cycle(veh, speed=0.6)  # the glide needs more pump than 0.8 kg
    with pytest.raises(gc.ArgumentTypeError):
        gc.dive_cycle(veh, depths=5.0)


def test_tuned_pitch_pid_stabilizes_the_linearized_full_pump_glide(veh):
    plant = gc.ActuatedGlider(veh)
    for gamma in (-math.radians(25), math.radians(25)):
        g = gc.steady_glide(veh, 0.4, gamma, r_p3=0.02)
        kp, ki, _kd, margin = gc.tune_pitch_pid(plant, g)
        assert margin < 0
        assert ki == pytest.approx(kp / 20.0)
    with pytest.raises(gc.ArgumentTypeError):
        gc.tune_pitch_pid(veh, g)


def test_scheduled_lqr_reference_ramps_between_the_glides(veh):
    run_glides = [gc.steady_glide(veh, 0.35, s * math.radians(25), r_p3=0.02) for s in (1, -1)]
    xf, xt = run_glides[0].accel_state(), run_glides[1].accel_state()
    ctrl = gc.ScheduledGlideLQR(np.zeros((3, 11)), xf, xt, 10.0, 50.0, run_glides[1], np.array([-1.0]))
    x_mid, w_mid = ctrl.reference(35.0)
    np.testing.assert_allclose(x_mid[[2, 6, 10]], 0.5 * (xf + xt)[[2, 6, 10]], rtol=1e-12)
    assert x_mid[7] == pytest.approx((xt[6] - xf[6]) / 50.0) and w_mid[2] == pytest.approx((xt[10] - xf[10]) / 50.0)
    x_end, w_end = ctrl.reference(70.0)
    np.testing.assert_array_equal(x_end, xt)
    assert np.all(w_end == 0) and np.all(ctrl(70.0, xt) == 0)


# ------------------------------------------------------------------------------------------------ LQG, LQR design
def test_mission_lqr_gain_is_the_regulator_of_lqg_glide(veh):
    # one LQR computation: the mission's leg gain equals lqg_glide's regulator (same weights, same z'-free states)
    from glidectl.controllers.dive_cycle import LQG_NOISE, LQG_SENSORS, _lqr_gain

    g = gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=0.02)
    K, poles, states, inputs = _lqr_gain(veh, gc.ActuatedGlider(veh), g, None)
    d = gc.lqg_glide(veh, g, LQG_SENSORS, LQG_NOISE, inputs="acceleration")
    assert inputs == d.actuate == ("w1", "w4") and set(states) == set(d.regulated_states)
    lqg = gc.ScheduledGlideLQG(d, gc.ActuatedGlider(veh), g.accel_state(), g.accel_state(), 0.0, 0.0, (0, 1, 2))
    np.testing.assert_allclose(K, lqg._mats[0], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(np.sort_complex(poles), np.sort_complex(d.regulator_poles), rtol=1e-9)
    assert np.all(K[1] == 0)  # r_P3 is fixed: no w3


def test_lqg_estimate_converges_on_the_nonlinear_plant(veh):
    # start the estimate 0.1 kg and 1 cm off in the unmeasured pump mass and battery position, 2 deg off in pitch:
    # with noise-free sensors the estimate converges to the true state of the steady glide
    from glidectl.controllers.dive_cycle import LQG_NOISE, LQG_SENSORS

    plant = gc.ActuatedGlider(veh)
    g = gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=0.02)
    d = gc.lqg_glide(veh, g, LQG_SENSORS, LQG_NOISE, inputs="acceleration")
    assert np.max(d.estimator_poles.real) < 0
    x0 = g.accel_state(0.0, 10.0)
    xh0 = x0.copy()
    xh0[[2, 6, 10]] += (math.radians(2.0), 0.01, 0.1)
    ctrl = gc.ScheduledGlideLQG(d, plant, x0, x0, 0.0, 0.0, (0, 1, 2), xh0)
    run = gc.simulate_actuated(plant, x0, 300.0, ctrl, sensors=LQG_SENSORS, rtol=1e-7, atol=1e-9,
                               t_eval=np.linspace(0.0, 300.0, 301))
    err = run.xc - run.x
    idx = [2, 3, 4, 5, 6, 7, 10]  # theta, Omega2, v1, v3, r_P1, rdot_P1, m0
    assert abs(err[0, 10]) == pytest.approx(0.1)
    slowest = np.max(d.estimator_poles.real)  # the pump-mass mode: e-folds in 1/|slowest| s
    assert np.all(np.abs(err[-1, idx]) <= np.abs(err[0, idx]).max() * math.exp(slowest * 300.0) * 5 + 1e-6)
    assert abs(err[-1, 10]) < 0.1 * abs(err[0, 10])
    # and the controller brings the glider back to the glide (actuators within their limits)
    assert run.x[-1, 10] == pytest.approx(g.m0, abs=0.02) and run.x[-1, 6] == pytest.approx(g.r_p1, abs=2e-3)


def test_lqg_mission_flies_on_noisy_depth_pitch_and_rate(veh):
    run = gc.dive_cycle(veh, "lqg", depths=(5.0, 10.0), cycles=1, seed=3, sensor_period=5.0)
    assert run.sensors == ("z", "theta", "Omega2") and run.seed == 3
    top, bottom = 5.0, 10.0
    # the supervisor switches on the measured (noisy, sigma 5 cm) depth: the true depth is near the limit
    np.testing.assert_allclose(run.switch_depths, (top, bottom, top), atol=0.3)
    c = run.cycles[0]
    assert np.isfinite([c.distance, c.duration, c.energy]).all() and c.energy > 0
    assert c.distance > 2 * (bottom - top) / math.tan(run.gamma)
    for k, name in enumerate(run.actuator_names):
        p = run.actuator(name)
        assert np.all(p >= run.lower[k] - 1e-8) and np.all(p <= run.upper[k] + 1e-8)


def test_nonlinear_leg_design_holds_its_glide():
    # the chapter-6 controller applies to the chapter-5 sphere given a moving mass (mbar = 1 kg): each leg's
    # battery and pump commands at the leg's glide are the glide's own (the glide is an equilibrium of the loop)
    from glidectl.controllers.dive_cycle import _nonlinear_designs

    v = gc.load_vehicle("sphere_ch5", mbar=1.0).with_actuators(
        r_P1={"min": -0.05, "max": 0.05, "rate": 0.005}, r_P3={"fixed": 0.0})
    legs = _nonlinear_designs(v, gc.ActuatedGlider(v), math.radians(25), 0.3, 0.0)
    for sign, leg in zip((-1, 1), legs, strict=True):
        g = gc.steady_glide(v, 0.3, sign * math.radians(25), r_p3=0.0)
        assert leg.m0e == pytest.approx(g.m0, rel=1e-9)
        cmd = leg(0.0, g.accel_state())
        assert cmd["r_P1"] == pytest.approx(g.r_p1, rel=1e-9) and cmd["m0"] == pytest.approx(g.m0, rel=1e-12)
