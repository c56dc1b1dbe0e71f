"""Robust region-of-attraction certificates (gc.certify_roa_family): one ellipsoid shape about the moving equilibrium
for every uncertain coefficient in the box; checked by simulation and sampled dV/dt at the corners and at vehicles
drawn in the box, reduced to the nominal certificate for a vanishing box, bad inputs refused; and the nominal LMI
certificate unchanged by the refactoring of glidectl.roa.lmi that the robust driver shares."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import glidectl as gc

#: a short search (the tests check soundness and structure, not the largest set)
SMALL = dict(rounds=2, n_radii=4, refine=2, n_hessian=128)
KEYS = ("K_D0", "K_L", "K_M")


def _member(loop, sl, **kw):
    """The loop of the nominal controller on another vehicle, at its own equilibrium (the recipe of the docstring)."""
    def member(v):
        lv = gc.with_vehicle(loop, v)
        xe = gc.loop_poles(lv, loop.equilibrium, sl.free).equilibrium
        return gc.saturated_loop(gc.ClosedLoop(lv.plant, lv.law, xe, lv.description), **kw)

    return member


def _slocum_loop(rel):
    veh = gc.load_vehicle("slocum_shallow").with_uncertainty({k: {"rel": rel} for k in KEYS})
    glide = gc.steady_glide(veh, 0.35, -0.436, r_p3=0.05)
    loop = gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration"))
    return veh, loop, gc.saturated_loop(loop)          # actuator_limits=True (the default): 6 affine limits


def _buoyancy_loop(rel, keys=KEYS):
    veh = gc.load_vehicle("sphere_ch5").with_uncertainty({k: {"rel": rel} for k in keys})
    loop = gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0))
    return veh, loop, gc.saturated_loop(loop)


@pytest.fixture(scope="module")
def slocum():
    """The slocum_shallow LQR loop with the actuators' limits, +-10 % on K_D0, K_L, K_M, a short search."""
    veh, loop, sl = _slocum_loop(0.1)
    cert = gc.certify_roa_family(sl, _member(loop, sl), n_samples=4, n_verify=200, n_simulate=2, **SMALL)
    return veh, loop, sl, cert


# --------------------------------------------------------------------------------------------- soundness
def test_robust_certificate_is_a_family_about_the_moving_equilibria(slocum):
    veh, _, sl, cert = slocum
    assert len(sl.limits) == 6                                   # the actuators' range and rate limits are certified
    assert cert.certified, cert.verification.summary()
    assert not cert.rigorous and cert.method == "lmi-robust"
    assert cert.verification.kinds.count("vertex") == 8 and cert.verification.n_converged == 8 * 2 + 5 * 2
    f = list(sl.free)
    # the equilibrium moves with the coefficients, much farther than the certified half-widths along some axis
    shift = np.max(np.abs(cert.vertex_equilibria[:, f] - sl.equilibrium[f]), axis=0)
    half = 1.0 / np.sqrt(np.diag(cert.P))
    assert np.max(shift / half) > 1.0
    # a member is the common shape about its own equilibrium, inside the loop's box
    v0 = veh.vertices()[0]
    m = cert.at(v0, n_verify=2, n_simulate=0)
    np.testing.assert_allclose(m.P, cert.P, rtol=1e-12)
    np.testing.assert_allclose(m.system.equilibrium, cert.vertex_equilibria[0], rtol=0, atol=1e-12)
    lo, hi = sl.box
    X = m.sample(200, seed=3, boundary=True)
    assert np.all((X >= lo) & (X <= hi))
    # the protocol's set is the nominal member; its extent is comparable with the nominal certificate's
    ext = cert.extent()
    np.testing.assert_allclose(ext.above[f], half, rtol=1e-12)
    assert ext.rigorous is False and "lmi-robust" in ext.what
    assert np.all(cert.contains(cert.sample(50, seed=1))) and cert.volume() > 0


def test_simulations_from_the_members_boundaries_converge_at_corners_and_sampled_vehicles(slocum):
    _, _, _, cert = slocum
    ver = cert.verify_by_simulation(n_vehicles=2, n_points=3, seed=5)
    assert ver.kinds.count("vertex") == 8 and ver.kinds.count("sample") + ver.n_invalid == 2
    assert ver.n_simulated == 3 * len(ver.members) >= 3 * 8
    assert ver.n_converged == ver.n_simulated
    assert ver.passed, ver.summary()


