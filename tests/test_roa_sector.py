"""Saturation in the SOS path (glidectl.roa.sector, gc.certify_roa of a SaturatedLoop, method 'sos-sector'): the
exact graph of sat as S-procedure terms; exact regions on synthetic loops, soundness on the saturated loop,
agreement with the LMI path, bad inputs."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov

import glidectl as gc
from glidectl.batch import integrate_batch
from glidectl.roa import Poly, max_level, sector_system

warnings.filterwarnings("ignore", message="Solution may be inaccurate")

SMALL = dict(iterations=1, solver=dict(extra=0), sampling=dict(n_truth=32, n_verify=600, n_simulate=4))


def _loop(name, F, K, lo, hi, box):
    """``x' = F(x) + e_n w`` with ``w = sat(K x)``."""
    n = K.shape[1]
    B = np.eye(n)[:, -1:]
    return gc.SaturatedLoop(name, tuple(f"x{i + 1}" for i in range(n)), ("u",),
                            lambda X, W: F(X) + W @ B.T, np.zeros(n), K, np.array([lo]), np.array([hi]),
                            (-np.full(n, box), np.full(n, box)))


A2 = np.array([[0.0, 1.0], [1.0, 0.0]])          # open-loop unstable
K2 = np.array([[-2.0, -2.0]])
ACL2 = A2 + np.array([[0.0], [1.0]]) @ K2


def test_graph_terms_describe_the_saturation_exactly():
    sl = _loop("lin2", lambda X: X @ A2.T, K2, -1.0, 0.5, 3.0)       # asymmetric levels
    ps = sector_system(sl)
    assert ps.method == "sos-sector" and ps.z_names[-1] == "sat(u)" and ps.inputs == (2,)
    assert ps.state_names == ("x1", "x2") and len(ps.cuts) == 2       # the box, one cut per state
    g1, g2 = ps.valid[-2:]
    h = ps.equalities[-1]
    rng = np.random.default_rng(0)
    X = rng.uniform(-3, 3, (2000, 2))
    Z = ps.lift(X)
    u = X @ K2.T[:, 0]
    np.testing.assert_allclose(Z[:, 2], np.clip(u, -1.0, 0.5))       # the lift carries sat(K x)
    assert np.all(g1(Z) >= -1e-12) and np.all(g2(Z) >= -1e-12) and np.max(np.abs(h(Z))) < 1e-12
    # off the graph a term is violated: v within the levels but v != sat(u)
    Zb = Z.copy()
    Zb[:, 2] = rng.uniform(-1.0, 0.5, 2000)
    off = np.abs(Zb[:, 2] - Z[:, 2]) > 1e-3
    viol = (g1(Zb) < -1e-12) | (g2(Zb) < -1e-12) | (np.abs(h(Zb)) > 1e-12)
    assert np.all(viol[off])
    # the polynomial F(x, v) is the loop on the graph
    np.testing.assert_allclose(ps.zdot(Z)[:, :2], sl.rhs(X), atol=1e-12)


def test_scalar_loop_reaches_its_exact_region():
    # x' = x + sat(-2x): x' = -x for |x| <= 1/2, x' = x - sign(x) beyond, equilibria at +-1: the region is |x| < 1
    sl = _loop("scalar", lambda X: X, np.array([[-2.0]]), -1.0, 1.0, 2.0)
    cert = gc.certify_roa(sl, degree=2, **{**SMALL, "solver": dict(extra=0, backoff=0.01)})
    assert cert.method == "sos-sector" and cert.certified, cert.verification.failing()
    assert all(e[1] == 0 for e in cert.V.terms)                       # V does not depend on sat(u)
    X = np.linspace(-2, 2, 4001)[:, None]
    ins = X[cert.contains(X), 0]
    assert 0.985 <= min(-ins.min(), ins.max()) and max(-ins.min(), ins.max()) < 1.0


@pytest.fixture(scope="module")
def lin2():
    sl = _loop("lin2", lambda X: X @ A2.T, K2, -1.0, 1.0, 3.0)
    return sl, gc.certify_roa(sl, degree=2, **SMALL)


