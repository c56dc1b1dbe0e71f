"""The CTOL right-hand sides on a single state (the calls of a simulation): the vehicle constants read once per model,
scalars instead of 0-d views (Python floats, with libm's sin and cos and numpy's arctan, in the aircraft model and
the steady-glide law), no re-validation of the control law per call. A single state must give the batch row to the
last bit (real and complex-step states), the constants must be the vehicle's, and the argument checks at the fast
path's boundary must still raise the same errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.controllers.ctol import SteadyGlideController
from glidectl.controllers.ctol_tracking import _augmented, _closed_loop_jacobian
from glidectl.errors import ArgumentError, ArgumentTypeError, ModelError
from glidectl.models.ctol import CTOLAircraft, CTOLReduced, ExtendedCTOL, drag_coefficient, lift_coefficient
from glidectl.models.ctol_closed_loop import ClosedLoopCTOL, steady_glide_inputs

VEH = gc.load_vehicle("dc8_ctol")
V_LEVEL = 0.85 / math.sqrt(30.0)
GLIDE = gc.ctol_glide(VEH, 0.2, 0.15)
N = 40


def _states(rng: np.random.Generator, n: int = N) -> tuple[np.ndarray, np.ndarray]:
    """Full states (wide: speeds of both signs of xdot, pitch angles beyond pi, fast pitch rates) and inputs."""
    V = rng.uniform(0.05, 2.0, n)
    g = rng.uniform(-3.0, 3.0, n)
    x = np.column_stack([rng.normal(size=n), rng.normal(size=n), V * np.cos(g), V * np.sin(g),
                         rng.uniform(-8.0, 8.0, n), rng.normal(scale=300.0, size=n)])
    u = np.column_stack([rng.normal(scale=3.0, size=n), rng.normal(scale=1e3, size=n)])
    return x, u


def _reduced(rng: np.random.Generator, n: int = N) -> np.ndarray:
    return np.column_stack([rng.uniform(-0.6, 0.6, n), rng.uniform(-1.0, 1.0, n), rng.uniform(-4.0, 4.0, n),
                            rng.normal(scale=30.0, size=n)])


def _bitwise(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal to the last bit (real and imaginary parts; NaNs with the same payload count as equal)."""
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def _cases(rng: np.random.Generator) -> list[tuple[str, object, np.ndarray, np.ndarray | None]]:
    """(name, f, states, inputs or None): every CTOL right-hand side and control law taking states."""
    x, u = _states(rng)
    s = _reduced(rng)
    X8 = np.column_stack([x, u[:, 0], rng.normal(size=N)])
    U8 = np.column_stack([rng.normal(size=N), u[:, 1]])
    cl = ClosedLoopCTOL(VEH, GLIDE, 7e5, 250.0, 1.3)
    ctrl = SteadyGlideController(VEH, GLIDE, 7e5, 250.0, 1.3)
    model = CTOLAircraft(VEH)
    z = np.column_stack([x, rng.normal(size=(N, 3))])
    return [
        ("CTOLAircraft.rhs", model.rhs, x, u),
        ("CTOLReduced.rhs", CTOLReduced(VEH, GLIDE.speed, GLIDE.gamma, GLIDE.theta, 1.3).rhs, s, u),
        ("ExtendedCTOL.rhs", ExtendedCTOL(VEH).rhs, X8, U8),
        ("ClosedLoopCTOL.rhs", cl.rhs, s, None),
        ("ClosedLoopCTOLAlpha.rhs", cl.roa_model().rhs, s, None),
        ("SteadyGlideController.u", ctrl.u, x, None),
        ("SteadyGlideController.reduced_input", ctrl.reduced_input, s, None),
        ("tracking _augmented", lambda Z: _augmented(model, ctrl, Z), z, None),
    ]


