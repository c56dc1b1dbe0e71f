"""The 3-D actuated glider (models/actuated3d.py) and the currents (environment.py): reductions to the fixed-mass
3-D model and to the longitudinal acceleration form, actuator limits under random commands, Galilean invariance in
a uniform current, steady turns against helix_trim, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.environment import CURRENT_MAX, Current, as_current
from glidectl.errors import ArgumentError, ArgumentTypeError, ModelError, VehicleFileError
from glidectl.models.actuated3d import ACTUATED3D_STATES, ActuatedGlider3D
from glidectl.models.glider3d import FixedMassGlider3D, R_to_ypr, quat_to_R, ypr_to_quat

SLOCUM = gc.load_vehicle("slocum_shallow")
ROLLER = SLOCUM.with_actuators(roll={"min": -0.6, "max": 0.6, "rate": 0.1, "unit": "rad", "source": "test"})


def _state(rng: np.random.Generator, plant: ActuatedGlider3D) -> np.ndarray:
    x = np.zeros(19)
    x[0:3] = rng.uniform(-100, 100, 3)
    x[3:7] = ypr_to_quat(rng.uniform(-3, 3), rng.uniform(-0.8, 0.8), rng.uniform(-0.5, 0.5))
    x[7:10] = [rng.uniform(0.1, 0.6), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05)]
    x[10:13] = rng.uniform(-0.05, 0.05, 3)
    x[13] = rng.uniform(plant.lower[0], plant.upper[0])
    x[15] = rng.uniform(plant.lower[1], plant.upper[1])
    x[17] = rng.uniform(plant.lower[2], plant.upper[2])
    x[18] = rng.uniform(plant.lower[3], plant.upper[3])
    return x


@pytest.mark.parametrize("veh", [SLOCUM, ROLLER], ids=["rudder", "roll"])
def test_battery_at_rest_reduces_to_the_fixed_mass_model(veh):
    plant = ActuatedGlider3D(veh)
    rng = np.random.default_rng(1)
    for _ in range(20):
        x = _state(rng, plant)
        f = plant.rhs(x, np.zeros(4))
        rp = plant.moving_mass(x)
        fixed = FixedMassGlider3D(veh, tuple(rp), x[17], rudder=x[18]).rhs(x[:13])
        np.testing.assert_allclose(f[:13], fixed, rtol=1e-12, atol=1e-14)


def test_the_vertical_plane_is_the_longitudinal_acceleration_form():
    """Battery moving along body-1 with acceleration w1, no roll: the 3-D accelerations are those of (2.33)."""
    plant = ActuatedGlider3D(SLOCUM)
    acc = gc.AccelerationControlledGlider(SLOCUM)
    rng = np.random.default_rng(2)
    for _ in range(20):
        theta, v1, v3, q2 = rng.uniform(-0.6, 0.6), rng.uniform(0.1, 0.5), rng.uniform(-0.05, 0.05), \
            rng.uniform(-0.05, 0.05)
        r1, rd1, m0, req = rng.uniform(-0.02, 0.02), rng.uniform(-0.002, 0.002), rng.uniform(-0.2, 0.2), \
            rng.uniform(-0.005, 0.005)
        x = np.zeros(19)
        x[3:7] = ypr_to_quat(0.0, theta, 0.0)
        x[7], x[9], x[11], x[13], x[14], x[17] = v1, v3, q2, r1, rd1, m0
        u = np.array([req, 0.0, 0.0, 0.0])
        f = plant.rhs(x, u)
        w1 = (plant.limited_rates(x, u)[0] - rd1) / plant.servo_time
        x2 = np.array([0.0, 0.0, theta, q2, v1, v3, r1, rd1, plant.rho, 0.0, m0])
        g = acc.rhs(x2, np.array([w1, 0.0, 0.0]))
        np.testing.assert_allclose([f[7], f[9], f[11]], [g[4], g[5], g[3]], rtol=1e-10, atol=1e-13)
        assert abs(f[8]) < 1e-14 and abs(f[10]) < 1e-14 and abs(f[12]) < 1e-14  # stays in the plane


@settings(max_examples=5, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_actuator_limits_hold_under_random_commands(seed):
    plant = ActuatedGlider3D(ROLLER)
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, 120.0, 10.0)
    cmds = rng.uniform(-3, 3, (times.size, 4)) * np.maximum(plant.rate_limit, 1e-3)

    def controller(t, x):
        return cmds[min(int(t // 10.0), len(cmds) - 1)]

    controller.switch_times = times[1:]
    x0 = np.zeros(19)
    x0[3:7] = ypr_to_quat(0.0, -0.4, 0.0)
    x0[7], x0[17] = 0.3, 0.05
    sim = gc.simulate(plant, x0, 120.0, controller, t_eval=np.linspace(0, 120, 601), rtol=1e-8, atol=1e-10)
    pos = plant.positions(sim.x)
    slack = 1e-6 * np.maximum(plant.upper - plant.lower, 1e-3)
    assert np.all(pos >= plant.lower - slack) and np.all(pos <= plant.upper + slack)
    for col, i in ((14, 0), (16, 1)):
        assert np.all(np.abs(sim.x[:, col]) <= plant.rate_limit[i] * (1 + 1e-6) + 1e-12)


def test_uniform_current_is_a_galilean_shift():
    """In a uniform current the motion through the water is unchanged and the track shifts by c t."""
    x0 = np.zeros(19)
    x0[3:7] = ypr_to_quat(0.3, -0.4, 0.1)
    x0[7], x0[17], x0[18] = 0.3, 0.06, 0.1
    te = np.linspace(0, 300, 31)
    still = gc.simulate(ActuatedGlider3D(SLOCUM), x0, 300.0, t_eval=te, rtol=1e-10, atol=1e-12)
    moving = gc.simulate(ActuatedGlider3D(SLOCUM, current=(0.2, -0.1)), x0, 300.0, t_eval=te, rtol=1e-10,
                         atol=1e-12)
    np.testing.assert_allclose(moving.x[:, 3:], still.x[:, 3:], atol=1e-8)
    shift = moving.x[:, :3] - still.x[:, :3]
    np.testing.assert_allclose(shift[:, 0], -0.1 * te, atol=1e-6)   # north
    np.testing.assert_allclose(shift[:, 1], 0.2 * te, atol=1e-6)    # east
    np.testing.assert_allclose(shift[:, 2], 0.0, atol=1e-9)


def test_time_varying_current_reaches_the_model_through_simulate():
    field = Current.field(lambda t, p: (0.0, 0.01 * t))
    plant = ActuatedGlider3D(SLOCUM, current=field)
    assert plant.time_varying
    x0 = np.zeros(19)
    x0[3:7] = ypr_to_quat(0.0, 0.0, 0.0)
    sim = gc.simulate(plant, x0, 10.0, t_eval=[0.0, 10.0], rtol=1e-10, atol=1e-12)
    still = gc.simulate(ActuatedGlider3D(SLOCUM), x0, 10.0, t_eval=[0.0, 10.0], rtol=1e-10, atol=1e-12)
    assert sim.x[-1, 0] - still.x[-1, 0] == pytest.approx(0.5 * 0.01 * 10.0 ** 2, rel=1e-6)   # integral of 0.01 t


@pytest.mark.parametrize(("veh", "axis", "setting"), [(ROLLER, "roll", 0.4), (SLOCUM, "rudder", 0.3),
                                                     (ROLLER, "roll", -0.3)])
@pytest.mark.parametrize("gamma_deg", [-25.0, 25.0])
def test_simulated_turn_matches_helix_trim(veh, axis, setting, gamma_deg):
    """A held roll or rudder setting: the simulated turn's radius and drop per turn agree with helix_trim."""
    plant = ActuatedGlider3D(veh)
    g = gc.steady_glide(veh, 0.35, math.radians(gamma_deg), r_p3=plant.rho)
    if axis == "roll":
        h = gc.helix_trim(veh, (g.r_p1, plant.rho * math.sin(setting), plant.rho * math.cos(setting)), g.m0)
    else:
        h = gc.helix_trim(veh, (g.r_p1, 0.0, plant.rho), g.m0, rudder=setting)
    assert h.stable
    x0 = np.zeros(19)
    x0[3:7] = ypr_to_quat(0.0, g.theta, 0.0)
    x0[7], x0[9], x0[13], x0[17] = g.v1, g.v3, g.r_p1, g.m0
    x0[15 if axis == "roll" else 18] = setting
    t_settle = 1500.0
    T = t_settle + 1.5 * h.period
    te = np.linspace(t_settle, T, 1500)
    sim = gc.simulate(plant, x0, T, t_eval=te, rtol=1e-9, atol=1e-11, max_steps=200_000)
    xy = sim.x[:, :2]
    # radius from a least-squares circle fit of the horizontal track over the last turn and a half
    A = np.c_[2 * xy, np.ones(len(xy))]
    sol, *_ = np.linalg.lstsq(A, (xy ** 2).sum(1), rcond=None)
    radius = math.sqrt(sol[2] + sol[0] ** 2 + sol[1] ** 2)
    drop = (sim.x[-1, 2] - sim.x[0, 2]) / (te[-1] - te[0]) * h.period
    assert radius == pytest.approx(h.radius, rel=0.02)
    assert drop == pytest.approx(h.pitch, rel=0.02)


