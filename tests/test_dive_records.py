"""Dive records (Slocum binary and CSV files, checked arrays) and the flight-model fit on them."""

from __future__ import annotations

import math
import os
from pathlib import Path

import dbdreader
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import CubicSpline

import glidectl as gc

AMMONITE = os.path.join(os.path.dirname(dbdreader.__file__), "data", "ammonite-2008-028-01-000.mbd")
FIELDS = ("time", "depth", "pitch", "buoyancy_volume")
OPTIONAL = ("roll", "heading", "density", "temperature")


@pytest.fixture(scope="module")
def ammonite(tmp_path_factory: pytest.TempPathFactory) -> gc.DiveRecord:
    return gc.read_dive_record(AMMONITE, cache_dir=tmp_path_factory.mktemp("dbdcache"))


def _hull_vehicle(**extra: float) -> gc.Vehicle:
    return gc.load_vehicle("slocum_shallow").with_hydrodynamics(mass=70.0, compressibility=5e-10, **extra)


# --------------------------------------------------------------------------------------------- 1. Slocum file


def test_read_slocum_record(ammonite):
    rec = ammonite
    assert len(rec) >= 1500
    assert np.all(np.diff(rec.time) > 0)
    assert 600.0 < rec.depth.max() < 615.0
    assert np.abs(rec.pitch).max() < 0.7
    assert np.abs(rec.buoyancy_volume).max() <= 3e-4
    assert rec.roll is not None and rec.heading is not None
    assert rec.roll.shape == rec.heading.shape == rec.time.shape
    assert np.abs(rec.heading).max() <= 2 * math.pi + 1e-9
    assert rec.density is None and rec.temperature is None
    assert rec.source == AMMONITE
    for name in (*FIELDS, "roll", "heading"):
        assert not getattr(rec, name).flags.writeable, name


def test_slocum_depth_is_hydrostatic_pressure(ammonite, tmp_path):
    # depth is the hydrostatic depth of m_pressure (bar) with gliderflight's constants (1025 kg/m^3, 9.81 m/s^2)
    dbd = dbdreader.DBD(AMMONITE, cacheDir=str(tmp_path))
    try:
        t, p = dbd.get("m_pressure")
    finally:
        dbd.close()
    on_record = np.interp(ammonite.time, t, p)  # the record is on the time base of m_pressure
    np.testing.assert_allclose(ammonite.depth, on_record * 1e5 / (1025.0 * 9.81), rtol=1e-12, atol=1e-9)


def _dive_bottoms(depth: np.ndarray) -> np.ndarray:
    """Deepest depth of the run below 5 m each sample belongs to (NaN at the surface): an independent dive split."""
    below = depth > 5.0
    bottom = np.full(depth.shape, np.nan)
    i = 0
    while i < depth.size:
        if not below[i]:
            i += 1
            continue
        j = i
        while j < depth.size and below[j]:
            j += 1
        bottom[i:j] = depth[i:j].max()
        i = j
    return bottom


def test_default_mask(ammonite):
    rec = ammonite
    m = rec.mask()
    assert m.dtype == bool and m.shape == (len(rec),)
    assert m.sum() > 1200
    bottom = _dive_bottoms(rec.depth)
    assert np.all(rec.depth[m] >= 20.0)
    assert np.all(rec.depth[m] <= bottom[m] - 20.0)
    assert np.all(np.abs(rec.pitch[m]) >= math.radians(10.0))
    # and it keeps every sample that passes all three, but for the samples of the last climb within 20 m of its
    # last inflection (the glider pitches over at 1.9 m at the surface: 20 m around it reach 21.9 m)
    keep = (rec.depth >= 20.0) & (rec.depth <= np.nan_to_num(bottom, nan=-np.inf) - 20.0) & (
        np.abs(rec.pitch) >= math.radians(10.0))
    bottom_turn, last = rec.inflections()[-2:]
    i = np.arange(len(rec))
    climb_top = (i > bottom_turn) & (i < last) & (rec.depth < rec.depth[last] + 20.0)
    assert np.array_equal(m, keep & ~climb_top)
    assert 0 < (keep & ~m).sum() <= 3
    # other settings: a wider surface layer leaves out more
    wide = rec.mask(gc.MaskSettings(surface_depth=100.0))
    assert np.all(rec.depth[wide] >= 100.0) and wide.sum() < m.sum() and np.all(m[wide])
    with pytest.raises(gc.RecordError, match="MaskSettings"):
        rec.mask({"surface_depth": 20.0})


