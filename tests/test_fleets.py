"""Fleets (glidectl.fleets): the formation's potentials and slots, a fleet run whose spacing follows the schedule,
serial and parallel runs equal, bad input."""

from __future__ import annotations

import itertools
import math
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import glidectl as gc
from glidectl.errors import ArgumentError, ArgumentTypeError, InfeasibleGlideError
from glidectl.fleets import shape_offsets

SLOCUM = gc.load_vehicle("slocum_shallow")
DIVES = gc.Mission(waypoints=[(1.0, 0.0)], depths=(5.0, 100.0), surface_time=300.0)


def _formation(**kw):
    args = dict(shape="triangle", spacing=[(0.0, 6000.0), (12 * 3600.0, 3000.0)], leader_path=[(0, 0), (30000, 0)],
                leader_speed=0.12)
    return gc.FormationControl(**{**args, **kw})


def test_triangle_offsets_have_the_spacing_as_sides():
    off = shape_offsets("triangle", 3, 5000.0)
    for i, j in itertools.combinations(range(3), 2):
        assert math.hypot(*(off[i] - off[j])) == pytest.approx(5000.0, rel=1e-12)
    np.testing.assert_allclose(off.mean(0), 0.0, atol=1e-9)
    assert off[0, 0] > 0 and off[0, 1] == pytest.approx(0.0, abs=1e-9)          # a vertex ahead
    np.testing.assert_allclose(np.diff(shape_offsets("line", 4, 100.0)[:, 1]), 100.0)


def test_the_potentials_equilibrium_is_the_desired_shape():
    fc = _formation()
    for t in (0.0, 5000.0, 20 * 3600.0):
        slots = fc.slots(3, t)
        assert fc.potential(slots, t) == pytest.approx(0.0, abs=1e-12)
        d = fc.spacing_at(t)
        for i, j in itertools.combinations(range(3), 2):
            assert math.hypot(*(slots[i] - slots[j])) == pytest.approx(d, rel=1e-12)
        # every glider on its slot: the waypoint for the next surfacing is the slot there (the gradient vanishes)
        h = 1700.0
        reports = {j: (t, slots[j]) for j in range(3)}
        for i in range(3):
            np.testing.assert_allclose(fc.waypoint(i, 3, t, h, reports), fc.slots(3, t + h)[i], atol=1e-6)
        # off the shape the potential is positive
        assert fc.potential(slots + np.array([[100.0, 0.0], [0.0, 0.0], [0.0, 0.0]]), t) > 0


