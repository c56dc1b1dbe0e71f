"""LQR state feedback on exact linearizations and the batch closed-loop comparison."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_continuous_are

import glidectl as gc
from glidectl.analysis.closed_loop import compare_controllers, lqr_state_feedback


class _Linear:
    state_names = ("a", "b")
    input_names = ("u",)
    A = np.array([[0.0, 1.0], [2.0, -1.0]])
    B = np.array([[0.0], [1.0]])

    def rhs(self, x, u):
        return np.asarray(x) @ self.A.T + np.asarray(u) @ self.B.T


class _Integrator:
    state_names = ("x",)
    input_names = ("u",)

    def rhs(self, x, u):
        return np.asarray(u) + 0.0 * np.asarray(x)


def test_lqr_gain_matches_riccati():
    m = _Linear()
    Q, R = np.diag([3.0, 0.5]), np.array([[2.0]])
    c = lqr_state_feedback(m, [0.0, 0.0], [0.0], Q=Q, R=R)
    P = solve_continuous_are(m.A, m.B, Q, R)
    np.testing.assert_allclose(c.K, np.linalg.solve(R, m.B.T @ P), rtol=1e-8)
    np.testing.assert_allclose(np.sort(c.closed_loop_poles.real), np.sort(np.linalg.eigvals(m.A - m.B @ c.K).real))
    assert np.all(c.closed_loop_poles.real < 0)


def test_lqr_rejects_non_equilibrium_and_shapes():
    with pytest.raises(gc.ModelError, match="not an equilibrium"):
        lqr_state_feedback(_Linear(), [1.0, 0.0], [0.0])
    with pytest.raises(gc.ArgumentError, match="shape"):
        lqr_state_feedback(_Linear(), [0.0], [0.0])


class _Tiny:
    """x' = -x + u + c with tiny numbers: the equilibrium test must be relative to the terms, not absolute."""

    state_names = ("x",)
    input_names = ("u",)

    def rhs(self, x, u):
        return -np.asarray(x) + np.asarray(u) + 1e-12 * np.ones_like(np.asarray(x))


def test_lqr_equilibrium_check_is_relative():
    # |rhs| = 1e-12 passed the old absolute test (1e-8 (1 + |x_e|)) although x_e = 1e-15 is far from x* = 1e-12
    with pytest.raises(gc.ModelError, match="not an equilibrium"):
        lqr_state_feedback(_Tiny(), [1e-15], [0.0])
    c = lqr_state_feedback(_Tiny(), [1e-12], [0.0])
    assert np.all(c.closed_loop_poles.real < 0)


@pytest.mark.parametrize(("kw", "exc"), [
    ({"model": None}, gc.ArgumentTypeError), ({"x_e": [np.nan, 0.0]}, gc.ArgumentError),
    ({"x_e": "0"}, gc.ArgumentTypeError), ({"Q": np.eye(3)}, gc.ArgumentError),
    ({"Q": [[1.0, 1.0], [0.0, 1.0]]}, gc.ArgumentError), ({"R": [0.0]}, gc.ArgumentError),
    ({"R": [-1.0]}, gc.ArgumentError), ({"u_min": [1.0], "u_max": [-1.0]}, gc.ArgumentError),
    ({"u_min": [0.5]}, gc.ArgumentError), ({"u_min": [np.nan]}, gc.ArgumentError), ({"name": 3}, gc.ArgumentTypeError),
])
def test_lqr_bad_arguments(kw, exc):
    args = {"model": _Linear(), "x_e": [0.0, 0.0], "u_e": [0.0]} | kw
    with pytest.raises(exc):
        lqr_state_feedback(args.pop("model"), args.pop("x_e"), args.pop("u_e"), **args)


class _Blowup:
    """x' = 1 / (1 - x) + u: the state reaches the pole x = 1 from x0 = 0.9 in finite time without feedback."""

    state_names = ("x",)
    input_names = ("u",)

    def rhs(self, x, u):
        x = np.asarray(x)
        with np.errstate(all="ignore"):
            return np.where(x < 1.0, 1.0 / (1.0 - x), np.nan) + np.asarray(u)


