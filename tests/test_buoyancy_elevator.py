"""Buoyancy control (§6.2) and elevator + buoyancy control (§6.3): equilibria, corrections to the text, Theorem 3,
saturations in closed loop, the Fig 6.2 example and the sampled check of the Lyapunov argument (6.10)-(6.12)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl import GlidectlError, InfeasibleGlideError, composite_lyapunov, load_vehicle, simulate
from glidectl.controllers.buoyancy import (
    BuoyancyController,
    buoyancy_equilibrium,
    buoyancy_lyapunov_check,
    nu_b_derivative,
)
from glidectl.controllers.elevator import (
    ElevatorBuoyancyController,
    closed_loop_eigenvalues,
    elevator_equilibrium,
    elevator_example,
    infer_J2,
)
from glidectl.models.buoyancy_glider import ActuatorLimits, BuoyancyGlider, loaded_rates
from glidectl.models.elevator_glider import ElevatorBuoyancyGlider, effective_coefficients, elevator_loads
from glidectl.models.reduced import ReducedLongitudinalGlider

#: the thesis's Fig 6.2 example (section 6.3): speed (m/s), gamma (rad), printed alpha_e (deg), m0e (kg), eps1, eps2
FIG62 = {"speed": 1.0, "gamma": -math.pi / 4, "alpha_e_deg": 3.51, "m0e": 2.657, "eps1": 0.075, "eps2": 0.012}

ELEV = load_vehicle("elevator_ch6")
SPHERE = load_vehicle("sphere_ch5")
SPHERE100 = load_vehicle("sphere_ch5", K_M=-100.0)  # the certified variant of §5.3.1


@pytest.fixture(scope="module")
def eq62():
    return elevator_equilibrium(ELEV, FIG62["speed"], FIG62["gamma"])


@pytest.fixture(scope="module")
def example62():
    return elevator_example(ELEV, FIG62["speed"], FIG62["gamma"])


# ------------------------------------------------------------------------------------------- model consistency
def test_loaded_rates_without_load_is_the_reduced_model():
    rng = np.random.default_rng(1)
    x = np.column_stack([rng.uniform(0.5, 2, 50), rng.uniform(-1.5, 1.5, 50), rng.uniform(-0.2, 0.2, 50),
                         rng.uniform(-1, 1, 50), rng.choice([0.5, 2.0, 3.1], 50)])
    r = loaded_rates(ELEV, x)
    for m0 in (0.5, 2.0, 3.1):
        rows = x[:, 4] == m0
        ref = ReducedLongitudinalGlider(ELEV.with_overrides(m0=m0)).rhs(x[rows, :4])
        np.testing.assert_array_equal(r[rows], ref)


def test_elevator_force_is_a_body3_force_behind_the_centre_of_mass():
    """Check of the signs of (6.14)-(6.19): the elevator's effect on (V', gamma') is exactly a force f3 e3 in the
    body frame (inertial momentum balance), and its moment has the sign of an aft surface (arm > 0)."""
    model = ElevatorBuoyancyGlider(ELEV)
    x = np.array([0.9, -0.6, 0.08, 0.1, 2.4])
    u2 = -0.05
    d = model.rhs(x, [0.0, u2]) - model.rhs(x, [0.0, 0.0])
    V, gam, al, _, m0 = x
    m1 = ELEV.mass(1, m0)
    f3, M = elevator_loads(ELEV, V * V, u2)
    th = gam + al
    # inertial (x forward, z down): xdot = V cos(gamma), zdot = -V sin(gamma); body e3 = (sin th, cos th)
    ax = d[0] * math.cos(gam) - V * math.sin(gam) * d[1]
    az = -d[0] * math.sin(gam) - V * math.cos(gam) * d[1]
    assert m1 * ax == pytest.approx(f3 * math.sin(th), rel=1e-12)
    assert m1 * az == pytest.approx(f3 * math.cos(th), rel=1e-12)
    assert d[3] == pytest.approx(M / ELEV.J2, rel=1e-12)
    assert M / f3 == pytest.approx(-ELEV.K_M / ELEV.delta) and M / f3 > 0   # aft elevator: l = -K_M/delta > 0
    # (6.14) as printed would add +h sin(alpha) to V' (h = delta u2 V^2); the body-3 force adds -h sin(alpha)
    h = ELEV.delta * u2 * V * V
    assert d[0] * m1 == pytest.approx(-h * math.sin(al), rel=1e-12)
    # (6.15): +h cos(alpha) in gamma' (as printed)
    assert d[1] * m1 * V == pytest.approx(h * math.cos(al), rel=1e-12)


# ------------------------------------------------------------------------------------------- equilibrium §6.3
def test_elevator_equilibrium_residual_and_api(eq62):
    assert eq62.residual < 1e-10
    model = ElevatorBuoyancyGlider(ELEV)
    assert np.max(np.abs(model.rhs(eq62.state, [0.0, eq62.u2e]))) < 1e-10
    for name in ("m0e", "alpha", "u2e", "eps1", "eps2", "K_De_eff"):
        assert math.isfinite(getattr(eq62, name))
    assert eq62.provenance == ELEV.provenance


def test_printed_fig62_numbers_and_g_sensitivity(eq62):
    eq98 = elevator_equilibrium(ELEV.with_overrides(g=9.8), 1.0, -math.pi / 4)
    # alpha_e does not depend on g: 3.5189 deg (printed 3.51)
    assert math.degrees(eq62.alpha) == pytest.approx(3.51894674, abs=1e-6)
    assert math.degrees(eq62.alpha) == pytest.approx(FIG62["alpha_e_deg"], abs=0.01)
    assert eq98.alpha == pytest.approx(eq62.alpha, abs=1e-14)
    # m0e: g = 9.8 reproduces the printed 2.657 kg, the file's g = 9.81 gives 2.6546 kg
    assert eq98.m0e == pytest.approx(2.657316, abs=1e-6)
    assert eq62.m0e == pytest.approx(2.654607, abs=1e-6)
    assert abs(eq98.m0e - FIG62["m0e"]) < 5e-4 < abs(eq62.m0e - FIG62["m0e"])
    assert eq62.m0e / eq98.m0e == pytest.approx(9.8 / 9.81, rel=1e-12)
    # eps1 = 0.075 (chapter-5 definition with tau_s of (6.27)), eps2 = 0.012 with the file's inferred J2 = 0.1
    assert eq62.eps1 == pytest.approx(FIG62["eps1"], abs=1e-3)
    assert eq62.eps2 == pytest.approx(FIG62["eps2"], abs=1e-3)
    assert eq62.eps2 == pytest.approx(0.012014, abs=1e-6)


def test_J2_inference():
    assert ELEV.J2 == 0.1
    J2 = infer_J2(ELEV, FIG62["eps2"], FIG62["speed"], FIG62["gamma"])
    assert J2 == pytest.approx(0.09988, abs=1e-4)
    J2_98 = infer_J2(ELEV.with_overrides(g=9.8), FIG62["eps2"], FIG62["speed"], FIG62["gamma"])
    assert J2_98 == pytest.approx(0.09989, abs=1e-4)
    eq = elevator_equilibrium(ELEV.with_overrides(J2=J2), 1.0, -math.pi / 4)
    assert eq.eps2 == pytest.approx(FIG62["eps2"], rel=1e-12)


def test_620_sign_correction(eq62):
    """alpha_e = -K_M0/K_M - u2e with the stated torque K_M u2 V^2; the printed + u2e is not an equilibrium."""
    assert eq62.alpha == pytest.approx(-ELEV.K_M0 / ELEV.K_M - eq62.u2e, abs=1e-15)
    assert eq62.u2e == pytest.approx(-0.0364172, abs=1e-7)
    a_printed = eq62.alpha_printed_620
    assert a_printed == pytest.approx(-ELEV.K_M0 / ELEV.K_M + eq62.u2e)
    x = eq62.state.copy()
    x[2] = a_printed
    r = ElevatorBuoyancyGlider(ELEV).rhs(x, [0.0, eq62.u2e])
    assert abs(r[3]) > 1.0   # large pitch acceleration: no moment balance at the printed alpha_e


def test_theorem3_condition_corrected_vs_printed(eq62):
    d, a, u = ELEV.delta, eq62.alpha, eq62.u2e
    # corrected (6.23): + delta u2e sin(alpha_e), no V_e^2
    assert eq62.K_De_eff == pytest.approx(ELEV.K_D0 + ELEV.K_D * a**2 + d * u * math.sin(a), rel=1e-14)
    assert eq62.K_De_eff == pytest.approx(18.4142575, abs=1e-6)
    assert eq62.K_De_eff_printed == pytest.approx(18.4155986, abs=1e-6)
    assert eq62.K_De_eff < eq62.K_De < eq62.K_De_eff_printed   # the down force at the tail is a small thrust
    assert eq62.certified
    # it is the drag the model really sees: -(force along the velocity) / V^2 at the equilibrium
    V, al = eq62.speed, eq62.alpha
    L, D = (ELEV.K_L0 + ELEV.K_L * al) * V**2, eq62.K_De * V**2
    f3, _ = elevator_loads(ELEV, V**2, eq62.u2e)
    assert (D - f3 * math.sin(al)) / V**2 == pytest.approx(eq62.K_De_eff, rel=1e-14)
    assert (L - f3 * math.cos(al)) / V**2 == pytest.approx(eq62.K_Le_eff, rel=1e-14)
    # equilibrium relations m0 g sin(gamma) = -K'_De V^2, m0 g cos(gamma) = K'_Le V^2
    assert eq62.m0e * ELEV.g * math.sin(eq62.gamma) == pytest.approx(-eq62.K_De_eff * V**2, rel=1e-12)
    assert eq62.m0e * ELEV.g * math.cos(eq62.gamma) == pytest.approx(eq62.K_Le_eff * V**2, rel=1e-12)
    # the printed V_e^2 factor: at V_e = 2 the printed coupling term is 4x the corrected one
    eq2 = elevator_equilibrium(ELEV.with_actuators(m0={"min": -20.0, "max": 20.0, "rate": 0.05}), 2.0, -math.pi / 4)
    t_c = eq2.K_De_eff - eq2.K_De
    t_p = eq2.K_De_eff_printed - eq2.K_De
    assert t_p == pytest.approx(-4 * t_c, rel=1e-12)


def test_theorem3_reduced_subsystem_is_lanchester_with_effective_coefficients(eq62):
    """Proof of Theorem 3, (6.24)-(6.26): at alpha = alpha_e, Omega2 = 0, m0 = m0e the slow dynamics are those of
    chapter 5 with K'_De, K'_Le (corrected signs)."""
    rng = np.random.default_rng(3)
    V = rng.uniform(0.6, 1.4, 20)
    gam = rng.uniform(-1.5, 0.5, 20)
    x = np.column_stack([V, gam, np.full(20, eq62.alpha), np.zeros(20), np.full(20, eq62.m0e)])
    r = ElevatorBuoyancyGlider(ELEV).rhs(x, np.tile([0.0, eq62.u2e], (20, 1)))
    m1, mg = eq62.m_e, eq62.m0e * ELEV.g
    np.testing.assert_allclose(r[:, 0], -(mg * np.sin(gam) + eq62.K_De_eff * V**2) / m1, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(r[:, 1], (-mg * np.cos(gam) + eq62.K_Le_eff * V**2) / (m1 * V), rtol=1e-12,
                               atol=1e-14)
    kd, kl = effective_coefficients(ELEV, eq62.alpha, eq62.u2e)
    assert (kd, kl) == (eq62.K_De_eff, eq62.K_Le_eff)


def test_closed_loop_eigenvalues_theorem3(eq62):
    lam = closed_loop_eigenvalues(eq62, ELEV)
    assert np.all(lam.real < 0)
    assert lam.real.max() == pytest.approx(-1 / eq62.tau_s, rel=1e-6)   # the buoyancy mode K / tau_s


@pytest.mark.parametrize(("speed", "gamma_deg", "match"), [
    (1.0, 0.0, "no steady glide"),
    (1.0, -10.0, "no steady glide"),
    (1.0, -18.0, "saturation \\[-0.2, 0.2\\] rad"),
    (2.0, -45.0, "outside the range"),
])
def test_elevator_infeasible(speed, gamma_deg, match):
    with pytest.raises(InfeasibleGlideError, match=match):
        elevator_equilibrium(ELEV, speed, math.radians(gamma_deg))


@pytest.mark.parametrize(("speed", "gamma", "err", "match"), [
    (-1.0, -math.pi / 4, gc.ArgumentError, "speed"),
    (0.0, -math.pi / 4, gc.ArgumentError, "speed"),
    (1e200, -math.pi / 4, gc.ArgumentError, "speed"),
    (math.nan, -math.pi / 4, gc.ArgumentError, "speed"),
    (1.0, math.radians(-95.0), gc.ArgumentError, "gamma_e"),
    (1.0, math.pi / 2, gc.ArgumentError, "gamma_e"),
    ("1.0", -math.pi / 4, gc.ArgumentTypeError, "speed"),
    (1.0, None, gc.ArgumentTypeError, "gamma_e"),
    (np.array([1.0]), -math.pi / 4, gc.ArgumentTypeError, "speed"),
])
def test_elevator_bad_arguments(speed, gamma, err, match):
    with pytest.raises(err, match=match):
        elevator_equilibrium(ELEV, speed, gamma)


def test_climb_is_mirror_of_descent(eq62):
    up = elevator_equilibrium(ELEV, 1.0, math.pi / 4)
    assert up.m0e < 0 and up.alpha < 0 and up.residual < 1e-10 and up.certified


# ------------------------------------------------------------------------------------------- Fig 6.2 closed loop
def test_fig62_closed_loop_converges_and_respects_saturations(example62):
    ex = example62
    lim = ex.limits
    assert (lim.u2_max, lim.u4_max, lim.m0_max) == (0.2, 0.05, 4.0)
    assert ex.max_abs_u2 <= lim.u2_max
    assert ex.max_abs_m0dot <= lim.u4_max * (1 + 1e-12)
    assert ex.max_abs_m0dot == pytest.approx(lim.u4_max)        # the pump does hit its rate limit
    assert ex.max_abs_m0 <= lim.m0_max
    assert np.all(np.abs(ex.sim.u[:, 0]) <= lim.u4_max * (1 + 1e-12))
    e0 = np.abs(ex.x0 - ex.eq.state)
    assert np.all(np.abs(ex.final_error) < 1e-3)
    assert np.linalg.norm(ex.final_error) < 2e-3 * np.linalg.norm(e0)
    assert ex.sim.t[-1] == 10.0


def test_controller_saturates_commands(eq62):
    ctrl = ElevatorBuoyancyController(eq62, ELEV, K=50.0)
    u = ctrl(0.0, np.array([1.0, -0.7, 0.06, 0.0, 1.0]))
    assert u[0] == pytest.approx(ELEV.actuators["m0"].rate) and u[1] == pytest.approx(eq62.u2e)
    big = ElevatorBuoyancyGlider(ELEV.with_actuators(elevator={"min": -0.01, "max": 0.01}))
    r1 = big.rhs(eq62.state, [0.0, 0.5])
    r2 = big.rhs(eq62.state, [0.0, 0.01])
    np.testing.assert_array_equal(r1, r2)
    with pytest.raises(GlidectlError):
        ElevatorBuoyancyController(eq62, ELEV, K=0.0)


def test_pump_limits():
    lim = ActuatorLimits(u4_max=0.05, m0_max=1.0)
    np.testing.assert_array_equal(lim.pump(np.array([0.0, 1.0, 1.0, -1.0, -1.0]), np.array([1, 1, -1, -1, 1])),
                                  [0.05, 0.0, -0.05, 0.0, 0.05])


# ------------------------------------------------------------------------------------------- §6.2 buoyancy
def test_buoyancy_equilibrium_67():
    eq = buoyancy_equilibrium(SPHERE, 1.5)
    assert eq.residual < 1e-12
    assert eq.m0e == pytest.approx(math.hypot(eq.K_De, eq.K_Le) * 1.5**2 / SPHERE.g, rel=1e-14)
    assert eq.speed == pytest.approx(1.5, rel=1e-12) and eq.gamma < 0
    assert eq.alpha == pytest.approx(-SPHERE.K_M0 / SPHERE.K_M)       # buoyancy does not move alpha_e
    with pytest.raises(InfeasibleGlideError, match="inverted"):   # alpha_e > 0 fixed: no upright climb
        buoyancy_equilibrium(SPHERE, 1.5, descending=False)
    up = buoyancy_equilibrium(load_vehicle("sphere_ch5", K_M0=-1.0), 1.5, descending=False)
    assert up.m0e < 0 and 0 < up.gamma < math.pi / 2 and up.residual < 1e-12
    with pytest.raises(InfeasibleGlideError, match="outside the range"):
        buoyancy_equilibrium(SPHERE, 2.5)
    with pytest.raises(gc.ArgumentError, match="speed"):
        buoyancy_equilibrium(SPHERE, 0.0)


def test_buoyancy_closed_loop_changes_speed_within_pump_limits():
    eq = buoyancy_equilibrium(SPHERE, 1.5)
    x0 = buoyancy_equilibrium(SPHERE, 1.648).state   # steady glide at the nominal m0 ~ 0.7 kg
    model = BuoyancyGlider(SPHERE)
    ctrl = BuoyancyController(eq, SPHERE, K_b=5.0)
    sim = simulate(model, x0, 150.0, ctrl)
    m0dot = model.rhs(sim.x, sim.u)[:, 4]
    assert np.max(np.abs(m0dot)) == pytest.approx(SPHERE.actuators["m0"].rate)   # rate limited at first
    assert np.max(np.abs(sim.u[:, 0])) <= SPHERE.actuators["m0"].rate * (1 + 1e-12)
    assert np.max(np.abs(sim.x[:, 4])) <= SPHERE.actuators["m0"].max
    assert np.all(np.abs(sim.x[-1] - eq.state) < 1e-4)


def test_buoyancy_lyapunov_cross_term_and_local_threshold():
    eq = buoyancy_equilibrium(SPHERE100, 1.7889614473799471)
    assert eq.m0e == pytest.approx(0.7, rel=1e-12)
    cert = composite_lyapunov(SPHERE100)
    chk = buoyancy_lyapunov_check(eq, SPHERE100, K_b=1.0, n=4000, cert=cert)
    assert chk.nu_certified
    assert chk.dnu_max_at_m0e < 0            # Theorem 2 at m0 = m0e
    assert chk.cross_term_max > 0.1          # (6.11) drops this term: it is not zero
    assert chk.K_b_star == pytest.approx(191.63, rel=1e-3)
    assert chk.n_positive_local > 0 and not chk.passed
    assert {"K_b > K_b_star", "K_b >= K_b_required (near 0)"} <= set(chk.failing())
    # along the worst direction dnu_b/dt_n > 0 arbitrarily close to the origin when K_b < K_b_star ...
    m = np.array([1e-4, 1e-5])
    z = np.outer(m, chk.z_star)
    dnub, cross = nu_b_derivative(eq, SPHERE100, cert, z, m, K_b=0.9 * chk.K_b_star)
    assert np.all(dnub > 0) and np.all(cross != 0)
    # ... and < 0 when K_b > K_b_star
    dnub, _ = nu_b_derivative(eq, SPHERE100, cert, z, m, K_b=1.1 * chk.K_b_star)
    assert np.all(dnub < 0)
    big = buoyancy_lyapunov_check(eq, SPHERE100, K_b=2 * chk.K_b_star, n=4000, cert=cert)
    assert big.n_positive == 0 and big.n_positive_local == 0 and big.passed and big.failing() == {}


# ------------------------------------------------------------------------------------------- bad inputs (issue 15)
def test_elevator_eigenvalues_check_that_the_equilibrium_belongs_to_the_vehicle(eq62):
    other = ELEV.with_overrides(delta=ELEV.delta * 1.1)
    with pytest.raises(gc.VehicleMismatchError):
        closed_loop_eigenvalues(eq62, other)
    with pytest.raises(gc.VehicleMismatchError):
        ElevatorBuoyancyController(eq62, other)
    with pytest.raises(gc.ArgumentTypeError, match="ElevatorEquilibrium"):
        closed_loop_eigenvalues(eq62.state, ELEV)
    with pytest.raises(gc.ArgumentError):
        closed_loop_eigenvalues(eq62, ELEV, K=math.nan)
    with pytest.raises(gc.ArgumentTypeError):
        closed_loop_eigenvalues(eq62, ELEV, K="1")
    with pytest.raises(gc.ModelError, match="not an underwater glider"):
        closed_loop_eigenvalues(eq62, load_vehicle("dc8_ctol"))


def test_buoyancy_equilibrium_and_controller_inputs():
    for bad, err in [(math.nan, gc.ArgumentError), (-1.5, gc.ArgumentError), (1e6, gc.ArgumentError),
                     ("1.5", gc.ArgumentTypeError), (None, gc.ArgumentTypeError), (True, gc.ArgumentTypeError)]:
        with pytest.raises(err):
            buoyancy_equilibrium(SPHERE, bad)
    with pytest.raises(gc.ArgumentTypeError, match="descending"):
        buoyancy_equilibrium(SPHERE, 1.5, descending="yes")
    with pytest.raises(gc.ModelError, match="not an underwater glider"):
        buoyancy_equilibrium(load_vehicle("dc8_ctol"), 1.5)
    with pytest.raises(gc.ArgumentTypeError, match="load_vehicle"):
        buoyancy_equilibrium("sphere_ch5", 1.5)
    eq = buoyancy_equilibrium(SPHERE, 1.5)
    with pytest.raises(gc.VehicleMismatchError):
        BuoyancyController(eq, SPHERE100)
    with pytest.raises(gc.ArgumentError, match="K_b"):
        BuoyancyController(eq, SPHERE, K_b=-1.0)
    with pytest.raises(gc.ArgumentTypeError, match="BuoyancyEquilibrium"):
        BuoyancyController(None, SPHERE)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 5"):
        BuoyancyController(eq, SPHERE)(0.0, np.zeros(4))


def test_buoyancy_lyapunov_check_budget_and_inputs():
    eq = buoyancy_equilibrium(SPHERE100, 1.5)
    for kw, err in [({"n": 0}, gc.ArgumentError), ({"n": 10**9}, gc.ArgumentError),
                    ({"n": 100.0}, gc.ArgumentTypeError), ({"n_m0": 4}, gc.ArgumentError),
                    ({"mbar0_max": -0.01}, gc.ArgumentError),
                    ({"K_b": math.nan}, gc.ArgumentError), ({"local_radius": 0.0}, gc.ArgumentError),
                    ({"seed": -1}, gc.ArgumentError), ({"cert": "nu"}, gc.ArgumentTypeError)]:
        with pytest.raises(err):
            buoyancy_lyapunov_check(eq, SPHERE100, **kw)
    with pytest.raises(gc.VehicleMismatchError):
        buoyancy_lyapunov_check(eq, SPHERE)


def test_elevator_example_and_infer_J2_inputs():
    for kw in ({"t_final": 0.0}, {"t_final": math.inf}, {"x0": [1.0, -0.7, 0.06, 0.0]},
               {"x0": [-1.0, -0.7, 0.06, 0.0, 2.5]}, {"m0_start": 0.0}, {"K": 0.0}):
        with pytest.raises(gc.ArgumentError):
            elevator_example(ELEV, 1.0, -math.pi / 4, **kw)
    with pytest.raises(gc.ArgumentError, match="eps2"):
        infer_J2(ELEV, -0.012, 1.0, -math.pi / 4)
    with pytest.raises(gc.ModelError, match="K_q"):
        elevator_equilibrium(ELEV.with_overrides(K_q=0.0), 1.0, -math.pi / 4)  # was a ZeroDivisionError in (5.17)


def test_actuator_and_model_inputs():
    with pytest.raises(gc.ArgumentError, match="u4_max"):
        ActuatorLimits(u4_max=-0.05)
    with pytest.raises(gc.ArgumentTypeError):
        ActuatorLimits(m0_max="1")
    with pytest.raises(gc.ArgumentError, match="trailing dimension 5"):
        loaded_rates(SPHERE, np.zeros(4))
    with pytest.raises(gc.ModelError, match="not an underwater glider"):
        elevator_loads(load_vehicle("dc8_ctol"), 1.0, 0.1)  # was an AttributeError (K_M)
    with pytest.raises(gc.ArgumentError, match="trailing dimension 1"):
        BuoyancyGlider(SPHERE).rhs(np.ones(5), np.zeros(2))