def test_missing_record_file(tmp_path):
    with pytest.raises(gc.RecordError) as info:
        gc.read_dive_record(tmp_path / "absent.mbd", cache_dir=tmp_path)
    assert "absent.mbd" in str(info.value)


# --------------------------------------------------------------------------------------------- 2. CSV


def _write_csv(path: Path, columns: dict[str, np.ndarray]) -> Path:
    np.savetxt(path, np.column_stack(list(columns.values())), delimiter=",", header=",".join(columns),
               comments="", fmt="%.17g")
    return path


def test_csv_round_trip(ammonite, tmp_path):
    cols = {n: getattr(ammonite, n) for n in FIELDS}
    rec = gc.read_dive_record(_write_csv(tmp_path / "rec.csv", cols))
    for n in FIELDS:
        assert np.array_equal(getattr(rec, n), getattr(ammonite, n)), n
    assert rec.roll is None and rec.heading is None
    assert rec.provenance != ammonite.provenance  # roll and heading are part of the data
    cols.update(roll=ammonite.roll, heading=ammonite.heading)
    rec2 = gc.read_dive_record(_write_csv(tmp_path / "rec2.csv", cols))
    for n in (*FIELDS, "roll", "heading"):
        assert np.array_equal(getattr(rec2, n), getattr(ammonite, n)), n
    assert rec2.provenance == ammonite.provenance
    assert np.array_equal(rec2.mask(), ammonite.mask())


@pytest.mark.parametrize("missing", FIELDS)
def test_csv_missing_column(ammonite, tmp_path, missing):
    cols = {n: getattr(ammonite, n) for n in FIELDS if n != missing}
    with pytest.raises(gc.RecordError) as info:
        gc.read_dive_record(_write_csv(tmp_path / "rec.csv", cols))
    msg = str(info.value)
    assert missing in msg and "no column" in msg
    assert not any(f"column(s) {other}" in msg for other in FIELDS if other != missing)


# --------------------------------------------------------------------------------------------- 3. bad arrays


def _arrays(n: int = 60) -> dict[str, np.ndarray]:
    t = np.arange(n) * 4.0
    half = n // 2
    depth = np.concatenate([np.linspace(0.0, 80.0, half), np.linspace(80.0, 0.0, n - half)])
    pitch = np.where(np.arange(n) < half, -0.45, 0.45)
    vol = np.where(np.arange(n) < half, -2e-4, 2e-4)
    return {"time": t, "depth": depth, "pitch": pitch, "buoyancy_volume": vol}


def _record_error(**changes: object) -> str:
    a = {**_arrays(), **changes}
    with pytest.raises(gc.RecordError) as info:
        gc.DiveRecord.from_arrays(**a)
    return str(info.value)


def test_good_arrays_make_a_record():
    a = _arrays()
    rec = gc.DiveRecord.from_arrays(**a)
    for n in FIELDS:
        assert np.array_equal(getattr(rec, n), a[n])
    assert len(rec) == 60 and rec.source == "arrays"
    assert np.array_equal(rec.dive_number, np.zeros(60, dtype=int))


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(FIELDS + OPTIONAL), index=st.integers(0, 59), bad=st.sampled_from([np.nan, np.inf]))
def test_non_finite_value_names_field_and_sample(name, index, bad):
    a = _arrays()
    for opt in OPTIONAL:
        a[opt] = np.full(60, 1025.0 if opt == "density" else 0.1)
    a[name] = a[name].copy()
    a[name][index] = bad
    with pytest.raises(gc.RecordError) as info:
        gc.DiveRecord.from_arrays(**a)
    msg = str(info.value)
    assert f"'{name}'" in msg and f"sample {index}" in msg and "non-finite" in msg


def test_nan_in_depth():
    d = _arrays()["depth"].copy()
    d[7] = np.nan
    msg = _record_error(depth=d)
    assert "'depth'" in msg and "sample 7" in msg