def test_helix_trim_checks_the_rudder_range():
    g = gc.steady_glide(SLOCUM, 0.35, math.radians(-25), r_p3=0.05)
    with pytest.raises(gc.InfeasibleGlideError, match="rudder"):
        gc.helix_trim(SLOCUM, (g.r_p1, 0.0, 0.05), g.m0, rudder=0.5)


def test_current_kinds_and_values():
    u = as_current((0.1, -0.2))
    np.testing.assert_allclose(u.at(0.0, [[0, 0, 10], [5, 5, 50]]), [[0.1, -0.2], [0.1, -0.2]])
    np.testing.assert_allclose(u.velocity(0.0, np.zeros(3)), [-0.2, 0.1, 0.0])   # north, east, down
    p = Current.profile([0, 50, 100], [0.2, 0.0, -0.2], [0.0, 0.1, 0.0])
    np.testing.assert_allclose(p.at(0.0, [[0, 0, 25], [0, 0, 150], [0, 0, -3]]),
                               [[0.1, 0.05], [-0.2, 0.0], [0.2, 0.0]])
    f = as_current(lambda t, pos: (pos[0] * 1e-4, t * 1e-3))
    np.testing.assert_allclose(f.at(2.0, [100.0, 0.0, 0.0]), [0.01, 0.002])
    assert as_current(None).still and not p.still and f.time_varying and not p.time_varying


