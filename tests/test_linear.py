"""Linearization about steady glides, modes, controllability and observability (§2.3.1)."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from glidectl import GlidectlError, load_vehicle
from glidectl.analysis.linear import controllability, linearize_glide, modes, observability
from glidectl.trim.glide import steady_glide

ROGUE = load_vehicle("rogue")
FORCE_LABELS = ["z_prime", "theta", "Omega2", "v1", "v3", "r_P1", "r_P3", "P_P1", "P_P3", "m0"]
ACCEL_LABELS = ["z_prime", "theta", "Omega2", "v1", "v3", "r_P1", "rdot_P1", "r_P3", "rdot_P3", "m0"]
GAMMAS_DEG = (-45.0, -30.0, 30.0, 45.0)
OUTPUT_SETS = (("r_P1", "r_P3", "m0"), ("theta", "r_P1", "m0"), ("theta", "r_P3", "m0"))

_CACHE: dict[tuple[float, str], control.StateSpace] = {}


def glide(deg: float):
    return steady_glide(ROGUE, 0.3, math.radians(deg), r_p3=0.05)


def lin(deg: float, inputs: str) -> control.StateSpace:
    key = (deg, inputs)
    if key not in _CACHE:
        _CACHE[key] = linearize_glide(ROGUE, glide(deg), inputs=inputs)
    return _CACHE[key]


def same_multiset(a: np.ndarray, b: np.ndarray, tol: float) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return False
    r, c = linear_sum_assignment(np.abs(a[:, None] - b[None, :]))
    return bool(np.max(np.abs(a[r] - b[c])) <= tol)


# ------------------------------------------------------------------------------------------ structure


def test_force_form_labels():
    sys = lin(-45.0, "force")
    assert isinstance(sys, control.StateSpace)
    assert list(sys.state_labels) == FORCE_LABELS
    assert list(sys.input_labels) == ["u1", "u3", "u4"]
    assert list(sys.output_labels) == FORCE_LABELS
    assert np.array_equal(sys.C, np.eye(10)) and np.all(sys.D == 0)


def test_acceleration_form_labels():
    sys = lin(-45.0, "acceleration")
    assert list(sys.state_labels) == ACCEL_LABELS
    assert list(sys.input_labels) == ["w1", "w3", "w4"]


def test_default_is_force():
    sys = linearize_glide(ROGUE, glide(30.0))
    assert np.array_equal(sys.A, lin(30.0, "force").A)


@pytest.mark.parametrize("bad", ["torque", "Force", "", None])
def test_bad_inputs_kind(bad):
    with pytest.raises(GlidectlError):
        linearize_glide(ROGUE, glide(-45.0), inputs=bad)


def test_glide_of_another_vehicle_is_rejected():
    other = load_vehicle("rogue", K_M=-40.0)
    with pytest.raises(GlidectlError):
        linearize_glide(other, glide(-45.0))


@pytest.mark.parametrize("deg", GAMMAS_DEG)
def test_acceleration_form_zeta_block(deg):
    """(2.36): zeta' = A zeta + B w, A the double integrators, B selecting w; eta does not enter zeta'."""
    sys = lin(deg, "acceleration")
    A, B = np.asarray(sys.A), np.asarray(sys.B)
    i = {s: k for k, s in enumerate(ACCEL_LABELS)}
    for row, b in (("rdot_P1", [1, 0, 0]), ("rdot_P3", [0, 1, 0]), ("m0", [0, 0, 1])):
        assert np.all(np.abs(A[i[row]]) <= 1e-14), row
        np.testing.assert_allclose(B[i[row]], b, rtol=0, atol=1e-14)
    for pos, vel in (("r_P1", "rdot_P1"), ("r_P3", "rdot_P3")):
        expected = np.zeros(10)
        expected[i[vel]] = 1.0
        np.testing.assert_allclose(A[i[pos]], expected, rtol=0, atol=1e-14)
        np.testing.assert_allclose(B[i[pos]], 0, atol=1e-14)


@pytest.mark.parametrize("deg", GAMMAS_DEG)
@pytest.mark.parametrize("inputs", ["force", "acceleration"])
def test_glide_path_row(deg, inputs):
    """(2.30) linearized at a glide: dz''/dtheta = -V, dz''/dv1 = -sin(alpha), dz''/dv3 = cos(alpha)."""
    sys = lin(deg, inputs)
    gl = glide(deg)
    A = np.asarray(sys.A)
    row = A[0]
    assert row[1] == pytest.approx(-gl.speed, rel=1e-13)
    assert row[3] == pytest.approx(-math.sin(gl.alpha), rel=1e-12)
    assert row[4] == pytest.approx(math.cos(gl.alpha), rel=1e-13)
    assert np.all(np.abs(A[:, 0]) == 0)  # nothing depends on z'
    assert np.all(np.abs(np.asarray(sys.B)[0]) <= 1e-14)


@pytest.mark.parametrize("deg", GAMMAS_DEG)
def test_force_form_spectrum_structure(deg):
    """With u = 0 the rows of P_P1, P_P3, m0 and the column of z' vanish: four exact zeros, and the
    remaining block (theta, Omega2, v1, v3, r_P1, r_P3) has one more zero (r_P moved along gravity is still an
    equilibrium)."""
    sys = lin(deg, "force")
    A = np.asarray(sys.A)
    i = {s: k for k, s in enumerate(FORCE_LABELS)}
    for row in ("P_P1", "P_P3", "m0"):
        assert np.all(A[i[row]] == 0)
    blk = [i[s] for s in ("theta", "Omega2", "v1", "v3", "r_P1", "r_P3")]
    gl = glide(deg)
    null = np.zeros(10)
    null[i["r_P1"]], null[i["r_P3"]] = -math.sin(gl.theta), math.cos(gl.theta)
    assert np.max(np.abs(A @ null)) < 1e-12
    lam = np.linalg.eigvals(A)
    block = np.linalg.eigvals(A[np.ix_(blk, blk)])
    assert same_multiset(lam, np.concatenate([block, np.zeros(4)]), 1e-9)
    assert np.sum(np.abs(lam) < 1e-9) == 5


def test_up_and_down_glides_are_not_dynamically_mirrored():
    """The +-gamma glides with the same r_p3 are mirror images as equilibria (test_trim.py) but the model has
    no reflection symmetry (test_longitudinal.py): their spectra differ. Numbers computed with glidectl."""
    up = np.linalg.eigvals(np.asarray(lin(45.0, "force").A))
    down = np.linalg.eigvals(np.asarray(lin(-45.0, "force").A))
    assert not same_multiset(up, down, 1e-3)
    assert up.real.max() > 1.0  # +45 deg: a real unstable mode near 2.05 1/s
    assert down.real.max() < 1e-9  # -45 deg with r_p3 = 0.05 m: no unstable mode


# ------------------------------------------------------------------------------------------ modes


@pytest.mark.parametrize("deg", GAMMAS_DEG)
@pytest.mark.parametrize("inputs", ["force", "acceleration"])
def test_modes(deg, inputs):
    sys = lin(deg, inputs)
    A = np.asarray(sys.A)
    m = modes(sys)
    assert same_multiset(m.eigenvalues, np.linalg.eigvals(A), 1e-10)
    assert np.all(np.diff(m.eigenvalues.real) <= 1e-12)  # decreasing real part
    np.testing.assert_allclose(np.linalg.norm(m.eigenvectors, axis=0), 1.0, rtol=1e-12)
    np.testing.assert_allclose(A @ m.eigenvectors, m.eigenvectors * m.eigenvalues, atol=1e-8)
    np.testing.assert_allclose(m.wn, np.abs(m.eigenvalues), rtol=1e-14)
    nz = m.wn > 1e-9
    np.testing.assert_allclose(m.zeta[nz], -m.eigenvalues.real[nz] / m.wn[nz], rtol=1e-12)
    assert m.stable == bool(np.all(m.eigenvalues.real < 0))
    assert not m.stable  # z' and the integrators give zero eigenvalues
    assert set(m.dominant_states) <= set(sys.state_labels)


# ------------------------------------------------------------------------------------------ controllability


@pytest.mark.parametrize("deg", GAMMAS_DEG)
@pytest.mark.parametrize("inputs", ["force", "acceleration"])
def test_full_controllability(deg, inputs):
    r = controllability(lin(deg, inputs))
    assert r.full and r.rank == r.n == 10
    assert r.uncontrollable_modes.size == 0
    assert r.pbh_min.min() > 1e-3
    assert r.channels == tuple(lin(deg, inputs).input_labels)


@pytest.mark.parametrize("deg", GAMMAS_DEG)
@pytest.mark.parametrize("axis", [1, 3])
def test_controllability_with_moving_mass_on_one_axis(deg, axis):
    """Acceleration form, mass locked on the other axis (its r_P, rdot_P removed): still controllable."""
    sys = lin(deg, "acceleration")
    other = 3 if axis == 1 else 1
    states = [s for s in ACCEL_LABELS if s not in (f"r_P{other}", f"rdot_P{other}")]
    r = controllability(sys, inputs=[f"w{axis}", "w4"], states=states)
    assert r.n == 8
    assert r.full and r.rank == 8
    assert r.channels == (f"w{axis}", "w4")


@pytest.mark.parametrize("deg", GAMMAS_DEG)
def test_force_form_without_buoyancy_input(deg):
    """Finding: without u4 the force model loses exactly one direction, m0 (m0' = u4 is then frozen); every
    other state, including z', stays controllable from (u1, u3)."""
    sys = lin(deg, "force")
    r = controllability(sys, inputs=["u1", "u3"])
    assert not r.full
    assert r.rank == 9
    assert np.all(np.abs(r.uncontrollable_modes) < 1e-12)
    keep = [s for s in FORCE_LABELS if s != "m0"]
    r2 = controllability(sys, inputs=["u1", "u3"], states=keep)
    assert r2.full and r2.rank == 9
    # the left null vector of [B, AB, ...] is e_m0
    A, B = np.asarray(sys.A), np.asarray(sys.B)[:, :2]
    e = np.zeros(10)
    e[FORCE_LABELS.index("m0")] = 1.0
    assert np.all(e @ A == 0) and np.all(e @ B == 0)


@pytest.mark.parametrize("deg", GAMMAS_DEG)
def test_force_form_single_force_component_is_not_enough(deg):
    """In force form P_P3' = u3: dropping u3 freezes P_P3, so (u1, u4) cannot be a one-axis design there
    (hence the one-axis study is done in acceleration form)."""
    r = controllability(lin(deg, "force"), inputs=["u1", "u4"])
    assert not r.full and r.rank == 9


@pytest.mark.parametrize("deg", GAMMAS_DEG)
def test_acceleration_form_without_buoyancy_input(deg):
    r = controllability(lin(deg, "acceleration"), inputs=["w1", "w3"])
    assert r.rank == 9 and not r.full
    keep = [s for s in ACCEL_LABELS if s != "m0"]
    assert controllability(lin(deg, "acceleration"), inputs=["w1", "w3"], states=keep).full


def test_controllability_unknown_names():
    sys = lin(-45.0, "force")
    with pytest.raises(GlidectlError):
        controllability(sys, inputs=["u2"])
    with pytest.raises(GlidectlError):
        controllability(sys, states=["theta", "bogus"])
    with pytest.raises(GlidectlError):
        observability(sys, ["bogus"])


# ------------------------------------------------------------------------------------------ observability


def _sub(sys: control.StateSpace, drop: str) -> control.StateSpace:
    keep = [k for k, s in enumerate(sys.state_labels) if s != drop]
    A = np.asarray(sys.A)[np.ix_(keep, keep)]
    B = np.asarray(sys.B)[keep]
    names = [sys.state_labels[k] for k in keep]
    return control.ss(A, B, np.eye(len(keep)), 0, states=names, inputs=list(sys.input_labels), outputs=names)


@pytest.mark.parametrize("deg", GAMMAS_DEG)
@pytest.mark.parametrize("outputs", OUTPUT_SETS)
def test_observability_force_form(deg, outputs):
    """All states but z' observable from (r_P1, r_P3, m0), (theta, r_P1, m0) or (theta, r_P3, m0)."""
    sys = lin(deg, "force")
    r = observability(sys, list(outputs))
    assert r.rank == r.n - 1 == 9
    assert not r.full
    assert r.channels == outputs
    assert r.uncontrollable_modes.size >= 1
    assert np.all(np.abs(r.uncontrollable_modes) < 1e-12)  # the unobservable eigenvalue is 0
    # z' is the unobservable direction: A e_z' = 0, C e_z' = 0, and the rest is observable
    assert np.all(np.asarray(sys.A)[:, 0] == 0) and "z_prime" not in outputs
    assert observability(_sub(sys, "z_prime"), list(outputs)).full
    assert observability(sys, [*outputs, "z_prime"]).full


@pytest.mark.parametrize("deg", GAMMAS_DEG)
@pytest.mark.parametrize("outputs", OUTPUT_SETS[1:])
def test_observability_acceleration_form_with_pitch(deg, outputs):
    sys = lin(deg, "acceleration")
    r = observability(sys, list(outputs))
    assert r.rank == 9
    assert np.all(np.abs(r.uncontrollable_modes) < 1e-12)
    assert observability(_sub(sys, "z_prime"), list(outputs)).full
    assert observability(sys, [*outputs, "z_prime"]).full


@pytest.mark.parametrize("deg", GAMMAS_DEG)
def test_observability_acceleration_form_from_mass_states_only(deg):
    """Finding: in acceleration form (r_P1, r_P3, m0) sees only zeta. zeta' = A zeta + B w does not depend on
    eta (block-triangular (2.35)-(2.36)), so the observable subspace is zeta: rank 5, not n - 1. The thesis's
    claim for these outputs is about the force-form models of [6, 48] (true there, test above)."""
    sys = lin(deg, "acceleration")
    A = np.asarray(sys.A)
    i = {s: k for k, s in enumerate(ACCEL_LABELS)}
    zeta = [i[s] for s in ("r_P1", "rdot_P1", "r_P3", "rdot_P3", "m0")]
    eta = [i[s] for s in ("z_prime", "theta", "Omega2", "v1", "v3")]
    assert np.all(np.abs(A[np.ix_(zeta, eta)]) <= 1e-14)
    r = observability(sys, ["r_P1", "r_P3", "m0"])
    assert r.rank == 5
    # unobservable modes: those of the eta block (0 for z' and the four eigenvalues of dq_r/deta_r)
    eta_eigs = np.linalg.eigvals(A[np.ix_(eta, eta)])
    for lam in eta_eigs:
        assert np.min(np.abs(r.uncontrollable_modes - lam)) < 1e-9, lam
    assert np.any(np.abs(eta_eigs) > 0.1)  # so these are genuinely unobservable dynamic modes, not just z'


@pytest.mark.parametrize("what", ["inputs", "states", "outputs"])
def test_empty_selection_is_not_everything(what):
    """An empty channel/state selection must not silently mean 'all of them' (which reports full rank), nor
    fail deep inside python-control: either a GlidectlError or a rank-0 answer."""
    sys = lin(-45.0, "force")
    try:
        if what == "inputs":
            r = controllability(sys, inputs=[])
        elif what == "states":
            r = controllability(sys, states=[])
        else:
            r = observability(sys, [])
    except GlidectlError:
        return
    assert r.rank == 0
    if what != "states":  # with no inputs/outputs a 10-state system is neither controllable nor observable
        assert r.n == 10 and not r.full


# ------------------------------------------------------------------------------------------ argument checks (issue 15)


@pytest.mark.parametrize(("veh", "g", "exc"), [
    (ROGUE, None, "ArgumentTypeError"),          # issue 15: was an AttributeError
    (ROGUE, "glide", "ArgumentTypeError"),
    ("rogue", None, "ArgumentTypeError"),
    (load_vehicle("dc8_ctol"), None, "ModelError"),
])
def test_linearize_glide_bad_arguments(veh, g, exc):
    import glidectl as gc

    with pytest.raises(getattr(gc, exc)):
        linearize_glide(veh, glide(-45.0) if g is None and exc == "ModelError" else g)
    with pytest.raises(TypeError if exc == "ArgumentTypeError" else ValueError):  # builtin classes catch them too
        linearize_glide(veh, glide(-45.0) if g is None and exc == "ModelError" else g)


def test_linearize_glide_of_another_vehicle_is_a_mismatch():
    import glidectl as gc

    with pytest.raises(gc.VehicleMismatchError):
        linearize_glide(load_vehicle("rogue", K_M=-40.0), glide(-45.0))
    with pytest.raises(gc.ArgumentError):
        linearize_glide(ROGUE, glide(-45.0), inputs="torque")


def test_single_channel_name_is_not_split_into_characters():
    """observability(sys, "theta") used to report channels ('t', 'h', 'e', 't', 'a')."""
    sys = lin(-45.0, "force")
    r = observability(sys, "theta")
    assert r.channels == ("theta",)
    assert r.rank == observability(sys, ["theta"]).rank
    c = controllability(sys, inputs="u1")
    assert c.channels == ("u1",) and c.rank == controllability(sys, inputs=["u1"]).rank


@pytest.mark.parametrize("kw", [{"inputs": 3}, {"inputs": [b"u1"]}, {"states": [1, 2]}, {"pbh_tol": "1e-8"}])
def test_controllability_wrong_types(kw):
    import glidectl as gc

    with pytest.raises(gc.ArgumentTypeError):
        controllability(lin(-45.0, "force"), **kw)


@pytest.mark.parametrize("kw", [{"inputs": ["u1", "u1"]}, {"tol": -1.0}, {"tol": math.nan}, {"pbh_tol": 0.0}])
def test_controllability_bad_values(kw):
    import glidectl as gc

    with pytest.raises(gc.ArgumentError):
        controllability(lin(-45.0, "force"), **kw)


@pytest.mark.parametrize("bad", [None, "sys", np.eye(3)])
def test_modes_and_ranks_need_a_state_space(bad):
    import glidectl as gc

    for fn in (modes, controllability, lambda s: observability(s, ["theta"])):
        with pytest.raises(gc.ArgumentTypeError):
            fn(bad)


def test_non_finite_model_is_refused():
    import glidectl as gc

    sys = control.ss(np.array([[np.nan]]), np.array([[1.0]]), np.eye(1), 0)
    with pytest.raises(gc.ArgumentError):
        modes(sys)
    with pytest.raises(gc.ArgumentError):
        controllability(sys)
    zero = controllability(control.ss(np.zeros((2, 2)), np.zeros((2, 1)), np.eye(2), 0))
    assert not zero.full and np.all(np.isfinite(zero.pbh_min))  # A = B = 0: no NaN margins


def test_jacobians_refuse_functions_that_are_not_complex_safe():
    import glidectl as gc

    with pytest.raises(gc.ModelError, match="complex-safe"):
        gc.jacobians(lambda x, u: np.real(x * x), [1.0, 2.0], [])  # would give a zero derivative
    with pytest.raises(gc.ModelError):
        gc.jacobians(lambda x, u: x + np.nan, [1.0], [])  # not finite at x
    with pytest.raises(gc.ArgumentError):
        gc.jacobians(lambda x, u: x, [np.nan], [0.0])
    with pytest.raises(gc.ArgumentTypeError):
        gc.jacobians(42, [0.0], [0.0])
    with pytest.raises(gc.ArgumentError):
        gc.hessian(lambda x: (x**2).sum(-1), [1.0, 2.0], h=0.0)
    A, B = gc.jacobians(lambda x, u: x * x + u, [1.0, 2.0], [0.0, 0.0])
    np.testing.assert_array_equal(A, np.diag([2.0, 4.0]))
    np.testing.assert_array_equal(B, np.eye(2))


# ------------------------------------------------------------------------------------------ modes and failing modes in
# state terms
def _ss(A, names, C=None, outputs=None):
    A = np.asarray(A, dtype=float)
    C = np.eye(A.shape[0]) if C is None else np.atleast_2d(C)
    return control.ss(A, np.zeros((A.shape[0], 1)), C, 0, states=list(names),
                      outputs=list(outputs or [f"y{i}" for i in range(C.shape[0])]))


def test_observability_names_a_known_unobservable_mode_in_state_terms():
    # x_c decouples from the output a (a' = -a + b, b' = -2 b, c' = -3 c): the mode at -3 is c alone
    A = np.diag([-1.0, -2.0, -3.0])
    A[0, 1] = 1.0
    r = observability(_ss(A, "abc"), ["a"])
    assert not r.full and len(r.mode_states) == 1
    m = r.mode_states[0]
    assert m.eigenvalue == pytest.approx(-3.0) and m.states == ("c",) and m.dimension == 1
    assert "-3+0i (c 100%)" in str(r)
    # an unobservable mode spread over two states: eigenvector (0, 1, 1) at -2, output y = a + b - c
    V = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 1.0]])
    A = V @ np.diag([-1.0, -2.0, -3.0]) @ np.linalg.inv(V)
    r = observability(_ss(A, "abc", C=[1.0, 1.0, -1.0], outputs=["y"]), "y")
    (m,) = r.mode_states
    assert m.eigenvalue == pytest.approx(-2.0) and set(m.states) == {"b", "c"}
    np.testing.assert_allclose(m.shares, [0.5, 0.5], atol=1e-9)
    # restricting the states to those the output sees makes the test pass
    assert observability(_ss(A, "abc", C=[1.0, 1.0, -1.0], outputs=["y"]), "y", states=["a"]).full
    # the dual: with a single input into a, the controllability failure is named alike
    B = np.array([[1.0], [0.0], [0.0]])
    cr = controllability(control.ss(np.diag([-1.0, -2.0]), B[:2], np.eye(2), 0, states=["a", "b"]))
    assert [ms.states for ms in cr.mode_states] == [("b",)]
    assert observability(lin(-45.0, "force"), ["z_prime", "theta", "m0", "r_P1", "r_P3"]).mode_states == ()


