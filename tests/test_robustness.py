"""Monte Carlo of any study over a vehicle's [uncertainty] table (gc.monte_carlo) and closed-loop robustness of a
controller designed on the nominal vehicle (gc.robust_stability): seeded reproducibility across executors, failures
counted with their reasons, the worst case against an exhaustive grid, the margin checked on both sides, and the
model rebuilt on another vehicle equal to one built on it directly."""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

import glidectl as gc
from glidectl.missions.behaviours import dead_zone
from glidectl.robustness.stability import MARGIN_MAX, loop_poles


def glide_study(veh):
    """Speed and glide angle of a steady glide at a fixed pump and battery setting (a study of the vehicle)."""
    if veh.K_M < -125.0:
        raise gc.ModelError("a study that refuses this vehicle")
    g = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=0.05)
    return {"m0": g.m0, "r_P1": g.r_p1, "note": "text is left out"}


@pytest.fixture(scope="module")
def uncertain():
    veh = gc.load_vehicle("slocum_shallow")
    return veh.with_uncertainty({"K_M": {"rel": 0.3}, "K_D0": {"std": 0.2}, "K_L": {"rel": 0.2}})


def test_monte_carlo_table_quantiles_and_failures(uncertain):
    mc = gc.monte_carlo(glide_study, uncertain, n=60, seed=3)
    assert set(mc.keys) == {"K_L", "K_D0", "K_M"}
    assert mc.names == ("m0", "r_P1") and mc.n == 60 and mc.values.shape == (60, 3)
    refused = mc.values[:, mc.keys.index("K_M")] < -125.0
    assert refused.any() and (~refused).any()
    np.testing.assert_array_equal(mc.ok, ~refused)
    assert mc.failures == {"ModelError: a study that refuses this vehicle": int(refused.sum())}
    assert np.all(np.isnan(mc.results[refused]))
    # each row is the study of that sample's vehicle
    i = int(np.flatnonzero(~refused)[0])
    veh_i = uncertain.sample(60, seed=3).vehicles[i]
    assert mc.results[i, 0] == pytest.approx(glide_study(veh_i)["m0"], rel=1e-12)
    t = mc.table
    assert t.shape == (60,) and t["ok"].sum() == mc.ok.sum() and np.array_equal(t["K_M"], mc.values[:, 2])
    np.testing.assert_allclose(mc.quantiles("m0", [0.1, 0.9]), np.quantile(mc.column("m0"), [0.1, 0.9]))
    infl = mc.influence("m0")
    assert set(infl) == set(mc.keys) and all(-1 <= v <= 1 for v in infl.values())
    with pytest.raises(gc.ArgumentError, match="unknown column"):
        mc.quantiles("speed")
    with pytest.raises(gc.ArgumentError, match=r"\[0, 1\]"):
        mc.quantiles("m0", 1.5)
    axes = mc.plot()
    assert axes.shape == (2, 2) and axes[0, 1].get_xlabel().endswith("(sampled)")


def test_monte_carlo_is_the_same_whatever_the_executor(uncertain):
    ref = gc.monte_carlo(glide_study, uncertain, n=24, seed=5)
    with ThreadPoolExecutor(2) as ex:
        thr = gc.monte_carlo(glide_study, uncertain, n=24, seed=5, executor=ex, chunks=5)
    with ProcessPoolExecutor(2) as ex:
        proc = gc.monte_carlo(glide_study, uncertain, n=24, seed=5, executor=ex)
    for other in (thr, proc):
        np.testing.assert_array_equal(other.values, ref.values)
        np.testing.assert_array_equal(other.results, ref.results)
        assert other.errors == ref.errors
    assert proc.executor.endswith("ProcessPoolExecutor") and ref.executor == "none"
    assert not np.array_equal(gc.monte_carlo(glide_study, uncertain, n=24, seed=6).values, ref.values)


