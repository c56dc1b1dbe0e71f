"""LMI path of the region-of-attraction layer (glidectl.roa.lmi): saturated loops, generalized sector condition,
bounded remainder; soundness on the true saturated right-hand sides, agreement with the SOS path, bad inputs."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov

import glidectl as gc
from glidectl.batch import integrate_batch
from glidectl.roa import Poly, max_level, polynomial_system

FAST = dict(rounds=2, n_radii=4, refine=2, n_hessian=256, n_verify=1000, n_simulate=8)


def _loop(name, F, K, lo, hi, box, B=None):
    """``x' = F(x) + B w`` with ``w = sat(K x)`` (2 states unless F says otherwise)."""
    n = K.shape[1]
    B = np.eye(n)[:, -1:] if B is None else B
    return gc.SaturatedLoop(name, tuple(f"x{i + 1}" for i in range(n)), ("u",),
                            lambda X, W: F(X) + W @ B.T, np.zeros(n), K, np.array([lo]), np.array([hi]),
                            (-np.full(n, box), np.full(n, box)))


# --------------------------------------------------------------------------------------------- exact cases
def test_scalar_saturated_loop_reaches_its_exact_region_and_not_beyond():
    # x' = x + sat(-2x): stable for |x| < 1 (x' = -x inside |x| <= 1/2, x' = x - 1 beyond), equilibria at +-1
    sl = _loop("scalar", lambda X: X, np.array([[-2.0]]), -1.0, 1.0, 2.0)
    cert = gc.certify_roa_lmi(sl, backoff=0.0)
    half = 1 / np.sqrt(cert.P[0, 0])
    assert half <= 1.0 + 1e-6          # never beyond the true region (x = 1 is an equilibrium)
    assert half >= 0.99                # the generalized sector condition is lossless here
    assert cert.certified and cert.method == "lmi"
    assert cert.contains([[0.98 * half]])[0] and not cert.contains([[1.01]])[0]


def test_linear_saturated_loop_sector_condition_is_used_and_respected():
    A = np.array([[0.0, 1.0], [1.0, 0.0]])            # open-loop unstable
    K = np.array([[-2.0, -2.0]])
    sl = _loop("lin2", lambda X: X @ A.T, K, -1.0, 1.0, 3.0)
    cert = gc.certify_roa_lmi(sl)
    assert cert.certified
    X = np.concatenate([cert.sample(3000, seed=3), cert.sample(3000, seed=4, boundary=True)])
    v = X @ K.T
    assert np.max(np.abs(v)) > 1.5                   # the ellipsoid reaches well into saturation
    Gx = X @ cert.G.T
    assert np.max(np.abs(v - Gx)) <= 1.0 + 1e-6       # region |(K - G) x| <= u0 of the sector condition
    u0 = 1.0
    Kg = K - cert.G
    assert np.sqrt((Kg @ np.linalg.inv(cert.P) @ Kg.T)[0, 0]) <= u0 * (1 + 1e-6)
    psi = v - np.clip(v, -1.0, 1.0)
    assert np.all(psi * (psi - Gx) <= 1e-12)          # hence the sector inequality at every sample
    # true dV/dt < 0 (fresh samples), and the set is inside the box
    xdot = sl.rhs(X)
    assert np.all(np.einsum("ni,ij,nj->n", X, cert.P, xdot) < 0)
    assert np.all(np.abs(X) <= 3.0)
    # exact volume against quasi-Monte Carlo in the box
    assert cert.volume(box=sl.box, n=2**14) == pytest.approx(cert.volume(), rel=0.03)


# --------------------------------------------------------------------------------------------- agreement with SOS
def _sos_level(F, P0):
    Z = Poly.variables(2)
    ps = polynomial_system("p", ("x1", "x2"), F, box=(-np.ones(2), np.ones(2)))
    ps = dataclasses.replace(ps, cuts=(1 - Z[0] ** 2, 1 - Z[1] ** 2))     # the same box as the LMI's
    V = P0[0, 0] * Z[0] ** 2 + 2 * P0[0, 1] * Z[0] * Z[1] + P0[1, 1] * Z[1] ** 2
    return max_level(ps, V).rho


