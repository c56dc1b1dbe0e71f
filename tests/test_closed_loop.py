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
    with pytest.raises(gc.ModelError, match="shape"):
        lqr_state_feedback(_Linear(), [0.0], [0.0])


def test_batch_metrics_on_an_integrator():
    # x' = u, u = -x: x = x0 exp(-t); peak |u| = |x0|, int |u| = |x0| (1 - exp(-T)), settling ln(|x0| / settle)
    c = lqr_state_feedback(_Integrator(), [0.0], [0.0], Q=[1.0], R=[1.0])
    np.testing.assert_allclose(c.K, [[1.0]])
    x0 = np.array([[0.5], [-1.0], [2.0]])
    T = 8.0
    r = compare_controllers(_Integrator(), {"lqr": c}, x0, [0.0], [0.0], T, settle=0.05, n_out=8001, rtol=1e-10,
                            atol=1e-12).records["lqr"]
    assert r.converged.all() and r.fraction == 1.0
    np.testing.assert_allclose(r.peak_u[:, 0], np.abs(x0[:, 0]), rtol=1e-9)
    np.testing.assert_allclose(r.integrated_u[:, 0], np.abs(x0[:, 0]) * (1 - np.exp(-T)), rtol=1e-7)
    np.testing.assert_allclose(r.settling_time, np.log(np.abs(x0[:, 0]) / 0.05), atol=2e-3)


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
