"""Closed loops of the package's controllers as models (glidectl.closed_loop, glidectl.ClosedLoop): the equilibrium
each controller was designed for is an equilibrium of its closed loop, the right-hand side is batch-capable, and
the closed loop is the plant's own vector field under the controller's law."""

from __future__ import annotations

import dataclasses
import math
import pickle

import numpy as np
import pytest

import glidectl as gc
from glidectl.derivatives import jacobians
from glidectl.models.reduced import ReducedLongitudinalGlider

ROGUE = gc.load_vehicle("rogue")
SPHERE = gc.load_vehicle("sphere_ch5")
ELEV = gc.load_vehicle("elevator_ch6")
DC8 = gc.load_vehicle("dc8_ctol")


def _lqr(inputs: str = "force", offset: float = 0.0) -> gc.LinearGlideController:
    ctrl = gc.lqr_glide(ROGUE, gc.steady_glide(ROGUE, 0.3, math.radians(-45), r_p3=0.05), inputs=inputs)
    return dataclasses.replace(ctrl, path_offset=offset) if offset else ctrl


def _torque() -> gc.TorqueDesign:
    return gc.design_torque_control(SPHERE, speed=1.6)


def _buoyancy() -> gc.BuoyancyController:
    return gc.BuoyancyController(gc.buoyancy_equilibrium(SPHERE, 1.5), SPHERE, K_b=5.0)


def _elevator() -> gc.ElevatorBuoyancyController:
    return gc.ElevatorBuoyancyController(gc.elevator_equilibrium(ELEV, 1.0, -math.pi / 4), ELEV, K=1.0)


def _ctol() -> gc.SteadyGlideController:
    return gc.SteadyGlideController(DC8, gc.ctol_glide(DC8, speed=0.85 / math.sqrt(30.0), gamma=0.0), 10.0, 5.0)


CONTROLLERS = {
    "lqr_glide force": lambda: _lqr(),
    "lqr_glide acceleration": lambda: _lqr("acceleration"),
    "lqr_glide path offset": lambda: _lqr(offset=2.0),
    "torque design": _torque,
    "buoyancy": _buoyancy,
    "elevator": _elevator,
    "ctol steady glide": _ctol,
}


@pytest.fixture(scope="module", params=list(CONTROLLERS))
def loop(request):
    ctrl = CONTROLLERS[request.param]()
    return ctrl, gc.closed_loop(ctrl)


def test_equilibrium_is_an_equilibrium(loop):
    _, cl = loop
    xe = cl.equilibrium
    assert isinstance(cl, gc.ClosedLoop) and isinstance(xe, np.ndarray)
    assert xe.shape == (cl.n_states,) == (len(cl.state_names),)
    assert cl.input_names == ()
    f = cl.rhs(xe)
    assert f.shape == xe.shape
    assert np.max(np.abs(f)) <= 1e-9 * max(1.0, float(np.max(np.abs(xe))))
    assert cl.vehicle.provenance == cl.provenance and cl.provenance
    assert type(cl.plant).__name__ in cl.name


def test_batch_rhs_equals_row_wise(loop):
    _, cl = loop
    rng = np.random.default_rng(3)
    xe = cl.equilibrium
    X = xe + 0.02 * (1.0 + np.abs(xe)) * rng.standard_normal((5, cl.n_states))
    F = cl.rhs(X)
    assert F.shape == (5, cl.n_states)
    rows = np.array([cl.rhs(x) for x in X])
    np.testing.assert_allclose(F, rows, rtol=1e-12, atol=1e-14 * float(np.max(np.abs(rows))))
    np.testing.assert_allclose(cl.rhs(X[None]), F[None], rtol=1e-12, atol=1e-14 * float(np.max(np.abs(rows))))