def test_sampled_dVdt_is_negative_inside_members_at_corners_and_sampled_vehicles(slocum):
    veh, _, _, cert = slocum
    vehicles = list(veh.vertices()) + list(veh.sample(3, seed=11))        # 'rel' intervals: uniform in the box
    assert len(vehicles) == 11
    for i, v in enumerate(vehicles):
        m = cert.at(v, n_verify=2, n_simulate=0)
        sl = m.system                                           # the vehicle's own saturated loop
        f = list(sl.free)
        X = np.concatenate([m.sample(300, seed=i), m.sample(300, seed=100 + i, boundary=True)])
        dX = (X - sl.equilibrium)[:, f]
        Vdot = 2.0 * np.einsum("ni,ij,nj->n", dX, cert.P, np.asarray(sl.rhs(X))[:, f])
        assert np.max(Vdot / np.sum((dX / cert.scale) ** 2, axis=1)) < 0, v.overrides
        np.testing.assert_allclose(sl.rhs(sl.equilibrium[None, :])[0, f], 0.0, atol=1e-9)


def test_at_refuses_a_vehicle_outside_the_box_or_with_other_coefficients(slocum):
    veh, _, _, cert = slocum
    hi = cert.coefficient_box[1]
    with pytest.raises(gc.ArgumentError, match="outside the certified box"):
        cert.at(veh.with_overrides(K_D0=1.2 * hi[cert.keys.index("K_D0")]))
    with pytest.raises(gc.ArgumentError, match="not uncertain coefficients"):
        cert.at(veh.with_overrides(K_D=1.1 * veh.params["K_D"]))
    with pytest.raises(gc.ArgumentTypeError, match="Vehicle"):
        cert.at("slocum_shallow")


def test_summary_and_plot(slocum):
    cert = slocum[3]
    text = cert.summary()
    assert "sampled-sound" in text and all(k in text for k in KEYS) and "8 corners" in text
    ax = cert.plot(dims=("theta", "v1"), vertices=3)
    assert ax.get_xlabel().endswith("[deg]") and ax.get_ylabel().endswith("[m/s]")
    assert len(ax.lines) >= 3 + 3                               # the corner members, nominal, corner equilibria
    with pytest.raises(gc.GlidectlError, match="free states"):
        cert.plot(dims=("theta", "theta"))


# --------------------------------------------------------------------------------------------- the chapter-6 loop
def test_buoyancy_loop_robust_extent_against_the_nominal_and_a_box_too_wide():
    _, loop, sl = _buoyancy_loop(0.1)
    cert = gc.certify_roa_family(sl, _member(loop, sl), n_samples=4, n_verify=200, n_simulate=2, **SMALL)
    nom = gc.certify_roa_lmi(sl, n_verify=200, n_simulate=2, **SMALL)
    assert cert.certified and nom.certified
    r = cert.extent_ratio(nom)[list(sl.free)]
    assert np.all((r > 0.2) & (r < 1.5)), r
    assert np.isnan(cert.extent_ratio(nom)).sum() == len(sl.held)
    # +-30 %: the pitch-rate row is too far from its interpolation (sampled at 16 points) for one shape at every
    # corner
    _, loop, sl = _buoyancy_loop(0.3)
    with pytest.raises(gc.SolverError, match=r"too wide.*smaller box"):
        gc.certify_roa_family(sl, _member(loop, sl), n_samples=16, n_verify=200, n_simulate=2, **SMALL)


def test_a_vanishing_box_gives_the_nominal_certificate():
    # +-1e-6: the corners' [A B] agree to 5e-6 of its largest entry and share one LMI, so the program is the nominal
    # one (its objectives equal the nominal search's, the shape to the solver's accuracy)
    _, loop, sl = _buoyancy_loop(1e-6)
    cert = gc.certify_roa_family(sl, _member(loop, sl), n_samples=2, n_verify=200, n_simulate=2, **SMALL)
    nom = gc.certify_roa_lmi(sl, n_verify=200, n_simulate=2, **SMALL)
    obj = [h["objective"] for h in cert.history]
    np.testing.assert_allclose(obj, [h["objective"] for h in nom.history], rtol=1e-4)
    r = cert.extent_ratio(nom)[list(sl.free)]
    np.testing.assert_allclose(r, 1.0, rtol=2e-3)
    np.testing.assert_allclose(cert.P, nom.P, rtol=5e-3, atol=5e-3 * np.max(np.abs(nom.P)))


# --------------------------------------------------------------------------------------------- a toy family
SPHERE = gc.load_vehicle("sphere_ch5")


