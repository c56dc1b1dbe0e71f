"""Issue 17: the surrogate route's remainder bound is cubic (the surrogate matches the loop to second order at the
equilibrium) and enters the decrease condition through Young's inequality, so it costs quartic terms only: loops
whose quadratic remainder defeated the linear decrease are certified, soundly."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.batch import integrate_batch
from glidectl.roa import dVdt
from glidectl.roa.polynomial import Poly
from glidectl.roa.surrogate import robust_decrease_bound, skeleton, surrogate_error, surrogate_system

XE = np.array([0.3, 0.0])
BOX = ([-1.2, -1.5], [1.8, 1.5])


class WeakPendulum:
    """A lightly damped pendulum (damping 0.3) held at theta_e = 0.3 by a constant torque, in a box of +-1.5 rad
    about it: its linear decrease is slow against the curvature of sin over the box."""

    state_names = ("theta", "omega")
    input_names = ()
    name = "weak pendulum"
    provenance = "test"
    equilibrium = XE

    def rhs(self, X, u=None):
        X = np.asarray(X)
        th, om = X[..., 0], X[..., 1]
        return np.stack([om, -np.sin(th) + math.sin(0.3) - 0.3 * om], axis=-1)


@pytest.fixture(scope="module")
def weak_cert():
    return gc.certify_roa(WeakPendulum(), degree=2, box=BOX, iterations=1, sampling=dict(n_truth=256, n_verify=2000,
                                                                                         n_simulate=32))


def test_lightly_damped_loop_is_certified_soundly(weak_cert):
    """With the quadratic remainder c |y|^2 of a first-order surrogate this loop was not certified (its local robust
    decrease failed: slack -0.395); with the cubic one it is, and the set is sound on the true model."""
    cert = weak_cert
    assert cert.certified and cert.method == "surrogate+remainder"
    local = [c for c in cert.verification.gram if c.name.startswith("local robust decrease")]
    assert len(local) == 1 and local[0].passed
    X = np.concatenate([cert.sample(1500, seed=3), cert.sample(1000, seed=4, boundary=True)])
    assert np.all(cert.contains(X))
    vd = dVdt(cert.V, cert.system.lift, cert.system.rhs, X)
    r2 = np.sum((X - XE) ** 2, axis=1)
    assert np.all(vd[r2 > 1e-12] < 0)
    lo, hi = cert.box
    assert cert.volume(n=2**12) / np.prod(np.asarray(hi) - np.asarray(lo)) > 0.1
    X0 = cert.sample(64, seed=9, boundary=True)
    res = integrate_batch(cert.system.rhs, X0, 120.0, rtol=1e-8, atol=1e-10)
    assert np.all(res.converged_to(XE, 1e-4))


def test_cubic_remainder_bound_holds_on_dense_samples():
    ps = surrogate_system(WeakPendulum(), BOX)
    b = ps.remainder_bound
    rng = np.random.default_rng(11)
    lo, hi = np.array(BOX[0]), np.array(BOX[1])
    X = lo + (hi - lo) * rng.random((100_000, 2))
    E, R = surrogate_error(ps, X)
    assert np.all(E <= R)
    # third order at the equilibrium: along a ray, the error falls like t^3 (the quadratic allowance is rounding)
    y = ps.lift(np.array([[0.9, 1.2]]))[0]
    errs = [surrogate_error(ps, ps.equilibrium[None, :] + (t * y * ps.scale)[None, :])[0][0, 1]
            for t in (0.2, 0.1)]
    assert 6.0 < errs[0] / errs[1] < 10.0
    assert np.max(b.quadratic) < 1e-5 * np.max(b.cubic)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(1, 4), seed=st.integers(0, 10_000), logk=st.floats(-3.0, 3.0))
def test_robust_decrease_bound_dominates_the_remainder_term(n, seed, logk):
    """For any k_i > 0: sum_i r_i |dV/dy_i| <= the polynomial bound, at every point (not only in a box), and the
    bound's quadratic part is sum_i a_i k_i / 2 |y|^2 (so a rounding-level a costs nothing near 0)."""
    rng = np.random.default_rng(seed)
    ps = skeleton(n, 3)
    q = ps.remainder_norm
    M = rng.normal(size=(n, n))
    V = Poly.quadratic(M @ M.T + 0.1 * np.eye(n))
    grads = [V.diff(i) for i in range(n)]
    a, b = rng.random(n), rng.random(n)
    k = np.exp(logk + rng.normal(size=n))
    W = robust_decrease_bound(ps, grads, [q * float(x) for x in a], b, k)
    Y = rng.normal(size=(500, n)) * rng.choice([1e-3, 1.0, 10.0], size=(500, 1))
    r = np.linalg.norm(Y, axis=1)
    G = np.stack([g(Y) for g in grads], axis=-1)
    exact = np.sum((a * r[:, None] ** 2 + b * r[:, None] ** 3) * np.abs(G), axis=1)
    assert np.all(W(Y) >= exact * (1 - 1e-12) - 1e-300)
    Wq = {e: c for e, c in W.terms.items() if sum(e) == 2}
    assert all(max(e) == 2 for e in Wq) and all(c == pytest.approx(float(np.sum(a * k)) / 2, rel=1e-12)
                                                  for c in Wq.values())
    assert all(sum(e) in (2, 4) for e in W.terms)


BIG = ([-2.2, -2.5], [2.8, 2.5])
OPTS = dict(degree=2, iterations=1, sampling=dict(n_truth=256, n_verify=2000, n_simulate=32))


