"""glidectl.sim: argument checks, honest output times, budgets (steps, right-hand-side evaluations, wall time) and
what stopped a run, for simulate and simulate_many (issue 15)."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

import glidectl as gc
from glidectl.sim import MAX_STEPS, MAX_T_FINAL, MIN_T_FINAL


class Oscillator:
    """Damped oscillator ``q'' + 0.1 q' + q = f`` with one input (a cheap stand-in for a glider model)."""

    state_names = ("q", "p")
    input_names = ("f",)

    def rhs(self, x, u):
        return np.array([x[1], -x[0] - 0.1 * x[1] + u[0]])


class Decay:
    """``x' = -x`` for a batch of states (input-free, for simulate_many)."""

    state_names = ("a", "b")
    input_names = ()

    def rhs(self, X, u):
        return -np.asarray(X)


class Spinner:
    """``theta' = w sin(w), w' = 1 + w / 2``: the rate grows without bound and ``theta`` oscillates ever faster (a
    tumbling vehicle in miniature)."""

    state_names = ("theta", "w")
    input_names = ()

    def rhs(self, x, u):
        return np.array([np.sin(x[1]) * x[1], 1.0 + 0.5 * x[1]])


OSC, X0 = Oscillator(), np.array([1.0, 0.0])


@pytest.fixture(scope="module")
def rogue():
    veh = gc.load_vehicle("rogue")
    return veh, gc.steady_glide(veh, 0.3, -np.pi / 4, r_p3=0.05)


# ------------------------------------------------------------------------------------------ right answers
def test_free_response_matches_the_exact_solution():
    sim = gc.simulate(OSC, X0, 10.0, rtol=1e-10, atol=1e-12)
    wd = math.sqrt(1 - 0.05**2)
    q = np.exp(-0.05 * sim.t) * (np.cos(wd * sim.t) + 0.05 / wd * np.sin(wd * sim.t))
    np.testing.assert_allclose(sim.state("q"), q, atol=1e-8)
    assert sim.stopped_by == "t_final" and sim.stopped_at is None and sim.t[-1] == 10.0
    assert sim.n_steps > 0 and sim.nfev >= sim.n_steps and sim.u.shape == (2001, 1)


def test_switch_times_and_breakpoints_restart_the_integrator():
    class Step:
        switch_times = (2.5,)

        def __call__(self, t, x):
            return np.array([1.0 if t >= 2.5 else 0.0])

    sim = gc.simulate(OSC, np.zeros(2), 5.0, Step(), breakpoints=[1.0, 7.0], t_eval=np.linspace(0, 5, 11))
    assert np.allclose(sim.x[sim.t <= 2.5], 0.0) and sim.x[-1, 0] > 0.1
    np.testing.assert_array_equal(sim.u[:, 0], (sim.t >= 2.5).astype(float))


def test_t_eval_rounding_beyond_the_end_is_kept_not_dropped():
    te = np.arange(0.0, 1.0 + 0.1, 0.1)          # the last time may exceed 1.0 by rounding
    sim = gc.simulate(OSC, X0, float(te[-1] - 1e-13), t_eval=te)
    assert sim.t.size == te.size


def test_stop_condition_is_located_and_recorded():
    sim = gc.simulate(OSC, X0, 10.0, stop=lambda t, x: x[0] + 0.5)   # q falls through -0.5
    assert sim.stopped_by == "stop" and 0 < sim.stopped_at < 10.0
    assert sim.t[-1] <= sim.stopped_at and sim.x[-1, 0] >= -0.5 - 1e-9


def test_scalar_controller_output_for_one_input():
    sim = gc.simulate(OSC, X0, 1.0, lambda t, x: 0.5)
    assert np.all(sim.u == 0.5)


# ------------------------------------------------------------------------------------------ bad arguments
@pytest.mark.parametrize(("args", "kwargs"), [
    ((OSC, X0, "10"), {}),
    ((OSC, X0, None), {}),
    ((OSC, X0, True), {}),
    ((OSC, X0, np.array([10.0])), {}),
    ((OSC, X0 + 1j, 1.0), {}),
    ((OSC, "x0", 1.0), {}),
    ((None, X0, 1.0), {}),
    (("LongitudinalGlider", X0, 1.0), {}),
    ((OSC, X0, 1.0, 42), {}),
    ((OSC, X0, 1.0), {"stop": "no"}),
    ((OSC, X0, 1.0), {"rtol": "1e-6"}),
    ((OSC, X0, 1.0), {"max_steps": 10.0}),
    ((OSC, X0, 1.0), {"time_limit": "1"}),
    ((OSC, X0, 1.0, lambda t, x: "fast"), {}),
    ((OSC, X0, 1.0, lambda t, x: np.array([1j])), {}),
])
def test_wrong_types_are_argument_type_errors(args, kwargs):
    with pytest.raises(gc.ArgumentTypeError):
        gc.simulate(*args, **kwargs)
    assert issubclass(gc.ArgumentTypeError, TypeError)