def test_non_finite_derivatives_are_not_zeroed():
    """A run that leaves the model's domain used to get d = 0 there (frozen silently, counted as a plain failure);
    now the batch raises a SolverError naming the run, unless diverged= freezes it explicitly."""
    zero = lambda t, X: np.zeros((len(X), 1))  # noqa: E731
    X0 = np.array([[0.9], [-5.0]])
    with pytest.raises(gc.SolverError, match="non-finite"):
        compare_controllers(_Blowup(), {"none": zero}, X0, [0.0], [0.0], 1.0, method="RK45")
    out = compare_controllers(_Blowup(), {"none": zero}, X0, [0.0], [0.0], 1.0, method="RK45",
                              diverged=lambda X: X[:, 0] > 0.95)
    assert not out.records["none"].converged.any()


def test_controller_returning_wrong_shape_or_nan():
    m = _Linear()
    X0 = np.array([[0.1, 0.0], [0.0, 0.1]])
    with pytest.raises(gc.ArgumentError, match="'two'"):
        compare_controllers(m, {"two": lambda t, X: np.zeros((len(X), 2))}, X0, [0.0, 0.0], [0.0], 1.0)
    with pytest.raises(gc.ArgumentTypeError):
        compare_controllers(m, {"none": lambda t, X: None}, X0, [0.0, 0.0], [0.0], 1.0)
    with pytest.raises(gc.SolverError, match="non-finite input"):
        compare_controllers(m, {"nan": lambda t, X: np.full((len(X), 1), np.nan)}, X0, [0.0, 0.0], [0.0], 1.0)


def test_user_callback_errors_pass_through():
    class Boom(Exception):
        pass

    def ctrl(t, X):
        raise Boom("mine")

    with pytest.raises(Boom):
        compare_controllers(_Linear(), {"boom": ctrl}, np.zeros((1, 2)), [0.0, 0.0], [0.0], 1.0)


@pytest.mark.parametrize(("kw", "exc"), [
    ({"controllers": {}}, gc.ArgumentError), ({"controllers": {"x": "lqr"}}, gc.ArgumentTypeError),
    ({"controllers": [1]}, gc.ArgumentTypeError), ({"x0": np.zeros((2, 3))}, gc.ArgumentError),
    ({"x0": np.zeros(2)}, gc.ArgumentError), ({"t_final": 0.0}, gc.ArgumentError),
    ({"t_final": "10"}, gc.ArgumentTypeError), ({"t_final": np.inf}, gc.ArgumentError),
    ({"scale": [1.0, 0.0]}, gc.ArgumentError), ({"n_out": 1}, gc.ArgumentError),
    ({"method": "Euler"}, gc.ArgumentError), ({"rtol": -1.0}, gc.ArgumentError),
    ({"diverged": 3}, gc.ArgumentTypeError), ({"max_evaluations": 0}, gc.ArgumentError),
])
def test_compare_bad_arguments(kw, exc):
    c = lqr_state_feedback(_Linear(), [0.0, 0.0], [0.0])
    args = {"controllers": {"lqr": c}, "x0": np.zeros((2, 2)), "t_final": 5.0} | kw
    with pytest.raises(exc):
        compare_controllers(_Linear(), args.pop("controllers"), args.pop("x0"), [0.0, 0.0], [0.0],
                            args.pop("t_final"), **args)


def test_compare_budgets():
    c = lqr_state_feedback(_Linear(), [0.0, 0.0], [0.0])
    X0 = np.array([[0.5, 0.0]])
    with pytest.raises(gc.BudgetError, match="max_evaluations"):
        compare_controllers(_Linear(), {"lqr": c}, X0, [0.0, 0.0], [0.0], 1e6, method="RK45", max_evaluations=50)
    with pytest.raises(gc.BudgetError, match="size"):
        compare_controllers(_Linear(), {"lqr": c}, np.zeros((400_000, 2)), [0.0, 0.0], [0.0], 1.0)
    r = compare_controllers(_Linear(), {"lqr": c}, X0, [0.0, 0.0], [0.0], 5.0).records["lqr"]
    assert 0 < r.evaluations <= 2_000_000