def test_invalid_samples_and_bad_studies_do_not_stop_the_run():
    veh = gc.load_vehicle("slocum_shallow")
    # hull masses above 43 kg leave a negative buoyancy mass: those samples are not vehicles
    vu = veh.with_uncertainty({"m_h": {"min": 40.0, "max": 46.0}})
    mc = gc.monte_carlo(lambda v: v.m_h, vu, n=40, seed=0)
    bad = mc.values[:, 0] > 43.0
    assert bad.any() and (~bad).any()
    np.testing.assert_array_equal(mc.ok, ~bad)
    assert all("buoyancy mass" in mc.errors[i] for i in np.flatnonzero(bad))
    assert sum(mc.failures.values()) == int(bad.sum())
    np.testing.assert_allclose(mc.column("value"), mc.values[~bad, 0])
    fine = veh.with_uncertainty({"K_M": {"rel": 0.1}})
    with pytest.raises(gc.ArgumentTypeError, match="must return numbers"):
        gc.monte_carlo(lambda v: "speed", fine, n=3)
    with pytest.raises(gc.ArgumentTypeError, match="no number"):
        gc.monte_carlo(lambda v: {"a": "b"}, fine, n=3)
    with pytest.raises(gc.ArgumentError, match="uncertainty"):
        gc.monte_carlo(lambda v: 1.0, veh, n=3)
    with pytest.raises(gc.ArgumentTypeError, match="submit"):
        gc.monte_carlo(lambda v: 1.0, vu, n=3, executor=object())


@pytest.fixture(scope="module")
def lqr_two():
    """The slocum LQR dive-cycle loop with two uncertain coefficients (the two most influential)."""
    veh = gc.load_vehicle("slocum_shallow").with_uncertainty({"K_D0": {"rel": 0.5}, "K_L": {"rel": 0.4}})
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    ctrl = gc.lqr_glide(veh, glide, inputs="acceleration")
    return veh, ctrl, gc.robust_stability(ctrl, n=40, seed=1)


def _grid_worst(veh, ctrl, m=13):
    loop = gc.closed_loop(ctrl)
    (lo1, hi1), (lo2, hi2) = (veh.uncertainty[k].box(veh.params[k]) for k in ("K_D0", "K_L"))
    worst = -math.inf
    for a in np.linspace(lo1, hi1, m):
        for b in np.linspace(lo2, hi2, m):
            v = veh.with_overrides(K_D0=float(a), K_L=float(b))
            worst = max(worst, loop_poles(gc.with_vehicle(loop, v), loop.equilibrium).max_real)
    return worst


def test_worst_case_is_at_least_the_exhaustive_grids(lqr_two):
    veh, ctrl, rs = lqr_two
    grid = _grid_worst(veh, ctrl)
    wc = rs.worst_case
    assert wc.max_real >= grid - 1e-9
    assert wc.max_real >= np.max(rs.max_real)                      # no sample is worse than the worst case
    lo, hi = rs.box
    for k, v in wc.coefficients.items():
        j = rs.keys.index(k)
        assert lo[j] - 1e-12 <= v <= hi[j] + 1e-12
    # the worst case's pole is the loop's at those coefficients
    loop = gc.closed_loop(ctrl)
    lp = loop_poles(gc.with_vehicle(loop, veh.with_overrides(**wc.coefficients)), loop.equilibrium)
    assert lp.max_real == pytest.approx(wc.max_real, abs=1e-10)
    assert rs.probability == 1.0 and rs.nominal_max_real < 0 and rs.stable.all()


def test_margin_holds_below_and_fails_above(lqr_two):
    veh, ctrl, rs = lqr_two
    assert rs.margin_bounded and 1.0 < rs.margin < MARGIN_MAX
    loop = gc.closed_loop(ctrl)
    lo, hi = rs.box
    nom = np.array([veh.params[k] for k in rs.keys])

    def worst_corner(scale):
        worst = -math.inf
        for s1 in (-1, 1):
            for s2 in (-1, 1):
                u = np.array([s1, s2]) * scale
                x = np.where(u < 0, nom + u * (nom - lo), nom + u * (hi - nom))
                try:
                    v = veh.with_overrides(**dict(zip(rs.keys, map(float, x), strict=True)))
                    worst = max(worst, loop_poles(gc.with_vehicle(loop, v), loop.equilibrium).max_real)
                except gc.GlidectlError:
                    worst = math.inf
        return worst

    assert worst_corner(0.95 * rs.margin) < 0
    assert worst_corner(1.05 * rs.margin) >= 0          # here the first unstable vehicle is a corner