@pytest.mark.parametrize(("args", "kwargs"), [
    ((OSC, [1.0, np.nan], 1.0), {}),
    ((OSC, [1.0, np.inf], 1.0), {}),
    ((OSC, np.zeros(3), 1.0), {}),
    ((OSC, X0, 0.0), {}),
    ((OSC, X0, -1.0), {}),
    ((OSC, X0, float("nan")), {}),
    ((OSC, X0, float("inf")), {}),
    ((OSC, X0, 1e-200), {}),
    ((OSC, X0, 0.5 * MIN_T_FINAL), {}),
    ((OSC, X0, 1e200), {}),
    ((OSC, X0, 1.0), {"t_eval": [0.0, 5.0]}),
    ((OSC, X0, 1.0), {"t_eval": [-0.5, 0.5]}),
    ((OSC, X0, 1.0), {"t_eval": [0.5, 0.2]}),
    ((OSC, X0, 1.0), {"t_eval": []}),
    ((OSC, X0, 1.0), {"t_eval": [0.5, np.nan]}),
    ((OSC, X0, 1.0), {"method": "bogus"}),
    ((OSC, X0, 1.0), {"rtol": -1.0}),
    ((OSC, X0, 1.0), {"rtol": 1e-20}),
    ((OSC, X0, 1.0), {"atol": 0.0}),
    ((OSC, X0, 1.0), {"atol": [1e-9, 1e-9, 1e-9]}),
    ((OSC, X0, 1.0), {"max_steps": 0}),
    ((OSC, X0, 1.0), {"max_nfev": -1}),
    ((OSC, X0, 1.0), {"time_limit": 0.0}),
    ((OSC, X0, 1.0), {"on_budget": "ignore"}),
    ((OSC, X0, 1.0), {"breakpoints": [np.nan]}),
    ((OSC, X0, 1.0), {"stop": lambda t, x: -1.0}),
    ((OSC, X0, 1.0, lambda t, x: np.zeros(2)), {}),
    ((OSC, X0, 1.0, lambda t, x: np.zeros((1, 1, 1))), {}),
    ((OSC, X0, 1.0, lambda t, x: np.array([np.nan])), {}),
])
def test_bad_values_are_argument_errors(args, kwargs):
    t0 = time.perf_counter()
    with pytest.raises(gc.ArgumentError):
        gc.simulate(*args, **kwargs)
    assert time.perf_counter() - t0 < 5.0, "refused before integrating"
    assert issubclass(gc.ArgumentError, ValueError)


def test_messages_name_the_argument_and_what_is_accepted():
    with pytest.raises(gc.ArgumentError, match=r"shape \(1,\), one value per input \('f',\)"):
        gc.simulate(OSC, X0, 1.0, lambda t, x: np.zeros(2))
    with pytest.raises(gc.ArgumentError, match=r"outside \[0, t_final\]"):
        gc.simulate(OSC, X0, 1.0, t_eval=[0.0, 5.0])
    with pytest.raises(gc.ArgumentError, match="MIN_T_FINAL"):
        gc.simulate(OSC, X0, 1e-200)
    with pytest.raises(gc.ArgumentError, match="x0 must be finite"):
        gc.simulate(OSC, [np.nan, 0.0], 1.0)


def test_issue_examples_on_the_glider(rogue):
    veh, g = rogue
    m, x0 = gc.LongitudinalGlider(veh), g.force_state()
    with pytest.raises(gc.ArgumentTypeError):
        gc.simulate(m, x0, "10")
    x = x0.copy()
    x[2] = np.nan
    with pytest.raises(gc.ArgumentError):
        gc.simulate(m, x, 10.0)
    with pytest.raises(gc.ArgumentError, match=r"shape \(3,\)"):
        gc.simulate(m, x0, 10.0, lambda t, x: np.zeros(2))
    with pytest.raises(gc.ArgumentError):
        gc.simulate(m, x0, 1.0, t_eval=[0.0, 5.0])
    t0 = time.perf_counter()
    with pytest.raises(gc.ArgumentError):
        gc.simulate(m, x0, 1e-200)           # LSODA used to loop forever here
    assert time.perf_counter() - t0 < 1.0