A_OL = np.array([[-1.0, 2.0], [0.0, -1.0]])
B_IN = np.array([[0.0], [1.0]])
K_FB = np.array([[-0.5, 0.0]])
A_CL = A_OL + B_IN @ K_FB
P_LYAP = solve_continuous_lyapunov(A_CL.T, -np.eye(2))


def test_unsaturated_linear_loop_fixed_shape_level_equals_sos_level():
    # the same quadratic V = x' P0 x (Lyapunov matrix of the loop), the same box |x_i| <= 1: both programs compute
    # the largest level inside the box (the decrease holds globally), the LMI by its box rows, the SOS program by
    # its containment multipliers; analytically min_i 1 / (P0^-1)_ii
    sl = _loop("lin", lambda X: X @ A_OL.T, K_FB, -np.inf, np.inf, 1.0)
    cert = gc.certify_roa_lmi(sl, shape=P_LYAP, backoff=0.0)
    c_lmi = P_LYAP[0, 0] / cert.P[0, 0]
    np.testing.assert_allclose(cert.P * c_lmi, P_LYAP, rtol=1e-9)            # the shape was kept
    Z = Poly.variables(2)
    c_sos = _sos_level([A_CL[i, 0] * Z[0] + A_CL[i, 1] * Z[1] for i in range(2)], P_LYAP)
    exact = 1 / np.max(np.diag(np.linalg.inv(P_LYAP)))
    assert c_lmi == pytest.approx(exact, rel=1e-6)
    assert c_sos == pytest.approx(exact, rel=1e-6)


def test_lmi_certifies_at_least_the_sos_degree2_certificate_on_an_unsaturated_linear_loop():
    # gc.certify_roa at degree 2 (with the box as cuts) returns V = x' P x at a backed-off level rho; the LMI with the
    # same shape P certifies a level >= rho (both are exact here: the level is set by the box), and the free-shape
    # LMI ellipsoid is at least as large as the SOS one
    Z = Poly.variables(2)
    ps = polynomial_system("lin", ("x1", "x2"), [A_CL[i, 0] * Z[0] + A_CL[i, 1] * Z[1] for i in range(2)],
                           box=(-np.ones(2), np.ones(2)))
    ps = dataclasses.replace(ps, cuts=(1 - Z[0] ** 2, 1 - Z[1] ** 2))
    sos = gc.certify_roa(ps, degree=2, iterations=1, sampling=dict(n_truth=64, n_verify=500, n_simulate=4),
                         solver=dict(extra=0))
    assert sos.certified
    t = sos.V.terms
    P = np.array([[t.get((2, 0), 0.0), t.get((1, 1), 0.0) / 2], [t.get((1, 1), 0.0) / 2, t.get((0, 2), 0.0)]])
    sl = _loop("lin", lambda X: X @ A_OL.T, K_FB, -np.inf, np.inf, 1.0)
    fixed = gc.certify_roa_lmi(sl, shape=P, backoff=0.0)
    c_lmi = P[0, 0] / fixed.P[0, 0]
    assert c_lmi >= sos.rho * (1 - 1e-6)
    assert c_lmi == pytest.approx(sos.rho_star, rel=1e-4)
    free = gc.certify_roa_lmi(sl)
    ellipse_sos = np.pi * sos.rho / np.sqrt(np.linalg.det(P))
    assert free.volume() >= ellipse_sos * (1 - 1e-6)


