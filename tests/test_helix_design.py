"""Inverse helix design and helix stability versus bottom-heaviness (§8.3)."""

from __future__ import annotations

import numpy as np
import pytest

import glidectl as gc
from glidectl.analysis.helix_stability import mass_position_at_rbh

SLOCUM = gc.load_vehicle("slocum_ch8")
NOMINAL_83 = (0.02, -0.02, 0.04)


@pytest.mark.parametrize("target", [{"radius": 50.0, "pitch": 150.0}, {"radius": 30.0, "speed": 0.6},
                                    {"radius": 50.0, "pitch": -150.0}])
def test_design_meets_targets_with_a_stable_helix(target):
    d = gc.design_helix(SLOCUM, **target)
    h = gc.helix_trim(SLOCUM, d.r_p, d.m0)  # independent re-trim at the returned controls
    assert h.radius == pytest.approx(target["radius"], rel=1e-6)
    if "pitch" in target:
        assert h.pitch == pytest.approx(target["pitch"], rel=1e-6)
        assert np.sign(d.m0) == np.sign(target["pitch"])  # descending helices need a heavy glider
    else:
        assert h.speed == pytest.approx(target["speed"], rel=1e-6)
    assert np.max(h.eigenvalues.real) < 0
    for x, (lo, hi) in zip(d.r_p, gc.trim.helix_design.DEFAULT_R_P_BOUNDS, strict=True):
        assert lo <= x <= hi
    assert d.error <= 1e-6


def test_design_recovers_the_thesis_helix():
    d = gc.design_helix(SLOCUM, radius=66.5996, pitch=206.21)
    assert d.helix.radius == pytest.approx(66.5996, rel=1e-6)


def test_infeasible_design_says_so():
    with pytest.raises(gc.InfeasibleGlideError, match="no stable helix"):
        gc.design_helix(SLOCUM, radius=1.0, pitch=1000.0, n_starts=2)


def test_design_bad_inputs():
    with pytest.raises(gc.GlidectlError, match="exactly one"):
        gc.design_helix(SLOCUM, radius=50.0)
    with pytest.raises(gc.GlidectlError, match="exactly one"):
        gc.design_helix(SLOCUM, radius=50.0, pitch=100.0, speed=0.5)
    with pytest.raises(gc.GlidectlError, match="radius"):
        gc.design_helix(SLOCUM, radius=-5.0, pitch=100.0)
    with pytest.raises(gc.GlidectlError, match="bounds"):
        gc.design_helix(SLOCUM, radius=50.0, pitch=100.0, m0_bounds=(0.5, 0.1))


@pytest.mark.parametrize(("kw", "err", "match"), [
    ({}, gc.ArgumentError, "exactly one"),
    ({"pitch": 100.0, "speed": 0.5}, gc.ArgumentError, "exactly one"),
    ({"pitch": 100.0, "radius": -5.0}, gc.ArgumentError, "radius"),
    ({"pitch": 100.0, "radius": "10"}, gc.ArgumentTypeError, "radius"),
    ({"pitch": 100.0, "radius": None}, gc.ArgumentTypeError, "radius"),
    ({"pitch": 100.0, "radius": 1e300}, gc.ArgumentError, "radius"),
    ({"pitch": "5"}, gc.ArgumentTypeError, "pitch"),
    ({"pitch": 0.0}, gc.ArgumentError, "pitch"),
    ({"pitch": float("nan")}, gc.ArgumentError, "pitch"),
    ({"speed": 0.0}, gc.ArgumentError, "speed"),
    ({"speed": 1e200}, gc.ArgumentError, "speed"),
    ({"pitch": 100.0, "r_p_bounds": 5}, gc.ArgumentError, "r_p_bounds"),
    ({"pitch": 100.0, "r_p_bounds": ((0, 1e9), (0, 1), (0, 1))}, gc.ArgumentError, "R_P_MAX"),
    ({"pitch": 100.0, "m0_bounds": (0, "a")}, gc.ArgumentTypeError, "m0_bounds"),
    ({"pitch": 100.0, "m0_bounds": (0.1, float("inf"))}, gc.ArgumentError, "m0_bounds"),
    ({"pitch": 100.0, "n_starts": 0}, gc.ArgumentError, "n_starts"),
    ({"pitch": 100.0, "n_starts": 10**9}, gc.ArgumentError, "n_starts"),
    ({"pitch": 100.0, "n_starts": 2.0}, gc.ArgumentTypeError, "n_starts"),
    ({"pitch": 100.0, "tol": -1.0}, gc.ArgumentError, "tol"),
    ({"pitch": 100.0, "stability_margin": float("nan")}, gc.ArgumentError, "stability_margin"),
    ({"pitch": 100.0, "seed": -1}, gc.ArgumentError, "seed"),
    ({"pitch": 100.0, "time_limit": 0.0}, gc.ArgumentError, "time_limit"),
])
def test_design_bad_inputs_get_precise_classes(kw, err, match):
    args = {"radius": 50.0, **kw}
    with pytest.raises(err, match=match):
        gc.design_helix(SLOCUM, **args)


def test_design_with_a_vehicle_of_the_wrong_kind_is_a_model_error():
    """A CTOL aircraft or a longitudinal-only glider is a ModelError, not 'no stable helix found'."""
    with pytest.raises(gc.ModelError, match="not an underwater glider"):
        gc.design_helix(gc.load_vehicle("dc8_ctol"), radius=10.0, pitch=5.0)
    with pytest.raises(gc.ModelError, match="3D parameters"):
        gc.design_helix(gc.load_vehicle("rogue"), radius=10.0, pitch=5.0)
    with pytest.raises(gc.ArgumentTypeError, match="Vehicle"):
        gc.design_helix("slocum_ch8", radius=10.0, pitch=5.0)