def test_time_not_increasing():
    t = _arrays()["time"].copy()
    t[10], t[11] = t[11], t[10]
    msg = _record_error(time=t)
    assert "'time'" in msg and "increase" in msg and "t[11]" in msg


def test_duplicated_time_sample():
    t = _arrays()["time"].copy()
    t[21] = t[20]
    msg = _record_error(time=t)
    assert "'time'" in msg and "duplicated" in msg and "samples 20 and 21" in msg


def test_record_with_no_dive():
    msg = _record_error(depth=np.linspace(1.0, 4.5, 60))
    assert "'depth'" in msg and "no dive" in msg


def test_pitch_in_degrees():
    msg = _record_error(pitch=np.degrees(_arrays()["pitch"]))
    assert "'pitch'" in msg and "degrees" in msg


def test_buoyancy_volume_in_cm3():
    msg = _record_error(buoyancy_volume=_arrays()["buoyancy_volume"] * 1e6)
    assert "'buoyancy_volume'" in msg and "cm^3" in msg


@pytest.mark.parametrize("name", ["depth", "pitch", "buoyancy_volume", "roll", "density"])
def test_different_lengths(name):
    msg = _record_error(**{name: np.full(59, 1025.0 if name == "density" else 0.1)})
    assert f"'{name}'" in msg and "59" in msg and "60" in msg


def test_negative_density():
    msg = _record_error(density=np.full(60, -1025.0))
    assert "'density'" in msg


# --------------------------------------------------------------------------------------------- 4. vertical speed


def test_vertical_speed_is_central_differences(ammonite):
    rec = ammonite
    w = rec.vertical_speed
    assert np.array_equal(w, -np.gradient(rec.depth) / np.gradient(rec.time))
    d, t = rec.depth, rec.time
    np.testing.assert_allclose(w[1:-1], -(d[2:] - d[:-2]) / (t[2:] - t[:-2]), rtol=1e-12, atol=1e-15)
    assert w[0] == pytest.approx(-(d[1] - d[0]) / (t[1] - t[0]), rel=1e-12)
    assert w[-1] == pytest.approx(-(d[-1] - d[-2]) / (t[-1] - t[-2]), rel=1e-12)
    # descending (depth increasing) is a negative vertical speed
    assert np.median(w[rec.pitch < -0.3]) < 0 < np.median(w[rec.pitch > 0.3])


@settings(max_examples=40, deadline=None)
@given(t0=st.floats(0.0, 2e9), steps=st.lists(st.floats(1.0, 30.0), min_size=30, max_size=120))
def test_constant_descent_rate(t0, steps):
    # uneven time steps: the central difference of a linear depth is still its slope
    t = t0 + np.concatenate([[0.0], np.cumsum(steps)])
    depth = 2.0 + 0.2 * (t - t0)
    rec = gc.DiveRecord.from_arrays(t, depth, np.full(t.size, -0.4), np.full(t.size, -2e-4))
    np.testing.assert_allclose(rec.vertical_speed, -0.2, rtol=1e-9, atol=0)


def test_uniform_constant_descent_is_minus_0_2():
    t = np.arange(200) * 0.5
    rec = gc.DiveRecord.from_arrays(t, 0.2 * t, np.full(200, -0.4), np.full(200, -2e-4))
    np.testing.assert_allclose(rec.vertical_speed, -0.2, rtol=1e-12, atol=0)


# --------------------------------------------------------------------------------------------- 5. fit on ammonite

LAWS = {None: "thesis", "seaglider": "seaglider", "gliderflight": "gliderflight"}
PARASITIC = {"thesis": "K_D0", "seaglider": "hd_b", "gliderflight": "Cd0"}


@pytest.fixture(scope="module")
def fits(ammonite) -> dict[str | None, gc.FlightFit]:
    veh = _hull_vehicle()
    return {law: gc.fit_flight_model(veh, ammonite, law=law) for law in LAWS}


def _sum_of_squares(veh: gc.Vehicle, rec: gc.DiveRecord, used: np.ndarray) -> float:
    r = gc.predict_flight(veh, rec, used).vertical_speed - rec.vertical_speed[used]
    return float(r @ r)