@pytest.mark.parametrize(("make", "err", "match"), [
    (lambda: as_current((CURRENT_MAX, 1.0)), ArgumentError, "faster than any ocean current"),
    (lambda: as_current("north"), ArgumentTypeError, "current must be"),
    (lambda: as_current((0.1, 0.2, 0.3)), ArgumentTypeError, "current must be"),
    (lambda: Current.profile([0, 10], [0.1], [0.1]), ArgumentError, "depths"),
    (lambda: Current.profile([10, 0], [0.1, 0.1], [0.1, 0.1]), ArgumentError, "increasing"),
    (lambda: Current.field(3.0), ArgumentTypeError, "callable"),
    (lambda: as_current(lambda t, p: (np.nan, 0.0)).at(0.0, [0, 0, 0]), ArgumentError, "finite"),
    (lambda: as_current(lambda t, p: 0.1).at(0.0, [0, 0, 0]), ArgumentError, "pair"),
])
def test_bad_currents_are_refused(make, err, match):
    with pytest.raises(err, match=match):
        make()


def test_vehicle_file_checks_for_roll_and_rudder():
    with pytest.raises(VehicleFileError, match="cannot also translate"):
        SLOCUM.with_actuators(roll={"min": -0.5, "max": 0.5, "rate": 0.1},
                              r_P2={"min": -0.01, "max": 0.01, "rate": 0.001})
    with pytest.raises(VehicleFileError, match="K_SF_rudder"):
        gc.load_vehicle("slocum_ch8").with_actuators(rudder={"min": -0.4, "max": 0.4, "rate": 0.1})
    with pytest.raises(VehicleFileError, match="rho = r_P3 > 0"):
        gc.load_vehicle("sphere_ch5").with_actuators(roll={"min": -0.5, "max": 0.5, "rate": 0.1})


