"""The chapter-6 models and laws build their chapter-5 model and actuator limits once: the cached pieces are the
vehicle's, and the right-hand sides equal the public building blocks they are made of."""

from __future__ import annotations

import numpy as np

import glidectl as gc
from glidectl.models.buoyancy_glider import actuator_limits, loaded_rates
from glidectl.models.elevator_glider import elevator_loads

RNG = np.random.default_rng(11)
X = np.array([1.0, -0.7, 0.05, 0.0, 0.5]) + RNG.uniform(-0.3, 0.3, (64, 5))
U = RNG.uniform(-0.1, 0.1, (64, 2))


def test_buoyancy_glider_rhs_is_loaded_rates_plus_pump():
    sph = gc.load_vehicle("sphere_ch5")
    model = gc.BuoyancyGlider(sph)
    assert model.limits == actuator_limits(sph) and model.limits is model.limits
    want = np.concatenate([loaded_rates(sph, X), actuator_limits(sph).pump(X[:, 4], U[:, 0])[:, None]], axis=1)
    np.testing.assert_allclose(model.rhs(X, U[:, :1]), want, rtol=1e-12, atol=0.0)
    # one state at a time (no batch) gives the same rows
    np.testing.assert_allclose(np.array([model.rhs(x, u) for x, u in zip(X[:5], U[:5, :1], strict=True)]),
                               want[:5], rtol=1e-12, atol=0.0)


def test_elevator_glider_rhs_is_loaded_rates_with_the_elevator_load():
    ev = gc.load_vehicle("elevator_ch6")
    model = gc.ElevatorBuoyancyGlider(ev)
    lim = actuator_limits(ev)
    assert model.limits == lim
    u2 = lim.elevator(U[:, 1])
    f3, M = elevator_loads(ev, X[:, 0] ** 2, u2)
    want = np.concatenate([loaded_rates(ev, X, f3, M), lim.pump(X[:, 4], U[:, 0])[:, None]], axis=1)
    np.testing.assert_allclose(model.rhs(X, U), want, rtol=1e-12, atol=0.0)


def test_cached_models_follow_their_own_vehicle():
    # two models of different vehicles never share a cached chapter-5 model or limits
    sph = gc.load_vehicle("sphere_ch5")
    heavy = sph.with_overrides(J2=2 * sph.J2)
    a, b = gc.TorqueControlledGlider(sph), gc.TorqueControlledGlider(heavy)
    assert a.open_loop.vehicle.J2 == sph.J2 and b.open_loop.vehicle.J2 == heavy.J2
    x, u = X[:8, :4], U[:8, :1]
    ra, rb = a.rhs(x, u), b.rhs(x, u)
    np.testing.assert_allclose(ra[:, :3], rb[:, :3], rtol=1e-12)
    assert not np.allclose(ra[:, 3], rb[:, 3])


def test_laws_use_the_vehicle_limits():
    sph = gc.load_vehicle("sphere_ch5")
    beq = gc.buoyancy_equilibrium(sph, 1.5)
    ctrl = gc.BuoyancyController(beq, sph, 5.0)
    lim = actuator_limits(sph)
    want = lim.pump(X[:, 4], -ctrl.rate_gain * (X[:, 4] - beq.m0e))[:, None]
    np.testing.assert_array_equal(ctrl(0.0, X), want)
    ev = gc.load_vehicle("elevator_ch6")
    eq = gc.elevator_equilibrium(ev, 1.0, -np.pi / 4)
    U2 = gc.ElevatorBuoyancyController(eq, ev, 1.0)(0.0, X)
    np.testing.assert_array_equal(U2[:, 1], actuator_limits(ev).elevator(eq.u2e))
    assert np.all(np.abs(U2[:, 0]) <= actuator_limits(ev).u4_max)


def test_model_loaded_rates_equal_the_function():
    sph = gc.load_vehicle("sphere_ch5")
    f3, M2 = RNG.uniform(-1.0, 1.0, 64), RNG.uniform(-0.5, 0.5, 64)
    np.testing.assert_allclose(gc.BuoyancyGlider(sph).loaded_rates(X, f3, M2), loaded_rates(sph, X, f3, M2),
                               rtol=1e-12, atol=0.0)