def _toy_member(gain=1.0, form_change=False):
    """x1' = x2, x2' = a x1 + w, w = sat(-3 x1 - 2 x2) at +-2 and w <= 0.5 - x1, with a = 1 + gain (K_D0 / K_D0_nom -
    1): linear and saturated (no remainder), its equilibrium at 0 for every coefficient."""
    k0 = SPHERE.params["K_D0"]

    def member(v):
        a = 1.0 + gain * (v.params["K_D0"] / k0 - 1.0)
        K = np.array([[-3.0, -2.0]]) if not (form_change and v.params["K_D0"] != k0) else np.array([[-3.0, -2.5]])
        return gc.SaturatedLoop("toy", ("x1", "x2"), ("w",),
                                lambda X, W: np.stack([X[..., 1], a * X[..., 0] + W[..., 0]], axis=-1),
                                np.zeros(2), K, np.array([-2.0]), np.array([2.0]), (-np.ones(2), np.ones(2)),
                                limits=(gc.AffineLimit(0, True, np.array([-1.0, 0.0]), 0.5, "taper"),), vehicle=v)

    return member


def test_toy_family_with_a_vanishing_box_is_the_nominal_program():
    veh = SPHERE.with_uncertainty({"K_D0": {"rel": 1e-12}, "K_L": {"rel": 1e-12}})
    member = _toy_member()
    sl = member(veh)
    cert = gc.certify_roa_family(sl, member, n_samples=2, n_verify=200, n_simulate=2)
    nom = gc.certify_roa_lmi(sl, n_verify=200, n_simulate=2)
    assert cert.certified and len(cert.history) == len(nom.history) == 1     # no remainder: one SDP
    # the same program up to a 2e-12 change of one entry: the optimum (log sqrt det W) agrees to 1e-10; the
    # optimizer of the flat log det moves by 1e-5 (as the nominal certificate's own does for that change of data)
    assert cert.history[0]["objective"] == pytest.approx(nom.history[0]["objective"], abs=1e-9)
    np.testing.assert_allclose(cert.P, nom.P, rtol=1e-4)
    wide = gc.certify_roa_family(sl, _toy_member(), SPHERE.with_uncertainty({"K_D0": {"rel": 0.2}}), n_samples=2,
                                 n_verify=200, n_simulate=2)
    assert wide.certified and wide.volume() < 0.999 * nom.volume()           # with a = 1 -+ 0.2: a smaller set


def test_bad_inputs_are_refused_with_clear_errors():
    member = _toy_member(gain=10.0)
    sl = member(SPHERE)
    with pytest.raises(gc.ArgumentError, match=r"no \[uncertainty\] table"):
        gc.certify_roa_family(sl, member)
    with pytest.raises(gc.ArgumentError, match="no vehicle"):
        gc.certify_roa_family(dataclasses.replace(sl, vehicle=None), member)
    # a = 1 + 10 (K_D0 / K_D0_nom - 1) reaches 3.5 at the upper corner: A + BK is unstable there
    with pytest.raises(gc.ModelError, match=r"corner .* not exponentially stable.*too wide.*smaller box"):
        gc.certify_roa_family(sl, member, SPHERE.with_uncertainty({"K_D0": {"rel": 0.25}}))
    with pytest.raises(gc.ArgumentError, match="another form"):
        gc.certify_roa_family(sl, _toy_member(form_change=True), SPHERE.with_uncertainty({"K_D0": {"rel": 0.1}}))
    many = SPHERE.with_uncertainty({k: {"rel": 0.01} for k in ("K_D0", "K_L", "K_M")})
    with pytest.raises(gc.ArgumentError, match="max_vertices"):
        gc.certify_roa_family(sl, member, many, max_vertices=4)
    with pytest.raises(gc.ArgumentError, match="coefficients of the loop's vehicle"):
        gc.certify_roa_family(sl, member, gc.load_vehicle("slocum_shallow").with_uncertainty({"K_D0": {"rel": 0.1}}))
    with pytest.raises(gc.ArgumentTypeError, match="member"):
        gc.certify_roa_family(sl, "member", SPHERE.with_uncertainty({"K_D0": {"rel": 0.1}}))


