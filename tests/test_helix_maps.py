"""Helix maps of §8.2.2 (Fig 8.5-8.12) and the existence claim: helix_sweep (continuation, chunking, executors) and
existence_scan.

Qualitative statements of §8.2.2 are asserted where this model bears them out; where it does not, the test asserts
what the model does and says so in its docstring (see also the notes in glidectl.analysis.helix_maps' users' report).
"""

from __future__ import annotations

import math
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import glidectl as gc
from glidectl import FixedMassGlider3D, GlidectlError, InfeasibleGlideError, ModelError, helix_trim, load_vehicle
from glidectl.analysis.continuation import COLUMNS
from glidectl.analysis.helix_existence import existence_scan
from glidectl.analysis.helix_stability import mass_position_at_rbh
from glidectl.analysis.helix_sweeps import HelixSweep, helix_sweep
from glidectl.trim.helix import zeta_of

SLOCUM = load_vehicle("slocum_ch8")
HEAVY = ((0.02, 0.02, 0.04), 0.25)  # Fig 8.5, 8.7, 8.9, 8.11: r_P (m), m0 (kg)
LIGHT = ((-0.02, 0.02, 0.04), -0.25)  # Fig 8.6, 8.8, 8.10, 8.12
MIRROR_FLIPS = ("beta", "phi", "psidot", "v2")


def _sweep(parameter: str, values: np.ndarray, case: tuple, **kw) -> HelixSweep:
    return helix_sweep(SLOCUM, parameter, values, r_p=case[0], m0=case[1], **kw)


@pytest.fixture(scope="module")
def maps() -> dict[str, HelixSweep]:
    return {
        "rP1_heavy": _sweep("r_P1", np.linspace(0.002, 0.06, 30), HEAVY),
        "rP1_light": _sweep("r_P1", np.linspace(-0.06, -0.002, 30), LIGHT),
        "rP2_heavy": _sweep("r_P2", np.linspace(-0.05, 0.05, 41), HEAVY),
        "rP2_light": _sweep("r_P2", np.linspace(-0.05, 0.05, 41), LIGHT),
        "rP3_heavy": _sweep("r_P3", np.linspace(0.0, 0.1, 101), HEAVY),
        "rP3_light": _sweep("r_P3", np.linspace(0.0, 0.1, 51), LIGHT),
        "m0_heavy": _sweep("m0", np.linspace(0.05, 0.6, 23), HEAVY),
        "m0_light": _sweep("m0", np.linspace(-0.6, -0.05, 23), LIGHT),
    }


def _assert_same(a: HelixSweep, b: HelixSweep, tol: float) -> None:
    np.testing.assert_array_equal(a.exists, b.exists)
    np.testing.assert_allclose(a.data, b.data, rtol=tol, atol=tol)
    np.testing.assert_allclose(a.unknowns, b.unknowns, rtol=tol, atol=tol)
    assert a.how == b.how and a.notes == b.notes


# ---------------------------------------------------------------------------------------------- the sweep itself