def test_design_m0_bounds_must_leave_a_solid_mass():
    with pytest.raises(gc.ModelError, match="solid mass"):
        gc.design_helix(SLOCUM, radius=50.0, pitch=-100.0, m0_bounds=(-41.0, 0.5))


def test_design_time_limit_is_a_budget_error():
    with pytest.raises(gc.BudgetError, match="time limit"):
        gc.design_helix(SLOCUM, radius=50.0, pitch=150.0, time_limit=1e-9)
    with pytest.raises(RuntimeError):  # BudgetError is also a RuntimeError
        gc.design_helix(SLOCUM, radius=50.0, pitch=150.0, time_limit=1e-9)


@pytest.fixture(scope="module")
def frozen():
    return gc.helix_rbh_locus(SLOCUM, NOMINAL_83, 0.25, np.linspace(-0.03, 0.1, 131), frozen=True)


def test_nominal_bottom_heaviness_matches_thesis(frozen):
    assert frozen.nominal.r_bh == pytest.approx(0.0481, abs=5e-5)


def test_frozen_locus_crossing_is_a_zero_real_part(frozen):
    (rc,) = frozen.crossings
    assert -0.02 < rc < 0.0
    model = gc.FixedMassGlider3D(SLOCUM, mass_position_at_rbh(frozen.nominal, rc), 0.25)
    from glidectl.trim.helix import helix_eigenvalues

    lam = helix_eigenvalues(model, frozen.nominal.unknowns)
    assert abs(np.max(lam.real)) < 1e-8
    # stable above, unstable below
    vals = frozen.locus.values
    mr = frozen.locus.branches.real.max(axis=1)
    assert np.all(mr[vals > rc + 1e-6] < 0) and np.all(mr[vals < rc - 1e-6] > 0)


def test_frozen_state_is_an_equilibrium_only_at_the_nominal_rbh(frozen):
    i = int(np.argmin(np.abs(frozen.locus.values - frozen.nominal.r_bh)))
    assert frozen.residual.max() > 1e-6  # r_bh does change the equilibrium (against 8.3's statement)
    # the residual grows with the distance from the nominal r_bh
    assert frozen.residual[0] > frozen.residual[i]


def test_resolved_locus_uses_true_equilibria():
    loc = gc.helix_rbh_locus(SLOCUM, NOMINAL_83, 0.25, np.linspace(0.0, 0.08, 17), frozen=False)
    assert loc.residual.max() < 1e-10
    assert np.all(loc.locus.branches.real.max(axis=1) < 0)


def test_resolved_crossing_brackets_the_loss_of_stability():
    rc, h = gc.resolved_crossing(SLOCUM, NOMINAL_83, 0.25)
    assert rc is not None and rc < 0
    assert h.stable and abs(np.max(h.eigenvalues.real)) < 1e-6  # a true crossing, not a branch jump
    below = gc.helix_trim(SLOCUM, mass_position_at_rbh(gc.helix_trim(SLOCUM, NOMINAL_83, 0.25), rc - 1e-6), 0.25,
                          guess=h, n_random=0, continuation_steps=1)
    assert not below.stable


def test_resolved_crossing_refuses_a_branch_jump():
    """With coarse steps the walk jumps across the fold near r_bh = -0.008 m: reported, not taken for a crossing."""
    with pytest.raises(gc.SolverError, match="jumps"):
        gc.resolved_crossing(SLOCUM, NOMINAL_83, 0.25, step=2e-3)


@pytest.mark.parametrize(("r_p", "m0", "key"), [((0.02, 0.02, 0.04), 0.25, "pitch"),
                                                 ((0.0088, 0.0242, 0.0412), 0.28, "speed"),
                                                 ((-0.02, 0.0088, 0.0426), -0.2436, "pitch")])
def test_design_sensitivities_match_central_differences_of_retrims(r_p, m0, key):
    """The implicit-function-theorem Jacobian design_helix gives least_squares (d(radius, pitch or speed)/dc and
    d max Re(lambda)/dc, c = (r_P1, r_P2, r_P3, m0)) equals central differences through independent re-trims."""
    from glidectl.trim.helix_design import _control_sensitivity

    h = gc.helix_trim(SLOCUM, r_p, m0)
    dq, dmax = _control_sensitivity(SLOCUM, h, key, True)
    c = np.r_[r_p, m0]
    for j, step in enumerate((1e-5, 1e-5, 1e-5, 1e-4)):
        hs = []
        for sgn in (1, -1):
            cc = c.copy()
            cc[j] += sgn * step
            hs.append(gc.helix_trim(SLOCUM, cc[:3], cc[3], guess=h, n_random=0))
        second = [x.pitch if key == "pitch" else x.speed for x in hs]
        fd_q = np.array([hs[0].radius - hs[1].radius, second[0] - second[1]]) / (2 * step)
        fd_max = (np.max(hs[0].eigenvalues.real) - np.max(hs[1].eigenvalues.real)) / (2 * step)
        np.testing.assert_allclose(dq[:, j], fd_q, rtol=1e-4, atol=1e-6 * np.abs(dq).max())
        assert dmax[j] == pytest.approx(fd_max, rel=1e-3, abs=1e-6 * np.abs(dmax).max())
