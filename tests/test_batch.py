"""Vectorized stiff batch integrator (glidectl.batch)."""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

import glidectl
from glidectl.batch import DIVERGED, FINISHED, STEP_UNDERFLOW, TIME_LIMIT, batch_jacobian, integrate_batch
from glidectl.errors import ArgumentError, ArgumentTypeError, BudgetError, GlidectlError, ModelError

A_STIFF = np.array([[-1.0, 1.0, 0.0], [0.0, -2000.0, 10.0], [0.0, 3.0, -0.5]])


@pytest.fixture(scope="module")
def glider():
    sp = glidectl.singular_perturbation(glidectl.load_vehicle("sphere_ch5"))
    scale = sp.tau_s * np.array([1.0 / sp.speed, 1.0, 1.0, sp.omega_scale])
    return sp, (lambda z: sp.model.rhs(sp.to_dimensional(z)) * scale)


@pytest.mark.parametrize("jac", ["complex", "central"])
def test_linear_stiff_matches_expm(jac):
    X0 = np.random.default_rng(1).normal(size=(40, 3))
    res = integrate_batch(lambda X: X @ A_STIFF.T, X0, 4.0, t_eval=[0.5, 2.0, 4.0], rtol=1e-8, atol=1e-10,
                          jacobian=jac)
    assert res.all_finished and res.samples.shape == (40, 3, 3)
    for k, tk in enumerate(res.t_eval):
        np.testing.assert_allclose(res.samples[:, k], X0 @ expm(tk * A_STIFF).T, atol=1e-7)
    np.testing.assert_array_equal(res.samples[:, -1], res.x_final)
    np.testing.assert_array_equal(res.t, 4.0)
    # stiffness: far fewer steps than an explicit method would need (|lambda| h < ~3 -> > 2600 steps)
    assert res.n_steps.max() < 1000


def test_fourth_order_convergence():
    X0 = np.array([[1.0, -1.0, 0.5]])
    exact = X0 @ expm(2.0 * A_STIFF).T
    errs = [np.abs(integrate_batch(lambda X: X @ A_STIFF.T, X0, 2.0, rtol=r, atol=r).x_final - exact).max()
            for r in (1e-5, 1e-9)]
    assert errs[1] < errs[0] * 1e-3


def test_batch_jacobian_methods_agree(glider):
    sp, f = glider
    Z = np.random.default_rng(2).uniform(-1, 1, (7, 4)) * [0.4, 1.5, 0.2, 0.1]
    Jc = batch_jacobian(f, Z, method="complex")
    Jd = batch_jacobian(f, Z, method="central")
    assert Jc.shape == (7, 4, 4)
    np.testing.assert_allclose(Jd, Jc, rtol=1e-5, atol=1e-5 * np.abs(Jc).max())
    lam = np.sort_complex(np.linalg.eigvals(batch_jacobian(f, np.zeros((1, 4)))[0]))
    np.testing.assert_allclose(lam, np.sort_complex(sp.full_eigenvalues), rtol=1e-8)
    assert lam.real.min() < -1000  # stiff on the t_n scale


def test_glider_matches_radau(glider):
    sp, f = glider
    np.testing.assert_allclose(f(np.full((1, 4), 0.05)), sp.full_rhs_nondimensional(np.full((1, 4), 0.05)),
                               rtol=1e-12, atol=1e-12)
    Z0 = np.random.default_rng(3).uniform(-1, 1, (20, 4)) * [0.4, np.pi / 2, 0.2, 0.1]
    res = integrate_batch(f, Z0, 10.0, t_eval=[3.0], rtol=1e-8, atol=1e-10)
    assert res.all_finished
    for i, z0 in enumerate(Z0):
        sol = solve_ivp(lambda t, z: f(z), (0, 10.0), z0, method="Radau", rtol=1e-9, atol=1e-11, t_eval=[3.0, 10.0],
                        jac=lambda t, z: batch_jacobian(f, z[None])[0])
        np.testing.assert_allclose(res.samples[i, 0], sol.y[:, 0], rtol=1e-5, atol=1e-7)
        np.testing.assert_allclose(res.x_final[i], sol.y[:, 1], rtol=1e-5, atol=1e-7)