def test_transported_V_is_the_same_function_of_the_states():
    from glidectl.roa.routes import transport

    a, b = surrogate_system(WeakPendulum(), BIG), surrogate_system(WeakPendulum(), BOX)
    assert not np.allclose(a.scale, b.scale)
    V = Poly.quadratic(np.array([[2.0, 0.3], [0.3, 1.0]]))
    X = XE + np.random.default_rng(2).uniform(-0.5, 0.5, (200, 2))
    np.testing.assert_allclose(transport(V, a, b)(b.lift(X)), V(a.lift(X)), rtol=1e-12)


def test_remainder_box_search_certifies_more_on_a_large_box():
    """On +-2.5 rad the remainder bound of the whole box is loose where the set lies: the search finds a smaller
    box (one more level SDP) and the certified set is larger, sound, and inside the box it reports."""
    whole = gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_search=0, box_rounds=1))
    cert = gc.certify_roa(WeakPendulum(), box=BIG, **OPTS)
    assert whole.certified and cert.certified
    np.testing.assert_allclose(whole.box, BIG)
    assert not any(h.step.startswith("remainder") for h in whole.history)
    steps = [h for h in cert.history if h.step.startswith("remainder box")]
    assert len(steps) >= 2 and steps[0].step.endswith("(the box)")
    lo, hi = (np.asarray(b) for b in cert.box)
    assert np.all(lo > np.asarray(BIG[0])) and np.all(hi < np.asarray(BIG[1]))
    assert cert.volume(n=2**14) > 1.05 * whole.volume(n=2**14)
    X = np.concatenate([cert.sample(1000, seed=5), cert.sample(500, seed=6, boundary=True)])
    assert np.all((X >= lo) & (X <= hi))
    vd = dVdt(cert.V, cert.system.lift, cert.system.rhs, X)
    assert np.all(vd[np.sum((X - XE) ** 2, axis=1) > 1e-12] < 0)
    with pytest.raises(gc.ArgumentError, match="box_search"):
        gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_search=-1))
    with pytest.raises(gc.ArgumentError, match="box_rounds"):
        gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_rounds=0))


def test_second_remainder_box_round_is_skipped_when_the_box_would_not_change():
    """The second round re-certifies on three times the extents of the first certificate. On this loop that box is
    within 10 % of the one used: the round is skipped, recorded, and the first certificate is returned as it was.
    (The kept path: tests/test_design_roa_certification.py, the elevator loop; the not-kept path:
    tests/test_roa_sector.py, the sin loop.)"""
    one = gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_rounds=1))
    two = gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_rounds=2))
    assert one.certified and two.certified
    rounds = [h.step for h in two.history if h.step.startswith("remainder-box round")]
    assert rounds == ["remainder-box round 2 skipped: the box would change by less than 10 %"]
    assert not any(h.step.startswith("remainder-box round") for h in one.history)
    np.testing.assert_array_equal(two.box, one.box)
    assert two.rho == one.rho and two.V.terms == one.V.terms
    # the first round's sampled checks ran after the round was skipped: the same as run at once
    assert two.verification == one.verification and two.verification.n_sampled > 0


def test_first_round_is_sampled_only_when_it_is_the_certificate_kept(monkeypatch: pytest.MonkeyPatch) -> None:
    """With a second remainder-box round, the first round's sampling and simulations wait: when the second round
    is kept (the whole box, no box search, on this loop) they never run; the second round's do, in full."""
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    calls: list[int] = []
    real = certificate.verify_certificate

    def counted(*a: object, **k: object) -> object:
        calls.append(int(k["n_verify"]))
        return real(*a, **k)

    monkeypatch.setattr(alternation, "verify_certificate", counted)
    cert = gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_search=0, box_rounds=2))
    steps = [h.step for h in cert.history if h.step.startswith("remainder-box round")]
    assert steps == ["remainder-box round 2: the box three times the extents of the certified set"]     # kept
    assert calls == [OPTS["sampling"]["n_verify"]]
    v = cert.verification
    assert cert.certified and v.n_sampled > 0 and v.n_simulated == v.n_converged == OPTS["sampling"]["n_simulate"]
    calls.clear()
    one = gc.certify_roa(WeakPendulum(), box=BIG, **OPTS, surrogate=dict(box_search=0, box_rounds=1))
    assert calls == [OPTS["sampling"]["n_verify"]] and one.certified
    assert cert.volume(n=2**14) > one.volume(n=2**14)


@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 5), seed=st.integers(0, 10_000))
def test_quadratic_part_inverts_quadratic(n, seed):
    rng = np.random.default_rng(seed)
    M = rng.normal(size=(n, n))
    p = Poly.quadratic(M) + Poly.const(1.5, n) + Poly.variables(n)[0] ** 3
    np.testing.assert_allclose(p.quadratic_part(), 0.5 * (M + M.T), rtol=1e-12, atol=1e-14)


def test_unsampled_checks_gate_without_certifying():
    """A verification with no samples yet (a first round waiting for its sampled checks) passes the unsampled checks
    that gate a second round, and is not ``passed``; a failing local check fails both."""
    from glidectl.roa.certificate import ROAVerification

    waiting = ROAVerification((), 1.0, -1.0, 0, float("nan"), 0, 0, 10.0)
    assert waiting.unsampled_passed and not waiting.passed
    assert not ROAVerification((), -1e-9, -1.0, 0, float("nan"), 0, 0, 10.0).unsampled_passed
    assert not ROAVerification((), 1.0, 1e-9, 0, float("nan"), 0, 0, 10.0).unsampled_passed
    done = ROAVerification((), 1.0, -1.0, 500, -0.3, 32, 32, 10.0)
    assert done.unsampled_passed and done.passed