def test_single_real_state_is_bitwise_the_batch_row():
    """Scalar columns for one real state: the same IEEE operations as a batch row, so the values are equal to the
    last bit, for every CTOL right-hand side and control law."""
    rng = np.random.default_rng(11)
    for name, f, X, U in _cases(rng):
        with np.errstate(all="ignore"):
            batch = f(X) if U is None else f(X, U)
            assert batch.shape[0] == N and batch.dtype == np.float64
            for i in range(N):
                one = f(X[i]) if U is None else f(X[i], U[i])
                assert _bitwise(one, batch[i]), (name, i, one, batch[i])
                if name.startswith("tracking"):
                    continue  # (private: the solvers pass arrays)
                # a list (validated, converted path) gives the same values as the array
                lst = f(X[i].tolist()) if U is None else f(X[i].tolist(), U[i].tolist())
                assert _bitwise(np.asarray(lst), batch[i]), (name, i)


@pytest.mark.parametrize("kind", ["complex state", "complex input"])
def test_single_complex_state_matches_the_batch_row(kind):
    """A single complex-step state keeps the column-view path (its arithmetic is unchanged: the approximate
    linearization's second derivatives use such states, and its ledger number depends on their last bits). Real
    parts equal the batch row to the last bit; imaginary parts agree to rounding (numpy's scalar complex division
    rounds differently from its array loop). (Larger imaginary parts, as in the second-derivative steps, mix into
    the real parts as well.)"""
    rng = np.random.default_rng(11)
    for name, f, X, U in _cases(rng):
        if kind == "complex state":
            X = X + 1e-30j * rng.normal(size=X.shape)  # the complex step of glidectl's Jacobians
        elif U is None:
            continue
        else:
            U = U + 1e-30j * rng.normal(size=U.shape)
        with np.errstate(all="ignore"):
            batch = f(X) if U is None else f(X, U)
            assert batch.dtype == np.complex128
            for i in range(N):
                one = f(X[i]) if U is None else f(X[i], U[i])
                assert one.shape == batch[i].shape and one.dtype == np.complex128, name
                assert _bitwise(one.real.copy(), batch[i].real.copy()), (name, kind, i)
                ok = np.isfinite(batch[i].imag)
                np.testing.assert_allclose(one.imag[ok], batch[i].imag[ok], rtol=1e-12,
                                           atol=1e-12 * np.max(np.abs(batch[i].imag[ok]), initial=0.0))


def test_single_real_state_broadcasts_against_a_batch_of_inputs():
    """One real state with a batch of inputs (and the reverse) broadcasts like the batch of repeated states."""
    rng = np.random.default_rng(12)
    x, u = _states(rng)
    model = CTOLAircraft(VEH)
    got = model.rhs(x[3], u)
    want = model.rhs(np.broadcast_to(x[3], x.shape), u)
    assert _bitwise(got, want)
    got = model.rhs(x, u[5])
    assert _bitwise(got, model.rhs(x, np.broadcast_to(u[5], u.shape)))


def test_rhs_is_the_published_model_with_the_vehicle_coefficients():
    """(7.5)-(7.7) through the public lift and drag coefficients (7.1)-(7.2), read from the vehicle on each call:
    the constants cached per model are the vehicle's, to the last bit."""
    rng = np.random.default_rng(13)
    x, u = _states(rng)
    model = CTOLAircraft(VEH)
    xd, yd, th, om = x[:, 2], x[:, 3], x[:, 4], x[:, 5]
    V2 = xd * xd + yd * yd
    V = np.sqrt(V2)
    alpha = th - 2 * np.arctan(yd / (V + xd))
    alpha = alpha - 2 * np.pi * np.round(alpha / (2 * np.pi))
    L, D = lift_coefficient(VEH, alpha) * V2, drag_coefficient(VEH, alpha) * V2
    cg, sg = xd / V, yd / V
    xdd = (-D * cg - L * sg + u[:, 0] * np.cos(th) + VEH.epsilon * u[:, 1] * np.sin(th)) / VEH.m
    ydd = (-D * sg + L * cg + u[:, 0] * np.sin(th) - VEH.epsilon * u[:, 1] * np.cos(th)) / VEH.m - VEH.g
    want = np.column_stack([xd, yd, xdd, ydd, om, u[:, 1] / VEH.J])
    assert _bitwise(model.rhs(x, u), want)
    for i in range(N):
        assert _bitwise(model.rhs(x[i], u[i]), want[i])
    # another vehicle (every constant changed) gives its own constants, not a cached copy of the first
    other = VEH.with_overrides(a_L=20.0, a_D=2.0, b=0.5, c=4.0, epsilon=0.2, m=2.0, g=1.5, J=3.0, rho_AW_half=0.7)
    mo = CTOLAircraft(other)
    assert mo._constants == (0.7 * 20.0, 0.7 * 2.0, 0.5, 4.0, 0.2, 2.0, 1.5, 3.0)
    assert not np.array_equal(mo.rhs(x[0], u[0]), model.rhs(x[0], u[0]))