@pytest.mark.parametrize("law", list(LAWS))
def test_fit_ammonite(fits, ammonite, law):
    fit = fits[law]
    assert fit.law == LAWS[law] == fit.vehicle.law == fit.start.law
    assert fit.context["status"] > 0 and fit.context["nfev"] < 200
    assert set(fit.params) == {"volume", PARASITIC[fit.law]}
    used = fit.used
    assert np.array_equal(used, ammonite.mask()) and fit.context["n_used"] == used.sum()
    for key, value in fit.params.items():
        assert fit.vehicle.params[key] == value
        assert "fit_flight_model" in fit.vehicle.sources[key]
    # RMS recomputed from the fitted vehicle's prediction of the whole record
    pred = fit.predict()
    assert pred.vertical_speed.shape == (len(ammonite),)
    res = pred.vertical_speed[used] - ammonite.vertical_speed[used]
    rms = math.sqrt(float(np.mean(res**2)))
    assert rms == pytest.approx(fit.rms, rel=1e-12)
    np.testing.assert_allclose(fit.residual, res, rtol=1e-12, atol=1e-14)
    assert fit.rms < 0.07
    # a hull of 70 kg neutral near 0.0683 m^3 of sea water
    assert 0.067 < fit.params["volume"] < 0.0695
    # stationary: no coefficient moved by stderr/100 lowers the sum of squares
    ss0 = _sum_of_squares(fit.vehicle, ammonite, used)
    assert ss0 == pytest.approx(len(res) * fit.rms**2, rel=1e-12)
    for key, value in fit.params.items():
        err = fit.stderr[key]
        assert math.isfinite(err) and err > 0, key
        for sign in (-1.0, 1.0):
            ss = _sum_of_squares(fit.vehicle.with_hydrodynamics(**{key: value + sign * err / 100}), ammonite, used)
            assert ss >= ss0 * (1 - 1e-9), (key, sign, ss / ss0 - 1)
    assert fit.correlation.shape == (2, 2)
    np.testing.assert_allclose(np.diag(fit.correlation), 1.0, rtol=1e-12)
    assert np.all(np.abs(fit.correlation) <= 1 + 1e-12)


@pytest.mark.parametrize("law", list(LAWS))
def test_fit_to_toml_round_trip(fits, tmp_path, law):
    fit = fits[law]
    path = fit.to_toml(tmp_path / "fitted.toml")
    veh = gc.load_vehicle(path)
    assert veh.law == fit.law
    assert {k: veh.params[k] for k in fit.params} == fit.params
    assert dict(veh.params) == dict(fit.vehicle.params)
    assert veh.provenance == fit.uncertain_vehicle().provenance     # the file adds the standard errors
    assert gc.predict_flight(veh, fit.record, fit.used).vertical_speed.tolist() == \
        fit.predict().vertical_speed[fit.used].tolist()


def test_fit_holdout(ammonite, fits):
    fit = gc.fit_flight_model(_hull_vehicle(), ammonite, holdout=3)
    assert fit.context["holdout_blocks"] == "time blocks"  # one dive with used samples: blocks in time
    assert fit.params == fits[None].params
    assert len(fit.cv_fold_rms) == 3
    assert all(math.isfinite(v) and v > 0 for v in fit.cv_fold_rms)
    assert fit.cv_rms is not None and fit.cv_rms >= 0.9 * fit.rms
    # the pooled RMS (weighted mean square of the blocks) lies between the smallest and largest block RMS
    assert min(fit.cv_fold_rms) <= fit.cv_rms <= max(fit.cv_fold_rms)
    assert fits[None].cv_rms is None and fits[None].cv_fold_rms == ()


# --------------------------------------------------------------------------------------------- 6. synthetic


TRUE = {"volume": 0.0683, "Cd0": 0.12}