def test_model_output_shape_and_arithmetic_failures():
    class Wrong(Oscillator):
        def rhs(self, x, u):
            return np.zeros(3)

    class Divides(Oscillator):
        def rhs(self, x, u):
            if abs(x[0]) < 0.5:
                raise ZeroDivisionError("float division by zero")
            return super().rhs(x, u)

    with pytest.raises(gc.ModelError, match="shape"):
        gc.simulate(Wrong(), X0, 1.0)
    with pytest.raises(gc.SolverError, match="ZeroDivisionError") as info:
        gc.simulate(Divides(), X0, 10.0)
    assert isinstance(info.value.__cause__, ZeroDivisionError)


def test_user_callback_exceptions_pass_through_unchanged():
    class Mine(Exception):
        pass

    def controller(t, x):
        if t > 0.3:
            raise Mine("controller")
        return np.zeros(1)

    def stop(t, x):
        if t > 0.3:
            raise KeyError("stop")
        return 1.0

    with pytest.raises(Mine):
        gc.simulate(OSC, X0, 1.0, controller)
    with pytest.raises(KeyError):
        gc.simulate(OSC, X0, 1.0, stop=stop)
    with pytest.raises(ValueError, match="mine"):          # a user's ValueError is not turned into anything else
        gc.simulate(OSC, X0, 1.0, lambda t, x: (_ for _ in ()).throw(ValueError("mine")))


def test_simulation_state_checks_its_argument():
    sim = gc.simulate(OSC, X0, 1.0)
    with pytest.raises(gc.ArgumentError, match="no state"):
        sim.state("nope")
    with pytest.raises(gc.ArgumentTypeError):
        sim.state(0)


# ------------------------------------------------------------------------------------------ budgets
def test_max_steps_raises_or_returns_the_partial_run():
    with pytest.raises(gc.BudgetError, match="max_steps = 20 "):
        gc.simulate(OSC, X0, 100.0, max_steps=20)
    sim = gc.simulate(OSC, X0, 100.0, max_steps=20, on_budget="stop")
    assert sim.stopped_by == "max_steps" and sim.n_steps == 20 and 0 < sim.stopped_at < 100.0
    assert sim.t[-1] <= sim.stopped_at and np.all(np.isfinite(sim.x)) and sim.t.size > 1
    full = gc.simulate(OSC, X0, 100.0)
    np.testing.assert_allclose(sim.x, full.x[: sim.t.size], atol=1e-6)


def test_max_nfev_stops_inside_a_step():
    with pytest.raises(gc.BudgetError, match="max_nfev = 3 "):
        gc.simulate(OSC, X0, 10.0, max_nfev=3)
    sim = gc.simulate(OSC, X0, 10.0, max_nfev=3, on_budget="stop")
    assert sim.stopped_by == "max_nfev" and sim.nfev <= 3 and sim.stopped_at < 1e-3
    assert sim.t.tolist() == [0.0] and np.array_equal(sim.x[0], X0)
    sim = gc.simulate(OSC, X0, 10.0, max_nfev=100, on_budget="stop")
    assert sim.stopped_by == "max_nfev" and sim.nfev == 100 and 0 < sim.stopped_at < 10.0


def test_time_limit_raises_or_stops():
    class Slow(Oscillator):
        def rhs(self, x, u):
            time.sleep(0.001)
            return super().rhs(x, u)

    t0 = time.perf_counter()
    with pytest.raises(gc.BudgetError, match=r"time_limit = 0\.2 s"):
        gc.simulate(Slow(), X0, 1e4, time_limit=0.2)
    assert time.perf_counter() - t0 < 5.0
    sim = gc.simulate(Slow(), X0, 1e4, time_limit=0.2, on_budget="stop")
    assert sim.stopped_by == "time_limit" and sim.stopped_at < 1e4 and np.all(np.isfinite(sim.x))