def test_closed_loop_is_plant_under_controller(loop):
    ctrl, cl = loop
    X = cl.equilibrium + 0.01 * np.random.default_rng(5).standard_normal((4, cl.n_states))
    if isinstance(ctrl, gc.TorqueDesign):
        ref = cl.plant.rhs(X, ctrl.law(0.0, X))
    elif isinstance(ctrl, gc.SteadyGlideController):
        ref = gc.ClosedLoopCTOL(ctrl.vehicle, ctrl.glide, ctrl.k3, ctrl.k4, ctrl.T).rhs(X)
    elif isinstance(ctrl, gc.LinearGlideController):  # the controller acts on full states (x, z, ...)
        g = ctrl.glide.gamma
        full = np.concatenate([(np.sin(g) * X[:, :1]), (np.cos(g) * X[:, :1]), X[:, 1:]], axis=1)
        ref = cl.plant.rhs(X, ctrl(0.0, full))
    else:
        ref = cl.plant.rhs(X, ctrl(0.0, X))
    np.testing.assert_allclose(cl.rhs(X), ref, rtol=1e-12, atol=1e-13 * float(np.max(np.abs(ref))))


def test_closed_loop_is_locally_stable(loop):
    ctrl, cl = loop
    A, _ = jacobians(lambda x, u: cl.rhs(x), cl.equilibrium, np.zeros(0))
    lam = np.linalg.eigvals(A)
    if isinstance(ctrl, gc.LinearGlideController):  # the exact linearization of the loop is A - B K
        np.testing.assert_allclose(np.sort_complex(lam), np.sort_complex(ctrl.closed_loop_poles), rtol=1e-6,
                                   atol=1e-9)
    assert np.max(lam.real) < 0


def test_torque_closed_loop_is_the_overridden_open_loop():
    d = _torque()
    cl = gc.closed_loop(d)
    X = cl.equilibrium + 0.05 * np.random.default_rng(0).standard_normal((20, 4))
    ol = ReducedLongitudinalGlider(d.closed_loop_vehicle).rhs(X)
    assert np.max(np.abs(cl.rhs(X) - ol)) <= 1e-12 * np.max(np.abs(ol))
    via_law = d.law.closed_loop(SPHERE, d.equilibrium)
    np.testing.assert_array_equal(via_law.rhs(X), cl.rhs(X))


def test_simulate_many_and_pickle():
    cl = gc.closed_loop(_buoyancy())
    X0 = cl.equilibrium + np.array([[0.05, 0.02, 0.0, 0.0, 0.05], [-0.05, -0.02, 0.01, 0.0, -0.05]])
    ens = gc.simulate_many(cl, X0, 5.0)
    assert ens.x_final.shape == X0.shape and np.all(np.isfinite(ens.x_final))
    back = pickle.loads(pickle.dumps(cl))
    np.testing.assert_array_equal(back.rhs(X0), cl.rhs(X0))


def test_two_argument_form_and_errors():
    ctrl = _elevator()
    plant = gc.ElevatorBuoyancyGlider(ELEV)
    cl = gc.closed_loop(plant, ctrl.u, equilibrium=ctrl.eq.state)
    np.testing.assert_array_equal(cl.rhs(ctrl.eq.state), gc.closed_loop(ctrl).rhs(ctrl.eq.state))
    free = gc.closed_loop(plant, ctrl.u)
    assert free.equilibrium is None
    with pytest.raises(gc.ArgumentError, match="equilibrium"):
        gc.closed_loop(ctrl, equilibrium=ctrl.eq.state)
    with pytest.raises(gc.ArgumentTypeError, match="does not know"):
        gc.closed_loop(gc.FeedbackLinearizingController(DC8, gc.climb_trajectory(DC8)))
    with pytest.raises(gc.ArgumentError, match="equilibrium"):
        gc.ClosedLoop(plant, ctrl.u, np.zeros(3))
    with pytest.raises(gc.ArgumentTypeError, match="not a glidectl model"):
        gc.ClosedLoop(object(), ctrl.u)
    with pytest.raises(gc.ArgumentError, match="trailing dimension"):
        cl.rhs(np.zeros(4))


