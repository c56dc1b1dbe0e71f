"""Chosen inputs and sensors (issue 16 part 4): named outputs, designs on a subset of the inputs, observability by
output name, LQG output feedback with an explicit estimator, and python-control interop (to_iosys)."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest

import glidectl as gc
from glidectl.analysis.linear import DepthGlidePathModel, depth_rate, glide_model
from glidectl.derivatives import central_difference_jacobians

ROGUE = gc.load_vehicle("rogue")
GLIDE = gc.steady_glide(ROGUE, 0.3, math.radians(-45), r_p3=0.05)
SENSORS = ("z", "theta", "Omega2")
NOISE = {"z": 0.1, "theta": 0.01, "Omega2": 0.01}
_CACHE: dict[str, object] = {}


def lqg() -> gc.LQGController:
    """LQG from depth, pitch and pitch rate, with the vertical mass axis held (acceleration form, w3 left out)."""
    if "lqg" not in _CACHE:
        _CACHE["lqg"] = gc.lqg_glide(ROGUE, GLIDE, SENSORS, NOISE, inputs="acceleration", actuate=("w1", "w4"))
    return _CACHE["lqg"]  # type: ignore[return-value]


# ----------------------------------------------------------------------------------------------------- named outputs
def test_default_outputs_are_all_states_and_unchanged():
    sys = gc.linearize_glide(ROGUE, GLIDE)
    assert list(sys.output_labels) == list(sys.state_labels) and sys.nstates == 10
    np.testing.assert_array_equal(sys.C, np.eye(10))
    named = gc.linearize_glide(ROGUE, GLIDE, outputs=("theta", "m0"))
    np.testing.assert_array_equal(named.A, sys.A)
    np.testing.assert_array_equal(named.C, np.eye(10)[[1, 9]])


def test_depth_output_appends_the_kinematic_state_and_matches_central_differences():
    sys = gc.linearize_glide(ROGUE, GLIDE, outputs={"z": "z", "theta": "theta", "sink": "depth_rate",
                                                    "lead": {"theta": 1.0, "Omega2": 0.5}})
    assert list(sys.output_labels) == ["z", "theta", "sink", "lead"]
    assert list(sys.state_labels)[-1] == "z" and sys.nstates == 11
    C = np.asarray(sys.C)
    np.testing.assert_array_equal(C[0], np.eye(11)[10])
    np.testing.assert_array_equal(C[3], np.eye(11)[1] + 0.5 * np.eye(11)[2])
    model, xe = glide_model(ROGUE, GLIDE)
    dmodel = DepthGlidePathModel(model)
    xe = np.append(xe, 0.0)
    # depth is a pure integrator whose row is the linearized sink rate (2.16), equal to the depth-rate output row
    Acd, _ = central_difference_jacobians(dmodel.rhs, xe, np.zeros(3))
    np.testing.assert_allclose(np.asarray(sys.A)[10], Acd[10], atol=1e-8)
    np.testing.assert_array_equal(np.asarray(sys.A)[:, 10], 0.0)
    h = 1e-6
    Ccd = np.array([(depth_rate(dmodel, xe + h * e) - depth_rate(dmodel, xe - h * e)) / (2 * h) for e in np.eye(11)])
    np.testing.assert_allclose(C[2], Ccd, atol=1e-8)
    np.testing.assert_allclose(C[2], np.asarray(sys.A)[10], atol=1e-12)
    # the sink rate of the trimmed glide: -V sin(gamma) (z down)
    theta, v1, v3 = xe[1], xe[3], xe[4]
    assert -math.sin(theta) * v1 + math.cos(theta) * v3 == pytest.approx(-0.3 * math.sin(GLIDE.gamma), rel=1e-9)
    # the body rows are the glide-path model's
    np.testing.assert_allclose(np.asarray(sys.A)[:10, :10], np.asarray(gc.linearize_glide(ROGUE, GLIDE).A),
                               atol=1e-14)


@pytest.mark.parametrize(("outputs", "err", "match"), [
    (("depth",), gc.ArgumentError, "unknown output channel"),
    ((), gc.ArgumentError, "empty output selection"),
    (("theta", "theta"), gc.ArgumentError, "twice"),
    ({"a": {"theta": 0.0}}, gc.ArgumentError, "no nonzero coefficient"),
    ({"a": {"theta": "x"}}, gc.ArgumentTypeError, "coefficient"),
    (3, gc.ArgumentTypeError, "outputs must be"),
    ({"a": 1.0}, gc.ArgumentTypeError, "channel name or a mapping"),
])
def test_bad_outputs(outputs, err, match):
    with pytest.raises(err, match=match):
        gc.linearize_glide(ROGUE, GLIDE, outputs=outputs)


# ------------------------------------------------------------------------------------------------ inputs (actuate)
@pytest.mark.parametrize(("inputs", "actuate", "left_out", "locked"), [
    ("force", ("u1", "u4"), 1, ("P_P3",)),
    ("acceleration", ("w1", "w4"), 1, ("r_P3", "rdot_P3")),
    ("acceleration", ("w1", "w3"), 2, ("m0",)),
])
def test_lqr_on_a_subset_of_inputs(inputs, actuate, left_out, locked):
    c = gc.lqr_glide(ROGUE, GLIDE, inputs=inputs, actuate=actuate)
    assert c.actuate == actuate and c.locked_states == locked
    assert np.all(c.K[left_out] == 0.0)
    cols = [c.state_names.index(s) for s in locked]
    assert np.all(c.K[:, cols] == 0.0)
    A, B = np.asarray(c.plant.A), np.asarray(c.plant.B)
    keep = [i for i in range(10) if i not in cols]
    E = np.linalg.eigvals((A - B @ c.K)[np.ix_(keep, keep)])
    assert np.max(E.real) < 0
    # each locked state adds a pole at 0 (the actuator stays where it is), the rest are the designed ones
    assert np.sum(np.abs(c.closed_loop_poles) < 1e-9) == len(locked)
    assert np.max(c.closed_loop_poles.real) < 1e-9


def test_lqr_subset_holds_the_left_out_mass_axis_on_the_nonlinear_plant():
    c = gc.lqr_glide(ROGUE, GLIDE, inputs="acceleration", actuate=("w1", "w4"))
    cl = gc.closed_loop(c)
    x0 = cl.equilibrium.copy()
    x0[1] += 0.05
    x0[0] += 0.3
    run = gc.simulate(cl, x0, 40.0, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(run.state("r_P3"), x0[7], atol=1e-12)
    np.testing.assert_allclose(run.state("rdot_P3"), 0.0, atol=1e-12)
    # the slowest designed pole is -0.048/s: over 40 s the deviation shrinks to about exp(-1.9) = 0.15
    dev = np.linalg.norm(run.x - cl.equilibrium, axis=1)
    slowest = -np.max(c.closed_loop_poles.real[np.abs(c.closed_loop_poles) > 1e-9])
    assert dev[-1] < 2 * math.exp(-slowest * 40.0) * dev[0] and dev[-1] < 0.25 * dev[0]


def test_default_actuate_leaves_out_a_fixed_actuator_and_keeps_preset_gains():
    assert gc.default_actuate(ROGUE) == ("u1", "u3", "u4")
    default = gc.lqr_glide(ROGUE, GLIDE)
    explicit = gc.lqr_glide(ROGUE, GLIDE, actuate=("u1", "u3", "u4"))
    np.testing.assert_array_equal(default.K, explicit.K)
    assert default.locked_states == ()
    fixed = ROGUE.with_actuators(r_P3={"fixed": 0.05, "unit": "m"})
    assert gc.default_actuate(fixed, "acceleration") == ("w1", "w4")
    g = gc.steady_glide(fixed, 0.3, math.radians(-45), r_p3=0.05)
    c = gc.lqr_glide(fixed, g, inputs="acceleration")
    # the fixed r_P3 leaves the design model with its states and its input w3
    assert c.actuate == ("w1", "w4") and c.plant.input_labels == ["w1", "w4"] and c.K.shape == (2, 8)
    full = gc.lqr_glide(fixed, g, inputs="acceleration", reduce_fixed=False)
    assert full.actuate == ("w1", "w4") and np.all(full.K[1] == 0.0)
    assert np.max(np.abs(gc.lqr_glide(ROGUE, GLIDE, inputs="acceleration").K[1])) > 0


def test_place_glide_on_a_subset_places_the_poles():
    poles = [-0.5, -0.6, -0.7, -0.8 + 0.3j, -0.8 - 0.3j, -1.0, -1.1, -1.2]
    c = gc.place_glide(ROGUE, GLIDE, poles, inputs="acceleration", actuate=("w1", "w4"))
    assert np.all(c.K[1] == 0.0) and np.all(c.K[:, [7, 8]] == 0.0)
    E = c.closed_loop_poles
    E = E[np.abs(E) > 1e-9]
    np.testing.assert_allclose(np.sort_complex(E), np.sort_complex(np.array(poles)), atol=1e-6)
    with pytest.raises(gc.ArgumentError, match="need 8 poles"):
        gc.place_glide(ROGUE, GLIDE, [-1.0 - 0.1 * k for k in range(10)], inputs="acceleration",
                       actuate=("w1", "w4"))
    with pytest.raises(gc.ArgumentError, match="at most 2 times"):
        gc.place_glide(ROGUE, GLIDE, [-1.0] * 3 + poles[3:], inputs="acceleration", actuate=("w1", "w4"))


@pytest.mark.parametrize(("actuate", "err", "match"), [
    ((), gc.ArgumentError, "actuate is empty"),
    (("u1", "w4"), gc.ArgumentError, "not inputs"),
    (("u1", "u1"), gc.ArgumentError, "twice"),
    ((1, 2), gc.ArgumentTypeError, "actuate must be"),
])
def test_bad_actuate(actuate, err, match):
    with pytest.raises(err, match=match):
        gc.lqr_glide(ROGUE, GLIDE, actuate=actuate)


# ------------------------------------------------------------------------------------------ observability by output
def test_observability_by_output_name():
    sys = gc.linearize_glide(ROGUE, GLIDE, outputs={"depth": "z", "pitch": "theta", "lead": {"theta": 1.0,
                                                                                              "Omega2": 1.0}})
    depth = gc.observability(sys, "depth")
    both = gc.observability(sys, ["depth", "pitch"])
    assert depth.channels == ("depth",) and both.channels == ("depth", "pitch")
    # independent count: rank of the Kalman observability matrix on the balanced pair
    A, C = np.asarray(sys.A), np.asarray(sys.C)
    for rt, rows in ((depth, [0]), (both, [0, 1])):
        O = control.obsv(A, C[rows])
        s = np.linalg.svd(O / np.linalg.norm(O, axis=0).clip(1e-300), compute_uv=False)
        assert rt.rank == int(np.sum(s > 1e-9 * s[0]))
    assert (depth.rank, both.rank) == (7, 8)
    assert not both.full  # z' needs the horizontal position: never observable from depth and pitch
    assert 0.0 in np.round(both.uncontrollable_modes, 9)
    # a state name selects its row of I; an output name its row of C (here the same row)
    by_state = gc.observability(sys, ["z", "theta"])
    assert by_state.rank == both.rank
    assert gc.observability(sys, ["depth", "lead"]).rank == gc.observability(sys, ["z", "theta", "Omega2"]).rank
    with pytest.raises(gc.ArgumentError, match="unknown output or state"):
        gc.observability(sys, "altitude")


# ------------------------------------------------------------------------------------------------------------- LQG
def test_lqg_design_estimates_what_the_sensors_see():
    c = lqg()
    assert "z_prime" not in c.estimated_states  # not measured: needs the horizontal position
    assert c.estimated_states[-1] == "z" and "z" not in c.regulated_states
    assert "r_P3" not in c.estimated_states  # held: w3 is left out
    assert np.max(c.estimator_poles.real) < 0 and np.max(c.regulator_poles.real) < 0
    assert np.all(c.K[1] == 0.0)
    assert c.L.shape == (len(c.estimated_states), 3)
    # the Kalman gain is python-control's lqe on the estimated states
    ei = [c.state_names.index(s) for s in c.estimated_states]
    A, C = np.asarray(c.plant.A)[np.ix_(ei, ei)], np.asarray(c.plant.C)[:, ei]
    L, _, _ = control.lqe(A, np.eye(len(ei)), C, c.process_noise, np.diag(c.noise**2))
    np.testing.assert_allclose(c.L, L, rtol=1e-8, atol=1e-12)


def test_lqg_estimation_error_decays_on_the_nonlinear_plant():
    c = lqg()
    cl = gc.closed_loop(c)
    assert cl.equilibrium is None  # depth grows along the glide
    _, xe = c.plant_model()
    n = len(xe)
    ei = [c.state_names.index(s) for s in c.estimated_states]
    x0 = np.concatenate([xe, xe[ei]])
    x0[1] += 0.03           # the plant is off the glide
    x0[n + 1] -= 0.05       # and the estimate is wrong: pitch,
    x0[n + 3] += 0.02       # forward speed,
    x0[-1] += 1.0           # depth
    run = gc.simulate(cl, x0, 40.0, rtol=1e-6, atol=1e-9)
    err = run.x[:, n:] - run.x[:, ei]
    e = np.linalg.norm(err / np.array([0.1 if s == "z" else 1.0 for s in c.estimated_states]), axis=1)
    assert e[-1] < 0.05 * e[0]
    k = np.searchsorted(run.t, 20.0)
    assert e[-1] < e[k] < e[0]
    # and the plant is regulated to the glide (pitch back to theta_e)
    assert abs(run.state("theta")[-1] - xe[1]) < 0.1 * 0.03


def test_lqg_to_iosys_is_the_estimator_and_law():
    c = lqg()
    io = c.to_iosys()
    assert list(io.input_labels) == list(SENSORS) and list(io.output_labels) == ["w1", "w3", "w4"]
    assert list(io.state_labels) == [f"{s}_hat" for s in c.estimated_states]
    _, xe = c.plant_model()
    ei = [c.state_names.index(s) for s in c.estimated_states]
    ye = c.measure(xe)
    d = io._rhs(0.0, xe[ei], ye)
    expected = np.zeros(len(ei))
    expected[-1] = -0.3 * math.sin(GLIDE.gamma)  # the estimate follows the nominal sink
    np.testing.assert_allclose(d, expected, atol=1e-9)
    np.testing.assert_allclose(io._out(0.0, xe[ei], ye), 0.0, atol=1e-12)
    xh = xe[ei].copy()
    xh[0] += 0.01
    np.testing.assert_allclose(io._out(0.0, xh, ye), c.u_from_estimate(xh))


def test_lqg_with_full_mass_sensors_regulates_the_path_when_z_prime_is_measured():
    c = gc.lqg_glide(ROGUE, GLIDE, ("z_prime", "theta", "r_P1", "r_P3", "m0"),
                     {"z_prime": 0.5, "theta": 0.01, "r_P1": 1e-3, "r_P3": 1e-3, "m0": 1e-3})
    assert c.estimated_states == tuple(c.state_names) and c.regulated_states == tuple(c.state_names)
    cl = gc.closed_loop(c)
    assert cl.equilibrium is not None
    J, _ = gc.jacobians(cl.rhs, cl.equilibrium, np.zeros(0))
    assert np.max(np.linalg.eigvals(J).real) < 0


@pytest.mark.parametrize(("kw", "err", "match"), [
    ({"sensors": ("depth",)}, gc.ArgumentError, "unknown output channel"),
    ({"sensors": ()}, gc.ArgumentError, "empty output selection"),
    ({"noise": {"z": -0.1, "theta": 0.01, "Omega2": 0.01}}, gc.ArgumentError, "noise"),
    ({"noise": {"z": 0.1, "theta": 0.01}}, gc.ArgumentError, "no standard deviation"),
    ({"noise": {**NOISE, "m0": 0.1}}, gc.ArgumentError, "not sensors"),
    ({"noise": 0.1}, gc.ArgumentTypeError, "mapping"),
    ({"actuate": None}, gc.ArgumentError, "cannot detect"),
    ({"sensors": ("m0",), "noise": {"m0": 0.01}}, gc.ArgumentError, "cannot detect"),
    ({"process_noise": {"z_prime": 1.0}}, gc.ArgumentError, "not estimated"),
    ({"process_noise": {"theta": 0.0}}, gc.ArgumentError, "process_noise"),
])
def test_lqg_bad_sensors_and_noise(kw, err, match):
    args = {"sensors": SENSORS, "noise": NOISE, "inputs": "acceleration", "actuate": ("w1", "w4"), **kw}
    if kw.get("actuate", 0) is None:
        args["inputs"] = "force"
    with pytest.raises(err, match=match):
        gc.lqg_glide(ROGUE, GLIDE, args.pop("sensors"), args.pop("noise"), **args)


# ---------------------------------------------------------------------------------------------------------- iosys
def test_to_iosys_matches_simulate_on_a_closed_loop():
    cl = gc.closed_loop(gc.lqr_glide(ROGUE, GLIDE))
    io = cl.to_iosys()
    assert list(io.state_labels) == list(cl.state_names) and io.ninputs == 0
    x0 = cl.equilibrium.copy()
    x0[0] += 0.5
    x0[1] += 0.05
    kw = {"rtol": 1e-10, "atol": 1e-12}
    r = control.input_output_response(io, np.linspace(0.0, 10.0, 11), 0.0, x0, solve_ivp_kwargs=kw)
    run = gc.simulate(cl, x0, 10.0, **kw)
    np.testing.assert_allclose(r.states[:, -1], run.x[-1], atol=1e-7)


def test_to_iosys_matches_simulate_on_the_open_loop_glider():
    m = gc.LongitudinalGlider(ROGUE)
    io = gc.to_iosys(m)
    assert list(io.input_labels) == ["u1", "u3", "u4"] and list(io.state_labels) == list(m.state_names)
    x0 = GLIDE.force_state()
    u = np.array([0.01, -0.02, 0.001])
    kw = {"rtol": 1e-10, "atol": 1e-12}
    T = np.linspace(0.0, 5.0, 6)
    r = control.input_output_response(io, T, np.tile(u[:, None], (1, T.size)), x0, solve_ivp_kwargs=kw)
    run = gc.simulate(m, x0, 5.0, controller=lambda t, x: u, **kw)
    np.testing.assert_allclose(r.states[:, -1], run.x[-1], atol=1e-7)
    with pytest.raises(gc.ArgumentTypeError, match="glidectl model"):
        gc.to_iosys(object())


def test_longitudinal_models_export_to_python_control():
    """``LongitudinalGlider.to_iosys()`` (and the acceleration and glide-path forms) are python-control systems with
    the model's names whose ``input_output_response`` follows ``gc.simulate`` at the trim with a constant input."""
    import control

    veh = gc.load_vehicle("rogue")
    g = gc.steady_glide(veh, 0.3, -np.pi / 4, r_p3=0.05)
    model = gc.LongitudinalGlider(veh)
    sys = model.to_iosys()
    assert isinstance(sys, control.NonlinearIOSystem)
    assert tuple(sys.state_labels) == tuple(model.state_names) and tuple(sys.input_labels) == tuple(model.input_names)
    for m in (gc.AccelerationControlledGlider(veh), gc.GlidePathModel(model, g.gamma)):
        s2 = m.to_iosys(name="x")
        assert tuple(s2.state_labels) == tuple(m.state_names) and s2.name == "x"
    x0 = g.force_state()
    x0[2] += 0.01
    t = np.linspace(0.0, 5.0, 51)
    u = np.zeros(len(model.input_names))
    resp = control.input_output_response(sys, t, np.tile(u[:, None], (1, len(t))), x0,
                                         solve_ivp_kwargs={"rtol": 1e-9, "atol": 1e-12})
    sim = gc.simulate(model, x0, 5.0, lambda tt, x: u, t_eval=t, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(resp.states.T, sim.x, rtol=1e-6, atol=1e-8)
