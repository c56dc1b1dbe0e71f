"""Issue 17: certify_roa on any closed loop (exact recast or polynomial surrogate with a remainder bound), scaling,
budgets before allocation, and the certificate API (sample, box, scale, method, plot)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.batch import integrate_batch
from glidectl.errors import ArgumentError, BudgetError, ModelError
from glidectl.roa import dVdt, recast
from glidectl.roa.scaling import box_scale, resolve_box, scaled_lyapunov
from glidectl.roa.surrogate import surrogate_error, surrogate_system

B = 1.0                                   # damping
XE = np.array([0.3, 0.0])                 # equilibrium (theta_e = 0.3 rad under a constant torque sin(0.3))
BOX = ([-0.7, -1.2], [1.3, 1.2])
QUICK = {"iterations": 1, "sampling": dict(n_truth=256, n_verify=2000, n_simulate=32)}


class Pendulum:
    """Damped pendulum held at theta_e = 0.3 by a constant torque: not polynomial (sin theta)."""

    state_names = ("theta", "omega")
    input_names = ()
    name = "pendulum"
    provenance = "test"

    def __init__(self) -> None:
        self.equilibrium = XE.copy()
        self.calls = 0

    def rhs(self, X, u=None):
        self.calls += 1
        X = np.asarray(X)
        th, om = X[..., 0], X[..., 1]
        return np.stack([om, -np.sin(th) + math.sin(0.3) - B * om], axis=-1)


class Cubic:
    """A polynomial closed loop with its equilibrium away from the origin: x' = -(x - 1) - (x - 1)^3 + y - 2,
    y' = -2 (y - 2) + (x - 1)^2 (equilibrium (1, 2))."""

    state_names = ("x", "y")
    input_names = ()
    name = "cubic"
    equilibrium = np.array([1.0, 2.0])

    def rhs(self, X, u=None):
        X = np.asarray(X)
        a, b = X[..., 0] - 1.0, X[..., 1] - 2.0
        return np.stack([-a - a**3 + b, -2.0 * b + a**2], axis=-1)


@pytest.fixture(scope="module")
def pend_cert():
    return gc.certify_roa(Pendulum(), degree=2, box=BOX, **QUICK)


def test_remainder_bound_holds_on_dense_samples():
    ps = surrogate_system(Pendulum(), BOX)
    b = ps.remainder_bound
    assert b.n_fit < 10_000
    rng = np.random.default_rng(5)
    lo, hi = np.array(BOX[0]), np.array(BOX[1])
    X = lo + (hi - lo) * rng.random((200_000, 2))               # 20x more points than the fit and the grid
    edges = np.array([[lo[0], t] for t in np.linspace(lo[1], hi[1], 501)]
                     + [[t, hi[1]] for t in np.linspace(lo[0], hi[0], 501)])
    E, R = surrogate_error(ps, np.concatenate([X, edges]))
    assert np.all(E <= R)
    # the bound is cubic: the error is third order at the equilibrium (the quadratic allowance is rounding level)
    # and the cubic coefficient is not vacuous: within a factor 100 of the worst sampled error/|y|^3
    Y = ps.lift(X)
    r = np.linalg.norm(Y, axis=1)[:, None]
    assert np.all(b.quadratic < 1e-5 * np.max(b.cubic))
    ratio = np.max(E[: len(X), 1] / r[:, 0] ** 3)               # omega' (theta' = omega is exactly linear)
    assert b.cubic[1] >= ratio and b.cubic[1] < 100 * ratio
    assert np.allclose(R, b(ps.lift(np.concatenate([X, edges]))), rtol=1e-12)
    # the surrogate matches the exact linearization and the second derivatives of sin at the equilibrium
    A_true = gc.roa.programs.linearization(ps) * ps.scale[None, :] / ps.scale[:, None]
    A_p = np.array([[p.terms.get(tuple(int(k == j) for k in range(2)), 0.0) for j in range(2)] for p in ps.F])
    assert np.allclose(A_p, A_true, atol=1e-12)
    s0, s1 = ps.scale
    # omega' = -sin(theta) + ...: d^2/dy0^2 of g_1 = sin(0.3) s0^2 / s1, so the y0^2 coefficient is half that
    assert ps.F[1].terms.get((2, 0), 0.0) == pytest.approx(0.5 * math.sin(0.3) * s0**2 / s1, rel=1e-7)
    assert ps.F[0].terms.get((2, 0), 0.0) == 0.0 and ps.F[1].terms.get((1, 1), 0.0) == pytest.approx(0, abs=1e-9)


