"""Glide envelope (issue 16 part 3) and trims that respect the actuator table (issue 16 part 1, trims).

The envelope must agree point by point with ``steady_glide`` plus the actuator limits; binding codes are checked at
points built to violate one limit; a property test checks the trim equations at every feasible point.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.models.longitudinal import LongitudinalGlider
from glidectl.trim.envelope import BINDING_LABELS

ROGUE = gc.load_vehicle("rogue")
SLOCUM = gc.load_vehicle("slocum_ch8")
# the issue's actuator table; r_P3 fixed at the preset's own 4 cm (a fixed actuator must agree with the file's
# r_P3 = 0.04 m, so the issue's 3.5 cm cannot be combined with this preset)
SLOCUM_ACT = SLOCUM.with_actuators(
    m0={"min": -0.25, "max": 0.25, "rate": 0.01}, r_P1={"min": -0.025, "max": 0.025, "rate": 0.005},
    r_P3={"fixed": 0.04})
# ROGUE with plausible, deliberately asymmetric ranges (ours) so that every limit binds somewhere
ROGUE_ACT = ROGUE.with_actuators(m0={"min": -0.6, "max": 1.0, "rate": 0.02},
                                 r_P1={"min": -0.01, "max": 0.02, "rate": 0.005})
CODE = {lab: k for k, lab in enumerate(BINDING_LABELS)}


def _free(veh: gc.Vehicle) -> gc.Vehicle:
    """The same vehicle without the limits the envelope applies."""
    return veh.with_actuators(m0=None, r_P1=None, r_P3=None)


@pytest.mark.parametrize(("veh", "r_p3"), [(ROGUE, 0.05), (ROGUE_ACT, 0.05), (SLOCUM_ACT, None)],
                         ids=["rogue", "rogue+actuators", "slocum_ch8+actuators"])
def test_envelope_agrees_point_by_point_with_steady_glide_plus_limits(veh, r_p3):
    speeds = np.array([0.05, 0.2, 0.35, 0.6, 1.0, 2.0])
    gammas = np.radians(np.r_[-89.9, -70.0, -45.0, -25.0, -12.0, -3.0, 0.0, 2.0, 8.5, 20.0, 45.0, 80.0, 90.0])
    env = gc.glide_envelope(veh, speeds, gammas, r_p3=r_p3)
    assert env.feasible.shape == env.binding.shape == env.m0.shape == (speeds.size, gammas.size)
    r3 = env.r_p3 if r_p3 is None else r_p3
    m0_act, rp1_act = veh.actuators.get("m0"), veh.actuators.get("r_P1")
    kinds = set()
    for i, V in enumerate(speeds):
        for j, g in enumerate(gammas):
            try:  # the glide without limits
                free = gc.steady_glide(_free(veh), float(V), float(g), r_p3=r3)
            except gc.InfeasibleGlideError:
                assert not env.feasible[i, j]
                assert env.binding[i, j] in (CODE["no glide"], CODE["no trim"])
                assert math.isnan(env.m0[i, j]) and math.isnan(env.r_p1[i, j]) and math.isnan(env.alpha[i, j])
                kinds.add("none")
                continue
            assert env.m0[i, j] == pytest.approx(free.m0, rel=1e-12, abs=1e-15)
            assert env.r_p1[i, j] == pytest.approx(free.r_p1, rel=1e-12, abs=1e-15)
            assert env.alpha[i, j] == pytest.approx(free.alpha, rel=1e-12, abs=1e-15)
            assert env.theta[i, j] == pytest.approx(free.theta, rel=1e-12, abs=1e-15)
            assert env.horizontal_speed[i, j] == pytest.approx(V * math.cos(g), rel=1e-12)
            assert env.vertical_speed[i, j] == pytest.approx(-V * math.sin(g), rel=1e-12, abs=1e-15)
            in_range = ((m0_act is None or m0_act.contains(free.m0))
                        and (rp1_act is None or rp1_act.contains(free.r_p1)))
            assert env.feasible[i, j] == in_range
            try:  # the glide with limits: exactly the feasible points
                limited = gc.steady_glide(veh, float(V), float(g), r_p3=r3)
                assert env.feasible[i, j]
                assert limited.m0 == free.m0
                kinds.add("feasible")
            except gc.InfeasibleGlideError as exc:
                assert not env.feasible[i, j]
                assert "actuator" in str(exc)
                assert BINDING_LABELS[env.binding[i, j]].split()[0] in ("m0", "r_P1")
                kinds.add("limited")
    assert "feasible" in kinds and "none" in kinds
    if veh.actuators:
        assert "limited" in kinds


def test_slocum_with_the_issue_actuators_has_a_nonempty_feasible_region():
    speeds = np.linspace(0.05, 1.0, 40)
    gammas = np.radians(np.linspace(-60, 60, 41))
    env = gc.glide_envelope(SLOCUM_ACT, speeds, gammas)
    assert env.r_p3 == 0.04
    assert 0 < env.feasible.sum() < env.feasible.size
    assert np.all(np.abs(env.m0[env.feasible]) <= 0.25 * (1 + 1e-9))
    assert np.all(np.abs(env.r_p1[env.feasible]) <= 0.025 * (1 + 1e-9))
    counts = env.counts()
    assert sum(counts.values()) == env.feasible.size and counts["none"] == int(env.feasible.sum())
    # slow, steep glides need too much pitch; fast glides need too much buoyancy (m0 ~ V^2)
    assert {"m0 max", "m0 min", "r_P1 min", "r_P1 max", "no glide"} <= {k for k, v in counts.items() if v}


def _limits_around(veh, V, g, **offsets):
    """Vehicle whose m0 / r_P1 range is ``value + |value| * (a, b)`` for the trim value of the glide (V, g)."""
    free = gc.steady_glide(veh, V, g, r_p3=0.05)
    acts = {}
    for name, value in (("m0", free.m0), ("r_P1", free.r_p1)):
        a, b = offsets.get(name, (-10.0, 10.0))
        acts[name] = {"min": value + abs(value) * a, "max": value + abs(value) * b}
    return veh.with_actuators(**acts), free


@pytest.mark.parametrize(("offsets", "expect"), [
    ({}, "none"),
    ({"m0": (-0.5, -0.1)}, "m0 max"),     # range entirely below the needed m0
    ({"m0": (0.1, 0.5)}, "m0 min"),       # entirely above
    ({"r_P1": (-0.5, -0.1)}, "r_P1 max"),
    ({"r_P1": (0.1, 0.5)}, "r_P1 min"),
    # both out: m0 by 0.1/0.4 = 25 % of its range width, r_P1 by 1.0/0.2 = 500 %: r_P1 binds, and the reverse
    ({"m0": (-0.5, -0.1), "r_P1": (1.0, 1.2)}, "r_P1 min"),
    ({"m0": (1.0, 1.2), "r_P1": (-0.5, -0.1)}, "m0 min"),
])
def test_binding_codes_at_constructed_points(offsets, expect):
    V, g = 0.4, math.radians(-30.0)
    veh, _ = _limits_around(ROGUE, V, g, **offsets)
    env = gc.glide_envelope(veh, [V], [g, 0.0], r_p3=0.05)
    assert env.binding_labels[0, 0] == expect
    assert env.feasible[0, 0] == (expect == "none")
    assert env.binding_labels[0, 1] == "no glide"  # gamma = 0: no steady glide (2.26)


def test_no_trim_code_when_the_moment_balance_needs_an_implausible_mass_position():
    # a near-vertical glide at r_p3 given: r_P1 = (a_perp - r_p3 sin theta) / cos theta blows up
    env = gc.glide_envelope(ROGUE, [0.3], [math.radians(-89.999999)], r_p3=0.05)
    with pytest.raises(gc.InfeasibleGlideError, match=r"R_P_MAX|90 deg"):
        gc.steady_glide(ROGUE, 0.3, math.radians(-89.999999), r_p3=0.05)
    assert env.binding_labels[0, 0] == "no trim" and not env.feasible[0, 0] and math.isnan(env.m0[0, 0])


@settings(max_examples=30, deadline=None)
@given(speeds=st.lists(st.floats(0.01, 3.0), min_size=1, max_size=8),
       gammas=st.lists(st.floats(-1.55, 1.55), min_size=1, max_size=8),
       which=st.sampled_from(["rogue", "slocum"]))
def test_every_feasible_point_satisfies_the_trim_equations_and_the_limits(speeds, gammas, which):
    veh, r3 = (ROGUE_ACT, 0.05) if which == "rogue" else (SLOCUM_ACT, None)
    env = gc.glide_envelope(veh, speeds, gammas, r_p3=r3)
    i, j = np.nonzero(env.feasible)
    if i.size == 0:
        return
    V, gam = env.speeds[i], env.gammas[j]
    m0, rp1, alpha, theta = env.m0[i, j], env.r_p1[i, j], env.alpha[i, j], env.theta[i, j]
    v1, v3 = V * np.cos(alpha), V * np.sin(alpha)
    mbar, g = veh.mbar, veh.g
    x = np.stack([0 * V, 0 * V, theta, 0 * V, v1, v3, rp1, np.full_like(V, env.r_p3), mbar * v1, mbar * v3, m0], -1)
    f = LongitudinalGlider(veh).rhs(x, np.zeros((V.size, 3)))
    m1, m3 = veh.mass(1, m0), veh.mass(3, m0)
    force = np.maximum(np.abs(m0) * g, (veh.K_D0 + veh.K_D * alpha**2) * V**2)  # weight and drag
    torque = mbar * g * np.hypot(rp1, env.r_p3) + np.abs((veh.K_M0 + veh.K_M * alpha) * V**2)
    assert np.all(np.abs(f[:, 4] * m1) <= 1e-8 * force)  # (2.18)
    assert np.all(np.abs(f[:, 5] * m3) <= 1e-8 * force)  # (2.19)
    assert np.all(np.abs(f[:, 3] * veh.J2) <= 1e-8 * torque)  # (2.20)
    assert np.all(np.abs(f[:, 6:8]) <= 1e-8 * V[:, None])  # (2.21)-(2.22)
    np.testing.assert_allclose(theta, gam + alpha, rtol=0, atol=1e-15)
    assert np.all(veh.actuators["m0"].contains(m0)) and np.all(veh.actuators["r_P1"].contains(rp1))
    assert np.all(np.sign(m0) == -np.sign(gam))  # heavy glides down, light glides up
    np.testing.assert_allclose(np.hypot(env.horizontal_speed[i, j], env.vertical_speed[i, j]), V, rtol=1e-12)


@pytest.mark.parametrize(("kwargs", "exc", "match"), [
    ({"speeds": [[0.3, 0.4]]}, gc.ArgumentError, "dimension"),
    ({"gammas": np.zeros((2, 2)) - 0.5}, gc.ArgumentError, "dimension"),
    ({"speeds": [0.3, np.nan]}, gc.ArgumentError, "finite"),
    ({"gammas": [np.inf]}, gc.ArgumentError, "finite"),
    ({"speeds": []}, gc.ArgumentError, "at least 1"),
    ({"gammas": np.array([])}, gc.ArgumentError, "at least 1"),
    ({"speeds": [0.0, 0.3]}, gc.ArgumentError, r"\(0, 100\]"),
    ({"speeds": [-0.3]}, gc.ArgumentError, r"\(0, 100\]"),
    ({"speeds": [101.0]}, gc.ArgumentError, r"\(0, 100\]"),
    ({"speeds": "fast"}, gc.ArgumentTypeError, "real numbers"),
    ({"gammas": ["a", "b"]}, gc.ArgumentTypeError, "real numbers"),
    ({"gammas": [0.3 + 1j]}, gc.ArgumentTypeError, "real numbers"),
    ({"r_p3": "0.05"}, gc.ArgumentTypeError, "r_p3"),
    ({"r_p3": 11.0}, gc.ArgumentError, "r_p3"),
    ({"veh": "rogue"}, gc.ArgumentTypeError, "Vehicle"),
    ({"veh": gc.load_vehicle("dc8_ctol")}, gc.ModelError, "ctol_glide"),
    ({"veh": gc.load_vehicle("sphere_ch5")}, gc.ModelError, "mbar"),
    ({"veh": ROGUE, "r_p3": None}, gc.ArgumentError, "r_p3="),
    ({"veh": SLOCUM_ACT, "r_p3": 0.05}, gc.InfeasibleGlideError, "actuator 'r_P3'"),
    ({"veh": ROGUE.with_overrides(K_D=0.0)}, gc.GlidectlError, "K_D"),
])
def test_bad_inputs_raise_the_specific_error(kwargs, exc, match):
    args = {"veh": ROGUE, "speeds": [0.3], "gammas": [-0.5], "r_p3": 0.05, **kwargs}
    with pytest.raises(exc, match=match):
        gc.glide_envelope(args.pop("veh"), args.pop("speeds"), args.pop("gammas"), **args)


def test_result_is_frozen_and_carries_provenance_and_grid():
    env = gc.glide_envelope(SLOCUM_ACT, [0.2, 0.4], [-0.5, 0.5])
    assert env.provenance == SLOCUM_ACT.provenance and env.vehicle is SLOCUM_ACT
    assert env.m0_bounds == (-0.25, 0.25) and env.r_p1_bounds == (-0.025, 0.025)
    np.testing.assert_array_equal(env.speeds, [0.2, 0.4])
    with pytest.raises(dataclasses.FrozenInstanceError):
        env.r_p3 = 0.0
    with pytest.raises(ValueError, match="read-only"):
        env.m0[0, 0] = 1.0
    assert "feasible" in env.summary()
    gb = gc.permissible_gamma(SLOCUM_ACT)
    assert env.gamma_bounds == gb


def test_plot_shows_the_polar_with_a_legend_of_binding_limits():
    import matplotlib

    matplotlib.use("Agg", force=False)
    env = gc.glide_envelope(SLOCUM_ACT, np.linspace(0.1, 1.0, 12), np.radians(np.linspace(-60, 60, 13)))
    ax = env.plot()
    fig = ax.figure
    try:
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert any(lab.startswith("feasible") for lab in labels)
        assert any("binds" in lab for lab in labels)
        assert "[m/s]" in ax.get_xlabel() and "positive down" in ax.get_ylabel()
        assert ax.yaxis_inverted()
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


# ------------------------------------------------------------------------------------------------ steady_glide
def test_steady_glide_refuses_a_trim_outside_the_actuator_ranges():
    V, g = 1.0, math.radians(-30.0)
    free = gc.steady_glide(SLOCUM, V, g, r_p3=0.04)
    assert free.m0 > 0.25  # too heavy for the issue's pump
    with pytest.raises(gc.InfeasibleGlideError, match=r"actuator 'm0'.*max 0.25 kg"):
        gc.steady_glide(SLOCUM_ACT, V, g, r_p3=0.04)
    only_rp1 = SLOCUM_ACT.with_actuators(m0=None)
    V2, g2 = 0.3, math.radians(-70.0)
    need = gc.steady_glide(SLOCUM, V2, g2, r_p3=0.04).r_p1
    assert abs(need) > 0.025
    side = "max" if need > 0 else "min"
    with pytest.raises(gc.InfeasibleGlideError, match=rf"actuator 'r_P1'.*{side} "):
        gc.steady_glide(only_rp1, V2, g2, r_p3=0.04)
    with pytest.raises(gc.InfeasibleGlideError, match=r"actuator 'r_P3'.*fixed setting 0.04"):
        gc.steady_glide(SLOCUM_ACT, 0.3, math.radians(-30.0), r_p3=0.03)
    ok = gc.steady_glide(SLOCUM_ACT, 0.3, math.radians(-30.0), r_p3=0.04)
    assert abs(ok.m0) <= 0.25 and abs(ok.r_p1) <= 0.025


def test_steady_glide_without_an_actuator_table_is_unchanged():
    assert not ROGUE.actuators
    g = gc.steady_glide(ROGUE, 2.0, math.radians(-45.0), r_p3=0.05)  # m0 of several kg: no limit applies
    assert g.m0 > 5.0


def test_steady_glide_takes_scalars_and_points_arrays_to_glide_envelope():
    a = gc.steady_glide(ROGUE, np.float64(0.3), np.array(-0.5), r_p3=np.array(0.05))
    b = gc.steady_glide(ROGUE, 0.3, -0.5, r_p3=0.05)
    assert a == b
    for bad in ({"speed": np.array([0.3, 0.4])}, {"gamma": [-0.5]}, {"speed": np.array([0.3])},
                {"r_p3": (0.05,)}):
        args = {"speed": 0.3, "gamma": -0.5, "r_p3": 0.05, **bad}
        with pytest.raises(gc.ArgumentTypeError, match="glide_envelope"):
            gc.steady_glide(ROGUE, **args)


# ------------------------------------------------------------------------------------------------ helices
def test_helix_trim_refuses_settings_outside_the_actuator_ranges():
    with pytest.raises(gc.InfeasibleGlideError, match="actuator 'm0'"):
        gc.helix_trim(SLOCUM_ACT, (0.015, 0.01, 0.04), 0.3)
    with pytest.raises(gc.InfeasibleGlideError, match="actuator 'r_P3'"):
        gc.helix_trim(SLOCUM_ACT, (0.015, 0.01, 0.05), 0.2)
    with pytest.raises(gc.InfeasibleGlideError, match="actuator 'r_P1'"):
        gc.helix_trim(SLOCUM_ACT, (0.03, 0.01, 0.04), 0.2)


def test_design_helix_takes_its_bounds_from_the_actuator_table():
    h = gc.helix_trim(SLOCUM_ACT, (0.015, 0.01, 0.04), 0.2)
    d = gc.design_helix(SLOCUM_ACT, radius=h.radius * 1.2, pitch=h.pitch * 0.9)
    assert d.bounds == ((-0.025, 0.025), gc.trim.DEFAULT_R_P_BOUNDS[1], (0.04, 0.04), (-0.25, 0.25))
    assert d.r_p[2] == 0.04  # the fixed axis is not moved
    assert -0.025 <= d.r_p[0] <= 0.025 and -0.25 <= d.m0 <= 0.25
    assert d.helix.radius == pytest.approx(h.radius * 1.2, rel=1e-6)
    assert d.helix.pitch == pytest.approx(h.pitch * 0.9, rel=1e-6)


def test_design_helix_refuses_bounds_outside_the_actuator_ranges():
    with pytest.raises(gc.ArgumentError, match=r"m0_bounds.*actuator 'm0'"):
        gc.design_helix(SLOCUM_ACT, radius=50.0, pitch=100.0, m0_bounds=(-0.5, 0.5))
    with pytest.raises(gc.ArgumentError, match=r"r_p_bounds\[2\].*actuator 'r_P3'.*fixed at 0.04"):
        gc.design_helix(SLOCUM_ACT, radius=50.0, pitch=100.0, r_p_bounds=((-0.02, 0.02), (-0.05, 0.05), (0, 0.08)))
    with pytest.raises(gc.ArgumentError, match="every control"):
        gc.design_helix(SLOCUM_ACT, radius=50.0, pitch=100.0, r_p_bounds=((0.01, 0.01), (0.0, 0.0), (0.04, 0.04)),
                        m0_bounds=(0.2, 0.2))


def test_design_helix_without_a_table_keeps_the_default_bounds():
    assert not SLOCUM.actuators
    from glidectl.trim.helix_design import _actuator_bounds

    rb, mb = _actuator_bounds(SLOCUM, None, None)
    assert tuple(map(tuple, rb)) == gc.trim.DEFAULT_R_P_BOUNDS and tuple(mb) == gc.trim.DEFAULT_M0_BOUNDS
    one_sided = SLOCUM.with_actuators(m0=gc.Actuator("m0", max=0.3))
    rb, mb = _actuator_bounds(one_sided, None, None)
    assert tuple(mb) == (gc.trim.DEFAULT_M0_BOUNDS[0], 0.3)