def _synthetic_record() -> tuple[gc.DiveRecord, np.ndarray, gc.Vehicle]:
    """A sawtooth flown by a known gliderflight-law vehicle: depth integrated (RK4, 0.5 s) from its steady vertical
    speed; within a leg the speed depends on depth only (compressible hull), so each leg's w(z) is a cubic spline
    of steady_flight on a 1 cm depth grid. The mask leaves out the ends and the samples at each leg change, where
    the central difference straddles two legs."""
    veh = _hull_vehicle().with_hydrodynamics("gliderflight", **TRUE)
    dt, n_leg = 0.5, 700
    legs = [(-25.0, -2.5e-4), (25.0, 2.5e-4), (-25.0, -2.5e-4), (25.0, 2.5e-4)]
    z_grid = np.linspace(0.0, 200.0, 20001)
    speed = {}
    for pitch, dv in set(legs):
        sf = gc.steady_flight(veh, math.radians(pitch), gc.excess_mass(veh, z_grid, dv))
        assert sf.feasible.all()
        speed[pitch, dv] = CubicSpline(z_grid, sf.vertical_speed)
    n = len(legs) * n_leg + 1
    z = np.empty(n)
    z[0] = 10.0
    pitch = np.empty(n)
    volume = np.empty(n)
    for k in range(n - 1):
        leg = legs[min(k // n_leg, len(legs) - 1)]
        w = speed[leg]
        pitch[k], volume[k] = math.radians(leg[0]), leg[1]
        k1 = -w(z[k])
        k2 = -w(z[k] + dt / 2 * k1)
        k3 = -w(z[k] + dt / 2 * k2)
        k4 = -w(z[k] + dt * k3)
        z[k + 1] = z[k] + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    pitch[-1], volume[-1] = pitch[-2], volume[-2]
    assert 20.0 < z.max() < 200.0 and z.min() >= 10.0
    mask = np.ones(n, dtype=bool)
    mask[[0, -1]] = False
    for b in range(1, len(legs)):
        mask[b * n_leg - 1:b * n_leg + 1] = False
    rec = gc.DiveRecord.from_arrays(np.arange(n) * dt, z, pitch, volume, source="synthetic sawtooth")
    return rec, mask, veh


def test_synthetic_recovery():
    rec, mask, veh = _synthetic_record()
    # the record's central differences are the model's vertical speed
    model = gc.predict_flight(veh, rec, mask).vertical_speed
    assert np.max(np.abs(model - rec.vertical_speed[mask])) < 1e-9
    start = veh.with_hydrodynamics(volume=0.0690, Cd0=0.2)
    fit = gc.fit_flight_model(start, rec, fit=["volume", "Cd0"], mask=mask)
    for key, value in TRUE.items():
        assert fit.params[key] == pytest.approx(value, rel=1e-6), key
    assert fit.rms < 1e-6
    assert fit.context["n_used"] == mask.sum()


# --------------------------------------------------------------------------------------------- 7. bad fits


def test_fit_names_a_coefficient_twice(ammonite):
    with pytest.raises(gc.ArgumentError) as info:
        gc.fit_flight_model(_hull_vehicle(), ammonite, fit=["volume", "volume"])
    assert "volume" in str(info.value) and "twice" in str(info.value)


def test_fit_coefficient_of_another_law(ammonite):
    veh = _hull_vehicle().with_hydrodynamics("gliderflight", Cd0=0.12, volume=0.0683)
    with pytest.raises(gc.ArgumentError) as info:
        gc.fit_flight_model(veh, ammonite, fit=["hd_a"])
    msg = str(info.value)
    assert "'hd_a'" in msg and "gliderflight" in msg
    with pytest.raises(gc.ArgumentError, match="K_D0"):
        gc.fit_flight_model(veh, ammonite, fit=["volume", "K_D0"])


def test_fit_too_few_samples(ammonite):
    mask = np.zeros(len(ammonite), dtype=bool)
    mask[np.flatnonzero(ammonite.mask())[:2]] = True
    with pytest.raises(gc.RecordError) as info:
        gc.fit_flight_model(_hull_vehicle(), ammonite, mask=mask)
    msg = str(info.value)
    assert "2 usable sample" in msg and "2 coefficient" in msg
    with pytest.raises(gc.RecordError, match="mask"):
        gc.fit_flight_model(_hull_vehicle(), ammonite, mask=mask[:-1])


def test_fit_bad_holdout(ammonite):
    for bad in (1, 0, True, 2.0, 10**6):
        with pytest.raises(gc.ArgumentError, match="holdout"):
            gc.fit_flight_model(_hull_vehicle(), ammonite, holdout=bad)


def test_fit_mass_and_volume_cannot_be_told_apart(ammonite):
    # without compressibility and at constant density the heaviness is mass - rho (volume + dV): only the
    # difference mass - rho volume is seen by the record
    veh = _hull_vehicle().with_hydrodynamics(compressibility=0.0)
    with pytest.raises(gc.SolverError) as info:
        gc.fit_flight_model(veh, ammonite, fit=["mass", "volume"])
    msg = str(info.value)
    assert "mass" in msg and "volume" in msg


def test_holdout_groups_whole_dives(ammonite):
    """A record of three identical dives held out in two groups: whole dives per group, so each group is predicted
    by a fit to identical dives and its RMS is the in-sample RMS (contiguous halves would split the middle dive and
    fit on one and a half dives, which moves the coefficients)."""
    n, span = len(ammonite), ammonite.time[-1] - ammonite.time[0] + 60.0
    rec = gc.DiveRecord.from_arrays(
        np.concatenate([ammonite.time + k * span for k in range(3)]), np.tile(ammonite.depth, 3),
        np.tile(ammonite.pitch, 3), np.tile(ammonite.buoyancy_volume, 3))
    used = rec.mask()
    # each copy: its dive, and a dive started at its end (a few shallow samples, none used)
    assert np.array_equal(np.unique(rec.dive_number), np.arange(6))
    assert np.array_equal(np.unique(rec.dive_number[used]), [0, 2, 4])
    assert np.all(rec.dive_number[:n][used[:n]] == 0)
    fit = gc.fit_flight_model(_hull_vehicle(), rec, law="gliderflight", holdout=2)
    assert len(fit.cv_fold_rms) == 2 and fit.context["holdout_blocks"] == "dives"
    for fold in fit.cv_fold_rms:
        assert fold == pytest.approx(fit.rms, rel=1e-6)


def test_record_and_fit_draw_themselves_with_units(ammonite, fits):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    axes = ammonite.plot()
    assert len(axes) == 3
    assert [a.get_ylabel() for a in axes] == ["depth [m]", r"pitch $\theta$ [deg]", "pumped volume [cm$^3$]"]
    assert axes[0].get_ylim()[0] > axes[0].get_ylim()[1]  # depth grows downwards
    fit = fits["gliderflight"]
    fa = fit.plot()
    assert len(fa) == 2 and fa[0].get_ylabel() == "vertical speed [m/s]" and fa[1].get_ylabel() == "depth [m]"
    assert f"{fit.rms:.4f}" in fa[0].get_title()
    # the residual panel shows exactly the fit's residuals
    x = fa[1].lines[0].get_xdata()
    np.testing.assert_array_equal(x, fit.residual)
    _, two = plt.subplots(2)
    with pytest.raises(gc.GlidectlError, match="3 axes"):
        ammonite.plot(ax=two)
    plt.close("all")


def test_law_start_and_fit_refuse_an_unknown_law(ammonite):
    veh = _hull_vehicle()
    for bad in ("Seaglider", "foo"):
        with pytest.raises(gc.VehicleFileError, match="unknown hydrodynamic law"):
            gc.law_start(veh, bad)
        with pytest.raises(gc.VehicleFileError, match="unknown hydrodynamic law"):
            gc.fit_flight_model(veh, ammonite, law=bad)


def test_fit_refuses_an_optimum_where_samples_have_no_glide(ammonite):
    """Fitting K_D with the volume drives some used samples past their steady glide (modelled vertical speed 0, a
    jump in the objective): refused, naming the count, not returned with meaningless standard errors."""
    with pytest.raises(gc.SolverError, match=r"samples used have no steady glide"):
        gc.fit_flight_model(_hull_vehicle(), ammonite, fit=("volume", "K_D"))


def test_fit_at_an_active_bound_keeps_its_steps_inside(ammonite):
    """A coefficient that ends on its lower bound (compressibility 0, when the record's hull looks stiffer than the
    start) gets one-sided differences: no step below the bound, finite standard errors."""
    rec = gc.DiveRecord.from_arrays(ammonite.time, ammonite.depth, ammonite.pitch,
                                    ammonite.buoyancy_volume + 0.0684 * 2e-9 * ammonite.pressure)
    fit = gc.fit_flight_model(_hull_vehicle(), rec, fit=("volume", "K_D0", "compressibility"))
    assert fit.params["compressibility"] >= 0.0
    assert all(math.isfinite(v) and v > 0 for v in fit.stderr.values())


def test_fit_starts_derived_gliderflight_coefficients_at_their_values(ammonite):
    """gliderflight's Cd1 and aw are derived from the wing (aw^2 / (pi e AR) + Cd1_hull, the swept-wing estimate)
    when a file leaves them out; a fit of them starts at those values, not at 0."""
    from glidectl.analysis.flight_fit import _coefficient_values

    veh = _hull_vehicle(volume=0.0684).with_hydrodynamics("gliderflight", Cd0=0.094, ah=3.8, S=0.1)
    assert "Cd1" not in veh.params and "aw" not in veh.params
    slope, _, cd1 = gc.hydro.gliderflight_coefficients(veh)
    assert _coefficient_values(veh, ("Cd1", "aw")).tolist() == [cd1, slope - 3.8]
    fit = gc.fit_flight_model(veh, ammonite, fit=("volume", "Cd1"))
    assert 0.2 * cd1 < fit.params["Cd1"] < 5 * cd1 and fit.rms < 0.07



def _profile_record(depths: list[float], times: list[float]) -> gc.DiveRecord:
    """A record of straight legs between the given depths (m) at the given times (s), pitch +-23 deg and pump
    +-200 cm^3 by the sign of the motion."""
    t = np.arange(0.0, times[-1] + 1.0, 4.0)
    d = np.interp(t, times, depths)
    down = np.gradient(d) > 0
    return gc.DiveRecord.from_arrays(t, d, np.where(down, -0.4, 0.4), np.where(down, -2e-4, 2e-4))


def test_mask_leaves_out_every_inflection_of_a_yo():
    """A dive with a yo (0 -> 100 -> 30 -> 60 -> 0 m): 20 m about each turning point are left out on both sides of
    it, the top of the yo at 30 m included, not only the dive's deepest point."""
    rec = _profile_record([0.5, 100.0, 30.0, 60.0, 0.5], [0.0, 1000.0, 1800.0, 2400.0, 4000.0])
    turns = rec.inflections()
    np.testing.assert_allclose(rec.depth[turns], [100.0, 30.0, 60.0], atol=0.5)
    m = rec.mask()
    leg = np.searchsorted(turns, np.arange(len(rec)), side="right")
    assert np.all(rec.depth[m & (leg == 1)] > 50.0 - 0.5)  # the climb from 100 to 30 m: 20 m off both ends
    assert np.all(rec.depth[m & (leg == 1)] < 80.0 + 0.5)
    assert not np.any(m & (leg == 2))  # the 30 -> 60 m leg is within 20 m of one of its ends everywhere
    assert np.all(rec.depth[m & (leg == 3)] < 40.0 + 0.5)


def test_dive_number_of_a_record_that_starts_under_water():
    """Starting at 50 m (a dive under way), surfacing, then a full dive: two dives, the second after the surfacing."""
    rec = _profile_record([50.0, 0.5, 100.0, 0.5], [0.0, 500.0, 2000.0, 4000.0])
    n = rec.dive_number
    assert np.array_equal(np.unique(n), [0, 1])
    first = np.argmax(n == 1)
    assert rec.depth[first] > 5.0 and rec.depth[:first].min() < 2.0 and rec.time[first] < 1000.0


def test_csv_with_a_byte_order_mark(ammonite, tmp_path):
    """A CSV saved by a spreadsheet starts with a UTF-8 byte-order mark: its first column is still 'time'."""
    path = tmp_path / "excel.csv"
    rows = np.column_stack([ammonite.time, ammonite.depth, ammonite.pitch, ammonite.buoyancy_volume])
    text = "time,depth,pitch,buoyancy_volume\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows)
    path.write_bytes(b"\xef\xbb\xbf" + text.encode())
    rec = gc.read_dive_record(path)
    assert np.array_equal(rec.time, ammonite.time) and np.array_equal(rec.depth, ammonite.depth)