# ------------------------------------------------------------------------------------------- bad inputs (issue 15)
@pytest.mark.parametrize("thing", [None, "lqr", 3.0, object(), ROGUE, np.zeros(3)])
def test_closed_loop_of_a_non_controller_is_an_argument_type_error(thing):
    with pytest.raises(gc.ArgumentTypeError, match="does not know"):
        gc.closed_loop(thing)
    with pytest.raises(TypeError):  # the builtin still catches it
        gc.closed_loop(thing)


def test_closed_loop_with_a_law_checks_plant_law_and_outputs():
    ctrl = _elevator()
    plant = gc.ElevatorBuoyancyGlider(ELEV)
    with pytest.raises(gc.ArgumentTypeError, match="callable"):
        gc.closed_loop(plant, "u")
    with pytest.raises(gc.ArgumentError, match="equilibrium"):
        gc.closed_loop(plant, ctrl.u, equilibrium=[1.0, math.nan, 0.0, 0.0, 2.6])
    with pytest.raises(gc.ArgumentTypeError):
        gc.ClosedLoop(plant, ctrl.u, description=3)
    cl = gc.closed_loop(plant, lambda x: np.zeros((*np.shape(x)[:-1], 3)))
    with pytest.raises(gc.ArgumentError, match="the law returned shape"):
        cl.rhs(ctrl.eq.state)
    with pytest.raises(gc.ArgumentTypeError):
        cl.rhs("state")

    def bad_law(x):
        raise KeyError("the user's own error")

    with pytest.raises(KeyError, match="user"):  # a law's own exception reaches the caller unchanged
        gc.closed_loop(plant, bad_law).rhs(ctrl.eq.state)


def test_linear_controller_without_vehicle_is_a_model_error():
    ctrl = dataclasses.replace(_lqr(), vehicle=None)
    with pytest.raises(gc.ModelError, match="without its vehicle"):
        gc.closed_loop(ctrl)


@pytest.mark.parametrize("model, n, m", [
    (lambda: gc.LongitudinalGlider(ROGUE), 11, 3), (lambda: gc.AccelerationControlledGlider(ROGUE), 11, 3),
    (lambda: gc.BuoyancyGlider(SPHERE), 5, 1), (lambda: gc.ElevatorBuoyancyGlider(ELEV), 5, 2),
    (lambda: gc.TorqueControlledGlider(SPHERE), 4, 1), (lambda: gc.CTOLAircraft(DC8), 6, 2),
    (lambda: gc.ExtendedCTOL(DC8), 8, 2), (lambda: gc.Glider3D(gc.load_vehicle("slocum_ch8")), 20, 4),
])
def test_plant_rhs_checks_the_shapes_of_state_and_input(model, n, m):
    plant = model()
    with pytest.raises(gc.ArgumentError, match=f"trailing dimension {n}"):
        plant.rhs(np.ones(n + 1), np.zeros(m))
    with pytest.raises(gc.ArgumentError, match=f"trailing dimension {m}"):
        plant.rhs(np.ones(n), np.zeros(m + 1))
    with pytest.raises(gc.ArgumentTypeError):
        plant.rhs(np.ones(n), None)
    with pytest.raises(gc.ArgumentTypeError):
        plant.rhs([[1.0, 2.0], [3.0]], np.zeros(m))  # ragged


@pytest.mark.parametrize("cls", [gc.LongitudinalGlider, gc.BuoyancyGlider, gc.ElevatorBuoyancyGlider,
                                 gc.TorqueControlledGlider, gc.ReducedLongitudinalGlider, gc.Glider3D])
def test_glider_models_refuse_other_vehicles_at_construction(cls):
    with pytest.raises(gc.ModelError, match="not an underwater glider"):
        cls(DC8)
    with pytest.raises(gc.ArgumentTypeError, match="load_vehicle"):
        cls("rogue")


def test_realized_torque_loop_needs_a_controller_with_a_vehicle():
    with pytest.raises(gc.ArgumentTypeError, match="callable"):
        gc.RealizedTorqueLoop(3.0)
    with pytest.raises(gc.ArgumentTypeError, match="vehicle"):
        gc.RealizedTorqueLoop(lambda t, x: np.zeros(3))