def test_mode_participation_is_unit_free_and_labels_say_which_states():
    sys = lin(-45.0, "acceleration")
    m = modes(sys)
    np.testing.assert_allclose(m.participation.sum(axis=0), 1.0, rtol=1e-12)
    # express z_prime in km and theta in mrad: the participation (and the labels) do not change
    T = np.diag([1e-3, 1e3, 1, 1, 1, 1, 1, 1, 1, 1])
    scaled = control.ss(T @ sys.A @ np.linalg.inv(T), T @ sys.B, np.eye(10), 0, states=sys.state_labels)
    ms = modes(scaled)
    np.testing.assert_allclose(ms.participation, m.participation, atol=1e-8)
    assert ms.labels == m.labels and ms.dominant_states == m.dominant_states
    assert len(set(m.labels)) == len(m.labels)
    # ROGUE's pitch oscillation (-0.81 +- 4.37i /s) is a pitch-rate and pitch mode; the six integrators at 0 (z',
    # the two mass axes and the pump) share their eigenvalue, and the label lists all six states
    osc = [k for k in range(10) if m.eigenvalues[k].imag != 0]
    assert [m.labels[k][-9:] for k in osc] == ["(pair +i)", "(pair -i)"]
    assert all(m.dominant_states[k] == "Omega2" and "theta" in m.labels[k] for k in osc)
    zero = [lab for lab in m.labels if lab.endswith("of 6 at 0+0i)")]
    assert len(zero) == 6 and all(q in zero[0] for q in ("z_prime", "r_P1", "rdot_P1", "r_P3", "rdot_P3", "m0"))


