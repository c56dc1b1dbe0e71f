"""The trims, linear tools and controllers of the thesis run unchanged on the other lift and drag laws.

``gc.law_start`` matches a law to the vehicle's thesis law at 0.25 m/s (lift slope, zero-incidence drag and the
drag's alpha^2 factor), so at that speed every law has the same lift and drag polynomial in alpha and every steady
glide must be the same; away from it the Seaglider law's drag (``q^(3/4)``) differs and so must the glides.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.analysis.flight_fit import MATCH_SPEED

LAWS = ("seaglider", "gliderflight")


@pytest.fixture(scope="module")
def slocum() -> gc.Vehicle:
    """slocum_shallow without pump and battery limits (the trims here test the laws, not the actuators)."""
    return gc.load_vehicle("slocum_shallow").with_actuators(m0=None, r_P1=None)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("gamma_deg", [-35.0, -20.0, 25.0])
def test_steady_glide_equals_thesis_at_the_matched_speed(slocum, law, gamma_deg):
    gamma = math.radians(gamma_deg)
    ref = gc.steady_glide(slocum, MATCH_SPEED, gamma, r_p3=0.05)
    g = gc.steady_glide(gc.law_start(slocum, law), MATCH_SPEED, gamma, r_p3=0.05)
    for k in ("alpha", "theta", "m0", "r_p1"):
        assert getattr(g, k) == pytest.approx(getattr(ref, k), rel=1e-10, abs=1e-14), k
    assert g.residual < 1e-12


@pytest.mark.parametrize("speed", [0.1, 0.5])
def test_seaglider_glides_differ_from_thesis_away_from_the_match(slocum, speed):
    """The Seaglider drag coefficient falls as q^(-1/4): slower glides need more angle of attack (relative to lift)
    and faster ones less, than the thesis law matched at 0.25 m/s."""
    gamma = math.radians(-25.0)
    ref = gc.steady_glide(slocum, speed, gamma, r_p3=0.05)
    sg = gc.steady_glide(gc.law_start(slocum, "seaglider"), speed, gamma, r_p3=0.05)
    # drag/lift = -tan(gamma) at both: more drag at the same alpha needs more alpha (lift) to balance
    assert (sg.alpha > ref.alpha) == (speed < MATCH_SPEED)
    veh = sg.vehicle
    L, D = gc.lift_drag(veh, speed**2, sg.alpha)
    assert D / L == pytest.approx(-math.tan(gamma), rel=1e-12)
    assert L == pytest.approx(sg.m0 * veh.g * math.cos(gamma), rel=1e-12)


@pytest.mark.parametrize("law", LAWS)
def test_permissible_set_is_the_smallest_drag_to_lift_ratio(slocum, law):
    veh = gc.law_start(slocum, law)
    lo, hi = gc.permissible_gamma(veh, speed=0.3)
    a = np.linspace(1e-4, 0.5, 200_001)
    L, D = gc.lift_drag(veh, 0.09, a)
    assert math.tan(hi) == pytest.approx(np.min(D / L), rel=1e-8) and lo == -hi
    with pytest.raises(gc.InfeasibleGlideError):
        gc.steady_glide(veh, 0.3, 0.999 * lo, r_p3=0.05)  # just shallower than the shallowest glide
    gc.steady_glide(veh, 0.3, 1.001 * lo, r_p3=0.05)


def test_seaglider_permissible_set_needs_the_speed(slocum):
    veh = gc.law_start(slocum, "seaglider")
    with pytest.raises(gc.ArgumentError, match="speed"):
        gc.permissible_gamma(veh)
    # the glide ratio improves with speed: the set widens
    assert gc.permissible_gamma(veh, 0.5)[1] < gc.permissible_gamma(veh, 0.1)[1]


@pytest.mark.parametrize("law", LAWS)
def test_linearization_is_exact_on_every_law(slocum, law):
    """The complex-step Jacobian of the longitudinal model goes through lift_drag (the Seaglider law's q^(3/4)
    included) and equals central differences."""
    veh = gc.law_start(slocum, law)
    g = gc.steady_glide(veh, 0.4, math.radians(-30.0), r_p3=0.05)
    model = gc.LongitudinalGlider(veh)
    x0, u0 = g.force_state(), np.zeros(3)
    A, _ = gc.jacobians(model.rhs, x0, u0)
    h = 1e-6
    A_fd = np.column_stack([(model.rhs(x0 + h * e, u0) - model.rhs(x0 - h * e, u0)) / (2 * h)
                            for e in np.eye(x0.size)])
    assert np.allclose(A, A_fd, rtol=1e-6, atol=1e-7)
    assert np.abs(model.rhs(x0, u0)[2:]).max() < 1e-12  # the trim is an equilibrium of the model


@pytest.mark.parametrize("law", LAWS)
def test_lqr_closed_loop_is_stable_on_every_law(slocum, law):
    veh = gc.law_start(slocum, law)
    g = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=0.05)
    ctrl = gc.lqr_glide(veh, g, inputs="acceleration")
    loop = gc.closed_loop(ctrl)
    assert np.abs(loop.rhs(loop.equilibrium)).max() < 1e-9
    poles = ctrl.closed_loop_poles
    assert np.max(poles.real[np.abs(poles) > 1e-9]) < 0


def test_glide_envelope_on_the_seaglider_law(slocum):
    veh = gc.law_start(slocum, "seaglider")
    speeds, gammas = np.linspace(0.1, 0.6, 6), np.radians(np.linspace(-50.0, -10.0, 9))
    env = gc.glide_envelope(veh, speeds, gammas)
    for i, V in enumerate(speeds):
        for j, gam in enumerate(gammas):
            if env.exists[i, j]:
                g = gc.steady_glide(veh, V, gam, r_p3=env.r_p3) if env.feasible[i, j] else None
                if g is not None:
                    assert g.m0 == pytest.approx(env.m0[i, j], rel=1e-12)
    assert env.feasible.any()


@pytest.mark.parametrize("law", LAWS)
def test_helix_trim_equals_thesis_where_the_laws_agree(law):
    """gliderflight's law has the thesis's form, so matched it gives the same helix at every speed; the
    Seaglider law's helix is an equilibrium of the same 3-D model but differs (its drag is not quadratic in V)."""
    slo = gc.load_vehicle("slocum_ch8")
    ref = gc.helix_trim(slo, r_p=(0.02, 0.02, 0.04), m0=0.25)
    h = gc.helix_trim(gc.law_start(slo, law), r_p=(0.02, 0.02, 0.04), m0=0.25)
    if law == "gliderflight":
        assert h.radius == pytest.approx(ref.radius, rel=1e-9) and h.speed == pytest.approx(ref.speed, rel=1e-9)
    else:
        assert h.speed > ref.speed  # less drag at 0.7 m/s than the quadratic law matched at 0.25 m/s
    assert h.residual < 1e-9


