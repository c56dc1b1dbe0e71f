"""Missions (glidectl.missions): waypoints in a current with surfacings, dead reckoning and the current estimate;
energy against a hand integral; determinism; bad input."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest

import glidectl as gc
from glidectl.controllers.dive_cycle import P_ATM
from glidectl.errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError, ModelError
from glidectl.missions import current_corrected_heading, dead_zone, wrap_angle

matplotlib.use("Agg")

SLOCUM = gc.load_vehicle("slocum_shallow")
ROLLER = SLOCUM.with_actuators(rudder=None, roll={"min": -0.6, "max": 0.6, "rate": 0.1, "unit": "rad",
                                                  "source": "test"})
SHORT = gc.Mission(waypoints=[(1500.0, 0.0)], depths=(5.0, 40.0), surface_time=120.0, arrival_radius=80.0)


@pytest.fixture(scope="module")
def crossing():
    """One leg east across a northward current: the first dive dead-reckons without the current."""
    return gc.fly_mission(SLOCUM, SHORT, current=(0.0, 0.08))


def test_first_dive_dead_reckoning_error_is_the_current_times_the_dive_time(crossing):
    d = crossing.dives[0]
    # the glider knows no current before its first fix: its dead reckoning misses c * T
    assert d.dead_reckoning_error == pytest.approx(0.08 * d.duration, rel=0.03)
    # the estimate is the current plus the dead reckoning's own speed error (the designed glide's angle of attack
    # stands for the whole dive, start from rest included): a few percent of the glider's speed, along its track
    assert d.current_estimate[1] == pytest.approx(0.08, abs=0.003)
    assert abs(d.current_estimate[0]) < 0.03 * SHORT.speed
    # later dives correct for the estimate: their error is a small fraction of the first
    assert max(x.dead_reckoning_error for x in crossing.dives[1:]) < 0.1 * d.dead_reckoning_error


def test_leg_arrives_and_corrects_its_heading_for_the_current(crossing):
    leg = crossing.legs[0]
    assert leg.arrived and leg.reason == "arrived"
    assert leg.arrival_error <= SHORT.arrival_radius * 1.2
    assert leg.current_estimate[1] == pytest.approx(0.08, abs=0.005)
    # with the estimate the glider crabs to the south of east: the last dive's mean heading is past 90 deg
    last = (crossing.t >= crossing.dives[-1].start) & (crossing.phase != 0)
    assert np.degrees(np.mean(crossing.heading[last])) > 95.0
    assert leg.distance_made_good == pytest.approx(1500.0 - leg.arrival_error, abs=1e-6)


def test_pump_energy_of_a_dive_is_the_hand_integral(crossing):
    """The pump pushes (m0_down - m0_up) / rho of oil out at the bottom inflection, against p(z): the sum of
    p(z) (-dm0) / (rho eta) over the recorded samples (a Stieltjes sum on the pump's position, not on its rate)."""
    plan = gc.DivePlan(gc.ActuatedGlider3D(SLOCUM), SHORT.gamma, SHORT.speed)
    d = crossing.dives[1]
    rho, eta = float(SLOCUM.water_density(0.0)), SLOCUM.params["pump_efficiency"]
    sel = (crossing.t >= d.start) & (crossing.t <= d.end)
    z = crossing.position[sel, 2]
    dm0 = np.diff(crossing.actuator("m0")[sel])
    out = dm0 < 0
    assert -dm0[out].sum() == pytest.approx(plan.down.m0 - plan.up.m0, rel=1e-3)
    hand = np.sum((P_ATM + rho * SLOCUM.g * 0.5 * (z[1:] + z[:-1])[out]) * -dm0[out]) / rho / eta
    assert d.energy == pytest.approx(hand, rel=5e-3)
    assert crossing.legs[0].energy == pytest.approx(sum(x.energy for x in crossing.dives), rel=1e-9)


def test_actuators_stay_in_range_and_depths_follow_the_mission(crossing):
    plant = crossing.plant
    for i, name in enumerate(plant.actuator_names):
        v = crossing.actuator(name)
        assert np.all(v >= plant.lower[i] - 1e-9) and np.all(v <= plant.upper[i] + 1e-9), name
    for d in crossing.dives:
        assert 0.0 <= d.overshoot < 5.0
    assert np.all(crossing.position[:, 2] >= -1e-6)


def test_hotel_power_adds_its_energy_and_a_field_current_equals_the_uniform_one(crossing):
    again = gc.fly_mission(SLOCUM, SHORT, current=gc.Current.field(lambda t, p: (0.0, 0.08)), hotel_power=0.5)
    leg, leg0 = again.legs[0], crossing.legs[0]
    assert leg.duration == pytest.approx(leg0.duration, rel=1e-6)
    assert leg.energy == pytest.approx(leg0.energy + 0.5 * leg0.duration, rel=1e-6)


def test_roll_steering_flies_the_leg():
    run = gc.fly_mission(ROLLER, SHORT, current=(0.0, 0.05), steer="roll")
    assert run.legs[0].arrived
    assert np.max(np.abs(run.actuator("roll"))) > 0.01 and np.all(run.actuator("rudder") == 0.0)


def test_unreachable_waypoint_ends_the_leg_with_a_reason():
    m = gc.Mission(waypoints=[(0.0, 3000.0), (500.0, 0.0)], depths=(5.0, 30.0), surface_time=60.0)
    run = gc.fly_mission(SLOCUM, m, current=(0.0, -0.6))
    assert run.legs[0].reason.startswith("unreachable") and "m/s" in run.legs[0].reason
    assert len(run.dives) <= 4


def test_runs_are_deterministic_for_a_seed():
    kw = dict(current=(0.05, 0.0), gps_noise=10.0)
    a = gc.fly_mission(SLOCUM, SHORT, seed=3, **kw)
    b = gc.fly_mission(SLOCUM, SHORT, seed=3, **kw)
    c = gc.fly_mission(SLOCUM, SHORT, seed=4, **kw)
    np.testing.assert_array_equal(a.states, b.states)
    assert a.dives[0].fix.tolist() != c.dives[0].fix.tolist()


def test_run_accessors_and_plots(crossing):
    assert crossing.position.shape == (crossing.t.size, 3)
    assert np.all(np.diff(crossing.t) >= 0)
    np.testing.assert_array_equal(crossing.position[:, 0], crossing.state("y"))
    axes = crossing.plot()
    assert len(axes) == 3 and axes[0].get_xlabel() == "east [km]"
    ax3 = crossing.plot_3d()
    assert ax3.name == "3d"
    table = crossing.table()
    assert "arrived" in table and crossing.summary().startswith("slocum_shallow")
    d = crossing.as_dict()
    assert d["legs"][0]["reason"] == "arrived" and d["dives"] == len(crossing.dives)
    with pytest.raises(ArgumentError, match="unknown actuator"):
        crossing.actuator("elevator")


def test_guidance_helpers():
    assert wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    np.testing.assert_allclose(dead_zone(np.array([-0.3, 0.05, 0.2]), 0.1), [-0.2, 0.0, 0.1])
    # no current: head straight for the target; cross current: crab into it
    assert current_corrected_heading([0, 0], [1000, 0], [0, 0], 0.3) == pytest.approx(math.pi / 2)
    h = current_corrected_heading([0, 0], [1000, 0], [0, 0.1], 0.3)
    assert math.sin(h) * 0.3 > 0 and math.cos(h) * 0.3 == pytest.approx(-0.1)


@pytest.mark.parametrize(("kwargs", "err", "match"), [
    (dict(waypoints=[]), ArgumentError, "at least one"),
    (dict(waypoints=[(0.0, np.nan)]), ArgumentError, "finite"),
    (dict(waypoints=[(100.0, 0.0), (100.0, 0.0)]), ArgumentError, "same point"),
    (dict(waypoints=[(100.0, 0.0)], depths=(50.0, 10.0)), ArgumentError, "top < bottom"),
    (dict(waypoints=[(100.0, 0.0)], gamma=0.0), ArgumentError, "gamma"),
    (dict(waypoints=[(100.0, 0.0)], arrival_radius=-1.0), ArgumentError, "arrival_radius"),
])
def test_bad_missions_are_refused(kwargs, err, match):
    with pytest.raises(err, match=match):
        gc.Mission(**kwargs)


def test_bad_flights_are_refused():
    deep = gc.Mission(waypoints=[(1000.0, 0.0)], depths=(5.0, 500.0))
    with pytest.raises(InfeasibleGlideError, match="depth rating"):
        gc.fly_mission(SLOCUM, deep)
    with pytest.raises(ModelError, match="heading actuator"):
        gc.fly_mission(SLOCUM.with_actuators(rudder=None), SHORT)
    with pytest.raises(ModelError, match="no moving \\[actuators\\] roll"):
        gc.fly_mission(SLOCUM, SHORT, steer="roll")
    with pytest.raises(ArgumentTypeError, match="Mission"):
        gc.fly_mission(SLOCUM, {"waypoints": [(1, 2)]})
    with pytest.raises(ArgumentTypeError, match="rates"):
        gc.fly_mission(SLOCUM, SHORT, controller=object())
    with pytest.raises(InfeasibleGlideError, match="outside the range"):
        gc.fly_mission(SLOCUM, gc.Mission(waypoints=[(1000.0, 0.0)], depths=(5.0, 40.0), gamma=0.6, speed=0.6))


def _circle_radius(xy: np.ndarray) -> float:
    """Least-squares circle through horizontal positions (m)."""
    A = np.c_[2 * xy, np.ones(len(xy))]
    sol, *_ = np.linalg.lstsq(A, (xy ** 2).sum(1), rcond=None)
    return math.sqrt(sol[2] + sol[0] ** 2 + sol[1] ** 2)


def test_design_turn_meets_the_radius_and_refuses_what_no_setting_reaches():
    d = gc.design_turn(SLOCUM, 150.0)
    assert d.steer == "rudder" and d.direction == 1
    for p in (1, -1):
        assert d.helices[p].radius == pytest.approx(150.0, rel=1e-8)
        assert d.helices[p].stable and d.helices[p].psidot > 0
        assert abs(d.settings[p]) <= 0.45
    with pytest.raises(InfeasibleGlideError, match="tightest stable turn"):
        gc.design_turn(SLOCUM, 50.0)
    with pytest.raises(ModelError, match="heading actuator"):
        gc.design_turn(SLOCUM.with_actuators(rudder=None), 150.0)


@pytest.mark.parametrize(("veh", "radius"), [(ROLLER, 200.0), (SLOCUM, 150.0)], ids=["roll", "rudder"])
def test_the_mission_flies_a_designed_turn(veh, radius):
    """A spiral: the behaviours hold the designed setting; the dive's steady part turns on the designed radius."""
    d = gc.design_turn(veh, radius, gamma=math.radians(25.0), speed=0.35)
    m = gc.Mission(waypoints=[(1e5, 0.0)], depths=(5.0, 150.0))
    run = gc.fly_mission(veh, m, controller=gc.GliderBehaviours(turn=d, pitch_deadband=0.0), duration=900.0)
    z = run.position[:, 2]
    steady = (run.phase == 1) & (z > 60.0) & (z < 140.0)
    assert _circle_radius(run.position[steady, :2]) == pytest.approx(radius, rel=0.02)
    with pytest.raises(ArgumentError, match="designed for another glide"):
        gc.fly_mission(veh, gc.Mission(waypoints=[(1e5, 0.0)], speed=0.3), controller=gc.GliderBehaviours(turn=d))


def test_lqr_dive_controller_flies_the_mission_within_the_limits():
    run = gc.fly_mission(SLOCUM, SHORT, controller="lqr", current=(0.0, 0.05))
    assert run.controller == "lqr" and run.legs[0].arrived
    plant = run.plant
    for i, name in enumerate(plant.actuator_names):
        v = run.actuator(name)
        assert np.all(v >= plant.lower[i] - 1e-9) and np.all(v <= plant.upper[i] + 1e-9), name
    # between inflections the LQR holds the designed glide: pitch within a degree over the dives' middle thirds
    plan = gc.DivePlan(plant, SHORT.gamma, SHORT.speed)
    z = run.position[:, 2]
    mid = (run.phase == 1) & (z > 15.0) & (z < 30.0)
    assert np.max(np.abs(np.degrees(run.pitch[mid] - plan.down.theta))) < 1.0
    with pytest.raises(ArgumentError, match="prepare"):
        gc.DiveLQR().rates(plant, plan, run.states[0, :19], 1, 0.0)


@pytest.fixture(scope="module")
def box_runs():
    """The same two-leg mission in a sheared current with the full and the fast model."""
    m = gc.Mission(waypoints=[(1500.0, 0.0), (1500.0, 1500.0)], depths=(5.0, 60.0), surface_time=120.0)
    cur = gc.Current.profile([0.0, 60.0], [0.10, 0.02], [0.05, 0.0])
    return m, gc.fly_mission(SLOCUM, m, current=cur), gc.fly_mission(SLOCUM, m, current=cur, model="fast")


def test_fast_model_flies_the_mission_like_the_full_one(box_runs):
    from glidectl.missions.fast import calibrate_dive, replay_errors

    m, full, fast = box_runs
    assert [leg.reason for leg in fast.legs] == [leg.reason for leg in full.legs] == ["arrived", "arrived"]
    for a, b in zip(full.legs, fast.legs, strict=True):
        assert b.duration == pytest.approx(a.duration, rel=0.15)
    assert fast.energy_per_km == pytest.approx(full.energy_per_km, rel=0.15)
    # per dive, from the full model's own dive starts (dives without a waypoint switch under water): the replayed
    # dive surfaces within a few percent of the dive's horizontal displacement of the full model's fix
    plan = gc.DivePlan(full.plant, m.gamma, m.speed)
    prof = calibrate_dive(full.plant, plan, gc.GliderBehaviours(), m.depths)
    assert prof.duration == pytest.approx(full.dives[0].duration, rel=1e-3)   # still water, straight: the same dive
    rel = replay_errors(full)[:, 1]
    assert len(rel) >= 3 and float(np.median(rel)) < 0.05
    # the fast run's samples carry the calibrated attitude and actuators: limits hold there too
    for i, name in enumerate(fast.plant.actuator_names):
        v = fast.actuator(name)
        assert np.all(v >= fast.plant.lower[i] - 1e-9) and np.all(v <= fast.plant.upper[i] + 1e-9)
    with pytest.raises(ArgumentError, match="model"):
        gc.fly_mission(SLOCUM, m, model="kinematic")


def test_a_run_that_ends_at_the_surface_stops_there():
    m = gc.Mission(waypoints=[(5000.0, 0.0)], depths=(5.0, 40.0), surface_time=600.0)
    first = gc.fly_mission(SLOCUM, m, model="fast", duration=3000.0).dives[0]
    for model in ("fast", "full"):
        run = gc.fly_mission(SLOCUM, m, model=model, duration=first.end + 100.0)   # inside the surface interval
        assert run.t[-1] <= first.end + 100.0 + 1e-6 and run.ended_by == "duration"