def test_sensitivities_are_the_slopes_of_the_dominant_pole(lqr_two):
    veh, ctrl, rs = lqr_two
    loop = gc.closed_loop(ctrl)
    lo, hi = rs.box
    j = rs.keys.index("K_D0")
    nom = veh.params["K_D0"]
    h = 0.02
    vals = []
    for s in (-h, h):
        x = nom + s * ((hi[j] - nom) if s > 0 else (nom - lo[j]))
        vals.append(loop_poles(gc.with_vehicle(loop, veh.with_overrides(K_D0=x)), loop.equilibrium).dominant)
    slope = (vals[1] - vals[0]) / (2 * h)
    assert rs.sensitivities["K_D0"].real == pytest.approx(slope.real, rel=0.02)
    assert rs.sensitivities["K_D0"].real > 0 > rs.sensitivities["K_L"].real
    axes = rs.plot()
    assert len(axes) == 3 and "stable in" in axes[0].get_title()
    assert "margin" in rs.summary()


def test_robust_stability_is_the_same_across_executors(lqr_two):
    _, ctrl, rs = lqr_two
    with ProcessPoolExecutor(2) as ex:
        par = gc.robust_stability(ctrl, n=40, seed=1, executor=ex, worst_case=False, margin=False)
    np.testing.assert_array_equal(par.max_real, rs.max_real)
    np.testing.assert_array_equal(par.values, rs.values)
    assert par.worst_case is None and par.margin is None and par.probability == rs.probability


def test_with_vehicle_equals_the_model_built_on_that_vehicle():
    veh = gc.load_vehicle("slocum_shallow")
    other = veh.with_overrides(K_M=-80.0, K_D0=2.5)
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=0.05)
    model, xe = gc.design_model(veh, glide, "acceleration")
    rebuilt = gc.with_vehicle(model, other)
    assert rebuilt.vehicle is other and type(rebuilt) is type(model)
    assert isinstance(model, gc.FixedActuatorModel)
    direct = gc.FixedActuatorModel(gc.GlidePathModel(gc.AccelerationControlledGlider(other), glide.gamma),
                                   model.actuators, model.values)
    X = xe + 0.01 * np.random.default_rng(0).standard_normal((5, xe.size))
    U = 0.001 * np.random.default_rng(1).standard_normal((5, len(model.input_names)))
    np.testing.assert_array_equal(rebuilt.rhs(X, U), direct.rhs(X, U))
    assert not np.allclose(rebuilt.rhs(X, U), model.rhs(X, U))
    with pytest.raises(gc.ArgumentTypeError, match="Vehicle"):
        gc.with_vehicle(model, "slocum_shallow")


def test_robust_stability_bad_input(lqr_two):
    veh, ctrl, _ = lqr_two
    v0 = gc.load_vehicle("slocum_shallow")
    plain = gc.lqr_glide(v0, gc.steady_glide(v0, 0.35, math.radians(-25.0), r_p3=0.05), inputs="acceleration")
    with pytest.raises(gc.ArgumentError, match="no \\[uncertainty\\] table"):
        gc.robust_stability(plain, n=2)
    with pytest.raises(gc.ArgumentError, match="does not have the coefficients"):
        gc.robust_stability(ctrl, n=2, vehicle=veh.with_overrides(K_M=-90.0))
    with pytest.raises(gc.ArgumentTypeError):
        gc.robust_stability("lqr", n=2)
    lqg = gc.lqg_glide(veh, ctrl.glide, ("theta", "Omega2", "m0", "r_P1"), {"theta": 1e-3, "Omega2": 1e-3,
                                                                          "m0": 1e-3, "r_P1": 1e-4},
                       inputs="acceleration")
    with pytest.raises(gc.ArgumentTypeError, match="state-feedback"):
        gc.robust_stability(lqg, n=2)


def test_a_controller_with_its_design_plant_pickles(lqr_two):
    import pickle

    _, ctrl, _ = lqr_two
    back = pickle.loads(pickle.dumps(ctrl))
    for name in ("A", "B", "C", "D"):
        np.testing.assert_array_equal(getattr(back.plant, name), getattr(ctrl.plant, name))
    assert back.plant.state_labels == ctrl.plant.state_labels and back.plant.input_labels == ctrl.plant.input_labels
    x = gc.closed_loop(ctrl).equilibrium + 0.01
    np.testing.assert_array_equal(gc.closed_loop(back).rhs(x), gc.closed_loop(ctrl).rhs(x))