@pytest.mark.parametrize("method, n_out", [("BDF", 8001), ("batch", 401)])  # batch steps on every output time
def test_batch_metrics_on_an_integrator(method, n_out):
    # x' = u, u = -x: x = x0 exp(-t); peak |u| = |x0|, int |u| = |x0| (1 - exp(-T)), settling ln(|x0| / settle)
    c = lqr_state_feedback(_Integrator(), [0.0], [0.0], Q=[1.0], R=[1.0])
    np.testing.assert_allclose(c.K, [[1.0]])
    x0 = np.array([[0.5], [-1.0], [2.0]])
    T = 8.0
    r = compare_controllers(_Integrator(), {"lqr": c}, x0, [0.0], [0.0], T, settle=0.05, n_out=n_out, rtol=1e-10,
                            atol=1e-12, method=method).records["lqr"]
    assert r.converged.all() and r.fraction == 1.0
    np.testing.assert_allclose(r.peak_u[:, 0], np.abs(x0[:, 0]), rtol=1e-9)
    np.testing.assert_allclose(r.integrated_u[:, 0], np.abs(x0[:, 0]) * (1 - np.exp(-T)), rtol=1e-7)
    # the settling time is read on the output grid (spacing T / (n_out - 1))
    np.testing.assert_allclose(r.settling_time, np.log(np.abs(x0[:, 0]) / 0.05), atol=2e-3 + T / (n_out - 1))


def test_saturation_shrinks_the_simulated_region():
    m = _Linear()
    X0 = np.random.default_rng(0).uniform(-1.0, 1.0, (300, 2))
    free = lqr_state_feedback(m, [0.0, 0.0], [0.0])
    sat = lqr_state_feedback(m, [0.0, 0.0], [0.0], u_min=[-1.0], u_max=[1.0], name="sat")
    out = compare_controllers(m, {"free": free, "sat": sat}, X0, [0.0, 0.0], [0.0], 15.0,
                              diverged=lambda X: np.abs(X).max(axis=1) > 50)
    assert out.records["free"].fraction == 1.0
    assert 0.2 < out.records["sat"].fraction < 1.0
    assert np.all(out.records["sat"].peak_u <= 1.0 + 1e-12)
    assert np.all(out.common == out.records["sat"].converged)


def test_table_rows_compare_on_the_common_runs():
    from glidectl.analysis.closed_loop import BatchComparison, ControllerRecord

    conv_a = np.array([True, True, True, False])
    conv_b = np.array([True, False, True, True])
    peak_a = np.array([[1.0, 10.0], [2.0, 20.0], [3.0, 30.0], [9.0, 90.0]])
    a = ControllerRecord("A", conv_a, peak_a, 2 * peak_a, np.array([1.0, 2.0, 5.0, np.inf]))
    b = ControllerRecord("B", conv_b, peak_a / 10, peak_a / 5, np.array([4.0, np.inf, 6.0, 1.0]))
    never = ControllerRecord("C", np.zeros(4, bool), peak_a, peak_a, np.full(4, np.inf))
    cmp = BatchComparison(np.zeros((4, 2)), np.zeros(2), np.ones(2), 10.0, 0.02, 0.05, {"A": a, "B": b})
    # common runs: 0 and 2; medians over those two only (run 1 converged for A alone, run 3 for B alone)
    assert cmp.table_rows() == [["A", "75.0%", "2, 20", "3, 30", "4, 40", "3.00"],
                                ["B", "75.0%", "0.2, 2", "0.3, 3", "0.4, 4", "5.00"]]
    assert len(cmp.table_rows()[0]) == len(BatchComparison.TABLE_HEADER)
    none = BatchComparison(np.zeros((4, 2)), np.zeros(2), np.ones(2), 10.0, 0.02, 0.05, {"A": a, "C": never})
    assert none.table_rows() == [["A", "75.0%", "-", "-", "-", "-"], ["C", "0.0%", "-", "-", "-", "-"]]


# ------------------------------------------------------------------------------------------ method="batch"
@pytest.mark.parametrize("method", ["batch", "RK45"])
def test_non_finite_derivatives_raise_or_freeze_with_either_integrator(method):
    zero = lambda t, X: np.zeros((len(X), 1))  # noqa: E731
    X0 = np.array([[0.9], [-5.0]])
    with pytest.raises(gc.SolverError, match="non-finite"):
        compare_controllers(_Blowup(), {"none": zero}, X0, [0.0], [0.0], 1.0, method=method)
    rec = compare_controllers(_Blowup(), {"none": zero}, X0, [0.0], [0.0], 1.0, method=method,
                              diverged=lambda X: X[:, 0] > 0.95).records["none"]
    assert not rec.converged.any()


