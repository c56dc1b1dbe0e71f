"""glidectl.derivatives: complex-step derivatives against analytic ones, refusal of functions that are not
complex-safe, shapes, and the arithmetic the batched primitives promise (equal to the last bit to the hand-written
``Im f(x + i h e) / h`` they replace)."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import glidectl as gc
from glidectl import derivatives as dv
from glidectl.errors import ArgumentError, ArgumentTypeError, ModelError

RNG = np.random.default_rng(20240611)


def _bitwise(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


# ------------------------------------------------------------------------------- analytic test functions
def field(x, u):
    """f(x, u) = (x0^2 x1 + sin(u0), exp(x1) cos(x0) + x0 u0^3, x0 x1 u1), batch-capable."""
    x0, x1 = x[..., 0], x[..., 1]
    u0, u1 = u[..., 0], u[..., 1]
    return np.stack([x0**2 * x1 + np.sin(u0), np.exp(x1) * np.cos(x0) + x0 * u0**3, x0 * x1 * u1], axis=-1)


def field_A(x, u):
    x0, x1 = x
    u0, u1 = u
    return np.array([[2 * x0 * x1, x0**2],
                     [-np.exp(x1) * np.sin(x0) + u0**3, np.exp(x1) * np.cos(x0)],
                     [x1 * u1, x0 * u1]])


def field_B(x, u):
    x0, x1 = x
    u0, _ = u
    return np.array([[np.cos(u0), 0.0], [3 * x0 * u0**2, 0.0], [0.0, x0 * x1]])


def scalar(X):
    """s(x) = x0^3 x1 + sin(x1) x2^2 + x0 x2, batch-capable."""
    return X[..., 0] ** 3 * X[..., 1] + np.sin(X[..., 1]) * X[..., 2] ** 2 + X[..., 0] * X[..., 2]


def scalar_grad(x):
    x0, x1, x2 = x[..., 0], x[..., 1], x[..., 2]
    return np.stack([3 * x0**2 * x1 + x2, x0**3 + np.cos(x1) * x2**2, 2 * np.sin(x1) * x2 + x0], axis=-1)


def scalar_hess(x):
    x0, x1, x2 = x
    return np.array([[6 * x0 * x1, 3 * x0**2, 1.0],
                     [3 * x0**2, -np.sin(x1) * x2**2, 2 * np.cos(x1) * x2],
                     [1.0, 2 * np.cos(x1) * x2, 2 * np.sin(x1)]])


def vec(X):
    """v(x) = (sin(x0) x1, x0^2 + x1^3), batch-capable: J = [[cos(x0) x1, sin(x0)], [2 x0, 3 x1^2]]."""
    return np.stack([np.sin(X[..., 0]) * X[..., 1], X[..., 0] ** 2 + X[..., 1] ** 3], axis=-1)


def vec_J(X):
    x0, x1 = X[..., 0], X[..., 1]
    return np.stack([np.stack([np.cos(x0) * x1, np.sin(x0)], -1), np.stack([2 * x0, 3 * x1**2], -1)], -2)


def not_complex_safe(X):
    return np.real(np.asarray(X)) ** 2


# ------------------------------------------------------------------------------- checked single-point tools
def test_jacobians_are_the_analytic_ones_to_rounding():
    for _ in range(20):
        x, u = RNG.uniform(-2, 2, 2), RNG.uniform(-2, 2, 2)
        A, B = dv.jacobians(field, x, u)
        assert A.shape == (3, 2) and B.shape == (3, 2)
        np.testing.assert_allclose(A, field_A(x, u), rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(B, field_B(x, u), rtol=1e-14, atol=1e-14)
        # central differences (a square field: the rows of field(x, u) without the last) agree to O(h^2)
        Ac, Bc = dv.central_difference_jacobians(lambda xx, uu: field(xx, uu)[:2], x, u)
        np.testing.assert_allclose(Ac, A[:2], rtol=1e-7, atol=1e-8)
        np.testing.assert_allclose(Bc, B[:2], rtol=1e-7, atol=1e-8)


def test_jacobians_of_an_input_free_field_have_an_empty_B():
    A, B = dv.jacobians(lambda x, u: vec(x), np.array([0.4, -1.3]), np.zeros(0))
    np.testing.assert_allclose(A, vec_J(np.array([0.4, -1.3])), rtol=1e-15, atol=1e-15)
    assert B.shape == (2, 0)


def test_hessian_of_a_cubic_is_exact_up_to_rounding():
    for _ in range(10):
        x = RNG.uniform(-1.5, 1.5, 3)
        H = dv.hessian(scalar, x)
        assert H.shape == (3, 3)
        np.testing.assert_allclose(H, H.T, rtol=0, atol=0)
        np.testing.assert_allclose(H, scalar_hess(x), rtol=1e-8, atol=1e-8)


def test_checked_tools_refuse_functions_that_are_not_complex_safe():
    with pytest.raises(ModelError, match="complex-safe"):
        dv.jacobians(lambda x, u: not_complex_safe(x), np.ones(2), np.zeros(0))
    with pytest.raises(ModelError, match="complex-safe"):
        dv.hessian(lambda X: not_complex_safe(X)[..., 0], np.ones(2))


def test_checked_tools_refuse_non_finite_derivatives_and_bad_arguments():
    with pytest.raises(ModelError, match="not finite"), np.errstate(divide="ignore"):
        dv.jacobians(lambda x, u: np.log(x), np.array([0.0, 1.0]), np.zeros(0))
    with pytest.raises(ArgumentError):
        dv.jacobians(field, np.zeros(0), np.zeros(2))
    with pytest.raises(ArgumentError):
        dv.hessian(scalar, np.ones(3), h=0.0)
    with pytest.raises(ArgumentTypeError):
        dv.jacobians("f", np.ones(2), np.ones(2))


def test_the_top_level_re_exports_the_same_functions():
    assert gc.jacobians is dv.jacobians and gc.hessian is dv.hessian
    assert gc.analysis.central_difference_jacobians is dv.central_difference_jacobians


def test_the_module_sits_at_the_foundation():
    """derivatives imports only numpy, glidectl.checks and glidectl.errors, so every layer may use it."""
    tree = ast.parse(Path(dv.__file__).read_text())
    mods = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            mods.add(("." * node.level) + (node.module or ""))
        elif isinstance(node, ast.Import):
            mods.update(a.name for a in node.names)
    assert mods <= {"__future__", "cmath", "math", "collections.abc", "typing", "numpy", ".checks", ".errors"}, mods


# ------------------------------------------------------------------------------- batched primitives
def test_complex_step_gives_directional_derivatives_at_many_points():
    X = RNG.uniform(-1.5, 1.5, (50, 3))
    D = RNG.normal(size=(50, 3))
    d = dv.complex_step(scalar, X, D)
    assert d.shape == (50,)
    np.testing.assert_allclose(d, np.sum(scalar_grad(X) * D, axis=1), rtol=1e-13, atol=1e-13)
    val, d2 = dv.complex_step(scalar, X, D, value=True)
    assert _bitwise(d2, d)
    np.testing.assert_allclose(val, scalar(X), rtol=1e-15, atol=1e-15)


def test_complex_step_of_a_scalar_function_of_a_scalar():
    t = np.linspace(-3, 3, 41)
    val, d = dv.complex_step(lambda z: np.sin(z) * np.exp(z), t, 1.0, value=True)
    np.testing.assert_allclose(d, (np.cos(t) + np.sin(t)) * np.exp(t), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(val, np.sin(t) * np.exp(t), rtol=1e-15, atol=1e-15)


def test_complex_step_is_the_hand_written_formula_to_the_last_bit():
    X = RNG.normal(size=(30, 2))
    D = RNG.normal(size=(30, 2))
    h = 1e-30
    assert _bitwise(dv.complex_step(vec, X, D, h), np.imag(vec(X + 1j * h * D)) / h)
    # the Jacobians of many points in one call, direction-major rows (the layout of glidectl.batch)
    Z = dv.complex_step(lambda Z: vec(Z.reshape(-1, 2)), X[None], np.eye(2)[:, None, :], h).reshape(2, 30, 2)
    assert _bitwise(np.transpose(Z, (1, 2, 0)), np.transpose(np.imag(vec(
        (X[None] + 1j * h * np.eye(2)[:, None, :]).reshape(-1, 2))).reshape(2, 30, 2) / h, (1, 2, 0)))
    np.testing.assert_allclose(np.transpose(Z, (1, 2, 0)), vec_J(X), rtol=1e-14, atol=1e-14)


def test_partial_derivative_perturbs_one_column_only():
    X = RNG.normal(size=(20, 3))
    X[3, 2] = -0.0
    for j in range(3):
        np.testing.assert_allclose(dv.partial_derivative(scalar, X, j), scalar_grad(X)[:, j], rtol=1e-14, atol=1e-14)
    # the other columns reach f unchanged (signed zeros included), and X itself is not modified
    seen = {}

    def spy(Z):
        seen["Z"] = Z.copy()
        return Z[..., 2].copy()

    before = X.copy()
    val, d = dv.partial_derivative(spy, X, 0, value=True)
    assert _bitwise(X, before)
    assert _bitwise(seen["Z"][:, 1:].real, X[:, 1:]) and np.all(seen["Z"][:, 1:].imag == 0)
    assert np.signbit(seen["Z"][3, 2].real)
    assert np.all(d == 0) and _bitwise(val, X[:, 2])
    h = 1e-30
    zc = X.astype(complex)
    zc[:, 1] += 1j * h
    assert _bitwise(dv.partial_derivative(scalar, X, 1, h), np.imag(scalar(zc)) / h)


def test_jacobian_batch_vector_and_scalar_functions_and_shapes():
    X = RNG.uniform(-2, 2, (7, 5, 2))
    J = dv.jacobian_batch(vec, X)
    assert J.shape == (7, 5, 2, 2)
    np.testing.assert_allclose(J, vec_J(X), rtol=1e-14, atol=1e-14)
    x = np.array([0.3, -0.8])
    np.testing.assert_allclose(dv.jacobian_batch(vec, x), vec_J(x), rtol=1e-15, atol=1e-15)
    Y = RNG.uniform(-1, 1, (9, 3))
    g = dv.jacobian_batch(scalar, Y)
    assert g.shape == (9, 3)
    np.testing.assert_allclose(g, scalar_grad(Y), rtol=1e-14, atol=1e-14)
    h = 1e-30
    assert _bitwise(g, np.imag(scalar(Y[..., None, :] + 1j * h * np.eye(3))) / h)
    with pytest.raises(ArgumentError, match="one value or one vector"):
        dv.jacobian_batch(lambda Z: np.sum(Z), Y)
    with pytest.raises(ArgumentError):
        dv.jacobian_batch(vec, np.zeros((3, 0)))


def test_jacobians_batch_agrees_with_jacobians_at_each_point():
    X = RNG.uniform(-2, 2, (4, 3, 2))
    U = RNG.uniform(-2, 2, (4, 3, 2))
    A, B = dv.jacobians_batch(field, X, U)
    assert A.shape == (4, 3, 3, 2) and B.shape == (4, 3, 3, 2)
    for i in range(4):
        for k in range(3):
            Ai, Bi = dv.jacobians(field, X[i, k], U[i, k])
            np.testing.assert_allclose(A[i, k], Ai, rtol=1e-15, atol=1e-15)
            np.testing.assert_allclose(B[i, k], Bi, rtol=1e-15, atol=1e-15)
            np.testing.assert_allclose(A[i, k], field_A(X[i, k], U[i, k]), rtol=1e-14, atol=1e-14)
    A0, B0 = dv.jacobians_batch(lambda x, u: vec(x), X[0], np.zeros((3, 0)))
    assert A0.shape == (3, 2, 2) and B0.shape == (3, 2, 0)
    with pytest.raises(ArgumentError, match="leading shape"):
        dv.jacobians_batch(field, X, U[0])


def test_second_directional_derivative_against_the_analytic_one():
    for _ in range(10):
        x = RNG.uniform(-1.5, 1.5, 3)
        v = RNG.normal(size=3)
        h = 1e-3 / np.linalg.norm(v)
        s2 = dv.second_directional_derivative(scalar, x, v, h)
        np.testing.assert_allclose(s2, v @ scalar_hess(x) @ v, rtol=1e-9, atol=1e-9)
    # a vector function, many points at once
    X = RNG.uniform(-1, 1, (6, 2))
    V = np.array([1.0, 0.0])
    np.testing.assert_allclose(dv.second_directional_derivative(vec, X, V, 1e-3),
                               np.stack([-np.sin(X[:, 0]) * X[:, 1], np.full(6, 2.0)], -1), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("call", [
    lambda f: dv.complex_step(f, np.ones((3, 2)), np.ones(2)),
    lambda f: dv.partial_derivative(f, np.ones((3, 2)), 1),
    lambda f: dv.jacobian_batch(f, np.ones((3, 2))),
    lambda f: dv.jacobians_batch(lambda x, u: f(x), np.ones((3, 2)), np.ones((3, 1))),
    lambda f: dv.second_directional_derivative(f, np.ones(2), np.ones(2), 1e-3),
], ids=["complex_step", "partial_derivative", "jacobian_batch", "jacobians_batch", "second_directional"])
def test_batched_primitives_refuse_functions_that_are_not_complex_safe(call):
    with pytest.raises(ModelError, match="not complex-safe"):
        call(not_complex_safe)


def test_batched_primitives_name_the_function_and_give_the_advice():
    with pytest.raises(ModelError, match=r"^the right-hand side returned .* use jacobian='central'"):
        dv.complex_step(not_complex_safe, np.ones(2), np.ones(2), name="the right-hand side",
                        advice="use jacobian='central'")


def test_batched_primitives_pass_non_finite_values_through():
    """A row where f overflows is inf; the other rows are unaffected (no error: the caller decides)."""
    X = np.array([[1.0], [1000.0], [2.0]])
    with np.errstate(over="ignore", invalid="ignore"):
        d = dv.partial_derivative(lambda Z: np.exp(Z[..., 0]), X, 0)
    assert d[0] == np.exp(1.0) and d[2] == np.exp(2.0) and not np.isfinite(d[1])


def test_batched_primitives_check_their_arguments():
    with pytest.raises(ArgumentTypeError):
        dv.complex_step(vec, np.ones(2) + 0j, np.ones(2))
    with pytest.raises(ArgumentError):
        dv.complex_step(vec, np.ones(2), np.ones(2), h=0.0)
    with pytest.raises(ArgumentError):
        dv.complex_step(vec, np.ones(2), np.ones(2), h=-1e-30)
    with pytest.raises(ArgumentError):
        dv.partial_derivative(vec, np.ones((3, 2)), 2)
    with pytest.raises(ArgumentTypeError):
        dv.partial_derivative(vec, np.ones((3, 2)), 1.0)
    with pytest.raises(ArgumentTypeError):
        dv.jacobian_batch(None, np.ones(2))
    with pytest.raises(ArgumentError):
        dv.second_directional_derivative(vec, np.ones(2), np.ones(2), 0.0)