def test_vehicle_constants_and_plant_are_built_once():
    model = CTOLAircraft(VEH)
    assert model._constants is model._constants
    assert model == CTOLAircraft(VEH)  # the cache is not a field: equality is unchanged
    ext = ExtendedCTOL(VEH)
    assert ext._plant is ext._plant and ext._plant.vehicle is VEH
    cl = ClosedLoopCTOL(VEH, GLIDE, 10.0, 5.0)
    assert cl.reduced is cl.reduced
    assert (cl.reduced.speed, cl.reduced.gamma, cl.reduced.theta, cl.reduced.T) == (GLIDE.speed, GLIDE.gamma,
                                                                                      GLIDE.theta, cl.T)


def test_controller_equals_the_checked_public_law():
    """The controller calls the law without re-checking its data (checked once at construction); the values are
    those of the public, checking :func:`steady_glide_inputs`."""
    rng = np.random.default_rng(14)
    x, _ = _states(rng)
    ctrl = SteadyGlideController(VEH, GLIDE, 7e5, 250.0, 1.3)
    want = steady_glide_inputs(VEH, GLIDE, 7e5, 250.0, 1.3, x[:, 4], x[:, 5])
    assert _bitwise(ctrl.u(x), want)
    for i in range(N):
        assert _bitwise(ctrl.u(x[i]), want[i])
        assert _bitwise(ctrl(0.0, x[i]), want[i])
    # the public law still checks its vehicle on every call
    with pytest.raises(ModelError, match="epsilon"):
        steady_glide_inputs(VEH.with_overrides(epsilon=0.0), GLIDE, 7e5, 250.0, 1.3, 0.1, 0.0)
    with pytest.raises(ArgumentTypeError):
        steady_glide_inputs("dc8_ctol", GLIDE, 7e5, 250.0, 1.3, 0.1, 0.0)
    with pytest.raises(ModelError):
        steady_glide_inputs(gc.load_vehicle("rogue"), GLIDE, 7e5, 250.0, 1.3, 0.1, 0.0)


def test_tracking_jacobian_is_the_complex_step_of_the_single_state_rhs():
    """The solvers' Jacobian (complex step of the batch) agrees with central differences of the single-state
    right-hand side, and its columns of the position and quadrature states are exactly zero."""
    model = CTOLAircraft(VEH)
    ctrl = SteadyGlideController(VEH, GLIDE, 10.0, 5.0)
    z = np.r_[GLIDE.full_state((0.0, 0.0)), 0.0, 0.0, 0.0] + np.r_[0, 0, 0.01, -0.02, 0.05, 0.3, 0, 0, 0]
    J = _closed_loop_jacobian(model, ctrl)(0.0, z)
    h = 1e-6
    Jc = np.column_stack([(_augmented(model, ctrl, z + h * e) - _augmented(model, ctrl, z - h * e)) / (2 * h)
                          for e in np.eye(9)])
    np.testing.assert_allclose(J, Jc, rtol=1e-6, atol=1e-6 * np.max(np.abs(J)))
    assert np.all(J[:, [0, 1, 6, 7, 8]] == 0.0)
    assert np.any(J[:, 2:6] != 0.0)


