"""A saturated loop is a model like any other closed loop: gc.saturated_loop returns an input-free model
(glidectl.models.saturated_loop.SaturatedLoop, fed-back channels in ``feedback_names``) with an equilibrium, that
gc.simulate, gc.simulate_many and gc.jacobians take like a gc.closed_loop, with its saturation in the right-hand
side."""

from __future__ import annotations

import control
import numpy as np
import pytest

import glidectl as gc
from glidectl.models.saturated_loop import SaturatedLoop


@pytest.fixture(scope="module")
def slocum():
    """The slocum_shallow LQR glide-path loop (w1, w4 fed back; w4 saturated at the pump rate, the actuators'
    ranges not modelled), saturated form."""
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, 0.35, np.radians(-25.0), r_p3=0.05)
    ctrl = gc.lqr_glide(veh, glide, inputs="acceleration", actuate=("w1", "w4"), reduce_fixed=False)
    loop = gc.closed_loop(ctrl)
    return veh, loop, gc.saturated_loop(loop, actuator_limits=False)


def _near(sl, scale, n, seed):
    """``n`` states about the equilibrium, the free states moved by up to ``scale`` of the box's half-widths."""
    lo, hi = sl.box
    X = np.tile(sl.equilibrium, (n, 1))
    free = list(sl.free)
    X[:, free] += scale * ((hi - lo) / 2)[free] * np.random.default_rng(seed).uniform(-1, 1, (n, len(free)))
    return X


def test_saturated_loop_is_an_input_free_model(slocum):
    veh, loop, sl = slocum
    assert isinstance(sl, SaturatedLoop) and gc.SaturatedLoop is SaturatedLoop
    assert sl.input_names == () and loop.input_names == ()
    assert sl.feedback_names == ("w1", "w4") and sl.n_feedback == 2
    assert sl.state_names == loop.state_names and sl.n_states == sl.n == len(loop.state_names)
    assert sl.vehicle is veh and sl.time_unit == "s" and sl.provenance == loop.provenance
    np.testing.assert_array_equal(sl.equilibrium, loop.equilibrium)
    assert not sl.equilibrium.flags.writeable
    x = sl.equilibrium
    assert sl.rhs(x).shape == (sl.n,) and np.max(np.abs(sl.rhs(x))) < 1e-12
    np.testing.assert_array_equal(sl.rhs(x, np.zeros(0)), sl.rhs(x))               # u is ignored
    with pytest.raises(gc.ArgumentError, match="trailing dimension"):
        sl.rhs(np.zeros(3))
    sys = sl.to_iosys(name="saturated")
    assert sys.ninputs == 0 and sys.nstates == sl.n


def test_linearization_at_the_equilibrium_is_the_unsaturated_loops(slocum):
    _, loop, sl = slocum
    A_sat, B_sat = gc.jacobians(sl.rhs, sl.equilibrium, np.zeros(0))
    A_cl, _ = gc.jacobians(loop.rhs, loop.equilibrium, np.zeros(0))
    assert B_sat.shape == (sl.n, 0)
    assert np.max(np.abs(A_sat - A_cl)) <= 1e-10 * max(1.0, float(np.max(np.abs(A_cl))))
    # python-control's linearization of the exported system (finite differences) agrees
    lin = control.linearize(sl.to_iosys(name="saturated"), sl.equilibrium, [])
    np.testing.assert_allclose(lin.A, A_cl, rtol=0, atol=1e-4 * np.max(np.abs(A_cl)))


def test_simulate_equals_the_closed_loop_where_nothing_saturates(slocum):
    _, loop, sl = slocum
    x0 = _near(sl, 0.02, 1, seed=5)[0]
    run = gc.simulate(sl, x0, 100.0)
    ref = gc.simulate(loop, x0, 100.0)
    v = (run.x - sl.equilibrium) @ sl.K.T
    assert np.max(np.abs(v[:, 1])) < 0.5 * sl.u_hi[1]                               # w4 never saturates
    assert run.input_names == () and run.u.shape == (len(run.t), 0)
    assert run.model_name == "SaturatedLoop(slocum_shallow)" and run.provenance == loop.provenance
    np.testing.assert_array_equal(run.t, ref.t)
    np.testing.assert_allclose(run.x, ref.x, rtol=0, atol=1e-7)


def test_simulate_many_from_points_near_the_equilibrium_converges(slocum):
    _, _, sl = slocum
    X0 = _near(sl, 0.05, 16, seed=0)
    v = (X0 - sl.equilibrium) @ sl.K.T
    assert np.any(np.abs(v[:, 1]) > sl.u_hi[1])                                      # some start saturated
    ens = gc.simulate_many(sl, X0, 300.0)
    lo, hi = sl.box
    assert not ens.frozen.any() and ens.stopped_by == "t_final" and ens.state_names == sl.state_names
    assert np.max(np.abs(ens.x_final - sl.equilibrium) / ((hi - lo) / 2)) < 1e-5
    # the same as one simulate per point (to the integrators' tolerances)
    one = gc.simulate(sl, X0[0], 300.0, t_eval=[300.0])
    np.testing.assert_allclose(ens.x_final[0], one.x[-1], rtol=0, atol=1e-6)


def test_saturated_rhs_differs_from_the_unsaturated_one_where_it_saturates(slocum):
    _, loop, sl = slocum
    lo, hi = sl.box
    rng = np.random.default_rng(1)
    X = lo + (hi - lo) * rng.random((400, sl.n))
    X[:, list(sl.held)] = sl.equilibrium[list(sl.held)]
    v = (X - sl.equilibrium) @ sl.K.T
    sat = np.abs(v[:, 1]) > sl.u_hi[1]
    assert sat.any() and (~sat).any()
    d_sat, d_cl = sl.rhs(X), loop.rhs(X)
    np.testing.assert_allclose(d_sat[~sat], d_cl[~sat], rtol=1e-12, atol=1e-15)
    m0 = sl.state_names.index("m0")
    assert np.all(d_sat[sat, m0] != d_cl[sat, m0])
    np.testing.assert_array_equal(np.abs(d_sat[sat, m0]), sl.u_hi[1])              # the pump at its rate limit
    assert np.all(np.abs(d_cl[sat, m0]) > sl.u_hi[1])
    other = [i for i in range(sl.n) if i != m0]
    np.testing.assert_allclose(d_sat[sat][:, other], d_cl[sat][:, other], rtol=1e-12, atol=1e-15)