def test_reduced_analyses_refuse_other_laws_naming_them():
    sph = gc.law_start(gc.load_vehicle("sphere_ch5"), "seaglider")
    with pytest.raises(gc.ModelError, match="seaglider"):
        gc.singular_perturbation(sph)


def _dense_first_root(veh: gc.Vehicle, theta: np.ndarray, m0: float) -> np.ndarray:
    """The efficient root of the steady-flight balance by brute force: the first angle from zero lift, on a dense
    grid (1e-12 .. 30 deg, 60,000 points), where the drag balance at the speed of the lift balance turns <= 0."""
    A = np.concatenate([np.geomspace(1e-12, 1e-3, 10_000), np.linspace(1e-3, np.pi / 6, 50_000)])
    W = m0 * veh.g
    s = np.sign(W)
    lift_unit, _ = gc.lift_drag(veh, 1.0, s * A)
    out = np.full(theta.shape, np.nan)
    for i, th in enumerate(theta):
        V2 = W * np.cos(th - s * A) / lift_unit
        _, D = gc.lift_drag(veh, np.maximum(V2, 0.0), s * A)
        r = np.where(V2 > 0, (D + W * np.sin(th - s * A)) / abs(W), np.inf)
        neg = np.flatnonzero(r <= 0)
        if neg.size:
            out[i] = s * A[neg[0]]
    return out