def test_runaway_spin_stops_with_a_budget_error_in_bounded_time():
    t0 = time.perf_counter()
    with pytest.raises(gc.BudgetError, match="max_steps") as info:
        gc.simulate(Spinner(), np.zeros(2), 40.0)
    assert f"max_steps = {MAX_STEPS}" in str(info.value) and time.perf_counter() - t0 < 60.0
    assert isinstance(info.value, RuntimeError)


def test_tumbling_glider_finishes_or_stops_within_its_budget(rogue):
    """The issue's tumbling vehicle (top heavy, r_bh < 0) over 40 s: cost grows without bound; the default budget
    ends it with a BudgetError, and on_budget='stop' returns the finite part computed."""
    veh, _ = rogue
    gt = gc.steady_glide(veh, 0.3, -np.pi / 4, r_bh=-0.05)
    x = gt.force_state()
    x[2] += 0.3
    m = gc.LongitudinalGlider(veh)
    t0 = time.perf_counter()
    with pytest.raises(gc.BudgetError, match="max_steps"):
        gc.simulate(m, x, 40.0, max_steps=3000)
    sim = gc.simulate(m, x, 40.0, max_steps=3000, on_budget="stop")
    assert sim.stopped_by == "max_steps" and sim.stopped_at < 40.0 and np.all(np.isfinite(sim.x))
    assert time.perf_counter() - t0 < 120.0


def test_defaults_are_documented():
    assert MIN_T_FINAL == 1e-9 and MAX_T_FINAL == 1e9 and MAX_STEPS == 20_000
    doc = gc.simulate.__doc__
    for word in ("max_steps", "max_nfev", "time_limit", "on_budget", "BudgetError", "MIN_T_FINAL"):
        assert word in doc


# ------------------------------------------------------------------------------------------ simulate_many
def test_simulate_many_right_answer_and_record():
    X = np.array([[1.0, 2.0], [-1.0, 0.5], [0.0, 0.0]])
    ens = gc.simulate_many(Decay(), X, 2.0, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ens.x_final, X * math.exp(-2.0), atol=1e-8)
    assert ens.stopped_by == "t_final" and ens.stopped_at is None and ens.n_steps > 0


@pytest.mark.parametrize(("exc", "args", "kwargs"), [
    (gc.ArgumentError, (Decay(), [[1.0, np.nan]], 1.0), {}),
    (gc.ArgumentError, (Decay(), np.zeros((2, 3)), 1.0), {}),
    (gc.ArgumentError, (Decay(), np.zeros((0, 2)), 1.0), {}),
    (gc.ArgumentError, (Decay(), np.zeros((2, 2)), 1e-200), {}),
    (gc.ArgumentError, (OSC, np.zeros((2, 2)), 1.0), {}),
    (gc.ArgumentError, (Decay(), np.zeros((2, 2)), 1.0), {"freeze": lambda X: np.zeros(3, dtype=bool)}),
    (gc.ArgumentTypeError, (Decay(), np.zeros((2, 2)), "1"), {}),
    (gc.ArgumentTypeError, (Decay(), np.zeros((2, 2)), 1.0), {"freeze": 1}),
    (gc.ArgumentTypeError, (None, np.zeros((2, 2)), 1.0), {}),
])
def test_simulate_many_bad_inputs(exc, args, kwargs):
    with pytest.raises(exc):
        gc.simulate_many(*args, **kwargs)


def test_simulate_many_budgets():
    X = np.ones((3, 2))
    with pytest.raises(gc.BudgetError, match="max_steps = 2 "):
        gc.simulate_many(Decay(), X, 10.0, max_steps=2)
    ens = gc.simulate_many(Decay(), X, 10.0, max_steps=2, on_budget="stop")
    assert ens.stopped_by == "max_steps" and 0 < ens.stopped_at < 10.0
    np.testing.assert_allclose(ens.x_final, np.exp(-ens.stopped_at), rtol=1e-4)


def test_simulate_many_freeze_keeps_diverging_runs_from_stalling_the_others():
    class Blowup:
        state_names = ("x",)
        input_names = ()

        def rhs(self, X, u):
            return np.asarray(X) ** 2

    ens = gc.simulate_many(Blowup(), [[0.5], [2.0]], 1.0, freeze=lambda X: X[:, 0] > 10.0)
    assert ens.frozen.tolist() == [False, True]
    assert ens.x_final[0, 0] == pytest.approx(1.0, rel=1e-4)