def test_surrogate_certificate_is_sound_on_the_true_model(pend_cert):
    cert = pend_cert
    assert cert.method == "surrogate+remainder" and cert.certified
    ps = cert.system
    # sampled true dV/dt < 0 inside the set, many more points than the verification used, boundary included
    X = np.concatenate([cert.sample(1500, seed=3), cert.sample(1000, seed=4, boundary=True)])
    assert np.all(cert.contains(X))
    vd = dVdt(cert.V, ps.lift, ps.rhs, X)
    r2 = np.sum((X - ps.equilibrium) ** 2, axis=1)
    assert np.all(vd[r2 > 1e-12] < 0)
    # the set lies in the box and is not trivial (more than 20 % of it)
    lo, hi = cert.box
    assert np.all(X >= lo) and np.all(X <= hi)
    assert cert.volume(n=2**12) / np.prod(np.array(hi) - np.array(lo)) > 0.2


def test_simulations_from_the_outermost_samples_converge(pend_cert):
    X0 = pend_cert.sample(64, seed=9, boundary=True)
    V0 = pend_cert.value(X0)
    assert np.all(V0 > 0.98 * pend_cert.rho)                    # really the outermost points
    res = integrate_batch(pend_cert.system.rhs, X0, 60.0, rtol=1e-8, atol=1e-10)
    assert np.all(res.converged_to(XE, 1e-4))


def test_certificate_api_fields(pend_cert, tmp_path):
    cert = pend_cert
    lo, hi = cert.box
    assert np.allclose(lo, BOX[0]) and np.allclose(hi, BOX[1])
    s = box_scale(cert.box, XE)
    assert np.allclose(s, [1.0, 1.2])
    assert cert.scale.shape == (2,) and np.all(cert.scale > 0) and np.all(cert.scale <= s * (1 + 1e-12))
    P = cert.sample(300, seed=1)
    assert P.shape == (300, 2) and np.all(cert.contains(P))
    assert np.array_equal(P, cert.sample(300, seed=1))
    with pytest.raises(ArgumentError):
        cert.sample(0)
    ax = cert.plot()
    path = tmp_path / "roa_general.png"
    ax.figure.savefig(path)
    assert path.stat().st_size > 10_000


def test_exact_recast_route_for_a_polynomial_loop():
    cert = gc.certify_roa(Cubic(), degree=2, box=([0.0, 1.0], [2.0, 3.0]), **QUICK)
    assert cert.method == "exact recast" and cert.certified
    X = cert.sample(500, seed=2)
    assert np.all(dVdt(cert.V, cert.system.lift, Cubic().rhs, X)[np.sum((X - [1, 2]) ** 2, axis=1) > 1e-12] < 0)
    with pytest.raises(ModelError, match=r"d\(omega\)/dt in theta"):
        gc.certify_roa(Pendulum(), degree=2, box=BOX, method="exact", **QUICK)


def test_recast_refusal_names_the_non_polynomial_terms():
    class Shifted:
        state_names = ("theta", "omega")
        equilibrium = np.zeros(2)
        box = (np.array([-1.0, -1.0]), np.array([1.0, 1.0]))

        def rhs(self, X):
            X = np.asarray(X)
            return np.stack([X[..., 1], -np.sin(X[..., 0] + 0.3) + math.sin(0.3) - X[..., 1]], axis=-1)

    with pytest.raises(ModelError) as exc:
        recast(Shifted(), max_degree=3)
    msg = str(exc.value)
    assert "d(omega)/dt in theta" in msg and "d(theta)/dt" not in msg and "surrogate" in msg
    assert "mixed_angle_states" not in msg