@pytest.mark.parametrize("bad, err", [
    (np.zeros(5), ArgumentError), (np.zeros((3, 5)), ArgumentError), (np.zeros(7), ArgumentError),
    (np.float64(0.3), ArgumentError), (np.zeros(0), ArgumentError),
    ("state", ArgumentTypeError), (np.zeros(6, dtype=bool), ArgumentTypeError),
    (np.array([0.0, 0.0, 0.2, 0.0, 0.1, "a"], dtype=object), ArgumentTypeError), (None, ArgumentTypeError),
])
def test_fast_path_boundary_bad_states_raise(bad, err):
    """States that are not float/complex vectors of the right width leave the fast path and raise the same
    GlidectlError as before (the rhs of each model and the controller)."""
    model = CTOLAircraft(VEH)
    ctrl = SteadyGlideController(VEH, GLIDE, 10.0, 5.0)
    with pytest.raises(err):
        model.rhs(bad, np.zeros(2))
    with pytest.raises(err):
        ctrl.u(bad)
    with pytest.raises(err):  # (4 reduced states: a wrong width is a 3-vector here)
        ClosedLoopCTOL(VEH, GLIDE, 10.0, 5.0).rhs(np.zeros(3) if err is ArgumentError else bad)


@pytest.mark.parametrize("bad", [np.zeros(3), np.zeros(1), np.zeros((4, 3))])
def test_fast_path_boundary_bad_inputs_raise(bad):
    x = GLIDE.full_state((0.0, 0.0))
    with pytest.raises(ArgumentError, match="trailing dimension 2"):
        CTOLAircraft(VEH).rhs(x, bad)
    with pytest.raises(ArgumentError, match="trailing dimension 2"):
        CTOLReduced(VEH, GLIDE.speed, GLIDE.gamma, GLIDE.theta).rhs(np.zeros(4), bad)


def test_integer_states_take_the_checked_path_with_the_same_values():
    """An integer state (not float: outside the fast path's early return) is converted and gives the values of the
    equal float state."""
    model = CTOLAircraft(VEH)
    xi, ui = np.array([0, 0, 1, 0, 0, 2]), np.array([1, 3])
    assert _bitwise(model.rhs(xi, ui), model.rhs(xi.astype(float), ui.astype(float)))
    assert _bitwise(model.rhs(np.stack([xi, xi]), ui)[1], model.rhs(xi.astype(float), ui.astype(float)))


@pytest.mark.parametrize("state", [
    (0.0, 0.0, 0.0, 0.0, 0.1, 0.0),          # V = 0: cos gamma = 0 / 0
    (0.0, 0.0, -1.0, 0.0, 0.1, 0.0),         # gamma = pi: the half-angle formula divides by V + xdot = 0
    (0.0, 0.0, np.nan, 0.1, 0.1, 0.0),       # a NaN state (a solver's step that blew up)
    (0.0, 0.0, 1.0, 0.1, np.inf, 0.0),       # an infinite pitch angle
    (0.0, 0.0, 0.3, 0.1, np.nan, np.inf),
    (0.0, 0.0, 1e200, 1e200, 0.2, 0.0),      # V^2 overflows
])
def test_single_state_at_a_singular_or_non_finite_point_gives_the_batch_row(state):
    """Where the single-state path's Python floats raise (division by zero, math domain, overflow), the right-hand
    side and the control law fall back to numpy scalars and return the batch row's inf and NaN, as before (a solver
    then fails its step and the run reports it), instead of raising."""
    x = np.array(state)
    u = np.array([1.0, 2.0])
    ctrl = SteadyGlideController(VEH, GLIDE, 7e5, 250.0, 1.3)
    model = CTOLAircraft(VEH)
    with np.errstate(all="ignore"):
        for one, batch in ((model.rhs(x, u), model.rhs(x[None], u[None])[0]), (ctrl.u(x), ctrl.u(x[None])[0]),
                           (_augmented(model, ctrl, np.r_[x, 0, 0, 0]),
                            _augmented(model, ctrl, np.r_[x, 0, 0, 0][None])[0])):
            assert one.dtype == np.float64 and one.shape == batch.shape
            np.testing.assert_array_equal(one, batch)
    assert not np.all(np.isfinite(model.rhs(x, u)))