def test_batch_freezes_a_run_where_it_is_flagged():
    # x' = 1 from x0 = 0 and 0.5: the second run crosses x = 1 at t = 0.5 and is frozen there (held, not converged)
    class _Drift:
        state_names = ("x",)
        input_names = ("u",)

        def rhs(self, x, u):
            return np.ones_like(np.asarray(x, dtype=float)) + np.asarray(u)

    zero = lambda t, X: np.zeros((len(X), 1))  # noqa: E731
    out = compare_controllers(_Drift(), {"none": zero}, np.array([[0.0], [0.5]]), [0.2], [0.0], 0.2, tol=1e-6,
                              diverged=lambda X: X[:, 0] > 0.6, n_out=5)
    rec = out.records["none"]
    np.testing.assert_array_equal(rec.converged, [True, False])  # run 0 ends at x = 0.2 exactly (x' = 1)
    np.testing.assert_allclose(rec.integrated_u, 0.0)
    assert rec.settling_time[1] == np.inf


def test_batch_budget_and_bad_diverged():
    c = lqr_state_feedback(_Linear(), [0.0, 0.0], [0.0])
    X0 = np.array([[0.5, 0.0]])
    with pytest.raises(gc.BudgetError, match="max_evaluations"):
        compare_controllers(_Linear(), {"lqr": c}, X0, [0.0, 0.0], [0.0], 1e6, max_evaluations=50)
    with pytest.raises(gc.ArgumentError, match="one flag per run"):
        compare_controllers(_Linear(), {"lqr": c}, X0, [0.0, 0.0], [0.0], 1.0,
                            diverged=lambda X: np.zeros(len(X) + 1, bool))


def test_batch_equals_stacked_solve_ivp_with_saturation():
    """The per-run integrator (default) and one stacked BDF ODE give the same comparison to their tolerances."""
    m = _Linear()
    X0 = np.random.default_rng(3).uniform(-1.0, 1.0, (16, 2))
    sat = lqr_state_feedback(m, [0.0, 0.0], [0.0], u_min=[-1.0], u_max=[1.0], name="sat")
    kw = {"diverged": lambda X: np.abs(X).max(axis=1) > 50, "rtol": 1e-8, "atol": 1e-10, "n_out": 25}
    a = compare_controllers(m, {"sat": sat}, X0, [0.0, 0.0], [0.0], 12.0, **kw).records["sat"]
    b = compare_controllers(m, {"sat": sat}, X0, [0.0, 0.0], [0.0], 12.0, method="BDF", **kw).records["sat"]
    np.testing.assert_array_equal(a.converged, b.converged)
    assert 0 < a.fraction < 1
    c = a.converged
    np.testing.assert_allclose(a.peak_u[c], b.peak_u[c], rtol=1e-6)
    np.testing.assert_allclose(a.integrated_u[c], b.integrated_u[c], rtol=1e-6)
    np.testing.assert_array_equal(a.settling_time, b.settling_time)


def test_batch_equals_stacked_solve_ivp_on_the_elevator_glider():
    ev = gc.load_vehicle("elevator_ch6")
    eq = gc.elevator_equilibrium(ev, 1.0, -np.pi / 4)
    model = gc.ElevatorBuoyancyGlider(ev)
    box = np.array([0.6, 0.8, 0.3, 1.0, 1.3])
    X0 = eq.state + np.random.default_rng(7).uniform(-1.0, 1.0, (3, 5)) * box
    ctrl = {"nl": gc.ElevatorBuoyancyController(eq, ev, 1.0)}
    kw = {"scale": box, "diverged": lambda X: X[:, 0] < 0.1, "rtol": 1e-8, "atol": 1e-10, "n_out": 11}
    ue = np.array([0.0, eq.u2e])
    a = compare_controllers(model, ctrl, X0, eq.state, ue, 8.0, **kw).records["nl"]
    b = compare_controllers(model, ctrl, X0, eq.state, ue, 8.0, method="LSODA", **kw).records["nl"]
    np.testing.assert_array_equal(a.converged, b.converged)
    np.testing.assert_allclose(a.integrated_u, b.integrated_u, rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(a.peak_u, b.peak_u, rtol=1e-5, atol=1e-9)