def test_missing_box_is_refused_clearly():
    with pytest.raises(ArgumentError, match=r"no limits known for states \['theta', 'omega'\].*box="):
        gc.certify_roa(Pendulum(), degree=2)
    with pytest.raises(ArgumentError, match="not strictly inside"):
        resolve_box(Pendulum(), ([0.5, -1.0], [1.0, 1.0]))
    lo, hi = resolve_box(Pendulum(), {"theta": (-1.0, 1.0), "omega": (-2.0, 2.0)})
    assert lo.tolist() == [-1.0, -2.0] and hi.tolist() == [1.0, 2.0]


def test_box_defaults_to_actuator_limits():
    veh = gc.load_vehicle("rogue").with_actuators(
        m0={"min": -0.3, "max": 0.9, "rate": 0.01}, r_P1={"min": -0.05, "max": 0.05, "rate": 0.01})
    glide = gc.steady_glide(veh, 0.3, math.radians(-25), r_p3=0.005)
    loop = gc.closed_loop(gc.lqr_glide(veh, glide))
    # the glider states have documented half-widths (validity_box); r_P3 has no actuator entry and the momenta
    # P_P1, P_P3 (force inputs) no limit: refused
    with pytest.raises(ArgumentError, match=r"no limits known for states \['r_P3', 'P_P1', 'P_P3'\].*'m0': \(-0.2994"):
        resolve_box(loop)
    lo, hi = resolve_box(loop, {k: (x - 0.1, x + 0.1) for k, x in zip(loop.state_names, loop.equilibrium, strict=True)
                                if k in ("r_P3", "P_P1", "P_P3")})
    i = loop.state_names.index("m0")
    assert (lo[i], hi[i]) == pytest.approx((0.3 - 0.999 * 0.6, 0.3 + 0.999 * 0.6), rel=1e-15)   # shrunk 0.1 %
    j = loop.state_names.index("r_P1")
    assert (lo[j], hi[j]) == pytest.approx((-0.999 * 0.05, 0.999 * 0.05), rel=1e-15)


def test_oversized_request_refused_before_any_allocation(monkeypatch):
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    def never(*args, **kwargs):
        raise AssertionError("a surrogate or recast was built before the size check")

    monkeypatch.setattr(routes, "surrogate_system", never)
    monkeypatch.setattr(routes, "recast", never)
    m = Pendulum()
    with pytest.raises(BudgetError, match="refused before building anything"):
        gc.certify_roa(m, degree=8, box=BOX, budget=dict(memory_limit=1e6))
    # nothing sampled, fitted or built: one batched evaluation only, the Jacobian at the equilibrium that finds the
    # held states (the size counts the free states; see test_roa_held)
    assert m.calls == 1
    with pytest.raises(BudgetError, match="max_degree"):
        gc.certify_roa(m, degree=10, box=BOX, budget=dict(max_degree=8))
    assert m.calls == 2


def test_scaled_lyapunov_start_solves_the_scaled_equation():
    A = np.array([[0.0, 1.0], [-math.cos(0.3), -B]])
    s = np.array([1.0, 1.2])
    V = scaled_lyapunov(A, s)
    P = np.array([[V.terms[(2, 0)], V.terms[(1, 1)] / 2], [V.terms[(1, 1)] / 2, V.terms[(0, 2)]]])
    Ay = A * s[None, :] / s[:, None]
    Qm = Ay.T @ P + P @ Ay
    assert np.allclose(Qm / Qm[0, 0], np.eye(2), atol=1e-10) and Qm[0, 0] < 0
    with pytest.raises(ModelError, match="not Hurwitz"):
        scaled_lyapunov(-A, s)


