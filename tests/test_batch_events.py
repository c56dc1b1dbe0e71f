"""Many runs integrated together with their own clocks, steps and events (glidectl.batch_events), the stacked
vehicle their right-hand sides broadcast over (glidectl.params.stack_vehicles), and the batched dive cycles built
on both (glidectl.controllers.dive_cycle.dive_cycles_batched)."""

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import glidectl as gc
from glidectl.batch import DIVERGED, FINISHED, STEP_UNDERFLOW
from glidectl.batch_events import EVENT, integrate_batch_events
from glidectl.controllers.dive_cycle import cycle_summary, dive_cycles_batched
from glidectl.params import StackedVehicle, stack_vehicles


def oscillators(omega):
    """x'' = -omega^2 x + 0.1 sin(t) per row (non-autonomous: the forcing reads each row's own clock)."""
    w2 = np.asarray(omega) ** 2

    def f(t, X):
        return np.stack([X[:, 1], -w2 * X[:, 0] + 0.1 * np.sin(t)], axis=1)
    return f


@settings(max_examples=15, deadline=None)
@given(st.lists(st.floats(0.3, 3.0), min_size=1, max_size=6))
def test_each_run_matches_its_own_solve_ivp(omega):
    f = oscillators(omega)
    X0 = np.column_stack([np.ones(len(omega)), np.zeros(len(omega))])
    res = integrate_batch_events(f, X0, 5.0, t_step=0.5, rtol=1e-9, atol=1e-12)
    assert np.all(res.status == FINISHED) and np.allclose(res.t, 5.0)
    for i, w in enumerate(omega):
        ref = solve_ivp(lambda t, x, w=w: [x[1], -w * w * x[0] + 0.1 * np.sin(t)], (0, 5), X0[i],
                        t_eval=np.arange(11) * 0.5, rtol=1e-11, atol=1e-13)
        np.testing.assert_allclose(res.samples[i, :11], ref.y.T, atol=2e-7)
        np.testing.assert_allclose(res.x[i], ref.y[:, -1], atol=2e-7)
    assert np.all(res.n_samples == 11)


def test_events_end_each_run_at_its_own_crossing():
    omega = np.array([0.5, 1.0, 2.0, 4.0])
    w2 = omega ** 2

    def f(t, X):
        return np.stack([X[:, 1], -w2 * X[:, 0]], axis=1)

    X0 = np.column_stack([np.ones(4), np.zeros(4)])
    res = integrate_batch_events(f, X0, 10.0, event=lambda t, X: X[:, 0], t_step=0.25, rtol=1e-9, atol=1e-12)
    assert np.all(res.status == EVENT) and res.stopped.all()
    np.testing.assert_array_equal(X0, np.column_stack([np.ones(4), np.zeros(4)]))     # the caller's array is kept
    np.testing.assert_allclose(res.t, np.pi / (2 * omega), rtol=1e-8)         # cos(omega t) = 0
    np.testing.assert_allclose(res.x[:, 0], 0.0, atol=1e-9)
    for i, w in enumerate(omega):
        k = int(res.n_samples[i])
        assert (k - 1) * 0.25 <= res.t[i] < k * 0.25                          # grid points at or before the end
        np.testing.assert_allclose(res.samples[i, :k, 0], np.cos(w * 0.25 * np.arange(k)), atol=1e-8)
        assert np.all(np.isnan(res.samples[i, k:]))
    assert res.reason(0) == "event"


def test_a_failing_run_does_not_stop_the_others_and_rows_are_independent():
    def f(t, X):                       # row 0 blows up in finite time (x' = x^2 from 1: at t = 1)
        return np.stack([X[:, 0] ** 2 * (X[:, 1] > 0), -X[:, 1]], axis=1)

    X0 = np.array([[1.0, 1.0], [1.0, -1.0], [2.0, -3.0]])
    res = integrate_batch_events(f, X0, 3.0, rtol=1e-8, atol=1e-10)
    assert res.status[0] in (DIVERGED, STEP_UNDERFLOW) and res.t[0] < 1.0 + 1e-6
    assert np.all(res.status[1:] == FINISHED)
    np.testing.assert_allclose(res.x[1:, 1], X0[1:, 1] * math.exp(-3.0), rtol=1e-6)
    alone = integrate_batch_events(f, X0[2:], 3.0, rtol=1e-8, atol=1e-10)
    np.testing.assert_array_equal(alone.x[0], res.x[2])                        # a run's steps are its own


def test_bad_arguments_are_refused():
    f = oscillators([1.0])
    with pytest.raises(gc.ArgumentError, match="shape"):
        integrate_batch_events(lambda t, X: X[:, :1], np.ones((2, 2)), 1.0)
    with pytest.raises(gc.ArgumentError):
        integrate_batch_events(f, np.ones((1, 2)), -1.0)
    with pytest.raises(gc.ArgumentError):
        integrate_batch_events(f, np.full((1, 2), np.nan), 1.0)
    res = integrate_batch_events(f, np.ones((1, 2)), 1.0, event=lambda t, X: -np.ones(len(X)))
    assert res.status[0] == EVENT and res.t[0] == 0.0                          # already met: ends at once