def test_an_output_feedback_loop_is_refused():
    rogue = gc.load_vehicle("rogue").with_uncertainty({"K_D0": {"rel": 0.1}})
    glide = gc.steady_glide(rogue, 0.3, math.radians(-45), r_p3=0.05)
    lqg = gc.lqg_glide(rogue, glide, ("z", "theta", "Omega2"), {"z": 0.1, "theta": 0.01, "Omega2": 0.01},
                       inputs="acceleration", actuate=("w1", "w4"))
    loop = gc.closed_loop(lqg)
    with pytest.raises(gc.ArgumentTypeError, match="state-feedback"):
        gc.certify_roa_family(loop, lambda v: None, rogue)
    with pytest.raises(gc.ArgumentTypeError, match="does not know the law"):          # nor can a member be built
        gc.saturated_loop(loop)


# --------------------------------------------------------------------------------------------- the nominal path
def test_nominal_lmi_certificates_are_unchanged_by_the_shared_search():
    # recorded from gc.certify_roa_lmi before its search, scaling and back-off were factored out for the robust
    # driver (the same numbers to the last bit there; 1e-7 leaves room for another machine's rounding)
    sph = gc.load_vehicle("sphere_ch5")
    sl = gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0)))
    cert = gc.certify_roa_lmi(sl, rounds=1, n_radii=4, refine=1, n_hessian=128, n_verify=500, n_simulate=4)
    P = [[224279.50818217816, -65613.34520473928, 208137.29358997807, -1808.280194128121, 85665.96240012356],
         [-65613.34520473928, 108055.91694001136, -218365.61750170958, 1879.4333194457447, -65678.49514786655],
         [208137.29358997807, -218365.61750170958, 75863791.60700308, 615593.7026636415, -139311.66249574738],
         [-1808.280194128121, 1879.4333194457447, 615593.7026636415, 44410.91446367606, 1535.6455409497544],
         [85665.96240012356, -65678.49514786655, -139311.66249574738, 1535.6455409497544, 72493.49949844158]]
    np.testing.assert_allclose(cert.P, P, rtol=1e-7, atol=1e-7 * 7.6e7)
    np.testing.assert_allclose(cert.extent().above, [0.0021115686352324303, 0.003042115672310164,
                                                     0.0001148107959290448, 0.004745206778260784,
                                                     0.003714073273060392], rtol=1e-7)
    np.testing.assert_allclose(cert.G, [[0.001304674037782214, -0.0010003760595025373, -0.0019036704705363877,
                                         2.776054547190881e-05, 0.0011031163947177675]], rtol=1e-6, atol=1e-12)
    toy = _toy_member()(SPHERE)
    cert = gc.certify_roa_lmi(toy)
    np.testing.assert_allclose(cert.P, [[1.1363581460558665, 0.40702551787924124],
                                        [0.40702551787924124, 1.3121616549179216]], rtol=1e-7)
    np.testing.assert_allclose(cert.G, [[-1.5669916344875583, -1.5346959368402269]], rtol=1e-7)


# --------------------------------------------------------------------------------------------- from a controller
def test_certify_roa_robust_takes_the_controller_and_builds_the_family():
    veh, loop, sl = _buoyancy_loop(0.05)
    ctrl = gc.BuoyancyController(gc.buoyancy_equilibrium(veh, 1.5), veh, 5.0)
    opts = dict(n_samples=2, n_verify=100, n_simulate=1, **SMALL)
    cert = gc.certify_roa_robust(ctrl, **opts)
    same = gc.certify_roa_family(sl, _member(loop, sl), **opts)
    np.testing.assert_array_equal(cert.P, same.P)                # the same members, the same programs
    assert cert.certified and cert.keys == same.keys
    # a member is the nominal law on the vehicle's plant at its own equilibrium: the loop's residual vanishes there
    v = veh.vertices()[3]
    m = gc.robustness.ControllerMember(loop, tuple(sl.free))(v)
    assert np.max(np.abs(np.asarray(m.rhs(m.equilibrium)))) < 1e-9
    assert not np.allclose(m.equilibrium, sl.equilibrium)
    with pytest.raises(gc.ArgumentError, match="uncertainty"):
        gc.certify_roa_robust(gc.BuoyancyController(gc.buoyancy_equilibrium(SPHERE, 1.5), SPHERE, 5.0), **opts)
    slocum = gc.load_vehicle("slocum_shallow").with_uncertainty({"K_M": {"rel": 0.1}})
    glide = gc.steady_glide(slocum, 0.35, -0.436, r_p3=0.05)
    with pytest.raises(gc.ArgumentTypeError, match="state-feedback"):
        gc.certify_roa_robust(gc.lqg_glide(slocum, glide, ("z", "theta", "Omega2"), {"z": 0.1, "theta": 0.01,
                                                                                  "Omega2": 0.01}))