def test_dive_cycle_with_its_own_design_vehicle_is_the_plain_dive_cycle():
    veh = gc.load_vehicle("slocum_shallow")
    a = gc.dive_cycle(veh, "lqr", cycles=1)
    b = gc.dive_cycle(veh, "lqr", cycles=1, design_vehicle=veh)
    np.testing.assert_array_equal(a.x, b.x)
    # another flying vehicle: same set points and gains, another flight
    c = gc.dive_cycle(veh.with_overrides(K_D0=2.6), "lqr", cycles=1, design_vehicle=veh)
    assert c.glides[0].speed == a.glides[0].speed and c.glides[0].m0 == a.glides[0].m0     # the design's glides
    assert not np.allclose(c.x[-1], a.x[-1])
    other = veh.with_actuators(m0={"min": -0.2, "max": 0.2, "rate": 0.01, "unit": "kg", "source": "a smaller pump"})
    with pytest.raises(gc.ArgumentError, match="other actuators"):
        gc.dive_cycle(veh, "lqr", cycles=1, design_vehicle=other)


def test_dive_cycle_ensemble_is_a_monte_carlo_of_the_nominal_design(uncertain):
    mc = gc.dive_cycle_ensemble(uncertain, n=4, seed=2, cycles=1)
    assert set(mc.names) == set(gc.robustness.DIVE_METRICS) and mc.ok.all()
    assert "designed on 'slocum_shallow'" in mc.study
    veh1 = uncertain.sample(4, seed=2).vehicles[1]
    run = gc.dive_cycle(veh1, "lqr", cycles=1, design_vehicle=uncertain)
    d = run.as_dict()
    j = mc.names.index("energy_per_km")
    serial = gc.dive_cycle_ensemble(uncertain, n=4, seed=2, cycles=1, batched=False)
    assert serial.results[1, j] == pytest.approx(1000.0 * d["energy_per_cycle"] / d["distance_per_cycle"],
                                                 rel=1e-12)
    # flown together (Dormand-Prince) or one by one (LSODA): the same metrics to the integration tolerance
    np.testing.assert_allclose(mc.results, serial.results, rtol=1e-3)
    k = mc.names.index("cycle_time")
    np.testing.assert_allclose(mc.results[:, k], serial.results[:, k], rtol=1e-4)
    with ProcessPoolExecutor(2) as ex:
        par = gc.dive_cycle_ensemble(uncertain, n=4, seed=2, cycles=1, executor=ex)
    np.testing.assert_array_equal(par.results, mc.results)      # each sample's flight is its own, in any batch
    with pytest.raises(gc.ArgumentError, match="design_vehicle"):
        gc.dive_cycle_ensemble(uncertain, n=2, design_vehicle=uncertain)
    with pytest.raises(gc.ArgumentError):
        gc.dive_cycle_ensemble(uncertain, n=2, controller="bangbang")


def test_mission_ensemble_flies_the_nominal_plan(uncertain):
    mission = gc.Mission(waypoints=[(800, 0)], depths=(5, 40), gamma=0.44, speed=0.35, surface_time=300,
                         arrival_radius=100)
    veh = gc.load_vehicle("slocum_shallow")
    plain = gc.fly_mission(veh, mission, model="fast")
    own = gc.fly_mission(veh, mission, model="fast", design_vehicle=veh)
    np.testing.assert_array_equal(own.states, plain.states)
    mc = gc.mission_ensemble(uncertain, mission, n=3, seed=1)
    assert set(mc.names) == set(gc.robustness.MISSION_METRICS) and mc.ok.all()
    v0 = uncertain.sample(3, seed=1).vehicles[0]
    run = gc.fly_mission(v0, mission, model="fast", design_vehicle=uncertain)
    assert mc.results[0, mc.names.index("energy_per_km")] == pytest.approx(run.energy_per_km, rel=1e-12)
    assert np.all(mc.column("waypoints_reached") == 1.0)
    assert mc.unit("mission_time") == "h" and mc.unit("K_M") == uncertain.units["K_M"]
    with pytest.raises(gc.ArgumentError, match="design_vehicle"):
        gc.mission_ensemble(uncertain, mission, n=2, design_vehicle=uncertain)
    with pytest.raises(gc.ArgumentTypeError, match="Mission"):
        gc.mission_ensemble(uncertain, "box", n=2)