def test_saturated_unstable_loop_certificate_is_sound(lin2):
    sl, cert = lin2
    assert cert.certified, cert.verification.failing()
    Xb = np.random.default_rng(3).uniform(-3, 3, (20000, 2))
    X = np.concatenate([Xb[cert.contains(Xb)], cert.sample(64, seed=4, boundary=True)])
    assert X.shape[0] > 2000 and np.all(cert.contains(X)) and np.all(np.abs(X) <= 3.0)
    assert np.max(np.abs(X @ K2.T)) > 1.5                            # the set reaches well into saturation
    vd = gc.dVdt(cert.V, cert.system.lift, sl.rhs, X)                # the true saturated loop
    assert np.all(vd < 0)
    res = integrate_batch(sl.rhs, X[-8:], 30.0, rtol=1e-6, atol=1e-10)          # outermost samples
    assert np.all(res.converged_to(np.zeros(2), 1e-4))
    # never beyond the true region: box points whose simulations diverge are not in the certified set
    far = np.array([[2.9, 2.9], [-2.9, -2.9], [2.5, 1.5]])
    diverge = ~integrate_batch(sl.rhs, far, 30.0, rtol=1e-8, atol=1e-11, bound=1e3).converged_to(np.zeros(2), 1e-3)
    assert not np.any(cert.contains(far[diverge]))


def test_degree_4_sos_sector_certificate_is_sound_and_larger_than_degree_2(lin2):
    """At degree 4 the containment conditions leave the saturated-input variable out (a box cut and V do not involve
    it; with it in the multipliers the Gram matrix had a structural near-zero eigenvalue, and the final check failed
    at every backoff). The certificate is sound on the true loop and larger than the degree-2 one."""
    sl, cert2 = lin2
    cert = gc.certify_roa(sl, degree=4, iterations=4, solver=dict(extra=0), sampling=dict(n_truth=256, n_verify=2000,
                                                                                          n_simulate=16))
    assert cert.method == "sos-sector" and cert.degree == 4 and cert.certified, cert.verification.failing()
    assert all(e[2] == 0 for e in cert.V.terms)                       # V does not depend on sat(u)
    assert cert.volume(n=2**12) > cert2.volume(n=2**12)
    Xb = np.random.default_rng(5).uniform(-3, 3, (20000, 2))
    X = np.concatenate([Xb[cert.contains(Xb)], cert.sample(64, seed=6, boundary=True)])
    assert np.all(gc.dVdt(cert.V, cert.system.lift, sl.rhs, X) < 0)
    res = integrate_batch(sl.rhs, X[-8:], 30.0, rtol=1e-6, atol=1e-10)          # outermost samples
    assert np.all(res.converged_to(np.zeros(2), 1e-4))


def test_sos_sector_level_equals_the_generalized_sector_lmi_level():
    # the same quadratic V (Lyapunov matrix of A + BK), a saturated linear loop: the SOS path with the exact graph
    # of sat and the LMI path with the generalized sector condition give the same largest level, and no level above
    # the true one (sampled: dV/dt >= 0 somewhere on a slightly larger ellipse)
    sl = _loop("lin2", lambda X: X @ A2.T, K2, -1.0, 1.0, 3.0)
    P = solve_continuous_lyapunov(ACL2.T, -np.eye(2))
    c_lmi = P[0, 0] / gc.certify_roa_lmi(sl, shape=P, backoff=0.0).P[0, 0]
    ps = sector_system(sl)
    Z = Poly.variables(ps.nz)
    V = P[0, 0] * Z[0] ** 2 + 2 * P[0, 1] * Z[0] * Z[1] + P[1, 1] * Z[1] ** 2
    c_sos = max_level(ps, V, extra=0).rho
    assert c_sos == pytest.approx(c_lmi, rel=1e-5)
    th = np.linspace(0, 2 * np.pi, 20000)
    L = np.linalg.cholesky(np.linalg.inv(P) * 1.02 * c_sos)
    Xb = np.stack([np.cos(th), np.sin(th)], 1) @ L.T
    assert np.max(2 * np.einsum("ni,ij,nj->n", Xb, P, sl.rhs(Xb))) > 0  # tight: 2 % more is not a certificate


def test_sos_sector_beats_the_lmi_remainder_bound_on_a_polynomial_loop():
    # with a quadratic term the LMI path bounds the remainder, the SOS path sees the polynomial itself
    def F(X):
        return np.stack([X[..., 1], X[..., 0] + 0.3 * X[..., 0] ** 2], -1)

    sl = _loop("quad", F, K2, -1.0, 1.0, 2.0)
    cert = gc.certify_roa(sl, degree=2, **SMALL)
    lmi = gc.certify_roa_lmi(sl, rounds=1, n_radii=4, refine=1, n_hessian=128, n_verify=300, n_simulate=2)
    assert cert.certified and lmi.certified
    assert cert.volume(n=2**12) > 1.2 * lmi.volume()
    Xb = np.random.default_rng(7).uniform(-2, 2, (20000, 2))
    X = Xb[cert.contains(Xb)]
    assert np.all(gc.dVdt(cert.V, cert.system.lift, sl.rhs, X) < 0)