def test_divergent_runs_flagged_without_breaking_others():
    # x' = x^2 blows up at t = 1/x0: x0 = 2 blows up before t = 1, the others do not
    X0 = np.array([[0.5], [2.0], [-1.0], [np.nan], [0.9]])
    res = integrate_batch(lambda X: X**2, X0, 1.0, rtol=1e-9, atol=1e-12, bound=1e6)
    assert res.status[1] in (DIVERGED, STEP_UNDERFLOW) and res.t[1] < 0.51
    assert res.status[3] == DIVERGED
    good = [0, 2, 4]
    np.testing.assert_array_equal(res.status[good], FINISHED)
    np.testing.assert_allclose(res.x_final[good, 0], X0[good, 0] / (1 - X0[good, 0]), rtol=1e-7)
    assert not res.all_finished and res.diverged[3] and "diverged" in res.summary()


def test_converged_to_classifies_region_of_attraction():
    """x' = -x + x^3: the origin attracts exactly (-1, 1); 1.2 blows up, 0.99 converges slowly, -0.5 fast."""
    X0 = np.array([[0.5], [-0.5], [0.99], [1.2]])
    res = integrate_batch(lambda X: -X + X**3, X0, 20.0, bound=1e6)
    np.testing.assert_array_equal(res.converged_to([0.0], 1e-3), [True, True, True, False])
    np.testing.assert_array_equal(res.converged_to([0.0], 1e-12), [False, False, False, False])


def test_hessian_matches_closed_form():
    from glidectl.derivatives import hessian

    f = lambda X: np.sin(X[..., 0]) * X[..., 1] ** 2 + X[..., 0] ** 3  # noqa: E731
    x, y = 0.3, -0.7
    exact = np.array([[-np.sin(x) * y**2 + 6 * x, 2 * np.cos(x) * y], [2 * np.cos(x) * y, 2 * np.sin(x)]])
    np.testing.assert_allclose(hessian(f, [x, y]), exact, rtol=1e-9, atol=1e-10)


def test_user_diverged_mask(glider):
    _, f = glider
    Z0 = np.array([[0.0, 0.3, 0.0, 0.0], [0.3, -1.0, 0.1, 0.0], [-0.95, 0.0, 0.0, 0.0]])
    res = integrate_batch(f, Z0, 10.0, diverged=lambda Z: Z[:, 0] < -0.9)
    assert res.status[2] == DIVERGED and res.t[2] == 0.0
    assert np.all(res.status[:2] == FINISHED)
    assert np.all(np.isnan(res.samples[2])) and res.samples.shape == (3, 0, 4)


@pytest.mark.parametrize("kwargs", [
    dict(X0=np.zeros((2, 2, 2))),
    dict(t_final=0.0),
    dict(t_final=np.nan),
    dict(rtol=-1.0),
    dict(rtol=0.0),
    dict(atol=[1.0, 2.0, 3.0]),
    dict(t_eval=[0.5, 0.2]),
    dict(t_eval=[2.0]),
    dict(max_steps=0),
    dict(h0=-1.0),
    dict(jacobian="forward"),
    dict(X0=np.ones((0, 2))),
    dict(h_min_rel=0.0),
    dict(bound=-1.0),
    dict(time_limit=-1.0),
    dict(on_budget="ignore"),
    dict(t_eval=[0.5, np.inf]),
])
def test_bad_inputs(kwargs):
    args = dict(f=lambda X: -X, X0=np.ones((3, 2)), t_final=1.0)
    args.update(kwargs)
    with pytest.raises(ArgumentError):
        integrate_batch(args.pop("f"), args.pop("X0"), args.pop("t_final"), **args)
    assert issubclass(ArgumentError, GlidectlError) and issubclass(ArgumentError, ValueError)


@pytest.mark.parametrize("kwargs", [
    dict(f="not a function"),
    dict(t_final="10"),
    dict(t0=None),
    dict(max_steps=10.0),
    dict(X0="ones"),
    dict(diverged=3),
    dict(rtol=True),
])
def test_bad_input_types(kwargs):
    args = dict(f=lambda X: -X, X0=np.ones((3, 2)), t_final=1.0)
    args.update(kwargs)
    with pytest.raises(ArgumentTypeError):
        integrate_batch(args.pop("f"), args.pop("X0"), args.pop("t_final"), **args)
    assert issubclass(ArgumentTypeError, TypeError)