def test_estimate_sos_size_of_a_closed_loop_counts_the_surrogate_route():
    m = Pendulum()
    size = gc.estimate_sos_size(m, 4)
    assert m.calls == 0 and size.n_vars == 2
    gram = dict(size.gram)
    # the robust bound of dV/dt has degree 2 deg V (Young's inequality, (dV/dz_i)^2 |z|^2): with the extra
    # multiplier degree 2 of a 2-variable program, the decrease polynomial has degree 8 + 4 = 12, its half basis the
    # 27 monomials of degree 1 to 6 in 2 variables (an exact degree-3 system would need degree 10: 20)
    assert gram["decrease"] == 27 and set(gram) == {"decrease", "tau0", "tau1", "containment0", "sigma0",
                                                    "containment1", "sigma1", "positivity"}
    assert gc.estimate_sos_size(m, 6).bytes > size.bytes


def test_lqr_cost_to_go_start():
    """With weight Q + K^T R K the start is the closed loop's cost-to-go: A_cl^T P + P A_cl = -(Q + K^T R K)."""
    A = np.array([[0.0, 1.0], [0.0, 0.0]])
    Bm = np.array([[0.0], [1.0]])
    Q, R = np.diag([2.0, 1.0]), np.array([[0.5]])
    from scipy.linalg import solve_continuous_are

    S = solve_continuous_are(A, Bm, Q, R)
    K = np.linalg.solve(R, Bm.T @ S)
    s = np.array([2.0, 3.0])
    V = scaled_lyapunov(A - Bm @ K, s, Q + K.T @ R @ K)
    Py = np.array([[V.terms[(2, 0)], V.terms[(1, 1)] / 2], [V.terms[(1, 1)] / 2, V.terms[(0, 2)]]])
    Px = Py / s[:, None] / s[None, :]
    assert np.allclose(Px / Px[0, 0], S / S[0, 0], atol=1e-10)           # the Riccati solution, up to scale
    with pytest.raises(ArgumentError, match="positive definite"):
        scaled_lyapunov(A - Bm @ K, s, -np.eye(2))
    cert = gc.certify_roa(Pendulum(), degree=2, box=BOX, initial=np.diag([1.0, 2.0]), **QUICK)
    assert cert.certified and cert.method == "surrogate+remainder"


def _rogue_lqr_loop():
    veh = gc.load_vehicle("rogue")
    return gc.closed_loop(gc.lqr_glide(veh, gc.steady_glide(veh, 0.3, math.radians(-25), r_p3=0.005)))


def test_glider_loop_refusal_names_the_non_polynomial_dependencies():
    """The issue's user loop: the angle of attack atan2(v3, v1) and the body's rotation make the velocity and
    rate equations non-polynomial in (theta, v1, v3); the message says so and points to the surrogate route."""
    from glidectl.roa.routes import ShiftedModel

    loop = _rogue_lqr_loop()
    xe = loop.equilibrium
    with pytest.raises(ModelError) as exc:
        recast(ShiftedModel(loop, xe, (xe - 0.01, xe + 0.01)), max_degree=2)
    msg = str(exc.value)
    assert "d(v1)/dt in theta, v1, v3" in msg and "d(v3)/dt in theta, v1, v3" in msg
    assert "d(r_P1)/dt" not in msg and "mixed_angle_states" not in msg and "surrogate" in msg


def test_glider_torque_loop_remainder_bound_holds_on_dense_samples():
    """The 4-state torque-law closed loop of the chapter-5 sphere glider (not polynomial: 1/V, sin/cos gamma)."""
    loop = gc.closed_loop(gc.design_torque_control(gc.load_vehicle("sphere_ch5"), speed=1.5))
    xe = loop.equilibrium
    hw = np.array([0.1, 0.1, 0.03, 0.1])
    ps = surrogate_system(loop, (xe - hw, xe + hw))
    assert ps.method == "surrogate+remainder" and ps.remainder_bound.grid ** 4 <= 4096
    X = xe - hw + 2 * hw * np.random.default_rng(0).random((50_000, 4))      # 12x the grid, 20x the fit
    E, R = surrogate_error(ps, X)
    assert np.all(E <= R)
    assert np.max(E / R) > 1e-3                                               # and not absurdly loose
