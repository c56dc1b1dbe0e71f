"""Steady glides of the longitudinal model: (2.26) reconstructed, (2.27)-(2.29), residuals and errors."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

import glidectl as gc
from glidectl import ArgumentError, ArgumentTypeError, InfeasibleGlideError, ModelError, load_vehicle
from glidectl.models.longitudinal import LongitudinalGlider
from glidectl.trim.glide import alpha_for_gamma, permissible_gamma, steady_glide

ROGUE = load_vehicle("rogue")
ROGUE_ASYM = load_vehicle("rogue", K_L0=20.0, K_M0=0.5)
VEHICLES = {"rogue": ROGUE, "rogue_asym": ROGUE_ASYM}

FAST = settings(max_examples=50, deadline=None)
MARGIN = 1e-3


@st.composite
def glide_requests(draw: st.DrawFn):
    name = draw(st.sampled_from(sorted(VEHICLES)))
    veh = VEHICLES[name]
    lo, hi = permissible_gamma(veh)
    frac = draw(st.floats(0.0, 1.0))
    if draw(st.booleans()):  # downward branch
        gamma = (-math.pi / 2 + MARGIN) + frac * ((lo - MARGIN) - (-math.pi / 2 + MARGIN))
    else:  # upward branch
        gamma = (hi + MARGIN) + frac * ((math.pi / 2 - MARGIN) - (hi + MARGIN))
    speed = draw(st.floats(0.05, 2.0))
    key = draw(st.sampled_from(["r_p3", "r_bh"]))
    value = draw(st.floats(-0.1, 0.1))
    return veh, speed, gamma, {key: value}


def _glide_or_skip(veh, speed, gamma, **family):
    """The glide, or skip the example when (near vertical) its moment balance needs |r_P| > R_P_MAX."""
    try:
        return steady_glide(veh, speed, gamma, **family)
    except InfeasibleGlideError as exc:
        assert "R_P_MAX" in str(exc) and abs(gamma) > 1.2, str(exc)
        assume(False)


@FAST
@given(req=glide_requests())
def test_steady_glide_is_an_equilibrium(req):
    veh, speed, gamma, family = req
    gl = _glide_or_skip(veh, speed, gamma, **family)
    assert gl.residual < 1e-10
    # independent residual on the force model, zero inputs
    f = LongitudinalGlider(veh).rhs(gl.force_state(), np.zeros(3))
    assert np.max(np.abs(f[2:])) < 1e-10
    # kinematics: the glide really has flight-path angle gamma (z down, gamma > 0 up) and speed V
    xdot, zdot = f[0], f[1]
    assert math.atan2(-zdot, xdot) == pytest.approx(gamma, abs=1e-12)
    assert math.hypot(xdot, zdot) == pytest.approx(speed, rel=1e-12)
    # stored relations
    assert gl.theta == pytest.approx(gl.gamma + gl.alpha, abs=1e-14)
    assert gl.speed == pytest.approx(math.hypot(gl.v1, gl.v3), rel=1e-14)
    assert gl.alpha == pytest.approx(math.atan2(gl.v3, gl.v1), abs=1e-14)
    st_, ct = math.sin(gl.theta), math.cos(gl.theta)
    assert gl.r_bh == pytest.approx(-gl.r_p1 * st_ + gl.r_p3 * ct, abs=1e-12 * max(1.0, abs(gl.r_p1)))
    assert np.sign(gl.m0) == -np.sign(gamma)
    key, value = next(iter(family.items()))
    assert getattr(gl, key) == pytest.approx(value, abs=1e-14)
    # (2.27) with bare coefficients: |m0| g = V^2 sqrt(K_L(alpha)^2 + K_D(alpha)^2)
    KLa = veh.K_L0 + veh.K_L * gl.alpha
    KDa = veh.K_D0 + veh.K_D * gl.alpha**2
    assert abs(gl.m0) * veh.g == pytest.approx(speed**2 * math.hypot(KLa, KDa), rel=1e-12)
    # (2.29) as printed, scaled by its largest term
    terms = [gl.m0 * (veh.m3 - veh.m1) * math.sin(gl.alpha) * math.cos(gl.alpha),
             gl.m0 * (veh.K_M0 + veh.K_M * gl.alpha),
             -veh.mbar * gl.r_p3 * (KLa * math.sin(gl.alpha) - KDa * math.cos(gl.alpha)),
             -veh.mbar * gl.r_p1 * (KLa * math.cos(gl.alpha) + KDa * math.sin(gl.alpha))]
    assert abs(sum(terms)) <= 1e-10 * max(1e-3, *map(abs, terms))
    # the root on the front side of the drag polar: between zero lift and the shallowest glide
    a0 = -veh.K_L0 / veh.K_L
    root = math.sqrt(a0**2 + veh.K_D0 / veh.K_D)
    if gamma < 0:
        assert a0 < gl.alpha <= a0 + root
    else:
        assert a0 - root <= gl.alpha < a0
    assert gl.provenance == veh.provenance and gl.vehicle is veh and gl.vehicle.name == veh.name


@FAST
@given(req=glide_requests())
def test_family_parameterizations_agree(req):
    veh, speed, gamma, family = req
    gl = _glide_or_skip(veh, speed, gamma, **family)
    other = (steady_glide(veh, speed, gamma, r_bh=gl.r_bh) if "r_p3" in family
             else steady_glide(veh, speed, gamma, r_p3=gl.r_p3))
    # r_p1 = (a_perp - r_p3 sin(theta))/cos(theta): rounding grows like 1/|cos(theta)| near vertical glides
    tol = 1e-12 * (1.0 + abs(gl.r_p1)) / abs(math.cos(gl.theta))
    for key in ("r_p1", "r_p3", "r_bh"):
        assert getattr(other, key) == pytest.approx(getattr(gl, key), abs=tol)
    for key in ("alpha", "theta", "m0", "v1", "v3"):
        assert getattr(other, key) == getattr(gl, key)


def test_minus_45_rogue_numbers():
    """A hand-checkable glide: K_L0 = 0, tan(gamma) = -K_D(a)/K_L(a) -> alpha from the quadratic."""
    gl = steady_glide(ROGUE, 0.3, math.radians(-45), r_p3=0.05)
    a = (306 - math.sqrt(306**2 - 4 * 109 * 18)) / (2 * 109)
    assert gl.alpha == pytest.approx(a, rel=1e-13)
    assert gl.m0 == pytest.approx(306 * a * 0.09 / (9.81 * math.cos(math.radians(45))), rel=1e-13)


# ------------------------------------------------------------------------------------ permissible set


def test_permissible_set_symmetric_vehicle():
    lo, hi = permissible_gamma(ROGUE)
    expected = math.atan(2 * math.sqrt(ROGUE.K_D0 * ROGUE.K_D) / ROGUE.K_L)
    assert lo == pytest.approx(-expected, rel=1e-14)
    assert hi == pytest.approx(expected, rel=1e-14)
    assert math.degrees(hi) == pytest.approx(16.146, abs=5e-4)


@pytest.mark.parametrize("name", sorted(VEHICLES))
def test_permissible_set_is_the_minimal_glide_ratio(name):
    """Bounds = shallowest glides: min over alpha of K_D(a)/|K_L(a)| for each sign of lift, numerically."""
    veh = VEHICLES[name]
    lo, hi = permissible_gamma(veh)

    def ratio(a: float, sign: float) -> float:
        KL = veh.K_L0 + veh.K_L * a
        return (veh.K_D0 + veh.K_D * a * a) / (sign * KL) if sign * KL > 0 else np.inf

    a0 = -veh.K_L0 / veh.K_L
    down = minimize_scalar(lambda a: ratio(a, 1.0), bounds=(a0 + 1e-9, a0 + 2), method="bounded",
                           options={"xatol": 1e-12})
    up = minimize_scalar(lambda a: ratio(a, -1.0), bounds=(a0 - 2, a0 - 1e-9), method="bounded",
                         options={"xatol": 1e-12})
    assert lo == pytest.approx(-math.atan(down.fun), rel=1e-9)
    assert hi == pytest.approx(math.atan(up.fun), rel=1e-9)
    if veh.K_L0 > 0:  # positive zero-incidence lift makes downward glides shallower
        assert -lo < hi


def _numbers(msg: str) -> list[float]:
    return [float(s) for s in re.findall(r"[-+]?\d+\.\d+", msg)]


@pytest.mark.parametrize("name", sorted(VEHICLES))
def test_boundary_of_permissible_set(name):
    veh = VEHICLES[name]
    lo, hi = permissible_gamma(veh)
    assert steady_glide(veh, 0.3, lo - 1e-6, r_p3=0.0).residual < 1e-10
    assert steady_glide(veh, 0.3, hi + 1e-6, r_p3=0.0).residual < 1e-10
    for gamma in (lo + 1e-6, hi - 1e-6, 0.0, 0.5 * (lo + hi)):
        with pytest.raises(InfeasibleGlideError) as info:
            steady_glide(veh, 0.3, gamma, r_p3=0.0)
        nums = _numbers(str(info.value))
        assert any(abs(v - math.degrees(lo)) < 1e-3 for v in nums), str(info.value)
        assert any(abs(v - math.degrees(hi)) < 1e-3 for v in nums), str(info.value)


@pytest.mark.parametrize("gamma", [math.pi / 2, -math.pi / 2, 2.0, -3.0])
def test_gamma_out_of_range(gamma):
    with pytest.raises(InfeasibleGlideError):
        steady_glide(ROGUE, 0.3, gamma, r_p3=0.0)


@pytest.mark.parametrize("gamma", [math.nan, math.inf, -math.inf])
def test_non_finite_gamma_is_an_argument_error(gamma):
    with pytest.raises(ArgumentError, match="gamma"):
        steady_glide(ROGUE, 0.3, gamma, r_p3=0.0)


@pytest.mark.parametrize("speed", [0.0, -0.3, math.nan, math.inf, 100.01, 1e200])
def test_bad_speed(speed):
    with pytest.raises(ArgumentError, match="speed"):
        steady_glide(ROGUE, speed, math.radians(-30), r_p3=0.0)
    with pytest.raises(ValueError):  # ArgumentError is also a ValueError
        steady_glide(ROGUE, speed, math.radians(-30), r_p3=0.0)


def test_mass_position_parameter_must_be_unique():
    with pytest.raises(ArgumentError, match="exactly one"):
        steady_glide(ROGUE, 0.3, math.radians(-30), r_p3=0.0, r_bh=0.01)
    with pytest.raises(ArgumentError, match="exactly one"):
        steady_glide(ROGUE, 0.3, math.radians(-30))


# ------------------------------------------------------------------------- issue 15: argument checks


@pytest.mark.parametrize("speed", ["0.3", None, np.array([0.3]), [0.3], True, 0.3 + 0j])
def test_speed_of_the_wrong_type_is_an_argument_type_error(speed):
    """Issue 15: ``steady_glide(v, '0.3', ...)``, ``speed=None``, ``speed=np.array([.3])`` raised raw TypeErrors."""
    with pytest.raises(ArgumentTypeError, match="speed"):
        steady_glide(ROGUE, speed, -0.785, r_p3=0.05)
    with pytest.raises(TypeError):
        steady_glide(ROGUE, speed, -0.785, r_p3=0.05)


@pytest.mark.parametrize("speed", [np.float64(0.3), np.float32(0.3), np.int64(1), np.array(0.3)])
def test_numpy_real_speeds_are_accepted(speed):
    gl = steady_glide(ROGUE, speed, -0.785, r_p3=0.05)
    assert gl.speed == pytest.approx(float(speed)) and isinstance(gl.speed, float)


@pytest.mark.parametrize(("kw", "err"), [({"gamma": "x"}, ArgumentTypeError), ({"gamma": None}, ArgumentTypeError),
                                         ({"r_p3": "1"}, ArgumentTypeError), ({"r_p3": math.nan}, ArgumentError),
                                         ({"r_p3": 1e300}, ArgumentError), ({"r_bh": 1e300}, ArgumentError),
                                         ({"r_bh": [0.01]}, ArgumentTypeError)])
def test_other_arguments_are_checked(kw, err):
    args = {"speed": 0.3, "gamma": -0.785, **kw}
    if "r_bh" not in kw:
        args.setdefault("r_p3", 0.05)
    with pytest.raises(err):
        steady_glide(ROGUE, **args)


@pytest.mark.parametrize("veh", ["rogue", None, 3])
def test_vehicle_must_be_a_vehicle(veh):
    for call in (lambda: steady_glide(veh, 0.3, -0.785, r_p3=0.05), lambda: permissible_gamma(veh),
                 lambda: alpha_for_gamma(veh, -0.785)):
        with pytest.raises(ArgumentTypeError, match="Vehicle"):
            call()


def test_alpha_for_gamma_checks_gamma():
    with pytest.raises(ArgumentTypeError):
        alpha_for_gamma(ROGUE, "x")
    with pytest.raises(ArgumentError):
        alpha_for_gamma(ROGUE, math.nan)
    with pytest.raises(InfeasibleGlideError):
        alpha_for_gamma(ROGUE, 2.0)
    with pytest.raises(InfeasibleGlideError):  # K_D = 0 at gamma = 0 used to divide by zero
        alpha_for_gamma(load_vehicle("rogue", K_D=0.0), 0.0)


def test_mass_position_beyond_the_plausibility_limit_is_infeasible():
    """Near a vertical glide r_p3 = 0.1 m needs r_P1 far outside any hull: refused, not returned."""
    with pytest.raises(InfeasibleGlideError, match="R_P_MAX"):
        steady_glide(ROGUE, 0.3, -math.pi / 2 + 1e-4, r_p3=0.1)


def test_underflowing_speed_is_refused_not_a_zero_buoyancy_glide():
    """speed = 1e-200 gave m0 = 0.0 (V^2 underflows) and a 'glide' with no net weight."""
    with pytest.raises(ArgumentError, match="underflow"):
        steady_glide(ROGUE, 1e-200, -0.785, r_p3=0.05)


def test_residual_check_is_relative_so_tiny_valid_glides_pass():
    """The residual test scales with the forces: a glide at 1e-100 m/s is the 0.3 m/s glide with m0 scaled by V^2."""
    ref = steady_glide(ROGUE, 0.3, -0.785, r_bh=0.05)
    tiny = steady_glide(ROGUE, 1e-100, -0.785, r_bh=0.05)
    assert tiny.alpha == ref.alpha and tiny.theta == ref.theta
    assert tiny.m0 == pytest.approx(ref.m0 * (1e-100 / 0.3) ** 2, rel=1e-12)
    f = LongitudinalGlider(ROGUE).rhs(tiny.force_state(), np.zeros(3))
    weight = abs(tiny.m0) * ROGUE.g  # ~2.6e-199 N: the force equations balance to that scale, not to 1e-9 absolute
    assert abs(f[4]) * ROGUE.m1 <= 1e-12 * weight and abs(f[5]) * ROGUE.m3 <= 1e-12 * weight


def test_state_helpers_check_positions():
    gl = steady_glide(ROGUE, 0.3, -0.785, r_p3=0.05)
    assert gl.force_state(1.0, np.float32(2.0))[:2].tolist() == [1.0, 2.0]
    with pytest.raises(ArgumentTypeError):
        gl.force_state("1")
    with pytest.raises(ArgumentError):
        gl.accel_state(0.0, math.inf)


def test_hydrodynamic_loads_check_their_arguments():
    from glidectl import hydro

    alpha, L, D, M = hydro.longitudinal_loads(ROGUE, 0.3, 0.02, 0.0)
    assert np.isfinite([alpha, L, D, M]).all()
    with pytest.raises(ArgumentTypeError, match="Vehicle"):
        hydro.longitudinal_loads("rogue", 0.3, 0.0, 0.0)
    with pytest.raises(ModelError):
        hydro.loads_at(load_vehicle("dc8_ctol"), 0.09, 0.0, 0.0)
    with pytest.raises(ArgumentTypeError, match="V2"):
        hydro.loads_at(ROGUE, "a", 0.0, 0.0)
    with pytest.raises(ArgumentTypeError):
        hydro.angle_of_attack(None, 0.0)
    with pytest.raises(ArgumentError, match="broadcast"):
        hydro.atan2_cs(np.zeros(2), np.zeros(3))
    # complex input (complex-step derivatives) is still accepted
    assert np.iscomplexobj(hydro.loads_at(ROGUE, 0.09 + 1e-20j, 0.1, 0.0)[0])


def test_ctol_vehicle_is_model_error():
    ctol = load_vehicle("dc8_ctol")
    with pytest.raises(ModelError):
        steady_glide(ctol, 0.3, math.radians(-30), r_p3=0.0)
    with pytest.raises(ModelError):
        permissible_gamma(ctol)
    with pytest.raises(ModelError):
        alpha_for_gamma(ctol, -0.5)
    assert issubclass(gc.ModelError, gc.GlidectlError)


def test_no_moving_mass_is_model_error():
    with pytest.raises(ModelError):
        steady_glide(load_vehicle("sphere_ch5"), 0.3, math.radians(-45), r_p3=0.0)


# ------------------------------------------------------------------------------------ up/down correspondence


@pytest.mark.parametrize("deg", [20.0, 30.0, 45.0, 60.0, 85.0])
@pytest.mark.parametrize("r_p3", [-0.05, 0.0, 0.05])
def test_up_down_glides_mirror(deg, r_p3):
    down = steady_glide(ROGUE, 0.3, -math.radians(deg), r_p3=r_p3)
    up = steady_glide(ROGUE, 0.3, math.radians(deg), r_p3=r_p3)
    for key in ("alpha", "theta", "m0", "r_p1", "v3"):
        assert getattr(up, key) == pytest.approx(-getattr(down, key), rel=1e-12, abs=1e-15)
    assert up.r_bh == pytest.approx(down.r_bh, rel=1e-12, abs=1e-15)
    assert up.v1 == pytest.approx(down.v1, rel=1e-14)
    assert down.alpha > 0 and down.m0 > 0 and up.alpha < 0 and up.m0 < 0


def test_up_down_glides_do_not_mirror_when_asymmetric():
    down = steady_glide(ROGUE_ASYM, 0.3, -math.radians(45), r_p3=0.05)
    up = steady_glide(ROGUE_ASYM, 0.3, math.radians(45), r_p3=0.05)
    assert abs(up.alpha + down.alpha) > 1e-3
    assert abs(up.m0 + down.m0) > 1e-3


def test_printed_2_28_returns_pitch_not_gamma():
    """docs/conventions.md: (2.28) as printed evaluates to theta (bare L_e, D_e): atan(sin(theta)/cos(theta))."""
    for deg in (-45.0, -30.0, 30.0, 45.0):
        gl = steady_glide(ROGUE_ASYM, 0.3, math.radians(deg), r_p3=0.0)
        a = gl.alpha
        L = ROGUE_ASYM.K_L0 + ROGUE_ASYM.K_L * a
        D = ROGUE_ASYM.K_D0 + ROGUE_ASYM.K_D * a * a
        printed = math.atan((L * math.sin(a) - D * math.cos(a)) / (L * math.cos(a) + D * math.sin(a)))
        assert printed == pytest.approx(gl.theta, abs=1e-12)
        assert abs(printed - gl.gamma) > 1e-3