def test_bad_outputs_of_callbacks_are_model_errors():
    with pytest.raises(ModelError, match="shape"):
        integrate_batch(lambda X: X[:, :1], np.ones((3, 2)), 1.0)
    with pytest.raises(ModelError, match="one bool per row"):
        integrate_batch(lambda X: -X, np.ones((3, 2)), 1.0, diverged=lambda X: np.zeros(1, dtype=bool))


def test_user_exceptions_pass_through():
    class Mine(Exception):
        pass

    def f(X):
        raise Mine("from the user's right-hand side")

    with pytest.raises(Mine):
        integrate_batch(f, np.ones((3, 2)), 1.0)


def test_time_limit_raises_or_stops():
    def slow(X):
        time.sleep(0.002)
        return X @ A_STIFF.T

    with pytest.raises(BudgetError, match="time limit"):
        integrate_batch(slow, np.ones((2, 3)), 1e4, time_limit=0.05)
    res = integrate_batch(slow, np.ones((2, 3)), 1e4, time_limit=0.05, on_budget="stop")
    assert res.stopped_by == "time_limit" and np.all(res.status == TIME_LIMIT) and np.all(res.t < 1e4)
    assert np.all(np.isfinite(res.x_final)) and "stopped by time_limit" in res.summary()
    done = integrate_batch(lambda X: -X, np.ones((2, 3)), 1.0, time_limit=60.0)
    assert done.stopped_by == "t_final" and done.all_finished


def test_singular_iteration_matrix_is_retried_not_raised():
    # J = 2/h0 I makes I/(gamma h0) - J singular at the first step; the step is rejected and retried smaller
    h0 = 0.01
    res = integrate_batch(lambda X: (2.0 / h0) * X * 0.0 + X * 0.0 - X, np.ones((1, 2)), 1.0, h0=h0,
                          jacobian=lambda X: np.broadcast_to(2.0 / h0 * np.eye(2), (X.shape[0], 2, 2)).copy())
    assert res.status[0] in (FINISHED, STEP_UNDERFLOW, DIVERGED)


def test_batch_jacobian_and_converged_to_check_inputs():
    with pytest.raises(ArgumentError):
        batch_jacobian(lambda X: -X, np.ones((2, 2)), method="forward")
    with pytest.raises(ArgumentError):
        batch_jacobian(lambda X: -X, [[np.nan, 1.0]])
    res = integrate_batch(lambda X: -X, np.ones((2, 2)), 1.0)
    with pytest.raises(ArgumentError):
        res.converged_to([0.0, 0.0, 0.0], 1e-3)
    with pytest.raises(ArgumentError):
        res.converged_to([0.0, 0.0], -1.0)
    with pytest.raises(ArgumentTypeError):
        res.converged_to([0.0, 0.0], "1e-3")


@pytest.mark.filterwarnings("ignore::numpy.exceptions.ComplexWarning")
def test_not_complex_safe_rhs_needs_central():
    def f(X):
        return -np.asarray(X, dtype=float)
    with pytest.raises(ModelError, match="central"):
        integrate_batch(f, np.ones((2, 2)), 1.0)
    assert integrate_batch(f, np.ones((2, 2)), 1.0, jacobian="central").all_finished


def test_max_steps_status():
    res = integrate_batch(lambda X: X @ A_STIFF.T, np.ones((2, 3)), 10.0, max_steps=3)
    assert np.all(res.status == 3) and np.all(res.t < 10.0)


def test_jacobian_of_the_leading_columns_only():
    """``columns=c``: the first c columns equal the full Jacobian's, the others are zero (states that do not enter f,
    e.g. running integrals), for both methods; a bad count is refused."""
    def f(X):
        return np.stack([X[:, 0] * X[:, 1], np.sin(X[:, 0]), X[:, 0] ** 2 + 0.0 * X[:, 2]], axis=-1)

    X = np.random.default_rng(3).normal(size=(5, 3))
    for method in ("complex", "central"):
        full = batch_jacobian(f, X, method=method)
        part = batch_jacobian(f, X, method=method, columns=2)
        np.testing.assert_allclose(part[:, :, :2], full[:, :, :2], rtol=0, atol=0 if method == "complex" else 1e-12)
        assert np.all(part[:, :, 2] == 0.0)
    with pytest.raises(ArgumentError):
        batch_jacobian(f, X, columns=4)