def test_unsaturated_polynomial_loop_lmi_level_is_below_the_sos_level():
    # with a quadratic term the LMI certifies the level of V through a bound on the remainder: it can only be more
    # conservative than the SOS level problem, which treats the polynomial exactly (never above it)
    def F(X):
        return X @ A_OL.T + np.stack([0 * X[..., 0], 0.8 * X[..., 0] ** 2], axis=-1)

    sl = _loop("quad", F, K_FB, -np.inf, np.inf, 1.0)
    cert = gc.certify_roa_lmi(sl, shape=P_LYAP, backoff=0.0, **{k: FAST[k] for k in ("n_radii", "refine")})
    c_lmi = P_LYAP[0, 0] / cert.P[0, 0]
    Z = Poly.variables(2)
    c_sos = _sos_level([A_CL[0, 0] * Z[0] + A_CL[0, 1] * Z[1],
                        A_CL[1, 0] * Z[0] + A_CL[1, 1] * Z[1] + 0.8 * Z[0] ** 2], P_LYAP)
    assert 0 < c_lmi <= c_sos * (1 + 1e-6)
    assert cert.certified
    # the remainder bound used holds on dense samples of the set (also checked in the verification)
    X = cert.sample(4000, seed=9)
    delta = F(X) + np.clip(X @ K_FB.T, -np.inf, np.inf) @ B_IN.T - X @ A_CL.T
    x = X / cert.scale
    bound2 = np.einsum("ni,jik,nk->nj", x, cert.remainder, x)
    assert np.all((delta / cert.scale) ** 2 <= bound2 * (1 + 1e-9) + 1e-24)


# --------------------------------------------------------------------------------------------- the glider loops
@pytest.fixture(scope="module")
def buoyancy():
    sph = gc.load_vehicle("sphere_ch5")
    beq = gc.buoyancy_equilibrium(sph, 1.5)
    loop = gc.closed_loop(gc.BuoyancyController(beq, sph, 5.0))
    return loop, gc.certify_roa_lmi(gc.saturated_loop(loop), rounds=1, n_radii=4, refine=1, n_hessian=128,
                                    n_verify=500, n_simulate=4)


def test_buoyancy_loop_extraction_is_the_loop():
    sph = gc.load_vehicle("sphere_ch5")
    beq = gc.buoyancy_equilibrium(sph, 1.5)
    c = gc.BuoyancyController(beq, sph, 5.0)
    loop = gc.closed_loop(c)
    sl = gc.saturated_loop(loop)
    assert sl.feedback_names == ("u1",)
    np.testing.assert_allclose(sl.K, [[0, 0, 0, 0, -c.rate_gain]])
    np.testing.assert_allclose([sl.u_lo[0], sl.u_hi[0]], [-0.02, 0.02])        # [actuators] m0.rate
    lo, hi = sl.box
    assert -1.0 < lo[4] < hi[4] < 1.0                                          # inside the pump range
    X = lo + (hi - lo) * np.random.default_rng(0).random((200, 5))
    np.testing.assert_allclose(sl.plant_rhs(X, sl.feedback(X)), loop.rhs(X), rtol=1e-12, atol=1e-15)


def test_buoyancy_loop_certificate_is_sound_on_the_true_loop(buoyancy):
    loop, cert = buoyancy
    assert cert.certified, cert.verification.failing()
    xe = loop.equilibrium
    X = np.concatenate([cert.sample(2000, seed=21), cert.sample(2000, seed=22, boundary=True)])
    assert np.all(cert.contains(cert.sample(500, seed=23)))
    lo, hi = cert.box
    assert np.all((X >= lo) & (X <= hi))
    dX = X - xe
    Vdot = 2 * np.einsum("ni,ij,nj->n", dX, cert.P, loop.rhs(X))                 # the loop's own right-hand side
    assert np.max(Vdot / np.sum((dX / cert.scale) ** 2, axis=1)) < 0
    # simulated convergence from boundary points (outermost samples)
    X0 = cert.sample(8, seed=24, boundary=True)
    res = integrate_batch(loop.rhs, X0, 200.0, rtol=1e-7, atol=1e-10)
    assert np.all(res.converged_to(xe, 1e-4))
    assert cert.volume_fraction > 0
    ax = cert.plot(dims=("V", "m0"))
    assert ax.get_xlabel().endswith("[m/s]") and ax.get_ylabel().endswith("[kg]")
    # the title (the loop's name, wrapped to the figure's width) stays inside the figure, even for a long name
    long = dataclasses.replace(cert, system=dataclasses.replace(cert.system, name=" ".join([cert.system.name] * 4)))
    for c in (cert, long):
        fig = c.plot(dims=("V", "m0")).figure
        fig.canvas.draw()
        box = fig.axes[0].title.get_window_extent(fig.canvas.get_renderer())
        assert box.x0 >= 0 and box.x1 <= fig.bbox.x1