@pytest.mark.parametrize("case", ["steep_drag", "gliderflight_big_Cd1", "seaglider"])
def test_steady_flight_finds_the_efficient_root_of_a_dense_scan(case):
    """Near the edge of the feasible pitches the drag balance dips below zero between the search grid's points,
    or only far out on the stall branch: steady_flight must find the first root all the same, and call a pitch
    infeasible exactly where the dense scan finds none."""
    slo = gc.load_vehicle("slocum_ch8")
    veh = {"steep_drag": slo.with_overrides(K_D=400.0),
           "gliderflight_big_Cd1": slo.with_hydrodynamics("gliderflight", Cd0=0.02, Cd1=40.0, ah=0.5, aw=0.5),
           "seaglider": slo.with_hydrodynamics("seaglider", hd_a=0.003836, hd_b=0.010078, hd_c=9.8e-6,
                                               length=1.8)}[case]
    theta = np.radians(np.linspace(-70.0, 70.0, 561))
    for m0 in (0.2, -0.2):
        fl = gc.steady_flight(veh, theta, m0)
        dense = _dense_first_root(veh, theta, m0)
        assert np.array_equal(fl.feasible, np.isfinite(dense))
        ok = fl.feasible
        # the dense grid's spacing (1e-5 rad) bounds the agreement
        assert np.max(np.abs(fl.alpha[ok] - dense[ok])) < 2e-5


def test_steady_flight_of_a_sample_does_not_depend_on_the_others():
    """Each sample stops iterating on its own convergence: a subset solved alone equals the same samples solved
    among many, bit for bit (fit residuals and predictions of the same vehicle agree exactly)."""
    veh = gc.law_start(gc.load_vehicle("slocum_ch8"), "seaglider")
    rng = np.random.default_rng(3)
    theta = np.radians(rng.uniform(15.0, 45.0, 400)) * np.where(rng.uniform(size=400) < 0.5, -1, 1)
    m0 = np.where(theta < 0, 1.0, -1.0) * rng.uniform(0.05, 0.4, 400)
    full = gc.steady_flight(veh, theta, m0)
    part = gc.steady_flight(veh, theta[::7], m0[::7])
    assert np.array_equal(part.alpha, full.alpha[::7]) and np.array_equal(part.speed, full.speed[::7])


def test_excess_mass_takes_the_recorded_pressure():
    veh = gc.load_vehicle("slocum_shallow").with_hydrodynamics(mass=70.0, volume=0.0684, compressibility=5e-10,
                                                               density=1027.0)
    depth = np.array([0.0, 300.0, 600.0])
    default = gc.excess_mass(veh, depth, 0.0)
    # m0 is a difference of two numbers near 70 kg: compare to rounding of those (1e-12 kg)
    np.testing.assert_allclose(default, 70.0 - 1027.0 * 0.0684 * (1 - 5e-10 * 1027.0 * veh.g * depth), rtol=0,
                               atol=1e-12)
    p = depth * 1025.0 * 9.81  # a Slocum record's pressure, converted with its own constants
    given = gc.excess_mass(veh, depth, 0.0, pressure=p)
    np.testing.assert_allclose(given, 70.0 - 1027.0 * 0.0684 * (1 - 5e-10 * p), rtol=0, atol=1e-12)
    assert not np.array_equal(given[1:], default[1:])


@pytest.mark.parametrize("law", ["thesis", "seaglider", "gliderflight"])
def test_steady_flight_inverts_steady_glide(slocum, law):
    """Two solvers of one balance: steady_glide takes speed and flight-path angle (closed form for the thesis law,
    the root search otherwise) and gives pitch and heaviness; steady_flight at that pitch and heaviness must give the
    speed and angle of attack back."""
    veh = gc.law_start(slocum, law)
    for V, gamma_deg in ((0.15, -35.0), (0.35, -25.0), (0.5, 30.0)):
        g = gc.steady_glide(veh, V, math.radians(gamma_deg), r_p3=0.05)
        fl = gc.steady_flight(veh, g.theta, g.m0)
        assert bool(fl.feasible)
        assert float(fl.speed) == pytest.approx(V, rel=1e-12)
        assert float(fl.alpha) == pytest.approx(g.alpha, rel=1e-10, abs=1e-14)