def test_model_refuses_what_it_cannot_move():
    with pytest.raises(ModelError, match="m0"):
        ActuatedGlider3D(gc.load_vehicle("slocum_ch8"))
    with pytest.raises(ModelError, match="translates the battery along r_P3"):
        ActuatedGlider3D(SLOCUM.with_actuators(r_P3={"min": 0.0, "max": 0.06, "rate": 0.001}))
    with pytest.raises(gc.InfeasibleGlideError, match="outside the range"):
        ActuatedGlider3D(SLOCUM).check_state(np.r_[np.zeros(17), 1.0, 0.0])


def test_states_are_named_and_attitude_is_consistent():
    assert len(ACTUATED3D_STATES) == 19 and ACTUATED3D_STATES[15] == "roll"
    q = ypr_to_quat(0.7, -0.3, 0.2)
    np.testing.assert_allclose(R_to_ypr(quat_to_R(q)), [0.7, -0.3, 0.2], atol=1e-14)
    x = np.zeros(19)
    x[3:7] = q
    theta, psi = gc.missions.pitch_heading(x)
    assert theta == pytest.approx(-0.3, abs=1e-14) and psi == pytest.approx(0.7, abs=1e-14)


def test_a_compressible_hull_in_a_stratified_sea_changes_buoyancy_with_depth():
    veh = SLOCUM.with_hydrodynamics(compressibility=3e-10)
    veh = gc.Vehicle(**{**{f: getattr(veh, f) for f in ("name", "kind", "title", "params", "sources", "path",
                                                           "overrides", "notes", "actuators", "law")},
                        "density_profile": ((0.0, 100.0), (1022.0, 1027.0))})
    plant = ActuatedGlider3D(veh)
    z = 80.0
    dm = float(gc.excess_mass(veh, z, 0.0) - gc.excess_mass(veh, 0.0, 0.0))
    assert plant.buoyancy_change(z) == pytest.approx(dm, rel=1e-9)
    assert abs(dm) > 1e-3                         # a real effect: grams at 80 m
    rng = np.random.default_rng(5)
    x = _state(rng, plant)
    x[2] = z
    at_depth = plant.rhs(x, np.zeros(4))
    x_surface = x.copy()
    x_surface[2], x_surface[17] = 0.0, x[17] + dm
    np.testing.assert_allclose(at_depth[7:13], plant.rhs(x_surface, np.zeros(4))[7:13], rtol=1e-12, atol=1e-15)
    assert ActuatedGlider3D(SLOCUM).buoyancy_change(z) == 0.0


def test_gridded_current_interpolates_and_reads_an_xarray_dataset():
    import xarray as xr
    east, north = np.array([0.0, 1000.0, 2000.0]), np.array([0.0, 500.0])
    E, N = np.meshgrid(east, north)
    u, v = 1e-4 * E, 2e-4 * N                       # a linear field: interpolation is exact inside the grid
    c = Current.gridded(east, north, u, v)
    np.testing.assert_allclose(c.at(0.0, [750.0, 250.0, 30.0]), [0.075, 0.05], atol=1e-12)
    np.testing.assert_allclose(c.at(0.0, [5000.0, -100.0, 0.0]), [0.2, 0.0], atol=1e-12)    # held at the edges
    assert not c.time_varying
    times = np.array([0.0, 3600.0])
    ut = np.stack([u, 2 * u])
    vt = np.stack([v, v])
    ds = xr.Dataset({"u": (("time", "north", "east"), ut), "v": (("time", "north", "east"), vt)},
                    coords={"time": times, "north": north, "east": east})
    cd = Current.from_dataset(ds)
    assert cd.time_varying
    np.testing.assert_allclose(cd.at(1800.0, [1000.0, 0.0, 0.0]), [0.15, 0.0], atol=1e-12)
    with pytest.raises(ArgumentError, match="dimensions"):
        Current.from_dataset(ds.transpose("east", "north", "time"))
    with pytest.raises(ArgumentError, match="shape"):
        Current.gridded(east, north, u[:, :2], v)