def test_bad_saturated_loops_are_refused():
    sl = _loop("sin", lambda X: np.stack([X[..., 1], np.sin(X[..., 0])], -1), K2, -1.0, 1.0, 1.0)
    with pytest.raises(gc.ModelError, match=r"method 'exact'.*'surrogate'.*certify_roa_lmi"):
        sector_system(sl, max_degree=2, method="exact")
    lin = _loop("lin", lambda X: X @ A2.T, K2, -np.inf, np.inf, 1.0)
    with pytest.raises(gc.ModelError, match="no saturating channel"):
        gc.certify_roa(lin, degree=2)
    with pytest.raises(gc.ArgumentError, match="method"):
        gc.certify_roa(_loop("l", lambda X: X @ A2.T, K2, -1.0, 1.0, 1.0), degree=2, method="remainder")
    with pytest.raises(gc.ArgumentError, match="box must lie in the loop's box"):
        sector_system(sl, box=(np.array([-2.0, -0.5]), np.array([0.5, 0.5])))
    with pytest.raises(gc.ArgumentError, match="contain the equilibrium"):
        sector_system(sl, box=(np.array([0.1, -0.5]), np.array([0.5, 0.5])))
    with pytest.raises(gc.ArgumentTypeError, match="SaturatedLoop"):
        sector_system(gc.benchmarks.van_der_pol())
    with pytest.raises(gc.ArgumentTypeError):
        sector_system(lin, box_cuts=1)


def test_certificate_times_cover_the_whole_call_and_rounds_not_kept():
    """``wall_time`` and ``solve_time`` are those of the whole call: under a time limit the first round is verified
    at once, and the second round (not kept on this loop) ran after that certificate was made; its SDPs, and the
    remainder-box search's, are counted (solve_time is the sum of the history's SDP times)."""
    import time

    sl = _loop("sin", lambda X: np.stack([X[..., 1], np.sin(X[..., 0])], -1), K2, -1.0, 1.0, 2.0)
    t0 = time.perf_counter()
    cert = gc.certify_roa(sl, degree=2, **SMALL, budget=dict(time_limit=600.0))
    wall = time.perf_counter() - t0
    steps = [h.step for h in cert.history]
    assert "remainder-box round 2 not kept (not certified or not larger)" in steps
    assert any(s.startswith("remainder box r = ") for s in steps)
    assert 0.97 * wall - 0.01 <= cert.wall_time <= wall
    assert cert.solve_time == pytest.approx(sum(h.sdp_time for h in cert.history), rel=1e-12)


def test_non_polynomial_plant_gets_a_surrogate_and_a_sound_certificate():
    """x1' = x2, x2' = sin(x1) + sat(-2 x1 - 2 x2): the plant does not recast, so the SOS path takes a surrogate of
    it in (x, v) with its remainder bound (method 'sos-sector+remainder'); the certificate holds on the saturated
    loop itself, and its level set reaches where the input saturates."""
    sl = _loop("sin", lambda X: np.stack([X[..., 1], np.sin(X[..., 0])], -1), K2, -1.0, 1.0, 2.0)
    ps = sector_system(sl)
    assert ps.method == "sos-sector+remainder" and ps.inputs == (2,) and ps.remainder_bound is not None
    assert len(ps.cuts) == 2 and len(ps.valid) == 3          # x box cuts; v range, g1, g2 valid on the graph
    cert = gc.certify_roa(sl, degree=2, **SMALL)
    assert cert.certified and cert.method == "sos-sector+remainder"
    # the second remainder-box round ran and was not kept: the certificate is the first round's
    assert [h.step for h in cert.history if h.step.startswith("remainder-box round 2")] == [
        "remainder-box round 2: the box three times the extents of the certified set",
        "remainder-box round 2 not kept (not certified or not larger)"]
    local = [c for c in cert.verification.gram if c.name.startswith("local robust decrease")]
    assert len(local) == 1 and local[0].passed
    lo, hi = cert.box
    assert np.all(np.asarray(lo) >= -2.0) and np.all(np.asarray(hi) <= 2.0)
    X = np.concatenate([cert.sample(2000, seed=1), cert.sample(1000, seed=2, boundary=True)])
    assert np.all(cert.contains(X))
    r2 = np.sum(X**2, axis=1)
    assert np.all(gc.dVdt(cert.V, cert.system.lift, sl.rhs, X)[r2 > 1e-12] < 0)
    assert np.any(np.abs(X @ K2.T) > 1.0)                       # saturated points are certified
    res = integrate_batch(sl.rhs, cert.sample(64, seed=3, boundary=True), 40.0, rtol=1e-8, atol=1e-10)
    assert np.all(res.converged_to(np.zeros(2), 1e-4))