def test_robust_stability_of_a_nonlinear_chapter6_law():
    """The chapter-6 buoyancy controller keeps its nominal law (equilibrium, gain) over +-30 % on the sphere's lift,
    drag and moment coefficients: every sample stays stable, and the worst case is no better than the nominal loop."""
    sph = gc.load_vehicle("sphere_ch5").with_uncertainty({k: {"rel": 0.3} for k in ("K_M", "K_D", "K_L")})
    ctrl = gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0)
    rs = gc.robust_stability(ctrl, n=30, seed=2, margin=False)
    assert rs.probability == 1.0 and rs.worst_case.max_real >= rs.nominal_max_real
    assert set(rs.sensitivities) == {"K_M", "K_D", "K_L"}
    # the sampled loops really are the sphere's at those coefficients, under the nominal law
    loop = gc.closed_loop(ctrl)
    v = sph.with_overrides(**dict(zip(rs.keys, map(float, rs.values[0]), strict=True)))
    lp = loop_poles(gc.with_vehicle(loop, v), loop.equilibrium)
    assert lp.max_real == pytest.approx(rs.max_real[0], abs=1e-12)
    assert np.max(np.abs(gc.with_vehicle(loop, v).rhs(lp.equilibrium))) < 1e-9


def test_a_box_with_no_equilibrium_at_a_corner_is_unstable_there():
    """With -80 % lift and +90 % parasitic drag the glide the LQR regulates to no longer exists near the nominal
    one: the worst case is that corner, reported as inf (no equilibrium), and the margin falls below the box."""
    veh = gc.load_vehicle("slocum_shallow").with_uncertainty({"K_D0": {"rel": 0.9}, "K_L": {"rel": 0.8}})
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    rs = gc.robust_stability(gc.lqr_glide(veh, glide, inputs="acceleration"), n=20, seed=0)
    assert rs.worst_case.max_real == math.inf and math.isnan(rs.worst_case.pole.real)
    assert rs.margin_bounded and 0.0 < rs.margin < 1.0
    with pytest.raises(gc.ModelError, match="no closed-loop equilibrium"):
        loop = gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration"))
        loop_poles(gc.with_vehicle(loop, veh.with_overrides(**rs.worst_case.coefficients)), loop.equilibrium)


def test_the_pitch_behaviour_loop_converges_and_its_positions_are_held_out():
    veh = gc.load_vehicle("slocum_shallow").with_uncertainty({"K_M": {"rel": 0.3}, "K_D0": {"rel": 0.3}})
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    beh = gc.GliderBehaviours(pitch_time=20.0)
    loop = beh.pitch_loop(veh, glide)
    xe = loop.equilibrium
    d = np.asarray(loop.rhs(xe))
    assert np.max(np.abs(d[2:])) < 1e-12 and d[0] > 0 and d[1] > 0          # gliding down and forward
    # the battery law: rate r_P3 (theta - theta_ref) / pitch_time, the dead zone's slope-1 branch
    x = xe.copy()
    x[2] += 0.01
    assert loop.law(x)[0] == pytest.approx(xe[8] * 0.01 / 20.0, rel=1e-12)
    assert loop.law(x)[0] == pytest.approx(xe[8] / 20.0 * dead_zone(0.01, 0.0), rel=1e-12)
    # from 3 deg of pitch error the loop returns to the glide's pitch and battery position
    x0 = xe.copy()
    x0[2] += math.radians(3.0)
    run = gc.simulate(loop, x0, 600.0, rtol=1e-8, atol=1e-10)
    assert abs(run.x[-1, 2] - xe[2]) < math.radians(0.05) and abs(run.x[-1, 6] - xe[6]) < 1e-4
    rs = gc.robust_stability(loop, n=40, seed=1, margin=False, corner_limit=4, starts=1, maxfev=40)
    assert rs.probability == 1.0 and rs.nominal_max_real < 0
    # x and z drift along the glide and nothing depends on them: held, with the fixed r_P3 and its rate
    A = gc.jacobians(lambda x, u: np.asarray(loop.rhs(x)), xe, np.zeros(0))[0]
    assert np.all(A[:, :2] == 0) and np.any(A[:2] != 0)
    kept = [2, 3, 4, 5, 6, 7, 10]
    assert rs.nominal_max_real == pytest.approx(np.max(np.linalg.eigvals(A[np.ix_(kept, kept)]).real), rel=1e-9)
    small_pump = veh.with_actuators(m0={"min": -0.05, "max": 0.05, "rate": 0.01, "unit": "kg", "source": "test"})
    with pytest.raises(gc.InfeasibleGlideError, match="m0"):
        beh.pitch_loop(small_pump, glide)                     # the glide needs more buoyancy than this pump has
    with pytest.raises(gc.ArgumentTypeError, match="SteadyGlide"):
        beh.pitch_loop(veh, "glide")