def test_leader_moves_along_its_path_and_stops_at_its_end():
    fc = _formation()
    pos, u = fc.leader(1000.0)
    np.testing.assert_allclose(pos, [120.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(u, [1.0, 0.0])
    np.testing.assert_allclose(fc.leader(1e7)[0], [30000.0, 0.0])
    np.testing.assert_allclose(fc.leader_velocity(1e7), [0.0, 0.0])


@pytest.fixture(scope="module")
def still_run():
    fc = _formation()
    starts = fc.slots(3, 0.0) + np.array([[800.0, -600.0], [-700.0, 900.0], [500.0, 1000.0]])
    return gc.fly_fleet([SLOCUM] * 3, fc, mission=DIVES, starts=starts, duration=24 * 3600.0)


def test_spacing_converges_in_still_water_and_follows_the_schedule(still_run):
    times, spacing = still_run.mean_spacing()
    desired = still_run.desired_spacing(times)
    assert abs(spacing[0] - 6000.0) > 400.0                     # launched off the shape
    for lo, hi in ((6 * 3600.0, 12 * 3600.0), (18 * 3600.0, 24 * 3600.0)):
        sel = (times >= lo) & (times < hi)
        err = np.abs(spacing[sel] - desired[sel]) / desired[sel]
        assert float(np.mean(err)) < 0.1
    assert still_run.late_reports == 0 and still_run.executor == "serial"
    assert len(still_run.surfacings) >= 3 * 40 and len(still_run.waypoints) >= len(still_run.surfacings)
    axes = still_run.plot()
    assert len(axes) == 2 and axes[1].get_ylabel() == "spacing [km]"


def test_parallel_run_is_the_serial_run():
    fc = _formation()
    kw = dict(mission=DIVES, duration=4 * 3600.0, current=(0.05, 0.1), seed=3)
    serial = gc.fly_fleet([SLOCUM] * 3, fc, **kw)
    with ProcessPoolExecutor(2) as pool:
        parallel = gc.fly_fleet([SLOCUM] * 3, fc, executor=pool, **kw)
    for a, b in zip(serial.states, parallel.states, strict=True):
        np.testing.assert_array_equal(a, b)
    assert parallel.executor.endswith("ProcessPoolExecutor")


def test_bad_fleets_are_refused():
    fc = _formation()
    with pytest.raises(ArgumentError, match="non-empty"):
        gc.fly_fleet([], fc, mission=DIVES, starts=np.zeros((0, 2)), duration=3600.0)
    with pytest.raises(ArgumentError, match="triangle formation has 3 gliders"):
        gc.fly_fleet([SLOCUM] * 2, fc, mission=DIVES, duration=3600.0)
    with pytest.raises(InfeasibleGlideError, match="cannot keep up"):
        gc.fly_fleet([SLOCUM] * 3, _formation(leader_speed=0.5), mission=DIVES, duration=3600.0)
    with pytest.raises(ArgumentError, match="delay"):
        gc.fly_fleet([SLOCUM] * 3, fc, mission=DIVES, duration=3600.0, delay=1e5)
    with pytest.raises(ArgumentTypeError, match="waypoint"):
        gc.fly_fleet([SLOCUM] * 3, object(), mission=DIVES, starts=np.zeros((3, 2)), duration=3600.0)
    with pytest.raises(ArgumentError, match="spacing"):
        _formation(spacing=[(0.0, 6000.0), (0.0, 3000.0)])
    with pytest.raises(ArgumentError, match="zero length"):
        _formation(leader_path=[(0, 0), (0, 0)])


def _drifter(v=(0.08, 0.04), hours=48.0):
    return gc.drift_track(v, (100.0, -50.0), hours * 3600.0)


def test_drift_track_of_a_uniform_current_is_a_straight_line():
    t, p = _drifter()
    np.testing.assert_allclose(p, np.c_[100.0 + 0.08 * t, -50.0 + 0.04 * t], atol=1e-9)


def test_drifter_prediction_from_delayed_reports_against_a_constructed_drift():
    dt = gc.DrifterTracking(_drifter(), radius=1000.0)
    # reports every 30 min, 15 min late: at t = 2 h 10 min the last report is from 1 h 30 min
    t = 2 * 3600.0 + 600.0
    assert dt.last_report(t) == 5400.0
    # a constant drift is predicted exactly from the last two reports, for any time ahead
    for ahead in (0.0, 1700.0, 7200.0):
        np.testing.assert_allclose(dt.predicted(t, t + ahead), dt.actual(t + ahead), atol=1e-6)
    delayed = gc.DrifterTracking(_drifter(), radius=1000.0, mode="delayed")
    np.testing.assert_allclose(delayed.centre(t, 1700.0), dt.actual(5400.0), atol=1e-9)
    # the waypoint is on the circle, one chord ahead of the glider's own bearing, counter-clockwise
    c = dt.centre(t, 1700.0)
    own = c + np.array([1000.0, 0.0])
    wp = dt.waypoint(0, 1, t, 1700.0, {0: (t, own)})
    assert math.hypot(*(wp - c)) == pytest.approx(1000.0, rel=1e-12)
    assert math.hypot(*(wp - own)) == pytest.approx(min(0.3 * 1700.0, 2000.0), rel=1e-9) and wp[1] > c[1]


def test_real_time_tracking_stays_on_the_circle_and_the_delayed_one_lags():
    runs = {}
    for mode in ("predicted", "delayed"):
        dt = gc.DrifterTracking(_drifter(), radius=1500.0, mode=mode)
        run = gc.fly_fleet([SLOCUM], dt, mission=DIVES, starts=[(1600.0, -50.0)], current=(0.08, 0.04),
                           duration=18 * 3600.0)
        runs[mode] = dt.errors(run)
    assert runs["predicted"]["circle"] < 0.1 * 1500.0
    assert runs["delayed"]["circle"] > runs["predicted"]["circle"]
    with pytest.raises(ArgumentError, match="drifter"):
        gc.DrifterTracking(3.0, radius=100.0)


def test_mapping_error_by_hand_on_a_tiny_grid():
    L, tau, eta = 1000.0, 3600.0, 0.1
    # one measurement 500 m and 1800 s from the point: e = 1 - c^2 / (1 + eta), c = exp(-0.25 - 0.5)
    e = gc.fleets.mapping_error([(500.0, 0.0)], 1800.0, [(0.0, 0.0)], [0.0], space_scale=L, time_scale=tau,
                                noise=eta)
    c = math.exp(-0.25 - 0.5)
    assert e[0] == pytest.approx(1.0 - c * c / (1.0 + eta), rel=1e-12)
    # two measurements at the same place and time: e = 1 - 2 c^2 / (2 + eta) at a point at distance 0
    e2 = gc.fleets.mapping_error([(0.0, 0.0), (1e6, 0.0)], 0.0, [(0.0, 0.0), (0.0, 0.0)], [0.0, 0.0],
                                 space_scale=L, time_scale=tau, noise=eta)
    assert e2[0] == pytest.approx(1.0 - 2.0 / (2.0 + eta), rel=1e-12) and e2[1] == pytest.approx(1.0)
    assert gc.fleets.mapping_error([(0.0, 0.0)], 0.0, np.zeros((0, 2)), [], space_scale=L, time_scale=tau)[0] == 1.0


def test_curve_patrol_spaces_the_gliders_evenly_and_scores_better_than_bunched():
    curve = [(0, 0), (4000, 0), (4000, 4000), (0, 4000)]
    cp = gc.CurvePatrol(curve, speed=0.2)
    assert cp.length == pytest.approx(16000.0)
    s = cp.slots(4, 1000.0)
    np.testing.assert_allclose(s[0], [200.0, 0.0])
    np.testing.assert_allclose(s[1], [0.0, 3800.0])        # a quarter of the curve behind
    E, N = np.meshgrid(np.linspace(0, 4000, 5), np.linspace(0, 4000, 5))
    grid = np.c_[E.ravel(), N.ravel()]
    scores = {}
    for spacing in ("even", "none"):
        run = gc.fly_fleet([SLOCUM] * 3, gc.CurvePatrol(curve, 0.2, spacing), mission=DIVES, duration=12 * 3600.0)
        scores[spacing] = gc.coverage_metric(run, grid, space_scale=1500.0, time_scale=4 * 3600.0).mean
    assert 0.0 < scores["even"] < scores["none"] < 1.0


def test_least_squares_gradient_of_a_plane_is_exact():
    gcl = gc.GradientClimbing(lambda e, n: 3.0 + 2e-3 * e - 5e-4 * n, "triangle", 1000.0, 0.1)
    reports = {0: (0.0, (0.0, 0.0)), 1: (0.0, (1000.0, 200.0)), 2: (0.0, (300.0, 900.0))}
    np.testing.assert_allclose(gcl.gradient(reports), [2e-3, -5e-4], rtol=1e-10)
    assert gcl.gradient({0: (0.0, (0.0, 0.0)), 1: (0.0, (1.0, 1.0)), 2: (0.0, (2.0, 2.0))}) is None   # collinear


def test_the_formation_climbs_to_the_maximum_of_a_field():
    top = np.array([6000.0, 3000.0])
    gcl = gc.GradientClimbing(lambda e, n: -((e - top[0]) ** 2 + (n - top[1]) ** 2), "triangle", 1000.0, 0.12)
    run = gc.fly_fleet([SLOCUM] * 3, gcl, mission=DIVES, starts=gcl.slots(3, 0.0), duration=20 * 3600.0)
    start, end = (float(np.hypot(*(run.positions_at([t])[0].mean(0) - top))) for t in (0.0, 19.5 * 3600.0))
    assert start > 6000.0 and end < 1000.0


def test_a_spacing_tighter_than_the_gliders_turn_is_refused():
    from glidectl.missions.fast import tightest_turn

    plant = gc.ActuatedGlider3D(SLOCUM)
    r = tightest_turn(plant, gc.DivePlan(plant, DIVES.gamma, DIVES.speed))
    assert 50.0 < r < 500.0                 # the rudder's tightest dive turn, about 110 m
    with pytest.raises(InfeasibleGlideError, match="tightest turn radius"):
        gc.fly_fleet([SLOCUM] * 3, _formation(spacing=0.5 * r), mission=DIVES, duration=3600.0)


def test_dask_run_is_the_serial_run_and_other_kinds_are_refused():
    from dask.distributed import Client

    fc = _formation()
    kw = dict(mission=DIVES, duration=3 * 3600.0, current=(0.05, 0.1), seed=1)
    serial = gc.fly_fleet([SLOCUM] * 3, fc, **kw)
    with Client(processes=False, n_workers=2, threads_per_worker=1, dashboard_address=None) as client:
        run = gc.fly_fleet([SLOCUM] * 3, fc, executor=client.get_executor(), **kw)
    for a, b in zip(serial.states, run.states, strict=True):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(gc.ModelError, match="underwater glider"):
        gc.fly_fleet([SLOCUM, SLOCUM, gc.load_vehicle("dc8_ctol")], fc, mission=DIVES, duration=3600.0)


def test_per_glider_controllers_default_dives_and_a_failing_glider_ends_the_run():
    fc = _formation()
    run = gc.fly_fleet([SLOCUM] * 3, fc, controller=["behaviours", "lqr", "behaviours"], duration=2 * 3600.0)
    assert run.ended_by == "duration" and all(len(t) for t in run.t)
    with pytest.raises(ArgumentError, match="one per glider"):
        gc.fly_fleet([SLOCUM] * 3, fc, controller=["lqr", "lqr"], duration=3600.0)

    class Breaks:
        """The behaviours until its pump fails, after some thousands of evaluations (past the first dives)."""

        name = "breaks"

        def __init__(self, after):
            self.law, self.calls, self.after = gc.GliderBehaviours(), 0, after

        def rates(self, plant, plan, x, phase, heading_ref):
            self.calls += 1
            if self.calls > self.after:
                raise gc.SolverError("the pump failed")
            return self.law.rates(plant, plan, x, phase, heading_ref)

    probe = Breaks(10**9)
    gc.fly_fleet([SLOCUM] * 3, fc, controller=probe, model="full", duration=1800.0)     # one dive each
    broken = gc.fly_fleet([SLOCUM] * 3, fc, controller=Breaks(probe.calls + 10), model="full", duration=4 * 3600.0)
    assert broken.ended_by.startswith("a glider could not fly its dive") and "pump failed" in broken.ended_by
    assert all(len(t) for t in broken.t) and max(t[-1] for t in broken.t) < 4 * 3600.0


def test_line_formation_slots_are_the_potentials_equilibrium():
    fc = gc.FormationControl("line", 1000.0, leader_path=[(0, 0), (10000, 0)], leader_speed=0.1)
    slots = fc.slots(4, 3600.0)
    assert fc.potential(slots, 3600.0) == pytest.approx(0.0, abs=1e-9)
    reports = {j: (3600.0, slots[j]) for j in range(4)}
    for i in range(4):
        np.testing.assert_allclose(fc.waypoint(i, 4, 3600.0, 1500.0, reports), fc.slots(4, 5100.0)[i], atol=1e-6)


def test_runs_of_a_stateful_coordinator_are_repeatable():
    top = np.array([4000.0, 2000.0])
    gcl = gc.GradientClimbing(lambda e, n: -((e - top[0]) ** 2 + (n - top[1]) ** 2), "triangle", 1000.0, 0.12)
    kw = dict(mission=DIVES, starts=gcl.slots(3, 0.0), duration=4 * 3600.0, delay=600.0)
    a, b = gc.fly_fleet([SLOCUM] * 3, gcl, **kw), gc.fly_fleet([SLOCUM] * 3, gcl, **kw)
    for x, y in zip(a.states, b.states, strict=True):
        np.testing.assert_array_equal(x, y)
    assert gcl.history == [] and len(a.coordinator.history) > 0      # the runs flew copies
    # with the delay the first round has no gradient: the virtual body keeps moving along its direction
    h = a.coordinator.history
    assert h[3][0] > h[0][0] == 0.0
    assert float(np.hypot(*(h[3][1] - h[0][1]))) == pytest.approx(0.12 * h[3][0], rel=1e-9)


def test_full_model_dive_time_is_the_flown_one():
    from glidectl.missions import GliderFlight

    for yos in (1, 3):
        m = gc.Mission(waypoints=[(1.0, 0.0)], depths=(20.0, 100.0), surface_time=300.0, yos=yos)
        g = GliderFlight(SLOCUM, m, model="full")
        dive, _ = g.dive((3000.0, 0.0))
        assert g.dive_time == pytest.approx(dive.duration + 300.0, rel=0.1)
