"""One damping convention (issue 16, part 2): every model reads rotational damping through
:func:`glidectl.hydro.damping_moment`; a file giving the linear damping twice is refused; the reduced analyses of
chapters 4-5 refuse a vehicle that breaks their assumptions instead of dropping a term."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.controllers.torque import TorqueLaw
from glidectl.derivatives import jacobians
from glidectl.errors import ArgumentError, ArgumentTypeError, ModelError, VehicleFileError
from glidectl.hydro import DAMPING_KEYS, damping_moment, loads_3d, loads_at
from glidectl.models.glider3d import FixedMassGlider3D, Glider3D, ypr_to_quat
from glidectl.models.longitudinal import FORCE_STATES
from glidectl.models.reduced import ReducedLongitudinalGlider

SLOCUM = gc.load_vehicle("slocum_ch8")  # pitch damping K_Omega1_2 = -60 (no V^2), K_q = 0
SLOCUM_KQ = gc.load_vehicle("slocum_ch8", K_Omega1_2=0.0, K_q=-3.0)  # pitch damping in the V^2 form of (2.13)
SLOCUM_QUAD = gc.load_vehicle("slocum_ch8", K_Omega2_1=-4.0, K_Omega2_2=-7.0, K_Omega2_3=-5.0)  # + quadratic terms
SPHERE = gc.load_vehicle("sphere_ch5")
GAMMA, SPEED, R_P3 = math.radians(-25.0), 0.35, 0.04  # the glide of the issue

FAST = settings(max_examples=30, deadline=None)


def _nonzero(lam: np.ndarray, tol: float = 1e-6) -> np.ndarray:
    lam = lam[np.abs(lam) > tol]
    return lam[np.lexsort((lam.imag, lam.real))]


def _contained(sub: np.ndarray, full: np.ndarray) -> float:
    """Largest relative distance from an eigenvalue of ``sub`` to the nearest one of ``full``."""
    return max(float(np.min(np.abs(full - lam)) / abs(lam)) for lam in sub)


def _embed(xl: np.ndarray) -> np.ndarray:
    """Longitudinal force state (11) -> Glider3D state (20) in the plane (roll = yaw = 0, out-of-plane parts 0)."""
    L = dict(zip(FORCE_STATES, xl, strict=True))
    return np.r_[L["x"], 0.0, L["z"], ypr_to_quat(0.0, L["theta"], 0.0), L["v1"], 0.0, L["v3"], 0.0, L["Omega2"],
                 0.0, L["r_P1"], 0.0, L["r_P3"], L["P_P1"], 0.0, L["P_P3"], L["m0"]]


# ------------------------------------------------------------------------------------------ the damping function

@FAST
@given(st.floats(0.0, 2.0), st.tuples(*[st.floats(-1.0, 1.0)] * 3))
def test_damping_moment_formula_and_sign(V2, Om):
    """M_i = K_qi Omega_i V^2 + K_Omega1_i Omega_i + K_Omega2_i Omega_i |Omega_i|, opposing the rotation."""
    veh = gc.load_vehicle("slocum_ch8", K_q=-3.0, K_Omega1_2=0.0, K_q1=-1.0, K_Omega1_1=0.0,
                          K_Omega2_1=-4.0, K_Omega2_2=-7.0, K_Omega2_3=-5.0)
    p = veh.params
    for axis, Oi in zip((1, 2, 3), Om, strict=True):
        kq, k1, k2 = DAMPING_KEYS[axis]
        want = p.get(kq, 0.0) * Oi * V2 + p[k1] * Oi + p[k2] * Oi * abs(Oi)
        got = damping_moment(veh, V2, Oi, axis)
        assert got == pytest.approx(want, rel=1e-14, abs=1e-15)
        assert got * Oi <= 0.0  # every coefficient is <= 0: the moment never feeds the rotation


def test_damping_moment_complex_step_derivative():
    """Analytic in a complex step: d/dOmega = K_q V^2 + K_Omega1 + 2 K_Omega2 |Omega| (also at Omega = 0, < 0)."""
    h = 1e-30
    for Om in (-0.3, 0.0, 0.2):
        d = damping_moment(SLOCUM_QUAD, 0.25, Om + 1j * h, 2).imag / h
        assert d == pytest.approx(-60.0 + 2 * -7.0 * abs(Om), rel=1e-14)
        d = damping_moment(SLOCUM_KQ, 0.25, Om + 1j * h, 2).imag / h
        assert d == pytest.approx(-3.0 * 0.25, rel=1e-14)


def test_damping_moment_bad_arguments():
    with pytest.raises(ArgumentError, match="axis must be 1"):
        damping_moment(SLOCUM, 0.1, 0.1, 4)
    with pytest.raises(ArgumentTypeError, match="axis"):
        damping_moment(SLOCUM, 0.1, 0.1, "2")
    with pytest.raises(ArgumentTypeError, match="Omega"):
        damping_moment(SLOCUM, 0.1, "0.1", 2)
    with pytest.raises(ModelError, match="not an underwater glider"):
        damping_moment(gc.load_vehicle("dc8_ctol"), 0.1, 0.1, 2)


@FAST
@given(st.tuples(st.floats(0.05, 1.5), st.floats(-0.3, 0.3), st.floats(-0.5, 0.5)),
       st.tuples(*[st.floats(-0.5, 0.5)] * 3))
def test_2d_and_3d_loads_read_the_same_damping(v, Om):
    """loads_at (every 2-D model) and loads_3d (every 3-D model) take their damping from damping_moment."""
    v, Om = np.array(v), np.array(Om)
    for veh in (SLOCUM, SLOCUM_KQ, SLOCUM_QUAD):
        _, T, alpha, _, _ = loads_3d(veh, v, Om)
        V2 = float(v @ v)
        for i, axis in enumerate((1, 2, 3)):
            rest = T[i] - damping_moment(veh, V2, Om[i], axis)
            at_rest = loads_3d(veh, v, np.zeros(3))[1][i]
            assert rest == pytest.approx(at_rest, rel=1e-12, abs=1e-13)
        _, _, M = loads_at(veh, V2, alpha, Om[1])
        assert M == pytest.approx(T[1], rel=1e-13, abs=1e-14)
        assert M == pytest.approx((veh.K_M0 + veh.K_M * alpha) * V2 + damping_moment(veh, V2, Om[1], 2), rel=1e-13,
                                  abs=1e-14)


# ------------------------------------------------------------------------------------------ 2-D and 3-D agree

@pytest.mark.parametrize("veh", [SLOCUM, SLOCUM_KQ, SLOCUM_QUAD], ids=["ch8_K_Omega1", "K_q_form", "quadratic"])
def test_2d_and_3d_glide_eigenvalues_agree(veh):
    """The straight -25 deg glide of a 3-D file: every nonzero eigenvalue of the 2-D linearization (public
    ``linearize_glide``) is one of the full 3-D model's, to 1e-10 relative: with the moving mass free (force form,
    Glider3D, 20 states) and held fixed (acceleration form, FixedMassGlider3D, 13 states). The 3-D spectrum also has
    the lateral modes, which the plane does not see."""
    g = gc.steady_glide(veh, SPEED, GAMMA, r_p3=R_P3)
    l2 = _nonzero(np.linalg.eigvals(gc.linearize_glide(veh, g).A))
    A3, _ = jacobians(Glider3D(veh).rhs, _embed(g.force_state()), np.zeros(4))
    l3 = _nonzero(np.linalg.eigvals(A3))
    assert len(l2) == 5 and len(l3) > len(l2)
    assert _contained(l2, l3) < 1e-10
    # battery held: acceleration form with w = 0 against the fixed-mass 3-D model
    la = _nonzero(np.linalg.eigvals(gc.linearize_glide(veh, g, inputs="acceleration").A))
    fm = FixedMassGlider3D(veh, (g.r_p1, 0.0, g.r_p3), g.m0)
    x3 = np.r_[0.0, 0.0, 0.0, ypr_to_quat(0.0, g.theta, 0.0), g.v1, 0.0, g.v3, 0.0, 0.0, 0.0]
    assert np.max(np.abs(fm.rhs(x3)[3:])) < 1e-12  # the 2-D trim is a 3-D equilibrium
    Af, _ = jacobians(lambda x, u: fm.rhs(x), x3, np.zeros(0))
    lf = _nonzero(np.linalg.eigvals(Af))
    assert len(la) == 4 and len(lf) > len(la)
    assert _contained(la, lf) < 1e-10


def test_slocum_2d_glide_has_its_pitch_damping():
    """The issue: the 2-D model read only K_q, so slocum_ch8 had no pitch damping in 2-D. Now the Jacobian differs
    from the undamped one (K_Omega1_2 = 0, the old behaviour) in exactly one entry, dOmega2'/dOmega2, by
    K_Omega1_2 / J2 = -5 1/s; the trim (Omega2 = 0) is unchanged. With the battery held (acceleration form) the
    damped glide is stable and the undamped one is not; with the battery free (force form, u = 0) the unstable
    pair shrinks from 0.3965 +- 0.722i to 0.0246 +- 0.2565i (the free battery slides: no restoring force)."""
    undamped = gc.load_vehicle("slocum_ch8", K_Omega1_2=0.0)
    g, g0 = (gc.steady_glide(v, SPEED, GAMMA, r_p3=R_P3) for v in (SLOCUM, undamped))
    np.testing.assert_array_equal(g.force_state(), g0.force_state())
    i = 2  # Omega2 in the glide-path state (z_prime, theta, Omega2, ...)
    for inputs in ("force", "acceleration"):
        A, A0 = (gc.linearize_glide(v, gl, inputs=inputs).A for v, gl in ((SLOCUM, g), (undamped, g0)))
        dA = A - A0
        if inputs == "force":  # the damping enters Omega2' = (... + M_DL2)/J2 only
            assert dA[i, i] == pytest.approx(SLOCUM.K_Omega1_2 / SLOCUM.J2, rel=1e-9)
            dA[i, i] = 0.0
        else:  # holding the battery couples the moment into v1', v3' through the mass forces (2.33)
            assert dA[i, i] < 0.9 * SLOCUM.K_Omega1_2 / SLOCUM.J2
            dA[:, i] = 0.0
        assert np.max(np.abs(dA)) <= 1e-9 * np.max(np.abs(A))
    la, la0 = (_nonzero(np.linalg.eigvals(gc.linearize_glide(v, gl, inputs="acceleration").A))
               for v, gl in ((SLOCUM, g), (undamped, g0)))
    assert np.max(la.real) < 0 < np.max(la0.real)
    lf, lf0 = (_nonzero(np.linalg.eigvals(gc.linearize_glide(v, gl).A)) for v, gl in ((SLOCUM, g), (undamped, g0)))
    assert np.max(lf.real) < 0.1 * np.max(lf0.real)


# ------------------------------------------------------------------------------------------ refused twice

@pytest.mark.parametrize("kq, k1", [("K_q1", "K_Omega1_1"), ("K_q", "K_Omega1_2"), ("K_q3", "K_Omega1_3")])
def test_damping_given_twice_is_refused(kq, k1):
    """Nonzero V^2-scaled and chapter-8 linear damping about the same axis: refused at load, naming both keys."""
    with pytest.raises(VehicleFileError, match=rf"{kq} = -2 .* {k1} = -5"):
        gc.load_vehicle("slocum_ch8", **{kq: -2.0, k1: -5.0})
    with pytest.raises(VehicleFileError, match=rf"{kq}.*{k1}"):
        gc.load_vehicle("sphere_ch5", **{kq: -2.0, k1: -5.0})
    with pytest.raises(VehicleFileError, match=rf"{kq}.*{k1}"):
        gc.load_vehicle("slocum_ch8", **{k1: 0.0}).with_overrides(**{kq: -2.0, k1: -5.0})
    # one form zero is fine, either way round, and the quadratic term is a different term
    assert gc.load_vehicle("slocum_ch8", **{kq: -2.0, k1: 0.0}).params[kq] == -2.0
    assert gc.load_vehicle("slocum_ch8", **{kq: 0.0, k1: -5.0}).params[k1] == -5.0
    assert gc.load_vehicle("slocum_ch8", **{kq: -2.0, k1: 0.0, "K_Omega2_" + k1[-1]: -1.0}).params[kq] == -2.0


def test_damping_given_twice_in_a_file_is_refused(tmp_path):
    text = (Path(gc.__file__).parent / "vehicles" / "slocum_ch8.toml").read_text()
    text = text.replace("K_q        = { value = 0.0,", "K_q        = { value = -1.0,")
    assert "value = -1.0" in text
    path = tmp_path / "twice.toml"
    path.write_text(text)
    with pytest.raises(VehicleFileError, match=r"twice.toml.*pitch damping is given twice.*K_q = -1.*K_Omega1_2 = -60"):
        gc.load_vehicle(str(path))


# ------------------------------------------------------------------------------------------ chapter-5 assumptions

OFFSET = gc.load_vehicle("sphere_ch5", mbar=2.0, r_P1=0.02)  # battery 2 cm forward: breaks assumption 1
OFFSET3 = gc.load_vehicle("sphere_ch5", mbar=2.0, r_P3=-0.01)


@pytest.mark.parametrize("veh, key", [(OFFSET, "r_P1 = 0.02 m"), (OFFSET3, "r_P3 = -0.01 m")])
@pytest.mark.parametrize("analysis", [
    gc.singular_perturbation, gc.composite_lyapunov, gc.unequal_mass_check, ReducedLongitudinalGlider,
    gc.TorqueControlledGlider, gc.BuoyancyGlider, lambda v: gc.NondimensionalScaling(v, 1, -0.5, 0.0, 1.0, 0.1, 0.1),
], ids=["singular_perturbation", "composite_lyapunov", "unequal_mass_check", "ReducedLongitudinalGlider",
        "TorqueControlledGlider", "BuoyancyGlider", "NondimensionalScaling"])
def test_reduced_analyses_refuse_a_battery_offset(analysis, veh, key):
    """A nonzero moving-mass offset with mbar > 0 is refused, naming chapter 5 assumption 1 and the offset; it is
    never dropped (which turned slocum_ch8 into a vertical 90 deg dive)."""
    with pytest.raises(ModelError, match=rf"chapter 5 assumption 1 .*r_P = 0.*{key}"):
        analysis(veh)


def test_phugoid_refuses_a_battery_offset():
    with pytest.raises(ModelError, match=r"§4.1 assumption 4.*r_P = 0.*r_P1 = 0.02 m"):
        gc.PhugoidModel.from_vehicle(OFFSET, 0.1)


def test_issue_slocum_is_refused_not_a_vertical_dive():
    with pytest.raises(ModelError, match=r"singular_perturbation.*assumption 1.*r_P1 = 0.02 m, r_P2 = 0.02 m, "
                                         r"r_P3 = 0.04 m"):
        gc.singular_perturbation(SLOCUM)
    # with the battery centred the pitch damping is still the chapter-8 form, which (5.15)-(5.17) cannot use
    with pytest.raises(ModelError, match=r"K_q Omega2 V\^2 .*K_Omega1_2 = -60"):
        gc.singular_perturbation(SLOCUM.with_overrides(r_P1=0.0, r_P2=0.0, r_P3=0.0))


def test_actuator_range_excluding_zero_is_refused():
    """No nominal r_P1 in the file, but its actuator cannot reach 0: the battery cannot be centred."""
    params = {k: v for k, v in SPHERE.params.items() if k != "r_P1"} | {"mbar": 2.0}
    sources = {k: "test" for k in params}

    def make(lo: float, hi: float) -> gc.Vehicle:
        return gc.Vehicle("offset", "underwater_glider", "test", params, sources, "", actuators={
            "r_P1": {"min": lo, "max": hi, "unit": "m", "source": "test"}})

    with pytest.raises(ModelError, match=r"assumption 1.*r_P1 actuator range \[0.01, 0.03\] m excludes 0"):
        gc.singular_perturbation(make(0.01, 0.03))
    assert gc.singular_perturbation(make(-0.03, 0.03)).speed > 0


def test_vehicles_within_the_assumptions_still_work():
    """Centred battery (r_P = 0 given explicitly, mbar = 2 kg): accepted, and the same as lumping the battery into
    m1 = m3 (mbar = 0), as the reduced model says (M_i = m_i + mbar). An offset without a battery (mbar = 0) is
    irrelevant and accepted."""
    centred = SPHERE.with_overrides(mbar=2.0, r_P1=0.0, r_P3=0.0)
    lumped = SPHERE.with_overrides(m1=30.0, m3=30.0)
    a, b = gc.singular_perturbation(centred), gc.singular_perturbation(lumped)
    for k in ("speed", "gamma", "alpha", "tau_s", "eps1", "eps2"):
        assert getattr(a, k) == pytest.approx(getattr(b, k), rel=1e-14)
    np.testing.assert_allclose(a.full_eigenvalues, b.full_eigenvalues, rtol=1e-10)
    assert gc.composite_lyapunov(centred).mu == pytest.approx(gc.composite_lyapunov(lumped).mu, rel=1e-14)
    no_battery = SPHERE.with_overrides(r_P1=0.05)  # mbar = 0: nothing sits at r_P
    assert gc.singular_perturbation(no_battery).speed == pytest.approx(gc.singular_perturbation(SPHERE).speed,
                                                                       rel=0)
    assert gc.PhugoidModel.from_vehicle(centred, 0.1).mass == pytest.approx(30.0)


def test_composite_names_assumption_3():
    with pytest.raises(ModelError, match=r"chapter 5 assumption 3 .*m1 = m3"):
        gc.composite_lyapunov(SPHERE.with_overrides(m3=30.0))


@pytest.mark.parametrize("call", ["elevator", "torque", "scaling"])
def test_chapter5_small_parameters_refuse_chapter8_damping(call):
    """The small parameters (5.16)-(5.17) are built from ``K_q``: a vehicle damped by ``K_Omega1_2`` (no ``V^2``) is
    refused with the assumption named, not given eps2 = inf or a double-damped loop."""
    from glidectl.controllers.elevator import elevator_equilibrium

    if call == "elevator":
        veh = gc.load_vehicle("elevator_ch6", K_q=0.0, K_Omega1_2=-5.0)
        with pytest.raises(gc.ModelError, match="K_Omega1_2"):
            elevator_equilibrium(veh, 0.3, -0.5)
    elif call == "torque":
        veh = gc.load_vehicle("sphere_ch5", K_q=0.0, K_Omega1_2=-1.0)
        ctrl = TorqueLaw(K_M0u=0.0, K_Mu=0.0, K_qu=-1.0)
        with pytest.raises(gc.ModelError, match="K_Omega1_2"):
            ctrl.closed_loop_vehicle(veh)
    else:
        sph = gc.load_vehicle("sphere_ch5")
        sc = gc.singular_perturbation(sph).scaling
        with pytest.raises(gc.ModelError, match="K_Omega1_2"):
            dataclasses.replace(sc, vehicle=sph.with_overrides(K_q=0.0, K_Omega1_2=-1.0))