def test_continuation_equals_cold_solves_point_by_point():
    """Each continued point equals an independent cold helix_trim(guess=None) of the same controls to 1e-8."""
    vals = np.linspace(0.002, 0.03, 15)
    sw = _sweep("r_P1", vals, HEAVY)
    assert sw.exists.all() and sw.how[0] == "cold" and set(sw.how[1:]) == {"warm"}
    for i, x in enumerate(vals):
        h = helix_trim(SLOCUM, (x, 0.02, 0.04), 0.25)
        row = np.array([*(h.as_dict()[c] for c in COLUMNS[:14]), *h.v])
        np.testing.assert_allclose(sw.data[i], row, rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(sw.unknowns[i], h.unknowns, atol=1e-8)
    cold = _sweep("r_P1", vals, HEAVY, continuation=False)
    assert set(cold.how) == {"cold"}
    np.testing.assert_allclose(cold.data, sw.data, rtol=1e-8, atol=1e-8)


def test_result_is_frozen_picklable_and_documented(maps):
    sw = maps["rP1_heavy"]
    with pytest.raises(ValueError):
        sw.data[0, 0] = 1.0
    with pytest.raises(AttributeError):
        sw.parameter = "m0"  # type: ignore[misc]
    back = pickle.loads(pickle.dumps(sw))
    _assert_same(back, sw, 0.0)
    assert sw.unit == "m" and sw.columns == COLUMNS and sw.data.shape == (30, len(COLUMNS))
    assert sw.context["vehicle_provenance"] == SLOCUM.provenance and sw.context["continuation"]
    assert sw.provenance == SLOCUM.provenance and sw.vehicle.name == SLOCUM.name
    assert sw.controls(3) == ((float(sw.values[3]), 0.02, 0.04), 0.25)
    rec = sw.records()[0]
    assert rec["r_P1"] == sw.values[0] and rec["exists"] and rec["how"] == "cold"
    np.testing.assert_array_equal(sw.column("radius"), sw.radius)
    with pytest.raises(GlidectlError, match="unknown column"):
        sw.column("nope")
    ax = sw.plot(column="speed")  # draws only; no computation
    assert "r_{P1}" in ax.get_xlabel() and ax.get_ylabel() == "speed [m/s]"
    ax.figure.clf()


def test_residuals_and_stability_on_every_existing_point(maps):
    """Every existing point is a relative equilibrium of (8.23) to 1e-10 (rechecked with a fresh model)."""
    for key, sw in maps.items():
        assert sw.exists.all(), key
        assert np.all(sw.residual[sw.exists] < 1e-10), key
        for i in np.flatnonzero(sw.exists)[::7]:
            rp, m0 = sw.controls(i)
            v, psidot, th, ph = sw.unknowns[i, :3], sw.unknowns[i, 3], sw.unknowns[i, 4], sw.unknowns[i, 5]
            z = zeta_of(th, ph)
            vd, Od = FixedMassGlider3D(SLOCUM, rp, m0).accelerations(v, psidot * z, z)
            assert max(np.max(np.abs(vd)), np.max(np.abs(Od))) < 1e-10
        np.testing.assert_array_equal(sw.stable, sw.exists & (sw.max_re_eig < 0))


def test_chunked_sweeps_equal_serial_including_seed_search_and_branch_changes():
    """Chunks walked independently and reconciled equal the serial walk, also when (a) the cold start fails on the
    first points (seed search, then the downward walk finds them by continuation) and (b) chunk seeds land on
    another branch (m0 < 0, r_P1 > 0, where several motions coexist)."""
    vals = np.linspace(0.4, 0.0, 9)  # r_P2; with one r_P2 step and no random starts the cold start fails at first
    serial = helix_sweep(SLOCUM, "r_P2", vals, continuation_steps=1, n_random=0)
    assert serial.how[:3] == ("warm",) * 3 and serial.how[3] == "cold" and serial.exists.all()
    assert "walking down from the seed" in serial.notes[0]
    assert math.isinf(serial.radius[-1])  # r_P2 = 0: straight longitudinal glide
    for ch in (2, 3, 4):
        _assert_same(helix_sweep(SLOCUM, "r_P2", vals, continuation_steps=1, n_random=0, chunks=ch), serial, 1e-9)
    vals = np.linspace(-0.02, 0.06, 41)
    serial = _sweep("r_P1", vals, LIGHT)
    chunked = _sweep("r_P1", vals, LIGHT, chunks=7)
    assert any("re-walked" in s for s in chunked.context["reconciliation"])
    _assert_same(chunked, serial, 1e-9)


def test_sweep_starting_without_solutions_finds_the_branch():
    """m0 = 0 has no steady motion: recorded as missing with the reason, and the walk starts at the next value."""
    sw = helix_sweep(SLOCUM, "m0", [0.0, 0.1, 0.2, 0.3])
    assert list(sw.exists) == [False, True, True, True] and sw.how[:2] == ("none", "cold")
    assert "m0 = 0" in sw.notes[0] and np.all(np.isnan(sw.data[0])) and np.all(np.isnan(sw.unknowns[0]))
    assert not sw.stable[0]
    _assert_same(helix_sweep(SLOCUM, "m0", [0.0, 0.1, 0.2, 0.3], chunks=4), sw, 1e-9)


def test_process_pool_and_dask_executors_equal_serial():
    vals = np.linspace(-0.02, 0.06, 20)
    serial = _sweep("r_P1", vals, LIGHT)
    with ProcessPoolExecutor(2) as ex:
        pooled = _sweep("r_P1", vals, LIGHT, executor=ex, chunks=4)
    _assert_same(pooled, serial, 1e-9)
    assert pooled.context["executor"].endswith("ProcessPoolExecutor") and pooled.context["chunks"] == 4
    distributed = pytest.importorskip("distributed")
    with (distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl,
          distributed.Client(cl) as client):
        dasked = _sweep("r_P1", vals, LIGHT, executor=client.get_executor())
    _assert_same(dasked, serial, 1e-9)


def test_bad_inputs():
    for bad in ({"parameter": "r_P4", "values": [0.01]}, {"parameter": "m0", "values": []},
                {"parameter": "r_P1", "values": [[0.01, 0.02]]}, {"parameter": "r_P1", "values": [0.01, np.nan]},
                {"parameter": "r_P1", "values": ["a"]}):
        with pytest.raises(GlidectlError):
            helix_sweep(SLOCUM, **bad)
    for kw in ({"chunks": 0}, {"r_p": (0.0, 0.0)}, {"m0": math.inf}, {"continuation_steps": 0}):
        with pytest.raises(GlidectlError):
            helix_sweep(SLOCUM, "r_P1", [0.01], **kw)
    with pytest.raises(ModelError):
        helix_sweep(load_vehicle("rogue"), "r_P1", [0.01])
    with pytest.raises(GlidectlError):
        existence_scan(SLOCUM, [], [0.25])


# ---------------------------------------------------------------------------------------------- §8.2.2 statements


def test_fig85_heavy_rP1_trends(maps):
    """Fig 8.5 (m0 > 0): "as r_P1 increases the equilibrium pitch angle as well as the flight path angle become more
    negative ... alpha_e and beta_e become lower (both are positive) ... greater V_e ... smaller |Omega_e| ...
    greater helical radius, pitch and period". Pitch, flight-path angle and speed are monotone on the whole
    range 0.2-6 cm and alpha, beta stay positive; the decrease of beta and |Omega| and the growth of radius, pitch and
    period hold only up to r_P1 ~ 2.8 cm: |Omega| passes (almost) through zero near 3.5 cm, where the helix turns
    the other way (psidot changes sign), and alpha turns up again near 4.8 cm."""
    sw = maps["rP1_heavy"]
    for c in ("theta", "gamma"):
        assert np.all(np.diff(sw.column(c)) < 0), c
    assert np.all(np.diff(sw.speed) > 0)
    assert np.all(sw.alpha > 0) and np.all(sw.beta > 0)
    low = sw.values <= 0.028
    for c in ("alpha", "beta", "Omega_norm"):
        assert np.all(np.diff(sw.column(c)[low]) < 0), c
    for c in ("radius", "pitch", "period"):
        assert np.all(np.diff(sw.column(c)[low]) > 0), c
    # not on the whole range: psidot changes sign between 3 and 4 cm, |Omega| has its minimum there
    assert np.sign(sw.psidot[0]) != np.sign(sw.psidot[-1])
    assert 0.03 < sw.values[np.argmin(sw.Omega_norm)] < 0.04 and sw.radius[-1] < sw.radius[low][-1]


def test_fig86_light_rP1_trends(maps):
    """Fig 8.6 (m0 < 0): alpha_e, beta_e negative; decreasing r_P1 from near 0, alpha first decreases (drag up, V
    down), then beyond a critical value alpha and V increase again."""
    sw = maps["rP1_light"]
    assert np.all(sw.alpha < 0) and np.all(sw.beta < 0)
    ia, iv = int(np.argmin(sw.alpha)), int(np.argmin(sw.speed))
    assert 0 < ia < sw.values.size - 1 and 0 < iv < sw.values.size - 1
    assert -0.01 < sw.values[ia] < -0.002 and -0.01 < sw.values[iv] < -0.002


@pytest.mark.parametrize("key", ["rP2_heavy", "rP2_light"])
def test_fig87_88_rP2(maps, key):
    """Fig 8.7-8.8: radius -> infinity and beta -> 0 as r_P2 -> 0 (straight longitudinal glide); the solutions are
    mirror-symmetric in r_P2 (r_P2 -> -r_P2 flips beta, phi, psidot and v2, keeps the rest).

    The printed sign rule ("beta_e is positive when m0 and r_P2 have opposite signs") is the reverse of what this
    model gives: sign(beta) = sign(m0 r_P2). The thesis's own numbers side with the model: §8.2.2's initial
    condition for m0 = 0.25 kg, r_P2 = 2 cm has v2 = +0.014 m/s, and its Fig 8.5 text has beta > 0 for that case."""
    sw = maps[key]
    m0 = sw.m0
    x = sw.values
    i0 = int(np.argmin(np.abs(x)))
    assert x[i0] == 0 and math.isinf(sw.radius[i0]) and sw.psidot[i0] == 0 and abs(sw.beta[i0]) < 1e-12
    r = sw.radius[i0 + 1:]
    assert np.all(np.diff(r) < 0) and r[0] > 100
    assert r[0] * x[i0 + 1] == pytest.approx(r[1] * x[i0 + 2], rel=0.02)  # radius ~ 1/r_P2: unbounded at 0
    nz = x != 0
    np.testing.assert_array_equal(np.sign(sw.beta[nz]), np.sign(m0 * x[nz]))
    flip = [COLUMNS.index(c) for c in MIRROR_FLIPS]
    keep = [i for i, c in enumerate(COLUMNS) if c not in (*MIRROR_FLIPS, "residual")]
    mirror = sw.data[::-1]
    np.testing.assert_allclose(sw.data[:, keep], mirror[:, keep], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sw.data[:, flip], -mirror[:, flip], rtol=1e-9, atol=1e-12)


def test_fig87_88_roll_range(maps):
    """"For nonzero r_P2 the range of variation of the equilibrium roll angle is smaller for m0 = 0.25 kg than for
    m0 = -0.25 kg"."""
    heavy, light = maps["rP2_heavy"], maps["rP2_light"]
    assert np.ptp(heavy.phi) < np.ptp(light.phi)


def test_fig89_810_rP3(maps):
    """Fig 8.9 (m0 > 0): a critical r_P3 with zero angular velocity, a straight glide out of the longitudinal plane
    (beta != 0). Fig 8.10 (m0 < 0): smooth in r_P3. The model also has a fold on the m0 > 0 map near r_P3 = 1.5 cm
    (the steep branch ends; the continuation falls back to a cold start and jumps), which the text does not mention."""
    heavy, light = maps["rP3_heavy"], maps["rP3_light"]
    k = np.flatnonzero(np.diff(np.sign(heavy.psidot)) != 0)
    assert k.size == 1 and 0.015 < heavy.values[k[0]] < 0.03
    assert abs(heavy.beta[k[0]]) > 0.01 and abs(heavy.beta[k[0] + 1]) > 0.01
    assert heavy.radius[k[0]] > 500 and heavy.radius[k[0] + 1] > 500
    assert list(heavy.branch_jumps) == [pytest.approx(0.015)]
    assert "cold (warm failed)" in heavy.how
    assert light.branch_jumps.size == 0 and np.all(light.psidot < 0) and set(light.how[1:]) == {"warm"}


@pytest.mark.parametrize("key", ["m0_heavy", "m0_light"])
def test_fig811_812_m0(maps, key):
    """Fig 8.11-8.12: |Omega| grows faster than V with |m0|, so the radius decreases. "The variation of translational
    speed versus |m0| is almost linear" is not what the model gives over 0.05-0.6 kg: V ~ |m0|^0.45-0.55 (square-root
    like, as for a straight glide)."""
    sw = maps[key]
    o = np.argsort(np.abs(sw.values))
    m, V, W, R = np.abs(sw.values)[o], sw.speed[o], sw.Omega_norm[o], sw.radius[o]
    assert np.all(np.diff(V) > 0) and np.all(np.diff(W / V) > 0) and np.all(np.diff(R) < 0)
    slope = np.polyfit(np.log(m), np.log(V), 1)[0]
    assert 0.4 < slope < 0.6


def test_existence_claim_of_822():
    """§8.2.2: "We could not find any equilibrium solutions for m0 > 0 with r_P1 < 0 or m0 < 0 with r_P1 > 0".
    Not so in this model (r_P2 = 2 cm, r_P3 = 4 cm): motions exist there, found by the cold start and by continuation
    across r_P1 = 0. For m0 > 0, r_P1 < 0 they are stable, upright (|phi| < 90 deg), nose-up (theta > 0) descents at a
    high angle of attack (alpha > theta > 0, gamma < 0); for m0 < 0, r_P1 > 0 stable upright ones are steeply banked."""
    scan = existence_scan(SLOCUM, [-0.01, 0.01], [-0.25, 0.25], n_starts=8)
    assert not scan.reproduced and scan.exists.all()
    assert scan.claim_region.tolist() == [[False, True], [True, False]]
    heavy_aft = [c for c in scan.counterexamples(stable_only=True, upright_only=True) if c["m0"] > 0]
    assert heavy_aft, scan.summary()
    c = heavy_aft[0]
    assert c["theta"] > 0 and c["alpha"] > c["theta"] and c["gamma"] < 0 and c["residual"] < 1e-10
    assert c["alpha"] < math.radians(15)
    light_fore = scan.counterexamples(stable_only=True, upright_only=True)
    assert any(d["m0"] < 0 and abs(d["phi"]) > math.radians(45) for d in light_fore)
    # each recorded motion re-solves (warm start) to itself: a genuine equilibrium
    h = helix_trim(SLOCUM, (c["r_P1"], 0.02, 0.04), c["m0"], guess=np.asarray(c["unknowns"]), n_random=0)
    np.testing.assert_allclose(np.r_[h.unknowns[:5], math.remainder(h.phi, 2 * math.pi)], c["unknowns"], atol=1e-9)
    assert "continuation in r_P1" in c["found_by"] and "cold start" in c["found_by"]
    assert "claim does not hold" in scan.summary()
    with pytest.raises(InfeasibleGlideError):  # m0 = 0 stays infeasible
        helix_trim(SLOCUM, (0.01, 0.02, 0.04), 0.0)


# ------------------------------------------------------------------------------------- argument checks (issue 15)

NOM = (0.02, -0.02, 0.04)  # §8.3 nominal r_P (m), with m0 = 0.25 kg


@pytest.mark.parametrize(("args", "kw", "exc"), [
    (("bogus", [0.01]), {}, gc.ArgumentError),
    (("r_P1", []), {}, gc.ArgumentError),
    (("r_P1", "abc"), {}, gc.ArgumentTypeError),
    (("r_P1", [0.01]), {"chunks": 0}, gc.ArgumentError),
    (("r_P1", [0.01]), {"chunks": 2.0}, gc.ArgumentTypeError),
    (("r_P1", [0.01]), {"executor": "pool"}, gc.ArgumentTypeError),
    (("r_P1", [0.01]), {"continuation": 1}, gc.ArgumentTypeError),
    (("r_P1", [0.01]), {"m0": "0.25"}, gc.ArgumentTypeError),
    (("r_P1", [0.01]), {"seed": -1}, gc.ArgumentError),
    (("r_P1", [0.01]), {"n_random": 10**6}, gc.ArgumentError),  # multistart is bounded
    (("r_P1", [20.0]), {}, gc.ArgumentError),  # the moving mass 20 m from the centre
    (("m0", [-41.0, 0.25]), {"r_p": (0.02, 0.02, 0.04)}, gc.ModelError),  # issue 15: solid mass 0 at m0 = -41 kg
])
def test_sweep_arguments_are_refused_before_solving(args, kw, exc):
    with pytest.raises(exc):
        helix_sweep(SLOCUM, *args, **kw)


def test_sweep_and_scan_budgets():
    with pytest.raises(gc.BudgetError, match="Newton solves"):
        helix_sweep(SLOCUM, "r_P1", np.linspace(0.0, 0.01, 200_000))
    with pytest.raises(gc.BudgetError, match="Newton solves"):
        existence_scan(SLOCUM, np.linspace(-0.02, 0.02, 300), np.linspace(0.1, 0.3, 300), n_starts=100)
    with pytest.raises(gc.ArgumentError):
        existence_scan(SLOCUM, [0.01], [0.25], n_starts=10**6)


@pytest.mark.parametrize(("args", "kw", "exc"), [
    (([0.01], [math.nan]), {}, gc.ArgumentError),
    (([0.01], [0.25]), {"n_starts": -1}, gc.ArgumentError),
    (([0.01], [0.25]), {"tol": -1.0}, gc.ArgumentError),
    (([0.01], [0.25]), {"continuation": "yes"}, gc.ArgumentTypeError),
    (([0.01], [-41.0]), {}, gc.ModelError),
])
def test_existence_scan_bad_arguments(args, kw, exc):
    with pytest.raises(exc):
        existence_scan(SLOCUM, *args, **kw)
    with pytest.raises(ModelError):
        existence_scan(load_vehicle("dc8_ctol"), [0.01], [0.25])


def test_straight_glides_checks_the_sweep():
    sw = _sweep("r_P2", np.linspace(-0.01, 0.01, 3), HEAVY)
    with pytest.raises(gc.ArgumentTypeError):
        gc.straight_glides(SLOCUM, "sweep")
    with pytest.raises(gc.VehicleMismatchError):  # was silently re-trimmed with the other vehicle
        gc.straight_glides(SLOCUM.with_overrides(K_M=-40.0), sw)
    with pytest.raises(gc.ArgumentError):
        gc.straight_glides(SLOCUM, sw, xtol=0.0)
    with pytest.raises(gc.ArgumentError):
        sw.column("nope")
    with pytest.raises(gc.ArgumentError):
        sw.controls(3)


def test_helix_stability_arguments():
    with pytest.raises(gc.ArgumentError):
        gc.helix_rbh_locus(SLOCUM, NOM, 0.25, [0.01, math.nan])
    with pytest.raises(gc.ArgumentError):
        gc.helix_rbh_locus(SLOCUM, (0.02, 0.04), 0.25, [0.01, 0.02])
    with pytest.raises(gc.ArgumentTypeError):
        gc.helix_rbh_locus(SLOCUM, NOM, "0.25", [0.01, 0.02])
    with pytest.raises(gc.ArgumentTypeError):
        gc.helix_rbh_locus(SLOCUM, NOM, 0.25, [0.01, 0.02], frozen="no")
    for kw in ({"step": 0.0}, {"step": -5e-4}, {"stop": math.nan}, {"max_steps": 0}):
        with pytest.raises(gc.ArgumentError):
            gc.resolved_crossing(SLOCUM, NOM, 0.25, **kw)
    with pytest.raises(gc.BudgetError, match="max_steps"):  # 1e11 continuation steps: refused up front
        gc.resolved_crossing(SLOCUM, NOM, 0.25, step=1e-12)
    with pytest.raises(gc.ArgumentTypeError):
        mass_position_at_rbh("helix", 0.01)


def test_resolved_crossing_needs_a_stable_nominal_helix():
    """The walk bisects between a stable upper and an unstable lower point; from an unstable nominal helix it used
    to return a 'crossing' where stability is gained. Now it refuses."""
    nominal = helix_trim(SLOCUM, NOM, 0.25)
    assert nominal.stable
    below = mass_position_at_rbh(nominal, -0.0293)  # past the re-solved crossing near r_bh = -0.0273 m
    assert not helix_trim(SLOCUM, below, 0.25).stable
    with pytest.raises(ModelError, match="not stable"):
        gc.resolved_crossing(SLOCUM, below, 0.25)


def test_mirror_error_measures_the_rP2_symmetry(maps):
    sw = maps["rP2_heavy"]
    assert sw.mirror_error("speed") < 1e-9 and sw.mirror_error("radius") < 1e-6 * np.nanmax(sw.radius[sw.values != 0])
    assert sw.mirror_error("beta", -1) < 1e-9
    # taken as even, the odd beta shows twice its largest magnitude
    assert sw.mirror_error("beta", 1) == pytest.approx(2 * np.max(np.abs(sw.beta)), rel=1e-9)
    assert math.isnan(maps["rP1_heavy"].mirror_error("speed"))  # no point has its mirror on that grid
    with pytest.raises(gc.ArgumentError, match="parity"):
        sw.mirror_error("beta", 0)
    with pytest.raises(gc.ArgumentError, match="column"):
        sw.mirror_error("nope")


def test_branch_end_walks_a_smooth_branch(maps):
    light = maps["rP3_light"]  # smooth in r_P3: the walk reaches its target
    x, re = light.branch_end(0, float(light.values[1]), 0.0005)
    k = int(abs(light.values[1] - light.values[0]) / 0.0005)
    assert x == pytest.approx(light.values[0] + k * 0.0005, abs=1e-15)
    h = gc.helix_trim(SLOCUM, (light.r_p[0], light.r_p[1], x), light.m0)
    assert re == pytest.approx(float(np.max(h.eigenvalues.real)), abs=1e-8)
    heavy = maps["rP3_heavy"]
    i = int(np.flatnonzero(heavy.values == heavy.branch_jumps[0])[0])
    target = float(heavy.values[i + 1]) + 1e-3
    # (the fold itself, just after the jump at 1.5 cm, needs steps of a few um: the chapter-8 design walks it)
    assert heavy.branch_end(i, float(heavy.values[i]), 1.0) == (float(heavy.values[i]),
                                                                 float(heavy.max_re_eig[i]))  # no step
    with pytest.raises(gc.ArgumentError):
        heavy.branch_end(i, target, 0.0)
    with pytest.raises(gc.BudgetError, match="steps"):
        heavy.branch_end(i, 10.0, 1e-9)
