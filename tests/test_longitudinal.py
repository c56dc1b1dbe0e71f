"""Longitudinal glider models (2.15)-(2.25), (2.30), (2.31)-(2.36): exact Jacobians, the force-to-acceleration
transform, batch evaluation and the reflection symmetry of the equations."""

from __future__ import annotations

import dataclasses
import itertools
from types import MappingProxyType

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl import ModelError, load_vehicle
from glidectl.derivatives import central_difference_jacobians, jacobians
from glidectl.models.longitudinal import (
    ACCEL_INPUTS,
    ACCEL_STATES,
    FORCE_INPUTS,
    FORCE_STATES,
    AccelerationControlledGlider,
    GlidePathModel,
    LongitudinalGlider,
)

FI = {s: i for i, s in enumerate(FORCE_STATES)}
AI = {s: i for i, s in enumerate(ACCEL_STATES)}

ROGUE = load_vehicle("rogue")
# every term of (2.13) and (2.11) switched on
ROGUE_FULL = load_vehicle("rogue", K_q=-1.5, K_L0=20.0, K_M0=0.5)
SLOCUM = load_vehicle("slocum_ch8")  # 'added' mass model: m1, m3 depend on m0
VEHICLES = {"rogue": ROGUE, "rogue_full": ROGUE_FULL, "slocum": SLOCUM}

FAST = settings(max_examples=50, deadline=None)

# ---------------------------------------------------------------------------------------- random states