def test_identical_state_content_gets_distinct_labels():
    # two distinct modes made of the same two states in the same proportions carry their eigenvalue
    V = np.array([[1.0, 1.0, 0.0], [0.3, -0.3, 0.0], [0.0, 0.0, 1.0]])
    m = modes(_ss(V @ np.diag([-1.0, -2.0, -3.0]) @ np.linalg.inv(V), "abc"))
    assert m.labels[0] != m.labels[1] and "[-1+0i/s]" in m.labels[0] and "[-2+0i/s]" in m.labels[1]
    # a complex pair is marked as the pair's two members; a repeated (defective) eigenvalue as k of m
    m = modes(_ss([[-0.1, 2.0, 0.0], [-2.0, -0.1, 0.0], [0.0, 0.0, -1.0]], ["th", "om", "q"]))
    assert m.labels[:2] == ("th 50% + om 50% (pair +i)", "th 50% + om 50% (pair -i)")
    m = modes(_ss([[0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, -1.0]], ["p", "v", "q"]))
    assert m.labels[:2] == ("p 50% + v 50% (1 of 2 at 0+0i)", "p 50% + v 50% (2 of 2 at 0+0i)")
    assert len(set(m.labels)) == 3


@pytest.mark.parametrize("inputs", ["force", "acceleration"])
@pytest.mark.parametrize("reduce_fixed", [True, False])
def test_labels_of_slocum_shallow_longitudinal_modes_are_distinct(inputs, reduce_fixed):
    veh = load_vehicle("slocum_shallow")
    g = steady_glide(veh, 0.35, math.radians(-25.0), r_p3=0.05)
    m = modes(linearize_glide(veh, g, inputs, reduce_fixed=reduce_fixed))
    assert len(set(m.labels)) == len(m.labels) == len(m.eigenvalues)
    text = str(m)
    assert all(lab in text for lab in m.labels)