def test_elevator_and_lqr_loops_are_extracted_with_their_saturations():
    ev = gc.load_vehicle("elevator_ch6")
    eq = gc.elevator_equilibrium(ev, 1.0, -np.pi / 4)
    sl = gc.saturated_loop(gc.closed_loop(gc.ElevatorBuoyancyController(eq, ev, 1.0)))
    assert sl.feedback_names == ("u1",) and sl.u_hi[0] == 0.05                    # the elevator is not fed back
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, 0.35, np.radians(-25.0), r_p3=0.05)
    ctrl = gc.lqr_glide(veh, glide, inputs="acceleration", actuate=("w1", "w4"), reduce_fixed=False)
    loop = gc.closed_loop(ctrl)
    assert len(gc.saturated_loop(loop).limits) == 6        # the actuators' ranges (tests/test_actuator_limits.py)
    sl = gc.saturated_loop(loop, actuator_limits=False)
    assert sl.feedback_names == ("w1", "w4") and sl.limits == ()
    assert np.isinf(sl.u_hi[0]) and sl.u_hi[1] == veh.actuators["m0"].rate
    assert [sl.state_names[i] for i in sl.held] == ["r_P3", "rdot_P3"]
    i = sl.state_names.index("rdot_P1")
    assert sl.box[1][i] == pytest.approx(0.999 * veh.actuators["r_P1"].rate)
    # the saturated loop equals gc.closed_loop's (unsaturated) one wherever w4 is not saturated
    rng = np.random.default_rng(1)
    lo, hi = sl.box
    X = lo + (hi - lo) * rng.random((400, sl.n))
    X[:, list(sl.held)] = sl.equilibrium[list(sl.held)]
    v = (X - sl.equilibrium) @ sl.K.T
    inside = np.abs(v[:, 1]) < 0.01
    assert inside.any() and (~inside).any()
    np.testing.assert_allclose(sl.rhs(X[inside]), loop.rhs(X[inside]), rtol=1e-12, atol=1e-15)
    m0 = sl.state_names.index("m0")
    np.testing.assert_allclose(sl.rhs(X[~inside])[:, m0], np.clip(v[~inside, 1], -0.01, 0.01))
    # explicit limits (absolute, one per plant input) override the vehicle's
    sl2 = gc.saturated_loop(loop, u_min=[-0.1, -1.0, -0.005], u_max=[0.2, 1.0, 0.005])
    np.testing.assert_allclose(np.c_[sl2.u_lo, sl2.u_hi], [[-0.1, 0.2], [-0.005, 0.005]])
    with pytest.raises(gc.ArgumentError, match="u_min < u_e < u_max"):
        gc.saturated_loop(loop, u_min=[0.1, -1.0, -0.005], u_max=[0.2, 1.0, 0.005])


# --------------------------------------------------------------------------------------------- bad inputs
def test_unstable_loop_is_refused():
    sl = _loop("unstable", lambda X: X, np.array([[-0.5]]), -1.0, 1.0, 2.0)     # x' = x + sat(-x/2)
    with pytest.raises(gc.ModelError, match="not exponentially stable"):
        gc.certify_roa_lmi(sl)


