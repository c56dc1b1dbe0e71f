"""State-dependent actuator limits of a saturated loop (gc.AffineLimit): gc.saturated_loop models the pump's range
and the battery's range and rate of a linear glide regulator as the ActuatedGlider law does, the loop keeps its
actuators in their ranges, the LMI path certifies it through the generalized sector condition, and gc.certify_roa
chooses that path for a saturated loop."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import glidectl as gc
from glidectl.models.actuated import ActuatedGlider, rate_interval
from glidectl.roa.certify import _auto_degree


@pytest.fixture(scope="module")
def slocum():
    """The slocum_shallow LQR dive-cycle loop of the roa design (w1, w4 fed back; r_P3 fixed) and its saturated
    form with the actuators' limits."""
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, 0.35, np.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    loop = gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration"))
    return veh, loop, gc.saturated_loop(loop)


def _box_points(sl, n, seed):
    lo, hi = sl.box
    return lo + (hi - lo) * np.random.default_rng(seed).random((n, sl.n))


def test_limits_are_the_actuated_glider_law(slocum):
    veh, loop, sl = slocum
    names = sl.state_names
    ip, iv, im = names.index("r_P1"), names.index("rdot_P1"), names.index("m0")
    assert {q.label.split()[0] for q in sl.limits} == {"r_P1", "m0"} and len(sl.limits) == 6
    X = _box_points(sl, 2000, 3)
    w = sl.feedback(X)
    v = (X - sl.equilibrium) @ sl.K.T
    tau, kp = ActuatedGlider.servo_time, ActuatedGlider.pump_gain
    a1, am = veh.actuators["r_P1"], veh.actuators["m0"]
    # battery: the requested rate rdot + tau w1 clipped to the rate interval of its position (ActuatedGlider.rhs)
    lo, hi = rate_interval(X[:, ip], a1.min, a1.max, a1.rate, 0.25 / tau)
    want_w1 = (np.clip(X[:, iv] + tau * v[:, 0], lo, hi) - X[:, iv]) / tau
    # pump: the requested rate clipped to the pump rate and its taper onto the m0 range
    lo, hi = rate_interval(X[:, im], am.min, am.max, am.rate, kp)
    want_w4 = np.clip(v[:, 1], lo, hi)
    np.testing.assert_allclose(w[:, 0], want_w1, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(w[:, 1], want_w4, rtol=1e-12, atol=1e-15)
    assert np.mean(w[:, 0] != v[:, 0]) > 0.5 and np.any(w[:, 1] != v[:, 1])      # the limits do act in the box
    # near the equilibrium nothing acts: the linearization is the closed loop's
    A_sat, _ = gc.jacobians(sl.rhs, sl.equilibrium, np.zeros(0))
    A_cl, _ = gc.jacobians(loop.rhs, loop.equilibrium, np.zeros(0))
    np.testing.assert_allclose(A_sat, A_cl, rtol=0, atol=1e-10 * np.max(np.abs(A_cl)))


def test_runs_keep_the_actuators_in_their_ranges(slocum):
    veh, loop, sl = slocum
    names = sl.state_names
    ip, iv, im = names.index("r_P1"), names.index("rdot_P1"), names.index("m0")
    a1, am = veh.actuators["r_P1"], veh.actuators["m0"]
    X0 = np.tile(sl.equilibrium, (4, 1))
    X0[:, names.index("theta")] += [0.4, -0.4, 0.0, 0.2]
    X0[:, names.index("v1")] += [0.0, 0.0, 0.15, -0.1]
    free = gc.saturated_loop(loop, actuator_limits=False)
    for x0 in X0:
        run = gc.simulate(sl, x0, 600.0)
        assert run.stopped_by == "t_final"
        assert np.all(run.x[:, ip] <= a1.max + 1e-9) and np.all(run.x[:, ip] >= a1.min - 1e-9)
        assert np.max(np.abs(run.x[:, iv])) <= a1.rate * (1 + 1e-6)
        assert np.all(np.abs(run.x[:, im]) <= am.max + 1e-9)
        assert np.max(np.abs(run.x[-1] - sl.equilibrium)) < 1e-6                   # and still converge
    # without the limits the first run drives the battery out of its range: the limits are what keeps it in
    run = gc.simulate(free, X0[0], 600.0)
    assert np.max(run.x[:, ip]) > 2 * a1.max


def test_affine_limit_validation(slocum):
    _, _, sl = slocum
    q = sl.limits[0]
    with pytest.raises(gc.ArgumentError, match="must hold strictly at the equilibrium"):
        dataclasses.replace(sl, limits=(gc.AffineLimit(q.channel, True, q.a, -0.1, "bad"),))
    with pytest.raises(gc.ArgumentError, match="must hold strictly at the equilibrium"):
        dataclasses.replace(sl, limits=(gc.AffineLimit(q.channel, False, q.a, 0.0, "bad"),))
    with pytest.raises(gc.ArgumentError, match="limit channel"):
        dataclasses.replace(sl, limits=(gc.AffineLimit(5, True, q.a, 0.1, "bad"),))
    with pytest.raises(gc.ArgumentError, match="shape"):
        dataclasses.replace(sl, limits=(gc.AffineLimit(0, True, np.ones(3), 0.1, "bad"),))
    with pytest.raises(gc.ArgumentTypeError, match="AffineLimit"):
        dataclasses.replace(sl, limits=((0, True, q.a, 0.1),))
    with pytest.raises(gc.ArgumentTypeError, match="actuator_limits"):
        gc.saturated_loop(_loop_of(slocum), actuator_limits="yes")


def _loop_of(slocum):
    return slocum[1]


def _toy(limit_b: float = 0.5):
    """x1' = x2, x2' = x1 + w with w = sat(-3 x1 - 2 x2) at +-2, and w <= 0.5 - x1 (a state-dependent upper
    limit of slope -1, the shape of a range taper)."""
    return gc.SaturatedLoop("toy", ("x1", "x2"), ("w",), lambda X, W: np.stack([X[..., 1], X[..., 0] + W[..., 0]],
                                                                              axis=-1),
                            np.zeros(2), np.array([[-3.0, -2.0]]), np.array([-2.0]), np.array([2.0]),
                            (-np.ones(2), np.ones(2)),
                            limits=(gc.AffineLimit(0, True, np.array([-1.0, 0.0]), limit_b, "taper"),))


def test_lmi_certificate_of_a_loop_with_a_state_dependent_limit_is_sound():
    sl = _toy()
    cert = gc.certify_roa(sl)                                                      # default: the LMI path
    assert isinstance(cert, gc.EllipsoidCertificate) and cert.method == "lmi" and cert.certified
    assert cert.rigorous                                  # a linear plant: no remainder, the LMIs are the proof
    assert np.isfinite(cert.verification.region_min_eig) and cert.verification.region_min_eig >= -1e-9
    X = cert.sample(400, seed=2, boundary=True)
    w = sl.feedback(X)
    v = (X - sl.equilibrium) @ sl.K.T
    assert np.any(w < v - 1e-9)                                                    # the limit acts on the set
    ens = gc.simulate_many(sl, X, 40.0)
    assert np.max(np.abs(ens.x_final)) < 1e-4                                       # and it converges
    dV = 2 * np.einsum("ni,ij,nj->n", X, cert.P, sl.rhs(X))
    assert np.all(dV < 0)
    # a tighter limit certifies a smaller set (the sector condition sees the limit)
    tight = gc.certify_roa(_toy(0.1))
    assert tight.certified and tight.volume() < cert.volume()


def test_certify_roa_routes(slocum):
    _, loop, sl = slocum
    with pytest.raises(gc.ArgumentError, match="method='lmi' needs a saturated loop"):
        gc.certify_roa(loop, method="lmi")
    with pytest.raises(gc.ModelError, match="state-dependent actuator limits"):
        gc.certify_roa(sl, degree=2)                                               # the SOS path cannot model them
    assert _auto_degree(gc.benchmarks.van_der_pol(), None) == 6
    assert _auto_degree(loop, None) == 2                                           # degree 4 would need ~1.6 TB


def test_certify_roa_takes_the_sos_path_for_constant_levels():
    sl = dataclasses.replace(_toy(), limits=())
    cert = gc.certify_roa(sl, iterations=1)
    assert isinstance(cert, gc.ROACertificate) and cert.method.startswith("sos-sector") and cert.certified
    X = cert.sample(200, seed=1, boundary=True)
    ens = gc.simulate_many(sl, X, 40.0)
    assert np.max(np.abs(ens.x_final)) < 1e-4