@pytest.fixture(scope="module")
def uncertain():
    keys = ("K_L", "K_D0", "K_D", "K_M", "K_Omega1_2", "m_f1", "m_f3", "J2")
    return gc.load_vehicle("slocum_shallow").with_uncertainty({k: {"rel": 0.3} for k in keys})


def test_a_stacked_vehicle_gives_each_member_its_own_right_hand_side(uncertain):
    sample = uncertain.sample(16, seed=4)
    sv = sample.stacked()
    assert isinstance(sv, StackedVehicle) and sv.size == 16
    assert isinstance(sv.K_M, np.ndarray) and sv.K_M.shape == (16,) and np.isscalar(sv.m)
    glide = gc.steady_glide(uncertain, 0.35, -0.436, r_p3=0.05)
    rng = np.random.default_rng(0)
    X = glide.accel_state(0.0, 10.0) + 1e-2 * rng.standard_normal((16, 11))
    U = 1e-3 * rng.standard_normal((16, 3))
    stacked = gc.ActuatedGlider(sv).rhs(X, U)
    alone = np.array([gc.ActuatedGlider(v).rhs(X[i], U[i]) for i, v in enumerate(sample)])
    np.testing.assert_array_equal(stacked, alone)
    again = pickle.loads(pickle.dumps(sv))
    assert again.provenance == sv.provenance and again.size == 16
    assert sv.provenance != stack_vehicles(list(sample)[:8]).provenance


def test_stack_vehicles_refuses_vehicles_that_differ_in_more_than_values(uncertain):
    other = uncertain.with_actuators(m0={"min": -0.2, "max": 0.2, "rate": 0.01, "unit": "kg", "source": "test"})
    with pytest.raises(gc.ArgumentError, match="more than parameter values"):
        stack_vehicles([uncertain, other])
    with pytest.raises(gc.ArgumentError, match="at least one"):
        stack_vehicles([])
    with pytest.raises(gc.ArgumentTypeError):
        stack_vehicles([uncertain, "slocum"])


def test_batched_dive_cycles_agree_with_dive_cycle(uncertain):
    vehicles = list(uncertain.sample(5, seed=11))
    batched = dive_cycles_batched(vehicles, uncertain, cycles=1)
    for veh, got in zip(vehicles, batched, strict=True):
        want = gc.dive_cycle(veh, "lqr", cycles=1, design_vehicle=uncertain)
        a, b = cycle_summary(got), want.as_dict()
        for key in ("distance_per_cycle", "duration_per_cycle"):
            assert a[key] == pytest.approx(b[key], rel=1e-4)
        for key in ("energy_per_cycle", "max_overshoot"):
            assert a[key] == pytest.approx(b[key], rel=2e-3)
        assert a["saturated_time_per_cycle"] == pytest.approx(b["saturated_time_per_cycle"], abs=2.0)
        assert got[0].t_end == pytest.approx(want.switch_times[2], rel=1e-4)


def test_batched_dive_cycles_report_each_failure_in_its_slot(uncertain):
    vehicles = list(uncertain.sample(3, seed=1))
    other = vehicles[1].with_actuators(m0={"min": -0.2, "max": 0.2, "rate": 0.01, "unit": "kg", "source": "test"})
    out = dive_cycles_batched([vehicles[0], other, "not a vehicle", vehicles[2]], uncertain, cycles=1)
    assert isinstance(out[1], gc.ArgumentError) and "other actuators" in str(out[1])
    assert isinstance(out[2], gc.ArgumentTypeError)
    assert all(isinstance(m, gc.CycleMetrics) for r in (out[0], out[3]) for m in r)
    short = dive_cycles_batched(vehicles[:2], uncertain, cycles=1, max_leg_time=60.0)
    assert all(isinstance(r, gc.BudgetError) and "did not reach 100 m within 60 s" in str(r) for r in short)
    with pytest.raises(gc.ArgumentError):
        dive_cycles_batched(vehicles, uncertain, depths=(50.0, 10.0))


def test_a_batch_study_keeps_the_sample_order_and_its_failures(uncertain):
    class Study:
        name = "batch"

        def __call__(self, veh):              # pragma: no cover - the batch path is taken
            raise AssertionError

        def batch(self, vehicles):
            return [gc.ModelError("too heavy") if v.K_M > uncertain.K_M else {"K_M": v.K_M} for v in vehicles]

    mc = gc.monte_carlo(Study(), uncertain, n=12, seed=3)
    km = mc.values[:, mc.keys.index("K_M")]
    assert np.array_equal(mc.ok, km <= uncertain.K_M)
    np.testing.assert_array_equal(mc.results[mc.ok, 0], km[mc.ok])
    assert mc.failures == {"ModelError: too heavy": int((km > uncertain.K_M).sum())}

    class Short(Study):
        def batch(self, vehicles):
            return [{"x": 1.0}]

    with pytest.raises(gc.ArgumentTypeError, match="one per vehicle"):
        gc.monte_carlo(Short(), uncertain, n=3, seed=0)