def test_loop_not_of_the_saturated_form_is_refused():
    sph = gc.load_vehicle("sphere_ch5")
    beq = gc.buoyancy_equilibrium(sph, 1.5)
    loop = gc.closed_loop(gc.BuoyancyGlider(sph), lambda x: np.tanh(x[..., 4:5] - beq.m0e), equilibrium=beq.state)
    with pytest.raises(gc.ArgumentTypeError, match="saturated linear state feedback"):
        gc.saturated_loop(loop)
    with pytest.raises(gc.ArgumentTypeError, match="ClosedLoop"):
        gc.saturated_loop(gc.benchmarks.van_der_pol())
    with pytest.raises(gc.ArgumentTypeError, match="saturated_loop"):
        gc.certify_roa_lmi(loop)
    with pytest.raises(gc.ArgumentTypeError, match="StateFeedback"):
        gc.saturated_loop(gc.BuoyancyGlider(sph), feedback=lambda t, x: x)


def test_infeasible_lmi_raises_solver_error():
    # P0 = I is not a Lyapunov matrix of A + BK = [[-1, 10], [0, -1]] (A'+A indefinite): no level of that shape
    A = np.array([[-1.0, 10.0], [0.0, 0.0]])
    sl = _loop("shear", lambda X: X @ A.T, np.array([[0.0, -1.0]]), -1.0, 1.0, 1.0)
    with pytest.raises(gc.SolverError, match="no ellipsoid of the given shape"):
        gc.certify_roa_lmi(sl, shape=np.eye(2))


def test_bad_arguments_raise_clear_errors():
    sl = _loop("lin", lambda X: -X, np.array([[-1.0, 0.0]]), -1.0, 1.0, 1.0)
    with pytest.raises(gc.ArgumentError, match="symmetric positive definite"):
        gc.certify_roa_lmi(sl, shape=-np.eye(2))
    with pytest.raises(gc.ArgumentError):
        gc.certify_roa_lmi(sl, solver="NOPE")
    with pytest.raises(gc.ArgumentError, match="bracket 0"):
        dataclasses.replace(sl, u_lo=np.array([0.5]))
    with pytest.raises(gc.ArgumentError, match="zero gain"):
        dataclasses.replace(sl, K=np.zeros((1, 2)))
    with pytest.raises(gc.ArgumentError, match="contain the equilibrium"):
        dataclasses.replace(sl, box=(np.zeros(2), np.ones(2)))
    with pytest.raises(gc.ArgumentTypeError):
        gc.certify_roa_lmi(sl, rounds=1.5)


def test_state_feedback_loop_is_extracted():
    # the ch6 design's saturated LQR on the buoyancy glider (gc.lqr_state_feedback with u_min/u_max)
    sph = gc.load_vehicle("sphere_ch5")
    beq = gc.buoyancy_equilibrium(sph, 1.5)
    plant = gc.BuoyancyGlider(sph)
    box = np.array([0.3, 0.3, 0.1, 0.3, 0.3])
    sf = gc.lqr_state_feedback(plant, beq.state, [0.0], Q=1 / box**2, R=[1 / 0.02**2], u_min=[-0.02], u_max=[0.02])
    sl = gc.saturated_loop(plant, feedback=sf)
    np.testing.assert_allclose(sl.K, -sf.K)
    assert (sl.u_lo[0], sl.u_hi[0]) == (-0.02, 0.02)
    X = sl.box[0] + (sl.box[1] - sl.box[0]) * np.random.default_rng(2).random((100, 5))
    np.testing.assert_allclose(sl.rhs(X), plant.rhs(X, sf(0.0, X)), rtol=1e-12)
    with pytest.raises(gc.ArgumentError, match="come from the StateFeedback"):
        gc.saturated_loop(plant, feedback=sf, u_max=[1.0])