def _u(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def force_states(draw: st.DrawFn) -> np.ndarray:
    """Non-equilibrium force-form states: v1 > 0.05 m/s, |theta| < 1.2 rad, |alpha| moderate."""
    return np.array([
        draw(_u(-10, 10)), draw(_u(-10, 10)),      # x, z
        draw(_u(-1.2, 1.2)), draw(_u(-0.8, 0.8)),  # theta, Omega2
        draw(_u(0.05, 1.5)), draw(_u(-0.4, 0.4)),  # v1, v3
        draw(_u(-0.1, 0.1)), draw(_u(-0.1, 0.1)),  # r_P1, r_P3
        draw(_u(-3.0, 3.0)), draw(_u(-1.0, 1.0)),  # P_P1, P_P3
        draw(_u(-1.0, 1.0)),                       # m0
    ])


@st.composite
def accel_states(draw: st.DrawFn) -> np.ndarray:
    return np.array([
        draw(_u(-10, 10)), draw(_u(-10, 10)),
        draw(_u(-1.2, 1.2)), draw(_u(-0.8, 0.8)),
        draw(_u(0.05, 1.5)), draw(_u(-0.4, 0.4)),
        draw(_u(-0.1, 0.1)), draw(_u(-0.5, 0.5)),  # r_P1, rdot_P1
        draw(_u(-0.1, 0.1)), draw(_u(-0.5, 0.5)),  # r_P3, rdot_P3
        draw(_u(-1.0, 1.0)),
    ])


inputs3 = st.tuples(_u(-5, 5), _u(-5, 5), _u(-0.5, 0.5)).map(np.array)
vehicle_names = st.sampled_from(sorted(VEHICLES))


def random_force_batch(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    x = np.column_stack([
        rng.uniform(-10, 10, n), rng.uniform(-10, 10, n), rng.uniform(-1.2, 1.2, n),
        rng.uniform(-0.8, 0.8, n), rng.uniform(0.05, 1.5, n), rng.uniform(-0.4, 0.4, n),
        rng.uniform(-0.1, 0.1, (n, 2)),
        rng.uniform(-3, 3, n), rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)])
    u = np.column_stack([rng.uniform(-5, 5, (n, 2)), rng.uniform(-0.5, 0.5, n)])
    return x, u


def random_accel_batch(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    x = np.column_stack([
        rng.uniform(-10, 10, n), rng.uniform(-10, 10, n), rng.uniform(-1.2, 1.2, n),
        rng.uniform(-0.8, 0.8, n), rng.uniform(0.05, 1.5, n), rng.uniform(-0.4, 0.4, n),
        rng.uniform(-0.1, 0.1, n), rng.uniform(-0.5, 0.5, n), rng.uniform(-0.1, 0.1, n),
        rng.uniform(-0.5, 0.5, n), rng.uniform(-1, 1, n)])
    w = np.column_stack([rng.uniform(-2, 2, (n, 2)), rng.uniform(-0.5, 0.5, n)])
    return x, w


def assert_jacobians_agree(f, x, u, rtol: float = 1e-6) -> None:
    A, B = jacobians(f, x, u)
    Ac, Bc = central_difference_jacobians(f, x, u)
    assert A.shape == (x.size, x.size) and B.shape == (x.size, u.size)
    assert np.all(np.isfinite(A)) and np.all(np.isfinite(B))
    scale_a = np.linalg.norm(A)
    scale_b = np.linalg.norm(B)
    assert scale_a > 0 and scale_b > 0
    assert np.linalg.norm(A - Ac) <= rtol * scale_a, np.abs(A - Ac).max()
    assert np.linalg.norm(B - Bc) <= rtol * scale_b, np.abs(B - Bc).max()


# ---------------------------------------------------------------------------------------- (a) Jacobians


@FAST
@given(name=vehicle_names, x=force_states(), u=inputs3)
def test_jacobian_force_model(name, x, u):
    assert_jacobians_agree(LongitudinalGlider(VEHICLES[name]).rhs, x, u)


@FAST
@given(name=vehicle_names, x=accel_states(), w=inputs3)
def test_jacobian_acceleration_model(name, x, w):
    assert_jacobians_agree(AccelerationControlledGlider(VEHICLES[name]).rhs, x, w)


@FAST
@given(name=vehicle_names, x=force_states(), u=inputs3, gamma_e=_u(-1.4, 1.4))
def test_jacobian_glide_path_model_force(name, x, u, gamma_e):
    model = GlidePathModel(LongitudinalGlider(VEHICLES[name]), gamma_e)
    assert_jacobians_agree(model.rhs, x[1:], u)


@FAST
@given(name=vehicle_names, x=accel_states(), w=inputs3, gamma_e=_u(-1.4, 1.4))
def test_jacobian_glide_path_model_acceleration(name, x, w, gamma_e):
    model = GlidePathModel(AccelerationControlledGlider(VEHICLES[name]), gamma_e)
    assert_jacobians_agree(model.rhs, x[1:], w)


def test_jacobian_known_entries():
    """Entries of the force-model Jacobian that can be read off (2.15)-(2.25) exactly."""
    veh = ROGUE_FULL
    x = np.array([1.0, 2.0, 0.3, 0.2, 0.5, 0.1, 0.03, -0.04, 1.1, 0.3, 0.4])
    u = np.array([0.7, -0.2, 0.05])
    A, B = jacobians(LongitudinalGlider(veh).rhs, x, u)
    assert A[FI["theta"], FI["Omega2"]] == pytest.approx(1.0, abs=1e-15)
    assert A[FI["r_P1"], FI["P_P1"]] == pytest.approx(1 / veh.mbar, rel=1e-14)
    assert A[FI["r_P1"], FI["v1"]] == pytest.approx(-1.0, rel=1e-14)
    assert A[FI["r_P3"], FI["r_P1"]] == pytest.approx(x[FI["Omega2"]], rel=1e-14)
    assert A[FI["x"], FI["v1"]] == pytest.approx(np.cos(x[2]), rel=1e-14)
    assert B[FI["P_P1"]] == pytest.approx([1, 0, 0], abs=1e-15)
    assert B[FI["m0"]] == pytest.approx([0, 0, 1], abs=1e-15)
    assert B[FI["v1"], 0] == pytest.approx(-1 / veh.m1, rel=1e-14)
    assert B[FI["Omega2"], 1] == pytest.approx(x[FI["r_P1"]] / veh.J2, rel=1e-14)
    assert B[FI["Omega2"], 0] == pytest.approx(-x[FI["r_P3"]] / veh.J2, rel=1e-14)
    # position does not enter the dynamics
    assert np.all(A[:, :2] == 0)


# ---------------------------------------------------------------------------------------- (b), (c) transform


def _rddot_from_force_model(acc: AccelerationControlledGlider, xa: np.ndarray, u: np.ndarray) -> np.ndarray:
    """rddot_P obtained by differentiating (2.21)-(2.22) along the force right-hand side."""
    mbar = acc.vehicle.mbar
    xf = acc.to_force_state(xa)
    fd = acc.force_model.rhs(xf, u)
    Om = xa[..., AI["Omega2"]]
    rP1, rdP1 = xa[..., AI["r_P1"]], xa[..., AI["rdot_P1"]]
    rP3, rdP3 = xa[..., AI["r_P3"]], xa[..., AI["rdot_P3"]]
    r1 = fd[..., FI["P_P1"]] / mbar - fd[..., FI["v1"]] - rdP3 * Om - rP3 * fd[..., FI["Omega2"]]
    r3 = fd[..., FI["P_P3"]] / mbar - fd[..., FI["v3"]] + rdP1 * Om + rP1 * fd[..., FI["Omega2"]]
    return np.stack([r1, r3], axis=-1)


@FAST
@given(name=vehicle_names, xa=accel_states(), w=inputs3)
def test_acceleration_transform_realizes_w(name, xa, w):
    acc = AccelerationControlledGlider(VEHICLES[name])
    u = acc.force_input(xa, w)
    assert u[2] == w[2]  # (2.34)
    rdd = _rddot_from_force_model(acc, xa, u)
    np.testing.assert_allclose(rdd, w[:2], rtol=0, atol=1e-10)
    d = acc.rhs(xa, w)
    assert d[AI["rdot_P1"]] == pytest.approx(w[0], abs=1e-15)
    assert d[AI["rdot_P3"]] == pytest.approx(w[1], abs=1e-15)
    assert d[AI["m0"]] == pytest.approx(w[2], abs=1e-15)
    assert d[AI["r_P1"]] == xa[AI["rdot_P1"]]
    assert d[AI["r_P3"]] == xa[AI["rdot_P3"]]


@FAST
@given(name=vehicle_names, xa=accel_states(), w=inputs3)
def test_acceleration_transform_complex_step_time_derivative(name, xa, w):
    """Independent of the hand differentiation above: d/dt of the map (2.31) along the force flow, by complex
    step, equals (w1, w3), and the eta-part of the acceleration rhs is the force rhs."""
    acc = AccelerationControlledGlider(VEHICLES[name])
    xf = acc.to_force_state(xa)
    fd = acc.force_model.rhs(xf, acc.force_input(xa, w))
    h = 1e-30
    dxa = np.imag(acc.from_force_state(xf + 1j * h * fd)) / h
    np.testing.assert_allclose(dxa[[AI["rdot_P1"], AI["rdot_P3"]]], w[:2], rtol=0, atol=1e-10)
    np.testing.assert_allclose(acc.rhs(xa, w), dxa, rtol=1e-12, atol=1e-12)


@FAST
@given(name=vehicle_names, xa=accel_states(), w=inputs3)
def test_transform_is_affine_in_u(name, xa, w):
    """rddot_P = Z + F u with (Z, F) of acc.transform (Z with corrected sign); F symmetric pos. definite."""
    acc = AccelerationControlledGlider(VEHICLES[name])
    Z, F = acc.transform(xa)
    assert Z.shape == (2,) and F.shape == (2, 2)
    np.testing.assert_allclose(F, F.T, rtol=0, atol=0)
    assert np.all(np.linalg.eigvalsh(F) > 0)
    u = np.array([w[0], w[1], 0.0])
    rdd = _rddot_from_force_model(acc, xa, u)
    np.testing.assert_allclose(rdd, Z + F @ u[:2], rtol=0, atol=1e-10)


def test_printed_sign_of_Z_is_wrong():
    """(2.32)-(2.33) as printed: u = F^-1(-Z_printed + w) with Z_printed = -Z. Then rddot_P = w + 2 Z != w."""
    rng = np.random.default_rng(7)
    xa, w = random_accel_batch(rng, 20)
    for veh in VEHICLES.values():
        acc = AccelerationControlledGlider(veh)
        Z, F = acc.transform(xa)
        assert np.all(np.linalg.norm(Z, axis=-1) > 1e-3)  # generic states: Z is not small
        u_printed = np.concatenate([np.linalg.solve(F, (Z + w[:, :2])[..., None])[..., 0], w[:, 2:]], axis=-1)
        rdd = _rddot_from_force_model(acc, xa, u_printed)
        err = np.linalg.norm(rdd - w[:, :2], axis=-1)
        assert np.all(err > 1e-3), err
        np.testing.assert_allclose(rdd, w[:, :2] + 2 * Z, rtol=1e-9, atol=1e-9)
        # the corrected law is exact for the same states
        rdd_ok = _rddot_from_force_model(acc, xa, acc.force_input(xa, w))
        np.testing.assert_allclose(rdd_ok, w[:, :2], rtol=0, atol=1e-10)


def test_transform_Z_matches_printed_brackets():
    """Z (corrected) = -[X1/m1 + rdot_P3 Om + r_P3 Y/J2, X3/m3 - rdot_P1 Om - r_P1 Y/J2] with X1, X3, Y
    written with the printed (2.32) expressions in acceleration-form variables."""
    veh = ROGUE_FULL
    acc = AccelerationControlledGlider(veh)
    rng = np.random.default_rng(3)
    xa, _ = random_accel_batch(rng, 10)
    th, Om, v1, v3 = xa[:, 2], xa[:, 3], xa[:, 4], xa[:, 5]
    rP1, rdP1, rP3, rdP3, m0 = xa[:, 6], xa[:, 7], xa[:, 8], xa[:, 9], xa[:, 10]
    V2 = v1**2 + v3**2
    al = np.arctan2(v3, v1)
    L = (veh.K_L0 + veh.K_L * al) * V2
    D = (veh.K_D0 + veh.K_D * al**2) * V2
    M = (veh.K_M0 + veh.K_M * al + veh.K_q * Om) * V2
    m1, m3, mb, g, J2 = veh.m1, veh.m3, veh.mbar, veh.g, veh.J2
    X1 = (-m3 * v3 * Om - mb * (v3 + rdP3 - rP1 * Om) * Om - m0 * g * np.sin(th)
          + L * np.sin(al) - D * np.cos(al))
    X3 = (m1 * v1 * Om + mb * (v1 + rdP1 + rP3 * Om) * Om + m0 * g * np.cos(th)
          - L * np.cos(al) - D * np.sin(al))
    PP1, PP3 = mb * (rdP1 + v1 + rP3 * Om), mb * (rdP3 + v3 - rP1 * Om)
    Y = ((m3 - m1) * v1 * v3 - mb * g * (rP1 * np.cos(th) + rP3 * np.sin(th)) + M
         - Om * (rP1 * PP1 + rP3 * PP3))
    Z_printed = np.column_stack([X1 / m1 + rdP3 * Om + rP3 * Y / J2, X3 / m3 - rdP1 * Om - rP1 * Y / J2])
    Z, F = acc.transform(xa)
    np.testing.assert_allclose(Z, -Z_printed, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(F[:, 0, 0], 1 / mb + 1 / m1 + rP3**2 / J2, rtol=1e-14)
    np.testing.assert_allclose(F[:, 1, 1], 1 / mb + 1 / m3 + rP1**2 / J2, rtol=1e-14)
    np.testing.assert_allclose(F[:, 0, 1], -rP1 * rP3 / J2, rtol=1e-14)


# ---------------------------------------------------------------------------------------- (d) state maps


@FAST
@given(name=vehicle_names, xa=accel_states(), xf=force_states())
def test_state_maps_are_inverse(name, xa, xf):
    acc = AccelerationControlledGlider(VEHICLES[name])
    np.testing.assert_allclose(acc.from_force_state(acc.to_force_state(xa)), xa, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(acc.to_force_state(acc.from_force_state(xf)), xf, rtol=1e-12, atol=1e-14)
    # the first six states and m0 are shared
    idx = [0, 1, 2, 3, 4, 5, 10]
    assert np.array_equal(acc.to_force_state(xa)[idx], xa[idx])


def test_state_map_is_2_31():
    acc = AccelerationControlledGlider(ROGUE)
    xf = np.array([0, 0, 0.2, 0.3, 0.5, 0.1, 0.02, -0.03, 1.4, 0.1, 0.2])
    xa = acc.from_force_state(xf)
    mb = ROGUE.mbar
    assert xa[AI["rdot_P1"]] == pytest.approx(1.4 / mb - 0.5 - (-0.03) * 0.3, rel=1e-14)
    assert xa[AI["rdot_P3"]] == pytest.approx(0.1 / mb - 0.1 + 0.02 * 0.3, rel=1e-14)
    # the rdot_P states equal the force model's r_P rates (2.21)-(2.22)
    fd = LongitudinalGlider(ROGUE).rhs(xf, np.zeros(3))
    assert xa[AI["rdot_P1"]] == pytest.approx(fd[FI["r_P1"]], rel=1e-14)
    assert xa[AI["rdot_P3"]] == pytest.approx(fd[FI["r_P3"]], rel=1e-14)


# ---------------------------------------------------------------------------------------- (e) batches


@pytest.mark.parametrize("name", sorted(VEHICLES))
def test_batch_equals_rowwise(name):
    veh = VEHICLES[name]
    rng = np.random.default_rng(11)
    xf, u = random_force_batch(rng, 12)
    xa, w = random_accel_batch(rng, 12)
    cases = [
        (LongitudinalGlider(veh), xf, u, 11),
        (AccelerationControlledGlider(veh), xa, w, 11),
        (GlidePathModel(LongitudinalGlider(veh), -0.5), xf[:, 1:], u, 10),
        (GlidePathModel(AccelerationControlledGlider(veh), 0.7), xa[:, 1:], w, 10),
    ]
    for model, X, U, n in cases:
        batch = model.rhs(X, U)
        assert batch.shape == (12, n)
        rows = np.array([model.rhs(X[i], U[i]) for i in range(12)])
        np.testing.assert_allclose(batch, rows, rtol=1e-14, atol=1e-14)
        # deeper batch shapes
        deep = model.rhs(X.reshape(3, 4, n), U.reshape(3, 4, 3))
        assert deep.shape == (3, 4, n)
        np.testing.assert_allclose(deep.reshape(12, n), rows, rtol=1e-14, atol=1e-14)
        # one input broadcast over a batch of states
        np.testing.assert_allclose(model.rhs(X, U[0]), np.array([model.rhs(X[i], U[0]) for i in range(12)]),
                                   rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("name", sorted(VEHICLES))
def test_single_real_state_is_bitwise_the_batch_row(name):
    """The single-state path (scalar columns, the calls of a simulation) does the same IEEE operations as the batch
    path: equal to the last bit, for both models and the force input."""
    veh = VEHICLES[name]
    rng = np.random.default_rng(5)
    xf, u = random_force_batch(rng, 8)
    xa, w = random_accel_batch(rng, 8)
    fm, am = LongitudinalGlider(veh), AccelerationControlledGlider(veh)
    for f, X, U in ((fm.rhs, xf, u), (am.rhs, xa, w), (am.force_input, xa, w)):
        batch = f(X, U)
        for i in range(8):
            one = f(X[i], U[i])
            assert one.shape == batch[i].shape and one.dtype == np.float64
            assert np.array_equal(one, batch[i]), (f, i, one - batch[i])
    for i in range(8):
        Z, F = am.transform(xa[i])
        Zb, Fb = am.transform(xa)
        assert np.array_equal(Z, Zb[i]) and np.array_equal(F, Fb[i]) and F.shape == (2, 2)


@pytest.mark.parametrize("name", sorted(VEHICLES))
def test_acceleration_rhs_is_the_force_rhs_at_the_force_input(name):
    """One right-hand side: the acceleration-form rhs (brackets computed once) equals, bit for bit, the two-pass
    composition of the public steps: force state (2.31), force input (2.33)-(2.34), force rhs (2.15)-(2.20)."""
    veh = VEHICLES[name]
    am = AccelerationControlledGlider(veh)
    assert am.force_model is am.force_model  # built once
    rng = np.random.default_rng(6)
    xa, w = random_accel_batch(rng, 10)
    for X, W in ((xa, w), (xa[3], w[3]), (xa + 1e-20j, w)):
        fdot = am.force_model.rhs(am.to_force_state(X), am.force_input(X, W))
        want = np.concatenate([fdot[..., :6], X[..., 7:8], W[..., 0:1], X[..., 9:10], W[..., 1:2], W[..., 2:3]],
                              axis=-1)
        got = am.rhs(X, W)
        assert got.shape == want.shape
        assert np.array_equal(got, want)


def test_model_names():
    assert LongitudinalGlider(ROGUE).state_names == FORCE_STATES
    assert LongitudinalGlider(ROGUE).input_names == FORCE_INPUTS
    assert AccelerationControlledGlider(ROGUE).state_names == ACCEL_STATES
    assert AccelerationControlledGlider(ROGUE).input_names == ACCEL_INPUTS
    gp = GlidePathModel(AccelerationControlledGlider(ROGUE), 0.1)
    assert gp.state_names == ("z_prime", *ACCEL_STATES[2:])
    assert gp.input_names == ACCEL_INPUTS


def test_glide_path_rate_is_2_30():
    rng = np.random.default_rng(5)
    xf, u = random_force_batch(rng, 8)
    for gamma_e in (-0.8, 0.0, 0.6):
        gp = GlidePathModel(LongitudinalGlider(ROGUE), gamma_e)
        d = gp.rhs(xf[:, 1:], u)
        th, v1, v3 = xf[:, 2], xf[:, 4], xf[:, 5]
        zp = (np.sin(gamma_e) * (v1 * np.cos(th) + v3 * np.sin(th))
              + np.cos(gamma_e) * (-v1 * np.sin(th) + v3 * np.cos(th)))
        np.testing.assert_allclose(d[:, 0], zp, rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(d[:, 1:], LongitudinalGlider(ROGUE).rhs(xf, u)[:, 2:], rtol=1e-14, atol=0)
        # z' itself does not enter the dynamics
        shifted = xf[:, 1:].copy()
        shifted[:, 0] += 5.0
        np.testing.assert_array_equal(gp.rhs(shifted, u), d)


# ---------------------------------------------------------------------------------------- (f) reflection
#
# Derivation from (2.15)-(2.25) with K_L0 = K_M0 = 0, so that alpha -> -alpha gives L -> -L, D -> D and
# M_DL2 -> -M_DL2. Mirroring the vertical plane in a horizontal line (z -> -z) turns the body 3-axis over:
# body-3 components change sign, body-1 components do not,
#     R: (x, z, theta, Omega2, v1, v3, r_P1, r_P3, P_P1, P_P3, m0)
#        -> (x, -z, -theta, -Omega2, v1, -v3, r_P1, -r_P3, P_P1, -P_P3, m0),
#     T: (u1, u3, u4) -> (u1, -u3, u4).
# Every term of (2.15)-(2.25) maps with the sign of its left-hand side *except the weights*: gravity is not
# mirrored. Hence f_g(R x, T u) = R f_{-g}(x, u) exactly (mirror world = reversed gravity). With g fixed,
# also flipping m0 and u4 repairs the buoyancy terms, but the moving-mass weight torque
# -mbar g (r_P1 cos(theta) + r_P3 sin(theta)) is even under R while Omega2' is odd, so R is a symmetry only up
# to that torque. The map proposed in the brief,
#     (theta, Omega2, v1, v3, r_P1, r_P3, P_P1, P_P3, m0) -> (-, -, +, -, -, +, -, +, -),
# is not a symmetry: with r_P1 odd, (2.21) r_P1' = P_P1/mbar - v1 - r_P3 Omega2 would have to be odd, but v1
# is even (the defect is 2 v1). An exhaustive search below confirms that no sign pattern at all is a symmetry.
# The up/down correspondence of *steady glides* (tested in test_trim.py) flips r_P1 and keeps r_P3; it is a
# symmetry of the equilibrium equations only (all terms carrying Omega2 or u vanish there).

R_STATE = np.array([1, -1, -1, -1, 1, -1, 1, -1, 1, -1, 1], dtype=float)
R_INPUT = np.array([1, -1, 1], dtype=float)


def _reversed_gravity(veh):
    """The same vehicle in a world whose gravity points up (bypasses the vehicle's validation on purpose: g < 0 is
    not a vehicle a user can load)."""
    out = object.__new__(type(veh))
    for f in dataclasses.fields(veh):
        object.__setattr__(out, f.name, getattr(veh, f.name))
    object.__setattr__(out, "params", MappingProxyType({**veh.params, "g": -veh.g}))
    return out


def test_mirror_with_reversed_gravity_is_exact():
    veh = load_vehicle("rogue", K_q=-1.5)
    f = LongitudinalGlider(veh).rhs
    f_up = LongitudinalGlider(_reversed_gravity(veh)).rhs
    rng = np.random.default_rng(1)
    x, u = random_force_batch(rng, 50)
    np.testing.assert_allclose(f(x * R_STATE, u * R_INPUT), R_STATE * f_up(x, u), rtol=1e-13, atol=1e-12)


def test_mirror_needs_symmetric_hydrodynamics():
    veh = load_vehicle("rogue", K_L0=20.0, K_M0=0.5)
    f = LongitudinalGlider(veh).rhs
    f_up = LongitudinalGlider(_reversed_gravity(veh)).rhs
    rng = np.random.default_rng(1)
    x, u = random_force_batch(rng, 20)
    err = np.abs(f(x * R_STATE, u * R_INPUT) - R_STATE * f_up(x, u))
    assert err[:, [FI["Omega2"], FI["v1"], FI["v3"]]].max() > 1e-2


def test_heavy_light_mirror_fails_only_by_the_moving_mass_weight_torque():
    veh = load_vehicle("rogue", K_q=-1.5)
    f = LongitudinalGlider(veh).rhs
    S = R_STATE.copy()
    S[FI["m0"]] = -1.0
    T = np.array([1.0, -1.0, -1.0])
    rng = np.random.default_rng(2)
    x, u = random_force_batch(rng, 50)
    defect = f(x * S, u * T) - S * f(x, u)
    th, rP1, rP3 = x[:, FI["theta"]], x[:, FI["r_P1"]], x[:, FI["r_P3"]]
    torque = -veh.mbar * veh.g * (rP1 * np.cos(th) + rP3 * np.sin(th)) / veh.J2
    expected = np.zeros_like(defect)
    expected[:, FI["Omega2"]] = 2 * torque
    np.testing.assert_allclose(defect, expected, rtol=1e-12, atol=1e-11)
    assert np.abs(torque).max() > 1.0  # so the symmetry really is broken for generic states
    # ... and exact where the moving mass is directly above/below the centre of buoyancy
    x0 = x.copy()
    x0[:, FI["r_P1"]] = -x0[:, FI["r_P3"]] * np.tan(th)
    np.testing.assert_allclose(f(x0 * S, u * T), S * f(x0, u), rtol=1e-13, atol=1e-12)


def test_brief_reflection_is_not_a_symmetry():
    veh = ROGUE
    f = LongitudinalGlider(veh).rhs
    S = np.array([1, 1, -1, -1, 1, -1, -1, 1, -1, 1, -1], dtype=float)  # x, z untouched
    T = np.array([-1.0, 1.0, -1.0])
    x = np.array([0, 0, 0.3, 0.2, 0.5, 0.1, 0.03, -0.04, 1.1, 0.3, 0.4])
    u = np.array([0.7, -0.2, 0.05])
    err = np.abs(f(x * S, u * T) - S * f(x, u))
    # (2.21): r_P1' = P_P1/mbar - v1 - r_P3 Om must be odd like r_P1, but its v1 term is even: defect 2 v1
    assert err[FI["r_P1"]] == pytest.approx(2 * x[FI["v1"]], rel=1e-12)
    assert err[FI["r_P1"]] > 0.1


def test_no_sign_pattern_is_a_symmetry():
    """Exhaustive: among all 2^11 * 2^3 sign patterns (S, T), f(S x, T u) = S f(x, u) holds only for the
    identity, for ROGUE with K_L0 = K_M0 = 0 (the most symmetric case)."""
    f = LongitudinalGlider(load_vehicle("rogue", K_q=-1.5)).rhs
    rng = np.random.default_rng(4)
    x, u = random_force_batch(rng, 6)
    S = np.array(list(itertools.product([1.0, -1.0], repeat=11)))  # (2048, 11)
    found = []
    for T in itertools.product([1.0, -1.0], repeat=3):
        T = np.array(T)
        lhs = f(S[:, None, :] * x[None], (T * u)[None])  # (2048, 6, 11)
        rhs = S[:, None, :] * f(x, u)[None]
        ok = np.all(np.abs(lhs - rhs) <= 1e-10 * (1 + np.abs(rhs)), axis=(1, 2))
        found += [(tuple(s), tuple(T)) for s in S[ok]]
    assert found == [((1.0,) * 11, (1.0, 1.0, 1.0))]


# ---------------------------------------------------------------------------------------- (g) errors


def test_no_moving_mass_is_model_error():
    sphere = load_vehicle("sphere_ch5")
    assert sphere.mbar == 0
    with pytest.raises(ModelError, match="mbar"):
        LongitudinalGlider(sphere)


def test_ctol_vehicle_is_model_error():
    with pytest.raises(ModelError):
        LongitudinalGlider(load_vehicle("dc8_ctol"))


@pytest.mark.parametrize("call", ["rhs", "transform", "force_input", "glide_path", "to_force_state",
                                  "from_force_state"])
def test_acceleration_model_without_moving_mass_is_model_error(call):
    """Every use of the acceleration-controlled model with mbar = 0 must raise ModelError (no inf/NaN)."""
    sphere = load_vehicle("sphere_ch5")
    xa = np.array([0, 0, 0.1, 0.0, 0.5, 0.05, 0.0, 0.0, 0.0, 0.0, 0.7])
    xf = xa.copy()
    w = np.zeros(3)
    with pytest.raises(ModelError):
        acc = AccelerationControlledGlider(sphere)
        if call == "rhs":
            acc.rhs(xa, w)
        elif call == "transform":
            acc.transform(xa)
        elif call == "force_input":
            acc.force_input(xa, w)
        elif call == "glide_path":
            GlidePathModel(acc, -0.5).rhs(xa[1:], w)
        elif call == "to_force_state":
            acc.to_force_state(xa)
        else:
            acc.from_force_state(xf)


# ---------------------------------------------------------------------------------------- bad inputs (issue 15)
def test_rhs_checks_state_and_input_shapes():
    force, accel = LongitudinalGlider(ROGUE), AccelerationControlledGlider(ROGUE)
    x = np.zeros(11)
    x[4] = 0.3
    for model in (force, accel):
        with pytest.raises(gc.ArgumentError, match="trailing dimension 11"):
            model.rhs(np.zeros(10), np.zeros(3))  # was an IndexError deep in numpy
        with pytest.raises(gc.ArgumentError, match="trailing dimension 3"):
            model.rhs(x, np.zeros(2))
        with pytest.raises(gc.ArgumentTypeError):
            model.rhs(x, None)
        with pytest.raises(gc.ArgumentTypeError):
            model.rhs(["a"] * 11, np.zeros(3))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 11"):
        accel.to_force_state(np.zeros(9))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 3"):
        accel.force_input(x, np.zeros(4))


def test_glide_path_model_checks_its_base_and_angle():
    with pytest.raises(gc.ArgumentTypeError, match="base"):
        GlidePathModel("rogue", -0.5)
    with pytest.raises(gc.ArgumentError, match="gamma"):
        GlidePathModel(LongitudinalGlider(ROGUE), np.nan)
    with pytest.raises(gc.ArgumentError, match="gamma"):
        GlidePathModel(LongitudinalGlider(ROGUE), 2.0)
    with pytest.raises(gc.ArgumentTypeError):
        GlidePathModel(LongitudinalGlider(ROGUE), "-0.5")
    gp = GlidePathModel(LongitudinalGlider(ROGUE), np.float64(-0.5))
    assert isinstance(gp.gamma, float)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 10"):
        gp.rhs(np.zeros(11), np.zeros(3))


def test_reduced_and_nondimensional_models_check_inputs():
    from glidectl.models.nondimensional import NondimensionalModel, NondimensionalScaling, SlowModel
    from glidectl.models.reduced import ReducedLongitudinalGlider

    sphere = load_vehicle("sphere_ch5")
    with pytest.raises(gc.ArgumentError, match="trailing dimension 4"):
        ReducedLongitudinalGlider(sphere).rhs(np.ones(5))
    with pytest.raises(gc.ArgumentError, match="speed"):
        NondimensionalScaling(sphere, -1.0, -0.9, 0.02, 10.0, 0.1, 0.1)
    with pytest.raises(gc.ArgumentTypeError, match="tau_s"):
        NondimensionalScaling(sphere, 1.0, -0.9, 0.02, "10", 0.1, 0.1)
    sc = NondimensionalScaling(sphere, 1.6, -0.9, 0.02, 10.0, 0.1, 0.1)
    box = (np.array([-0.4, -1.0]), np.array([0.4, 1.0]))
    with pytest.raises(gc.ArgumentError, match="kind"):
        NondimensionalModel(sc, "fast", ("Vbar", "gammabar"), box)
    with pytest.raises(gc.ArgumentError, match="states"):
        NondimensionalModel(sc, "full", ("Vbar", "gammabar"), box)
    with pytest.raises(gc.ArgumentError, match="lo < hi"):
        NondimensionalModel(sc, "reduced", ("Vbar", "gammabar"), (box[1], box[0]))
    with pytest.raises(gc.ArgumentError, match="trailing dimension 2"):
        NondimensionalModel(sc, "reduced", ("Vbar", "gammabar"), box).rhs(np.zeros(4))
    with pytest.raises(gc.ArgumentError, match="alpha"):
        SlowModel(sphere, np.inf)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 2"):
        SlowModel(sphere, 0.02).rhs(np.zeros(3))
