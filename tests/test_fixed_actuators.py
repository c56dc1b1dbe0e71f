"""Fixed actuators leave the design models: linearize_glide, lqr_glide, place_glide, lqg_glide and
gc.closed_loop on a vehicle whose [actuators] table fixes r_P3 (the slocum_shallow preset) work on the states that
move; reduce_fixed=False keeps the full model; vehicles without fixed actuators are unchanged."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.analysis.linear import FixedActuatorModel, design_model, fixed_actuators
from glidectl.derivatives import jacobians

SLOCUM = gc.load_vehicle("slocum_shallow")
GLIDE = gc.steady_glide(SLOCUM, 0.35, -math.radians(25), r_p3=SLOCUM.actuators["r_P3"].fixed)
ROGUE = gc.load_vehicle("rogue")
ROGUE_GLIDE = gc.steady_glide(ROGUE, 0.3, math.radians(-45), r_p3=0.0)
SENSORS = ("z", "theta", "Omega2")
NOISE = {"z": 0.05, "theta": math.radians(0.5), "Omega2": math.radians(0.2)}


def _without_zeros(poles, count):
    """``poles`` less its ``count`` eigenvalues nearest 0 (which must be 0 to rounding), sorted."""
    p = np.asarray(poles)
    order = np.argsort(np.abs(p))
    assert np.all(np.abs(p[order[:count]]) < 1e-9)
    return np.sort_complex(p[order[count:]])


def test_slocum_fixes_r_p3_and_the_design_model_drops_its_states_and_input():
    assert fixed_actuators(SLOCUM) == ("r_P3",) and fixed_actuators(ROGUE) == ()
    for inputs, states, removed_input in (("acceleration", ("r_P3", "rdot_P3"), "w3"),
                                          ("force", ("r_P3", "P_P3"), "u3")):
        red = gc.linearize_glide(SLOCUM, GLIDE, inputs)
        full = gc.linearize_glide(SLOCUM, GLIDE, inputs, reduce_fixed=False)
        assert full.nstates == 10 and red.nstates == 8 and red.ninputs == 2
        assert not set(states) & set(red.state_labels) and removed_input not in red.input_labels
        assert [q for q in full.state_labels if q not in states] == list(red.state_labels)
    # acceleration form: w3 = 0 holds the mass exactly, so the reduced model is the full one's block, bit for bit
    red = gc.linearize_glide(SLOCUM, GLIDE, "acceleration")
    full = gc.linearize_glide(SLOCUM, GLIDE, "acceleration", reduce_fixed=False)
    keep = [full.state_labels.index(q) for q in red.state_labels]
    np.testing.assert_array_equal(red.A, np.asarray(full.A)[np.ix_(keep, keep)])
    np.testing.assert_array_equal(red.B, np.asarray(full.B)[np.ix_(keep, [0, 2])])
    # its eigenvalues are the full model's less the two zeros of the mass that never moves
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(red.A)),
                               _without_zeros(np.linalg.eigvals(full.A), 2), atol=1e-12)


def test_a_vehicle_without_fixed_actuators_gets_the_same_model_bit_for_bit():
    for inputs in ("force", "acceleration"):
        a = gc.linearize_glide(ROGUE, ROGUE_GLIDE, inputs)
        b = gc.linearize_glide(ROGUE, ROGUE_GLIDE, inputs, reduce_fixed=False)
        for m in ("A", "B", "C", "D"):
            np.testing.assert_array_equal(getattr(a, m), getattr(b, m))
        assert a.state_labels == b.state_labels and a.input_labels == b.input_labels
        ca, cb = gc.lqr_glide(ROGUE, ROGUE_GLIDE, inputs=inputs), gc.lqr_glide(ROGUE, ROGUE_GLIDE, inputs=inputs,
                                                                                reduce_fixed=False)
        np.testing.assert_array_equal(ca.K, cb.K)
        assert ca.fixed_actuators == () and ca.K.shape == (3, 10)


@pytest.mark.parametrize("inputs", ["acceleration", "force"])
def test_lqr_closed_loop_of_slocum_has_no_pole_at_zero(inputs):
    c = gc.lqr_glide(SLOCUM, GLIDE, inputs=inputs)
    assert c.fixed_actuators == ("r_P3",) and c.locked_states == ()
    assert np.min(np.abs(c.closed_loop_poles)) > 1e-3 and np.max(c.closed_loop_poles.real) < 0
    # the poles of the nonlinear closed loop's linearization are the designed ones
    cl = gc.closed_loop(c)
    assert cl.state_names == c.state_names and len(cl.state_names) == 8
    A, _ = jacobians(lambda x, u: cl.rhs(x), cl.equilibrium, np.zeros(0))
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(A)), np.sort_complex(c.closed_loop_poles),
                               rtol=1e-8, atol=1e-10)


def test_reduced_lqr_poles_are_the_full_poles_less_the_two_zeros_of_the_fixed_mass():
    red = gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration")
    full = gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration", reduce_fixed=False)
    assert full.locked_states == ("r_P3", "rdot_P3") and full.K.shape == (3, 10) and red.K.shape == (2, 8)
    np.testing.assert_allclose(np.sort_complex(red.closed_loop_poles), _without_zeros(full.closed_loop_poles, 2),
                               rtol=1e-10, atol=1e-12)
    # the same gain on the states that move (the full design's w3 row and r_P3 columns are zero)
    keep = [full.state_names.index(q) for q in red.state_names]
    np.testing.assert_allclose(red.K, full.K[np.ix_([0, 2], keep)], rtol=1e-10, atol=1e-12)
    # and the same input for a full state: u(x) puts w3 = 0 where the design has no w3
    x = GLIDE.accel_state(3.0, 40.0) + np.array([0, 0, 0.02, 0.01, 0.01, -0.01, 0.002, 0.0, 0.0, 0.0, 0.01])
    np.testing.assert_allclose(red.u(x), full.u(x), rtol=1e-10, atol=1e-13)
    assert red.u(x)[1] == 0.0


def test_place_glide_places_the_poles_of_the_states_that_move():
    poles = [-0.3, -0.4, -0.5, -0.6 + 0.2j, -0.6 - 0.2j, -0.8, -1.0, -1.2]
    c = gc.place_glide(SLOCUM, GLIDE, poles, inputs="acceleration")
    np.testing.assert_allclose(np.sort_complex(c.closed_loop_poles), np.sort_complex(poles), rtol=1e-6)
    with pytest.raises(gc.ArgumentError, match="need 8 poles"):
        gc.place_glide(SLOCUM, GLIDE, [*poles, -1.5, -1.6], inputs="acceleration")


def test_reduced_closed_loop_simulates_as_the_full_one_with_the_fixed_states_held():
    red = gc.closed_loop(gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration"))
    full = gc.closed_loop(gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration", reduce_fixed=False))
    dx = np.array([0.4, 0.03, 0.01, 0.02, -0.01, 0.003, 0.001, 0.02])
    x0 = red.equilibrium + dx
    keep = [full.state_names.index(q) for q in red.state_names]
    xf0 = full.equilibrium.copy()
    xf0[keep] = x0
    te = np.linspace(0.0, 60.0, 121)
    a = gc.simulate(red, x0, 60.0, t_eval=te, rtol=1e-10, atol=1e-12)
    b = gc.simulate(full, xf0, 60.0, t_eval=te, rtol=1e-10, atol=1e-12)
    i3, i3d = full.state_names.index("r_P3"), full.state_names.index("rdot_P3")
    assert np.all(b.x[:, i3] == full.equilibrium[i3]) and np.all(b.x[:, i3d] == 0.0)
    np.testing.assert_allclose(a.x, b.x[:, keep], rtol=1e-7, atol=1e-9)
    assert np.linalg.norm(a.x[-1] - red.equilibrium) < 0.2 * np.linalg.norm(dx)


def test_force_form_holds_the_mass_by_its_constraint_force():
    model, xe = design_model(SLOCUM, GLIDE, "force")
    assert isinstance(model, FixedActuatorModel) and model.removed_states == ("r_P3", "P_P3")
    assert model.removed_inputs == ("u3",)
    inner = model.inner
    x0 = model.full_state(xe + np.array([0.1, 0.05, 0.01, 0.01, -0.01, 0.002, 0.001, 0.01]))
    u = np.zeros(2)
    full = gc.simulate(inner, x0, 20.0, lambda t, x: model.full_input(model.reduce(x), u), rtol=1e-11, atol=1e-13)
    red = gc.simulate(model, model.reduce(x0), 20.0, lambda t, x: u, rtol=1e-11, atol=1e-13)
    i3 = inner.state_names.index("r_P3")
    # the constraint force keeps the mass where it is fixed, and the reduced model is the full one on the rest
    assert np.ptp(full.x[:, i3]) < 1e-8 and np.ptp(model.reduce(full.x)[:, 0]) > 0.1
    np.testing.assert_allclose(model.reduce(full.x), red.x, rtol=1e-7, atol=1e-8)


def test_lqg_design_and_closed_loop_on_slocum_drop_the_fixed_mass():
    red = gc.lqg_glide(SLOCUM, GLIDE, SENSORS, NOISE, inputs="acceleration")
    full = gc.lqg_glide(SLOCUM, GLIDE, SENSORS, NOISE, inputs="acceleration", reduce_fixed=False)
    assert "r_P3" not in red.state_names and red.fixed_actuators == ("r_P3",) and red.K.shape == (2, 9)
    assert np.min(np.abs(red.regulator_poles)) > 1e-3 and np.min(np.abs(red.estimator_poles)) > 1e-3
    np.testing.assert_allclose(np.sort_complex(red.regulator_poles), np.sort_complex(full.regulator_poles),
                               rtol=1e-9)
    np.testing.assert_allclose(np.sort_complex(red.estimator_poles), np.sort_complex(full.estimator_poles),
                               rtol=1e-9)

    def spectrum(d):
        cl = gc.closed_loop(d)
        xe, ei = d._data()[1], d._data()[2]
        A, _ = jacobians(lambda x, u: cl.rhs(x), np.concatenate([xe, xe[ei]]), np.zeros(0))
        return np.linalg.eigvals(A)

    # plant + estimator: the full loop has the reduced loop's eigenvalues and the two zeros of r_P3, rdot_P3
    e_red, e_full = spectrum(red), spectrum(full)
    zeros_red = int(np.sum(np.abs(e_red) < 1e-9))  # z' and z: integrators nothing regulates (no fixed part)
    assert zeros_red == 2 and e_full.size == e_red.size + 2
    np.testing.assert_allclose(_without_zeros(e_red, zeros_red), _without_zeros(e_full, zeros_red + 2),
                               rtol=1e-7, atol=1e-10)


def test_observability_no_longer_counts_the_dead_states():
    red = gc.linearize_glide(SLOCUM, GLIDE, "acceleration", outputs=SENSORS)
    full = gc.linearize_glide(SLOCUM, GLIDE, "acceleration", outputs=SENSORS, reduce_fixed=False)
    r_red, r_full = gc.observability(red, SENSORS), gc.observability(full, SENSORS)
    assert r_full.n - r_full.rank == r_red.n - r_red.rank + 2
    # the dead mass's eigenvector (r_P3; rdot_P3 is its generalized eigenvector) is named among the unobservable
    named = {q for m in r_full.mode_states for q in m.states}
    assert "r_P3" in named and "r_P3" in str(r_full)
    assert all(q in ("z_prime",) for m in r_red.mode_states for q in m.states)


def test_weights_in_full_size_are_restricted_and_bad_inputs_name_the_fixed_actuator():
    full_q = np.diag([4.0, 100.0, 25.0, 400.0, 400.0, 2500.0, 2500.0, 2500.0, 2500.0, 100.0])
    a = gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration", Q=full_q, R=np.diag([100.0, 1.0, 400.0]))
    keep = [0, 1, 2, 3, 4, 5, 6, 9]
    b = gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration", Q=full_q[np.ix_(keep, keep)], R=np.diag([100.0, 400.0]))
    np.testing.assert_array_equal(a.K, b.K)
    with pytest.raises(gc.ArgumentError, match=r"fixed by the vehicle file.*reduce_fixed=False"):
        gc.lqr_glide(SLOCUM, GLIDE, inputs="acceleration", actuate=("w1", "w3"))
    with pytest.raises(gc.ArgumentTypeError, match="reduce_fixed"):
        gc.linearize_glide(SLOCUM, GLIDE, reduce_fixed="yes")
    with pytest.raises(gc.ArgumentError, match="unknown output channel 'r_P3'"):
        gc.linearize_glide(SLOCUM, GLIDE, "acceleration", outputs=("r_P3",))
    assert gc.linearize_glide(SLOCUM, GLIDE, "acceleration", outputs=("r_P3",), reduce_fixed=False).noutputs == 1
